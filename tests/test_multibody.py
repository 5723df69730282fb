"""The planar Kane multibody core (issue 11) against independent references.

* pendulums: scipy's solve_ivp on the Lagrangian equations written out below (both integrators);
* the generalised mass assembled in O(N^2) against the explicit sum over partial velocities, and the
  partial velocities against finite differences of the positions;
* energy and horizontal momentum of a free branched chain with added mass (no friction, no drag);
* a block sliding on the seabed with Coulomb friction: closed-form stopping time and distance, the stop
  located by the event on the continuous extension;
* a chain hanging between two pins, relaxed to rest: the catenary and its end tension;
* pin forces: statics of a hanging chain and the pin force of a swinging rod (Newton's second law);
* seabed-contact kernels against their closed-form integrals; statuses; bad descriptions.

Every system here is one right-hand side (:func:`rhs`) with parameters, so the driver is compiled once.
"""

import math

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from mineburial import multibody as mbp
from mineburial.kernels import multibody as mb
from mineburial.kernels import seabed_contact as sc
from mineburial.kernels.core import System

G = 9.81

# extra parameters of the test system (a float array, so that every system has the same numba type)
LIN_DAMP, ROT_DAMP = 0, 1  # linear damping on every body: -c v, -c_r om
SPRING_BODY, SPRING_A, SPRING_X, SPRING_Z, SPRING_K, SPRING_C = 2, 3, 4, 5, 6, 7  # spring from body point
CONTACT_ON, CONTACT_B, CONTACT_K, CONTACT_C, CONTACT_MU, CONTACT_VREG = 8, 9, 10, 11, 12, 13  # body 0 point
EVENT_INDEX, EVENT_LEVEL, T_FAIL = 14, 15, 16
SEGMENT_HALF, SEGMENT_K = 17, 18  # segment contact of every body with mass (half length; 0: off)
N_EXTRA = 19


def extra(**kw):
    e = np.zeros(N_EXTRA)
    e[SPRING_BODY] = -1.0
    e[EVENT_INDEX] = -1.0
    e[T_FAIL] = np.inf
    for k, v in kw.items():
        e[globals()[k.upper()]] = v
    return e


@njit
def forces_of(t, q, u, desc, weight, ex):
    pos, vel = mb.body_states(q, u, desc)
    n = weight.shape[0]
    f = np.zeros((n, 3))
    for k in range(n):
        f[k, 1] = -weight[k]
        f[k, 0] -= ex[LIN_DAMP] * vel[k, 0]
        f[k, 1] -= ex[LIN_DAMP] * vel[k, 1]
        f[k, 2] -= ex[ROT_DAMP] * vel[k, 2]
    kb = int(ex[SPRING_BODY])
    if kb >= 0:
        # a spring-damper from body point (a, 0) to the fixed point (X, Z): a second pin, by penalty
        c = math.cos(pos[kb, 2])
        s = math.sin(pos[kb, 2])
        rx = c * ex[SPRING_A]
        rz = s * ex[SPRING_A]
        dx = pos[kb, 0] + rx - ex[SPRING_X]
        dz = pos[kb, 1] + rz - ex[SPRING_Z]
        vx = vel[kb, 0] - vel[kb, 2] * rz
        vz = vel[kb, 1] + vel[kb, 2] * rx
        fx = -ex[SPRING_K] * dx - ex[SPRING_C] * vx
        fz = -ex[SPRING_K] * dz - ex[SPRING_C] * vz
        f[kb, 0] += fx
        f[kb, 1] += fz
        f[kb, 2] += rx * fz - rz * fx
    if ex[CONTACT_ON] > 0.0:
        fx, fz, my = sc.point_contact(
            pos[0, 0],
            pos[0, 1],
            pos[0, 2],
            vel[0, 0],
            vel[0, 1],
            vel[0, 2],
            0.0,
            ex[CONTACT_B],
            0.0,
            ex[CONTACT_K],
            ex[CONTACT_C],
            ex[CONTACT_MU],
            ex[CONTACT_VREG],
        )
        f[0, 0] += fx
        f[0, 1] += fz
        f[0, 2] += my
    if ex[SEGMENT_HALF] > 0.0:
        for k in range(n):
            if weight[k] > 0.0:
                fx, fz, my = sc.segment_contact(
                    pos[k, 0],
                    pos[k, 1],
                    pos[k, 2],
                    vel[k, 0],
                    vel[k, 1],
                    vel[k, 2],
                    ex[SEGMENT_HALF],
                    0.0,
                    ex[SEGMENT_K],
                    0.0,
                    0.0,
                    1e-3,
                )
                f[k, 0] += fx
                f[k, 1] += fz
                f[k, 2] += my
    return f


