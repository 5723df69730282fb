"""Cold compile of two trees side by side: the A/B that a shared 2-core machine can resolve.

Run:  python benchmarks/compare_compile.py TREE_A TREE_B [--rounds 4] [--path default|self-check]

Each round compiles both trees at the same time, one on each core (``taskset``; the cores are swapped
every round), each in a fresh ``NUMBA_CACHE_DIR``, by the tree's own ``bench_startup.measure()`` (imports,
one drop of the default ensemble through the batch driver, or of the self-check's path). Both see the same
load from the machine's other tenants, so their difference per round is steadier than two runs one after
the other (on the shared host single runs of one tree moved by +-5 s; session 11, docs/design.md).
Prints each round's CPU s of both, their medians and the differences B - A. Linux only (``taskset``).
"""

import argparse
import os
import statistics
import subprocess
import sys

CODE = """
import sys, tempfile
sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_startup
with tempfile.TemporaryDirectory() as cache:
    reference = None if sys.argv[2] == "default" else sys.argv[2]
    print(bench_startup.measure(cache, reference=reference)[2])
"""


def _start(tree, core, path):
    env = {**os.environ, "PYTHONPATH": tree}
    command = ["taskset", "-c", str(core), sys.executable, "-c", CODE, tree, path]
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", nargs=2, help="two source trees (each with mineburial/ and benchmarks/)")
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--path", choices=("default", "self-check"), default="default")
    args = parser.parse_args(argv)
    trees = [os.path.abspath(t) for t in args.trees]
    cpu = {t: [] for t in trees}
    for k in range(args.rounds):
        cores = (0, 1) if k % 2 == 0 else (1, 0)
        runs = {t: _start(t, c, args.path) for t, c in zip(trees, cores)}
        for tree, run in runs.items():
            out, err = run.communicate()
            if run.returncode != 0:
                sys.exit(f"{tree}: the compile failed:\n{err[-2000:]}")
            cpu[tree].append(float(out.split()[-1]))
        print(f"round {k}: " + "   ".join(f"{t} {cpu[t][-1]:.2f} s CPU" for t in trees), flush=True)
    a, b = trees
    medians = statistics.median(cpu[a]), statistics.median(cpu[b])
    print(f"median: A {medians[0]:.2f}, B {medians[1]:.2f} s CPU ({args.path} path)")
    print("B - A per round: " + ", ".join(f"{y - x:+.2f}" for x, y in zip(cpu[a], cpu[b])))


if __name__ == "__main__":
    main()
