"""``mineburial sensitivity``: Sobol' indices of penetration, burial and the burial-class
indicators for every random input, and the share of the model-form inputs.

Variance-based global sensitivity analysis (Sobol' 2001, Math. Comput. Simul. 55,
271-280) with :func:`scipy.stats.sobol_indices`: the Saltelli et al. (2010, Comput.
Phys. Commun. 181, 259-270) estimator of the first-order indices S_i and the Jansen
(1999) estimator of the total indices S_Ti, on a scrambled Sobol' design of two
n-point matrices A and B and the d matrices AB_i (A with column i from B):
n (d + 2) drops. The design's uniforms are mapped through each input's own
distribution (``ppf`` of :mod:`mineburial.ensembles.distributions`; a choice among
labels -- a sediment class or core file -- by its index), packed into the scenario
(:class:`DesignSpec`: the design's points in place of the sampled inputs) and run as one
ensemble on the run driver (:func:`mineburial.ensembles.runner.run_jobs`: threads, a dask
cluster, resume).

Model-form share: the inputs that are model choices (the documented set
:data:`mineburial.systems.mine.model_form.MODEL_FORM_INPUTS`: the water-column model, its
``munk_factor``, the sediment resistance and strain-rate laws) are grouped, and the sums of
their first-order and total indices bound the share of each output's variance that comes
from model form (:func:`model_form_share`). A choice among labels enters the design like
any input: the design's uniform mapped through the choice's cumulative weights to an index,
as the ensemble's sampling does.

Why scipy and not SALib: scipy is already a dependency and well kept; its
``sobol_indices`` takes a vectorised function (one call for the whole design, which
the batch driver needs), the input distributions directly, and accepts precomputed
evaluations (``func={"f_A", "f_B", "f_AB"}``), which the bootstrap below uses. SALib
would add a dependency (and pandas) for the same estimators.

Confidence intervals: percentile bootstrap (:func:`scipy.stats.bootstrap`, 999
resamples of the n rows of the design, seeded: the same seed gives the same
intervals). scipy's own ``SobolResult.bootstrap`` draws from an unseeded generator,
so its intervals would change from run to run.

Burial after a post-impact process (issue 20; scour is the one there is,
:mod:`mineburial.systems.mine.processes.registry`): with a ``[scour]`` section the outputs are the burial
measures of the post-impact stage at **one lead time** (:func:`at_lead_time`: ``--lead-time DAYS``,
default the section's last lead time; docs/validation.md), and the stage's sampled inputs
(``scour.hs_scale``, ``scour.beq_a``, ...) are inputs of the design beside the impact's. The
stage runs inside every chunk of the design (the run driver's chunks carry it), so threads, a
dask cluster and resume behave as without it. A drop whose stage gives no value (its impact
ended outside the statistics, or the stage refused its parameters or forcing) keeps its impact
measures -- burial never decreases in the stage -- and is counted in ``scour_status_counts``.

Drops that end outside the burial statistics (``time_limit``, ``floated``, ...) still
have a penetration and burial at their last state; they are kept (a Sobol' design
cannot drop points) and counted in the attribute ``n_not_in_statistics``.
"""

from __future__ import annotations

import dataclasses
import json
import time

import numpy as np
import scipy
from scipy import stats

from mineburial._deferred import xarray as xr
from mineburial.analyses.compare import cli_client, cli_output
from mineburial.ensembles import engine, runner
from mineburial.errors import ScenarioError
from mineburial.io import variables as V
from mineburial.io.dataset import build
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as st
from mineburial.resources import memory_refusal
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import model_form
from mineburial.systems.mine.calibration import posterior
from mineburial.systems.mine.figures import pyplot, save_figure
from mineburial.systems.mine.processes import registry as processes
from mineburial.systems.mine.processes.registry import at_lead_time
from mineburial.systems.mine.statistics import burial_class

__all__ = [
    "sobol_analysis",
    "run_sensitivity",
    "sensitivity_table",
    "plot_sensitivity",
    "ranking",
    "run_sensitivity_cli",
    "OUTPUTS",
    "CLASS_OUTPUTS",
    "model_form_share",
    "model_form_lines",
    "at_lead_time",
]

