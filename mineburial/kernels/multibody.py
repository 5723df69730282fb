"""Planar finite-segment multibody core: Kane's equations in Huston's form (seed 004 sec. 2.3).

A *description* (data, built by :mod:`mineburial.multibody`) is the tuple::

    desc = (parent, joint_on_parent, joint_on_body, mass_matrix, root_free, root_pose)

    parent           int64[N]       parent body of each body; -1 for body 0 (the root) only; parent[k] < k
    joint_on_parent  float64[N, 2]  body-frame (a, b) of the pin joining k to its parent, from the parent's
                                    centroid (row 0 unused)
    joint_on_body    float64[N, 2]  body-frame (a, b) of the same pin, from body k's centroid (row 0 unused)
    mass_matrix      float64[N,3,3] body-frame generalised mass at the centroid in the order (a, b, theta):
                                    the rigid body's diag(m, m, I) plus any added mass
    root_free        int64[3]       1 where the root's x, z, theta are generalised coordinates
    root_pose        float64[3]     the root's x, z, theta; the locked ones keep these values

Planar conventions: x horizontal, z vertical up; a body's attitude theta turns +x toward +z; a body-frame
vector (a, b) is (a cos th - b sin th, a sin th + b cos th) in the inertial frame. A body's state at its
centroid is (x, z, th) and (vx, vz, om); applied forces are (Fx, Fz, My) at the centroid, My = rx Fz - rz Fx.

Generalised coordinates (see docs/multibody.md for why they differ from seed 004's Euler parameters): q = the
root's free coordinates in the order x, z, th, then the absolute angles th_1 .. th_{N-1}; generalised speeds
u = dq/dt; the state of an integration is y = concat(q, u). In the plane the Euler parameters of seed 004
eq. (2) reduce to (sin(beta/2), cos(beta/2)) of one angle and eq. (28) to d(beta)/dt = omega, so the angle
itself is the coordinate: no normalisation drift, no singularity (the Cardan singularity of eq. (5) does not
exist for one rotation axis). Absolute rather than relative (seed 004 eq. (8)) angles make each partial
angular velocity a unit vector (eq. (10) reduces to a Kronecker delta) and leave the joint-space mass matrix
the same up to a congruence with a constant triangular matrix.

Kane's equations (seed 004 eqs. (21)-(26)): with the partial velocities V_k = d(vx, vz, om)_k / du
(eqs. (10), (15)), the generalised active forces F_l = sum_k V_k[:, l] . F_k (eq. (23)) and the generalised
inertia forces F*_l = -sum_k V_k[:, l] . (M_k a_k + g_k) (eqs. (20)-(22)), F_l + F*_l = 0 (eq. (24)) gives

    A du/dt = f,   A = sum_k V_k^T M_k V_k  (eq. (26)),   f = sum_k V_k^T (F_k - M_k b_k - g_k)  (eq. (25))

where a_k = V_k du/dt + b_k (eq. (17): b_k = dV_k/dt u, the velocity-product accelerations), M_k the
inertial-frame generalised mass (eq. (19) generalised to a full 3 x 3 with added mass) and g_k the velocity
terms of a rotating anisotropic mass: dM_k/dt w_k plus the Munk moment (0, 0, vx Pz - vz Px) with
P = (M_k w_k)[0:2] (for a rigid body's diag(m, m, I) both vanish; for an added mass they make the equations
Lagrange's equations of the kinetic energy 1/2 sum w^T M w, so that energy is conserved exactly; see
docs/multibody.md for the comparison with the Morison-type added-mass force of seed 004 eq. (46)).

:func:`generalised_mass_and_force` assembles A and f in O(N^2) from the partial velocities without forming
them (a body's partial velocity with respect to an ancestor's angle is the same for its whole subtree, so the
sums over bodies become subtree sums); :func:`accelerations_assembled` solves them by Cholesky and
:func:`accelerations` solves the same equations in O(N) by the tree recursion; :func:`partial_velocities`
forms the partial velocities explicitly for systems and tests.
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.core import (
    GO_ON,
    all_finite,
    driver_loop,
    locate_event,
    method_code,
    record_until,
    system_event,
    system_rhs,
)
from mineburial.kernels.integrators import N_STAGES, ROS_STAGES, dense_state
from mineburial.kernels.methods import ADAPTIVE, METHOD_NAMES
from mineburial.kernels.status import END, INVALID_INPUT, NUMERICAL_FAILURE, TIME_LIMIT

# --- status codes of an integration: the integration core's shared vocabulary (kernels/status.py), whose
# normal end (0) a multibody system calls "stopped"; the drop statuses there are the falling mine's ------
STOPPED = END

#: status code -> name (codes 0, 1, 3, 4; 2 is not used by a multibody system: issue 18 made the codes
#: the core's, they were 0-3 before; docs/restraint.md)
STATUS_NAMES = {
    STOPPED: "stopped",
    TIME_LIMIT: "time_limit",
    NUMERICAL_FAILURE: "numerical_failure",
    INVALID_INPUT: "invalid_input",
}
STATUS_DESCRIPTIONS = {
    STOPPED: "the system's event function crossed zero from above (e.g. the ship stopped); the run ends "
    "there",
    TIME_LIMIT: "the time limit was reached before the event",
    NUMERICAL_FAILURE: "a non-finite value appeared in the state or its rate, the step size underflowed, "
    "the step budget (max_steps) was spent, or the system's own check of the run failed (e.g. its energy "
    "balance)",
    INVALID_INPUT: "the integration settings were invalid (integrator, step, tolerances, record interval); "
    "nothing was run",
}
#: the codes in order: the CF ``flag_values`` of a status variable (``flag_meanings``: their names)
STATUS_CODES = np.array(list(STATUS_NAMES), dtype=np.int8)
STATUS_MEANINGS = " ".join(STATUS_NAMES.values())

#: integration methods of :func:`integrate`: every step method of the integration core (:mod:`.methods`)
METHODS = METHOD_NAMES

#: default step budget of :func:`integrate` (accepted plus rejected steps): a run that needs more has
#: equations too stiff for its settings (e.g. a tiny friction regularisation) and ends as
#: NUMERICAL_FAILURE instead of running for hours; seed 004's longest case takes ~1e4 dopri5 steps and
#: its 120 s limit at the seed's rk4 step of 2 ms 6e4
MAX_STEPS = 2_000_000


#: the stop event is located on the continuous extension to this fraction of the step, relative to
#: max(1, t / h) (the resolution of the time t itself), in at most MAX_EVENT_ITERATIONS iterations
EVENT_TOLERANCE = 1e-13
MAX_EVENT_ITERATIONS = 200


# --- description helpers ------------------------------------------------------------------------------
@kernel
def dof_map(desc):
    """(root_dof[3], angle_dof[N], n_dof): the index in q of the root's x, z, th (-1 where locked) and of
    each body's angle (body 0: the root's th)."""
    parent = desc[0]
    root_free = desc[4]
    n = parent.shape[0]
    root_dof = np.full(3, -1, np.int64)
    i = 0
    for c in range(3):
        if root_free[c] != 0:
            root_dof[c] = i
            i += 1
    angle_dof = np.empty(n, np.int64)
    angle_dof[0] = root_dof[2]
    for k in range(1, n):
        angle_dof[k] = i + k - 1
    return root_dof, angle_dof, i + n - 1


@kernel
def n_dof(desc):
    """Number of generalised coordinates of a description."""
    return dof_map(desc)[2]


@kernel
def _rot(th, a, b):
    """Body-frame (a, b) in the inertial frame at attitude th."""
    c = math.cos(th)
    s = math.sin(th)
    return c * a - s * b, s * a + c * b


@kernel
def _inertial_mass(mb, th, out):
    """out = T mb T^T with T = [[c, -s, 0], [s, c, 0], [0, 0, 1]] (seed 004 eq. (19))."""
    c = math.cos(th)
    s = math.sin(th)
    # rows of T mb
    a00 = c * mb[0, 0] - s * mb[1, 0]
    a01 = c * mb[0, 1] - s * mb[1, 1]
    a02 = c * mb[0, 2] - s * mb[1, 2]
    a10 = s * mb[0, 0] + c * mb[1, 0]
    a11 = s * mb[0, 1] + c * mb[1, 1]
    a12 = s * mb[0, 2] + c * mb[1, 2]
    out[0, 0] = a00 * c - a01 * s
    out[0, 1] = a00 * s + a01 * c
    out[0, 2] = a02
    out[1, 0] = a10 * c - a11 * s
    out[1, 1] = a10 * s + a11 * c
    out[1, 2] = a12
    out[2, 0] = mb[2, 0] * c - mb[2, 1] * s
    out[2, 1] = mb[2, 0] * s + mb[2, 1] * c
    out[2, 2] = mb[2, 2]


@kernel
def _kinematics(q, u, desc):
    """(pos, vel, lever, rel): centroid poses and velocities of every body, and per body k >= 1 the
    inertial vectors ``lever[k]`` = R_j (c_k - d_j) (parent's pin to k's pin; d_0 = 0: the root turns
    about its centroid) and ``rel[k]`` = -R_k d_k (k's pin to k's centroid); seed 004 eq. (13) with s = 0."""
    parent = desc[0]
    jp = desc[1]
    jb = desc[2]
    root_pose = desc[5]
    n = parent.shape[0]
    pos = np.empty((n, 3))
    vel = np.empty((n, 3))
    lever = np.empty((n, 2))
    rel = np.empty((n, 2))
    root_dof, angle_dof, nd = dof_map(desc)
    for c in range(3):
        d = root_dof[c]
        if d >= 0:
            pos[0, c] = q[d]
            vel[0, c] = u[d]
        else:
            pos[0, c] = root_pose[c]
            vel[0, c] = 0.0
    rel[0, 0] = 0.0
    rel[0, 1] = 0.0
    lever[0, 0] = 0.0
    lever[0, 1] = 0.0
    for k in range(1, n):
        j = parent[k]
        d = angle_dof[k]
        th = q[d]
        om = u[d]
        rcx, rcz = _rot(pos[j, 2], jp[k, 0], jp[k, 1])
        rdx, rdz = _rot(th, jb[k, 0], jb[k, 1])
        pos[k, 0] = pos[j, 0] + rcx - rdx
        pos[k, 1] = pos[j, 1] + rcz - rdz
        pos[k, 2] = th
        # v_k = v_j + om_j J R_j c - om_k J R_k d, J (x, z) = (-z, x)
        vel[k, 0] = vel[j, 0] - vel[j, 2] * rcz + om * rdz
        vel[k, 1] = vel[j, 1] + vel[j, 2] * rcx - om * rdx
        vel[k, 2] = om
        rel[k, 0] = -rdx
        rel[k, 1] = -rdz
        # lever from the parent's pin (its centroid for the root): rc - R_j d_j = rc + rel[j]
        lever[k, 0] = rcx + rel[j, 0]
        lever[k, 1] = rcz + rel[j, 1]
    return pos, vel, lever, rel


@kernel
def body_states(q, u, desc):
    """Kinematics of every centroid: pos[N, 3] = (x, z, th), vel[N, 3] = (vx, vz, om)
    (seed 004 eqs. (13)-(14))."""
    pos, vel, _, _ = _kinematics(q, u, desc)
    return pos, vel


@kernel
def partial_velocities(q, desc):
    """V[N, 3, n_dof]: d(vx, vz, om)_k / du_l, Kane's partial velocities and partial angular velocities
    (seed 004 eqs. (10) and (15) in the plane: the partial angular velocity of body k with respect to an
    absolute angle is 1 for its own angle and 0 otherwise; the partial velocity of its centroid with
    respect to an ancestor j's angle is J R_j (c - d_j), the arm from j's pin to the next pin on the path,
    turned by 90 degrees, and with respect to its own angle J R_k (-d_k))."""
    parent = desc[0]
    n = parent.shape[0]
    root_dof, angle_dof, nd = dof_map(desc)
    u = np.zeros(nd)
    pos, vel, lever, rel = _kinematics(q, u, desc)
    v = np.zeros((n, 3, nd))
    for c in range(3):
        if root_dof[c] >= 0:
            v[0, c, root_dof[c]] = 1.0
    for k in range(1, n):
        j = parent[k]
        for i in range(2):
            for l in range(nd):
                v[k, i, l] = v[j, i, l]
        dj = angle_dof[j]
        if dj >= 0:
            # replace the parent's own column (arm to its centroid) by the arm to k's pin
            v[k, 0, dj] = -lever[k, 1]
            v[k, 1, dj] = lever[k, 0]
        dk = angle_dof[k]
        v[k, 0, dk] = -rel[k, 1]
        v[k, 1, dk] = rel[k, 0]
        v[k, 2, dk] = 1.0
    return v


@kernel
def rotating_mass_velocity_terms(mi, vx, vz, om):
    """The velocity terms g = dM/dt w + (0, 0, vx Pz - vz Px) of the inertia of a rotating anisotropic
    mass: ``mi`` the inertial-frame generalised mass (eq. (19)), w = (vx, vz, om) the velocity it moves
    with, P = M w its momentum. Zero for diag(m, m, I)."""
    # P = M w; dM/dt w = om (J3 M w - M J3 w) with J3 (x, z, th) = (-z, x, 0)
    px = mi[0, 0] * vx + mi[0, 1] * vz + mi[0, 2] * om
    pz = mi[1, 0] * vx + mi[1, 1] * vz + mi[1, 2] * om
    mjw0 = -mi[0, 0] * vz + mi[0, 1] * vx
    mjw1 = -mi[1, 0] * vz + mi[1, 1] * vx
    mjw2 = -mi[2, 0] * vz + mi[2, 1] * vx
    # the Munk moment vx Pz - vz Px = -dT/d(th), the configuration term of Lagrange's equations
    return om * (-pz - mjw0), om * (px - mjw1), -om * mjw2 + (vx * pz - vz * px)


@kernel
def inertial_mass(mb, th):
    """The inertial-frame generalised mass T mb T^T of the body-frame mass ``mb`` at attitude th
    (seed 004 eq. (19))."""
    out = np.empty((3, 3))
    _inertial_mass(mb, th, out)
    return out


@kernel
def _inertia_terms(desc, pos, vel, lever, rel, mi, bias, gterm):
    """Per body: inertial mass mi[k] (eq. (19)), velocity-product acceleration bias[k] = dV_k/dt u
    (eqs. (16)-(17); translational only, the angular part is zero for absolute angles) and the velocity
    terms gterm[k] = dM_k/dt w_k + (0, 0, vx Pz - vz Px) of a rotating anisotropic mass."""
    parent = desc[0]
    mass = desc[3]
    n = parent.shape[0]
    bias[0, 0] = 0.0
    bias[0, 1] = 0.0
    for k in range(n):
        _inertial_mass(mass[k], pos[k, 2], mi[k])
        if k > 0:
            j = parent[k]
            omj = vel[j, 2]
            omk = vel[k, 2]
            # a_k = a_j + al_j J(arm_j) - om_j^2 arm_j + al_k J(rel_k) - om_k^2 rel_k, arm_j = R_j c
            armx = lever[k, 0] - rel[j, 0]
            armz = lever[k, 1] - rel[j, 1]
            bias[k, 0] = bias[j, 0] - omj * omj * armx - omk * omk * rel[k, 0]
            bias[k, 1] = bias[j, 1] - omj * omj * armz - omk * omk * rel[k, 1]
        g0, g1, g2 = rotating_mass_velocity_terms(mi[k], vel[k, 0], vel[k, 1], vel[k, 2])
        gterm[k, 0] = g0
        gterm[k, 1] = g1
        gterm[k, 2] = g2


@kernel
def _state_terms(q, u, desc):
    """The kinematics (:func:`_kinematics`) and inertia terms (:func:`_inertia_terms`) of every
    body at state (q, u): (pos, vel, lever, rel, M_k, bias, g_k)."""
    n = desc[0].shape[0]
    pos, vel, lever, rel = _kinematics(q, u, desc)
    mi = np.empty((n, 3, 3))
    bias = np.empty((n, 2))
    gterm = np.empty((n, 3))
    _inertia_terms(desc, pos, vel, lever, rel, mi, bias, gterm)
    return pos, vel, lever, rel, mi, bias, gterm


@kernel
def _cholesky_solve(a, b, x):
    """Solve a x = b for symmetric positive definite a (overwritten by its Cholesky factor); False if a
    pivot is not positive."""
    n = a.shape[0]
    for j in range(n):
        s = a[j, j]
        for p in range(j):
            s -= a[j, p] * a[j, p]
        if not (s > 0.0):
            return False
        d = math.sqrt(s)
        a[j, j] = d
        for i in range(j + 1, n):
            s = a[i, j]
            for p in range(j):
                s -= a[i, p] * a[j, p]
            a[i, j] = s / d
    for i in range(n):
        s = b[i]
        for p in range(i):
            s -= a[i, p] * x[p]
        x[i] = s / a[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for p in range(i + 1, n):
            s -= a[p, i] * x[p]
        x[i] = s / a[i, i]
    return True


@kernel
def generalised_mass_and_force(q, u, forces, desc):
    """Kane's equations as assembled (seed 004 eqs. (25)-(26)): the generalised mass matrix
    A = sum_k V_k^T M_k V_k and the right-hand side f = sum_k V_k^T (F_k - M_k b_k - g_k).

    Assembled from the description in O(N^2): for an ancestor j of body k, V_k[:, dof j] = (J lever_m, 0)
    with m the child of j on the path to k, the same for every body of m's subtree, so sums over bodies
    become subtree sums; the explicit sum over :func:`partial_velocities` gives the same matrix."""
    parent = desc[0]
    n = parent.shape[0]
    root_dof, angle_dof, nd = dof_map(desc)
    pos, vel, lever, rel, mi, bias, gterm = _state_terms(q, u, desc)
    a = np.zeros((nd, nd))
    f = np.zeros(nd)
    # h_k = F_k - M_k b_k - g_k, and its translational subtree sums
    h = np.empty((n, 3))
    for k in range(n):
        for i in range(3):
            h[k, i] = forces[k, i] - mi[k, i, 0] * bias[k, 0] - mi[k, i, 1] * bias[k, 1] - gterm[k, i]
    hs = np.empty((n, 2))
    for k in range(n):
        hs[k, 0] = h[k, 0]
        hs[k, 1] = h[k, 1]
    for k in range(n - 1, 0, -1):
        hs[parent[k], 0] += hs[k, 0]
        hs[parent[k], 1] += hs[k, 1]
    # generalised forces (eq. (23) for the applied part)
    rx = root_dof[0]
    rz = root_dof[1]
    if rx >= 0:
        f[rx] += hs[0, 0]
    if rz >= 0:
        f[rz] += hs[0, 1]
    for k in range(n):
        dk = angle_dof[k]
        if dk >= 0:
            f[dk] += -rel[k, 1] * h[k, 0] + rel[k, 0] * h[k, 1] + h[k, 2]
        if k > 0:
            dj = angle_dof[parent[k]]
            if dj >= 0:
                f[dj] += -lever[k, 1] * hs[k, 0] + lever[k, 0] * hs[k, 1]
    # root translations: V_k[:, x] = (1, 0, 0), V_k[:, z] = (0, 1, 0) for every body
    for k in range(n):
        if rx >= 0:
            a[rx, rx] += mi[k, 0, 0]
        if rz >= 0:
            a[rz, rz] += mi[k, 1, 1]
        if rx >= 0 and rz >= 0:
            a[rx, rz] += mi[k, 0, 1]
    if rx >= 0 and rz >= 0:
        a[rz, rx] = a[rx, rz]
    # angle columns: subtree momentum G_p generated by a unit rate of p's angle
    branch = np.empty(n, np.int64)
    for p in range(n):
        dp = angle_dof[p]
        if dp < 0:
            continue
        g0 = 0.0
        g1 = 0.0
        app = 0.0
        # body p itself: column (J rel_p, 1)
        cx = -rel[p, 1]
        cz = rel[p, 0]
        m0 = mi[p, 0, 0] * cx + mi[p, 0, 1] * cz + mi[p, 0, 2]
        m1 = mi[p, 1, 0] * cx + mi[p, 1, 1] * cz + mi[p, 1, 2]
        m2 = mi[p, 2, 0] * cx + mi[p, 2, 1] * cz + mi[p, 2, 2]
        g0 += m0
        g1 += m1
        app += cx * m0 + cz * m1 + m2
        branch[p] = p
        for k in range(p + 1, n):
            j = parent[k]
            if j == p:
                branch[k] = k
            elif j > p and branch[j] >= 0:
                branch[k] = branch[j]
            else:
                branch[k] = -1
                continue
            m = branch[k]
            cx = -lever[m, 1]
            cz = lever[m, 0]
            m0 = mi[k, 0, 0] * cx + mi[k, 0, 1] * cz
            m1 = mi[k, 1, 0] * cx + mi[k, 1, 1] * cz
            g0 += m0
            g1 += m1
            app += cx * m0 + cz * m1
        a[dp, dp] = app
        if rx >= 0:
            a[rx, dp] = g0
            a[dp, rx] = g0
        if rz >= 0:
            a[rz, dp] = g1
            a[dp, rz] = g1
        m = p
        j = parent[p] if p > 0 else -1
        while j >= 0:
            dj = angle_dof[j]
            if dj >= 0:
                v = -lever[m, 1] * g0 + lever[m, 0] * g1
                a[dj, dp] = v
                a[dp, dj] = v
            m = j
            j = parent[j] if j > 0 else -1
    return a, f


@kernel
def accelerations_assembled(q, u, forces, desc):
    """du/dt from Kane's equations A du/dt = f (seed 004 eqs. (24)-(27)) for the applied centroid forces
    ``forces[N, 3]`` = (Fx, Fz, My), with A and f assembled by :func:`generalised_mass_and_force` and solved
    by Cholesky (O(N^3) for a chain); NaN where A is not positive definite. The reference for
    :func:`accelerations`."""
    a, f = generalised_mass_and_force(q, u, forces, desc)
    du = np.empty(f.shape[0])
    if not _cholesky_solve(a, f, du):
        du[:] = np.nan
    return du


@kernel
def _xt_m_x(m, ax, az, out):
    """out += X^T m X for X = [[1, 0, -az], [0, 1, ax], [0, 0, 0]] (the map from a parent's centroid
    motion to its child's centroid motion at fixed absolute child angle; arm (ax, az) from the parent's
    centroid to the pin)."""
    # m X: columns 0, 1 of m, and column 2 = -az m[:, 0] + ax m[:, 1]
    c0 = -az * m[0, 0] + ax * m[0, 1]
    c1 = -az * m[1, 0] + ax * m[1, 1]
    out[0, 0] += m[0, 0]
    out[0, 1] += m[0, 1]
    out[1, 0] += m[1, 0]
    out[1, 1] += m[1, 1]
    out[0, 2] += c0
    out[1, 2] += c1
    out[2, 0] += -az * m[0, 0] + ax * m[1, 0]
    out[2, 1] += -az * m[0, 1] + ax * m[1, 1]
    out[2, 2] += -az * c0 + ax * c1


@kernel
def accelerations(q, u, forces, desc):
    """du/dt from Kane's equations (seed 004 eqs. (24)-(27)) for the applied centroid forces
    ``forces[N, 3]`` = (Fx, Fz, My); NaN where the equations are singular.

    The same equations as :func:`accelerations_assembled`, solved in O(N) by eliminating the tree from
    its leaves inward (the articulated-body recursion, Featherstone 2008, *Rigid Body Dynamics
    Algorithms*, ch. 7, written for absolute angles): with the centroid motion w_k = X_k w_j + s_k u_k,
    s_k = (J rel_k, 1), each subtree is reduced to an articulated inertia and bias force at its root
    body's centroid, then the accelerations are found outward."""
    parent = desc[0]
    n = parent.shape[0]
    root_dof, angle_dof, nd = dof_map(desc)
    pos, vel, lever, rel, ia, bias, gterm = _state_terms(q, u, desc)
    pa = np.empty((n, 3))
    for k in range(n):
        for i in range(3):
            pa[k, i] = gterm[k, i] - forces[k, i]
    uvec = np.empty((n, 3))
    dinv = np.zeros(n)
    uu = np.zeros(n)
    cb = np.zeros((n, 3))  # velocity-product acceleration of k relative to its parent's motion
    arm = np.zeros((n, 2))
    tmp = np.empty((3, 3))
    pk = np.empty(3)
    du = np.empty(nd)
    for k in range(n - 1, 0, -1):
        j = parent[k]
        arm[k, 0] = lever[k, 0] - rel[j, 0]
        arm[k, 1] = lever[k, 1] - rel[j, 1]
        omj = vel[j, 2]
        omk = vel[k, 2]
        cb[k, 0] = -omj * omj * arm[k, 0] - omk * omk * rel[k, 0]
        cb[k, 1] = -omj * omj * arm[k, 1] - omk * omk * rel[k, 1]
        sx = -rel[k, 1]
        sz = rel[k, 0]
        for i in range(3):
            uvec[k, i] = ia[k, i, 0] * sx + ia[k, i, 1] * sz + ia[k, i, 2]
        d = sx * uvec[k, 0] + sz * uvec[k, 1] + uvec[k, 2]
        if not (d > 0.0):
            du[:] = np.nan
            return du
        dinv[k] = 1.0 / d
        uu[k] = -(sx * pa[k, 0] + sz * pa[k, 1] + pa[k, 2])
        # articulated inertia and bias force passed to the parent
        for i in range(3):
            for l in range(3):
                tmp[i, l] = ia[k, i, l] - uvec[k, i] * uvec[k, l] * dinv[k]
        for i in range(3):
            pk[i] = pa[k, i] + tmp[i, 0] * cb[k, 0] + tmp[i, 1] * cb[k, 1] + uvec[k, i] * uu[k] * dinv[k]
        _xt_m_x(tmp, arm[k, 0], arm[k, 1], ia[j])
        pa[j, 0] += pk[0]
        pa[j, 1] += pk[1]
        pa[j, 2] += -arm[k, 1] * pk[0] + arm[k, 0] * pk[1]
    # the root: its free coordinates solve (S^T I S) a = -S^T p
    acc = np.zeros((n, 3))
    nr = 0
    idx = np.empty(3, np.int64)
    for c in range(3):
        if root_dof[c] >= 0:
            idx[nr] = c
            nr += 1
    if nr > 0:
        a0 = np.zeros((nr, nr))
        b0 = np.empty(nr)
        x0 = np.empty(nr)
        for i in range(nr):
            b0[i] = -pa[0, idx[i]]
            for l in range(nr):
                a0[i, l] = ia[0, idx[i], idx[l]]
        if not _cholesky_solve(a0, b0, x0):
            du[:] = np.nan
            return du
        for i in range(nr):
            acc[0, idx[i]] = x0[i]
            du[root_dof[idx[i]]] = x0[i]
    for k in range(1, n):
        j = parent[k]
        ax = acc[j, 0] - acc[j, 2] * arm[k, 1] + cb[k, 0]
        az = acc[j, 1] + acc[j, 2] * arm[k, 0] + cb[k, 1]
        ddk = (uu[k] - uvec[k, 0] * ax - uvec[k, 1] * az) * dinv[k]
        acc[k, 0] = ax - rel[k, 1] * ddk
        acc[k, 1] = az + rel[k, 0] * ddk
        acc[k, 2] = ddk
        du[angle_dof[k]] = ddk
    return du


