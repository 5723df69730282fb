"""The mine scenario's fields and cross-field rules, each declared once (issue 18 item 3).

:data:`TABLE` lists every field of a scenario file (``docs/scenario.md``), in the order of
the kernels' parameter slots for those with one (``slot=True``): the slot order of
:data:`mineburial.kernels.layout.PARAM_NAMES` is this table's, so a new slot goes at the
end of the slotted fields (the compiled kernels index slots by the constants of layout.py,
which are looked up by name). :data:`RULES` are the relations between fields, checked per
scenario by :mod:`mineburial.config` and over the packed rows of an ensemble by
:func:`mineburial.config.check_params`, from the same declaration.

Sources: seed 000 (Chu's IMPACT35 drop model), seed 004 (Liu et al.), and the references
named in each description; ``docs/scenario.md`` is generated from this table.
"""

from __future__ import annotations

import math

from mineburial.schema import Field

# --- names of the choices (the kernels receive their indices) ---------------
MODEL_NAMES = ("mineburial", "impact35")
INTEGRATOR_NAMES = ("rk4", "local_linear", "dopri5", "dopri5_ros34pw2")
SEDIMENT_QUADRATURE_NAMES = ("fast", "reference")
OVERBURDEN_QUADRATURE_NAMES = ("fast", "reference")  # kernels/overburden.py
CURRENT_KINDS = ("none", "uniform", "power_law", "table")
# water-column models (docs/physics.md, "Water-column model choices"): the strip added mass
# with the tuned numerics.munk_factor, or the viscous-crossflow method with the added-mass
# tensor of the finite cylinder
WATER_COLUMN_NAMES = ("munk_factor", "viscous_crossflow")
# sediment model codes (kernels.sediment)
RESISTANCE_NAMES = ("delta", "friction", "bearing")
RATE_LAW_NAMES = ("impact35", "semilog", "none")

#: 1 %/h, the conventional laboratory (triaxial) shear rate, in s-1.
LAB_STRAIN_RATE = 0.01 / 3600.0

_OPEN_LOW = (False, True)
_OPEN = (False, False)


def _f(path, units, low, high, description, default=None, *, incl=(True, True), location=None, **kw):
    """A numeric field with a kernel slot unless ``slot=False``."""
    kw.setdefault("slot", True)
    return Field(
        path,
        units,
        float(low),
        float(high),
        incl[0],
        incl[1],
        description,
        None if default is None else float(default),
        location or path,
        **kw,
    )


def _choice(path, names, description, default=None, *, location=None, **kw):
    """A choice among ``names`` (the slot holds its index)."""
    return Field(
        path,
        "1",
        0,
        len(names) - 1,
        True,
        True,
        description,
        default,
        location or path,
        kind="choice",
        choices=names,
        slot=True,
        **kw,
    )


def _switch(path, description, default):
    return Field(path, "1", 0, 1, True, True, description, default, path, kind="bool", slot=True)


def _code(path, description):
    """An internal integer of the kernels that no file holds (a bank row, -1 for none)."""
    return Field(
        path, "1", -1, math.inf, True, False, description, None, None, kind="code", slot=True, sampled=False
    )


