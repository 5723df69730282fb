"""Post-impact scour burial under waves and currents (issue 20): the closures and one stage kernel.

Pure numba kernels over floats and flat float64 arrays (docs/design.md, Kernels); each cites its
source. The stage (:func:`scour_stage`) grows the burial of a mine lying on a sandy bed from the
burial the impact phase left, over a forcing time series, and reports it at requested lead times.
docs/scour.md describes the model, the choices and what is not yet done.

Burial ``B`` [m] is the depth of the mine's lowest point below the undisturbed (far-field) bed, the
quantity of Rennie, Brandt & Friedrichs (2017) (B/D = 1: the top of a horizontal cylinder is level
with the bed) and the penetration the impact phase reports. Angles are in radians; the wave and
current directions only enter through their difference.
"""

import math

import numpy as np

from mineburial._numba import kernel

#: von Karman's constant (Soulsby 1997, Dynamics of Marine Sands, §3.3: 0.40)
KAPPA = 0.40

# --- status codes of the stage (never raised; the Python side explains them) -----------------------
SCOUR_OK = 0
SCOUR_INVALID_PARAMETER = 1
SCOUR_INVALID_FORCING = 2
SCOUR_BEYOND_FORCING = 3

STATUS_NAMES = ("ok", "invalid_parameter", "invalid_forcing", "beyond_forcing")
STATUS_DESCRIPTIONS = (
    "the stage ran over the whole forcing",
    "a stage parameter was non-finite or outside its documented range (docs/scour.md, Status "
    "codes); nothing was computed",
    "the forcing was not strictly increasing in time, had fewer than two samples, or held a "
    "non-finite or negative value (wave height, current speed), a non-positive period, a depth "
    "below the floor (depth_floor: 10 ks) or not above the current's height; nothing was computed",
    "a requested lead time lies outside the forcing's time span: its burial is NaN (the others are valid)",
)

# --- choices ----------------------------------------------------------------------------------------
#: near-bed orbital velocity from the JONSWAP spectrum (Wiberg & Sherwood 2008), the default
ORBITAL_SPECTRAL = 0
#: monochromatic linear wave with H = H_rms = Hs / sqrt(2) and T = Tp
ORBITAL_HRMS = 1
#: monochromatic linear wave with H = Hs and T = Tp (an upper bound, ~40 % above ORBITAL_HRMS)
ORBITAL_HS = 2
#: wave friction factor of Swart (1974), the default
FRICTION_SWART = 0
#: wave friction factor of Soulsby (1997)
FRICTION_SOULSBY = 1

# --- the stage's parameter vector (one flat float64 array; defaults in default_parameters) ---------
#: the slots of the stage's parameter vector, named (issue 33 item 1, issue 36 item 4): a ``[scour]``
#: field's path where the slot holds that field's value (its default, range and units are the
#: schema's, mineburial/systems/mine/scenario_fields.py; a choice as its code; a field in days as seconds),
#: ``derived.*`` a value the run computes for each drop (its impact, body and water), ``code.*`` a
#: constant of the code (its value and source in :func:`default_parameters`). The ``S_`` constants
#: below are looked up by name, so a slot added here moves no other; systems/mine/processes/scour.py fills the
#: field slots by name (``NUMERIC``, ``CHOICES`` are derived from these names) and
#: tests/test_scour_layout.py checks that each field slot's default here is the schema's.
PARAM_NAMES = (
    "derived.b0",  # initial burial [m] (from the impact phase)
    "derived.diameter",  # mine diameter D [m]
    "derived.mine_sg",  # mine density / water density [-] (for the mobility parameter)
    "scour.d50",  # median grain size [m]
    "scour.grain_density",  # grain density [kg/m^3]
    "derived.rho_water",  # water density [kg/m^3]
    "derived.nu",  # kinematic viscosity of the water [m^2/s]
    "derived.gravity",  # gravity [m/s^2]
    "scour.cohesive",  # 1: cohesive bed, no scour (docs/scour.md); 0: sand
    "scour.mobile_layer",  # thickness of the mobile sand layer [m] (inf: unlimited)
    "code.ripple_d50",  # d50 [m] at the middle of the blend into the coarse-sand exposure limit
    "scour.beq_a",  # a of B_eq / D = a theta^b (Rennie et al. 2017)
    "scour.beq_b",  # b
    "code.tstar_c",  # c of T* = c KC^m theta^p (the scour.tstar_law preset)
    "code.tstar_m",  # m (the preset)
    "scour.theta_exponent",  # p (the preset's unless given)
    "scour.orbital",  # ORBITAL_SPECTRAL, ORBITAL_HRMS or ORBITAL_HS
    "scour.friction",  # FRICTION_SWART or FRICTION_SOULSBY
    "code.current_z",  # height [m] above the bed of the current speed; <= 0: the speed is the depth mean
    "code.mob_c",  # c of the mobility threshold c (D/k)^p (Rennie et al. 2017)
    "code.mob_p",  # p
    "code.tstar_kc_min",  # smallest KC at which a KC law (m > 0) applies; below it no growth (T = inf)
    "code.mob_burial_max",  # B/D up to which the mine counts as proud for the mobility criterion
    "scour.ripple_exposure",  # coarse sand: height left proud above the ripple crests, in ripple heights
    # issue 33: the scour-and-settle law with memory and the burial-aware mobility (docs/scour.md)
    "scour.burial_law",  # BURIAL_RENNIE (one state) or BURIAL_SCOUR_SETTLE (pit + mine)
    "scour.wave_a",  # a_w of the wave pit S_w/D = a_w KC^m_w (Sumer & Fredsoe 1990: 0.1)
    "scour.wave_kc_exponent",  # m_w (Sumer & Fredsoe 1990: 0.5)
    "scour.infill_days",  # time scale [s] of the pit's infill toward a shallower equilibrium (inf: none)
    "scour.bed_lowering_rate",  # far-field bed lowering rate [m/s], >= 0 (re-exposes the mine)
    "scour.mobility",  # MOBILITY_PROUD (the first version's flag) or MOBILITY_POCKET (burial-aware)
    "scour.mobility_drag",  # drag coefficient of the lying cylinder in the burial-aware criterion
    # issue 33 item 2: the tilt state (docs/scour.md, Tilt: the two ends as states)
    "scour.rest_attitude",  # REST_FLAT (laid flat at lead 0) or REST_IMPACT (the impact's attitude)
    "derived.b0_high",  # REST_IMPACT: depth [m] of the higher end's lowest point at lead 0 (< 0: proud)
    "derived.axis_span",  # REST_IMPACT: axial span L [m] of the mine (tail to nose): sin(tilt) = (B - H)/L
    # issue 36: the body's attitude in the stage (the body protocol's, shapes.Shape.scour_geometry)
    "derived.standing",  # 0: a body lying on its side (the cylinder); 1: a short body standing on its base
    "derived.height",  # STANDING: the body's height [m] above its base (B = height: top level with the bed)
    "derived.flank_angle",  # STANDING: the flank's inclination from the vertical [rad] (0: a vertical wall)
)
N_PARAMS = len(PARAM_NAMES)


def slot(name: str) -> int:
    """The index of the stage parameter ``name`` (:data:`PARAM_NAMES`); KeyError naming it."""
    try:
        return PARAM_NAMES.index(name)
    except ValueError:
        raise KeyError(f"no stage parameter {name!r}; the names: {', '.join(PARAM_NAMES)}") from None


S_B0 = slot("derived.b0")
S_DIAMETER = slot("derived.diameter")
S_MINE_SG = slot("derived.mine_sg")
S_D50 = slot("scour.d50")
S_RHO_GRAIN = slot("scour.grain_density")
S_RHO_WATER = slot("derived.rho_water")
S_NU = slot("derived.nu")
S_G = slot("derived.gravity")
S_COHESIVE = slot("scour.cohesive")
S_MOBILE_LAYER = slot("scour.mobile_layer")
S_RIPPLE_D50 = slot("code.ripple_d50")
S_BEQ_A = slot("scour.beq_a")
S_BEQ_B = slot("scour.beq_b")
S_TSTAR_C = slot("code.tstar_c")
S_TSTAR_M = slot("code.tstar_m")
S_TSTAR_P = slot("scour.theta_exponent")
S_ORBITAL = slot("scour.orbital")
S_FRICTION = slot("scour.friction")
S_CURRENT_Z = slot("code.current_z")
S_MOB_C = slot("code.mob_c")
S_MOB_P = slot("code.mob_p")
S_TSTAR_KC_MIN = slot("code.tstar_kc_min")
S_MOB_BURIAL_MAX = slot("code.mob_burial_max")
S_RIPPLE_EXPOSURE = slot("scour.ripple_exposure")
S_BURIAL_LAW = slot("scour.burial_law")
S_WAVE_A = slot("scour.wave_a")
S_WAVE_KC_EXP = slot("scour.wave_kc_exponent")
S_INFILL_TIME = slot("scour.infill_days")
S_BED_RATE = slot("scour.bed_lowering_rate")
S_MOBILITY = slot("scour.mobility")
S_MOB_CD = slot("scour.mobility_drag")
S_REST_ATTITUDE = slot("scour.rest_attitude")
S_B0_HIGH = slot("derived.b0_high")
S_AXIS_SPAN = slot("derived.axis_span")
S_STANDING = slot("derived.standing")
S_HEIGHT = slot("derived.height")
S_FLANK_ANGLE = slot("derived.flank_angle")

