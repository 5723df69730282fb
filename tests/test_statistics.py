"""Burial statistics against exact sample statistics computed independently.

References: numpy's own estimators applied to the same values (the statistics
must be these estimators, bit for bit), the standard library ``statistics``
module (independent implementation, tolerance 1e-12 relative), brute-force
counting, the Wilson (1927) score interval written out by hand, and
``scipy.stats.binomtest(...).proportion_ci(method="wilson")``.
"""

import math
import statistics as pystats
import warnings

import numpy as np
import pytest
from scipy.stats import binomtest

from mineburial.ensembles.intervals import two_sided_normal_quantile, wilson_interval
from mineburial.io import variables as V
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as S
from mineburial.systems.mine.statistics import burial_class, burial_statistics, status_counts

IDX = layout.SUMMARY_INDEX
Q = (0.05, 0.25, 0.5, 0.75, 0.95)
#: the 0.975 quantile of the standard normal distribution (tabulated value)
Z975 = 1.959963984540054


def synthetic(n=400, seed=20240611):
    """Random per-drop results with every status code and exact class boundaries."""
    rng = np.random.default_rng(seed)
    summary = rng.normal(1.0, 0.5, size=(n, layout.N_SUMMARY))
    for name in V.PERCENT_OUTPUTS:
        col = rng.uniform(0.0, 100.0, n)
        col[rng.random(n) < 0.15] = 0.0  # exactly 0 % -> class 0
        col[:7] = (0.0, 10.0, 20.0, 75.0, 100.0, 1e-300, 75.0000001)
        summary[:, IDX[name]] = col
    summary[:, IDX["penetration_depth"]] = rng.gamma(2.0, 0.3, n)
    summary[:, IDX["com_depth"]] = rng.normal(0.2, 0.4, n)
    summary[:, IDX["height_proud"]] = rng.uniform(0.0, 1.2, n)
    status = rng.choice(5, size=n, p=[0.7, 0.1, 0.08, 0.07, 0.05]).astype(np.int8)
    status[:7] = S.AT_REST
    return summary, status


def test_moments_and_quantiles_equal_numpy_and_stdlib():
    summary, status = synthetic()
    ds = burial_statistics(summary, status, quantiles=Q)
    ok = status == S.AT_REST
    for name in layout.SUMMARY_NAMES:
        x = summary[ok, IDX[name]]
        # exactly numpy's estimators on the same values
        assert ds[f"{name}_mean"].item() == np.mean(x)
        assert ds[f"{name}_std"].item() == np.std(x, ddof=1)
        assert ds[f"{name}_stderr"].item() == np.std(x, ddof=1) / np.sqrt(x.size)
        np.testing.assert_array_equal(ds[f"{name}_quantile"].values, np.quantile(x, Q, method="linear"))
        assert ds[f"{name}_mean"].attrs["sample_size"] == x.size
        # independent implementation (Python's statistics module), relative 1e-12
        assert ds[f"{name}_mean"].item() == pytest.approx(pystats.fmean(x), rel=1e-12, abs=1e-12)
        assert ds[f"{name}_std"].item() == pytest.approx(pystats.stdev(x), rel=1e-12)
        # Hyndman & Fan type 7 == statistics.quantiles(method="inclusive")
        pct = pystats.quantiles(x, n=20, method="inclusive")  # 5 %, 10 %, ..., 95 %
        ref = [pct[0], pct[4], pct[9], pct[14], pct[18]]
        np.testing.assert_allclose(ds[f"{name}_quantile"].values, ref, rtol=1e-12, atol=1e-12)


