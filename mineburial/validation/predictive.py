"""The fourth kind of validation rows: leave-one-out posterior predictive checks of the
evidence set (issue 32 item 5; docs/calibration.md, "Predictive checks").

A calibration of :data:`SETS` coefficient sets is run
afresh into a temporary folder; each evidence row is then left out, the posterior rebuilt
from the other rows (their weights, on the same simulations) and the held-out measurement
predicted with its 90 % band (:func:`mineburial.systems.mine.calibration.conditioning.predictive_check`).
A row passes when the measurement lies inside the band; a calibration row never counts as a
pass here, since every row is predicted without itself.

Declared here, not in :data:`mineburial.validation.cases.CASES`: the calibration's cases use
the validation's experiments, so ``cases`` cannot import the calibration back; the report
runs :data:`CASES` after the cases of ``cases`` (:mod:`mineburial.validation.report`).
"""

from __future__ import annotations

import math
import pathlib
import tempfile

import numpy as np

from mineburial.systems.mine.calibration import calibrate, cases, posterior
from mineburial.systems.mine.calibration.priors import choice_labels, load_evidence
from mineburial.validation import cases as vc
from mineburial.validation.cases import MINE, PREDICTIVE, Case, Row

#: coefficient sets of the validation's calibration, the same in the full suite and the quick
#: subset CI runs (its rows are quick rows: the committed summary must equal a fresh quick run);
#: about 20 s on 2 cores. The shipped calibration's own checks use 2,048 (docs/calibration_report.md)
SETS = 128
SOURCE = "mineburial/data/calibration/evidence.toml (its source column names each measurement)"


def predictive_checks(quick_only=False, figures=None, sets=None):
    """One row per evidence row: the measurement against its leave-one-out predictive band."""
    n = sets or SETS
    rows, _ = load_evidence()
    with tempfile.TemporaryDirectory(prefix="mineburial-validate-") as tmp:
        record = calibrate.calibrate(pathlib.Path(tmp) / "posterior.json", n=n).record
    by_id = {r.id: r for r in rows}
    out = []
    for chk in record["report"]["predictive"]:
        row = by_id[chk["id"]]
        if math.isfinite(chk["probability"]):
            model = f"P(observed) = {chk['probability']:.2f}"
            tol = "the model gives the observed pattern with predictive probability >= 10 %"
        else:
            model = f"{chk['lower']:.3g}-{chk['upper']:.3g}"
            tol = "inside the 5-95 % predictive band"
        out.append(
            Row(
                "evidence left out",
                f"{row.id}: {row.quantity} predicted from the other rows ({n} prior sets, "
                f"ESS without it {chk['ess_without']:.0f})",
                row.source,
                f"{row.observed:g}",
                model,
                row.units,
                tol,
                passed=bool(chk["passed"]),
                quick=True,
            )
        )
    return out


#: the scour field bands predicted by the shipped posterior: variant -> (the band, its source, its
#: role). Oahu and Halekulani are the calibration's evidence (their held-out checks are the
#: "evidence left out" rows); Indian Rocks Beach is not evidence: the validation of the split
SCOUR_BANDS = {
    "oahu": (vc.SCOUR_OAHU_THICK_BAND, vc.SCOUR_OAHU_SOURCE + ": 'about their diameter'", "calibration"),
    "halekulani": (vc.SCOUR_HALEKULANI_BAND, vc.SCOUR_OAHU_SOURCE + ", Halekulani 2008", "calibration"),
    "irb": (vc.SCOUR_IRB_FINE_BAND, vc.SCOUR_IRB_WOLFSON_SOURCE + ": 74.5 % or more", "validation"),
}
#: the prior of the Oahu events' unprinted peak period (evidence.toml's nuisance scour_bands.peak_tp),
#: drawn once per set for the two calibration bands (seeded: the rows are reproducible)
PEAK_TP = (10.0, 14.0)
PEAK_TP_SEED = 20261129


