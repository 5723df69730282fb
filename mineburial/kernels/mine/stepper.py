"""The per-drop driver: integrate one drop from release to its end (seed 000 section 7).

The driver is built from parts that each live in one place:

* the **right-hand side** of the falling mine, :func:`.dynamics.derivatives`;
* the **integrator protocol** (:mod:`.integrators`): a step returns the new state, an
  error estimate (``dopri5``) and a continuous extension over the step;
* **events** as functions of the state (:func:`event_values`: the lowest and highest
  points of the mine against the water surface and the seabed; :func:`rest_measure`:
  speed and spin against the rest criteria), located by root finding on the
  continuous extension, never by re-stepping; the step is cut at the first event and
  the integration restarts there (the right-hand side is not smooth across an
  interface);
* the **end of the drop** (:mod:`.rest`): at rest when slow and held by the sediment
  (forces and torques); floated; fully buried and still sinking at the time limit;
* a **recorder** that samples the continuous extension at exact output times;
* the integration core's **driver loop** (:func:`.core.driver_loop`), which runs these through the
  mine's two hooks, :func:`_next_step` and :func:`_accepted`.

Integrators (``numerics.integrator``); every step is taken by the integration core's
:func:`.core.attempt_step`, so the mine offers each method of the core (:mod:`.methods`):

``dopri5_ros34pw2`` (default of the ``mineburial`` model)
    ``dopri5`` in air and water, ``ros34pw2`` while in contact with the sediment.
``dopri5`` (default of the ``impact35`` model)
    Dormand-Prince 5(4) with error control on a mixed tolerance
    (``numerics.rtol``, ``numerics.atol``) over position, velocity, attitude and
    angular velocity, PI step-size controller and 4th-order dense output.
``ros34pw2``
    The Rosenbrock-W method ROS34PW2 throughout, linearly implicit in the velocities
    (:data:`VELOCITY_SLOTS`), cubic Hermite continuous extension.
``rk4``
    Classical fourth-order Runge-Kutta at the fixed step ``numerics.dt`` (the
    reference; seed 004 uses Runge-Kutta for its Kane equations; seed 000 section 10
    asks for "a fully numerical calculation"), cubic Hermite continuous extension.
``local_linear``
    The recursive local-linearisation scheme of seed 000 eqs. (83)-(87): each
    velocity component obeys dv/dt = -d v + beta with d and beta frozen at t_n
    and is advanced exactly; positions by eq. (86); rotation-angle increments by
    eq. (87) with its typos fixed (docs/physics.md), composed onto the quaternion.
    The diagonal damping d of eqs. (81)-(82) is the diagonal of the Jacobian of
    the acceleration with respect to the velocity, evaluated by a one-sided
    difference so that the same scheme serves both physics models. First order.
"""

import math
from collections import namedtuple

import numpy as np
from numba.core import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS, kernel, small_kernel
from mineburial.kernels.core import GO_ON, System, all_finite, borrowed, driver_loop, keep_alive, locate_event
from mineburial.kernels.integrators import N_STAGES, ROS_STAGES, dense_state
from mineburial.kernels.methods import ADAPTIVE, DOPRI5, METHOD_NAMES, OWN_METHOD, ROS34PW2
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine import status as st
from mineburial.kernels.mine.bodies.shapes import DEFAULT_SHAPE, shape_of_params
from mineburial.kernels.mine.dynamics import body_of, derivatives, drop_body, with_shape
from mineburial.kernels.mine.layout import (
    I_WORK_FLUID,
    I_WORK_SEDIMENT,
    INTEGRATOR_NAMES,
    N_DIAG,
    N_EXT,
    N_PARAMS,
    N_SUMMARY,
    N_WORK,
    P_ATOL,
    P_DEPTH,
    P_DT,
    P_INTEGRATOR,
    P_MASS,
    P_OM10,
    P_OM20,
    P_OM30,
    P_Q00,
    P_Q10,
    P_Q20,
    P_Q30,
    P_REST_SPEED,
    P_REST_SPIN,
    P_RHO_WATER,
    P_RTOL,
    P_SED_QUADRATURE,
    P_TMAX,
    P_TMAX_FALL,
    P_U0,
    P_V0,
    P_W0,
    P_X0,
    P_Y0,
    P_Z0,
    S_BURIAL_AREA,
    S_BURIAL_HEIGHT,
    S_BURIAL_VOLUME,
    S_COM_DEPTH,
    S_ENTRY_TIME,
    S_FINAL_HEADING,
    S_FINAL_PITCH,
    S_FINAL_ROLL,
    S_FINAL_X,
    S_FINAL_Y,
    S_HEIGHT_PROUD,
    S_IMPACT_ANGLE,
    S_IMPACT_PITCH,
    S_IMPACT_SPEED,
    S_IMPACT_TIME,
    S_MAX_DECEL,
    S_N_STEPS,
    S_PENETRATION,
    S_TOTAL_TIME,
)
from mineburial.kernels.mine.rest import held_by_sediment
from mineburial.kernels.mine.sediment import QUADRATURE_FAST, pack_law
from mineburial.kernels.mine.sediment.laws import drop_bank
from mineburial.kernels.rotation import (
    euler_angles,
    normalize_quaternion,
    quaternion_multiply,
    rotation_matrix,
    rotation_vector_quaternion,
)

