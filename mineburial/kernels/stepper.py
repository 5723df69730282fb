"""The per-drop stepper: integrate one drop from release to rest (seed 000 section 7).

Integrators (``numerics.integrator``):

``rk4`` (default)
    Classical fourth-order Runge-Kutta on the extended state (seed 004 uses
    Runge-Kutta for its Kane equations; seed 000 section 10 asks for "a fully
    numerical calculation"). Fourth order in dt.
``local_linear``
    The recursive local-linearisation scheme of seed 000 eqs. (83)-(87): each
    velocity component obeys dv/dt = -d v + beta with d and beta frozen at t_n
    and is advanced exactly; positions by eq. (86); rotation-angle increments by
    eq. (87) with its typos fixed (PHYSICS.md §3), composed onto the quaternion.
    The diagonal damping d of eqs. (81)-(82) is the diagonal of the Jacobian of
    the acceleration with respect to the velocity, evaluated by a one-sided
    difference so that the same scheme serves both physics models. First order.

Interface crossings (lowest/highest point of the mine through the water
surface or the seabed) are located by bisection on the step fraction to
``EVENT_TIME_TOLERANCE`` and the step is cut there, so no crossing is stepped over.
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels import status as st
from mineburial.kernels.dynamics import (I_WORK_FLUID, I_WORK_SEDIMENT, N_DIAG, N_EXT, N_WORK,
                                         derivatives, held_by_sediment)
from mineburial.kernels.geometry import burial_measures, vertical_extent
from mineburial.kernels.layout import (N_SUMMARY, P_CHI, P_MASS, P_DEPTH, P_DIAMETER, P_DT, P_INTEGRATOR,
                                       P_LENGTH, P_OM10, P_OM20, P_OM30, P_Q00, P_Q10, P_Q20, P_Q30,
                                       P_REST_SPEED, P_REST_SPIN, P_TMAX, P_U0, P_V0, P_W0, P_X0,
                                       P_Y0, P_Z0, S_BURIAL_AREA, S_BURIAL_HEIGHT, S_BURIAL_VOLUME,
                                       S_COM_DEPTH, S_ENTRY_TIME, S_FINAL_HEADING, S_FINAL_PITCH,
                                       S_FINAL_ROLL, S_FINAL_X, S_FINAL_Y, S_HEIGHT_PROUD,
                                       S_IMPACT_ANGLE, S_IMPACT_PITCH, S_IMPACT_SPEED, S_IMPACT_TIME,
                                       S_MAX_DECEL, S_N_STEPS, S_PENETRATION, S_TOTAL_TIME)
from mineburial.kernels.sediment import pack_law
from mineburial.kernels.rotation import (euler_angles, normalize_quaternion, rotation_matrix,
                                         rotation_vector_quaternion, quaternion_multiply)

# columns of a recorded trajectory row
TRAJ_COLUMNS = ("time", "x", "y", "z", "u", "v", "w", "q0", "q1", "q2", "q3",
                "omega1", "omega2", "omega3", "work_fluid", "work_sediment", "phase",
                "fluid_force_x", "fluid_force_y", "fluid_force_z",
                "sediment_force_x", "sediment_force_y", "sediment_force_z",
                "torque_1", "torque_2", "torque_3")
N_TRAJ = len(TRAJ_COLUMNS)

N_EVENTS = 4
MAX_STEPS = 50_000_000
EVENT_TIME_TOLERANCE = 1e-9   # s: crossing times are located to this accuracy
DOMAIN_RADIUS = 1e5           # m: a drop that drifts further has left the domain
REST_TIME = 1.0               # s: force tolerance of the rest test is mass * rest_speed / REST_TIME


@kernel
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


@kernel
def event_values(y, p, g):
    """Signed distances of the lowest/highest point to the surface and the seabed."""
    L = p[P_LENGTH]
    R = 0.5 * p[P_DIAMETER]
    qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
    a_z = 2.0 * (y[7] * y[9] - y[6] * y[8]) / (qn * qn)   # R[2,0] = i_M . k
    lo, hi = vertical_extent(L, R, p[P_CHI], a_z, y[2])
    depth = p[P_DEPTH]
    g[0] = lo
    g[1] = hi
    g[2] = lo + depth
    g[3] = hi + depth


@kernel
def rk4_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp, diag, out):
    """One classical Runge-Kutta step from y (k1 = f(y) must already be filled)."""
    n = y.shape[0]
    for i in range(n):
        ytmp[i] = y[i] + 0.5 * dt * k1[i]
    derivatives(ytmp, p, law, sed_bank, cur_bank, work, k2, diag)
    for i in range(n):
        ytmp[i] = y[i] + 0.5 * dt * k2[i]
    derivatives(ytmp, p, law, sed_bank, cur_bank, work, k3, diag)
    for i in range(n):
        ytmp[i] = y[i] + dt * k3[i]
    derivatives(ytmp, p, law, sed_bank, cur_bank, work, k4, diag)
    for i in range(n):
        out[i] = y[i] + dt * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0
    q0, q1, q2, q3 = normalize_quaternion(out[6], out[7], out[8], out[9])
    out[6] = q0
    out[7] = q1
    out[8] = q2
    out[9] = q3


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


@kernel
def local_linear_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, ytmp, diag, out):
    """Seed 000 local-linearisation step (eqs. (83)-(87)); k1 = f(y) pre-filled."""
    n = y.shape[0]
    # velocity slots: u v w (E-frame) and omega1..3 (body)
    for s in range(6):
        i = 3 + s if s < 3 else 7 + s   # 3,4,5,10,11,12
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
            out[s] = y[s] + integral        # eq. (86)
        else:
            k3[s - 3] = integral            # rotation-angle increments, eq. (87)
    q0, q1, q2, q3 = rotation_vector_quaternion(k3[0], k3[1], k3[2])
    a0, a1, a2, a3 = quaternion_multiply(y[6], y[7], y[8], y[9], q0, q1, q2, q3)
    a0, a1, a2, a3 = normalize_quaternion(a0, a1, a2, a3)
    out[6] = a0
    out[7] = a1
    out[8] = a2
    out[9] = a3
    out[I_WORK_FLUID] = y[I_WORK_FLUID] + dt * k1[I_WORK_FLUID]
    out[I_WORK_SEDIMENT] = y[I_WORK_SEDIMENT] + dt * k1[I_WORK_SEDIMENT]


@kernel
def take_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp, diag, out, integrator):
    if integrator == 0:
        rk4_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp, diag, out)
    else:
        local_linear_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, ytmp, diag, out)


@kernel
def _crossed(g0, g1):
    return (g0 > 0.0 and g1 <= 0.0) or (g0 <= 0.0 and g1 > 0.0)


@kernel
def _record(traj, row, t, y, phase, diag):
    traj[row, 0] = t
    for i in range(N_EXT):
        traj[row, 1 + i] = y[i]
    traj[row, 16] = phase
    for i in range(9):
        traj[row, 17 + i] = diag[i]


@kernel
def run_drop(p, sed_bank, cur_bank, summary, traj, record_dt):
    """Integrate one drop. Fills ``summary`` (N_SUMMARY) and, when ``traj`` has rows,
    the trajectory every ``record_dt`` seconds. Returns (status, rows recorded).
    """
    for i in range(N_SUMMARY):
        summary[i] = np.nan
    y = np.empty(N_EXT)
    ynew = np.empty(N_EXT)
    k1 = np.empty(N_EXT)
    k2 = np.empty(N_EXT)
    k3 = np.empty(N_EXT)
    k4 = np.empty(N_EXT)
    ytmp = np.empty(N_EXT)
    work = np.empty(N_WORK)
    diag = np.zeros(N_DIAG)
    g0 = np.empty(N_EVENTS)
    g1 = np.empty(N_EVENTS)
    initial_state(p, y)
    law = pack_law(p, p[P_DIAMETER])
    dt_nominal = p[P_DT]
    t_max = p[P_TMAX]
    integrator = min(int(p[P_INTEGRATOR]), 1)
    rest_speed = p[P_REST_SPEED]
    rest_spin = p[P_REST_SPIN]
    depth = p[P_DEPTH]
    z_release = p[P_Z0]
    n_rows = traj.shape[0]
    row = 0
    t = 0.0
    next_record = 0.0
    status = st.TIME_LIMIT
    entered_water = False
    hit_seabed = False
    max_decel = 0.0
    n_steps = 0
    phase = derivatives(y, p, law, sed_bank, cur_bank, work, k1, diag)
    event_values(y, p, g0)
    if g0[0] < 0.0:
        entered_water = True
        summary[S_ENTRY_TIME] = 0.0
    if g0[2] < 0.0:
        hit_seabed = True
        summary[S_IMPACT_TIME] = 0.0
    while True:
        if row < n_rows and t >= next_record - 1e-12:
            _record(traj, row, t, y, phase, diag)
            row += 1
            next_record += record_dt
        if t >= t_max - 1e-12:
            status = st.TIME_LIMIT
            break
        if n_steps >= MAX_STEPS:
            status = st.TIME_LIMIT
            break
        dt = min(dt_nominal, t_max - t)
        take_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp, diag, ynew,
                  integrator)
        event_values(ynew, p, g1)
        first = -1
        for e in range(N_EVENTS):
            if _crossed(g0[e], g1[e]):
                first = e
                break
        if first >= 0:
            # locate the earliest crossing by bisection on the step fraction: the
            # step is cut just after the first interface crossing
            lo = 0.0
            hi = 1.0
            for it in range(60):
                if (hi - lo) * dt <= EVENT_TIME_TOLERANCE:
                    break
                theta = 0.5 * (lo + hi)
                take_step(y, theta * dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp,
                          diag, ynew, integrator)
                event_values(ynew, p, g1)
                any_crossed = False
                for e in range(N_EVENTS):
                    if _crossed(g0[e], g1[e]):
                        any_crossed = True
                if any_crossed:
                    hi = theta
                else:
                    lo = theta
            dt = hi * dt
            take_step(y, dt, p, law, sed_bank, cur_bank, work, k1, k2, k3, k4, ytmp, diag, ynew,
                      integrator)
            event_values(ynew, p, g1)
        # accept the step
        dv_step = math.sqrt((ynew[3] - y[3]) ** 2 + (ynew[4] - y[4]) ** 2 + (ynew[5] - y[5]) ** 2)
        dw_step = math.sqrt((ynew[10] - y[10]) ** 2 + (ynew[11] - y[11]) ** 2
                            + (ynew[12] - y[12]) ** 2)
        for i in range(N_EXT):
            y[i] = ynew[i]
        t += dt
        n_steps += 1
        if not entered_water and g1[0] < 0.0:
            entered_water = True
            summary[S_ENTRY_TIME] = t
        if not hit_seabed and g1[2] < 0.0:
            hit_seabed = True
            speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
            summary[S_IMPACT_TIME] = t
            summary[S_IMPACT_SPEED] = speed
            psi1, psi2, psi3 = euler_angles(y[6], y[7], y[8], y[9])
            summary[S_IMPACT_PITCH] = math.degrees(psi2)
            summary[S_IMPACT_ANGLE] = math.degrees(math.atan2(-y[5], math.sqrt(y[3] * y[3] + y[4] * y[4])))
        for e in range(N_EVENTS):
            g0[e] = g1[e]
        phase = derivatives(y, p, law, sed_bank, cur_bank, work, k1, diag)
        finite = True
        for i in range(N_EXT):
            if not math.isfinite(y[i]) or not math.isfinite(k1[i]):
                finite = False
        if not finite:
            status = st.NUMERICAL_FAILURE
            break
        if g1[2] < 0.0:
            acc = math.sqrt(k1[3] * k1[3] + k1[4] * k1[4] + k1[5] * k1[5])
            if acc > max_decel:
                max_decel = acc
            speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
            spin = math.sqrt(y[10] * y[10] + y[11] * y[11] + y[12] * y[12])
            # seed 000 eq. (89) as a speed criterion, plus a test that the sediment can
            # hold the mine there: one at a turning point of an oscillation is
            # momentarily slow but not at rest. A speed below the change of velocity
            # over the last step counts as zero: the rigid-plastic resistance reverses
            # within one step there (stick), which an explicit step cannot resolve.
            if (speed < max(rest_speed, 2.0 * dv_step)
                    and spin < max(rest_spin, 2.0 * dw_step)):
                if held_by_sediment(y, p, law, sed_bank, p[P_MASS] * rest_speed / REST_TIME, rest_speed):
                    status = st.AT_REST
                    break
        if y[2] > z_release + 1000.0 or abs(y[0]) > DOMAIN_RADIUS or abs(y[1]) > DOMAIN_RADIUS:
            status = st.LEFT_DOMAIN
            break
    if row < n_rows and row > 0 and traj[row - 1, 0] < t:
        _record(traj, row, t, y, phase, diag)
        row += 1
    # ---- burial measures and final attitude ----
    L = p[P_LENGTH]
    R = 0.5 * p[P_DIAMETER]
    chi = p[P_CHI]
    r = rotation_matrix(y[6], y[7], y[8], y[9])
    a_z = r[6]
    pv, ph, pa, proud, pen = burial_measures(L, R, chi, a_z, y[2], -depth)
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
    return status, row
