"""The integrator protocol (dopri5 with error control, continuous extension, events) and the
end of a drop, against closed forms and the fixed-step RK4 reference.

References: the exponential and the harmonic oscillator (closed forms), ballistic flight in
vacuum (closed-form interface crossing times), RK4 at small dt on a full drop, Archimedes
for a mine lighter than the water.
"""

import math

import numpy as np
import pytest
from conftest import make_scenario
from scipy.integrate import quad

from mineburial.kernels import integrators as it
from mineburial.kernels.mine import layout, status
from mineburial.systems.mine.drop import run_params, simulate_drop

G = 9.81


# ---------------------------------------------------------------------------
# the generic pieces, driven from Python on closed-form problems
# ---------------------------------------------------------------------------
def _oscillator(y, dy):
    dy[0] = y[1]
    dy[1] = -y[0]


def _dopri_step(f, y, h):
    k = np.zeros((it.N_STAGES, y.size))
    f(y, k[0])
    tmp = np.empty_like(y)
    for s in range(1, it.N_STAGES):
        it.dopri_stage_state(y, k, s, h, tmp)
        f(tmp, k[s])
    out = np.empty_like(y)
    err = np.empty_like(y)
    it.dopri_solution(y, k, h, out, err)
    r = np.empty((5, y.size))
    it.dopri_dense(y, out, k, h, r)
    return out, err, r


def test_dopri_local_error_is_fifth_order_and_estimate_fourth():
    """On the harmonic oscillator the local error of the 5th-order solution falls as h^6
    and the embedded estimate as h^5 (Dormand & Prince 1980)."""
    y0 = np.array([1.0, 0.0])
    errs, ests = [], []
    hs = (0.2, 0.1, 0.05)
    for h in hs:
        out, err, _ = _dopri_step(_oscillator, y0, h)
        exact = np.array([math.cos(h), -math.sin(h)])
        errs.append(np.linalg.norm(out - exact))
        ests.append(np.linalg.norm(err))
    order_sol = math.log2(errs[1] / errs[2])
    order_est = math.log2(ests[1] / ests[2])
    assert 5.5 < order_sol < 6.6, order_sol
    assert 4.6 < order_est < 5.5, order_est


def test_dense_output_is_fourth_order_inside_the_step():
    """The continuous extension at theta = 0.3 and 0.7: error O(h^5) against cos, -sin."""
    y0 = np.array([1.0, 0.0])
    errs = []
    for h in (0.2, 0.1):
        _, _, r = _dopri_step(_oscillator, y0, h)
        e = 0.0
        for th in (0.3, 0.7):
            y = np.empty(2)
            it.dense_state(r, th, y)
            e = max(e, abs(y[0] - math.cos(th * h)) + abs(y[1] + math.sin(th * h)))
        errs.append(e)
    assert 4.4 < math.log2(errs[0] / errs[1]) < 6.5
    # the ends are exact
    out, _, r = _dopri_step(_oscillator, y0, 0.1)
    y = np.empty(2)
    it.dense_state(r, 1.0, y)
    np.testing.assert_allclose(y, out, rtol=0, atol=1e-15)
    it.dense_state(r, 0.0, y)
    np.testing.assert_allclose(y, y0, rtol=0, atol=1e-15)


def _integrate(rtol, t_end=10.0):
    """dopri5 with the PI controller on the oscillator; returns (global error, steps)."""
    y = np.array([1.0, 0.0])
    t, h, err_prev, ok_before, n = 0.0, 0.01, 1e-4, True, 0
    while t < t_end - 1e-12:
        h = min(h, t_end - t)
        out, err, _ = _dopri_step(_oscillator, y, h)
        e = it.error_norm(y, out, err, ((0, 1), (1, 2)), rtol, rtol * 1e-3)
        h_next, accept, err_prev = it.next_step_size(h, e, err_prev, ok_before)
        ok_before = accept
        if accept:
            y, t, n = out, t + h, n + 1
        h = h_next
    return abs(y[0] - math.cos(t_end)) + abs(y[1] + math.sin(t_end)), n


def test_step_size_controller_follows_the_tolerance():
    """Global error tracks rtol (within a factor ~30 either way) and the number of steps
    grows like rtol^(-1/5)."""
    e5, n5 = _integrate(1e-5)
    e8, n8 = _integrate(1e-8)
    assert 1e-7 < e5 < 1e-3 and 1e-10 < e8 < 1e-6, (e5, e8)
    assert e8 < e5 / 50
    ratio = n8 / n5
    assert 2.5 < ratio < 6.0, (n5, n8)  # 10^(3/5) = 3.98