def test_histogram_counts_and_bounds_equal_numpy_histogram():
    summary, status = synthetic()
    ds = burial_statistics(summary, status)
    ok = status == S.AT_REST
    for name in layout.SUMMARY_NAMES:
        x = summary[ok, IDX[name]]
        bins = np.linspace(0, 100, 21) if name in V.PERCENT_OUTPUTS else 20
        counts, edges = np.histogram(x, bins=bins)
        np.testing.assert_array_equal(ds[f"{name}_histogram"].values, counts)
        np.testing.assert_array_equal(ds[f"{name}_bin_bounds"].values[:, 0], edges[:-1])
        np.testing.assert_array_equal(ds[f"{name}_bin_bounds"].values[:, 1], edges[1:])
        np.testing.assert_allclose(ds[f"{name}_bin"].values, 0.5 * (edges[:-1] + edges[1:]), rtol=0, atol=0)
        assert ds[f"{name}_bin"].attrs["bounds"] == f"{name}_bin_bounds"
    # percent bins by brute-force counting: [a, b) and the last bin [95, 100]
    x = summary[ok, IDX["burial_volume"]]
    brute = [np.sum((x >= a) & (x < a + 5)) for a in range(0, 95, 5)]
    brute.append(np.sum((x >= 95) & (x <= 100)))
    np.testing.assert_array_equal(ds["burial_volume_histogram"].values, brute)
    assert ds["burial_volume_histogram"].sum() == x.size


def test_custom_bins_levels_and_values_outside_range():
    summary, status = synthetic()
    ok = status == S.AT_REST
    edges = np.array([0.0, 0.5, 1.0])
    ds = burial_statistics(
        summary,
        status,
        histogram_bins={"penetration_depth": edges},
        exceedance_levels={"penetration_depth": [0.1, 0.2]},
        outputs=("penetration_depth", "burial_volume"),
    )
    x = summary[ok, IDX["penetration_depth"]]
    np.testing.assert_array_equal(ds["penetration_depth_histogram"].values, np.histogram(x, bins=edges)[0])
    assert ds["penetration_depth_histogram"].attrs["n_outside_range"] == np.sum(x > 1.0)
    np.testing.assert_array_equal(
        ds["penetration_depth_exceedance"].values, [np.mean(x >= 0.1), np.mean(x >= 0.2)]
    )
    assert "com_depth_mean" not in ds
    with pytest.raises(ValueError, match="strictly increasing"):
        burial_statistics(summary, status, exceedance_levels={"burial_volume": [5.0, 5.0]})


def test_exceedance_is_the_fraction_of_values_at_or_above_each_level():
    summary, status = synthetic()
    ds = burial_statistics(summary, status)
    ok = status == S.AT_REST
    np.testing.assert_array_equal(ds["burial_volume_level"].values, np.arange(0, 101, 5.0))
    lv = ds["penetration_depth_level"].values
    assert lv[0] == 0.0 and lv[-1] == 5.0 and np.allclose(np.diff(lv), 0.05, rtol=0, atol=1e-12)
    assert ds["com_depth_level"].values[0] == -2.0
    for name in layout.SUMMARY_NAMES:
        x = summary[ok, IDX[name]]
        levels = ds[f"{name}_level"].values
        brute = np.array([np.count_nonzero(x >= L) for L in levels]) / x.size
        np.testing.assert_array_equal(ds[f"{name}_exceedance"].values, brute)
    # P(burial_volume >= 0) = 1, and ">=" includes the level itself (value 100 present)
    assert ds["burial_volume_exceedance"].values[0] == 1.0
    x = summary[ok, IDX["burial_volume"]]
    assert ds["burial_volume_exceedance"].values[-1] == np.count_nonzero(x == 100.0) / x.size > 0


@pytest.mark.parametrize(
    "value, expected",
    [
        (0.0, 0),
        (-0.0, 0),
        (-1.0, 0),
        (5e-324, 1),
        (1e-300, 1),
        (10.0, 1),
        (np.nextafter(10.0, 11.0), 2),
        (20.0, 2),
        (np.nextafter(20.0, 21.0), 3),
        (75.0, 3),
        (np.nextafter(75.0, 76.0), 4),
        (100.0, 4),
        (120.0, 4),
        (np.nan, -1),
    ],
)
def test_burial_class_boundaries(value, expected):
    assert burial_class(value) == expected
    assert burial_class(np.array([value]))[0] == expected


