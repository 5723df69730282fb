"""Compile time and start-up: the engine from an empty numba cache, then with a warm one; and the
README's first command on a fresh install (``--fresh-install``).

Run:  python benchmarks/bench_startup.py [--repeat 3] [--cold-only] [--profile [N]]
      python benchmarks/bench_startup.py --phases 3
      python benchmarks/bench_startup.py --fresh-install [--runs 2] [--no-precompile]

Each measurement is a fresh interpreter that imports the engine, samples one drop of
the embedded default ensemble and runs it through the batch driver (what
``mineburial run`` does before its first chunk), timed from the start of the
interpreter's first import to the end of the drop:

* **cold**: numba's cache pointed at an empty folder (``NUMBA_CACHE_DIR``), so every
  kernel the default path needs is compiled: the cost a user pays once per installation;
* **warm**: the same again with the cache that the cold run filled: the start-up of
  every later run (imports + loading the compiled kernels).

Each line gives the wall time and the CPU time (user + system) of the interpreter: on a
shared machine the CPU time is the steadier measure of the compile work.

The reference paths (``rk4``, ``local_linear``, the reference sediment quadrature) are
compiled only when a drop asks for one (``stepper.reference_paths``); their cold compile
is measured separately ("cold, reference paths"). Issue 9 targets: cold <= 20 s,
warm <= 1 s on the 2-core development machine.

``--cold-only`` times only the cold compile of the default paths (``--repeat`` times).
``--profile N`` runs one cold compile of the default paths with numba's event API
(``numba.core.event``) listening, and lists the N costliest compile units (each
``@kernel`` compiled for one signature): CPU seconds of its own (its callees' compiles
taken out), split into numba's typing and lowering passes and the LLVM work inside
lowering (function passes, linking the callees' modules, module optimisation, machine
code), plus the CPU time spent writing the cache files. The LLVM split wraps numba's
``CPUCodeLibrary`` methods in that one process (measurement only).

``--phases N`` times N warm runs of the README's command 2 (``mineburial run`` in an empty folder,
the default job or ``--run-args``, the numba cache where it is: run one first to fill it) by phase,
each in a fresh interpreter with its functions wrapped (measurement only): imports, loading the
scenario (the first compiled kernel's load with numba's one-time set-up), the ensemble, the
statistics (``ensemble_dataset``, with the first ``xarray`` use), the self-check (since it runs
beside the statistics, ``runner._dataset_checked``: the wait for it after them), the NetCDF write
and the summary: wall and CPU seconds each (``benchmarks/bench_second_run.py`` times each phase on
its own thread); then, in another fresh interpreter, the CPU seconds of
the first imports in the order a run makes them (numpy, numba, scipy.special, the engine, xarray and
pandas, dask.array, distributed, netCDF4: the last three come through xarray when dask is
installed, issue 34 item 4).

``--fresh-install`` measures what a newcomer waits for (issue 34 item 1): a ``git clone`` of this
repository's committed HEAD (``--source``) and a fresh virtual environment, then the README's
command 1 from the clone's root, ``python3 -m pip install . && mineburial run``, the install and each
of ``--runs`` runs of ``mineburial run`` timed apart (wall and CPU s), with the number of numba cache
indexes each run wrote (0: every kernel came from the cache that the build backend compiled at
install time, docs/design.md "Install-time cache"). ``--no-precompile`` installs with
``MINEBURIAL_PRECOMPILE=0`` (a wheel without cache: the first run compiles, as before issue 34). The
environment's ``NUMBA_CACHE_DIR``, ``MINEBURIAL_*`` and ``PYTHONPATH`` are not passed on.
"""

import argparse
import json
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

from _common import machine

SNIPPET = """
import time
t0 = time.perf_counter()
from mineburial.systems.mine.batch import run_batch
from mineburial.ensembles.engine import load_ensemble
from mineburial.systems.mine.ensemble import chunk_inputs
t_import = time.perf_counter() - t0
spec = load_ensemble(None)
P, valid, _ = chunk_inputs(spec, 0, 1)
if {reference!r} == "reference":
    from mineburial.kernels.mine import layout
    P[:, layout.P_INTEGRATOR] = layout.INTEGRATOR_NAMES.index("rk4")
    P[:, layout.P_SED_QUADRATURE] = layout.SEDIMENT_QUADRATURE_NAMES.index("reference")
elif {reference!r} == "self-check":
    from mineburial.systems.mine.accuracy import reference_params
    P = reference_params(P)
run_batch(P, valid, spec.sediment_bank, spec.current_bank)
print(t_import, time.perf_counter() - t0)
"""

