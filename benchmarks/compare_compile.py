"""Cold compile of two trees side by side: the A/B that a shared 2-core machine can resolve.

Run:  python benchmarks/compare_compile.py TREE_A TREE_B [--rounds 4] [--path default|self-check]
      python benchmarks/compare_compile.py TREE_A TREE_B --warm 7

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

CODE = """
import sys, tempfile
sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_startup
reference = None if sys.argv[2] == "default" else sys.argv[2]
if len(sys.argv) > 3:  # a cache folder that stays (--warm)
    print(*bench_startup.measure(sys.argv[3], reference=reference))
else:
    with tempfile.TemporaryDirectory() as cache:
        print(*bench_startup.measure(cache, reference=reference))
"""


def _start(tree, core, path, cache=None):
    env = {**os.environ, "PYTHONPATH": tree}
    pinned = ["taskset", "-c", str(core)] if core is not None else []
    command = [*pinned, sys.executable, "-c", CODE, tree, path, *([cache] if cache else [])]
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _result(tree, run) -> list[float]:
    """(import wall s, total wall s, CPU s) of a finished measurement."""
    out, err = run.communicate()
    if run.returncode != 0:
        sys.exit(f"{tree}: the measurement failed:\n{err[-2000:]}")
    return [float(x) for x in out.split()[-3:]]


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
    args = parser.parse_args(argv)
    trees = [os.path.abspath(t) for t in args.trees]
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
