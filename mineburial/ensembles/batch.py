"""Compiled parallel batch driver: many drops, one ``prange`` loop, no Python per drop.

Drops differ widely in length (a mine that floats runs to the time limit, one
that hits a hard bottom stops early), so the loop is scheduled dynamically in
small chunks (``numba.parallel_chunksize``) rather than split evenly up front.
Each drop writes only its own row, so results do not depend on the thread
count or the schedule.
"""

import numba
import numpy as np
from numba import prange

from mineburial._numba import parallel_kernel
from mineburial.kernels import status as st
from mineburial.kernels.layout import N_SUMMARY
from mineburial.kernels.stepper import N_TRAJ, run_drop

CHUNK_SIZE = 1  # drops handed to a thread at a time (drops are long: balance, not overhead)


@parallel_kernel
def _run_batch(params, valid, sediment_bank, current_bank, summary, codes):
    n = params.shape[0]
    no_traj = np.empty((0, N_TRAJ))
    for i in prange(n):
        if valid[i] == 0:
            for k in range(N_SUMMARY):
                summary[i, k] = np.nan
            codes[i] = st.INVALID_INPUT
            continue
        code, _ = run_drop(params[i], sediment_bank, current_bank, summary[i], no_traj, 1.0)
        codes[i] = code


def run_batch(params, valid, sediment_bank, current_bank):
    """Run the drops whose packed parameters are the rows of ``params``.

    ``valid`` (bool per drop) marks drops whose sampled inputs passed validation;
    the others get status ``invalid_input`` without being run. Returns
    ``(summary (n, N_SUMMARY), status (n,) int8)``.
    """
    params = np.ascontiguousarray(params, dtype=np.float64)
    n = params.shape[0]
    summary = np.empty((n, N_SUMMARY))
    codes = np.empty(n, dtype=np.int8)
    with numba.parallel_chunksize(CHUNK_SIZE):
        _run_batch(params, np.ascontiguousarray(valid, dtype=np.uint8),
                   np.ascontiguousarray(sediment_bank, dtype=np.float64),
                   np.ascontiguousarray(current_bank, dtype=np.float64), summary, codes)
    return summary, codes