#: Outputs whose indices are computed and printed per input.
OUTPUTS = ("penetration_depth", "burial_volume")
#: The impact-burial class indicators (1 where a drop falls in the class, by the scenario's
#: class basis): the variance of class k's indicator is p_k (1 - p_k), so their indices say
#: which inputs the class probabilities depend on; written, and summarised by their
#: model-form share.
CLASS_OUTPUTS = tuple(f"class_{m}" for m in V.BURIAL_CLASS_MEANINGS)
_TINY = 2.0**-53


def _constant(values: np.ndarray) -> bool:
    """Whether an output is constant over the design: its spread is within 1e-12 of its
    magnitude (rounding), so its variance, the denominator of every index, is 0."""
    return bool(np.ptp(values) <= 1e-12 * np.max(np.abs(values)))


class _OnUnitInterval:
    """The ``ppf`` scipy needs, for one input: uniforms (clipped into the open interval)
    through the distribution's ``ppf``, or to the index of a choice among labels."""

    def __init__(self, distribution):
        self.distribution = distribution

    def ppf(self, u):
        u = np.clip(np.asarray(u, dtype=np.float64), _TINY, 1.0 - _TINY)
        if getattr(self.distribution, "categorical", False):
            return self.distribution.index(u).astype(np.float64)
        return np.asarray(self.distribution.ppf(u), dtype=np.float64)


def _design(dists, n: int, seed: int) -> list:
    """The points :func:`scipy.stats.sobol_indices` evaluates for ``seed``, in its order:
    A, B and the d matrices AB_i side by side, each (d, points).

    scipy draws its design inside ``sobol_indices`` and hands it to the function in three
    calls; this runs it once on placeholder values (two outputs, the point's index: any
    outputs with a variance; with one output of one input scipy's arrays lose a dimension)
    to record them. :func:`sobol_analysis` then evaluates all the points at once
    and replays the evaluations to a second call with the same seed, which checks that
    scipy drew the same points."""
    points = []

    def record(x):
        points.append(np.array(x, dtype=np.float64, copy=True))
        return np.tile(np.arange(x.shape[1], dtype=np.float64), (2, 1))

    stats.sobol_indices(func=record, n=n, dists=dists, rng=np.random.default_rng(seed))
    return points


def sobol_analysis(
    func,
    inputs: dict,
    n: int,
    seed: int,
    outputs=("y",),
    *,
    confidence_level: float = 0.95,
    n_resamples: int = 999,
) -> xr.Dataset:
    """First-order and total Sobol' indices of ``func`` with bootstrap intervals.

    ``inputs`` maps each input's name to a distribution (an object with ``ppf``, e.g.
    a :class:`mineburial.ensembles.distributions.Distribution`); ``func`` takes a dict
    name -> values (m,) and returns an array (len(outputs), m). ``n`` (a power of two)
    is the base sample size: ``func`` is called once, with the n (d + 2) points of the
    whole design (:func:`_design`), so that they run as one ensemble. Returns a Dataset
    over ``(output, input)``.
    """
    names = list(inputs)
    d = len(names)
    if d < 1:
        raise ValueError("a sensitivity analysis needs at least one random input")
    if n < 2 or n & (n - 1):
        raise ValueError(f"n = {n} must be a power of two >= 2 (the Sobol' design)")
    dists = [_OnUnitInterval(inputs[k]) for k in names]
    points = _design(dists, n, seed)
    y = _evaluate(func, names, points, len(outputs))
    # the evaluations, as scipy arranged them: f(A), f(B), then the d pages AB_i
    f_a, f_b, f_ab = np.split(y, np.cumsum([p.shape[1] for p in points])[:-1], axis=1)
    replay = iter(zip(points, (f_a, f_b, f_ab)))

    def evaluated(xs):
        p, f = next(replay)
        if not np.array_equal(xs, p):  # pragma: no cover
            raise RuntimeError("scipy.stats.sobol_indices drew another design from the same seed")
        return f.copy()  # scipy centres its arrays in place

    res = stats.sobol_indices(func=evaluated, n=n, dists=dists, rng=np.random.default_rng(seed))
    f_ab = np.moveaxis(f_ab.reshape((-1, n, d)), -1, 0)

    def indices(idx):
        r = stats.sobol_indices(
            func={"f_A": f_a[:, idx], "f_B": f_b[:, idx], "f_AB": f_ab[..., idx]}, n=len(idx)
        )
        shape = (len(outputs), d)
        return np.stack([np.reshape(r.first_order, shape), np.reshape(r.total_order, shape)])

    point = indices(np.arange(n))
    # the same estimates to rounding (the summation order may differ)
    same_first = np.allclose(point[0], np.reshape(res.first_order, point[0].shape), rtol=1e-9, atol=1e-12)
    same_total = np.allclose(point[1], np.reshape(res.total_order, point[1].shape), rtol=1e-9, atol=1e-12)
    if not (same_first and same_total):  # pragma: no cover
        raise RuntimeError(
            "scipy.stats.sobol_indices arranged its evaluations differently from what the bootstrap assumes"
        )
    lo, hi = _bootstrap_intervals(indices, n, seed, confidence_level, n_resamples)
    constant = np.array(
        [_constant(np.concatenate([f_a[k], f_b[k], f_ab[:, k].ravel()])) for k in range(len(outputs))]
    )
    for arr in (point[0], point[1], lo[0], lo[1], hi[0], hi[1]):
        arr[constant] = np.nan  # scipy writes 0 for 0 / 0: the index is undefined, not zero
    return _indices_dataset(
        point,
        lo,
        hi,
        constant,
        np.concatenate([f_a, f_b], axis=1),
        outputs,
        names,
        n,
        seed,
        confidence_level,
        n_resamples,
    )


