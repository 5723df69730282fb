"""The truncated normal without scipy.stats: its draws are a public contract.

The sampled inputs of an existing (scenario, seed, drop index) must not change, and until
issue 9 they were ``np.clip(scipy.stats.truncnorm.ppf(u, a, b, loc=mean, scale=std), low,
high)``. :class:`TruncatedNormal` now computes them with scipy.special alone (importing
scipy.stats cost ~0.5 s of every start-up). Reference here: scipy.stats itself, compared
with ``np.array_equal`` (bit for bit, not approximately) on >= 1e5 uniforms per interval,
including u = 0, 1, the extremes the samplers produce (2**-53 and 1 - 2**-53 for Monte
Carlo) and u far into both tails; mean and probability outside against scipy.stats to
1e-12 relative.
"""

import math
import subprocess
import sys

import numpy as np
import pytest
import tomllib
from scipy import stats

from mineburial.ensembles.distributions import LogNormal, TruncatedNormal, from_dict
from mineburial.ensembles.sampling import sample_fields, uniforms

INF = math.inf


def _uniforms():
    """1e5 uniforms, plus the ends, the samplers' extremes and both far tails."""
    rng = np.random.default_rng(20261124)
    bulk = rng.random(100_000)
    special_points = [
        0.0,
        1.0,
        0.5,
        2.0**-53,
        1.0 - 2.0**-53,
        2.0**-32,
        1.0 - 2.0**-32,
        np.nextafter(0.0, 1.0),
        np.nextafter(1.0, 0.0),
        1e-300,
        1e-100,
        1e-20,
        1.0 - 1e-12,
    ]
    tails = rng.random(2_000) ** 40  # down to ~1e-100 and below
    return np.concatenate([bulk, special_points, tails, 1.0 - tails, 2.0 ** -rng.integers(1, 1075, 500)])


U = _uniforms()

# (mean, std, low, high): a = (low - mean)/std, b = (high - mean)/std
INTERVALS = {
    "central": (1.0, 2.0, 0.0, 4.0),
    "central_symmetric": (0.0, 1.0, -2.0, 2.0),
    "central_wide": (0.0, 1.0, -40.0, 40.0),
    "left_of_mode": (0.0, 1.0, -3.0, -0.5),
    "right_of_mode": (0.0, 1.0, 0.5, 3.0),
    "a_zero": (0.0, 1.0, 0.0, 2.0),
    "b_zero": (0.0, 1.0, -2.0, 0.0),
    "low_only": (0.0, 1.0, 1.5, INF),
    "low_only_below_mode": (0.0, 1.0, -1.5, INF),
    "high_only": (0.0, 1.0, -INF, -1.5),
    "high_only_above_mode": (5.0, 2.0, -INF, 6.0),
    "half_normal": (0.0, 1.0, 0.0, INF),
    "far_right_8": (0.0, 1.0, 8.0, INF),
    "far_right_15": (0.0, 1.0, 15.0, INF),
    "far_right_30": (0.0, 1.0, 30.0, INF),
    "far_left_8": (0.0, 1.0, -INF, -8.0),
    "far_left_15": (0.0, 1.0, -INF, -15.0),
    "far_left_30": (0.0, 1.0, -INF, -30.0),
    "far_right_window": (0.0, 1.0, 30.0, 31.0),
    "far_left_window": (0.0, 1.0, -31.0, -30.0),
    "narrow_central": (0.0, 1.0, -1e-3, 1e-3),
    "narrow_left": (0.0, 1.0, -1.001, -1.0),
    "narrow_right": (30.0, 1.0, 29.999, 30.0),
    "tiny_width_right": (0.0, 1.0, 1.0, 1.0 + 1e-12),
    "tiny_width_left": (0.0, 1.0, -1.0 - 1e-9, -1.0),
    "scaled": (-20.0, 5.0, 0.0, 30.0),
    "one_sided_mass": (750.0, 15.0, 760.0, INF),
    "one_sided_speed": (4.0, 0.5, -INF, 3.0),
}


