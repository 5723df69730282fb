"""Operational burial-probability maps: one ensemble per cell of an environment grid.

An *environment grid* (NetCDF, format in docs/maps.md) gives per cell the water depth,
the seabed sediment (a catalogue class or linear-profile values) and optionally the
current. For every water cell, the ensemble scenario with that cell's environment
overriding the corresponding fields is run with ``n`` drops and a seed derived from
the map seed and the cell index (:func:`cell_seed`); the per-cell statistics
(:func:`mineburial.systems.mine.statistics.burial_statistics`) are gathered into one
CF-1.11 map (:func:`run_map`), optionally drawn for a planner (:func:`plot_map`).

A cell's statistics are exactly those of ``run_ensemble(cell scenario, n, seed=cell
seed)``: the map only decides which scenario and seed each cell gets. Chunks of all
cells are spread over a dask cluster as one flat list of tasks
(:func:`mineburial.ensembles.distributed.run_tasks_distributed`), and with an output
path the finished chunks are kept in ``MAP.nc.parts/cell-<index>/`` so an interrupted
map resumes: the map is run by the same driver and chunk store as a single ensemble
(:func:`mineburial.ensembles.runner.run_jobs`, :mod:`mineburial.ensembles.store`), with
one job per cell.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import json
import math
import pathlib
import time
from collections.abc import Callable, Mapping

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial._version import __version__
from mineburial.ensembles import engine, runner
from mineburial.ensembles.distributed import run_tasks_distributed
from mineburial.ensembles.settings import file_digest, merge_invalid_reasons
from mineburial.ensembles.store import OutputRun, check_output_path, same_file
from mineburial.errors import unknown_name_message
from mineburial.io import netcdf as ncio
from mineburial.io import variables as V
from mineburial.io.dataset import build
from mineburial.io.files import atomic_write_bytes
from mineburial.io.inputs import check_input, read_toml
from mineburial.kernels.mine import layout
from mineburial.resources import memory_refusal
from mineburial.systems.mine import config as cfg
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import epistemic
from mineburial.systems.mine.calibration import posterior
from mineburial.systems.mine.figures import check_plot_path, figure_class, save_figure
from mineburial.systems.mine.processes import registry as processes
from mineburial.systems.mine.sediment_profiles import class_names
from mineburial.systems.mine.statistics import burial_statistics

__all__ = [
    "MapError",
    "EnvironmentGrid",
    "read_environment",
    "cell_seed",
    "cell_scenario",
    "run_map",
    "plot_map",
    "run_map_cli",
    "MAP_OUTPUTS",
    "CELL_STATUS_MEANINGS",
]

#: summary outputs whose mean, standard deviation and quantiles go into the map (the registry's
#: map family, :mod:`mineburial.io.variables`, declares the map's variables)
MAP_OUTPUTS = V.MAP_OUTPUTS
#: codes of the per-cell variable ``cell_status``
CELL_COMPUTED, CELL_LAND, CELL_NO_SEDIMENT = 0, 1, 2
CELL_STATUS_MEANINGS = V.CELL_STATUS_MEANINGS

_SEDIMENT_PARAMS = {
    "sediment_density": "density",
    "sediment_density_gradient": "density_gradient",
    "sediment_strength": "strength",
    "sediment_strength_gradient": "strength_gradient",
}
_SEDIMENT_KEYS = ("class", "profile", "file", "density", "density_gradient", "strength", "strength_gradient")
_METRE = {"m", "meter", "meters", "metre", "metres"}
_SPEED = {"m s-1", "m/s", "m s^-1", "m.s-1", "meter second-1", "m s**-1"}
_DEGREE = {"degree", "degrees", "degree_true", "degrees_true", "deg"}
_SEED_TAG = "mineburial-map-cell"
#: CF standard names of a depth of the seabed, positive downwards: the sea-floor depth
#: below the surface (CF standard name table, v84) and the four depth formula terms of the
#: ocean parametric vertical coordinates (CF 1.11 Appendix D, Table D.1), plus ``depth``
#: (CF: "vertical distance below the surface")
DEPTH_NAMES = frozenset(
    {
        "sea_floor_depth_below_sea_surface",
        "sea_floor_depth_below_geoid",
        "sea_floor_depth_below_geopotential_datum",
        "sea_floor_depth_below_reference_ellipsoid",
        "sea_floor_depth_below_mean_sea_level",
        "depth",
    }
)
#: CF standard names of a height of the seabed, positive upwards (sea negative): the
#: heights that CF 1.11 Appendix D pairs with the depth names above (``altitude`` is the
#: height above the geoid)
ELEVATION_NAMES = frozenset(
    {
        "altitude",
        "height_above_geopotential_datum",
        "height_above_reference_ellipsoid",
        "height_above_mean_sea_level",
    }
)


class MapError(cfg.ScenarioError):
    """A problem with an environment grid or a map run (message names variable/cell)."""


# ---------------------------------------------------------------------------
# environment grid
# ---------------------------------------------------------------------------
@dataclasses.dataclass
class EnvironmentGrid:
    """An environment grid read by :func:`read_environment` (arrays of shape (ny, nx))."""

    ds: xr.Dataset  # the grid as read (2-D variables, squeezed)
    ydim: str
    xdim: str
    geographic: bool  # latitude/longitude axes (else projected y/x)
    grid_mapping: str | None  # name of the grid-mapping variable, if any
    water_depth: np.ndarray  # m, NaN on land
    sediment_class: np.ndarray | None  # object array of class names (None: missing)
    sediment_params: dict | None  # scenario key ('density', ...) -> array
    current_u: np.ndarray | None  # m s-1 towards the east (scenario x)
    current_v: np.ndarray | None  # m s-1 towards the north (scenario y)
    source: str = ""
    vertical: str = "depth"  # how water_depth was read (:func:`_vertical_sign`)

    @property
    def shape(self) -> tuple[int, int]:
        return self.water_depth.shape

    def cell_status(self) -> np.ndarray:
        """int8 (ny, nx): 0 computed, 1 land / no water depth, 2 no sediment data."""
        st = np.full(self.shape, CELL_COMPUTED, dtype=np.int8)
        land = ~(np.isfinite(self.water_depth) & (self.water_depth > 0))
        if self.sediment_class is not None:
            nosed = np.vectorize(lambda v: v is None, otypes=[bool])(self.sediment_class)
        else:
            nosed = np.zeros(self.shape, dtype=bool)
            for arr in self.sediment_params.values():
                nosed |= ~np.isfinite(arr)
        st[nosed] = CELL_NO_SEDIMENT
        st[land] = CELL_LAND
        return st


def _units(da) -> str:
    return " ".join(str(da.attrs.get("units", "")).split()).lower()


def _is_axis(da, kind: str) -> bool:
    """Whether coordinate ``da`` is a latitude ('lat'), longitude ('lon'), projected y or x."""
    sn = str(da.attrs.get("standard_name", "")).lower()
    u = _units(da)
    name = str(da.name).lower()
    if kind == "lat":
        return (
            sn == "latitude"
            or u in ("degrees_north", "degree_north", "degree_n", "degrees_n")
            or name in ("lat", "latitude")
        )
    if kind == "lon":
        return (
            sn == "longitude"
            or u in ("degrees_east", "degree_east", "degree_e", "degrees_e")
            or name in ("lon", "longitude")
        )
    if kind == "y":
        return sn == "projection_y_coordinate" or str(da.attrs.get("axis", "")).upper() == "Y" or name == "y"
    return sn == "projection_x_coordinate" or str(da.attrs.get("axis", "")).upper() == "X" or name == "x"


def _field(ds, name, dims):
    if name not in ds:
        return None
    da = ds[name]
    extra = [d for d in da.dims if d not in dims]
    for d in extra:
        if da.sizes[d] != 1:
            raise MapError(
                f"environment variable '{name}' has the extra dimension '{d}' of "
                f"size {da.sizes[d]}; give one 2-D field over {dims}"
            )
        da = da.isel({d: 0})
    if set(da.dims) != set(dims):
        raise MapError(f"environment variable '{name}' has dimensions {da.dims}; expected {dims}")
    if not (np.issubdtype(da.dtype, np.floating) or np.issubdtype(da.dtype, np.integer)):
        raise MapError(f"environment variable '{name}' holds {da.dtype} values; expected numbers")
    return da.transpose(*dims)


def _check_units(da, allowed, want, name):
    u = _units(da)
    if u not in allowed:
        raise MapError(
            f"environment variable '{name}' has units '{da.attrs.get('units', '')}'; expected {want}"
        )


def _check_axis(da) -> None:
    """A horizontal axis must be 1-D, finite and strictly monotonic (increasing or
    decreasing): cells are drawn between midpoints of neighbouring coordinates, so an
    unsorted or repeated coordinate would put cells in the wrong place."""
    name = str(da.name)
    if da.ndim != 1:
        raise MapError(f"environment grid: coordinate '{name}' must be 1-D, got dimensions {da.dims}")
    c = np.asarray(da.values, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(c))
    if bad.size:
        raise MapError(
            f"environment grid: coordinate '{name}' has the non-finite value {c[bad[0]]} at index {bad[0]}"
        )
    step = np.diff(c)
    same = np.flatnonzero(step == 0)
    if same.size:
        k = int(same[0])
        raise MapError(
            f"environment grid: coordinate '{name}' repeats the value {c[k]:g} "
            f"(indices {k} and {k + 1}); each cell needs its own coordinate"
        )
    if step.size and not (np.all(step > 0) or np.all(step < 0)):
        k = int(np.flatnonzero(np.sign(step) != np.sign(step[0]))[0])
        raise MapError(
            f"environment grid: coordinate '{name}' is not sorted: {c[k]:g} then "
            f"{c[k + 1]:g} at indices {k}, {k + 1} (it must increase or decrease "
            f"throughout; sort the grid, e.g. ds.sortby('{name}'))"
        )


def read_environment(source) -> EnvironmentGrid:
    """Read and check an environment grid (path or :class:`xarray.Dataset`); docs/maps.md.

    Horizontal axes: 1-D ``latitude``/``longitude`` (CF attributes) or projected ``y``/``x``
    (``standard_name`` ``projection_*_coordinate``) with a ``grid_mapping`` variable.
    Variables: ``water_depth`` (m, NaN or <= 0 on land); ``sediment_class`` (integer codes
    named by ``flag_values``/``flag_meanings``, or indexes into a ``labels`` attribute,
    naming catalogue classes) or ``sediment_density``, ``sediment_strength``,
    ``sediment_strength_gradient`` (+ optional ``sediment_density_gradient``); optional
    ``current_u``/``current_v`` (eastward/northward, m s-1) or ``current_speed`` (m s-1)
    with ``current_direction`` (degrees clockwise from north, direction *towards* which the
    water flows, as CF ``direction_of_sea_water_velocity``).
    """
    ds, label = _open_grid(source)
    ydim, xdim, geographic, gm = _horizontal_axes(ds)
    dims = (ydim, xdim)
    depth_da = _field(ds, "water_depth", dims)
    _check_units(depth_da, _METRE, "m", "water_depth")
    sign, vertical = _vertical_sign(depth_da)
    depth = sign * np.asarray(depth_da.values, dtype=np.float64)
    _check_conflicts(ds)
    sed_class, sed_params = _read_sediment(ds, dims)
    cu, cv = _read_currents(ds, dims)
    grid = EnvironmentGrid(
        ds=ds,
        ydim=ydim,
        xdim=xdim,
        geographic=geographic,
        grid_mapping=gm,
        water_depth=depth,
        sediment_class=sed_class,
        sediment_params=sed_params,
        current_u=cu,
        current_v=cv,
        source=label,
        vertical=vertical,
    )
    _check_cells(grid)
    return grid


def _open_grid(source):
    """(Dataset, label): ``source`` itself, or the NetCDF file it names, loaded and checked."""
    label = ""
    if isinstance(source, xr.Dataset):
        ds = source
    else:
        path = pathlib.Path(source)
        if not path.exists():
            raise FileNotFoundError(f"environment grid '{path}' does not exist")
        try:
            check_input(path, "grid")
            with xr.open_dataset(path) as opened:
                ds = opened.load()
        except (OSError, ValueError) as exc:
            raise MapError(f"cannot read environment grid '{path}' as NetCDF: {exc}") from None
        label = str(path)
    return ds, label


def _horizontal_axes(ds):
    """(ydim, xdim, geographic, grid_mapping) of ``water_depth``: lat/lon or projected y/x."""
    if "water_depth" not in ds:
        raise MapError(
            "environment grid: the variable 'water_depth' (m) is required; found "
            + ", ".join(map(str, ds.data_vars))
        )
    wd = ds["water_depth"]
    dims = tuple(wd.dims)
    if len(dims) > 2:  # drop size-1 extra dimensions (a single time, a single level)
        dims = tuple(
            d
            for d in dims
            if wd.sizes[d] != 1
            or (d in ds.coords and any(_is_axis(ds[d], k) for k in ("lat", "lon", "y", "x")))
        )
    if len(dims) != 2:
        raise MapError(
            f"environment grid: 'water_depth' must be a 2-D field (y, x), got "
            f"dimensions {wd.dims} with sizes {tuple(wd.shape)}"
        )
    ydim, xdim = dims
    for d in dims:
        if d not in ds.coords:
            raise MapError(f"environment grid: dimension '{d}' has no coordinate variable")
    yc, xc = ds[ydim], ds[xdim]
    if _is_axis(yc, "lon") and _is_axis(xc, "lat"):  # (longitude, latitude) order
        ydim, xdim = xdim, ydim
        yc, xc = xc, yc
    geographic = _is_axis(yc, "lat") and _is_axis(xc, "lon")
    if not geographic and not (_is_axis(yc, "y") and _is_axis(xc, "x")):
        raise MapError(
            f"environment grid: axes '{ydim}', '{xdim}' are neither latitude/longitude "
            f"(units degrees_north/degrees_east) nor projected y/x (standard_name "
            f"projection_y_coordinate/projection_x_coordinate)"
        )
    gm = wd.attrs.get("grid_mapping") or wd.encoding.get("grid_mapping")
    if gm is not None and gm not in ds.variables:
        raise MapError(
            f"environment grid: water_depth names the grid_mapping '{gm}', which is not in the file"
        )
    if not geographic and gm is None:
        raise MapError(
            "environment grid: a projected y/x grid needs a grid_mapping variable "
            "(CF 5.6) named by the grid_mapping attribute of water_depth"
        )
    _check_axis(yc)
    _check_axis(xc)
    return ydim, xdim, geographic, gm


def _read_sediment(ds, dims):
    """(class codes, None) from ``sediment_class``, or (None, linear-profile fields)."""
    sed_class = sed_params = None
    if "sediment_class" in ds:
        sed_class = _read_classes(_field(ds, "sediment_class", dims))
    else:
        needed = ("sediment_density", "sediment_strength", "sediment_strength_gradient")
        missing = [k for k in needed if k not in ds]
        if missing:
            raise MapError(
                "environment grid: give 'sediment_class' (catalogue class codes) or "
                "the linear-profile fields sediment_density (kg m-3), sediment_strength "
                "(Pa), sediment_strength_gradient (Pa m-1) [, sediment_density_gradient "
                f"(kg m-4)]; missing {', '.join(missing)}"
            )
        sed_params = {}
        want = {
            "sediment_density": ("kg m-3", {"kg m-3", "kg/m3", "kg m^-3", "kg m**-3"}),
            "sediment_density_gradient": ("kg m-4", {"kg m-4", "kg/m4", "kg m^-4", "kg m**-4"}),
            "sediment_strength": ("Pa", {"pa"}),
            "sediment_strength_gradient": ("Pa m-1", {"pa m-1", "pa/m", "pa m^-1", "pa m**-1"}),
        }
        for name, key in _SEDIMENT_PARAMS.items():
            if name in ds:
                da = _field(ds, name, dims)
                _check_units(da, want[name][1], want[name][0], name)
                sed_params[key] = np.asarray(da.values, dtype=np.float64)
    return sed_class, sed_params


def _read_currents(ds, dims):
    """(eastward, northward) current, m s-1, from u/v or speed/direction; (None, None) if absent."""
    cu = cv = None
    if "current_u" in ds or "current_v" in ds:
        if not ("current_u" in ds and "current_v" in ds):
            raise MapError("environment grid: give both current_u and current_v")
        ua, va = _field(ds, "current_u", dims), _field(ds, "current_v", dims)
        for da, name in ((ua, "current_u"), (va, "current_v")):
            _check_units(da, _SPEED, "m s-1", name)
        cu, cv = np.asarray(ua.values, np.float64), np.asarray(va.values, np.float64)
    elif "current_speed" in ds or "current_direction" in ds:
        if not ("current_speed" in ds and "current_direction" in ds):
            raise MapError("environment grid: give both current_speed and current_direction")
        sp, di = _field(ds, "current_speed", dims), _field(ds, "current_direction", dims)
        _check_units(sp, _SPEED, "m s-1", "current_speed")
        _check_units(di, _DEGREE, "degree (clockwise from north, towards)", "current_direction")
        speed = np.asarray(sp.values, np.float64)
        rad = np.radians(np.asarray(di.values, np.float64))
        cu, cv = speed * np.sin(rad), speed * np.cos(rad)  # towards-direction, clockwise from N
    return cu, cv


def _vertical_sign(da) -> tuple[float, str]:
    """(sign, how it was decided): +1 when ``water_depth`` is a depth (positive down),
    -1 when it is an elevation (positive up, the sea negative), by its CF attributes:
    ``positive`` (CF 1.11 section 4.3: "up" or "down") decides; ``standard_name``
    (:data:`DEPTH_NAMES`, :data:`ELEVATION_NAMES`) decides without it and must agree with
    it. With neither, the variable's name says depth (documented in docs/maps.md); a
    standard name that is neither a depth nor an elevation, without ``positive``, is
    refused."""
    sn = str(da.attrs.get("standard_name", "")).strip()
    by_name = 1.0 if sn in DEPTH_NAMES else (-1.0 if sn in ELEVATION_NAMES else None)
    positive = da.attrs.get("positive")
    if positive is None:
        if by_name is None and sn:
            raise MapError(
                f"environment grid: water_depth has the standard_name '{sn}', which is neither a "
                f"depth ({', '.join(sorted(DEPTH_NAMES))}) nor an elevation "
                f"({', '.join(sorted(ELEVATION_NAMES))}); give the attribute positive = 'down' "
                f"(depth) or 'up' (elevation, the sea negative)"
            )
        if by_name is None:
            return 1.0, "a depth (no positive or standard_name attribute: by its name)"
        kind = "a depth" if by_name > 0 else "an elevation"
        return by_name, f"{kind} (by its standard_name '{sn}')"
    text = str(positive).strip().lower()
    if text not in ("up", "down"):
        raise MapError(
            f"environment grid: water_depth has positive = {str(positive)!r}; CF allows 'up' "
            f"(elevation, the sea negative) or 'down' (depth)"
        )
    sign = 1.0 if text == "down" else -1.0
    if by_name is not None and by_name != sign:
        kind = "a depth (positive down)" if by_name > 0 else "an elevation (positive up)"
        raise MapError(
            f"environment grid: water_depth has positive = '{text}' but its standard_name "
            f"'{sn}' is {kind}; correct one of them"
        )
    kind = "a depth" if sign > 0 else "an elevation"
    return sign, f"{kind} (by its attribute positive = '{text}')"


#: pairs of grid variables of which only one may be given: (either, or)
_ALTERNATIVES = (
    (("current_u", "current_v"), ("current_speed", "current_direction")),
    (("sediment_class",), tuple(_SEDIMENT_PARAMS)),
)


def _check_conflicts(ds) -> None:
    """Refuse a grid that gives one quantity twice (a current as u/v and as speed and
    direction; a sediment as a class and as linear-profile values): one would be ignored."""
    for first, second in _ALTERNATIVES:
        a = [v for v in first if v in ds]
        b = [v for v in second if v in ds]
        if a and b:
            raise MapError(
                f"environment grid: both {', '.join(a)} and {', '.join(b)} are given; they "
                f"describe the same quantity, give only one of them"
            )


def _check_cells(grid: EnvironmentGrid) -> None:
    """Refuse an empty grid, an infinite value (a depth, sediment or current value; NaN
    means missing) naming its cell, and a grid without a cell to compute."""
    if grid.water_depth.size == 0:
        raise MapError(
            f"environment grid: water_depth has no cells (shape {grid.shape[0]} x {grid.shape[1]})"
        )
    fields = {"water_depth": grid.water_depth, "current_u": grid.current_u, "current_v": grid.current_v}
    fields.update({f"sediment_{k}": v for k, v in (grid.sediment_params or {}).items()})
    for name, arr in fields.items():
        if arr is None:
            continue
        bad = np.argwhere(np.isinf(arr))
        if bad.size:
            j, i = (int(v) for v in bad[0])
            raise MapError(
                f"environment grid: {name} is {arr[j, i]} at {_cell_label(grid, j, i)} "
                f"({len(bad)} infinite value{'s' * (len(bad) > 1)}); give a finite value, or NaN for "
                f"missing data"
            )
    status = grid.cell_status()
    if not np.any(status == CELL_COMPUTED):
        land = int(np.count_nonzero(status == CELL_LAND))
        raise MapError(
            f"environment grid: no cell to compute among its {status.size}: {land} land (water_depth "
            f"missing or <= 0), {status.size - land} without sediment data" + _sign_hint(grid)
        )


def _sign_hint(grid: EnvironmentGrid) -> str:
    """How water_depth was read, when no finite value is a water depth > 0 (the grid may
    follow the other convention than its attributes say)."""
    finite = grid.water_depth[np.isfinite(grid.water_depth)]
    if finite.size == 0 or np.any(finite > 0):
        return ""
    hint = f"; water_depth was read as {grid.vertical}"
    if grid.vertical.startswith("a depth (no positive"):
        hint += ": if it is an elevation (the sea negative), give it the attribute positive = 'up'"
    return hint


def _read_classes(da) -> np.ndarray:
    """Names of the catalogue classes of an integer-coded sediment_class field (None: no data)."""
    known = class_names()
    meanings = da.attrs.get("flag_meanings")
    if meanings is not None:
        names = str(meanings).split()
        values = da.attrs.get("flag_values")
        values = list(range(len(names))) if values is None else [int(v) for v in np.atleast_1d(values)]
        if len(values) != len(names):
            raise MapError(
                f"environment grid: sediment_class has {len(values)} flag_values but "
                f"{len(names)} flag_meanings"
            )
        table = dict(zip(values, names))
    else:
        labels = da.attrs.get("labels", da.attrs.get("class_names"))
        if labels is None:
            raise MapError(
                "environment grid: sediment_class needs flag_values/flag_meanings "
                "(CF flags) or a 'labels' attribute naming the catalogue class of each "
                f"code; classes: {', '.join(known)}"
            )
        names = [s.strip() for s in str(labels).replace(",", " ").split()]
        table = dict(enumerate(names))
    for name in table.values():
        if name not in known:
            raise MapError(
                "environment grid: sediment_class: " + unknown_name_message("sediment class", name, known)
            )
    vals = np.asarray(da.values, dtype=np.float64)
    out = np.full(vals.shape, None, dtype=object)
    fill = da.attrs.get("_FillValue", da.encoding.get("_FillValue"))
    for idx in np.ndindex(vals.shape):
        v = vals[idx]
        if not np.isfinite(v) or (fill is not None and v == float(fill)):
            continue
        name = table.get(int(v))
        if name is None or v != int(v):
            raise MapError(
                f"environment grid: sediment_class value {v:g} at cell {idx} is not "
                f"one of the codes {sorted(table)}"
            )
        out[idx] = name
    return out


# ---------------------------------------------------------------------------
# per-cell scenario and seed
# ---------------------------------------------------------------------------
def cell_seed(seed: int, index: int) -> int:
    """Seed of cell ``index`` (row-major flat index ``j * nx + i``) of a map with seed
    ``seed``: the first 8 bytes, little-endian, of SHA-256 of the ASCII text
    ``"mineburial-map-cell:<seed>:<index>"`` (decimal integers), an integer in [0, 2**64).

    Deterministic, platform independent, and different cells get unrelated streams.
    """
    digest = hashlib.sha256(f"{_SEED_TAG}:{int(seed)}:{int(index)}".encode("ascii")).digest()
    return int.from_bytes(digest[:8], "little")


#: how a map seeds its cells: ``"index"`` (default) :func:`cell_seed` of the cell's row-major index, every
#: cell its own ensemble; ``"inputs"`` :func:`inputs_seed` of the cell's resolved scenario, so cells with
#: identical inputs share one ensemble, computed once (docs/maps.md, "Cells with identical inputs")
CELL_SEEDS = ("index", "inputs")
_INPUTS_SEED_TAG = "mineburial-map-inputs"


def inputs_digest(cell_raw: Mapping) -> str | None:
    """SHA-256 (hex) of a cell's scenario dict ``cell_raw`` in a canonical form: JSON with sorted keys,
    floats by ``repr`` (exact), numpy arrays by dtype, shape and the SHA-256 of their bytes, dataclasses by
    their type and fields. Two cells have the same digest exactly when their scenarios are equal value for
    value (up to SHA-256 collisions). None when the scenario holds a value of another kind (the cell is
    then never merged with another)."""

    def encode(obj):
        if isinstance(obj, np.ndarray):
            a = np.ascontiguousarray(obj)
            return {"__ndarray__": [a.dtype.str, list(a.shape), hashlib.sha256(a.tobytes()).hexdigest()]}
        if isinstance(obj, np.generic):
            return obj.item()
        if isinstance(obj, pathlib.PurePath):
            return {"__path__": str(obj)}
        if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
            fields = {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
            return {"__dataclass__": type(obj).__qualname__, **fields}
        raise TypeError(type(obj).__name__)

    try:
        text = json.dumps(cell_raw, sort_keys=True, default=encode, allow_nan=True)
    except (TypeError, ValueError):
        return None
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def inputs_seed(seed: int, digest: str) -> int:
    """Seed of the cells whose scenario has the :func:`inputs_digest` ``digest``, in a map with seed
    ``seed`` and ``cell_seeds = "inputs"``: the first 8 bytes, little-endian, of SHA-256 of the ASCII
    text ``"mineburial-map-inputs:<seed>:<digest>"``, an integer in [0, 2**64)."""
    text = f"{_INPUTS_SEED_TAG}:{int(seed)}:{digest}"
    return int.from_bytes(hashlib.sha256(text.encode("ascii")).digest()[:8], "little")


def cell_scenario(raw: Mapping, grid: EnvironmentGrid, j: int, i: int) -> dict:
    """The scenario dict of cell (j, i): ``raw`` with the cell's environment overriding
    ``environment.water_depth``, the sediment profile (``sediment.class`` or the linear
    ``density``/``density_gradient``/``strength``/``strength_gradient``; the resistance
    options are kept) and, when the grid has a current, the current (``velocity`` of a
    ``none``/``uniform`` current, ``surface_velocity`` of a ``power_law`` one).

    Overridden fields lose any distribution they had in ``raw``. The sediment density
    gradient comes from ``sediment_density_gradient`` when the grid has it, else from a
    fixed linear ``density_gradient`` of the scenario, else 0.
    """
    d = copy.deepcopy(dict(raw))
    ens = d.pop("ensemble", None)
    if isinstance(ens, Mapping) and "coefficients" in ens:  # each cell draws from the base's posterior
        d["ensemble"] = {"coefficients": ens["coefficients"]}
    env = d.setdefault("environment", {})
    env["water_depth"] = float(grid.water_depth[j, i])
    sed = d.setdefault("sediment", {})
    old_gradient = sed.get("density_gradient")
    for key in _SEDIMENT_KEYS:
        sed.pop(key, None)
    if grid.sediment_class is not None:
        sed["class"] = str(grid.sediment_class[j, i])
    else:
        p = grid.sediment_params
        for key in ("density", "strength", "strength_gradient"):
            sed[key] = float(p[key][j, i])
        if "density_gradient" in p:
            sed["density_gradient"] = float(p["density_gradient"][j, i])
        elif isinstance(old_gradient, (int, float)) and not isinstance(old_gradient, bool):
            sed["density_gradient"] = float(old_gradient)
        else:
            sed["density_gradient"] = 0.0
    if grid.current_u is not None:
        u, v = float(grid.current_u[j, i]), float(grid.current_v[j, i])
        if math.isfinite(u) and math.isfinite(v):
            cur = env.get("current", {"kind": "none"}) or {"kind": "none"}
            kind = cur.get("kind", "none")
            if kind == "power_law":
                new = {"kind": "power_law", "surface_velocity": [u, v]}
                if "exponent" in cur:
                    new["exponent"] = cur["exponent"]
            elif kind in ("none", "uniform"):
                new = {"kind": "uniform", "velocity": [u, v]}
            else:
                raise MapError(
                    f"the environment grid gives a current but the scenario's "
                    f"current is of kind '{kind}', which a cell value cannot replace; "
                    f"use kind 'uniform' or 'power_law' (or remove the current from "
                    f"the grid)"
                )
            env["current"] = new
    return d


def _cell_label(grid: EnvironmentGrid, j: int, i: int) -> str:
    y = float(grid.ds[grid.ydim].values[j])
    x = float(grid.ds[grid.xdim].values[i])
    if grid.geographic:
        return f"cell ({j}, {i}) at latitude {y:.5f}, longitude {x:.5f}"
    return f"cell ({j}, {i}) at {grid.ydim} = {y:g}, {grid.xdim} = {x:g}"


# ---------------------------------------------------------------------------
# the map
# ---------------------------------------------------------------------------
def _cell_statistics(spec, chunks) -> dict:
    """Statistics of one cell from its chunk results in drop order, name -> values: the
    impact's and each post-impact process's
    (:meth:`~mineburial.systems.mine.processes.registry.Process.statistics`; scour's at each lead time). Plain
    arrays: a Dataset's item access and a merge per cell cost about as much as the stage of 20 drops (measured
    with
    benchmarks/bench_map_scour.py)."""
    summary = np.concatenate([r["summary"] for r in chunks])
    status = np.concatenate([r["status"] for r in chunks])
    parts = [burial_statistics(summary, status, class_basis=spec.class_basis, outputs=MAP_OUTPUTS)]
    for process, own in processes.active(spec.processes):
        parts.append(process.statistics(own, chunks, spec.class_basis))
    out = {name: v.values for part in parts for name, v in part.variables.items()}
    if spec.posterior is not None:  # the band across the posterior's coefficient sets (docs/calibration.md)
        sets = np.concatenate([r["input:" + posterior.SET_INPUT] for r in chunks])
        out.update(
            {
                k: v.values
                for k, v in epistemic.band_variables(summary, status, sets, spec.class_basis).items()
            }
        )
    return out


# ---------------------------------------------------------------------------
# per-cell sequential stopping
# ---------------------------------------------------------------------------
#: default of ``min_drops`` (capped at the cell maximum ``n``): a floor so that no cell is decided on
#: a handful of drops that all fell in one class: a class of 3 % of the drops is missed by the first
#: 100 drops with probability 0.97**100 = 4.8 %, by the first 35 (where a one-class cell meets a
#: target of 0.05) with 0.97**35 = 34 %
MIN_DROPS_DEFAULT = 100
#: cells whose drops are in flight at once on a dask cluster with sequential stopping: each round
#: submits the next segment of each (one flat list); bounds the per-drop values held in memory
SEQUENTIAL_CELLS_IN_FLIGHT = 256


@dataclasses.dataclass(frozen=True)
class Stopping:
    """Per-cell sequential stopping (docs/maps.md, "Sequential stopping").

    A cell is looked at only at its *decision points*, fixed drop counts of its own drop
    sequence: ``min_drops``, ``min_drops + step``, ... and its maximum ``n`` (with Sobol'
    sampling the powers of two from ``min_drops`` to ``n``, where the net is balanced). It stops
    at the first where every class probability's Wilson 95 % interval (impact, and with
    ``[scour]`` every lead time's) has a half-width ``(upper - lower) / 2`` under
    ``target_half_width``; a NaN interval (no drop at rest) is never under it. The drops are a
    pure function of (cell seed, drop index), so a cell that stops at ``m`` drops holds exactly
    the statistics of ``mineburial run`` of its scenario with its seed and ``-n m``, whatever
    the threads, chunks, cluster or resume (tests/test_map_sequential.py)."""

    target_half_width: float
    min_drops: int
    step: int | None  # None with Sobol' sampling (powers of two)

    def points(self, n: int) -> list[int]:
        """The decision points of a cell of at most ``n`` drops, increasing, the last ``n``."""
        if self.step is None:
            pts = [1 << e for e in range(64) if self.min_drops <= (1 << e) < n]
        else:
            pts = list(range(self.min_drops, n, self.step))
        return pts + [n]

    def record(self, n: int, sampling: str) -> dict:
        """The settings as the map's ``scenario`` and ``sequential_stopping`` attributes record them."""
        return {
            "target_half_width": self.target_half_width,
            "min_drops": self.min_drops,
            "max_drops": int(n),
            "step": self.step,
            "decision_points": "powers of two from min_drops, and max_drops"
            if self.step is None
            else "min_drops + j * step (j = 0, 1, ...) below max_drops, and max_drops",
            "criterion": "every class probability's Wilson 95 % interval (impact and, with [scour], every "
            "lead time's) has (upper - lower) / 2 < target_half_width; the epistemic band is not part "
            "of it",
        }