@kernel
def body_accelerations(q, u, du, desc):
    """Centroid accelerations acc[N, 3] = (ax, az, alpha) for the generalised accelerations du
    (seed 004 eq. (17))."""
    parent = desc[0]
    n = parent.shape[0]
    root_dof, angle_dof, nd = dof_map(desc)
    pos, vel, lever, rel = _kinematics(q, u, desc)
    acc = np.empty((n, 3))
    for c in range(3):
        acc[0, c] = du[root_dof[c]] if root_dof[c] >= 0 else 0.0
    for k in range(1, n):
        j = parent[k]
        alj = acc[j, 2]
        omj = vel[j, 2]
        alk = du[angle_dof[k]]
        omk = vel[k, 2]
        armx = lever[k, 0] - rel[j, 0]
        armz = lever[k, 1] - rel[j, 1]
        acc[k, 0] = acc[j, 0] - alj * armz - omj * omj * armx - alk * rel[k, 1] - omk * omk * rel[k, 0]
        acc[k, 1] = acc[j, 1] + alj * armx - omj * omj * armz + alk * rel[k, 0] - omk * omk * rel[k, 1]
        acc[k, 2] = alk
    return acc


@kernel
def joint_forces(q, u, du, forces, desc):
    """Constraint force (Hx, Hz)[N, 2] that each pin exerts on body k (from its parent), seed 004
    eqs. (48)-(52): the equations of the degrees of freedom the pins remove give F^C_k = M_k a_k + g_k - F_k
    at each centroid (eq. (51)) and the pin force is the sum over the body's subtree (eq. (52): in a chain,
    the bodies outboard of the pin). Row 0 is the reaction of the root's locked coordinates (zero for a
    free root). Smooth pins carry no moment."""
    parent = desc[0]
    n = parent.shape[0]
    pos, vel, lever, rel, mi, bias, gterm = _state_terms(q, u, desc)
    acc = body_accelerations(q, u, du, desc)
    hf = np.empty((n, 2))
    for k in range(n):
        for i in range(2):
            hf[k, i] = (
                mi[k, i, 0] * acc[k, 0] + mi[k, i, 1] * acc[k, 1] + mi[k, i, 2] * acc[k, 2] + gterm[k, i]
            ) - forces[k, i]
    for k in range(n - 1, 0, -1):
        hf[parent[k], 0] += hf[k, 0]
        hf[parent[k], 1] += hf[k, 1]
    return hf


