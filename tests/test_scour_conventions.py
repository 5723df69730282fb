"""The orbital-velocity and wave-friction conventions of the scour stage as scenario keys
(``scour.orbital``, ``scour.friction``; issue 20 item 4, docs/scour.md): each key reaches the
stage and selects its closure, checked against independent references — the orbital velocities of
sources.md §3 [computed] (h = 12 m, Hs = 1.25 m, Tp = 10 s: U(Hs) = 0.473, U(H_rms) = 0.334 m/s,
spectral u_br = 0.310 m/s, Wiberg & Sherwood 2008), and, end to end in a run under constant waves,
the closed-form relaxation of every drop from the printed laws with the dispersion root from
scipy's brentq, Swart's (1974) and Soulsby's (1997 eq. 62a) friction factors written out."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from test_scour_run import D50, LEADS, RHO_S, D, N, forcing_csv, lying_b0, scenario, scour_section

from mineburial.analyses import compare
from mineburial.cli import main
from mineburial.ensembles import engine, runner
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as sc
from mineburial.systems.mine.processes import scour

G = 9.81
RHO = 1025.0  # the test scenario's water (tests/conftest.py)
HS, TP = 0.5, 8.0  # the constant waves of the end-to-end runs (forcing_csv holds Tp = 8 s)


@pytest.fixture
def no_computing(monkeypatch):
    def fail(spec, start, stop):
        raise AssertionError("a drop was computed")

    monkeypatch.setattr(engine, "compute_chunk", fail)


def stage_vector(tmp_path, **keys):
    """The stage parameters a run gives one drop (a 0.53 m mine, the published cases' water)."""
    spec = scour.parse(scour_section(tmp_path, **keys))
    P = np.zeros((1, len(layout.PARAM_NAMES)))
    P[0, layout.P_DIAMETER], P[0, layout.P_LENGTH], P[0, layout.P_MASS] = 0.53, 2.0, 750.0
    P[0, layout.P_RHO_WATER], P[0, layout.P_NU_WATER], P[0, layout.P_GRAVITY] = RHO, 1.05e-6, G
    S, _ = scour.stage_parameters(spec, P, {})
    return S[0]


@pytest.mark.parametrize(
    "orbital, published", [(None, 0.310), ("spectral", 0.310), ("hrms", 0.334), ("hs", 0.473)]
)
def test_orbital_key_selects_the_published_bed_velocity(tmp_path, orbital, published):
    keys = {} if orbital is None else {"orbital": orbital}
    p = stage_vector(tmp_path, **keys)
    _, ub, _, _ = sc.bed_forcing(p, 1.25, 10.0, 0.0, 0.0, 0.0, 12.0, scour._orbital_table())
    assert ub == pytest.approx(published, abs=5e-4)


def kh_root(h, period):
    omega = 2.0 * math.pi / period
    return brentq(lambda y: y * math.tanh(y) - omega**2 * h / G, 1e-9, 50.0, xtol=1e-14)


def friction_factor(name, a):
    ks = 2.5 * D50
    if name == "soulsby":  # Soulsby 1997 eq. 62a, z0 = ks/30
        return 1.39 * (a / (ks / 30.0)) ** -0.52
    # Swart 1974, simplified (docs/scour.md): 0.3 below A/ks = 1.57
    return 0.00251 * math.exp(5.21 * (a / ks) ** -0.19) if a / ks > 1.57 else 0.3


def closed_form_waves(b0, depth, t_s, orbital, friction):
    """B(t) under constant pure waves: linear-wave U = pi H/(T sinh kh) (H = Hs or Hs/sqrt 2),
    tau = rho f_w U^2 / 2, the Rennie et al. (2017) B_eq and Whitehouse's (1998) time scale."""
    height = HS if orbital == "hs" else HS / math.sqrt(2.0)
    u = math.pi * height / (TP * math.sinh(kh_root(depth, TP)))
    fw = friction_factor(friction, u * TP / (2.0 * math.pi))
    s = RHO_S / RHO
    theta = 0.5 * fw * u * u / ((s - 1.0) * G * D50)
    b_eq = min(D * 1.3 * theta**0.36, D)
    t_scale = 0.014 * theta**-1.29 * D * D / math.sqrt(G * (s - 1.0) * D50**3)
    return np.maximum(b0, b_eq - (b_eq - b0) * np.exp(-np.asarray(t_s) / t_scale)), b_eq


@pytest.fixture(scope="module")
def wave_runs(tmp_path_factory):
    """The same scenario and seed under constant waves, with two pairs of conventions."""
    out = {}
    for orbital, friction in (("hrms", "soulsby"), ("hs", "swart")):
        tmp = tmp_path_factory.mktemp(f"{orbital}_{friction}")
        forcing = str(forcing_csv(tmp / "waves.csv", hs=HS, u=0.0))
        sec = scour_section(tmp, forcing=forcing, orbital=orbital, friction=friction)
        out[orbital, friction] = runner.run_ensemble(scenario(tmp, sec))
    return out


@pytest.mark.parametrize("orbital, friction", [("hrms", "soulsby"), ("hs", "swart")])
def test_each_convention_gives_the_closed_form_under_constant_waves(wave_runs, orbital, friction):
    ds = wave_runs[orbital, friction]
    assert np.all(ds["scour_status"].values == 0)
    t_s = np.asarray(LEADS) * 86400.0
    grew = 0
    for i, b0 in enumerate(lying_b0(ds)):
        depth = float(ds["input_environment_water_depth"][i])
        expected, b_eq = closed_form_waves(b0, depth, t_s, orbital, friction)
        np.testing.assert_allclose(ds["scour_penetration_depth"].values[i], expected, rtol=1e-9, atol=1e-12)
        grew += b_eq > b0
    assert grew == N  # every drop scoured: the check is not of a constant
    assert ds.attrs["scenario"].count(f'"orbital": "{orbital}"') == 1


def test_conventions_change_the_burial_but_no_sampled_input(wave_runs):
    a, b = wave_runs["hrms", "soulsby"], wave_runs["hs", "swart"]
    inputs = [v for v in a.variables if str(v).startswith("input_")]
    assert inputs
    for name in inputs + ["penetration_depth", "burial_volume"]:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    assert not np.array_equal(a["scour_penetration_depth"].values, b["scour_penetration_depth"].values)


@pytest.mark.parametrize(
    "over, needle",
    [
        ({"orbital": "jonswap"}, "scour.orbital: unknown name 'jonswap'"),
        ({"friction": "nielsen"}, "scour.friction: unknown name 'nielsen'"),
        ({"orbital": {"distribution": "uniform", "low": 0, "high": 2}}, "scour.orbital"),
    ],
)
def test_bad_convention_is_one_line_naming_the_key(tmp_path, capsys, no_computing, over, needle):
    path = scenario(tmp_path, scour_section(tmp_path, **over))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err and ("spectral" in err or "swart" in err), err
    assert not (tmp_path / "out.nc").exists()


def test_compare_varies_a_convention_at_a_lead_time_and_gives_each_closed_form(wave_runs, tmp_path):
    """``mineburial compare`` with [scour] (issue 20): the burial compared is the stage's at
    ``--lead-time``, each variant's that of its convention (the drops' impact burial is the same
    in every run of this scenario and seed: their sampled inputs are checked equal)."""
    ref = wave_runs["hs", "swart"]
    forcing = str(forcing_csv(tmp_path / "waves.csv", hs=HS, u=0.0))
    path = scenario(tmp_path, scour_section(tmp_path, forcing=forcing, friction="swart"))
    lead = LEADS[2]
    ds = compare.run_comparison(path, "scour.orbital", ["hrms", "hs"], lead_time=lead)
    assert ds.attrs["lead_time_days"] == lead and "hrms: ok 8; hs: ok 8" in ds.attrs["scour_status_counts"]
    np.testing.assert_array_equal(
        ds["input_environment_water_depth"].values, ref["input_environment_water_depth"].values
    )
    for k, orbital in enumerate(["hrms", "hs"]):
        for i, b0 in enumerate(lying_b0(ref)):
            depth = float(ref["input_environment_water_depth"][i])
            (want,), _ = closed_form_waves(b0, depth, [lead * 86400.0], orbital, "swart")
            assert ds["drop_penetration_depth"].values[k, i] == pytest.approx(want, rel=1e-9)
    assert np.all(ds["drop_penetration_depth"].values[1] > ds["drop_penetration_depth"].values[0])


def test_compare_lead_time_without_scour_is_one_line(tmp_path, capsys, no_computing):
    path = scenario(tmp_path, None)
    argv = ["compare", str(path), "--vary", "sediment.resistance=bearing,delta", "-n", "4"]
    assert main([*argv, "--lead-time", "1", "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--lead-time 1: the scenario has no [scour] section" in err, err
    assert not (tmp_path / "out.nc").exists()