# ---------------------------------------------------------------------------
# ROS34PW2 (Rosenbrock-W), driven from Python on closed-form problems
# ---------------------------------------------------------------------------
def _ros_step(f, y, h, jac, cols):
    """One ROS34PW2 step with the Jacobian columns ``jac`` (n x len(cols)) of ``cols``."""
    n = y.size
    m = cols.size
    c = h * it.ROS_GAMMA_DIAG
    wa = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    assert it.w_factor(jac, cols, c, wa, piv)
    kr = np.zeros((it.ROS_STAGES, n))
    ys, fy, z = np.empty(n), np.empty(n), np.empty(m)
    for s in range(it.ROS_STAGES):
        it.ros_stage_state(y, kr, s, ys)
        f(ys, fy)
        it.ros_coupling(kr, s, cols, z)
        it.j_times(jac, z, kr[s])
        kr[s] = h * (fy + kr[s])
        it.w_solve(jac, cols, c, wa, piv, kr[s], z)
    out, err = np.empty(n), np.empty(n)
    it.ros_solution(y, kr, out, err)
    return out, err


def _oscillator_jacobian(scale):
    return scale * np.array([[0.0, 1.0], [-1.0, 0.0]])


@pytest.mark.parametrize("scale", [1.0, 0.0, 3.0])
def test_rosenbrock_w_is_third_order_whatever_the_jacobian(scale):
    """ROS34PW2 on the harmonic oscillator: the local error falls as h^4 (order 3) with the
    exact Jacobian, with none (J = 0) and with a wrong one (3 J): the W-method property of
    Rang & Angermann (2005) that lets the stepper reuse a Jacobian over many steps; the
    embedded estimate falls as h^3."""
    y0 = np.array([1.0, 0.0])
    cols = np.array([0, 1], dtype=np.int64)
    jac = _oscillator_jacobian(scale)
    errs, ests = [], []
    for h in (0.1, 0.05, 0.025):
        out, err = _ros_step(_oscillator, y0, h, jac, cols)
        errs.append(np.linalg.norm(out - [math.cos(h), -math.sin(h)]))
        ests.append(np.linalg.norm(err))
    order_sol = math.log2(errs[1] / errs[2])
    order_est = math.log2(ests[1] / ests[2])
    assert 3.6 < order_sol < 4.6, order_sol
    assert 2.6 < order_est < 3.5, order_est


def test_rosenbrock_w_step_solves_a_stiff_relaxation_in_one_step():
    """y' = -k (y - cos t) as an autonomous pair (y, t) with k = 1e6 and one step of
    h = 0.1 (h k = 1e5, far outside any explicit method's stability region): the method is
    L-stable and stiffly accurate, so y lands on the slow manifold y ~ cos t + sin(t)/k,
    with the Jacobian of the stiff column only (columns = [0])."""
    k = 1e6

    def f(y, dy):
        dy[0] = -k * (y[0] - math.cos(y[1]))
        dy[1] = 1.0

    y0 = np.array([5.0, 0.0])  # far from the slow manifold
    jac = np.array([[-k], [0.0]])
    h = 0.1
    out, _ = _ros_step(f, y0, h, jac, np.array([0], dtype=np.int64))
    assert out[1] == pytest.approx(h, abs=1e-15)
    assert out[0] == pytest.approx(math.cos(h) + math.sin(h) / k, abs=2e-4)


def test_reduced_w_solve_matches_the_dense_solve():
    """W x = b solved through the len(cols) x len(cols) system equals numpy's dense solve of
    (I - c J) x = b with J zero outside the columns."""
    rng = np.random.default_rng(3)
    n, cols = 9, np.array([1, 4, 5, 8], dtype=np.int64)
    jc = rng.normal(size=(n, cols.size))
    full = np.zeros((n, n))
    full[:, cols] = jc
    c = 0.37
    b = rng.normal(size=n)
    wa, piv, z = np.empty((4, 4)), np.empty(4, dtype=np.int64), np.empty(4)
    assert it.w_factor(jc, cols, c, wa, piv)
    x = b.copy()
    it.w_solve(jc, cols, c, wa, piv, x, z)
    np.testing.assert_allclose(x, np.linalg.solve(np.eye(n) - c * full, b), rtol=1e-12, atol=1e-12)
    v = rng.normal(size=n)
    out = np.empty(n)
    it.j_times(jc, v[cols], out)
    np.testing.assert_allclose(out, full @ v, rtol=1e-13, atol=1e-13)
    # the coupling's entries in the columns: (sum_j GAMMA[s, j] k_j)[cols], against numpy
    kr = rng.normal(size=(it.ROS_STAGES, n))
    for s in range(it.ROS_STAGES):
        it.ros_coupling(kr, s, cols, z)
        np.testing.assert_allclose(z, (it.ROS_GAMMA[s, :s] @ kr[:s])[cols], rtol=1e-13, atol=1e-13)


