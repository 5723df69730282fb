"""The scour-and-settle law and the per-lead-time mobility in ``mineburial run`` (issue 33 items 2, 3
and 5): under a constant current every drop's pit follows the closed form S_eq (1 - exp(-t/T)) from
the printed laws, its burial is max(B0, S), the mobility of each drop at each lead time is the hand
evaluation of the moment-balance criterion, and the new statistics are the per-drop shares and means."""

import math

import numpy as np
import pytest
from test_scour_run import D50, KAPPA, LEADS, LENGTH, RHO_S, D, G, U, lying_b0, scenario, scour_section

from mineburial.ensembles import engine, runner

RHO = 1025.0  # conftest's water
NU = 1.0e-6


def pit_closed_form(depth, t_s):
    """S(t) from the printed laws (docs/scour.md, Scour and settle): a depth-mean current alone
    (U_cw = 1), so S_eq = D (1 - theta_cr/theta) 1.3 theta^0.36 (capped at D), T of Whitehouse
    (1998); the pit starts at 0."""
    s = RHO_S / RHO
    tau = RHO * (KAPPA / (math.log(depth / (D50 / 12.0)) - 1.0)) ** 2 * U * U
    theta = tau / (RHO * (s - 1.0) * G * D50)
    dstar = D50 * (G * (s - 1.0) / NU**2) ** (1.0 / 3.0)
    theta_cr = 0.30 / (1.0 + 1.2 * dstar) + 0.055 * (1.0 - math.exp(-0.020 * dstar))
    assert theta > theta_cr
    s_eq = min(D * (1.0 - theta_cr / theta) * 1.3 * theta**0.36, D)
    t_scale = 0.014 * theta**-1.29 * D * D / math.sqrt(G * (s - 1.0) * D50**3)
    return s_eq * (1.0 - np.exp(-np.asarray(t_s) / t_scale))


def pocket_mobile(burial, mass):
    """The pocket criterion by hand: Theta_U = U^2/(g D (s_obj - 1)) against max(1.6 (D/k)^-0.72,
    (pi/(2 C_D)) tan(alpha)/(1 - B/D)), cos(alpha) = 1 - 2 B/D, k = 2.5 d50, C_D = 1.2; no waves."""
    s_obj = mass / (RHO * math.pi * D * D / 4.0 * LENGTH)
    theta_u = U * U / (G * D * (s_obj - 1.0))
    rigid = 1.6 * (D / (2.5 * D50)) ** -0.72
    f = burial / D
    if f >= 0.5:
        return 0.0
    c = 1.0 - 2.0 * f
    tan_a = math.sqrt(1.0 - c * c) / c if f > 0 else 0.0
    return float(theta_u > max(rigid, math.pi / 2.4 * tan_a / (1.0 - f)))


@pytest.fixture(scope="module")
def settle_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scour_settle_run")
    sec = scour_section(tmp, burial_law="scour_settle", mobility="pocket")
    return runner.run_ensemble(scenario(tmp, sec))


def test_each_drop_follows_the_closed_form_pit_and_settles_into_it(settle_run):
    ds = settle_run
    assert np.all(ds["scour_status"].values == 0)
    t_s = np.asarray(LEADS) * 86400.0
    b0s = lying_b0(ds)
    for i in range(ds.sizes["realization"]):
        pit = pit_closed_form(float(ds["input_environment_water_depth"][i]), t_s)
        np.testing.assert_allclose(ds["scour_pit_depth"].values[i], pit, rtol=1e-9, atol=1e-13)
        np.testing.assert_allclose(
            ds["scour_penetration_depth"].values[i], np.maximum(b0s[i], pit), rtol=1e-9, atol=1e-12
        )
    np.testing.assert_allclose(ds["scour_pit_depth_mean"].values, ds["scour_pit_depth"].values.mean(axis=0))
    assert ds["scour_pit_depth"].values[:, -1].min() > 0.0  # the check is not of a constant


