"""The mine scenario's fields and cross-field rules, each declared once (issue 18 item 3).

:data:`TABLE` lists every field of a scenario file (``docs/scenario.md``), in the order of
the kernels' parameter slots for those with one (``slot=True``): the slot order of
:data:`mineburial.kernels.mine.layout.PARAM_NAMES` is this table's, so a new slot goes at the
end of the slotted fields (the compiled kernels index slots by the constants of layout.py,
which are looked up by name). :data:`RULES` are the relations between fields, checked per
scenario by :mod:`mineburial.systems.mine.config` and over the packed rows of an ensemble by
:func:`mineburial.systems.mine.config.check_params`, from the same declaration.

Sources: seed 000 (Chu's IMPACT35 drop model), seed 004 (Liu et al.), and the references
named in each description; ``docs/scenario.md`` is generated from this table.
"""

from __future__ import annotations

import math

from mineburial.kernels.methods import METHOD_NAMES
from mineburial.schema import Field

# --- names of the choices (the kernels receive their indices) ---------------
MODEL_NAMES = ("mineburial", "impact35")
#: the mine's integrators: its first four (their codes are the parameter vector's P_INTEGRATOR), then
#: every other step method of the integration core (kernels/methods.py), which the mine offers as well
INTEGRATOR_NAMES = ("rk4", "local_linear", "dopri5", "dopri5_ros34pw2")
INTEGRATOR_NAMES += tuple(name for name in METHOD_NAMES if name not in INTEGRATOR_NAMES)
SEDIMENT_QUADRATURE_NAMES = ("fast", "reference")
OVERBURDEN_QUADRATURE_NAMES = ("fast", "reference")  # kernels/mine/overburden.py
CURRENT_KINDS = ("none", "uniform", "power_law", "table")
# water-column models (docs/physics.md, "Water-column model choices"): the strip added mass
# with the tuned numerics.munk_factor, or the viscous-crossflow method with the added-mass
# tensor of the finite cylinder
WATER_COLUMN_NAMES = ("munk_factor", "viscous_crossflow")
# sediment model codes (kernels.mine.sediment)
RESISTANCE_NAMES = ("delta", "friction", "bearing")
RATE_LAW_NAMES = ("impact35", "semilog", "none")
# scour conventions (kernels.mine.scour: ORBITAL_*, FRICTION_* are these indices; docs/scour.md)
SCOUR_ORBITAL_NAMES = ("spectral", "hrms", "hs")
SCOUR_FRICTION_NAMES = ("swart", "soulsby")
# scour time-scale laws T* = c KC^m theta^p (kernels.mine.scour.TSTAR_LAWS holds their constants)
SCOUR_TSTAR_LAWS = ("whitehouse", "pipeline", "pile_waves")
# scour burial laws and mobility criteria (kernels.mine.scour: BURIAL_*, MOBILITY_* are these indices)
SCOUR_BURIAL_LAWS = ("rennie", "scour_settle")
# scour.burial_law's further value: each drop's law drawn with its coefficient set from the posterior
# (systems/mine/calibration/posterior.py); never a kernel code (systems/mine/processes/scour.py
# stage_parameters fills the slot)
SCOUR_LAW_FROM_POSTERIOR = "posterior"
SCOUR_MOBILITY_NAMES = ("proud", "pocket")
# the scour stage's rest attitude at lead 0 (kernels.mine.scour: REST_* are these indices)
SCOUR_REST_ATTITUDES = ("flat", "impact")
# the mine's body shapes (kernels/mine/bodies/shapes.py: SHAPES, one Shape per name, in this order)
MINE_SHAPES = ("cylinder", "frustum")

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
        **{"slot": True, **kw},
    )


def _switch(path, description, default):
    return Field(path, "1", 0, 1, True, True, description, default, path, kind="bool", slot=True)


def _code(path, description):
    """An internal integer of the kernels that no file holds (a bank row, -1 for none)."""
    return Field(
        path, "1", -1, math.inf, True, False, description, None, None, kind="code", slot=True, sampled=False
    )