def check_stopping(target_half_width, min_drops, step, n: int, sampling: str) -> Stopping | None:
    """The sequential stopping of a map with at most ``n`` drops a cell, or None (off: no
    ``target_half_width``); bad values stop with one line naming the option, the value and the
    allowed range."""

    def refuse(name, value, allowed):
        opt = "--" + name.replace("_", "-")
        raise MapError(f"{name} ({opt}) = {value!r} is outside the allowed range {allowed}")

    if target_half_width is None:
        for name, value in (("min_drops", min_drops), ("step", step)):
            if value is not None:
                raise MapError(
                    f"{name} (--{name.replace('_', '-')}) = {value!r} sets the sequential stopping of "
                    "the cells; give target_half_width (--target-half-width) too, or leave it out"
                )
        return None

    def integer(value):
        return isinstance(value, (int, np.integer)) and not isinstance(value, bool)

    if isinstance(target_half_width, bool) or not isinstance(target_half_width, (int, float, np.number)):
        refuse("target_half_width", target_half_width, "(0, 0.5] (a probability's half-width)")
    target = float(target_half_width)
    if not (0.0 < target <= 0.5):  # also NaN; a 95 % Wilson interval is at most [0, 1] wide
        refuse("target_half_width", target_half_width, "(0, 0.5] (a probability's half-width)")
    if min_drops is None:
        min_drops = min(MIN_DROPS_DEFAULT, n)
    if not integer(min_drops) or not 1 <= min_drops <= n:
        refuse("min_drops", min_drops, f"[1, {n}] (an integer, at most -n, the drops a cell at most)")
    if sampling == "sobol":
        if step is not None:
            raise MapError(
                f"step (--step) = {step!r}: with sampling = 'sobol' a cell is looked at only at powers "
                "of two (where the net is balanced); leave --step out"
            )
        return Stopping(target, int(min_drops), None)
    if step is None:
        step = min_drops
    if not integer(step) or not 1 <= step <= n:
        refuse("step", step, f"[1, {n}] (an integer number of drops, at most -n)")
    return Stopping(target, int(min_drops), int(step))