def test_mobility_per_lead_time_is_the_moment_balance_by_hand(settle_run):
    ds = settle_run
    mass = ds["input_mine_mass"].values
    burial = ds["scour_penetration_depth"].values
    want = np.array([[pocket_mobile(b, m) for b in row] for row, m in zip(burial, mass)])
    np.testing.assert_array_equal(ds["scour_mobile_at_lead_time"].values, want)
    np.testing.assert_allclose(ds["scour_mobile_probability"].values, want.mean(axis=0), rtol=1e-15)
    assert ds["scour_mobile_probability"].dims == ("lead_time",)
    # the impact leaves these mines 0.45-0.6 D in the sand: none moves, while the same flow moves a
    # mine lying on the bed (the criterion is not a constant; mobile cases: tests/test_scour_settle.py)
    assert want.sum() == 0 and all(pocket_mobile(0.0, m) == 1.0 for m in mass)


@pytest.fixture
def no_computing(monkeypatch):
    def fail(spec, start, stop):
        raise AssertionError("a drop was computed")

    monkeypatch.setattr(engine, "compute_chunk", fail)


@pytest.mark.parametrize(
    "over, needle",
    [
        ({"burial_law": "nope"}, "scour.burial_law"),
        ({"mobility": "rolling"}, "scour.mobility"),
        ({"wave_a": 0.0}, "scour.wave_a = 0.0 is outside the allowed range"),
        ({"wave_kc_exponent": 3.0}, "scour.wave_kc_exponent = 3.0 is outside the allowed range"),
        ({"infill_days": -1.0}, "scour.infill_days = -1.0 d is outside the allowed range"),
        ({"bed_lowering_rate": -0.1}, "scour.bed_lowering_rate = -0.1 m d-1 is outside the allowed range"),
        ({"mobility_drag": 9.0}, "scour.mobility_drag = 9.0 is outside the allowed range"),
    ],
)
def test_bad_settle_input_is_one_line_naming_the_field(tmp_path, capsys, no_computing, over, needle):
    from mineburial.cli import main

    path = scenario(tmp_path, scour_section(tmp_path, **{"burial_law": "scour_settle", **over}))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err, err


def test_what_follows_a_move_is_split_into_rolling_back_into_an_open_pit_and_leaving_a_flat_bed():
    """Issue 33 item 5, "what follows reported (rolls into its pit vs migrates away)": of the drops
    that would move at a lead time, those with a pit at least PIT_OPEN = 0.1 diameters deep roll back
    into it, the others may migrate away; the two shares add up to the share that would move. Hand
    arrays: 4 drops (D 0.5 m; one whose stage did not run) at 3 lead times."""
    from mineburial.systems.mine.processes import scour

    mobile = np.array([[1.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 0.0], [np.nan, np.nan, np.nan]])
    pit = np.array([[0.0, 0.05, 0.2], [0.049, 0.3, 0.051], [0.4, 0.4, 0.4], [np.nan, np.nan, np.nan]])
    d = np.full(4, 0.5)
    in_pit = scour.mobile_in_pit(mobile, pit, d)
    # 0.1 D = 0.05 m: a pit of 0.05 m counts as open, 0.049 m does not
    np.testing.assert_array_equal(in_pit[:3], [[0, 1, 0], [0, 0, 1], [0, 0, 0]])
    assert np.all(np.isnan(in_pit[3]))
    codes = np.array([0, 0, 0, 1], dtype=np.int8)
    chunks = [
        {"scour:status": codes, "scour:pit": pit, "scour:mobile_lead": mobile, "scour:mobile_in_pit": in_pit}
    ]
    spec = type("Spec", (), {"lead_times_days": (0.0, 1.0, 2.0)})()
    got = {k: v.values for k, v in scour.lead_time_states(spec, chunks, codes).items()}
    np.testing.assert_allclose(got["scour_mobile_probability"], [2 / 3, 1 / 3, 1 / 3])
    np.testing.assert_allclose(got["scour_mobile_into_pit_probability"], [0.0, 1 / 3, 1 / 3])
    np.testing.assert_allclose(got["scour_mobile_away_probability"], [2 / 3, 0.0, 0.0])
    np.testing.assert_allclose(got["scour_pit_depth_mean"], pit[:3].mean(axis=0))
