"""The scour field bands predicted by a posterior (issue 33, "the field-band table ... with the
calibration/validation split"; mineburial/validation/predictive.py): each set runs under its own
law and coefficients; the weighted quantiles are those of the sets; the Indian Rocks Beach band is
the validation row (not evidence), the Oahu and Halekulani bands information."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mineburial.systems.mine.calibration import cases, posterior
from mineburial.validation import cases as vc
from mineburial.validation import predictive as pr


def test_weighted_quantiles_of_equal_weights_are_numpy_s_midpoint_quantiles():
    rng = np.random.default_rng(3)
    v = rng.normal(size=101)
    got = pr._weighted_quantiles(v, np.full(101, 1 / 101), (0.05, 0.5, 0.95))
    # (cumsum - w/2) / sum at equal weights is Hazen's plotting position (k - 0.5)/n: numpy's 'hazen'
    want = np.quantile(v, (0.05, 0.5, 0.95), method="hazen")
    np.testing.assert_allclose(got, want, rtol=1e-12)
    # a set carrying all the weight is every quantile
    w = np.zeros(101)
    w[17] = 1.0
    assert pr._weighted_quantiles(v, w, (0.05, 0.95)) == [v[17], v[17]]


def test_each_set_runs_under_its_own_law_and_irb_on_quartz():
    """A two-set posterior: set 0 rennie with its a, b; set 1 scour_settle with a_w; every band's
    prediction equals scour_burial of that set alone (an invariance), and the IRB event at the
    default coefficients equals the validation's own IRB burial on quartz sand."""
    paths = ("scour.beq_a", "scour.beq_b", "scour.wave_a", "scour.burial_law")
    table = np.array([[1.2, 0.3, 0.2, 0.0], [1.4, 0.4, 0.5, 1.0]])
    post = posterior.Posterior(paths, table, np.array([0.5, 0.5]), "test", "0", {})
    got, _ = pr.scour_band_predictions(post)
    tps = np.random.default_rng(pr.PEAK_TP_SEED).uniform(*pr.PEAK_TP, size=2)
    for i, law in enumerate(("rennie", "scour_settle")):
        coefficients = dict(zip(paths[:3], table[i, :3]), **{"scour.burial_law": law})
        assert got["oahu"][i] == cases.scour_burial("oahu", coefficients, tps[i])
        assert got["irb"][i] == cases.scour_burial("irb", coefficients, 7.0)
    assert got["oahu"][0] != got["oahu"][1]
    b, _ = vc.scour_final_burial(vc.SCOUR_EVENTS["irb"], d50=vc.SCOUR_FINE, rho_grain=vc.SCOUR_QUARTZ)
    assert cases.scour_burial("irb", {}, 7.0) == b
    assert cases.SCOUR_GRAINS["irb"] == vc.SCOUR_QUARTZ != vc.SCOUR_CARBONATE


def test_only_the_validation_band_can_fail_and_it_fails_exactly_when_the_bands_do_not_overlap(monkeypatch):
    fake = {"oahu": np.linspace(0.6, 1.0, 21), "halekulani": np.linspace(0.3, 0.7, 21)}
    post = dataclasses.make_dataclass("P", ["table", "weights"])(np.zeros((21, 1)), np.full(21, 1 / 21))
    for irb, want in ((np.linspace(0.2, 0.5, 21), False), (np.linspace(0.5, 0.9, 21), True)):
        monkeypatch.setattr(pr, "scour_band_predictions", lambda irb=irb: ({**fake, "irb": irb}, post))
        rows = {r.quantity.split()[1]: r for r in pr.scour_posterior_bands()}
        assert rows["oahu"].passed is None and rows["halekulani"].passed is None
        assert rows["irb"].passed is want
        assert rows["irb"].reference == "0.745-1"


@pytest.mark.parametrize("variant", list(pr.SCOUR_BANDS))
def test_every_band_has_its_event(variant):
    assert variant in vc.SCOUR_EVENTS and variant in cases.SCOUR_GRAINS
