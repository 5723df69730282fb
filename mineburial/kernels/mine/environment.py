"""Water-column environment kernels: the ambient current V_w of seed 000 eq. (11)."""

import math

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.mine.layout import (
    P_CURRENT_EXPONENT,
    P_CURRENT_KIND,
    P_CURRENT_TABLE,
    P_CURRENT_U,
    P_CURRENT_V,
    P_DEPTH,
)


@small_kernel
def last_point(bank, row):
    """Index of the last point of bank row ``row``: rows are NaN-padded after their last
    point, so the first NaN is found by bisection (O(log n); the whole row was scanned
    before, which made a long profile's every evaluation cost its length, issue 21)."""
    hi = bank.shape[2] - 1
    if not math.isnan(bank[row, 0, hi]):
        return hi
    lo = 0
    if math.isnan(bank[row, 0, lo]):
        return lo
    while hi - lo > 1:  # bank[row, 0, lo] is a point, bank[row, 0, hi] padding
        mid = (lo + hi) // 2
        if math.isnan(bank[row, 0, mid]):
            hi = mid
        else:
            lo = mid
    return lo


#: column of a drop's own sediment bank (``sediment.laws.drop_bank``) holding its bucket
#: index: entry b is the last point at or above depth d_0 + b (d_last - d_0) / n, n points
COLUMN_BUCKET = 4


@small_kernel
def _below(a, x, strict):
    return a < x if strict else a <= x


@kernel
def bracket(bank, row, x, last, strict):
    """``(lo, lo + 1)`` with ``lo`` the last point of bank row ``row`` below ``x``
    (``bank[row, 0, lo] <= x``, or ``< x`` when ``strict``), for ``x`` between the first
    point and the last (``last``), which the caller checked.

    The answer is unique (the depths increase), so it is the same whatever the search: a
    bank with a :data:`COLUMN_BUCKET` narrows it to the points of one bucket (O(1) for any
    reasonably even spacing; a bucket that does not hold ``x``, by rounding, is not used),
    then bisection (O(log n)) finishes."""
    lo = 0
    hi = last
    if bank.shape[1] > COLUMN_BUCKET and last > 1 and x == x:
        d0 = bank[row, 0, 0]
        b = int((x - d0) / ((bank[row, 0, last] - d0) / (last + 1)))
        if b >= 0 and b <= last:
            lb = int(bank[row, COLUMN_BUCKET, b])
            hb = last if b == last else min(int(bank[row, COLUMN_BUCKET, b + 1]) + 1, last)
            if _below(bank[row, 0, lb], x, strict) and not _below(bank[row, 0, hb], x, strict):
                lo = lb
                hi = hb
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _below(bank[row, 0, mid], x, strict):
            lo = mid
        else:
            hi = mid
    return lo, hi


@kernel
def interpolate_row(bank, row, column, x):
    """Piecewise-linear interpolation of bank[row, column, :] against bank[row, 0, :].

    The abscissa increases; rows are NaN-padded after their last point. Values
    are held constant beyond the first and last points. The last point and the
    bracketing pair are searched (:func:`last_point`, :func:`bracket`), not scanned.
    """
    last = last_point(bank, row)
    if x <= bank[row, 0, 0]:
        return bank[row, column, 0]
    if x >= bank[row, 0, last]:
        return bank[row, column, last]
    lo, hi = bracket(bank, row, x, last, False)
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