#: burial laws (S_BURIAL_LAW): the first version's single state B relaxing to D a theta^b
#: (Rennie et al. 2017), and the scour-and-settle law (pit depth S and burial B as two states)
BURIAL_RENNIE = 0
BURIAL_SCOUR_SETTLE = 1
#: mobility criteria (S_MOBILITY): the first version's (Rennie et al. 2017 on a rigid bottom,
#: while B/D <= S_MOB_BURIAL_MAX) and the burial-aware pivot criterion (mobility_threshold_pocket)
MOBILITY_PROUD = 0
MOBILITY_POCKET = 1
#: rest attitudes (S_REST_ATTITUDE): the mine laid flat at lead 0 with the impact's buried volume
#: (the first version's, scour_batch.lying_burial), or the impact's own attitude, whose tilt is a
#: state (the two ends' depths) that levels as the pit undermines the higher end (docs/scour.md, Tilt)
REST_FLAT = 0
REST_IMPACT = 1

#: half-width, in phi units (phi = -log2(d50 / 1 mm), Krumbein), of the d50 interval over which the
#: coarse-sand exposure limit blends in around S_RIPPLE_D50: from 0.354 to 0.707 mm about the
#: default 0.5 mm (Wentworth's medium/coarse boundary). Our choice (docs/scour.md, Coarse sand):
#: the sources name fine and coarse sand, not the grain size at which the behaviour changes
RIPPLE_BLEND_PHI = 0.5
#: height of a ripple crest above the undisturbed (mean) bed, in ripple heights: a ripple
#: symmetric about the mean bed level (crest eta/2 above it, trough eta/2 below)
RIPPLE_CREST = 0.5

#: the depth must be at least this many Nikuradse roughnesses ks = 2.5 d50 (docs/scour.md)
DEPTH_MIN_OVER_KS = 10.0

#: T* = c KC^m theta^p presets (c, m, p, kc_min); sources in docs/scour.md. kc_min is the smallest
#: KC at which a KC law (m > 0) applies: below it (no waves included) it gives no growth. The
#: pile-in-current law (1/2000)(delta/D) theta^-2.2 is :func:`pile_current_tstar`.
TSTAR_LAWS = {
    # Whitehouse (1998), quoted in sources.md §3: T* = 0.014 theta^-1.29
    "whitehouse": (0.014, 0.0, -1.29, 0.0),
    # pipelines (Fredsoe, Sumer & Arnskov 1992, "Time scale for wave/current scour below
    # pipelines"): T* = (1/50) theta^-5/3, for currents and waves alike, KC entering only the
    # equilibrium depth (S/D = 0.1 sqrt(KC) in waves) [unverified: as recalled by the review and
    # by us; the KC^1.5 factor once coded here was found in no source, so m = 0]
    "pipeline": (1.0 / 50.0, 0.0, -5.0 / 3.0, 0.0),
    # piles in waves (Sumer, Christiansen & Fredsoe 1992): T* = 1e-6 (KC/theta)^3, quoted for
    # 0.07 <= theta <= 0.19, 7 <= KC <= 34: applied from KC = 7 (no growth below), extrapolated
    # above KC = 34 and outside the theta range (docs/scour.md)
    "pile_waves": (1.0e-6, 3.0, -3.0, 7.0),
}


def pile_current_tstar(delta_over_d):
    """(c, m, p, kc_min) of the pile-in-current law T* = (1/2000)(delta/D) theta^-2.2 (Sumer,
    Christiansen & Fredsoe 1992, as quoted in sources.md §3), delta the boundary-layer thickness."""
    return (delta_over_d / 2000.0, 0.0, -2.2, 0.0)


def default_parameters(**overrides):
    """The stage's parameter vector with its documented defaults (docs/scour.md), keys by name
    (``b0``, ``diameter``, ...: the ``S_`` constants in lower case)."""
    p = np.empty(N_PARAMS)
    p[S_B0] = 0.0
    p[S_DIAMETER] = 0.53
    p[S_MINE_SG] = 1.5
    p[S_D50] = 2.0e-4
    p[S_RHO_GRAIN] = 2650.0  # quartz
    p[S_RHO_WATER] = 1027.0  # sea water, 10 C, 35 ppt (Soulsby 1997, Table 2)
    p[S_NU] = 1.36e-6  # idem
    p[S_G] = 9.81
    p[S_COHESIVE] = 0.0
    p[S_MOBILE_LAYER] = math.inf
    p[S_RIPPLE_D50] = 5.0e-4  # Wentworth: coarse sand from 0.5 mm (the blend's middle)
    p[S_BEQ_A] = 1.3  # Rennie et al. 2017, D > 8 cm
    p[S_BEQ_B] = 0.36
    p[S_TSTAR_C], p[S_TSTAR_M], p[S_TSTAR_P], p[S_TSTAR_KC_MIN] = TSTAR_LAWS["whitehouse"]
    p[S_ORBITAL] = ORBITAL_SPECTRAL
    p[S_FRICTION] = FRICTION_SWART
    p[S_CURRENT_Z] = 0.0
    p[S_MOB_C] = 1.6  # Rennie et al. 2017
    p[S_MOB_P] = -0.72
    p[S_MOB_BURIAL_MAX] = 0.1  # our choice (docs/scour.md): the criterion is for a proud object
    # Traykovski et al. 2007 (IEEE JOE 32(1):150, abstract): in coarse sand "mines were observed to
    # bury until the exposed height above the ripple crests was approximately the same as the large
    # wave orbital ripple height"
    p[S_RIPPLE_EXPOSURE] = 1.0
    p[S_BURIAL_LAW] = BURIAL_RENNIE  # the first version's law: existing scenarios keep their answers
    # Sumer & Fredsoe (1990; 2002, ch. 3, live-bed scour below pipelines in waves): S/D = 0.1 KC^0.5
    p[S_WAVE_A] = 0.1
    p[S_WAVE_KC_EXP] = 0.5
    p[S_INFILL_TIME] = 5.0 * 86400.0  # judgement, docs/scour.md (Infill): field pits fill in days-weeks
    p[S_BED_RATE] = 0.0
    p[S_MOBILITY] = MOBILITY_PROUD
    # a circular cylinder in cross-flow at subcritical Reynolds number, about 1.2 (Sumer & Fredsoe
    # 2006, Hydrodynamics around Cylindrical Structures, ch. 2, as recalled)
    p[S_MOB_CD] = 1.2
    p[S_REST_ATTITUDE] = REST_FLAT  # the first version's: existing scenarios keep their answers
    p[S_B0_HIGH] = 0.0
    p[S_AXIS_SPAN] = 1.0
    p[S_STANDING] = 0.0  # the lying cylinder (the first version's): existing scenarios keep their answers
    p[S_HEIGHT] = 0.53  # unused while lying (the lying body's height is its diameter)
    p[S_FLANK_ANGLE] = 0.0
    for key, value in overrides.items():
        p[globals()["S_" + key.upper()]] = value
    return p


# --- wave dispersion ----------------------------------------------------------------------------------


@kernel
def kh_soulsby(omega, h, g):
    """kh from the explicit approximation of Soulsby (1997, Dynamics of Marine Sands, §3.4):
    with xi = omega^2 h / g, kh = sqrt(xi) (1 + 0.2 xi) for xi <= 1 and kh = xi (1 + 0.2 exp(2 - 2 xi))
    for xi > 1; stated accuracy about 1 % (checked against the exact root in tests/test_scour.py)."""
    xi = omega * omega * h / g
    if xi <= 1.0:
        return math.sqrt(xi) * (1.0 + 0.2 * xi)
    return xi * (1.0 + 0.2 * math.exp(2.0 - 2.0 * xi))


@kernel
def kh_exact(omega, h, g):
    """kh, the root of the linear dispersion relation omega^2 = g k tanh(kh), by Newton's method
    on f(y) = y tanh(y) - xi = 0 (xi = omega^2 h / g). f is increasing (f' = tanh y + y sech^2 y
    > 0) but not convex everywhere (f'' = 2 sech^2 y (1 - y tanh y) < 0 where y tanh y > 1), so
    convergence rests on the start: Soulsby's explicit approximation, within 1 % of the root, where
    Newton converges quadratically (machine precision in a few steps; checked against brentq to
    1e-13 for xi from 5e-3 to 2e3 in tests/test_scour.py). NaN for a non-positive xi."""
    xi = omega * omega * h / g
    if not xi > 0.0:
        return math.nan
    y = kh_soulsby(omega, h, g)
    for _ in range(60):
        t = math.tanh(y)
        dy = (y * t - xi) / (t + y * (1.0 - t * t))
        y -= dy
        if abs(dy) <= 1e-15 * y:
            break
    return y


# --- near-bed orbital velocity ------------------------------------------------------------------------