@kernel
def inertia_velocity_terms(q, u, desc):
    """g[N, 3] = dM_k/dt w_k + (0, 0, vx Pz - vz Px) per body: the velocity terms of the inertia of a
    rotating anisotropic (added) mass that the core includes (zero for a rigid body's diag(m, m, I)).
    A system that wants the Morison-type added-mass force of seed 004 eq. (46), -m_a n (n . a) with
    nothing else, adds these to its applied forces (docs/multibody.md); energy is then not conserved."""
    return _state_terms(q, u, desc)[6]


@kernel
def kinetic_energy(q, u, desc):
    """E^K = 1/2 sum_k w_k^T M_k w_k, w_k = (vx, vz, om) (seed 004 eq. (64), with the added mass)."""
    parent = desc[0]
    mass = desc[3]
    n = parent.shape[0]
    pos, vel = body_states(q, u, desc)
    mi = np.empty((3, 3))
    e = 0.0
    for k in range(n):
        _inertial_mass(mass[k], pos[k, 2], mi)
        for i in range(3):
            for j in range(3):
                e += 0.5 * vel[k, i] * mi[i, j] * vel[k, j]
    return e


# --- time integration ---------------------------------------------------------------------------------
@kernel
def _columns_valid(cols, n):
    """Whether the Jacobian columns ``cols`` are distinct indices of a state of size n."""
    for j in range(cols.shape[0]):
        if cols[j] < 0 or cols[j] >= n:
            return False
        for i in range(j):
            if cols[i] == cols[j]:
                return False
    return True


