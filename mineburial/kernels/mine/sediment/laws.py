"""Sediment traction laws: profiles, strain-rate laws and the traction at one surface point.

Seed 000 section 6 (Chu & Fan 2006, eqs. (63)-(75)) writes the force of the
sediment on a penetrating cylinder as a surface integral over the part of the
surface below the seabed, switched on only where the surface moves towards the
sediment (the step function delta of eq. (65): delta = 1 when v.n >= 0, with
v = V + omega x r the local velocity and n the outward normal). This module holds
what is evaluated at one surface point; the quadratures over the embedded surface
are in :mod:`.reference` and :mod:`.fast`.

Traction laws (code ``law[0]``, ``layout.RESISTANCE_NAMES``), on advancing
elements (v.n >= 0; on the receding side a water-filled cavity opens, seed 000
section 6.1). ``sigma'(zeta) = int_0^zeta (rho_s - rho_w) g dzeta'`` is the
*effective* (submerged) overburden: seed 000 eq. (68) uses the total one, but the
stepper applies the water pressure (Archimedes with rho_w) to the whole submerged
volume, so the total overburden would count the water twice. The normal traction
is scaled by the regularised switch h_n = v_n / sqrt(v_n^2 + V_REG_N^2) so that it
is continuous in the velocity.

0 ``delta``    seed 000 eq. (74): normal pressure sigma' h_n, tangential traction
               mu G S along tau = -v_tau/|v_tau| (eq. (67)).
1 ``friction`` seed 000 section 10 item 4: normal pressure N S G h_n with
               N = p[P_SED_NC] (default pi + 2, the undrained bearing factor of
               Prandtl 1920), tangential mu times the normal pressure.
2 ``bearing``  in the spirit of Chu & Fan 2007 (IEEE J. Oceanic Eng. 32(1):34):
               normal pressure N_c(zeta) S G h_n with the depth factor of Brinch
               Hansen (1970), N_c = p[P_SED_NC] (1 + f arctan(zeta/d)) with
               f = p[P_SED_DEPTH_FACTOR] (0.4 by default), i.e. 5.14 at the seabed and
               8.4 deep (Skempton 1951: 7.5 strip, 9.0 circle); side adhesion alpha S G
               with alpha = p[P_SED_MU] (True 1976; Aubeny & Shi 2006: alpha ~ 1/S_t).
Every law adds, when ``sediment.inertial_drag`` C_D = p[P_SED_CD] > 0, the soil's inertial
drag 0.5 C_D rho_s v_n^2 to the normal pressure of an advancing element (the drag term
0.5 C_D rho_s A v^2 of True 1976, Aubeny & Shi 2006 and O'Loughlin et al. 2013, written per
element; not a strength, so no friction follows from it); C_D = 0 (default): none.
For ``friction`` and ``bearing`` the geostatic part sigma' acts on every embedded
element whatever its motion and is added by the stepper in closed form
(:mod:`mineburial.kernels.mine.overburden`: Archimedes with the sediment density).

Rate laws G (code ``law[1]``, ``layout.RATE_LAW_NAMES``), evaluated with the LOCAL
speed |v| of the surface element (the seed's COM speed V for a pure translation):
0 ``impact35`` seed 000 eq. (70): G = A [1 - (1 - 1/A) exp(-|v|/V_rest)].
1 ``semilog``  G = 1 + beta log10(max(rate/rate_ref, 1)), rate = |v|/d
               (Biscontin & Pestana 2001; Aubeny & Shi 2006).
2 ``none``     G = 1.

The law is packed once per drop into a tuple (:func:`pack_law`, layout ``LAW_*``).
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.mine.environment import COLUMN_BUCKET, bracket, last_point
from mineburial.kernels.mine.layout import (
    P_GRAVITY,
    P_RHO_WATER,
    P_SED_A,
    P_SED_B,
    P_SED_BETA,
    P_SED_CD,
    P_SED_DEPTH_FACTOR,
    P_SED_EV,
    P_SED_KP,
    P_SED_MU,
    P_SED_NC,
    P_SED_PORE,
    P_SED_PROFILE,
    P_SED_QUADRATURE,
    P_SED_RATE_LAW,
    P_SED_RATE_REF,
    P_SED_RESISTANCE,
    P_SED_RHO,
    P_SED_RHO_GRAD,
    P_SED_S,
    P_SED_S_GRAD,
    P_SED_VREST,
    P_SLIP_SPEED,
    P_SWITCH_SPEED,
)

# --- model codes (layout.RESISTANCE_NAMES, layout.RATE_LAW_NAMES) -----------
RES_DELTA = 0
RES_FRICTION = 1
RES_BEARING = 2
RATE_IMPACT35 = 0
RATE_SEMILOG = 1
RATE_NONE = 2

#: Default regularisation speed (``numerics.slip_speed``, ``numerics.switch_speed``), m/s, of
#: * the slip direction: tau = -v_tau / sqrt(|v_tau|^2 + V_REG^2), which makes the tangential
#:   traction continuous at rest (it grows linearly with the slip below ~V_REG), and
#: * the advancing switch delta (eq. (65)): the normal traction is scaled by
#:   v_n / sqrt(v_n^2 + V_REG_N^2) on advancing elements.
#: The value sets the stiffness of the sediment phase (docs/design.md, "Time stepping");
#: the law reads it from the packed law (slots LAW_VREG, LAW_VREG_N), these constants are
#: the default and what the reference quadrature resolves.
SWITCH_SPEED = 5.0e-3
V_REG = SWITCH_SPEED
V_REG_N = SWITCH_SPEED

#: Gauss-Legendre nodes and weights on [-1, 1], row n holding the n-point rule (n <= GL_MAX),
#: shared by the quadratures (:mod:`.reference`, :mod:`.fast`).
GL_MAX = 12
GL_NODES = np.zeros((GL_MAX + 1, GL_MAX))
GL_WEIGHTS = np.zeros((GL_MAX + 1, GL_MAX))
for _n in range(1, GL_MAX + 1):
    _xg, _wg = np.polynomial.legendre.leggauss(_n)
    GL_NODES[_n, :_n] = _xg
    GL_WEIGHTS[_n, :_n] = _wg
del _n, _xg, _wg

# =============================================================================
# sediment properties
# =============================================================================
#: column of a drop's own sediment bank (:func:`drop_bank`) holding the running integral
#: int_0^d (rho_s - rho_w) dzeta' at each tabulated depth d
COLUMN_OVERBURDEN = 3


@kernel
def _scan_properties(zeta, bank, row, rho_w, g):
    """:func:`_bank_properties` on a bank without the integral column: one pass down the
    row (O(points above zeta)), the sums in the order :func:`drop_bank` makes them."""
    d_prev = bank[row, 0, 0]
    r_prev = bank[row, 1, 0]
    s_prev = bank[row, 2, 0]
    if zeta <= d_prev:
        return r_prev, s_prev, (r_prev - rho_w) * g * zeta
    acc = (r_prev - rho_w) * d_prev
    n = bank.shape[2]
    for j in range(1, n):
        d = bank[row, 0, j]
        if not (d == d):  # NaN padding: end of this row
            break
        r = bank[row, 1, j]
        s = bank[row, 2, j]
        if zeta <= d:
            h = d - d_prev
            f = (zeta - d_prev) / h if h > 0.0 else 1.0
            rz = r_prev + f * (r - r_prev)
            sz = s_prev + f * (s - s_prev)
            acc += (0.5 * (r_prev + rz) - rho_w) * (zeta - d_prev)
            return rz, sz, acc * g
        acc += (0.5 * (r_prev + r) - rho_w) * (d - d_prev)
        d_prev = d
        r_prev = r
        s_prev = s
    acc += (r_prev - rho_w) * (zeta - d_prev)
    return r_prev, s_prev, acc * g


@kernel
def _bank_properties(zeta, bank, row, rho_w, g):
    """Piecewise-linear profile of bank row ``row`` at depth ``zeta``.

    Returns (rho_s, S, sigma'_eff) with sigma'_eff = int_0^zeta (rho_s - rho_w) g,
    exact for the piecewise-linear density (trapezoids); constant values above
    the first and below the last tabulated depth. On a drop's own bank
    (:func:`drop_bank`) the segment is searched (``environment.bracket``: O(1) for an
    even spacing, O(log n) at worst) and the integral down to its top read from
    :data:`COLUMN_OVERBURDEN`: bit-identical to the scan of :func:`_scan_properties`,
    which banks without that column (Python callers) use.
    """
    if bank.shape[1] <= COLUMN_OVERBURDEN:
        return _scan_properties(zeta, bank, row, rho_w, g)
    if zeta <= bank[row, 0, 0]:
        return bank[row, 1, 0], bank[row, 2, 0], (bank[row, 1, 0] - rho_w) * g * zeta
    hi = last_point(bank, row)
    if not (zeta <= bank[row, 0, hi]):  # below the last point (or NaN): constant
        r = bank[row, 1, hi]
        return (
            r,
            bank[row, 2, hi],
            (bank[row, COLUMN_OVERBURDEN, hi] + (r - rho_w) * (zeta - bank[row, 0, hi])) * g,
        )
    lo, hi = bracket(bank, row, zeta, hi, True)  # bank[row, 0, lo] < zeta <= bank[row, 0, hi]
    d_prev = bank[row, 0, lo]
    r_prev = bank[row, 1, lo]
    s_prev = bank[row, 2, lo]
    h = bank[row, 0, hi] - d_prev
    f = (zeta - d_prev) / h if h > 0.0 else 1.0
    rz = r_prev + f * (bank[row, 1, hi] - r_prev)
    sz = s_prev + f * (bank[row, 2, hi] - s_prev)
    acc = bank[row, COLUMN_OVERBURDEN, lo] + (0.5 * (r_prev + rz) - rho_w) * (zeta - d_prev)
    return rz, sz, acc * g


@kernel
def drop_bank(p, bank):
    """``(p, bank)`` for one drop: its sediment profile row alone (row 0 of a new bank,
    ``p`` copied with ``sediment.profile_index = 0``) with :data:`COLUMN_OVERBURDEN`
    filled for the drop's water density and the bucket index of
    :data:`~mineburial.kernels.mine.environment.COLUMN_BUCKET`, so that a depth is found in
    O(1) (:func:`~mineburial.kernels.mine.environment.bracket`) instead of by summing the rows
    above it: O(n) once per drop instead of at every evaluation. A linear profile
    (index < 0) returns the arguments unchanged."""
    row = int(p[P_SED_PROFILE])
    if row < 0:
        return p, bank
    n = last_point(bank, row) + 1
    own = np.empty((1, COLUMN_BUCKET + 1, n))
    for c in range(COLUMN_OVERBURDEN):
        for j in range(n):
            own[0, c, j] = bank[row, c, j]
    rho_w = p[P_RHO_WATER]
    d_prev = own[0, 0, 0]
    r_prev = own[0, 1, 0]
    acc = (r_prev - rho_w) * d_prev  # the sums of _scan_properties, in its order
    own[0, COLUMN_OVERBURDEN, 0] = acc
    for j in range(1, n):
        d = own[0, 0, j]
        r = own[0, 1, j]
        acc += (0.5 * (r_prev + r) - rho_w) * (d - d_prev)
        own[0, COLUMN_OVERBURDEN, j] = acc
        d_prev = d
        r_prev = r
    d0 = own[0, 0, 0]
    width = (own[0, 0, n - 1] - d0) / n  # n buckets of equal depth (bracket())
    j = 0
    for b in range(n):
        while j + 1 < n and own[0, 0, j + 1] <= d0 + b * width:
            j += 1
        own[0, COLUMN_BUCKET, b] = j
    q = p.copy()
    q[P_SED_PROFILE] = 0.0
    return q, own


@kernel
def _properties(zeta, rho0, krho, s0, ks, row, bank, rho_w, g):
    """(rho_s, S, sigma'_eff) at depth zeta: linear profile when row < 0, else bank row."""
    if row < 0:
        return _linear_properties(zeta, rho0, krho, s0, ks, rho_w, g)
    if zeta < 0.0:
        zeta = 0.0
    return _bank_properties(zeta, bank, row, rho_w, g)


@small_kernel
def _linear_properties(zeta, rho0, krho, s0, ks, rho_w, g):
    """:func:`_properties` of the linear profile (row < 0), which needs no bank."""
    if zeta < 0.0:
        zeta = 0.0
    rho = rho0 + krho * zeta
    s = s0 + ks * zeta
    if s < 0.0:
        s = 0.0
    sig = g * zeta * ((rho0 - rho_w) + 0.5 * krho * zeta)
    return rho, s, sig


@kernel
def sediment_properties(zeta, p, bank):
    """Sediment bulk density, undrained shear strength and effective overburden at depth zeta.

    Returns ``(rho_s [kg m-3], S [Pa], sigma'_eff [Pa])`` with
    ``sigma'_eff = int_0^zeta (rho_s - rho_w) g dzeta'`` (the submerged form of seed
    000 eq. (68)). ``p[P_SED_PROFILE] < 0``: linear profile rho0 + k_rho zeta,
    S0 + k_S zeta; otherwise piecewise-linear interpolation of that bank row.
    """
    return _properties(
        zeta,
        p[P_SED_RHO],
        p[P_SED_RHO_GRAD],
        p[P_SED_S],
        p[P_SED_S_GRAD],
        int(p[P_SED_PROFILE]),
        bank,
        p[P_RHO_WATER],
        p[P_GRAVITY],
    )


# =============================================================================
# rate laws and bearing factor
# =============================================================================
#: 1 / ln 10 (:func:`_rate` with ``natural_log``)
INV_LN10 = 1.0 / math.log(10.0)


@kernel
def _rate(speed, law, a, vrest, beta, rate_ref, diameter, natural_log=False):
    """Strain-rate factor G of law code ``law`` (:func:`rate_factor`). ``natural_log``: the semilog
    law's log10 as ``log(ratio) / ln 10`` (a product by :data:`INV_LN10`): the same G up to rounding
    (|change| <= 2 ulp of the logarithm), for a third of the instructions (glibc's log10 is its log plus
    a reduction and a wrapper). The fast rule's tractions take it (:func:`.fast.fast_tractions`,
    issue 34 item 4); the reference quadrature and :func:`rate_factor` keep log10."""
    if law == RATE_IMPACT35:
        # seed 000 eq. (70), written A - (A - 1) exp(-V/V_rest) (no division by A)
        if vrest > 0.0:
            return a - (a - 1.0) * math.exp(-speed / vrest)
        return a if speed > 0.0 else 1.0
    if law == RATE_SEMILOG:
        # Biscontin & Pestana (2001), Aubeny & Shi (2006): 1 + beta log10(rate/rate_ref)
        if rate_ref > 0.0 and diameter > 0.0:
            ratio = speed / (diameter * rate_ref)
            if ratio > 1.0:
                if natural_log:
                    return 1.0 + beta * (math.log(ratio) * INV_LN10)
                return 1.0 + beta * math.log10(ratio)
        return 1.0
    return 1.0


@kernel
def rate_factor(speed, diameter, p):
    """Strain-rate factor G of the shear strength at local speed ``speed`` (m/s).

    Law ``int(p[P_SED_RATE_LAW])``: 0 seed 000 eq. (70) (G(0) = 1, G(inf) = A, eq. (71));
    1 semi-log law with strain rate speed/diameter; 2 G = 1.
    """
    return _rate(
        speed, int(p[P_SED_RATE_LAW]), p[P_SED_A], p[P_SED_VREST], p[P_SED_BETA], p[P_SED_RATE_REF], diameter
    )


# =============================================================================
# traction at one surface point
# =============================================================================
@small_kernel
def _traction(x, y, z, nx, ny, nz, zeta, v1, v2, v3, w1, w2, w3, law, bank):
    """Traction (body frame) of the sediment on an advancing surface element.

    (x, y, z): body-frame point; (nx, ny, nz): outward normal; (v1, v2, v3): COM
    velocity in the body frame; (w1, w2, w3): angular velocity (body).
    ``law``: :func:`pack_law` (slots ``LAW_*``).
    """
    return _traction_at(x, y, z, nx, ny, nz, _depth_terms(zeta, law, bank), v1, v2, v3, w1, w2, w3, law)


@small_kernel
def _depth_terms(zeta, law, bank):
    """What :func:`_traction` needs of the depth zeta alone: (rho_s, S, sigma'_eff, N_c), N_c the
    bearing law's factor with its depth factor (0 for the other laws). A rule whose points share
    a depth (a cap's chord) computes them once (:func:`.fast._cap`); the same operations as
    inside :func:`_traction`, so the tractions are the same to the bit."""
    rho, s, sig = _law_properties(zeta, law, bank)
    return rho, s, sig, _bearing_factor(zeta, law)


@small_kernel
def _linear_depth_terms(zeta, law):
    """:func:`_depth_terms` where the law's profile is linear (``law[LAW_ROW] < 0``), without the bank,
    the same operations. A rule's loop over points takes it there (issue 34 item 4): an inlined kernel
    that takes the bank array binds it, and numba then counts a reference to it up and down (two
    calls and two atomic updates a point; with those of :func:`_properties`, 3.5 % of a default drop's
    instructions)."""
    rho, s, sig = _linear_properties(
        zeta, law[LAW_RHO0], law[LAW_KRHO], law[LAW_S0], law[LAW_KS], law[LAW_RHO_W], law[LAW_G]
    )
    return rho, s, sig, _bearing_factor(zeta, law)


@small_kernel
def _bearing_factor(zeta, law):
    """N_c of the bearing law at depth zeta, with its depth factor (0 for the other laws)."""
    model = law[LAW_MODEL]
    if model == RES_DELTA or model == RES_FRICTION:
        return 0.0
    # Brinch Hansen (1970) depth factor 1 + f arctan(zeta/d), f = sediment.bearing_depth_factor
    return law[LAW_N0] * (1.0 + law[LAW_DEPTH_FACTOR] * math.atan(zeta / law[LAW_DIAMETER]))


@small_kernel
def _traction_at(x, y, z, nx, ny, nz, depth, v1, v2, v3, w1, w2, w3, law, lnrate=False):
    """:func:`_traction` with the depth's terms given (:func:`_depth_terms`); ``lnrate``: the rate
    law's logarithm by ``log / ln 10`` (:func:`_rate`'s ``natural_log``: the fast rule's)."""
    rho, s, sig, nc = depth
    model = law[LAW_MODEL]
    vx = v1 + w2 * z - w3 * y
    vy = v2 + w3 * x - w1 * z
    vz = v3 + w1 * y - w2 * x
    vn = vx * nx + vy * ny + vz * nz
    tx = vx - vn * nx
    ty = vy - vn * ny
    tz = vz - vn * nz
    vt2 = tx * tx + ty * ty + tz * tz
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    rl = law[LAW_RATE]
    a = law[LAW_A]
    vrest = law[LAW_VREST]
    beta = law[LAW_BETA]
    rref = law[LAW_RATE_REF]
    dia = law[LAW_DIAMETER]
    gfac = _rate(speed, rl, a, vrest, beta, rref, dia, lnrate)
    mu = law[LAW_MU]
    # regularised advancing switch: the normal traction grows from 0 at v.n = 0 to its
    # full value over ~V_REG_N, so the force is continuous in the velocity (no
    # chattering of the explicit integrator at rest; docs/notes/sediment.md). The form
    # v_n / sqrt(v_n^2 + V_REG_N^2) has a short tail (1 - h ~ V_REG_N^2 / (2 v_n^2)), so
    # the ramp is a thin layer along the delta line that the quadrature need not resolve
    # (v_n / (v_n + V_REG_N) would lower the traction by 1 % up to v_n = 100 V_REG_N).
    vrn = law[LAW_VREG_N]
    hn = vn / math.sqrt(vn * vn + vrn * vrn) if vn > 0.0 else 0.0
    if model == RES_DELTA:
        pn = sig * hn
        ft = mu * gfac * s
    elif model == RES_FRICTION:
        # the geostatic overburden sig acts on every embedded element and is added in
        # closed form by the stepper (kernels/mine/overburden.py)
        pn = law[LAW_N0] * s * gfac * hn
        ft = mu * pn
    else:  # bearing: nc from _depth_terms
        pn = nc * s * gfac * hn
        ft = mu * s * gfac
    cd = law[LAW_INERTIAL_DRAG]
    if cd > 0.0 and vn > 0.0:  # soil inertial drag (module docstring); skipped at C_D = 0
        pn += 0.5 * cd * rho * vn * vn
    k = ft / math.sqrt(vt2 + law[LAW_VREG] * law[LAW_VREG])
    return -pn * nx - k * tx, -pn * ny - k * ty, -pn * nz - k * tz


# =============================================================================
# the law of one drop, packed once
# =============================================================================
#: What each slot of the packed law tuple (:func:`pack_law`) holds, by name (issue 36 item 4): a scenario
#: field's path where the slot carries the field's value as it is (from its parameter slot
#: ``layout.INDEX[path]``; an integer code as ``int``), ``derived.*`` where :func:`pack_law` computes it
#: (a fallback, a boolean, the body's diameter) and ``code.*`` for the argument whose numba type chooses what
#: is compiled. The ``LAW_*`` indices are looked up here by name; tests/test_law_slots.py checks that
#: :func:`pack_law` fills every field slot from its field's parameter slot and each derived one by its rule.
LAW_NAMES = (
    "derived.resistance",  # sediment.resistance's code (layout.RESISTANCE_NAMES); an unknown code: delta
    "sediment.rate_law",
    "sediment.impact_factor",
    "sediment.rest_speed",
    "sediment.rate_coefficient",
    "sediment.reference_rate",
    "sediment.friction",
    "derived.bearing_factor",  # sediment.bearing_factor; non-positive: pi + 2 (Prandtl 1920)
    "derived.diameter",  # the body's reference diameter (bodies.reference_lengths)
    "environment.water_density",
    "environment.gravity",
    "sediment.density",
    "sediment.density_gradient",
    "sediment.strength",
    "sediment.strength_gradient",
    "sediment.profile_index",
    "numerics.sediment_quadrature",
    "derived.pore_pressure",  # sediment.pore_pressure > 0, a boolean
    "sediment.rupture_length",
    "sediment.permeability",
    "sediment.void_ratio",
    "numerics.slip_speed",
    "numerics.switch_speed",
    "sediment.bearing_depth_factor",
    "sediment.inertial_drag",
    "code.reference_paths",  # None: the fast rule only; True: the reference quadrature too
)
_LAW = {name: k for k, name in enumerate(LAW_NAMES)}
LAW_MODEL = _LAW["derived.resistance"]
LAW_RATE = _LAW["sediment.rate_law"]
LAW_A = _LAW["sediment.impact_factor"]
LAW_VREST = _LAW["sediment.rest_speed"]
LAW_BETA = _LAW["sediment.rate_coefficient"]
LAW_RATE_REF = _LAW["sediment.reference_rate"]
LAW_MU = _LAW["sediment.friction"]
LAW_N0 = _LAW["derived.bearing_factor"]
LAW_DIAMETER = _LAW["derived.diameter"]
LAW_RHO_W = _LAW["environment.water_density"]
LAW_G = _LAW["environment.gravity"]
LAW_RHO0 = _LAW["sediment.density"]
LAW_KRHO = _LAW["sediment.density_gradient"]
LAW_S0 = _LAW["sediment.strength"]
LAW_KS = _LAW["sediment.strength_gradient"]
LAW_ROW = _LAW["sediment.profile_index"]
LAW_QUADRATURE = _LAW["numerics.sediment_quadrature"]
LAW_PORE = _LAW["derived.pore_pressure"]
LAW_B = _LAW["sediment.rupture_length"]
LAW_KP = _LAW["sediment.permeability"]
LAW_EV = _LAW["sediment.void_ratio"]
LAW_VREG = _LAW["numerics.slip_speed"]
LAW_VREG_N = _LAW["numerics.switch_speed"]
LAW_DEPTH_FACTOR = _LAW["sediment.bearing_depth_factor"]
LAW_INERTIAL_DRAG = _LAW["sediment.inertial_drag"]
LAW_REFERENCE_PATHS = _LAW["code.reference_paths"]


@kernel
def pack_law(p, diameter, reference_paths=True):
    """The sediment law of the drop with parameters ``p``, as a tuple (slots ``LAW_*``).

    Unknown resistance codes fall back to ``delta``; a non-positive N_c to pi + 2
    (Prandtl 1920). The quadrature code (``layout.SEDIMENT_QUADRATURE_NAMES``) and the
    pore-pressure constants of seed 000 eq. (73) ride along, and the regularisation speeds
    of the slip direction (``numerics.slip_speed``) and of the advancing switch
    (``numerics.switch_speed``), and the calibration coefficients: the depth-factor coefficient
    of the ``bearing`` law and the soil's inertial-drag coefficient.

    ``reference_paths`` decides, by its *type*, what is compiled (see
    :func:`.stepper.reference_paths`): ``None`` compiles the fast rule only, ``True`` the
    reference quadrature as well, chosen per drop by the quadrature code
    (:func:`.sediment_tractions`).
    """
    model = int(p[P_SED_RESISTANCE])
    if model < 0 or model > 2:
        model = RES_DELTA
    n0 = p[P_SED_NC]
    if not (n0 > 0.0):
        n0 = math.pi + 2.0  # Prandtl (1920)
    return (
        model,
        int(p[P_SED_RATE_LAW]),
        p[P_SED_A],
        p[P_SED_VREST],
        p[P_SED_BETA],
        p[P_SED_RATE_REF],
        p[P_SED_MU],
        n0,
        diameter,
        p[P_RHO_WATER],
        p[P_GRAVITY],
        p[P_SED_RHO],
        p[P_SED_RHO_GRAD],
        p[P_SED_S],
        p[P_SED_S_GRAD],
        int(p[P_SED_PROFILE]),
        int(p[P_SED_QUADRATURE]),
        p[P_SED_PORE] > 0.0,
        p[P_SED_B],
        p[P_SED_KP],
        p[P_SED_EV],
        p[P_SLIP_SPEED],
        p[P_SWITCH_SPEED],
        p[P_SED_DEPTH_FACTOR],
        p[P_SED_CD],
        reference_paths,
    )


@small_kernel
def _law_properties(zeta, law, bank):
    """(rho_s, S, sigma'_eff) at depth zeta for the packed law (inlined: a call would copy the law
    tuple)."""
    return _properties(
        zeta,
        law[LAW_RHO0],
        law[LAW_KRHO],
        law[LAW_S0],
        law[LAW_KS],
        law[LAW_ROW],
        bank,
        law[LAW_RHO_W],
        law[LAW_G],
    )


@small_kernel
def add_point_traction(acc, wgt, x, y, z, g1, g2, g3):
    """The accumulator ``acc`` = (F1, F2, F3, M1, M2, M3) plus ``wgt`` times the traction
    (g1, g2, g3) at body point (x, y, z) and its moment r x g about the COM (body frame)."""
    f1, f2, f3, m1, m2, m3 = acc
    return (
        f1 + wgt * g1,
        f2 + wgt * g2,
        f3 + wgt * g3,
        m1 + wgt * (y * g3 - z * g2),
        m2 + wgt * (z * g1 - x * g3),
        m3 + wgt * (x * g2 - y * g1),
    )


@small_kernel
def add_weighted(acc, wgt, part):
    """The 6-tuple ``acc`` plus ``wgt`` times the 6-tuple ``part`` (a line's force and torque)."""
    return (
        acc[0] + wgt * part[0],
        acc[1] + wgt * part[1],
        acc[2] + wgt * part[2],
        acc[3] + wgt * part[3],
        acc[4] + wgt * part[4],
        acc[5] + wgt * part[5],
    )