def _reference_ppf(u, mean, std, low, high):
    a, b = (low - mean) / std, (high - mean) / std
    return np.clip(stats.truncnorm.ppf(u, a, b, loc=mean, scale=std), low, high)


@pytest.mark.parametrize("mean,std,low,high", INTERVALS.values(), ids=INTERVALS.keys())
def test_ppf_is_bit_identical_to_scipy_stats(mean, std, low, high):
    d = TruncatedNormal(mean, std, low, high)
    got = d.ppf(U)
    expected = _reference_ppf(U, mean, std, low, high)
    assert got.dtype == np.float64 and got.shape == U.shape
    assert not np.any(np.isnan(expected))  # numbers (u = 1 gives an infinite bound) to compare
    assert np.array_equal(got, expected)
    # scalars, and uniforms outside [0, 1] (NaN, as scipy gives)
    for u in (0.0, 1.0, 0.5, 2.0**-53):
        assert np.array_equal(d.ppf(u), _reference_ppf(u, mean, std, low, high))
    bad = np.array([-0.25, 1.5, np.nan])
    assert np.array_equal(d.ppf(bad), _reference_ppf(bad, mean, std, low, high), equal_nan=True)


def _embedded_truncated_normals():
    """Every truncated_normal table in the embedded default ensemble and the examples."""
    from mineburial.systems.mine.config import ensemble_example_names, example_names, example_path
    from mineburial.systems.mine.ensemble import DEFAULT_SCENARIO
    from mineburial.systems.restraint import ensemble as restraint_ensemble
    from mineburial.systems.restraint import model as restraint

    texts = {"default": DEFAULT_SCENARIO.read_text()}
    for name in example_names() + ensemble_example_names():
        texts[name] = example_path(name).read_text()
    texts[restraint_ensemble.EXAMPLE_NAME] = restraint_ensemble.example_text()
    for name in restraint.example_names():
        texts[name] = restraint.example_text(name)

    found = {}

    def walk(node, path):
        if isinstance(node, dict):
            if node.get("distribution") == "truncated_normal":
                found[path] = node
            for key, value in node.items():
                walk(value, f"{path}.{key}")
        elif isinstance(node, list):
            for i, value in enumerate(node):
                walk(value, f"{path}[{i}]")

    for name, text in texts.items():
        walk(tomllib.loads(text), name)
    return found


EMBEDDED = _embedded_truncated_normals()


def test_the_default_ensemble_has_truncated_normals():
    """Guards the next test against an empty list: the default ensemble draws the current
    speed and the sediment density from truncated normals."""
    assert "default.environment.current.surface_velocity[0]" in EMBEDDED
    assert "default.sediment.density" in EMBEDDED


@pytest.mark.parametrize("path", sorted(EMBEDDED))
def test_embedded_scenarios_sample_as_scipy_stats_did(path):
    """Through the sampler itself: the drawn column equals scipy's quantile of the very
    uniforms :func:`uniforms` gives that field, for Monte Carlo and Sobol' draws."""
    table = EMBEDDED[path]
    d = from_dict(table, path)
    for method in ("mc", "sobol"):
        u = uniforms(20261122, [path], 0, 100_000, method)[:, 0]
        drawn = sample_fields({path: table}, 20261122, 0, 100_000, method)[path]
        assert np.array_equal(drawn, _reference_ppf(u, d.mu, d.std, d.low, d.high))


@pytest.mark.parametrize("mean,std,low,high", INTERVALS.values(), ids=INTERVALS.keys())
def test_mean_matches_scipy_stats(mean, std, low, high):
    d = TruncatedNormal(mean, std, low, high)
    a, b = (low - mean) / std, (high - mean) / std
    if high - low < 1e-5 * std:
        # phi(a) - phi(b) and Z are both left to rounding (scipy's too): only the
        # bounds of the mean are exact
        assert low <= d.mean() <= high
        return
    expected = float(stats.truncnorm.mean(a, b, loc=mean, scale=std))
    assert d.mean() == pytest.approx(expected, rel=1e-12, abs=1e-12 * std)