# Listens to numba's compile events and times the LLVM stages; prints one JSON line.
PROFILER = """
import json, time
from collections import defaultdict
from numba.core import codegen, event, dispatcher

clock = time.thread_time
units = {}            # (name, signature) -> dict of seconds
stack = []            # open compile units: [key, start, child seconds, llvm dict]
llvm_stage = [None]   # LLVM stage being timed (stages nest: finalize inside lowering)


def _key(data):
    d = data["dispatcher"]
    return (f"{d.py_func.__module__}.{d.py_func.__qualname__}", str(tuple(data["args"])))


class Units(event.Listener):
    def on_start(self, ev):
        stack.append([_key(ev.data), clock(), 0.0, defaultdict(float)])

    def on_end(self, ev):
        key, t0, child, llvm = stack.pop()
        total = clock() - t0
        u = units.setdefault(key, defaultdict(float))
        u["own"] += total - child
        u["count"] += 1
        for k, v in llvm.items():
            u[k] += v
        if stack:
            stack[-1][2] += total


class Passes(event.Listener):
    # each pass's own CPU time: callees compiled inside it (typing) and passes nested in
    # it (the pipelines of inlined functions) taken out

    def __init__(self):
        self.open = []

    def on_start(self, ev):
        child = stack[-1][2] if stack else 0.0
        self.open.append([ev.data["name"].split(" [")[0], clock(), child, 0.0, len(stack)])

    def on_end(self, ev):
        name, t0, child0, nested, depth = self.open.pop()
        total = clock() - t0 - ((stack[-1][2] if stack else 0.0) - child0)
        if self.open and self.open[-1][4] == depth:
            self.open[-1][3] += total
        if stack:
            stack[-1][3]["pass:" + name] += total - nested


def _timed(cls, meth, label):
    orig = getattr(cls, meth)

    def wrapper(self, *a, **k):
        outer = llvm_stage[0]
        llvm_stage[0] = label
        t0 = clock()
        try:
            return orig(self, *a, **k)
        finally:
            dt = clock() - t0
            llvm_stage[0] = outer
            if stack:
                stack[-1][3][label] += dt
                if outer is not None:
                    stack[-1][3][outer] -= dt

    setattr(cls, meth, wrapper)


_timed(codegen.CPUCodeLibrary, "_optimize_functions", "llvm_function_passes")
_timed(codegen.CPUCodeLibrary, "finalize", "llvm_link_finalize")
_timed(codegen.CPUCodeLibrary, "_optimize_final_module", "llvm_module_passes")
_timed(codegen.JITCodeLibrary, "get_pointer_to_function", "llvm_machine_code")

save_time = defaultdict(float)
_save = dispatcher.Dispatcher._cache_class if hasattr(dispatcher.Dispatcher, "_cache_class") else None
from numba.core import caching
_orig_save = caching.Cache.save_overload
def _save_overload(self, sig, data):
    t0 = clock()
    try:
        return _orig_save(self, sig, data)
    finally:
        save_time[self._name] += clock() - t0
caching.Cache.save_overload = _save_overload

event.register("numba:compile", Units())
event.register("numba:run_pass", Passes())
"""

PROFILE_TAIL = """
rows = [dict(name=k[0], sig=k[1], **v) for k, v in units.items()]
print("PROFILE " + json.dumps(dict(units=rows, save=dict(save_time))))
"""


def _run(code, cache_dir):
    """Run ``code`` in a fresh interpreter with ``cache_dir`` as numba's cache; return its
    stdout and the CPU seconds (user + system) it used."""
    # bytecode written and read as for an installed package (pip compiles it at install):
    # with PYTHONDONTWRITEBYTECODE set, every start-up of a source tree compiled mineburial's
    # 61 modules again: 0.28-0.47 s of CPU against 0.12-0.18 s from bytecode (the loaded 2-core
    # host, 2026-11-27), a part of the "warm" start-up that no installation pays
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir, "MINEBURIAL_NUMBA_CACHE": "1"}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out.stdout, cpu