INTEGRATOR_STIFF = INTEGRATOR_NAMES.index("dopri5_ros34pw2")
#: the mine's own integrators beside the core's (:mod:`.methods`): the phase switch dopri5_ros34pw2
#: (Dormand-Prince 5(4), the Rosenbrock-W step ROS34PW2 while in contact with the sediment) and the
#: seed's local-linearisation step (a fixed step of the mine's own, :func:`mine_own_step`)
_OWN = {"dopri5_ros34pw2": (DOPRI5, True), "local_linear": (OWN_METHOD, False)}
#: per code of numerics.integrator (P_INTEGRATOR): the core's method of a step (the stiff composite's
#: outside the sediment) and whether the steps are error-controlled
CORE_METHOD = np.array(
    [METHOD_NAMES.index(n) if n in METHOD_NAMES else _OWN[n][0] for n in INTEGRATOR_NAMES], dtype=np.int64
)
ADAPTIVE_INTEGRATOR = np.array(
    [ADAPTIVE[METHOD_NAMES.index(n)] if n in METHOD_NAMES else _OWN[n][1] for n in INTEGRATOR_NAMES]
)

#: state slots of the velocities (u, v, w, omega1..3): the columns of the Jacobian that
#: the Rosenbrock-W step uses (the stiffness of the sediment phase is in them)
VELOCITY_SLOTS = np.array([3, 4, 5, 10, 11, 12], dtype=np.int64)
N_VEL = 6

#: vector groups of the error norm: position, velocity, attitude quaternion, angular velocity
ERROR_GROUPS = ((0, 3), (3, 6), (6, 10), (10, 13))
N_EVENTS = 5  # 4 interfaces + the rest measure
EVENT_REST = 4
MAX_STEPS = 50_000_000
EVENT_TOLERANCE = 1e-12  # fraction of a step: events are located to this accuracy
MAX_EVENT_ITERATIONS = 60
REDO_MARGIN = 1e-6  # a step ending at an interface is retaken 1e-6 of a step past it
MAX_REDO = 2  # at most this many retakes per accepted step
MIN_REDO_STEP = 1e-9  # s: a crossing closer than this to the step's start is cut, not retaken
#: relative margin of the cap on a Dormand-Prince step at the seabed crossing predicted from the state at its
#: start (:func:`_seabed_cap`, the ``dopri5_ros34pw2`` integrator). A trial that straddles the seabed has the
#: sediment's force, a jump, in its stages: its error estimate sees the jump and it is rejected, shrunk by
#: up to 5x, until one is accepted and then retaken to end at the located crossing (on main f654336, 9.5 such
#: trials a default drop, 6.1 of them rejected, with 41 of its 511 sediment right-hand sides). Capped at the
#: predicted crossing plus this margin, the step ends just past the seabed with the sediment in (almost) none
#: of its stages, is accepted and retaken at the crossing as before: 2.6 such trials a drop, 4.8 sediment
#: right-hand sides (benchmarks/results/error_norm.md; margins 1e-4 to 1e-1 measured, 1e-3 the fewest).
SEABED_CAP_MARGIN = 1e-3
#: s: the time step of the one-sided difference of the lowest point's height along f (:func:`_seabed_cap`)
SEABED_RATE_STEP = 1e-6
DOMAIN_RADIUS = 1e5  # m: a drop that drifts further has left the domain
MAX_STEP = 0.5  # s: largest adaptive step (events are detected per step)
MIN_STEP = 1e-12  # s: an adaptive step below this is a numerical failure


@small_kernel
def initial_state(p, y):
    y[0] = p[P_X0]
    y[1] = p[P_Y0]
    y[2] = p[P_Z0]
    y[3] = p[P_U0]
    y[4] = p[P_V0]
    y[5] = p[P_W0]
    q0, q1, q2, q3 = normalize_quaternion(p[P_Q00], p[P_Q10], p[P_Q20], p[P_Q30])
    y[6] = q0
    y[7] = q1
    y[8] = q2
    y[9] = q3
    y[10] = p[P_OM10]
    y[11] = p[P_OM20]
    y[12] = p[P_OM30]
    y[I_WORK_FLUID] = 0.0
    y[I_WORK_SEDIMENT] = 0.0


