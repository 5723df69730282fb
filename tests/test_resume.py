"""Resume, run identity and the output lock (issue 12 items 2, 3, 7, 9).

Independent reference in every test: a clean run of the same command without an
output path (no chunk files exist for it), whose per-drop values are a pure function
of (scenario, seed, drop index). A run that was killed (simulated by a monkeypatched
``compute_chunk`` that raises after some chunks) and rerun -- after another run, a
changed input file or a damaged chunk file -- must give exactly the same bits.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.ensembles import engine, store
from mineburial.ensembles.runner import run_ensemble
from mineburial.ensembles.store import RunLock, RunLockedError
from mineburial.systems.mine.config import dumps_toml

N, CHUNK = 8, 2
COMPUTE_CHUNK = engine.compute_chunk


def cheap(**over):
    """Cheap drops (~0.1 s): a small cylinder released 1 m above 2.5-3.5 m of water onto
    stiff clay, 3 s limit, the fast sediment rule; mass, pitch and water depth are random."""
    d = scenario_dict(
        environment={"water_depth": {"distribution": "uniform", "low": 2.5, "high": 3.5}},
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        sediment={"class": "stiff_clay"},
        numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
    )
    d["mine"]["mass"] = {"distribution": "normal", "mean": 80.0, "std": 5.0}
    d["ensemble"] = {"n": N, "chunk_size": CHUNK, "per_drop": True}
    for key, value in over.items():
        d[key] = value
    return d


def killed_after(monkeypatch, chunks: int):
    """Make compute_chunk raise KeyboardInterrupt once ``chunks`` chunks have run."""
    real = COMPUTE_CHUNK
    calls = []

    def dying(spec, start, stop):
        if len(calls) == chunks:
            raise KeyboardInterrupt
        calls.append((spec.seed, start, stop))
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", dying)
    return calls


def counting(monkeypatch):
    real = COMPUTE_CHUNK
    calls = []
    monkeypatch.setattr(
        engine, "compute_chunk", lambda spec, s, e: (calls.append((s, e)), real(spec, s, e))[1]
    )
    return calls


def assert_bit_identical(a: xr.Dataset, b: xr.Dataset):
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.variables:
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name
    skip = {"date_created", "history"}
    assert {k: str(v) for k, v in a.attrs.items() if k not in skip} == {
        k: str(v) for k, v in b.attrs.items() if k not in skip
    }


def parts_of(out):
    return out.with_name(out.name + ".parts")


def test_resume_refuses_chunks_of_another_seed(tmp_path, monkeypatch, capsys):
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 3)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=1, output=out)
    assert len(list(parts_of(out).glob("chunk-*.npz"))) == 3
    calls = counting(monkeypatch)
    mixed = run_ensemble(cheap(), seed=2, output=out)
    assert "discarding 3 finished chunk file(s)" in capsys.readouterr().err
    assert len(calls) == N // CHUNK  # nothing of seed 1 was reused
    clean = run_ensemble(cheap(), seed=2)
    assert_bit_identical(mixed, clean)
    assert_bit_identical(xr.load_dataset(out), clean)
    assert xr.load_dataset(out).attrs["random_seed"] == 2


def test_resume_refuses_chunks_of_another_scenario(tmp_path, monkeypatch, capsys):
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=3, output=out)
    other = cheap()
    other["mine"]["mass"] = {"distribution": "normal", "mean": 95.0, "std": 5.0}
    counting(monkeypatch)
    resumed = run_ensemble(other, seed=3, output=out)
    assert "discarding 2 finished chunk file(s)" in capsys.readouterr().err
    assert_bit_identical(resumed, run_ensemble(other, seed=3))


def test_a_chunk_file_of_another_run_is_recomputed(tmp_path, monkeypatch, capsys):
    """Chunk files that slipped into the folder from another run (same names, manifest of
    this run) are recognised by the identity stamped into each file."""
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    killed_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=4, output=a)
    killed_after(monkeypatch, 1)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=5, output=b)
    name = "chunk-000000000000-000000000002.npz"
    (parts_of(b) / name).write_bytes((parts_of(a) / name).read_bytes())  # seed 4's into b
    capsys.readouterr()
    calls = counting(monkeypatch)
    resumed = run_ensemble(cheap(), seed=5, output=b)
    err = capsys.readouterr().err
    assert "chunk-000000000000-000000000002.npz was written by another run" in err
    assert (0, 2) in calls
    assert_bit_identical(resumed, run_ensemble(cheap(), seed=5))


def test_truncated_chunk_file_is_recomputed_and_reported(tmp_path, monkeypatch, capsys):
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 3)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=6, output=out)
    chunk = parts_of(out) / "chunk-000000000002-000000000004.npz"
    data = chunk.read_bytes()
    chunk.write_bytes(data[: len(data) // 2])  # a write cut short
    garbage = parts_of(out) / "chunk-000000000004-000000000006.npz"
    garbage.write_bytes(b"not a zip file")
    calls = counting(monkeypatch)
    resumed = run_ensemble(cheap(), seed=6, output=out)
    err = capsys.readouterr().err
    assert f"chunk file {chunk} is unreadable" in err and "recomputing drops [2, 4)" in err
    assert f"chunk file {garbage} is unreadable" in err
    assert sorted(calls) == [(2, 4), (4, 6), (6, 8)]
    assert_bit_identical(resumed, run_ensemble(cheap(), seed=6))


def test_stray_temporary_files_of_a_killed_write_are_removed(tmp_path, capsys):
    out = tmp_path / "burial.nc"
    final_tmp = tmp_path / ".burial.nc.0123456789abcdef.tmp"  # write_netcdf's pattern
    final_tmp.write_bytes(b"half a netCDF file")
    store.own_folder(parts_of(out))  # as a killed run left it
    chunk_tmp = parts_of(out) / ".chunk-000000000000-000000000002.npz.999-abcd.tmp"
    chunk_tmp.write_bytes(b"half a chunk")
    unrelated = tmp_path / ".other.nc.0123456789abcdef.tmp"
    unrelated.write_bytes(b"someone else's")
    run_ensemble(cheap(), n=2, seed=7, output=out)
    assert f"removing {final_tmp}" in capsys.readouterr().err
    assert not final_tmp.exists() and not chunk_tmp.exists() and unrelated.exists()
    assert out.exists() and not parts_of(out).exists()


def write_csv(path, strength_factor=1.0):
    rows = [(0.0, 1500.0, 2000.0), (0.5, 1600.0, 4000.0), (2.0, 1700.0, 8000.0)]
    path.write_text(
        "depth_m,density_kg_m3,strength_pa\n"
        + "".join(f"{z},{rho},{su * strength_factor}\n" for z, rho, su in rows)
    )


def test_resume_after_the_profile_csv_changed_matches_a_clean_run(tmp_path, monkeypatch, capsys):
    csv = tmp_path / "core.csv"
    write_csv(csv)
    scen = tmp_path / "scenario.toml"
    scen.write_text(dumps_toml(cheap(sediment={"file": "core.csv"})))
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 1)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(scen, seed=8, output=out)
    write_csv(csv, strength_factor=10.0)  # the core was re-measured
    counting(monkeypatch)
    resumed = run_ensemble(scen, seed=8, output=out)
    assert "discarding 1 finished chunk file(s)" in capsys.readouterr().err
    clean = run_ensemble(scen, seed=8)
    assert_bit_identical(resumed, clean)
    recorded = json.loads(xr.load_dataset(out).attrs["scenario"])["input_files"]
    assert list(recorded) == [str(csv.resolve())]
    import hashlib

    assert recorded[str(csv.resolve())] == hashlib.sha256(csv.read_bytes()).hexdigest()


def test_resume_after_an_empirical_distribution_file_changed(tmp_path, monkeypatch, capsys):
    data = tmp_path / "masses.csv"
    data.write_text("mass\n75.0\n80.0\n85.0\n")
    d = cheap()
    d["mine"]["mass"] = {"distribution": "empirical", "file": str(data), "column": "mass"}
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(d, seed=9, output=out)
    data.write_text("mass\n60.0\n65.0\n70.0\n")
    counting(monkeypatch)
    resumed = run_ensemble(d, seed=9, output=out)
    assert "discarding 2 finished chunk file(s)" in capsys.readouterr().err
    assert_bit_identical(resumed, run_ensemble(d, seed=9))
    assert resumed["input_mine_mass"].values.max() <= 70.0


def test_a_second_run_on_a_locked_output_is_refused(tmp_path, monkeypatch, capsys):
    from mineburial.cli import main

    scen = tmp_path / "scenario.toml"
    scen.write_text(dumps_toml(cheap()))
    out = tmp_path / "burial.nc"
    live = RunLock(parts_of(out), out).acquire()  # a live run holds the output
    try:
        calls = counting(monkeypatch)
        rc = main(["run", str(scen), "-o", str(out), "--quiet"])
        with pytest.raises(RunLockedError):  # the library refuses as well
            run_ensemble(cheap(), output=out)
    finally:
        live.release()
    err = capsys.readouterr().err
    assert rc == 2 and calls == []
    assert err.count("\n") == 1 and err.startswith("mineburial: error: output ")
    assert f"being written by another mineburial run (process {os.getpid()} on" in err
    assert "Traceback" not in err and not out.exists()


def test_a_stale_lock_of_a_dead_process_is_taken_over(tmp_path, capsys):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()  # its pid is not alive any more
    out = tmp_path / "burial.nc"
    store.own_folder(parts_of(out))  # as a killed run left it
    (parts_of(out) / "lock").write_text(
        json.dumps({"pid": dead.pid, "host": os.uname().nodename, "started": "2026-01-01T00:00:00Z"})
    )
    ds = run_ensemble(cheap(), n=4, seed=10, output=out)
    assert_bit_identical(ds, run_ensemble(cheap(), n=4, seed=10))
    assert out.exists() and not parts_of(out).exists()


def test_lock_is_released_when_a_run_is_interrupted(tmp_path, monkeypatch):
    out = tmp_path / "burial.nc"
    killed_after(monkeypatch, 1)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(cheap(), seed=11, output=out)
    RunLock(parts_of(out), out).acquire().release()  # free again


def test_per_drop_and_class_basis_do_not_change_the_run_identity():
    """The identity covers what decides the chunks, not what is made of them."""
    a = engine.load_ensemble(cheap(), seed=12)
    b = engine.load_ensemble(cheap(), seed=12, per_drop=False, class_basis="burial_height")
    c = engine.load_ensemble(cheap(), seed=13)
    d = engine.load_ensemble(cheap(), seed=12, chunk_size=3)
    assert store.run_identity(a) == store.run_identity(b)
    assert len({store.run_identity(x) for x in (a, c, d)}) == 3


def write_grid(path, depth):
    from mineburial.analyses.synthetic import synthetic_environment

    env = synthetic_environment(ny=2, nx=2, seed=1)  # 3 water cells, 1 land cell
    wet = np.isfinite(env["water_depth"].values)
    env["water_depth"].values[wet] = depth
    env["sediment_class"].values[wet] = 4  # stiff_clay
    env.to_netcdf(path)


def test_map_resume_after_the_environment_grid_changed_matches_a_clean_map(tmp_path, monkeypatch, capsys):
    from mineburial.analyses.maps import run_map

    env, out = tmp_path / "env.nc", tmp_path / "map.nc"
    scen = cheap()
    write_grid(env, 3.0)
    killed_after(monkeypatch, 3)
    with pytest.raises(KeyboardInterrupt):
        run_map(scen, env, n=2, seed=3, chunk_size=1, output=out)
    write_grid(env, 3.4)  # a new survey of the area
    calls = counting(monkeypatch)
    resumed = run_map(scen, env, n=2, seed=3, chunk_size=1, output=out)
    assert "discarding" in capsys.readouterr().err
    assert len(calls) == 6  # 3 cells x 2 chunks, all new
    assert_bit_identical(resumed, run_map(scen, env, n=2, seed=3, chunk_size=1))
    assert not parts_of(out).exists()
