"""The post-impact scour stage in ``mineburial run`` (issue 20 items 1, 2, 5, 6): the optional
``[scour]`` section leaves every impact output as it was, a constant forcing gives the closed-form
relaxation of every drop from its own impact burial (that of the mine lying with the impact's
buried volume, docs/scour.md), a cohesive bed does not scour, the class probabilities per lead
time are the fractions of the per-drop burials, and bad input is one line."""

import hashlib
import json
import math
import pathlib

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict
from test_scour_rest import segment_burial

from mineburial.cli import main
from mineburial.ensembles import engine, runner
from mineburial.systems.mine.config import dumps_toml, example_path
from mineburial.systems.mine.processes import scour

N = 8
G = 9.81
KAPPA = 0.40
D = 0.25  # conftest's test cylinder
LENGTH = 1.0
U = 0.7  # m/s, depth-mean current of the constant forcing
D50 = 2.0e-4
RHO_S = 2650.0
LEADS = [0.0, 0.002, 0.005, 0.01, 0.03, 0.5]  # days
LEVELS = [0.5, 0.75]


def forcing_csv(path, hours=24, hs=0.0, u=U, level=0.0):
    rows = ["time_s,hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg,water_level_m"]
    rows += [f"{3600.0 * i},{hs},8.0,270.0,{u},0.0,{level}" for i in range(hours + 1)]
    path.write_text("\n".join(rows) + "\n")
    return path


def scenario(tmp_path, scour=None, depth=None, **ensemble):
    d = scenario_dict(
        environment={"water_depth": {"distribution": "uniform", "low": 2.5, "high": 3.5}},
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        sediment={"class": "soft_clay"},
        numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
    )
    d["mine"]["mass"] = {"distribution": "normal", "mean": 80.0, "std": 5.0}
    d["ensemble"] = {"n": N, "chunk_size": 4, "per_drop": True, "seed": 3, **ensemble}
    if scour is not None:
        d["scour"] = scour
    if depth is not None:
        d["environment"]["water_depth"] = depth
    path = tmp_path / "scenario.toml"
    path.write_text(dumps_toml(d))
    return path


def scour_section(tmp_path, **over):
    sec = {
        "forcing": str(forcing_csv(tmp_path / "constant.csv")),
        "lead_times_days": LEADS,
        "burial_levels": LEVELS,
        "d50": D50,
        "grain_density": RHO_S,
        "cohesive": False,  # sand on the scenario's soft_clay class (else the class's cohesive bed)
    }
    sec.update(over)
    return sec


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scour_run")
    plain = runner.run_ensemble(scenario(tmp, None))
    with_scour = runner.run_ensemble(scenario(tmp, scour_section(tmp)))
    return plain, with_scour


def test_scour_section_absent_leaves_every_output_bit_identical(runs):
    plain, with_scour = runs
    assert not [
        v for v in plain.variables if str(v).startswith("scour_") or v in ("lead_time", "burial_level")
    ]
    for name, var in plain.variables.items():
        assert np.array_equal(var.values, with_scour[name].values, equal_nan=var.dtype.kind == "f"), name


def lying_b0(ds):
    """Each drop's initial burial of the stage: the horizontal cylinder with the impact's burial
    by volume (the segment, solved by brentq), or, when the mine's top is below the bed
    (penetration beyond its vertical extent L|sin pitch| + D cos pitch), D + the top's depth."""
    pitch = np.radians(ds["final_pitch"].values)
    top = ds["penetration_depth"].values - (LENGTH * np.abs(np.sin(pitch)) + D * np.cos(pitch))
    vol = ds["burial_volume"].values / 100.0
    return np.array([D + tp if tp >= 0 else segment_burial(v, D / 2) for tp, v in zip(top, vol)])