@small_kernel
def _normalize_attitude(y):
    q0, q1, q2, q3 = normalize_quaternion(y[6], y[7], y[8], y[9])
    y[6] = q0
    y[7] = q1
    y[8] = q2
    y[9] = q3


@kernel
def event_values(y, p, law, g):
    """Event functions of the state: signed distances of the lowest/highest point to the
    water surface (g0, g1) and to the seabed (g2, g3), and the rest measure (g4); the body is
    ``p``'s of the shape the packed ``law`` carries (:func:`.dynamics.drop_body`)."""
    qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
    a_z = 2.0 * (y[7] * y[9] - y[6] * y[8]) / (qn * qn)  # R[2,0] = i_M . k
    lo, hi = bodies.extent(drop_body(p, law), a_z, y[2])
    depth = p[P_DEPTH]
    g[0] = lo
    g[1] = hi
    g[2] = lo + depth
    g[3] = hi + depth
    g[4] = rest_measure(y, p)


@small_kernel
def rest_measure(y, p):
    """max(speed / rest_speed, spin / rest_spin) - 1: negative when the mine is slow
    enough to be at rest by seed 000 eq. (89) (epsilon_1 on the speed, as a speed)."""
    speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
    spin = math.sqrt(y[10] * y[10] + y[11] * y[11] + y[12] * y[12])
    return max(speed / p[P_REST_SPEED], spin / p[P_REST_SPIN]) - 1.0


@kernel
def _exact_linear(v, d, beta, dt):
    """v(t+dt) and the integral of v over the step for dv/dt = -d v + beta.

    Seed 000 eqs. (84)-(87); eq. (87) corrected: the increment is
    (beta/d) dt - (1/d)(v - beta/d)(exp(-d dt) - 1).
    """
    if d * dt < 1e-12:
        return v + beta * dt, v * dt + 0.5 * beta * dt * dt
    e = math.exp(-d * dt)
    vinf = beta / d
    return (v - vinf) * e + vinf, vinf * dt - (v - vinf) * (e - 1.0) / d


@small_kernel
def local_linear_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, ytmp, diag, out):
    """Seed 000 local-linearisation step (eqs. (83)-(87)); k1 = f(y) pre-filled. Inlined into the
    core's fixed step (:func:`.core.fixed_trial`), one compile unit with ``rk4`` (docs/design.md)."""
    n = y.shape[0]
    # velocity slots: u v w (E-frame) and omega1..3 (body)
    for s in range(6):
        i = 3 + s if s < 3 else 7 + s  # 3,4,5,10,11,12
        h = 1e-6 * max(1.0, abs(y[i]))
        for j in range(n):
            ytmp[j] = y[j]
        ytmp[i] = y[i] + h
        derivatives(ytmp, p, law, sed_bank, cur_bank, work, k2, diag)
        d = -(k2[i] - k1[i]) / h
        if d < 0.0 or not math.isfinite(d):
            d = 0.0
        beta = k1[i] + d * y[i]
        vnew, integral = _exact_linear(y[i], d, beta, dt)
        out[i] = vnew
        if s < 3:
            out[s] = y[s] + integral  # eq. (86)
        else:
            k3[s - 3] = integral  # rotation-angle increments, eq. (87)
    q0, q1, q2, q3 = rotation_vector_quaternion(k3[0], k3[1], k3[2])
    a0, a1, a2, a3 = quaternion_multiply(y[6], y[7], y[8], y[9], q0, q1, q2, q3)
    a0, a1, a2, a3 = normalize_quaternion(a0, a1, a2, a3)
    out[6] = a0
    out[7] = a1
    out[8] = a2
    out[9] = a3
    out[I_WORK_FLUID] = y[I_WORK_FLUID] + dt * k1[I_WORK_FLUID]
    out[I_WORK_SEDIMENT] = y[I_WORK_SEDIMENT] + dt * k1[I_WORK_SEDIMENT]


@small_kernel
def _crossed(g0, g1):
    return (g0 > 0.0 and g1 <= 0.0) or (g0 <= 0.0 and g1 > 0.0)


@kernel
def _record(traj, row, t, y, p, law, sed_bank, cur_bank, work, dy, diag):
    """Recorder: one trajectory row at time t (forces evaluated at the recorded state)."""
    phase = derivatives(y, p, law, sed_bank, cur_bank, work, dy, diag)
    traj[row, 0] = t
    for i in range(N_EXT):
        traj[row, 1 + i] = y[i]
    q0, q1, q2, q3 = normalize_quaternion(y[6], y[7], y[8], y[9])
    traj[row, 7] = q0
    traj[row, 8] = q1
    traj[row, 9] = q2
    traj[row, 10] = q3
    traj[row, 16] = phase
    for i in range(9):
        traj[row, 17 + i] = diag[i]


