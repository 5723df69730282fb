"""Full drops into the sediment against independent references (issue 3)."""

import math

import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from mineburial.drop import run_params, simulate_drop
from mineburial.kernels import layout, status

from conftest import scenario_dict
from mineburial.config import Scenario

G = 9.81
RHO_W = 1025.0


def _scenario(**sections):
    d = scenario_dict(**sections)
    if "sediment" in sections:
        d["sediment"] = sections["sediment"]
    return Scenario.from_dict(d)


def _summary(sc):
    p, sb, cb = sc.to_params()
    code, summary, _ = run_params(p, sb, cb)
    return code, dict(zip(layout.SUMMARY_NAMES, summary))


# ---------------------------------------------------------------------------
# Archimedes: a mine lighter than a zero-strength sediment floats in it
# ---------------------------------------------------------------------------
def _archimedes_case(penetration, t_max):
    L, d, rho_mine, rho_s = 1.0, 0.25, 1300.0, 1600.0
    r = d / 2
    vol = math.pi * r * r * L
    depth = 10.0
    sc = _scenario(mine={"mass": rho_mine * vol},
                   environment={"water_depth": depth, "gravity": G, "water_density": RHO_W},
                   release={"position": [0.0, 0.0, -depth + r - penetration], "pitch_deg": 0.0,
                            "embedded": True},
                   sediment={"density": rho_s, "density_gradient": 0.0, "strength": 0.0,
                             "strength_gradient": 0.0, "resistance": "bearing"},
                   numerics={"t_max": t_max, "dt": 1e-3})
    # closed form: (rho_s - rho_w) V_emb + rho_w V = rho_mine V with V_emb = L * segment(h)
    v_emb = (rho_mine - RHO_W) * vol / (rho_s - RHO_W)

    def segment(h):
        return r * r * math.acos((r - h) / r) - (r - h) * math.sqrt(max(r * r - (r - h) ** 2, 0.0))

    h = brentq(lambda h: L * segment(h) - v_emb, 0.0, d)
    return sc, h, depth, r


def test_rests_at_archimedes_depth_in_zero_strength_sediment():
    """Released at rest at the closed-form Archimedes depth, it is at rest there."""
    sc0, h, _, _ = _archimedes_case(0.0, 1.0)
    sc, h, depth, r = _archimedes_case(h, 5.0)
    code, s = _summary(sc)
    assert code == status.AT_REST
    assert abs(s["penetration_depth"] - h) / h < 1e-6


def test_oscillates_about_archimedes_depth_from_above():
    """Released 1 cm too shallow into a zero-strength sediment, it oscillates about
    the Archimedes depth (only the water above damps it, weakly)."""
    _, h, _, _ = _archimedes_case(0.0, 1.0)
    sc, h, depth, r = _archimedes_case(h - 0.01, 12.0)
    ds = simulate_drop(sc, record_interval=0.002)
    pen = r - (ds.z.values + depth)
    late = ds.time.values > 2.0
    assert pen[late].max() - pen[late].min() > 0.01      # it does oscillate
    assert abs(pen[late].mean() - h) / h < 0.005, (pen[late].mean(), h)


