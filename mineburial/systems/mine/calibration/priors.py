"""The priors of the open coefficients and the evidence set, read from the package's
``data/calibration`` TOML files (issue 32; docs/calibration.md).

A *coefficient* is a scenario field (docs/scenario.md) that no measurement fixes: its prior
is a distribution in the scenario-file syntax (:mod:`mineburial.ensembles.distributions`)
with its source. An *evidence row* is one measurement: value, stated uncertainty, declared
model discrepancy, and the case that reproduces it (:mod:`mineburial.systems.mine.calibration.cases`). A
*nuisance* parameter is an unknown condition of an experiment (the Exp-1 pool depth), drawn
with every coefficient set and integrated out.

The files are versioned by their SHA-256, which the posterior records
(:mod:`mineburial.systems.mine.calibration.posterior`): a posterior built from other priors or other
evidence is reported stale.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import pathlib
from dataclasses import dataclass

import numpy as np

from mineburial.ensembles import distributions as dist
from mineburial.errors import ScenarioError
from mineburial.io.files import atomic_write_text
from mineburial.schema import replace_generated
from mineburial.systems.mine import model_form
from mineburial.systems.mine.scenario_fields import SCOUR_BURIAL_LAWS

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

DATA = pathlib.Path(__file__).resolve().parent.parent.parent.parent / "data" / "calibration"
PRIORS_FILE = DATA / "priors.toml"
EVIDENCE_FILE = DATA / "evidence.toml"
POSTERIOR_FILE = DATA / "posterior.json"

#: the quantities an evidence row may compare (mineburial.systems.mine.calibration.cases computes them)
QUANTITIES = {
    "travel_time": "continuous",
    "embedment_lengths": "continuous",
    "slant_straight": "binary",
    "flip_then_spiral": "binary",
    "burial_fraction": "continuous",
}


@dataclass(frozen=True)
class Prior:
    """The prior of one coefficient (a scenario field) or nuisance parameter."""

    path: str  # the scenario field, or "<case>.<name>" of a nuisance parameter
    distribution: dist.Distribution
    source: str
    units: str = ""
    #: a nuisance parameter integrated on this many points (quantile midpoints of its prior)
    #: instead of drawn with the sets; 0: drawn
    integrate: int = 0

    @property
    def categorical(self) -> bool:
        return isinstance(self.distribution, dist.Choice) and self.distribution.categorical

    def grid(self):
        """The integration points of an integrated nuisance parameter: the prior's quantiles at
        the midpoints (k + 1/2)/n, each standing for probability 1/n."""
        return self.distribution.ppf((np.arange(self.integrate) + 0.5) / self.integrate)


@dataclass(frozen=True)
class EvidenceRow:
    """One measurement of the evidence set."""

    id: str
    case: str  # the case builder (cases.CASES)
    variant: str  # which experiment of that case
    quantity: str  # a key of QUANTITIES
    observed: float
    units: str
    source: str
    assumptions: str
    sigma: float = 0.0  # measurement standard deviation (continuous rows)
    discrepancy: float = 0.0  # model-discrepancy standard deviation (continuous rows)
    error_rate: float = 0.0  # probability of disagreement when the model is right (binary rows)

    @property
    def binary(self) -> bool:
        return QUANTITIES[self.quantity] == "binary"

    @property
    def total_sigma(self) -> float:
        """sqrt(sigma^2 + discrepancy^2): the scale of a continuous row's Gaussian score."""
        return math.hypot(self.sigma, self.discrepancy)


def file_digest(path) -> str:
    """SHA-256 of a file's bytes (the version of a priors or evidence file)."""
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def _read(path) -> dict:
    path = pathlib.Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML ({exc})") from None


def _prior(entry: dict, where: str, key: str) -> Prior:
    for name in (key, "distribution", "source"):
        if name not in entry:
            raise ScenarioError(f"{where}: missing '{name}'")
    path = str(entry[key])
    d = dist.from_dict(entry["distribution"], path)
    integrate = entry.get("integrate", 0)
    if not isinstance(integrate, int) or isinstance(integrate, bool) or not 0 <= integrate <= 1000:
        raise ScenarioError(
            f"{where}: integrate = {integrate!r} must be an integer number of points in [0, 1000]"
        )
    return Prior(path, d, str(entry["source"]), str(entry.get("units", "")), integrate)


def choice_labels(path: str) -> tuple | None:
    """The labels of the model choice ``path`` that a prior may sample, in the order of their
    codes (a posterior file's table holds a label as its code), or None for a number: the impact
    phase's choices (:data:`mineburial.systems.mine.model_form.CHOICE_FIELDS`) and the scour stage's
    burial law (``scour.burial_law``: its laws, the kernel's codes; not ``posterior``, which asks a
    posterior for the law)."""
    if path in model_form.CHOICE_FIELDS:
        return tuple(model_form.CHOICE_FIELDS[path])
    if path == "scour.burial_law":
        return SCOUR_BURIAL_LAWS
    return None