def test_illinois_finds_a_root():
    def f(x):
        return math.cos(x) - x  # root 0.7390851332151607

    a, b = 0.0, 1.0
    ga, gb, side = f(a), f(b), 0
    for _ in range(60):
        if b - a < 1e-14:
            break
        t = it.illinois_next(a, ga, b, gb)
        a, ga, b, gb, side = it.illinois_update(a, ga, b, gb, t, f(t), side)
    assert abs(0.5 * (a + b) - 0.7390851332151607) < 1e-12


# ---------------------------------------------------------------------------
# events on the continuous extension of a full drop
# ---------------------------------------------------------------------------
def _vacuum(**over):
    """Ballistic flight: no air, no water (both densities 0), drag off."""
    base = dict(
        mine={"mass": 80.0, "com_offset": 0.0},
        environment={"water_depth": 20.0, "water_density": 0.0, "air_density": 0.0, "gravity": G},
        release={"position": [0.0, 0.0, 10.0], "pitch_deg": 0.0},
        numerics={"t_max": 3.0, "drag": False, "rtol": 1e-6, "atol": 1e-8},
    )
    for k, v in over.items():
        base[k] = {**base[k], **v}
    return make_scenario(**base)


@pytest.mark.parametrize("integrator", ["dopri5", "rk4"])
def test_interface_events_are_located_on_the_interpolant(integrator):
    """A horizontal cylinder (R = 0.125 m) falling from rest at z = 10 m in vacuum: its
    lowest point reaches the water surface at t = sqrt(2 (10 - R) / g) and the seabed
    (z = -20) at t = sqrt(2 (30 - R) / g), to the event tolerance, whatever the steps."""
    sc = _vacuum(numerics={"integrator": integrator, "dt": 7e-3})
    p, sb, cb = sc.to_params()
    _, s, _ = run_params(p, sb, cb)
    R = 0.125
    assert abs(s[layout.S_ENTRY_TIME] - math.sqrt(2 * (10 - R) / G)) < 1e-9
    assert abs(s[layout.S_IMPACT_TIME] - math.sqrt(2 * (30 - R) / G)) < 1e-9
    # the speed at the cut comes from the continuous extension (cubic Hermite for RK4)
    assert abs(s[layout.S_IMPACT_SPEED] - math.sqrt(2 * G * (30 - R))) < 1e-4


def test_recorder_samples_exact_output_times():
    """Rows at exact multiples of the interval, on the ballistic parabola."""
    ds = simulate_drop(_vacuum(numerics={"t_max_fall": 1.0}), record_interval=0.1)
    t = ds.time.values
    np.testing.assert_allclose(t[:11], np.arange(11) * 0.1, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ds.z.values[:11], 10.0 - 0.5 * G * t[:11] ** 2, rtol=0, atol=1e-9)