def closed_form(b0, depth, t_s, rho=1025.0, nu=1.0e-6):
    """B(t) from the printed laws (docs/scour.md): depth-mean current stress (Soulsby 1997 eqs.
    36-37, z0 = d50/12), Shields parameter, threshold of Soulsby & Whitehouse (1997), B_eq = D a
    theta^b capped at D (Rennie et al. 2017, a = 1.3, b = 0.36), T = 0.014 theta^-1.29 D^2 /
    sqrt(g (s - 1) d50^3) (Whitehouse 1998), exact relaxation, never decreasing."""
    s = RHO_S / rho
    tau = rho * (KAPPA / (math.log(depth / (D50 / 12.0)) - 1.0)) ** 2 * U * U
    theta = tau / (rho * (s - 1.0) * G * D50)
    dstar = D50 * (G * (s - 1.0) / nu**2) ** (1.0 / 3.0)
    theta_cr = 0.30 / (1.0 + 1.2 * dstar) + 0.055 * (1.0 - math.exp(-0.020 * dstar))
    assert theta > theta_cr  # the case must scour
    b_eq = min(D * 1.3 * theta**0.36, D)
    t_scale = 0.014 * theta**-1.29 * D * D / math.sqrt(G * (s - 1.0) * D50**3)
    return np.maximum(b0, b_eq - (b_eq - b0) * np.exp(-np.asarray(t_s) / t_scale)), b_eq, t_scale


def test_constant_current_gives_the_closed_form_relaxation_of_each_drop(runs):
    _, ds = runs
    assert np.all(ds["scour_status"].values == 0)
    t_s = np.asarray(LEADS) * 86400.0
    grew = 0
    b0s = lying_b0(ds)
    for i in range(N):
        b0 = b0s[i]
        depth = float(ds["input_environment_water_depth"][i])
        expected, b_eq, t_scale = closed_form(b0, depth, t_s)
        got = ds["scour_penetration_depth"].values[i]
        np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)
        grew += b_eq > b0
        for k, level in enumerate(LEVELS):  # time to reach: the inverted relaxation
            target = level * D
            if b0 >= target:
                want = 0.0
            elif b_eq <= target:
                want = math.inf
            else:
                want = t_scale * math.log((b_eq - b0) / (b_eq - target)) / 86400.0
            assert ds["scour_time_to_level"].values[i, k] == pytest.approx(want, rel=1e-9)
    assert grew == N  # every drop scoured, so the check is not of a constant
    assert float(ds["lead_time"][0]) == 0.0 and ds["lead_time"].attrs["standard_name"] == "forecast_period"


def classify(percent):
    """The impact-burial classes, written out: 0 exactly 0 %, (0, 10], (10, 20], (20, 75], > 75."""
    out = []
    for p in percent:
        out.append(0 if p <= 0 else 1 if p <= 10 else 2 if p <= 20 else 3 if p <= 75 else 4)
    return np.array(out)


def test_class_probabilities_per_lead_time_are_the_per_drop_fractions(runs):
    _, ds = runs
    vol = ds["scour_burial_volume"].values
    prob = ds["scour_burial_class_probability"].values
    assert prob.shape == (len(LEADS), 5)
    for j in range(len(LEADS)):
        counts = np.bincount(classify(vol[:, j]), minlength=5)
        np.testing.assert_array_equal(prob[j], counts / N)
        lo = ds["scour_burial_class_probability_lower"].values[j]
        hi = ds["scour_burial_class_probability_upper"].values[j]
        assert np.all(lo <= prob[j]) and np.all(prob[j] <= hi)
    assert len(set(map(tuple, np.round(prob, 12)))) > 1  # the classes move with lead time
    np.testing.assert_allclose(
        ds["scour_burial_volume_mean"].values, np.mean(vol, axis=0), rtol=1e-12
    )  # fmt: skip


def test_cohesive_bed_does_not_scour(tmp_path):
    ds = runner.run_ensemble(scenario(tmp_path, scour_section(tmp_path, cohesive=True)))
    b0 = lying_b0(ds)
    got = ds["scour_penetration_depth"].values
    np.testing.assert_allclose(got, np.repeat(b0[:, None], len(LEADS), axis=1), rtol=1e-12)
    for k, level in enumerate(LEVELS):
        t = ds["scour_time_to_level"].values[:, k]
        assert np.all(np.where(b0 >= level * D, t == 0.0, np.isinf(t)))


@pytest.fixture
def no_computing(monkeypatch):
    def fail(spec, start, stop):
        raise AssertionError("a drop was computed")

    monkeypatch.setattr(engine, "compute_chunk", fail)