def _bootstrap_intervals(indices, n, seed, confidence_level, n_resamples):
    """(lower, upper) percentile-bootstrap bounds of ``indices`` over resampled design rows."""
    boot = stats.bootstrap(
        (np.arange(n),),
        lambda idx: indices(idx),
        vectorized=False,
        n_resamples=n_resamples,
        confidence_level=confidence_level,
        method="percentile",
        rng=np.random.default_rng([seed, 1]),
    )
    return boot.confidence_interval


def _evaluate(func, names, points, n_outputs):
    """``func`` on the whole design at once, checked: (n_outputs, points) and all finite."""
    x = np.concatenate(points, axis=1)
    y = np.atleast_2d(np.asarray(func({k: x[i] for i, k in enumerate(names)}), dtype=np.float64))
    if y.shape != (n_outputs, x.shape[1]):
        raise ValueError(f"func returned shape {y.shape}, expected ({n_outputs}, {x.shape[1]})")
    if not np.all(np.isfinite(y)):
        raise ValueError(
            f"func returned {int(np.count_nonzero(~np.isfinite(y)))} "
            "non-finite values; Sobol' indices need every point"
        )
    return y


def _indices_dataset(point, lo, hi, constant, f_a_b, outputs, names, n, seed, confidence_level, n_resamples):
    """The Sobol' indices, their bootstrap bounds and status as a ``kind="sensitivity"`` Dataset.

    ``f_a_b`` holds the evaluations f(A) and f(B) side by side (the output variance).
    """
    d = len(names)
    ci = {
        "confidence_level": confidence_level,
        "interval_method": f"percentile bootstrap, {n_resamples} resamples of the design rows",
    }
    data = {
        "first_order": point[0],
        "first_order_lower": (lo[0], ci),
        "first_order_upper": (hi[0], ci),
        "total_order": point[1],
        "total_order_lower": (lo[1], ci),
        "total_order_upper": (hi[1], ci),
        "output_variance": np.var(f_a_b, axis=1),
        "index_status": constant,
    }
    coords = {"output": np.array(outputs, dtype=object), "input": np.array(names, dtype=object)}
    attrs = {
        "base_sample_size": np.int64(n),
        "n_evaluations": np.int64(n * (d + 2)),
        "design_seed": str(seed),
        "confidence_level": confidence_level,
        "method": "scipy.stats.sobol_indices (saltelli_2010) on a scrambled Sobol' "
        "design; percentile bootstrap intervals",
    }
    return build(data, coords, attrs, kind="sensitivity")


#: the last design made by :func:`design_points` in this process, as ``(key, points)``
_LAST_DESIGN: list = [None]


