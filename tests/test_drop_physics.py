"""Whole drops against independent references: the impact35 model, currents, the events
and impact summary, the stepper's own ends (time limit, left domain, numerical failure) and
tabulated sediment profiles (issue 12 item 18).

References: closed-form free fall (events, impact values), ordinary differential equations
of the same printed laws solved by scipy (impact35 and the default model falling
broadside; a mine carried by a current), exact integrals of a tabulated density
(overburden, scipy quadrature).
"""

import math

import numpy as np
import pytest
from conftest import make_scenario as _make_scenario
from conftest import scenario_dict
from printed_laws import AREA, NU, RHO, VOL, D, G, L, R, broadside_drag
from scipy.integrate import quad, solve_ivp

from mineburial.kernels.mine import layout, status
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.overburden import overburden_force
from mineburial.kernels.mine.sediment.laws import pack_law
from mineburial.systems.mine.config import Numerics, Scenario
from mineburial.systems.mine.drop import run_params, simulate_drop


def make_scenario(**sections):
    """The test scenario; a ``sediment`` section replaces the base one whole."""
    sediment = sections.pop("sediment", None)
    if sediment is None:
        return _make_scenario(**sections)
    d = scenario_dict(**sections)
    d["sediment"] = sediment
    return Scenario.from_dict(d)


def _summary(sc):
    p, sb, cb = sc.to_params()
    code, summary, _ = run_params(p, sb, cb)
    return code, dict(zip(layout.SUMMARY_NAMES, summary))


# ---------------------------------------------------------------------------
# the impact35 model and the default model, falling broadside from rest
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("model, added_mass", [("impact35", 0.0), ("mineburial", RHO * VOL)])
def test_broadside_fall_matches_the_ode_of_the_printed_laws(model, added_mass):
    """Falling broadside from rest in still water, the vertical velocity obeys
    (m + m_a) dw/dt = -(m - rho V) g + drag(w): seed 000 eq. (44) drag, no added mass in
    impact35 (its ratios f_i are never given), strip-theory added mass rho pi R^2 L
    (C_M = 1, seed 001) in the default model."""
    mass = 60.0
    sc = make_scenario(
        mine={"mass": mass},
        environment={"gravity": G, "water_density": RHO},
        release={"position": [0, 0, -5.0], "pitch_deg": 0.0},
        numerics={"model": model, "integrator": "dopri5", "t_max_fall": 6.0, "rtol": 1e-9, "atol": 1e-12},
    )
    ds = simulate_drop(sc, record_interval=0.05)
    assert ds.attrs["model"] == model

    def rhs(t, y):
        return [(-(mass - RHO * VOL) * G + broadside_drag(y[0])) / (mass + added_mass)]

    ref = solve_ivp(rhs, (0.0, 6.0), [0.0], t_eval=ds.time.values, rtol=1e-11, atol=1e-13, max_step=0.01)
    np.testing.assert_allclose(ds.w.values, ref.y[0], rtol=0, atol=2e-5)
    assert float(ds.w[-1]) < -0.3  # the drag law was exercised
    np.testing.assert_allclose(ds.psi2.values, 0.0, atol=1e-9)  # no torque: stays broadside


