"""Full drops into the sediment against independent references (issue 3)."""

import math

import pytest
from conftest import scenario_dict

from mineburial.kernels.mine import layout, status
from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.drop import run_params, simulate_drop
from mineburial.validation import cases
from mineburial.validation.references import archimedes_penetration

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
    sc = _scenario(
        mine={"mass": rho_mine * vol},
        environment={"water_depth": depth, "gravity": G, "water_density": RHO_W},
        release={"position": [0.0, 0.0, -depth + r - penetration], "pitch_deg": 0.0, "embedded": True},
        sediment={
            "density": rho_s,
            "density_gradient": 0.0,
            "strength": 0.0,
            "strength_gradient": 0.0,
            "resistance": "bearing",
        },
        numerics={"t_max": t_max, "dt": 1e-3},
    )
    # closed form: (rho_s - rho_w) V_emb + rho_w V = rho_mine V with V_emb = L * segment(h)
    h = archimedes_penetration(L, d, rho_mine, rho_s, RHO_W)
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
    assert pen[late].max() - pen[late].min() > 0.01  # it does oscillate
    assert abs(pen[late].mean() - h) / h < 0.005, (pen[late].mean(), h)


# ---------------------------------------------------------------------------
# vertical axial penetration against a 1-D solution of the same force law
# ---------------------------------------------------------------------------
def test_vertical_penetration_matches_one_dimensional_solution():
    """A vertical cylinder hitting the seabed axially at 3 m/s (bearing law, semi-log rate,
    S = 3 + 2 z kPa) against scipy.integrate.solve_ivp on the same force law in 1-D: the
    case of ``mineburial validate`` (validation/cases.py, references.axial_penetration)."""
    (row,) = cases.axial_penetration()
    assert row.passed, row  # at rest, within its 1 % tolerance
    assert abs(row.model - row.reference) / row.reference < 0.01, (row.model, row.reference)


# ---------------------------------------------------------------------------
# monotonic trends over sweeps
# ---------------------------------------------------------------------------
def _penetration(**over):
    # nose-down vertical drops (nose-heavy, stable): no toppling after the stop
    base = dict(
        mine={"mass": 120.0, "com_offset": 0.05},
        environment={"water_depth": 8.0},
        release={"position": [0.0, 0.0, -7.0], "pitch_deg": 90.0, "velocity": [0.0, 0.0, -3.0]},
        sediment={
            "density": 1500.0,
            "density_gradient": 0.0,
            "strength": 3000.0,
            "strength_gradient": 2000.0,
        },
        numerics={"t_max": 20.0},
    )
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
    from mineburial.systems.mine.config import load_example

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
