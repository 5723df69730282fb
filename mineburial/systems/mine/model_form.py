"""Model choices of an ensemble: which may be sampled, which are model-form inputs, and how
the run reports them.

A model choice named by a label (the water-column model, the sediment resistance and
strain-rate laws) may be sampled like any other uncertain input, as a ``choice`` among its
labels with optional weights::

    numerics.water_column = {distribution = "choice", values = ["munk_factor", "viscous_crossflow"]}
    sediment.resistance = {distribution = "choice", values = ["bearing", "friction", "delta"],
                           weights = [2, 1, 1]}

The draws follow the seed contract of every input (:mod:`mineburial.ensembles.sampling`:
the uniform of field *k* of drop *i* is a pure function of (seed, i, k), the stream keyed
by the field's name), the uniform mapped through the choice's cumulative weights
(:meth:`~mineburial.ensembles.distributions.Choice.index`); the chosen label's code in
``kernels.mine.layout`` goes into the drop's parameter row. ``numerics.model`` and
``numerics.integrator`` stay fixed per run (they change the defaults of other inputs and
the numerical method, not the physics of one drop's input).

:data:`MODEL_FORM_INPUTS` is the documented set of model-form inputs whose variance share
``mineburial sensitivity`` reports (docs/physics.md, "Model-form uncertainty").
"""

from __future__ import annotations

import numpy as np

from mineburial.ensembles import distributions as dist
from mineburial.kernels.mine import layout

#: model choices that may be sampled as a ``choice`` among labels: path -> the labels, in
#: the order of their codes in the parameter row
CHOICE_FIELDS = {
    "numerics.water_column": layout.WATER_COLUMN_NAMES,
    "sediment.resistance": layout.RESISTANCE_NAMES,
    "sediment.rate_law": layout.RATE_LAW_NAMES,
}

#: the model-form inputs: the model choices above and the water-column model's continuous
#: parameter; their Sobol' indices are grouped as the "model-form share"
MODEL_FORM_INPUTS = (*CHOICE_FIELDS, "numerics.munk_factor")

#: every model choice the run summary and the output attributes name, in that order
REPORTED = (
    "numerics.model",
    "numerics.integrator",
    "numerics.water_column",
    "numerics.munk_factor",
    "sediment.resistance",
    "sediment.rate_law",
)


def check_labels(path: str, d) -> str | None:
    """Why the sampled model choice ``path`` = ``d`` is not allowed, or None."""
    if not isinstance(d, dist.Choice) or not d.categorical:
        return (
            f"{path} can only vary as a 'choice' among {', '.join(CHOICE_FIELDS[path])}, "
            f"got {d.family}" + (" of numbers" if isinstance(d, dist.Choice) else "")
        )
    bad = [v for v in d.values if v not in CHOICE_FIELDS[path]]
    if bad:
        return f"{path}: {', '.join(map(repr, bad))} not one of {', '.join(CHOICE_FIELDS[path])}"
    return None


def codes(path: str, d, index) -> np.ndarray:
    """The parameter-row codes (float64) of the labels of choice ``d`` at indices ``index``."""
    table = np.array([CHOICE_FIELDS[path].index(v) for v in d.values], dtype=np.float64)
    return table[np.asarray(index, dtype=np.int64)]


def describe(d) -> str:
    """A distribution in one line: ``choice of a (p), b (q)`` or ``family(key=value, ...)``."""
    if isinstance(d, dist.Choice):
        return "choice of " + ", ".join(f"{v} ({w:.3g})" for v, w in zip(d.values, d.weights))
    pairs = {k: v for k, v in d.to_dict().items() if k != "distribution"}
    return f"{d.family}(" + ", ".join(f"{k}={v}" for k, v in pairs.items()) + ")"


def _fixed_value(scenario, path: str):
    section, name = path.split(".")
    return getattr(getattr(scenario, section), name)


def choices(spec) -> dict[str, str]:
    """Every model choice of ensemble ``spec`` (:data:`REPORTED`): ``"fixed: <value>"``,
    ``"sampled: <distribution>"`` or ``"from the posterior (<source>): <its marginal>"``."""
    out = {}
    for path in REPORTED:
        if path in spec.random:
            out[path] = "sampled: " + describe(spec.random[path])
        elif path in getattr(spec, "posterior_paths", ()):
            out[path] = f"from the posterior ({spec.posterior.source}): " + _posterior_text(
                spec.posterior, path
            )
        else:
            out[path] = f"fixed: {_fixed_value(spec.base, path)}"
    return out


def _posterior_text(post, path: str) -> str:
    """A coefficient under the posterior's weights: each label's probability for a model
    choice, the median and 5-95 % for a number."""
    col = post.table[:, post.paths.index(path)]
    if path in CHOICE_FIELDS:
        names = CHOICE_FIELDS[path]
        return ", ".join(
            f"{names[k]} ({float(post.weights[col == k].sum()):.3g})" for k in np.unique(col).astype(int)
        )
    order = np.argsort(col, kind="stable")
    cum = np.cumsum(post.weights[order])
    lo, med, hi = (
        col[order][min(np.searchsorted(cum, q * cum[-1]), col.size - 1)] for q in (0.05, 0.5, 0.95)
    )
    return f"median {med:.3g}, 5-95 % {lo:.3g}-{hi:.3g}"


def attribute_name(path: str) -> str:
    """The global attribute of model choice ``path``: ``model_choice_<section>_<name>``."""
    return "model_choice_" + path.replace(".", "_")


def attributes(spec) -> dict[str, str]:
    """Global attributes naming every model choice and whether it was fixed or sampled."""
    return {attribute_name(path): text for path, text in choices(spec).items()}


def summary_lines(ds) -> list[str]:
    """The printed summary's lines for the model choices recorded in ``ds``'s attributes."""
    found = [(p, ds.attrs[attribute_name(p)]) for p in REPORTED if attribute_name(p) in ds.attrs]
    if not found:
        return []
    return ["model choices:"] + [f"  {path}: {text}" for path, text in found]
