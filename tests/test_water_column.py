"""Per-drop stepper in air and water against closed forms and conservation laws."""

import math

import numpy as np
import pytest
from conftest import make_scenario as _make_scenario
from scipy.spatial.transform import Rotation

from mineburial.kernels.mine import layout
from mineburial.systems.mine.drop import run_params, simulate_drop
from mineburial.validation.references import terminal_velocity_axial, terminal_velocity_broadside


def make_scenario(**sections):
    """The test scenario with dopri5 at tolerances far below these closed-form checks'."""
    numerics = {"rtol": 1e-10, "atol": 1e-12, **sections.pop("numerics", {})}
    return _make_scenario(numerics=numerics, **sections)


G = 9.81


def _body_rotation(row_q):
    """Rotation body->earth from a (q0, q1, q2, q3) quaternion, via scipy (scalar last)."""
    q0, q1, q2, q3 = row_q
    return Rotation.from_quat([q1, q2, q3, q0]).as_matrix()


# ---------------------------------------------------------------------------
# terminal velocity: closed form built from the same drag coefficient laws
# ---------------------------------------------------------------------------
RHO = 1025.0
L = 1.0
D = 0.25
VOL = math.pi * (D / 2) ** 2 * L
MASS = 52.0  # slightly heavier than the displaced water (50.3 kg)


def test_terminal_velocity_broadside():
    # seed 000 eq. (44), branch 12 000 < Re <= 150 000 (checked by the reference)
    v_t = terminal_velocity_broadside(MASS, L, D, RHO, G, 1.0e-6)
    sc = make_scenario(
        mine={"mass": MASS},
        environment={"gravity": G},
        release={"position": [0, 0, -5.0], "pitch_deg": 0.0},
        numerics={"t_max_fall": 40.0, "dt": 5e-3},
    )
    ds = simulate_drop(sc)
    w_end = -float(ds.w[-1])
    assert abs(w_end - v_t) / v_t < 0.005
    # it stayed broadside
    assert abs(float(ds.psi2[-1])) < 1e-6


def test_terminal_velocity_axial():
    v_t = terminal_velocity_axial(MASS, L, D, RHO, G)  # seed 000 eq. (40)
    sc = make_scenario(
        mine={"mass": MASS},
        environment={"gravity": G},
        release={"position": [0, 0, -5.0], "pitch_deg": 90.0},
        numerics={"t_max_fall": 40.0, "dt": 5e-3},
    )
    ds = simulate_drop(sc)
    w_end = -float(ds.w[-1])
    assert abs(w_end - v_t) / v_t < 0.005
    assert abs(float(ds.psi2[-1]) - 90.0) < 1e-6


# ---------------------------------------------------------------------------
# ballistic limit and neutral buoyancy
# ---------------------------------------------------------------------------
def test_ballistic_without_fluids():
    v0 = np.array([3.0, -2.0, 5.0])
    om0 = np.array([4.0, 0.7, -1.1])
    sc = make_scenario(
        environment={"air_density": 0.0, "water_density": 0.0, "gravity": G},
        release={
            "position": [1.0, 2.0, 0.5],
            "velocity": list(v0),
            "pitch_deg": 20.0,
            "heading_deg": 30.0,
            "angular_velocity": list(om0),
        },
        numerics={"t_max_fall": 2.0, "dt": 1e-3},
    )
    ds = simulate_drop(sc, record_interval=0.1)
    t = ds.time.values
    np.testing.assert_allclose(ds.x, 1.0 + v0[0] * t, rtol=0, atol=1e-10)
    np.testing.assert_allclose(ds.y, 2.0 + v0[1] * t, rtol=0, atol=1e-10)
    np.testing.assert_allclose(ds.z, 0.5 + v0[2] * t - 0.5 * G * t**2, rtol=0, atol=1e-10)
    # torque-free symmetric top: omega1 constant, (omega2, omega3) precess at
    # lambda = (J1 - J2) omega1 / J2 (Euler's equations)
    m = 80.0
    r = D / 2
    j1 = 0.5 * m * r * r
    j2 = m * (3 * r * r + L * L) / 12.0
    lam = (j1 - j2) * om0[0] / j2
    np.testing.assert_allclose(ds.omega1, om0[0], atol=1e-10)
    np.testing.assert_allclose(ds.omega2, om0[1] * np.cos(lam * t) - om0[2] * np.sin(lam * t), atol=1e-8)
    np.testing.assert_allclose(ds.omega3, om0[1] * np.sin(lam * t) + om0[2] * np.cos(lam * t), atol=1e-8)
    # angular momentum is conserved in the earth frame
    h = []
    for k in range(len(t)):
        rot = _body_rotation([float(ds[c][k]) for c in ("q0", "q1", "q2", "q3")])
        om = np.array([float(ds[c][k]) for c in ("omega1", "omega2", "omega3")])
        h.append(rot @ (np.array([j1, j2, j2]) * om))
    h = np.array(h)
    np.testing.assert_allclose(h, np.broadcast_to(h[0], h.shape), atol=1e-9)