PHASES_SNIPPET = """
import sys, time
W0, C0 = time.perf_counter(), time.process_time()
marks = []


def mark(label):
    marks.append((label, time.perf_counter() - W0, time.process_time() - C0))


import mineburial.cli as cli
from mineburial.systems.mine import accuracy
from mineburial.ensembles import engine, runner, store
mark("imports")


def wrap(mod, name, before, after):
    f = getattr(mod, name)

    def g(*a, **k):
        mark(before)
        r = f(*a, **k)
        mark(after)
        return r

    setattr(mod, name, g)


wrap(engine, "load_ensemble", "-", "scenario loaded")
wrap(runner, "ensemble_dataset", "ensemble", "statistics")
if hasattr(runner, "_Beside"):  # the check runs beside the statistics: its phase is the wait after them
    wrap(runner._Beside, "result", "-", "self-check")
else:
    wrap(accuracy, "self_check", "-", "self-check")
wrap(store, "write_netcdf", "-", "NetCDF write")
cli.main(["run", "-o", "out.nc", "--quiet", *sys.argv[1:]])
mark("summary")
print(repr(marks))
"""

IMPORTS_SNIPPET = """
import time
T = time.process_time
out = []
t = T()
for name in ("numpy", "numba", "scipy.special", "mineburial.ensembles.runner", "xarray", "dask.array",
             "distributed", "netCDF4"):
    __import__(name)
    out.append((name, T() - t))
    t = T()
print(repr(out))
"""


def phases(runs: int, run_args=()) -> None:
    """Print the phases of ``runs`` warm runs of ``mineburial run`` (see the module)."""
    import ast

    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    rows = []
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as folder:
            out = subprocess.run(
                [sys.executable, "-c", PHASES_SNIPPET, *run_args],
                env=env,
                cwd=folder,
                capture_output=True,
                text=True,
            )
            if out.returncode != 0:
                raise SystemExit(out.stderr)
            marks = ast.literal_eval(out.stdout.strip().splitlines()[-1])
        kept, w0, c0 = [], 0.0, 0.0
        for label, w, c in marks:
            if label != "-":
                kept.append((label, w - w0, c - c0))
            w0, c0 = w, c
        rows.append(kept)
        print(
            "  ".join(f"{lab} {w:.2f}/{c:.2f}" for lab, w, c in kept), f"| total {w0:.2f} s wall", flush=True
        )
    med = [
        (lab, statistics.median(r[i][1] for r in rows), statistics.median(r[i][2] for r in rows))
        for i, (lab, _, _) in enumerate(rows[0])
    ]
    print("median of the runs (wall s / CPU s):", "  ".join(f"{lab} {w:.2f}/{c:.2f}" for lab, w, c in med))
    out = subprocess.run([sys.executable, "-c", IMPORTS_SNIPPET], env=env, capture_output=True, text=True)
    print("first imports, CPU s:", ", ".join(f"{n} {c:.2f}" for n, c in ast.literal_eval(out.stdout.strip())))


def measure(cache_dir, reference=None):
    """(import wall s, total wall s, total CPU s) of one start-up: of the default paths, or
    (``reference``) of the "reference" paths (``rk4`` and the reference sediment quadrature)
    or of the "self-check" path (``accuracy.reference_params``: the drop's own adaptive integrator
    at rtol 3e-5 with the reference sediment and overburden quadratures)."""
    stdout, cpu = _run(SNIPPET.format(reference=reference), cache_dir)
    t_import, total = map(float, stdout.splitlines()[-1].split())
    return t_import, total, cpu


