"""CF-1.11 + ACDD-1.3 NetCDF output of an ensemble run.

:func:`build_dataset` assembles the burial statistics
(:func:`mineburial.ensembles.statistics.burial_statistics`), optionally the
per-drop results and sampled inputs along the CF ``realization`` dimension, and
the global attributes that make a file a complete record of how it was made
(resolved scenario as JSON, seed, sampling method, package version).
:func:`write_netcdf` writes it atomically in NETCDF4 format with zlib
compression.

Every variable and its attributes come from the one registry
:mod:`mineburial.io.variables`.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import hashlib
import json
from pathlib import Path
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from mineburial.io import variables as V
from mineburial.io.files import atomic_path
from mineburial.kernels import layout
from mineburial.kernels import status as status_codes

__all__ = ["build_dataset", "write_netcdf", "scenario_json", "CONVENTIONS"]

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
    "sampled inputs along the realization dimension.")
KEYWORDS = ("naval mines, mine burial, impact burial, Monte Carlo, ensemble, sediment "
            "penetration, seabed, rigid body dynamics")
REFERENCES = ("Chu, P. C. and Fan, C. W. (2006), Prediction of falling cylinder through "
              "air-water-sediment columns, doi:10.1115/1.2125975; Wilson, E. B. (1927), J. Am. "
              "Stat. Assoc. 22(158), 209-212; Hyndman, R. J. and Fan, Y. (1996), Am. Stat. 50(4), "
              "361-365")

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


def _seed_attr(seed):
    """netCDF attributes hold at most 64-bit integers: larger seeds are written as text."""
    if seed is None:
        return None
    if isinstance(seed, (int, np.integer)) and _INT64.min <= int(seed) <= _INT64.max:
        return np.int64(seed)
    if isinstance(seed, (int, np.integer)):
        return str(int(seed))
    return json.dumps(seed, default=_json_default)


def _utc_now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).strftime("%Y-%m-%dT%H:%M:%SZ")


def _clean_attrs(attrs: Mapping[str, Any]) -> dict[str, Any]:
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
# Dataset assembly
# ---------------------------------------------------------------------------


def build_dataset(
    summary,
    status,
    *,
    inputs: Mapping[str, Any] | None = None,
    input_metadata: Mapping[str, tuple[str, str]] | None = None,
    scenario: Any = None,
    seed=None,
    version: str | None = None,
    sampling_method: str | None = None,
    n_drops: int | None = None,
    realization=None,
    per_drop: bool = True,
    statistics: xr.Dataset | None = None,
    statistics_options: Mapping[str, Any] | None = None,
    title: str | None = None,
    summary_text: str | None = None,
    creator: Mapping[str, str] | None = None,
    history: str | None = None,
    date_created: str | None = None,
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """Assemble the output Dataset of an ensemble run.

    Parameters
    ----------
    summary, status : per-drop results, (n, N_SUMMARY) float64 and (n,) integer codes.
    inputs : optional sampled inputs, dotted scenario path -> float64 array (n,);
        written as ``input_<path with _>`` along ``realization`` when ``per_drop``.
    input_metadata : path -> (UDUNITS units, description) of the sampled inputs.
    scenario : the resolved scenario (dict-like), written as JSON to the global
        attribute ``scenario``.
    seed, version, sampling_method, n_drops : run metadata (``version`` is
        ``mineburial.__version__``; ``n_drops`` defaults to ``len(status)``).
    realization : drop indices of the rows (default ``0..n-1``).
    per_drop : also write the per-drop results and sampled inputs along
        ``realization`` (with ``per_drop=False`` only the statistics are written
        and ``inputs`` is not used).
    statistics : precomputed statistics Dataset; by default computed with
        ``burial_statistics(summary, status, **statistics_options)``.
    title, summary_text, creator, history, date_created : ACDD attributes;
        ``creator`` may hold ``name``, ``email``, ``url``, ``type``,
        ``institution`` (written as ``creator_*``/``institution``).
    attrs : further global attributes (override the defaults).
    """
    from mineburial.ensembles.statistics import burial_class, burial_statistics

    summary = np.asarray(summary, dtype=np.float64)
    status = np.asarray(status)
    if summary.ndim != 2 or summary.shape[1] != layout.N_SUMMARY:
        raise ValueError(f"summary must have shape (n, {layout.N_SUMMARY}), got {summary.shape}")
    if status.shape != (summary.shape[0],):
        raise ValueError(f"status must have shape ({summary.shape[0]},), got {status.shape}")
    n = summary.shape[0]
    opts = dict(statistics_options or {})
    if statistics is None:
        statistics = burial_statistics(summary, status, **opts)
    class_basis = statistics.attrs.get("burial_class_basis", opts.get("class_basis", "burial_volume"))

    parts = [statistics]
    if per_drop:
        parts.append(_per_drop_dataset(summary, status, inputs, input_metadata, realization,
                                       class_basis, burial_class))
    ds = xr.merge(parts, combine_attrs="override", compat="no_conflicts", join="exact")
    for part in parts:  # merge may drop encodings (fill values): restore them
        for name, da in part.variables.items():
            ds[name].encoding.update(da.encoding)

    n_total = int(n if n_drops is None else n_drops)
    created = date_created or _utc_now()
    version_s = str(version) if version is not None else "unknown"
    scen = scenario_json(scenario) if scenario is not None else None
    ident_src = json.dumps([scen, str(seed), sampling_method, n_total, version_s])
    line = (f"{created} mineburial {version_s}: Monte Carlo ensemble of {n_total} drops"
            + (f", {sampling_method} sampling" if sampling_method else "")
            + (f", seed {seed}" if seed is not None else ""))
    cr = dict(creator or {})
    global_attrs = {
        "Conventions": CONVENTIONS,
        "title": title or DEFAULT_TITLE,
        "summary": summary_text or DEFAULT_SUMMARY,
        "keywords": KEYWORDS,
        "id": "mineburial-" + hashlib.sha256(ident_src.encode()).hexdigest()[:16],
        "history": f"{history}\n{line}" if history else line,
        "date_created": created,
        "creator_name": cr.get("name"),
        "creator_email": cr.get("email"),
        "creator_url": cr.get("url"),
        "creator_type": cr.get("type"),
        "institution": cr.get("institution"),
        "product_version": version_s,
        "source": f"mineburial {version_s} (numba-compiled Monte Carlo impact-burial model)",
        "processing_level": "model output: Monte Carlo ensemble statistics",
        "standard_name_vocabulary": STANDARD_NAME_VOCABULARY,
        "references": REFERENCES,
        "comment": ("Statistics use only drops with status at_rest or buried_sinking; "
                    "status_count gives the "
                    "number of drops with every status code. Variable definitions: "
                    "docs/notes/output.md of the mineburial sources."),
        "scenario": scen,
        "random_seed": _seed_attr(seed),
        "sampling_method": sampling_method,
        "mineburial_version": version_s,
        "n_drops": np.int64(n_total),
        "n_at_rest": np.int64(np.count_nonzero(status == status_codes.AT_REST)),
    }
    # statistics options recorded as well (basis, confidence level, quantile method ...)
    for k, v in statistics.attrs.items():
        global_attrs.setdefault(k, v)
    global_attrs.update(attrs or {})
    ds.attrs = _clean_attrs(global_attrs)
    return ds


def _per_drop_dataset(summary, status, inputs, input_metadata, realization, class_basis,
                      burial_class) -> xr.Dataset:
    n = summary.shape[0]
    idx = np.arange(n, dtype=np.int64) if realization is None else np.asarray(realization)
    if idx.shape != (n,):
        raise ValueError(f"realization must have shape ({n},), got {idx.shape}")
    data = {}
    for j, name in enumerate(layout.SUMMARY_NAMES):
        data[name] = V.variable(name).data_array(summary[:, j])
    data["status"] = V.variable("status").data_array(status)
    cls = burial_class(summary[:, layout.SUMMARY_INDEX[class_basis]])
    cls = np.where(np.isin(status, status_codes.IN_STATISTICS), cls,
                   np.int8(V.UNCLASSIFIED)).astype(np.int8)
    data["burial_class"] = V.variable("burial_class").data_array(
        cls, burial_class_basis=class_basis)
    meta = dict(input_metadata or {})
    for path, values in (inputs or {}).items():
        units, desc = meta.get(path, (None, None))
        var = V.input_variable(path, units, desc)
        if var.name in data or var.name in V.VARIABLES:
            raise ValueError(f"sampled input {path!r} maps onto the existing variable {var.name!r}")
        arr = np.asarray(values, dtype=np.float64)
        if arr.shape != (n,):
            raise ValueError(f"sampled input {path!r} must have shape ({n},), got {arr.shape}")
        data[var.name] = var.data_array(arr)
    coords = {"realization": V.variable("realization").data_array(idx)}
    ds = xr.Dataset(data, coords=coords)
    for name, da in {**data, **coords}.items():
        ds[name].encoding.update(da.encoding)
    return ds


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


def write_netcdf(ds: xr.Dataset, path, *, complevel: int = 4) -> Path:
    """Write ``ds`` to ``path`` atomically (NETCDF4, zlib level ``complevel``).

    The file is written to a temporary file in the same directory, flushed to
    disk with ``fsync`` and moved over ``path`` with ``os.replace``
    (:func:`mineburial.io.files.atomic_path`): readers see either the previous file
    or the complete new one, never a partial file. On any error the temporary file
    is removed and the previous ``path`` is left untouched. Returns the path written.
    """
    path = Path(path)
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4",
                     encoding=_encoding(ds, complevel))
    return path
