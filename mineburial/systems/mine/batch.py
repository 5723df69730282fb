"""The mine's batch driver: many drops, no Python per drop, spread over threads.

Each drop is one call of the compiled :func:`run_drop`, which releases the GIL
(``nogil``); the one thread pool of the runs (:func:`~mineburial.ensembles.threads.run_blocks`),
one thread per numba thread (``numba.set_num_threads``), takes consecutive blocks of drops, so
drops of very different lengths (a mine that floats ends at once, one that creeps in a soft
bottom runs long) balance themselves. Each drop writes only its own row, so results do not
depend on the thread count or the schedule.

Threads rather than ``prange``: the parallel loop's compile (parfor lowering) was a
quarter of the engine's compile time from an empty cache, for a loop with nothing to
vectorise; the pool costs a few microseconds a block against ~10 ms a drop.

Ctrl-C stops the pool between blocks, whatever the chunk size; the drops finished by then are
named (:class:`~mineburial.ensembles.interrupt.Interrupted`) and kept by the run driver.
Stopping between drops changes no result: each drop's row is the same whichever thread runs it
and whenever.
"""

import numba
import numpy as np

from mineburial.ensembles.interrupt import Interrupted
from mineburial.ensembles.threads import run_blocks
from mineburial.kernels import status as st
from mineburial.kernels.mine.layout import N_SUMMARY
from mineburial.kernels.mine.overburden import with_long_tables
from mineburial.kernels.mine.stepper import reference_paths, run_drop


def _run_drops(params, valid, sediment_bank, current_bank, summary, codes, references, start, stop):
    """Run drops ``start`` to ``stop`` (exclusive); each writes only its own row.

    A Python loop over the compiled :func:`run_drop`, which releases the GIL for the whole
    drop: the call costs microseconds against milliseconds a drop, and a compiled loop
    around it would be one more link-and-optimise pass over the whole engine at compile
    time (~3 s from an empty cache).
    """
    for i in range(start, stop):
        if valid[i] == 0:
            summary[i, :] = np.nan
            codes[i] = st.INVALID_INPUT
            continue
        code, _ = run_drop(params[i], sediment_bank, current_bank, summary[i], None, 1.0, references)
        codes[i] = code


def run_batch(params, valid, sediment_bank, current_bank, threads=None):
    """Run the drops whose packed parameters are the rows of ``params``.

    ``valid`` (bool per drop) marks drops whose sampled inputs passed validation;
    the others get status ``invalid_input`` without being run. ``threads``: number of
    threads (default ``numba.get_num_threads()``). Returns
    ``(summary (n, N_SUMMARY), status (n,) int8)``.

    Ctrl-C (SIGINT) stops it within about one drop: the threads take no new block, and
    :class:`Interrupted` is raised with the drops finished before the first unfinished one
    (:func:`run_blocks`).
    """
    params = np.ascontiguousarray(params, dtype=np.float64)
    n = params.shape[0]
    summary = np.empty((n, N_SUMMARY))
    codes = np.empty(n, dtype=np.int8)
    args = (
        params,
        np.ascontiguousarray(valid, dtype=np.uint8),
        np.ascontiguousarray(sediment_bank, dtype=np.float64),
        np.ascontiguousarray(current_bank, dtype=np.float64),
        summary,
        codes,
        with_long_tables(reference_paths(params), params, sediment_bank),
    )
    threads = numba.get_num_threads() if threads is None else int(threads)
    try:
        run_blocks(n, lambda a, b: _run_drops(*args, a, b), threads)
    except Interrupted as exc:
        exc.summary, exc.status = summary[: exc.done], codes[: exc.done]
        raise
    return summary, codes