def _setup(path, kind, description, allowed, *, units="", low=-math.inf, high=math.inf, **kw):
    """A key of a section that is no number of the kernels: a file or name (``text``), an inline
    table (``table``) or a list of numbers (``list``, each in [``low``, ``high``]), whose checks
    its reader makes (``allowed`` says them)."""
    kw.setdefault("default_text", "—")
    return Field(
        path,
        units,
        low,
        high,
        description=description,
        kind=kind,
        sampled=False,
        allowed_text=allowed,
        **kw,
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
        (
            "χ: displacement of the centre of mass (COM) from the centre of volume towards the nose "
            "(seed 000 Fig. 1). χ > 0: nose-heavy"
        ),
        0.0,
        incl=_OPEN,
    ),
    _f(
        "mine.inertia_axial",
        "kg m2",
        0,
        1e7,
        "J1, moment of inertia about the main axis through the COM",
        incl=_OPEN_LOW,
        default_text="m R²/2",
    ),
    _f(
        "mine.inertia_transverse",
        "kg m2",
        0,
        1e7,
        "J2 = J3, moment of inertia about a transverse axis through the COM",
        incl=_OPEN_LOW,
        default_text="m (3R² + L²)/12",
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
    _f("release.roll_deg", "deg", -360, 360, "ψ1, roll about the main axis", 0.0, slot=False),
    _f(
        "release.pitch_deg",
        "deg",
        -90,
        90,
        "ψ2, dip of the nose below the horizontal (+90 = nose straight down)",
        0.0,
        slot=False,
    ),
    _f(
        "release.heading_deg",
        "deg",
        -360,
        360,
        "ψ3, heading of the nose, from +x towards +y",
        0.0,
        slot=False,
    ),
    _f(
        "release.q0",
        "1",
        -1,
        1,
        "orientation quaternion, scalar part",
        location="release.quaternion[0]",
        default_text="— (or the angles)",
    ),
    _f(
        "release.q1",
        "1",
        -1,
        1,
        "orientation quaternion, x part",
        location="release.quaternion[1]",
        default_text="— (or the angles)",
    ),
    _f(
        "release.q2",
        "1",
        -1,
        1,
        "orientation quaternion, y part",
        location="release.quaternion[2]",
        default_text="— (or the angles)",
    ),
    _f(
        "release.q3",
        "1",
        -1,
        1,
        "orientation quaternion, z part",
        location="release.quaternion[3]",
        default_text="— (or the angles)",
    ),
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
    Field(
        "release.embedded",
        "1",
        description="allow the mine to start partly inside the seabed (a mine placed on or pressed into the "
        "sediment)",
        default=False,
        kind="bool",
        sampled=False,
    ),
    # --- environment ----------------------------------------------------------
    _f("environment.gravity", "m s-2", 0, 100, "gravitational acceleration g", 9.81, incl=_OPEN_LOW),
    _f("environment.air_density", "kg m-3", 0, 10, "air density (ISA sea level)", 1.225),
    _f(
        "environment.air_viscosity",
        "m2 s-1",
        0,
        1e-3,
        "kinematic viscosity of air (ISA 15 °C: 1.46e-5)",
        1.5e-5,
        incl=_OPEN_LOW,
    ),
    _f(
        "environment.water_density",
        "kg m-3",
        0,
        1300,
        (
            "sea water (seed 004 sec. 4); fresh water ≈ 998; 0 (with `air_density = 0`) removes the "
            "fluids for ballistic checks"
        ),
        1025.0,
    ),
    _f(
        "environment.water_viscosity",
        "m2 s-1",
        0,
        1e-4,
        "kinematic viscosity of sea water (seed 004 sec. 4); fresh water at 20 °C ≈ 1.0e-6",
        1.05e-6,
        incl=_OPEN_LOW,
    ),
    _f("environment.water_depth", "m", 0, 11000, "water depth H; the seabed is at z = −H", incl=_OPEN_LOW),
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
        default_text="1/7",
    ),
    _code("current.table_index", "row of the current bank, -1: the parametric current"),
    _code("sediment.profile_index", "row of the sediment bank, -1: the linear profile"),
    # --- sediment -------------------------------------------------------------
    _f(
        "sediment.density",
        "kg m-3",
        1000,
        2700,
        "linear profile: bulk density at the seabed",
        default_text="required (linear)",
    ),
    _f("sediment.density_gradient", "kg m-4", 0, 1e4, "linear profile: density gradient", 0.0),
    _f(
        "sediment.strength",
        "Pa",
        0,
        1e6,
        "linear profile: undrained shear strength at the seabed",
        default_text="required (linear)",
    ),
    _f("sediment.strength_gradient", "Pa m-1", 0, 1e6, "linear profile: strength gradient", 0.0),
    _choice(
        "sediment.resistance",
        RESISTANCE_NAMES,
        (
            "normal/tangential traction model: `delta` = seed 000 eq. (74); `friction` = the friction"
            " law of seed 000 sec. 10 item 4 (tangential ∝ normal); `bearing` = bearing-factor method"
            " (Chu & Fan 2007, IEEE J. Oceanic Eng. 32(1):34)"
        ),
        default_text="by model",
    ),
    _choice(
        "sediment.rate_law",
        RATE_LAW_NAMES,
        (
            "strain-rate factor on the strength: `impact35` = G(V) of seed 000 eq. (70); `semilog` = "
            "1 + β log10(γ̇/γ̇_ref); `none` = 1"
        ),
        default_text="by model",
    ),
    _f("sediment.impact_factor", "1", 1, 100, "A of seed 000 eq. (70); 10 in its eq. (72)", 10.0),
    _f(
        "sediment.rest_speed",
        "m s-1",
        0,
        10,
        "V_rest of eq. (70); 0.04 in seed 000 eq. (72)",
        0.04,
        incl=_OPEN_LOW,
    ),
    _f(
        "sediment.rate_coefficient",
        "1",
        0,
        2,
        (
            "β, strength increase per log10 cycle of strain rate; ≈ 0.1 (about 10 % per cycle, "
            "Kulhawy & Mayne 1990)"
        ),
        0.1,
    ),
    _f(
        "sediment.reference_rate",
        "s-1",
        0,
        1e6,
        "γ̇_ref: 1 %/h, the conventional laboratory shear rate at which s_u is usually quoted",
        LAB_STRAIN_RATE,
        incl=_OPEN_LOW,
        default_text="2.78e-6 (1 %/h)",
    ),
    _f(
        "sediment.friction",
        "1",
        0,
        5,
        (
            "μ, tangential/normal traction ratio (μ of seed 000 eq. (74), never given a value there; "
            "0.3 is the seabed friction of seed 004 Table 2 case 1)"
        ),
        0.3,
    ),
    _f(
        "sediment.bearing_factor",
        "1",
        0,
        50,
        (
            "N_c for undrained bearing at the surface (Prandtl 1920); deep penetration tends to ≈ 9 "
            "(Skempton 1951)"
        ),
        math.pi + 2.0,
        incl=_OPEN_LOW,
        default_text="π + 2 ≈ 5.14",
    ),
    _switch("sediment.pore_pressure", "add the pore-water force of seed 000 eq. (73)", False),
    _f(
        "sediment.rupture_length",
        "m",
        0,
        10,
        "B of seed 000 eq. (73), undefined there; the force grows as B³ ([physics.md](physics.md))",
        0.1,
        incl=_OPEN_LOW,
    ),
    _f(
        "sediment.permeability",
        "m s-1",
        0,
        1,
        "k_p of seed 000 eq. (73) (1e-4: its ref. [15])",
        1e-4,
        incl=_OPEN_LOW,
    ),
    _f("sediment.void_ratio", "1", 0, 20, "e_v of seed 000 eq. (73) (≈ 0.5 there)", 0.5, incl=_OPEN_LOW),
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
        (
            "error-controlled Dormand–Prince 5(4) in air and water and the Rosenbrock-W method "
            "ROS34PW2 (linearly implicit in the velocities) in contact with the seabed (default of "
            "the `mineburial` model); Dormand–Prince 5(4) throughout (default of the `impact35` "
            "model, whose delta law the Rosenbrock-W step does not speed up); the fixed-step "
            "classical Runge–Kutta reference; the local-linearisation step of seed 000 eqs. "
            "(83)–(87); or the Rosenbrock-W step ROS34PW2 throughout"
        ),
        default_text="by model",
    ),
    _f(
        "numerics.dt",
        "s",
        0,
        1,
        "time step of `rk4` and `local_linear`; first trial step of the adaptive integrators",
        1e-3,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.t_max",
        "s",
        0,
        1e6,
        (
            "limit on the simulated time after the mine first touches the seabed (status "
            "`time_limit`, or `buried_sinking`, when reached); a mine released in contact with the "
            "seabed counts it from release"
        ),
        60.0,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.rest_speed",
        "m s-1",
        0,
        10,
        (
            "the mine is at rest when its COM speed is below this (seed 000 eq. (89); printed as ε1 ="
            ' 1e-6 "m", a speed) and the sediment can hold it against forces and torques (rigid-'
            "plastic hold test probed at this speed; `mineburial/kernels/mine/rest.py`, docs/design.md); "
            "see also numerics.rest_spin"
        ),
        1e-2,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.rest_spin",
        "rad s-1",
        0,
        100,
        "the mine is at rest only when its angular speed is below this too (with numerics.rest_speed)",
        5e-2,
        incl=_OPEN_LOW,
    ),
    _switch("numerics.drag", "fluid drag and lift on (switch off for energy checks)", True),
    _f(
        "numerics.munk_factor",
        "1",
        0,
        1,
        (
            "fraction of the potential-flow Munk moment kept by the added-mass tensor: 0 gives the "
            "axial direction the transverse added mass (no Munk moment; chosen on the Exp-1 drops), 1"
            " is slender-body strip theory (docs/physics.md §2)"
        ),
        0.0,
    ),
    _f(
        "numerics.rtol",
        "1",
        0,
        0.1,
        (
            "relative tolerance of the adaptive integrators (per step, RMS over position, velocity, "
            "quaternion, angular velocity); chosen from the work-precision measurements "
            "(docs/design.md)"
        ),
        3e-4,
        incl=_OPEN_LOW,
        default_text="3e-4 (`mineburial`), 1e-5 (`impact35`)",
    ),
    _f(
        "numerics.atol",
        "1",
        0,
        1.0,
        "absolute tolerance of the adaptive integrators (m, m s⁻¹, 1, rad s⁻¹)",
        3e-5,
        incl=_OPEN_LOW,
        default_text="3e-5 (`mineburial`), 1e-6 (`impact35`)",
    ),
    _choice(
        "numerics.sediment_quadrature",
        SEDIMENT_QUADRATURE_NAMES,
        (
            "rule for the sediment tractions over the embedded surface: the fixed-cost rule, smooth "
            "in the state (docs/notes/sediment_fast.md), or the accurate adaptive quadrature "
            "(docs/notes/sediment.md)"
        ),
        "fast",
    ),
    _f(
        "numerics.slip_speed",
        "m s-1",
        0,
        0.1,
        (
            "regularisation speed of the slip direction of the sediment's tangential traction (seed "
            "000 eq. (67)): it ramps up over this slip speed (1e-3 before the adaptive integrator; "
            'the rest test uses the unregularised law; docs/design.md, "Time stepping")'
        ),
        5e-3,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.switch_speed",
        "m s-1",
        0,
        0.1,
        (
            "regularisation speed of the advancing switch δ of seed 000 eq. (65): the normal traction"
            " ramps up over this normal speed (1e-4 before the adaptive integrator)"
        ),
        5e-3,
        incl=_OPEN_LOW,
    ),
    _f(
        "numerics.t_max_fall",
        "s",
        0,
        1e6,
        (
            "limit on the simulated time of the fall, from release to the first seabed contact "
            "(status `time_limit` when reached while still falling); the fall ends by itself at the "
            "seabed, so this only guards a mine that barely sinks, or stops a fall at a chosen time. "
            'Until version 0.1.0 `t_max` bounded the whole drop (docs/design.md, "The end of a drop")'
        ),
        600.0,
        incl=_OPEN_LOW,
    ),
    _choice(
        "numerics.water_column",
        WATER_COLUMN_NAMES,
        (
            "water-column added-mass and moment model: strip-theory added mass with the axial added "
            "mass set by `munk_factor` (default), or the viscous-crossflow method (Allen & Perkins "
            "1951; Jorgensen, NASA TR R-474) with the added-mass tensor of the finite closed cylinder"
            " (BEM tables) and the Munk moment × cos(α/2) × `crossflow_munk_fraction`, `munk_factor` "
            'unused (docs/physics.md, "Water-column model choices")'
        ),
        "munk_factor",
    ),
    _choice(
        "numerics.overburden_quadrature",
        OVERBURDEN_QUADRATURE_NAMES,
        (
            "rule for the geostatic overburden force (`friction`, `bearing`): `fast` slices the body "
            "at the table's depths while at most 12 lie inside it (exact) and in 12 equal slices "
            "beyond (cost independent of the table's rows; error ~1e-5 on smooth profiles), "
            "`reference` at every table depth while at most 256 lie inside it and in 256 equal slices "
            "beyond (error ~1e-6 of the former slicing at every depth on a rough 20,000-row core) "
            "(docs/notes/sediment.md)"
        ),
        "fast",
    ),
    # --- calibration coefficients (issue 32): constants of the kernels made inputs, appended
    # after the last slot (module docstring); with their defaults the kernels compute what they
    # did with the constants (docs/physics.md, "Calibration coefficients as inputs")
    _f(
        "sediment.bearing_depth_factor",
        "1",
        0,
        5,
        (
            "f of Brinch Hansen's (1970) depth factor in the `bearing` law, N_c(ζ) = N_c0 (1 + f "
            "arctan(ζ/d)) with N_c0 = `bearing_factor`: the deep value is N_c0 (1 + f π/2), 8.4 with "
            "the defaults (Skempton 1951: 7.5 strip, 9 circle); analyses of dynamically installed "
            "anchors use a deep N_c ≈ 12 (O'Loughlin et al. 2013), f ≈ 0.85"
        ),
        0.4,
    ),
    _f(
        "numerics.crossflow_drag_factor",
        "1",
        0,
        5,
        (
            "factor on seed 000 eq. (44)'s cross-flow drag coefficient where Re > 150 000, the "
            "super-critical range whose value the surface roughness sets (smooth post-critical "
            "cylinders ≈ 0.3–0.55, rough ones ≈ 0.8–1.2: Achenbach 1971, Achenbach & Heinecke 1981; "
            "DATCOM's C_dc 1.2); every water-column model and `impact35`; unchanged below"
        ),
        1.0,
        incl=_OPEN_LOW,
    ),
    _f(
        "sediment.inertial_drag",
        "1",
        0,
        2,
        (
            "C_D of the soil's inertial drag, a normal pressure ½ C_D ρ_s v_n² on every advancing "
            "embedded element (the drag term ½ C_D ρ_s A v² of True 1976, Aubeny & Shi 2006, "
            "O'Loughlin et al. 2013: C_D ≈ 0.24–0.7 there); 0: none, as in seed 000"
        ),
        0.0,
    ),
    _f(
        "numerics.crossflow_munk_fraction",
        "1",
        0,
        1,
        (
            "fraction of the potential-flow (Munk) moment kept by the `viscous_crossflow` model, "
            "(k_t − k_a) ρV U² sinα cosα · cos(α/2) (Jorgensen, NASA TR R-474) times this fraction:"
            " 1 the full moment (Allen & Perkins 1951), 0 none — the same continuous Munk fraction as"
            ' `munk_factor` of the `munk_factor` model (docs/physics.md, "Water-column model '
            'choices"); unused by the other models'
        ),
        1.0,
    ),
    _f(
        "numerics.added_mass_factor",
        "1",
        0,
        3,
        (
            "factor on every added-mass coefficient of the water column (transverse, axial and "
            "rotational: strip theory's C_M = 1 of seed 001 eqs. (20)–(21), or the finite cylinder's "
            "BEM tensor of `viscous_crossflow`); 1 the potential-flow values, which measured "
            "effective added masses of finite cylinders in real flows scatter about (docs/physics.md,"
            ' "Calibration coefficients as inputs")'
        ),
        1.0,
        incl=_OPEN_LOW,
    ),
    # the body's shape (issue 36): slots appended after the last slotted field (layout.py)
    _choice(
        "mine.shape",
        MINE_SHAPES,
        (
            "the body's shape: `cylinder` (seed 000), or `frustum`, a solid truncated cone whose base "
            "(the tail, diameter `mine.diameter`) and top (the nose, `mine.top_ratio` of it) are "
            "`mine.length` apart; one per scenario, not sampled (it is the compiled body's type; "
            "docs/bodies_revolution.md)"
        ),
        "cylinder",
        sampled=False,
    ),
    _f(
        "mine.top_ratio",
        "1",
        0,
        1,
        (
            "a frustum's top (nose) diameter over its base diameter `mine.diameter` (0 a cone); "
            "1 for the cylinder, whose ends are equal"
        ),
        1.0,
    ),
    # --- post-impact scour, the optional [scour] section (docs/scour.md): no kernel slot of the
    # impact phase; read by mineburial/systems/mine/processes/scour.py (its key list is this table's), the
    # numbers packed into the stage's own parameters there. First the keys that set up the stage
    # (a forcing, lists, a switch, a law: none may be sampled), then its numbers and conventions.
    _setup(
        "scour.forcing",
        "text",
        "the forcing series: Hs, a period, wave direction, current, optional water level (formats and "
        "checks: docs/scour.md, Forcing)",
        "a `.csv` or `.nc` path (relative to the scenario file), or the name of a shipped forcing "
        "(`storm_example`)",
    ),
    _setup(
        "scour.storm",
        "table",
        "a parametrised storm instead of a file (exactly one of `forcing`, `storm`)",
        "inline table of `storm_series` keywords: `peak_hs`, `peak_tp`, `duration_h` (required), `ramp`, "
        "`current`, `start`, `step_h`, `peak_h`, `total_h`, `background_hs`, `background_current`, "
        "`wave_from`, `current_to`, `surge`",
    ),
    _setup(
        "scour.forcing_grid",
        "text",
        "`mineburial map` only: each water cell takes its own series (docs/maps.md, Burial over time); "
        "`run`, `compare` and `sensitivity` refuse it",
        "a `.nc` path (relative to the scenario file) with (time, y, x) variables on the environment "
        "grid's cells",
    ),
    _setup(
        "scour.forcing_location",
        "list",
        "the point of a gridded wave product (ERA5, Copernicus Marine, WAVEWATCH III) given as "
        "`forcing`, its series interpolated bilinearly there and linearly in time to 1 h steps "
        "(docs/scour.md, Wave-model products)",
        "[latitude, longitude]: latitude in [-90, 90], longitude in [-360, 360] (modulo 360), inside "
        "the product's grid",
        units="deg",
        default_text="none (optional): `forcing` is then one series (time)",
    ),
    _setup(
        "scour.lead_times_days",
        "list",
        "times after the forcing's first record at which the burial is reported (coordinate `lead_time`)",
        "non-empty, strictly increasing, in [0, the forcing's span]",
        units="d",
        low=0.0,
        default_text="none (optional): `run` and `map` then report no lead time, only the times to the "
        "burial levels and the mobility; `compare` and `sensitivity` take the end of each drop's "
        "forcing window",
    ),
    _setup(
        "scour.burial_levels",
        "list",
        "levels of B/D (a lying body; B/h for one standing on its base) whose time to reach is reported",
        "strictly increasing, in [0, 1]",
        units="1",
        low=0.0,
        high=1.0,
        default=(0.5, 0.75),
        default_text="`[0.5, 0.75]`",
    ),
    Field(
        "scour.cohesive",
        "1",
        description="a cohesive bed (mud, clay) does not scour in this model: the laws used are fitted to "
        "non-cohesive sand and contain no bed strength (Whitehouse et al. 2000; docs/scour.md)",
        default=False,
        kind="bool",
        sampled=False,
        default_text="`sediment.class`'s (`true` for every class but `sand`), else `false`",
    ),
    _choice(
        "scour.tstar_law",
        SCOUR_TSTAR_LAWS,
        "the time-scale law T* = c KC^m θ^p (docs/scour.md)",
        "whitehouse",
        slot=False,
        sampled=False,
    ),
    Field(
        "scour.window_days",
        "d",
        0.0,
        math.inf,
        False,
        True,
        "each drop sees only a window of this length of the forcing, lead times counted from the "
        "window's start; where it starts is `scour.window_position` (docs/scour.md, Forcing window)",
        sampled=False,
        default_text="the whole series",
        allowed_text="(0, the forcing's span]",
    ),
    _f(
        "scour.d50",
        "m",
        6.25e-5,
        2e-3,
        "median grain size of the bed's sand (Wentworth's sand)",
        2e-4,
        slot=False,
        default_text="`sediment.class`'s (sand 0.0002), else 0.0002",
    ),
    _f(
        "scour.grain_density",
        "kg m-3",
        1200,
        8000,
        "density of the sand grains (quartz 2650)",
        2650,
        slot=False,
        default_text="`sediment.class`'s (2650), else 2650",
    ),
    _f(
        "scour.mobile_layer",
        "m",
        0,
        100,
        "thickness of the mobile sand layer over a bed scour cannot dig: caps the burial",
        incl=_OPEN_LOW,
        slot=False,
        default_text="unlimited",
    ),
    _f(
        "scour.beq_a",
        "1",
        0,
        100,
        (
            "a of B_eq/D = a θ^b (Rennie, Brandt & Friedrichs 2017: 1.3 for D > 8 cm; 15 for small or"
            " tapered objects). **Sampling range: about 1.1–1.5** around the fit (assumption: the "
            "paper gives the fit, not its spread)"
        ),
        1.3,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.beq_b",
        "1",
        0,
        3,
        (
            "b of the same law (0.36; 1.1 for small objects). **Sampling range: about 0.30–0.42** "
            "(assumption, as for a)"
        ),
        0.36,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.theta_exponent",
        "1",
        -5,
        0,
        (
            "exponent p of θ in T*. **Sampling range: −2.2 to −1.3** (Whitehouse 1998 −1.29; piles in"
            " current −2.2, Sumer et al. 1992; Larsen & Fuhrman 2023 about −1.5 at field scale)"
        ),
        slot=False,
        default_text="the law's (−1.29 Whitehouse; −5/3 pipeline; −3 pile in waves)",
    ),
    _f(
        "scour.ripple_exposure",
        "1",
        0,
        5,
        (
            "coarse sand: burial stops where the mine stands this many ripple heights above the "
            "ripple crests (Traykovski et al. 2007, MVCO: about one; docs/scour.md, Coarse sand)"
        ),
        1.0,
        slot=False,
    ),
    _choice(
        "scour.burial_law",
        (*SCOUR_BURIAL_LAWS, SCOUR_LAW_FROM_POSTERIOR),
        (
            "the burial law (a model-form choice, docs/scour.md): `rennie`, the first version's one state "
            "B relaxing to B_eq/D = a θ^b (Rennie et al. 2017), no memory; `scour_settle`, a scour pit "
            "S and the mine's burial B as separate states: the pit deepens toward a wave-, current- and "
            "combined-flow equilibrium that is zero at the threshold of motion, the mine settles into it "
            "(B >= S), the pit infills in calm spells (scour.infill_days) without lifting the mine, and "
            "the far-field bed may lower (scour.bed_lowering_rate); `posterior`, each drop's law drawn with "
            "its coefficient set from the posterior of `ensemble.coefficients`, which carries the "
            "evidence's weight on each law (docs/calibration.md). A named law with a posterior gets the "
            "coefficients of the posterior's sets of that law"
        ),
        "rennie",
        slot=False,
        sampled=False,
    ),
    _f(
        "scour.wave_a",
        "1",
        0,
        5,
        (
            "`scour_settle`: a_w of the wave pit S/D = a_w KC^m_w (Sumer & Fredsøe 1990, pipelines "
            "in waves, live bed: 0.1). **Sampling range: about 0.05–0.6** (short cylinders settle "
            "into their pits and bury deeper than pipelines scour; docs/scour.md)"
        ),
        0.1,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.wave_kc_exponent",
        "1",
        0,
        2,
        "`scour_settle`: m_w of the same law (Sumer & Fredsøe 1990: 0.5). **Sampling range: about 0.3–0.8**",
        0.5,
        slot=False,
    ),
    _f(
        "scour.infill_days",
        "d",
        0,
        1e6,
        (
            "`scour_settle`: time scale of the pit's infill toward a shallower equilibrium (the ambient "
            "bed in calm); the mine is not lifted. Judgement: field pits infill over days to weeks "
            "(docs/scour.md, Infill). **Sampling range: about 1–30 d**"
        ),
        5.0,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.bed_lowering_rate",
        "m d-1",
        0,
        1,
        (
            "`scour_settle`: lowering rate of the far-field bed (erosion by a migrating bar or a storm "
            "profile): re-exposes the mine, whose burial falls with the bed until it rests on it or in "
            "its pit (docs/scour.md, Re-exposure). 0: a stable bed"
        ),
        0.0,
        slot=False,
    ),
    _choice(
        "scour.mobility",
        SCOUR_MOBILITY_NAMES,
        (
            "the mobility criterion: `proud`, the first version's rigid-bottom threshold of Rennie et al. "
            "(2017) while B/D <= 0.1; `pocket`, that threshold raised by the burial: the moment balance "
            "of a lying cylinder rolling out of a depression of depth B (docs/scour.md, Mobility)"
        ),
        "proud",
        slot=False,
        sampled=False,
    ),
    _choice(
        "scour.rest_attitude",
        SCOUR_REST_ATTITUDES,
        (
            "the mine's attitude at lead time 0 (a model-form choice, docs/scour.md, Tilt): `flat`, the "
            "cylinder laid level with the impact's buried volume (the first version's); `impact`, the "
            "impact's own rest attitude, its tilt a state: the two ends' depths, each settling into the "
            "pit where it rests in the sand, so the mine levels as the pit passes its higher end and lies "
            'in the pit once the pit reaches its lower end (needs `burial_law = "scour_settle"`)'
        ),
        "flat",
        slot=False,
        sampled=False,
    ),
    _f(
        "scour.mobility_drag",
        "1",
        0,
        5,
        (
            "`pocket` mobility: drag coefficient C_D of the lying cylinder in cross-flow (1.2, "
            "subcritical Reynolds number). **Sampling range: about 0.8–1.5**"
        ),
        1.2,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.hs_scale",
        "1",
        0,
        10,
        ("factor on every significant wave height of the forcing (hindcast uncertainty; the period is kept)"),
        1.0,
        incl=_OPEN_LOW,
        slot=False,
    ),
    _f(
        "scour.window_position",
        "1",
        0,
        1,
        (
            "where each drop's window of scour.window_days starts in the forcing: 0 its first record, "
            "1 the last start that fits (a uniform draw is a start date drawn from a long series)"
        ),
        0.0,
        slot=False,
    ),
    _choice(
        "scour.orbital",
        SCOUR_ORBITAL_NAMES,
        (
            "near-bed orbital velocity and period: `spectral` from a JONSWAP spectrum (Wiberg & "
            "Sherwood 2008), `hrms` a monochromatic wave of height H_rms = Hs/√2 and period Tp, `hs` "
            "one of height Hs (about 50 % above `spectral`; docs/scour.md, Choices)"
        ),
        "spectral",
        slot=False,
        sampled=False,
    ),
    _choice(
        "scour.friction",
        SCOUR_FRICTION_NAMES,
        "wave friction factor: Swart (1974) or Soulsby (1997, eq. 62a) (docs/scour.md, Closures)",
        "swart",
        slot=False,
        sampled=False,
    ),
)