def _under_target(stats: Mapping, target: float) -> bool:
    """Whether every class probability's Wilson interval in a cell's statistics (impact and scour,
    not the epistemic band) has a half-width under ``target`` (NaN: not under)."""
    widths = [
        (np.asarray(stats[name[: -len("_lower")] + "_upper"]) - np.asarray(stats[name])) / 2.0
        for name in stats
        if name.endswith("class_probability_lower")
    ]
    return bool(widths) and all(bool(np.all(w < target)) for w in widths)  # NaN < target is False


def _segments(points: list[int], chunk_size: int) -> list[list[tuple[int, int]]]:
    """The chunks ``(start, stop)`` between consecutive decision points, ``chunk_size`` drops at
    most each: a decision point is always a chunk boundary, so no chunk is ever cut."""
    out, a = [], 0
    for b in points:
        out.append([(s, min(s + chunk_size, b)) for s in range(a, b, chunk_size)])
        a = b
    return out


def _run_sequential(specs: Mapping, stores: Mapping, stopping: Stopping, *, client=None, progress=False):
    """Run the cells ``specs`` (cell -> ensemble) with sequential stopping; a list of
    ``(cell, chunks of its first m drops in drop order, statistics)``.

    Each cell goes through its decision points in order: the chunks of the next segment are
    loaded from its store (``stores``: cell -> ChunkStore, resume) or computed, then the cell's
    statistics of its drops so far decide whether it stops. Cells are taken in rounds: each round
    computes the missing chunks of the current segment of every cell in flight (here one cell at a
    time, its chunks spread over the numba threads; on a dask cluster
    :data:`SEQUENTIAL_CELLS_IN_FLIGHT` cells, one flat list of tasks a round). The rounds only
    decide what is computed when: a cell's result depends on its own drops alone."""
    order = sorted(specs)
    segments = {k: _segments(stopping.points(specs[k].n), specs[k].chunk_size) for k in order}
    points = {k: stopping.points(specs[k].n) for k in order}
    level = dict.fromkeys(order, 0)
    pending: dict = {}  # cell -> {(start, stop): chunk} of its current segment
    got: dict = {}  # cell -> chunks of its completed segments, in drop order
    finished = []
    unit = specs[order[0]].unit if order else "drops"
    bar = runner.Progress(sum(specs[k].n for k in order), enabled=progress, unit=unit)
    done = 0

    def enter(k):
        nonlocal done
        pending[k] = {}
        store = stores.get(k)
        for b in segments[k][level[k]]:
            res = None if store is None else store.load(*b)
            if res is not None:
                pending[k][b] = res
                done += b[1] - b[0]

    def advance(k) -> list:
        """The chunks cell ``k`` still needs for its current segment; [] once it stopped."""
        nonlocal done
        while True:
            seg = segments[k][level[k]]
            missing = [b for b in seg if b not in pending[k]]
            if missing:
                return missing
            have = pending.pop(k)
            got[k].extend(have[b] for b in seg)
            st = _cell_statistics(specs[k], got[k])
            if level[k] == len(points[k]) - 1 or _under_target(st, stopping.target_half_width):
                done += specs[k].n - points[k][level[k]]  # the drops the cell does not need
                finished.append((k, got.pop(k), st))
                return []
            level[k] += 1
            enter(k)

    window = 1 if client is None else SEQUENTIAL_CELLS_IN_FLIGHT
    queue = list(reversed(order))
    active: list = []
    first = True
    bar.update(done)
    while queue or active:
        while queue and len(active) < window:
            k = queue.pop()
            got[k] = []
            enter(k)
            active.append(k)
        todo = []
        for k in list(active):
            missing = advance(k)
            if missing:
                todo += [(k, specs[k], s, e, stores.get(k)) for s, e in missing]
            else:
                active.remove(k)
        bar.update(done)
        if not todo:
            continue
        if client is None:
            stream = runner._run_local(todo)  # the driver's own loop: resumes a cut chunk's head
        else:
            stream = run_tasks_distributed(client, todo, warm=first)
            first = False
        for k, b, res in stream:
            pending[k][b] = res
            done += b[1] - b[0]
            bar.update(done)
    bar.update(done, final=True)
    return finished


