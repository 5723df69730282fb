"""The calibration of issue 32: priors, evidence, importance sampling, the shipped posterior,
ensembles that draw from it and the epistemic band (docs/calibration.md).

References: the engine's own floor event (a separate event locator) for the cut Exp-1
trajectories; the validation's implementations of the Exp-1 patterns; scipy.integrate for a
one-dimensional posterior; scipy.stats.beta for the band; the Beta-binomial variance for the
random-effects estimator; the Philox streams of the seed contract."""

import json
import math

import numpy as np
import pytest
import scipy.integrate
import scipy.stats
import xarray as xr
from test_compare import short_default

from mineburial.ensembles import distributions as dist
from mineburial.ensembles import engine
from mineburial.ensembles.sampling import uniforms
from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import epistemic
from mineburial.systems.mine.calibration import calibrate, cases, conditioning, posterior, priors
from mineburial.systems.mine.drop import run_params
from mineburial.validation import cases as vc


# ---------------------------------------------------------------------------
# the evidence cases
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("water_column", ["munk_factor", "viscous_crossflow"])
@pytest.mark.parametrize("variant", ["exp1_case92", "exp1_case93"])
def test_cut_trajectory_reaches_each_floor_when_the_engine_does(variant, water_column):
    """One drop to a deep floor, cut where the lowest point crosses a shallower floor, gives
    the travel time the engine's own floor event gives with the floor there."""
    depths = np.array([1.2, 2.0, 2.4])
    coeffs = {"numerics.water_column": water_column}
    _, got = cases.run_case("exp1", variant, {}, {"pool_depth": depths}, coeffs)
    for depth, travel in zip(depths, got["travel_time"]):
        p, sed, cur = cases._exp1(variant, depth).to_params()
        _, summary, _ = run_params(cases.apply_coefficients(p, coeffs), sed, cur)
        engine_travel = summary[layout.S_IMPACT_TIME] - summary[layout.S_ENTRY_TIME]
        assert travel == pytest.approx(engine_travel, abs=1e-4)


@pytest.mark.parametrize("variant", ["exp1_case92", "exp1_case93"])
def test_exp1_patterns_agree_with_the_validation_rows(variant):
    """Straightness, flip and turning on the whole water column agree with the validation's
    implementations (validation.cases) on its drop at its pool depth."""
    ds = vc._exp1_drop(variant, "mineburial", "munk_factor")
    traj = np.stack([ds[c].values for c in ("x", "y", "z")], axis=1)
    m, te, ti = vc._water_column(ds)
    assert cases._straightness(traj[m]) == pytest.approx(vc._straightness(ds), rel=1e-12)
    psi2 = np.radians(ds.psi2.values[m])
    ours = cases._flip_time(ds.time.values[m], psi2)
    theirs = vc._flip_time(ds)
    assert (ours is None) == (theirs is None)
    if ours is not None:
        assert ours - te == pytest.approx(theirs, abs=1e-9)


def test_apply_coefficients_writes_labels_as_codes():
    p = np.zeros(layout.N_PARAMS)
    q = cases.apply_coefficients(p, {"numerics.water_column": "viscous_crossflow", "sediment.friction": 0.4})
    assert q[layout.P_WATER_COLUMN] == layout.WC_VISCOUS_CROSSFLOW
    assert q[layout.INDEX["sediment.friction"]] == 0.4
    assert p.sum() == 0.0  # a copy


# ---------------------------------------------------------------------------
# conditioning
# ---------------------------------------------------------------------------
def _row(**kw):
    base = dict(
        id="r",
        case="c",
        variant="v",
        quantity="travel_time",
        observed=0.7,
        units="s",
        source="s",
        assumptions="a",
        sigma=0.3,
        discrepancy=0.4,
    )
    return priors.EvidenceRow(**{**base, **kw})