def profile(top, dump=None, reference=None):
    """List the ``top`` costliest compile units of one cold compile of the default paths, or
    (``reference``, see :func:`measure`) of that path compiled after the default paths."""
    with tempfile.TemporaryDirectory() as cache:
        if reference:
            measure(cache)
        stdout, cpu = _run(PROFILER + SNIPPET.format(reference=reference) + PROFILE_TAIL, cache)
    lines = stdout.splitlines()
    data = json.loads(next(l for l in lines if l.startswith("PROFILE "))[8:])
    if dump:
        with open(dump, "w") as fh:
            json.dump(data, fh, indent=1)
    wall = float(lines[-2].split()[1])  # the snippet's line, before the PROFILE line
    units = data["units"]
    llvm_cols = ("llvm_function_passes", "llvm_module_passes", "llvm_link_finalize")
    for u in units:
        llvm = sum(u.get(k, 0.0) for k in llvm_cols)
        u["typing"] = u.get("pass:nopython_type_inference", 0.0)
        u["lowering"] = u.get("pass:native_lowering", 0.0) - llvm
        u["other"] = u["own"] - llvm - u["typing"] - u["lowering"]
    own_total = sum(u["own"] for u in units)
    save_total = sum(data["save"].values())
    print(f"machine: {machine()}")
    print(
        f"cold compile of the {reference or 'default'} paths: {cpu:.2f} s CPU, {wall:.2f} s wall; "
        f"{len(units)} compile units, {own_total:.2f} s CPU inside them, "
        f"{save_total:.2f} s writing cache files"
    )
    cols = ("own", "typing", "lowering", "other") + llvm_cols
    heads = ("own", "typing", "lower", "other", "fpass", "module", "link")
    print(" ".join(f"{h:>6}" for h in heads) + "  unit")
    for u in sorted(units, key=lambda u: -u["own"])[:top]:
        vals = " ".join(f"{u.get(c, 0.0):6.2f}" for c in cols)
        n = f" x{int(u['count'])}" if u["count"] > 1 else ""
        print(f"{vals}  {u['name'].replace('mineburial.', '')}{n} {u['sig'][:70]}")
    tot = {c: sum(u.get(c, 0.0) for u in units) for c in cols}
    print(" ".join(f"{tot[c]:6.2f}" for c in cols) + "  (all units)")
    passes = {}
    for u in units:
        for k, v in u.items():
            if k.startswith("pass:"):
                passes[k[5:]] = passes.get(k[5:], 0.0) + v
    print(
        "numba passes (CPU s, all units; NativeLowering includes the LLVM work): "
        + ", ".join(f"{k} {v:.2f}" for k, v in sorted(passes.items(), key=lambda kv: -kv[1])[:14])
    )
    print(
        "columns: own = the unit's CPU s without its callees' compiles; typing = numba's type "
        "inference; lower = numba's lowering to LLVM IR; other = numba's other IR passes; "
        "fpass, module = LLVM function and module passes; link = linking the callees' "
        "modules and machine code"
    )


#: variables of the caller's environment that a fresh install does not see
_NOT_PASSED = ("NUMBA_CACHE_DIR", "PYTHONPATH", "PYTHONDONTWRITEBYTECODE", "VIRTUAL_ENV", "PYTHONHOME")


def _timed(cmd, cwd, env):
    """(wall s, CPU s of the process and its children, stdout) of ``cmd``; exits on failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise SystemExit(f"{' '.join(map(str, cmd))} failed ({out.returncode}):\n{out.stderr[-3000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, out.stdout


def _indexes(folder: pathlib.Path) -> dict:
    """numba's cache indexes under ``folder`` and their modification times."""
    return {p: p.stat().st_mtime_ns for p in folder.rglob("__pycache__/*.nbi")}