def _merged(parts) -> xr.Dataset:
    """The datasets ``parts`` merged (shared coordinates must agree), encodings kept."""
    out = xr.merge(parts, combine_attrs="drop_conflicts", compat="no_conflicts", join="exact")
    for part in parts:
        for name, da in part.variables.items():
            out[name].encoding.update(da.encoding)
    return out


def _cell_variables(template) -> tuple:
    """The statistics copied per cell: :data:`mineburial.io.variables.MAP_STATISTICS` and every
    variable of the post-impact processes' statistics (``<section>_*``, their per-cell declarations:
    :meth:`mineburial.io.variables.ProcessVariables.map_statistics`)."""
    prefixes = tuple(f"{name}_" for name in processes.PROCESSES)
    own = tuple(v for v in template.data_vars if str(v).startswith(prefixes))
    return V.MAP_STATISTICS + own + tuple(v for v in V.MAP_EPISTEMIC if v in template)


# ---------------------------------------------------------------------------
# what a post-impact process reads per cell (scour's gridded forcing: systems/mine/processes/scour_map.py)
# ---------------------------------------------------------------------------
def _scenario_raw(scenario):
    """The scenario as a dict when it is a file or a dict; None otherwise, or when the file
    cannot be read (engine.load_ensemble then reports it)."""
    if isinstance(scenario, Mapping):
        return dict(scenario)
    if isinstance(scenario, (str, pathlib.Path)):
        try:
            return read_toml(pathlib.Path(scenario))
        except (OSError, ValueError, cfg.ScenarioError):
            return None
    return None


@dataclasses.dataclass(frozen=True)
class MapCells:
    """What a post-impact process sees of a map's grid when it reads inputs per cell
    (:meth:`mineburial.systems.mine.processes.registry.Process.cell_inputs`: scour's gridded forcing)."""

    dims: tuple  # the environment grid's (y, x) dimension names
    y: np.ndarray  # their coordinate values
    x: np.ndarray
    geographic: bool  # latitude/longitude axes (else projected y/x)
    computed: np.ndarray  # (ny, nx) bool: the cells the map computes (not land, with sediment data)
    label: Callable[[int, int], str]  # "cell (j, i) at latitude ..., longitude ..." of an error line


def map_cells(grid: EnvironmentGrid) -> MapCells:
    """The :class:`MapCells` of the environment grid ``grid``."""
    return MapCells(
        (grid.ydim, grid.xdim),
        grid.ds[grid.ydim].values,
        grid.ds[grid.xdim].values,
        grid.geographic,
        grid.cell_status() == CELL_COMPUTED,
        functools.partial(_cell_label, grid),
    )


def _load_base(scenario, environment, **settings):
    """(base ensemble spec, environment grid, what the post-impact processes read per cell of the
    grid ({section: its cell inputs}, :meth:`~mineburial.systems.mine.processes.registry.Process.cell_inputs`:
    scour's gridded forcing), the scenario's folder) of a map. A process with cell inputs gives
    the base scenario its section (``base_section``; scour's: the series of the first cell to
    compute, recorded as the grid file alone); the environment is then read first."""
    base_dir = None
    if isinstance(scenario, (str, pathlib.Path)):
        base_dir = pathlib.Path(scenario).resolve().parent
    raw = _scenario_raw(scenario)
    grid = None

    def cells() -> MapCells:
        nonlocal grid
        if grid is None:
            grid = read_environment(environment)
        return map_cells(grid)

    per_cell = {}
    for name, process in processes.PROCESSES.items():
        if name not in (raw or {}):
            continue
        try:
            found = process.cell_inputs(raw[name], base_dir=base_dir, cells=cells)
        except MapError:
            raise
        except cfg.ScenarioError as exc:
            raise MapError(str(exc)) from None
        if found is not None:
            per_cell[name] = found
    if per_cell:
        raw = dict(raw, **{name: found.base_section(raw[name]) for name, found in per_cell.items()})
    base = engine.load_ensemble(raw if per_cell else scenario, per_drop=False, base_dir=base_dir, **settings)
    return base, grid if grid is not None else read_environment(environment), per_cell, base_dir


def run_map(
    scenario,
    environment,
    n: int | None = None,
    seed: int | None = None,
    *,
    client=None,
    output=None,
    progress: bool = False,
    chunk_size: int | None = None,
    target_half_width: float | None = None,
    min_drops: int | None = None,
    step: int | None = None,
    cell_seeds: str = "index",
) -> xr.Dataset:
    """Burial-probability map: one ensemble of ``n`` drops per water cell of ``environment``.

    Parameters
    ----------
    scenario : ensemble scenario (path, dict, Scenario or None for the embedded default).
    environment : environment grid (path or :class:`xarray.Dataset`, docs/maps.md).
    n : drops per cell (default: the scenario's ``[ensemble] n``).
    seed : map seed (default: the scenario's); cell ``k`` (row-major index) runs with
        :func:`cell_seed` ``(seed, k)``.
    client : dask.distributed.Client, optional: all (cell, chunk) tasks go to its cluster.
    output : path, optional: write the map there (NetCDF, atomically); finished chunks
        are kept in ``OUTPUT.parts/cell-<k>/`` until then, so an interrupted map resumes
        (the run driver and chunk store of :func:`mineburial.ensembles.runner.run_jobs`:
        a rerun reuses only chunks of the same run identity, which includes the contents
        of the environment grid; a second live run on the same output is refused).
    progress : print rate-limited progress lines (drops over all cells) to stderr.
    chunk_size : drops per chunk (default: the scenario's ``[ensemble] chunk_size``).
    target_half_width, min_drops, step : per-cell sequential stopping (:class:`Stopping`,
        docs/maps.md): with ``target_half_width`` a cell stops at the first of its decision
        points (``min_drops``, then every ``step`` drops; ``n`` is the maximum) where every
        class probability's Wilson 95 % interval has a half-width under the target. Default
        (None): every cell runs ``n`` drops.
    cell_seeds : ``"index"`` (default): cell ``k`` has the seed :func:`cell_seed` ``(seed, k)``, every cell
        its own ensemble; ``"inputs"``: the seed :func:`inputs_seed` of the cell's resolved scenario
        (:func:`inputs_digest`), so cells with identical inputs share one ensemble, computed once and
        copied to each of them (docs/maps.md, "Cells with identical inputs").

    Returns the map as a CF-1.11 :class:`xarray.Dataset` (docs/maps.md).
    """
    base, grid, per_cell, base_dir = _load_base(scenario, environment, n=n, seed=seed, chunk_size=chunk_size)
    stopping = check_stopping(target_half_width, min_drops, step, base.n, base.sampling)
    check_cell_seeds(cell_seeds)
    runner.check_run(base, what="each cell of the map")
    runner.warn_run(base)
    status = grid.cell_status()
    ny, nx = grid.shape
    _check_map_memory(base, status, per_cell)
    plan = _cell_plan(base, grid, per_cell, base_dir, status, cell_seeds)
    specs = plan.specs
    template = _cell_statistics_template(base)
    names = _cell_variables(template)
    arrays = {name: _empty_cell_array(template[name], ny, nx) for name in names}
    drops = np.zeros((ny, nx), dtype=np.int64)
    invalid: dict = {}

    def reduce(stream):
        for k, chunks, st in stream:
            st = _cell_statistics(specs[k], chunks) if st is None else st
            used = sum(len(c["status"]) for c in chunks)
            for j, i in plan.members[k]:  # the cells with the inputs of cell k (itself alone by default)
                for name in names:
                    arrays[name][..., j, i] = st[name]
                drops[j, i] = used
            for rule, (count, example) in merge_invalid_reasons(chunks).items():
                invalid.setdefault(rule, [0, example])[0] += count

    def cells(stores=None):
        """(cell, its chunks in drop order, its statistics or None) as cells complete, in cell order
        with sequential stopping (so the first example of an invalid input does not depend on the
        order the cells finished in)."""
        if stopping is None:
            jobs = [runner.Job(k, spec, None if stores is None else stores[k]) for k, spec in specs.items()]
            for k, chunks in runner.run_jobs(jobs, client=client, progress=progress):
                yield k, chunks, None
            return
        done = _run_sequential(specs, stores or {}, stopping, client=client, progress=progress)
        yield from sorted(done, key=lambda item: item[0])

    def finish():
        ds = _assemble(grid, status, arrays, drops, template, base, __version__, stopping, plan)
        ds.attrs["scenario_name"] = (
            pathlib.Path(scenario).stem if isinstance(scenario, (str, pathlib.Path)) else base.base.mine.name
        )
        if invalid:
            ds.attrs["invalid_inputs"] = mine.invalid_inputs_text(invalid)
        return ds

    if output is None:
        reduce(cells())
        return finish()
    inputs, env_files = _map_inputs(scenario, base, environment, per_cell, specs)
    with OutputRun(output, inputs) as out:
        reduce(cells({k: out.store(spec, f"cell-{k:09d}", env_files) for k, spec in specs.items()}))
        ds = finish()
        out.commit(ds)
    return ds


def check_cell_seeds(cell_seeds) -> None:
    """Refuse, in one line, a ``cell_seeds`` (``--cell-seeds``) other than those of :data:`CELL_SEEDS`."""
    if cell_seeds not in CELL_SEEDS:
        raise MapError(
            f"cell_seeds (--cell-seeds) = {cell_seeds!r} is not one of {', '.join(map(repr, CELL_SEEDS))}"
        )


@dataclasses.dataclass(frozen=True)
class _CellPlan:
    """Which ensembles a map computes and where each one's statistics go."""

    specs: dict  # k -> the ensemble of cell k (row-major), for each cell that is computed
    members: dict  # k -> the (j, i) cells that take cell k's statistics (k itself first)
    seeds: np.ndarray  # (ny, nx) uint64: each cell's seed, 0 for skipped cells
    cell_seeds: str  # "index" or "inputs" (CELL_SEEDS)


