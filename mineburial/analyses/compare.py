"""``mineburial compare``: the same sampled drops under several variants of one scenario field.

Every variant is an ensemble of its own on the run driver
(:func:`mineburial.ensembles.runner.run_jobs`: threads, a dask cluster, resume), with the
seed, sampling and chunks of the given scenario: the random inputs of drop *i* are a pure
function of (seed, *i*, field) (:mod:`mineburial.ensembles.sampling`), so every variant
draws the same inputs, packed into a scenario that differs from the given one only in
the varied field (and what the scenario derives from it: choosing
``numerics.model = "impact35"`` also switches the sediment resistance and rate law to
that model's defaults unless the scenario names them). Before any drop runs, the packed
parameter rows of every variant are checked against those of the first, chunk by
chunk: only the parameter slots that the varied field changes in the fixed scenario may
differ (a ``RuntimeError`` otherwise); after the run, the sampled inputs of every
variant must be identical. Differences between variants are therefore the models' own,
not sampling noise, and the paired differences of the means have much narrower
intervals than independent runs would give.

Intervals: means +- z standard errors (normal approximation, z for 95 %); class
probabilities with the Wilson score interval (as ``mineburial run``); paired
differences to the first variant over the drops in the statistics of both, mean +- z
standard errors of the per-drop differences.

Burial after a post-impact process (issue 20; scour is the one there is,
:mod:`mineburial.systems.mine.processes.registry`): with a ``[scour]`` section every variant runs the
post-impact stage and the compared burial measures are those at **one lead time** (``--lead-time DAYS``,
default the section's last; :func:`mineburial.systems.mine.processes.registry.at_lead_time`), as in
``mineburial sensitivity``; a drop whose stage did not give a value is left out of the burial
statistics, as in ``run``'s statistics after scour (the process's ``burial_after``).
A process's own field (``scour.*``) may be varied (``--vary scour.orbital=spectral,hs``): it changes no packed
impact parameter, and the sampled inputs of the stage are checked equal across variants like
every other.
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import pathlib
import time

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.ensembles import engine, runner
from mineburial.ensembles.intervals import two_sided_normal_quantile
from mineburial.ensembles.sampling import check_drop_count
from mineburial.ensembles.store import OutputRun
from mineburial.io import variables as V
from mineburial.io.dataset import build
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as st
from mineburial.resources import memory_refusal
from mineburial.systems.mine import config as cfg
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import epistemic
from mineburial.systems.mine.calibration import posterior
from mineburial.systems.mine.figures import check_plot_path, pyplot, save_figure
from mineburial.systems.mine.processes import registry as processes
from mineburial.systems.mine.statistics import burial_statistics

__all__ = [
    "ComparisonError",
    "SHORT_NAMES",
    "parse_vary",
    "run_comparison",
    "comparison_table",
    "plot_comparison",
    "run_compare_cli",
]

#: Short names accepted by ``--vary`` for the model choices.
SHORT_NAMES = {
    "model": "numerics.model",
    "resistance": "sediment.resistance",
    "rate_law": "sediment.rate_law",
    "integrator": "numerics.integrator",
    "sediment_quadrature": "numerics.sediment_quadrature",
    "water_column": "numerics.water_column",
}

#: Outputs whose statistics are compared (the registry's comparison family declares the file).
OUTPUTS = V.COMPARE_OUTPUTS
#: Per-drop outputs stored for every variant.
PER_DROP = V.COMPARE_PER_DROP


class ComparisonError(cfg.ScenarioError):
    """A bad ``--vary`` request (unknown field, random field, too few values)."""


# ---------------------------------------------------------------------------
# the varied field
# ---------------------------------------------------------------------------
def _value(text: str):
    t = text.strip()
    if t.lower() in ("true", "false"):
        return t.lower() == "true"
    try:
        return int(t)
    except ValueError:
        pass
    try:
        return float(t)
    except ValueError:
        return t


def parse_vary(text: str):
    """``"FIELD=A,B,C"`` -> ``(dotted field, [A, B, C])`` with numbers and booleans parsed.

    ``FIELD`` is a dotted scenario path (``sediment.resistance``, ``mine.com_offset``,
    ``release.z``) or one of :data:`SHORT_NAMES` (``model``, ``resistance``, ``rate_law``).
    """
    if not isinstance(text, str) or "=" not in text:
        raise ComparisonError(
            f"--vary {text!r}: expected FIELD=A,B,... (for example "
            f"sediment.resistance=bearing,friction,delta)"
        )
    field, _, values = text.partition("=")
    field = SHORT_NAMES.get(field.strip(), field.strip())
    vals = [_value(v) for v in values.split(",") if v.strip()]
    if not field:
        raise ComparisonError(f"--vary {text!r}: the field name is empty")
    if len(vals) < 2:
        raise ComparisonError(f"--vary {text!r}: give at least two values, comma-separated")
    if len({repr(v) for v in vals}) != len(vals):
        raise ComparisonError(f"--vary {text!r}: a value is listed twice")
    return field, vals


def _location(field: str) -> str:
    """Where ``field`` sits in a scenario file (``release.z`` -> ``release.position[2]``)."""
    spec = cfg.FIELDS.get(field)
    if spec is not None:
        return spec.location
    return field


def _set_field(raw: dict, location: str, value) -> None:
    parts = location.split(".")
    node = raw
    for part in parts[:-1]:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise ComparisonError(f"--vary {location}: '{part}' is not a table of the scenario")
    last = parts[-1]
    if "[" in last:
        key, idx = last[:-1].split("[")
        seq = node.get(key)
        if not isinstance(seq, list) or not int(idx) < len(seq):
            raise ComparisonError(f"--vary {location}: the scenario has no list '{key}' with an entry {idx}")
        seq[int(idx)] = value
    else:
        node[last] = value


def _variant_spec(base: mine.EnsembleSpec, field: str, value, n: int, seed: int, base_dir=None):
    raw = copy.deepcopy(base.raw)
    _set_field(raw, _location(field), value)
    try:
        spec = engine.load_ensemble(
            raw,
            base_dir=base_dir,
            n=n,
            seed=seed,
            sampling=base.sampling,
            chunk_size=base.chunk_size,
            class_basis=base.class_basis,
            per_drop=False,
        )
    except cfg.ScenarioError as exc:
        raise ComparisonError(f"--vary {field}={value!r}: {exc}") from None
    if set(spec.random) != set(base.random):
        raise ComparisonError(
            f"--vary {field}={value!r} changes which inputs are random; compare varies fixed fields only"
        )
    return spec


def _random_slots(spec: mine.EnsembleSpec) -> set[int]:
    """Parameter slots written from the sampled inputs (not fixed by the scenario)."""
    slots = set()
    for path in spec.random:
        if path == spec.sediment_choice:
            slots.add(layout.P_SED_PROFILE)
        elif path in mine._ANGLE_FIELDS:
            slots.update(range(layout.P_Q00, layout.P_Q30 + 1))
        elif processes.owns_input(path):  # a post-impact process's own inputs: no impact slot
            continue
        elif path == posterior.SET_INPUT:  # the coefficients drawn from the posterior
            slots.update(layout.INDEX[p] for p in spec.posterior_paths if not processes.owns_input(p))
        else:
            slots.add(layout.INDEX[cfg.ALIASES.get(path, path)])
    if spec.recompute_inertia:
        slots.update((layout.P_J1, layout.P_J2))
    return slots


def _differs(a, b):
    return ~((a == b) | (np.isnan(a) & np.isnan(b)))


# ---------------------------------------------------------------------------
# the comparison
# ---------------------------------------------------------------------------
def _plan(scenario, field, values, *, n=None, seed=None, sampling=None, lead_time=None):
    """``(field, base spec, variant specs)`` of a comparison, every request checked; with a
    post-impact process that changes the burial (``[scour]``) every spec's process reports the one
    lead time compared."""
    field = SHORT_NAMES.get(field, field)
    if values is None or len(values) < 2:
        raise ComparisonError("compare needs at least two values of the varied field")
    if field.startswith("ensemble."):
        raise ComparisonError(f"--vary {field}: the [ensemble] settings cannot be varied (use -n and --seed)")
    base = processes.at_lead_time(
        engine.load_ensemble(scenario, n=n, seed=seed, sampling=sampling, per_drop=False), lead_time
    )
    loc = _location(field)
    if field in base.random or loc in base.random:
        raise ComparisonError(
            f"--vary {field}: this input is random in the scenario (a distribution); compare "
            f"varies fields held fixed. Random inputs: {', '.join(sorted(base.random))}"
        )
    if base.sampling == "sobol":
        check_drop_count(base.n, "sobol")
    # the variants' file names are resolved like the scenario's own: against its folder
    path = scenario if isinstance(scenario, (str, os.PathLike)) else None
    base_dir = pathlib.Path(path).resolve().parent if path is not None else None
    lead = processes.analysed_lead_time(base)
    variants = [_variant_spec(base, field, v, base.n, base.seed, base_dir) for v in values]
    return field, base, [processes.at_lead_time(spec, lead) for spec in variants]


def comparison_inputs(scenario, field, values, *, n=None, seed=None, lead_time=None) -> list:
    """The files a comparison reads: the scenario file, the files it names and those the
    varied values name (``--vary sediment.file=a.csv,b.csv``)."""
    _, base, specs = _plan(scenario, field, values, n=n, seed=seed, lead_time=lead_time)
    return runner.input_paths(scenario, base) + [
        pathlib.Path(f) for spec in specs for f, _ in spec.input_files
    ]


def run_comparison(
    scenario=None,
    field: str = "sediment.resistance",
    values=None,
    *,
    n: int | None = None,
    seed: int | None = None,
    sampling: str | None = None,
    threads: int | None = None,
    progress: bool = False,
    confidence_level: float = 0.95,
    client=None,
    output_run=None,
    lead_time: float | None = None,
) -> xr.Dataset:
    """Run the same sampled drops under ``field = value`` for each of ``values``.

    Each variant is one ensemble of the run driver (:func:`mineburial.ensembles.runner.
    run_jobs`: ``threads`` numba threads here, or the cluster of a dask ``client``); with
    ``output_run`` (an :class:`~mineburial.ensembles.store.OutputRun`) its finished chunks
    are kept in ``variant-<k>/`` of the parts folder, so an interrupted comparison resumes.

    Returns a Dataset with a ``variant`` dimension (statistics per variant, paired
    differences to the first variant, per-drop penetration, burial and status) and the
    sampled inputs once along ``realization``. Raises :class:`ComparisonError` for a
    field that is random in the scenario or a value the scenario rejects, and
    ``RuntimeError`` if the sampled inputs were not identical across variants. With a
    ``[scour]`` section the burial measures are those after the stage at ``lead_time`` days.
    """
    field, base, specs = _plan(
        scenario, field, values, n=n, seed=seed, sampling=sampling, lead_time=lead_time
    )
    threads = runner.check_threads(threads, "--threads")
    refusal = memory_refusal(  # every variant keeps its per-drop values, as one run does
        len(specs) * runner.memory_needed(specs[0]),
        f"ensemble.n = {base.n} drops under {len(specs)} variants",
        "run fewer drops",
    )
    if refusal:
        raise ComparisonError(refusal)
    changed = _changed_parameters(specs, values)
    jobs = [
        runner.Job(k, spec, None if output_run is None else output_run.store(spec, f"variant-{k}"))
        for k, spec in enumerate(specs)
    ]
    t0 = time.monotonic()
    chunks = dict(runner.run_jobs(jobs, client=client, progress=progress, threads=threads))
    elapsed = time.monotonic() - t0
    chunks = [chunks[k] for k in range(len(specs))]
    summaries = [np.concatenate([r["summary"] for r in c]) for c in chunks]
    statuses = [np.concatenate([r["status"] for r in c]) for c in chunks]
    inputs = _same_inputs(chunks)
    after = processes.burial_process(base)
    if after is not None:
        summaries = [after[0].burial_after(after[1], s, c) for s, c in zip(summaries, chunks)]
    attrs = {
        "title": f"mineburial comparison: {base.base.mine.name}, {field} = "
        + ", ".join(str(v) for v in values),
        "varied_field": field,
        "scenario": json.dumps(base.resolved(), default=str),
        "random_seed": str(base.seed),
        "sampling_method": base.sampling,
        "n_drops": np.int64(base.n),
        "inputs_identical_across_variants": "yes (checked chunk by chunk: the same sampled "
        "inputs, and only the varied field's parameter "
        "slots differ)",
        "elapsed_seconds": float(elapsed),
    }
    ds = _assemble(base, field, values, (summaries, statuses, inputs, changed), confidence_level, attrs)
    if after is not None:
        _process_attrs(ds, after[0], processes.analysed_lead_time(base), chunks, values)
    return ds


def _process_attrs(ds, process, lead, chunks, values) -> None:
    """The lead time compared and each variant's count of the process's statuses
    (``<section>_status_counts``), in ``ds.attrs``."""
    ds.attrs["title"] += f", burial after {process.section} at lead time {lead:g} d"
    ds.attrs["lead_time_days"] = lead
    counts = [f"{value}: {process.status_text(c)}" for value, c in zip(values, chunks)]
    ds.attrs[f"{process.section}_status_counts"] = "; ".join(counts)


def _changed_parameters(specs, values) -> list[set]:
    """The parameter slots in which each variant's packed drops differ from the first
    variant's, checked chunk by chunk before any drop runs: only the slots that the varied
    field changes in the fixed scenario may differ (a RuntimeError names the others)."""
    rand_slots = _random_slots(specs[0])
    allowed = [
        set(np.flatnonzero(_differs(s.base_params, specs[0].base_params)).tolist()) - rand_slots
        for s in specs
    ]
    changed = [set() for _ in specs]
    for s, e in engine.chunk_bounds(specs[0].n, specs[0].chunk_size):
        rows0 = mine.chunk_inputs(specs[0], s, e)[0]
        for k in range(1, len(specs)):
            cols = set(
                np.flatnonzero(_differs(mine.chunk_inputs(specs[k], s, e)[0], rows0).any(axis=0)).tolist()
            )
            if not cols <= allowed[k]:
                bad = [layout.PARAM_NAMES[i] for i in sorted(cols - allowed[k])]
                raise RuntimeError(
                    f"variant {values[k]!r} changed parameters other than the varied "
                    f"field's: {', '.join(bad)}"
                )
            changed[k] |= cols
    return changed


def _same_inputs(chunks) -> dict:
    """The sampled inputs of the drops (``input:<path>`` of the chunk results), checked to
    be the same in every variant (a RuntimeError otherwise)."""
    first = chunks[0]
    for other in chunks[1:]:
        for a, b in zip(first, other):
            keys = [key for key in a if key.startswith("input:")]
            if keys != [key for key in b if key.startswith("input:")] or not all(
                np.array_equal(a[key], b[key]) for key in keys
            ):
                raise RuntimeError("sampled inputs differ between variants")
    return {key[6:]: np.concatenate([r[key] for r in first]) for key in first[0] if key.startswith("input:")}


def _assemble(base, field, values, per_drop, confidence_level, attrs) -> xr.Dataset:
    """The comparison Dataset, built from the registry's comparison family
    (:func:`mineburial.io.dataset.build`): statistics per variant, paired differences, per-drop
    values; ``per_drop`` is (summaries, statuses, sampled inputs, changed slots) of the variants,
    ``attrs`` the run's global attributes."""
    summaries, statuses, inputs, changed = per_drop
    z = two_sided_normal_quantile(confidence_level)
    labels = [str(v) for v in values]
    stats = _variant_statistics(base, summaries, statuses, confidence_level, z)
    family = V.family("comparison")
    data = {  # each statistic with the attributes its computation gave beyond the declaration
        name: (da.values, {k: v for k, v in da.attrs.items() if k not in family[name].cf_attrs()})
        for name, da in stats.data_vars.items()
    }
    if posterior.SET_INPUT in inputs:  # the epistemic band of each variant (docs/calibration.md)
        bands = [
            epistemic.band_variables(s, t, inputs[posterior.SET_INPUT], base.class_basis)
            for s, t in zip(summaries, statuses)
        ]
        for name in epistemic.NAMES:
            extra = {k: v for k, v in bands[0][name].attrs.items() if k not in family[name].cf_attrs()}
            extra.pop("coefficient_sets", None)
            data[name] = (np.stack([b[name].values for b in bands]), extra)
    data.update(_paired_differences(summaries, statuses, labels[0], confidence_level, z))
    data.update(_drops(summaries, statuses, inputs, changed))
    coords = {name: stats[name].values for name in stats.coords}
    coords["variant"] = (np.array(labels, dtype=object), {"long_name": f"value of {field}"})
    coords["realization"] = np.arange(summaries[0].shape[0], dtype=np.int64)
    return build(data, coords, {**stats.attrs, **attrs}, kind="comparison")


