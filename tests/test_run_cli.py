"""``mineburial run`` and ``mineburial map``: checks before computing, what the summary
says, and the scenario's own settings (issue 12 items 1, 5, 7, 8, 11, 12).

Every refused command must end with exit code 2 and one line ``mineburial: error: ...``
naming the option, before a single drop is computed (``compute_chunk`` is replaced by
a function that fails the test), and must leave its inputs untouched.
"""

import math
import re

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.cli import main
from mineburial.ensembles import engine, runner
from mineburial.systems.mine.config import dumps_toml

N = 8


def cheap(**ensemble):
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
    d["ensemble"] = {"n": N, "chunk_size": 4, **ensemble}
    return d


@pytest.fixture
def scenario_file(tmp_path):
    path = tmp_path / "scenario.toml"
    path.write_text(dumps_toml(cheap()))
    return path


@pytest.fixture
def no_computing(monkeypatch):
    def fail(spec, start, stop):
        raise AssertionError("a drop was computed before the check")

    monkeypatch.setattr(engine, "compute_chunk", fail)


def refused(capsys, argv, *needles):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: "), err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


def test_output_equal_to_the_scenario_file_is_refused(scenario_file, capsys, no_computing):
    before = scenario_file.read_bytes()
    refused(
        capsys,
        ["run", str(scenario_file), "-o", str(scenario_file), "--quiet"],
        "-o",
        "is an input of the run",
    )
    assert scenario_file.read_bytes() == before


def test_output_equal_to_a_profile_file_is_refused(tmp_path, capsys, no_computing):
    csv = tmp_path / "core.csv"
    csv.write_text("depth_m,density_kg_m3,strength_pa\n0,1500,2000\n2,1700,8000\n")
    scen = tmp_path / "scenario.toml"
    d = cheap()
    d["sediment"] = {"file": "core.csv"}
    scen.write_text(dumps_toml(d))
    before = csv.read_bytes()
    refused(
        capsys,
        ["run", str(scen), "-o", str(tmp_path / "." / "core.csv"), "--quiet"],
        "is an input of the run",
        "core.csv",
    )
    assert csv.read_bytes() == before


def test_existing_folder_as_output_is_refused(scenario_file, tmp_path, capsys, no_computing):
    refused(capsys, ["run", str(scenario_file), "-o", str(tmp_path), "--quiet"], "is an existing folder")


def test_output_whose_parent_is_a_file_is_refused(scenario_file, tmp_path, capsys, no_computing):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file")
    refused(
        capsys,
        ["run", str(scenario_file), "-o", str(blocker / "out.nc"), "--quiet"],
        "is a file, not a folder",
    )
    refused(
        capsys,
        ["run", str(scenario_file), "-o", str(tmp_path / "missing" / "out.nc"), "--quiet"],
        "does not exist",
    )


@pytest.mark.parametrize("threads", ["0", "-3", "100000"])
def test_threads_outside_one_to_cores_are_refused(scenario_file, tmp_path, capsys, no_computing, threads):
    refused(
        capsys,
        ["run", str(scenario_file), "-o", str(tmp_path / "o.nc"), "--threads", threads, "--quiet"],
        "--threads",
        "outside the allowed range 1..",
    )


def test_unreachable_scheduler_is_refused_after_a_short_timeout(
    scenario_file, tmp_path, capsys, monkeypatch, no_computing
):
    monkeypatch.setattr(runner, "SCHEDULER_TIMEOUT", 1.0)
    refused(
        capsys,
        [
            "run",
            str(scenario_file),
            "-o",
            str(tmp_path / "o.nc"),
            "--scheduler",
            "tcp://127.0.0.1:9",
            "--quiet",
        ],
        "--scheduler tcp://127.0.0.1:9: cannot reach a dask scheduler there within 1 s",
    )


def test_huge_n_is_refused_with_the_memory_it_would_need(scenario_file, tmp_path, capsys, no_computing):
    err = refused(
        capsys,
        ["run", str(scenario_file), "-o", str(tmp_path / "o.nc"), "-n", str(10**15), "--quiet"],
        "ensemble.n = 1000000000000000",
        "would need about",
    )
    # the estimate: N_SUMMARY float64 + status + 3 sampled inputs a drop, times 4
    from mineburial.kernels.mine import layout

    per_drop = int(re.search(r"\((\d+) bytes a drop", err).group(1))
    assert per_drop == layout.N_SUMMARY * 8 + 1 + 3 * 8


def test_fixed_step_integrator_with_too_many_steps_gets_a_warning(capsys):
    many = cheap()
    many["numerics"].update(integrator="rk4", dt=1e-8, t_max=3.0)
    runner.warn_run(engine.load_ensemble(many))
    err = capsys.readouterr().err
    # the longest drop: a fall of t_max_fall = 5 s (the test scenario) and t_max = 3 s after contact
    assert "warning: (numerics.t_max_fall + numerics.t_max) / numerics.dt = 8 s" in err
    assert "8e+08 time steps" in err
    for integrator, dt in (("dopri5", 1e-8), ("rk4", 1e-3)):  # adaptive, or few steps
        ok = cheap()
        ok["numerics"].update(integrator=integrator, dt=dt, t_max=3.0)
        runner.warn_run(engine.load_ensemble(ok))
        assert capsys.readouterr().err == ""


def test_scenario_per_drop_true_is_honoured_by_the_cli(tmp_path, capsys):
    scen = tmp_path / "scenario.toml"
    scen.write_text(dumps_toml(cheap(per_drop=True)))
    out = tmp_path / "o.nc"
    assert main(["run", str(scen), "-o", str(out), "-n", "2", "--quiet"]) == 0
    assert xr.load_dataset(out).sizes.get("realization") == 2
    assert main(["run", str(scen), "-o", str(out), "-n", "2", "--no-per-drop", "--quiet"]) == 0
    assert "realization" not in xr.load_dataset(out).dims