@pytest.mark.parametrize(
    "over, needle",
    [
        ({"beq_a": -1.0}, "scour.beq_a = -1.0 is outside the allowed range"),
        ({"d50": 0.05}, "scour.d50 = 0.05 m is outside the allowed range"),
        ({"hs_scale": {"distribution": "uniform", "low": -1.0, "high": 2.0}}, "scour.hs_scale"),
        ({"lead_times_days": [1.0, 2.0]}, "scour.lead_times_days[1] = 2 is outside the allowed range [0, 1]"),
        ({"lead_times_days": [0.5, 0.1]}, "scour.lead_times_days = [0.5, 0.1] must be strictly increasing"),
        ({"burial_levels": [1.5]}, "scour.burial_levels[0] = 1.5"),
        ({"tstar_law": "nope"}, "scour.tstar_law"),
        ({"tstar_law": ["whitehouse"]}, "scour.tstar_law = ['whitehouse'] must be a name"),
        ({"cohesive": "yes"}, "scour.cohesive = 'yes' must be true or false"),
        ({"d5O": 1.0}, "[scour]"),
        ({"storm": {"peak_hs": 2.0}}, "exactly one of forcing"),
        ({"forcing": "no_such_storm"}, "scour.forcing: unknown shipped forcing"),
    ],
)
def test_bad_scour_input_is_one_line_naming_the_field(tmp_path, capsys, no_computing, over, needle):
    path = scenario(tmp_path, scour_section(tmp_path, **over))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err, err
    assert not (tmp_path / "out.nc").exists()


def test_bad_storm_is_one_line(tmp_path, capsys, no_computing):
    sec = scour_section(tmp_path, storm={"peak_hs": 2.0, "duration_h": 24.0})
    del sec["forcing"]
    path = scenario(tmp_path, sec)
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "scour.storm: peak_tp missing" in err, err