def design_points(random: dict, n: int, seed: int) -> dict:
    """The points of the Sobol' design of base size ``n`` over the inputs ``random`` drawn
    with ``seed`` (:func:`_design`: A, B, then the d matrices AB_i, n (d + 2) points), as an
    ensemble's inputs: each input's values at every point (the index of a choice among
    labels as an integer). The last design is kept, so the chunks of a run in one process
    (a dask worker) make it once (~0.1 s for n = 4096 over 9 inputs)."""
    key = (tuple((k, repr(d)) for k, d in random.items()), int(n), int(seed))
    last = _LAST_DESIGN[0]
    if last is not None and last[0] == key:
        return last[1]
    x = np.concatenate(_design([_OnUnitInterval(d) for d in random.values()], n, seed), axis=1)
    points = {
        k: x[i].astype(np.int64) if getattr(d, "categorical", False) else x[i]
        for i, (k, d) in enumerate(random.items())
    }
    _LAST_DESIGN[0] = (key, points)
    return points


@dataclasses.dataclass(frozen=True)
class DesignSpec(mine.EnsembleSpec):
    """An ensemble whose drops are the points of the Sobol' design of base size ``base_n``
    (:func:`design_points`) instead of draws. Its chunks run on the run driver like any
    ensemble's; it carries the design's recipe, not its points (a dask task of a large
    design stays small: the worker makes the points), and its run identity names the
    recipe and scipy's version, which draws the points (a resumed run reuses only chunks
    of the same design)."""

    base_n: int = 0

    @classmethod
    def of(cls, spec: mine.EnsembleSpec, base_n: int) -> DesignSpec:
        fields = {f.name: getattr(spec, f.name) for f in dataclasses.fields(mine.EnsembleSpec)}
        n = base_n * (len(spec.random) + 2)
        return cls(**{**fields, "n": n, "per_drop": False}, base_n=base_n)

    def sampled_inputs(self, start: int, stop: int) -> dict:
        points = design_points(self.random, self.base_n, self.seed)
        return {path: values[start:stop] for path, values in points.items()}

    def identity_items(self) -> list:
        recipe = f"Sobol' design of base size {self.base_n} by scipy {scipy.__version__}"
        return super().identity_items() + [("design", recipe)]


def run_sensitivity(
    scenario=None,
    n: int = 256,
    seed: int | None = None,
    *,
    lead_time: float | None = None,
    threads: int | None = None,
    progress: bool = False,
    client=None,
    output_run=None,
) -> xr.Dataset:
    """Sobol' indices of penetration, burial by volume and the burial-class indicators
    (:data:`CLASS_OUTPUTS`), with the model-form share (:func:`model_form_share`), for
    every random input of an ensemble scenario (see the module docstring); ``n (d + 2)`` drops are run.
    With a ``[scour]`` section the outputs are those after the stage at ``lead_time`` days
    (:func:`at_lead_time`).

    The drops of the design are one ensemble of the run driver
    (:func:`mineburial.ensembles.runner.run_jobs`: ``threads`` numba threads here, or the
    cluster of a dask ``client``); with ``output_run`` (an
    :class:`~mineburial.ensembles.store.OutputRun`) its finished chunks are kept in the
    parts folder, so an interrupted analysis resumes."""
    spec = at_lead_time(engine.load_ensemble(scenario, seed=seed), lead_time)
    if not spec.random:
        raise engine.EnsembleError("the scenario has no random input: nothing to analyse")
    threads = runner.check_threads(threads)
    names = list(spec.random)
    total = n * (len(names) + 2)
    refusal = memory_refusal(
        memory_needed(n, len(names), spec),
        f"-n {n}: the Sobol' design of {total} drops over {len(names)} random inputs",
        "give a smaller -n (a power of two)",
    )
    if refusal:
        raise engine.EnsembleError(refusal)
    counts = np.zeros(len(st.NAMES), dtype=np.int64)
    after = processes.burial_process(spec)  # the post-impact process whose burial is analysed
    process_counts = [""]  # its statuses' counts (the process's status_text)
    no_value = [0]  # drops in the burial statistics without a value of the process

    def model(values):
        points = DesignSpec.of(spec, n)
        design = design_points(spec.random, n, spec.seed)
        if any(not np.array_equal(values[k], design[k]) for k in names):  # pragma: no cover
            raise RuntimeError("the design's points are not those of the Sobol' analysis")
        store = None if output_run is None else output_run.store(points)
        job = runner.Job(None, points, store)
        ((_, chunks),) = runner.run_jobs([job], client=client, progress=progress, threads=threads)
        summary = np.concatenate([r["summary"] for r in chunks])
        status = np.concatenate([r["status"] for r in chunks])
        counts[:] = np.bincount(status.astype(np.int64), minlength=len(st.NAMES))
        if after is not None:
            process, own = after
            process_counts[0] = process.status_text(chunks)
            lacking = process.lacks_value(own, chunks)
            no_value[0] = int(np.sum(np.isin(status, st.IN_STATISTICS) & lacking))
            summary = process.burial_after(own, summary, chunks, missing="impact")  # Sobol' needs every point
        return _outputs(summary, spec.class_basis)

    t0 = time.monotonic()
    ds = model_form_share(sobol_analysis(model, spec.random, n, spec.seed, OUTPUTS + CLASS_OUTPUTS))
    left = int(sum(c for k, c in enumerate(counts) if k not in st.IN_STATISTICS))
    warning = failure_warning(left, total, counts)
    if no_value[0]:  # their burial at the lead time is the impact's (issue 35)
        warning = (warning + "; " if warning else "warning: ") + (
            f"{no_value[0]} of {total} drops have no value of the {after[0].section} stage at the lead time "
            f"({after[0].section} status not ok): their burial in the indices is the impact's"
        )
    if warning:
        ds.attrs["warning"] = warning
    title = f"mineburial Sobol' sensitivity: {spec.base.mine.name}"
    if after is not None:
        lead = processes.analysed_lead_time(spec)
        title += f", burial after {after[0].section} at lead time {lead:g} d"
        ds.attrs["lead_time_days"] = lead
        ds.attrs[f"{after[0].section}_status_counts"] = process_counts[0]
    ds.attrs.update(
        {
            "title": title,
            "scenario": json.dumps(spec.resolved(), default=str),
            "random_seed": str(spec.seed),
            "n_not_in_statistics": np.int64(left),
            "status_counts": ", ".join(f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c),
            "elapsed_seconds": time.monotonic() - t0,
        }
    )
    return ds


