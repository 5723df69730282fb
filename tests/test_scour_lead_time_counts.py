"""``compare`` and ``sensitivity`` at a lead time count the drops as ``run`` does (issue 35,
item 4): a drop whose scour stage gave no value (scour status not ok) is left out of the burial
statistics after scour, not counted with its impact burial (was: P(> 75 %) 0.25 against
``run``'s 1.00 on the same 16 drops).

The fault is injected as the stage reports it: for half of the drops the stage's status is
``invalid_parameter`` and its measures NaN (docs/scour.md, "NaN results only with a status
that is not ok"). Independent reference: ``run``'s own statistics after scour
(``scour_burial_class_probability`` over the drops with scour status ok), a separate code
path (systems/mine/statistics.scour_statistics) from compare's burial statistics.
"""

import numpy as np
import pytest
from test_scour_sensitivity import scenario

from mineburial.analyses.compare import run_comparison
from mineburial.analyses.sensitivity import run_sensitivity
from mineburial.ensembles.runner import run_ensemble
from mineburial.systems.mine.processes import scour

LEAD = 0.5  # d: the section's last lead time


@pytest.fixture
def half_fail(monkeypatch):
    """The stage of every other drop of each chunk fails with invalid_parameter."""
    real = scour.run_chunk

    def failing(spec, P, summary, status, inputs):
        out = real(spec, P, summary, status, inputs)
        bad = np.arange(P.shape[0]) % 2 == 1
        out["scour:status"] = np.where(bad, 1, out["scour:status"]).astype(np.int8)
        out["scour:measures"] = np.where(bad[:, None, None], np.nan, out["scour:measures"])
        return out

    monkeypatch.setattr(scour, "run_chunk", failing)


def test_compare_at_a_lead_time_counts_the_drops_run_counts(tmp_path, half_fail):
    path = scenario(tmp_path, pitch=0.0)
    ran = run_ensemble(path, n=8, seed=3)
    k = list(ran["lead_time"].values).index(LEAD)
    assert int(ran.attrs["scour_n_in_statistics"]) == 4  # the 4 drops whose stage gave a value
    want = ran["scour_burial_class_probability"].values[k]
    cmp = run_comparison(path, "numerics.t_max", [3.0, 3.5], n=8, seed=3, lead_time=LEAD)
    got = cmp["burial_class_probability"].sel(variant=cmp["variant"].values[0]).values
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)
    assert int(cmp["burial_class_count"].sel(variant=cmp["variant"].values[0]).sum()) == 4


def test_after_scour_leaves_a_drop_without_a_stage_value_out_or_keeps_its_impact_on_request():
    from mineburial.kernels.mine import layout
    from mineburial.systems.mine.processes.scour_variables import SCOUR_MEASURES

    summary = np.zeros((2, layout.N_SUMMARY))
    col = layout.SUMMARY_INDEX["burial_volume"]
    summary[:, col] = [10.0, 20.0]
    measures = np.full((2, len(SCOUR_MEASURES), 1), np.nan)
    measures[0, :, 0] = 90.0
    assert scour.after_scour(summary, measures)[:, col].tolist()[0] == 90.0
    assert np.isnan(scour.after_scour(summary, measures)[1, col])
    assert scour.after_scour(summary, measures, missing="impact")[:, col].tolist() == [90.0, 20.0]


def test_sensitivity_at_a_lead_time_says_how_many_drops_had_no_stage_value(tmp_path, half_fail):
    """A Sobol' design needs a value at each point: the impact's is kept, and a warning says
    for how many drops."""
    ds = run_sensitivity(scenario(tmp_path), n=8, seed=1, lead_time=LEAD)
    total = 8 * (1 + 2)  # one random input: n (d + 2) drops
    assert f"{total // 2} of {total} drops have no value of the scour stage" in ds.attrs["warning"]


def test_a_lead_time_just_beyond_the_forcing_is_not_printed_as_equal_to_its_end(tmp_path):
    """Was: "--lead-time 1 is outside the allowed range [0, 1] days" for 1.0000001."""
    from mineburial.ensembles import engine
    from mineburial.errors import ScenarioError

    spec = engine.load_ensemble(scenario(tmp_path))  # a 24 h forcing: lead times in [0, 1] d
    with pytest.raises(ScenarioError, match=r"--lead-time 1\.0000001 is outside the allowed range \[0, 1\]"):
        scour.at_lead_time(spec, 1.0000001)
    with pytest.raises(ScenarioError, match=r"--lead-time 1\.7 is outside"):  # plainly beyond: as before
        scour.at_lead_time(spec, 1.7)