def _variant_statistics(base, summaries, statuses, confidence_level, z):
    """Each variant's burial statistics (no histograms) with normal bounds of the means, along ``variant``."""
    per_variant = []
    for summary, status in zip(summaries, statuses):
        stats = burial_statistics(
            summary,
            status,
            class_basis=base.class_basis,
            outputs=OUTPUTS,
            confidence_level=confidence_level,
        )
        drop = [v for v in stats.variables if v.endswith(("_bin", "_bin_bounds", "_histogram"))]
        stats = stats.drop_vars(drop)
        for name in OUTPUTS:
            mean = stats[f"{name}_mean"]
            se = stats[f"{name}_stderr"]
            stats[f"{name}_mean_lower"] = mean - z * se
            stats[f"{name}_mean_upper"] = mean + z * se
        stats["n_in_statistics"] = np.int64(stats.attrs["n_in_statistics"])
        per_variant.append(stats)
    ds = xr.concat(
        per_variant,
        dim="variant",
        coords="minimal",
        compat="override",
        combine_attrs="drop_conflicts",
        data_vars="all",
    )
    for name in (
        "quantile",
        "impact_burial_class",
        "status_code",
        "burial_class_lower_percent",
        "burial_class_upper_percent",
    ):
        if name in ds and "variant" in ds[name].dims:
            ds[name] = ds[name].isel(variant=0, drop=True)
    return ds