def test_trajectory_of_a_drop_longer_than_its_first_buffer_reaches_its_end():
    """A ballistic fall of 2.4 s with t_max = 0.5 s after the seabed contact: the first
    trajectory buffer (t_max) is too short, the drop is run again with one that reaches its
    end; the rows keep the parabola and the summary is that of the run without a recorder."""
    sc = _vacuum(numerics={"t_max_fall": 60.0, "t_max": 0.5})
    p, sb, cb = sc.to_params()
    code, summary, _ = run_params(p, sb, cb)
    ds = simulate_drop(sc, record_interval=0.1)
    t = ds.time.values
    end = float(ds.total_time)
    R = 0.125  # radius of the horizontal cylinder: its lowest line touches the seabed
    assert float(ds.impact_time) == pytest.approx(math.sqrt(2 * (30 - R) / G), abs=1e-9)
    assert end > 0.5  # the fall alone outlasts the first buffer
    assert t[-1] == end and len(t) == math.floor(end / 0.1) + 2
    np.testing.assert_allclose(t[:-1], np.arange(len(t) - 1) * 0.1, rtol=0, atol=1e-12)
    falling = t < math.sqrt(2 * (30 - R) / G)
    np.testing.assert_allclose(ds.z.values[falling], 10.0 - 0.5 * G * t[falling] ** 2, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(
        [float(ds[name]) for name in ("total_time", "penetration_depth", "impact_time")],
        [summary[layout.S_TOTAL_TIME], summary[layout.S_PENETRATION], summary[layout.S_IMPACT_TIME]],
    )
    assert int(ds.status) == code


# ---------------------------------------------------------------------------
# a full drop: dopri5 + fast rule against RK4 at small dt + reference quadrature
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("integrator", ["dopri5_ros34pw2", "dopri5", "ros34pw2"])
def test_default_path_matches_rk4_reference_on_the_default_mine(integrator):
    """The default path (dopri5 in air and water, the Rosenbrock-W step in the sediment, fast
    rule), dopri5 throughout and the Rosenbrock-W step throughout (the core's method the mine
    offers since both drivers step with core.attempt_step), all at the default tolerances, against
    RK4 at 0.25 ms with the reference quadrature."""
    from mineburial.systems.mine.config import Scenario, load_example

    d = load_example("default_mine").to_dict()
    d["numerics"] = dict(d["numerics"], integrator=integrator, sediment_quadrature="fast")
    fast = Scenario.from_dict(d)
    d["numerics"] = dict(d["numerics"], integrator="rk4", dt=2.5e-4, sediment_quadrature="reference")
    ref = Scenario.from_dict(d)
    out = []
    for sc in (fast, ref):
        p, sb, cb = sc.to_params()
        code, s, _ = run_params(p, sb, cb)
        assert code == status.AT_REST
        out.append(s)
    a, b = out
    assert abs(a[layout.S_IMPACT_TIME] - b[layout.S_IMPACT_TIME]) < 2e-3
    assert abs(a[layout.S_PENETRATION] - b[layout.S_PENETRATION]) < 0.01 * b[layout.S_PENETRATION]
    assert a[layout.S_N_STEPS] < b[layout.S_N_STEPS] / 10


# ---------------------------------------------------------------------------
# the end of a drop
# ---------------------------------------------------------------------------
def test_mine_lighter_than_water_floats_and_ends():
    """mass 40 kg < rho_w V = 50.3 kg: it enters, turns round, and ends 'floated' long
    before the time limit, without touching the seabed."""
    sc = make_scenario(
        mine={"mass": 40.0},
        release={"position": [0.0, 0.0, 1.0]},
        environment={"water_depth": 50.0},
        numerics={"t_max_fall": 60.0},
    )
    p, sb, cb = sc.to_params()
    code, s, _ = run_params(p, sb, cb)
    assert code == status.FLOATED
    assert s[layout.S_TOTAL_TIME] < 5.0
    assert np.isnan(s[layout.S_IMPACT_TIME])


def test_mine_in_sediment_that_cannot_hold_it_is_buried_sinking():
    """A zero-strength sediment lighter than the mine (1100 kg/m3 against 1630): it sinks
    without limit, fully buried at the time limit; reported as such, 100 % buried."""
    from conftest import scenario_dict

    from mineburial.systems.mine.config import Scenario

    d = scenario_dict(
        environment={"water_depth": 3.0},
        release={"position": [0.0, 0.0, -2.0], "pitch_deg": 90.0},
        numerics={"t_max": 6.0},
    )
    d["sediment"] = {"density": 1100.0, "density_gradient": 0.0, "strength": 0.0, "strength_gradient": 0.0}
    sc = Scenario.from_dict(d)
    p, sb, cb = sc.to_params()
    code, s, _ = run_params(p, sb, cb)
    assert code == status.BURIED_SINKING
    assert s[layout.S_BURIAL_VOLUME] == pytest.approx(100.0)


def test_mine_placed_on_a_bottom_that_holds_it_stops_at_once():
    """A horizontal mine released at rest with its lower half in a stiff clay (rigid-plastic
    bearing capacity far above its submerged weight): at rest within the first steps,
    within 5 mm of where it was put (the regularised switch mobilises the resistance over
    a few mm of settlement)."""
    sc = make_scenario(
        environment={"water_depth": 10.0},
        release={"position": [0.0, 0.0, -10.0 + 0.06], "pitch_deg": 0.0, "embedded": True},
        sediment={"class": "stiff_clay"},
        numerics={"t_max": 10.0},
    )
    p, sb, cb = sc.to_params()
    code, s, _ = run_params(p, sb, cb)
    assert code == status.AT_REST
    assert s[layout.S_TOTAL_TIME] < 0.05
    assert abs(s[layout.S_COM_DEPTH] - (-0.06)) < 5e-3


def _toppling_time(m, g_eff, r_c, inertia_com, psi0, psi1, pivot_fixed):
    """Time for a rigid body toppling about a contact point on a flat bottom, released at rest
    with its centre of mass psi0 past the vertical through the contact, to reach psi1.

    Energy: (1/2) I(psi) psi'^2 = m g r_c (cos psi0 - cos psi), with I = I_c + m r_c^2 for
    a contact that does not move (rigid pivot) and I = I_c + m r_c^2 sin^2 psi for one that
    slides without friction (the centre of mass then falls vertically; Goldstein-style
    ladder problem). Integrated by quadrature with psi = psi0 + s^2, which removes the
    inverse-square-root singularity at the start."""

    def integrand(s):
        psi = psi0 + s * s
        inertia = inertia_com + m * r_c * r_c * (1.0 if pivot_fixed else math.sin(psi) ** 2)
        k = 2.0 * m * g_eff * r_c / inertia
        if s == 0.0:
            return 2.0 / math.sqrt(k * math.sin(psi0))
        return 2.0 * s / math.sqrt(k * (math.cos(psi0) - math.cos(psi)))

    t, _ = quad(integrand, 0.0, math.sqrt(psi1 - psi0), epsabs=1e-12, epsrel=1e-10)
    return t


def test_mine_that_cannot_be_held_topples_in_the_rigid_pivot_time():
    """A dense cylinder stood on its end on a stiff clay, tilted 5 deg past the point where
    its centre of mass is over the edge of its lower rim: the rigid-plastic bottom cannot
    hold it (the toppling mechanism of kernels/mine/rest.py), so it must topple about the rim.
    References: the closed-form energy integrals of a body toppling under its submerged
    weight about a rigid pivot and about a contact sliding without friction (the rim on
    the clay lies between the two). The water's added inertia and drag only slow the
    fall, a little for a steel body (water/body density 0.13): the model must take at
    least the frictionless-sliding time and not much more than the rigid-pivot time."""
    L, D = 1.0, 0.2
    R = D / 2
    rho_steel = 7800.0
    volume = math.pi * R * R * L
    m = rho_steel * volume
    depth = 10.0
    alpha = math.atan2(R, L / 2)  # axis tilt with the COM over the rim
    phi0 = alpha + math.radians(5.0)  # axis tilt from the vertical at release
    phi1 = math.radians(70.0)  # measured up to here (before the side lands)
    z_c = -depth + (L / 2) * math.cos(phi0) + R * math.sin(phi0) - 0.002  # rim 2 mm in
    sc = make_scenario(
        mine={"length": L, "diameter": D, "mass": m},
        environment={"water_depth": depth},
        release={"position": [0.0, 0.0, z_c], "pitch_deg": 90.0 - math.degrees(phi0), "embedded": True},
        sediment={"class": "stiff_clay"},
        numerics={"t_max": 5.0, "sediment_quadrature": "fast"},
    )
    ds = simulate_drop(sc, record_interval=0.002)
    tilt = 90.0 - np.abs(ds.psi2.values)  # axis tilt from the vertical, degrees
    assert tilt[0] == pytest.approx(math.degrees(phi0), abs=1e-6)
    reached = np.flatnonzero(tilt >= math.degrees(phi1))
    assert reached.size, f"did not topple: largest tilt {tilt.max():.1f} deg"
    t_model = float(ds.time[reached[0]])
    rho_w = sc.environment.water_density
    g = sc.environment.gravity
    r_c = math.hypot(L / 2, R)
    g_eff = g * (1.0 - rho_w * volume / m)
    times = [
        _toppling_time(m, g_eff, r_c, sc.mine.inertia_transverse, phi0 - alpha, phi1 - alpha, pivot_fixed)
        for pivot_fixed in (False, True)
    ]
    t_slide, t_pivot = times
    assert t_slide < t_pivot
    assert t_slide <= t_model <= 1.3 * t_pivot, (t_model, t_slide, t_pivot)
    assert ds.attrs["status"] == "at_rest"
