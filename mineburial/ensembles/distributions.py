"""Probability distributions of scenario inputs.

Every numeric input of a scenario may be a fixed value or a distribution,
written in the TOML file as an inline table that names its family::

    mass = {distribution = "normal", mean = 500.0, std = 25.0}
    sediment.class = {distribution = "choice", values = ["clay", "sand"], weights = [3, 1]}

This module turns such a table into a frozen dataclass (``parse_value``) with
validation that names the field, the bad value and the allowed range, and
gives every distribution a vectorised inverse CDF ``ppf(u)`` that maps
uniform numbers ``u`` in (0, 1) onto draws. The uniforms themselves come from
:mod:`mineburial.ensembles.sampling`, so that every draw of drop *i* is a pure
function of (seed, i) (see ``docs/notes/sampling.md``).

Families and parameterisations (scipy.stats names in brackets):

``uniform(low, high)``                  [``uniform(loc=low, scale=high-low)``]
``normal(mean, std)``                   [``norm(loc=mean, scale=std)``]
``truncated_normal(mean, std, low, high)`` -- the normal(mean, std) restricted
    to [low, high]; ``mean``/``std`` are those of the *parent* normal, not of the
    truncated variable. A missing bound is infinite.
                                        [``truncnorm((low-mean)/std, (high-mean)/std, mean, std)``]
``lognormal(median, sigma)`` -- ln X ~ normal(ln median, sigma), i.e. ``median``
    is the median of X and ``sigma`` the standard deviation of ln X. The
    (mean, std) of X are *not* accepted; the error message gives the
    conversion.                         [``lognorm(s=sigma, scale=median)``]
``choice(values, weights=None)`` -- one of ``values`` (all numbers or all
    strings) with probabilities proportional to ``weights`` (equal if omitted).
``empirical(values=[...])`` or ``empirical(file="...", column="...")`` --
    resample the given numbers with equal weight (inverse empirical CDF).

Every family also gives ``probability_outside(low, high)``, the probability of a draw
outside an interval, with which :func:`mineburial.systems.mine.config.check_distribution` checks a
distribution against its field's allowed range when an ensemble scenario is loaded.

Only :mod:`scipy.special` is used, never :mod:`scipy.stats`: importing scipy.stats
costs ~0.5 s of the start-up of every run. The truncated normal's inverse CDF is
written out here (:func:`_truncated_normal_quantile`) with the same floating-point
operations as scipy 1.17's ``truncnorm.ppf``, so its draws are bit for bit those of
``truncnorm((low-mean)/std, (high-mean)/std, mean, std).ppf`` (tested), and from now on
depend only on scipy.special's ``log_ndtr``, ``ndtr``, ``log1p``, ``logsumexp`` and
``ndtri_exp``, not on how scipy.stats arranges them.
"""

from __future__ import annotations

import csv
import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from scipy import special

from mineburial.errors import ScenarioError
from mineburial.io import inputs

__all__ = [
    "DistributionError",
    "Distribution",
    "Uniform",
    "Normal",
    "TruncatedNormal",
    "LogNormal",
    "Choice",
    "Empirical",
    "DISTRIBUTIONS",
    "from_dict",
    "parse_value",
    "is_distribution_table",
]


class DistributionError(ScenarioError):
    """A scenario value or distribution table is invalid.

    The message always starts with the dotted field path, e.g.
    ``"mine.mass: std = -1 must be > 0"``. A :class:`ScenarioError` (so a
    ``ValueError``): the command line reports it as a one-line error.
    """


# ---------------------------------------------------------------------------
# validation helpers
# ---------------------------------------------------------------------------


def _nearest(name: str, options) -> str:
    close = difflib.get_close_matches(name, list(options), n=1, cutoff=0.5)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _number(d: Mapping, key: str, field: str, family: str, *, default=None, allow_inf: bool = False) -> float:
    """Read ``d[key]`` as a float; reject bools, strings, NaN (and inf unless allowed)."""
    if key not in d:
        if default is not None:
            return default
        raise DistributionError(f"{field}: {family} distribution needs '{key}' (missing)")
    raw = d[key]
    if isinstance(raw, bool) or not isinstance(raw, (int, float, np.integer, np.floating)):
        raise DistributionError(f"{field}: {key} = {raw!r} must be a number, got {type(raw).__name__}")
    val = float(raw)
    if math.isnan(val) or (math.isinf(val) and not allow_inf):
        raise DistributionError(f"{field}: {key} = {raw} must be a finite number")
    return val