def test_neutrally_buoyant_at_rest_stays_at_rest():
    sc = make_scenario(
        mine={"mass": RHO * VOL},
        release={"position": [0, 0, -20.0], "pitch_deg": 30.0},
        numerics={"t_max_fall": 5.0},
    )
    ds = simulate_drop(sc)
    for c in ("u", "v", "w", "omega1", "omega2", "omega3"):
        assert np.max(np.abs(ds[c].values)) < 1e-12, c
    assert np.max(np.abs(ds.z.values + 20.0)) < 1e-12


# ---------------------------------------------------------------------------
# invariance under a rotation of the whole drop about the vertical
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("integrator, tol", [("rk4", 1e-9), ("dopri5", 1e-7)])
def test_rotation_about_vertical_rotates_trajectory(integrator, tol):
    """Fixed RK4 (the steps are the same): to rounding; dopri5 (its step sizes follow a
    rotation-invariant error norm, but rounding in the rotated coordinates perturbs the
    controller's decisions): to 1e-7 m, far below its tolerance."""
    alpha = math.radians(40.0)
    v0 = np.array([1.0, 0.5, -2.0])
    rot = np.array([[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]])
    pos = np.array([0.3, -0.2])
    # air, water entry and the water column (the seabed at 1000 m is not reached); 3 s: at the
    # test's tight tolerance dopri5 needs 800 000 steps between 3 s and 6 s (the drag law's
    # jumps at its Reynolds-number breakpoints), 280 before
    common = dict(mine={"com_offset": 0.05}, numerics={"t_max_fall": 3.0, "integrator": integrator})
    a = make_scenario(
        release={
            "position": [pos[0], pos[1], 2.0],
            "velocity": list(v0),
            "pitch_deg": 30.0,
            "heading_deg": 10.0,
            "angular_velocity": [0.3, 0.5, -0.2],
        },
        **common,
    )
    pb = rot @ pos
    vb = rot @ v0[:2]
    b = make_scenario(
        release={
            "position": [pb[0], pb[1], 2.0],
            "velocity": [vb[0], vb[1], v0[2]],
            "pitch_deg": 30.0,
            "heading_deg": 50.0,
            "angular_velocity": [0.3, 0.5, -0.2],
        },
        **common,
    )
    da = simulate_drop(a, record_interval=0.01)
    db = simulate_drop(b, record_interval=0.01)
    n = min(da.sizes["time"], db.sizes["time"])
    np.testing.assert_allclose(db.z[:n], da.z[:n], rtol=0, atol=tol)
    xy = rot @ np.vstack([da.x[:n], da.y[:n]])
    np.testing.assert_allclose(db.x[:n], xy[0], rtol=0, atol=tol)
    np.testing.assert_allclose(db.y[:n], xy[1], rtol=0, atol=tol)
    np.testing.assert_allclose(db.psi2[:n], da.psi2[:n], rtol=0, atol=100 * tol)
    dpsi3 = (db.psi3.values[:n] - da.psi3.values[:n] - 40.0 + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(dpsi3, 0.0, rtol=0, atol=100 * tol)


# ---------------------------------------------------------------------------
# convergence order of both integrators
# ---------------------------------------------------------------------------
def _final_state(sc, dt, integrator):
    p, sb, cb = sc.to_params()
    p = p.copy()
    p[layout.P_DT] = dt
    p[layout.P_INTEGRATOR] = layout.INTEGRATOR_NAMES.index(integrator)
    code, summary, traj = run_params(p, sb, cb, record_interval=1e9)
    return traj[-1, 1:14]


@pytest.fixture(scope="module")
def submerged_rotating():
    return make_scenario(
        mine={"mass": 60.0, "com_offset": 0.04},
        release={
            "position": [0, 0, -20.0],
            "velocity": [0.3, 0.0, -0.3],
            "pitch_deg": 30.0,
            "angular_velocity": [0.2, 0.5, 0.1],
        },
        numerics={"t_max_fall": 1.0},
    )


def _observed_orders(sc, dts, integrator, reference):
    errs = [np.max(np.abs(_final_state(sc, dt, integrator) - reference)) for dt in dts]
    return [math.log2(errs[k] / errs[k + 1]) for k in range(len(errs) - 1)], errs


def test_rk4_converges_at_fourth_order(submerged_rotating):
    ref = _final_state(submerged_rotating, 1e-3, "rk4")
    orders, errs = _observed_orders(submerged_rotating, [0.04, 0.02, 0.01], "rk4", ref)
    assert all(3.5 < o < 4.6 for o in orders), (orders, errs)


def test_local_linearisation_converges_at_first_order(submerged_rotating):
    ref = _final_state(submerged_rotating, 1e-3, "rk4")
    orders, errs = _observed_orders(submerged_rotating, [0.004, 0.002, 0.001], "local_linear", ref)
    assert all(0.8 < o < 1.3 for o in orders), (orders, errs)


# ---------------------------------------------------------------------------
# energy conservation with drag and lift off (buoyancy and added mass only)
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("munk", [0.0, 0.5, 1.0])
def test_mechanical_energy_conserved_without_drag(munk):
    m, chi = 60.0, 0.05
    sc = make_scenario(
        mine={"mass": m, "com_offset": chi},
        environment={"gravity": G},
        release={
            "position": [0, 0, -50.0],
            "velocity": [0.4, -0.2, 0.3],
            "pitch_deg": 30.0,
            "angular_velocity": [0.5, 1.0, -0.7],
        },
        numerics={"t_max_fall": 2.0, "drag": False, "dt": 1e-3, "munk_factor": munk},
    )
    ds = simulate_drop(sc, record_interval=0.05)
    r = D / 2
    j1 = 0.5 * m * r * r
    j2 = m * (3 * r * r + L * L) / 12.0
    # strip-theory added mass per unit length (seed 001 eqs. (20)-(21)), over the
    # body's axial interval [-L/2 - chi, L/2 - chi]
    a = RHO * math.pi * r * r
    i0, i1, i2 = L, -chi * L, L**3 / 12.0 + chi**2 * L
    a_axial = (1.0 - munk) * a * i0  # axial added mass (docs/physics.md, Munk factor)
    energies = []
    for k in range(ds.sizes["time"]):
        rot = _body_rotation([float(ds[c][k]) for c in ("q0", "q1", "q2", "q3")])
        vel = np.array([float(ds[c][k]) for c in ("u", "v", "w")])
        u = rot.T @ vel
        w = np.array([float(ds[c][k]) for c in ("omega1", "omega2", "omega3")])
        kin = 0.5 * (m * u @ u + j1 * w[0] ** 2 + j2 * (w[1] ** 2 + w[2] ** 2))
        kin += 0.5 * a_axial * u[0] ** 2
        kin += (
            0.5
            * a
            * (
                i0 * (u[1] ** 2 + u[2] ** 2)
                + 2 * i1 * (u[1] * w[2] - u[2] * w[1])
                + i2 * (w[1] ** 2 + w[2] ** 2)
            )
        )
        z = float(ds.z[k])
        z_cov = z + rot[2, 0] * (-chi)  # centre of volume lies at -chi i_M
        pot = m * G * z - RHO * VOL * G * z_cov
        energies.append(kin + pot)
    energies = np.array(energies)
    scale = abs(energies[0]) + m * G * L
    drift = np.max(np.abs(energies - energies[0])) / scale / 2.0  # per second
    assert drift < 1e-6, drift
