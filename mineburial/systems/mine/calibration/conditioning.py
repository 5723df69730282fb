"""Conditioning the coefficient priors on the evidence: importance sampling from the prior
(issue 32; docs/calibration.md, where the method is justified).

1. ``n`` coefficient sets are drawn from the priors with scrambled Sobol' sequences
   (scipy.stats.qmc; one dimension per coefficient and nuisance parameter, mapped through
   each prior's inverse CDF; one sequence per block of the evidence, :func:`draw_sets`), so
   the prior is covered evenly with few sets.
2. Every evidence drop is run under every set (:mod:`mineburial.systems.mine.calibration.cases`).
3. Each row scores each set: a continuous row with a Gaussian of scale
   sqrt(sigma^2 + discrepancy^2) around the measurement; a binary row (a pattern seen)
   with 1 - error_rate when the model's pattern agrees, error_rate when not. A set whose
   drop fails (no quantity) scores zero: it cannot reproduce the experiment.
4. The weights are the products of the row scores (the likelihood; the prior is already in
   the draws): the weighted sets are the posterior. Its effective sample size is
   (sum w)^2 / sum w^2.

The same simulations answer, at no further cost, which rows move which coefficient (each
row's weights alone against the prior) and the leave-one-out predictive checks (the weights
of all rows but one, predicting the held-out measurement with its band).
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

import numpy as np

from mineburial.systems.mine.calibration.priors import EvidenceRow, Prior

#: the predictive band of the leave-one-out checks
PREDICTIVE_BAND = (0.05, 0.95)
#: draws of the predictive mixture from which its band's quantiles are read
PREDICTIVE_DRAWS = 20000
#: a binary row passes when the model gives its observed outcome with at least this predictive
#: probability (the observed outcome lies in the smallest set of outcomes holding 90 %)
BINARY_LEVEL = 0.1


def draw_sets(priors: tuple[Prior, ...], n: int, seed: int, block_of=None) -> dict:
    """``n`` draws of every prior (coefficients and nuisance parameters): ``{path: array (labels
    as str)}``. The priors of each block of the evidence (``block_of(path)``; one block when
    None) are drawn from a scrambled Sobol' sequence of their own, seeded by ``seed`` and the
    block's name, so that a prior added to or removed from one block leaves every other block's
    draws, and so its weights and resampled sets, bit-identical (a sequence over all dimensions
    at once redraws every block: adding the scour-and-settle priors moved the impact block's
    sets and the default ensemble's P(> 75 %) by its Monte Carlo error, 0.265 -> 0.372)."""
    # local import: scipy.stats costs ~0.5 s of start-up; only calibrate draws sets
    from scipy.stats import qmc

    groups: dict = {}
    for p in priors:
        groups.setdefault("" if block_of is None else block_of(p.path), []).append(p)
    out = {}
    for block, members in groups.items():
        stream = seed if block_of is None else np.random.SeedSequence([seed, zlib.crc32(block.encode())])
        rng = np.random.default_rng(stream)
        u = qmc.Sobol(d=len(members), scramble=True, seed=rng).random(n)
        u = np.clip(u, 1e-12, 1.0 - 1e-12)  # the open interval every ppf takes
        out.update({p.path: p.distribution.ppf(u[:, j]) for j, p in enumerate(members)})
    return {p.path: out[p.path] for p in priors}


def log_scores(rows: tuple[EvidenceRow, ...], simulated: np.ndarray) -> np.ndarray:
    """Log scores of the simulated quantities, (sets, rows, grid) like ``simulated`` (NaN: no
    value, -inf)."""
    out = np.empty_like(simulated)
    for j, row in enumerate(rows):
        y = simulated[:, j]
        if row.binary:
            agree = y == row.observed
            out[:, j] = np.where(agree, math.log1p(-row.error_rate), math.log(row.error_rate))
        else:
            s = row.total_sigma
            out[:, j] = -0.5 * ((y - row.observed) / s) ** 2 - math.log(s * math.sqrt(2.0 * math.pi))
        out[:, j][~np.isfinite(y)] = -np.inf
    return out


def log_mean_exp(a: np.ndarray, axis: int) -> np.ndarray:
    """log(mean(exp(a))) along ``axis``, without overflow (all -inf: -inf)."""
    top = np.max(a, axis=axis, keepdims=True)
    safe = np.where(np.isfinite(top), top, 0.0)
    with np.errstate(divide="ignore"):
        out = np.log(np.mean(np.exp(a - safe), axis=axis)) + np.squeeze(safe, axis=axis)
    return out


def case_log_likelihoods(scores: np.ndarray, row_cases: list[str]) -> dict:
    """Per case, the (sets,) log likelihood of its rows with its integrated nuisance parameter
    averaged out over its grid (equal probability a point); a case without one has the same
    value at every grid point, which the average keeps."""
    out = {}
    for case in dict.fromkeys(row_cases):
        cols = [j for j, c in enumerate(row_cases) if c == case]
        out[case] = log_mean_exp(scores[:, cols, :].sum(axis=1), axis=1)
    return out


def normalised(log_w: np.ndarray) -> np.ndarray:
    """Weights summing to 1 from log weights (all -inf: all zero)."""
    top = np.max(log_w)
    if not np.isfinite(top):
        return np.zeros_like(log_w)
    w = np.exp(log_w - top)
    return w / w.sum()


def effective_sample_size(w: np.ndarray) -> float:
    """Kish's effective sample size (sum w)^2 / sum w^2 of importance weights ``w``."""
    s2 = float(np.sum(w**2))
    return float(np.sum(w)) ** 2 / s2 if s2 > 0 else 0.0


def weighted_quantile(values, w, q):
    """Quantile(s) ``q`` of ``values`` under weights ``w`` (inverse of the weighted CDF)."""
    order = np.argsort(values, kind="stable")
    v, c = np.asarray(values, dtype=np.float64)[order], np.cumsum(np.asarray(w)[order])
    c /= c[-1]
    return v[np.minimum(np.searchsorted(c, np.atleast_1d(q), side="left"), v.size - 1)]


def marginal(prior: Prior, values, w) -> dict:
    """A coefficient's summary under weights ``w``: label probabilities for a model choice;
    median and 5-95 % for a number."""
    if prior.categorical:
        return {lab: float(np.sum(w[np.asarray(values) == lab])) for lab in prior.distribution.values}
    lo, med, hi = weighted_quantile(np.asarray(values, dtype=np.float64), w, [0.05, 0.5, 0.95])
    return {"median": float(med), "q05": float(lo), "q95": float(hi)}


def influence(prior: Prior, values, w_row, w_prior) -> float:
    """How far one row's weights move a coefficient: the total-variation distance between
    its prior and single-row distributions (0: not moved; 1: disjoint), on the labels of a
    model choice or on 10 prior-quantile bins of a number."""
    values = np.asarray(values)
    if prior.categorical:
        keys = values
    else:
        edges = weighted_quantile(values.astype(np.float64), w_prior, np.linspace(0.1, 0.9, 9))
        keys = np.searchsorted(edges, values.astype(np.float64), side="right")
    tv = 0.0
    for k in np.unique(keys):
        m = keys == k
        tv += abs(float(np.sum(w_row[m])) - float(np.sum(w_prior[m])))
    return 0.5 * tv


@dataclass
class PredictiveCheck:
    """One leave-one-out predictive check: the row left out, predicted from the others."""

    row: EvidenceRow
    ess: float  # effective sample size of the posterior without the row
    lower: float  # predictive band (continuous rows); nan for binary rows
    upper: float
    probability: float  # predictive probability of the observed outcome (binary rows); nan otherwise
    passed: bool


def predictive_check(row: EvidenceRow, y: np.ndarray, w: np.ndarray, seed: int) -> PredictiveCheck:
    """Predict row ``row`` (simulated ``y`` per set and grid point, flattened) from weights
    ``w`` of the other rows (on the same points): a continuous row's measurement passes
    inside the 5-95 % band of the mixture of N(y_s, sigma^2 + discrepancy^2) over the
    weighted sets; a binary row's observed outcome passes when the model gives it with a
    predictive probability of at least 10 % (it lies in the smallest set of outcomes holding
    90 %). The row's error rate is left out of this probability: with it, the probability of
    any outcome is at least the error rate (0.1), and the check could not fail."""
    ok = np.isfinite(y) & (w > 0)
    ess = effective_sample_size(w)
    if not ok.any():
        return PredictiveCheck(row, ess, math.nan, math.nan, math.nan, False)
    y, w = y[ok], w[ok] / w[ok].sum()
    if row.binary:
        p = float(np.sum(w[y == row.observed]))
        return PredictiveCheck(row, ess, math.nan, math.nan, p, p >= BINARY_LEVEL)
    rng = np.random.default_rng(seed)
    pick = rng.choice(y.size, size=PREDICTIVE_DRAWS, p=w)
    draws = y[pick] + rng.normal(0.0, row.total_sigma, PREDICTIVE_DRAWS)
    lo, hi = np.quantile(draws, PREDICTIVE_BAND)
    return PredictiveCheck(row, ess, float(lo), float(hi), math.nan, bool(lo <= row.observed <= hi))


def systematic_resample(w: np.ndarray, m: int) -> np.ndarray:
    """``m`` indices drawn from weights ``w`` by systematic resampling at the points
    (j + 1/2)/m of their cumulative sum (deterministic, sorted; each index appears within one
    of m times its weight)."""
    cum = np.cumsum(w)
    cum /= cum[-1]
    return np.minimum(np.searchsorted(cum, (np.arange(m) + 0.5) / m, side="right"), cum.size - 1)
