"""Reproducible per-drop uniforms (Philox Monte Carlo and scrambled Sobol').

Independent references: the Random123 known-answer vectors for Philox4x64-10
(Salmon et al. 2011, ``tests/kat_vectors`` of Random123 1.09), numpy's own
``numpy.random.Philox`` raw stream, hashlib BLAKE2b, and the (0, m, s)-net
stratification property of Sobol' points (Sobol' 1967; Dick & Pillichshammer
2010, Thm 4.10 for the first two dimensions).
"""

import hashlib
import math
import warnings

import numpy as np
import pytest
from scipy import stats

from mineburial.ensembles import sampling
from mineburial.ensembles.distributions import Normal
from mineburial.ensembles.sampling import (
    SobolBalanceWarning,
    check_drop_count,
    field_id,
    sample_fields,
    uniforms,
)

SEED = 987654321
FIELDS = ["mine.mass", "mine.length", "release.z", "sediment.strength"]


# --- the generator itself ---------------------------------------------------

# Random123 tests/kat_vectors, "philox4x64 10": counter (4 words), key (2 words) -> output
KAT = [
    ([0, 0, 0, 0], [0, 0], [0x16554D9ECA36314C, 0xDB20FE9D672D0FDC, 0xD7E772CEE186176B, 0x7E68B68AEC7BA23B]),
    (
        [2**64 - 1] * 4,
        [2**64 - 1] * 2,
        [0x87B092C3013FE90B, 0x438C3C67BE8D0224, 0x9CC7D7C69CD777B6, 0xA09CAEBF594F0BA0],
    ),
    (
        [0x243F6A8885A308D3, 0x13198A2E03707344, 0xA4093822299F31D0, 0x082EFA98EC4E6C89],
        [0x452821E638D01377, 0xBE5466CF34E90C6C],
        [0xA528F45403E61D95, 0x38C72DBD566E9788, 0xA5A1610E72FD18B5, 0x57BD43B5E52B7FE6],
    ),
]


@pytest.mark.parametrize("ctr,key,expected", KAT)
def test_philox_known_answers(ctr, key, expected):
    out = sampling._philox4x64_10(*(np.uint64(x) for x in ctr + key))
    assert [int(x) for x in out] == expected


def test_mc_stream_is_numpy_philox_keyed_by_seed_and_field():
    for name in ("mine.mass", "environment.water_depth"):
        key = np.array([SEED, field_id(name)], dtype=np.uint64)
        raw = np.random.Philox(key=key).random_raw(1003)
        ref = ((raw >> np.uint64(12)).astype(np.float64) + 0.5) * 2.0**-52
        u = uniforms(SEED, [name], 0, 1003)[:, 0]
        np.testing.assert_array_equal(u, ref)
        np.testing.assert_array_equal(uniforms(SEED, [name], 517, 1003)[:, 0], ref[517:])


def test_mc_uniforms_open_interval_53_bit_grid():
    u = uniforms(1, FIELDS, 0, 50_000)
    assert u.shape == (50_000, 4) and u.dtype == np.float64 and u.flags.c_contiguous
    assert np.all((u > 0.0) & (u < 1.0))
    k = u * 2.0**53  # exact: odd integers below 2**53
    assert np.all(k == np.round(k)) and np.all(k % 2 == 1)
    assert stats.kstest(u.ravel(), "uniform").pvalue > 0.01


def test_field_id_is_blake2b_of_the_name():
    name = "sediment.strength"
    ref = int.from_bytes(hashlib.blake2b(name.encode(), digest_size=8).digest(), "little")
    assert field_id(name) == ref
    # names, not positions: passing the id or the name gives the same column
    np.testing.assert_array_equal(uniforms(3, [ref], 0, 10), uniforms(3, [name], 0, 10))


# --- reproducibility --------------------------------------------------------


@pytest.mark.parametrize("method", ["mc", "sobol"])
def test_chunk_invariance_bit_for_bit(method):
    whole = uniforms(SEED, FIELDS, 0, 1000, method)
    two = np.concatenate([uniforms(SEED, FIELDS, 0, 300, method), uniforms(SEED, FIELDS, 300, 1000, method)])
    odd = np.concatenate(
        [uniforms(SEED, FIELDS, a, b, method) for a, b in [(0, 1), (1, 7), (7, 64), (64, 999), (999, 1000)]]
    )
    assert whole.tobytes() == two.tobytes() == odd.tobytes()
    # any single drop can be re-drawn on its own
    np.testing.assert_array_equal(uniforms(SEED, FIELDS, 613, 614, method)[0], whole[613])


@pytest.mark.parametrize("method", ["mc", "sobol"])
def test_sample_fields_chunk_invariance_all_families(method):
    spec = {
        "mine.mass": {"distribution": "normal", "mean": 500.0, "std": 25.0},
        "mine.length": {"distribution": "uniform", "low": 1.0, "high": 3.0},
        "release.z": {"distribution": "truncated_normal", "mean": 10, "std": 3, "low": 5, "high": 20},
        "sediment.strength": {"distribution": "lognormal", "median": 2e3, "sigma": 0.4},
        "sediment.class": {"distribution": "choice", "values": ["clay", "sand"]},
        "sediment.density": {"distribution": "empirical", "values": [1500.0, 1600.0, 1800.0]},
        "environment.water_depth": 30.0,
    }
    whole = sample_fields(spec, SEED, 0, 1000, method)
    a = sample_fields(spec, SEED, 0, 300, method)
    b = sample_fields(spec, SEED, 300, 1000, method)
    for name in spec:
        assert np.concatenate([a[name], b[name]]).tobytes() == whole[name].tobytes(), name
    assert np.all(whole["environment.water_depth"] == 30.0)