def _cell_plan(base, grid, per_cell, base_dir, status, cell_seeds: str = "index") -> _CellPlan:
    """The ensemble of each computed cell, by row-major index ``k``, seeded :func:`cell_seed`; with
    ``cell_seeds = "inputs"`` seeded :func:`inputs_seed`, and one ensemble (that of the first such
    cell) for all the cells whose scenario is the same (:func:`inputs_digest`)."""
    ny, nx = grid.shape
    raw = copy.deepcopy(base.raw)
    specs: dict[int, mine.EnsembleSpec] = {}
    members: dict[int, list] = {}
    seeds = np.zeros((ny, nx), dtype=np.uint64)
    first: dict[str, int] = {}  # inputs digest -> the first cell with it
    for j in range(ny):
        for i in range(nx):
            if status[j, i] != CELL_COMPUTED:
                continue
            k = j * nx + i
            try:
                cell_raw = cell_scenario(raw, grid, j, i)
                for name, found in per_cell.items():  # the cell's own inputs (scour: its series)
                    cell_raw[name] = found.section(cell_raw[name], j, i)
                seed = cell_seed(base.seed, k)
                if cell_seeds == "inputs":
                    digest = inputs_digest(cell_raw)
                    if digest is not None:
                        seed = inputs_seed(base.seed, digest)
                        if digest in first:  # computed once, for the first cell with these inputs
                            seeds[j, i] = seed
                            members[first[digest]].append((j, i))
                            continue
                        first[digest] = k
                seeds[j, i] = seed
                members[k] = [(j, i)]
                specs[k] = engine.load_ensemble(
                    cell_raw,
                    n=base.n,
                    seed=seed,
                    sampling=base.sampling,
                    chunk_size=base.chunk_size,
                    per_drop=False,
                    class_basis=base.class_basis,
                    base_dir=base_dir,
                )
            except cfg.ScenarioError as exc:
                raise MapError(f"{_cell_label(grid, j, i)}: {exc}") from None
    return _CellPlan(specs, members, seeds, cell_seeds)


def _empty_cell_array(da, ny, nx) -> np.ndarray:
    """A (statistic's shape, ny, nx) array for ``da`` per cell: 0 for integers, NaN otherwise."""
    fill = 0 if da.dtype.kind in "iu" else np.nan
    return np.full(da.shape + (ny, nx), fill, dtype=da.dtype)


def _map_inputs(scenario, base, environment, per_cell, specs):
    """(input paths, (file, digest) pairs of the grids) that identify a map's run on disk."""
    env_path = None if isinstance(environment, xr.Dataset) else pathlib.Path(environment)
    env_files = ((str(env_path.resolve()), file_digest(env_path)),) if env_path else ()
    read = [(pathlib.Path(f), digest) for found in per_cell.values() for f, digest in found.files]
    grid_files = [f for f, _ in read]
    env_files += tuple((str(f.resolve()), digest) for f, digest in read)
    inputs = (
        runner.input_paths(scenario, base)
        + ([env_path] if env_path else [])
        + grid_files
        + [pathlib.Path(f) for spec in specs.values() for f, _ in spec.input_files]
    )
    return inputs, env_files


#: bytes of memory a map needs per cell it computes (the cell's scenario and ensemble, its
#: chunk store and tasks, its statistics) and per grid cell (the grid, the map's arrays and
#: their copies while the file is written): tracemalloc peaks of run_map with an output, a
#: 12 x 12 grid and n = 2, 9.6 kB a cell in all, doubled; the per-drop values of a cell's
#: ensemble in flight come on top (:func:`mineburial.ensembles.runner.memory_needed`)
MAP_BYTES_A_COMPUTED_CELL = 20_000
MAP_BYTES_A_GRID_CELL = 1_000


def _check_map_memory(base, status: np.ndarray, per_cell=None) -> None:
    """Refuse, before computing, a map whose cells would not fit in the available memory: with
    a post-impact process its per-cell arrays (three copies: the arrays, the Dataset, the file
    being written) and its inputs per cell (scour's gridded forcing: its fields and each cell's
    copy) count too."""
    n_comp = int(np.count_nonzero(status == CELL_COMPUTED))
    per_grid_cell = MAP_BYTES_A_GRID_CELL
    for process, own in processes.active(base.processes):
        template = process.statistics(own, [], base.class_basis)
        per_grid_cell += 3 * sum(da.nbytes for da in template.data_vars.values())
    forcing_bytes = sum(found.nbytes for found in (per_cell or {}).values())
    need = (
        n_comp * MAP_BYTES_A_COMPUTED_CELL
        + status.size * per_grid_cell
        + forcing_bytes
        + runner.memory_needed(base)
    )
    refusal = memory_refusal(
        need,
        f"the map over the {status.shape[0]} x {status.shape[1]} environment grid "
        f"({n_comp} cells to compute)",
        "split the grid into parts (one map each) or coarsen it",
    )
    if refusal:
        raise MapError(refusal)


def _cell_statistics_template(spec) -> xr.Dataset:
    """Statistics of an empty cell: the shapes, coordinates and attributes of the map
    variables (every value NaN / 0)."""
    st = burial_statistics(
        np.empty((0, layout.N_SUMMARY)),
        np.empty(0, dtype=np.int8),
        class_basis=spec.class_basis,
        outputs=MAP_OUTPUTS,
    )
    if spec.posterior is not None:
        band = epistemic.band_variables(
            np.empty((0, layout.N_SUMMARY)), np.empty(0, np.int8), [], spec.class_basis
        )
        st = st.assign(band)
    found = processes.active(spec.processes)
    if not found:
        return st
    return _merged([st] + [process.statistics(own, [], spec.class_basis) for process, own in found])


def _horizontal_coords(grid: EnvironmentGrid) -> dict:
    """The map's coordinates by their names in the map family: the grid's axes as the grid gives
    them (``y``, ``x``: DataArrays with the grid's names and attributes) and, on a projected
    grid, the latitude and longitude of each cell where they can be had."""
    ds = grid.ds
    coords: dict = {}
    for key, dim in ((V.MAP_Y, grid.ydim), (V.MAP_X, grid.xdim)):
        c = ds[dim]
        attrs = {k: v for k, v in c.attrs.items() if k not in ("_FillValue",)}
        coords[key] = xr.DataArray(np.asarray(c.values), dims=(dim,), attrs=attrs)
    if grid.geographic:
        coords[V.MAP_Y].attrs.setdefault("standard_name", "latitude")
        coords[V.MAP_Y].attrs.setdefault("units", "degrees_north")
        coords[V.MAP_Y].attrs.setdefault("axis", "Y")
        coords[V.MAP_X].attrs.setdefault("standard_name", "longitude")
        coords[V.MAP_X].attrs.setdefault("units", "degrees_east")
        coords[V.MAP_X].attrs.setdefault("axis", "X")
        return coords
    lat = lon = None
    for name in ds.coords:
        c = ds[name]
        if c.ndim == 2 and set(c.dims) == {grid.ydim, grid.xdim}:
            if _is_axis(c, "lat"):
                lat = c.transpose(grid.ydim, grid.xdim)
            elif _is_axis(c, "lon"):
                lon = c.transpose(grid.ydim, grid.xdim)
    if lat is None or lon is None:
        lat, lon = _latlon_from_projection(grid)
    if lat is not None:
        coords["latitude"] = np.asarray(getattr(lat, "values", lat))
        coords["longitude"] = np.asarray(getattr(lon, "values", lon))
    return coords


def _latlon_from_projection(grid: EnvironmentGrid):
    """2-D latitude/longitude of a projected grid from its grid mapping (needs pyproj)."""
    try:
        import pyproj
    except ImportError:
        return None, None
    try:
        crs = pyproj.CRS.from_cf(dict(grid.ds[grid.grid_mapping].attrs))
        tr = pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
    except Exception:  # pragma: no cover - an exotic mapping pyproj cannot read
        return None, None
    y = np.asarray(grid.ds[grid.ydim].values, dtype=np.float64)
    x = np.asarray(grid.ds[grid.xdim].values, dtype=np.float64)
    xx, yy = np.meshgrid(x, y)
    lon, lat = tr.transform(xx, yy)
    return np.asarray(lat), np.asarray(lon)


def _assemble(grid, status, arrays, drops, template, base, version, stopping=None, plan=None) -> xr.Dataset:
    """The map Dataset, built from the registry's map family (:func:`mineburial.io.dataset.build`):
    per-cell results, the cells' status and seeds, the environment used. The family's ``y``, ``x``
    and ``grid_mapping`` take the grid's names."""
    extra = {"grid_mapping": grid.grid_mapping} if grid.grid_mapping else {}
    data = _result_fields(arrays, template, extra)
    data["most_likely_burial_class"] = (_most_likely_class(arrays["burial_class_probability"]), extra)
    data.update(_cell_fields(grid, status, plan.seeds, plan.cell_seeds, extra))
    data["cell_drop_count"] = (drops, extra)
    data.update(_environment_fields(grid, extra))
    coords = {c: template[c] for c in V.map_shared_coords() if c in template.coords}
    coords.update(_horizontal_coords(grid))
    names = {V.MAP_Y: grid.ydim, V.MAP_X: grid.xdim}
    if grid.grid_mapping:
        names["grid_mapping"] = grid.grid_mapping
    attrs = _global_attrs(grid, status, base, version, stopping, drops, plan)
    return build(data, coords, attrs, kind="map", version=version, names=names)


def _result_fields(arrays, template, extra) -> dict:
    """Each cell's ensemble statistics (``arrays``) with the run-time attributes of the template
    run (the class basis; not its sample size, which is per cell), and the class bounds."""
    family = V.family("map")
    data: dict = {}
    for name in _cell_variables(template):
        declared = family[name].cf_attrs()
        runtime = {k: v for k, v in template[name].attrs.items() if k not in declared and k != "sample_size"}
        data[name] = (arrays[name], {**runtime, **extra})
    for name in ("burial_class_lower_percent", "burial_class_upper_percent"):
        data[name] = template[name].values
    return data


def _most_likely_class(prob) -> np.ndarray:
    """The class of highest probability per cell (the lower on ties), -1 without data."""
    finite = np.isfinite(prob).all(axis=0)
    likely = np.where(finite, np.argmax(np.where(np.isfinite(prob), prob, -1.0), axis=0), -1)
    return likely.astype(np.int8)


def _cell_fields(grid, status, seeds, cell_seeds, extra) -> dict:
    """Per-cell status, ensemble seed (:func:`cell_seed`, or :func:`inputs_seed` with ``cell_seeds =
    "inputs"``) and the water depth used."""
    seed_attrs = dict(extra)
    if cell_seeds == "inputs":
        seed_attrs["comment"] = (
            "First 8 bytes (little-endian) of SHA-256 of 'mineburial-map-inputs:<seed>:<digest>' with <seed> "
            "the global attribute random_seed and <digest> the SHA-256 of the cell's resolved scenario "
            "(global attribute seed_derivation): cells with identical inputs share the seed and one "
            "ensemble; rerun a cell with mineburial run --seed <cell_seed>. 0 for skipped cells."
        )
    depth = np.where(status == CELL_LAND, np.nan, grid.water_depth)
    how = (
        "Water depth of the cell used by its ensemble (from the environment grid's "
        f"water_depth, read as {grid.vertical})."
    )
    return {
        "cell_status": (status, extra),
        "cell_seed": (seeds, seed_attrs),
        "water_depth": (depth, {"comment": how, **extra}),
    }


def _environment_fields(grid, extra) -> dict:
    """The sediment, currents and grid mapping of the environment grid, as the cells used them."""
    ny, nx = grid.shape
    data: dict = {}
    if grid.sediment_class is not None:
        names = class_names()
        codes = np.full((ny, nx), -1, dtype=np.int8)
        for (j, i), v in np.ndenumerate(grid.sediment_class):
            if v is not None:
                codes[j, i] = names.index(v)
        flags = {"flag_values": np.arange(len(names), dtype=np.int8), "flag_meanings": " ".join(names)}
        data["sediment_class"] = (codes, {**flags, **extra})
    else:
        for key, arr in grid.sediment_params.items():
            data[f"sediment_{key}"] = (arr, extra)
    if grid.current_u is not None:
        data["current_u"] = (grid.current_u, extra)
        data["current_v"] = (grid.current_v, extra)
    if grid.grid_mapping:
        g = grid.ds[grid.grid_mapping]
        data["grid_mapping"] = xr.DataArray(np.int32(0), attrs=dict(g.attrs))
    return data