def _check_keys(d: Mapping, field: str, family: str, allowed: tuple[str, ...]) -> None:
    unknown = [key for key in d if key != "distribution" and key not in allowed]
    if len(unknown) == 1:
        key = unknown[0]
        raise DistributionError(
            f"{field}: unknown parameter {key!r} for the {family} distribution; "
            f"allowed parameters are {', '.join(allowed)}{_nearest(key, allowed)}"
        )
    if unknown:
        names = ", ".join(f"{key!r}{_nearest(key, allowed)}" for key in unknown)
        raise DistributionError(
            f"{field}: unknown parameters {names} for the {family} distribution; "
            f"allowed parameters are {', '.join(allowed)}"
        )


def _check_family(d: Mapping, field: str, family: str) -> None:
    name = d.get("distribution", family)
    if name != family:
        raise DistributionError(f"{field}: distribution = {name!r} given to the {family} parser")


def _as_u(u) -> np.ndarray:
    return np.asarray(u, dtype=np.float64)


def _inside(values, low, high, low_inclusive, high_inclusive) -> np.ndarray:
    v = np.asarray(values, dtype=np.float64)
    return ((v >= low) if low_inclusive else (v > low)) & ((v <= high) if high_inclusive else (v < high))


# ---------------------------------------------------------------------------
# the standard normal restricted to [a, b], in log space
# ---------------------------------------------------------------------------

#: ln sqrt(2 pi), the log of the standard normal density's normalisation.
_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


def _log_exp_difference(log_p, log_q):
    """ln(p - q) from ln p and ln q (p >= q), as the log of a sum of exponentials with
    the second term turned negative by the phase pi: ``p - q = e^ln p + e^(ln q + i pi)``.
    ``special.logsumexp`` on those two complex terms, keeping the real part, is how scipy
    1.17 computes it; the same call here gives the same bits."""
    terms = np.array([log_p, log_q + np.pi * 1j])
    return np.real(special.logsumexp(terms, axis=0))


def _log_normal_mass(a: float, b: float) -> float:
    """ln Z(a, b) with Z(a, b) = Phi(b) - Phi(a), the standard normal probability of
    [a, b] (a < b, either may be infinite), without underflow in the far tails:

    * [a, b] left of the mode (b <= 0): ln(Phi(b) - Phi(a)) from ln Phi(b) and ln Phi(a)
      (``log_ndtr``, accurate far into the left tail);
    * [a, b] right of the mode (a > 0): the mirror image, Z(a, b) = Z(-b, -a);
    * [a, b] around the mode (a <= 0 < b): ln(1 - Phi(a) - Phi(-b)) with ``log1p``, which
      stays accurate as Z approaches 1.

    Evaluated on one-element arrays with the scipy.special calls of scipy 1.17's
    ``_log_gauss_mass``, so that the inverse CDF below reproduces its bits.
    """
    lower, upper = np.array([a], dtype=np.float64), np.array([b], dtype=np.float64)
    if a > 0:
        lower, upper = -upper, -lower
    if upper[0] <= 0:
        log_z = _log_exp_difference(special.log_ndtr(upper), special.log_ndtr(lower))
    else:
        log_z = special.log1p(-special.ndtr(lower) - special.ndtr(-upper))
    return float(log_z[0])


