"""The Monte Carlo ensemble engine: an ensemble scenario, and the per-drop results of
any chunk of its drops computed in compiled code.

An ensemble scenario is an ordinary scenario file in which any numeric input may
be a distribution (``mass = {distribution = "normal", mean = 750, std = 20}``),
``sediment.class`` / ``sediment.file`` may be a ``choice`` among catalogue
classes or core files, and an optional ``[ensemble]`` table sets ``n``, ``seed``,
``sampling``, ``chunk_size``, ``per_drop`` and ``class_basis``.

The optional top-level key ``system`` names the system the ensemble runs (:data:`SYSTEMS`):
``"mine"`` (the default, this module: the falling mine) or ``"restraint"`` (seed 004's
restraining system: the scenario is then a restraint case file with distributions,
:mod:`mineburial.ensembles.restraint`). :func:`load_ensemble` reads either; the run driver
computes, stores and writes the chunks of both alike.

Drops are processed in chunks ``[start, stop)`` (:func:`compute_chunk`). Every
random input of drop *i* is a pure function of ``(seed, i)``
(:mod:`mineburial.ensembles.sampling`) and each drop writes only its own result
row, so a chunk gives the same bits for any chunk size, thread count or dask
worker. Running the chunks, keeping finished ones on disk and reducing them to
statistics is the run driver's job (:mod:`mineburial.ensembles.runner`, with the
chunk store :mod:`mineburial.ensembles.store`).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import pathlib
from collections.abc import Mapping
from typing import ClassVar

import numpy as np

from mineburial import config as cfg
from mineburial.ensembles import distributions as dist
from mineburial.ensembles import model_form, scour
from mineburial.ensembles.interrupt import Interrupted
from mineburial.ensembles.sampling import sample_fields
from mineburial.ensembles.settings import check_ensemble_settings, input_files_of
from mineburial.io.inputs import read_toml
from mineburial.kernels import layout
from mineburial.sediment_profiles import catalogue_profile, load_file, pack_banks, unknown_name_message

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

DEFAULT_SCENARIO = (
    pathlib.Path(__file__).resolve().parent.parent / "data" / "ensembles" / "default_soft_mud.toml"
)

ENSEMBLE_DEFAULTS = {
    "n": 1000,
    "seed": 0,
    "sampling": "mc",
    "chunk_size": 256,
    "per_drop": False,
    "class_basis": "burial_volume",
    "accuracy_check": 8,  # drops re-run on the tight reference path after a run (accuracy.py; 0: off)
}
_ENSEMBLE_KEYS = tuple(ENSEMBLE_DEFAULTS)
#: the systems an ensemble scenario may name with its top-level ``system`` key
SYSTEMS = ("mine", "restraint")
_ANGLE_FIELDS = ("release.roll_deg", "release.pitch_deg", "release.heading_deg")
_INERTIA_INPUTS = ("mine.mass", "mine.length", "mine.diameter")


class EnsembleError(cfg.ScenarioError):
    """A problem with an ensemble scenario (bad distribution, field that cannot vary)."""


# ---------------------------------------------------------------------------
# scenario with distributions
# ---------------------------------------------------------------------------
def _walk(node, path, out):
    """Collect (path, value) of every distribution leaf and every choice of strings."""
    if isinstance(node, Mapping):
        if dist.is_distribution_table(node):
            out[path] = node
            return
        for key, value in node.items():
            _walk(value, f"{path}.{key}" if path else key, out)
    elif isinstance(node, list):
        for k, value in enumerate(node):
            if isinstance(value, Mapping) and dist.is_distribution_table(value):
                out[f"{path}[{k}]"] = value


def _set_path(d, path, value):
    parts = path.replace("]", "").split(".")
    node = d
    for part in parts[:-1]:
        node = node[part]
    last = parts[-1]
    if "[" in last:
        key, idx = last.split("[")
        node[key][int(idx)] = value
    else:
        node[last] = value


def _representative(d: dist.Distribution):
    """A value inside the support used to validate the scenario's fixed structure."""
    if isinstance(d, dist.Choice):
        return d.values[0]
    return float(d.ppf(np.array([0.5]))[0])


