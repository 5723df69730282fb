"""Drag and lift coefficient laws of a circular cylinder (numba kernels).

* :func:`axial_drag_coefficient` -- seed 000 eq. (40), along the axis, vs aspect ratio.
* :func:`cross_drag_coefficient` -- seed 000 eq. (44), across the axis, vs Re and aspect ratio.
* :func:`lift_coefficient` -- seed 000 eq. (50), Magnus lift vs spin ratio.
* :func:`roughness_scaled` -- ``numerics.crossflow_drag_factor`` on eq. (44) above
  Re = 150 000 (docs/physics.md, "Calibration coefficients as inputs").

The aspect ratio is ``delta = L / d`` (length over diameter) and the Reynolds
number ``Re = |V2| d / nu`` (cross-flow speed, diameter, kinematic viscosity).
The piecewise laws are implemented as printed, including their jumps at the
breakpoints (listed in ``docs/notes/crossflow.md``); the only departures are the
documented guards and corrections flagged ``DEVIATION`` below.
"""

import math

from mineburial._numba import kernel, small_kernel

#: Reynolds numbers below this are raised to it (guards the 1/Re terms).
RE_MIN = 1e-6
#: above this Reynolds number eq. (44) is in its super-critical branches, where the surface
#: roughness decides the value (Achenbach 1971; Achenbach & Heinecke 1981)
RE_SUPERCRITICAL = 150000.0


@kernel
def axial_drag_coefficient(aspect):
    """Axial drag coefficient C_d1(delta), seed 000 eq. (40), ``delta = L / d``.

    1.0 for delta > 8; ``0.75 + delta/32.1934 + 0.09612/delta^2`` for
    0.5 < delta <= 8; 1.15 for delta <= 0.5. (Continuous to 1e-4 at both
    breakpoints.) NaN in, NaN out.
    """
    if aspect > 8.0:
        return 1.0
    if aspect > 0.5:
        return 0.75 + aspect / 32.1934 + 0.09612 / (aspect * aspect)
    if aspect <= 0.5:
        return 1.15
    return aspect  # NaN


@kernel
def cross_drag_coefficient(reynolds, aspect):
    """Cross-flow drag coefficient C_d2(Re, delta), seed 000 eq. (44).

    Branches as printed (``Re = |V2| d / nu``, ``delta = L / d``)::

        Re <= 12               1.9276 + 8/Re
        12 < Re <= 180         1.261 + 16/Re
        180 < Re <= 2000       0.855 + 89/Re
        2000 < Re <= 12000     0.84 + 0.00003 Re
        12000 < Re <= 150000   1.2 - 4/delta        (delta >= 10)
                               0.835 - 0.35/delta   (2 <= delta < 10)
                               0.7 - 0.08/delta     (delta < 2)
        150000 < Re <= 350000  1.875 - 0.0000045 Re
        Re > 350000            1 / (641550/Re + 1.5)

    The law jumps at Re = 12000 and Re = 150000 unless delta is infinite
    (see ``docs/notes/crossflow.md``); it is not smoothed.

    DEVIATION (guards): Re below ``RE_MIN`` = 1e-6 (including Re = 0) is raised
    to 1e-6, so C_d2 <= 8e6 and the drag ``C_d2 V2^2`` tends to the Stokes-like
    ``8 nu V2 / d`` instead of 0/0. In the 12000-150000 band the delta < 2 branch
    ``0.7 - 0.08/delta`` turns negative below delta = 0.1143; it is floored at 0
    (no thrust from drag). NaN in, NaN out.
    """
    if reynolds != reynolds or aspect != aspect:
        return math.nan
    re = reynolds
    if re < RE_MIN:
        re = RE_MIN
    if re <= 12.0:
        return 1.9276 + 8.0 / re
    if re <= 180.0:
        return 1.261 + 16.0 / re
    if re <= 2000.0:
        return 0.855 + 89.0 / re
    if re <= 12000.0:
        return 0.84 + 0.00003 * re
    if re <= 150000.0:
        if aspect >= 10.0:
            return 1.2 - 4.0 / aspect
        if aspect >= 2.0:
            return 0.835 - 0.35 / aspect
        if aspect <= 0.0:
            return 0.0
        return max(0.0, 0.7 - 0.08 / aspect)
    if re <= 350000.0:
        return 1.875 - 0.0000045 * re
    return 1.0 / (641550.0 / re + 1.5)


@small_kernel
def roughness_scaled(cd2, reynolds, factor):
    """Eq. (44)'s ``cd2`` times ``factor`` (``numerics.crossflow_drag_factor``) where
    ``reynolds`` > :data:`RE_SUPERCRITICAL`, ``cd2`` itself below: eq. (44) prints one
    super-critical law, while the measured post-critical C_d of a circular cylinder runs from
    about 0.3 (smooth) to about 1.2 (rough) (Achenbach 1971, J. Fluid Mech. 46:321; Achenbach &
    Heinecke 1981, J. Fluid Mech. 109:239). ``factor`` = 1 returns ``cd2`` bit for bit
    (1.0 * x is exact); NaN stays NaN."""
    if reynolds > RE_SUPERCRITICAL:
        return factor * cd2
    return cd2


@kernel
def lift_coefficient(spin_ratio):
    """Magnus lift coefficient C_l(s), seed 000 eq. (50), ``s = omega1 R / V2``.

    ``2 s`` for s <= 4 and ``8 + 0.24 (s - 4)`` for s > 4 (continuous at 4).

    DEVIATION: the printed law is not odd for s < -4 (it would keep ``2 s``);
    it is extended as an odd function, ``C_l(-s) = -C_l(s)``, so that reversing
    the spin (or the cross-flow) reverses the lift: for s < -4,
    ``C_l = -8 + 0.24 (s + 4)``. The caller must keep V2 != 0 (the lift force
    ``C_l V2^2`` tends to ``0.24 omega1 R V2 -> 0`` as V2 -> 0). NaN in, NaN out.
    """
    s = abs(spin_ratio)
    if s <= 4.0:
        return 2.0 * spin_ratio
    if s > 4.0:
        return math.copysign(8.0 + 0.24 * (s - 4.0), spin_ratio)
    return spin_ratio  # NaN
