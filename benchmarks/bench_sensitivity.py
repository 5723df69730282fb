"""Sobol' indices of the default ensemble for two seeds: is the ranking of the leading inputs stable?

Run:  python benchmarks/bench_sensitivity.py [-n 256] [--seeds 1 2] [--leading 3]

For each seed, ``mineburial sensitivity`` on the embedded default scenario (n (d + 2)
drops, d = 9 random inputs). The leading inputs are the ``--leading`` inputs of largest
total index S_Ti; the script prints both tables, both rankings, and whether the
leading inputs and their order agree (issue 10: "on the default ensemble the ranking of
the leading inputs is the same for two different seeds"). It also prints the cost.
"""

import argparse
import time

from _common import machine


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=256)
    ap.add_argument("--seeds", type=int, nargs=2, default=(1, 2))
    ap.add_argument("--leading", type=int, default=3)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--scenario", default=None)
    args = ap.parse_args()
    from mineburial.analyses.sensitivity import ranking, run_sensitivity, sensitivity_table

    print(f"machine: {machine()}")
    ranks = {}
    for seed in args.seeds:
        t0 = time.perf_counter()
        ds = run_sensitivity(args.scenario, args.n, seed, threads=args.threads)
        dt = time.perf_counter() - t0
        print(
            f"\nseed {seed}: {int(ds.attrs['n_evaluations'])} drops in {dt:.0f} s "
            f"({int(ds.attrs['n_evaluations']) / dt:.1f} drops/s; {ds.attrs['status_counts']})"
        )
        print(sensitivity_table(ds))
        ranks[seed] = {str(o): ranking(ds, str(o)) for o in ds.output.values}
    a, b = args.seeds
    ok = True
    for out in ranks[a]:
        la, lb = ranks[a][out][: args.leading], ranks[b][out][: args.leading]
        same = la == lb
        ok &= same
        print(
            f"\n{out}: leading {args.leading} by S_Ti, seed {a}: {la}; seed {b}: {lb} -> "
            f"{'same' if same else 'DIFFERENT'}"
        )
    print("\nranking of the leading inputs the same for both seeds:", "yes" if ok else "NO")


if __name__ == "__main__":
    main()
