"""A posterior of coefficient sets, as written by ``mineburial calibrate`` (JSON), and how an
ensemble draws from it (issue 32; docs/calibration.md).

An ensemble with ``ensemble.coefficients = "posterior"`` (the shipped posterior) or a path
to a posterior file draws, for every drop, one coefficient set from the posterior's weighted
sets: the set's index is the sampled input :data:`SET_INPUT`, a ``choice`` among the set
indices with the posterior weights, drawn from its own stream like any other input (so the
other inputs' draws are unchanged), and the set's values go into the drop's parameter row.
A coefficient the scenario gives itself (a value or a distribution) is not taken from the
posterior.
"""

from __future__ import annotations

import hashlib
import json
import pathlib
from dataclasses import dataclass

import numpy as np

from mineburial.calibration import conditioning
from mineburial.calibration.priors import EVIDENCE_FILE, POSTERIOR_FILE, PRIORS_FILE, file_digest
from mineburial.ensembles import distributions as dist
from mineburial.ensembles import model_form
from mineburial.errors import ScenarioError

#: the sampled input that picks each drop's coefficient set
SET_INPUT = "calibration.posterior_set"
#: the values of ``ensemble.coefficients`` besides a path
SHIPPED, FIXED = "posterior", "fixed"
#: the coefficient sets an ensemble draws from: the posterior resampled to this many equally
#: weighted sets (:meth:`Posterior.representative_sets`); a 2,000-drop run has ~60 drops a set
ENSEMBLE_SETS = 32
#: the physics model of the evidence cases, the only one a posterior applies to
CALIBRATED_MODEL = "mineburial"


@dataclass(frozen=True)
class Posterior:
    """The weighted coefficient sets of a posterior file."""

    paths: tuple[str, ...]  # the coefficients, in column order
    table: np.ndarray  # (sets, coefficients) values; a model choice as its label's code
    weights: np.ndarray  # (sets,), summing to 1
    source: str  # "shipped" or the file's path
    digest: str  # SHA-256 of the file
    record: dict  # provenance: priors/evidence digests, method, date, effective sample size

    def representative_sets(self, k: int = None) -> np.ndarray:
        """``k`` set indices (default :data:`ENSEMBLE_SETS`) that stand for the posterior with
        equal weight: systematic resampling of the weights at the points (j + 1/2)/k of their
        cumulative sum, deterministic (a heavy set may appear more than once)."""
        return conditioning.systematic_resample(self.weights, ENSEMBLE_SETS if k is None else k)

    def set_choice(self) -> dist.Choice:
        """The distribution of :data:`SET_INPUT`: :meth:`representative_sets` with equal weights,
        so that the drops of an ensemble share few sets and the per-set class probabilities of
        the epistemic band are estimated from many drops each (docs/calibration.md)."""
        sets = self.representative_sets()
        return dist.Choice(tuple(float(i) for i in sets), tuple(1.0 / sets.size for _ in sets))

    def stale(self) -> str | None:
        """Why this posterior no longer matches the package's priors or evidence, or None."""
        for key, path in (("priors_sha256", PRIORS_FILE), ("evidence_sha256", EVIDENCE_FILE)):
            if self.record.get(key) != file_digest(path):
                return f"{path.name} changed since it was built ({self.record.get('created', '?')})"
        return None

    def provenance(self) -> dict:
        """What the output records of the posterior an ensemble drew from."""
        keys = (
            "created",
            "method",
            "n_prior_sets",
            "seed",
            "priors_sha256",
            "evidence_sha256",
            "ess",
            "ess_blocks",
        )
        return {
            "source": self.source,
            "sha256": self.digest,
            "coefficients": list(self.paths),
            "sets": len(self.weights),
            **{k: self.record.get(k) for k in keys},
        }


def load(which, base_dir=None) -> Posterior:
    """The posterior ``which``: ``"posterior"`` (the shipped one) or a file path (relative
    to ``base_dir``)."""
    if which == SHIPPED:
        path, source = POSTERIOR_FILE, "shipped"
    else:
        path = pathlib.Path(which)
        if base_dir is not None and not path.is_absolute():
            path = pathlib.Path(base_dir) / path
        source = str(path)
    try:
        data = path.read_bytes()
        record = json.loads(data)
    except OSError as exc:
        raise ScenarioError(f"ensemble.coefficients: cannot read {path}: {exc.strerror}") from None
    except ValueError as exc:
        raise ScenarioError(f"ensemble.coefficients: {path} is not a posterior file (JSON: {exc})") from None
    if not isinstance(record, dict) or record.get("format") != "mineburial-posterior":
        raise ScenarioError(
            f"ensemble.coefficients: {path} is not a posterior file written by mineburial calibrate"
        )
    paths = tuple(record["coefficients"])
    labels = record.get("labels", {})
    table = np.empty((len(record["sets"]), len(paths)))
    for k, path_k in enumerate(paths):
        column = [row[k] for row in record["sets"]]
        if path_k in labels:
            table[:, k] = [model_form.CHOICE_FIELDS[path_k].index(v) for v in column]
        else:
            table[:, k] = column
    w = np.asarray(record["weights"], dtype=np.float64)
    if w.shape != (table.shape[0],) or not (np.all(w >= 0) and w.sum() > 0):
        raise ScenarioError(f"ensemble.coefficients: {path}: the weights do not match the sets")
    return Posterior(paths, table, w / w.sum(), source, hashlib.sha256(data).hexdigest(), record)


#: the coefficients only the ``scour_settle`` burial law reads (priors.toml's)
SCOUR_SETTLE_COEFFICIENTS = ("scour.wave_a", "scour.wave_kc_exponent", "scour.infill_days")


def scour_law(coefficients) -> str:
    """The burial law (``scour.burial_law``) under which a coefficient set's scour coefficients
    are conditioned (the calibration's scour case runs the set under it): ``scour_settle`` when
    the set (its paths, or ``path -> value``) carries one of that law's coefficients, as the
    priors of priors.toml do, else the stage's default ``rennie``."""
    return "scour_settle" if any(k in coefficients for k in SCOUR_SETTLE_COEFFICIENTS) else "rennie"


def drawn_paths(posterior: Posterior, raw: dict) -> tuple[str, ...]:
    """The posterior's coefficients that scenario ``raw`` does not give itself; those of the
    post-impact scour stage only where the scenario has a ``[scour]`` section whose burial law
    is the one they were conditioned under (:func:`scour_law`): the coefficients a, b of
    B_eq = a theta^b conditioned with the scour-and-settle law are not those of ``rennie``, so a
    ``rennie`` section keeps its own (or the defaults)."""
    out = []
    section_scour = raw.get("scour")
    same_law = isinstance(section_scour, dict) and section_scour.get("burial_law", "rennie") == scour_law(
        posterior.paths
    )
    for path in posterior.paths:
        section, name = path.split(".")
        if section == "scour" and not same_law:
            continue
        if name not in raw.get(section, {}):
            out.append(path)
    return tuple(out)
