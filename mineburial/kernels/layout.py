"""Index layout of the flat arrays that carry one drop through the kernels.

A drop is fully described by

* one **parameter vector** ``p`` (float64, length :data:`N_PARAMS`) whose entries
  are named after the scenario fields they come from (``PARAM_NAMES``), and
* two **banks** of tabulated profiles shared by all drops of a run:
  ``sediment_bank`` with shape ``(n_profiles, 3, n_points)`` holding
  ``(depth below seabed [m], bulk density [kg m-3], undrained shear strength [Pa])``
  and ``current_bank`` with shape ``(n_currents, 3, n_points)`` holding
  ``(depth below surface [m], u [m s-1], v [m s-1])``; rows are padded with NaN
  after their last point. A drop selects a row with ``sediment.profile_index`` /
  ``current.table_index`` (``-1``: use the parametric form in ``p`` instead).

The names are the dotted paths of the scenario file, so an ensemble can map a
sampled scenario field straight onto its slot (``INDEX["mine.mass"]``).

The per-drop **state** is 13 floats: position and velocity of the centre of mass
in the E-frame, the unit quaternion body->earth, the body angular velocity; the
kernels carry it **extended** by two work accumulators (:data:`N_EXT`). The phase
codes, the columns of a recorded trajectory and the per-drop summary are declared
here too, once.
"""

# --- state -----------------------------------------------------------------
X, Y, Z, U, V, W, Q0, Q1, Q2, Q3, P, Q, R = range(13)
N_STATE = 13
STATE_NAMES = ("x", "y", "z", "u", "v", "w", "q0", "q1", "q2", "q3", "omega1", "omega2", "omega3")

# --- extended state: the state plus two work accumulators --------------------
# (the work done on the mine by fluid forces and by sediment forces, integrated with
# the state so that the energy bookkeeping closes to the integration error)
N_EXT = 15
I_WORK_FLUID = 13
I_WORK_SEDIMENT = 14
N_WORK = 48  # size of the per-drop scratch array of dynamics.derivatives()
N_DIAG = 16  # diagnostics written by dynamics.derivatives()

# --- phase of the mine with respect to the interfaces (output variable "phase") ---
PHASE_NAMES = ("air", "crossing_water_surface", "water", "crossing_seabed", "embedded")
PHASE_AIR, PHASE_SURFACE, PHASE_WATER, PHASE_SEABED, PHASE_EMBEDDED = range(len(PHASE_NAMES))

# --- columns of a recorded trajectory row (kernels.stepper._record) -----------
TRAJ_COLUMNS = (
    ("time",)
    + STATE_NAMES
    + (
        "work_fluid",
        "work_sediment",
        "phase",
        "fluid_force_x",
        "fluid_force_y",
        "fluid_force_z",
        "sediment_force_x",
        "sediment_force_y",
        "sediment_force_z",
        "torque_1",
        "torque_2",
        "torque_3",
    )
)
N_TRAJ = len(TRAJ_COLUMNS)