def _check_labels(path: str, d) -> str | None:
    """Why the prior ``d`` of the model choice ``path`` is not a choice among its labels, or None."""
    labels = choice_labels(path)
    if not isinstance(d, dist.Choice) or not d.categorical:
        return f"{path} can only vary as a 'choice' among {', '.join(labels)}, got {d.family}" + (
            " of numbers" if isinstance(d, dist.Choice) else ""
        )
    bad = [v for v in d.values if v not in labels]
    if bad:
        return f"{path}: {', '.join(map(repr, bad))} not one of {', '.join(labels)}"
    if len(set(d.values)) != len(d.values):
        return f"{path}: a label is given twice in {list(d.values)}"
    return None


def load_priors(path=PRIORS_FILE) -> tuple[Prior, ...]:
    """The coefficient priors of ``path``, each checked against its field's allowed range
    (:func:`mineburial.systems.mine.config.check_distribution`) and, for a model choice, its labels."""
    # local import: config pulls in the kernels' layout; a priors file is read by calibrate and run only
    from mineburial.systems.mine import config as cfg

    raw = _read(path)
    out = []
    for j, entry in enumerate(raw.get("coefficient", [])):
        prior = _prior(entry, f"{path}: coefficient[{j}]", "path")
        if choice_labels(prior.path) is not None:
            why = _check_labels(prior.path, prior.distribution)
            if why:
                raise ScenarioError(f"{path}: {why}")
        elif prior.path not in cfg.FIELDS:
            raise ScenarioError(f"{path}: coefficient[{j}] path {prior.path!r} is not a scenario field")
        else:
            cfg.check_distribution(prior.path, prior.distribution)
        out.append(prior)
    paths = [p.path for p in out]
    if len(set(paths)) != len(paths):
        raise ScenarioError(f"{path}: a coefficient is given twice")
    if not out:
        raise ScenarioError(f"{path}: no [[coefficient]]")
    return tuple(out)


def load_evidence(path=EVIDENCE_FILE) -> tuple[tuple[EvidenceRow, ...], tuple[Prior, ...]]:
    """The evidence rows and the nuisance priors (path ``<case>.<name>``) of ``path``."""
    raw = _read(path)
    rows = []
    for j, entry in enumerate(raw.get("row", [])):
        where = f"{path}: row[{j}]"
        for name in ("id", "case", "variant", "quantity", "observed", "units", "source", "assumptions"):
            if name not in entry:
                raise ScenarioError(f"{where}: missing '{name}'")
        if entry["quantity"] not in QUANTITIES:
            raise ScenarioError(f"{where}: quantity {entry['quantity']!r} not one of {', '.join(QUANTITIES)}")
        known = {f.name for f in dataclasses.fields(EvidenceRow)}
        unknown = sorted(set(entry) - known)
        if unknown:
            raise ScenarioError(
                f"{where}: unknown key(s) {', '.join(unknown)} (allowed: {', '.join(sorted(known))})"
            )
        row = EvidenceRow(**entry)
        if row.binary:
            if not (0.0 < row.error_rate < 0.5) or row.observed not in (0.0, 1.0):
                raise ScenarioError(f"{where}: a binary row needs observed 0 or 1 and 0 < error_rate < 0.5")
        elif not row.total_sigma > 0.0:
            raise ScenarioError(f"{where}: a continuous row needs sigma or discrepancy > 0")
        rows.append(row)
    ids = [r.id for r in rows]
    if len(set(ids)) != len(ids):
        raise ScenarioError(f"{path}: an evidence row id is given twice")
    nuisance = []
    for j, entry in enumerate(raw.get("nuisance", [])):
        entry = dict(entry)
        entry["path"] = f"{entry.get('case')}.{entry.get('name')}"
        nuisance.append(_prior(entry, f"{path}: nuisance[{j}]", "path"))
    return tuple(rows), tuple(nuisance)


#: who writes the priors table of docs/physics.md (schema.replace_generated's markers)
DOC_WRITER = "mineburial.systems.mine.calibration.priors.write_prior_table"


def _prior_text(d: dist.Distribution) -> str:
    """A prior in a few words: ``uniform 0.2-0.6``, ``a 1 : b 1``."""
    if isinstance(d, dist.Choice):
        return " : ".join(f"{v} {w:g}" for v, w in zip(d.values, d.weights))
    if isinstance(d, dist.Uniform):
        return f"uniform {d.low:g} to {d.high:g}"
    return ", ".join(f"{k} {v}" for k, v in d.to_dict().items())


def prior_table(path=PRIORS_FILE) -> str:
    """The Markdown table of every coefficient prior of ``path`` (docs/physics.md)."""
    lines = ["| coefficient | prior | source |", "|---|---|---|"]
    for p in load_priors(path):
        lines.append(f"| `{p.path}` | {_prior_text(p.distribution)} | {p.source} |")
    return "\n".join(lines) + "\n"


def write_prior_table(doc="docs/physics.md") -> None:
    """Regenerate the priors table of ``doc`` from priors.toml (run from the repository root;
    tests/test_calibration.py fails until then)."""
    doc = pathlib.Path(doc)
    atomic_write_text(
        doc, replace_generated(doc.read_text(encoding="utf-8"), "priors", prior_table(), DOC_WRITER)
    )
