"""Ensemble throughput: drops/s on the default scenario with 1 and 2 threads.

Run:  python benchmarks/bench_ensemble.py [-n 64] [--scenario FILE]

Reports the compile (or cache-load) time of the batch kernel separately, then the
drops/s of the compiled batch driver (threads over a GIL-free loop) on the embedded default soft-mud ensemble
for 1, 2, ... threads (up to the cores available), and the parallel efficiency
(speed-up / threads). Sampling and statistics are excluded: the timed part is
``run_batch`` on pre-sampled parameter rows, the same rows for every thread count.
"""

import argparse
import os
import time

import numpy as np
from _common import machine


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=64, help="drops per measurement")
    ap.add_argument("--scenario", default=None, help="ensemble scenario (default: embedded)")
    ap.add_argument("--max-threads", type=int, default=None)
    args = ap.parse_args()
    import numba

    print(f"machine: {machine()}")
    t0 = time.perf_counter()
    from mineburial.ensembles.engine import load_ensemble
    from mineburial.systems.mine.batch import run_batch
    from mineburial.systems.mine.ensemble import chunk_inputs

    spec = load_ensemble(args.scenario)
    P, valid, _ = chunk_inputs(spec, 0, args.n)
    run_batch(P[:1], valid[:1], spec.sediment_bank, spec.current_bank)
    print(f"compile or cache load of the batch kernel + first drop: {time.perf_counter() - t0:.1f} s")
    cores = args.max_threads or len(os.sched_getaffinity(0))
    base = None
    print(f"{'threads':>7s} {'drops':>6s} {'time [s]':>9s} {'drops/s':>8s} {'efficiency':>10s}")
    ref = None
    for th in range(1, cores + 1):
        numba.set_num_threads(th)
        t = time.perf_counter()
        summary, status = run_batch(P, valid, spec.sediment_bank, spec.current_bank)
        el = time.perf_counter() - t
        if ref is None:
            ref = summary
        else:  # same results whatever the thread count
            assert np.array_equal(ref, summary, equal_nan=True)
        rate = args.n / el
        base = base or rate
        print(f"{th:7d} {args.n:6d} {el:9.2f} {rate:8.2f} {rate / base / th:10.2f}")


if __name__ == "__main__":
    main()
