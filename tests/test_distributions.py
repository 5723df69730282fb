"""Input distributions: parsing, validation messages and inverse CDFs.

References: scipy.stats distributions (KS tests), closed-form moments
(truncated normal: Johnson, Kotz & Balakrishnan 1994, eq. 13.134; lognormal:
mean = median exp(sigma^2/2)), tabulated normal quantile z_0.975 = 1.959963984540054.
"""

import math

import numpy as np
import pytest
from scipy import stats

from mineburial.ensembles.distributions import (
    DISTRIBUTIONS,
    Choice,
    DistributionError,
    Empirical,
    LogNormal,
    Normal,
    TruncatedNormal,
    Uniform,
    from_dict,
    is_distribution_table,
    parse_value,
)
from mineburial.ensembles.sampling import sample_fields

N = 100_000
SEED = 20240611


def draws(table, method="mc", n=N, seed=SEED, field="test.x"):
    return sample_fields({field: table}, seed, 0, n, method)[field]


# --- continuous families: Kolmogorov-Smirnov against scipy.stats -------------

CONTINUOUS = [
    ({"distribution": "uniform", "low": 2.0, "high": 5.0}, stats.uniform(loc=2.0, scale=3.0)),
    ({"distribution": "normal", "mean": 500.0, "std": 25.0}, stats.norm(loc=500.0, scale=25.0)),
    (
        {"distribution": "truncated_normal", "mean": 1.0, "std": 2.0, "low": 0.0, "high": 4.0},
        stats.truncnorm(-0.5, 1.5, loc=1.0, scale=2.0),
    ),
    ({"distribution": "truncated_normal", "mean": 0.0, "std": 1.0, "low": 1.5}, stats.truncnorm(1.5, np.inf)),
    ({"distribution": "lognormal", "median": 3.0, "sigma": 0.5}, stats.lognorm(s=0.5, scale=3.0)),
]


@pytest.mark.parametrize(
    "table,ref", CONTINUOUS, ids=lambda x: x["distribution"] if isinstance(x, dict) else ""
)
@pytest.mark.parametrize("method", ["mc", "sobol"])
def test_ks_against_scipy(table, ref, method):
    x = draws(table, method)
    assert x.dtype == np.float64 and x.shape == (N,)
    lo, hi = from_dict(table, "test.x").support()
    assert np.all((x >= lo) & (x <= hi))
    assert stats.kstest(x, ref.cdf).pvalue > 0.01


def test_normal_quantile_and_mean():
    d = Normal.from_dict({"mean": 500.0, "std": 25.0}, "mine.mass")
    # tabulated z_0.975 = 1.959963984540054
    assert d.ppf(np.array([0.975]))[0] == pytest.approx(500.0 + 25.0 * 1.959963984540054, rel=1e-14)
    assert d.ppf(0.5) == pytest.approx(500.0, rel=1e-15)
    assert d.mean() == 500.0


def test_uniform_ppf_is_linear():
    d = Uniform.from_dict({"low": -1.0, "high": 3.0}, "x")
    u = np.array([1e-12, 0.25, 0.5, 1 - 1e-12])
    np.testing.assert_allclose(d.ppf(u), -1.0 + 4.0 * u, rtol=0, atol=1e-15)
    assert d.mean() == 1.0


def test_truncated_normal_mean_closed_form():
    # E[X] = mu + sigma (phi(a) - phi(b)) / (Phi(b) - Phi(a))  (Johnson, Kotz & Balakrishnan)
    mu, sd, lo, hi = 1.0, 2.0, 0.0, 4.0
    a, b = (lo - mu) / sd, (hi - mu) / sd

    def phi(z):
        return math.exp(-0.5 * z * z) / math.sqrt(2 * math.pi)

    def Phi(z):
        return 0.5 * math.erfc(-z / math.sqrt(2))

    exact = mu + sd * (phi(a) - phi(b)) / (Phi(b) - Phi(a))
    d = TruncatedNormal.from_dict({"mean": mu, "std": sd, "low": lo, "high": hi}, "x")
    assert d.mean() == pytest.approx(exact, rel=1e-12)
    x = draws(d.to_dict())
    assert abs(x.mean() - exact) < 4 * x.std() / math.sqrt(N)