def _global_attrs(grid, status, base, version, stopping=None, drops=None, plan=None) -> dict:
    """The map's own global attributes (ACDD/CF; :func:`mineburial.io.dataset.build` adds the
    ones every file carries), scenario included."""
    created = ncio.utc_now()
    resolved = _map_scenario(grid, base, stopping, plan)
    scen = ncio.scenario_json(resolved)
    n_cells = int(status.size)
    n_comp = int(np.count_nonzero(status == CELL_COMPUTED))
    ident = json.dumps([scen, str(base.seed), base.n, version, grid.source])
    name = base.base.mine.name
    line = (
        f"{created} mineburial {version}: burial map over {grid.source or 'a grid'}, "
        f"{base.n} drops in each of {n_comp} cells, seed {base.seed}"
    )
    attrs = {
        "title": f"mineburial impact-burial probability map: {name}",
        "summary": (
            "Map of the Monte Carlo prediction of naval mine impact burial: for every "
            "water cell of an environment grid (water depth, seabed sediment, current) an "
            f"ensemble of {base.n} drops of the scenario with the cell's environment was "
            "computed with mineburial (numba-compiled rigid-body impact-burial model after "
            "Chu and Fan 2006, IMPACT35). Per cell: probabilities of the impact-burial "
            "classes 0 %, 0-10 %, 10-20 %, 20-75 %, > 75 % with Wilson 95 % intervals, the "
            "most likely class, mean, standard deviation and quantiles of burial by volume "
            "and penetration depth, and the count of every drop status."
        ),
        "keywords": ncio.KEYWORDS + ", map, grid",
        "id": "mineburial-map-" + hashlib.sha256(ident.encode()).hexdigest()[:16],
        "history": line,
        "date_created": created,
        "product_version": str(version),
        "source": f"mineburial {version} (numba-compiled Monte Carlo impact-burial model)",
        "processing_level": "model output: Monte Carlo ensemble statistics per grid cell",
        "standard_name_vocabulary": ncio.STANDARD_NAME_VOCABULARY,
        "references": ncio.REFERENCES,
        "comment": (
            "Statistics use only drops with status at_rest or buried_sinking; status_count gives "
            "the number of drops with every status code per cell. Skipped cells (cell_status != 0) "
            "hold NaN and zero counts. Format: docs/maps.md of the mineburial sources."
        ),
        "cdm_data_type": "Grid",
        "scenario": scen,
        "random_seed": ncio.seed_attr(base.seed),
        "seed_derivation": resolved["map"]["seed_derivation"],
        "sampling_method": base.sampling,
        "n_drops_per_cell": np.int64(base.n),
        "n_cells": np.int64(n_cells),
        "n_cells_computed": np.int64(n_comp),
        "n_cells_land": np.int64(np.count_nonzero(status == CELL_LAND)),
        "n_cells_no_sediment": np.int64(np.count_nonzero(status == CELL_NO_SEDIMENT)),
        "burial_class_basis": base.class_basis,
        "environment_source": grid.source or "xarray.Dataset",
    }
    for process, own in processes.active(base.processes):  # what each post-impact process adds
        text, extra = process.map_attributes(own)
        attrs["summary"] += text
        attrs.update(extra)
    if stopping is not None:
        attrs["sequential_stopping"] = json.dumps(resolved["map"]["sequential_stopping"], sort_keys=True)
        attrs["n_drops_total"] = np.int64(_drops_computed(drops, plan))
        attrs["history"] += f" (at most; sequential stopping: {int(attrs['n_drops_total'])} drops in all)"
        attrs["summary"] = attrs["summary"].replace(
            f"an ensemble of {base.n} drops",
            f"an ensemble of at most {base.n} drops (fewer where every class probability's Wilson "
            f"95 % interval was narrower than +/- {stopping.target_half_width:g}; cell_drop_count)",
        )
    if plan is not None and plan.cell_seeds == "inputs":
        attrs["cell_seeds"] = "inputs"
        attrs["n_cells_distinct"] = np.int64(len(plan.specs))
        attrs["n_drops_total"] = np.int64(_drops_computed(drops, plan))
        attrs["history"] += (
            f" (cells with identical inputs computed once: {len(plan.specs)} distinct of {n_comp} cells, "
            f"{int(attrs['n_drops_total'])} drops computed)"
        )
    if grid.geographic:
        attrs.update(_geospatial_bounds(grid))
    return attrs


def _drops_computed(drops, plan=None) -> int:
    """The drops a map computed: every cell's ``cell_drop_count``, or with ``cell_seeds = "inputs"``
    those of one cell of each set of cells with identical inputs."""
    if drops is None:
        return 0
    if plan is None or plan.cell_seeds != "inputs":
        return int(drops.sum())
    return sum(int(drops[plan.members[k][0]]) for k in plan.specs)


def _map_scenario(grid, base, stopping=None, plan=None) -> dict:
    """The resolved scenario with a ``map`` section: the grid, what it overrides per cell, the seeds
    (and with sequential stopping its settings)."""
    resolved = base.resolved()
    overridden = [
        "environment.water_depth",
        "sediment.class"
        if grid.sediment_class is not None
        else "sediment.density, sediment.density_gradient, sediment.strength, sediment.strength_gradient",
    ]
    if grid.current_u is not None:
        overridden.append("environment.current")
    resolved["map"] = {
        "environment": grid.source or "xarray.Dataset",
        "environment_title": str(grid.ds.attrs.get("title", "")),
        "overridden_per_cell": overridden,
        "drops_per_cell": base.n,
        "seed_derivation": "cell_seed = first 8 bytes (little-endian) of SHA-256 of "
        "'mineburial-map-cell:<seed>:<k>', k = row * n_columns + column",
    }
    if plan is not None and plan.cell_seeds == "inputs":
        resolved["map"]["cell_seeds"] = "inputs"
        resolved["map"]["seed_derivation"] = (
            "cell_seed = first 8 bytes (little-endian) of SHA-256 of "
            "'mineburial-map-inputs:<seed>:<digest>', digest = SHA-256 (hex) of the cell's "
            "resolved scenario as JSON with sorted keys (floats exact, arrays by dtype, shape and "
            "the SHA-256 of their bytes); cells with the same digest share one ensemble"
        )
    if stopping is not None:
        resolved["map"]["sequential_stopping"] = stopping.record(base.n, base.sampling)
    return resolved


def _geospatial_bounds(grid) -> dict:
    """ACDD latitude/longitude bounds of a geographic grid."""
    lat = np.asarray(grid.ds[grid.ydim].values, dtype=np.float64)
    lon = np.asarray(grid.ds[grid.xdim].values, dtype=np.float64)
    return dict(
        geospatial_lat_min=float(lat.min()),
        geospatial_lat_max=float(lat.max()),
        geospatial_lon_min=float(lon.min()),
        geospatial_lon_max=float(lon.max()),
        geospatial_lat_units="degrees_north",
        geospatial_lon_units="degrees_east",
    )


# ---------------------------------------------------------------------------
# plot
# ---------------------------------------------------------------------------
#: colours of the impact-burial classes 0..4 (ColorBrewer YlOrRd, 5 classes: colour-blind
#: safe, darker = deeper burial)
CLASS_COLOURS = ("#ffffb2", "#fecc5c", "#fd8d3c", "#f03b20", "#bd0026")
_CLASS_LABELS = ("0 % (not buried)", "0-10 %", "10-20 %", "20-75 %", "> 75 %")
_LAND_COLOUR = "#c8b48c"
_NODATA_COLOUR = "#d9d9d9"


def _cell_edges(c: np.ndarray, other: np.ndarray) -> np.ndarray:
    """Cell edges from cell centres (midpoints; the end cells mirrored). A single centre
    gets the spacing of the other axis (or 1)."""
    if c.size > 1:
        mid = 0.5 * (c[:-1] + c[1:])
        return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])
    step = float(np.abs(np.diff(other)).mean()) if other.size > 1 else 1.0
    return np.array([c[0] - 0.5 * step, c[0] + 0.5 * step])


@dataclasses.dataclass
class _Grid:
    """The geometry of a map for drawing: cell centres and edges, axis labels, cell status."""

    x: np.ndarray
    y: np.ndarray
    xe: np.ndarray
    ye: np.ndarray
    geographic: bool
    xlabel: str
    ylabel: str
    status: np.ndarray

    @classmethod
    def of(cls, ds):
        ydim, xdim = ds["cell_status"].dims
        y = np.asarray(ds[ydim].values, dtype=np.float64)
        x = np.asarray(ds[xdim].values, dtype=np.float64)
        geographic = _is_axis(ds[ydim], "lat")
        if geographic:
            xlabel, ylabel = "longitude (degrees east)", "latitude (degrees north)"
        else:
            xlabel = f"{ds[xdim].attrs.get('long_name', xdim)} ({ds[xdim].attrs.get('units', '')})"
            ylabel = f"{ds[ydim].attrs.get('long_name', ydim)} ({ds[ydim].attrs.get('units', '')})"
        ye, xe = _cell_edges(y, x), _cell_edges(x, y)
        return cls(x, y, xe, ye, geographic, xlabel, ylabel, ds["cell_status"].values)

    def mesh(self, ax, values, **kw):
        return ax.pcolormesh(self.xe, self.ye, values, shading="flat", **kw)

    def background(self, ax, nodata):
        """Land tan, the cells flagged ``nodata`` grey, axis labels and equal ground scale."""
        from matplotlib.colors import ListedColormap

        land = (self.status == CELL_LAND).astype(float)
        nodata = (nodata & (self.status != CELL_LAND)).astype(float)
        self.mesh(ax, np.ma.masked_where(land == 0, land), cmap=ListedColormap([_LAND_COLOUR]))
        self.mesh(
            ax,
            np.ma.masked_where(nodata == 0, nodata),
            cmap=ListedColormap([_NODATA_COLOUR]),
            edgecolors="white",
            linewidth=0.5,
        )
        ax.set_xlabel(self.xlabel)
        ax.set_ylabel(self.ylabel)
        if self.geographic:  # equal ground distances in x and y
            ax.set_aspect(1.0 / max(math.cos(math.radians(float(np.mean(self.y)))), 1e-3))
        else:
            ax.set_aspect("equal")
        # long coordinates (projected, or degrees to 3 decimals on a small grid) would overlap
        ax.tick_params(axis="x", labelrotation=30)
        ax.ticklabel_format(useOffset=False, style="plain")


def plot_map(ds: xr.Dataset, path, *, dpi: int = 150, lead_times=None, burial_class: int = 4) -> pathlib.Path:
    """Draw a map produced by :func:`run_map` to a PNG for a planner.

    Left: the most likely impact-burial class per cell in class colours (legend), with
    its probability written in each cell of small grids; right: P(burial > 75 %) as a
    colour map with a colour bar; a map whose cells draw their coefficients from a posterior
    adds a second row, the lower and upper ends of each cell's epistemic band of that
    probability (:func:`_draw_epistemic_band`). Land is drawn tan, water cells without a result grey.
    With ``lead_times`` (days, among the map's ``lead_time``; a map with ``[scour]``): one
    panel per lead time of the probability of ``burial_class`` after scour instead
    (:func:`plot_lead_times`). Needs matplotlib (the optional extra ``plot``).
    """
    if lead_times is not None:
        return plot_lead_times(ds, path, lead_times, burial_class=burial_class, dpi=dpi)
    Figure = figure_class("drawing the map")
    g = _Grid.of(ds)
    likely = ds["most_likely_burial_class"].values.astype(float)
    band = all(f"{EPISTEMIC}_{side}" in ds for side in ("lower", "upper"))
    fig = Figure(figsize=(13.0, 12.6 if band else 6.8), layout="constrained")
    gs = fig.add_gridspec(3 if band else 2, 2, height_ratios=(1.0, 1.0, 0.16) if band else (1.0, 0.16))
    axes = (fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[0, 1]))
    legend_ax = fig.add_subplot(gs[-1, 0])
    legend_ax.axis("off")
    cbar_gs = gs[-1, 1].subgridspec(2, 3, width_ratios=(0.1, 0.8, 0.1), height_ratios=(0.3, 0.7))
    cax = fig.add_subplot(cbar_gs[0, 1])
    basis = ds.attrs.get("burial_class_basis", "burial_volume").replace("burial_", "")
    _draw_likely_class(axes[0], legend_ax, ds, g, likely, basis)
    _draw_burial_over_75(fig, axes[1], cax, ds, g, likely, basis)
    if band:
        _draw_epistemic_band((fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[1, 1])), ds, g, likely, basis)
    fig.suptitle(f"Impact burial of {_plot_title(ds)}", fontsize=13)
    path = pathlib.Path(path)
    save_figure(fig, path, dpi=dpi)
    return path


