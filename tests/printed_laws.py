"""Independent references shared by the tests: seed 000's printed cross-flow drag law,
written out from the paper (not from the kernels), for the test cylinder of conftest.BASE
(1 m x 0.25 m) in water."""

import math

G = 9.81
RHO = 1025.0
NU = 1.0e-6
L = 1.0
D = 0.25
R = D / 2
AREA = math.pi * R * R
VOL = AREA * L


def cd2_eq44(re, delta):
    """Cross-flow drag coefficient, seed 000 eq. (44), written out from the paper."""
    re = max(re, 1e-6)
    if re <= 12:
        return 1.9276 + 8 / re
    if re <= 180:
        return 1.261 + 16 / re
    if re <= 2000:
        return 0.855 + 89 / re
    if re <= 12000:
        return 0.84 + 0.00003 * re
    if re <= 150000:
        if delta >= 10:
            return 1.2 - 4 / delta
        if delta >= 2:
            return 0.835 - 0.35 / delta
        return max(0.0, 0.7 - 0.08 / delta)
    if re <= 350000:
        return 1.875 - 0.0000045 * re
    return 1 / (641550 / re + 1.5)


def broadside_drag(w):
    """Drag force (N, along +z) on the broadside test cylinder moving at vertical speed w."""
    return -0.5 * RHO * cd2_eq44(abs(w) * D / NU, L / D) * D * L * abs(w) * w
