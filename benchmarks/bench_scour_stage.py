"""Cost of the post-impact scour stage per drop against the impact phase (issue 20).

Run:  python benchmarks/bench_scour_stage.py [-n 200] [--repeat 3]

The stage (mineburial.kernels.mine.scour.scour_stage) runs over a 90-day hourly forcing (2,161
samples, 2,160 intervals: a synthetic series of storms and a tidal current) once per drop, each
drop with its own initial burial; the JONSWAP orbital table is built once (its time is reported
apart: it is shared by every drop of a run). The impact phase is measured as bench_ensemble.py
does: ``run_batch`` on ``n`` pre-sampled drops of the embedded default scenario, one thread,
after the compile; and, for the user's view, ``mineburial.run_ensemble`` on the same ``n`` drops
(sampling and statistics included). Both phases are timed alternately, best of ``--repeat``, so
that the load of a shared machine affects them alike.
"""

import argparse
import math
import time

import numpy as np
from _common import best_of, machine


def forcing_90_days():
    """A 90-day hourly series: a background sea with three storms (Hs up to 3 m), a tidal current."""
    t = np.arange(90 * 24 + 1) * 3600.0
    days = t / 86400.0
    hs = 0.6 + sum(2.4 * np.exp(-(((days - c) / 1.5) ** 2)) for c in (12.0, 41.0, 70.0))
    tp = 6.0 + 2.5 * hs
    wdir = np.full(t.size, math.radians(30.0))
    uc = 0.25 * np.abs(np.sin(2 * math.pi * t / (12.42 * 3600.0)))
    cdir = np.where(np.sin(2 * math.pi * t / (12.42 * 3600.0)) > 0, 0.0, math.pi)
    h = 13.0 + 0.4 * np.sin(2 * math.pi * t / (12.42 * 3600.0))
    return t, hs, tp, wdir, uc, cdir, h


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=200, help="drops per measurement")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    import numba

    from mineburial import run_ensemble
    from mineburial.ensembles.engine import load_ensemble
    from mineburial.kernels.mine import scour as S
    from mineburial.systems.mine.batch import run_batch
    from mineburial.systems.mine.ensemble import chunk_inputs

    print(f"machine: {machine()}")
    numba.set_num_threads(1)
    spec = load_ensemble(None)
    P, valid, _ = chunk_inputs(spec, 0, args.n)
    t0 = time.perf_counter()
    run_batch(P[:1], valid[:1], spec.sediment_bank, spec.current_bank)
    print(f"impact: compile or cache load + first drop {time.perf_counter() - t0:.1f} s")

    forcing = forcing_90_days()
    leads = np.array([1.0, 7.0, 14.0, 30.0, 60.0, 90.0]) * 86400.0
    fractions = np.array([0.5, 0.75, 1.0])
    out_b = np.empty(leads.size)
    out_t = np.empty(fractions.size)
    b0 = np.random.default_rng(0).uniform(0.0, 0.1, args.n)
    params = {kind: S.default_parameters(orbital=kind) for kind in (S.ORBITAL_SPECTRAL, S.ORBITAL_HRMS)}
    # the scour-and-settle law with the pocket mobility (issue 33): pit and mine as two states
    settle = S.default_parameters(burial_law=S.BURIAL_SCOUR_SETTLE, mobility=S.MOBILITY_POCKET)
    t0 = time.perf_counter()
    S.scour_stage(params[0], *forcing, np.zeros((2, S.TABLE_N)), leads, fractions, out_b, out_t)
    print(f"scour stage: compile or cache load {time.perf_counter() - t0:.1f} s")
    t0 = time.perf_counter()
    table = S.build_orbital_table()
    print(f"JONSWAP orbital table (once per run): {time.perf_counter() - t0:.3f} s (incl. any compile)")
    table_time, _ = best_of(S.build_orbital_table, 1)
    print(f"JONSWAP orbital table, compiled: {table_time:.3f} s")

    def stage(p):
        buried = 0
        for i in range(args.n):
            p[S.S_B0] = b0[i]
            status, _, _ = S.scour_stage(p, *forcing, table, leads, fractions, out_b, out_t)
            assert status == S.SCOUR_OK
            buried += out_b[-1] >= 0.5 * p[S.S_DIAMETER]
        return buried

    def impact():
        return run_batch(P, valid, spec.sediment_bank, spec.current_bank)

    best = {"impact": math.inf, "spectral": math.inf, "hrms": math.inf, "settle": math.inf}
    for _ in range(args.repeat):
        best["impact"] = min(best["impact"], best_of(impact, 1)[0])
        el, buried = best_of(lambda: stage(params[S.ORBITAL_SPECTRAL]), 1)
        best["spectral"] = min(best["spectral"], el)
        best["hrms"] = min(best["hrms"], best_of(lambda: stage(params[S.ORBITAL_HRMS]), 1)[0])
        best["settle"] = min(best["settle"], best_of(lambda: stage(settle), 1)[0])
    run_ensemble(n=args.n, threads=1)  # warm
    ens, _ = best_of(lambda: run_ensemble(n=args.n, threads=1), args.repeat)

    n = args.n
    steps = forcing[0].size - 1
    print(f"drops: {n}; forcing: {steps} hourly intervals (90 days); one thread; best of {args.repeat}")
    print(f"{'phase':<44s} {'per drop [ms]':>13s} {'drops/s':>9s}")
    for name, el in (
        ("impact, run_batch (default scenario)", best["impact"]),
        ("impact, run_ensemble (sampling + statistics)", ens),
        ("scour stage, spectral orbital velocity", best["spectral"]),
        ("scour stage, monochromatic H_rms", best["hrms"]),
        ("scour stage, scour_settle law (spectral)", best["settle"]),
    ):
        print(f"{name:<44s} {1e3 * el / n:13.3f} {n / el:9.1f}")
    print(f"scour stage per forcing interval: {1e9 * best['spectral'] / n / steps:.0f} ns (spectral)")
    print(f"scour stage / impact (run_batch): {best['spectral'] / best['impact']:.3f} (spectral)")
    print(f"scour stage / impact (run_batch): {best['settle'] / best['impact']:.3f} (scour_settle)")
    print(f"drops with B/D >= 0.5 at 90 days: {buried} of {n}")


if __name__ == "__main__":
    main()