def test_lognormal_median_and_mean():
    d = LogNormal.from_dict({"median": 3.0, "sigma": 0.5}, "x")
    assert d.ppf(0.5) == pytest.approx(3.0, rel=1e-15)
    exact = 3.0 * math.exp(0.5 * 0.25)
    assert d.mean() == pytest.approx(exact, rel=1e-15)
    x = draws(d)
    assert abs(x.mean() - exact) < 4 * x.std() / math.sqrt(N)


def test_far_tail_truncation_is_finite():
    d = TruncatedNormal.from_dict({"mean": 0.0, "std": 1.0, "low": 30.0, "high": 31.0}, "x")
    x = d.ppf(np.array([2.0**-53, 0.5, 1 - 2.0**-53]))
    assert np.all(np.isfinite(x)) and np.all((x >= 30.0) & (x <= 31.0))


# --- discrete families ---------------------------------------------------------


def test_choice_weights_chi_square():
    d = {"distribution": "choice", "values": [1.0, 2.0, 5.0, 10.0], "weights": [1, 2, 3, 4]}
    x = draws(d)
    values, counts = np.unique(x, return_counts=True)
    np.testing.assert_array_equal(values, [1.0, 2.0, 5.0, 10.0])
    expected = N * np.array([0.1, 0.2, 0.3, 0.4])
    assert stats.chisquare(counts, expected).pvalue > 0.01


def test_choice_zero_weight_never_chosen_and_equal_default():
    d = Choice.from_dict({"values": [1, 2, 3], "weights": [0.5, 0, 0.5]}, "x")
    u = np.concatenate([np.linspace(1e-9, 1 - 1e-9, 10001), [0.5, np.nextafter(0.5, 0)]])
    assert 2.0 not in d.ppf(u)
    e = Choice.from_dict({"values": [4, 5]}, "x")
    assert e.weights == (0.5, 0.5) and e.mean() == 4.5 and e.support() == (4.0, 5.0)


def test_choice_labels_return_indices_and_labels():
    table = {"distribution": "choice", "values": ["clay", "silt", "sand"], "weights": [2, 1, 1]}
    s = sample_fields({"sediment.class": table, "mine.type": "manta"}, SEED, 0, N)
    idx = s["sediment.class"]
    assert idx.dtype == np.int64 and s.labels["sediment.class"] == ("clay", "silt", "sand")
    counts = np.bincount(idx, minlength=3)
    assert stats.chisquare(counts, N * np.array([0.5, 0.25, 0.25])).pvalue > 0.01
    assert set(s.decoded("sediment.class")) == {"clay", "silt", "sand"}
    # a fixed string is a categorical field with one label
    assert s.labels["mine.type"] == ("manta",) and np.all(s["mine.type"] == 0)
    assert from_dict(table, "x").ppf(np.array([0.1, 0.6, 0.9])).tolist() == ["clay", "silt", "sand"]
    with pytest.raises(TypeError, match="no mean"):
        from_dict(table, "x").mean()


def test_empirical_values_resampled_with_equal_weight():
    vals = [0.5, 1.0, 1.0, 2.0, 7.0]  # 1.0 twice -> probability 2/5
    x = draws({"distribution": "empirical", "values": vals})
    uniq, counts = np.unique(x, return_counts=True)
    np.testing.assert_array_equal(uniq, [0.5, 1.0, 2.0, 7.0])
    assert stats.chisquare(counts, N * np.array([1, 2, 1, 1]) / 5).pvalue > 0.01
    d = Empirical.from_dict({"values": vals}, "x")
    assert d.mean() == pytest.approx(np.mean(vals), rel=1e-15)
    assert d.support() == (0.5, 7.0)


def test_empirical_reproduces_a_continuous_sample():
    rng = np.random.default_rng(1)
    sample = rng.gamma(2.0, 3.0, size=400)  # 400 distinct values
    x = draws({"distribution": "empirical", "values": sample.tolist()})
    values, counts = np.unique(x, return_counts=True)
    # only the given values come out, each with probability 1/400
    assert np.isin(values, sample).all() and values.size == sample.size
    assert stats.chisquare(counts, np.full(400, N / 400)).pvalue > 0.01
    # and the step CDF matches: sup |F_draws - F_sample| at the support points
    # (a discrete KS statistic; the continuous 1 % critical value is conservative)
    f_draws = np.cumsum(counts) / N
    f_sample = np.arange(1, 401) / 400
    assert np.max(np.abs(f_draws - f_sample)) < 1.63 / math.sqrt(N)


