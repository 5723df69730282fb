"""The README's second ``mineburial run`` (numba's cache warm) by phase (issue 34 item 1: <= 10 s).

Run:  python benchmarks/bench_second_run.py [--runs 3] [--run-args "-n 2000"] [--profile FILE]

Each run is a fresh interpreter (bytecode cached, the numba cache where it is: run ``mineburial run``
once first to fill it) that times ``mineburial.cli.main(["run", "-o", OUT, "--quiet", ...])`` with
some of its functions wrapped (measurement only). Per phase it gives the wall seconds (inclusive, on
the thread that ran it), the process's CPU seconds (all threads) while it ran, the CPU seconds of
the thread that ran it ("own": the main thread's, except the self-check's, which runs on a thread of
its own, its drops on the pool's threads: the "CPU" column), and, of the wall,
how much went into imports that the phase triggered on its thread (the outermost
``importlib._bootstrap._find_and_load``):

* ``imports``: the interpreter's start to ``cli.main`` (``import mineburial.cli`` and what the
  ``run`` command imports before it loads the scenario);
* ``scenario``: ``engine.load_ensemble`` (resolving the scenario, the sediment and current banks;
  the first numba set-up comes later, with the first drop);
* ``sampling``: ``mine.chunk_inputs`` (the sampled inputs of each chunk, packed);
* ``ensemble``: ``batch.run_batch`` of the chunks (the drops on the thread pool; the first loads
  the compiled kernels from numba's cache: ``numba cache loads`` below, part of it);
* ``chunk files``: ``store.ChunkStore.save`` (each finished chunk written to ``OUT.parts/``);
* ``statistics``: ``statistics.burial_statistics`` (with the first xarray, pandas and dask.array
  imports: xarray builds a DataArray only after asking whether the data are a dask array);
* ``epistemic band``: ``epistemic.add_band``;
* ``dataset``: the rest of ``runner.ensemble_dataset`` (the per-drop variables, the attributes);
* ``self-check``: ``accuracy.self_check`` (its drops on the thread pool; since this branch it runs
  beside ``dataset`` and ``statistics``, so their wall overlaps);
* ``waiting for the self-check``: the main thread's wait for the check once the Dataset is built
  (this branch's ``runner._Beside.result``; 0 when the building took longer than the check);
* ``NetCDF write``: ``netcdf.write_netcdf``;
* ``numba cache loads``: numba's ``load_overload`` of each kernel (count, seconds), inside the phases.

The total is the interpreter's own wall and CPU (``resource``). ``--profile FILE`` runs one more
interpreter under ``cProfile`` (main thread only) and writes its stats to FILE, printing the
cumulative seconds of the same functions.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

SNIPPET = r"""
import sys, time, threading, resource, importlib._bootstrap as boot
W0 = time.perf_counter()
rows = {}          # phase -> [wall, cpu, import wall, calls]
depth = threading.local()
import_wall = [0.0]


def add(label, wall, cpu, imp, own=0.0):
    r = rows.setdefault(label, [0.0, 0.0, 0.0, 0, 0.0])
    r[0] += wall; r[1] += cpu; r[2] += imp; r[3] += 1; r[4] += own


_find_and_load = boot._find_and_load


def timed_find_and_load(name, import_):
    if getattr(depth, "n", 0) or threading.current_thread() is not threading.main_thread():
        return _find_and_load(name, import_)
    depth.n = 1
    t = time.perf_counter()
    try:
        return _find_and_load(name, import_)
    finally:
        depth.n = 0
        import_wall[0] += time.perf_counter() - t


boot._find_and_load = timed_find_and_load
import mineburial.cli as cli
from mineburial import _numba
from mineburial.systems.mine import accuracy, batch, dataset, epistemic, ensemble as mine
from mineburial.ensembles import engine, runner, store
from mineburial.io import netcdf


def wrap(mod, name, label, owner=None):
    f = getattr(owner or mod, name)

    def g(*a, **k):
        main = threading.current_thread() is threading.main_thread()
        w, c, i, o = time.perf_counter(), time.process_time(), import_wall[0], time.thread_time()
        try:
            return f(*a, **k)
        finally:
            imp = (import_wall[0] - i) if main else 0.0
            add(label, time.perf_counter() - w, time.process_time() - c, imp, time.thread_time() - o)

    setattr(owner or mod, name, g)