@kernel
def _output_times(t0, t_end, record_dt):
    """Output times t0 + i record_dt, ending exactly at t_end (recorded even off the grid)."""
    n_out = int(math.floor((t_end - t0) / record_dt * (1.0 + 1e-12))) + 1
    if t0 + (n_out - 1) * record_dt < t_end - 1e-12 * max(abs(t_end), record_dt):
        n_out += 1
    t_out = np.empty(n_out)
    for i in range(n_out):
        t_out[i] = min(t0 + i * record_dt, t_end)
    t_out[n_out - 1] = t_end
    return t_out


@small_kernel
def _settings_valid(y0, t0, t_end, dt, rtol, atol, record_dt, max_steps, jac_cols):
    """Whether the settings of :func:`integrate` are valid (finite times with t_end > t0, positive finite
    step and record interval, positive tolerances and step budget, a finite initial state, distinct
    Jacobian columns of it)."""
    return (
        math.isfinite(t0)
        and math.isfinite(t_end)
        and t_end > t0
        and dt > 0.0
        and math.isfinite(dt)
        and record_dt > 0.0
        and math.isfinite(record_dt)
        and rtol > 0.0
        and atol > 0.0
        and max_steps > 0
        and all_finite(y0)
        and _columns_valid(jac_cols, y0.shape[0])
    )


