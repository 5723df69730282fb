"""The one thread pool of the runs: items of an ensemble (drops, restraint cases, scour drops) in blocks
on daemon threads, the calling thread only waiting, so that Ctrl-C is seen within :data:`POLL` s.

A thread takes the next block when it is done with its last, so items of very different lengths
balance themselves; each item writes only its own row, so results do not depend on the thread count
or the schedule. The compiled kernels release the GIL (``nogil``). Threads rather than ``prange``:
:mod:`mineburial.systems.mine.batch` says why. Generic: it knows no system.
"""

import itertools
import threading

import numpy as np

from mineburial.ensembles.interrupt import Interrupted, sigint_flag

BLOCK_SIZE = 2  # items a thread takes at a time (drops are long: balance, not overhead)

#: seconds between the main thread's looks at the threads and at the Ctrl-C flag
POLL = 0.05
#: seconds a Ctrl-C waits for the items in flight before giving up on them (their
#: threads are daemons: an item cannot be stopped inside compiled code)
GRACE = 1.0


def run_blocks(n: int, run, threads: int) -> None:
    """``run(start, stop)`` over blocks of :data:`BLOCK_SIZE` of ``range(n)`` on ``threads``
    daemon threads, each taking the next block when done with its last.

    The main thread only waits, in steps of :data:`POLL` s. On SIGINT (:func:`sigint_flag`)
    no thread takes a new block; the blocks in flight are given :data:`GRACE` s, then
    :class:`Interrupted` says how many items at the start are finished.
    An exception in ``run`` is raised here once every thread has stopped.
    """
    threads = max(1, min(threads, -(-n // BLOCK_SIZE)))
    blocks = itertools.count(0, BLOCK_SIZE)  # next() is atomic under the GIL
    finished = np.zeros(-(-n // BLOCK_SIZE), dtype=bool)
    errors: list = []
    stop, all_done = threading.Event(), threading.Event()
    running = [threads]

    def worker():
        try:
            for start in blocks:
                if start >= n or stop.is_set():
                    return
                run(start, min(start + BLOCK_SIZE, n))
                finished[start // BLOCK_SIZE] = True
        except BaseException as exc:  # raised by the main thread
            errors.append(exc)
            stop.set()
        finally:
            with lock:
                running[0] -= 1
                if running[0] == 0:
                    all_done.set()

    lock = threading.Lock()
    with sigint_flag() as interrupted:
        for k in range(threads):
            threading.Thread(target=worker, name=f"mineburial-worker-{k}", daemon=True).start()
        while not all_done.wait(POLL) and not interrupted.is_set():
            pass
        if interrupted.is_set():
            stop.set()
            all_done.wait(GRACE)
            missing = np.flatnonzero(~finished)
            raise Interrupted(n if missing.size == 0 else int(missing[0]) * BLOCK_SIZE)
    if errors:
        raise errors[0]
