"""A posterior of coefficient sets, as written by ``mineburial calibrate`` (JSON), and how an
ensemble draws from it (issue 32; docs/calibration.md).

An ensemble with ``ensemble.coefficients = "posterior"`` (the shipped posterior) or a path
to a posterior file draws, for every drop, one coefficient set from the posterior's weighted
sets: the set's index is the sampled input :data:`SET_INPUT`, a ``choice`` among the set
indices with the posterior weights, drawn from its own stream like any other input (so the
other inputs' draws are unchanged), and the set's values go into the drop's parameter row.
A coefficient the scenario gives itself (a value or a distribution) is not taken from the
posterior.

The scour stage's burial law is a coefficient too (``scour.burial_law``, with a prior; issue 33):
each set carries a law, so the posterior weighs the laws by the evidence. A ``[scour]`` section
that names its law draws the coefficients of the posterior's sets of that law (the posterior
restricted to the law, :func:`restricted`); ``burial_law = "posterior"`` draws each drop's law with
its set (:func:`for_scenario`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import pathlib
from dataclasses import dataclass

import numpy as np

from mineburial.ensembles import distributions as dist
from mineburial.ensembles.store import notice
from mineburial.errors import ScenarioError
from mineburial.systems.mine.calibration import conditioning
from mineburial.systems.mine.calibration.priors import (
    EVIDENCE_FILE,
    POSTERIOR_FILE,
    PRIORS_FILE,
    choice_labels,
    file_digest,
)
from mineburial.systems.mine.scenario_fields import SCOUR_LAW_FROM_POSTERIOR

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
    #: the burial law whose sets the scour coefficients of every set were taken from
    #: (:func:`restricted`), or None: each set's own
    scour_law: str | None = None

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
        out = {
            "source": self.source,
            "sha256": self.digest,
            "coefficients": list(self.paths),
            "sets": len(self.weights),
            **{k: self.record.get(k) for k in keys},
        }
        if self.scour_law is not None:
            out["scour_coefficients_of_law"] = self.scour_law
        return out


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
            names = choice_labels(path_k)
            if names is None or any(v not in names for v in column):
                raise ScenarioError(
                    f"ensemble.coefficients: {path}: {path_k} holds labels other than {names}"
                )
            table[:, k] = [names.index(v) for v in column]
        else:
            table[:, k] = column
    w = np.asarray(record["weights"], dtype=np.float64)
    if w.shape != (table.shape[0],) or not (np.all(w >= 0) and w.sum() > 0):
        raise ScenarioError(f"ensemble.coefficients: {path}: the weights do not match the sets")
    return Posterior(paths, table, w / w.sum(), source, hashlib.sha256(data).hexdigest(), record)


#: the scour stage's burial law among a posterior's coefficients (priors.toml; a set's law)
LAW = "scour.burial_law"
#: the coefficients only the ``scour_settle`` burial law reads (priors.toml's); ``rennie`` does not
SCOUR_SETTLE_COEFFICIENTS = ("scour.wave_a", "scour.wave_kc_exponent", "scour.infill_days")
#: a burial law of less posterior probability than this has no sets to speak for it: a section
#: that names it draws no coefficient from the posterior (its own values, with a warning)
LAW_FLOOR = 0.01


def scour_law(coefficients) -> str:
    """The burial law under which the scour coefficients of a posterior file *without* a law per
    set (built before ``scour.burial_law`` had a prior) were conditioned: ``scour_settle`` when
    the set (its paths, or ``path -> value``) carries one of that law's coefficients, as such
    files' priors did, else the stage's default ``rennie``. A posterior with the law column
    carries each set's own law instead (:func:`law_probabilities`)."""
    return "scour_settle" if any(k in coefficients for k in SCOUR_SETTLE_COEFFICIENTS) else "rennie"


def law_probabilities(posterior: Posterior) -> dict | None:
    """Each burial law's posterior probability (the weight of the sets of that law), or None for
    a posterior without a law per set."""
    if LAW not in posterior.paths:
        return None
    codes = posterior.table[:, posterior.paths.index(LAW)]
    return {law: float(posterior.weights[codes == k].sum()) for k, law in enumerate(choice_labels(LAW))}


def restricted(posterior: Posterior, law: str) -> Posterior:
    """``posterior`` with the scour stage's coefficients of every set taken from its sets of burial
    law ``law``: the posterior conditioned on that law, in the scour block only (the other
    coefficients and the weights unchanged, so each drop keeps its set and its impact
    coefficients). A set of that law keeps its own; a set of another law, at the midpoint of its
    cumulative weight among those sets, takes those of the set of law ``law`` at the same point
    of their cumulative weight (systematic resampling), so that each set of the law carries
    w/P(law) in all and a drop whose set has that law is the same drop under ``burial_law =
    "posterior"``. The scour block's sets are in an order permuted independently of the impact
    block's (calibrate.posterior_record), so the pairing stays independent."""
    codes = posterior.table[:, posterior.paths.index(LAW)]
    mine = codes == choice_labels(LAW).index(law)
    w = posterior.weights
    if not np.any(mine & (w > 0)):
        raise ScenarioError(f"scour.burial_law = {law!r}: {_named(posterior)} has no set of that law")
    src = np.arange(w.size)
    other = np.flatnonzero(~mine)
    if other.size:
        w_other = w[other]
        cum_other = np.cumsum(w_other)
        mid = (cum_other - 0.5 * w_other) / max(cum_other[-1], np.finfo(float).tiny)
        cum_law = np.cumsum(np.where(mine, w, 0.0))
        cum_law /= cum_law[-1]
        src[other] = np.minimum(np.searchsorted(cum_law, mid, side="right"), w.size - 1)
    table = posterior.table.copy()
    cols = [k for k, p in enumerate(posterior.paths) if p.startswith("scour.")]
    table[:, cols] = posterior.table[src][:, cols]
    return dataclasses.replace(posterior, table=table, scour_law=law)