@dataclasses.dataclass(frozen=True)
class EnsembleSpec:
    """Everything needed to compute any chunk of an ensemble (picklable)."""

    raw: dict  # the scenario as given (distributions as tables)
    base: cfg.Scenario  # scenario with each distribution at a representative value
    random: dict  # path -> Distribution
    n: int
    seed: int
    sampling: str
    chunk_size: int
    per_drop: bool
    class_basis: str
    base_params: np.ndarray
    sediment_bank: np.ndarray
    current_bank: np.ndarray
    sediment_labels: tuple  # labels of a sediment choice, in bank-row order
    sediment_choice: str | None  # "sediment.class" or "sediment.file" when it varies
    recompute_inertia: bool
    angles_deg: tuple  # (roll, pitch, heading) of the base scenario
    input_files: tuple = ()  # ((path, SHA-256 of its contents), ...) of the files read
    scour: scour.ScourSpec | None = None  # the optional post-impact scour stage ([scour])
    accuracy_check: int = ENSEMBLE_DEFAULTS["accuracy_check"]  # the self-check's size (accuracy.py)

    system: ClassVar[str] = "mine"
    #: columns of a chunk's ``summary``
    summary_width: ClassVar[int] = layout.N_SUMMARY
    #: what one realization is, in messages
    unit: ClassVar[str] = "drops"

    def identity_items(self) -> list:
        """What decides the per-drop results beside the resolved scenario, the
        distributions and the settings (:func:`mineburial.ensembles.store.run_identity`):
        the packed parameters and banks handed to the kernels and the derived options."""
        items = []
        for name in ("base_params", "sediment_bank", "current_bank"):
            arr = np.ascontiguousarray(getattr(self, name), dtype=np.float64)
            items.append((name, f"{arr.shape}".encode() + arr.tobytes()))
        items.append(
            (
                "options",
                repr((self.sediment_labels, self.sediment_choice, self.recompute_inertia, self.angles_deg)),
            )
        )
        if self.scour is not None:
            items.append(("scour", self.scour.identity()))
        return items

    def resolved(self) -> dict:
        """The resolved scenario written into outputs: the base scenario fully
        resolved, the distributions of the random inputs, the files read (with the
        SHA-256 of their contents) and the run settings."""
        out = {
            "scenario": self.base.to_dict(),
            "random_inputs": {k: v.to_dict() for k, v in self.random.items()},
            "ensemble": {
                "n": self.n,
                "seed": self.seed,
                "sampling": self.sampling,
                "chunk_size": self.chunk_size,
                "per_drop": self.per_drop,
                "class_basis": self.class_basis,
            },
        }
        if self.input_files:
            out["input_files"] = {path: digest for path, digest in self.input_files}
        if self.scour is not None:
            out["scour"] = self.scour.resolved()
        return out


def refuse_scour(spec, command: str) -> None:
    """One line for a command that does not run the post-impact stage yet (docs/scour.md)."""
    if getattr(spec, "scour", None) is not None:
        raise cfg.ScenarioError(
            f"[scour]: `mineburial {command}` does not run the post-impact stage yet; "
            "use `mineburial run`, or remove the section"
        )


