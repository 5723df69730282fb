"""Throughput A/B of two trees: ``bench_ensemble.py`` in each, alternated, medians per thread count.

Run (on a quiet host; each tree a checkout or a ``git archive`` of a commit, with its own numba cache):

    python benchmarks/ab_throughput.py /tmp/ab-base /tmp/ab-new [-n 1000] [--rounds 4] [--max-threads 2]
           [--scenario FILE]

Each tree's own ``benchmarks/bench_ensemble.py`` runs in a fresh interpreter with ``PYTHONPATH`` set to
the tree and the tree as working directory (so each imports its own ``mineburial``; the script checks
it), first once at 64 drops to fill the tree's numba cache, then ``--rounds`` times alternated A, B,
B, A, ... (so a drift of the host's load hits both alike). Prints every round and the medians of
drops/s per thread count and the ratio B / A. The drops are the ensemble's first ``n`` in both trees:
equal work only where the two trees sample the same inputs (the default ensemble does since the
posterior of 290820d; check with ``profile_speed.py``, which prints each tree's sum of penetrations).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys


def run(tree, n, max_threads, scenario):
    tree = os.path.abspath(tree)
    cmd = [sys.executable, "benchmarks/bench_ensemble.py", "-n", str(n), "--max-threads", str(max_threads)]
    if scenario:
        cmd += ["--scenario", os.path.abspath(scenario)]
    env = dict(os.environ, PYTHONPATH=tree)
    check = subprocess.run(
        [sys.executable, "-c", "import mineburial; print(mineburial.__file__)"],
        env=env,
        cwd=tree,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    if not check.startswith(tree):
        raise SystemExit(f"ab_throughput: {tree} imports mineburial from {check}")
    out = subprocess.run(cmd, env=env, cwd=tree, capture_output=True, text=True, check=True).stdout
    rates = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\d+)\s+\d+\s+[\d.]+\s+([\d.]+)\s+[\d.]+\s*$", line)
        if m:
            rates[int(m.group(1))] = float(m.group(2))
    return rates


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("-n", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--max-threads", type=int, default=2)
    ap.add_argument("--scenario", default=None)
    args = ap.parse_args()
    trees = {"A": args.a, "B": args.b}
    for tree in trees.values():  # fill each tree's cache
        run(tree, 64, 1, args.scenario)
    got = {"A": [], "B": []}
    for r in range(args.rounds):
        order = ("A", "B") if r % 2 == 0 else ("B", "A")
        for key in order:
            rates = run(trees[key], args.n, args.max_threads, args.scenario)
            got[key].append(rates)
            print(
                f"round {r} {key} ({trees[key]}): "
                + ", ".join(f"{t} thr {v:.1f}/s" for t, v in rates.items())
            )
    print()
    for t in sorted(got["A"][0]):
        ma = statistics.median(x[t] for x in got["A"])
        mb = statistics.median(x[t] for x in got["B"])
        print(f"{t} thread(s): median A {ma:.1f} drops/s, B {mb:.1f} drops/s, B/A {mb / ma:.3f}")


if __name__ == "__main__":
    main()