@kernel
def orbital_monochromatic(height, period, h, g):
    """Amplitude of the near-bed orbital velocity of a linear monochromatic wave,
    U = pi H / (T sinh kh) (linear wave theory; Soulsby 1997 §3.4; Wiberg & Sherwood 2008)."""
    kh = kh_exact(2.0 * math.pi / period, h, g)
    return math.pi * height / (period * math.sinh(kh))


#: JONSWAP shape (Hasselmann et al. 1973) as in Wiberg & Sherwood (2008), ubspecpar: gamma = 3.3,
#: sigma = 0.07 below the peak, 0.09 above, on the grid f/fp = 0.2 ... 5 in steps of 0.01
JONSWAP_GAMMA = 3.3
SPEC_X0 = 0.2
SPEC_DX = 0.01
SPEC_NX = 481
#: the orbital table covers tau = sqrt(h/g) / Tp in [0, TAU_MAX]; beyond, u_br is below 1e-9 Hs/Tn
TAU_MAX = 1.0
TABLE_N = 2001


@kernel
def jonswap_shape(x):
    """JONSWAP spectral shape in x = f/fp, unnormalised: x^-5 exp(-1.25 x^-4) gamma^r,
    r = exp(-(x - 1)^2 / (2 sigma^2)) (Hasselmann et al. 1973), as in Wiberg & Sherwood (2008), ubspecpar."""
    sigma = 0.07 if x <= 1.0 else 0.09
    r = math.exp(-((x - 1.0) ** 2) / (2.0 * sigma * sigma))
    return x**-5 * math.exp(-1.25 * x**-4) * JONSWAP_GAMMA**r


@kernel
def spectral_orbital_factors(tau):
    """(F, G) of the JONSWAP near-bed velocity: u_br = F Hs / Tn and T_br = G Tp, with
    tau = Tn / Tp, Tn = sqrt(h/g).

    Wiberg & Sherwood (2008; their code ubspecpar, csdms-contrib/oceanwaves): the surface
    spectrum S(f), scaled to m0 = Hs^2/16, is transferred to the bed with (2 pi f / sinh kh)^2;
    u_br = sqrt(2 int S_u df) and T_br = int S_u df / int f S_u df. With x = f/fp, kh(x) solves
    the dispersion relation at xi = (2 pi x tau)^2, so both depend on tau only. The integrals
    are trapezoidal sums on W&S's fixed grid of x (they use rectangle sums on the same grid).
    """
    i0 = 0.0
    i2 = 0.0
    i3 = 0.0
    for j in range(SPEC_NX):
        x = SPEC_X0 + j * SPEC_DX
        w = 0.5 if j == 0 or j == SPEC_NX - 1 else 1.0
        s = jonswap_shape(x)
        if tau > 0.0:
            arg = 2.0 * math.pi * x * tau
            kh = kh_exact(arg, 1.0, 1.0)  # xi = arg^2
            transfer = (arg / math.sinh(kh)) ** 2 if kh < 700.0 else 0.0
        else:
            transfer = 1.0  # shallow-water limit: 2 pi x tau / sinh(kh) -> 1
        i0 += w * s
        i2 += w * s * transfer
        i3 += w * x * s * transfer
    f = math.sqrt(2.0) / 4.0 * math.sqrt(i2 / i0)
    return f, (i2 / i3 if i3 > 0.0 else math.nan)


@kernel
def build_orbital_table():
    """(2, TABLE_N) table of (F, G) of :func:`spectral_orbital_factors` on tau = 0 ... TAU_MAX;
    built once per run (about 1e6 kernel evaluations) and shared by every drop."""
    table = np.empty((2, TABLE_N))
    for i in range(TABLE_N):
        f, g_ = spectral_orbital_factors(TAU_MAX * i / (TABLE_N - 1))
        table[0, i] = f
        table[1, i] = g_
    return table


@kernel
def orbital_spectral(hs, tp, h, g, table):
    """(u_br, T_br): representative near-bed orbital velocity amplitude and period of a JONSWAP sea
    (Wiberg & Sherwood 2008), by linear interpolation in the table of :func:`build_orbital_table`.
    Beyond TAU_MAX (deep water for the period) u_br = 0 and T_br = G(TAU_MAX) Tp."""
    tn = math.sqrt(h / g)
    pos = (tn / tp) / TAU_MAX * (TABLE_N - 1)
    if pos >= TABLE_N - 1:
        return 0.0, table[1, TABLE_N - 1] * tp
    i = int(pos)
    w = pos - i
    f = table[0, i] + w * (table[0, i + 1] - table[0, i])
    g_ = table[1, i] + w * (table[1, i + 1] - table[1, i])
    return f * hs / tn, g_ * tp


# --- bed shear stresses -------------------------------------------------------------------------------


@kernel
def friction_swart(a_over_ks):
    """Wave friction factor of Swart (1974) in its simplified form f_w = 0.00251 exp(5.21
    (A/ks)^-0.19) for A/ks > 1.57, else 0.3 (as coded in ScientiMate ``wavebedstress``;
    sources.md §3; van der A et al. 2013, Coastal Eng. 76, App. A, put the branch at 1.587).
    Swart's original form exp(5.213 (A/ks)^-0.194 - 5.977) is 1.9 % below it at A/ks = 10 and
    2.8 % at 100. The branches meet at A/ks = 1.57 to 0.14 % (0.29957 against 0.3)."""
    if a_over_ks <= 1.57:
        return 0.3
    return 0.00251 * math.exp(5.21 * a_over_ks**-0.19)


@kernel
def friction_soulsby(a_over_z0):
    """Wave friction factor of Soulsby (1997, eq. 62a): f_w = 1.39 (A/z0)^-0.52 (rough turbulent)."""
    return 1.39 * a_over_z0**-0.52


@kernel
def wave_stress(ub, tb, d50, rho, friction):
    """Wave skin-friction stress amplitude tau_w = 0.5 rho f_w U^2 (Soulsby 1997 eq. 57), with the
    orbital excursion A = U T / (2 pi), Nikuradse grain roughness ks = 2.5 d50 and z0 = ks/30
    (Soulsby 1997 eqs. 25-26)."""
    if ub <= 0.0:
        return 0.0
    a = ub * tb / (2.0 * math.pi)
    ks = 2.5 * d50
    if friction == FRICTION_SOULSBY:
        fw = friction_soulsby(a / (ks / 30.0))
    else:
        fw = friction_swart(a / ks)
    return 0.5 * rho * fw * ub * ub


@kernel
def current_stress(u, z, h, d50, rho):
    """Current skin-friction stress from a logarithmic profile with z0 = ks/30 = d50/12 (Nikuradse
    ks = 2.5 d50; Soulsby 1997 eqs. 25-26, 30): a speed u at height z > 0 above the bed gives
    u* = kappa u / ln(z/z0); a depth-mean speed (z <= 0) gives tau = rho C_D u^2 with
    C_D = [kappa / (ln(h/z0) - 1)]^2 (Soulsby 1997 eq. 36-37). Valid for ks <= z < h and
    h >= DEPTH_MIN_OVER_KS ks (ln(z/z0) <= 0 or h <= e z0 would give an infinite or negative
    stress): the stage checks both (parameters_valid, forcing_valid) before calling it."""
    z0 = d50 / 12.0
    if z > 0.0:
        ustar = KAPPA * u / math.log(z / z0)
        return rho * ustar * ustar
    cd = (KAPPA / (math.log(h / z0) - 1.0)) ** 2
    return rho * cd * u * u


@kernel
def combined_stress(tau_c, tau_w, phi):
    """(tau_m, tau_max) of waves and a current at angle phi: the mean stress
    tau_m = tau_c [1 + 1.2 (tau_w / (tau_c + tau_w))^3.2] and the peak
    tau_max = sqrt((tau_m + tau_w |cos phi|)^2 + (tau_w sin phi)^2) (Soulsby 1997 eqs. 69-70, his
    fit to the DATA13 method of Soulsby 1995; equation numbers as recalled). |cos phi| rather than
    cos phi: the wave stress reverses every half period, and of the two half-cycle peaks
    (tau_m +- tau_w cos phi along the current) the larger is taken, so phi and phi + pi agree."""
    total = tau_c + tau_w
    if total <= 0.0:
        return 0.0, 0.0
    tau_m = tau_c * (1.0 + 1.2 * (tau_w / total) ** 3.2)
    c = abs(math.cos(phi))
    s = math.sin(phi)
    return tau_m, math.sqrt((tau_m + tau_w * c) ** 2 + (tau_w * s) ** 2)


# --- sediment motion ----------------------------------------------------------------------------------


@kernel
def shields(tau, rho, s, g, d50):
    """Shields parameter theta = tau / (rho (s - 1) g d50) (Soulsby 1997 eq. 74)."""
    return tau / (rho * (s - 1.0) * g * d50)


@kernel
def grain_size_number(d50, s, g, nu):
    """Dimensionless grain size D* = d50 [g (s - 1) / nu^2]^(1/3) (Soulsby 1997 eq. 75)."""
    return d50 * (g * (s - 1.0) / (nu * nu)) ** (1.0 / 3.0)