def test_importance_weights_reproduce_a_one_dimensional_posterior():
    """theta ~ U(-2, 2), one Gaussian row on theta itself: the weighted mean and standard
    deviation of 4096 Sobol' draws match the posterior integrated by scipy."""
    prior = priors.Prior("x", dist.Uniform(-2.0, 2.0), "test")
    draws = conditioning.draw_sets((prior,), 4096, seed=3)
    row = _row()
    scores = conditioning.log_scores((row,), draws["x"][:, None, None])
    w = conditioning.normalised(conditioning.case_log_likelihoods(scores, ["c"])["c"])
    s = row.total_sigma
    dens = lambda t: math.exp(-0.5 * ((t - row.observed) / s) ** 2)  # noqa: E731
    z = scipy.integrate.quad(dens, -2, 2)[0]
    mean = scipy.integrate.quad(lambda t: t * dens(t), -2, 2)[0] / z
    var = scipy.integrate.quad(lambda t: (t - mean) ** 2 * dens(t), -2, 2)[0] / z
    assert np.sum(w * draws["x"]) == pytest.approx(mean, abs=2e-3)
    assert math.sqrt(np.sum(w * (draws["x"] - np.sum(w * draws["x"])) ** 2)) == pytest.approx(
        math.sqrt(var), rel=5e-3
    )
    assert conditioning.effective_sample_size(w) < 4096


def test_a_grid_nuisance_is_averaged_not_maximised():
    """Two grid points, the model right at one of them: the set's likelihood is the mean of
    the two points' likelihoods (log-mean-exp), not the better one."""
    row = _row(sigma=0.5, discrepancy=0.0)
    sim = np.array([[[0.7, 5.0]]])  # (sets, rows, grid)
    ll = conditioning.case_log_likelihoods(conditioning.log_scores((row,), sim), ["c"])["c"][0]
    pdf = scipy.stats.norm(0.7, 0.5).pdf
    assert ll == pytest.approx(math.log(0.5 * (pdf(0.7) + pdf(5.0))), rel=1e-12)


def test_binary_rows_score_with_their_error_rate_and_failed_drops_score_zero():
    row = _row(quantity="slant_straight", observed=1.0, error_rate=0.1, sigma=0.0, discrepancy=0.0)
    s = conditioning.log_scores((row,), np.array([[[1.0]], [[0.0]], [[np.nan]]]))
    np.testing.assert_allclose(np.exp(s[:, 0, 0]), [0.9, 0.1, 0.0])


def test_predictive_band_of_a_point_model_is_the_gaussian_interval():
    row = _row(observed=1.0, sigma=0.3, discrepancy=0.4)
    chk = conditioning.predictive_check(row, np.full(50, 1.2), np.full(50, 1 / 50), seed=1)
    half = scipy.stats.norm.ppf(0.95) * 0.5
    assert chk.lower == pytest.approx(1.2 - half, abs=0.02)
    assert chk.upper == pytest.approx(1.2 + half, abs=0.02)
    assert chk.passed
    far = conditioning.predictive_check(_row(observed=3.0), np.full(50, 1.2), np.full(50, 1 / 50), seed=1)
    assert not far.passed


def test_weighted_quantile_matches_the_repeated_sample():
    v = np.array([3.0, 1.0, 2.0])
    w = np.array([1.0, 2.0, 1.0])
    expanded = np.array([3.0, 1.0, 1.0, 2.0])
    for q in (0.1, 0.5, 0.9):
        assert conditioning.weighted_quantile(v, w, q)[0] == np.quantile(expanded, q, method="inverted_cdf")


# ---------------------------------------------------------------------------
# the epistemic band
# ---------------------------------------------------------------------------
def test_between_set_variance_recovers_the_beta_binomial_spread():
    """Per-set probabilities from Beta(2, 5), 10 drops a set: the moment estimator recovers
    the Beta's variance ab / ((a + b)^2 (a + b + 1)) (within its sampling error)."""
    rng = np.random.default_rng(7)
    sets = np.repeat(np.arange(2000), 10)
    p = rng.beta(2.0, 5.0, 2000)[sets]
    y = (rng.random(sets.size) < p).astype(float)
    truth = 2 * 5 / (7**2 * 8)
    assert epistemic.between_group_variance(y, sets) == pytest.approx(truth, rel=0.12)
    same = (rng.random(sets.size) < 0.3).astype(float)  # no between-set spread
    assert epistemic.between_group_variance(same, sets) < 0.1 * truth


