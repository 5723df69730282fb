"""The scour stage's burial law as a model-form input with a prior (issue 33, item 3): the law is
drawn with the scour block's coefficient sets, every set is run under its own law, the posterior
carries the evidence's weight on each law, and an ensemble draws either a named law's sets or each
drop's law with its set (docs/calibration.md, docs/scour.md "Calibration").

References: the binomial bound for the categorical draw's frequencies; the draws of the priors
without the law (the other blocks, bit for bit); Bayes' rule with a closed-form likelihood (a
Gaussian integrated over a uniform prior: scipy.stats.norm) for a two-law toy evidence; systematic
resampling's counts for the posterior restricted to a law; the same drop run under a section fixed to
its law (an invariance) for the per-drop law column."""

import dataclasses
import json
import math

import numpy as np
import pytest
import scipy.stats
from test_compare import short_default

from mineburial.ensembles import distributions as dist
from mineburial.ensembles import engine
from mineburial.errors import ScenarioError
from mineburial.kernels.mine import scour as scour_kernels
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine.calibration import calibrate, cases, conditioning, posterior, priors
from mineburial.systems.mine.processes import scour as scour_ensemble

LAW = "scour.burial_law"
LAWS = ("rennie", "scour_settle")


def _law_prior(weights=(1.0, 1.0)):
    d = dist.Choice(LAWS, tuple(w / sum(weights) for w in weights))
    return priors.Prior(LAW, d, "test")


# ---------------------------------------------------------------------------
# the prior and its draws
# ---------------------------------------------------------------------------
def test_the_shipped_priors_give_the_burial_law_an_even_choice_in_the_scour_block():
    (law,) = [p for p in priors.load_priors() if p.path == LAW]
    assert law.categorical and law.distribution.values == LAWS
    assert law.distribution.weights == (0.5, 0.5)
    assert calibrate.block_of(LAW) == "scour"


@pytest.mark.parametrize("weights", [(1.0, 1.0), (1.0, 3.0)])
def test_the_law_is_drawn_with_its_prior_frequencies(weights):
    """Each label's count among n draws lies within 4 binomial standard deviations of n p (the
    scrambled Sobol' stream is more even than independent draws, so the bound holds a fortiori)."""
    coefficients = tuple(p for p in priors.load_priors() if p.path != LAW) + (_law_prior(weights),)
    n = 4096
    draws = conditioning.draw_sets(coefficients, n, 11, calibrate.block_of)
    got = draws[LAW]
    assert set(np.unique(got)) == set(LAWS)
    for label, w in zip(LAWS, weights):
        p = w / sum(weights)
        count = int(np.sum(got == label))
        assert abs(count - n * p) <= 4.0 * math.sqrt(n * p * (1.0 - p)), (label, count)


def test_adding_the_law_prior_leaves_the_other_blocks_draws_bit_identical():
    """The impact block's coefficients and the impact cases' nuisance parameters are drawn from
    their own Sobol' stream: the same with and without the law's prior, bit for bit."""
    coefficients = priors.load_priors()
    _, nuisance = priors.load_evidence()
    assert any(p.path == LAW for p in coefficients)
    without = tuple(p for p in coefficients if p.path != LAW)
    full = conditioning.draw_sets((*coefficients, *nuisance), 256, 20261128, calibrate.block_of)
    less = conditioning.draw_sets((*without, *nuisance), 256, 20261128, calibrate.block_of)
    others = [p.path for p in (*without, *nuisance) if calibrate.block_of(p.path) != "scour"]
    assert len(others) >= 11
    for path in others:
        np.testing.assert_array_equal(full[path], less[path], err_msg=path)


def test_a_law_prior_with_an_unknown_label_or_posterior_is_refused(tmp_path):
    for values in (["rennie", "posterior"], ["rennie", "sumer"]):
        f = tmp_path / "p.toml"
        f.write_text(
            "[[coefficient]]\n"
            f'path = "{LAW}"\n'
            f'distribution = {{distribution = "choice", values = {json.dumps(values)}}}\n'
            'source = "test"\n'
        )
        with pytest.raises(ScenarioError, match=f"'{values[1]}' not one of rennie, scour_settle"):
            priors.load_priors(f)


