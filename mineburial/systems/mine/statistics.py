"""Burial statistics of an ensemble of drops, computed exactly from the per-drop results.

Input: the per-drop ``summary`` array (n, N_SUMMARY) whose columns are
:data:`mineburial.kernels.mine.layout.SUMMARY_NAMES` and the per-drop ``status``
codes (:mod:`mineburial.kernels.status`). Only drops whose status is in
``status.IN_STATISTICS`` (``at_rest``, and ``buried_sinking``: fully buried and still
sinking at the time limit, whose penetration is a lower bound) and a finite value
enter the statistics of an output; the counts of every status code are reported as
well, and the summary says how many drops were left out and why.

Every statistic is a function of the stored per-drop values, so statistics of
several chunks of an ensemble are obtained by concatenating the chunks' arrays
and calling :func:`burial_statistics` once: quantiles are exact order
statistics, never merged sketches.

Definitions (all declared once in :mod:`mineburial.io.variables`):

* mean: ``numpy.mean``; standard deviation: ``numpy.std(ddof=1)`` (NaN for
  n < 2); standard error of the mean: std / sqrt(n).
* quantiles: ``numpy.quantile(method="linear")``, i.e. type 7 of Hyndman, R. J. &
  Fan, Y. (1996), Sample quantiles in statistical packages, Am. Stat. 50(4), 361-365.
* histogram: ``numpy.histogram`` (bins [a, b) except the last, [a, b]).
* exceedance: P(X >= x) = #{values >= x} / n.
* impact-burial classes (naval symbology 0 %, 0-10 %, 10-20 %, 20-75 %, > 75 %):
  class 0 is exactly 0 % (p <= 0), class 1 is (0, 10], class 2 (10, 20],
  class 3 (20, 75], class 4 p > 75; see :func:`burial_class`.
* class probabilities k/n with the Wilson score interval, Wilson, E. B. (1927),
  Probable inference, the law of succession, and statistical inference,
  J. Am. Stat. Assoc. 22(158), 209-212; see
  :func:`mineburial.ensembles.intervals.wilson_interval`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.ensembles.intervals import wilson_interval
from mineburial.io import variables as V
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as status_codes
from mineburial.systems.mine.processes.scour_variables import SCOUR_MEASURES, SCOUR_STATUS_NAMES

__all__ = [
    "burial_statistics",
    "burial_class",
    "default_exceedance_levels",
    "default_histogram_bins",
    "status_counts",
]

DEFAULT_QUANTILES = (0.05, 0.25, 0.5, 0.75, 0.95)
#: number of equal-width bins over the data range for outputs without fixed bins
DEFAULT_N_BINS = 20
QUANTILE_METHOD = "linear"


# ---------------------------------------------------------------------------
# building blocks
# ---------------------------------------------------------------------------


def burial_class(percent):
    """Impact-burial class (int8) of burial percentages, vectorised.

    0: exactly 0 % (any p <= 0); 1: 0 < p <= 10; 2: 10 < p <= 20;
    3: 20 < p <= 75; 4: p > 75 (values above 100 included);
    -1 (:data:`mineburial.io.variables.UNCLASSIFIED`) for NaN.

    Returns an int8 array of the shape of ``percent`` (a numpy int8 scalar
    for a scalar input).
    """
    p = np.asarray(percent, dtype=np.float64)
    # searchsorted(side="left") counts the edges strictly below p, which gives
    # exactly the half-open (lower, upper] intervals; NaN sorts last -> fixed below.
    cls = np.searchsorted(np.asarray(V.BURIAL_CLASS_EDGES), p, side="left").astype(np.int8)
    cls = np.where(np.isnan(p), np.int8(V.UNCLASSIFIED), cls).astype(np.int8)
    return cls[()] if cls.ndim == 0 else cls


def status_counts(status) -> np.ndarray:
    """Number of drops with each status code 0..len(NAMES)-1 (int64)."""
    s = np.asarray(status)
    if s.ndim != 1:
        raise ValueError(f"status must be a 1-D array, got shape {s.shape}")
    if not np.issubdtype(s.dtype, np.integer):
        raise TypeError(f"status must hold integer codes, got dtype {s.dtype}")
    n_codes = len(status_codes.NAMES)
    bad = (s < 0) | (s >= n_codes)
    if np.any(bad):
        raise ValueError(
            f"unknown status code(s) {sorted(set(np.asarray(s[bad]).tolist()))}; known codes are "
            + ", ".join(f"{i} {nm}" for i, nm in enumerate(status_codes.NAMES))
        )
    return np.bincount(s.astype(np.int64), minlength=n_codes).astype(np.int64)


def default_exceedance_levels(output: str) -> np.ndarray | None:
    """Fixed exceedance thresholds of a burial output (``None``: use the histogram edges).

    * percent outputs: 0, 5, ..., 100 %;
    * ``penetration_depth`` and ``height_proud``: 0 to 5 m by 0.05 m;
    * ``com_depth`` (negative above the seabed): -2 to 5 m by 0.05 m.

    Fixed grids make files of different runs directly comparable; the 5 m span
    covers full burial of mines up to ~3 m long in very soft mud.
    """
    if output in V.PERCENT_OUTPUTS:
        return np.arange(21, dtype=np.float64) * 5.0
    if output == "com_depth":
        return np.round(np.arange(-40, 101, dtype=np.float64) * 0.05, 10)
    if output in V.DEPTH_OUTPUTS:
        return np.round(np.arange(0, 101, dtype=np.float64) * 0.05, 10)
    if output not in V.SUMMARY_OUTPUTS:
        raise KeyError(f"unknown summary output {output!r}")
    return None


def default_histogram_bins(output: str):
    """Default ``bins`` argument of ``numpy.histogram`` for an output.

    Percent outputs: fixed edges 0, 5, ..., 100 %; every other output:
    :data:`DEFAULT_N_BINS` equal-width bins over the range of its values.
    """
    if output in V.PERCENT_OUTPUTS:
        return np.arange(21, dtype=np.float64) * 5.0
    if output not in V.SUMMARY_OUTPUTS:
        raise KeyError(f"unknown summary output {output!r}")
    return DEFAULT_N_BINS


def _histogram_bins(values, bins):
    """``bins`` for ``numpy.histogram``: a bin count over values whose range is too narrow
    for that many finite bins (constant to the last few digits, e.g. one impact time for
    every drop) becomes explicit edges over a range of 1e-6 of their magnitude around them
    (numpy raises "Too many bins for data range" there)."""
    if np.ndim(bins) != 0 or isinstance(bins, str) or values.size == 0:
        return bins
    lo = float(values.min())
    hi = float(values.max())
    scale = max(abs(lo), abs(hi), 1e-300)
    if hi - lo >= 1e-6 * scale or hi == lo:
        return bins
    mid = 0.5 * (lo + hi)
    return np.linspace(mid - 0.5e-6 * scale, mid + 0.5e-6 * scale, int(bins) + 1)


def _per_output(option, output: str, default):
    """Resolve an option that may be ``None`` / a single value / a mapping per output."""
    if option is None:
        return default(output)
    if isinstance(option, Mapping):
        return option[output] if output in option else default(output)
    return option


def _check_levels(levels, output: str) -> np.ndarray:
    lv = np.asarray(levels, dtype=np.float64)
    if lv.ndim != 1 or lv.size == 0 or not np.all(np.isfinite(lv)):
        raise ValueError(
            f"exceedance levels of {output!r} must be a non-empty 1-D array of finite numbers, got {levels!r}"
        )
    if np.any(np.diff(lv) <= 0):
        raise ValueError(
            f"exceedance levels of {output!r} must be strictly increasing "
            "(they become a CF coordinate variable)"
        )
    return lv


# ---------------------------------------------------------------------------
# the ensemble statistics
# ---------------------------------------------------------------------------


def burial_statistics(
    summary,
    status,
    *,
    quantiles: Sequence[float] = DEFAULT_QUANTILES,
    class_basis: str = "burial_volume",
    exceedance_levels=None,
    histogram_bins=None,
    outputs: Iterable[str] | None = None,
    confidence_level: float = 0.95,
) -> xr.Dataset:
    """Statistics of the drops at rest, as a CF-described :class:`xarray.Dataset`.

    Parameters
    ----------
    summary : array (n, N_SUMMARY), columns ``layout.SUMMARY_NAMES``.
    status : integer array (n,) of status codes; statistics use only code 0.
    quantiles : probability levels in [0, 1] of the quantiles.
    class_basis : summary output the impact-burial classes are based on, one of
        ``burial_volume`` (default), ``burial_height``, ``burial_area``.
    exceedance_levels : ``None`` (defaults of :func:`default_exceedance_levels`,
        histogram edges for outputs without a fixed grid), one 1-D array used
        for every output, or a mapping output -> array (others default).
    histogram_bins : ``None`` (defaults of :func:`default_histogram_bins`), one
        ``numpy.histogram`` ``bins`` argument used for every output, or a
        mapping output -> bins (others default).
    outputs : summary outputs to describe (default: all of ``SUMMARY_NAMES``).
    confidence_level : of the Wilson intervals of the class probabilities.

    With no drop at rest every statistic is NaN (counts 0) and the attribute
    ``statistics_note`` says why; nothing raises and no warning is emitted.
    """
    summary, counts, q, outputs = _checked_inputs(summary, status, quantiles, class_basis, outputs)
    used = np.isin(np.asarray(status), status_codes.IN_STATISTICS)
    n_at_rest = int(np.count_nonzero(np.asarray(status) == status_codes.AT_REST))
    n_used = int(np.count_nonzero(used))
    ok = summary[used]

    data_vars: dict[str, xr.DataArray] = {}
    coords: dict[str, xr.DataArray] = {"quantile": V.variable("quantile").data_array(q)}

    for name in outputs:
        col = ok[:, layout.SUMMARY_INDEX[name]]
        values = col[np.isfinite(col)]
        _describe_output(name, values, q, exceedance_levels, histogram_bins, data_vars, coords)

    basis = ok[:, layout.SUMMARY_INDEX[class_basis]]
    _describe_burial_classes(basis[np.isfinite(basis)], class_basis, confidence_level, data_vars, coords)

    coords["status_code"] = V.variable("status_code").data_array(np.arange(counts.size))
    data_vars["status_count"] = V.variable("status_count").data_array(counts)

    attrs = _statistics_attrs(int(summary.shape[0]), n_at_rest, n_used, class_basis, confidence_level)
    ds = xr.Dataset(data_vars=data_vars, coords=coords, attrs=attrs)
    # xarray keeps encodings on the variables; restore them in case construction dropped any
    for name, da in {**data_vars, **coords}.items():
        ds.variables[name].encoding.update(da.encoding)  # the Variable: no DataArray built
    return ds


def _checked_inputs(summary, status, quantiles, class_basis, outputs):
    """``(summary, status counts, quantile levels, outputs)`` of :func:`burial_statistics`'s
    arguments; a ValueError (TypeError for non-integer status codes) names a bad one."""
    summary = np.asarray(summary, dtype=np.float64)
    if summary.ndim != 2 or summary.shape[1] != layout.N_SUMMARY:
        raise ValueError(
            f"summary must have shape (n, {layout.N_SUMMARY}) with columns "
            f"layout.SUMMARY_NAMES, got {summary.shape}"
        )
    counts = status_counts(status)
    if np.asarray(status).shape[0] != summary.shape[0]:
        raise ValueError(f"status has {np.asarray(status).shape[0]} drops but summary has {summary.shape[0]}")
    if class_basis not in V.BURIAL_CLASS_BASES:
        raise ValueError(f"class_basis must be one of {', '.join(V.BURIAL_CLASS_BASES)}; got {class_basis!r}")
    q = np.asarray(quantiles, dtype=np.float64)
    if q.ndim != 1 or q.size == 0 or np.any((q < 0) | (q > 1)) or np.any(np.diff(q) <= 0):
        raise ValueError(f"quantiles must be strictly increasing probabilities in [0, 1], got {quantiles!r}")
    outputs = tuple(layout.SUMMARY_NAMES if outputs is None else outputs)
    for o in outputs:
        if o not in V.SUMMARY_OUTPUTS:
            raise ValueError(V._unknown("summary output", o, V.SUMMARY_OUTPUTS))
    return summary, counts, q, outputs


def _describe_burial_classes(basis, class_basis, confidence_level, data_vars, coords):
    """Add the impact-burial classes of the finite ``basis`` values to ``data_vars``/``coords``:
    class bounds, counts, probabilities k/n and their Wilson intervals."""
    n_cls = int(basis.size)
    k = np.bincount(burial_class(basis).astype(np.int64), minlength=5) if n_cls else np.zeros(5, np.int64)
    prob = k / n_cls if n_cls else np.full(5, np.nan)
    lo, hi = wilson_interval(k, np.full(5, n_cls), confidence_level)
    coords["impact_burial_class"] = V.variable("impact_burial_class").data_array(np.arange(5))
    cls_attrs = dict(burial_class_basis=class_basis, sample_size=np.int64(n_cls))
    ci_attrs = dict(
        cls_attrs,
        confidence_level=float(confidence_level),
        interval_method="Wilson score interval (Wilson 1927)",
    )
    for name, values, attrs in (
        ("burial_class_lower_percent", V.BURIAL_CLASS_LOWER, {}),
        ("burial_class_upper_percent", V.BURIAL_CLASS_UPPER, {}),
        ("burial_class_count", k, cls_attrs),
        ("burial_class_probability", prob, cls_attrs),
        ("burial_class_probability_lower", lo, ci_attrs),
        ("burial_class_probability_upper", hi, ci_attrs),
    ):
        data_vars[name] = V.variable(name).data_array(values, **attrs)


def _statistics_attrs(n_drops: int, n_at_rest: int, n_used: int, class_basis: str, confidence_level) -> dict:
    """Global attributes of the statistics: the drop counts, the class basis and the methods."""
    attrs = {
        "n_drops": np.int64(n_drops),
        "n_at_rest": np.int64(n_at_rest),
        "n_in_statistics": np.int64(n_used),
        "burial_class_basis": class_basis,
        "burial_class_definition": "0: exactly 0 %; 1: (0, 10] %; 2: (10, 20] %; 3: (20, 75] %; 4: > 75 %",
        "confidence_level": float(confidence_level),
        "quantile_method": "numpy.quantile method 'linear' (Hyndman & Fan 1996 type 7), exact "
        "from the stored per-drop values",
        "statistics_basis": (
            "drops with status at_rest or buried_sinking (fully buried, still "
            "sinking at the time limit: penetration is a lower bound) and a "
            "finite value of the output"
        ),
    }
    if n_used == 0:
        attrs["statistics_note"] = (
            "no drop came to rest or was buried (n_at_rest = 0, "
            "n_in_statistics = 0): every burial statistic is NaN and "
            "every count is 0; see status_count"
        )
    return attrs


def _describe_output(name, values, q, exceedance_levels, histogram_bins, data_vars, coords):
    """Add the statistics variables of one output to ``data_vars``/``coords``."""
    n = int(values.size)
    size_attr = {"sample_size": np.int64(n)}
    if n:
        mean = np.mean(values)
        std = np.std(values, ddof=1) if n > 1 else np.nan
        stderr = std / np.sqrt(n) if n > 1 else np.nan
        quant = np.quantile(values, q, method=QUANTILE_METHOD)
    else:
        mean = std = stderr = np.nan
        quant = np.full(q.shape, np.nan)

    bins = _histogram_bins(values, _per_output(histogram_bins, name, default_histogram_bins))
    counts, edges = np.histogram(values, bins=bins)
    edges = _check_levels(edges, f"{name} (histogram edges)")
    n_outside = n - int(counts.sum())

    levels = _per_output(exceedance_levels, name, default_exceedance_levels)
    levels = edges if levels is None else _check_levels(levels, name)
    if n:
        srt = np.sort(values)
        exceed = (n - np.searchsorted(srt, levels, side="left")) / n
    else:
        exceed = np.full(levels.shape, np.nan)

    var = V.variable
    bin_name, level_name = f"{name}_bin", f"{name}_level"
    coords[bin_name] = var(bin_name).data_array(0.5 * (edges[:-1] + edges[1:]))
    coords[level_name] = var(level_name).data_array(levels)
    data_vars[f"{name}_mean"] = var(f"{name}_mean").data_array(mean, **size_attr)
    data_vars[f"{name}_std"] = var(f"{name}_std").data_array(std, **size_attr)
    data_vars[f"{name}_stderr"] = var(f"{name}_stderr").data_array(stderr, **size_attr)
    data_vars[f"{name}_quantile"] = var(f"{name}_quantile").data_array(quant, **size_attr)
    data_vars[f"{name}_bin_bounds"] = var(f"{name}_bin_bounds").data_array(
        np.stack([edges[:-1], edges[1:]], axis=1)
    )
    data_vars[f"{name}_histogram"] = var(f"{name}_histogram").data_array(
        counts, n_outside_range=np.int64(n_outside), **size_attr
    )
    data_vars[f"{name}_exceedance"] = var(f"{name}_exceedance").data_array(exceed, **size_attr)


# ---------------------------------------------------------------------------
# the post-impact scour stage (optional [scour] section)
# ---------------------------------------------------------------------------


def _quantiles_with_inf(values, q):
    """Linear (type 7) quantiles of ``values`` that may hold +inf ("never"): the order statistics
    are those of the values with inf kept; a quantile that interpolates towards an inf is inf."""
    if values.size == 0:
        return np.full(q.shape, np.nan)
    srt = np.sort(values)
    h = (values.size - 1) * q
    lo = np.floor(h).astype(np.int64)
    hi = np.minimum(lo + 1, values.size - 1)
    w = h - lo
    a, b = srt[lo], srt[hi]
    with np.errstate(invalid="ignore"):
        out = np.where(w == 0.0, a, a + w * (b - a))
    return np.where(np.isinf(b) & (w > 0.0), np.inf, out)


def scour_statistics(
    measures,
    time_to_days,
    mobile_days,
    scour_status,
    lead_time_days,
    burial_levels,
    *,
    quantiles: Sequence[float] = DEFAULT_QUANTILES,
    class_basis: str = "burial_volume",
    confidence_level: float = 0.95,
) -> xr.Dataset:
    """Statistics of the scour stage at each lead time, as a CF-described Dataset.

    ``measures`` (n, len(SCOUR_MEASURES), n_lead): the burial measures of each drop at each lead
    time; ``time_to_days`` (n, n_levels); ``mobile_days`` (n,); ``scour_status`` (n,) codes of
    :data:`mineburial.systems.mine.processes.scour_variables.SCOUR_STATUS_NAMES`. Only drops with status ok
    enter: the same mean, type-7 quantiles, burial classes (:func:`burial_class`) and Wilson intervals
    (:func:`~mineburial.ensembles.intervals.wilson_interval`) as the impact statistics, per lead time.
    """
    measures = np.asarray(measures, dtype=np.float64)
    scour_status = np.asarray(scour_status)
    q = np.asarray(quantiles, dtype=np.float64)
    ok = scour_status == 0
    var = V.variable
    data_vars: dict[str, xr.DataArray] = {}
    coords = {
        "lead_time": var("lead_time").data_array(np.asarray(lead_time_days, dtype=np.float64)),
        "burial_level": var("burial_level").data_array(np.asarray(burial_levels, dtype=np.float64)),
        "quantile": var("quantile").data_array(q),
        "impact_burial_class": var("impact_burial_class").data_array(np.arange(5)),
        "scour_status_code": var("scour_status_code").data_array(np.arange(len(SCOUR_STATUS_NAMES))),
    }
    n_lead = coords["lead_time"].size
    for k, name in enumerate(SCOUR_MEASURES):
        mean = np.full(n_lead, np.nan)
        quant = np.full((n_lead, q.size), np.nan)
        for j in range(n_lead):
            col = measures[ok, k, j]
            col = col[np.isfinite(col)]
            if col.size:
                mean[j] = np.mean(col)
                quant[j] = np.quantile(col, q, method=QUANTILE_METHOD)
        data_vars[f"scour_{name}_mean"] = var(f"scour_{name}_mean").data_array(mean)
        data_vars[f"scour_{name}_quantile"] = var(f"scour_{name}_quantile").data_array(quant)

    k_basis = SCOUR_MEASURES.index(class_basis)
    counts = np.zeros((n_lead, 5), dtype=np.int64)
    n_cls = np.zeros(n_lead, dtype=np.int64)
    for j in range(n_lead):
        basis = measures[ok, k_basis, j]
        basis = basis[np.isfinite(basis)]
        n_cls[j] = basis.size
        counts[j] = np.bincount(burial_class(basis).astype(np.int64), minlength=5)
    with np.errstate(invalid="ignore", divide="ignore"):
        prob = np.where(n_cls[:, None] > 0, counts / n_cls[:, None], np.nan)
    lo, hi = wilson_interval(counts, np.broadcast_to(n_cls[:, None], counts.shape), confidence_level)
    cls_attrs = dict(burial_class_basis=class_basis)
    ci_attrs = dict(
        cls_attrs,
        confidence_level=float(confidence_level),
        interval_method="Wilson score interval (Wilson 1927)",
    )
    data_vars["scour_burial_class_count"] = var("scour_burial_class_count").data_array(counts, **cls_attrs)
    data_vars["scour_burial_class_probability"] = var("scour_burial_class_probability").data_array(
        prob, **cls_attrs
    )
    data_vars["scour_burial_class_probability_lower"] = var(
        "scour_burial_class_probability_lower"
    ).data_array(lo, **ci_attrs)
    data_vars["scour_burial_class_probability_upper"] = var(
        "scour_burial_class_probability_upper"
    ).data_array(hi, **ci_attrs)

    times = np.asarray(time_to_days, dtype=np.float64)[ok]
    n_ok = int(np.count_nonzero(ok))
    tq = np.stack([_quantiles_with_inf(np.sort(times[:, k]), q) for k in range(times.shape[1])])
    reached = np.isfinite(times).sum(axis=0) / n_ok if n_ok else np.full(times.shape[1], np.nan)
    data_vars["scour_time_to_level_quantile"] = var("scour_time_to_level_quantile").data_array(tq)
    data_vars["scour_level_reached_fraction"] = var("scour_level_reached_fraction").data_array(reached)
    mobile = np.asarray(mobile_days, dtype=np.float64)[ok]
    frac = float(np.count_nonzero(np.isfinite(mobile)) / n_ok) if n_ok else np.nan
    data_vars["scour_mobile_fraction"] = var("scour_mobile_fraction").data_array(frac)
    codes = np.bincount(scour_status.astype(np.int64), minlength=len(SCOUR_STATUS_NAMES))
    data_vars["scour_status_count"] = var("scour_status_count").data_array(codes)
    ds = xr.Dataset(data_vars=data_vars, coords=coords, attrs={"scour_n_in_statistics": np.int64(n_ok)})
    for name, da in {**data_vars, **coords}.items():
        ds.variables[name].encoding.update(da.encoding)  # the Variable: no DataArray built
    return ds