def test_beta_band_is_the_beta_distribution_interval():
    lo, hi = epistemic.beta_band(0.3, 0.01, 0.9)
    total = 0.3 * 0.7 / 0.01 - 1
    ref = scipy.stats.beta(0.3 * total, 0.7 * total)
    assert lo == pytest.approx(ref.ppf(0.05), rel=1e-9)
    assert hi == pytest.approx(ref.ppf(0.95), rel=1e-9)
    assert epistemic.beta_band(0.3, 0.0) == (0.3, 0.3)


# ---------------------------------------------------------------------------
# the shipped posterior and ensembles that draw from it
# ---------------------------------------------------------------------------
def test_shipped_posterior_matches_the_shipped_priors_and_evidence():
    post = posterior.load("posterior")
    assert post.stale() is None, "rebuild: mineburial calibrate -o mineburial/data/calibration/posterior.json"
    assert set(post.paths) == {p.path for p in priors.load_priors()}
    assert post.weights.sum() == pytest.approx(1.0)


def test_a_small_rebuild_reproduces_the_shipped_sets_it_shares(tmp_path):
    """The shipped calibration's first sets are the Sobol' points a small calibration with the
    same seed draws: block by block, their values and likelihoods are the same, bit for bit."""
    shipped = json.loads(priors.POSTERIOR_FILE.read_text())
    n = 32
    cal = calibrate.calibrate(tmp_path / "p.json", n=n, seed=shipped["seed"])
    coeffs = shipped["coefficients"]
    checked = set()
    for block, members in shipped["blocks"].items():
        for k, s in enumerate(shipped["set_index"][block]):
            if s >= n:
                continue
            for path in members:
                assert shipped["sets"][k][coeffs.index(path)] == calibrate._scalar(cal.draws[path][s]), path
            assert shipped["log_likelihood"][block][k] == cal.log_likelihood[block][s], block
            checked.add(block)
    assert checked == set(shipped["blocks"]), "a block without a shipped set among the first 32"
    assert cal.record["priors_sha256"] == shipped["priors_sha256"]


def test_the_scour_rows_leave_the_impact_blocks_weights_unchanged(tmp_path):
    """Invariance: the blocks read disjoint coefficients, so a calibration without the scour
    rows gives the impact block the same weights, bit for bit, and the impact coefficients'
    marginals are read under them alone."""
    text = priors.EVIDENCE_FILE.read_text()
    cut = text.index('[[row]]\nid = "scour_oahu_one_event"')  # the rows only: the nuisance
    without = tmp_path / "evidence.toml"  # parameter stays, so the Sobol' draws are the same
    without.write_text(text[:cut])
    a = calibrate.calibrate(tmp_path / "a.json", n=32, seed=7)
    b = calibrate.calibrate(tmp_path / "b.json", n=32, seed=7, evidence_file=without)
    assert set(a.weights) == {"impact", "scour"} and set(b.weights) == {"impact"}
    np.testing.assert_array_equal(a.weights["impact"], b.weights["impact"])
    assert (
        a.record["report"]["posterior"]["sediment.rate_coefficient"]
        == (b.record["report"]["posterior"]["sediment.rate_coefficient"])
    )
    # without its evidence the scour block is resampled from its prior draws with equal weights
    assert sorted(b.record["set_index"]["scour"]) == list(range(32))


def test_shipped_sets_resample_each_block_by_its_weights_and_pair_them_independently():
    """Equal weights; a prior set repeated among the shipped sets carries one likelihood; the
    blocks are paired by a permutation, not in the same order (rank correlation ~ 0)."""
    shipped = json.loads(priors.POSTERIOR_FILE.read_text())
    m = len(shipped["sets"])
    assert shipped["weights"] == [1.0 / m] * m
    cal_ll = shipped["log_likelihood"]
    idx = {b: np.array(shipped["set_index"][b]) for b in shipped["blocks"]}
    for b in shipped["blocks"]:
        counts = np.bincount(idx[b])
        # the likelihood recorded with a prior set is one value: the same set, the same score
        for s in np.flatnonzero(counts > 1)[:20]:
            assert len({ll for ll, k in zip(cal_ll[b], idx[b]) if k == s}) == 1
    rank = scipy.stats.spearmanr(idx["impact"], idx["scour"]).statistic
    assert abs(rank) < 0.1, rank


