"""A burial map with the post-impact scour stage and a gridded 90-day hourly forcing (issue 20).

Run:  python benchmarks/bench_map_scour.py [--ny 10] [--nx 11] [-n 20] [--out FOLDER]

The synthetic environment grid (mineburial.analyses.synthetic, ``ny`` x ``nx``; 109 water cells at the
default 10 x 11) and, on its cells, a gridded forcing written with
``mineburial.io.forcing.write_gridded_netcdf``: per cell a parametrised storm
(``forcing.storm_series``) over 90 days hourly (2,161 records), peaking on day 30 for 48 h with a
peak Hs growing offshore from 1 to 3 m (Tp 10 s at the peak, a 0.4 m/s current). The scenario is the
shipped ``scour_storm`` example with ``forcing_grid`` in place of its forcing and lead times 0, 7,
30, 60 and 90 days. Measured, after a small warm-up map (compile or cache load, reported apart):
the map with ``[scour]`` (drops/s over all cells), the stage's share of its wall time (the time
inside ``ensembles.scour.run_chunk``, which runs each chunk's stage), and the same map without the
section (the impact phase alone: the same drops, the seed contract).
"""

import argparse
import copy
import pathlib
import tempfile
import time

import numpy as np
from _common import machine

from mineburial.analyses.maps import run_map
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.io import forcing as fio
from mineburial.io.inputs import read_toml
from mineburial.systems.mine.config import example_path
from mineburial.systems.mine.processes import scour

LEADS = [0.0, 7.0, 30.0, 60.0, 90.0]


def gridded_forcing(env, path):
    """Per water cell a 90-day hourly storm series, peak Hs 1 m (west) to 3 m (east)."""
    depth = env["water_depth"].values
    nx = depth.shape[1]
    cells = [
        [
            None
            if not (np.isfinite(depth[j, i]) and depth[j, i] > 0)
            else fio.storm_series(
                peak_hs=1.0 + 2.0 * i / max(nx - 1, 1),
                peak_tp=10.0,
                duration_h=48.0,
                total_h=90 * 24.0,
                peak_h=30 * 24.0,
                current=0.4,
                background_hs=0.5,
            )
            for i in range(nx)
        ]
        for j in range(depth.shape[0])
    ]
    return fio.write_gridded_netcdf(cells, env["latitude"], env["longitude"], path)


def scenario(grid_path):
    d = read_toml(example_path("scour_storm"))
    d["scour"] = {k: v for k, v in d["scour"].items() if k != "forcing"}
    d["scour"].update(forcing_grid=str(grid_path), lead_times_days=LEADS)
    return d


def timed_map(scen, env, n, seed):
    """(wall time, seconds inside the scour stage, map)."""
    inside = [0.0]
    original = scour.run_chunk

    def run_chunk(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return original(*args, **kwargs)
        finally:
            inside[0] += time.perf_counter() - t0

    scour.run_chunk = run_chunk
    try:
        t0 = time.perf_counter()
        ds = run_map(scen, env, n=n, seed=seed)
        return time.perf_counter() - t0, inside[0], ds
    finally:
        scour.run_chunk = original


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ny", type=int, default=10)
    ap.add_argument("--nx", type=int, default=11)
    ap.add_argument("-n", type=int, default=20, help="drops per cell")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None, help="folder for the grids (default: a temporary one)")
    args = ap.parse_args()
    import numba

    print(f"machine: {machine()}, numba threads {numba.get_num_threads()}")
    folder = pathlib.Path(args.out or tempfile.mkdtemp(prefix="bench_map_scour_"))
    env = synthetic_environment(ny=args.ny, nx=args.nx, seed=0)
    t0 = time.perf_counter()
    grid_path = gridded_forcing(env, folder / "forcing_grid.nc")
    n_water = int(np.count_nonzero(np.isfinite(env["water_depth"].values) & (env["water_depth"].values > 0)))
    print(
        f"grid {args.ny} x {args.nx}: {n_water} water cells; gridded forcing 90 d hourly "
        f"({grid_path.stat().st_size / 1e6:.1f} MB) written in {time.perf_counter() - t0:.1f} s"
    )
    scen = scenario(grid_path)
    small = synthetic_environment(ny=2, nx=2, seed=0)
    t0 = time.perf_counter()
    timed_map(scenario(gridded_forcing(small, folder / "small.nc")), small, 2, args.seed)
    print(f"warm-up map (2 x 2, n = 2; compile or cache load): {time.perf_counter() - t0:.1f} s")

    wall, stage, ds = timed_map(scen, env, args.n, args.seed)
    drops = args.n * int(ds.attrs["n_cells_computed"])
    print(
        f"map with [scour]: {drops} drops ({args.n} a cell) in {wall:.1f} s = {drops / wall:.1f} drops/s; "
        f"scour stage {stage:.1f} s = {100 * stage / wall:.1f} % of the wall time "
        f"({1e3 * stage / drops:.2f} ms a drop)"
    )
    plain = copy.deepcopy(scen)
    del plain["scour"]
    t0 = time.perf_counter()
    ds0 = run_map(plain, env, n=args.n, seed=args.seed)
    wall0 = time.perf_counter() - t0
    print(f"same map without [scour]: {wall0:.1f} s = {drops / wall0:.1f} drops/s")
    print(
        f"[scour] adds {wall - wall0:.1f} s = {100 * (wall - wall0) / wall:.1f} % of the map's wall time "
        f"(the stage and, per cell, its forcing series, scenario and lead-time statistics)"
    )
    same = np.array_equal(
        ds["burial_class_probability"].values, ds0["burial_class_probability"].values, equal_nan=True
    )
    print(f"impact statistics of every cell equal with and without [scour]: {same}")
    p = ds["scour_burial_class_probability"].isel(impact_burial_class=4)
    for k, lead in enumerate(LEADS):
        print(f"  lead {lead:4g} d: mean over water cells of P(burial > 75 %) = {float(p[k].mean()):.3f}")


if __name__ == "__main__":
    main()