@small_kernel
def mine_rhs(t, y, args, dy):
    """The mine's right-hand side for the integration core: dy = :func:`.dynamics.derivatives` at y
    (autonomous: t unused); args = (p, law, sed_bank, cur_bank, work, diag), diag filled as a side effect."""
    p, law, sed_bank, cur_bank, work, diag = args
    derivatives(y, p, law, sed_bank, cur_bank, work, dy, diag)


@small_kernel
def event_component(t, y, args):
    """Event ``e`` of :func:`event_values` at state y, for the core's locator; args = (p, law, e, gtmp)."""
    p, law, e, gtmp = args
    event_values(y, p, law, gtmp)
    return gtmp[e]


@small_kernel
def mine_own_step(method, t, y, h, args, k, ytmp, out):
    """The mine's own fixed step for the core (:data:`.methods.OWN_METHOD`): the local-linearisation
    step of seed 000 (:func:`local_linear_step`); args as :func:`mine_rhs`, k[0] = f(y) pre-filled."""
    p, law, sed_bank, cur_bank, work, diag = args
    local_linear_step(y, h, p, law, sed_bank, cur_bank, work, k[0], k[1], k[2], ytmp, diag, out)


#: the falling mine as a system of the integration core: its steps are the core's (:func:`.core.attempt_step`)
#: over :func:`mine_rhs`, with the quaternion normalised after a fixed step and :func:`mine_own_step` as
#: its own; its events, located by :func:`.core.locate_event`, take the parameters (p, law, e, gtmp)
#: of :func:`event_component` (one component of :func:`event_values` at a time)
#: (its sizes declared: the Rosenbrock-W step's loops unrolled, issue 34 item 4)
MINE = System(
    "mine",
    mine_rhs,
    event_component,
    project=_normalize_attitude,
    own_step=mine_own_step,
    sizes=(N_EXT, N_VEL),
)


def reference_paths(params):
    """The ``reference_paths`` argument of :func:`run_drop` for the drops whose parameter
    vectors are the rows of ``params``.

    ``None`` when every drop uses the default paths (an adaptive integrator, the fast sediment
    rule): then the reference paths (the fixed-step ``rk4`` and ``local_linear`` integrators and
    the reference sediment quadrature) are not even compiled, which halves the compile
    time of the engine from an empty cache. ``True`` when any drop asks for one of them:
    then all are compiled and chosen per drop by its parameters.

    A drop of a shape other than the default (``mine.shape``) gets ``(paths, prototype)``: the
    paths above and a prototype body of its shape's class (``bodies.shapes.Shape.marker``), whose
    type selects the shape's compiled protocol (:func:`split_paths`, :func:`.dynamics.body_of`);
    the default shape's argument is the paths alone, as before (its kernels unchanged).
    """
    params = np.asarray(params, dtype=np.float64).reshape(-1, N_PARAMS)
    adaptive = ADAPTIVE_INTEGRATOR[params[:, P_INTEGRATOR].astype(np.int64)]
    uses_reference = ~adaptive | (params[:, P_SED_QUADRATURE] != QUADRATURE_FAST)
    paths = True if np.any(uses_reference) else None
    shape = shape_of_params(params)
    return paths if shape is DEFAULT_SHAPE else (paths, shape.marker())