@kernel
def shields_threshold(dstar):
    """Threshold of motion theta_cr = 0.30 / (1 + 1.2 D*) + 0.055 [1 - exp(-0.020 D*)]
    (Soulsby & Whitehouse 1997; Soulsby 1997 eq. 77)."""
    return 0.30 / (1.0 + 1.2 * dstar) + 0.055 * (1.0 - math.exp(-0.020 * dstar))


@kernel
def ripple_steepness_height(d0, lam):
    """Ripple height eta of wavelength lam under an orbital diameter d0 from the steepness law of
    Wiberg & Harris (1994): eta/lam = exp[-0.095 L^2 + 0.442 L - 2.28], L = ln(d0/eta),
    solved in closed form (Malarkey & Davies 2003): with eta = d0 exp(-L) it reads
    0.095 L^2 - 1.442 L + ln(d0/lam) + 2.28 = 0, whose smaller root is the ripple. No real root
    (d0/lam > ~24): the ripples are washed out, NaN."""
    c = math.log(d0 / lam) + 2.28
    disc = 1.442 * 1.442 - 4.0 * 0.095 * c
    if disc < 0.0:
        return math.nan
    return d0 * math.exp(-(1.442 - math.sqrt(disc)) / (2.0 * 0.095))


@kernel
def ripple_height(d0, d50):
    """Wave-ripple height [m] after Wiberg & Harris (1994) in the non-iterative form of Malarkey &
    Davies (2003): orbital ripples lam = 0.62 d0, anorbital lam = 535 d50; the anorbital height
    eta_ano decides the regime (d0/eta_ano < 20 orbital, > 100 anorbital, suborbital between, lam
    interpolated in log space); the height then follows from the steepness law. NaN where no
    ripple exists (d0 <= 0 or washed out)."""
    if not d0 > 0.0:
        return math.nan
    lam_orb = 0.62 * d0
    lam_ano = 535.0 * d50
    eta_ano = ripple_steepness_height(d0, lam_ano)
    r = d0 / eta_ano if eta_ano > 0.0 else math.inf
    if r < 20.0:
        lam = lam_orb
    elif r > 100.0:
        lam = lam_ano
    else:
        w = (math.log(r) - math.log(100.0)) / (math.log(20.0) - math.log(100.0))
        lam = math.exp(w * (math.log(lam_orb) - math.log(lam_ano)) + math.log(lam_ano))
    return ripple_steepness_height(d0, lam)


# --- burial law ----------------------------------------------------------------------------------------


@kernel
def equilibrium_burial(theta, diameter, a, b):
    """Equilibrium scour burial B_eq = D a theta^b (Rennie, Brandt & Friedrichs 2017, Ocean Eng.
    131:282, live-bed scour; a ~ 1.3, b ~ 0.36 for D > 8 cm; a ~ 15, b ~ 1.1 for D < 3 cm or
    tapered objects)."""
    return diameter * a * theta**b


@kernel
def scour_time_scale(theta, kc, diameter, d50, s, g, c, m, p, kc_min):
    """Time scale T = T* D^2 / sqrt(g (s - 1) d50^3) with T* = c KC^m theta^p (Sumer & Fredsoe
    2002, ch. 3-4; Whitehouse 1998: c = 0.014, m = 0, p = -1.29; presets in TSTAR_LAWS).

    A KC law (m > 0) is a law for waves: below kc_min (> 0, the lower edge of its range; KC = 0
    without waves) it gives no wave-driven growth, T = inf, rather than T -> 0 (an immediate
    equilibrium). Choose a law with m = 0 for current-dominated forcing (docs/scour.md)."""
    tstar = c * theta**p
    if m != 0.0:
        if not kc >= kc_min:
            return math.inf
        tstar *= kc**m
    return tstar * diameter * diameter / math.sqrt(g * (s - 1.0) * d50**3)


@kernel
def relax_burial(b, b_eq, dt, t_scale):
    """Burial after dt under constant forcing: the exact solution of dB/dt = (B_eq - B)/T,
    B_eq - (B_eq - B) exp(-dt/T), applied only while B < B_eq (burial never decreases); T = inf
    leaves B as it is."""
    if b_eq <= b or t_scale == math.inf:
        return b
    if not t_scale > 0.0:
        return b_eq
    return b_eq - (b_eq - b) * math.exp(-dt / t_scale)


@kernel
def time_to_reach(b, b_eq, target, t_scale):
    """Time [s] for the relaxation of :func:`relax_burial` to bring B to ``target``: 0 if B is there
    already, T ln((B_eq - B) / (B_eq - target)) if B_eq > target, inf otherwise."""
    if b >= target:
        return 0.0
    if b_eq <= target:
        return math.inf
    if not t_scale > 0.0:
        return 0.0
    return t_scale * math.log((b_eq - b) / (b_eq - target))


@kernel
def mobility_threshold(diameter, k, c, p):
    """Critical object mobility parameter Theta_Ucrit = c (D/k)^p, c ~ 1.6, p ~ -0.72, for
    cylinders under currents and waves resting on a rigid bottom of roughness k (Rennie et al.
    2017, abstract: "onset of motion on a rigid bottom", "object diameter-to-bottom roughness
    ratios (D/k)"); the stage applies it only while the mine is proud (docs/scour.md)."""
    return c * (diameter / k) ** p


@kernel
def mobility_parameter(u, diameter, mine_sg, g):
    """Object mobility parameter Theta_U = U^2 / (g D (s_obj - 1)) (Rennie et al. 2017)."""
    return u * u / (g * diameter * (mine_sg - 1.0))


# --- the scour-and-settle law with memory (issue 33 items 2 and 3; docs/scour.md, Scour and settle) -


@kernel
def onset_factor(theta, theta_cr):
    """Factor that takes an equilibrium scour depth smoothly to zero at the threshold of motion:
    1 - theta_cr/theta above it, 0 at or below it. Our smoothing choice (docs/scour.md, Scour and
    settle): the excess-stress form of the bed-load laws (Meyer-Peter & Mueller 1948: transport
    grows from zero with theta - theta_cr), continuous at the threshold and -> 1 in live-bed
    conditions (theta >> theta_cr), where the laws below were fitted."""
    if not theta > theta_cr:
        return 0.0
    return 1.0 - theta_cr / theta


@kernel
def current_ratio(uc, uw):
    """U_cw = U_c / (U_c + U_w), the current's share of the near-bed velocity (Sumer & Fredsoe
    2001, scour in combined waves and current); 0 with no flow at all."""
    total = uc + uw
    if not total > 0.0:
        return 0.0
    return uc / total


@kernel
def pit_equilibrium(theta, theta_cr, kc, ucw, diameter, a, b, aw, mw):
    """Equilibrium depth [m] of the scour pit beside a lying cylinder below the far-field bed:
    D f(theta) [(1 - U_cw) a_w KC^m_w + U_cw a theta^b], f = :func:`onset_factor`.

    Waves (U_cw = 0): S/D = a_w KC^m_w, live-bed scour below pipelines in waves (Sumer & Fredsoe
    1990, J. Waterway Port Coastal Ocean Eng. 116(3), S/D = 0.1 KC^0.5; Sumer & Fredsoe 2002,
    The Mechanics of Scour in the Marine Environment, ch. 3), the KC growth that the short-cylinder
    experiments under waves also show (Catano-Lopera & Garcia 2006; Demir & Garcia 2007) [their own
    coefficients not verified here: a_w and m_w are sampled with priors covering them]. Currents
    (U_cw = 1): B_eq/D = a theta^b (Rennie, Brandt & Friedrichs 2017). Combined: weighted by the
    current's share U_cw (our choice, the weight of Sumer & Fredsoe 2001's combined pile law)."""
    f = onset_factor(theta, theta_cr)
    if f == 0.0:
        return 0.0
    s_w = aw * kc**mw if kc > 0.0 else 0.0
    s_c = a * theta**b
    return diameter * f * ((1.0 - ucw) * s_w + ucw * s_c)


@kernel
def capped_target(p, s_eq, full, theta, theta_cr, ub, tb, kc):
    """(S_eq, T) from an uncapped equilibrium ``s_eq`` [m]: capped by full burial ``full`` [m] (the
    lying body's diameter, the standing body's height), the mobile layer and, in coarse sand, the
    exposure limit above the ripples (:func:`exposure_limit` of ``full``), with the section's time
    scale (:func:`scour_time_scale` of the diameter, KC ``kc``); no sediment moving: T = inf (no
    scour; the infill has its own time scale)."""
    d50 = p[S_D50]
    s_eq = min(min(s_eq, full), p[S_MOBILE_LAYER])
    w = coarse_weight(d50, p[S_RIPPLE_D50])
    if w > 0.0:
        eta = ripple_height(ub * tb / math.pi, d50)
        if eta >= 0.0:
            s_eq = min(s_eq, exposure_limit(full, eta, p[S_RIPPLE_EXPOSURE], w))
    if not theta > theta_cr:
        return s_eq, math.inf
    s = p[S_RHO_GRAIN] / p[S_RHO_WATER]
    t_scale = scour_time_scale(
        theta, kc, p[S_DIAMETER], d50, s, p[S_G], p[S_TSTAR_C], p[S_TSTAR_M], p[S_TSTAR_P], p[S_TSTAR_KC_MIN]
    )
    return s_eq, t_scale


