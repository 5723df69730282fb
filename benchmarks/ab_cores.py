"""Speed of two trees on the same drops, side by side in time: one tree a core, at once, then swapped.

Run:  python benchmarks/ab_cores.py /tmp/ab-base /tmp/ab-new [-n 200] [--reps 6] [--rounds 4]
      [--scenario FILE]

Why (issue 34 item 4): on the shared 2-core host the speed drifts by tens of per cent within minutes,
so ``ab_throughput.py``'s alternated rounds (A, then B) scatter by +-0.3 in their ratio. Here each round
runs both trees *at the same moment*, tree A pinned to one core and tree B to the other (then the
cores swapped, so that a difference between the cores cancels), each on one thread over the
ensemble's first ``n`` drops ``--reps`` times in a row, started together (a file barrier after both
have loaded their cache), and keeps each run's fastest repetition: the host's slow moments make a
repetition slower, never faster, so the best of several is the stable statistic (its spread between
rounds was +-2 % where the alternated rounds' medians moved by +-10 %).

Each tree runs its own ``stepper.run_drop`` on the rows its own ``chunk_inputs`` samples (a fresh
interpreter, ``PYTHONPATH`` set to the tree, the tree as working directory, its own numba cache, filled
first): the per-drop speed of the engine on one core, without the batch's threads (``ab_throughput.py``
measures those). Prints each run's best and mean drops/s, the medians per tree, the ratio B / A of the
medians and of each round's pair, and the sums of penetrations (equal where the trees give the same
answers on the same drops).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def worker(args):
    """One tree on one core: load, wait at the barrier, run the drops ``reps`` times, print JSON."""
    os.sched_setaffinity(0, {args.cpu})
    sys.path.insert(0, HERE)
    import numba
    from profile_speed import Drops

    numba.set_num_threads(1)
    drops = Drops(args.scenario, args.n)  # compiled or loaded before the timing
    if args.barrier:
        open(f"{args.barrier}.{args.cpu}", "w").close()
        deadline = time.monotonic() + 600.0
        while not all(os.path.exists(f"{args.barrier}.{c}") for c in (0, 1)):
            if time.monotonic() > deadline:
                raise SystemExit("ab_cores: the other tree never reached the barrier")
            time.sleep(0.005)
    rates = []
    for _ in range(args.reps):
        t = time.perf_counter()
        for i in range(len(drops)):
            drops.run(i)
        rates.append(len(drops) / (time.perf_counter() - t))
    print(json.dumps({"rates": rates, "drops": len(drops), "penetrations": drops.penetrations()}))


def launch(tree, cpu, args, barrier):
    tree = os.path.abspath(tree)
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", "--cpu", str(cpu), "-n", str(args.n)]
    cmd += ["--reps", str(args.reps)]
    if args.scenario:
        cmd += ["--scenario", os.path.abspath(args.scenario)]
    if barrier:
        cmd += ["--barrier", barrier]
    env = dict(os.environ, PYTHONPATH=tree, NUMBA_NUM_THREADS="1")
    return subprocess.Popen(cmd, env=env, cwd=tree, stdout=subprocess.PIPE, text=True)


def finish(proc):
    out, _ = proc.communicate()
    if proc.returncode != 0:
        raise SystemExit(f"ab_cores: a worker failed (exit status {proc.returncode})")
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a", nargs="?", help="tree A (a checkout or a git archive)")
    ap.add_argument("b", nargs="?", help="tree B")
    ap.add_argument("-n", type=int, default=200, help="drops (the ensemble's first n)")
    ap.add_argument("--reps", type=int, default=6, help="repetitions a run (the best counts)")
    ap.add_argument("--rounds", type=int, default=4, help="rounds (A on core 0, B on 1; swapped)")
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--cpu", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--barrier", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    if not (args.a and args.b):
        ap.error("two trees are needed")
    if not {0, 1} <= os.sched_getaffinity(0):
        raise SystemExit("ab_cores: needs cores 0 and 1 (one tree a core)")
    trees = {"A": args.a, "B": args.b}
    for tree in trees.values():  # fill each tree's cache, one after the other
        check = argparse.Namespace(**{**vars(args), "reps": 1, "n": 8})
        finish(launch(tree, 0, check, None))
    best = {"A": [], "B": []}
    pens = {}
    pairs = []
    with tempfile.TemporaryDirectory(prefix="mb-abcores-") as folder:
        for r in range(args.rounds):
            for swap in (False, True):
                cpus = {"A": 1, "B": 0} if swap else {"A": 0, "B": 1}
                barrier = os.path.join(folder, f"round{r}{'s' if swap else ''}")
                procs = {k: launch(trees[k], cpus[k], args, barrier) for k in trees}
                res = {k: finish(p) for k, p in procs.items()}
                line = []
                for k in trees:
                    b = max(res[k]["rates"])
                    best[k].append(b)
                    pens[k] = res[k]["penetrations"]
                    mean = statistics.mean(res[k]["rates"])
                    line.append(f"{k} core {cpus[k]}: best {b:.1f}, mean {mean:.1f}")
                pairs.append(best["B"][-1] / best["A"][-1])
                print(f"round {r}{' (swapped)' if swap else ''}: " + "; ".join(line) + " drops/s", flush=True)
    ma, mb = statistics.median(best["A"]), statistics.median(best["B"])
    print(f"\nA {trees['A']}: median of the best repetitions {ma:.1f} drops/s")
    print(f"B {trees['B']}: median of the best repetitions {mb:.1f} drops/s")
    print(
        f"B / A: {mb / ma:.3f} (the rounds' pairs: mean {statistics.mean(pairs):.3f}, "
        f"min {min(pairs):.3f}, max {max(pairs):.3f})"
    )
    same = pens["A"] == pens["B"]
    print(
        f"sums of penetrations: A {pens['A']:.9f} m, B {pens['B']:.9f} m"
        f" ({'the same answers' if same else 'the answers differ'})"
    )


if __name__ == "__main__":
    main()
