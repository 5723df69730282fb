"""Summarise a run of the two-storm example (issue 33) into ``benchmarks/results/scour_two_storms.txt``:
B/D of the lowest point (median and 5-95 %), the share fully buried, the mean pit depth, the median burial
by volume and the share of drops that would move, at each lead time.

    mineburial run mineburial/data/ensembles/scour_two_storms.toml -n 200 --seed 1 --threads 1 --per-drop \\
        -o two.nc --plot docs/figures/scour_two_storms.png
    python benchmarks/scour_two_storms_summary.py two.nc [OUT.txt]
"""

import pathlib
import sys

import numpy as np
import xarray as xr

ROOT = pathlib.Path(__file__).resolve().parents[1]


def summary(path) -> str:
    ds = xr.open_dataset(path)
    ok = ds["scour_status"].values == 0
    diameter = float(np.unique(ds["input_mine_diameter"].values)[0]) if "input_mine_diameter" in ds else 0.53
    bd = ds["scour_penetration_depth"].values[ok] / diameter
    q5, q50, q95 = np.nanpercentile(bd, [5, 50, 95], axis=0)
    rows = [
        f"two-storm example ({pathlib.Path(path).name}): {int(ok.sum())} drops whose stage ran; "
        f"D = {diameter} m",
        "lead [d]  B/D median [5 %, 95 %]   fully buried  mean pit [m]  volume median [%]  would move",
    ]
    vol = ds["scour_burial_volume_quantile"].sel(quantile=0.5).values
    for j, lead in enumerate(ds["lead_time"].values):
        rows.append(
            f"{lead:8.3g}  {q50[j]:.3f} [{q5[j]:.3f}, {q95[j]:.3f}]   {np.mean(bd[:, j] >= 0.999):12.3f}"
            f"  {float(ds['scour_pit_depth_mean'][j]):12.3f}  {vol[j]:17.1f}  "
            f"{float(ds['scour_mobile_probability'][j]):10.3f}"
        )
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    text = summary(sys.argv[1])
    out = (
        pathlib.Path(sys.argv[2])
        if len(sys.argv) > 2
        else ROOT / "benchmarks" / "results" / "scour_two_storms.txt"
    )
    out.write_text(text, encoding="utf-8")
    print(text)