@kernel
def pit_target(p, theta, theta_cr, ub, tb, uc):
    """(S_eq, T) of the scour-and-settle law for one forcing sample: :func:`pit_equilibrium` with
    the caps of :func:`burial_target` (full burial D, the mobile layer, the coarse-sand exposure
    limit) and its time scale (:func:`scour_time_scale`, the section's T* law). A cohesive bed:
    (0, inf), no scour."""
    diameter = p[S_DIAMETER]
    if p[S_COHESIVE] != 0.0:
        return 0.0, math.inf
    kc = ub * tb / diameter
    ucw = current_ratio(uc, ub)
    s_eq = pit_equilibrium(
        theta, theta_cr, kc, ucw, diameter, p[S_BEQ_A], p[S_BEQ_B], p[S_WAVE_A], p[S_WAVE_KC_EXP]
    )
    return capped_target(p, s_eq, diameter, theta, theta_cr, ub, tb, kc)


# --- a short body standing on its base (issue 36: a Manta-like frustum; docs/scour.md, Standing body) ----

#: S/D of local scour at a vertical pile in a steady current, live bed (Sumer, Fredsoe & Christiansen
#: 1992, J. Waterway Port Coastal Ocean Eng. 118(1); Breusers, Nicollet & Shen 1977, J. Hydraul. Res.
#: 15(3)); the KC -> infinity limit of :func:`pile_scour_ratio`
PILE_CURRENT_RATIO = 1.3
#: the flank's inclination [deg] and the factor on the scour depth of a vertical pile: Al-Awadi 2021
#: (Math. Model. Eng. Probl. 8(5):787, abstract), piers inclined downstream at 10, 16 and 22 deg scour
#: about 5, 10 and 15 % less than the vertical pier near the threshold (V/Vc = 0.989, clear water,
#: d50 0.72 mm). The upstream face of a frustum standing on its base leans downstream by its half-angle.
FLANK_DEG = (0.0, 10.0, 16.0, 22.0)
FLANK_FACTOR = (1.0, 0.95, 0.90, 0.85)


@kernel
def pile_scour_ratio(kc, ucw):
    """S/D of local scour at a vertical pile in combined waves and current (Sumer & Fredsoe 2001,
    J. Hydraul. Eng. 127(5):403, as quoted in sources.md section 3 and coded in pyCoastal
    ``scour_ratio_combined``): 1.3 {1 - exp[-A (KC - B)]} for KC > B, else 0, with A = 0.03 + 0.75
    U_cw^2.6 and B = 6 exp(-4.7 U_cw). U_cw = 0 is the waves-only law of Sumer, Fredsoe &
    Christiansen (1992), no scour below KC = 6 (no horseshoe vortex)."""
    a = 0.03 + 0.75 * ucw**2.6
    b = 6.0 * math.exp(-4.7 * ucw)
    if not kc > b:
        return 0.0
    return PILE_CURRENT_RATIO * (1.0 - math.exp(-a * (kc - b)))


@kernel
def flank_factor(angle):
    """Factor <= 1 on a vertical pile's scour depth for a flank inclined ``angle`` [rad] from the
    vertical: linear between the published points FLANK_DEG / FLANK_FACTOR (Al-Awadi 2021), held at
    the last (0.85 at 22 deg) beyond them: no extrapolation past the measured range (our choice,
    docs/scour.md)."""
    deg = math.degrees(angle)
    if not deg > 0.0:
        return 1.0
    for k in range(1, len(FLANK_DEG)):
        if deg <= FLANK_DEG[k]:
            w = (deg - FLANK_DEG[k - 1]) / (FLANK_DEG[k] - FLANK_DEG[k - 1])
            return FLANK_FACTOR[k - 1] + w * (FLANK_FACTOR[k] - FLANK_FACTOR[k - 1])
    return FLANK_FACTOR[len(FLANK_FACTOR) - 1]


@kernel
def standing_equilibrium(theta, theta_cr, kc, ucw, theta_c, diameter, angle):
    """Equilibrium depth [m] of the local scour at the foot of a short body standing on its base of
    diameter ``diameter`` (its horseshoe vortex; docs/scour.md, Standing body):
    D K(angle) max(f(theta) S/D(KC, U_cw), f(theta_c) 1.3), f = :func:`onset_factor`.

    S/D is the pile law in waves and current (:func:`pile_scour_ratio`), taken without a height
    factor: the scour depth at a submerged cylinder's upstream edge does not depend on its height
    for h/D < 2 (Zhao, Cheng & Zang 2010, Coastal Eng. 57:709, abstract). The second term is the
    current's own scour, the steady-current pile value 1.3 (Sumer et al. 1992) where the current
    alone (Shields parameter ``theta_c``) moves the bed: the KC of the combined law is the waves',
    so small waves on a strong current would give almost none (pyCoastal's floor, an addition to the
    published law). K is :func:`flank_factor`; the onset factor takes it to zero at the threshold
    of motion, as the scour-and-settle pit (our choice, docs/scour.md)."""
    s_wc = onset_factor(theta, theta_cr) * pile_scour_ratio(kc, ucw)
    s_c = onset_factor(theta_c, theta_cr) * PILE_CURRENT_RATIO
    return diameter * flank_factor(angle) * max(s_wc, s_c)


@kernel
def standing_target(p, theta, theta_cr, ub, tb, uc, theta_c):
    """(S_eq, T) of one forcing sample for a body standing on its base: :func:`standing_equilibrium`
    capped by full burial (the body's height: its top level with the bed), the mobile layer and, in
    coarse sand, the exposure limit above the ripples (:func:`exposure_limit` of the height), with
    the section's time scale (:func:`scour_time_scale` of the base diameter, KC = U_w T_w / D). A
    cohesive bed: (0, inf)."""
    diameter = p[S_DIAMETER]
    height = p[S_HEIGHT]
    if p[S_COHESIVE] != 0.0:
        return 0.0, math.inf
    kc = ub * tb / diameter
    ucw = current_ratio(uc, ub)
    s_eq = standing_equilibrium(theta, theta_cr, kc, ucw, theta_c, diameter, p[S_FLANK_ANGLE])
    return capped_target(p, s_eq, height, theta, theta_cr, ub, tb, kc)


@kernel
def relax_pit(s, s_eq, dt, t_grow, t_fill):
    """Pit depth after dt under constant forcing, the exact solution of dS/dt = (S_eq - S)/T with
    T = t_grow while S < S_eq (scour: :func:`relax_burial`) and T = t_fill while S > S_eq (infill
    toward the shallower equilibrium, 0 in calm: the ambient bed). An infinite T leaves S."""
    if s < s_eq:
        return relax_burial(s, s_eq, dt, t_grow)
    if s > s_eq and t_fill < math.inf:
        return s_eq + (s - s_eq) * math.exp(-dt / t_fill)
    return s


@kernel
def settled_burial(b_self, s, dt, rate):
    """The mine's burial [m] after dt: its own burial lowered by the far-field bed lowering
    ``rate`` dt (re-exposure; the mine rests on the bed, so never above it: >= 0), and at least the
    pit depth ``s`` beside it (scour and settle: a mine whose pit is deeper than its burial rolls
    or slumps into it, Whitehouse 1998; Trembanis et al. 2007; Friedrichs et al. 2016). Infill
    never lifts it."""
    return max(max(b_self - rate * dt, 0.0), s)


@kernel
def pocket_tangent(burial_fraction):
    """tan(alpha) of the pivot angle of a lying cylinder held in a depression of depth B = f D:
    it must roll over the lip, a step of height B, whose contact point sets cos(alpha) =
    (R - B)/R = 1 - 2f (the pivot-angle geometry of Wiberg & Smith 1987 for a grain on its
    neighbours, applied to the mine in its bed). 0 for f <= 0, inf for f >= 1/2 (the lip at or
    above the centre: no rolling out)."""
    if not burial_fraction > 0.0:
        return 0.0
    if burial_fraction >= 0.5:
        return math.inf
    c = 1.0 - 2.0 * burial_fraction
    return math.sqrt(1.0 - c * c) / c


@kernel
def mobility_threshold_pocket(theta_rigid, burial_fraction, cd):
    """Critical object mobility parameter of a partly buried lying cylinder: the larger of the
    rigid-bottom value of Rennie et al. (2017) and the moment balance about the lip of its
    depression, drag 1/2 rho C_D U^2 (D - B) L on the exposed height (arm R cos alpha) against the
    submerged weight (rho_m - rho) g pi D^2/4 L (arm R sin alpha): U^2/(g D (s - 1)) > (pi/(2 C_D))
    tan(alpha)/(1 - B/D). Our derivation (docs/scour.md, Mobility); it rises from the rigid-bottom
    value at B = 0 and is infinite from B = D/2, as partly buried munitions in flume tests needed
    much stronger flow to move (Menzel et al. 2022, qualitative)."""
    tan_a = pocket_tangent(burial_fraction)
    if tan_a == math.inf or burial_fraction >= 1.0:
        return math.inf
    return max(theta_rigid, math.pi / (2.0 * cd) * tan_a / (1.0 - burial_fraction))