def test_empirical_from_csv_file(tmp_path):
    f = tmp_path / "cores.csv"
    f.write_text("# shear strengths of cores\ncore,strength_kpa\nA,2.5\nB,3.5\n\nC,3.5\n")
    d = from_dict(
        {"distribution": "empirical", "file": "cores.csv", "column": "strength_kpa"},
        "sediment.strength",
        base_dir=tmp_path,
    )
    assert d.values == (2.5, 3.5, 3.5) and d.file == "cores.csv"
    assert d.to_dict() == {"distribution": "empirical", "file": "cores.csv", "column": "strength_kpa"}
    one = tmp_path / "one.csv"
    one.write_text("x\n1\n2\n")
    assert Empirical.from_dict({"file": str(one)}, "y").values == (1.0, 2.0)


@pytest.mark.parametrize("row", ["B,3.5,extra", "4.5"])
def test_empirical_csv_row_of_another_width_is_refused_naming_its_line(tmp_path, row):
    """Issue 35: a row with a cell more (or fewer) than the header was read by position, so
    "B,3.5,extra" gave 3.5 and "4.5" read the core name column; now the line is named."""
    f = tmp_path / "cores.csv"
    f.write_text(f"core,strength_kpa\nA,2.5\n{row}\n")
    with pytest.raises(
        DistributionError, match=r"sediment\.strength: .*line 3 has \d fields but the header \(line 1\) has 2"
    ):
        from_dict(
            {"distribution": "empirical", "file": "cores.csv", "column": "strength_kpa"},
            "sediment.strength",
            base_dir=tmp_path,
        )


# --- parse_value and round trip -----------------------------------------------


def test_parse_value_fixed_and_distribution():
    assert parse_value(500, "mine.mass") == 500.0 and isinstance(parse_value(500, "m"), float)
    assert parse_value("clay", "sediment.class") == "clay"
    d = parse_value({"distribution": "normal", "mean": 1.0, "std": 2.0}, "x")
    assert d == Normal(1.0, 2.0) and parse_value(d, "x") is d
    assert is_distribution_table({"distribution": "normal"}) and not is_distribution_table({"mean": 1})


@pytest.mark.parametrize(
    "table",
    [
        {"distribution": "uniform", "low": 0.0, "high": 1.0},
        {"distribution": "normal", "mean": 0.0, "std": 1.0},
        {"distribution": "truncated_normal", "mean": 0.0, "std": 1.0, "low": -1.0},
        {"distribution": "lognormal", "median": 1.0, "sigma": 0.1},
        {"distribution": "choice", "values": ["a", "b"], "weights": [0.25, 0.75]},
        {"distribution": "empirical", "values": [1.0, 2.0]},
    ],
)
def test_to_dict_round_trip(table):
    d = from_dict(table, "x")
    assert d.to_dict() == table
    assert from_dict(d.to_dict(), "x") == d


def test_registry_names():
    assert set(DISTRIBUTIONS) == {"uniform", "normal", "truncated_normal", "lognormal", "choice", "empirical"}


# --- error messages -------------------------------------------------------------

