"""Throughput of the per-drop uniforms (Philox Monte Carlo and scrambled Sobol').

Run:  python benchmarks/bench_sampling.py [-n 500000] [--fields 10]

Prints the best of three wall times of ``uniforms`` for ``n`` drops and ``--fields``
fields, as numbers per second. The target (formerly a timed assertion in the test suite)
is at least 1e7 Monte Carlo numbers per second on one core.
"""

import argparse

from _common import best_of, machine


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=500_000, help="drops")
    ap.add_argument("--fields", type=int, default=10, help="random fields per drop")
    args = ap.parse_args()
    from mineburial.ensembles.sampling import uniforms

    print(f"machine: {machine()}")
    names = [f"f.x{k}" for k in range(args.fields)]
    for method in ("mc", "sobol"):
        uniforms(1, names, 0, 10, method)  # compile / load the cached kernels
        best, _ = best_of(lambda method=method: uniforms(1, names, 0, args.n, method))
        rate = args.n * args.fields / best
        note = "  (target >= 1e7 /s)" if method == "mc" else ""
        print(f"{method:6s} {args.n} x {args.fields}: {best:.3f} s, {rate:.3g} numbers/s{note}")


if __name__ == "__main__":
    main()