def test_burial_class_vectorised_matches_interval_definition():
    rng = np.random.default_rng(3)
    p = np.concatenate([rng.uniform(-5, 110, 5000), [0, 10, 20, 75, 100, np.nan]])
    got = burial_class(p.reshape(-1, 2))
    assert got.dtype == np.int8 and got.shape == (p.size // 2, 2)
    ref = np.select([np.isnan(p), p <= 0, p <= 10, p <= 20, p <= 75], [-1, 0, 1, 2, 3], 4)
    np.testing.assert_array_equal(got.ravel(), ref)


def wilson_by_hand(k, n, z=Z975):
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return centre - half, centre + half


@pytest.mark.parametrize("k, n", [(0, 10), (1, 10), (5, 10), (10, 10), (3, 37), (250, 1000), (1, 1)])
def test_wilson_interval_closed_form_and_scipy(k, n):
    lo, hi = wilson_interval(k, n)
    hlo, hhi = wilson_by_hand(k, n)
    assert lo == pytest.approx(max(hlo, 0.0), abs=1e-14)
    assert hi == pytest.approx(min(hhi, 1.0), abs=1e-14)
    ci = binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    assert lo == pytest.approx(ci.low, abs=1e-12)
    assert hi == pytest.approx(ci.high, abs=1e-12)


def test_two_sided_normal_quantile_against_tabulated_values():
    # Abramowitz & Stegun (1964), table 26.5: z = 1.959963984540054 (95 %), 1.6448536269514722 (90 %)
    assert two_sided_normal_quantile(0.95) == pytest.approx(Z975, rel=1e-15)
    assert two_sided_normal_quantile(0.90) == pytest.approx(1.6448536269514722, rel=1e-15)


def test_wilson_interval_other_level_and_empty_sample():
    lo, hi = wilson_interval(7, 20, confidence_level=0.9)
    ci = binomtest(7, 20).proportion_ci(confidence_level=0.9, method="wilson")
    assert (lo, hi) == (pytest.approx(ci.low, abs=1e-12), pytest.approx(ci.high, abs=1e-12))
    lo, hi = wilson_interval([0, 2], [0, 4])
    assert np.isnan(lo[0]) and np.isnan(hi[0]) and np.isfinite(lo[1])
    with pytest.raises(ValueError):
        wilson_interval(5, 4)


@pytest.mark.parametrize("basis", V.BURIAL_CLASS_BASES)
def test_class_probabilities_and_intervals(basis):
    summary, status = synthetic()
    ds = burial_statistics(summary, status, class_basis=basis)
    x = summary[status == S.AT_REST, IDX[basis]]
    n = x.size
    k = np.array(
        [
            np.sum(x == 0),
            np.sum((x > 0) & (x <= 10)),
            np.sum((x > 10) & (x <= 20)),
            np.sum((x > 20) & (x <= 75)),
            np.sum(x > 75),
        ]
    )
    assert k.sum() == n and k.min() > 0
    np.testing.assert_array_equal(ds["burial_class_count"].values, k)
    np.testing.assert_array_equal(ds["burial_class_probability"].values, k / n)
    for j in range(5):
        ci = binomtest(int(k[j]), n).proportion_ci(method="wilson")
        assert ds["burial_class_probability_lower"].values[j] == pytest.approx(ci.low, abs=1e-12)
        assert ds["burial_class_probability_upper"].values[j] == pytest.approx(ci.high, abs=1e-12)
    assert ds.attrs["burial_class_basis"] == basis
    np.testing.assert_array_equal(ds["impact_burial_class"].values, np.arange(5))


def test_status_counts_cover_every_code():
    summary, status = synthetic()
    ds = burial_statistics(summary, status.astype(np.uint8))
    ref = [np.count_nonzero(status == c) for c in range(len(S.NAMES))]
    np.testing.assert_array_equal(ds["status_count"].values, ref)
    assert ds.attrs["n_drops"] == status.size and ds.attrs["n_at_rest"] == ref[0]
    assert ds["status_code"].attrs["flag_meanings"].split() == list(S.NAMES)
    with pytest.raises(ValueError, match="unknown status code"):
        status_counts(np.array([0, 7], np.int8))


def test_no_drop_at_rest_gives_nan_statistics_without_warnings():
    summary, _ = synthetic(50)
    status = np.full(50, S.TIME_LIMIT, np.int8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = burial_statistics(summary, status)
    assert "n_at_rest = 0" in ds.attrs["statistics_note"]
    for name in layout.SUMMARY_NAMES:
        assert np.isnan(ds[f"{name}_mean"].item()) and np.isnan(ds[f"{name}_std"].item())
        assert np.all(np.isnan(ds[f"{name}_quantile"].values))
        assert np.all(np.isnan(ds[f"{name}_exceedance"].values))
        assert ds[f"{name}_histogram"].sum() == 0
    assert np.all(ds["burial_class_count"].values == 0)
    assert np.all(np.isnan(ds["burial_class_probability"].values))
    assert np.all(np.isnan(ds["burial_class_probability_lower"].values))
    assert ds["status_count"].values[S.TIME_LIMIT] == 50
    empty = burial_statistics(np.empty((0, layout.N_SUMMARY)), np.empty(0, np.int8))
    assert empty.attrs["n_drops"] == 0


def test_single_drop_and_non_finite_values():
    summary, status = synthetic(30)
    status[:] = S.LEFT_DOMAIN
    status[3] = S.AT_REST
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = burial_statistics(summary, status)
    assert ds["penetration_depth_mean"].item() == summary[3, IDX["penetration_depth"]]
    assert np.isnan(ds["penetration_depth_std"].item())
    # a non-finite value of a drop at rest is left out of that output only
    summary, status = synthetic()
    summary[0, IDX["impact_time"]] = np.nan
    ds = burial_statistics(summary, status)
    x = summary[status == S.AT_REST, IDX["impact_time"]]
    assert ds["impact_time_mean"].attrs["sample_size"] == x.size - 1
    assert ds["impact_time_mean"].item() == np.mean(x[np.isfinite(x)])


def test_bad_arguments_have_clear_messages():
    summary, status = synthetic(10)
    with pytest.raises(ValueError, match="burial_volume, burial_height, burial_area"):
        burial_statistics(summary, status, class_basis="volume")
    with pytest.raises(ValueError, match="shape"):
        burial_statistics(summary[:, :5], status)
    with pytest.raises(ValueError, match="did you mean 'burial_volume'"):
        burial_statistics(summary, status, outputs=("burial_volumes",))
    with pytest.raises(ValueError, match="quantiles"):
        burial_statistics(summary, status, quantiles=(0.5, 0.25))


def test_nearly_constant_output_does_not_crash_histogram():
    """Issue 12 item 4: a summary variable constant to the last digit (here an impact time
    that differs by one ulp between drops) made numpy.histogram raise "Too many bins for
    data range" after every drop was computed. The statistics must accept it: the mean is
    the numpy mean and every value is counted once."""
    summary, _ = synthetic(12)
    t = 6.034
    summary[:, layout.SUMMARY_INDEX["impact_time"]] = t
    summary[1, layout.SUMMARY_INDEX["impact_time"]] = np.nextafter(t, 7.0)
    status = np.zeros(12, np.int8)
    with pytest.raises(ValueError, match="Too many bins"):  # what numpy alone does
        np.histogram(summary[:, layout.SUMMARY_INDEX["impact_time"]], bins=20)
    ds = burial_statistics(summary, status)
    assert float(ds["impact_time_mean"]) == pytest.approx(t, rel=1e-15)
    assert int(ds["impact_time_histogram"].sum()) == 12
