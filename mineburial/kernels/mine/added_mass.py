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