@pytest.mark.parametrize("mean,std,low,high", INTERVALS.values(), ids=INTERVALS.keys())
def test_probability_outside_matches_scipy_stats(mean, std, low, high):
    d = TruncatedNormal(mean, std, low, high)
    a, b = (low - mean) / std, (high - mean) / std
    ref = stats.truncnorm(a, b, loc=mean, scale=std)
    # ends inside the interval, at its bounds and outside it
    cuts = [ref.ppf(p) for p in (1e-12, 1e-6, 0.01, 0.3, 0.7, 0.99, 1 - 1e-6)]
    # Z = Phi(b) - Phi(a) from two rounded CDFs has a relative error ~1e-16 std / width
    # (scipy's too): an interval 1e-12 std wide resolves its CDF to ~1e-4 only
    rel = max(1e-12, 1e-14 * std / (high - low))
    ends = [-INF, low, high, INF, *(low - s for s in (1.0, 1e3)), *(high + s for s in (1.0, 1e3)), *cuts]
    for lo in ends:
        for hi in ends:
            if not lo <= hi:
                continue
            expected = min(float(ref.cdf(lo) + ref.sf(hi)), 1.0)
            got = d.probability_outside(lo, hi)
            assert got == pytest.approx(expected, rel=rel, abs=1e-300), (lo, hi)


def test_lognormal_probability_outside_matches_scipy_stats():
    d = LogNormal(2000.0, 0.4)
    ref = stats.lognorm(s=0.4, scale=2000.0)
    ends = [-INF, -1.0, 0.0, 1e-300, 1.0, 500.0, 2000.0, 5000.0, 1e5, INF]
    for lo in ends:
        for hi in ends:
            if lo <= hi:
                expected = min(float(ref.cdf(lo) + ref.sf(hi)), 1.0)
                assert d.probability_outside(lo, hi) == pytest.approx(expected, rel=1e-12, abs=1e-300)


def test_construction_refuses_what_scipy_stats_could_not_invert():
    """The constructor's finiteness probe: 40 std beyond the mean still inverts (log
    space); 40 std with an upper bound a hair above it does too; an interval out where
    even ln Phi underflows does not, as with scipy.stats."""
    ok = from_dict({"distribution": "truncated_normal", "mean": 0.0, "std": 1.0, "low": 40.0}, "x")
    assert np.all(np.isfinite(ok.ppf(np.array([2.0**-53, 0.5, 1 - 2.0**-53]))))
    far = 1e160  # -far**2/2 overflows: ln Phi(-far) = -inf
    with np.errstate(all="ignore"):
        probe = stats.truncnorm.ppf([2.0**-53, 0.5, 1 - 2.0**-53], far, far + 1e150)
    assert not np.all(np.isfinite(probe))
    with pytest.raises(ValueError, match=r"x: \[low, high\] .* carries no probability"):
        from_dict(
            {"distribution": "truncated_normal", "mean": 0.0, "std": 1.0, "low": far, "high": far + 1e150},
            "x",
        )


def test_start_up_does_not_import_scipy_stats():
    """Issue 9: importing scipy.stats costs ~0.5 s of every run; loading the default
    ensemble (which has truncated normals and lognormals, all checked against their
    fields' ranges) and sampling a chunk must not pull it in."""
    code = (
        "import sys\n"
        "import mineburial\n"
        "from mineburial.ensembles.engine import load_ensemble\n"
        "from mineburial.systems.mine.ensemble import chunk_inputs\n"
        "spec = load_ensemble(None)\n"
        "chunk_inputs(spec, 0, 64)\n"
        "assert 'scipy.stats' not in sys.modules, [m for m in sys.modules if m.startswith('scipy.stats')]\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]
