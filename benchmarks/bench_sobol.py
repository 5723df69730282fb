"""Sobol' vs Monte Carlo: error of the mean burial of the default ensemble at equal n.

Run:  python benchmarks/bench_sobol.py [-n 64] [--reference 1024] [--replicates 4] [--short]

The reference mean comes from one scrambled-Sobol' run of ``--reference`` drops;
each method is then run ``--replicates`` times (seeds 1, 2, ...) with ``-n`` drops
and the root-mean-square deviation of the estimated mean burial (by volume) from
the reference is printed. The reference is itself a Sobol' estimate, so this is a
benchmark, not a test (it was one, moved here by issue 12; the test suite checks
Sobol' against Monte Carlo on integrals known exactly, tests/test_sampling.py).

``--short`` runs the former test's variant: every random input of the default kept, the
drops released 1 m above a 4.5-5.5 m deep seabed and stopped at 3 s (``-n 16
--reference 128`` reproduce it).
"""

import argparse
import copy
import time

import numpy as np
from _common import machine


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=64)
    ap.add_argument("--reference", type=int, default=1024)
    ap.add_argument("--replicates", type=int, default=4)
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--short", action="store_true", help="short drops (see the module docstring)")
    args = ap.parse_args()
    from mineburial import run_ensemble
    from mineburial.systems.mine.config import tomllib  # tomllib or the tomli fallback (Python 3.10)
    from mineburial.systems.mine.ensemble import DEFAULT_SCENARIO

    if args.short:
        with open(args.scenario or DEFAULT_SCENARIO, "rb") as fh:
            raw = copy.deepcopy(tomllib.load(fh))
        raw["environment"]["water_depth"] = {"distribution": "uniform", "low": 4.5, "high": 5.5}
        raw["release"]["position"] = [0.0, 0.0, -4.0]
        raw["numerics"]["t_max"] = 3.0
        raw["ensemble"]["per_drop"] = False
        args.scenario = raw

    print(f"machine: {machine()}")
    t0 = time.perf_counter()
    ref = run_ensemble(args.scenario, n=args.reference, seed=1000, sampling="sobol")
    mu = float(ref["burial_volume_mean"])
    print(
        f"reference (Sobol', n = {args.reference}): mean burial {mu:.3f} % ({time.perf_counter() - t0:.0f} s)"
    )
    for method in ("mc", "sobol"):
        est = [
            float(run_ensemble(args.scenario, n=args.n, seed=s, sampling=method)["burial_volume_mean"])
            for s in range(1, args.replicates + 1)
        ]
        rms = float(np.sqrt(np.mean((np.array(est) - mu) ** 2)))
        print(f"{method:6s} n = {args.n}: estimates {np.round(est, 3).tolist()}  rms error {rms:.3f} %")


if __name__ == "__main__":
    main()