def split_paths(reference_paths):
    """``(paths, shape)`` of :func:`run_drop`'s ``reference_paths`` argument: the paths and the
    shape's prototype body (None for the default shape). Compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(split_paths, jit_options=JIT_OPTIONS, inline="always")
def _overload_split_paths(reference_paths):
    if isinstance(reference_paths, types.BaseTuple):

        def carried(reference_paths):
            return reference_paths[0], reference_paths[1]

        return carried

    def default_shape(reference_paths):
        return reference_paths, None

    return default_shape


@small_kernel
def _step_request(integrator, adaptive, stiff_in_sediment, t, h_adapt, t_limit, h_cap, p, g0):
    """The core's method and the size of the next step of a drop (its caps: :data:`MAX_STEP`, the time
    left, the interface cap), or h = -1.0 when an adaptive step fell below :data:`MIN_STEP` max(1, t)
    (a numerical failure); ``dopri5_ros34pw2`` takes the Rosenbrock-W step in sediment contact (g0[2] < 0)."""
    method = CORE_METHOD[integrator]
    if adaptive:
        h = min(h_adapt, MAX_STEP, t_limit - t, h_cap)
        if h < MIN_STEP * max(1.0, t):
            return method, -1.0
        if stiff_in_sediment and g0[2] < 0.0:
            method = ROS34PW2  # in contact with the sediment: the linearly implicit Rosenbrock-W step
    else:
        h = min(p[P_DT], t_limit - t, h_cap)
    return method, h


@small_kernel
def _seabed_cap(h, y, f, p, law, g0, ytmp, gtmp):
    """The step h capped at the seabed crossing predicted from the state y (rate f) at its start: the lowest
    point's height over the seabed g0[2] > 0 over its sinking rate (a one-sided difference of
    :func:`event_values` along f, :data:`SEABED_RATE_STEP`, so the rotation's share is in it), times
    1 + :data:`SEABED_CAP_MARGIN`; never below :data:`MIN_REDO_STEP`. h unchanged when the lowest point is
    not sinking or the crossing is predicted beyond the step."""
    for i in range(y.shape[0]):
        ytmp[i] = y[i] + SEABED_RATE_STEP * f[i]
    event_values(ytmp, p, law, gtmp)
    rate = (gtmp[2] - g0[2]) / SEABED_RATE_STEP
    if rate < 0.0:
        h_cross = max(g0[2] / -rate * (1.0 + SEABED_CAP_MARGIN), MIN_REDO_STEP)
        if h_cross < h:
            return h_cross
    return h


@small_kernel
def _first_event(r, t, h, g0, g1, p, law, gtmp, ytmp):
    """(theta, e): the first event inside the accepted step (t, t + h) on its continuous extension ``r``
    (theta = 2, e = -1 when none): an interface crossed (events 0-3) or the rest measure turning
    negative while in contact with the sediment (event 4), each located by :func:`.core.locate_event`."""
    theta = 2.0
    first = -1
    in_contact = g0[2] < 0.0 and g1[2] < 0.0
    for e in range(N_EVENTS):
        if e == EVENT_REST:
            # the rest measure turning negative while in contact with the sediment
            if not (in_contact and g0[e] > 0.0 and g1[e] <= 0.0):
                continue
        elif not _crossed(g0[e], g1[e]):
            continue
        th = locate_event(
            MINE, r, t, h, g0[e], g1[e], (p, law, e, gtmp), ytmp, EVENT_TOLERANCE, MAX_EVENT_ITERATIONS
        )
        if th < theta:
            theta = th
            first = e
    return theta, first


@small_kernel
def _record_step(traj, row, next_record, record_dt, r, t, h, t_end, ytmp, args, dy):
    """The recorder: trajectory rows at the exact output times within the step (t, t_end], on its
    continuous extension ``r``; args as :func:`mine_rhs`; returns (rows recorded, next output time)."""
    p, law, sed_bank, cur_bank, work, diag = args
    n_rows = traj.shape[0]
    while row < n_rows and next_record <= t_end + 1e-12 * max(1.0, t_end):
        dense_state(r, min(max((next_record - t) / h, 0.0), 1.0), ytmp)
        _record(traj, row, next_record, ytmp, p, law, sed_bank, cur_bank, work, dy, diag)
        row += 1
        next_record = row * record_dt
    return row, next_record


@small_kernel
def _cut_at_event(r, theta, first, ynew, p, law, g0, g1):
    """The end state of a step cut at its first event: ynew on the continuous extension at theta and
    its event values g1, with the event's sign change made exact (strictly: a value of -0.0 would
    read as not crossed)."""
    dense_state(r, theta, ynew)
    event_values(ynew, p, law, g1)
    if first < EVENT_REST:
        # the interface is crossed at the cut: make its sign change exact
        mag = max(abs(g1[first]), 1e-300)
        g1[first] = -mag if g0[first] > 0.0 else mag
    else:
        g1[EVENT_REST] = min(g1[EVENT_REST], -1e-300)


@small_kernel
def _impact_summary(summary, t, y):
    """The impact's time, speed, pitch and angle (seed 000 section 8) at the first seabed contact."""
    speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
    summary[S_IMPACT_TIME] = t
    summary[S_IMPACT_SPEED] = speed
    psi1, psi2, psi3 = euler_angles(y[6], y[7], y[8], y[9])
    summary[S_IMPACT_PITCH] = math.degrees(psi2)
    summary[S_IMPACT_ANGLE] = math.degrees(math.atan2(-y[5], math.sqrt(y[3] * y[3] + y[4] * y[4])))