# ---------------------------------------------------------------------------
# vertical axial penetration against a 1-D solution of the same force law
# ---------------------------------------------------------------------------
def test_vertical_penetration_matches_one_dimensional_solution():
    L, d, mass = 1.0, 0.25, 150.0
    r = d / 2
    area = math.pi * r * r
    depth = 10.0
    s0, ks, rho_s = 3000.0, 2000.0, 1500.0
    nc0 = math.pi + 2.0
    beta, rate_ref = 0.1, 2.78e-6
    w0 = -3.0
    sc = _scenario(mine={"mass": mass},
                   environment={"water_depth": depth, "gravity": G, "water_density": RHO_W},
                   release={"position": [0.0, 0.0, -depth + L / 2 + 1e-9], "pitch_deg": 90.0,
                            "velocity": [0.0, 0.0, w0]},
                   sediment={"density": rho_s, "density_gradient": 0.0, "strength": s0,
                             "strength_gradient": ks, "resistance": "bearing",
                             "rate_law": "semilog", "rate_coefficient": beta,
                             "reference_rate": rate_ref, "friction": 0.0,
                             "bearing_factor": nc0},
                   numerics={"t_max": 10.0, "dt": 1e-4, "drag": False})
    code, s = _summary(sc)
    assert code == status.AT_REST

    # The same force law written for a vertical cylinder penetrating axially to depth
    # zeta (tip below the seabed), speed v > 0 downwards (docs/notes/sediment.md):
    def strength(z):
        return s0 + ks * z

    def g_rate(v):                    # semi-log rate law, strain rate v/d
        ratio = v / (d * rate_ref)
        return 1.0 + beta * math.log10(ratio) if ratio > 1.0 else 1.0

    def rhs(t, y):
        zeta, v = y
        emb = min(max(zeta, 0.0), L)
        nc = nc0 * (1.0 + 0.4 * math.atan(zeta / d))           # Brinch Hansen depth factor
        h_reg = v / math.sqrt(v * v + 1e-8) if v > 0 else 0.0    # regularised advancing switch
        gv = g_rate(v)
        bearing = nc * strength(zeta) * gv * area * h_reg
        overburden = (rho_s - RHO_W) * G * area * emb            # effective sediment buoyancy
        weight = (mass - RHO_W * area * L) * G                    # weight in water
        water_len = L - emb
        m_eff = mass + RHO_W * area * water_len                    # isotropic added mass (munk 0)
        return [v, (weight - overburden - bearing) / m_eff]

    def stopped(t, y):
        return y[1] - 1e-2          # numerics.rest_speed
    stopped.terminal = True
    stopped.direction = -1
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, -w0], events=stopped, rtol=1e-10, atol=1e-12,
                    max_step=1e-3)
    zeta_ref = sol.y[0, -1]
    assert abs(s["penetration_depth"] - zeta_ref) / zeta_ref < 0.01, (s["penetration_depth"],
                                                                      zeta_ref)


# ---------------------------------------------------------------------------
# monotonic trends over sweeps
# ---------------------------------------------------------------------------
def _penetration(**over):
    # nose-down vertical drops (nose-heavy, stable): no toppling after the stop
    base = dict(mine={"mass": 120.0, "com_offset": 0.05}, environment={"water_depth": 8.0},
                release={"position": [0.0, 0.0, -7.0], "pitch_deg": 90.0,
                         "velocity": [0.0, 0.0, -3.0]},
                sediment={"density": 1500.0, "density_gradient": 0.0, "strength": 3000.0,
                          "strength_gradient": 2000.0},
                numerics={"t_max": 20.0})
    for k, v in over.items():
        base[k] = {**base[k], **v}
    code, s = _summary(_scenario(**base))
    assert code == status.AT_REST
    return s["penetration_depth"]


def test_burial_grows_with_impact_speed():
    pen = [_penetration(release={"velocity": [0.0, 0.0, -w]}) for w in (1.0, 3.0, 6.0, 10.0)]
    assert all(b > a for a, b in zip(pen, pen[1:])), pen


def test_burial_grows_with_mine_density():
    pen = [_penetration(mine={"mass": m}) for m in (60.0, 100.0, 150.0, 220.0)]
    assert all(b > a for a, b in zip(pen, pen[1:])), pen


def test_burial_falls_with_shear_strength():
    pen = [_penetration(sediment={"strength": s}) for s in (1000.0, 3000.0, 9000.0, 27000.0)]
    assert all(b < a for a, b in zip(pen, pen[1:])), pen


# ---------------------------------------------------------------------------
# time-step convergence of the burial on the example scenarios
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["exp2_barrel", "default_mine"])
def test_burial_converged_in_time_step(name):
    from mineburial.config import load_example
    sc = load_example(name)
    p, sb, cb = sc.to_params()
    out = []
    for f in (1.0, 0.25):
        q = p.copy()
        q[layout.P_DT] = p[layout.P_DT] * f
        code, summary, _ = run_params(q, sb, cb)
        assert code == status.AT_REST
        out.append(summary[layout.S_PENETRATION])
    assert abs(out[0] - out[1]) / out[1] < 0.01, out