def _named(posterior: Posterior) -> str:
    """The posterior in a message: ``the shipped posterior`` or ``the posterior <path>``."""
    return "the shipped posterior" if posterior.source == "shipped" else f"the posterior {posterior.source}"


def _section_law(raw: dict) -> str | None:
    """The burial law a scenario's ``[scour]`` section names (``rennie`` by default), or None
    without a section."""
    section = raw.get("scour")
    if not isinstance(section, dict):
        return None
    return section.get("burial_law", "rennie")


def drawn_paths(posterior: Posterior, raw: dict) -> tuple[str, ...]:
    """The posterior's coefficients that scenario ``raw`` does not give itself; those of the
    post-impact scour stage only where the scenario has a ``[scour]`` section:

    - with a law per set (``scour.burial_law`` among the coefficients): a section that names its
      law draws the coefficients that law reads (of the posterior :func:`restricted` to it,
      :func:`for_scenario`), none when the law's posterior probability is below
      :data:`LAW_FLOOR`; ``burial_law = "posterior"`` draws every one and the law itself;
    - a posterior file without it: only a section whose law is the one they were conditioned
      under (:func:`scour_law`): the coefficients a, b of B_eq = a theta^b conditioned with the
      scour-and-settle law are not those of ``rennie``, so a ``rennie`` section keeps its own."""
    law = _section_law(raw)
    probabilities = law_probabilities(posterior)
    if law is None:
        scour = ()
    elif probabilities is None:
        if law == SCOUR_LAW_FROM_POSTERIOR:
            raise ScenarioError(
                f"scour.burial_law = {law!r} draws each drop's law from the posterior, but "
                f"{_named(posterior)} carries no law per set (built before the law had a prior): "
                "name the law, or rebuild the posterior (mineburial calibrate, docs/calibration.md)"
            )
        same = law == scour_law(posterior.paths)
        scour = [p for p in posterior.paths if p.startswith("scour.")] if same else ()
    elif law == SCOUR_LAW_FROM_POSTERIOR:
        scour = [p for p in posterior.paths if p.startswith("scour.")]
    elif probabilities.get(law, 0.0) < LAW_FLOOR:
        scour = ()
    else:
        unread = (LAW, *(SCOUR_SETTLE_COEFFICIENTS if law == "rennie" else ()))
        scour = [p for p in posterior.paths if p.startswith("scour.") and p not in unread]
    out = []
    for path in posterior.paths:
        section, name = path.split(".")
        if section == "scour" and path not in scour:
            continue
        if path == LAW or name not in raw.get(section, {}):
            out.append(path)
    return tuple(out)


def for_scenario(posterior: Posterior | None, raw: dict) -> tuple[Posterior | None, tuple[str, ...]]:
    """The posterior an ensemble of scenario ``raw`` draws from and the coefficients it draws
    (:func:`drawn_paths`); ``posterior`` None: the scenario's own coefficients (``"fixed"``).
    A ``[scour]`` section that names its law gets the posterior :func:`restricted` to that law;
    one whose law has a posterior probability below :data:`LAW_FLOOR` gets none of its
    coefficients, with a warning. ``burial_law = "posterior"`` needs a posterior."""
    law = _section_law(raw)
    if posterior is None:
        if law == SCOUR_LAW_FROM_POSTERIOR:
            raise ScenarioError(
                f"scour.burial_law = {law!r} draws each drop's law from a posterior: give "
                "ensemble.coefficients = 'posterior' (the shipped one) or a posterior file, or name the law"
            )
        return None, ()
    probabilities = law_probabilities(posterior)
    if probabilities is not None and law not in (None, SCOUR_LAW_FROM_POSTERIOR):
        if probabilities.get(law, 0.0) < LAW_FLOOR:
            notice(
                f"warning: scour.burial_law = {law!r} has posterior probability "
                f"{probabilities.get(law, 0.0):.3g} (< {LAW_FLOOR:g}) in {_named(posterior)}: the evidence "
                "leaves no sets of it, so the section's scour coefficients are its own (or the defaults), "
                "not the posterior's; burial_law = 'posterior' draws the laws by their weight"
            )
        else:
            posterior = restricted(posterior, law)
    return posterior, drawn_paths(posterior, raw)