@njit
def rhs(t, y, p, dy):
    desc, weight, ex = p
    nd = y.shape[0] // 2
    q = y[:nd]
    u = y[nd:]
    f = forces_of(t, q, u, desc, weight, ex)
    du = mb.accelerations(q, u, f, desc)
    for i in range(nd):
        dy[i] = u[i]
        dy[nd + i] = du[i]
    if t > ex[T_FAIL]:
        dy[0] = np.nan


@njit
def event(t, y, p):
    ex = p[2]
    i = int(ex[EVENT_INDEX])
    if i < 0:
        return 1.0
    return y[i] - ex[EVENT_LEVEL]


#: the test systems of this module in the integration core (reached by static dispatch)
PENDULUM = System("test pendulum", rhs, event)


def weights_of(desc, wet_fraction=1.0):
    return np.ascontiguousarray(desc.mass_matrix[:, 0, 0] * G * wet_fraction)


def run(desc, y0, t_end, ex, method="dopri5", dt=1e-3, rtol=1e-10, atol=1e-12, record_dt=0.05, weight=None):
    weight = weights_of(desc) if weight is None else weight
    return mbp.integrate(
        PENDULUM, y0, 0.0, t_end, (desc.arrays(), weight, ex), method, dt, rtol, atol, record_dt
    )


def rod(m, length):
    return mbp.rigid_mass_matrix(m, m * length**2 / 12.0)


# --- pendulums against solve_ivp on their Lagrangian equations --------------------------------------
def double_pendulum_lagrangian(m1, l1, m2, l2):
    """Two uniform rods pinned at the origin, absolute angles from +x toward +z (up), gravity -z.
    T = 1/2 M11 w1^2 + M12 w1 w2 + 1/2 M22 w2^2, V = g (m1 l1/2 sin t1 + m2 (l1 sin t1 + l2/2 sin t2))."""
    i1 = m1 * l1**2 / 12.0
    i2 = m2 * l2**2 / 12.0

    def f(t, y):
        t1, t2, w1, w2 = y
        m11 = m1 * l1**2 / 4.0 + i1 + m2 * l1**2
        m22 = m2 * l2**2 / 4.0 + i2
        k = m2 * l1 * l2 / 2.0
        m12 = k * math.cos(t1 - t2)
        s = math.sin(t1 - t2)
        rhs1 = -G * (m1 * l1 / 2.0 + m2 * l1) * math.cos(t1) - k * s * w2 * w2
        rhs2 = -G * m2 * l2 / 2.0 * math.cos(t2) + k * s * w1 * w1
        det = m11 * m22 - m12 * m12
        return [w1, w2, (m22 * rhs1 - m12 * rhs2) / det, (m11 * rhs2 - m12 * rhs1) / det]

    return f


@pytest.mark.parametrize("method, tol", [("dopri5", 1e-8), ("rk4", 1e-6)])
def test_single_pendulum_matches_lagrangian(method, tol):
    m, length = 3.0, 1.2
    desc, q0 = mbp.chain(1, length, rod(m, length), [-0.3])
    y0 = desc.initial_state(q0, [0.5])
    res = run(desc, y0, 2.0, extra(), method=method, dt=2e-3, record_dt=0.1)
    assert res.status_name == "time_limit"
    inertia = m * length**2 / 12.0 + m * length**2 / 4.0

    def f(t, y):
        return [y[1], -m * G * length / 2.0 * math.cos(y[0]) / inertia]

    ref = solve_ivp(f, (0.0, 2.0), y0, t_eval=res.times, rtol=1e-12, atol=1e-12, method="DOP853")
    np.testing.assert_allclose(res.times, np.arange(21) * 0.1, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.states, ref.y.T, rtol=0, atol=tol)


@pytest.mark.parametrize("method, tol", [("dopri5", 1e-7), ("rk4", 2e-5)])
def test_double_pendulum_matches_lagrangian(method, tol):
    m1, l1, m2, l2 = 2.0, 1.0, 1.0, 0.7
    desc = mbp.Description(  # a ground and two unequal rods
        [-1, 0, 1],
        [[0, 0], [0, 0], [l1 / 2, 0]],
        [[0, 0], [-l1 / 2, 0], [-l2 / 2, 0]],
        [np.zeros((3, 3)), rod(m1, l1), rod(m2, l2)],
        [0, 0, 0],
        [0.0, 0.0, 0.0],
    )
    y0 = desc.initial_state([0.4, -0.2], [0.0, 1.5])
    t_end = 3.0
    res = run(desc, y0, t_end, extra(), method=method, dt=1e-3, record_dt=0.1)
    assert res.status_name == "time_limit"
    ref = solve_ivp(
        double_pendulum_lagrangian(m1, l1, m2, l2),
        (0.0, t_end),
        y0,
        t_eval=res.times,
        rtol=1e-12,
        atol=1e-12,
        method="DOP853",
    )
    np.testing.assert_allclose(res.states, ref.y.T, rtol=0, atol=tol)