def _paired_differences(summaries, statuses, first_label, confidence_level, z) -> dict:
    """Paired differences to the first variant, over the drops in the statistics of both."""
    used = [np.isin(s, st.IN_STATISTICS) for s in statuses]
    bound = "bound of the paired difference (normal approximation)"
    out = {}
    for name in PER_DROP:
        col = layout.SUMMARY_INDEX[name]
        diff, lo, hi, npair = [], [], [], []
        for k in range(len(summaries)):
            both = used[0] & used[k] & np.isfinite(summaries[0][:, col]) & np.isfinite(summaries[k][:, col])
            d = summaries[k][both, col] - summaries[0][both, col]
            m = d.mean() if d.size else np.nan
            se = d.std(ddof=1) / math.sqrt(d.size) if d.size > 1 else np.nan
            diff.append(m)
            lo.append(m - z * se)
            hi.append(m + z * se)
            npair.append(d.size)
        for suffix, vals, long_name in (
            ("", diff, f"mean paired difference of {name} to variant {first_label} (same drops)"),
            ("_lower", lo, f"lower {confidence_level:.0%} {bound}"),
            ("_upper", hi, f"upper {confidence_level:.0%} {bound}"),
        ):
            out[f"{name}_mean_difference{suffix}"] = (np.array(vals), {"long_name": long_name})
        out[f"{name}_n_paired"] = np.array(npair, dtype=np.int64)
    return out


