"""The ensemble engine: reproducibility, statistics, resume (issue 4). Sampling quality is tested
on the samples themselves in test_sampling.py; Sobol' against Monte Carlo on whole drops is
benchmarks/bench_sobol.py."""

import copy
import json

import numba
import numpy as np
import pytest
import xarray as xr

from mineburial.ensembles.engine import load_ensemble
from mineburial.ensembles.runner import run_ensemble
from mineburial.kernels.mine import layout
from mineburial.systems.mine.config import tomllib  # tomllib or the tomli fallback (Python 3.10)
from mineburial.systems.mine.drop import run_params
from mineburial.systems.mine.ensemble import DEFAULT_SCENARIO, chunk_inputs


def fast_default(**ensemble):
    """The embedded default ensemble, released 2 m above a 5 m deep seabed so that each
    drop is short; every random input of the default is kept."""
    with open(DEFAULT_SCENARIO, "rb") as fh:
        raw = tomllib.load(fh)
    raw = copy.deepcopy(raw)
    raw["environment"]["water_depth"] = {"distribution": "uniform", "low": 4.5, "high": 5.5}
    raw["release"]["position"] = [0.0, 0.0, -2.0]
    raw["numerics"]["t_max"] = 10.0
    raw["ensemble"].update({"n": 24, "chunk_size": 7, "per_drop": True, **ensemble})
    return raw


@pytest.fixture(scope="module")
def reference():
    numba.set_num_threads(2)
    return run_ensemble(fast_default(), seed=11)


def test_same_seed_bit_identical_for_threads_and_chunks(reference):
    numba.set_num_threads(1)
    try:
        other = run_ensemble(fast_default(chunk_size=5), seed=11)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    for name in (
        "penetration_depth",
        "burial_volume",
        "status",
        "final_pitch",
        "input_mine_mass",
        "input_release_pitch_deg",
    ):
        np.testing.assert_array_equal(other[name].values, reference[name].values)
    for name in ("burial_volume_mean", "burial_volume_quantile", "burial_class_probability", "status_count"):
        np.testing.assert_array_equal(other[name].values, reference[name].values)


def test_different_seed_differs(reference):
    other = run_ensemble(fast_default(n=6, chunk_size=6), seed=12)
    assert not np.array_equal(other["input_mine_mass"].values, reference["input_mine_mass"].values[:6])
    assert not np.array_equal(other["penetration_depth"].values, reference["penetration_depth"].values[:6])


def test_statistics_equal_numpy_on_the_per_drop_values(reference):
    ok = reference["status"].values == 0
    v = reference["burial_volume"].values[ok]
    assert ok.sum() >= 20
    assert float(reference["burial_volume_mean"]) == np.mean(v)
    assert float(reference["burial_volume_std"]) == np.std(v, ddof=1)
    np.testing.assert_array_equal(
        reference["burial_volume_quantile"].values, np.quantile(v, [0.05, 0.25, 0.5, 0.75, 0.95])
    )
    pen = reference["penetration_depth"].values[ok]
    assert float(reference["penetration_depth_mean"]) == np.mean(pen)


def test_per_drop_results_equal_simulate_drop(reference):
    spec = load_ensemble(fast_default(), seed=11)
    P, valid, _ = chunk_inputs(spec, 0, 4)
    for i in range(4):
        code, summary, _ = run_params(P[i], spec.sediment_bank, spec.current_bank)
        assert code == int(reference["status"].values[i])
        assert summary[layout.S_PENETRATION] == reference["penetration_depth"].values[i]
        assert summary[layout.S_BURIAL_VOLUME] == reference["burial_volume"].values[i]


def test_output_records_resolved_scenario_seed_and_version(reference, tmp_path):
    out = tmp_path / "burial.nc"
    run_ensemble(fast_default(n=4, chunk_size=2), seed=3, output=out)
    ds = xr.open_dataset(out)
    scen = json.loads(ds.attrs["scenario"])
    assert scen["ensemble"]["seed"] == 3 and scen["ensemble"]["n"] == 4
    assert scen["scenario"]["mine"]["length"] == 2.0
    assert "mine.mass" in scen["random_inputs"]
    assert ds.attrs["mineburial_version"]
    assert not (tmp_path / "burial.nc.parts").exists()


def test_interrupted_run_resumes_without_recomputing(tmp_path, monkeypatch):
    from mineburial.ensembles import engine

    out = tmp_path / "burial.nc"
    calls = []
    real = engine.compute_chunk

    def flaky(spec, start, stop):
        calls.append(start)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(fast_default(n=8, chunk_size=2), seed=5, output=out)
    assert len(list((tmp_path / "burial.nc.parts").glob("chunk-*.npz"))) == 2
    calls.clear()
    monkeypatch.setattr(engine, "compute_chunk", lambda s, a, b: (calls.append(a), real(s, a, b))[1])
    resumed = run_ensemble(fast_default(n=8, chunk_size=2), seed=5, output=out)
    assert sorted(calls) == [4, 6]  # only the unfinished chunks ran
    fresh = run_ensemble(fast_default(n=8, chunk_size=2), seed=5)
    np.testing.assert_array_equal(resumed["penetration_depth"].values, fresh["penetration_depth"].values)


def test_bad_ensemble_values_get_clear_errors():
    from mineburial.errors import ScenarioError

    with pytest.raises(ScenarioError, match=r"ensemble\.n = 0"):
        load_ensemble(fast_default(n=0))
    with pytest.raises(ScenarioError, match=r"ensemble\.sampling"):
        load_ensemble(fast_default(sampling="lhs"))
    raw = fast_default()
    raw["mine"]["name"] = {"distribution": "uniform", "low": 0, "high": 1}
    with pytest.raises(ScenarioError, match=r"mine\.name"):
        load_ensemble(raw)