def printed_probabilities(text):
    return {
        m.group(1): float(m.group(2)) for m in re.finditer(r"^  P\((\w+)\) = ([0-9.]+)", text, flags=re.M)
    }


@pytest.mark.parametrize("per_drop", [[], ["--per-drop"]])
def test_per_drop_summary_prints_the_files_class_probabilities(tmp_path, capsys, per_drop):
    scen = tmp_path / "scenario.toml"
    d = cheap()
    d["sediment"] = {"class": {"distribution": "choice", "values": ["soft_clay", "sand"]}}
    d["release"]["position"] = [0.0, 0.0, -1.5]
    scen.write_text(dumps_toml(d))
    out = tmp_path / "o.nc"
    assert (
        main(["run", str(scen), "-o", str(out), "-n", "12", "--seed", "1", "--quiet", "--per-drop"]) == 0
    )  # the reference: per-drop values
    capsys.readouterr()
    ref = xr.load_dataset(out)
    assert main(["run", str(scen), "-o", str(out), "-n", "12", "--seed", "1", "--quiet", *per_drop]) == 0
    printed = printed_probabilities(capsys.readouterr().out)
    rest = ref["status"].values == 0
    burial = ref["burial_volume"].values[rest]
    expected = {
        "not_buried": np.mean(burial <= 0),
        "buried_0_to_10_percent": np.mean((burial > 0) & (burial <= 10)),
        "buried_10_to_20_percent": np.mean((burial > 10) & (burial <= 20)),
        "buried_20_to_75_percent": np.mean((burial > 20) & (burial <= 75)),
        "buried_more_than_75_percent": np.mean(burial > 75),
    }
    assert set(printed) == set(expected)
    for name, p in expected.items():
        assert printed[name] == pytest.approx(p, abs=5e-4), name
    assert len({round(p, 3) for p in expected.values()}) > 1  # the labels matter here


def test_invalid_sampled_inputs_get_a_warning_with_reason_and_count(tmp_path, capsys):
    """A release 1 m below the surface over a random water depth of 0.5-3 m: the drops whose
    sampled depth is not more than 1 m would start inside the seabed. (A cross-field
    constraint: no single field's range can exclude it when the scenario is loaded.)"""
    scen = tmp_path / "scenario.toml"
    d = cheap(per_drop=True)
    d["environment"]["water_depth"] = {"distribution": "uniform", "low": 0.5, "high": 3.0}
    d["release"]["position"] = [0.0, 0.0, -1.0]
    scen.write_text(dumps_toml(d))
    out = tmp_path / "o.nc"
    assert main(["run", str(scen), "-o", str(out), "-n", "16", "--seed", "1", "--quiet"]) == 0
    text = capsys.readouterr().out
    ds = xr.load_dataset(out)
    depth = ds["input_environment_water_depth"].values
    bad = int(np.count_nonzero(depth <= 1.0))
    assert 0 < bad < 16
    # the drops whose mine reaches into the seabed at release are refused too: the lowest
    # point lies between the centre of mass and half the body's diagonal below it
    mine = d["mine"]
    reach = 0.5 * math.hypot(mine["length"], mine["diameter"]) + abs(mine["com_offset"])
    partly = int(np.count_nonzero((depth > 1.0) & (depth < 1.0 + reach)))
    n_invalid = int(ds["status_count"].sel(status_code=4))
    assert bad <= n_invalid <= bad + partly
    line = [ln for ln in text.splitlines() if "sampled inputs are invalid" in ln]
    assert len(line) == 1, text
    assert line[0].startswith(f"warning: {n_invalid} of 16 drops were not run")
    assert f"release.z > -environment.water_depth: {bad} drop" in line[0], line[0]
    assert f"environment.water_depth = {float(depth[depth <= 1.0][0])!r}" in line[0], line[0]


def write_grid(path):
    from mineburial.analyses.synthetic import write_synthetic_environment

    write_synthetic_environment(path, ny=2, nx=2, seed=1)


def test_map_output_equal_to_the_environment_grid_is_refused(scenario_file, tmp_path, capsys, no_computing):
    env = tmp_path / "env.nc"
    write_grid(env)
    before = env.read_bytes()
    refused(
        capsys,
        ["map", str(scenario_file), "--environment", str(env), "-o", str(env), "--quiet"],
        "-o",
        "is an input of the run",
    )
    assert env.read_bytes() == before


def test_map_plot_with_an_unsupported_extension_is_refused(scenario_file, tmp_path, capsys, no_computing):
    pytest.importorskip("matplotlib")
    env = tmp_path / "env.nc"
    write_grid(env)
    refused(
        capsys,
        [
            "map",
            str(scenario_file),
            "--environment",
            str(env),
            "-o",
            str(tmp_path / "m.nc"),
            "--plot",
            str(tmp_path / "m.xyz"),
            "--quiet",
        ],
        "--plot",
        "unsupported image type '.xyz'",
        ".png",
    )
    refused(
        capsys,
        [
            "map",
            str(scenario_file),
            "--environment",
            str(env),
            "-o",
            str(tmp_path / "m.png"),
            "--plot",
            str(tmp_path / "m.png"),
            "--quiet",
        ],
        "--plot",
        "is also the map's output (-o)",
    )
    refused(
        capsys,
        [
            "map",
            str(scenario_file),
            "--environment",
            str(env),
            "-o",
            str(tmp_path / "m.nc"),
            "--plot",
            str(tmp_path / "nowhere" / "m.png"),
            "--quiet",
        ],
        "--plot",
        "does not exist",
    )
