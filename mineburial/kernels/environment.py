"""Water-column environment kernels: the ambient current V_w of seed 000 eq. (11)."""

import math

from mineburial._numba import kernel
from mineburial.kernels.layout import (
    P_CURRENT_EXPONENT,
    P_CURRENT_KIND,
    P_CURRENT_TABLE,
    P_CURRENT_U,
    P_CURRENT_V,
    P_DEPTH,
)


@kernel
def interpolate_row(bank, row, column, x):
    """Piecewise-linear interpolation of bank[row, column, :] against bank[row, 0, :].

    The abscissa increases; rows are NaN-padded after their last point. Values
    are held constant beyond the first and last points.
    """
    n = bank.shape[2]
    last = 0
    for k in range(n):
        if math.isnan(bank[row, 0, k]):
            break
        last = k
    if x <= bank[row, 0, 0]:
        return bank[row, column, 0]
    if x >= bank[row, 0, last]:
        return bank[row, column, last]
    lo = 0
    hi = last
    while hi - lo > 1:  # bisection: tables may have many points
        mid = (lo + hi) // 2
        if bank[row, 0, mid] <= x:
            lo = mid
        else:
            hi = mid
    x0 = bank[row, 0, lo]
    x1 = bank[row, 0, hi]
    f = (x - x0) / (x1 - x0)
    return bank[row, column, lo] + f * (bank[row, column, hi] - bank[row, column, lo])


@kernel
def current_velocity(z, p, current_bank):
    """Horizontal water velocity (u, v) at height z (E-frame, z = 0 at the surface).

    kind 0: still water; 1: uniform; 2: power law U(h) = U_s (h/d)^n with h the
    height above the seabed and d the water depth (seed 004 eq. (38), n = 1/7);
    3: table of (depth below surface, u, v). No current above the surface (no wind
    is modelled) and none below the seabed.
    """
    depth = p[P_DEPTH]
    if z > 0.0 or z < -depth:
        return 0.0, 0.0
    kind = int(p[P_CURRENT_KIND])
    if kind == 0:
        return 0.0, 0.0
    if kind == 1:
        return p[P_CURRENT_U], p[P_CURRENT_V]
    if kind == 2:
        h = z + depth
        f = (h / depth) ** p[P_CURRENT_EXPONENT] if h > 0.0 else 0.0
        return f * p[P_CURRENT_U], f * p[P_CURRENT_V]
    row = int(p[P_CURRENT_TABLE])
    return (interpolate_row(current_bank, row, 1, -z), interpolate_row(current_bank, row, 2, -z))
