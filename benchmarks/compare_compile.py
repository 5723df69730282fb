"""Two trees side by side (cold compile, warm start, throughput): the A/B a shared 2-core machine can resolve.

Run:  python benchmarks/compare_compile.py TREE_A TREE_B [--rounds 4] [--path default|self-check]
      python benchmarks/compare_compile.py TREE_A TREE_B --warm 7
      python benchmarks/compare_compile.py TREE_A TREE_B --throughput SCENARIO.toml [--rounds 6] [-n 1000]

Each round compiles both trees at the same time, one on each core (``taskset``; the cores are swapped
every round), each in a fresh ``NUMBA_CACHE_DIR``, by the tree's own ``bench_startup.measure()`` (imports,
one drop of the default ensemble through the batch driver, or of the self-check's path). Both see the same
load from the machine's other tenants, so their difference per round is steadier than two runs one after
the other (on the shared host single runs of one tree moved by +-5 s; session 11, docs/design.md).
Prints each round's CPU s of both, their medians and the differences B - A. Linux only (``taskset``).

``--warm N`` compares the warm start instead: both trees first fill a cache folder of their own (side by
side, as above), then ``bench_startup.measure()`` runs from those caches N times per tree, one run at a
time, the trees alternated (A B, B A, ...): wall s to the end of the first drop, and of the imports.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile

#: the first lines of each measurement. It runs in the tree (cwd), and a `python -c` puts its working
#: directory first on sys.path, so it imports the tree's mineburial; started in another checkout it would
#: import that checkout's whatever PYTHONPATH says, so any other origin ends the measurement
OWN_TREE = """
import os, sys
import mineburial
if not mineburial.__file__.startswith(os.path.join(os.getcwd(), "")):
    sys.exit(f"imported {mineburial.__file__}, not the tree's")
"""

#: the start-up of one tree: its own bench_startup.measure(), whose fresh interpreter runs in the tree too
CODE = (
    OWN_TREE
    + """
import tempfile
sys.path.insert(0, "benchmarks")
import bench_startup
reference = None if sys.argv[1] == "default" else sys.argv[1]
if len(sys.argv) > 2:  # a cache folder that stays (--warm)
    print(*bench_startup.measure(sys.argv[2], reference=reference))
else:
    with tempfile.TemporaryDirectory() as cache:
        print(*bench_startup.measure(cache, reference=reference))
"""
)


#: the batch driver's best of three over the scenario's first n drops, one numba thread: wall s, CPU s
THROUGHPUT = (
    OWN_TREE
    + """
import time, numba
numba.set_num_threads(1)
from mineburial.systems.mine.batch import run_batch
from mineburial.ensembles.engine import load_ensemble
from mineburial.systems.mine.ensemble import chunk_inputs
spec = load_ensemble(sys.argv[1])
P, valid, _ = chunk_inputs(spec, 0, int(sys.argv[2]))
run_batch(P[:1], valid[:1], spec.sediment_bank, spec.current_bank)
best = (float("inf"), float("inf"))
for _ in range(3):
    wall, cpu = time.perf_counter(), time.process_time()
    run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    best = min(best, (time.perf_counter() - wall, time.process_time() - cpu))