@kernel
def is_mobile(p, u, b, theta_mob, b_proud):
    """Whether the mine at burial ``b`` [m] moves under the near-bed speed ``u``: the object
    mobility parameter above the criterion S_MOBILITY selects (:data:`MOBILITY_PROUD`: the
    rigid-bottom threshold while B <= b_proud; :data:`MOBILITY_POCKET`:
    :func:`mobility_threshold_pocket`)."""
    diameter = p[S_DIAMETER]
    theta_u = mobility_parameter(u, diameter, p[S_MINE_SG], p[S_G])
    if p[S_MOBILITY] == MOBILITY_POCKET:
        return theta_u > mobility_threshold_pocket(theta_mob, b / diameter, p[S_MOB_CD])
    return b <= b_proud and theta_u > theta_mob


# --- the tilt state: the two ends of the mine (issue 33 item 2; docs/scour.md, Tilt) ---------------


@kernel
def settled_high_end(b, h, s, dt, rate):
    """Depth [m] below the far-field bed of the higher end's lowest point after dt, the mine's
    lowest point (the deeper end) following :func:`settled_burial`. Both ends fall with the bed
    (``rate`` dt, the tilt kept). Then: a pit at least as deep as the lower end, ``s >= max(B -
    rate dt, 0)``, has undermined the whole mine, which lies in it, both ends at ``s`` (the mines
    "fell into their own scour pits ... and became level", Traykovski et al. 2007; "mine roll into
    the resulting pit", Baeye et al. 2011; a lower end lowered to the bed itself, B = 0 = s, leaves
    nothing embedded: the mine lies on the bed); else an end that
    rests in the sand (H >= 0) settles into the pit beside it, max(H, s) (Whitehouse 1998; Trembanis
    et al. 2007; Friedrichs et al. 2016: scour and settle, applied to each end), so the mine levels
    about its lower end as the pit passes the higher; a proud end (H < 0, held up by the embedded
    one) stays. Our geometric choice; infill never lifts an end."""
    bl = max(b - rate * dt, 0.0)
    if s >= bl:
        return s
    hl = h - rate * dt
    if hl >= 0.0:
        return max(hl, s)
    return hl


@kernel
def tilt_sine(b, h, span):
    """sin of the tilt of the axis to the horizontal from the depths of the two ends' lowest
    points: (B - H)/L, in [0, 1]."""
    return min(max((b - h) / span, 0.0), 1.0)


@kernel
def mean_clipped_linear(y0, y1):
    """Mean over [0, 1] of clip(y, 0, 1) for y linear from y0 to y1 (exact, piecewise)."""
    if y0 == y1:
        return min(max(y0, 0.0), 1.0)
    lo = min(y0, y1)
    hi = max(y0, y1)
    w = hi - lo
    # length-weighted: the part below 0 counts 0, above 1 counts 1, between the mean of the line
    a = max(lo, 0.0)
    e = min(hi, 1.0)
    mid = 0.0
    if e > a:
        mid = (e - a) / w * 0.5 * (a + e)
    top = 0.0
    if hi > 1.0:
        top = (hi - max(lo, 1.0)) / w
    return mid + top


@kernel
def mobility_threshold_tilted(theta_rigid, b, h, diameter, span, cd):
    """Critical object mobility parameter of a tilted, partly buried cylinder (``mobility =
    "pocket"`` under ``rest_attitude = "impact"``): the rolling moment balance of
    :func:`mobility_threshold_pocket` written per section along the axis and integrated. In the
    section normal to the axis the bed lies (D - b_n) below the top, b_n(x) = d(x)/cos(beta),
    d(x) the depth of the bottom line, linear from H (higher end) to B (lower end). A rigid roll
    turns about a line parallel to the axis over the highest lip, the deepest section's:
    cos(alpha) = 1 - 2 B/(D cos beta). Drag 1/2 rho C_D U^2 (D - b_n)+ per length, arm R cos(alpha);
    the weight's part normal to the axis (rho_m - rho) g pi D^2/4 L cos(beta), arm R sin(alpha):
    U^2/(g D (s - 1)) > (pi/(2 C_D)) tan(alpha) cos(beta)/e, e the mean over the axis of
    clip(1 - b_n/D, 0, 1). Our derivation (docs/scour.md, Tilt); with H = B (level) it is
    :func:`mobility_threshold_pocket` (same operations)."""
    sb = tilt_sine(b, h, span)
    cb = math.sqrt(1.0 - sb * sb) if sb > 0.0 else 1.0
    if not cb > 0.0:
        return math.inf
    f = b / (diameter * cb)
    tan_a = pocket_tangent(f)
    if tan_a == math.inf or f >= 1.0:
        return math.inf
    if h == b:
        e = 1.0 - f
    else:
        e = mean_clipped_linear(1.0 - h / (diameter * cb), 1.0 - f)
    if not e > 0.0:
        return math.inf
    return max(theta_rigid, math.pi / (2.0 * cd) * tan_a * cb / e)


@kernel
def is_mobile_tilted(p, u, b, h, theta_mob, b_proud):
    """:func:`is_mobile` of a tilted mine (lowest point ``b``, higher end ``h``): the pocket
    criterion by :func:`mobility_threshold_tilted`; the proud one on the lowest point, as level."""
    diameter = p[S_DIAMETER]
    theta_u = mobility_parameter(u, diameter, p[S_MINE_SG], p[S_G])
    if p[S_MOBILITY] == MOBILITY_POCKET:
        return theta_u > mobility_threshold_tilted(theta_mob, b, h, diameter, p[S_AXIS_SPAN], p[S_MOB_CD])
    return b <= b_proud and theta_u > theta_mob


# --- the stage ---------------------------------------------------------------------------------------


@kernel
def bed_forcing(p, hs, tp, wdir, uc, cdir, h, table):
    """(theta, ub, tb, u_near_bed): the Shields parameter of the maximum combined skin-friction stress
    (Soulsby 1997), the near-bed orbital velocity and period of the chosen convention, and the speed
    entering the mobility parameter (current + orbital amplitude, collinear: an upper bound) for one
    forcing sample."""
    g = p[S_G]
    rho = p[S_RHO_WATER]
    d50 = p[S_D50]
    orbital = int(p[S_ORBITAL])
    if hs <= 0.0:
        ub, tb = 0.0, tp
    elif orbital == ORBITAL_SPECTRAL:
        ub, tb = orbital_spectral(hs, tp, h, g, table)
    elif orbital == ORBITAL_HRMS:
        ub, tb = orbital_monochromatic(hs / math.sqrt(2.0), tp, h, g), tp
    else:
        ub, tb = orbital_monochromatic(hs, tp, h, g), tp
    tau_w = wave_stress(ub, tb, d50, rho, int(p[S_FRICTION]))
    tau_c = current_stress(uc, p[S_CURRENT_Z], h, d50, rho)
    _, tau_max = combined_stress(tau_c, tau_w, wdir - cdir)
    theta = shields(tau_max, rho, p[S_RHO_GRAIN] / rho, g, d50)
    return theta, ub, tb, uc + ub


@kernel
def coarse_weight(d50, d_mid):
    """Weight in [0, 1] of the coarse-sand exposure limit at grain size ``d50``: 0 below
    ``d_mid`` 2^-RIPPLE_BLEND_PHI, 1 above ``d_mid`` 2^RIPPLE_BLEND_PHI, and between them the
    smoothstep 3x^2 - 2x^3 of x, the position in phi (log2 d50) across that interval: continuous
    with a continuous slope at both ends, no switch in grain size (docs/scour.md, Coarse sand)."""
    x = 0.5 + math.log2(d50 / d_mid) / (2.0 * RIPPLE_BLEND_PHI)
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * x * (3.0 - 2.0 * x)


@kernel
def exposure_limit(diameter, eta, exposure, weight):
    """Largest burial [m] of a mine in rippled coarse sand: the height proud above the ripple
    crests stops at ``exposure`` ripple heights (Traykovski et al. 2007, MVCO coarse sand: about
    one ripple height). The crests stand RIPPLE_CREST eta above the undisturbed bed, the mine's
    top D - B above it, so D - B - eta/2 = exposure eta: B_lim = D - (exposure + 1/2) eta, eased in
    by ``weight`` (:func:`coarse_weight`): D - weight (exposure + 1/2) eta, never below 0."""
    return max(diameter - weight * (exposure + RIPPLE_CREST) * eta, 0.0)