# ---------------------------------------------------------------------------
# a current acting on a drop
# ---------------------------------------------------------------------------
def test_neutral_mine_relaxes_to_a_uniform_current():
    """A neutrally buoyant mine released at rest in a uniform current across its axis is
    carried along: (m + m_a) dv/dt = 0.5 rho C_d2 d L (U - v)^2, so with C_d2 constant
    (Re in the 12 000-150 000 band of eq. (44)) U - v = U / (1 + k U t),
    k = 0.5 rho C_d2 d L / (m + m_a)."""
    U = 0.5
    mass = RHO * VOL
    sc = make_scenario(
        mine={"mass": mass},
        environment={"water_density": RHO, "current": {"kind": "uniform", "velocity": [0.0, U]}},
        release={"position": [0, 0, -20.0], "pitch_deg": 0.0},
        numerics={"t_max_fall": 15.0, "rtol": 1e-9, "atol": 1e-12},
    )
    ds = simulate_drop(sc, record_interval=0.5)
    cd2 = 0.835 - 0.35 / (L / D)
    k = 0.5 * RHO * cd2 * D * L / (mass + RHO * VOL)
    t = ds.time.values
    assert (U - ds.v.values[-1]) * D / NU > 12000  # still in the constant-C_d2 band
    np.testing.assert_allclose(ds.v.values, U - U / (1 + k * U * t), rtol=0, atol=5e-5)
    np.testing.assert_allclose(ds.u.values, 0.0, atol=1e-12)  # along the current only
    np.testing.assert_allclose(ds.w.values, 0.0, atol=1e-9)  # neutrally buoyant
    assert float(ds.v[-1]) > 0.85 * U


def test_heavy_mine_drifts_with_the_current_at_terminal_velocity():
    """Falling broadside through a uniform current across its axis, a mine that has reached
    its terminal state moves sideways with the water (no relative cross-flow sideways, so no
    sideways force): the lateral lag decays with the time constant (m + m_a) / (0.5 rho C_d2
    d L |w|) ~ 3 s, far below the 40 s simulated."""
    U = 0.3
    sc = make_scenario(
        mine={"mass": 60.0},
        environment={"current": {"kind": "uniform", "velocity": [0.0, U]}},
        release={"position": [0, 0, -5.0], "pitch_deg": 0.0},
        numerics={"t_max_fall": 40.0},
    )
    ds = simulate_drop(sc, record_interval=1.0)
    assert abs(float(ds.v[-1]) - U) < 1e-4
    assert abs(float(ds.u[-1])) < 1e-9
    assert float(ds.w[-1]) < -0.3


# ---------------------------------------------------------------------------
# events and the impact summary against closed-form free fall (no fluids)
# ---------------------------------------------------------------------------
def test_water_entry_and_impact_events_match_free_fall():
    z0, u0, w0, pitch, depth = 4.0, 2.0, -3.0, 30.0, 6.0
    sc = make_scenario(
        environment={"air_density": 0.0, "water_density": 0.0, "gravity": G, "water_depth": depth},
        release={"position": [0.0, 0.0, z0], "velocity": [u0, 0.0, w0], "pitch_deg": pitch},
        numerics={"t_max": 2.0},
    )
    p, sb, cb = sc.to_params()
    # lowest point of a cylinder at dip psi2 below its centre: L/2 sin psi2 + R cos psi2
    drop = 0.5 * L * math.sin(math.radians(pitch)) + R * math.cos(math.radians(pitch))

    def crossing(level):  # z0 - drop + w0 t - g t^2 / 2 = level, the first root t > 0
        a, b, c = -0.5 * G, w0, z0 - drop - level
        return (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)

    t_entry, t_impact = crossing(0.0), crossing(-depth)
    p[layout.P_TMAX] = t_impact + 0.05
    code, summary, _ = run_params(p, sb, cb)
    s = dict(zip(layout.SUMMARY_NAMES, summary))
    assert s["water_entry_time"] == pytest.approx(t_entry, abs=1e-10)
    assert s["impact_time"] == pytest.approx(t_impact, abs=1e-10)
    w_i = w0 - G * t_impact
    assert s["impact_speed"] == pytest.approx(math.hypot(u0, w_i), rel=1e-10)
    assert s["impact_angle"] == pytest.approx(math.degrees(math.atan2(-w_i, u0)), abs=1e-8)
    assert s["impact_pitch"] == pytest.approx(pitch, abs=1e-8)