@small_kernel
def _end_summary(summary, p, body, y, t, max_decel, hit_seabed, n_steps):
    """The burial measures (:func:`.bodies.burial`), final attitude and position at the end of the drop."""
    depth = p[P_DEPTH]
    rot = rotation_matrix(y[6], y[7], y[8], y[9])
    pv, ph, pa, proud, pen = bodies.burial(body, rot[6], y[2], -depth)
    summary[S_PENETRATION] = pen
    summary[S_COM_DEPTH] = -depth - y[2]
    summary[S_BURIAL_VOLUME] = pv
    summary[S_BURIAL_HEIGHT] = ph
    summary[S_BURIAL_AREA] = pa
    summary[S_HEIGHT_PROUD] = proud
    psi1, psi2, psi3 = euler_angles(y[6], y[7], y[8], y[9])
    summary[S_FINAL_PITCH] = math.degrees(psi2)
    summary[S_FINAL_ROLL] = math.degrees(psi1)
    summary[S_FINAL_HEADING] = math.degrees(psi3)
    summary[S_FINAL_X] = y[0]
    summary[S_FINAL_Y] = y[1]
    summary[S_TOTAL_TIME] = t
    summary[S_MAX_DECEL] = max_decel if hit_seabed else np.nan
    summary[S_N_STEPS] = n_steps


@small_kernel
def _end_test(y, f, g1, p, law, sed_bank, max_decel, buoyant, entered_water, hit_seabed):
    """The end tests after an accepted step at state y with rate f and event values g1: a non-finite
    state or rate; at rest (slow by seed 000 eq. (89) and held by the sediment, kernels/mine/rest.py);
    floated (lighter than the water, in it and rising before any seabed contact); left the domain.
    Returns (status, or :data:`GO_ON`; the largest deceleration in the sediment so far)."""
    if not (all_finite(y) and all_finite(f)):
        return st.NUMERICAL_FAILURE, max_decel
    if g1[2] < 0.0:
        acc = math.sqrt(f[3] * f[3] + f[4] * f[4] + f[5] * f[5])
        if acc > max_decel:
            max_decel = acc
        # the end of the drop: slow (eq. (89)) and held by the sediment (kernels/mine/rest.py)
        if g1[EVENT_REST] <= 0.0 and held_by_sediment(y, p, law, sed_bank, p[P_REST_SPEED]):
            return st.AT_REST, max_decel
    elif buoyant and entered_water and not hit_seabed and g1[0] < 0.0 and y[5] > 0.0:
        # lighter than the water, in it and rising: it will not reach the seabed
        return st.FLOATED, max_decel
    if y[2] > p[P_Z0] + 1000.0 or abs(y[0]) > DOMAIN_RADIUS or abs(y[1]) > DOMAIN_RADIUS:
        return st.LEFT_DOMAIN, max_decel
    return GO_ON, max_decel


@small_kernel
def _work_arrays():
    """The work arrays of a drop: (y, ynew, err, k, ytmp, dy, r, work, diag, g0, g1, gtmp, jc, wa, piv, kr,
    ztmp) (jc, wa, piv, kr, ztmp: the Rosenbrock-W step's, over :data:`VELOCITY_SLOTS`)."""
    return (
        np.empty(N_EXT),
        np.empty(N_EXT),
        np.empty(N_EXT),
        np.empty((N_STAGES, N_EXT)),
        np.empty(N_EXT),
        np.empty(N_EXT),
        np.empty((5, N_EXT)),
        np.empty(N_WORK),
        np.zeros(N_DIAG),
        np.empty(N_EVENTS),
        np.empty(N_EVENTS),
        np.empty(N_EVENTS),
        np.zeros((N_EXT, N_VEL)),
        np.empty((N_VEL, N_VEL)),
        np.empty(N_VEL, dtype=np.int64),
        np.empty((ROS_STAGES, N_EXT)),
        np.empty(N_VEL),
    )


@small_kernel
def _borrowed_all(a):
    """:func:`.core.borrowed` of each of :func:`_work_arrays`."""
    return (
        borrowed(a[0]), borrowed(a[1]), borrowed(a[2]), borrowed(a[3]), borrowed(a[4]), borrowed(a[5]),
        borrowed(a[6]), borrowed(a[7]), borrowed(a[8]), borrowed(a[9]), borrowed(a[10]), borrowed(a[11]),
        borrowed(a[12]), borrowed(a[13]), borrowed(a[14]), borrowed(a[15]), borrowed(a[16]),
    )  # fmt: skip


#: what the mine's hooks of the driver loop read: the right-hand side's arguments (:func:`mine_rhs`), the
#: summary, the record interval, the work arrays, the integrator's code, whether it is adaptive and takes
#: the Rosenbrock-W step in the sediment, and whether the mine is lighter than the water
DropContext = namedtuple(
    "DropContext",
    "args summary record_dt y ynew k r ytmp dy g0 g1 gtmp integrator adaptive stiff_in_sediment buoyant",
)
#: the scalars the mine's hooks of the driver loop carry from step to step: the time limit of the phase
#: the drop is in, the cap of the next step (a step taken again to end at an interface) and the retakes
#: of this step, the largest deceleration in the sediment, the accepted steps and the attempts, the
#: trajectory rows recorded and the next output time, whether the mine has entered the water and hit
#: the seabed
DropLoop = namedtuple(
    "DropLoop",
    "t_limit h_cap redo max_decel n_steps n_attempts row next_record entered_water hit_seabed",
)