ERRORS = [
    ({"distribution": "normal", "mean": 500.0, "std": -1}, r"^mine\.mass: std = -1 must be > 0$"),
    ({"distribution": "normal", "mean": 500.0}, r"^mine\.mass: normal distribution needs 'std'"),
    ({"distribution": "normal", "mean": "500", "std": 1.0}, r"^mine\.mass: mean = '500' must be a number"),
    (
        {"distribution": "normal", "mean": 500.0, "sdt": 1.0},
        r"^mine\.mass: unknown parameter 'sdt' .*allowed parameters are mean, std \(did you mean 'std'\?\)",
    ),
    (
        {"distribution": "normal", "mean": float("nan"), "std": 1.0},
        r"^mine\.mass: mean = nan must be a finite",
    ),
    (
        {"distribution": "nromal", "mean": 0, "std": 1},
        r"^mine\.mass: unknown distribution 'nromal'; available distributions are uniform, normal, "
        r"truncated_normal, lognormal, choice, empirical \(did you mean 'normal'\?\)",
    ),
    ({"mean": 0, "std": 1}, r"^mine\.mass: an inline table must name its family .*available distributions"),
    ({"distribution": "uniform", "low": 5, "high": 2}, r"^mine\.mass: high = 2 must be > low = 5$"),
    (
        {"distribution": "truncated_normal", "mean": 0, "std": 1},
        r"^mine\.mass: truncated_normal needs at least one",
    ),
    (
        {"distribution": "truncated_normal", "mean": 0, "std": 1, "low": 3, "high": 1},
        r"^mine\.mass: high = 1 must be > low = 3$",
    ),
    (
        {"distribution": "lognormal", "mean": 500.0, "std": 50.0},
        r"^mine\.mass: lognormal is parameterised by median .*median = 497\.519, sigma = 0\.0997513",
    ),
    ({"distribution": "lognormal", "median": -2, "sigma": 1}, r"^mine\.mass: median = -2 must be > 0$"),
    ({"distribution": "lognormal", "median": 2, "sigma": 0}, r"^mine\.mass: sigma = 0 must be > 0$"),
    (
        {"distribution": "choice", "values": [1, 2], "weights": [1]},
        r"^mine\.mass: weights has 1 entries but values has 2$",
    ),
    (
        {"distribution": "choice", "values": [1, 2], "weights": [1, -0.5]},
        r"^mine\.mass: weights\[1\] = -0\.5 must be finite and >= 0$",
    ),
    (
        {"distribution": "choice", "values": [1, 2], "weights": [0, 0]},
        r"^mine\.mass: weights must not all be zero",
    ),
    (
        {"distribution": "choice", "values": [1, "a"]},
        r"^mine\.mass: values\[1\] = 'a' must be a number.*mixed",
    ),
    ({"distribution": "choice", "values": []}, r"^mine\.mass: values = \[\] must be a non-empty list"),
    (
        {"distribution": "empirical", "values": ["a"]},
        r"^mine\.mass: values\[0\] = 'a' .*use distribution = \"choice\"",
    ),
    ({"distribution": "empirical"}, r"^mine\.mass: empirical distribution needs exactly one of"),
]


@pytest.mark.parametrize("table,pattern", ERRORS)
def test_error_messages_name_field_value_and_range(table, pattern):
    with pytest.raises(DistributionError, match=pattern):
        parse_value(table, "mine.mass")


def test_error_is_a_value_error():
    assert issubclass(DistributionError, ValueError)


@pytest.mark.parametrize(
    "value,pattern",
    [
        (True, r"^release\.z: True must be a number"),
        ([1, 2], r"^release\.z: a list \[1, 2\] is not a value; write a choice"),
        (float("inf"), r"^release\.z: inf must be a finite number"),
    ],
)
def test_parse_value_rejects(value, pattern):
    with pytest.raises(DistributionError, match=pattern):
        parse_value(value, "release.z")