def test_impact_values_of_a_vertical_drop_through_air():
    """A nose-down mine dropped through air only (no water) from rest: impact at the
    free-fall time and speed of its nose, angle 90 degrees, no water entry before it."""
    h = 3.0  # nose height above the surface
    depth = 0.5
    sc = make_scenario(
        environment={"air_density": 0.0, "water_density": 0.0, "gravity": G, "water_depth": depth},
        release={"position": [0.0, 0.0, h + 0.5 * L], "pitch_deg": 90.0},
        numerics={"t_max": 1.2},
    )
    code, s = _summary(sc)
    assert s["water_entry_time"] == pytest.approx(math.sqrt(2 * h / G), abs=1e-10)
    assert s["impact_time"] == pytest.approx(math.sqrt(2 * (h + depth) / G), abs=1e-10)
    # to the integrator's tolerance, not 1e-10: the flat nose meets the seabed over its whole
    # face, the force jumps there, and the step retaken to end 1e-6 of a step past the
    # crossing feels it through its last stages; the error control bounds what it leaves in
    # the speed (measured: 1.4e-8 relative at rtol 1e-5, 1.9e-4 at rtol 1e-4)
    rtol = Numerics().rtol
    assert s["impact_speed"] == pytest.approx(math.sqrt(2 * G * (h + depth)), rel=3 * rtol)
    assert s["impact_angle"] == pytest.approx(90.0, abs=1e-9)
    assert s["impact_pitch"] == pytest.approx(90.0, abs=1e-6)


# ---------------------------------------------------------------------------
# the stepper's own ends of a drop
# ---------------------------------------------------------------------------
def test_time_limit():
    sc = make_scenario(release={"position": [0, 0, -5.0]}, numerics={"t_max_fall": 0.7})
    ds = simulate_drop(sc, record_interval=0.1)
    assert int(ds.status) == status.TIME_LIMIT and ds.attrs["status"] == "time_limit"
    assert float(ds.total_time) == pytest.approx(0.7, abs=1e-12)
    assert float(ds.time[-1]) == pytest.approx(0.7, abs=1e-12)
    assert math.isnan(float(ds.impact_time))  # it never reached the seabed


def test_time_limit_counts_from_the_first_seabed_contact():
    """numerics.t_max bounds the time after the first seabed contact, not the fall."""
    sc = make_scenario(environment={"water_depth": 10.0}, numerics={"t_max_fall": 60.0, "t_max": 0.02})
    code, s = _summary(sc)
    assert code == status.TIME_LIMIT  # still moving 20 ms after hitting the soft clay at ~4 m/s
    assert s["impact_time"] > 1.0
    assert s["total_time"] == pytest.approx(s["impact_time"] + 0.02, abs=1e-12)


def test_slow_sinker_falls_longer_than_t_max_and_comes_to_rest():
    """A mine 3.4 % heavier than the water it displaces sinks broadside at the terminal
    velocity of seed 000 eq. (44) (closed form); its fall, ~37 s, is not counted in
    numerics.t_max (5 s here): it reaches the seabed and comes to rest."""
    from mineburial.validation.references import terminal_velocity_broadside

    mass = 1.034 * RHO * VOL
    v_t = terminal_velocity_broadside(mass, L, D, RHO, G, NU)
    depth = 20.0
    sc = make_scenario(
        mine={"mass": mass},
        environment={"water_depth": depth, "water_density": RHO, "gravity": G},
        release={"position": [0.0, 0.0, -5.0], "pitch_deg": 0.0},
        numerics={"t_max_fall": 600.0, "t_max": 5.0},
    )
    code, s = _summary(sc)
    # from rest under a quadratic drag reaching v_t, with the added mass rho V of a
    # cylinder moving broadside: x(t) = v_t tau ln cosh(t / tau), tau = v_t / g',
    # g' = g (m - rho V) / (m + rho V) (within 3e-5 of the run; 0.2 % allowed)
    tau = v_t / (G * (mass - RHO * VOL) / (mass + RHO * VOL))
    distance = depth - 5.0 - R  # from the release to the contact of the lowest line
    fall = tau * math.acosh(math.exp(distance / (v_t * tau)))
    assert fall > 30.0
    assert code == status.AT_REST
    assert s["impact_time"] == pytest.approx(fall, rel=0.002)
    assert s["total_time"] < s["impact_time"] + 5.0