@small_kernel
def _next_step(t, h_adapt, traj, ctx, loop):
    """The mine's hook of the driver loop before each attempt (:func:`.core.driver_loop`): the time limit
    (buried and still sinking when the mine's top is below the seabed then), the step budget, then the
    method and size of the step (:func:`_step_request`, a numerical failure below the step floor)."""
    t_limit, h_cap, redo, max_decel, n_steps, n_attempts, row, next_record, entered_water, hit_seabed = loop
    status = GO_ON
    method = CORE_METHOD[ctx.integrator]
    h = h_adapt
    if t >= t_limit * (1.0 - 1e-15):
        status = st.BURIED_SINKING if ctx.g0[3] < 0.0 else st.TIME_LIMIT
    else:
        n_attempts += 1
        if n_steps >= MAX_STEPS or n_attempts >= 4 * MAX_STEPS:
            status = st.TIME_LIMIT
        else:
            p, g0 = ctx.args[0], ctx.g0
            method, h = _step_request(
                ctx.integrator, ctx.adaptive, ctx.stiff_in_sediment, t, h_adapt, t_limit, h_cap, p, g0
            )
            if h < 0.0:
                status = st.NUMERICAL_FAILURE
            elif ctx.stiff_in_sediment and method == DOPRI5 and g0[2] > 0.0 and h_cap == math.inf:
                # above the seabed, not a retake: end the step just past the predicted crossing
                h = _seabed_cap(h, ctx.y, ctx.k[0], p, ctx.args[1], g0, ctx.ytmp, ctx.gtmp)
    loop = DropLoop(
        t_limit, h_cap, redo, max_decel, n_steps, n_attempts, row, next_record, entered_water, hit_seabed
    )
    return status, method, h, loop


@small_kernel
def _accepted(t, h, traj, ctx, loop):
    """The mine's hook of the driver loop after an accepted step (:func:`.core.driver_loop`): its first
    event; an interface inside the step has the step taken again to end just past it (at most
    :data:`MAX_REDO` times); otherwise the records up to the step's end (or its first event), the state
    moved on (cut at the event, the quaternion normalised, the integration restarted at a cut), the water
    entry and the impact noted, and the end tests (:func:`_end_test`)."""
    args, summary, y, ynew, k, r, ytmp, dy, g0, g1, gtmp = (
        ctx.args,
        ctx.summary,
        ctx.y,
        ctx.ynew,
        ctx.k,
        ctx.r,
        ctx.ytmp,
        ctx.dy,
        ctx.g0,
        ctx.g1,
        ctx.gtmp,
    )
    p, law, sed_bank, cur_bank, work, diag = args
    t_limit, h_cap, redo, max_decel, n_steps, n_attempts, row, next_record, entered_water, hit_seabed = loop
    status = GO_ON
    accepted_before = True
    event_values(ynew, p, law, g1)
    theta, first = _first_event(r, t, h, g0, g1, p, law, gtmp, ytmp)
    if (
        first >= 0
        and first < EVENT_REST
        and theta < 1.0 - REDO_MARGIN
        and redo < MAX_REDO
        and theta * h > MIN_REDO_STEP
    ):
        # an interface inside the step: the step's continuous extension has seen the
        # forces beyond it; take the step again, ending just past the located crossing,
        # so that the state at the interface comes from the forces before it
        h_cap = theta * h * (1.0 + REDO_MARGIN)
        redo += 1
    else:
        t_end = t + h if first < 0 else t + theta * h
        if traj is not None:
            row, next_record = _record_step(
                traj, row, next_record, ctx.record_dt, r, t, h, t_end, ytmp, args, dy
            )
        # ---- accept the step (cut at the first event) ----
        if first >= 0:
            _cut_at_event(r, theta, first, ynew, p, law, g0, g1)
        h_cap = math.inf
        redo = 0
        _normalize_attitude(ynew)
        for i in range(N_EXT):
            y[i] = ynew[i]
        t = t_end
        n_steps += 1
        if first >= 0:
            # restart: f at the cut state (the right-hand side is not smooth there)
            derivatives(y, p, law, sed_bank, cur_bank, work, k[0], diag)
            accepted_before = False
        else:
            for i in range(N_EXT):
                k[0, i] = k[6, i]
        if not entered_water and g1[0] < 0.0:
            entered_water = True
            summary[S_ENTRY_TIME] = t
        if not hit_seabed and g1[2] < 0.0:
            hit_seabed = True
            t_limit = t + p[P_TMAX]
            _impact_summary(summary, t, y)
        for e in range(N_EVENTS):
            g0[e] = g1[e]
        status, max_decel = _end_test(
            y, k[0], g1, p, law, sed_bank, max_decel, ctx.buoyant, entered_water, hit_seabed
        )
    loop = DropLoop(
        t_limit, h_cap, redo, max_decel, n_steps, n_attempts, row, next_record, entered_water, hit_seabed
    )
    return status, t, accepted_before, loop


