"""``mineburial sensitivity`` on the one run driver (issue 18 item 5): the Sobol' design runs as
one ensemble whose drops are the design's points.

Independent references: the ensemble's own chunks (a design made of the ensemble's own draws
must give its drops bit for bit), the process's numba thread count before the call, and the
chunk files on disk and the chunks computed after an interrupt; threads, a dask cluster and
resume must not change a bit of the indices.
"""

import dataclasses

import numba
import numpy as np
import pytest
import xarray as xr
from test_compare import short_default
from test_compare_driver import _count_chunks, toml_text

from mineburial.analyses import sensitivity
from mineburial.analyses.sensitivity import DesignSpec, run_sensitivity
from mineburial.cli import main
from mineburial.ensembles import engine, runner, store

N, SEED = 4, 1
D = len(engine.load_ensemble(short_default()).random)  # the design's dimension: its random inputs
DROPS = N * (D + 2)


def test_a_design_of_the_ensembles_own_draws_gives_its_drops(monkeypatch):
    spec = engine.load_ensemble(short_default(), seed=SEED)
    points = DesignSpec.of(spec, 1)  # n (d + 2) = D + 2 points ...
    assert points.n == D + 2
    own = {k: np.asarray(v) for k, v in spec.sampled_inputs(0, D + 2).items()}  # ... the ensemble's draws
    monkeypatch.setattr(sensitivity, "design_points", lambda random, n, seed: own)
    ((_, chunks),) = runner.run_jobs([runner.Job(None, points)], threads=1)
    ref = engine.compute_chunk(dataclasses.replace(spec, n=D + 2), 0, D + 2)
    for key in ("summary", "status"):
        np.testing.assert_array_equal(np.concatenate([c[key] for c in chunks]), ref[key])


def test_the_design_is_scipys_and_its_identity_changes_with_it():
    """The points are those scipy's sobol_indices evaluates (recorded from it), the same for
    the same seed; a resumed analysis must not reuse the chunks of another design."""
    spec = engine.load_ensemble(short_default(), seed=SEED)
    seen = []

    def record(x):
        seen.append({k: np.array(v) for k, v in x.items()})
        return np.zeros((1, len(x["mine.mass"])))

    sensitivity.sobol_analysis(record, spec.random, N, SEED, n_resamples=9)
    points = sensitivity.design_points(spec.random, N, SEED)
    for k in spec.random:
        np.testing.assert_array_equal(points[k], seen[0][k])
        assert points[k].shape == (DROPS,)
    ids = {
        store.run_identity(DesignSpec.of(s, n))
        for s, n in ((spec, N), (spec, N), (spec, 2 * N), (dataclasses.replace(spec, seed=SEED + 1), N))
    }
    assert len(ids) == 3


@pytest.fixture(scope="module")
def reference():
    return run_sensitivity(short_default(), n=N, seed=SEED)


def assert_same_indices(a: xr.Dataset, b: xr.Dataset):
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name


def test_one_thread_gives_the_same_bits_and_leaves_the_thread_count(reference):
    """Was: sensitivity called numba.set_num_threads for the whole process."""
    before = numba.get_num_threads()
    ds = run_sensitivity(short_default(), n=N, seed=SEED, threads=1)
    assert numba.get_num_threads() == before
    assert_same_indices(ds, reference)


def test_a_dask_cluster_gives_the_same_bits(reference):
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None, silence_logs=50
        ) as cluster,
        Client(cluster) as client,
    ):
        ds = run_sensitivity(short_default(), n=N, seed=SEED, client=client)
    assert_same_indices(ds, reference)


def test_an_interrupted_analysis_keeps_its_chunks_and_the_rerun_resumes_them(tmp_path, monkeypatch, capsys):
    scenario, out = tmp_path / "s.toml", tmp_path / "s.nc"
    scenario.write_text(toml_text(short_default()))
    argv = ["sensitivity", str(scenario), "-n", str(N), "--seed", str(SEED), "--quiet", "-o", str(out)]
    chunks = len(engine.chunk_bounds(DROPS, 4))  # short_default(): chunks of 4 drops
    _count_chunks(monkeypatch, interrupt_at=6)
    assert main(argv) == 130
    assert capsys.readouterr().err.splitlines() == [
        "mineburial: interrupted; rerun the same command to resume"
    ]
    assert len(list((tmp_path / "s.nc.parts").glob("chunk-*.npz"))) == 5
    monkeypatch.undo()
    calls = _count_chunks(monkeypatch)
    assert main(argv) == 0
    assert len(calls) == chunks - 5
    assert not (tmp_path / "s.nc.parts").exists()
    monkeypatch.undo()
    # the file's inputs are in another order than the dict's: the design's columns differ
    fresh = run_sensitivity(scenario, n=N, seed=SEED)
    with xr.open_dataset(out) as ds:
        assert_same_indices(ds.load(), fresh)