def _fixed_and_drawn(n=400):
    fixed = short_default(n)
    fixed["ensemble"]["coefficients"] = "fixed"
    drawn = short_default(n)
    drawn["ensemble"]["coefficients"] = "posterior"
    return engine.load_ensemble(fixed), engine.load_ensemble(drawn)


def test_drops_draw_posterior_sets_by_weight_and_leave_other_inputs_unchanged():
    fixed, drawn = _fixed_and_drawn()
    n = fixed.n
    P0, _, in0 = mine.chunk_inputs(fixed, 0, n)
    P1, _, in1 = mine.chunk_inputs(drawn, 0, n)
    for path, values in in0.items():  # the seed contract: every other input unchanged
        np.testing.assert_array_equal(in1[path], values, err_msg=path)
    post = drawn.posterior
    sets = in1[posterior.SET_INPUT].astype(int)
    # the set of drop i: the representative set at the field's own Philox uniform, equal weights
    u = uniforms(drawn.seed, [posterior.SET_INPUT], 0, n, "mc")[:, 0]
    rep = post.representative_sets()
    np.testing.assert_array_equal(sets, rep[np.minimum((u * rep.size).astype(int), rep.size - 1)])
    # a scenario without a [scour] section draws no coefficient of the scour stage
    assert drawn.posterior_paths == tuple(p for p in post.paths if not p.startswith("scour."))
    for path in drawn.posterior_paths:
        k = post.paths.index(path)
        np.testing.assert_array_equal(P1[:, layout.INDEX[path]], post.table[sets, k], err_msg=path)


def test_a_scour_ensemble_draws_the_stages_coefficients_from_the_posterior():
    """With a [scour] section of the law the posterior was conditioned with (scour_settle) the
    scour stage's calibrated coefficients come from each drop's set (the stage reads them from
    the sampled inputs); one the section gives is kept."""
    from mineburial.systems.mine.processes import scour as scour_ensemble

    raw = short_default(12)
    raw["ensemble"]["coefficients"] = "posterior"
    storm = {"peak_hs": 2.0, "peak_tp": 9.0, "duration_h": 24.0}
    raw["scour"] = {"storm": storm, "beq_b": 0.33, "burial_law": "scour_settle"}
    raw["sediment"] = {"class": "sand"}
    spec = engine.load_ensemble(raw)
    assert "scour.beq_a" in spec.posterior_paths and "scour.beq_b" not in spec.posterior_paths
    P, _, inputs = mine.chunk_inputs(spec, 0, spec.n)
    sets = inputs[posterior.SET_INPUT].astype(int)
    a = spec.posterior.table[sets, spec.posterior.paths.index("scour.beq_a")]
    S, _ = scour_ensemble.stage_parameters(spec.process("scour"), P, inputs)
    np.testing.assert_array_equal(S[:, scour_ensemble.NUMERIC["beq_a"]], a)
    assert np.all(S[:, scour_ensemble.NUMERIC["beq_b"]] == 0.33)


def test_the_scour_case_names_the_slots_the_ensemble_fills():
    """calibration.cases.SCOUR_COEFFICIENTS (field -> the stage's parameter name) and the
    ensemble's NUMERIC (name -> slot) must point at the same slots."""
    from mineburial.kernels.mine import scour as scour_kernels
    from mineburial.systems.mine.processes import scour as scour_ensemble

    for path, kernel_name in cases.SCOUR_COEFFICIENTS.items():
        slot = getattr(scour_kernels, "S_" + kernel_name.upper())
        assert scour_ensemble.NUMERIC[path.split(".", 1)[1]] == slot, path
    calibrated = {p.path for p in priors.load_priors() if p.path.startswith("scour.")}
    assert calibrated <= {*cases.SCOUR_COEFFICIENTS, cases.SCOUR_LAW}  # the law: the set's own