def load_ensemble(
    source=None,
    *,
    n=None,
    seed=None,
    sampling=None,
    chunk_size=None,
    per_drop=None,
    class_basis=None,
    base_dir=None,
    systems=("mine",),
):
    """Parse an ensemble scenario (path, TOML text dict, or None for the embedded default).

    Keyword arguments override the ``[ensemble]`` table. ``systems``: the values of the
    scenario's ``system`` key the caller can run (default only ``"mine"``, the falling
    mine: maps, comparisons and sensitivity indices are of burial); ``mineburial run``
    passes :data:`SYSTEMS`. Returns an :class:`EnsembleSpec`, or for
    ``system = "restraint"`` a :class:`mineburial.ensembles.restraint.RestraintEnsembleSpec`.
    """
    if source is None:
        source = DEFAULT_SCENARIO
    if isinstance(source, EnsembleSpec):
        raw = copy.deepcopy(source.raw)
    elif isinstance(source, Mapping):
        raw = copy.deepcopy(dict(source))
    elif isinstance(source, cfg.Scenario):
        raw = source.to_dict()
    else:
        path = pathlib.Path(source)
        try:
            raw = read_toml(path)
        except OSError as exc:
            raise cfg.ScenarioError(f"cannot read scenario file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise cfg.ScenarioError(f"scenario file '{path}' is not valid TOML: {exc}") from None
        base_dir = base_dir or path.resolve().parent
    system = raw.pop("system", "mine")
    if system not in SYSTEMS:
        raise cfg.ScenarioError(unknown_name_message("system", system, SYSTEMS))
    if system not in systems:
        raise cfg.ScenarioError(
            f"system = {system!r}: this command runs only {' or '.join(repr(s) for s in systems)} "
            f"ensembles; run a {system!r} ensemble with 'mineburial run'"
        )
    if system == "restraint":
        from mineburial.ensembles import restraint

        overrides = {"n": n, "seed": seed, "sampling": sampling, "chunk_size": chunk_size}
        overrides.update(per_drop=per_drop, class_basis=class_basis)
        return restraint.load(raw, overrides, base_dir)
    ens = dict(ENSEMBLE_DEFAULTS)
    given = raw.pop("ensemble", {})
    if not isinstance(given, Mapping):
        raise cfg.ScenarioError(
            f"ensemble = {given!r} must be a table: [ensemble] with {', '.join(_ENSEMBLE_KEYS)}"
        )
    unknown = [key for key in given if key not in _ENSEMBLE_KEYS]
    if unknown:
        raise cfg.ScenarioError("[ensemble]: " + cfg.unknown_names_message("key", unknown, _ENSEMBLE_KEYS))
    ens.update(given)
    for key, value in (
        ("n", n),
        ("seed", seed),
        ("sampling", sampling),
        ("chunk_size", chunk_size),
        ("per_drop", per_drop),
        ("class_basis", class_basis),
    ):
        if value is not None:
            ens[key] = value
    check_ensemble_settings(ens)

    leaves = {}
    _walk(raw, "", leaves)
    random = {}
    template = copy.deepcopy(raw)
    for path, table in leaves.items():
        d = dist.from_dict(table, path, base_dir=base_dir)
        if path in ("sediment.class", "sediment.file") and not isinstance(d, dist.Choice):
            raise EnsembleError(
                f"{path} can only vary as a 'choice' distribution, got {type(d).__name__.lower()}"
            )
        if path in model_form.CHOICE_FIELDS and model_form.check_labels(path, d):
            raise EnsembleError(model_form.check_labels(path, d))
        cfg.check_distribution(path, d)
        random[path] = d
        _set_path(template, path, _representative(d))
    scour_section = template.pop("scour", None)
    base = cfg.Scenario.from_dict(template, base_dir=base_dir)
    fixed_depth = None if "environment.water_depth" in random else base.environment.water_depth
    scour_spec = None if scour_section is None else scour.parse(scour_section, base_dir, fixed_depth)
    p, sed_bank, cur_bank = base.to_params()

    labels = ()
    choice = None
    for key in ("sediment.class", "sediment.file"):
        if key in random:
            labels = tuple(str(v) for v in random[key].values)
            if key == "sediment.class":
                profiles = [catalogue_profile(v) for v in labels]
            else:
                profiles = [load_file(v, base_dir) for v in labels]
            sed_bank = pack_banks(profiles)
            choice = key
    for path in random:
        if path in (choice,) or path in _ANGLE_FIELDS or path in model_form.CHOICE_FIELDS:
            continue
        if path.startswith("scour.") and path in cfg.FIELDS:  # the stage's own inputs (scour.py)
            continue
        slot = cfg.ALIASES.get(path, path)
        if slot not in layout.INDEX or slot not in cfg.FIELDS:  # not a number: a name, a code
            raise EnsembleError(
                f"{path} cannot vary in an ensemble: only numeric inputs of the kernels "
                f"(docs/scenario.md), the release angles and sediment.class/sediment.file can"
            )
        if isinstance(random[path], dist.Choice) and not all(
            isinstance(v, (int, float)) for v in random[path].values
        ):
            raise EnsembleError(f"{path}: a choice for a numeric input needs numeric values")
    rel = raw.get("release", {})
    explicit_inertia = any(k in raw.get("mine", {}) for k in ("inertia_axial", "inertia_transverse"))
    recompute = (not explicit_inertia) and any(k in random for k in _INERTIA_INPUTS)
    angles = tuple(
        float(rel.get(k.split(".")[1], 0.0)) if not isinstance(rel.get(k.split(".")[1]), Mapping) else 0.0
        for k in _ANGLE_FIELDS
    )
    if any(k in random for k in _ANGLE_FIELDS) and "quaternion" in rel:
        raise EnsembleError("release: random angles cannot be combined with a fixed quaternion")
    files = input_files_of(raw, random, base_dir)
    if scour_spec is not None and "forcing_file" in scour_spec.forcing_record:
        rec = scour_spec.forcing_record
        files += ((rec["forcing_file"], rec["forcing_sha256"]),)
    return EnsembleSpec(
        raw=raw,
        base=base,
        random=random,
        n=int(ens["n"]),
        seed=int(ens["seed"]),
        sampling=str(ens["sampling"]),
        chunk_size=int(ens["chunk_size"]),
        per_drop=bool(ens["per_drop"]),
        class_basis=str(ens["class_basis"]),
        base_params=p,
        sediment_bank=sed_bank,
        current_bank=cur_bank,
        sediment_labels=labels,
        sediment_choice=choice,
        recompute_inertia=recompute,
        angles_deg=angles,
        input_files=files,
        scour=scour_spec,
        accuracy_check=int(ens["accuracy_check"]),
    )


# ---------------------------------------------------------------------------
# one chunk
# ---------------------------------------------------------------------------
def chunk_inputs(spec: EnsembleSpec, start: int, stop: int, table=None):
    """Packed parameters, validity mask and sampled inputs of drops [start, stop).

    ``table`` (optional): the sampled inputs to pack instead of drawing them, a mapping
    of each of ``spec.random``'s fields to its values for these drops (as returned by
    :func:`~mineburial.ensembles.sampling.sample_fields`). ``mineburial compare`` draws
    once and packs the same draws into every variant; ``mineburial sensitivity`` packs
    the points of its Sobol' design.
    """
    n = stop - start
    P = np.tile(spec.base_params, (n, 1))
    inputs = {}
    if spec.random:
        if table is None:
            table = sample_fields(spec.random, spec.seed, start, stop, spec.sampling)
        for path, values in table.items():
            values = np.asarray(values)
            if path == spec.sediment_choice:
                P[:, layout.P_SED_PROFILE] = values
                inputs[path] = values.astype(np.float64)
                continue
            if path in _ANGLE_FIELDS or path.startswith("scour."):
                inputs[path] = values.astype(np.float64)
                continue
            if path in model_form.CHOICE_FIELDS:  # label indices -> the labels' codes
                values = model_form.codes(path, spec.random[path], values)
            slot = cfg.ALIASES.get(path, path)
            P[:, layout.INDEX[slot]] = values
            inputs[path] = values.astype(np.float64)
        if any(k in spec.random for k in _ANGLE_FIELDS):
            ang = [inputs.get(k, np.full(n, spec.angles_deg[j])) for j, k in enumerate(_ANGLE_FIELDS)]
            q = cfg.quaternion_from_angles(*(np.radians(a) for a in ang))
            P[:, layout.P_Q00 : layout.P_Q30 + 1] = q
        if spec.recompute_inertia:
            P[:, layout.P_J1], P[:, layout.P_J2] = cfg.uniform_cylinder_inertia(
                P[:, layout.P_MASS], P[:, layout.P_DIAMETER], P[:, layout.P_LENGTH]
            )
    valid = cfg.check_params(
        P,
        n_sediment=spec.sediment_bank.shape[0],
        n_current=spec.current_bank.shape[0],
        embedded=spec.base.release.embedded,
    )
    valid &= cfg.check_samples(inputs, n)  # also the release angles, not in P
    return P, valid, inputs


def compute_chunk(spec, start: int, stop: int) -> dict:
    """Run drops [start, stop): returns a dict of per-drop arrays (``summary``,
    ``status``, ``input:<path>`` of every sampled input) and ``invalid_inputs``, the
    reasons why drops were not run (:func:`invalid_reasons`). A restraint ensemble's
    cases are run by :func:`mineburial.ensembles.restraint.compute_chunk` (the same dict).

    On Ctrl-C the :class:`~mineburial.ensembles.batch.Interrupted` raised carries in
    ``partial`` the dict of the drops finished first, ``[start, start + done)``."""
    if spec.system == "restraint":
        from mineburial.ensembles import restraint

        return restraint.compute_chunk(spec, start, stop)
    from mineburial.ensembles.batch import run_batch

    P, valid, inputs = chunk_inputs(spec, start, stop)
    try:
        summary, status = run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    except Interrupted as exc:  # Ctrl-C: the drops finished first are a chunk of their own
        k = exc.done
        if k == 0:  # nothing to keep (and no stage to load while a drop thread may hold the compiler)
            raise
        part = {key: v[:k] for key, v in inputs.items()}
        exc.partial = _chunk_result(spec, start, start + k, P[:k], valid[:k], exc.summary, exc.status, part)
        raise
    return _chunk_result(spec, start, stop, P, valid, summary, status, inputs)


def _chunk_result(spec, start, stop, P, valid, summary, status, inputs) -> dict:
    out = {
        "start": np.int64(start),
        "stop": np.int64(stop),
        "summary": summary,
        "status": status,
        "invalid_inputs": np.array(json.dumps(invalid_reasons(spec, P, valid), sort_keys=True)),
    }
    if spec.scour is not None:
        out.update(scour.run_chunk(spec.scour, P, summary, status, inputs))
    for k, v in inputs.items():
        out["input:" + k] = v
    return out


def input_metadata(spec: EnsembleSpec, path: str) -> tuple[str, str]:
    """(UDUNITS units, description) of the sampled input ``path`` in the output."""
    if path == spec.sediment_choice:
        return "1", f"index into the sediment choices: {', '.join(spec.sediment_labels)}"
    if path in _ANGLE_FIELDS:
        return "degree", path.split(".")[1].replace("_deg", "") + " angle at release"
    if path in model_form.CHOICE_FIELDS:
        names = model_form.CHOICE_FIELDS[path]
        return "1", f"code of {path}: " + ", ".join(f"{k} {v}" for k, v in enumerate(names))
    field = cfg.FIELDS.get(cfg.ALIASES.get(path, path))
    if field is not None:
        return field.units, field.description
    return "1", path


def invalid_reasons(spec: EnsembleSpec, P, valid) -> dict:
    """Why the drops with ``valid`` False were not run: ``{constraint: [count, first
    offending values]}`` (the constraints of :func:`mineburial.config.explain_params`; the
    moments of inertia computed from a sampled mass or size are left out where the mass
    or size itself is the reason)."""
    reasons: dict = {}
    for i in np.flatnonzero(~np.asarray(valid, dtype=bool)):
        texts = cfg.explain_params(
            P[i], n_sediment=spec.sediment_bank.shape[0], n_current=spec.current_bank.shape[0]
        )
        if spec.recompute_inertia:  # inertia computed from a bad mass/size: not a reason
            texts = [t for t in texts if "inertia" not in t.partition(" (got ")[0]] or texts
        for text in texts:
            rule, _, got = text.partition(" (got ")
            entry = reasons.setdefault(rule, [0, got.rstrip(")")])
            entry[0] += 1
    return reasons


def chunk_bounds(n: int, chunk_size: int):
    """The chunks ``[(start, stop), ...]`` of ``n`` drops, ``chunk_size`` drops each (the
    last may be shorter)."""
    return [(s, min(s + chunk_size, n)) for s in range(0, n, chunk_size)]