# --- parameter vector ------------------------------------------------------
PARAM_NAMES = (
    # mine (body)
    "mine.length",  # m
    "mine.diameter",  # m
    "mine.mass",  # kg
    "mine.com_offset",  # m, chi of seed 000 (COM towards the nose > 0)
    "mine.inertia_axial",  # kg m2, J1 about the COM
    "mine.inertia_transverse",  # kg m2, J2 = J3 about the COM
    # release (initial state)
    "release.x",
    "release.y",
    "release.z",  # m
    "release.u",
    "release.v",
    "release.w",  # m s-1
    "release.q0",
    "release.q1",
    "release.q2",
    "release.q3",
    "release.omega1",
    "release.omega2",
    "release.omega3",  # rad s-1, body frame
    # environment
    "environment.gravity",  # m s-2
    "environment.air_density",  # kg m-3
    "environment.air_viscosity",  # m2 s-1 (kinematic)
    "environment.water_density",  # kg m-3
    "environment.water_viscosity",  # m2 s-1 (kinematic)
    "environment.water_depth",  # m
    "current.kind",  # 0 none, 1 uniform, 2 power law (seed 004 eq. (38)), 3 table
    "current.u",  # m s-1, uniform value or surface value of the power law
    "current.v",  # m s-1
    "current.exponent",  # power-law exponent (1/7 in seed 004)
    "current.table_index",  # row of current_bank, -1 for none
    # sediment
    "sediment.profile_index",  # row of sediment_bank, -1: linear profile below
    "sediment.density",  # kg m-3 at the seabed (linear profile)
    "sediment.density_gradient",  # kg m-4
    "sediment.strength",  # Pa at the seabed (linear profile)
    "sediment.strength_gradient",  # Pa m-1
    "sediment.resistance",  # code of the resistance model (kernels.sediment)
    "sediment.rate_law",  # code of the strain-rate law
    "sediment.impact_factor",  # A of seed 000 eq. (70)
    "sediment.rest_speed",  # V_rest of seed 000 eq. (70), m s-1
    "sediment.rate_coefficient",  # beta of the semi-logarithmic law
    "sediment.reference_rate",  # reference strain rate of the semi-log law, s-1
    "sediment.friction",  # mu, tangential/normal traction ratio
    "sediment.bearing_factor",  # N_c, bearing-capacity factor
    "sediment.pore_pressure",  # 0/1, seed 000 eq. (73) on or off
    "sediment.rupture_length",  # B of eq. (73), m
    "sediment.permeability",  # k_p of eq. (73), m s-1
    "sediment.void_ratio",  # e_v of eq. (73)
    # numerics
    "numerics.model",  # 0 mineburial (default), 1 impact35
    "numerics.integrator",  # 0 rk4, 1 local_linear (seed 000 eqs. (83)-(87)), 2 dopri5
    "numerics.dt",  # s
    "numerics.t_max",  # s, limit on the simulated time after the first seabed contact
    "numerics.rest_speed",  # m s-1, eq. (89) speed criterion
    "numerics.rest_spin",  # rad s-1
    "numerics.drag",  # 1/0: fluid drag and lift on (0 for energy tests)
    "numerics.munk_factor",  # fraction of the potential-flow Munk moment kept (docs/physics.md)
    "numerics.rtol",  # relative tolerance of the adaptive integrator
    "numerics.atol",  # absolute tolerance of the adaptive integrator (scaled units)
    "numerics.sediment_quadrature",  # 0 fast (fixed-cost rule), 1 reference (adaptive quadrature)
    "numerics.slip_speed",  # m s-1, regularisation speed of the sediment's slip direction
    "numerics.switch_speed",  # m s-1, regularisation speed of the sediment's advancing switch
    "numerics.t_max_fall",  # s, limit on the simulated time of the fall (release to seabed contact)
    "numerics.water_column",  # code of the water-column added-mass/moment model (WATER_COLUMN_NAMES)
    "numerics.overburden_quadrature",  # 0 fast (bounded cost), 1 reference (a slice per table depth)
)
N_PARAMS = len(PARAM_NAMES)
INDEX = {name: i for i, name in enumerate(PARAM_NAMES)}

