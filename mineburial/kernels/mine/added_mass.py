"""Added-mass coefficients of a closed finite circular cylinder and the incidence factor
of the potential-flow (Munk) moment, for ``numerics.water_column = "crossflow"``.

Tables (docs/physics.md, "Water-column model choices"):

* :data:`LD_TABLE`, :data:`KT_TABLE`, :data:`KA_TABLE`: transverse and axial added-mass
  coefficients of a closed circular cylinder (flat ends) in unbounded potential flow,
  as fractions of rho V, at L/D = 2, 3, 4, 6. **[computed]** boundary-element values
  (capytaine, sphere check 0.5006 vs 0.5) from ``shared/notes/sources.md`` section 1;
  re-computed in ``benchmarks/results/water_column_models.txt``.
* :data:`KR_TABLE`: rotational (pitch/yaw) added inertia about the centroid, as a fraction
  of strip theory's, at the same L/D **[computed]** by ``benchmarks/added_mass_bem.py``
  (capytaine 3.0.0, direct method, sphere check 0.4999).
* :data:`ETA_LD`, :data:`ETA_TABLE`: crossflow efficiency eta(L/D) of the viscous-crossflow
  method, Digital DATCOM ``bodyrt.f`` table (Jorgensen, NASA TR R-474, 1977): the separated
  crossflow is eta C_dn(Re) with C_dn the 2-D cylinder's. Seed 000 eq. (44) is that 2-D
  value in every Reynolds band but 12000-150000, where it is already the finite body's
  (0.835 - 0.35/delta, within 4 % of eta x 1.2); :func:`finite_body_cross_drag` applies eta
  in the other bands (docs/physics.md, "Water-column model choices").

Interpolation is linear in L/D; outside the table the end values are held (the default
mine has L/D = 3.8, the Exp-1 cylinders 3.0 and 3.8).
"""

import math

import numpy as np

from mineburial._numba import kernel

LD_TABLE = np.array([2.0, 3.0, 4.0, 6.0])
KT_TABLE = np.array([0.736, 0.810, 0.852, 0.898])  # transverse k_t, of rho V
KA_TABLE = np.array([0.305, 0.208, 0.157, 0.106])  # axial k_a, of rho V
# rotational k_r: added moment of inertia about a transverse axis through the centroid, of
# strip theory's rho pi R^2 L^3 / 12 [computed: benchmarks/added_mass_bem.py, capytaine]
KR_TABLE = np.array([0.4645, 0.5686, 0.6429, 0.7360])

ETA_LD = np.array([2.0, 4.0, 8.0, 12.0, 16.0, 20.0])
ETA_TABLE = np.array([0.56, 0.60, 0.66, 0.71, 0.74, 0.76])  # DATCOM bodyrt.f
C_DC_SUBCRITICAL = 1.2  # DATCOM crossflow drag coefficient, low crossflow Mach
# the Reynolds band (RE_FINITE_LOW, RE_FINITE_HIGH] in which seed 000 eq. (44) depends on L/D
RE_FINITE_LOW = 12000.0
RE_FINITE_HIGH = 150000.0


@kernel
def table_lookup(xs, ys, x):
    """Linear interpolation of (xs, ys) at x, end values held outside [xs[0], xs[-1]]."""
    n = xs.shape[0]
    if x <= xs[0]:
        return ys[0]
    if x >= xs[n - 1]:
        return ys[n - 1]
    i = 1
    while xs[i] < x:
        i += 1
    t = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    return ys[i - 1] + t * (ys[i] - ys[i - 1])


@kernel
def cylinder_added_mass(aspect):
    """(k_t, k_a, k_r) of a closed cylinder of L/D = ``aspect``: transverse and axial added
    mass as fractions of rho V, rotational added inertia about the centroid as a fraction of
    strip theory's rho pi R^2 L^3 / 12 (tables above)."""
    return (
        table_lookup(LD_TABLE, KT_TABLE, aspect),
        table_lookup(LD_TABLE, KA_TABLE, aspect),
        table_lookup(LD_TABLE, KR_TABLE, aspect),
    )


@kernel
def crossflow_efficiency(aspect):
    """eta(L/D) of the viscous-crossflow method (DATCOM bodyrt.f table above)."""
    return table_lookup(ETA_LD, ETA_TABLE, aspect)


@kernel
def finite_body_cross_drag(cd2, reynolds, eta):
    """Separated crossflow coefficient eta C_dn (Jorgensen, NASA TR R-474; DATCOM
    bodyjm.f) from seed 000 eq. (44)'s ``cd2``: eq. (44) is the 2-D cylinder's C_dn outside
    RE_FINITE_LOW < Re <= RE_FINITE_HIGH, where it already carries the L/D dependence, so
    ``eta`` multiplies it outside that band only (eta = 1 returns ``cd2`` unchanged)."""
    if RE_FINITE_LOW < reynolds <= RE_FINITE_HIGH:
        return cd2
    return eta * cd2


@kernel
def munk_incidence_factor(u1, u2, u3):
    """cos(alpha/2) of the viscous-crossflow method (Allen & Perkins 1951; Jorgensen,
    NASA TR R-474, as coded in Digital DATCOM bodyjm.f: potential term ~ sin 2alpha cos(alpha/2)).

    alpha is the incidence between the body axis and the relative flow (u1 axial, u2, u3
    transverse), folded into [0, 90 deg] because the closed cylinder is fore-aft symmetric
    (a flow from behind at 180 deg - alpha is the flow at alpha). cos(alpha/2) =
    sqrt((1 + cos alpha)/2) with cos alpha = |u1|/|u|; 1 at rest."""
    speed = math.sqrt(u1 * u1 + u2 * u2 + u3 * u3)
    if speed <= 0.0:
        return 1.0
    return math.sqrt(0.5 * (1.0 + abs(u1) / speed))