@pytest.mark.parametrize("method", ["mc", "sobol"])
def test_different_seeds_differ(method):
    a = uniforms(1, FIELDS, 0, 256, method)
    b = uniforms(2, FIELDS, 0, 256, method)
    assert not np.any(a == b)


def test_fields_are_distinct_streams():
    u = uniforms(SEED, FIELDS, 0, 10_000)
    r = np.corrcoef(u.T)
    assert np.all(np.abs(r[np.triu_indices(4, 1)]) < 4 / math.sqrt(10_000))


def test_adding_a_field_leaves_other_mc_draws_unchanged():
    spec = {
        "mine.mass": Normal(500.0, 25.0),
        "sediment.strength": {"distribution": "lognormal", "median": 2e3, "sigma": 0.4},
    }
    before = sample_fields(spec, SEED, 0, 500)
    grown = {
        "release.psi2_deg": {"distribution": "uniform", "low": 0, "high": 90},
        **spec,
        "current.u": {"distribution": "normal", "mean": 0.0, "std": 0.2},
    }
    after = sample_fields(grown, SEED, 0, 500)
    for name in spec:
        np.testing.assert_array_equal(after[name], before[name])


def test_sobol_depends_on_the_field_set_not_its_order():
    a = uniforms(SEED, FIELDS, 0, 128, "sobol")
    perm = [2, 0, 3, 1]
    b = uniforms(SEED, [FIELDS[i] for i in perm], 0, 128, "sobol")
    np.testing.assert_array_equal(b, a[:, perm])


# --- Sobol' structure -------------------------------------------------------


def test_sobol_open_interval_and_one_point_per_cell():
    m = 12
    n = 2**m
    u = uniforms(SEED, ["a.x", "a.y"], 0, n, "sobol")
    assert np.all((u > 0) & (u < 1))
    # every one-dimensional projection: one point in each [j/n, (j+1)/n)
    for k in range(2):
        assert np.array_equal(np.sort(np.floor(u[:, k] * n).astype(np.int64)), np.arange(n))
    # first two Sobol' dimensions form a (0, m, 2)-net: one point per elementary box
    for a in range(m + 1):
        cell = np.floor(u[:, 0] * 2**a).astype(np.int64) * 2 ** (m - a) + np.floor(
            u[:, 1] * 2 ** (m - a)
        ).astype(np.int64)
        assert np.array_equal(np.sort(cell), np.arange(n)), a


def test_sobol_marginals_are_continuous_uniform():
    u = uniforms(SEED, FIELDS, 4096, 4096 + 2**14, "sobol")
    assert len(np.unique(u)) == u.size  # no 2**-32 grid ties
    for k in range(u.shape[1]):
        assert stats.kstest(u[:, k], "uniform").pvalue > 0.01


def test_sobol_empirical_choice_is_exactly_balanced():
    s = sample_fields(
        {"sediment.density": {"distribution": "empirical", "values": [1.0, 2.0, 3.0, 4.0]}},
        SEED,
        0,
        4096,
        "sobol",
    )
    np.testing.assert_array_equal(np.unique(s["sediment.density"], return_counts=True)[1], [1024] * 4)


def test_sobol_integrates_smooth_functions_better_than_mc():
    n, d = 2**12, 5
    names = [f"x.u{k}" for k in range(d)]
    err = {"mc": [], "sobol": []}
    for seed in range(8):
        for method in err:
            u = uniforms(seed, names, 0, n, method)
            # prod_k (1 + (u_k - 1/2)) has integral exactly 1 over the unit cube
            err[method].append(np.mean(np.prod(1.0 + (u - 0.5), axis=1)) - 1.0)
    rmse = {k: math.sqrt(np.mean(np.square(v))) for k, v in err.items()}
    assert rmse["sobol"] < rmse["mc"] / 10
    # the mean of a normal ppf: exactly the normal mean
    spec = {"mine.mass": Normal(500.0, 25.0)}
    e = {m: abs(sample_fields(spec, 5, 0, n, m)["mine.mass"].mean() - 500.0) for m in err}
    assert e["sobol"] < 0.01 * 25.0 / math.sqrt(n) and e["sobol"] < e["mc"]


def test_check_drop_count_warns_for_non_power_of_two():
    with pytest.warns(SobolBalanceWarning, match=r"n_drops = 1000 is not a power of two.*use 512 or 1024"):
        check_drop_count(1000, "sobol")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_drop_count(1024, "sobol")
        check_drop_count(1000, "mc")
        uniforms(1, FIELDS, 0, 1000, "sobol")  # chunks never warn


# --- errors -------------------------------------------------------


def test_argument_errors():
    with pytest.raises(ValueError, match=r"unknown sampling method 'qmc'; available methods are mc, sobol"):
        uniforms(1, FIELDS, 0, 10, "qmc")
    with pytest.raises(ValueError, match=r"seed = -1 must be in \[0, 2\*\*64\)"):
        uniforms(-1, FIELDS, 0, 10)
    with pytest.raises(ValueError, match=r"\[start, stop\) = \[10, 5\)"):
        uniforms(1, FIELDS, 10, 5)
    with pytest.raises(ValueError, match="distinct"):
        uniforms(1, ["a", "a"], 0, 10)
    with pytest.raises(ValueError, match=r"mine\.mass: std = 0 must be > 0"):
        sample_fields({"mine.mass": {"distribution": "normal", "mean": 1, "std": 0}}, 1, 0, 10)
    assert uniforms(1, [], 0, 5).shape == (5, 0) and uniforms(1, FIELDS, 5, 5, "sobol").shape == (0, 4)
