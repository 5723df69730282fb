"""Sobol' vs Monte Carlo: error of the mean burial of the default ensemble at equal n.

Run:  python benchmarks/bench_sobol.py [-n 64] [--reference 1024] [--replicates 4]

The reference mean comes from one scrambled-Sobol' run of ``--reference`` drops;
each method is then run ``--replicates`` times (seeds 1, 2, ...) with ``-n`` drops
and the root-mean-square deviation of the estimated mean burial (by volume) from
the reference is printed. The test suite checks the same ordering on a shortened
variant (tests/test_ensemble.py); this script uses the unmodified default scenario.
"""

import argparse
import time

import numpy as np

from _common import machine


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=64)
    ap.add_argument("--reference", type=int, default=1024)
    ap.add_argument("--replicates", type=int, default=4)
    ap.add_argument("--scenario", default=None)
    args = ap.parse_args()
    from mineburial import run_ensemble

    print(f"machine: {machine()}")
    t0 = time.perf_counter()
    ref = run_ensemble(args.scenario, n=args.reference, seed=1000, sampling="sobol")
    mu = float(ref["burial_volume_mean"])
    print(f"reference (Sobol', n = {args.reference}): mean burial {mu:.3f} % "
          f"({time.perf_counter() - t0:.0f} s)")
    for method in ("mc", "sobol"):
        est = [float(run_ensemble(args.scenario, n=args.n, seed=s, sampling=method)
                     ["burial_volume_mean"]) for s in range(1, args.replicates + 1)]
        rms = float(np.sqrt(np.mean((np.array(est) - mu) ** 2)))
        print(f"{method:6s} n = {args.n}: estimates {np.round(est, 3).tolist()}  rms error {rms:.3f} %")


if __name__ == "__main__":
    main()