def _outputs(summary: np.ndarray, class_basis: str) -> np.ndarray:
    """The analysed outputs of each drop, (len(OUTPUTS) + len(CLASS_OUTPUTS), drops): its
    :data:`OUTPUTS` and the indicators of its burial class (by ``class_basis``)."""
    classes = burial_class(summary[:, layout.SUMMARY_INDEX[class_basis]])
    indicators = classes == np.arange(len(CLASS_OUTPUTS))[:, None]
    return np.vstack([summary[:, [layout.SUMMARY_INDEX[o] for o in OUTPUTS]].T, indicators])


def memory_needed(n: int, d: int, spec=None, n_resamples: int = 999) -> float:
    """Bytes an analysis of base sample size ``n`` over ``d`` inputs needs at its peak.

    Measured with :mod:`tracemalloc` on :func:`sobol_analysis` (two outputs; d = 3 and 16,
    n = 2048, 99 and 999 resamples: peaks of 2279 and 2533 (999), 272 and 703 (99) times
    8 n bytes; with the seven outputs of :func:`run_sensitivity`, 999 resamples: 2220 (d = 3)
    and 3128 (d = 16) times 8 n bytes). The bootstrap's resampled row indices (``n_resamples``
    x n integers and their copies) dominate, then scipy's d x d x n matrix AB (and its reshaped copy); the
    bound 8 n (2.3 n_resamples + 2 d**2 + 20 d + 60) lies above every measured peak. With
    ``spec``, the per-drop values of the n (d + 2) drops of the design, kept until the
    indices are computed (:func:`mineburial.ensembles.runner.memory_needed`)."""
    need = 8.0 * n * (2.3 * n_resamples + 2.0 * d * d + 20.0 * d + 60.0)
    if spec is not None:
        need += runner.memory_needed(dataclasses.replace(spec, n=n * (d + 2)))
    return need


#: share of the drops outside the burial statistics (time limit, floated, failures) from
#: which ``sensitivity`` warns: their penetration and burial are those of an unfinished drop
FAILED_SHARE_WARNING = 0.10