# Module-level integer constants for use inside kernels (numba treats them as
# compile-time constants).
(
    P_LENGTH,
    P_DIAMETER,
    P_MASS,
    P_CHI,
    P_J1,
    P_J2,
    P_X0,
    P_Y0,
    P_Z0,
    P_U0,
    P_V0,
    P_W0,
    P_Q00,
    P_Q10,
    P_Q20,
    P_Q30,
    P_OM10,
    P_OM20,
    P_OM30,
    P_GRAVITY,
    P_RHO_AIR,
    P_NU_AIR,
    P_RHO_WATER,
    P_NU_WATER,
    P_DEPTH,
    P_CURRENT_KIND,
    P_CURRENT_U,
    P_CURRENT_V,
    P_CURRENT_EXPONENT,
    P_CURRENT_TABLE,
    P_SED_PROFILE,
    P_SED_RHO,
    P_SED_RHO_GRAD,
    P_SED_S,
    P_SED_S_GRAD,
    P_SED_RESISTANCE,
    P_SED_RATE_LAW,
    P_SED_A,
    P_SED_VREST,
    P_SED_BETA,
    P_SED_RATE_REF,
    P_SED_MU,
    P_SED_NC,
    P_SED_PORE,
    P_SED_B,
    P_SED_KP,
    P_SED_EV,
    P_MODEL,
    P_INTEGRATOR,
    P_DT,
    P_TMAX,
    P_REST_SPEED,
    P_REST_SPIN,
    P_DRAG,
    P_MUNK,
    P_RTOL,
    P_ATOL,
    P_SED_QUADRATURE,
    P_SLIP_SPEED,
    P_SWITCH_SPEED,
    P_TMAX_FALL,
    P_WATER_COLUMN,
    P_OB_QUADRATURE,
) = range(N_PARAMS)

# model and integrator codes
MODEL_NAMES = ("mineburial", "impact35")
INTEGRATOR_NAMES = ("rk4", "local_linear", "dopri5", "dopri5_ros34pw2")
SEDIMENT_QUADRATURE_NAMES = ("fast", "reference")
OVERBURDEN_QUADRATURE_NAMES = ("fast", "reference")  # kernels/overburden.py
CURRENT_KINDS = ("none", "uniform", "power_law", "table")
# water-column models (docs/physics.md, "Water-column model choices"): the strip added mass
# with the tuned numerics.munk_factor, or the viscous-crossflow method with the added-mass
# tensor of the finite cylinder
WATER_COLUMN_NAMES = ("munk_factor", "viscous_crossflow")
WC_MUNK_FACTOR = 0
WC_VISCOUS_CROSSFLOW = 1

# --- per-drop summary (results) -------------------------------------------
SUMMARY_NAMES = (
    "penetration_depth",  # m, lowest point of the mine below the seabed
    "com_depth",  # m, centre of mass below the seabed (negative: above)
    "burial_volume",  # percent of the volume below the seabed
    "burial_height",  # percent of the vertical extent below the seabed
    "burial_area",  # percent of the surface area below the seabed
    "height_proud",  # m, highest point above the seabed (0 if buried)
    "final_pitch",  # deg, psi2 at rest
    "final_roll",  # deg, psi1 at rest
    "final_heading",  # deg, psi3 at rest
    "final_x",
    "final_y",  # m, COM position at rest
    "impact_speed",  # m s-1, COM speed at first contact with the seabed
    "impact_pitch",  # deg, psi2 at first contact
    "impact_angle",  # deg, angle of the COM velocity below the horizontal at contact
    "impact_time",  # s, time of first contact with the seabed
    "water_entry_time",  # s, time of first contact with the water surface
    "total_time",  # s
    "max_deceleration",  # m s-2, largest deceleration magnitude in the sediment
    "n_steps",  # number of time steps taken
)
N_SUMMARY = len(SUMMARY_NAMES)
SUMMARY_INDEX = {name: i for i, name in enumerate(SUMMARY_NAMES)}
(
    S_PENETRATION,
    S_COM_DEPTH,
    S_BURIAL_VOLUME,
    S_BURIAL_HEIGHT,
    S_BURIAL_AREA,
    S_HEIGHT_PROUD,
    S_FINAL_PITCH,
    S_FINAL_ROLL,
    S_FINAL_HEADING,
    S_FINAL_X,
    S_FINAL_Y,
    S_IMPACT_SPEED,
    S_IMPACT_PITCH,
    S_IMPACT_ANGLE,
    S_IMPACT_TIME,
    S_ENTRY_TIME,
    S_TOTAL_TIME,
    S_MAX_DECEL,
    S_N_STEPS,
) = range(N_SUMMARY)

# sediment model codes (kernels.sediment)
RESISTANCE_NAMES = ("delta", "friction", "bearing")
RATE_LAW_NAMES = ("impact35", "semilog", "none")