print(*best)
"""
)


def _launch(tree, core, code, args, cache=None):
    env = {**os.environ, "PYTHONPATH": tree}
    if cache:
        env.update(NUMBA_CACHE_DIR=cache, MINEBURIAL_NUMBA_CACHE="1")
    pinned = ["taskset", "-c", str(core)] if core is not None else []
    command = [*pinned, sys.executable, "-c", code, *args]
    # cwd: the tree, whose mineburial a `python -c` then imports (its working directory is first on sys.path)
    return subprocess.Popen(
        command, env=env, cwd=tree, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def _start(tree, core, path, cache=None):
    return _launch(tree, core, CODE, [path, *([cache] if cache else [])])


def _result(tree, run, count=3) -> list[float]:
    """The last ``count`` numbers a finished measurement printed: (import wall s, total wall s, CPU s)
    of a start-up, (wall s, CPU s) of a throughput run."""
    out, err = run.communicate()
    if run.returncode != 0:
        sys.exit(f"{tree}: the measurement failed:\n{err[-2000:]}")
    return [float(x) for x in out.split()[-count:]]


def throughput(trees, rounds, scenario, n):
    """The batch driver's speed on one thread, both trees side by side, each from a cache it filled first."""
    args = [os.path.abspath(scenario), str(n)]
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        caches = dict(zip(trees, (a, b)))
        fills = {t: _launch(t, c, THROUGHPUT, [args[0], "1"], caches[t]) for t, c in zip(trees, (0, 1))}
        for tree, run in fills.items():
            _result(tree, run, 2)
        times = {t: [] for t in trees}
        for k in range(rounds):
            cores = (0, 1) if k % 2 == 0 else (1, 0)
            runs = {t: _launch(t, c, THROUGHPUT, args, caches[t]) for t, c in zip(trees, cores)}
            for tree, run in runs.items():
                times[tree].append(_result(tree, run, 2))
            print(
                f"round {k}: "
                + "   ".join(f"{t} {times[t][-1][0]:.3f} s wall {times[t][-1][1]:.3f} s CPU" for t in trees),
                flush=True,
            )
    a, b = trees
    for i, what in enumerate(("wall", "CPU")):
        ratios = [y[i] / x[i] - 1.0 for x, y in zip(times[a], times[b])]
        print(
            f"{what} s of {n} drops: median A {statistics.median(x[i] for x in times[a]):.3f}, "
            f"B {statistics.median(x[i] for x in times[b]):.3f}; B/A - 1 per round "
            + ", ".join(f"{100 * r:+.1f} %" for r in ratios)
            + f" (median {100 * statistics.median(ratios):+.1f} %)"
        )


def warm(trees, rounds, path):
    """The warm start of both trees, alternated, each from a cache folder it filled first."""
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        caches = dict(zip(trees, (a, b)))
        fills = {t: _start(t, c, path, caches[t]) for t, c in zip(trees, (0, 1))}
        for tree, run in fills.items():
            _result(tree, run)
        wall = {t: [] for t in trees}
        for k in range(rounds):
            for tree in trees if k % 2 == 0 else trees[::-1]:
                t_import, total, _ = _result(tree, _start(tree, None, path, caches[tree]))
                wall[tree].append(total)
                print(f"round {k}: {tree} {total:.3f} s wall (imports {t_import:.3f})", flush=True)
    medians = [statistics.median(wall[t]) for t in trees]
    print(f"median: A {medians[0]:.3f}, B {medians[1]:.3f} s wall (warm start)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", nargs=2, help="two source trees (each with mineburial/ and benchmarks/)")
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--path", choices=("default", "self-check"), default="default")
    parser.add_argument("--warm", type=int, metavar="N", help="compare the warm start, N runs per tree")
    parser.add_argument("--throughput", metavar="SCENARIO", help="compare the batch driver's drops/s on it")
    parser.add_argument("-n", type=int, default=1000, help="drops per throughput run (default 1000)")
    args = parser.parse_args(argv)
    trees = [os.path.abspath(t) for t in args.trees]
    if args.throughput:
        throughput(trees, args.rounds, args.throughput, args.n)
        return
    if args.warm:
        warm(trees, args.warm, args.path)
        return
    cpu = {t: [] for t in trees}
    for k in range(args.rounds):
        cores = (0, 1) if k % 2 == 0 else (1, 0)
        runs = {t: _start(t, c, args.path) for t, c in zip(trees, cores)}
        for tree, run in runs.items():
            cpu[tree].append(_result(tree, run)[2])
        print(f"round {k}: " + "   ".join(f"{t} {cpu[t][-1]:.2f} s CPU" for t in trees), flush=True)
    a, b = trees
    medians = statistics.median(cpu[a]), statistics.median(cpu[b])
    print(f"median: A {medians[0]:.2f}, B {medians[1]:.2f} s CPU ({args.path} path)")
    print("B - A per round: " + ", ".join(f"{y - x:+.2f}" for x, y in zip(cpu[a], cpu[b])))


if __name__ == "__main__":
    main()
