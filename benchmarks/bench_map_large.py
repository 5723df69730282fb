"""A 10^4-cell burial map at equal interval width: plain, sequential stopping, and cells with identical
inputs computed once (issue 34 item 5).

Run:  python benchmarks/bench_map_large.py [--ny 100] [--nx 100] [-n 100] [--target 0.1] [--min-drops 20]
      [--subset 200] [--out FOLDER]

The grid is the synthetic environment (mineburial.analyses.synthetic, ``ny`` x ``nx``; invented values) as a
chart product would give it: water depth in whole metres (soundings banded at 1 m) and no current layer (the
scenario's own current). The scenario is the shipped default (``mineburial example default_soft_mud``,
posterior coefficients). Equal interval width: a plain map runs ``n`` drops in every cell (every class
half-width at most 1.96 sqrt(0.25 / n), 0.098 at n = 100); sequential stopping stops a cell once every class
half-width is under ``--target`` (0.1), at most ``n`` drops.

Measured, after a warm-up map (compile or cache load):
1. **sequential stopping with cells seeded by their inputs** (``cell_seeds = "inputs"``) on the whole grid:
   the drops computed, the wall time, the distinct inputs, the largest half-width of any cell;
2. **the plain map's cost**: its drops are exactly ``n`` x the computed cells (every cell runs ``n``); its
   time is estimated as those drops over the drops/s of a plain ``cell_seeds = "inputs"`` map of the same
   grid (which runs ``n`` drops for each distinct input: the same per-cell work, fewer cells);
3. **sequential stopping alone** (cells seeded by their index, every cell its own ensemble) on a random
   subset of ``--subset`` computed cells (the others marked land, so each kept cell keeps its index and
   seed): the mean drops a cell and its standard error, scaled to the grid (an estimate; its time likewise).
"""

import argparse
import json
import pathlib
import tempfile
import time

import numpy as np
from _common import machine

from mineburial.analyses.maps import run_map
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.systems.mine.config import example_path


def chart_environment(ny, nx, seed=0):
    env = synthetic_environment(ny=ny, nx=nx, seed=seed)
    env["water_depth"].values[:] = np.round(env["water_depth"].values)
    return env.drop_vars(["current_u", "current_v"])


def half_width(ds):
    w = (ds["burial_class_probability_upper"] - ds["burial_class_probability_lower"]) / 2
    return float(np.nanmax(w.values))


def timed(label, **kw):
    t0 = time.perf_counter()
    ds = run_map(**kw)
    wall = time.perf_counter() - t0
    computed = int(ds.attrs.get("n_drops_total", ds["cell_drop_count"].values.sum()))
    print(f"{label}: {computed} drops computed in {wall:.1f} s ({computed / wall:.1f} drops/s)", flush=True)
    return ds, wall, computed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ny", type=int, default=100)
    ap.add_argument("--nx", type=int, default=100)
    ap.add_argument("-n", type=int, default=100)
    ap.add_argument("--target", type=float, default=0.1)
    ap.add_argument("--min-drops", type=int, default=20)
    ap.add_argument("--subset", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None, help="folder for the maps (default: a temporary one)")
    args = ap.parse_args()
    print(machine())
    out = pathlib.Path(args.out or tempfile.mkdtemp(prefix="bench_map_large_"))
    out.mkdir(parents=True, exist_ok=True)
    scen = str(example_path("default_soft_mud"))
    env = chart_environment(args.ny, args.nx)
    wet = np.isfinite(env["water_depth"].values) & (env["water_depth"].values > 0)
    n_cells = int(wet.sum())
    rows = np.stack([env["water_depth"].values[wet], env["sediment_class"].values[wet].astype(float)], axis=1)
    distinct = len(np.unique(rows, axis=0))
    print(f"grid {args.ny} x {args.nx}: {n_cells} computed cells, {distinct} distinct (depth, sediment)")
    seq = dict(target_half_width=args.target, min_drops=args.min_drops, step=args.min_drops)

    run_map(scenario=scen, environment=chart_environment(2, 3), n=4, seed=args.seed)  # warm-up
    ds1, t1, d1 = timed(
        "1. sequential, cells seeded by inputs",
        scenario=scen,
        environment=env,
        n=args.n,
        seed=args.seed,
        cell_seeds="inputs",
        output=out / "seq_inputs.nc",
        **seq,
    )
    w1 = half_width(ds1)
    ds2, t2, d2 = timed(
        "2. plain, cells seeded by inputs (rate of a plain map)",
        scenario=scen,
        environment=env,
        n=args.n,
        seed=args.seed,
        cell_seeds="inputs",
        output=out / "plain_inputs.nc",
    )
    plain_drops = args.n * n_cells
    plain_time = plain_drops / (d2 / t2)
    w2 = half_width(ds2)

    rng = np.random.default_rng(args.seed)
    keep = np.zeros(wet.size, dtype=bool)
    keep[rng.choice(np.flatnonzero(wet.ravel()), size=min(args.subset, n_cells), replace=False)] = True
    sub = env.copy(deep=True)
    sub["water_depth"].values[~keep.reshape(wet.shape)] = np.nan
    ds3, t3, d3 = timed(
        f"3. sequential, cells seeded by index, {int(keep.sum())} random cells",
        scenario=scen,
        environment=sub,
        n=args.n,
        seed=args.seed,
        output=out / "seq_index_subset.nc",
        **seq,
    )
    used = ds3["cell_drop_count"].values[keep.reshape(wet.shape)]
    mean, se = float(used.mean()), float(used.std(ddof=1) / np.sqrt(used.size))
    seq_drops, seq_se = mean * n_cells, se * n_cells
    seq_time = seq_drops / (d3 / t3)
    w3 = half_width(ds3)
    result = {
        "grid": [args.ny, args.nx],
        "computed_cells": n_cells,
        "distinct_inputs": distinct,
        "n_max": args.n,
        "target_half_width": args.target,
        "plain": {"drops": plain_drops, "time_s_estimated": plain_time, "max_half_width_distinct": w2},
        "sequential_index": {
            "drops_estimated": seq_drops,
            "drops_se": seq_se,
            "time_s_estimated": seq_time,
            "subset_cells": int(keep.sum()),
            "max_half_width_subset": w3,
        },
        "sequential_inputs": {"drops": d1, "time_s": t1, "max_half_width": w1},
    }
    print(json.dumps(result, indent=1))
    print(
        f"\nat equal interval width (class half-widths < {args.target:g} sequential; <= {w2:.3f} plain):\n"
        f"  plain map, {args.n} drops a cell:        {plain_drops:>10,d} drops, ~{plain_time / 60:.1f} min "
        "(drops exact; time from the plain rate)\n"
        f"  sequential stopping (index seeds):   ~{seq_drops:>10,.0f} drops (+/- {seq_se:,.0f}), "
        f"~{seq_time / 60:.1f} min (from {int(keep.sum())} random cells)\n"
        f"  sequential + identical inputs once:  {d1:>10,d} drops, {t1:.1f} s measured "
        f"({distinct} distinct inputs); largest half-width {w1:.3f}"
    )


if __name__ == "__main__":
    main()
