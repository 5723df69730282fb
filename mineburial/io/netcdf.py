"""CF-1.11 + ACDD-1.3 NetCDF files: writing them, and the attributes every output shares.

:func:`write_netcdf` writes a Dataset atomically in NETCDF4 format with zlib
compression (encodings from the one variable registry :mod:`mineburial.io.variables`).
The datasets themselves are made by the one builder :func:`mineburial.io.dataset.build`
from what the layers that compute them hand it (an ensemble:
:func:`mineburial.systems.mine.dataset.build_dataset`; a map: :mod:`mineburial.analyses.maps`);
this module only provides the shared attribute values (conventions, keywords,
references) and the helpers that make attribute values netCDF-safe.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime as _dt
import errno
import json
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.io import variables as V
from mineburial.io.files import atomic_path

__all__ = ["write_netcdf", "scenario_json", "seed_attr", "utc_now", "clean_attrs", "CONVENTIONS"]

CONVENTIONS = "CF-1.11, ACDD-1.3"
#: the CF standard-name table the only standard name used (``realization``) was checked against
STANDARD_NAME_VOCABULARY = "CF Standard Name Table v93"
DEFAULT_TITLE = "mineburial Monte Carlo prediction of naval mine impact burial"
DEFAULT_SUMMARY = (
    "Monte Carlo ensemble of a mine dropped through air, water and sediment, computed with "
    "mineburial (a numba-compiled rigid-body impact-burial model after Chu and Fan 2006, "
    "IMPACT35). The file holds burial statistics over the drops that came to rest (mean, "
    "standard deviation, standard error, quantiles, histograms, exceedance probabilities of "
    "burial depth and percent burial by volume, height and area, and the probabilities of the "
    "naval impact-burial classes 0 %, 0-10 %, 10-20 %, 20-75 %, > 75 % with Wilson 95 % "
    "intervals), the count of every drop status, and optionally the per-drop results and "
    "sampled inputs along the realization dimension."
)
KEYWORDS = (
    "naval mines, mine burial, impact burial, Monte Carlo, ensemble, sediment "
    "penetration, seabed, rigid body dynamics"
)
REFERENCES = (
    "Chu, P. C. and Fan, C. W. (2006), Prediction of falling cylinder through "
    "air-water-sediment columns, doi:10.1115/1.2125975; Wilson, E. B. (1927), J. Am. "
    "Stat. Assoc. 22(158), 209-212; Hyndman, R. J. and Fan, Y. (1996), Am. Stat. 50(4), "
    "361-365"
)

_INT64 = np.iinfo(np.int64)


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------


def _json_default(obj: Any):
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return dataclasses.asdict(obj)
    if isinstance(obj, (Path, _dt.date, _dt.datetime)):
        return str(obj)
    if isinstance(obj, (set, frozenset)):
        return sorted(obj)
    raise TypeError(f"cannot write {type(obj).__name__} {obj!r} into the scenario attribute")


def scenario_json(scenario: Any) -> str:
    """The resolved scenario as a JSON text (sorted keys; numpy values, dataclasses and
    paths converted; NaN/inf written as the JavaScript literals NaN/Infinity)."""
    return json.dumps(scenario, sort_keys=True, default=_json_default, allow_nan=True)


def seed_attr(seed):
    """netCDF attributes hold at most 64-bit integers: larger seeds are written as text."""
    if seed is None:
        return None
    if isinstance(seed, (int, np.integer)) and _INT64.min <= int(seed) <= _INT64.max:
        return np.int64(seed)
    if isinstance(seed, (int, np.integer)):
        return str(int(seed))
    return json.dumps(seed, default=_json_default)


def utc_now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).strftime("%Y-%m-%dT%H:%M:%SZ")


def clean_attrs(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """Drop ``None`` values (netCDF cannot store them) and turn bools into ints."""
    out = {}
    for k, v in attrs.items():
        if v is None:
            continue
        if isinstance(v, (bool, np.bool_)):
            v = np.int8(v)
        out[k] = v
    return out


# ---------------------------------------------------------------------------
# atomic write
# ---------------------------------------------------------------------------


def _encoding(ds: xr.Dataset, complevel: int) -> dict[str, dict[str, Any]]:
    """Per-variable netCDF encoding: zlib for numeric variables, CF-safe fill values.

    Coordinates and bounds get no ``_FillValue`` (CF 2.5.1: coordinates may not
    have missing values); declared variables take their registry fill value;
    other floats keep xarray's NaN fill.
    """
    bounds = {ds[v].attrs["bounds"] for v in ds.variables if "bounds" in ds[v].attrs}
    enc: dict[str, dict[str, Any]] = {}
    for name, var in ds.variables.items():
        e: dict[str, Any] = {}
        for key in ("_FillValue", "dtype"):
            if key in var.encoding:
                e[key] = var.encoding[key]
        decl = V.VARIABLES.get(name)
        if decl is not None:
            e.update(decl.encoding())
        if name in ds.coords or name in bounds:
            e["_FillValue"] = None
        if var.dtype.kind in "iufb":
            e["zlib"] = True
            e["complevel"] = int(complevel)
            if var.dtype.kind in "iub":
                e.setdefault("_FillValue", None)
        enc[str(name)] = e
    return enc


#: the modules whose import xarray's ``to_netcdf`` tries only to ask whether a dask.distributed
#: client is the scheduler (``xarray.backends.locks.get_dask_scheduler``)
_DISTRIBUTED = ("distributed", "dask.distributed")


@contextlib.contextmanager
def _without_distributed():
    """Within the block, ``import distributed`` (and ``dask.distributed``) fails with ImportError
    unless it was imported before, then it is importable again.

    Why (issue 34 item 1, the second run's start-up): xarray's ``to_netcdf`` asks dask which
    scheduler is active (``get_dask_scheduler``: ``dask.base.get_scheduler`` tries
    ``distributed.get_client()``, then ``from dask.distributed import Client``), and so imported
    dask.distributed, 0.2-0.25 s of CPU, on every write of a plain local run. A process that
    has not imported it has no dask.distributed client, so the answer is the same ("threaded":
    xarray then closes the file after the writes, as before; our datasets hold no dask arrays
    anyway); xarray's ``except ImportError`` is the path it takes where distributed is not
    installed. A run with ``--scheduler`` imported it with its client: nothing is blocked."""
    blocked = [] if "distributed" in sys.modules else [n for n in _DISTRIBUTED if n not in sys.modules]
    for name in blocked:
        sys.modules[name] = None  # the import machinery's "not importable" (ModuleNotFoundError)
    try:
        yield
    finally:
        for name in blocked:
            if name in sys.modules and sys.modules[name] is None:
                del sys.modules[name]


def write_netcdf(ds: xr.Dataset, path, *, complevel: int = 4) -> Path:
    """Write ``ds`` to ``path`` atomically (NETCDF4, zlib level ``complevel``).

    The file is written to a temporary file in the same directory, flushed to
    disk with ``fsync`` and moved over ``path`` with ``os.replace``
    (:func:`mineburial.io.files.atomic_path`): readers see either the previous file
    or the complete new one, never a partial file. On any error the temporary file
    is removed and the previous ``path`` is left untouched. Returns the path written.

    A write that fails in the netCDF/HDF5 library (a full disk, a file-size limit: it
    says only ``NetCDF: HDF error``) is raised as an :class:`OSError` naming ``path``.
    """
    path = Path(path)
    try:
        with atomic_path(path) as tmp, _without_distributed():
            ds.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4", encoding=_encoding(ds, complevel))
    except RuntimeError as exc:
        if not str(exc).startswith("NetCDF:"):  # not the library's report of a failed write
            raise
        raise OSError(
            errno.EIO,
            f"writing the NetCDF file failed ({exc}): is the disk full or the file larger than "
            f"a size limit allows? The previous file, if any, is unchanged",
            str(path),
        ) from exc
    return path