def test_empirical_file_errors(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text("depth,strength\n0.1,2\n0.2,x\n")
    with pytest.raises(
        DistributionError,
        match=r"^sediment\.strength: column = 'strenght' not in .*"
        r"available columns are depth, strength \(did you mean 'strength'\?\)",
    ):
        from_dict(
            {"distribution": "empirical", "file": "c.csv", "column": "strenght"},
            "sediment.strength",
            base_dir=tmp_path,
        )
    with pytest.raises(
        DistributionError, match=r"^sediment\.strength: .*line 3, column 2 \('strength'\): not a number$"
    ):
        from_dict(
            {"distribution": "empirical", "file": "c.csv", "column": "strength"},
            "sediment.strength",
            base_dir=tmp_path,
        )
    with pytest.raises(DistributionError, match=r"^sediment\.strength: file = 'missing\.csv' not found"):
        from_dict(
            {"distribution": "empirical", "file": "missing.csv", "column": "a"},
            "sediment.strength",
            base_dir=tmp_path,
        )
    with pytest.raises(DistributionError, match=r"has columns depth, strength; name one"):
        from_dict({"distribution": "empirical", "file": "c.csv"}, "sediment.strength", base_dir=tmp_path)


# --- probability outside an interval: the load-time support check (issue 12 item 6) ---
def _phi(x):
    return stats.norm.cdf(x)


def _truncnorm_cdf(x, mu, sd, a, b):
    """CDF of normal(mu, sd) restricted to [a, b], from the normal CDF alone."""
    x = min(max(x, a), b)
    za, zb = _phi((a - mu) / sd), _phi((b - mu) / sd)
    return (_phi((x - mu) / sd) - za) / (zb - za)


OUTSIDE = [
    (
        {"distribution": "uniform", "low": 2.0, "high": 5.0},
        lambda lo, hi: (min(max(lo - 2.0, 0.0), 3.0) + min(max(5.0 - hi, 0.0), 3.0)) / 3.0,
    ),
    (
        {"distribution": "normal", "mean": 3.0, "std": 1.5},
        lambda lo, hi: _phi((lo - 3.0) / 1.5) + 1.0 - _phi((hi - 3.0) / 1.5),
    ),
    (
        {"distribution": "truncated_normal", "mean": 1.0, "std": 2.0, "low": 0.5, "high": 6.0},
        lambda lo, hi: _truncnorm_cdf(lo, 1.0, 2.0, 0.5, 6.0) + 1.0 - _truncnorm_cdf(hi, 1.0, 2.0, 0.5, 6.0),
    ),
    (
        {"distribution": "lognormal", "median": 3.0, "sigma": 0.5},
        lambda lo, hi: (
            (_phi(math.log(lo / 3.0) / 0.5) if lo > 0 else 0.0) + 1.0 - _phi(math.log(hi / 3.0) / 0.5)
        ),
    ),
]
INTERVALS = [(-math.inf, math.inf), (2.5, 4.0), (0.0, 1.5), (-1.0, 3.0), (4.0, 100.0), (10.0, 20.0)]


@pytest.mark.parametrize(
    "table,reference", OUTSIDE, ids=lambda x: x["distribution"] if isinstance(x, dict) else ""
)
def test_probability_outside_matches_the_closed_form(table, reference):
    d = from_dict(table, "test.x")
    for low, high in INTERVALS:
        expected = min(reference(low, high), 1.0)
        assert d.probability_outside(low, high) == pytest.approx(expected, rel=1e-9, abs=1e-15)


def test_probability_outside_agrees_with_the_fraction_of_draws():
    """The CDF-based probability and the inverse-CDF draws are separate code: a normal(1, 1)
    puts Phi(-1) = 0.1587 below 0, and so many of 1e5 draws do (binomial 5 sigma)."""
    table = {"distribution": "normal", "mean": 1.0, "std": 1.0}
    p = from_dict(table, "test.x").probability_outside(0.0, math.inf)
    x = draws(table)
    assert abs(np.mean(x < 0.0) - p) < 5 * math.sqrt(p * (1 - p) / N)
    assert p == pytest.approx(0.15865525393145707, rel=1e-12)


def test_probability_outside_of_discrete_families_counts_open_ends():
    c = from_dict({"distribution": "choice", "values": [0.0, 1.0, 2.0], "weights": [1, 1, 2]}, "test.x")
    assert c.probability_outside(0.0, 2.0) == 0.0
    assert c.probability_outside(0.0, 2.0, low_inclusive=False) == 0.25
    assert c.probability_outside(0.0, 2.0, high_inclusive=False) == 0.5
    e = from_dict({"distribution": "empirical", "values": [1.0, 1.0, 2.0, 5.0]}, "test.x")
    assert e.probability_outside(0.0, 3.0) == 0.25
    assert e.probability_outside(1.0, 5.0, low_inclusive=False) == 0.5
    with pytest.raises(TypeError):
        from_dict({"distribution": "choice", "values": ["a", "b"]}, "t").probability_outside(0, 1)


def test_distribution_error_is_a_scenario_error():
    """The command line reports ScenarioErrors in one line: a bad distribution table is one
    (it used to end in a traceback)."""
    from mineburial.errors import ScenarioError

    assert issubclass(DistributionError, ScenarioError)