# ---------------------------------------------------------------------------
# the case runs each set under its own law
# ---------------------------------------------------------------------------
def test_the_scour_case_runs_each_set_under_its_own_law():
    """A set's law, not the coefficients it carries, picks the law: with the same coefficients the
    case equals the validation's stage run under that law's kernel code."""
    coeffs = {"scour.beq_a": 1.3, "scour.wave_a": 0.4, "scour.wave_kc_exponent": 0.5}
    params = {"beq_a": 1.3, "wave_a": 0.4, "wave_kc_exp": 0.5}
    event = {**cases.vc.SCOUR_EVENTS["oahu"], "peak_tp": 12.0}
    fine = {"d50": cases.vc.SCOUR_FINE, "rho_grain": cases.vc.SCOUR_CARBONATE}
    got = {}
    for law, code in (
        ("rennie", scour_kernels.BURIAL_RENNIE),
        ("scour_settle", scour_kernels.BURIAL_SCOUR_SETTLE),
    ):
        got[law] = cases.scour_burial("oahu", {**coeffs, LAW: law}, 12.0)
        ref, _ = cases.vc.scour_final_burial(event, burial_law=float(code), **params, **fine)
        assert got[law] == ref
    assert got["rennie"] != got["scour_settle"]
    # without a law the stage's default (rennie), whatever coefficients the set carries
    assert cases.scour_burial("oahu", coeffs, 12.0) == got["rennie"]


# ---------------------------------------------------------------------------
# the posterior's weight on each law: Bayes with a closed-form likelihood
# ---------------------------------------------------------------------------
def test_two_law_toy_evidence_weighs_the_laws_as_bayes_rule():
    """Toy: under law A (scour_settle) the case gives y = c, c ~ U(0, 1); under law B (rennie)
    y = 0.6 whatever c; one row observes 0.7 with a Gaussian error s = 0.1. By hand:
    P(A | y) = L_A / (L_A + L_B) with L_A = int_0^1 N(0.7; c, s) dc = Phi(3) - Phi(-7) and
    L_B = N(0.7; 0.6, s) = phi(1)/s (equal prior odds); c | A is N(0.7, s) truncated to [0, 1];
    the Kish effective sample size of A's sets is n_A (int f)^2 / int f^2 with f the Gaussian
    kernel in c. The calibration's importance weights must give the same."""
    s, obs = 0.1, 0.7
    c_prior = priors.Prior("scour.wave_a", dist.Uniform(0.0, 1.0), "test")
    law_prior = _law_prior()
    coefficients = (c_prior, law_prior)
    n = 4096
    draws = conditioning.draw_sets(coefficients, n, 3, calibrate.block_of)
    law, c = draws[LAW], draws["scour.wave_a"]
    y = np.where(law == "scour_settle", c, 0.6)
    row = priors.EvidenceRow("toy", "scour_bands", "oahu", "burial_fraction", obs, "1", "", "", sigma=s)
    _, block_w, report = calibrate.condition(coefficients, (), (row,), draws, y[:, None, None], 3)
    norm = scipy.stats.norm
    l_a = norm.cdf((1.0 - obs) / s) - norm.cdf((0.0 - obs) / s)
    l_b = norm.pdf((0.6 - obs) / s) / s
    p_a = l_a / (l_a + l_b)
    choice = report["choices"][LAW]
    assert choice["scour_settle"]["posterior"] == pytest.approx(p_a, abs=0.01)
    assert choice["rennie"]["posterior"] == pytest.approx(1.0 - p_a, abs=0.01)
    assert report["posterior"][LAW]["scour_settle"] == pytest.approx(p_a, abs=0.01)
    # c among law A's sets: the truncated normal's median
    lo, hi = norm.cdf(-obs / s), norm.cdf((1.0 - obs) / s)
    median = obs + s * norm.ppf(0.5 * (lo + hi))
    assert choice["scour_settle"]["coefficients"]["scour.wave_a"]["median"] == pytest.approx(median, abs=0.01)
    # the effective sample sizes within each law
    n_a = int(np.sum(law == "scour_settle"))
    f1 = s * math.sqrt(2.0 * math.pi) * l_a  # int_0^1 exp(-(c - 0.7)^2 / (2 s^2)) dc
    f2 = s * math.sqrt(math.pi) * (norm.cdf(0.3 * math.sqrt(2.0) / s) - norm.cdf(-0.7 * math.sqrt(2.0) / s))
    assert choice["scour_settle"]["ess"] == pytest.approx(n_a * f1 * f1 / f2, rel=0.03)
    assert choice["rennie"]["ess"] == pytest.approx(n - n_a, rel=1e-9)  # equal weights within B
    assert choice["rennie"]["prior_sets"] + n_a == n
    np.testing.assert_allclose(block_w["scour"].sum(), 1.0)
    text = calibrate.report_text({**_record_stub(), "report": report, "distinct_sets": {"scour": 1}})
    assert "### scour.burial_law" in text and f"{p_a:.3f}" in text


def _record_stub():
    return {
        "created": "now",
        "mineburial_version": "test",
        "seed": 3,
        "priors_sha256": "0" * 64,
        "evidence_sha256": "0" * 64,
        "method": "test",
        "weights": [1.0],
    }