wrap(engine, "load_ensemble", "scenario")
wrap(mine, "chunk_inputs", "sampling")
wrap(batch, "run_batch", "ensemble")
wrap(store.ChunkStore, "save", "chunk files", owner=store.ChunkStore)
wrap(dataset, "burial_statistics", "statistics")
wrap(epistemic, "add_band", "epistemic band")
wrap(runner, "ensemble_dataset", "dataset (incl. statistics, band)")
wrap(accuracy, "self_check", "self-check")
wrap(store, "write_netcdf", "NetCDF write")
if hasattr(runner, "_Beside"):  # the check beside the dataset's building (this branch)
    wrap(runner._Beside, "result", "waiting for the self-check", owner=runner._Beside)
_load = _numba._checked_load_overload


def load(*a, **k):
    w = time.perf_counter()
    try:
        return _load(*a, **k)
    finally:
        add("numba cache loads", time.perf_counter() - w, 0.0, 0.0)


_numba._checked_load_overload = load
add("imports", time.perf_counter() - W0, time.process_time(), import_wall[0], time.thread_time())
w, c = time.perf_counter(), time.process_time()
cli.main(["run", "-o", sys.argv[1], "--quiet", *sys.argv[2:]])
add("cli.main", time.perf_counter() - w, time.process_time() - c, 0.0)
rows["cli.main"][4] = float("nan")
ru = resource.getrusage(resource.RUSAGE_SELF)
add("process", time.perf_counter() - W0, ru.ru_utime + ru.ru_stime, import_wall[0], time.thread_time())
import json
print(json.dumps(rows))
"""

ORDER = (
    "imports",
    "scenario",
    "sampling",
    "ensemble",
    "numba cache loads",
    "chunk files",
    "statistics",
    "epistemic band",
    "dataset (incl. statistics, band)",
    "self-check",
    "waiting for the self-check",
    "NetCDF write",
    "cli.main",
    "process",
)

PROFILED = {  # (file, function) listed from the cProfile run (main thread only)
    ("engine.py", "load_ensemble"),
    ("mine.py", "chunk_inputs"),
    ("batch.py", "run_batch"),
    ("statistics.py", "burial_statistics"),
    ("epistemic.py", "add_band"),
    ("runner.py", "ensemble_dataset"),
    ("runner.py", "_dataset_checked"),
    ("runner.py", "result"),
    ("accuracy.py", "self_check"),
    ("netcdf.py", "write_netcdf"),
    ("cli.py", "main"),
}


def one_run(run_args, env):
    with tempfile.TemporaryDirectory() as folder:
        out = subprocess.run(
            [sys.executable, "-c", SNIPPET, os.path.join(folder, "out.nc"), *run_args],
            env=env,
            cwd=folder,
            capture_output=True,
            text=True,
        )
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout.strip().splitlines()[-1])


def profile(path, run_args, env):
    import pstats

    with tempfile.TemporaryDirectory() as folder:
        argv = ["run", "-o", "out.nc", "--quiet", *run_args]
        code = f'import cProfile; import mineburial.cli as cli; cProfile.run("cli.main({argv!r})", {path!r})'
        subprocess.run([sys.executable, "-c", code], env=env, cwd=folder, check=True, capture_output=True)
    st = pstats.Stats(path)
    print(f"cProfile (main thread; {path}), cumulative s:")
    for (file, line, name), (_, _, _, ct, _) in sorted(st.stats.items(), key=lambda kv: -kv[1][3]):
        if (os.path.basename(file), name) in PROFILED and "mineburial" in file:
            print(f"  {ct:7.3f}  {os.path.basename(file)}:{line}({name})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--run-args", default="", help="more arguments of 'mineburial run' (e.g. '-n 200')")
    ap.add_argument("--profile", default=None, metavar="FILE", help="also one cProfile run, stats to FILE")
    args = ap.parse_args()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    run_args = args.run_args.split()
    runs = [one_run(run_args, env) for _ in range(args.runs)]
    print(f"'mineburial run {args.run_args}' by phase, {args.runs} fresh interpreter(s); median (min-max)")
    print(f"{'phase':34s} {'wall s':>18s} {'CPU s':>18s} {'own CPU s':>18s} {'imports s':>10s} {'calls':>6s}")

    def cell(values):
        return f"{statistics.median(values):6.2f} ({min(values):.2f}-{max(values):.2f})"

    for label in ORDER:
        got = [r[label] for r in runs if label in r]
        if not got:
            continue
        print(
            f"{label:34s} {cell([g[0] for g in got]):>18s} {cell([g[1] for g in got]):>18s} "
            f"{cell([g[4] for g in got]):>18s} {statistics.median(g[2] for g in got):10.2f} {got[0][3]:6d}"
        )
    if args.profile:
        profile(args.profile, run_args, env)


if __name__ == "__main__":
    main()