TABLE: tuple[Field, ...] = (
    # --- mine ---------------------------------------------------------------
    _f("mine.length", "m", 0, 50, "length L of the cylinder", incl=_OPEN_LOW),
    _f("mine.diameter", "m", 0, 10, "diameter d = 2R of the cylinder", incl=_OPEN_LOW),
    _f("mine.mass", "kg", 0, 1e5, "mass m", incl=_OPEN_LOW),
    _f(
        "mine.com_offset",
        "m",
        -25,
        25,
        "chi: COM displacement from the centre of volume towards the nose (seed 000 "
        "Fig. 1); also |chi| < length/2",
        0.0,
        incl=_OPEN,
    ),
    _f(
        "mine.inertia_axial",
        "kg m2",
        0,
        1e7,
        "J1, moment of inertia about the main axis through the COM; default m R^2/2 "
        "(uniform cylinder); also J1 <= 2 J2",
        incl=_OPEN_LOW,
    ),
    _f(
        "mine.inertia_transverse",
        "kg m2",
        0,
        1e7,
        "J2 = J3, moment of inertia about a transverse axis through the COM; default "
        "m (3R^2 + L^2)/12 (uniform cylinder)",
        incl=_OPEN_LOW,
    ),
    # --- release ------------------------------------------------------------
    _f("release.x", "m", -1e5, 1e5, "initial x of the COM", 0.0, location="release.position[0]"),
    _f("release.y", "m", -1e5, 1e5, "initial y of the COM", 0.0, location="release.position[1]"),
    _f(
        "release.z",
        "m",
        -11000,
        20000,
        "initial height of the COM above the calm water surface; also > -environment.water_depth",
        0.0,
        location="release.position[2]",
    ),
    _f("release.u", "m s-1", -500, 500, "initial COM velocity, x", 0.0, location="release.velocity[0]"),
    _f("release.v", "m s-1", -500, 500, "initial COM velocity, y", 0.0, location="release.velocity[1]"),
    _f("release.w", "m s-1", -500, 500, "initial COM velocity, z (up)", 0.0, location="release.velocity[2]"),
    _f("release.roll_deg", "deg", -360, 360, "psi1, roll about the main axis", 0.0, slot=False),
    _f(
        "release.pitch_deg",
        "deg",
        -90,
        90,
        "psi2, dip of the nose below the horizontal (+90 = nose down)",
        0.0,
        slot=False,
    ),
    _f(
        "release.heading_deg",
        "deg",
        -360,
        360,
        "psi3, heading of the nose from +x towards +y",
        0.0,
        slot=False,
    ),
    _f("release.q0", "1", -1, 1, "orientation quaternion, scalar part", location="release.quaternion[0]"),
    _f("release.q1", "1", -1, 1, "orientation quaternion, x part", location="release.quaternion[1]"),
    _f("release.q2", "1", -1, 1, "orientation quaternion, y part", location="release.quaternion[2]"),
    _f("release.q3", "1", -1, 1, "orientation quaternion, z part", location="release.quaternion[3]"),
    _f(
        "release.omega1",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 1",
        0.0,
        location="release.angular_velocity[0]",
    ),
    _f(
        "release.omega2",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 2",
        0.0,
        location="release.angular_velocity[1]",
    ),
    _f(
        "release.omega3",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 3",
        0.0,
        location="release.angular_velocity[2]",
    ),
    # --- environment ----------------------------------------------------------
    _f("environment.gravity", "m s-2", 0, 100, "gravitational acceleration g", 9.81, incl=_OPEN_LOW),
    _f("environment.air_density", "kg m-3", 0, 10, "air density (ISA sea level 1.225)", 1.225),
    _f(
        "environment.air_viscosity",
        "m2 s-1",
        0,
        1e-3,
        "kinematic viscosity of air (ISA 15 C: 1.46e-5)",
        1.5e-5,
        incl=_OPEN_LOW,
    ),
    _f(
        "environment.water_density",
        "kg m-3",
        0,
        1300,
        "water density (sea water 1025, seed 004 sec. 4; fresh 998; 0 = no water, for ballistic checks)",
        1025.0,
    ),
    _f(
        "environment.water_viscosity",
        "m2 s-1",
        0,
        1e-4,
        "kinematic viscosity of water (sea water 1.05e-6, seed 004 sec. 4)",
        1.05e-6,
        incl=_OPEN_LOW,
    ),
    _f("environment.water_depth", "m", 0, 11000, "water depth H; the seabed is at z = -H", incl=_OPEN_LOW),
    _choice(
        "current.kind",
        CURRENT_KINDS,
        "current profile: none, uniform, power law (seed 004 eq. (38)) or table",
        "none",
        location="environment.current.kind",
        sampled=False,
    ),
    _f(
        "current.u",
        "m s-1",
        -10,
        10,
        "current x: uniform value or surface value of the power law",
        0.0,
        location="environment.current.velocity[0]",
    ),
    _f(
        "current.v",
        "m s-1",
        -10,
        10,
        "current y: uniform value or surface value of the power law",
        0.0,
        location="environment.current.velocity[1]",
    ),
    _f(
        "current.exponent",
        "1",
        0,
        1,
        "power-law exponent, U(h) = U_s (h/d)^exponent (seed 004 eq. (38))",
        1.0 / 7.0,
        incl=_OPEN_LOW,
        location="environment.current.exponent",
    ),
    _code("current.table_index", "row of the current bank, -1: the parametric current"),
    _code("sediment.profile_index", "row of the sediment bank, -1: the linear profile"),
    # --- sediment -------------------------------------------------------------
    _f("sediment.density", "kg m-3", 1000, 2700, "linear profile: bulk density at the seabed"),
    _f("sediment.density_gradient", "kg m-4", 0, 1e4, "linear profile: density gradient", 0.0),
    _f("sediment.strength", "Pa", 0, 1e6, "linear profile: undrained shear strength at the seabed"),
    _f("sediment.strength_gradient", "Pa m-1", 0, 1e6, "linear profile: strength gradient", 0.0),
    _choice(
        "sediment.resistance",
        RESISTANCE_NAMES,
        "normal/tangential traction model: delta = seed 000 eq. (74); friction = seed 000 sec. 10 item 4; "
        "bearing = bearing-factor method (Chu & Fan 2007)",
        default_text="by model",
    ),
    _choice(
        "sediment.rate_law",
        RATE_LAW_NAMES,
        "strain-rate factor on the strength: impact35 = G(V) of seed 000 eq. (70); semilog = "
        "1 + beta log10(rate/reference_rate); none = 1",
        default_text="by model",
    ),
    _f("sediment.impact_factor", "1", 1, 100, "A of seed 000 eq. (70), (72)", 10.0),
    _f("sediment.rest_speed", "m s-1", 0, 10, "V_rest of seed 000 eq. (70), (72)", 0.04, incl=_OPEN_LOW),
    _f(
        "sediment.rate_coefficient",
        "1",
        0,
        2,
        "beta of the semi-logarithmic rate law, per log10 cycle of strain rate (~0.1: Kulhawy & Mayne 1990)",
        0.1,
    ),
    _f(
        "sediment.reference_rate",
        "s-1",
        0,
        1e6,
        "reference strain rate of the semi-logarithmic law (1 %/h lab rate)",
        LAB_STRAIN_RATE,
        incl=_OPEN_LOW,
    ),
    _f(
        "sediment.friction",
        "1",
        0,
        5,
        "mu, tangential/normal traction ratio (seed 004 Table 2 case 1: 0.3)",
        0.3,
    ),
    _f(
        "sediment.bearing_factor",
        "1",
        0,
        50,
        "N_c, bearing-capacity factor (pi + 2, Prandtl 1920)",
        math.pi + 2.0,
        incl=_OPEN_LOW,
    ),
    _switch("sediment.pore_pressure", "add the pore-water force of seed 000 eq. (73)", False),
    _f("sediment.rupture_length", "m", 0, 10, "B of seed 000 eq. (73)", 0.1, incl=_OPEN_LOW),
    _f(
        "sediment.permeability",
        "m s-1",
        0,
        1,
        "k_p of seed 000 eq. (73) (1e-4, seed 000 ref. [15])",
        1e-4,
        incl=_OPEN_LOW,
    ),
    _f("sediment.void_ratio", "1", 0, 20, "e_v of seed 000 eq. (73) (~0.5)", 0.5, incl=_OPEN_LOW),
    # --- numerics -------------------------------------------------------------
    _choice(
        "numerics.model",
        MODEL_NAMES,
        "force model: this engine's, or seed 000's IMPACT35",
        "mineburial",
    ),
    _choice(
        "numerics.integrator",
        INTEGRATOR_NAMES,
        "time integrator: dopri5_ros34pw2 (Dormand-Prince 5(4) in air and water, Rosenbrock-W ROS34PW2 "
        "in the sediment), dopri5, the fixed-step rk4, or the local-linearisation step of seed 000 "
        "eqs. (83)-(87)",
        default_text="by model",
    ),
    _f("numerics.dt", "s", 0, 1, "time step; also dt <= t_max and dt <= t_max_fall", 1e-3, incl=_OPEN_LOW),
    _f(
        "numerics.t_max",
        "s",
        0,
        1e6,
        "limit on the simulated time after the mine first touches the seabed (time_limit)",
        60.0,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.rest_speed",
        "m s-1",
        0,
        10,
        "rest criterion on the COM speed (seed 000 eq. (89), epsilon_1); the sediment's "
        "hold is probed at this speed",
        1e-2,
        incl=_OPEN_LOW,
    ),
    _f("numerics.rest_spin", "rad s-1", 0, 100, "rest criterion on the angular speed", 5e-2, incl=_OPEN_LOW),
    _switch("numerics.drag", "fluid drag and lift on (switch off for energy checks)", True),
    _f(
        "numerics.munk_factor",
        "1",
        0,
        1,
        "fraction of the potential-flow Munk moment kept by the added-mass tensor "
        "(0: isotropic translational added mass, no Munk moment; 1: slender-body strip "
        "theory); see docs/physics.md",
        0.0,
    ),
    _f(
        "numerics.rtol",
        "1",
        0,
        0.1,
        "relative tolerance of the adaptive integrators (dopri5, dopri5_ros34pw2), per step on "
        "position, velocity, attitude and angular velocity; default 3e-4 for numerics.model = "
        "'mineburial', 1e-5 for 'impact35'",
        3e-4,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.atol",
        "1",
        0,
        1.0,
        "absolute tolerance of the adaptive integrators, in m, m s-1, 1 (quaternion) and rad s-1; "
        "default 3e-5 for numerics.model = 'mineburial', 1e-6 for 'impact35'",
        3e-5,
        incl=_OPEN_LOW,
    ),
    _choice(
        "numerics.sediment_quadrature",
        SEDIMENT_QUADRATURE_NAMES,
        "rule for the sediment tractions: the fixed-cost rule or the adaptive quadrature",
        "fast",
    ),
    _f(
        "numerics.slip_speed",
        "m s-1",
        0,
        0.1,
        "regularisation speed of the slip direction of the sediment's tangential traction "
        "(seed 000 eq. (67)): it ramps up over this slip speed (docs/design.md)",
        5e-3,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.switch_speed",
        "m s-1",
        0,
        0.1,
        "regularisation speed of the advancing switch of seed 000 eq. (65): the normal "
        "traction ramps up over this normal speed (docs/design.md)",
        5e-3,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.t_max_fall",
        "s",
        0,
        1e6,
        "limit on the simulated time of the fall, from release to the first seabed contact",
        600.0,
        incl=_OPEN_LOW,
    ),
    _choice(
        "numerics.water_column",
        WATER_COLUMN_NAMES,
        "water-column added-mass and moment model (docs/physics.md, 'Water-column model choices')",
        "munk_factor",
    ),
    _choice(
        "numerics.overburden_quadrature",
        OVERBURDEN_QUADRATURE_NAMES,
        "rule for the geostatic overburden force: bounded cost, or a slice at every table depth",
        "fast",
    ),
    # --- post-impact scour, the optional [scour] section (docs/scour.md): no kernel slot of the
    # impact phase; packed into the stage's own parameters by mineburial/ensembles/scour.py
    _f(
        "scour.d50",
        "m",
        6.25e-5,
        2e-3,
        "median grain size of the bed's sand (Wentworth's sand, 0.0625-2 mm: the scour laws are of "
        "non-cohesive sand, docs/scour.md)",
        2e-4,
        slot=False,
    ),
    _f(
        "scour.grain_density",
        "kg m-3",
        1200,
        8000,
        "density of the sand grains (quartz 2650)",
        2650,
        slot=False,
    ),
    _f(
        "scour.mobile_layer",
        "m",
        0,
        100,
        "thickness of the mobile sand layer over a bed scour cannot dig (absent: unlimited)",
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.beq_a",
        "1",
        0,
        100,
        "a of the equilibrium burial B_eq/D = a theta^b (Rennie, Brandt & Friedrichs 2017: 1.3 for "
        "D > 8 cm, 15 for small or tapered objects)",
        1.3,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.beq_b",
        "1",
        0,
        3,
        "b of B_eq/D = a theta^b (Rennie et al. 2017: 0.36; 1.1)",
        0.36,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.theta_exponent",
        "1",
        -5,
        0,
        "exponent p of the Shields parameter in the time scale T* = c KC^m theta^p (default: the "
        "T* law's, Whitehouse 1998 -1.29; uncertain between about -1.3 and -2.2)",
        slot=False,
    ),
    _f(
        "scour.hs_scale",
        "1",
        0,
        10,
        "factor on every significant wave height of the forcing (forcing uncertainty)",
        1.0,
        incl=_OPEN_LOW,
        slot=False,
    ),
)
