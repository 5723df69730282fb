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

from mineburial.systems.mine.scenario_fields import (  # noqa: F401 - the names of the coded choices, re-exported
    CURRENT_KINDS,
    INTEGRATOR_NAMES,
    MINE_SHAPES,
    MODEL_NAMES,
    OVERBURDEN_QUADRATURE_NAMES,
    RATE_LAW_NAMES,
    RESISTANCE_NAMES,
    SEDIMENT_QUADRATURE_NAMES,
    WATER_COLUMN_NAMES,
)
from mineburial.systems.mine.scenario_fields import TABLE as _TABLE

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

# --- columns of a recorded trajectory row (kernels.mine.stepper._record) -----------
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
# The slots are the fields of mineburial.systems.mine.scenario_fields.TABLE that have one, in the
# table's order: a field is declared there once. The constants below are looked up by
# name, so no positional list can drift from the table (tests/test_schema.py checks that
# every slot has exactly one constant and that the kernels use no other). A new slot is
# appended after the last slotted field: numba's disk cache is keyed on each kernel's own
# file, so a kernel compiled before a slot moved would read the old index (the test pins
# the order).
PARAM_NAMES = tuple(f.path for f in _TABLE if f.slot)
N_PARAMS = len(PARAM_NAMES)
INDEX = {name: i for i, name in enumerate(PARAM_NAMES)}

# Module-level integer constants for use inside kernels (numba treats them as
# compile-time constants).
P_LENGTH = INDEX["mine.length"]
P_DIAMETER = INDEX["mine.diameter"]
P_MASS = INDEX["mine.mass"]
P_CHI = INDEX["mine.com_offset"]
P_J1 = INDEX["mine.inertia_axial"]
P_J2 = INDEX["mine.inertia_transverse"]
P_X0 = INDEX["release.x"]
P_Y0 = INDEX["release.y"]
P_Z0 = INDEX["release.z"]
P_U0 = INDEX["release.u"]
P_V0 = INDEX["release.v"]
P_W0 = INDEX["release.w"]
P_Q00 = INDEX["release.q0"]
P_Q10 = INDEX["release.q1"]
P_Q20 = INDEX["release.q2"]
P_Q30 = INDEX["release.q3"]
P_OM10 = INDEX["release.omega1"]
P_OM20 = INDEX["release.omega2"]
P_OM30 = INDEX["release.omega3"]
P_GRAVITY = INDEX["environment.gravity"]
P_RHO_AIR = INDEX["environment.air_density"]
P_NU_AIR = INDEX["environment.air_viscosity"]
P_RHO_WATER = INDEX["environment.water_density"]
P_NU_WATER = INDEX["environment.water_viscosity"]
P_DEPTH = INDEX["environment.water_depth"]
P_CURRENT_KIND = INDEX["current.kind"]
P_CURRENT_U = INDEX["current.u"]
P_CURRENT_V = INDEX["current.v"]
P_CURRENT_EXPONENT = INDEX["current.exponent"]
P_CURRENT_TABLE = INDEX["current.table_index"]
P_SED_PROFILE = INDEX["sediment.profile_index"]
P_SED_RHO = INDEX["sediment.density"]
P_SED_RHO_GRAD = INDEX["sediment.density_gradient"]
P_SED_S = INDEX["sediment.strength"]
P_SED_S_GRAD = INDEX["sediment.strength_gradient"]
P_SED_RESISTANCE = INDEX["sediment.resistance"]
P_SED_RATE_LAW = INDEX["sediment.rate_law"]
P_SED_A = INDEX["sediment.impact_factor"]
P_SED_VREST = INDEX["sediment.rest_speed"]
P_SED_BETA = INDEX["sediment.rate_coefficient"]
P_SED_RATE_REF = INDEX["sediment.reference_rate"]
P_SED_MU = INDEX["sediment.friction"]
P_SED_NC = INDEX["sediment.bearing_factor"]
P_SED_PORE = INDEX["sediment.pore_pressure"]
P_SED_B = INDEX["sediment.rupture_length"]
P_SED_KP = INDEX["sediment.permeability"]
P_SED_EV = INDEX["sediment.void_ratio"]
P_MODEL = INDEX["numerics.model"]
P_INTEGRATOR = INDEX["numerics.integrator"]
P_DT = INDEX["numerics.dt"]
P_TMAX = INDEX["numerics.t_max"]
P_REST_SPEED = INDEX["numerics.rest_speed"]
P_REST_SPIN = INDEX["numerics.rest_spin"]
P_DRAG = INDEX["numerics.drag"]
P_MUNK = INDEX["numerics.munk_factor"]
P_RTOL = INDEX["numerics.rtol"]
P_ATOL = INDEX["numerics.atol"]
P_SED_QUADRATURE = INDEX["numerics.sediment_quadrature"]
P_SLIP_SPEED = INDEX["numerics.slip_speed"]
P_SWITCH_SPEED = INDEX["numerics.switch_speed"]
P_TMAX_FALL = INDEX["numerics.t_max_fall"]
P_WATER_COLUMN = INDEX["numerics.water_column"]
P_OB_QUADRATURE = INDEX["numerics.overburden_quadrature"]
P_SED_DEPTH_FACTOR = INDEX["sediment.bearing_depth_factor"]
P_CROSSFLOW_FACTOR = INDEX["numerics.crossflow_drag_factor"]
P_SED_CD = INDEX["sediment.inertial_drag"]
P_CROSSFLOW_MUNK = INDEX["numerics.crossflow_munk_fraction"]
P_ADDED_MASS_FACTOR = INDEX["numerics.added_mass_factor"]
P_SHAPE = INDEX["mine.shape"]
P_TOP_RATIO = INDEX["mine.top_ratio"]

WC_MUNK_FACTOR = WATER_COLUMN_NAMES.index("munk_factor")
WC_VISCOUS_CROSSFLOW = WATER_COLUMN_NAMES.index("viscous_crossflow")

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