def _truncated_normal_quantile(q: np.ndarray, a: float, b: float, log_z: float) -> np.ndarray:
    """Inverse CDF of the standard normal restricted to [a, b], for 0 < q < 1.

    The quantile x solves ``Phi(x) = Phi(a) + q Z`` with ``Z = Phi(b) - Phi(a)``
    (``log_z = ln Z`` from :func:`_log_normal_mass`). It is solved in log space:

        a < 0:   ln Phi(x)  = logsumexp(ln Phi(a),  ln q + ln Z),        x =  ndtri_exp(.)
        a >= 0:  ln Phi(-x) = logsumexp(ln Phi(-b), ln(1 - q) + ln Z),   x = -ndtri_exp(.)

    the second being the mirror image (``Phi(-x) = Phi(-b) + (1 - q) Z``), so that the
    sum is always taken on the side of the normal whose tail ``log_ndtr`` resolves and an
    interval 30 standard deviations out still gives finite, ordered draws. The operations
    are those of scipy 1.17's ``truncnorm._ppf`` (numpy's ``log``/``log1p`` on q,
    ``special.logsumexp`` over a 2 x n stack, ``special.ndtri_exp``), which makes the
    result bit-identical to it: the sampled inputs of existing scenarios depend on that.
    """
    if a < 0:
        edge = special.log_ndtr(np.full_like(q, a))
        log_phi = special.logsumexp(np.array([edge, np.log(q) + log_z]), axis=0)
        return special.ndtri_exp(log_phi)
    edge = special.log_ndtr(np.full_like(q, -b))
    log_phi = special.logsumexp(np.array([edge, np.log1p(-q) + log_z]), axis=0)
    return -special.ndtri_exp(log_phi)


# ---------------------------------------------------------------------------
# families
# ---------------------------------------------------------------------------