@kernel
def burial_target(p, theta, theta_cr, ub, tb):
    """(B_eq, T) of one forcing sample: B_eq = 0 at or below the threshold of motion and on a
    cohesive bed (no growth), else the Rennie et al. law capped by full burial (D), the mobile-layer
    thickness and, in coarse sand, the exposure limit of :func:`exposure_limit` with the current
    wave-ripple height (Wiberg & Harris 1994), weighted by :func:`coarse_weight` (0 in fine and
    medium sand up to 0.354 mm, 1 from 0.707 mm with the defaults). Without waves (d0 = 0) or
    where the ripples are washed out there is no wave ripple and no limit: current ripples are
    not modelled (docs/scour.md)."""
    diameter = p[S_DIAMETER]
    d50 = p[S_D50]
    if p[S_COHESIVE] != 0.0 or not theta > theta_cr:
        return 0.0, math.inf
    b_eq = min(equilibrium_burial(theta, diameter, p[S_BEQ_A], p[S_BEQ_B]), diameter)
    b_eq = min(b_eq, p[S_MOBILE_LAYER])
    w = coarse_weight(d50, p[S_RIPPLE_D50])
    if w > 0.0:
        eta = ripple_height(ub * tb / math.pi, d50)
        if eta >= 0.0:  # NaN (no ripples) leaves no limit
            b_eq = min(b_eq, exposure_limit(diameter, eta, p[S_RIPPLE_EXPOSURE], w))
    kc = ub * tb / diameter
    s = p[S_RHO_GRAIN] / p[S_RHO_WATER]
    t_scale = scour_time_scale(
        theta, kc, diameter, d50, s, p[S_G], p[S_TSTAR_C], p[S_TSTAR_M], p[S_TSTAR_P], p[S_TSTAR_KC_MIN]
    )
    return b_eq, t_scale


@kernel
def depth_floor(d50):
    """The smallest water depth [m] the stage accepts: DEPTH_MIN_OVER_KS (10) Nikuradse roughnesses
    ks = 2.5 d50, i.e. h/z0 >= 300, where the depth-mean drag coefficient of :func:`current_stress`
    has ln(h/z0) - 1 >= 4.7 (it becomes infinite at h = e z0). Far below any depth a mine is laid
    in (5 mm for 0.2 mm sand); it only rules out meaningless forcing (docs/scour.md)."""
    return DEPTH_MIN_OVER_KS * 2.5 * d50


@kernel
def parameters_valid(p):
    """Whether the stage's parameter vector lies in its documented ranges (docs/scour.md, Status
    codes): finite where it must be, positive sizes, densities and coefficients, s_obj > 1, grains
    heavier than water, b > 0 (B_eq grows with theta), p < 0 (T shrinks with theta), m >= 0 with
    kc_min > 0 for a KC law (m > 0), mobility exponent < 0, proud limit in [0, 1], a ripple
    exposure >= 0 and a positive blend d50, a known convention code, a known burial law and
    mobility criterion, a_w > 0, m_w >= 0, an infill time > 0 (inf: none), a finite bed rate >= 0, a
    positive finite drag coefficient, and a current height either <= 0 (depth mean) or >= ks =
    2.5 d50 (above the roughness elements, where the log profile holds)."""
    for i in range(N_PARAMS):
        if math.isnan(p[i]):
            return False
    positive = (
        S_DIAMETER, S_D50, S_RHO_GRAIN, S_RHO_WATER, S_NU, S_G, S_MOBILE_LAYER, S_BEQ_A, S_TSTAR_C,
        S_RIPPLE_D50,
    )  # fmt: skip
    for i in positive:
        if not p[i] > 0.0:
            return False
    finite = (
        S_B0, S_DIAMETER, S_MINE_SG, S_D50, S_COHESIVE, S_BEQ_B, S_TSTAR_M, S_TSTAR_P, S_MOB_C, S_MOB_P,
        S_RIPPLE_D50, S_RIPPLE_EXPOSURE,
    )  # fmt: skip
    for i in finite:
        if not math.isfinite(p[i]):
            return False
    if p[S_B0] < 0.0 or not p[S_MINE_SG] > 1.0 or not p[S_RHO_GRAIN] > p[S_RHO_WATER]:
        return False
    if p[S_RIPPLE_EXPOSURE] < 0.0:
        return False
    if not (p[S_BEQ_B] > 0.0 and p[S_TSTAR_P] < 0.0 and p[S_TSTAR_M] >= 0.0):
        return False
    kc_min = p[S_TSTAR_KC_MIN]
    if not (kc_min >= 0.0 and kc_min < math.inf) or (p[S_TSTAR_M] > 0.0 and not kc_min > 0.0):
        return False
    if not (p[S_MOB_C] > 0.0 and p[S_MOB_P] < 0.0 and 0.0 <= p[S_MOB_BURIAL_MAX] <= 1.0):
        return False
    law = p[S_BURIAL_LAW]
    if not (law == BURIAL_RENNIE or law == BURIAL_SCOUR_SETTLE):
        return False
    if not (p[S_WAVE_A] > 0.0 and p[S_WAVE_A] < math.inf):
        return False
    if not (p[S_WAVE_KC_EXP] >= 0.0 and p[S_WAVE_KC_EXP] < math.inf):
        return False
    if not (p[S_INFILL_TIME] > 0.0 and p[S_BED_RATE] >= 0.0 and p[S_BED_RATE] < math.inf):
        return False
    if not ((p[S_MOBILITY] == MOBILITY_PROUD or p[S_MOBILITY] == MOBILITY_POCKET) and p[S_MOB_CD] > 0.0):
        return False
    if not p[S_MOB_CD] < math.inf:
        return False
    attitude = p[S_REST_ATTITUDE]
    if not (attitude == REST_FLAT or attitude == REST_IMPACT):
        return False
    if attitude == REST_IMPACT:  # the tilt needs the pit as a state apart from the mine's burial
        if law != BURIAL_SCOUR_SETTLE or not (p[S_AXIS_SPAN] > 0.0 and p[S_AXIS_SPAN] < math.inf):
            return False
        if not (math.isfinite(p[S_B0_HIGH]) and p[S_B0_HIGH] <= p[S_B0]):
            return False
        if p[S_B0] - p[S_B0_HIGH] > p[S_AXIS_SPAN] * (1.0 + 1e-12):  # sin(tilt) <= 1
            return False
    standing = p[S_STANDING]
    if not (standing == 0.0 or standing == 1.0):
        return False
    if standing == 1.0:  # a body standing on its base: its height and flank; no tilt state
        if not (p[S_HEIGHT] > 0.0 and p[S_HEIGHT] < math.inf and attitude == REST_FLAT):
            return False
        if not (p[S_FLANK_ANGLE] >= 0.0 and p[S_FLANK_ANGLE] < 0.5 * math.pi):
            return False
    z = p[S_CURRENT_Z]
    if not (math.isfinite(z) and (z <= 0.0 or z >= 2.5 * p[S_D50])):
        return False
    orbital = p[S_ORBITAL]
    if not (orbital == ORBITAL_SPECTRAL or orbital == ORBITAL_HRMS or orbital == ORBITAL_HS):
        return False
    return p[S_FRICTION] == FRICTION_SWART or p[S_FRICTION] == FRICTION_SOULSBY


@kernel
def forcing_valid(t, hs, tp, wdir, uc, cdir, h, h_min, z_current):
    """Whether the forcing series is usable: equal lengths >= 2, strictly increasing finite times,
    finite non-negative wave heights and current speeds, positive finite periods, finite angles,
    finite depths h >= h_min (:func:`depth_floor`) and, for a current given at a height
    z_current > 0, above it (h > z_current)."""
    n = t.shape[0]
    if n < 2:
        return False
    for arr in (hs, tp, wdir, uc, cdir, h):
        if arr.shape[0] != n:
            return False
    for i in range(n):
        if not (math.isfinite(t[i]) and math.isfinite(wdir[i]) and math.isfinite(cdir[i])):
            return False
        if i > 0 and not t[i] > t[i - 1]:
            return False
        if not (hs[i] >= 0.0 and uc[i] >= 0.0 and tp[i] > 0.0 and h[i] >= h_min and h[i] > z_current):
            return False
        if not (hs[i] < math.inf and uc[i] < math.inf and tp[i] < math.inf and h[i] < math.inf):
            return False
    return True


@kernel
def initial_leads(lead_times, order, span, b0, out_burial):
    """(status, nxt) before the stage's loop: the burial b0 at lead times 0, SCOUR_BEYOND_FORCING
    if a lead time lies outside [0, span] (or is NaN), and nxt, the position in the sorted
    ``order`` of the first lead time > 0 (those <= 0 need no interval)."""
    status = SCOUR_OK
    nxt = 0
    for j in range(order.shape[0]):
        lt = lead_times[order[j]]
        if not (lt >= 0.0 and lt <= span):
            status = SCOUR_BEYOND_FORCING
        elif lt == 0.0:
            out_burial[order[j]] = b0
        if not lt > 0.0 and not math.isnan(lt):
            nxt = j + 1
    return status, nxt


@kernel
def scour_stage(p, t, hs, tp, wdir, uc, cdir, h, table, lead_times, fractions, out_burial, out_time_to):
    """Post-impact scour burial of one mine over a forcing series: :func:`scour_stage_states`
    without its pit-depth and mobility outputs (same arguments otherwise; returns (status,
    t_mobile, theta_max))."""
    n = lead_times.shape[0]
    return scour_stage_states(
        p, t, hs, tp, wdir, uc, cdir, h, table, lead_times, fractions, out_burial, out_time_to,
        np.empty(n), np.empty(n),
    )  # fmt: skip