def _draw_likely_class(ax, legend_ax, ds, g, likely, basis) -> None:
    """Left panel of :func:`plot_map`: the most likely class per cell, its legend, and on
    small grids the class probability and the drops at rest written in each cell."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    x, y, status, mesh = g.x, g.y, g.status, g.mesh
    prob = ds["burial_class_probability"].values
    likely_p = np.take_along_axis(
        np.where(np.isfinite(prob), prob, 0.0), np.clip(likely, 0, 4).astype(int)[None], axis=0
    )[0]
    g.background(ax, likely < 0)
    cmap = ListedColormap(CLASS_COLOURS)
    norm = BoundaryNorm(np.arange(-0.5, 5.5), cmap.N)
    mesh(ax, np.ma.masked_where(likely < 0, likely), cmap=cmap, norm=norm, edgecolors="white", linewidth=0.5)
    ax.set_title(
        f"most likely impact-burial class (burial by {basis})\n"
        "in a cell: its probability, and n = drops at rest",
        fontsize=11,
    )
    handles = [Patch(facecolor=c, edgecolor="0.5", label=lbl) for c, lbl in zip(CLASS_COLOURS, _CLASS_LABELS)]
    handles.append(Patch(facecolor=_LAND_COLOUR, edgecolor="0.5", label="land (not computed)"))
    handles.append(Patch(facecolor=_NODATA_COLOUR, edgecolor="0.5", label="no drop came to rest / no data"))
    legend_ax.legend(
        handles=handles,
        title=f"impact-burial class (burial by {basis})",
        loc="upper center",
        ncol=4,
        fontsize=8,
        title_fontsize=9,
        frameon=False,
    )
    if status.size <= 400:  # small grids: the class probability and its sample size
        n_cls = ds["burial_class_count"].values.sum(axis=0)
        for (j, i), c in np.ndenumerate(likely):
            if c >= 0:
                ax.text(
                    x[i],
                    y[j],
                    f"{likely_p[j, i]:.2f}\nn={int(n_cls[j, i])}",
                    ha="center",
                    va="center",
                    fontsize=7,
                    color="white" if c >= 3 else "black",
                )


def _draw_burial_over_75(fig, ax, cax, ds, g, likely, basis) -> None:
    """Right panel of :func:`plot_map`: P(burial > 75 %) per computed cell, colour bar in ``cax``."""
    p75_mesh = _probability_panel(ax, g, likely, ds["burial_class_probability"].values[4])
    cb = fig.colorbar(p75_mesh, cax=cax, orientation="horizontal")
    cb.set_label(f"P(burial by {basis} > 75 %), probability (0 to 1)")
    ax.set_title(
        f"probability of burial by {basis} > 75 %\n(the class '> 75 %' of the left map)", fontsize=11
    )


def _probability_panel(ax, g, likely, values):
    """A probability per computed cell on the 0-1 ``magma_r`` scale over the land/no-data
    background (the P(> 75 %) panel and the band's two panels share it); returns the mesh."""
    g.background(ax, likely < 0)
    return g.mesh(
        ax,
        np.ma.masked_invalid(np.where(g.status == CELL_COMPUTED, values, np.nan)),
        cmap="magma_r",
        vmin=0.0,
        vmax=1.0,
        edgecolors="white",
        linewidth=0.5,
    )


#: the epistemic band's variables (issue 32; systems/mine/epistemic.py): ``<EPISTEMIC>_lower`` and
#: ``_upper``, per class and cell, of a map that draws its coefficients from a posterior
EPISTEMIC = "burial_class_probability_epistemic"


def _draw_epistemic_band(axes, ds, g, likely, basis) -> None:
    """Second row of :func:`plot_map` (a map drawing its coefficients from a posterior): the
    lower and upper ends of each cell's epistemic band of P(burial > 75 %) — how far the
    probability moves across what the measurements leave open (docs/calibration.md) — on the
    colour scale of the panel above; small grids write the band in each cell."""
    level = int(round(100 * float(ds[f"{EPISTEMIC}_lower"].attrs.get("band_level", 0.9))))
    ends = {side: ds[f"{EPISTEMIC}_{side}"].values[4] for side in ("lower", "upper")}
    for ax, (side, values) in zip(axes, ends.items()):
        _probability_panel(ax, g, likely, values)
        ax.set_title(
            f"P(burial by {basis} > 75 %): {side} end of the {level} % band of\n"
            "what the measurements leave open (the calibrated coefficients)",
            fontsize=11,
        )
        if g.status.size <= 400:
            lo, hi = ends["lower"], ends["upper"]
            for (j, i), c in np.ndenumerate(likely):
                if c >= 0 and np.isfinite(values[j, i]):
                    ax.text(g.x[i], g.y[j], f"{lo[j, i]:.2f}-{hi[j, i]:.2f}", ha="center", va="center",
                            fontsize=7, color="white" if values[j, i] > 0.6 else "black")  # fmt: skip


def _plot_title(ds) -> str:
    n = int(ds.attrs.get("n_drops_per_cell", 0))
    name = ds.attrs.get("scenario_name") or ds.attrs.get("title", "").replace(
        "mineburial impact-burial probability map: ", ""
    )
    return f"{name}: {n} drops per cell, map seed {ds.attrs.get('random_seed', '')}"


#: a map cell counts as not modelled after impact when at least this share of its drops lie on a
#: bed where no post-impact process runs (<section>_not_modelled_fraction: scour's; docs/maps.md)
NOT_MODELLED_SHARE = 0.5


def not_modelled_cells(ds) -> np.ndarray:
    """(y, x) bool: the computed cells where no post-impact process is modelled for most drops
    (each process's ``<section>_not_modelled_fraction`` >= :data:`NOT_MODELLED_SHARE`; scour's: a
    cohesive bed, where the stage keeps the impact burial); all False for a map without such a
    variable."""
    status = ds["cell_status"].values
    names = [f"{name}_not_modelled_fraction" for name in processes.PROCESSES]
    shares = [ds[name].values for name in names if name in ds]
    if not shares:
        return np.zeros(status.shape, dtype=bool)
    out = status == CELL_COMPUTED
    for share in shares:
        out &= np.isfinite(share) & (share >= NOT_MODELLED_SHARE)
    return out


def hatched_cells(ds, k: int) -> np.ndarray:
    """The cells (y, x bool) a lead-time panel hatches at lead-time index ``k``: those of
    :func:`not_modelled_cells` after lead time 0. At lead time 0 the impact is modelled everywhere
    (its burial is the probability shown); after it, a cell where no post-impact process runs is
    hatched, not coloured as a prediction that nothing changes."""
    return not_modelled_cells(ds) & (float(ds["lead_time"].values[k]) > 0.0)


def _hatch_cells(ax, g, cells) -> None:
    """Each cell of ``cells`` (y, x bool) drawn light grey with dark diagonal hatching."""
    from matplotlib.patches import Rectangle

    for j, i in zip(*np.nonzero(cells)):
        x0, x1 = sorted((g.xe[i], g.xe[i + 1]))
        y0, y1 = sorted((g.ye[j], g.ye[j + 1]))
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor="0.9", edgecolor="0.35", hatch="///",
                               linewidth=0.0, zorder=3))  # fmt: skip


def _lead_time_sections() -> str:
    """The sections whose process gives a map its lead-time axis (the registered processes that
    change the burial: ``[scour]``), for an error line."""
    found = [f"[{n}]" for n, p in processes.PROCESSES.items() if isinstance(p, processes.BurialProcess)]
    return " or ".join(found)


def lead_indices(available, wanted, option="--lead-times") -> list[int]:
    """Indices into a map's lead times (days) of the ``wanted`` ones (each within 1e-9 d of one),
    else one line naming the value and the map's lead times."""
    available = np.asarray(available, dtype=np.float64)
    if available.size == 0:
        raise MapError(
            f"{option}: the map has no lead times (give {_lead_time_sections()} lead_times_days in the "
            "scenario)"
        )
    out = []
    for w in wanted:
        k = np.flatnonzero(np.abs(available - float(w)) <= 1e-9)
        if not k.size:
            have = ", ".join(f"{v:g}" for v in available)
            raise MapError(f"{option}: {float(w):g} d is not a lead time of the map; choose among {have} d")
        out.append(int(k[0]))
    return out


def _lead_time_section(ds, option: str) -> str:
    """The section of the post-impact process whose burial classes per lead time the map ``ds``
    holds (``<section>_burial_class_probability``; ``scour``), else one line naming ``option``."""
    for name in processes.PROCESSES:
        if f"{name}_burial_class_probability" in ds:
            return name
    raise MapError(f"{option}: the map has no lead-time axis (run it with a {_lead_time_sections()} section)")