# ---------------------------------------------------------------------------
# ensembles: a named law draws its own sets; "posterior" draws each drop's law
# ---------------------------------------------------------------------------
def _posterior_file(tmp_path, n=64, seed=2, n_rennie=None):
    """A posterior file: rate_coefficient (impact) and the scour block's a and law, equal weights;
    each set's law drawn at even odds, or ``n_rennie`` sets of rennie."""
    rng = np.random.default_rng(seed)
    laws = np.where(rng.random(n) < 0.5, "scour_settle", "rennie")
    if n_rennie is not None:
        laws = np.where(np.arange(n) < n_rennie, "rennie", "scour_settle")
    rate = rng.uniform(0.0, 0.25, n)
    a = rng.uniform(0.8, 2.0, n)
    record = {
        "format": "mineburial-posterior",
        "format_version": 2,
        "coefficients": ["sediment.rate_coefficient", "scour.beq_a", LAW],
        "labels": {LAW: list(LAWS)},
        "sets": [[float(r), float(x), str(w)] for r, x, w in zip(rate, a, laws)],
        "weights": [1.0 / n] * n,
    }
    path = tmp_path / "post.json"
    path.write_text(json.dumps(record))
    return path, laws, rate, a


def test_a_posterior_restricted_to_a_law_keeps_the_impact_block_and_resamples_that_laws_sets(tmp_path):
    path, laws, rate, a = _posterior_file(tmp_path)
    post = posterior.load(str(path))
    assert posterior.law_probabilities(post) == pytest.approx(
        {k: float(np.mean(laws == k)) for k in LAWS}, abs=1e-12
    )
    for k, law in enumerate(LAWS):
        r = posterior.restricted(post, law)
        np.testing.assert_array_equal(r.table[:, 0], rate)  # each set keeps its impact coefficients
        np.testing.assert_array_equal(r.weights, post.weights)
        assert np.all(r.table[:, 2] == k)
        of_law = np.flatnonzero(laws == law)
        np.testing.assert_array_equal(r.table[of_law, 1], a[of_law])  # a set of the law keeps its own
        # every set's scour coefficients are those of one set of the law, each of the law's m sets
        # serving n/m sets to within one (itself, and the others' systematically at (j + 1/2)/(n - m))
        src = [of_law[np.flatnonzero(a[of_law] == v)[0]] for v in r.table[:, 1]]
        counts = np.bincount(np.searchsorted(of_law, src), minlength=of_law.size)
        assert counts.sum() == laws.size
        assert np.all(np.abs(counts - laws.size / of_law.size) < 1.0 + 1e-9)


@pytest.mark.parametrize(
    "section, drawn",
    [
        (None, []),  # no [scour]: the stage does not run
        ({}, ["scour.beq_a"]),  # rennie by default: rennie's sets
        ({"burial_law": "rennie"}, ["scour.beq_a"]),
        ({"burial_law": "scour_settle"}, ["scour.beq_a"]),
        ({"burial_law": "scour_settle", "beq_a": 1.1}, []),  # one the section gives is kept
        ({"burial_law": "posterior"}, ["scour.beq_a", LAW]),  # the law and its coefficients per drop
        ({"burial_law": "posterior", "beq_a": 1.1}, [LAW]),
    ],
)
def test_what_a_section_draws_from_a_posterior_with_a_law_per_set(tmp_path, section, drawn):
    path, *_ = _posterior_file(tmp_path)
    post = posterior.load(str(path))
    raw = {"sediment": {}} if section is None else {"sediment": {}, "scour": section}
    got, paths = posterior.for_scenario(post, raw)
    assert [p for p in paths if p.startswith("scour.")] == drawn
    assert "sediment.rate_coefficient" in paths
    law = None if section is None else section.get("burial_law", "rennie")
    assert got.scour_law == (law if law in LAWS else None)


def test_a_law_the_evidence_leaves_without_sets_draws_nothing_and_says_so(tmp_path, capsys):
    path, laws, *_ = _posterior_file(tmp_path, n=200, n_rennie=1)
    assert 0 < np.sum(laws == "rennie") < posterior.LAW_FLOOR * laws.size
    post = posterior.load(str(path))
    got, paths = posterior.for_scenario(post, {"scour": {"burial_law": "rennie"}})
    assert got.scour_law is None and not [p for p in paths if p.startswith("scour.")]
    err = capsys.readouterr().err
    assert "scour.burial_law = 'rennie' has posterior probability" in err