@kernel
def scour_stage_states(
    p, t, hs, tp, wdir, uc, cdir, h, table, lead_times, fractions, out_burial, out_time_to, out_pit,
    out_mobile,
):  # fmt: skip
    """:func:`scour_stage_ends` without the higher end's depth (same arguments otherwise)."""
    return scour_stage_ends(
        p, t, hs, tp, wdir, uc, cdir, h, table, lead_times, fractions, out_burial, out_time_to, out_pit,
        out_mobile, np.empty(lead_times.shape[0]),
    )  # fmt: skip


@kernel
def scour_stage_ends(
    p,
    t,
    hs,
    tp,
    wdir,
    uc,
    cdir,
    h,
    table,
    lead_times,
    fractions,
    out_burial,
    out_time_to,
    out_pit,
    out_mobile,
    out_high,
):
    """Post-impact scour burial of one mine over a forcing series.

    Inputs: ``p`` the parameter vector (S_* layout, :func:`default_parameters`); the forcing as
    flat float64 arrays of equal length: time [s], Hs [m], Tp [s], wave direction [rad], current
    speed [m/s] (at S_CURRENT_Z, or depth mean), current direction [rad], water depth [m]; sample i
    holds over [t_i, t_i+1). ``table`` from :func:`build_orbital_table`. ``lead_times`` [s] after
    t_0 (any order), ``fractions`` burial levels B/D.

    Outputs, written in place: ``out_burial`` the burial B [m] at each lead time (NaN beyond the
    forcing), ``out_time_to`` the time [s] after t_0 at which B/D first reaches each fraction (inf:
    not within the forcing), ``out_pit`` the scour pit's depth [m] below the far-field bed at each
    lead time (the burial itself under BURIAL_RENNIE, whose one state is both), ``out_mobile`` 1.0
    where the mine would move at that lead time (the criterion S_MOBILITY selects, with the
    forcing interval holding the lead time and the burial then), else 0.0 (NaN beyond the forcing),
    ``out_high`` the depth [m] of the higher end's lowest point below the far-field bed (< 0: proud;
    equal to the burial for a level mine: always under REST_FLAT, where the mine lies level).
    Returns (status, t_mobile, theta_max): the start [s] of the first interval in which the mine
    met the mobility criterion with its burial at that start (inf: never), and the largest Shields
    parameter met.

    Over each interval the forcing is constant and the states follow exact solutions, so no time
    stepper is needed. BURIAL_RENNIE: dB/dt = (B_eq - B)/T (:func:`relax_burial`). BURIAL_SCOUR_SETTLE:
    the pit S relaxes to :func:`pit_target`'s S_eq, growing with T and filling with S_INFILL_TIME
    (:func:`relax_pit`, monotone within an interval), and the mine's burial is pointwise
    max(B_self - r tau, S, 0) (:func:`settled_burial`), exact for a constant lowering rate r >= 0.
    REST_IMPACT (scour and settle only): the mine keeps the impact's tilt, a second state, the depth H
    of its higher end (:func:`settled_high_end`, pointwise as B); B is the lower end's, as level.
    S_STANDING = 1 (a short body on its base, a frustum): the equilibrium and time scale of
    :func:`standing_target` (the pile laws), B the depth of the base, the burial levels fractions of
    S_HEIGHT, no mobility criterion (docs/scour.md, Standing body).
    The lead times are visited in sorted order with one pointer: O(N_intervals + N_leads log N_leads).
    """
    out_burial[:] = math.nan
    out_time_to[:] = math.inf
    out_pit[:] = math.nan
    out_mobile[:] = math.nan
    out_high[:] = math.nan
    if not parameters_valid(p):
        return SCOUR_INVALID_PARAMETER, math.nan, math.nan
    for k in range(fractions.shape[0]):
        if not (fractions[k] >= 0.0 and fractions[k] < math.inf):
            return SCOUR_INVALID_PARAMETER, math.nan, math.nan
    diameter = p[S_DIAMETER]
    d50 = p[S_D50]
    if not forcing_valid(t, hs, tp, wdir, uc, cdir, h, depth_floor(d50), p[S_CURRENT_Z]):
        return SCOUR_INVALID_FORCING, math.nan, math.nan
    g = p[S_G]
    s = p[S_RHO_GRAIN] / p[S_RHO_WATER]
    theta_cr = shields_threshold(grain_size_number(d50, s, g, p[S_NU]))
    theta_mob = mobility_threshold(diameter, 2.5 * d50, p[S_MOB_C], p[S_MOB_P])
    b_proud = p[S_MOB_BURIAL_MAX] * diameter
    settle = p[S_BURIAL_LAW] == BURIAL_SCOUR_SETTLE
    standing = p[S_STANDING] == 1.0  # a short body on its base: the pile laws, no mobility criterion
    size = p[S_HEIGHT] if standing else diameter  # the burial levels' unit: the height in the attitude
    rate = p[S_BED_RATE]
    t_fill = p[S_INFILL_TIME]
    b = p[S_B0]
    pit = 0.0 if settle else b  # the impact leaves no scour pit: the mine's burial is its own
    tilted = p[S_REST_ATTITUDE] == REST_IMPACT
    hb = p[S_B0_HIGH] if tilted else b  # the higher end's depth (a level mine: its burial)
    span = t[t.shape[0] - 1] - t[0]
    order = np.argsort(lead_times)  # NaN last
    status, nxt = initial_leads(lead_times, order, span, b, out_burial)
    for j in range(nxt):
        if out_burial[order[j]] == b:  # lead time 0 (NaN beyond the forcing)
            out_pit[order[j]] = pit
            out_high[order[j]] = hb
    for k in range(fractions.shape[0]):
        if b >= fractions[k] * size:
            out_time_to[k] = 0.0
    t_mobile = math.inf
    theta_max = 0.0
    for i in range(t.shape[0] - 1):
        ta = t[i] - t[0]
        te = t[i + 1] - t[0]
        theta, ub, tb, u = bed_forcing(p, hs[i], tp[i], wdir[i], uc[i], cdir[i], h[i], table)
        theta_max = max(theta_max, theta)
        if standing:  # Rennie et al.'s criteria are a lying cylinder's rolling (docs/scour.md)
            mobile_now = False
        elif tilted:
            mobile_now = is_mobile_tilted(p, u, b, hb, theta_mob, b_proud)
        else:
            mobile_now = is_mobile(p, u, b, theta_mob, b_proud)
        if t_mobile == math.inf and mobile_now:
            t_mobile = ta
        if i == 0:  # the mobility at lead time 0, with the first interval's flow
            for j in range(nxt):
                if out_burial[order[j]] == out_burial[order[j]]:
                    out_mobile[order[j]] = 1.0 if mobile_now else 0.0
        if standing:
            tau_c = current_stress(uc[i], p[S_CURRENT_Z], h[i], d50, p[S_RHO_WATER])
            theta_c = shields(tau_c, p[S_RHO_WATER], s, g, d50)
            s_eq, t_scale = standing_target(p, theta, theta_cr, ub, tb, uc[i], theta_c)
        elif settle:
            s_eq, t_scale = pit_target(p, theta, theta_cr, ub, tb, uc[i])
        else:
            s_eq, t_scale = burial_target(p, theta, theta_cr, ub, tb)
        while nxt < order.shape[0] and lead_times[order[nxt]] <= te:
            j = order[nxt]
            dt = lead_times[j] - ta
            if settle:
                out_pit[j] = relax_pit(pit, s_eq, dt, t_scale, t_fill)
                out_burial[j] = settled_burial(b, out_pit[j], dt, rate)
            else:
                out_burial[j] = relax_burial(b, s_eq, dt, t_scale)
                out_pit[j] = out_burial[j]
            if tilted:
                out_high[j] = settled_high_end(b, hb, out_pit[j], dt, rate)
                moving = is_mobile_tilted(p, u, out_burial[j], out_high[j], theta_mob, b_proud)
            else:
                out_high[j] = out_burial[j]
                moving = False if standing else is_mobile(p, u, out_burial[j], theta_mob, b_proud)
            out_mobile[j] = 1.0 if moving else 0.0
            nxt += 1
        if settle:
            pit_next = relax_pit(pit, s_eq, te - ta, t_scale, t_fill)
            b_next = settled_burial(b, pit_next, te - ta, rate)
        else:
            b_next = relax_burial(b, s_eq, te - ta, t_scale)
            pit_next = b_next
        hb = settled_high_end(b, hb, pit_next, te - ta, rate) if tilted else b_next
        for k in range(fractions.shape[0]):
            target = fractions[k] * size
            if out_time_to[k] == math.inf and b_next >= target:
                # under scour and settle only the pit's growth raises B within an interval
                start = pit if settle else b
                out_time_to[k] = ta + min(time_to_reach(start, s_eq, target, t_scale), te - ta)
        b = b_next
        pit = pit_next
    return status, t_mobile, theta_max