# ---------------------------------------------------------------------------------------------
# the closed frustum (a body of revolution: issue 36 item 2); the cylinder's tables above unchanged
# ---------------------------------------------------------------------------------------------
#: r_top / r_base (the smaller end's radius over the larger's) and L / (2 r_base) of the table
FRUSTUM_RATIO = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
FRUSTUM_LD = np.array([0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0])
# [computed: benchmarks/added_mass_revolution_bem.py, capytaine 3.0.0, direct method, unbounded
# fluid; results in benchmarks/results/added_mass_revolution_bem.txt] added masses of the closed
# frustum of base radius 1 in a fluid of density 1, rows FRUSTUM_RATIO, columns FRUSTUM_LD:
#: axial (along the axis)
FRUSTUM_MA = np.array(
    [
        [2.459770, 2.262234, 2.157679, 2.098166, 2.038417, 2.011889, 1.992986],
        [2.391114, 2.204433, 2.121219, 2.078325, 2.040195, 2.025771, 2.019143],
        [2.372307, 2.254646, 2.221976, 2.211754, 2.210749, 2.216198, 2.229456],
        [2.552387, 2.594658, 2.639343, 2.674708, 2.724453, 2.757391, 2.799669],
        [3.292588, 3.482869, 3.595743, 3.672453, 3.771658, 3.833809, 3.909880],
    ]
)
#: transverse
FRUSTUM_MT = np.array(
    [
        [0.111628, 0.382932, 0.737582, 1.137566, 2.011356, 2.939644, 4.876271],
        [0.176292, 0.577116, 1.081367, 1.639115, 2.839065, 4.098695, 6.700132],
        [0.259005, 0.811902, 1.497510, 2.254730, 3.883320, 5.590919, 9.107420],
        [0.350128, 1.062830, 1.949227, 2.935668, 5.073489, 7.327502, 11.984090],
        [0.433702, 1.308016, 2.410601, 3.650033, 6.363745, 9.248985, 15.248050],
    ]
)
#: transverse-rotation coupling about the volume centroid, positive when the centre of added
#: mass lies towards the top (the smaller end)
FRUSTUM_MC = np.array(
    [
        [-0.115823, -0.172206, -0.177649, -0.146116, -0.006995, +0.201377, +0.746947],
        [-0.139731, -0.188893, -0.172610, -0.110424, +0.107491, +0.410090, +1.168478],
        [-0.153487, -0.196680, -0.177890, -0.115043, +0.104813, +0.412721, +1.191044],
        [-0.121643, -0.151757, -0.143597, -0.107088, +0.029973, +0.229382, +0.747633],
        [+0.000019, +0.000008, +0.000007, +0.000008, -0.000003, +0.000001, +0.000010],
    ]
)
#: rotational (pitch/yaw) about a transverse axis through the volume centroid
FRUSTUM_MR = np.array(
    [
        [0.341456, 0.310374, 0.315232, 0.379218, 0.781044, 1.720027, 6.078159],
        [0.328878, 0.299513, 0.338704, 0.491826, 1.347295, 3.303396, 12.350527],
        [0.309853, 0.282472, 0.346648, 0.571890, 1.850524, 4.857666, 19.186396],
        [0.302131, 0.288042, 0.369563, 0.646829, 2.273515, 6.217244, 25.564070],
        [0.418759, 0.416548, 0.504162, 0.816252, 2.735295, 7.524276, 31.592645],
    ]
)


@kernel
def table_lookup2(xs, ys, table, x, y):
    """Bilinear interpolation of ``table[i, j]`` (at ``xs[i], ys[j]``) at ``(x, y)``, end values
    held outside the grid in each direction."""
    nx = xs.shape[0]
    ny = ys.shape[0]
    x = min(max(x, xs[0]), xs[nx - 1])
    y = min(max(y, ys[0]), ys[ny - 1])
    i = 1
    while i < nx - 1 and xs[i] < x:
        i += 1
    j = 1
    while j < ny - 1 and ys[j] < y:
        j += 1
    tx = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    ty = (y - ys[j - 1]) / (ys[j] - ys[j - 1])
    lo = table[i - 1, j - 1] + ty * (table[i - 1, j] - table[i - 1, j - 1])
    hi = table[i, j - 1] + ty * (table[i, j] - table[i, j - 1])
    return lo + tx * (hi - lo)


@kernel
def frustum_added_mass(r_base, r_top, length):
    """Added masses per unit fluid density of the closed frustum with base radius ``r_base`` (the
    larger), top radius ``r_top`` and length ``length`` (the tables above, scaled by ``r_base^3,
    r_base^4, r_base^5``): ``(m_axial, m_transverse, m_coupling, m_rotational)``, the last two about
    the volume centroid, the coupling positive towards the top."""
    q = r_top / r_base
    ld = length / (2.0 * r_base)
    a3 = r_base * r_base * r_base
    return (
        a3 * table_lookup2(FRUSTUM_RATIO, FRUSTUM_LD, FRUSTUM_MA, q, ld),
        a3 * table_lookup2(FRUSTUM_RATIO, FRUSTUM_LD, FRUSTUM_MT, q, ld),
        a3 * r_base * table_lookup2(FRUSTUM_RATIO, FRUSTUM_LD, FRUSTUM_MC, q, ld),
        a3 * r_base * r_base * table_lookup2(FRUSTUM_RATIO, FRUSTUM_LD, FRUSTUM_MR, q, ld),
    )