@small_kernel
def _work_arrays(n, m):
    """The work arrays of :func:`integrate` for a state of size n and m Jacobian columns: (k, ynew, err,
    r, ytmp, jc, wa, piv, kr, ztmp) of the core's attempt_step and the error norm's groups (one a
    component)."""
    groups = np.empty((n, 2), np.int64)
    for i in range(n):
        groups[i, 0] = i
        groups[i, 1] = i + 1
    return (
        np.empty((N_STAGES, n)),
        np.empty(n),
        np.empty(n),
        np.zeros((5, n)),
        np.empty(n),
        np.zeros((n, m)),
        np.empty((m, m)),
        np.empty(m, np.int64),
        np.empty((ROS_STAGES, n)),
        np.empty(m),
        groups,
    )


@small_kernel
def _record_stop(r, t, h, th, t_ev, t_out, i_rec, times, states, ytmp):
    """Records up to the located stop event at t_ev = t + th h (on the step's continuous extension r),
    the event state the last of them; returns the number of records."""
    i_rec = record_until(r, t, h, t_ev, t_out, i_rec, times, states, ytmp)
    if times[i_rec - 1] < t_ev:
        dense_state(r, th, ytmp)
        times[i_rec] = t_ev
        states[i_rec, :] = ytmp
        i_rec += 1
    return i_rec