def scour_band_predictions(post=None) -> dict:
    """{variant: B/D of every set of the posterior ``post`` (default the shipped one)} at the end of
    each field band's event (:data:`SCOUR_BANDS`), each set under its own burial law and
    coefficients (:func:`mineburial.systems.mine.calibration.cases.scour_burial`); the Oahu events' peak
    period
    drawn from its prior per set, the Indian Rocks Beach fronts at their assumed 7 s."""
    post = post or posterior.load(posterior.SHIPPED)
    labels = {p: choice_labels(p) for p in post.paths}
    cols = [k for k, p in enumerate(post.paths) if p.startswith("scour.")]
    law = posterior.scour_law(post.paths) if "scour.burial_law" not in post.paths else None
    tps = np.random.default_rng(PEAK_TP_SEED).uniform(*PEAK_TP, size=post.table.shape[0])
    out = {}
    for variant in SCOUR_BANDS:
        values = np.empty(post.table.shape[0])
        for i, row in enumerate(post.table):
            coefficients = {
                post.paths[k]: (labels[post.paths[k]][int(row[k])] if labels[post.paths[k]] else row[k])
                for k in cols
            }
            if law is not None:  # a posterior file without a law column: its sets' one law
                coefficients.setdefault("scour.burial_law", law)
            tp = tps[i] if variant != "irb" else vc.SCOUR_EVENTS["irb"]["peak_tp"]
            values[i] = cases.scour_burial(variant, coefficients, tp)
        out[variant] = values
    return out, post


def scour_posterior_bands(quick_only=False, figures=None):
    """One row per scour field band: the shipped posterior's predictive median and 5-95 % band of
    B/D (weighted sets) against the published band; the calibration's two bands as information
    (they weighed the sets), the Indian Rocks Beach band as the validation of the split: it passes
    when its band and the predictive 5-95 % band overlap. Not in the quick subset (about 20 s)."""
    if quick_only:
        return []
    predicted, post = scour_band_predictions()
    rows = []
    for variant, ((lo, hi), source, role) in SCOUR_BANDS.items():
        q = _weighted_quantiles(predicted[variant], post.weights, (0.05, 0.5, 0.95))
        overlap = q[0] <= hi and q[2] >= lo
        rows.append(
            Row(
                "scour posterior bands",
                f"B/D {variant} predicted by the shipped posterior ({post.table.shape[0]} sets; "
                + ("a calibration row" if role == "calibration" else "a validation row, not in the evidence")
                + ")",
                source,
                f"{lo:.3g}-{hi:.3g}",
                f"{q[1]:.3g} [{q[0]:.3g}, {q[2]:.3g}]",
                "B/D",
                "information: this band weighed the sets (its held-out check: 'evidence left out')"
                if role == "calibration"
                else "the band overlaps the predictive 5-95 % band",
                passed=None if role == "calibration" else bool(overlap),
            )
        )
    return rows


def _weighted_quantiles(values, weights, qs):
    """Quantiles ``qs`` of ``values`` under ``weights``: linear between the sets' midpoint
    positions (cumulative weight less half their own; Hazen's (k - 1/2)/n at equal weights);
    sets of zero weight left out."""
    keep = np.asarray(weights, dtype=np.float64) > 0.0
    values, weights = np.asarray(values, dtype=np.float64)[keep], np.asarray(weights, dtype=np.float64)[keep]
    order = np.argsort(values, kind="stable")
    v, w = values[order], weights[order]
    c = (np.cumsum(w) - 0.5 * w) / w.sum()
    return [float(np.interp(q, c, v)) for q in qs]


CASES = (
    Case(
        "predictive_checks",
        "Leave-one-out predictive checks of the calibration's evidence",
        predictive_checks,
        PREDICTIVE,
        system=MINE,
    ),
    Case(
        "scour_posterior_bands",
        "The scour field bands predicted by the shipped posterior: calibration and validation rows",
        scour_posterior_bands,
        PREDICTIVE,
        system=MINE,
    ),
)