@pytest.mark.parametrize(
    "velocity, gravity, t_exit",
    [
        # straight up in vacuum: z = z0 + 1000 m at the first root of 200 t - g t^2 / 2 = 1000
        ((0.0, 0.0, 200.0), G, (200.0 - math.sqrt(200.0**2 - 2 * G * 1000.0)) / G),
        # sideways at 500 m/s (almost no gravity): |x| = 1e5 m at t = 200 s
        ((500.0, 0.0, 0.0), 1e-6, 200.0),
    ],
)
def test_left_domain(velocity, gravity, t_exit):
    sc = make_scenario(
        environment={"air_density": 0.0, "water_density": 0.0, "gravity": gravity, "water_depth": 100.0},
        release={"position": [0.0, 0.0, 10.0], "velocity": list(velocity)},
        numerics={"t_max_fall": 1000.0},
    )
    code, s = _summary(sc)
    assert code == status.LEFT_DOMAIN
    # the domain is checked after each step, and no step is longer than 0.5 s
    assert t_exit <= s["total_time"] <= t_exit + 0.5


@pytest.mark.parametrize("integrator", ["rk4", "local_linear", "dopri5"])
@pytest.mark.parametrize("slot, value", [("P_MASS", math.nan), ("P_GRAVITY", math.inf)])
def test_numerical_failure(integrator, slot, value):
    """Non-finite physics (inputs that skip the scenario checks): the fixed-step integrators
    stop at the first non-finite state, dopri5 when its step size underflows; never a hang."""
    sc = make_scenario(numerics={"integrator": integrator, "t_max_fall": 2.0})
    p, sb, cb = sc.to_params()
    p[getattr(layout, slot)] = value
    code, summary, _ = run_params(p, sb, cb)
    assert code == status.NUMERICAL_FAILURE
    assert summary[layout.S_TOTAL_TIME] <= 1e-3


# ---------------------------------------------------------------------------
# tabulated sediment profiles: the overburden of the embedded part
# ---------------------------------------------------------------------------
TABLE = np.array(
    [
        [0.0, 0.2, 0.45, 1.5],  # depth below the seabed, m
        [1300.0, 1450.0, 1700.0, 1900.0],  # bulk density, kg m-3
        [500.0, 900.0, 2000.0, 6000.0],
    ]
)  # strength, Pa


def _tabulated_params(resistance="bearing"):
    sc = make_scenario(
        sediment={
            "profile": {"depth": list(TABLE[0]), "density": list(TABLE[1]), "strength": list(TABLE[2])},
            "resistance": resistance,
        },
        environment={"water_depth": 10.0, "water_density": RHO, "gravity": G},
    )
    return sc, *sc.to_params()


UNIFORM_TABLE = np.array([[0.0, 2.0], [1650.0, 1650.0], [1000.0, 1000.0]])