@small_kernel
def _next_step(t, h_try, out, ctx, loop):
    """The multibody hook of the driver loop before each attempt (:func:`.core.driver_loop`): the step
    budget, then the step's size: the proposal h_try cut to end at t_end (a numerical failure when it
    underflows) for an adaptive method, the next point t0 + i dt of the grid for a fixed one (the last
    step ending exactly at t_end)."""
    system, params, y, ynew, k, r, ytmp, t0, t_end, dt, kind, adaptive, max_steps = ctx
    n_tried, i_step, i_rec, t_new, g, armed = loop
    status = GO_ON
    h = h_try
    if n_tried >= max_steps:
        status = NUMERICAL_FAILURE
    else:
        n_tried += 1
        if adaptive:
            h = min(h_try, t_end - t)
            if h <= 1e-14 * max(1.0, abs(t)):
                status = NUMERICAL_FAILURE
        else:
            t_new = t0 + (i_step + 1) * dt
            if t_end - t_new <= 1e-9 * dt:
                t_new = t_end  # the last step ends exactly at t_end (shorter if t_end is off the grid)
            h = t_new - t
    return status, kind, h, (n_tried, i_step, i_rec, t_new, g, armed)


@small_kernel
def _accepted(t, h, out, ctx, loop):
    """The multibody hook of the driver loop after an accepted step (:func:`.core.driver_loop`): a
    non-finite end state, rate or event value is a numerical failure; the stop event (armed once
    positive) crossing zero is located on the step's continuous extension and ends the run there
    (STOPPED, its state the last record); otherwise the records in the step, the state moved on, and
    the time limit at t_end."""
    system, params, y, ynew, k, r, ytmp, t0, t_end, dt, kind, adaptive, max_steps = ctx
    t_out, times, states = out
    n_tried, i_step, i_rec, t_new, g, armed = loop
    status = GO_ON
    if not (all_finite(ynew) and all_finite(k[N_STAGES - 1])):
        status = NUMERICAL_FAILURE
    else:
        if adaptive:
            t_new = t_end if t + h >= t_end else t + h
        i_step += 1
        g_new = system_event(system, t_new, ynew, params)
        if not math.isfinite(g_new):
            status = NUMERICAL_FAILURE
        elif armed and g_new <= 0.0:
            tol = EVENT_TOLERANCE * max(1.0, abs(t) / max(h, 1e-300))
            th = locate_event(system, r, t, h, g, g_new, params, ytmp, tol, MAX_EVENT_ITERATIONS)
            t_ev = t + th * h
            i_rec = _record_stop(r, t, h, th, t_ev, t_out, i_rec, times, states, ytmp)
            t = t_ev
            status = STOPPED
        else:
            i_rec = record_until(r, t, h, t_new, t_out, i_rec, times, states, ytmp)
            if g_new > 0.0:
                armed = True
            g = g_new
            y[:] = ynew
            k[0, :] = k[N_STAGES - 1]
            t = t_new
            if t >= t_end:
                status = TIME_LIMIT
    return status, t, True, (n_tried, i_step, i_rec, t_new, g, armed)