def test_output_records_the_forcing_file_and_its_sha256(runs):
    _, ds = runs
    path = pathlib.Path(ds.attrs["forcing_file"])
    assert path.name == "constant.csv"
    assert ds.attrs["forcing_sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()
    assert json.loads(ds.attrs["scenario"])["scour"]["lead_times_days"] == LEADS


def test_scour_storm_example_reads_the_shipped_storm_file(no_computing):
    spec = engine.load_ensemble(example_path("scour_storm"), systems=engine.SYSTEMS)
    shipped = (
        pathlib.Path(scour.__file__).resolve().parent.parent.parent.parent
        / "data"
        / "forcing"
        / "storm_example.csv"
    )
    stage = spec.process("scour")
    assert stage.forcing_record["forcing_sha256"] == hashlib.sha256(shipped.read_bytes()).hexdigest()
    assert (str(shipped), stage.forcing_record["forcing_sha256"]) in spec.input_files
    assert stage.forcing.duration_s == 96 * 3600.0  # the storm file: 96 h hourly (docs/scour.md)
    assert {"scour.beq_a", "scour.beq_b", "scour.theta_exponent", "scour.hs_scale"} <= set(spec.random)


def test_a_drop_whose_bed_falls_dry_is_reported_not_a_silent_nan(tmp_path, capsys):
    """A water level of -3 m dries the bed where the drop's sampled depth (2.5-3.5 m) is at most
    3 m: those drops get scour_status invalid_forcing, NaN values, and the summary counts them."""
    sec = scour_section(tmp_path, forcing=str(forcing_csv(tmp_path / "low.csv", level=-3.0)))
    path = scenario(tmp_path, sec)
    out = tmp_path / "out.nc"
    assert main(["run", str(path), "-o", str(out), "--quiet", "--per-drop"]) == 0
    text = capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        dry = ds["input_environment_water_depth"].values <= 3.0
        status = ds["scour_status"].values
        assert 0 < dry.sum() < N
        np.testing.assert_array_equal(status, np.where(dry, 2, 0))
        assert np.all(np.isnan(ds["scour_burial_volume"].values[dry]))
        assert np.all(np.isfinite(ds["scour_burial_volume"].values[~dry]))
        assert int(ds.attrs["scour_n_in_statistics"]) == N - dry.sum()
    assert f"invalid_forcing {dry.sum()}" in text


def test_a_fixed_depth_that_the_water_level_dries_is_refused_before_computing(tmp_path, capsys, no_computing):
    sec = scour_section(tmp_path, forcing=str(forcing_csv(tmp_path / "low.csv", level=-4.0)))
    path = scenario(tmp_path, sec, depth=3.0)
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "variable 'water_level' = -4 m" in err and "dries the bed" in err, (
        err
    )


@pytest.mark.parametrize(
    "storm, needle",
    [
        ({"start": "yesterday"}, "start = 'yesterday' is not an ISO 8601 time"),
        ({"total_h": 1e9}, "at most 87661 are accepted"),
    ],
)
def test_bad_storm_start_or_length_is_one_line_not_a_traceback(tmp_path, capsys, no_computing, storm, needle):
    """Regressions (review): a storm start that is not ISO 8601 raised ValueError, and a storm
    of 1e9 hours allocated until memory ran out."""
    sec = scour_section(tmp_path, storm={"peak_hs": 2.0, "peak_tp": 9.0, "duration_h": 24.0, **storm})
    del sec["forcing"]
    path = scenario(tmp_path, sec)
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err, err


def test_storm_start_as_a_toml_datetime_or_with_z_is_the_same_utc_instant():
    """Regression (review): an unquoted TOML datetime reached str.strip (AttributeError), and
    Python 3.10's fromisoformat refuses a trailing 'Z'."""
    import datetime as dt

    from mineburial.io.forcing import storm_series

    want = np.datetime64("2003-01-15T06:00:00", "ns")
    for start in (
        "2003-01-15T06:00:00Z",
        "2003-01-15T07:00:00+01:00",
        "2003-01-15T06:00:00",
        dt.datetime(2003, 1, 15, 6, tzinfo=dt.timezone.utc),
    ):
        assert storm_series(2.0, 9.0, 24.0, start=start).start == want, start


def test_stage_results_do_not_depend_on_threads_or_chunking(runs, tmp_path):
    """The stage runs in blocks on every thread: each drop's lead-time values must be those of
    a run on one thread in chunks of 3 (an invariance, bit for bit)."""
    _, with_scour = runs
    one = runner.run_ensemble(scenario(tmp_path, scour_section(tmp_path)), threads=1, chunk_size=3)
    names = [v for v in with_scour.data_vars if v.startswith("scour_")]
    assert names
    for v in names:
        np.testing.assert_array_equal(one[v].values, with_scour[v].values, err_msg=v)


def test_ripple_exposure_is_a_section_field_that_fills_the_stages_slot():
    """scour.ripple_exposure (the coarse-sand exposure in ripple heights, kernel default 1 from
    Traykovski et al. 2007) reaches the stage: fixed, sampled, and refused out of range."""
    from test_compare import short_default

    from mineburial.ensembles import engine
    from mineburial.errors import ScenarioError
    from mineburial.kernels.mine import scour as scour_kernels
    from mineburial.systems.mine import ensemble as mine
    from mineburial.systems.mine.processes import scour as scour_ensemble

    def stage(exposure):
        raw = short_default(8)
        raw["ensemble"]["coefficients"] = "fixed"
        raw["sediment"] = {"class": "sand"}
        raw["scour"] = {"storm": {"peak_hs": 2.0, "peak_tp": 9.0, "duration_h": 24.0}}
        if exposure is not None:
            raw["scour"]["ripple_exposure"] = exposure
        spec = engine.load_ensemble(raw)
        P, _, inputs = mine.chunk_inputs(spec, 0, spec.n)
        S, _ = scour_ensemble.stage_parameters(spec.process("scour"), P, inputs)
        return S[:, scour_kernels.S_RIPPLE_EXPOSURE], inputs

    default, _ = stage(None)
    assert scour_kernels.default_parameters()[scour_kernels.S_RIPPLE_EXPOSURE] == 1.0
    assert np.all(default == 1.0)
    fixed, _ = stage(2.0)
    assert np.all(fixed == 2.0)
    drawn, inputs = stage({"distribution": "uniform", "low": 0.5, "high": 1.5})
    np.testing.assert_array_equal(drawn, inputs["scour.ripple_exposure"])
    assert np.all((drawn >= 0.5) & (drawn <= 1.5)) and np.unique(drawn).size == drawn.size
    with pytest.raises(ScenarioError, match=r"scour\.ripple_exposure = 6\.0 .*\[0, 5\]"):
        stage(6.0)