def plot_lead_times(ds, path, lead_times, *, burial_class: int = 4, dpi: int = 150) -> pathlib.Path:
    """One panel per lead time (days) of a map with ``[scour]``: the probability of the burial
    class ``burial_class`` (0..4, default '> 75 %') after scour, on one 0-1 colour scale with a
    colour bar; each cell of small grids shows it and n, the drops whose stage ran there."""
    Figure = figure_class("drawing the map")
    section = _lead_time_section(ds, "--lead-times")
    ks = lead_indices(ds["lead_time"].values, lead_times)
    g = _Grid.of(ds)
    prob = ds[f"{section}_burial_class_probability"].values[:, burial_class]
    count = ds[f"{section}_burial_class_count"].values.sum(axis=1)
    ncol = min(len(ks), 3)
    nrow = -(-len(ks) // ncol)
    fig = Figure(figsize=(4.6 * ncol + 0.8, 4.4 * nrow + 0.9), layout="constrained")
    axes = fig.subplots(nrow, ncol, squeeze=False).ravel()
    basis = ds.attrs.get("burial_class_basis", "burial_volume").replace("burial_", "")
    label = _CLASS_LABELS[burial_class]
    not_modelled = not_modelled_cells(ds)
    for ax, k in zip(axes, ks):
        hatched = hatched_cells(ds, k)
        p = np.where((g.status == CELL_COMPUTED) & ~hatched, prob[k], np.nan)
        g.background(ax, ~np.isfinite(p) & ~hatched)
        last = g.mesh(
            ax, np.ma.masked_invalid(p), cmap="magma_r", vmin=0.0, vmax=1.0, edgecolors="white", linewidth=0.5
        )
        _hatch_cells(ax, g, hatched)  # no post-impact process modelled there: not a probability
        ax.set_title(f"lead time {ds['lead_time'].values[k]:g} d", fontsize=11)
        if g.status.size <= 100:
            for (j, i), v in np.ndenumerate(p):
                if np.isfinite(v):
                    text = f"{v:.2f}\nn={int(count[k, j, i])}"
                    ax.text(g.x[i], g.y[j], text, ha="center", va="center", fontsize=7,
                            color="white" if v > 0.6 else "black")  # fmt: skip
    for ax in axes[len(ks) :]:
        ax.axis("off")
    cb = fig.colorbar(last, ax=list(axes[: len(ks)]), orientation="horizontal", shrink=0.6)
    cb.set_label(f"P(burial by {basis} in class '{label}') after {section}, probability (0 to 1)")
    fig.suptitle(
        f"Burial after impact and {section}, class '{label}' by {basis}, of {_plot_title(ds)}\n"
        f"land tan; grey: no drop's {section} stage ran"
        + ("\nhatched after lead time 0: not modelled (cohesive bed: no post-impact process runs; "
           "not 'stays unburied')" if not_modelled.any() else ""),
        fontsize=12,
    )  # fmt: skip
    path = pathlib.Path(path)
    save_figure(fig, path, dpi=dpi)
    return path


# ---------------------------------------------------------------------------
# GeoTIFF
# ---------------------------------------------------------------------------
def _import_rioxarray():
    """rioxarray (registers ``.rio``) and pyproj, or one line naming the extra."""
    try:
        import pyproj
        import rioxarray  # noqa: F401
    except ImportError:
        raise MapError(
            "--geotiff needs rioxarray, an optional dependency: pip install 'mineburial[geotiff]' "
            "(or pip install rioxarray)"
        ) from None
    return pyproj


def _regular_edges(c: np.ndarray, other: np.ndarray, name: str) -> tuple[float, float]:
    """(first edge, step) of a regular axis (a GeoTIFF has one cell size per axis); the edges
    are those of the map (:func:`_cell_edges`), else one line naming the axis."""
    if c.size > 1:
        step = np.diff(c)
        if not np.allclose(step, step[0], rtol=1e-6, atol=0.0):
            raise MapError(
                f"--geotiff: the axis '{name}' is not evenly spaced (steps {step.min():g} to "
                f"{step.max():g}); a GeoTIFF needs one cell size per axis"
            )
    e = _cell_edges(c, other)
    return float(e[0]), float((e[-1] - e[0]) / c.size)


def map_crs(ds: xr.Dataset, pyproj):
    """The map's coordinate reference system: its CF grid mapping (``grid_mapping`` of
    ``cell_status``; :meth:`pyproj.crs.CRS.from_cf` reads ``crs_wkt`` or the mapping's
    parameters), else for latitude/longitude axes WGS 84 (EPSG:4326, an assumption the
    GeoTIFF's description states), else one line."""
    gm = ds["cell_status"].attrs.get("grid_mapping")
    if gm is not None and gm in ds.variables:
        try:
            crs = pyproj.CRS.from_cf(dict(ds[gm].attrs))
        except pyproj.exceptions.CRSError as exc:
            raise MapError(
                f"--geotiff: the grid mapping '{gm}' is not a CRS pyproj can read: {exc}"
            ) from None
        return _as_wgs84(crs, pyproj)
    if _is_axis(ds[ds["cell_status"].dims[0]], "lat"):
        return pyproj.CRS.from_epsg(4326)
    raise MapError("--geotiff: the map has projected axes but no grid_mapping variable (CF 5.6)")


#: the WGS 84 ellipsoid (EPSG:7030): semi-major axis [m], inverse flattening
WGS84_ELLIPSOID = (6378137.0, 298.257223563)


def _as_wgs84(crs, pyproj):
    """EPSG:4326 for a CF ``latitude_longitude`` mapping on the WGS 84 ellipsoid with the
    Greenwich meridian, which :meth:`pyproj.crs.CRS.from_cf` reads as a geographic CRS with an
    "undefined" datum (a GeoTIFF then carries a user-defined datum, issue 33); any other CRS as
    it is. The datum ensemble WGS 84 is what a CF latitude/longitude grid on that ellipsoid means
    in practice (ERA5, WAVEWATCH III and Copernicus grids say WGS 84)."""
    if not crs.is_geographic or crs.to_epsg() == 4326:
        return crs
    e = crs.ellipsoid
    if (
        e is not None
        and e.semi_major_metre == WGS84_ELLIPSOID[0]
        and abs(e.inverse_flattening - WGS84_ELLIPSOID[1]) <= 1e-9 * WGS84_ELLIPSOID[1]
        and crs.prime_meridian is not None
        and crs.prime_meridian.longitude == 0.0
    ):
        return pyproj.CRS.from_epsg(4326)
    return crs


def write_geotiff(ds: xr.Dataset, path, *, lead_time=None, burial_class: int = 4) -> pathlib.Path:
    """Write the probability of ``burial_class`` (0..4, default '> 75 %') of a map as a
    one-band float32 GeoTIFF (NaN where not computed) with the map's CRS (:func:`map_crs`),
    atomically: the impact map, or after scour at ``lead_time`` days (one of the map's lead
    times). Rows run north to south (or down the y axis), the transform from the cell edges
    of the coordinates (midpoints; an evenly spaced axis is required). Needs rioxarray."""
    pyproj = _import_rioxarray()
    if not (0 <= int(burial_class) <= 4):
        raise MapError(f"--class {burial_class}: allowed 0..4 ({', '.join(_CLASS_LABELS)})")
    if lead_time is None:
        field = ds["burial_class_probability"].isel(impact_burial_class=int(burial_class))
        what = "impact burial"
    else:
        section = _lead_time_section(ds, "--lead-time")
        k = lead_indices(ds["lead_time"].values, [lead_time], "--lead-time")[0]
        probability = ds[f"{section}_burial_class_probability"]
        field = probability.isel(lead_time=k, impact_burial_class=int(burial_class))
        what = f"burial after {section} at lead time {float(lead_time):g} d"
    ydim, xdim = ds["cell_status"].dims
    values = np.where(ds["cell_status"].values == CELL_COMPUTED, field.values, np.nan).astype(np.float32)
    y = np.asarray(ds[ydim].values, dtype=np.float64)
    x = np.asarray(ds[xdim].values, dtype=np.float64)
    if y.size > 1 and y[1] > y[0]:  # north (or +y) up: the first row is the largest y
        y, values = y[::-1], values[::-1]
    if x.size > 1 and x[1] < x[0]:
        x, values = x[::-1], values[:, ::-1]
    x0, dx = _regular_edges(x, y, xdim)
    y0, dy = _regular_edges(y, x, ydim)
    if dy > 0:  # a single row: its top edge first
        y0, dy = y0 + dy, -dy
    crs = map_crs(ds, pyproj)
    from affine import Affine  # a dependency of rasterio, which rioxarray needs

    basis = ds.attrs.get("burial_class_basis", "burial_volume")
    label = _CLASS_LABELS[int(burial_class)]
    da = xr.DataArray(values, dims=("y", "x"), coords={"y": y, "x": x})
    epsg = crs.to_epsg()
    da = da.rio.write_crs(f"EPSG:{epsg}" if epsg is not None else crs.to_wkt())
    da = da.rio.write_transform(Affine(dx, 0.0, x0, 0.0, dy, y0))
    da = da.rio.write_nodata(np.nan)
    da.attrs = {
        "long_name": f"probability of the burial class '{label}' ({basis}), {what}",
        "units": "1",
        "comment": f"mineburial map {ds.attrs.get('id', '')}; {_plot_title(ds)}; NaN: not computed"
        + ("; CRS: WGS 84 (EPSG:4326) assumed for the latitude/longitude axes" if "grid_mapping" not in
           ds["cell_status"].attrs else ""),
    }  # fmt: skip
    path = pathlib.Path(path)
    atomic_write_bytes(path, _geotiff_bytes(da, path))
    return path


def _geotiff_bytes(da: xr.DataArray, path) -> bytes:
    """The GeoTIFF of ``da`` rendered in memory and read back: GDAL reports a failed write
    only on stderr, so the file is made in memory (GDAL's ``/vsimem``), its band compared
    with ``da`` (NaN where NaN) and then written by :func:`atomic_write_bytes`, whose own
    write raises on a full disk and checks the size (docs/design.md, "Outputs")."""
    from rasterio.io import MemoryFile  # local import: rasterio comes with the optional rioxarray

    with MemoryFile(ext=".tif") as mem:
        da.rio.to_raster(mem.name, driver="GTiff")
        data = mem.read()
    try:
        with MemoryFile(data) as back, back.open() as r:
            band = r.read(1)
    except Exception as exc:  # rasterio's errors have no common base with a message we rely on
        raise MapError(f"--geotiff '{path}': the GeoTIFF made does not read back ({exc})") from None
    if band.shape != da.shape or not np.array_equal(band, da.values, equal_nan=True):
        raise MapError(f"--geotiff '{path}': the GeoTIFF made does not read back as the map's field")
    return data


def _check_geotiff_grid(grid: EnvironmentGrid) -> None:
    """Before computing, what :func:`write_geotiff` needs of the map's grid, which is the
    environment grid's: evenly spaced axes and a CRS pyproj can read (was: refused only after
    the whole map was computed, issue 35). The same checks on a map without results."""
    pyproj = _import_rioxarray()
    coords = _horizontal_coords(grid)
    y, x = coords[V.MAP_Y], coords[V.MAP_X]
    status_attrs = {"grid_mapping": grid.grid_mapping} if grid.grid_mapping else {}
    shell = xr.Dataset(
        {"cell_status": ((grid.ydim, grid.xdim), np.zeros(grid.shape, np.int8), status_attrs)},
        coords={grid.ydim: y, grid.xdim: x},
    )
    if grid.grid_mapping:
        shell[grid.grid_mapping] = xr.DataArray(np.int32(0), attrs=dict(grid.ds[grid.grid_mapping].attrs))
    yv = np.asarray(y.values, dtype=np.float64)
    xv = np.asarray(x.values, dtype=np.float64)
    _regular_edges(np.sort(xv), np.sort(yv), grid.xdim)
    _regular_edges(np.sort(yv), np.sort(xv), grid.ydim)
    map_crs(shell, pyproj)


# ---------------------------------------------------------------------------
# CLI
# ---------------------------------------------------------------------------
def run_map_cli(args) -> int:
    """``mineburial map SCENARIO --environment ENV.nc -o MAP.nc [--plot MAP.png]``.

    Every check that can be made before computing is made first: the scenario, the
    environment grid, the output and plot paths, the scheduler."""
    base, grid, per_cell, _ = _load_base(args.scenario, args.environment, n=args.drops, seed=args.seed)
    stopping = check_stopping(args.target_half_width, args.min_drops, args.step, base.n, base.sampling)
    check_cell_seeds(args.cell_seeds)
    runner.check_run(base, what="each cell of the map")
    _check_map_memory(base, grid.cell_status(), per_cell)
    inputs = runner.input_paths(args.scenario, base) + [pathlib.Path(args.environment)]
    inputs += [pathlib.Path(f) for found in per_cell.values() for f, _ in found.files]
    check_output_path(args.output, inputs, "-o")
    if args.plot:
        check_plot_path(args.plot, args.output, inputs, "the map's output")
    leads = _check_map_options(args, base, inputs, grid)
    client = runner.connect_scheduler(args.scheduler) if args.scheduler else None
    t0 = time.monotonic()
    try:
        ds = run_map(
            args.scenario,
            args.environment,
            n=args.drops,
            seed=args.seed,
            client=client,
            output=args.output,
            progress=not args.quiet,
            target_half_width=args.target_half_width,
            min_drops=args.min_drops,
            step=args.step,
            cell_seeds=args.cell_seeds,
        )
    finally:
        if client is not None:
            client.close()
    elapsed = time.monotonic() - t0
    n_comp = int(ds.attrs["n_cells_computed"])
    n = int(ds.attrs["n_drops_per_cell"])
    total = int(ds.attrs.get("n_drops_total", ds["cell_drop_count"].values.sum()))
    per_cell = f"{n} drops per cell"
    if stopping is not None:
        used = ds["cell_drop_count"].values[ds["cell_status"].values == CELL_COMPUTED]
        per_cell = (
            f"{stopping.min_drops}-{n} drops per cell (sequential stopping at half-width "
            f"{stopping.target_half_width:g}: {total} drops in all, "
            f"{100.0 * total / max(n * n_comp, 1):.1f} % of {n * n_comp}; "
            f"{int(np.count_nonzero(used < n))} cells stopped early)"
        )
    if args.cell_seeds == "inputs":
        per_cell += (
            f"; cells with identical inputs computed once: {int(ds.attrs['n_cells_distinct'])} distinct "
            f"of {n_comp} ({total} drops computed)"
        )
    print(
        f"{ds.attrs['title']}\n"
        f"cells: {int(ds.attrs['n_cells'])} ({n_comp} computed, "
        f"{int(ds.attrs['n_cells_land'])} land, {int(ds.attrs['n_cells_no_sediment'])} without "
        f"sediment data), {per_cell}"
    )
    if ds.attrs.get("invalid_inputs"):
        print(
            f"warning: drops not run because their sampled inputs are invalid: {ds.attrs['invalid_inputs']}"
        )
    print(f"time: {elapsed:.1f} s ({total / max(elapsed, 1e-9):.1f} drops/s)\nwrote {args.output}")
    if args.plot:
        plot_map(ds, args.plot, lead_times=leads, burial_class=args.burial_class)
        print(f"wrote {args.plot}")
    if args.geotiff:
        write_geotiff(ds, args.geotiff, lead_time=args.lead_time, burial_class=args.burial_class)
        print(f"wrote {args.geotiff}")
    return 0


def _check_map_options(args, base, inputs, grid):
    """Check before computing the options of the lead-time panels and the GeoTIFF; returns the
    lead times (days) of the panels, or None."""
    after = processes.burial_process(base)  # the process whose burial the lead-time axis holds
    available = () if after is None else after[0].lead_times(after[1])
    if not (0 <= args.burial_class <= 4):
        raise MapError(f"--class {args.burial_class}: allowed 0..4 ({', '.join(_CLASS_LABELS)})")
    leads = None
    if args.lead_times is not None:
        if not args.plot:
            raise MapError("--lead-times draws the panels of --plot; give --plot MAP.png")
        try:
            leads = [float(v) for v in args.lead_times.split(",")]
        except ValueError:
            raise MapError(
                f"--lead-times {args.lead_times!r}: give days separated by commas, e.g. 0,1,4"
            ) from None
        if after is None:
            raise MapError(
                f"--lead-times: the map has no lead-time axis (give the scenario a {_lead_time_sections()} "
                "section)"
            )
        lead_indices(available, leads)
    if args.lead_time is not None and not args.geotiff:
        raise MapError("--lead-time chooses the field of --geotiff; give --geotiff MAP.tif")
    if args.geotiff:
        _import_rioxarray()
        path = pathlib.Path(args.geotiff)
        if path.suffix.lower() not in (".tif", ".tiff"):
            raise MapError(f"--geotiff '{path}': the file name must end in .tif or .tiff")
        for other, opt in ((args.output, "-o"), (args.plot, "--plot")):
            if other and same_file(path, pathlib.Path(other)):
                raise MapError(f"--geotiff '{path}' is also the map's {opt}; choose another path")
        check_output_path(path, inputs, "--geotiff")
        _check_geotiff_grid(grid)
        if args.lead_time is not None:
            if after is None:
                raise MapError(
                    "--lead-time: the map has no lead-time axis (give the scenario a "
                    f"{_lead_time_sections()} section)"
                )
            lead_indices(available, [args.lead_time], "--lead-time")
    return leads