def test_pin_force_of_swinging_rod_is_newtons_second_law():
    """Pin force on a swinging rod = m a_c - m g, a_c from the closed-form angular acceleration."""
    m, length = 2.0, 0.8
    desc, _ = mbp.chain(1, length, rod(m, length), [0.0])
    th, om = -0.7, 2.3
    q = np.array([th])
    u = np.array([om])
    f = np.zeros((2, 3))
    f[1, 1] = -m * G
    du = mb.accelerations(q, u, f, desc.arrays())
    alpha = -m * G * length / 2.0 * math.cos(th) / (m * length**2 / 3.0)
    assert du[0] == pytest.approx(alpha, rel=1e-13)
    e = np.array([math.cos(th), math.sin(th)])
    ep = np.array([-math.sin(th), math.cos(th)])
    a_c = length / 2.0 * (alpha * ep - om * om * e)
    expected = m * a_c - np.array([0.0, -m * G])
    h = mb.joint_forces(q, u, du, f, desc.arrays())
    np.testing.assert_allclose(h[1], expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(h[0], expected, rtol=1e-12, atol=1e-12)  # the ground's reaction


# --- the assembly of Kane's equations ----------------------------------------------------------------
def branched_tree():
    """Five segments with added mass (anisotropic) in a tree: 0 - 1 - 2, 1 - 3 - 4 (3 hangs off 1's middle),
    root free in x, z, theta."""
    mass = [
        mbp.segment_mass_matrix(m, ln, 0.05, 1.0)
        for m, ln in [(2, 1.0), (1, 0.6), (1.5, 0.8), (0.7, 0.5), (1, 0.4)]
    ]
    lengths = [1.0, 0.6, 0.8, 0.5, 0.4]
    parent = [-1, 0, 1, 1, 3]
    jp = [[0, 0], [0.5, 0], [0.3, 0], [0.0, 0.0], [0.25, 0]]
    jb = [[0, 0], [-0.3, 0], [-0.4, 0], [-0.25, 0], [-0.2, 0]]
    desc = mbp.Description(parent, jp, jb, mass, [1, 1, 1], [0.0, 2.0, 0.3])
    assert len(lengths) == desc.n_bodies
    return desc


def test_generalised_mass_equals_sum_over_partial_velocities():
    desc = branched_tree()
    d = desc.arrays()
    rng = np.random.default_rng(1)
    q = rng.uniform(-2, 2, desc.n_dof)
    u = rng.uniform(-2, 2, desc.n_dof)
    f = rng.uniform(-5, 5, (desc.n_bodies, 3))
    a, rhs_f = mb.generalised_mass_and_force(q, u, f, d)
    v = mb.partial_velocities(q, d)
    pos, vel = mb.body_states(q, u, d)
    explicit = np.zeros_like(a)
    for k in range(desc.n_bodies):
        c, s = math.cos(pos[k, 2]), math.sin(pos[k, 2])
        t = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
        explicit += v[k].T @ (t @ desc.mass_matrix[k] @ t.T) @ v[k]
    np.testing.assert_allclose(a, explicit, rtol=1e-12, atol=1e-12)
    # velocities are V u, and V is the derivative of the positions (central differences)
    np.testing.assert_allclose(np.einsum("kil,l->ki", v, u), vel, rtol=1e-13, atol=1e-13)
    eps = 1e-6
    for l in range(desc.n_dof):
        dq = np.zeros(desc.n_dof)
        dq[l] = eps
        p1, _ = mb.body_states(q + dq, u, d)
        p0, _ = mb.body_states(q - dq, u, d)
        np.testing.assert_allclose((p1 - p0) / (2 * eps), v[:, :, l], atol=1e-8)
    # generalised active force of the applied loads alone (u = 0): sum_k V_k^T F_k (eq. (23))
    _, f0 = mb.generalised_mass_and_force(q, np.zeros_like(u), f, d)
    np.testing.assert_allclose(f0, np.einsum("kil,ki->l", v, f), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("root_free", [[1, 1, 1], [1, 0, 0], [0, 0, 1], [0, 0, 0], [1, 1, 0]])
def test_recursive_solution_equals_assembled_kane_equations(root_free):
    """accelerations (O(N) recursion) solves the same equations as the assembled A du = f (Cholesky)."""
    tree = branched_tree()
    desc = mbp.Description(
        tree.parent, tree.joint_on_parent, tree.joint_on_body, tree.mass_matrix, root_free, tree.root_pose
    )
    d = desc.arrays()
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = rng.uniform(-2, 2, desc.n_dof)
        u = rng.uniform(-2, 2, desc.n_dof)
        f = rng.uniform(-5, 5, (desc.n_bodies, 3))
        du = mb.accelerations(q, u, f, d)
        a, rhs_f = mb.generalised_mass_and_force(q, u, f, d)
        np.testing.assert_allclose(a @ du, rhs_f, rtol=0, atol=1e-11 * np.abs(rhs_f).max())
        np.testing.assert_allclose(du, mb.accelerations_assembled(q, u, f, d), rtol=1e-10, atol=1e-12)
        # Newton's second law for the whole tree: no reaction on a free root coordinate
        hf = mb.joint_forces(q, u, du, f, d)
        for c in range(2):
            if root_free[c]:
                assert abs(hf[0, c]) < 1e-11 * np.abs(f).max()


def test_morison_terms_vanish_for_rigid_bodies():
    """The velocity terms of a rotating mass are zero for diag(m, m, I), not for an added mass."""
    desc, q0 = mbp.chain(3, 0.5, rod(1.0, 0.5), [0.3, -0.2, 0.5], pinned=False)
    u = np.array([0.4, -0.3, 1.0, -2.0, 1.5])
    np.testing.assert_allclose(mb.inertia_velocity_terms(q0, u, desc.arrays()), 0.0, atol=1e-14)
    g = mb.inertia_velocity_terms(
        branched_tree().coordinates([0.1, 0.2, 0.3, 0.4]), np.ones(7), branched_tree().arrays()
    )
    assert np.abs(g).max() > 0.1


def test_energy_and_momentum_of_free_tree_with_added_mass_are_conserved():
    """No friction, no drag: kinetic (with added mass) + potential energy conserved to 1e-6 relative,
    and the horizontal impulse sum (M_k w_k)_x (no horizontal force) conserved."""
    desc = branched_tree()
    d = desc.arrays()
    weight = weights_of(desc, wet_fraction=0.3)
    q0 = desc.coordinates([0.2, -1.0, 1.5, -0.4], root=[0.0, 2.0, 0.3])
    y0 = desc.initial_state(q0, [0.3, -0.2, 1.0, 2.0, -1.5, 0.5, 3.0])
    res = run(desc, y0, 4.0, extra(), weight=weight, rtol=1e-10, record_dt=0.05)
    assert res.status_name == "time_limit"
    nd = desc.n_dof
    energy, kinetic, impulse = [], [], []
    for y in res.states:
        pos, vel = mb.body_states(y[:nd], y[nd:], d)
        ke = 0.0
        px = 0.0
        for k in range(desc.n_bodies):
            c, s = math.cos(pos[k, 2]), math.sin(pos[k, 2])
            t = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
            p = t @ desc.mass_matrix[k] @ t.T @ vel[k]
            ke += 0.5 * vel[k] @ p
            px += p[0]
        assert mb.kinetic_energy(y[:nd], y[nd:], d) == pytest.approx(ke, rel=1e-12)
        kinetic.append(ke)
        energy.append(ke + weight @ pos[:, 1])
        impulse.append(px)
    energy = np.array(energy)
    assert np.ptp(kinetic) > 1.0  # it really moved: energy went between kinetic and potential
    assert np.abs(energy - energy[0]).max() < 1e-6 * max(kinetic)
    assert np.ptp(impulse) < 1e-6 * np.abs(impulse).max()


# --- seabed contact: a block sliding with Coulomb friction -----------------------------------------
@pytest.mark.parametrize("method, v_stop", [("dopri5", 1e-3), ("rk4", 0.05)])
def test_block_sliding_on_seabed_stops_at_closed_form_time_and_distance(method, v_stop):
    """Stopping under Coulomb friction: t = v0/(mu g), s = v0^2/(2 mu g). The run stops when the speed
    crosses v_stop (the event, located on the continuous extension), so the closed forms are
    t = (v0 - v_stop)/(mu g) and s = (v0^2 - v_stop^2)/(2 mu g); the regularisation (v_reg = 1e-6 m/s)
    changes them by O((v_reg/v_stop)^2).

    Fixed-step rk4 meets the friction's sign change inside a step whenever v < h mu g (here 8 mm/s at
    2 ms): its stages then straddle v = 0 and it stalls at a spurious speed of order h mu g unless v_reg
    exceeds about h mu g / 2.8 (the stability limit of the regularised law, docs/multibody.md); so the
    rk4 run is stopped at 5 cm/s, where every stage still slides forward."""
    m, h, k = 500.0, 0.5, 1e6
    mu, v0, v_reg = 0.4, 3.0, 1e-6
    desc = mbp.Description([-1], [[0, 0]], [[0, 0]], [rigid(m, m)], [1, 1, 0], [0.0, 0.0, 0.0])
    z_eq = h / 2.0 - m * G / k  # resting on the foundation
    y0 = desc.initial_state([0.0, z_eq], [v0, 0.0])
    ex = extra(
        contact_on=1.0,
        contact_b=-h / 2.0,
        contact_k=k,
        contact_c=2.0 * math.sqrt(k * m),
        contact_mu=mu,
        contact_vreg=v_reg,
        event_index=2.0,
        event_level=v_stop,
    )
    res = run(desc, y0, 5.0, ex, method=method, dt=2e-3, rtol=1e-10, record_dt=0.25)
    assert res.status_name == "stopped"
    t_ref = (v0 - v_stop) / (mu * G)
    s_ref = (v0**2 - v_stop**2) / (2 * mu * G)
    assert res.t_stop == pytest.approx(t_ref, rel=1e-5)
    assert res.times[-1] == res.t_stop
    assert res.states[-1, 2] == pytest.approx(v_stop, abs=1e-9)  # located on the interpolant
    assert res.states[-1, 0] == pytest.approx(s_ref, rel=1e-5)
    # the Coulomb limits v_stop -> 0
    assert res.t_stop == pytest.approx(v0 / (mu * G), rel=2 * v_stop / v0)
    assert res.states[-1, 0] == pytest.approx(v0**2 / (2 * mu * G), rel=(v_stop / v0) ** 2 + 1e-5)
    # records at the exact output times before the stop
    n = len(res.times) - 1
    np.testing.assert_allclose(res.times[:n], 0.25 * np.arange(n), atol=1e-12)


def rigid(m, inertia):
    return mbp.rigid_mass_matrix(m, inertia)


# --- a chain at rest: catenary and pin forces ---------------------------------------------------------
def test_hanging_chain_pin_forces_carry_the_weight_below():
    """A chain hanging straight down from a pin, at rest: each pin carries the weight of the links below."""
    n, length, m = 6, 0.3, 1.7
    desc, q0 = mbp.chain(n, length, rod(m, length), [-math.pi / 2])
    d = desc.arrays()
    u = np.zeros(desc.n_dof)
    f = np.zeros((desc.n_bodies, 3))
    f[1:, 1] = -m * G
    du = mb.accelerations(q0, u, f, d)
    np.testing.assert_allclose(du, 0.0, atol=1e-12)
    h = mb.joint_forces(q0, u, du, f, d)
    below = m * G * np.arange(n, 0, -1)
    np.testing.assert_allclose(h[1:, 1], below, rtol=1e-13)
    np.testing.assert_allclose(h[1:, 0], 0.0, atol=1e-12)


def chain_at_rest_between_two_pins(n, total=2.0, span=1.5, mass_per_length=1.6):
    """A chain of n links pinned at (0, 0) and, by a stiff spring, at (span, 0), released from a V shape
    (the two halves straight) and relaxed by linear damping until at rest. Returns the description, the
    rest state, the forces there, and the catenary parameter a: 2 a sinh(span/(2a)) = total."""
    link = total / n
    m = mass_per_length * link
    half = total / 2.0
    phi = math.acos((span / 2.0) / half)
    angles = np.array([-phi] * (n // 2) + [phi] * (n // 2))
    desc, q0 = mbp.chain(n, link, rod(m, link), angles)
    k_spring = 1e4 * n * m * G / link
    ex = extra(
        lin_damp=8.0 * m,
        rot_damp=8.0 * m * link**2 / 12,
        spring_body=float(n),
        spring_a=link / 2.0,
        spring_x=span,
        spring_z=0.0,
        spring_k=k_spring,
        spring_c=0.5 * math.sqrt(k_spring * m),
    )
    res = run(desc, desc.initial_state(q0), 12.0, ex, rtol=1e-8, atol=1e-10, record_dt=1.0)
    assert res.status_name == "time_limit"
    y = res.states[-1]
    nd = desc.n_dof
    assert np.abs(y[nd:]).max() < 1e-6  # at rest
    f = forces_of(0.0, y[:nd], y[nd:], desc.arrays(), weights_of(desc), ex)
    a = brentq(lambda a: 2 * a * math.sinh(span / (2 * a)) - total, 0.05, 100.0)
    return desc, y, f, a


def test_chain_between_two_pins_relaxes_to_the_catenary():
    """At rest the chain lies on y = a cosh((x - span/2)/a) + const. The pins of a chain of rigid links
    sample the catenary with the midpoint rule in arc length (each link is parallel to the catenary's
    tangent at its middle), so they lie within about total * L_link^2 / (24 a^2) of it, and the deviation
    falls as L_link^2 (checked: halving the links divides it by about 4); the spring stretches by only
    (end tension)/k = O(1e-5) m. End tension: horizontal w' a, vertical half the weight."""
    total, span, wl = 2.0, 1.5, 1.6 * G
    deviation = {}
    for n in (12, 24):
        desc, y, f, a = chain_at_rest_between_two_pins(n, total, span)
        link = total / n
        nd = desc.n_dof
        pos, _ = mb.body_states(y[:nd], y[nd:], desc.arrays())
        pins_x = pos[1:, 0] - np.cos(pos[1:, 2]) * link / 2
        pins_z = pos[1:, 1] - np.sin(pos[1:, 2]) * link / 2
        catenary = a * np.cosh((pins_x - span / 2) / a) - a * math.cosh(span / (2 * a))
        deviation[n] = np.abs(pins_z - catenary).max()
        tol = total * link**2 / (24 * a**2)
        assert deviation[n] < tol
        assert -catenary.min() > 50 * tol  # the sag is far larger: the comparison has teeth
        du = mb.accelerations(y[:nd], y[nd:], f, desc.arrays())
        hf = mb.joint_forces(y[:nd], y[nd:], du, f, desc.arrays())
        # (the discrete chain's horizontal tension differs from the catenary's by the same midpoint order)
        assert -hf[1, 0] == pytest.approx(wl * a, rel=link**2 / (12 * a**2))
        assert hf[1, 1] == pytest.approx(wl * total / 2.0, rel=1e-4)
    assert 3.0 < deviation[12] / deviation[24] < 5.0


def test_chain_bouncing_on_elastic_seabed_conserves_energy():
    """Three free links dropped, tilted and spinning, onto an undamped frictionless Winkler seabed: the
    kinetic + potential + foundation energy (closed form, segment_foundation_energy) is conserved, which
    checks the quadrature of the contact force and moment against the exact energy they derive from."""
    length, m, k = 0.6, 2.0, 2e5
    desc, q0 = mbp.chain(3, length, rod(m, length), [-0.4, 0.3, -0.2], start=(0.0, 0.5), pinned=False)
    weight = weights_of(desc)
    y0 = desc.initial_state(q0, [1.0, -1.0, 2.0, -1.0, 0.5])
    res = run(desc, y0, 1.5, extra(segment_half=length / 2, segment_k=k), weight=weight, rtol=1e-11)
    assert res.status_name == "time_limit"
    d = desc.arrays()
    nd = desc.n_dof
    energy, foundation = [], []
    for y in res.states:
        pos, _ = mb.body_states(y[:nd], y[nd:], d)
        ef = sum(sc.segment_foundation_energy(pos[i, 1], pos[i, 2], length / 2, 0.0, k) for i in range(3))
        foundation.append(ef)
        energy.append(mb.kinetic_energy(y[:nd], y[nd:], d) + weight @ pos[:, 1] + ef)
    energy = np.array(energy)
    scale = mb.kinetic_energy(y0[:nd], y0[nd:], d) + weight.sum() * 0.5
    assert max(foundation) > 0.1 * scale  # it hit the seabed hard
    assert np.abs(energy - energy[0]).max() < 1e-6 * scale


# --- seabed-contact kernels against closed-form integrals -------------------------------------------
def test_segment_contact_closed_forms():
    k, c, mu, v_reg = 2e5, 0.0, 0.5, 1e-6
    h = 0.4
    # flat segment embedded uniformly by d: F_z = k d 2h, no moment; sliding: F_x = -mu F_z
    d = 0.01
    fx, fz, my = sc.segment_contact(0.0, -d, 0.0, 1.0, 0.0, 0.0, h, 0.0, k, c, mu, v_reg)
    assert fz == pytest.approx(k * d * 2 * h, rel=1e-12)
    assert fx == pytest.approx(-mu * fz, rel=1e-9)
    assert abs(my) < 1e-12 * fz
    # tilted segment, partly embedded: d(s) = -(z + s sin th) on s in [-h, s*], a triangle load
    th, z = 0.1, -0.01
    s_star = -z / math.sin(th)
    fx, fz, my = sc.segment_contact(0.0, z, th, 0.0, 0.0, 0.0, h, 0.0, k, c, mu, v_reg)
    ln = s_star + h
    d_max = -(z - h * math.sin(th))
    assert fz == pytest.approx(k * d_max * ln / 2.0, rel=1e-12)
    # moment of the triangle about the centroid: resultant at one third of ln from the deep end
    s_res = -h + ln / 3.0
    assert my == pytest.approx(s_res * math.cos(th) * fz, rel=1e-12)
    assert fx == 0.0
    e = sc.segment_foundation_energy(z, th, h, 0.0, k)
    assert e == pytest.approx(0.5 * k * d_max**2 * ln / 3.0, rel=1e-12)
    # above the seabed: nothing
    assert sc.segment_contact(0.0, 0.1, 0.0, 1.0, 0.0, 0.0, h, 0.0, k, c, mu, v_reg) == (0.0, 0.0, 0.0)


def test_point_contact_force_and_moment():
    k, c, mu, v_reg = 1e5, 10.0, 0.3, 1e-6
    # point at body (0.5, -0.2), body rotated by th, moving
    x, z, th, vx, vz, om = 1.0, -0.1, 0.3, 0.5, -0.1, 0.2
    a, b = 0.5, -0.2
    rx = math.cos(th) * a - math.sin(th) * b
    rz = math.sin(th) * a + math.cos(th) * b
    d = -(z + rz)
    assert d > 0
    pvx, pvz = vx - om * rz, vz + om * rx
    n = k * d - c * pvz
    fx, fz, my = sc.point_contact(x, z, th, vx, vz, om, a, b, 0.0, k, c, mu, v_reg)
    assert fz == pytest.approx(n, rel=1e-14)
    assert fx == pytest.approx(-mu * n * math.copysign(1.0, pvx), rel=1e-9)
    assert my == pytest.approx(rx * fz - rz * fx, rel=1e-14)
    assert sc.point_foundation_energy(z, th, a, b, 0.0, k) == pytest.approx(0.5 * k * d * d, rel=1e-14)
    # pulled out fast: the damping would pull, but the seabed does not hold (no adhesion)
    assert sc.point_contact(x, z, th, vx, 1e4, om, a, b, 0.0, k, c, mu, v_reg) == (0.0, 0.0, 0.0)


# --- statuses -----------------------------------------------------------------------------------------
def test_numerical_failure_ends_with_finite_records():
    m, length = 1.0, 1.0
    desc, q0 = mbp.chain(1, length, rod(m, length), [-0.3])
    y0 = desc.initial_state(q0)
    for method in ("dopri5", "rk4"):
        res = run(desc, y0, 2.0, extra(t_fail=0.5), method=method, dt=1e-2, record_dt=0.1)
        assert res.status_name == "numerical_failure"
        assert np.all(np.isfinite(res.states))
        assert 0.4 <= res.t_stop <= 0.5 + 1e-9
        assert res.times[-1] <= res.t_stop


@pytest.mark.parametrize("method", ["dopri5", "rk4"])
def test_records_at_output_times_and_at_an_off_grid_end(method):
    m, length = 1.0, 1.0
    desc, q0 = mbp.chain(1, length, rod(m, length), [-0.3])
    y0 = desc.initial_state(q0, [1.0])
    res = run(desc, y0, 0.35, extra(), method=method, dt=0.02, record_dt=0.1)
    np.testing.assert_allclose(res.times, [0.0, 0.1, 0.2, 0.3, 0.35], atol=1e-15)
    assert res.t_stop == 0.35 and res.status_name == "time_limit"
    inertia = m * length**2 / 3.0

    def f(t, y):
        return [y[1], -m * G * length / 2.0 * math.cos(y[0]) / inertia]

    ref = solve_ivp(f, (0.0, 0.35), y0, t_eval=res.times, rtol=1e-12, atol=1e-12, method="DOP853")
    # rk4 at 20 ms: the records between steps come from the cubic Hermite interpolant (error ~ h^4)
    np.testing.assert_allclose(res.states, ref.y.T, atol=1e-5 if method == "rk4" else 1e-8)


def test_invalid_settings():
    desc, q0 = mbp.chain(1, 1.0, rod(1.0, 1.0), [-0.3])
    y0 = desc.initial_state(q0)
    p = (desc.arrays(), weights_of(desc), extra())
    times, states, status, _ = mb.integrate(
        PENDULUM, y0, 0.0, 1.0, p, "euler", 1e-3, 1e-8, 1e-10, 0.1, 1000, np.arange(y0.size)
    )
    assert status == mb.INVALID_INPUT and times.size == 0
    with pytest.raises(
        mbp.DescriptionError, match="method = 'euler' is not known; the methods are dopri5, rk4, ros34pw2"
    ):
        mbp.integrate(PENDULUM, y0, 0.0, 1.0, p, method="euler")
    with pytest.raises(mbp.DescriptionError, match="record_dt = -1"):
        mbp.integrate(PENDULUM, y0, 0.0, 1.0, p, record_dt=-1.0)
    with pytest.raises(mbp.DescriptionError, match="t_end"):
        mbp.integrate(PENDULUM, y0, 1.0, 1.0, p)


def test_step_budget_ends_in_numerical_failure():
    # a pendulum that needs ~100 steps at rtol 1e-10: a budget of 20 ends it as a numerical failure at the
    # last accepted state (never a silent run for hours), the default budget lets it finish
    desc, q0 = mbp.chain(1, 1.0, rod(1.0, 1.0), [-0.3])
    y0 = desc.initial_state(q0)
    p = (desc.arrays(), weights_of(desc), extra())
    full = mbp.integrate(PENDULUM, y0, 0.0, 1.0, p, rtol=1e-10, atol=1e-12, record_dt=0.01)
    assert full.status_name == "time_limit"
    short = mbp.integrate(PENDULUM, y0, 0.0, 1.0, p, rtol=1e-10, atol=1e-12, record_dt=0.01, max_steps=20)
    assert short.status_name == "numerical_failure"
    assert 0.0 < short.t_stop < 1.0 and np.all(np.isfinite(short.states))
    # the records it kept are those of the full run
    n = short.times.size
    np.testing.assert_allclose(short.states, full.states[:n], rtol=0, atol=1e-12)
    with pytest.raises(mbp.DescriptionError, match="max_steps = 0 must be an integer >= 1"):
        mbp.integrate(PENDULUM, y0, 0.0, 1.0, p, max_steps=0)


def test_records_that_do_not_fit_in_memory_are_refused():
    desc, q0 = mbp.chain(1, 1.0, rod(1.0, 1.0), [-0.3])
    y0 = desc.initial_state(q0)
    p = (desc.arrays(), weights_of(desc), extra())
    # 1e5 s every 1e-9 s: 1e14 records of 2 values, 1.6e15 bytes
    with pytest.raises(
        mbp.DescriptionError, match=r"record_dt = 1e-09 s \(1e\+14 states over 100000 s\) would need about"
    ):
        mbp.integrate(PENDULUM, y0, 0.0, 1e5, p, record_dt=1e-9)


# --- bad descriptions ---------------------------------------------------------------------------------
GOOD = dict(
    parent=[-1, 0],
    joint_on_parent=[[0, 0], [0.5, 0]],
    joint_on_body=[[0, 0], [-0.5, 0]],
    mass_matrix=[np.diag([1.0, 1.0, 0.1])] * 2,
    root_free=[1, 1, 1],
    root_pose=[0, 0, 0],
)


@pytest.mark.parametrize(
    "field, value, message",
    [
        ("parent", [0, 0], r"parent\[0\] = 0: body 0 is the root"),
        ("parent", [-1, 1], r"parent\[1\] = 1 is out of order"),
        ("joint_on_parent", [[0, 0], [np.nan, 0]], r"joint_on_parent\[1, 0\] = nan is not finite"),
        ("joint_on_body", [[0, 0]], r"joint_on_body must have shape \(2, 2\)"),
        (
            "mass_matrix",
            [np.diag([1.0, 1.0, 0.1]), np.diag([-1.0, 1.0, 0.1])],
            r"mass_matrix\[1\]\[0\]\[0\] = -1",
        ),
        (
            "mass_matrix",
            [np.diag([1.0, 1.0, 0.1]), np.diag([1.0, 1.0, np.inf])],
            r"mass_matrix\[1, 2, 2\] = inf",
        ),
        ("mass_matrix", [np.diag([1.0, 1.0, 0.1]), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]], "must be symmetric"),
        ("mass_matrix", [np.diag([1.0, 1.0, 0.1]), np.zeros((3, 3))], "generalised mass matrix is singular"),
        ("root_free", [1, 2, 0], "root_free must be three flags 0 or 1"),
        ("root_pose", [0, 0], r"root_pose must have shape \(3,\)"),
    ],
)
def test_bad_description_names_the_field(field, value, message):
    kw = dict(GOOD, **{field: value})
    with pytest.raises(mbp.DescriptionError, match=message):
        mbp.Description(**kw)


def test_builder_helpers_reject_bad_values():
    with pytest.raises(mbp.DescriptionError, match="mass = -1.0 must be finite and >= 0"):
        mbp.segment_mass_matrix(-1.0, 1.0)
    with pytest.raises(mbp.DescriptionError, match="n_links = 0 must be an integer >= 1"):
        mbp.chain(0, 1.0, rod(1.0, 1.0), [0.0])
    with pytest.raises(mbp.DescriptionError, match="angles must give one angle per link"):
        mbp.chain(3, 1.0, rod(1.0, 1.0), [0.0, 1.0])
    with pytest.raises(mbp.DescriptionError, match=r"link_length\[1\] = -0.5 m must be finite and > 0"):
        mbp.chain(2, [1.0, -0.5], rod(1.0, 1.0), [0.0, 1.0])
    # links of different lengths laid out end to end: the far pin of the last link
    desc, q0 = mbp.chain(3, [1.0, 0.5, 2.0], rod(1.0, 1.0), [0.0, -math.pi / 2, math.pi], start=(1.0, 2.0))
    pos, _ = mb.body_states(q0, np.zeros(desc.n_dof), desc.arrays())
    np.testing.assert_allclose(pos[3, :2] + [-1.0, 0.0], [0.0, 1.5], atol=1e-14)
    free, qf = mbp.chain(2, [1.0, 0.5], rod(1.0, 1.0), [0.0, 0.0], start=(1.0, 2.0), pinned=False)
    np.testing.assert_allclose(mb.body_states(qf, np.zeros(free.n_dof), free.arrays())[0][:, 0], [1.5, 2.25])
    # the segment's added mass acts on the normal only (seed 004 eq. (46))
    mm = mbp.segment_mass_matrix(2.0, 0.5, radius=0.1, added_mass_coefficient=1.0, water_density=1000.0)
    ma = 1000.0 * math.pi * 0.01 * 0.5
    np.testing.assert_allclose(np.diag(mm), [2.0, 2.0 + ma, (2.0 + ma) * 0.25 / 12.0])