@kernel
def integrate(system, y0, t0, t_end, params, method, dt, rtol, atol, record_dt, max_steps, jac_cols):
    """Integrate dy/dt = system.rhs(t, y, params, dy) from t0 to t_end, stopping where
    system.event(t, y, params) crosses zero from above (the event is armed once it has been positive);
    ``system`` is a :class:`mineburial.kernels.core.System`, reached by static dispatch.

    method: "dopri5" -- Dormand-Prince 5(4), PI step-size control on the mixed tolerance
    atol + rtol |y| per component, first step ``dt``, 4th-order continuous extension; "rk4" -- classical
    Runge-Kutta with the fixed step ``dt`` (seed 004 sec. 4.1: 2 ms), cubic Hermite continuous extension;
    "ros34pw2" -- the Rosenbrock-W method ROS34PW2 (linearly implicit, L-stable, for stiff systems such as
    the restraint's regularised friction), PI control on its order-3(2) error estimate, first step ``dt``,
    the Jacobian columns ``jac_cols`` of y by differences, reused by the core's Jacobian-age policy, cubic
    Hermite continuous extension. All reuse the steps of :mod:`.core` and :mod:`.integrators`. The state
    is recorded at the exact times t0 + i record_dt on the continuous extension, and the event is located
    on it (Illinois); when the run stops early the located event state is the last record. The steps are
    the integration core's driver loop (:func:`.core.driver_loop`) with the hooks :func:`_next_step` and
    :func:`_accepted`, inlined.

    At most ``max_steps`` steps (accepted and rejected) are taken (:data:`MAX_STEPS` is the Python default).

    Returns (times, states, status, t_stop): status STOPPED, TIME_LIMIT, NUMERICAL_FAILURE (a non-finite
    state or rate, a step-size underflow or the step budget spent: the records end at the last finite
    state) or INVALID_INPUT;
    t_stop is the time the run ended (the event time when STOPPED). Never returns NaN.

    Cached on disk once per system (its type names it, :mod:`.core`): a second process compiles nothing.
    """
    n = y0.shape[0]
    kind = method_code(method)
    if kind < 0:
        return np.zeros(0), np.zeros((0, n)), INVALID_INPUT, t0
    if not _settings_valid(y0, t0, t_end, dt, rtol, atol, record_dt, max_steps, jac_cols):
        return np.zeros(0), np.zeros((0, n)), INVALID_INPUT, t0
    t_out = _output_times(t0, t_end, record_dt)
    n_out = t_out.shape[0]
    times = np.zeros(n_out + 1)
    states = np.zeros((n_out + 1, n))
    y = y0.copy()
    k, ynew, err, r, ytmp, jc, wa, piv, kr, ztmp, groups = _work_arrays(n, jac_cols.shape[0])
    times[0] = t0
    states[0, :] = y
    t = t0
    system_rhs(system, t, y, params, k[0])
    if not all_finite(k[0]):
        return times[:1].copy(), states[:1].copy(), NUMERICAL_FAILURE, t
    g = system_event(system, t, y, params)
    ws = (k, ynew, err, r, ytmp, jac_cols, jc, wa, piv, kr, ztmp)  # of the core's attempt_step
    ctx = (system, params, y, ynew, k, r, ytmp, t0, t_end, dt, kind, ADAPTIVE[kind], max_steps)
    loop = (0, 0, 1, t0, g, g > 0.0)  # attempts, accepted steps, records, end of the step, event, armed
    out = (t_out, times, states)
    h_first = min(dt, t_end - t0)
    status, t, loop = driver_loop(
        _next_step, _accepted, system, t, y, h_first, params, True, groups, rtol, atol, ws, out, ctx, loop
    )
    i_rec = loop[2]
    return times[:i_rec].copy(), states[:i_rec].copy(), status, t
