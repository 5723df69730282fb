"""Ctrl-C (SIGINT) during a run: honoured within about a second, with the work finished kept.

The run driver computes drops on worker threads while the main thread waits
(:mod:`mineburial.ensembles.threads`). :func:`sigint_flag` turns SIGINT into a flag that the
waiting main thread reads every few hundredths of a second; the threads then take no new
drops, and :class:`Interrupted` (a ``KeyboardInterrupt``) says which drops are finished, so
that the run driver saves them (:mod:`mineburial.ensembles.runner`) before the command ends
with one line and status 130 (:mod:`mineburial.cli`).
"""

import contextlib
import signal
import threading

__all__ = ["Interrupted", "sigint_flag"]


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`~mineburial.systems.mine.batch.run_batch`: the first ``done`` drops
    are finished (``summary`` and ``status``: their rows, set by ``run_batch``; ``partial``:
    their chunk dict, set by :func:`~mineburial.ensembles.engine.compute_chunk`); the caller
    may keep them."""

    def __init__(self, done: int):
        super().__init__(done)
        self.done = done
        self.summary = self.status = self.partial = None


@contextlib.contextmanager
def sigint_flag():
    """Within the block, SIGINT sets the yielded :class:`threading.Event` instead of
    raising :class:`KeyboardInterrupt` wherever the main thread happens to be.

    Why: Python runs a signal's handler only in the main thread, between two bytecodes,
    while the kernel may deliver the signal to any thread. A main thread blocked without a
    timeout (waiting for a pool's futures) then ran the handler only when its wait ended,
    after the whole chunk (measured: 70-92 s after a SIGINT that came during the kernels'
    first compile; 35.6 s on a chunk of 20,000 drops), and the KeyboardInterrupt it raised
    threw that chunk away. A flag set by the handler and read by a main thread that waits
    in short steps (:data:`mineburial.ensembles.threads.POLL`) is seen at once, and the drops
    finished are known.

    Outside the main thread (a dask worker's task thread) signals cannot be handled: the
    event is never set. A SIGINT that this process inherited as ignored (a command started
    with ``&`` from a script, or under ``nohup``) stays ignored, as POSIX shells intend.
    """
    flag = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    old = signal.getsignal(signal.SIGINT)
    if old is signal.SIG_IGN:
        yield flag
        return
    signal.signal(signal.SIGINT, lambda signum, frame: flag.set())
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, old)