def test_the_scour_band_case_is_the_validation_row_at_its_assumptions():
    """At the stage's defaults and the validation's 12 s period the case gives the validation
    row's B/D, and it grows with a (B_eq/D = a theta^b, Rennie et al. 2017)."""
    (row,) = [r for r in vc.scour_field_bands() if r.quantity.startswith("B/D after one event")]
    _, got = cases.run_case("scour_bands", "oahu", {"peak_tp": 12.0}, {}, {})
    assert got["burial_fraction"][0] == pytest.approx(row.model, rel=1e-12)
    _, more = cases.run_case("scour_bands", "oahu", {"peak_tp": 12.0}, {}, {"scour.beq_a": 1.8})
    assert more["burial_fraction"][0] > got["burial_fraction"][0]


def test_systematic_resampling_keeps_each_weight_to_within_one_set():
    rng = np.random.default_rng(5)
    for m in (32, 1000, 2048):
        w = rng.dirichlet(np.full(300, 0.3))
        idx = conditioning.systematic_resample(w, m)
        counts = np.bincount(idx, minlength=w.size)
        assert counts.sum() == m and np.all(np.diff(idx) >= 0)
        assert np.all(np.abs(counts - m * w) < 1.0 + 1e-9)


def test_representative_sets_follow_the_weights_to_within_one_set():
    """Systematic resampling: each set appears within one of k times its weight."""
    post = posterior.load("posterior")
    for k in (32, 1000):
        counts = np.bincount(post.representative_sets(k), minlength=post.weights.size)
        assert counts.sum() == k
        assert np.all(np.abs(counts - k * post.weights) < 1.0 + 1e-9)


def test_a_coefficient_the_scenario_gives_is_not_drawn():
    raw = short_default(50)
    raw["ensemble"]["coefficients"] = "posterior"
    raw["sediment"]["rate_coefficient"] = 0.07
    spec = engine.load_ensemble(raw)
    assert "sediment.rate_coefficient" not in spec.posterior_paths
    P, _, _ = mine.chunk_inputs(spec, 0, 50)
    assert np.all(P[:, layout.INDEX["sediment.rate_coefficient"]] == 0.07)


@pytest.mark.parametrize(
    "section",
    [
        None,  # no [scour]: the stage does not run
        {"burial_law": "rennie"},
        {},  # rennie by default
        {"burial_law": "scour_settle"},
        {"burial_law": "scour_settle", "beq_a": 1.1},  # all but the one it gives
        {"burial_law": "posterior"},
    ],
)
def test_scour_coefficients_are_drawn_only_under_the_law_they_were_conditioned_with(section):
    """The shipped posterior's scour coefficients are drawn only under the law they were conditioned
    with. Built with a law per set (scour.burial_law has a prior): a section that names a law with
    posterior mass draws that law's coefficients (rennie does not read a_w, m_w, the infill time),
    "posterior" draws every one and the law. Built before (a file without the law, every set
    scour_settle): only a scour_settle section draws, every coefficient it does not give."""
    post = posterior.load("posterior")
    scour_paths = [p for p in post.paths if p.startswith("scour.")]
    raw = {"mine": {}} if section is None else {"mine": {}, "scour": section}
    given = {f"scour.{k}" for k in (section or {})}
    law = None if section is None else section.get("burial_law", "rennie")
    probabilities = posterior.law_probabilities(post)
    if probabilities is None and law == "posterior":
        with pytest.raises(ScenarioError, match="carries no law per set"):
            posterior.for_scenario(post, raw)
        return
    got = [p for p in posterior.for_scenario(post, raw)[1] if p.startswith("scour.")]
    if probabilities is None:
        assert posterior.scour_law(post.paths) == "scour_settle" and "scour.wave_a" in scour_paths
        want = [p for p in scour_paths if p not in given] if law == "scour_settle" else []
    elif law is None or (law != "posterior" and probabilities[law] < posterior.LAW_FLOOR):
        want = []
    elif law == "posterior":
        want = scour_paths
    else:
        unread = {posterior.LAW, *(posterior.SCOUR_SETTLE_COEFFICIENTS if law == "rennie" else ())}
        want = [p for p in scour_paths if p not in given and p not in unread]
    assert got == want


@pytest.mark.parametrize("value", ["", 3, "no/such/posterior.json"])
def test_bad_coefficients_setting_is_refused_with_its_name(value):
    raw = short_default(5)
    raw["ensemble"]["coefficients"] = value
    with pytest.raises(ScenarioError, match="ensemble.coefficients"):
        engine.load_ensemble(raw)