def failure_warning(left: int, total: int, counts) -> str | None:
    """One warning line when ``left`` of ``total`` drops (at least
    :data:`FAILED_SHARE_WARNING` of them) ended outside the burial statistics; else None."""
    if total <= 0 or left < FAILED_SHARE_WARNING * total:
        return None
    which = ", ".join(
        f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c and k not in st.IN_STATISTICS
    )
    share = "every drop" if left == total else f"{left} of {total} drops ({100.0 * left / total:.0f} %)"
    return (
        f"warning: {share} ended outside the burial statistics ({which}): the indices describe "
        f"where unfinished drops stopped, not their burial; lengthen numerics.t_max / t_max_fall "
        f"or check the scenario"
    )


def model_form_share(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with the share of each output's variance that comes from the model-form inputs
    (:data:`mineburial.systems.mine.model_form.MODEL_FORM_INPUTS` among ``ds``'s inputs).

    Two bounds of the group's share from the single-input indices, for any model (Sobol'
    2001; Saltelli et al. 2008, *Global Sensitivity Analysis: The Primer*, sec. 4.4):
    ``model_form_first_order`` = sum of the group's S_i, at most its closed first-order
    index (the share the group explains alone, interactions among its members left out), and
    ``model_form_total_order`` = sum of the group's S_Ti, at least the group's total index
    (all the variance in which a model-form input takes part). Both are 0 without model-form
    inputs and 1 when they are the only inputs of an additive model."""
    group = [str(k) for k in ds.input.values if str(k) in model_form.MODEL_FORM_INPUTS]
    out = ds.copy()
    members = {"model_form_inputs": ", ".join(group) or "none"}
    for key in ("first_order", "total_order"):  # long names: the registry's sensitivity family
        share = (
            ds[key].sel(input=group).sum("input", skipna=False) if group else 0.0 * abs(ds[key].isel(input=0))
        )
        name = f"model_form_{key}"
        out[name] = share.drop_vars("input", errors="ignore").assign_attrs(
            **V.family("sensitivity")[name].cf_attrs(**members)
        )
    return out


def model_form_lines(ds: xr.Dataset) -> list[str]:
    """The printed model-form share of each output (:func:`model_form_share`)."""
    if "model_form_first_order" not in ds:
        return []
    who = ds["model_form_first_order"].attrs.get("model_form_inputs", "none")
    lines = [f"model-form share of the variance (model-form inputs: {who}):"]
    for out in ds.output.values:
        first = float(ds["model_form_first_order"].sel(output=out))
        total = float(ds["model_form_total_order"].sel(output=out))
        if np.isnan(first) and np.isnan(total):
            lines.append(f"  {out}: undefined (output constant)")
        else:
            lines.append(f"  {out}: sum of S_i {first:.3f}, sum of S_Ti {total:.3f}")
    return lines


def calibrated_share_lines(ds: xr.Dataset) -> list[str]:
    """The printed share of the variance of the coefficients drawn from a posterior: the
    Sobol' indices of their one input, the drop's coefficient set (docs/calibration.md)."""
    if posterior.SET_INPUT not in ds.input.values:
        return []
    lines = [f"calibrated coefficients' share of the variance (input {posterior.SET_INPUT}):"]
    for out in ds.output.values:
        first = float(ds["first_order"].sel(output=out, input=posterior.SET_INPUT))
        total = float(ds["total_order"].sel(output=out, input=posterior.SET_INPUT))
        if np.isnan(first) and np.isnan(total):
            lines.append(f"  {out}: undefined (output constant)")
        else:
            lines.append(f"  {out}: S_i {first:.3f}, S_Ti {total:.3f}")
    return lines


def ranking(ds: xr.Dataset, output: str, index: str = "total_order") -> list[str]:
    """Inputs ordered by decreasing index of ``output``."""
    v = ds[index].sel(output=output).values
    return [str(ds.input.values[i]) for i in np.argsort(-v, kind="stable")]


def sensitivity_table(ds: xr.Dataset) -> str:
    """Markdown table: S_i and S_Ti with their intervals, inputs by decreasing S_Ti."""
    lines = []
    for out in ds.output.values:
        lines.append(f"\n{out} (variance {float(ds.output_variance.sel(output=out)):.4g}):\n")
        lines.append("| input | first order S_i [95 % CI] | total S_Ti [95 % CI] |")
        lines.append("|---|---|---|")
        undefined = "index_status" in ds and int(ds.index_status.sel(output=out)) == 1
        for name in ranking(ds, str(out)):
            if undefined:
                lines.append(f"| {name} | undefined (output constant) | undefined (output constant) |")
                continue
            r = ds.sel(output=out, input=name)
            lines.append(
                f"| {name} | {float(r.first_order):.3f} [{float(r.first_order_lower):.3f}, "
                f"{float(r.first_order_upper):.3f}] | {float(r.total_order):.3f} "
                f"[{float(r.total_order_lower):.3f}, {float(r.total_order_upper):.3f}] |"
            )
    return "\n".join(lines).lstrip("\n")


def plot_sensitivity(ds: xr.Dataset, path) -> None:
    """Bar chart of S_i and S_Ti with their bootstrap intervals, one panel per output."""
    plt = pyplot()

    outs = [str(o) for o in ds.output.values]
    fig, axes = plt.subplots(1, len(outs), figsize=(6 * len(outs), 4.5), squeeze=False)
    for ax, out in zip(axes[0], outs):
        order = ranking(ds, out)
        r = ds.sel(output=out, input=order)
        x = np.arange(len(order))
        for j, (key, label) in enumerate((("first_order", "first order S_i"), ("total_order", "total S_Ti"))):
            v = r[key].values
            err = np.vstack([v - r[f"{key}_lower"].values, r[f"{key}_upper"].values - v])
            ax.bar(x + (j - 0.5) * 0.4, v, 0.4, yerr=np.clip(err, 0, None), capsize=3, label=label)
        ax.set_xticks(x, order, rotation=35, ha="right", fontsize=8)
        ax.set_ylabel("Sobol' index (95 % bootstrap interval)")
        ax.set_title(out)
        ax.axhline(0, color="k", lw=0.5)
        ax.legend()
    fig.suptitle(
        f"{ds.attrs.get('title', 'Sobol indices')} (n = {int(ds.attrs['base_sample_size'])}, "
        f"{int(ds.attrs['n_evaluations'])} drops)",
        fontsize=10,
    )
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def run_sensitivity_cli(args) -> int:
    """``mineburial sensitivity``."""
    runner.check_threads(args.threads, "--threads")
    n = 256 if args.drops is None else args.drops
    if n < 2 or n & (n - 1):
        raise ScenarioError(
            f"-n {n}: the base sample size must be a power of two >= 2 "
            f"(the Sobol' design); n (d + 2) drops are run"
        )
    spec = engine.load_ensemble(args.scenario, seed=args.seed)
    at_lead_time(spec, args.lead_time)  # a lead time outside the forcing: one line before -o is opened
    inputs = runner.input_paths(args.scenario, spec)
    with cli_output(args, inputs) as out, cli_client(args) as client:  # -o, --plot checked first
        ds = run_sensitivity(
            args.scenario,
            n,
            args.seed,
            lead_time=args.lead_time,
            threads=args.threads,
            progress=not args.quiet,
            client=client,
            output_run=out,
        )
        print(ds.attrs["title"])
        print(
            f"n = {n}, {int(ds.attrs['n_evaluations'])} drops ({ds.attrs['status_counts']}), "
            f"seed {ds.attrs['random_seed']}, {ds.attrs['elapsed_seconds']:.1f} s"
        )
        if ds.attrs.get("warning"):
            print(ds.attrs["warning"])
        for name in processes.PROCESSES:  # the statuses of the process analysed after
            if ds.attrs.get(f"{name}_status_counts"):
                print(f"{name} stage: {ds.attrs[f'{name}_status_counts']} ({name}_status; docs/{name}.md)")
        print(sensitivity_table(ds.sel(output=list(OUTPUTS))))
        print("\n".join(model_form_lines(ds) + calibrated_share_lines(ds)))
        if out is not None:
            written = ds.copy()
            written["output"] = written["output"].astype(str)
            written["input"] = written["input"].astype(str)
            out.commit(written)
            print(f"wrote {args.output}")
    if args.plot:
        plot_sensitivity(ds.sel(output=list(OUTPUTS)), args.plot)
        print(f"wrote {args.plot}")
    return 0