def _drops(summaries, statuses, inputs, changed) -> dict:
    """Per-drop values and statuses of each variant, the sampled inputs once, the changed slots."""
    out = {
        f"drop_{name}": np.stack([s[:, layout.SUMMARY_INDEX[name]] for s in summaries]) for name in PER_DROP
    }
    out["drop_status"] = np.stack(statuses).astype(np.int8)
    for path, vals in inputs.items():
        out[V.input_variable_name(path)] = xr.DataArray(
            vals,
            dims=("realization",),
            attrs={"long_name": f"sampled {path} (the same for every variant)", "scenario_path": path},
        )
    out["changed_parameters"] = np.array(
        [" ".join(layout.PARAM_NAMES[i] for i in sorted(c)) for c in changed], dtype=object
    )
    return out


# ---------------------------------------------------------------------------
# table and plot
# ---------------------------------------------------------------------------
_CLASS_NAMES = ("0 %", "0-10 %", "10-20 %", "20-75 %", "> 75 %")


def comparison_table(ds: xr.Dataset) -> str:
    """A Markdown table of the statistics, one column per variant."""
    labels = [str(v) for v in ds.variant.values]
    rows = [("drops in statistics", [f"{int(x)}" for x in ds.n_in_statistics.values])]
    counts = ds.status_count.values
    for code in range(counts.shape[1]):
        if code not in st.IN_STATISTICS and counts[:, code].any():
            rows.append((f"drops {st.NAMES[code]} (left out)", [str(int(c)) for c in counts[:, code]]))

    def ci(name, fmt, k):
        m = float(ds[f"{name}_mean"][k])
        return (
            f"{m:{fmt}} [{float(ds[f'{name}_mean_lower'][k]):{fmt}}, "
            f"{float(ds[f'{name}_mean_upper'][k]):{fmt}}]"
        )

    def diff(name, fmt, k):
        if k == 0:
            return "(reference)"
        return (
            f"{float(ds[f'{name}_mean_difference'][k]):+{fmt}} "
            f"[{float(ds[f'{name}_mean_difference_lower'][k]):+{fmt}}, "
            f"{float(ds[f'{name}_mean_difference_upper'][k]):+{fmt}}]"
        )

    def quant(name, fmt, k):
        q = ds[f"{name}_quantile"][k].sel(quantile=[0.05, 0.5, 0.95]).values
        return " / ".join(f"{x:{fmt}}" for x in q)

    nv = len(labels)
    for name, label, fmt in (
        ("burial_volume", "burial by volume, %", ".1f"),
        ("penetration_depth", "penetration, m", ".3f"),
    ):
        rows.append((f"{label}: mean [95 % CI]", [ci(name, fmt, k) for k in range(nv)]))
        rows.append((f"{label}: 5 / 50 / 95 % quantiles", [quant(name, fmt, k) for k in range(nv)]))
        rows.append(
            (f"{label}: paired difference to {labels[0]} [95 % CI]", [diff(name, fmt, k) for k in range(nv)])
        )
    p = ds.burial_class_probability.values
    lo = ds.burial_class_probability_lower.values
    hi = ds.burial_class_probability_upper.values
    for c, cname in enumerate(_CLASS_NAMES):
        rows.append(
            (
                f"P(burial class {cname}) [95 % Wilson]",
                [f"{p[k, c]:.3f} [{lo[k, c]:.3f}, {hi[k, c]:.3f}]" for k in range(nv)],
            )
        )
    if "burial_class_probability_epistemic_lower" in ds:
        elo = ds.burial_class_probability_epistemic_lower.values
        ehi = ds.burial_class_probability_epistemic_upper.values
        for c, cname in enumerate(_CLASS_NAMES):
            rows.append(
                (
                    f"P(burial class {cname}): what the measurements leave open (90 %)",
                    [f"{elo[k, c]:.2f}-{ehi[k, c]:.2f}" for k in range(nv)],
                )
            )
    head = f"| {ds.attrs.get('varied_field', 'variant')} | " + " | ".join(labels) + " |"
    sep = "|---|" + "---|" * nv
    body = [f"| {r} | " + " | ".join(v) + " |" for r, v in rows]
    return "\n".join([head, sep, *body])


