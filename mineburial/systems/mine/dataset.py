"""The Dataset of an ensemble run: burial statistics, per-drop values, provenance.

:func:`build_dataset` assembles the burial statistics
(:func:`mineburial.systems.mine.statistics.burial_statistics`), optionally the
per-drop results and sampled inputs along the CF ``realization`` dimension, and
the global attributes that make a file a complete record of how it was made
(resolved scenario as JSON, seed, sampling method, package version).
:func:`mineburial.io.netcdf.write_netcdf` writes it.

Every variable and its attributes come from the one registry
:mod:`mineburial.io.variables`.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.io import netcdf as ncio
from mineburial.io import variables as V
from mineburial.io.dataset import build
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as status_codes
from mineburial.systems.mine.statistics import burial_class, burial_statistics

__all__ = ["build_dataset"]


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

    data = dict(statistics.data_vars)
    coords = dict(statistics.coords)
    if per_drop:
        data.update(_per_drop_variables(summary, status, inputs, input_metadata, class_basis))
        coords["realization"] = _realization(realization, n)

    n_total = int(n if n_drops is None else n_drops)
    version_s = str(version) if version is not None else "unknown"
    scen = ncio.scenario_json(scenario) if scenario is not None else None
    global_attrs = {
        "title": title or ncio.DEFAULT_TITLE,
        "summary": summary_text or ncio.DEFAULT_SUMMARY,
        "keywords": ncio.KEYWORDS,
        **_provenance(scen, seed, sampling_method, n_total, version_s, history, date_created),
        **_creator_attrs(creator),
        **_source_attrs(version_s),
        "scenario": scen,
        "random_seed": ncio.seed_attr(seed),
        "sampling_method": sampling_method,
        "n_drops": np.int64(n_total),
        "n_at_rest": np.int64(np.count_nonzero(status == status_codes.AT_REST)),
    }
    # statistics options recorded as well (basis, confidence level, quantile method ...)
    for k, v in statistics.attrs.items():
        global_attrs.setdefault(k, v)
    global_attrs.update(attrs or {})
    return build(data, coords, global_attrs, kind="ensemble", version=version_s)


def _creator_attrs(creator: Mapping[str, str] | None) -> dict:
    """ACDD ``creator_*`` and ``institution`` attributes from ``creator``'s keys (None where not given)."""
    cr = dict(creator or {})
    return {
        **{f"creator_{k}": cr.get(k) for k in ("name", "email", "url", "type")},
        "institution": cr.get("institution"),
    }


def _source_attrs(version_s: str) -> dict:
    """The attributes saying what made an ensemble file and where its variables are defined."""
    return {
        "product_version": version_s,
        "source": f"mineburial {version_s} (numba-compiled Monte Carlo impact-burial model)",
        "processing_level": "model output: Monte Carlo ensemble statistics",
        "standard_name_vocabulary": ncio.STANDARD_NAME_VOCABULARY,
        "references": ncio.REFERENCES,
        "comment": (
            "Statistics use only drops with status at_rest or buried_sinking; "
            "status_count gives the "
            "number of drops with every status code. Variable definitions: "
            "docs/notes/output.md of the mineburial sources."
        ),
    }


def _provenance(scen, seed, sampling_method, n_total: int, version_s: str, history, date_created) -> dict:
    """ACDD ``id`` (a hash of what makes the run), ``history`` (the run's line appended) and
    ``date_created`` of an ensemble file."""
    created = date_created or ncio.utc_now()
    ident_src = json.dumps([scen, str(seed), sampling_method, n_total, version_s])
    line = (
        f"{created} mineburial {version_s}: Monte Carlo ensemble of {n_total} drops"
        + (f", {sampling_method} sampling" if sampling_method else "")
        + (f", seed {seed}" if seed is not None else "")
    )
    return {
        "id": "mineburial-" + hashlib.sha256(ident_src.encode()).hexdigest()[:16],
        "history": f"{history}\n{line}" if history else line,
        "date_created": created,
    }


def _realization(realization, n: int) -> np.ndarray:
    idx = np.arange(n, dtype=np.int64) if realization is None else np.asarray(realization)
    if idx.shape != (n,):
        raise ValueError(f"realization must have shape ({n},), got {idx.shape}")
    return idx


def _per_drop_variables(summary, status, inputs, input_metadata, class_basis) -> dict:
    """The per-drop variables along ``realization``: every summary column, the status, the
    burial class on ``class_basis`` and the sampled inputs (``input_<path>``)."""
    n = summary.shape[0]
    data: dict = {name: summary[:, j] for j, name in enumerate(layout.SUMMARY_NAMES)}
    data["status"] = status
    cls = burial_class(summary[:, layout.SUMMARY_INDEX[class_basis]])
    cls = np.where(np.isin(status, status_codes.IN_STATISTICS), cls, np.int8(V.UNCLASSIFIED)).astype(np.int8)
    data["burial_class"] = (cls, {"burial_class_basis": class_basis})
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
    return data