def test_calibration_refuses_a_partial_folder_of_another_calibration(tmp_path):
    out = tmp_path / "p.json"
    calibrate._Blocks(out, {"seed": 1})
    with pytest.raises(ScenarioError, match="another calibration"):
        calibrate._Blocks(out, {"seed": 2})


def test_evidence_rows_need_their_uncertainty(tmp_path):
    text = priors.EVIDENCE_FILE.read_text()
    assert "sigma = 0.25\ndiscrepancy = 0.35" in text
    bad = tmp_path / "evidence.toml"
    bad.write_text(text.replace("sigma = 0.25\ndiscrepancy = 0.35", ""))
    with pytest.raises(ScenarioError, match="sigma or discrepancy"):
        priors.load_evidence(bad)


def test_a_posterior_is_refused_for_another_physics_model():
    raw = short_default(5)
    raw["ensemble"]["coefficients"] = "posterior"
    raw["numerics"]["model"] = "impact35"
    with pytest.raises(ScenarioError, match="calibrated with numerics.model"):
        engine.load_ensemble(raw)


def test_binary_predictive_check_fails_when_the_model_never_gives_the_pattern():
    row = _row(quantity="slant_straight", observed=1.0, error_rate=0.1, sigma=0.0, discrepancy=0.0)
    w = np.full(10, 0.1)
    never = conditioning.predictive_check(row, np.zeros(10), w, seed=0)
    assert never.probability == 0.0 and not never.passed
    some = conditioning.predictive_check(row, np.r_[np.ones(2), np.zeros(8)], w, seed=0)
    assert some.probability == pytest.approx(0.2) and some.passed


def test_the_summary_says_when_the_band_cannot_be_resolved():
    """Every drop its own set: the between-set variance cannot be separated (NaN), and the
    printed sentence says so instead of printing nan."""
    sets = np.arange(10)
    assert math.isnan(epistemic.between_group_variance(np.r_[np.ones(5), np.zeros(5)], sets))
    ds = xr.Dataset(
        {
            "burial_class_probability": ("c", [0.5]),
            "burial_class_probability_epistemic_lower": ("c", [np.nan], {"band_level": 0.9}),
            "burial_class_probability_epistemic_upper": ("c", [np.nan]),
        }
    )
    lines = epistemic.summary_lines(ds, ["x"])
    assert "not resolved" in lines[-1] and "nan" not in lines[-1]


def test_physics_doc_lists_every_prior_as_the_priors_file_declares_it():
    """docs/physics.md's priors table is the one generated from priors.toml (issue 32: the
    physics notes list every prior)."""
    import pathlib

    from mineburial.schema import generated_block

    doc = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "physics.md").read_text()
    assert generated_block("priors", priors.prior_table(), priors.DOC_WRITER) in doc, (
        "regenerate: python -c 'from mineburial.systems.mine.calibration.priors import write_prior_table; "
        "write_prior_table()'"
    )
    for p in priors.load_priors():
        assert f"`{p.path}`" in doc


def test_a_prior_added_to_one_block_leaves_the_other_blocks_draws_unchanged():
    """Each block's priors are drawn from a Sobol' sequence of their own (conditioning.draw_sets):
    the impact block's draws do not move when the scour block gains or loses a prior, and the
    first 32 draws are those of a 4096-set run (the Sobol' prefix, so small rebuilds reproduce)."""
    coefficients = priors.load_priors()
    scour = [p for p in coefficients if p.path.startswith("scour.")]
    assert len(scour) >= 2
    full = conditioning.draw_sets(tuple(coefficients), 64, 7, calibrate.block_of)
    fewer = conditioning.draw_sets(
        tuple(p for p in coefficients if p is not scour[-1]), 64, 7, calibrate.block_of
    )
    for p in coefficients:
        if p.path.startswith("scour."):
            continue
        np.testing.assert_array_equal(full[p.path], fewer[p.path])
    assert not np.array_equal(full[scour[0].path], fewer[scour[0].path])  # the scour block did change
    prefix = conditioning.draw_sets(tuple(coefficients), 32, 7, calibrate.block_of)
    for path, values in prefix.items():
        np.testing.assert_array_equal(values, full[path][:32])
