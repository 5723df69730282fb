"""A small SYNTHETIC environment grid for the map examples and tests (no download needed).

:func:`synthetic_environment` builds a latitude/longitude grid (default 6 x 8 cells)
in the format read by :mod:`mineburial.maps` (docs/maps.md):

* ``water_depth`` increasing offshore (towards the east) from about 4 m to about 30 m,
  with a little random relief; one land cell (NaN depth) on the coast, in the
  north-west corner;
* ``sediment_class``: sand near the coast, a band of soft mud (``very_soft_clay``
  flanked by ``soft_clay``) in the middle, ``sandy_silt`` offshore; the integer codes
  index :func:`mineburial.sediment_profiles.class_names` and are named by the CF
  ``flag_values``/``flag_meanings`` attributes;
* ``current_u``/``current_v``: an along-shore (northward) tidal current that grows
  offshore, with a small onshore component;
* a ``crs`` grid-mapping variable (WGS 84 latitude/longitude).

None of it is data: the values are invented to show the workflow and are labelled
synthetic in the title, summary and comment attributes. The position (western Baltic)
only gives the axes plausible numbers.
"""

from __future__ import annotations

import pathlib

import numpy as np
import xarray as xr

from mineburial.sediment_profiles import class_names

__all__ = ["synthetic_environment", "write_synthetic_environment"]

_SYNTHETIC_NOTE = (
    "SYNTHETIC DATA: invented values to demonstrate mineburial maps; not a survey, "
    "not a chart, not for operational use."
)


def synthetic_environment(
    ny: int = 6,
    nx: int = 8,
    seed: int = 0,
    *,
    lat0: float = 54.50,
    lon0: float = 10.30,
    dlat: float = 0.01,
    dlon: float = 0.015,
) -> xr.Dataset:
    """A synthetic environment grid of ``ny`` x ``nx`` cells (see the module docstring).

    ``seed`` drives the small random depth relief (numpy ``default_rng``); ``lat0``,
    ``lon0`` are the centre of the south-west cell and ``dlat``, ``dlon`` the spacing in
    degrees. Needs ``nx >= 2``, ``ny >= 1``.
    """
    if ny < 1 or nx < 2:
        raise ValueError(f"synthetic_environment needs ny >= 1 and nx >= 2, got {ny} x {nx}")
    rng = np.random.default_rng(seed)
    lat = lat0 + dlat * np.arange(ny)
    lon = lon0 + dlon * np.arange(nx)
    off = np.arange(nx) / (nx - 1)  # 0 at the coast (west), 1 offshore
    north = np.arange(ny) / max(ny - 1, 1)
    depth = 4.0 + 26.0 * off[None, :] ** 1.3 + 1.5 * north[:, None] * off[None, :]
    depth = depth + rng.uniform(-0.4, 0.4, size=(ny, nx))
    depth[-1, 0] = np.nan  # one land cell on the coast

    names = class_names()
    code = {name: k for k, name in enumerate(names)}
    band = np.empty(nx, dtype=np.int8)
    for i, o in enumerate(off):
        if o < 0.2:
            band[i] = code["sand"]
        elif o < 0.35:
            band[i] = code["soft_clay"]
        elif o < 0.6:
            band[i] = code["very_soft_clay"]
        elif o < 0.75:
            band[i] = code["soft_clay"]
        else:
            band[i] = code["sandy_silt"]
    sediment = np.broadcast_to(band, (ny, nx)).copy()
    sediment[-1, 0] = -1  # no sediment on land

    v = 0.15 + 0.35 * off[None, :] + 0.05 * north[:, None]  # along-shore, northward
    u = np.full((ny, nx), -0.05)  # weak onshore (westward)
    u[np.isnan(depth)] = np.nan
    v = np.where(np.isnan(depth), np.nan, v)

    coords = {
        "latitude": (
            "latitude",
            lat,
            {"standard_name": "latitude", "long_name": "latitude", "units": "degrees_north", "axis": "Y"},
        ),
        "longitude": (
            "longitude",
            lon,
            {"standard_name": "longitude", "long_name": "longitude", "units": "degrees_east", "axis": "X"},
        ),
    }
    dims = ("latitude", "longitude")
    gm = {"grid_mapping": "crs"}
    ds = xr.Dataset(
        {
            "water_depth": (
                dims,
                depth,
                {
                    "standard_name": "sea_floor_depth_below_sea_surface",
                    "long_name": "water depth (synthetic)",
                    "units": "m",
                    **gm,
                    "comment": "NaN on land. " + _SYNTHETIC_NOTE,
                },
            ),
            "sediment_class": (
                dims,
                sediment,
                {
                    "long_name": "seabed sediment class (synthetic)",
                    "flag_values": np.arange(len(names), dtype=np.int8),
                    "flag_meanings": " ".join(names),
                    **gm,
                    "comment": "Index into the mineburial sediment catalogue "
                    "(mineburial.sediment_profiles.class_names()); -1 (fill) on land. " + _SYNTHETIC_NOTE,
                },
            ),
            "current_u": (
                dims,
                u,
                {
                    "standard_name": "eastward_sea_water_velocity",
                    "long_name": "eastward current (synthetic)",
                    "units": "m s-1",
                    **gm,
                },
            ),
            "current_v": (
                dims,
                v,
                {
                    "standard_name": "northward_sea_water_velocity",
                    "long_name": "northward current (synthetic)",
                    "units": "m s-1",
                    **gm,
                },
            ),
            "crs": (
                (),
                np.int32(0),
                {
                    "grid_mapping_name": "latitude_longitude",
                    "longitude_of_prime_meridian": 0.0,
                    "semi_major_axis": 6378137.0,
                    "inverse_flattening": 298.257223563,
                    "long_name": "WGS 84",
                },
            ),
        },
        coords=coords,
        attrs={
            "Conventions": "CF-1.11, ACDD-1.3",
            "title": "SYNTHETIC environment grid for mineburial burial maps",
            "summary": (
                "A small invented grid of water depth, seabed sediment class and current "
                "for the mineburial map example: depth increasing offshore, sand at the "
                "coast, a band of soft mud, sandy silt offshore, one land cell. " + _SYNTHETIC_NOTE
            ),
            "comment": _SYNTHETIC_NOTE + f" Generated by mineburial.synthetic (seed {seed}).",
            "source": "mineburial.synthetic.synthetic_environment (invented values)",
            "keywords": "synthetic, example, bathymetry, sediment, current",
            "cdm_data_type": "Grid",
            "geospatial_lat_min": float(lat.min()),
            "geospatial_lat_max": float(lat.max()),
            "geospatial_lon_min": float(lon.min()),
            "geospatial_lon_max": float(lon.max()),
        },
    )
    ds["sediment_class"].encoding["_FillValue"] = np.int8(-1)
    return ds


def write_synthetic_environment(path, ny: int = 6, nx: int = 8, seed: int = 0) -> pathlib.Path:
    """Write :func:`synthetic_environment` to ``path`` (NetCDF, atomically); returns the path."""
    from mineburial.io.netcdf import write_netcdf

    return write_netcdf(synthetic_environment(ny=ny, nx=nx, seed=seed), path)


if __name__ == "__main__":  # python -m mineburial.synthetic [PATH]
    import sys

    out = write_synthetic_environment(sys.argv[1] if len(sys.argv) > 1 else "environment.nc")
    print(f"wrote synthetic environment grid {out}")