class Distribution:
    """Base class: a frozen dataclass per family with a vectorised inverse CDF.

    Subclasses define ``family`` (the name used in the TOML ``distribution``
    key), ``from_dict``, ``ppf``, ``mean``, ``support``,
    ``probability_outside`` and ``to_dict``.
    """

    family: ClassVar[str] = ""
    #: True when draws are labels (strings) returned as integer indices.
    categorical: ClassVar[bool] = False
    #: True for the families that draw from a finite list of values (choice,
    #: empirical); False for the continuous ones.
    discrete: ClassVar[bool] = False

    @classmethod
    def from_dict(
        cls, d: Mapping[str, Any], field: str, *, base_dir: str | Path | None = None
    ) -> Distribution:  # pragma: no cover
        raise NotImplementedError

    def ppf(self, u) -> np.ndarray:  # pragma: no cover
        """Inverse CDF: map uniforms ``u`` in (0, 1) onto draws (same shape)."""
        raise NotImplementedError

    def mean(self) -> float:  # pragma: no cover
        raise NotImplementedError

    def support(self) -> tuple[float, float]:  # pragma: no cover
        raise NotImplementedError

    def probability_outside(
        self, low: float, high: float, low_inclusive: bool = True, high_inclusive: bool = True
    ) -> float:  # pragma: no cover
        """Probability that a draw lies outside the interval from ``low`` to ``high``
        (each end closed or open as given; it matters only for the discrete families).
        Used to check a distribution against a field's allowed range when a scenario
        is loaded (:func:`mineburial.systems.mine.config.check_distribution`)."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        """The inline-table form, for recording the resolved scenario in outputs."""
        out: dict[str, Any] = {"distribution": self.family}
        for f in fields(self):  # type: ignore[arg-type]
            val = getattr(self, f.name)
            if val is None:
                continue
            out[f.name] = list(val) if isinstance(val, tuple) else val
        return out


@dataclass(frozen=True)
class Uniform(Distribution):
    """Continuous uniform on [low, high]."""

    low: float
    high: float
    family: ClassVar[str] = "uniform"

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        _check_keys(d, field, cls.family, ("low", "high"))
        low = _number(d, "low", field, cls.family)
        high = _number(d, "high", field, cls.family)
        if not high > low:
            raise DistributionError(f"{field}: high = {d['high']} must be > low = {d['low']}")
        return cls(low, high)

    def ppf(self, u):
        u = _as_u(u)
        return np.clip(self.low + (self.high - self.low) * u, self.low, self.high)

    def mean(self):
        return 0.5 * (self.low + self.high)

    def support(self):
        return (self.low, self.high)

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        width = self.high - self.low
        below = min(max(low - self.low, 0.0), width)
        above = min(max(self.high - high, 0.0), width)
        return min((below + above) / width, 1.0)


@dataclass(frozen=True)
class Normal(Distribution):
    """Normal with mean ``mean`` and standard deviation ``std``."""

    mu: float  #: the mean (TOML key ``mean``)
    std: float
    family: ClassVar[str] = "normal"

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        _check_keys(d, field, cls.family, ("mean", "std"))
        mean = _number(d, "mean", field, cls.family)
        std = _number(d, "std", field, cls.family)
        if not std > 0:
            raise DistributionError(f"{field}: std = {d['std']} must be > 0")
        return cls(mean, std)

    def ppf(self, u):
        return self.mu + self.std * special.ndtri(_as_u(u))

    def mean(self):
        return self.mu

    def support(self):
        return (-math.inf, math.inf)

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        return min(
            float(special.ndtr((low - self.mu) / self.std) + special.ndtr((self.mu - high) / self.std)), 1.0
        )

    def to_dict(self):
        return {"distribution": self.family, "mean": self.mu, "std": self.std}


@dataclass(frozen=True)
class TruncatedNormal(Distribution):
    """Normal(mean, std) of the parent variable, restricted to [low, high].

    ``mean`` and ``std`` are the parent's parameters; the truncated variable has
    a different mean (see :meth:`mean`). A missing bound is infinite (one-sided
    truncation).
    """

    mu: float  #: mean of the parent normal (TOML key ``mean``)
    std: float  #: standard deviation of the parent normal
    low: float
    high: float
    family: ClassVar[str] = "truncated_normal"

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        _check_keys(d, field, cls.family, ("mean", "std", "low", "high"))
        mean = _number(d, "mean", field, cls.family)
        std = _number(d, "std", field, cls.family)
        if not std > 0:
            raise DistributionError(f"{field}: std = {d['std']} must be > 0")
        if "low" not in d and "high" not in d:
            raise DistributionError(
                f"{field}: truncated_normal needs at least one of 'low', 'high' "
                '(use distribution = "normal" for no truncation)'
            )
        low = _number(d, "low", field, cls.family, default=-math.inf, allow_inf=True)
        high = _number(d, "high", field, cls.family, default=math.inf, allow_inf=True)
        if not high > low:
            raise DistributionError(
                f"{field}: high = {d.get('high', math.inf)} must be > low = {d.get('low', -math.inf)}"
            )
        # the inverse CDF works in log space, so even far-tail intervals are
        # fine; refuse only an interval whose inverse CDF is not finite.
        a, b = (low - mean) / std, (high - mean) / std
        probe = _truncated_normal_quantile(
            np.array([2.0**-53, 0.5, 1.0 - 2.0**-53]), a, b, _log_normal_mass(a, b)
        )
        if not np.all(np.isfinite(probe)):
            raise DistributionError(
                f"{field}: [low, high] = [{low}, {high}] carries no probability that "
                f"double precision resolves under normal(mean={mean}, std={std})"
            )
        return cls(mean, std, low, high)

    @property
    def _ab(self):
        return (self.low - self.mu) / self.std, (self.high - self.mu) / self.std

    def ppf(self, u):
        """``mean + std x`` with x the standard quantile of :func:`_truncated_normal_quantile`,
        clipped to [low, high]; u = 0 and u = 1 give the bounds, u outside [0, 1] or NaN
        gives NaN. Bit-identical to
        ``np.clip(truncnorm.ppf(u, a, b, loc=mean, scale=std), low, high)``."""
        u = _as_u(u)
        a, b = self._ab
        x = np.full(u.shape, np.nan)
        # the bounds through the same arithmetic as the interior (a std + mean, which may
        # round off low); the clip below puts them back on [low, high]
        x[u == 0.0] = a * self.std + self.mu
        x[u == 1.0] = b * self.std + self.mu
        interior = (u > 0.0) & (u < 1.0)
        if np.any(interior):
            z = _truncated_normal_quantile(u[interior], a, b, _log_normal_mass(a, b))
            x[interior] = z * self.std + self.mu
        return np.clip(x, self.low, self.high)

    def mean(self):
        """E[X] = mean + std (phi(a) - phi(b)) / Z (Johnson, Kotz & Balakrishnan 1994,
        eq. 13.134), with phi(.)/Z formed in log space so a far-tail interval neither
        underflows nor divides 0 by 0."""
        a, b = self._ab
        log_z = _log_normal_mass(a, b)
        density_ratio = math.exp(-0.5 * a * a - _LOG_SQRT_2PI - log_z) - math.exp(
            -0.5 * b * b - _LOG_SQRT_2PI - log_z
        )
        # in an interval ~1e-8 std wide, phi(a) - phi(b) and Z are mostly rounding and
        # the ratio can land outside [low, high]; the mean is kept inside
        return min(max(self.mu + self.std * density_ratio, self.low), self.high)

    def support(self):
        return (self.low, self.high)

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        """P(X < low) + P(X > high) = (Z(a, low') + Z(high', b)) / Z(a, b) with low', high'
        the standardised ends, each ratio formed in log space (0 or 1 for an end outside
        [a, b])."""
        a, b = self._ab
        log_z = _log_normal_mass(a, b)

        def share(lower, upper):  # Z(lower, upper) / Z(a, b) for [lower, upper] in [a, b]
            if lower >= upper:
                return 0.0
            if lower <= a and upper >= b:
                return 1.0
            return math.exp(_log_normal_mass(max(lower, a), min(upper, b)) - log_z)

        below = share(a, (low - self.mu) / self.std)
        above = share((high - self.mu) / self.std, b)
        return min(below + above, 1.0)

    def to_dict(self):
        out = {"distribution": self.family, "mean": self.mu, "std": self.std}
        if math.isfinite(self.low):
            out["low"] = self.low
        if math.isfinite(self.high):
            out["high"] = self.high
        return out


@dataclass(frozen=True)
class LogNormal(Distribution):
    """Log-normal: ln X ~ normal(ln median, sigma).

    Parameterised by the **median** of X and **sigma**, the standard deviation
    of ln X (scipy: ``lognorm(s=sigma, scale=median)``). Mean of X:
    ``median * exp(sigma**2 / 2)``.
    """

    median: float
    sigma: float
    family: ClassVar[str] = "lognormal"

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        if "mean" in d or "std" in d:
            hint = ""
            try:
                m = float(d["mean"])
                s = float(d["std"])
                if m > 0 and s > 0:
                    cv2 = (s / m) ** 2
                    hint = (
                        f"; for mean = {d['mean']}, std = {d['std']} of X use "
                        f"median = {m / math.sqrt(1.0 + cv2):.6g}, "
                        f"sigma = {math.sqrt(math.log1p(cv2)):.6g}"
                    )
            except (KeyError, TypeError, ValueError):
                pass
            raise DistributionError(
                f"{field}: lognormal is parameterised by median (of X) and sigma "
                f"(standard deviation of ln X), not by mean/std; "
                f"median = mean/sqrt(1 + (std/mean)^2), sigma = sqrt(ln(1 + (std/mean)^2))"
                f"{hint}"
            )
        _check_keys(d, field, cls.family, ("median", "sigma"))
        median = _number(d, "median", field, cls.family)
        sigma = _number(d, "sigma", field, cls.family)
        if not median > 0:
            raise DistributionError(f"{field}: median = {d['median']} must be > 0")
        if not sigma > 0:
            raise DistributionError(f"{field}: sigma = {d['sigma']} must be > 0")
        return cls(median, sigma)

    def ppf(self, u):
        return self.median * np.exp(self.sigma * special.ndtri(_as_u(u)))

    def mean(self):
        return self.median * math.exp(0.5 * self.sigma**2)

    def support(self):
        return (0.0, math.inf)

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        """P(X < low) + P(X > high) with P(X < x) = Phi(ln(x / median) / sigma) for x > 0."""
        low_ratio, high_ratio = low / self.median, high / self.median
        below = float(special.ndtr(math.log(low_ratio) / self.sigma)) if low_ratio > 0 else 0.0
        above = float(special.ndtr(-math.log(high_ratio) / self.sigma)) if high_ratio > 0 else 1.0
        return min(below + above, 1.0)


@dataclass(frozen=True)
class Choice(Distribution):
    """Discrete choice among ``values`` with normalised ``weights``.

    ``values`` are all numbers (draws are floats) or all strings (mine-type,
    sediment-class or core-file names: draws are labels; the sampler returns
    integer indices into ``values``, see :func:`sampling.sample_fields`).
    """

    values: tuple
    weights: tuple[float, ...]
    family: ClassVar[str] = "choice"
    discrete: ClassVar[bool] = True

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        _check_keys(d, field, cls.family, ("values", "weights"))
        if "values" not in d:
            raise DistributionError(f"{field}: choice distribution needs 'values' (missing)")
        raw = d["values"]
        if isinstance(raw, (str, bytes)) or not hasattr(raw, "__len__") or len(raw) == 0:
            raise DistributionError(
                f"{field}: values = {raw!r} must be a non-empty list of numbers or strings"
            )
        raw = list(raw)
        if all(isinstance(v, str) for v in raw):
            values = tuple(raw)
        else:
            values = []
            for j, v in enumerate(raw):
                if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
                    raise DistributionError(
                        f"{field}: values[{j}] = {v!r} must be a number, or all values "
                        "must be strings (numbers and strings cannot be mixed)"
                    )
                if not math.isfinite(float(v)):
                    raise DistributionError(f"{field}: values[{j}] = {v} must be finite")
                values.append(float(v))
            values = tuple(values)
        if "weights" in d and d["weights"] is not None:
            w_raw = d["weights"]
            if isinstance(w_raw, (str, bytes)) or not hasattr(w_raw, "__len__"):
                raise DistributionError(f"{field}: weights = {w_raw!r} must be a list of numbers")
            w_raw = list(w_raw)
            if len(w_raw) != len(values):
                raise DistributionError(
                    f"{field}: weights has {len(w_raw)} entries but values has {len(values)}"
                )
            w = []
            for j, x in enumerate(w_raw):
                if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
                    raise DistributionError(f"{field}: weights[{j}] = {x!r} must be a number")
                if not (math.isfinite(float(x)) and float(x) >= 0):
                    raise DistributionError(f"{field}: weights[{j}] = {x} must be finite and >= 0")
                w.append(float(x))
            try:
                total = math.fsum(w)
            except OverflowError:  # finite weights whose sum is beyond float (issue 35)
                total = math.inf
            if math.isinf(total):  # proportional weights: the same probabilities, scaled
                w = [x / max(w) for x in w]
                total = math.fsum(w)
            if not total > 0:
                raise DistributionError(f"{field}: weights must not all be zero")
            weights = tuple(x / total for x in w)
        else:
            weights = tuple(1.0 / len(values) for _ in values)
        return cls(values, weights)

    @property
    def categorical(self) -> bool:  # type: ignore[override]
        return isinstance(self.values[0], str)

    def _cdf_edges(self) -> np.ndarray:
        cum = np.cumsum(np.asarray(self.weights, dtype=np.float64))
        cum /= cum[-1]
        cum[-1] = 1.0
        return cum

    def index(self, u) -> np.ndarray:
        """Index into ``values`` chosen by uniforms ``u`` (int64, same shape).

        Value j is chosen for ``cum[j-1] <= u < cum[j]`` with ``cum`` the
        cumulative weights, so a zero weight is never chosen.
        """
        idx = np.searchsorted(self._cdf_edges(), _as_u(u), side="right")
        return np.minimum(idx, len(self.values) - 1).astype(np.int64)

    def ppf(self, u):
        """The chosen values: float64 for numbers, a numpy str array for labels."""
        idx = self.index(u)
        if self.categorical:
            return np.asarray(self.values)[idx]
        return np.asarray(self.values, dtype=np.float64)[idx]

    def mean(self):
        if self.categorical:
            raise TypeError(f"a choice among labels {self.values!r} has no mean")
        return math.fsum(v * w for v, w in zip(self.values, self.weights))

    def support(self):
        if self.categorical:
            raise TypeError(f"a choice among labels {self.values!r} has no numeric support")
        return (min(self.values), max(self.values))

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        if self.categorical:
            raise TypeError(f"a choice among labels {self.values!r} has no numeric support")
        out = ~_inside(self.values, low, high, low_inclusive, high_inclusive)
        return min(math.fsum(w for w, o in zip(self.weights, out) if o), 1.0)


@dataclass(frozen=True)
class Empirical(Distribution):
    """Resample the given numbers with equal weight (inverse empirical CDF).

    ``values`` are stored sorted; ``ppf(u) = values[floor(n u)]``, so each of
    the n values has probability 1/n (repeated values proportionally more).
    ``file``/``column`` record where the values were read from (a CSV file with
    a header row; ``#`` comment lines and blank lines are skipped; relative
    paths are resolved against ``base_dir``, normally the scenario file's folder).
    """

    values: tuple[float, ...]
    file: str | None = None
    column: str | None = None
    family: ClassVar[str] = "empirical"
    discrete: ClassVar[bool] = True

    @classmethod
    def from_dict(cls, d, field, *, base_dir=None):
        _check_family(d, field, cls.family)
        _check_keys(d, field, cls.family, ("values", "file", "column"))
        has_values, has_file = "values" in d, "file" in d
        if has_values == has_file:
            raise DistributionError(
                f"{field}: empirical distribution needs exactly one of "
                'values = [...] or file = "..." (with column = "...")'
            )
        if has_values:
            if "column" in d:
                raise DistributionError(f'{field}: column is only used with file = "..."')
            raw = d["values"]
            if isinstance(raw, (str, bytes)) or not hasattr(raw, "__len__") or len(raw) == 0:
                raise DistributionError(f"{field}: values = {raw!r} must be a non-empty list of numbers")
            vals = []
            for j, v in enumerate(raw):
                if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
                    hint = ' (use distribution = "choice" for labels)' if isinstance(v, str) else ""
                    raise DistributionError(f"{field}: values[{j}] = {v!r} must be a number{hint}")
                if not math.isfinite(float(v)):
                    raise DistributionError(f"{field}: values[{j}] = {v} must be finite")
                vals.append(float(v))
            return cls(tuple(sorted(vals)))
        file = d["file"]
        if not isinstance(file, str) or not file:
            raise DistributionError(f"{field}: file = {file!r} must be a file name")
        column = d.get("column")
        if column is not None and not isinstance(column, str):
            raise DistributionError(f"{field}: column = {column!r} must be a column name")
        vals = _read_column(field, file, column, base_dir)
        return cls(tuple(sorted(vals)), file, column)

    def ppf(self, u):
        v = np.asarray(self.values, dtype=np.float64)
        n = v.size
        idx = np.floor(_as_u(u) * n).astype(np.int64)
        return v[np.clip(idx, 0, n - 1)]

    def mean(self):
        return math.fsum(self.values) / len(self.values)

    def support(self):
        return (self.values[0], self.values[-1])

    def probability_outside(self, low, high, low_inclusive=True, high_inclusive=True):
        out = ~_inside(self.values, low, high, low_inclusive, high_inclusive)
        return int(out.sum()) / len(self.values)

    def to_dict(self):
        out: dict[str, Any] = {"distribution": self.family}
        if self.file is not None:
            out["file"] = self.file
            if self.column is not None:
                out["column"] = self.column
        else:
            out["values"] = list(self.values)
        return out


def _read_column(field: str, file: str, column: str | None, base_dir: str | Path | None) -> list[float]:
    path = Path(file)
    if not path.is_absolute() and base_dir is not None:
        path = Path(base_dir) / path
    try:
        rows = [
            (lineno, row)
            # every row one value per column: a row with a cell more or less would be read
            # shifted by the column's position (the forcing readers' rule, issue 35)
            for lineno, row in inputs.numbered_csv(inputs.read_text(path, "text"), as_wide_as_header=True)
            if any(c.strip() for c in row)
        ]
    except FileNotFoundError:
        raise DistributionError(f"{field}: file = {file!r} not found (looked for {path})") from None
    except OSError as exc:
        raise DistributionError(f"{field}: cannot read file {str(path)!r} ({exc.strerror})") from None
    except csv.Error as exc:
        raise DistributionError(f"{field}: file {str(path)!r} is not a CSV table ({exc})") from None
    if not rows:
        raise DistributionError(f"{field}: file {str(path)!r} has no header row")
    header = [h.strip() for h in rows[0][1]]
    names = inputs.column_names(header)
    if names is None:
        raise DistributionError(
            f"{field}: file {str(path)!r}, line {rows[0][0]}: the first row is not a header of "
            f"column names (each {inputs.COLUMN_NAME_RULE})"
        )
    if column is None:
        if len(header) != 1:
            raise DistributionError(
                f'{field}: file {str(path)!r} has columns {names}; name one with column = "..."'
            )
        col = 0
    elif column not in header:
        raise DistributionError(
            f"{field}: column = {column!r} not in {str(path)!r}; available columns are "
            f"{names}{_nearest(column, header)}"
        )
    else:
        col = header.index(column)
    vals = []
    for lineno, row in rows[1:]:
        cell = row[col].strip() if col < len(row) else ""
        where = f"{field}: {str(path)!r} line {lineno}, column {col + 1} ({header[col]!r})"
        try:
            x = float(cell)
        except ValueError:
            raise DistributionError(f"{where}: " + ("empty" if not cell else "not a number")) from None
        if not math.isfinite(x):
            raise DistributionError(f"{where}: {x} must be finite")
        vals.append(x)
    if not vals:
        raise DistributionError(f"{field}: file {str(path)!r} has no values below its header")
    return vals


#: Registry of families by their TOML name.
DISTRIBUTIONS: dict[str, type[Distribution]] = {
    cls.family: cls for cls in (Uniform, Normal, TruncatedNormal, LogNormal, Choice, Empirical)
}


def is_distribution_table(value: Any) -> bool:
    """True for an inline table that describes a distribution (has a ``distribution`` key)."""
    return isinstance(value, Mapping) and "distribution" in value


def from_dict(d: Mapping[str, Any], field: str, *, base_dir: str | Path | None = None) -> Distribution:
    """Build the distribution named by ``d["distribution"]``; errors name ``field``."""
    if not isinstance(d, Mapping):
        raise DistributionError(f"{field}: expected an inline table, got {d!r}")
    available = ", ".join(DISTRIBUTIONS)
    if "distribution" not in d:
        raise DistributionError(
            f'{field}: an inline table must name its family with distribution = "..."; '
            f"available distributions are {available}"
        )
    name = d["distribution"]
    if not isinstance(name, str) or name not in DISTRIBUTIONS:
        hint = _nearest(name, DISTRIBUTIONS) if isinstance(name, str) else ""
        raise DistributionError(
            f"{field}: unknown distribution {name!r}; available distributions are {available}{hint}"
        )
    return DISTRIBUTIONS[name].from_dict(d, field, base_dir=base_dir)


def parse_value(value: Any, field: str, *, base_dir: str | Path | None = None) -> float | str | Distribution:
    """A scenario value: a fixed float, a fixed string, or a distribution object.

    Numbers become ``float`` (must be finite); strings stay strings (labels);
    inline tables become a :class:`Distribution` via :func:`from_dict`; an
    existing :class:`Distribution` is returned unchanged.
    """
    if isinstance(value, Distribution):
        return value
    if isinstance(value, bool):
        raise DistributionError(f"{field}: {value!r} must be a number, a string or a distribution")
    if isinstance(value, (int, float, np.integer, np.floating)):
        x = float(value)
        if not math.isfinite(x):
            raise DistributionError(f"{field}: {value} must be a finite number")
        return x
    if isinstance(value, str):
        return value
    if isinstance(value, Mapping):
        return from_dict(value, field, base_dir=base_dir)
    if isinstance(value, (list, tuple)):
        raise DistributionError(
            f"{field}: a list {value!r} is not a value; write a choice as "
            '{distribution = "choice", values = [...]}'
        )
    raise DistributionError(
        f"{field}: {value!r} ({type(value).__name__}) must be a number, a string or a distribution table"
    )
