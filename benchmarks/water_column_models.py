"""Evidence for the water-column model choice (``numerics.water_column``; docs/physics.md,
"Water-column model choices"). Results: benchmarks/results/water_column_models.txt.

    python benchmarks/water_column_models.py ensemble A.nc B.nc ...   # per-drop ensemble files
    python benchmarks/water_column_models.py exp1                     # seed 000 Exp-1, both cases

``ensemble`` summarises ``mineburial run --per-drop`` outputs: median |impact pitch|, mean
impact speed, mean penetration, mean burial by volume and P(> 75 %) over the drops at rest.
``exp1`` runs the pool drops of eqs. (92) and (93) with each water-column model at the pool
depths the validation sweeps, and reports travel time, flip time and the pattern measures of
``mineburial.validation.cases`` (straightness of the path, turning of the horizontal velocity).
"""

import dataclasses
import sys

import numpy as np
import xarray as xr

from mineburial.kernels.mine.status import IN_STATISTICS
from mineburial.systems.mine.config import load_example
from mineburial.systems.mine.drop import simulate_drop
from mineburial.validation import cases

MODELS = {
    "munk_factor 0 (default)": {"water_column": "munk_factor", "munk_factor": 0.0},
    "munk_factor 1 (strip)": {"water_column": "munk_factor", "munk_factor": 1.0},
    "viscous_crossflow": {"water_column": "viscous_crossflow"},
}
DEPTHS = tuple(sorted({1.25, *cases.POOL_DEPTHS}))  # the validation's sweep, and 1.25 m


def ensemble(paths):
    print(
        "file | median |impact pitch| deg | mean impact speed m/s | mean penetration m"
        " | mean burial % | P(>75 %)"
    )
    for path in paths:
        ds = xr.open_dataset(path)
        rest = np.isin(ds.status.values, IN_STATISTICS)  # the drops of the burial statistics
        pitch = np.median(np.abs(ds.impact_pitch.values))
        speed = ds.impact_speed.values.mean()
        pen = ds.penetration_depth.values[rest].mean()
        bur = ds.burial_volume.values[rest].mean()
        p75 = (ds.burial_volume.values[rest] > 75.0).mean()
        print(f"{path} | {pitch:.1f} | {speed:.2f} | {pen:.3f} | {bur:.1f} | {p75:.3f} (n {rest.sum()})")


def _drop(name, numerics, depth):
    sc = load_example(name)
    sc = dataclasses.replace(
        sc,
        numerics=dataclasses.replace(sc.numerics, **numerics),
        environment=dataclasses.replace(sc.environment, water_depth=depth),
    )
    return simulate_drop(sc, record_interval=0.002)


def exp1():
    for name, info in cases.EXP1.items():
        print(
            f"{info['label']}: observed {info['pattern']}, travel {info['travel_time']} s, "
            f"flip {info.get('flip_time', '-')} s"
        )
        for label, numerics in MODELS.items():
            times = []
            for depth in DEPTHS:
                ds = _drop(name, numerics, depth)
                travel = float(ds.impact_time) - float(ds.water_entry_time)
                times.append(travel)
                flip = cases._flip_time(ds)
                straight = cases._straightness(ds)
                turn = cases._turning_deg(ds, flip if flip is not None else 0.0)
                k_impact = np.searchsorted(ds.time.values, float(ds.impact_time)) - 1
                flip_text = "no flip" if flip is None else f"flip {flip:.3f} s"
                print(
                    f"  {label:24s} depth {depth:.2f} m: travel {travel:.3f} s, {flip_text}, "
                    f"path off the chord {straight:.1%}, turning after flip {turn:.0f} deg, "
                    f"impact pitch {float(ds.psi2.values[k_impact]):.0f} deg"
                )
            t = np.array(times)
            inside = t.min() <= info["travel_time"] <= t.max() and np.all(np.diff(t) > 0)
            match = f"{np.interp(info['travel_time'], t, DEPTHS):.2f} m" if inside else "outside the sweep"
            print(f"  {label:24s} pool depth matching the observed travel time: {match}")


if __name__ == "__main__":
    if sys.argv[1] == "ensemble":
        ensemble(sys.argv[2:])
    elif sys.argv[1] == "exp1":
        exp1()
    else:
        raise SystemExit("usage: water_column_models.py ensemble FILES... | exp1")
