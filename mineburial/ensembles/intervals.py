"""Confidence intervals of the ensembles' statistics, for every system: they know no mine.

* :func:`two_sided_normal_quantile`: z such that a standard normal variable lies in [-z, z]
  with the given probability (``scipy.special.ndtri``);
* :func:`wilson_interval`: the Wilson score interval of a binomial proportion, Wilson,
  E. B. (1927), Probable inference, the law of succession, and statistical inference,
  J. Am. Stat. Assoc. 22(158), 209-212.
"""

from __future__ import annotations

import numpy as np
from scipy.special import ndtri

__all__ = ["two_sided_normal_quantile", "wilson_interval"]


def two_sided_normal_quantile(confidence_level: float) -> float:
    """The (1 + confidence_level) / 2 quantile of the standard normal distribution."""
    return float(ndtri(0.5 + 0.5 * confidence_level))


def wilson_interval(k, n, confidence_level: float = 0.95):
    """Wilson score interval for a binomial proportion k/n.

    Wilson (1927), eq. for the score interval::

        centre = (p + z^2 / (2 n)) / (1 + z^2 / n)
        half   = z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / (4 n^2))

    with p = k / n and z the (1 + confidence_level) / 2 quantile of the
    standard normal distribution. Returns ``(lower, upper)`` arrays, clipped to
    [0, 1] (they lie there analytically; clipping only removes round-off), and
    NaN where n = 0.
    """
    if not 0.0 < confidence_level < 1.0:
        raise ValueError(f"confidence_level must lie in (0, 1), got {confidence_level!r}")
    k = np.asarray(k, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    if np.any(k < 0) or np.any(k > n):
        raise ValueError("wilson_interval needs 0 <= k <= n")
    z = two_sided_normal_quantile(confidence_level)
    z2 = z * z
    with np.errstate(invalid="ignore", divide="ignore"):
        p = k / n
        denom = 1.0 + z2 / n
        centre = (p + z2 / (2.0 * n)) / denom
        half = z / denom * np.sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n))
    lower = np.where(n > 0, np.clip(centre - half, 0.0, 1.0), np.nan)
    upper = np.where(n > 0, np.clip(centre + half, 0.0, 1.0), np.nan)
    return lower, upper
