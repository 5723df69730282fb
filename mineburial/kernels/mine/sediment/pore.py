"""Pore-water pressure under the advancing mine, seed 000 eq. (73).

The rupture-line length B is undefined in the seed; it is bounded by the embedded
depth of the tip and the diameter (and by ``sediment.rupture_length`` when set),
which keeps the force finite and physical (docs/notes/sediment.md section 4). The
sign is fixed to oppose the vertical motion, and the dw/dt part is returned as a
vertical added mass that the caller puts on the left-hand side.
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.mine.sediment.laws import LAW_B, LAW_EV, LAW_G, LAW_KP, _law_properties


@kernel
def pore_pressure(L, R, chi, c20, c21, c22, d0, zeta_tip, w_up, law, bank):
    """Force (E-frame vertical), torque (body frame, about the COM) and vertical added
    mass of the pore-pressure law; ``w_up``: vertical COM velocity (E-frame, up > 0)."""
    diameter = 2.0 * R
    b = min(zeta_tip, diameter)
    if law[LAW_B] > 0.0:
        b = min(b, law[LAW_B])
    rho_tip, _, _ = _law_properties(zeta_tip, law, bank)
    coef = math.pi / 8.0 * rho_tip * b * b * b
    fpw = 0.0
    if law[LAW_KP] > 0.0:
        fpw = -coef * law[LAW_G] * w_up / law[LAW_KP]
    added = 0.0
    if law[LAW_EV] > 0.0:
        added = coef * (1.0 + law[LAW_EV]) / law[LAW_EV]
    # acting on the axis at the middle of its embedded length (r_pw of eq. (75))
    xa = -0.5 * L - chi
    xb = 0.5 * L - chi
    top = d0 + R * math.sqrt(c21 * c21 + c22 * c22)
    lo = xa
    hi = xb
    if c20 > 0.0:
        hi = min(hi, top / c20)
    elif c20 < 0.0:
        lo = max(lo, top / c20)
    xm = 0.5 * (lo + hi)
    # r_pw x (C^T k fpw) with r_pw = (xm, 0, 0)
    return fpw, -xm * fpw * c22, xm * fpw * c21, added
