"""The epistemic band of a class probability: its spread across the coefficient sets of a
posterior (issue 32; docs/calibration.md, "Epistemic band").

Each drop of an ensemble that draws its coefficients from a posterior carries the index of
its coefficient set. The predictive probability of a class is the fraction of all drops in
it (the sets are drawn with the posterior weights, so this averages over the posterior).
How much the probability itself depends on the coefficients is the spread of the per-set
probabilities p_j across sets drawn from the posterior. With few drops a set, the observed
per-set fractions add binomial noise to that spread, so the between-set variance is
estimated by the one-way random-effects analysis of variance (method of moments for
unbalanced groups; Searle, Casella & McCulloch 1992, Variance Components, sec. 3.6):

    sigma_b^2 = max(0, (MSB - MSW) / n0),   n0 = (N - sum n_j^2 / N) / (G - 1),

and the band is the central interval of the beta distribution with the predictive
probability as mean and sigma_b^2 as variance. It costs no drop beyond the ensemble's; its
own precision grows with the drops per set (a few hundred sets with ~10 drops each resolve
a between-set standard deviation of ~0.05).
"""

from __future__ import annotations

import numpy as np
from scipy import special

from mineburial.io import variables as V
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as status_codes
from mineburial.systems.mine.statistics import burial_class

#: the central band of the epistemic spread
BAND_LEVEL = 0.90


def between_group_variance(y: np.ndarray, group: np.ndarray) -> float:
    """Between-group variance component of the 0/1 (or real) values ``y`` in groups
    ``group`` (one-way random-effects ANOVA, method of moments); NaN when it cannot be
    separated from the within-group variance (fewer than 2 groups, or no group with 2 values)."""
    y = np.asarray(y, dtype=np.float64)
    _, g = np.unique(np.asarray(group), return_inverse=True)
    n_j = np.bincount(g).astype(np.float64)
    n, k = float(y.size), n_j.size
    if k < 2 or n <= k:
        return float("nan")
    mean_j = np.bincount(g, weights=y) / n_j
    mean = y.mean()
    msb = float(np.sum(n_j * (mean_j - mean) ** 2)) / (k - 1)
    msw = float(np.sum((y - mean_j[g]) ** 2)) / (n - k)
    n0 = (n - float(np.sum(n_j**2)) / n) / (k - 1)
    return max(0.0, (msb - msw) / n0)


def beta_band(mean: float, variance: float, level: float = BAND_LEVEL) -> tuple[float, float]:
    """Central ``level`` interval of the beta distribution with this mean and variance (the
    point ``mean`` when the variance is 0; the variance is capped just below the largest a
    beta of that mean can have, mean (1 - mean))."""
    if not (np.isfinite(mean) and np.isfinite(variance)):
        return float("nan"), float("nan")
    if variance <= 0.0 or mean <= 0.0 or mean >= 1.0:
        return float(mean), float(mean)
    variance = min(variance, 0.999 * mean * (1.0 - mean))
    total = mean * (1.0 - mean) / variance - 1.0
    a, b = mean * total, (1.0 - mean) * total
    tail = 0.5 * (1.0 - level)
    return float(special.betaincinv(a, b, tail)), float(special.betaincinv(a, b, 1.0 - tail))


def class_bands(classes: np.ndarray, group: np.ndarray, level: float = BAND_LEVEL):
    """(lower, upper) of every impact-burial class (5) from per-drop classes and sets."""
    lower, upper = np.full(5, np.nan), np.full(5, np.nan)
    for k in range(5):
        y = (classes == k).astype(np.float64)
        if y.size:
            lower[k], upper[k] = beta_band(float(y.mean()), between_group_variance(y, group), level)
    return lower, upper


#: the band's variables, beside burial_class_probability
NAMES = ("burial_class_probability_epistemic_lower", "burial_class_probability_epistemic_upper")


def band_variables(summary, status, sets, class_basis: str) -> dict:
    """The epistemic band of ``burial_class_probability`` (name -> DataArray) from the per-drop
    ``summary``, ``status`` and coefficient ``sets`` (NaN without drops in the statistics)."""
    used = np.isin(np.asarray(status), status_codes.IN_STATISTICS)
    basis = np.asarray(summary)[used, layout.SUMMARY_INDEX[class_basis]]
    ok = np.isfinite(basis)
    groups = np.asarray(sets)[used][ok]
    bands = class_bands(burial_class(basis[ok]), groups)
    n_sets = np.int64(np.unique(groups).size)
    return {
        name: V.variable(name).data_array(values, band_level=BAND_LEVEL, coefficient_sets=n_sets)
        for name, values in zip(NAMES, bands)
    }


def add_band(ds, summary, status, sets, class_basis: str) -> None:
    """Add the epistemic band (:func:`band_variables`) to ensemble dataset ``ds``."""
    for name, da in band_variables(summary, status, sets, class_basis).items():
        ds[name] = da


def summary_lines(ds, labels) -> list[str]:
    """The printed summary's sentences of the epistemic band (none without one)."""
    if "burial_class_probability_epistemic_lower" not in ds:
        return []
    p = ds["burial_class_probability"].values
    lo = ds["burial_class_probability_epistemic_lower"].values
    hi = ds["burial_class_probability_epistemic_upper"].values
    level = float(ds["burial_class_probability_epistemic_lower"].attrs.get("band_level", BAND_LEVEL))
    lines = [
        f"with what the measurements leave open (the calibrated coefficients, {level:.0%} band across "
        "the posterior's coefficient sets):"
    ]
    for name, pk, a, b in zip(labels, p, lo, hi):
        resolved = np.isfinite(a) and np.isfinite(b)
        band = f"{a:.2f}-{b:.2f}" if resolved else "not resolved (too few drops a set)"
        lines.append(f"  P({name}) = {pk:.2f}; with what the measurements leave open, {band}")
    return lines