@pytest.mark.parametrize("table", ["layered", "uniform"])
@pytest.mark.parametrize("a_z, zeta_lo", [(-1.0, 0.6), (-1.0, 0.3), (1.0, 0.9), (-0.6, 0.5)])
def test_tabulated_overburden_against_quadrature(a_z, zeta_lo, table):
    """F = g int_emb (rho_s(zeta) - rho_w) dV over the embedded part, rho_s piecewise linear
    between the table's points (held beyond the last): for a vertical mine the section is
    pi R^2 at every depth; for a tilted mine the volume integral is a double quadrature over
    the cross-sections. The first moment along the axis is exact where the density is
    uniform within each slice between table depths (the kernel's documented scope): checked
    on the uniform table."""
    sc, p, sb, cb = _tabulated_params()
    if table == "uniform":
        sb = UNIFORM_TABLE[None, :, :].copy()
    tab = UNIFORM_TABLE if table == "uniform" else TABLE
    seabed = -10.0
    b = math.sqrt(max(0.0, 1 - a_z * a_z))
    # place the COM so that the lowest point is zeta_lo below the seabed (chi = 0)
    z_c = seabed - zeta_lo + 0.5 * L * abs(a_z) + R * b
    z_lo = seabed - zeta_lo
    law = pack_law(p, p[layout.P_DIAMETER], True)
    f, fx, fe = overburden_force(Cylinder(L, R, 0.0), a_z, z_c, seabed, z_lo, RHO, G, p, sb, law)

    def rho(zeta):
        return np.interp(zeta, tab[0], tab[1])

    if b == 0.0:
        # x along the axis, depth zeta = seabed - (z_c + a_z x)
        def integrand(x, moment):
            zeta = seabed - (z_c + a_z * x)
            return (rho(zeta) - RHO) * G * AREA * (x if moment else 1.0) if zeta > 0 else 0.0

        kinks = [x for x in ((seabed - zeta - z_c) / a_z for zeta in tab[0]) if -0.5 * L < x < 0.5 * L]
        ref_f = quad(
            integrand, -0.5 * L, 0.5 * L, args=(False,), points=kinks, limit=200, epsabs=0.0, epsrel=1e-12
        )[0]
        ref_fx = quad(
            integrand, -0.5 * L, 0.5 * L, args=(True,), points=kinks, limit=200, epsabs=0.0, epsrel=1e-12
        )[0]
        assert f == pytest.approx(ref_f, rel=1e-9)
        if table == "uniform":
            assert fx == pytest.approx(ref_fx, rel=1e-9, abs=1e-9 * abs(ref_f))
        assert fe == 0.0
    else:
        # tilted: sum over axial stations of the cross-section strip integral
        def section(x):
            zc = z_c + a_z * x  # height of the axis point

            def strip(s):  # s along e_down, chord half-width sqrt(R^2 - s^2)
                zeta = seabed - (zc - b * s)
                return 2 * math.sqrt(R * R - s * s) * (rho(zeta) - RHO) if zeta > 0 else 0.0

            return quad(strip, -R, R, limit=100)[0]

        ref_f = G * quad(section, -0.5 * L, 0.5 * L, limit=100)[0]
        assert f == pytest.approx(ref_f, rel=1e-5)
        if table == "uniform":  # first moment along the axis: int x dF
            ref_fx = G * quad(lambda x: x * section(x), -0.5 * L, 0.5 * L, limit=100)[0]
            assert fx == pytest.approx(ref_fx, rel=1e-5, abs=1e-5 * abs(ref_f))


def test_tabulated_profile_on_a_line_gives_the_linear_profile():
    """A table whose points lie on a linear profile (density and strength) is the same
    sediment: the same drop reaches the same penetration (overburden exact per slice,
    interpolation exact on a line)."""
    depths = [0.0, 0.3, 0.8, 2.0]
    rho0, krho, s0, ks = 1500.0, 100.0, 3000.0, 2000.0
    common = dict(
        mine={"mass": 150.0},
        environment={"water_depth": 8.0},
        release={"position": [0.0, 0.0, -7.0], "pitch_deg": 90.0, "velocity": [0.0, 0.0, -3.0]},
        numerics={"t_max": 10.0},
    )
    linear = make_scenario(
        sediment={
            "density": rho0,
            "density_gradient": krho,
            "strength": s0,
            "strength_gradient": ks,
            "resistance": "bearing",
        },
        **common,
    )
    table = make_scenario(
        sediment={
            "profile": {
                "depth": depths,
                "density": [rho0 + krho * d for d in depths],
                "strength": [s0 + ks * d for d in depths],
            },
            "resistance": "bearing",
        },
        **common,
    )
    code_a, a = _summary(linear)
    code_b, b = _summary(table)
    assert code_a == code_b == status.AT_REST
    assert b["penetration_depth"] == pytest.approx(a["penetration_depth"], rel=1e-6)
    assert 0.1 < a["penetration_depth"] < 2.0  # inside the table, below its first point
