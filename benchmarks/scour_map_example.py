"""The scour map example of issue 33 ("a map with the 'not modelled' mask and the forcing read from a
standard-named wave file"): the SYNTHETIC 6 x 8 environment grid (sand near the coast, a band of
soft mud, sandy silt offshore: ``mineburial.analyses.synthetic``) under a SYNTHETIC storm written as a
Copernicus Marine wave product (variables found by their CF standard names, on the product's own
coarser grid, 3-hourly, int16-packed), run with the scour-and-settle law, then drawn.

    python benchmarks/scour_map_example.py [--out DIR] [-n DROPS] [--plot PNG]

writes DIR/environment.nc, DIR/waves_cmems.nc, DIR/scenario.toml and DIR/map.nc, draws the map's
lead-time panels (burial probability P(> 75 %) by volume at each lead time, the cohesive cells
hatched as "not modelled") to PNG (default docs/figures/scour_map_wave_product.png) and prints a
summary per lead time. Nothing here is data: both grids are invented (their attributes say so).
"""

from __future__ import annotations

import argparse
import pathlib
import subprocess
import sys

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.analyses.synthetic import write_synthetic_environment

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "mineburial" / "data" / "ensembles" / "scour_two_storms.toml"
LEAD_DAYS = (0.0, 3.0, 6.0, 10.0)
PANELS = "0,3,6"


def write_wave_product(path: pathlib.Path) -> None:
    """A SYNTHETIC storm in the layout of Copernicus Marine's global wave product
    (GLOBAL_ANALYSISFORECAST_WAV_001_027): VHM0, VTPK, VMDR with their CF standard names on a
    0.05-degree (time, latitude, longitude) grid covering the environment, hours since 1950,
    3-hourly for 10 days, int16 packed with a _FillValue. A cos^2 storm peaks on day 3 (48 h
    long) over a 0.4 m background; Hs grows by 30 % from the coast (west) to offshore (east);
    Tp = 10 s sqrt(Hs / 2 m) (constant steepness), waves from the west-north-west."""
    lat = np.arange(54.45, 54.601, 0.05)
    lon = np.arange(10.25, 10.451, 0.05)
    hours = np.arange(0.0, 240.0 + 1e-9, 3.0)
    tau = (hours - 72.0) / 24.0
    shape = np.where(np.abs(tau) < 1.0, np.cos(0.5 * np.pi * tau) ** 2, 0.0)
    offshore = 1.0 + 0.3 * (lon - lon[0]) / (lon[-1] - lon[0])
    hs = (0.4 + (2.0 - 0.4) * shape)[:, None, None] * offshore[None, None, :] * np.ones((1, lat.size, 1))
    tp = 10.0 * np.sqrt(hs / 2.0)
    wave_from = np.full(hs.shape, 290.0)
    spec = {
        "VHM0": (hs, "sea_surface_wave_significant_height", "m", 0.01),
        "VTPK": (tp, "sea_surface_wave_period_at_variance_spectral_density_maximum", "s", 0.01),
        "VMDR": (wave_from, "sea_surface_wave_from_direction", "degree", 0.1),
    }
    ds = xr.Dataset(
        {
            k: (("time", "latitude", "longitude"), v, {"standard_name": sn, "units": u})
            for k, (v, sn, u, _) in spec.items()
        },
        coords={
            "time": ("time", 657_432.0 + hours, {"units": "hours since 1950-01-01", "standard_name": "time"}),
            "latitude": ("latitude", lat, {"units": "degrees_north", "standard_name": "latitude"}),
            "longitude": ("longitude", lon, {"units": "degrees_east", "standard_name": "longitude"}),
        },
        attrs={
            "Conventions": "CF-1.6",
            "title": "SYNTHETIC storm in the layout of a Copernicus Marine wave product",
            "comment": "SYNTHETIC DATA: invented values for the mineburial scour map example; not a hindcast",
        },
    )
    encoding = {
        k: {"dtype": "int16", "scale_factor": s, "add_offset": 0.0, "_FillValue": -32767}
        for k, (_, _, _, s) in spec.items()
    }
    ds.to_netcdf(path, encoding=encoding)


def write_scenario(path: pathlib.Path, waves: pathlib.Path) -> None:
    """The shipped two-storm scenario with the wave product as its gridded forcing and the scour
    sediment (d50, grain density, cohesive) left to each cell's sediment class (docs/maps.md)."""
    text = SCENARIO.read_text()
    text = text.replace('forcing = "two_storms"', f'forcing_grid = "{waves.name}"', 1)
    lead = ", ".join(f"{d:g}" for d in LEAD_DAYS)
    lines = [
        f"lead_times_days = [{lead}]" if s.startswith("lead_times_days") else s for s in text.splitlines()
    ]
    lines = [s for s in lines if not s.startswith(("d50 ", "grain_density ", "cohesive "))]
    path.write_text("\n".join(lines) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="scour_map_example", help="folder for the inputs and the map")
    parser.add_argument("-n", "--drops", type=int, default=32, help="drops per cell (default 32)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--plot", default=str(ROOT / "docs" / "figures" / "scour_map_wave_product.png"))
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env, waves, scenario = out / "environment.nc", out / "waves_cmems.nc", out / "scenario.toml"
    write_synthetic_environment(env)
    write_wave_product(waves)
    write_scenario(scenario, waves)
    command = [
        sys.executable, "-m", "mineburial.cli", "map", str(scenario), "--environment", str(env),
        "-n", str(args.drops), "--seed", str(args.seed), "-o", str(out / "map.nc"),
        "--plot", args.plot, "--lead-times", PANELS, "--class", "4", "--quiet",
    ]  # fmt: skip
    print(" ".join(command))
    done = subprocess.run(command, check=False)
    if done.returncode:
        return done.returncode
    ds = xr.open_dataset(out / "map.nc")
    print(f"forcing_grid_interpolation: {ds.attrs.get('forcing_grid_interpolation')}")
    nm = ds["scour_not_modelled_fraction"]
    print(f"cells not modelled (share >= 0.5): {int((nm >= 0.5).sum())} of {int(np.isfinite(nm).sum())}")
    p = ds["scour_class_probability"] if "scour_class_probability" in ds else None
    if p is not None:
        print(p.dims)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
