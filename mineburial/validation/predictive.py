"""The fourth kind of validation rows: leave-one-out posterior predictive checks of the
evidence set (issue 32 item 5; docs/calibration.md, "Predictive checks").

A calibration of :data:`SETS` coefficient sets is run
afresh into a temporary folder; each evidence row is then left out, the posterior rebuilt
from the other rows (their weights, on the same simulations) and the held-out measurement
predicted with its 90 % band (:func:`mineburial.calibration.conditioning.predictive_check`).
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

from mineburial.calibration import calibrate
from mineburial.calibration.priors import load_evidence
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


CASES = (
    Case(
        "predictive_checks",
        "Leave-one-out predictive checks of the calibration's evidence",
        predictive_checks,
        PREDICTIVE,
        system=MINE,
    ),
)