def plot_comparison(ds: xr.Dataset, path) -> None:
    """Bar charts: mean burial by volume and penetration (95 % CI) and the class
    probabilities (Wilson 95 %) of every variant."""
    plt = pyplot()

    labels = [str(v) for v in ds.variant.values]
    nv = len(labels)
    x = np.arange(nv)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), gridspec_kw={"width_ratios": [1, 1, 2]})
    for ax, name, ylabel in (
        (axes[0], "burial_volume", "mean burial by volume (%)"),
        (axes[1], "penetration_depth", "mean penetration (m)"),
    ):
        m = ds[f"{name}_mean"].values
        # clipped: a constant output (every drop 100 % buried) has bounds equal to the mean
        # up to rounding, and matplotlib refuses negative error bars
        err = np.clip(
            np.vstack([m - ds[f"{name}_mean_lower"].values, ds[f"{name}_mean_upper"].values - m]), 0.0, None
        )
        ax.bar(x, m, yerr=err, capsize=4, color="C0")
        q = ds[f"{name}_quantile"].sel(quantile=[0.05, 0.95]).values
        ax.plot(np.repeat(x, 2).reshape(-1, 2).T, q.T, "k_", ms=14)
        ax.set_xticks(x, labels, rotation=20)
        ax.set_ylabel(ylabel)
        ax.set_title("mean, 95 % CI (bars: 5/95 % quantiles)", fontsize=9)
    ax = axes[2]
    p = ds.burial_class_probability.values
    lo = ds.burial_class_probability_lower.values
    hi = ds.burial_class_probability_upper.values
    w = 0.8 / nv
    for k in range(nv):
        xc = np.arange(5) + (k - (nv - 1) / 2) * w
        ax.bar(
            xc,
            p[k],
            w,
            yerr=np.clip(np.vstack([p[k] - lo[k], hi[k] - p[k]]), 0.0, None),
            capsize=3,
            label=labels[k],
        )
    ax.set_xticks(np.arange(5), _CLASS_NAMES)
    ax.set_xlabel(f"impact-burial class ({ds.attrs.get('burial_class_basis', 'burial_volume')})")
    ax.set_ylabel("probability (95 % Wilson interval)")
    ax.legend(title=ds.attrs.get("varied_field", ""), fontsize=8)
    fig.suptitle(
        ds.attrs.get("title", "mineburial comparison") + f" ({int(ds.attrs['n_drops'])} "
        "drops, the same sampled inputs)",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


@contextlib.contextmanager
def cli_output(args, inputs):
    """The output of ``compare`` and ``sensitivity``: ``-o`` and ``--plot`` checked before
    computing (not an input, a regular file or nothing, an image type matplotlib writes),
    and ``-o`` locked while computing; yields the :class:`OutputRun` whose parts folder
    keeps the finished chunks (so that an interrupted run resumes) and to commit the
    result to (None without ``-o``: nothing is kept)."""
    run = OutputRun(args.output, inputs, "-o") if args.output else None
    if args.plot:
        check_plot_path(args.plot, args.output, inputs)
    with run if run is not None else contextlib.nullcontext() as out:
        yield out


@contextlib.contextmanager
def cli_client(args):
    """The dask client of ``--scheduler`` (None without it), as ``mineburial run``
    connects it (:func:`mineburial.ensembles.runner.connect_scheduler`), closed at the end."""
    client = runner.connect_scheduler(args.scheduler) if args.scheduler else None
    try:
        yield client
    finally:
        if client is not None:
            client.close()


def run_compare_cli(args) -> int:
    """``mineburial compare``."""
    runner.check_threads(args.threads, "--threads")
    field, values = parse_vary(args.vary)
    lead_time = getattr(args, "lead_time", None)
    inputs = comparison_inputs(
        args.scenario, field, values, n=args.drops, seed=args.seed, lead_time=lead_time
    )
    with cli_output(args, inputs) as out, cli_client(args) as client:
        ds = run_comparison(
            args.scenario,
            field,
            values,
            n=args.drops,
            seed=args.seed,
            threads=args.threads,
            progress=not args.quiet,
            client=client,
            output_run=out,
            lead_time=lead_time,
        )
        print(ds.attrs["title"])
        print(
            f"{int(ds.attrs['n_drops'])} drops, seed {ds.attrs['random_seed']}; the same sampled "
            f"inputs for every variant (checked); {ds.attrs['elapsed_seconds']:.1f} s"
        )
        for name in processes.PROCESSES:  # the statuses of the process compared after
            if ds.attrs.get(f"{name}_status_counts"):
                print(f"{name} stage: {ds.attrs[f'{name}_status_counts']} ({name}_status; docs/{name}.md)")
        print(comparison_table(ds))
        if out is not None:
            out.commit(_for_netcdf(ds))
            print(f"wrote {args.output}")
    if args.plot:
        plot_comparison(ds, args.plot)
        print(f"wrote {args.plot}")
    return 0


def _for_netcdf(ds: xr.Dataset) -> xr.Dataset:
    out = ds.copy()
    for name in ("variant", "changed_parameters"):
        out[name] = out[name].astype(str)
    return out
