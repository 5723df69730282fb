"""``mineburial compare`` on the one run driver (issue 18 item 5): threads, a dask cluster and
resume give the drops of the variants' own ensemble runs.

Independent references: ``mineburial run`` of each variant scenario with the same seed (its
per-drop results are a pure function of (seed, drop index); test_compare.py checks the
comparison against it), the process's numba thread count before the call, and the chunk files
on disk and the chunks computed after an interrupt.
"""

import numba
import numpy as np
import pytest
import xarray as xr
from test_compare import short_default

from mineburial.analyses.compare import run_comparison
from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.runner import run_ensemble
from mineburial.systems.mine.config import dumps_toml

SEED = 5
VALUES = ["bearing", "delta"]
PER_DROP = ("drop_penetration_depth", "drop_burial_volume", "drop_status")


def toml_text(raw: dict) -> str:
    """``raw`` as TOML: config.dumps_toml, with the distributions inside lists (which it does
    not write) as inline tables."""
    tables = {}

    def mark(node):
        if isinstance(node, dict):
            return {k: mark(v) for k, v in node.items()}
        if isinstance(node, list):
            out = []
            for v in node:
                if isinstance(v, dict):
                    tables[f"@table{len(tables)}@"] = "{" + dumps_toml(v).strip().replace("\n", ", ") + "}"
                    v = f"@table{len(tables) - 1}@"
                out.append(v)
            return out
        return node

    text = dumps_toml(mark(raw))
    for key, table in tables.items():
        text = text.replace(f'"{key}"', table)
    return text


@pytest.fixture(scope="module")
def runs():
    """``mineburial run`` of each variant scenario: the drops every comparison must give."""
    out = []
    for value in VALUES:
        raw = short_default()
        raw["sediment"]["resistance"] = value
        out.append(run_ensemble(raw, seed=SEED, per_drop=True, threads=1))
    return out


def assert_variants_are_their_runs(ds: xr.Dataset, runs):
    for k, ref in enumerate(runs):
        np.testing.assert_array_equal(ds.drop_penetration_depth[k], ref.penetration_depth)
        np.testing.assert_array_equal(ds.drop_burial_volume[k], ref.burial_volume)
        np.testing.assert_array_equal(ds.drop_status[k], ref.status)
    for name in [v for v in runs[0].data_vars if v.startswith("input_")]:
        np.testing.assert_array_equal(ds[name], runs[0][name])


@pytest.mark.parametrize("threads", [1, 2])
def test_variants_equal_their_runs_on_1_and_2_threads_and_leave_the_thread_count(runs, threads):
    """Was: compare called numba.set_num_threads for the whole process."""
    threads = min(threads, numba.config.NUMBA_NUM_THREADS)
    before = numba.get_num_threads()
    ds = run_comparison(short_default(), "sediment.resistance", VALUES, seed=SEED, threads=threads)
    assert numba.get_num_threads() == before
    assert_variants_are_their_runs(ds, runs)


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None, silence_logs=50
    )
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_variants_equal_their_runs_on_a_dask_cluster(runs, client):
    ds = run_comparison(short_default(), "sediment.resistance", VALUES, seed=SEED, client=client)
    assert_variants_are_their_runs(ds, runs)


def _count_chunks(monkeypatch, interrupt_at=None):
    """Count the chunks computed; raise KeyboardInterrupt instead of computing chunk
    number ``interrupt_at`` (from 1)."""
    real = engine.compute_chunk
    calls = []

    def counted(spec, start, stop):
        calls.append((start, stop))
        if len(calls) == interrupt_at:
            raise KeyboardInterrupt
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", counted)
    return calls


def test_an_interrupted_comparison_keeps_its_chunks_and_the_rerun_resumes_them(
    runs, tmp_path, monkeypatch, capsys
):
    scenario, out = tmp_path / "s.toml", tmp_path / "c.nc"
    scenario.write_text(toml_text(short_default()))
    argv = ["compare", str(scenario), "--vary", "sediment.resistance=" + ",".join(VALUES)]
    argv += ["--seed", str(SEED), "--quiet", "-o", str(out), "--threads", "1"]
    chunks = len(engine.chunk_bounds(10, 4))  # short_default(): 10 drops in chunks of 4
    calls = _count_chunks(monkeypatch, interrupt_at=chunks + 2)  # variant 0 and 1 chunk of variant 1
    assert main(argv) == 130
    assert capsys.readouterr().err.splitlines() == [
        "mineburial: interrupted; rerun the same command to resume"
    ]
    parts = tmp_path / "c.nc.parts"
    assert len(list((parts / "variant-0").glob("chunk-*.npz"))) == chunks
    assert len(list((parts / "variant-1").glob("chunk-*.npz"))) == 1
    assert not out.exists()
    monkeypatch.undo()
    calls = _count_chunks(monkeypatch)
    assert main(argv) == 0
    assert len(calls) == chunks - 1  # only the chunks not kept
    assert not parts.exists()
    with xr.open_dataset(out) as ds:
        assert_variants_are_their_runs(ds.load(), runs)


def test_an_interrupted_comparison_without_output_does_not_promise_a_resume(monkeypatch, capsys):
    _count_chunks(monkeypatch, interrupt_at=1)
    argv = ["compare", "--vary", "sediment.resistance=bearing,delta", "-n", "2", "--quiet"]
    assert main(argv) == 130
    err = capsys.readouterr().err.splitlines()
    assert err == ["mineburial: interrupted; this command cannot resume: rerun it to start again"]


@pytest.mark.parametrize("command", ["compare", "sensitivity"])
def test_an_unreachable_scheduler_is_one_line_before_computing(tmp_path, monkeypatch, capsys, command):
    from mineburial.ensembles import runner

    monkeypatch.setattr(runner, "SCHEDULER_TIMEOUT", 1.0)
    calls = _count_chunks(monkeypatch)
    out = tmp_path / "o.nc"
    argv = {"compare": ["--vary", "sediment.resistance=bearing,delta", "-n", "2"], "sensitivity": ["-n", "2"]}
    assert main([command, *argv[command], "--quiet", "-o", str(out), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1
    assert err[0].startswith(
        "mineburial: error: --scheduler tcp://127.0.0.1:9: cannot reach a dask scheduler"
    )
    assert calls == [] and not out.exists() and not (tmp_path / "o.nc.parts").exists()


def test_the_cli_spreads_the_variants_over_a_scheduler(runs, tmp_path):
    from distributed import LocalCluster

    scenario, out = tmp_path / "s.toml", tmp_path / "c.nc"
    scenario.write_text(toml_text(short_default()))
    argv = ["compare", str(scenario), "--vary", "sediment.resistance=" + ",".join(VALUES)]
    argv += ["--seed", str(SEED), "--quiet", "-o", str(out)]
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tcp://", dashboard_address=None
    ) as cluster:
        assert main([*argv, "--scheduler", cluster.scheduler_address]) == 0
    with xr.open_dataset(out) as ds:
        assert_variants_are_their_runs(ds.load(), runs)