def fresh_install(source, runs=2, precompile=True):
    """Time the README's command 1 on a fresh clone of ``source`` in a fresh venv (module doc)."""
    with tempfile.TemporaryDirectory(prefix="mineburial-fresh-") as tmp:
        tmp = pathlib.Path(tmp)
        clone, venv = tmp / "clone", tmp / "venv"
        subprocess.run(["git", "clone", "-q", str(source), str(clone)], check=True)
        head = subprocess.run(
            ["git", "-C", str(clone), "log", "-1", "--format=%h %s"], capture_output=True, text=True
        ).stdout.strip()
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        env = {
            k: v for k, v in os.environ.items() if k not in _NOT_PASSED and not k.startswith("MINEBURIAL_")
        }
        env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
        if not precompile:
            env["MINEBURIAL_PRECOMPILE"] = "0"
        print(f"machine: {machine()}; load average {os.getloadavg()[0]:.1f}")
        print(f"fresh clone of {source} at {head}; MINEBURIAL_PRECOMPILE={'1' if precompile else '0'}")
        wall, cpu, _ = _timed([venv / "bin" / "python3", "-m", "pip", "install", "-q", "."], clone, env)
        print(f"python3 -m pip install .: {wall:6.1f} s wall, {cpu:6.1f} s CPU", flush=True)
        _, _, where = _timed(
            [
                venv / "bin" / "python3",
                "-c",
                "import mineburial, os; print(os.path.dirname(mineburial.__file__))",
            ],
            tmp,
            env,
        )
        package = pathlib.Path(where.strip())
        shipped = len(_indexes(package))
        print(f"installed: {package} with {shipped} numba cache indexes")
        for i in range(runs):
            before = _indexes(package)
            wall, cpu, out = _timed([venv / "bin" / "mineburial", "run"], clone, env)
            after = _indexes(package)
            written = sum(1 for p, t in after.items() if before.get(p) != t)
            check = next((line for line in out.splitlines() if line.startswith("numerical self-check")), "")
            took = next((line for line in out.splitlines() if line.startswith("time:")), "")
            print(
                f"mineburial run #{i + 1}: {wall:6.1f} s wall, {cpu:6.1f} s CPU, {written} cache indexes "
                f"written; {took}; self-check {check.rsplit(';', 2)[-2].strip() if ';' in check else '?'}",
                flush=True,
            )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="warm start-ups to time (best kept)")
    ap.add_argument("--cold-only", action="store_true", help="time only cold compiles (--repeat of them)")
    ap.add_argument(
        "--profile",
        type=int,
        nargs="?",
        const=25,
        metavar="N",
        help="list the N costliest compile units of one cold compile",
    )
    ap.add_argument(
        "--profile-json", metavar="PATH", help="with --profile: also write every unit's times to PATH"
    )
    ap.add_argument(
        "--reference",
        choices=("reference", "self-check"),
        help="with --profile or --cold-only: the compile of these paths after the default paths' "
        "(reference: rk4 and the reference sediment quadrature; self-check: the path of "
        "systems/mine/accuracy.py)",
    )
    ap.add_argument(
        "--fresh-install",
        action="store_true",
        help="time the README's command 1 on a fresh clone in a fresh venv (install, then --runs runs)",
    )
    ap.add_argument("--runs", type=int, default=2, help="with --fresh-install: runs of 'mineburial run'")
    ap.add_argument("--phases", type=int, metavar="N", help="time N warm runs of 'mineburial run' by phase")
    ap.add_argument(
        "--run-args", default="", help="with --phases: more arguments of 'mineburial run' (e.g. '-n 200')"
    )
    ap.add_argument(
        "--no-precompile",
        action="store_true",
        help="with --fresh-install: install with MINEBURIAL_PRECOMPILE=0 (no install-time cache)",
    )
    ap.add_argument(
        "--source",
        default=str(pathlib.Path(__file__).resolve().parent.parent),
        help="with --fresh-install: the repository to clone (default: this one; its committed HEAD)",
    )
    args = ap.parse_args()
    if args.fresh_install:
        fresh_install(args.source, args.runs, not args.no_precompile)
        return
    if args.phases:
        phases(args.phases, args.run_args.split())
        return
    if args.profile:
        profile(args.profile, args.profile_json, args.reference)
        return
    print(f"machine: {machine()}")
    if args.cold_only:
        runs = []
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory() as cache:
                if args.reference:
                    measure(cache)
                runs.append(measure(cache, args.reference))
            print(
                f"cold (empty cache), {args.reference or 'default'} paths: {runs[-1][1]:6.2f} s wall, "
                f"{runs[-1][2]:6.2f} s CPU",
                flush=True,
            )
        print(
            f"median: {statistics.median(r[1] for r in runs):6.2f} s wall, "
            f"{statistics.median(r[2] for r in runs):6.2f} s CPU"
        )
        return
    with tempfile.TemporaryDirectory() as cache:
        imp, cold, cpu = measure(cache)
        print(f"cold (empty cache), default paths: {cold:6.2f} s  (imports {imp:.2f} s; CPU {cpu:.2f} s)")
        warm = min(measure(cache) for _ in range(args.repeat))
        print(
            f"warm (cache filled), default paths: {warm[1]:6.2f} s  "
            f"(imports {warm[0]:.2f} s; CPU {warm[2]:.2f} s)"
        )
        for reference in ("self-check", "reference"):
            imp, cold_ref, cpu = measure(cache, reference)
            print(f"cold, {reference} paths (compiled on first use): {cold_ref:6.2f} s  (CPU {cpu:.2f} s)")


if __name__ == "__main__":
    main()