@kernel
def run_drop(p, sed_bank, cur_bank, summary, traj, record_dt, reference_paths):
    """Integrate one drop. Fills ``summary`` (N_SUMMARY) and, when ``traj`` is an array
    (rows, N_TRAJ), the trajectory every ``record_dt`` seconds; ``traj = None`` records
    nothing (and compiles no recorder). Returns (status, rows recorded).

    ``reference_paths``: :func:`reference_paths` of the drop (``None``: only the default
    paths are compiled). The steps are the integration core's driver loop (:func:`.core.driver_loop`)
    with the mine's hooks :func:`_next_step` and :func:`_accepted`; it and the hooks' pieces (step
    request, first event, recorder, cut, impact and end summaries) are inlined kernels
    (``small_kernel``): one compile unit.
    """
    # the caller's arrays, which it holds while the drop runs, without their reference counts
    # (core.borrowed): numba's counts on them were most of the drop's atomics, on meminfos that the
    # batch's threads share (the ensemble's rows P[i] and S[i], the banks); same data, same answers
    p, sed_bank, cur_bank, summary = borrowed(p), borrowed(sed_bank), borrowed(cur_bank), borrowed(summary)
    for i in range(N_SUMMARY):
        summary[i] = np.nan
    p, sed_bank = drop_bank(p, sed_bank)  # the drop's profile, searched by bisection
    paths, shape = split_paths(reference_paths)  # a shape other than the default rides with the paths
    body = body_of(p, shape)
    # the law's width D; the law carries the shape to every kernel that builds the body (drop_body)
    law = with_shape(pack_law(p, bodies.reference_lengths(body)[0], paths), shape)
    # the work arrays, borrowed (core.borrowed) from their owners, which keep_alive holds to the end: the
    # hooks and the compiled callees counted references on them (thread-private, but one atomic each)
    owners = _work_arrays()
    y, ynew, err, k, ytmp, dy, r, work, diag, g0, g1, gtmp, jc, wa, piv, kr, ztmp = _borrowed_all(owners)
    ws = (k, ynew, err, r, ytmp, VELOCITY_SLOTS, jc, wa, piv, kr, ztmp)  # of the core's attempt_step
    args = (p, law, sed_bank, cur_bank, work, diag)  # of mine_rhs
    initial_state(p, y)
    integrator = int(p[P_INTEGRATOR])
    adaptive = ADAPTIVE_INTEGRATOR[integrator]
    stiff_in_sediment = integrator == INTEGRATOR_STIFF
    volume, _ = bodies.volume(body)
    buoyant = p[P_MASS] < p[P_RHO_WATER] * volume  # lighter than the water it displaces
    derivatives(y, p, law, sed_bank, cur_bank, work, k[0], diag)
    event_values(y, p, law, g0)
    entered_water = g0[0] < 0.0
    hit_seabed = g0[2] < 0.0
    if entered_water:
        summary[S_ENTRY_TIME] = 0.0
    # the time limit of the phase the drop is in: numerics.t_max_fall for the fall,
    # then numerics.t_max counted from the first seabed contact (docs/design.md)
    t_limit = p[P_TMAX_FALL]
    if hit_seabed:
        summary[S_IMPACT_TIME] = 0.0
        t_limit = p[P_TMAX]
    ctx = DropContext(
        args, summary, record_dt, y, ynew, k, r, ytmp, dy, g0, g1, gtmp, integrator, adaptive,
        stiff_in_sediment, buoyant,
    )  # fmt: skip
    loop = DropLoop(t_limit, math.inf, 0, 0.0, 0, 0, 0, 0.0, entered_water, hit_seabed)
    # the first trial step of an adaptive integrator: numerics.dt
    status, t, loop = driver_loop(
        _next_step, _accepted,
        MINE, 0.0, y, p[P_DT], args, paths, ERROR_GROUPS, p[P_RTOL], p[P_ATOL], ws, traj, ctx, loop,
    )  # fmt: skip
    row = loop.row
    if traj is not None:
        if row < traj.shape[0] and (row == 0 or traj[row - 1, 0] < t):
            _record(traj, row, t, y, p, law, sed_bank, cur_bank, work, dy, diag)
            row += 1
    _end_summary(summary, p, body, y, t, loop.max_decel, loop.hit_seabed, loop.n_steps)
    keep_alive(owners)
    return status, row
