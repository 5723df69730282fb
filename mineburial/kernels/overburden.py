"""Geostatic (overburden) force of the sediment on the embedded part of the mine.

The effective overburden pressure sigma'(zeta) = int_0^zeta (rho_s - rho_w) g dzeta'
(seed 000 eq. (68) with the water's share removed: the water pressure is already
in the buoyancy of the whole submerged volume) acting on every embedded surface
element integrates, by the divergence theorem, to a volume integral over the
embedded part (sigma' vanishes on the seabed plane, which closes the surface):

    F = g int_emb (rho_s(zeta) - rho_w) dV  k,

an upward "sediment buoyancy" - Archimedes with the sediment's density. It is
evaluated exactly for the force by slicing the embedded part at the depths of the
profile table (density is linear within each slice, so int rho dV = V rho(zeta_c)
with zeta_c the slice's centroid depth), each slice acting at its centroid (exact
for the torque when the density is uniform within the slice).
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.environment import interpolate_row
from mineburial.kernels.geometry import cut_cylinder
from mineburial.kernels.layout import P_SED_PROFILE, P_SED_RHO, P_SED_RHO_GRAD


@kernel
def _density(zeta, p, bank):
    row = int(p[P_SED_PROFILE])
    if row < 0:
        return p[P_SED_RHO] + p[P_SED_RHO_GRAD] * zeta
    return interpolate_row(bank, row, 1, zeta)


@kernel
def overburden_force(L, R, chi, a_z, z_c, seabed_z, z_lo, rho_w, g, p, bank):
    """(F, F*x, F*eta): upward force [N] of the effective overburden and its first
    moments about the COM in the body frame (x along the axis, eta along e_down):
    the torque is (F*x i_M + F*eta e_down) x k."""
    depth_max = seabed_z - z_lo  # deepest embedded point below the seabed
    if depth_max <= 0.0:
        return 0.0, 0.0, 0.0
    c = math.sqrt(max(0.0, 1.0 - a_z * a_z))
    f_tot = 0.0
    mx = 0.0
    me = 0.0
    row = int(p[P_SED_PROFILE])
    top = 0.0
    k = 1
    # the part below each slice boundary; a slice's bottom cut is the next slice's top cut
    # (one cut per boundary: a tabulated profile has one boundary per depth in the body)
    v1, x1, e1, _, _, _ = cut_cylinder(L, R, chi, a_z, z_c, seabed_z - top)
    while top < depth_max:
        # next slice boundary: the next table depth, or the bottom of the body
        bottom = depth_max
        if row >= 0:
            while k < bank.shape[2] and not math.isnan(bank[row, 0, k]):
                if bank[row, 0, k] > top:
                    if bank[row, 0, k] < bottom:
                        bottom = bank[row, 0, k]
                    break
                k += 1
        v2, x2, e2, _, _, _ = cut_cylinder(L, R, chi, a_z, z_c, seabed_z - bottom)
        v = v1 - v2  # the part between the two planes, its centroid (xs, es)
        if v > 0.0:
            xs = (v1 * x1 - v2 * x2) / v
            es = (v1 * e1 - v2 * e2) / v
            z_cent = z_c + a_z * xs - es * c
            rho = _density(seabed_z - z_cent, p, bank)
            f = (rho - rho_w) * g * v
            f_tot += f
            mx += f * xs
            me += f * es
        top = bottom
        v1, x1, e1 = v2, x2, e2
    return f_tot, mx, me