def test_burial_law_posterior_needs_a_posterior_with_a_law_per_set(tmp_path):
    with pytest.raises(ScenarioError, match="ensemble.coefficients = 'posterior'"):
        posterior.for_scenario(None, {"scour": {"burial_law": "posterior"}})
    path, *_ = _posterior_file(tmp_path)
    record = json.loads(path.read_text())  # a file of before the law had a prior
    record["coefficients"] = record["coefficients"][:2]
    record["sets"] = [row[:2] for row in record["sets"]]
    record["labels"] = {}
    path.write_text(json.dumps(record))
    old = posterior.load(str(path))
    with pytest.raises(ScenarioError, match="carries no law per set"):
        posterior.for_scenario(old, {"scour": {"burial_law": "posterior"}})
    # its scour coefficients stay those of the law they were conditioned under (legacy rule)
    assert posterior.scour_law(old.paths) == "rennie"
    assert posterior.for_scenario(old, {"scour": {}})[1] == ("sediment.rate_coefficient", "scour.beq_a")
    assert posterior.for_scenario(old, {"scour": {"burial_law": "scour_settle"}})[1] == (
        "sediment.rate_coefficient",
    )


def _law_scenario(path, law, n=12):
    raw = short_default(n)
    raw["ensemble"]["coefficients"] = str(path)
    raw["sediment"] = {"class": "sand"}
    storm = {"peak_hs": 2.5, "peak_tp": 10.0, "duration_h": 48.0, "current": 0.3}
    raw["scour"] = {"storm": storm, "lead_times_days": [0.5, 1.0, 2.0], "burial_law": law}
    return raw


def test_each_drops_law_reaches_the_stage_as_under_a_section_fixed_to_it(tmp_path):
    """Invariance: under burial_law = "posterior" a drop whose set has law L gives, bit for bit, the
    stage results of the same drop under a section fixed to L (a set of law L keeps its own scour
    coefficients in the posterior restricted to L); the two laws give different burials."""
    path, *_ = _posterior_file(tmp_path, n=16)
    runs = {}
    for law in ("posterior", *LAWS):
        spec = engine.load_ensemble(_law_scenario(path, law))
        runs[law] = engine.compute_chunk(spec, 0, spec.n)
    per_drop = runs["posterior"]["input:" + LAW]
    assert set(np.unique(per_drop)) == {0.0, 1.0}  # both laws among the drops
    for k, law in enumerate(LAWS):
        m = per_drop == k
        for key in ("scour:measures", "scour:pit", "scour:time_to", "scour:status"):
            np.testing.assert_array_equal(runs["posterior"][key][m], runs[law][key][m], err_msg=(law, key))
        np.testing.assert_array_equal(runs["posterior"]["summary"], runs[law]["summary"])
        a = "input:scour.beq_a"  # the drop's own set's a under either section
        np.testing.assert_array_equal(runs["posterior"][a][m], runs[law][a][m])
    ok = runs["rennie"]["scour:status"] == 0
    assert ok.any()
    diff = runs["rennie"]["scour:measures"][ok] != runs["scour_settle"]["scour:measures"][ok]
    assert diff.any()


def test_stage_parameters_fill_the_law_slot_from_the_drops_column():
    spec = dataclasses.replace(_minimal_stage(), conventions={"burial_law": "posterior"})
    P = _params(3)
    S, _ = scour_ensemble.stage_parameters(spec, P, {LAW: np.array([1.0, 0.0, 1.0])})
    np.testing.assert_array_equal(S[:, scour_kernels.S_BURIAL_LAW], [1.0, 0.0, 1.0])
    with pytest.raises(ScenarioError, match="draws each drop's law from a posterior"):
        scour_ensemble.stage_parameters(spec, P, {})
    assert "wave_a" in spec.resolved()  # some drops read the scour-and-settle coefficients


def _minimal_stage():
    storm = {"peak_hs": 1.0, "peak_tp": 8.0, "duration_h": 12.0}
    return scour_ensemble.parse({"storm": storm, "d50": 2.0e-4})


def _params(n):
    spec = engine.load_ensemble({**short_default(n), "ensemble": {"n": n}})
    return mine.chunk_inputs(spec, 0, n)[0]


def test_the_per_drop_law_is_written_with_the_kernels_codes(tmp_path):
    """The sampled input scour.burial_law names its codes as the stage's kernel defines them."""
    from mineburial.systems.mine.ensemble import input_metadata

    path, *_ = _posterior_file(tmp_path)
    spec = engine.load_ensemble(_law_scenario(path, "posterior", n=4))
    assert LAW in spec.posterior_paths
    codes = f"{scour_kernels.BURIAL_RENNIE} rennie, {scour_kernels.BURIAL_SCOUR_SETTLE} scour_settle"
    assert input_metadata(spec, LAW) == ("1", f"code of {LAW}: {codes}")
