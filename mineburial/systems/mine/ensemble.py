"""The falling mine as an ensemble system (the default ``system = "mine"``): its
ensemble scenario, the per-drop results of any chunk of its drops computed in compiled
code, its output dataset and its printed summary.

An ensemble scenario is an ordinary scenario file in which any numeric input may
be a distribution (``mass = {distribution = "normal", mean = 750, std = 20}``),
``sediment.class`` / ``sediment.file`` may be a ``choice`` among catalogue
classes or core files, and an optional ``[ensemble]`` table sets ``n``, ``seed``,
``sampling``, ``chunk_size``, ``per_drop`` and ``class_basis``.

Drops are processed in chunks ``[start, stop)`` (:func:`compute_chunk`). Every
random input of drop *i* is a pure function of ``(seed, i)``
(:mod:`mineburial.ensembles.sampling`) and each drop writes only its own result
row, so a chunk gives the same bits for any chunk size, thread count or dask
worker. The system registry (:mod:`mineburial.systems.registry`) hands these functions
to the generic layer: :func:`mineburial.ensembles.engine.load_ensemble` reads a
scenario of any system, the run driver (:mod:`mineburial.ensembles.runner`, with the
chunk store :mod:`mineburial.ensembles.store`) runs, keeps and reduces the chunks.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import pathlib
from collections.abc import Mapping
from typing import ClassVar

import numpy as np

from mineburial._version import __version__
from mineburial.ensembles import distributions as dist
from mineburial.ensembles.interrupt import Interrupted
from mineburial.ensembles.sampling import sample_fields
from mineburial.ensembles.settings import check_ensemble_settings, input_files_of, merge_invalid_reasons
from mineburial.ensembles.store import notice
from mineburial.errors import EnsembleError, ScenarioError, unknown_names_message
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as st
from mineburial.kernels.mine.bodies.shapes import SHAPES, shape_of_params
from mineburial.kernels.mine.stepper import MAX_STEPS
from mineburial.systems.mine import accuracy, batch, epistemic, model_form
from mineburial.systems.mine import config as cfg
from mineburial.systems.mine.calibration import posterior
from mineburial.systems.mine.calibration.priors import choice_labels
from mineburial.systems.mine.dataset import build_dataset
from mineburial.systems.mine.processes import registry as processes
from mineburial.systems.mine.sediment_profiles import catalogue_profile, load_file, pack_banks

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

#: the value of the scenario's top-level ``system`` key that selects this module (the default)
SYSTEM = "mine"
DEFAULT_SCENARIO = (
    pathlib.Path(__file__).resolve().parent.parent.parent / "data" / "ensembles" / "default_soft_mud.toml"
)

ENSEMBLE_DEFAULTS = {
    "n": 1000,
    "seed": 0,
    "sampling": "mc",
    "chunk_size": 256,
    "per_drop": False,
    "class_basis": "burial_volume",
    # drops re-run on the tight reference path after a run: "auto" (~15 % of the run's time, 8 to
    # 230 drops: accuracy.default_size), an integer (0: off)
    "accuracy_check": accuracy.AUTO,
    # the open coefficients: "fixed" (the scenario's values and the fields' defaults), "posterior"
    # (drawn per drop from the shipped posterior of `mineburial calibrate`) or a posterior file
    "coefficients": posterior.FIXED,
}
_ENSEMBLE_KEYS = tuple(ENSEMBLE_DEFAULTS)
_ANGLE_FIELDS = ("release.roll_deg", "release.pitch_deg", "release.heading_deg")
#: the sampled inputs whose values change the default inertia (the mass and the shape's sizes)
_INERTIA_INPUTS = ("mine.mass", *dict.fromkeys(f for shape in SHAPES.values() for f in shape.inertia_fields))
#: time steps a drop above which a fixed-step integrator gets a warning: the stepper's step
#: budget, after which a drop still moving ends ``time_limit``
STEPS_WARNING = float(MAX_STEPS)
_FIXED_STEP = ("rk4", "local_linear")


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
    # ((section, spec), ...) of the post-impact processes the scenario has a section of (processes/)
    processes: tuple = ()
    accuracy_check: int | str = ENSEMBLE_DEFAULTS["accuracy_check"]  # the self-check's size (accuracy.py)
    posterior: posterior.Posterior | None = None  # the coefficient sets drawn per drop, if any
    posterior_paths: tuple = ()  # the posterior's coefficients this scenario does not give itself

    system: ClassVar[str] = SYSTEM
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
        for process, spec in processes.active(self.processes):
            items.append((process.section, process.identity(spec)))
        if self.posterior is not None:
            items.append(("posterior", repr((self.posterior.digest, self.posterior_paths)).encode()))
        return items

    def sampled_inputs(self, start: int, stop: int):
        """The random inputs of drops ``[start, stop)``: each field's values for these drops
        from its Philox stream (:func:`~mineburial.ensembles.sampling.sample_fields`). A spec
        whose drops are given points instead (``mineburial sensitivity``'s Sobol' design)
        overrides it."""
        return sample_fields(self.random, self.seed, start, stop, self.sampling)

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
                "coefficients": posterior.FIXED if self.posterior is None else self.posterior.source,
            },
        }
        if self.posterior is not None:
            out["posterior"] = {**self.posterior.provenance(), "drawn": list(self.posterior_paths)}
        if self.input_files:
            out["input_files"] = {path: digest for path, digest in self.input_files}
        for process, spec in processes.active(self.processes):
            out[process.section] = process.resolved(spec)
        return out

    def process(self, section: str):
        """The spec of the post-impact process ``section`` (None when the scenario has no such section)."""
        return dict(self.processes).get(section)

    def lead_time_sections(self) -> tuple:
        """The sections of the active post-impact processes that change the burial over lead times
        (the run's lead-time figure, :func:`mineburial.systems.mine.figures.check_lead_time_plot`)."""
        found = processes.active(self.processes)
        return tuple(p.section for p, _ in found if isinstance(p, processes.BurialProcess))

    def with_process(self, section: str, spec) -> EnsembleSpec:
        """This ensemble with the spec of its process ``section`` replaced by ``spec``."""
        return dataclasses.replace(
            self, processes=tuple((name, spec if name == section else old) for name, old in self.processes)
        )


def load(raw: Mapping, overrides: Mapping, base_dir=None) -> EnsembleSpec:
    """A mine ensemble from the parsed scenario ``raw`` (without its ``system`` key; its
    ``[ensemble]`` table, if any, still in it); ``overrides``: the run's settings given on
    the command line or by the caller (None where not given)."""
    raw = dict(raw)
    ens = dict(ENSEMBLE_DEFAULTS)
    given = raw.pop("ensemble", {})
    if not isinstance(given, Mapping):
        raise ScenarioError(
            f"ensemble = {given!r} must be a table: [ensemble] with {', '.join(_ENSEMBLE_KEYS)}"
        )
    unknown = [key for key in given if key not in _ENSEMBLE_KEYS]
    if unknown:
        raise ScenarioError("[ensemble]: " + unknown_names_message("key", unknown, _ENSEMBLE_KEYS))
    ens.update(given)
    for key, value in overrides.items():
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
    sections = {name: template.pop(name) for name in processes.PROCESSES if name in template}
    base = cfg.Scenario.from_dict(template, base_dir=base_dir)
    active = processes.load_all(sections, base_dir=base_dir, base=base, template=template, random=random)
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
        if processes.owns_input(path) and path in cfg.FIELDS:  # a post-impact process's own inputs
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
    post, drawn = _posterior(ens["coefficients"], raw, base_dir, base.numerics.model)
    if drawn:
        random[posterior.SET_INPUT] = post.set_choice()
    files = input_files_of(raw, random, base_dir)
    for process, spec in processes.active(active):
        files += process.input_files(spec)
    if drawn:  # kept with the scenario, so that a variant or a map cell re-loaded from it draws too
        raw["ensemble"] = {"coefficients": ens["coefficients"]}
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
        processes=active,
        accuracy_check=_check_size_setting(ens["accuracy_check"]),
        posterior=post if drawn else None,
        posterior_paths=drawn,
    )


def _posterior(which, raw, base_dir, model):
    """The posterior of ``ensemble.coefficients`` and the coefficients drawn from it (those
    the scenario does not give itself); (None, ()) for ``"fixed"``. A posterior is of the
    ``mineburial`` model, whose cases it was calibrated on: another model is refused."""
    if not isinstance(which, str) or not which:
        raise ScenarioError(
            f"ensemble.coefficients = {which!r} must be 'fixed', 'posterior' (the shipped posterior) "
            "or the path of a posterior file written by mineburial calibrate"
        )
    if which == posterior.FIXED:
        return posterior.for_scenario(None, raw)
    if model != posterior.CALIBRATED_MODEL:
        raise ScenarioError(
            f"ensemble.coefficients = {which!r}: the posterior was calibrated with numerics.model = "
            f"'{posterior.CALIBRATED_MODEL}', not {model!r}; give ensemble.coefficients = 'fixed' "
            "for another model"
        )
    post = posterior.load(which, base_dir)
    why = post.stale() if post.source == "shipped" else None
    if why:
        notice(f"warning: the shipped posterior is stale: {why}; rebuild it (docs/calibration.md)")
    return posterior.for_scenario(post, raw)  # a [scour] section's law restricts its block (issue 33)


# ---------------------------------------------------------------------------
# one chunk
# ---------------------------------------------------------------------------
def chunk_inputs(spec: EnsembleSpec, start: int, stop: int):
    """Packed parameters, validity mask and sampled inputs of drops [start, stop) (the
    random inputs from :meth:`EnsembleSpec.sampled_inputs`)."""
    n = stop - start
    P = np.tile(spec.base_params, (n, 1))
    inputs = {}
    if spec.random:
        for path, values in spec.sampled_inputs(start, stop).items():
            values = np.asarray(values)
            if path == spec.sediment_choice:
                P[:, layout.P_SED_PROFILE] = values
                inputs[path] = values.astype(np.float64)
                continue
            if path in _ANGLE_FIELDS or processes.owns_input(path):
                inputs[path] = values.astype(np.float64)
                continue
            if path == posterior.SET_INPUT:  # each drop's coefficient set from the posterior
                _posterior_inputs(spec, values, P, inputs)
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
            shape = shape_of_params(P)  # the scenario's one shape (mine.shape is not sampled)
            P[:, layout.P_J1], P[:, layout.P_J2] = shape.inertia(P[:, layout.P_MASS], shape.dims_of_params(P))
    valid = cfg.check_params(
        P,
        n_sediment=spec.sediment_bank.shape[0],
        n_current=spec.current_bank.shape[0],
        embedded=spec.base.release.embedded,
    )
    valid &= cfg.check_samples(inputs, n)  # also the release angles, not in P
    return P, valid, inputs


def _posterior_inputs(spec, index, P, inputs) -> None:
    """Write the coefficient sets ``index`` (one per drop) into the rows of ``P`` and record
    the set index and each drawn coefficient as sampled inputs."""
    sets = np.asarray(index, dtype=np.int64)
    inputs[posterior.SET_INPUT] = sets.astype(np.float64)
    columns = spec.posterior.paths
    for path in spec.posterior_paths:
        values = spec.posterior.table[sets, columns.index(path)]
        if not processes.owns_input(path):  # a post-impact process reads its own from the inputs
            P[:, layout.INDEX[path]] = values
        inputs[path] = values


def _check_size_setting(value) -> int | str:
    """``ensemble.accuracy_check`` as kept on the spec: ``"auto"`` (validated before) or an int."""
    return value if isinstance(value, str) else int(value)


def compute_chunk(spec, start: int, stop: int) -> dict:
    """Run drops [start, stop): returns a dict of per-drop arrays (``summary``,
    ``status``, ``input:<path>`` of every sampled input) and ``invalid_inputs``, the
    reasons why drops were not run (:func:`invalid_reasons`).

    On Ctrl-C the :class:`~mineburial.systems.mine.batch.Interrupted` raised carries in
    ``partial`` the dict of the drops finished first, ``[start, start + done)``."""
    P, valid, inputs = chunk_inputs(spec, start, stop)
    try:
        summary, status = batch.run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    except Interrupted as exc:  # Ctrl-C: the drops finished first are a chunk of their own
        k = exc.done
        if k == 0:  # nothing to keep (and no stage to load while a drop thread may hold the compiler)
            raise
        part = {key: v[:k] for key, v in inputs.items()}
        exc.partial = _chunk_result(spec, start, start + k, P[:k], valid[:k], exc.summary, exc.status, part)
        raise
    return _chunk_result(spec, start, stop, P, valid, summary, status, inputs)


def check_accuracy(spec, chunks, progress=None) -> dict:
    """The numerical self-check's global attributes of a finished run
    (:func:`mineburial.systems.mine.accuracy.self_check`; ``progress``: None or the class of its
    progress lines)."""
    return accuracy.self_check(spec, chunks, chunk_inputs, progress)


def _chunk_result(spec, start, stop, P, valid, summary, status, inputs) -> dict:
    out = {
        "start": np.int64(start),
        "stop": np.int64(stop),
        "summary": summary,
        "status": status,
        "invalid_inputs": np.array(json.dumps(invalid_reasons(spec, P, valid), sort_keys=True)),
    }
    for process, own in processes.active(spec.processes):  # after the impact phase
        out.update(process.run_chunk(own, P, summary, status, inputs))
    for k, v in inputs.items():
        out["input:" + k] = v
    return out


def input_metadata(spec: EnsembleSpec, path: str) -> tuple[str, str]:
    """(UDUNITS units, description) of the sampled input ``path`` in the output."""
    if path == spec.sediment_choice:
        return "1", f"index into the sediment choices: {', '.join(spec.sediment_labels)}"
    if path == posterior.SET_INPUT:
        return "1", f"index of the drop's coefficient set in the posterior ({spec.posterior.source})"
    if path in _ANGLE_FIELDS:
        return "degree", path.split(".")[1].replace("_deg", "") + " angle at release"
    names = choice_labels(path)  # a model choice of the impact phase, or the scour stage's law (issue 33)
    if names is not None:
        return "1", f"code of {path}: " + ", ".join(f"{k} {v}" for k, v in enumerate(names))
    field = cfg.FIELDS.get(cfg.ALIASES.get(path, path))
    if field is not None:
        return field.units, field.description
    return "1", path


def invalid_reasons(spec: EnsembleSpec, P, valid) -> dict:
    """Why the drops with ``valid`` False were not run: ``{constraint: [count, first
    offending values]}`` (the constraints of :func:`mineburial.systems.mine.config.explain_params`; the
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


def warm_up_spec() -> EnsembleSpec:
    """A one-drop ensemble that ends after one time step (the embedded default scenario,
    whose random inputs exercise every sampler, with both time limits,
    ``numerics.t_max_fall`` and ``numerics.t_max``, equal to ``numerics.dt``): its chunk
    compiles the batch kernel and the samplers on a dask worker."""
    with open(DEFAULT_SCENARIO, "rb") as fh:
        raw = tomllib.load(fh)
    numerics = raw.setdefault("numerics", {})
    numerics["t_max"] = numerics["t_max_fall"] = float(numerics.get("dt", 1e-3))
    return load(raw, {"n": 1, "chunk_size": 1})


# ---------------------------------------------------------------------------
# checks, output and report
# ---------------------------------------------------------------------------
def _extremes(spec, path, fixed):
    """(smallest, largest) value of input ``path`` (its distribution's central 1 - 2e-9)."""
    d = spec.random.get(path)
    if d is None:
        return fixed, fixed
    lo, hi = d.ppf(np.array([1e-9, 1.0 - 1e-9]))
    return float(lo), float(hi)


def bytes_a_drop(spec: EnsembleSpec) -> int:
    """Bytes of the per-drop values of a run kept until the statistics are computed: the
    summary row, the status, the sampled inputs and the post-impact processes' values."""
    inputs = len(spec.random) + len(spec.posterior_paths)
    own = sum(process.bytes_per_drop(p) for process, p in processes.active(spec.processes))
    return spec.summary_width * 8 + 1 + 8 * inputs + own


def warn_run(spec) -> None:
    """A warning when a fixed-step integrator would take more than :data:`STEPS_WARNING`
    steps a drop (the adaptive default ``dopri5`` is not warned about)."""
    num = spec.base.numerics
    if num.integrator in _FIXED_STEP:
        dt_lo, _ = _extremes(spec, "numerics.dt", num.dt)
        _, t_hi = _extremes(spec, "numerics.t_max", num.t_max)
        _, t_fall_hi = _extremes(spec, "numerics.t_max_fall", num.t_max_fall)
        t_hi += t_fall_hi
        steps = t_hi / dt_lo if dt_lo > 0 else math.inf
        if steps > STEPS_WARNING:
            notice(
                f"warning: (numerics.t_max_fall + numerics.t_max) / numerics.dt = {t_hi:g} s / {dt_lo:g} s = "
                f"{steps:.3g} time steps a drop with the fixed-step integrator "
                f"'{num.integrator}': a drop that does not come to rest early may run for "
                f"hours, and one still moving after {STEPS_WARNING:.0e} steps ends time_limit; "
                f"use the adaptive integrator 'dopri5' or a larger dt"
            )


def invalid_inputs_text(reasons: dict) -> str:
    """One line for the drops whose sampled inputs were invalid (empty if none)."""
    return "; ".join(
        f"{rule}: {count} drop{'s' * (count != 1)} (e.g. {example})"
        for rule, (count, example) in sorted(reasons.items(), key=lambda kv: -kv[1][0])
    )


def dataset(spec: EnsembleSpec, chunks):
    """The output Dataset of ensemble ``spec`` from its chunk results in drop order."""
    summary = np.concatenate([r["summary"] for r in chunks])
    status = np.concatenate([r["status"] for r in chunks])
    inputs = {
        key[6:]: np.concatenate([r[key] for r in chunks]) for key in chunks[0] if key.startswith("input:")
    }
    meta = {path: input_metadata(spec, path) for path in inputs}
    invalid = invalid_inputs_text(merge_invalid_reasons(chunks))
    attrs = {**model_form.attributes(spec), **({"invalid_inputs": invalid} if invalid else {})}
    ds = build_dataset(
        summary,
        status,
        inputs=inputs,
        input_metadata=meta,
        scenario=spec.resolved(),
        seed=spec.seed,
        version=__version__,
        sampling_method=spec.sampling,
        n_drops=spec.n,
        per_drop=spec.per_drop,
        statistics_options={"class_basis": spec.class_basis},
        title=f"mineburial impact-burial ensemble: {spec.base.mine.name}",
        attrs=attrs,
    )
    if posterior.SET_INPUT in inputs:
        epistemic.add_band(ds, summary, status, inputs[posterior.SET_INPUT], spec.class_basis)
    for process, own in processes.active(spec.processes):
        ds = process.dataset(own, chunks, ds, per_drop=spec.per_drop, class_basis=spec.class_basis)
    return ds


def class_labels(ds) -> list[str]:
    """Names of the impact-burial classes of the statistics, in the order of
    ``burial_class_probability`` (from its class coordinate's flag values and meanings)."""
    coord = ds["burial_class_probability"].dims[0]
    c = ds[coord]
    values = np.atleast_1d(c.attrs.get("flag_values", np.arange(c.size))).tolist()
    meanings = str(c.attrs.get("flag_meanings", "")).split()
    table = dict(zip(values, meanings))
    return [table.get(v, str(v)) for v in np.asarray(c.values).tolist()]


def summarize(ds, elapsed: float | None = None, output=None) -> str:
    """A short human-readable report of an ensemble Dataset."""
    lines = [ds.attrs.get("title", "mineburial ensemble")]
    n = int(ds.attrs.get("n_drops", ds.sizes.get("realization", 0)) or 0)
    counts = ds["status_count"].values if "status_count" in ds else None
    used = None
    if counts is not None:
        parts = [f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c]
        lines.append(f"drops: {n} (" + ", ".join(parts) + ")")
        used = int(sum(int(counts[k]) for k in st.IN_STATISTICS if k < len(counts)))
        lines.append(
            f"burial statistics over {used} of {n} drops (at_rest and buried_sinking; "
            f"a buried_sinking penetration is a lower bound)"
        )
        left = [f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c and k not in st.IN_STATISTICS]
        if left:
            lines.append(
                "warning: left out of the burial statistics: "
                + ", ".join(left)
                + " (floated: lighter than the water, never reached the seabed)"
                * bool(counts[st.FLOATED] if st.FLOATED < len(counts) else 0)
            )
    invalid = ds.attrs.get("invalid_inputs")
    if invalid:
        k = int(counts[st.INVALID_INPUT]) if counts is not None else 0
        lines.append(
            f"warning: {k} of {n} drops were not run because their sampled inputs are invalid: {invalid}"
        )
    for name, label, unit in (
        ("burial_volume", "burial by volume", "%"),
        ("penetration_depth", "penetration depth", "m"),
    ):
        mean = ds.get(f"{name}_mean")
        if mean is not None:
            q = ds.get(f"{name}_quantile")
            qtxt = ""
            if q is not None:
                qtxt = ", 5-50-95 % quantiles " + " / ".join(
                    f"{float(v):.3g}" for v in q.sel(quantile=[0.05, 0.5, 0.95]).values
                )
            lines.append(f"{label}: mean {float(mean):.3g} {unit}{qtxt} {unit}")
    if "burial_class_probability" in ds:
        p = ds["burial_class_probability"].values
        lo = ds["burial_class_probability_lower"].values if "burial_class_probability_lower" in ds else None
        hi = ds["burial_class_probability_upper"].values if "burial_class_probability_upper" in ds else None
        basis = ds.attrs.get("burial_class_basis", "burial_volume")
        of = f" of the {used} drops at rest" if used is not None else ""
        lines.append(f"impact-burial classes (by {basis}){of}:")
        for name, pk, k in zip(class_labels(ds), p, range(len(p))):
            ci = f" [{lo[k]:.3f}, {hi[k]:.3f}]" if lo is not None else ""
            lines.append(f"  P({name}) = {pk:.3f}{ci}")
        lines.extend(epistemic.summary_lines(ds, class_labels(ds)))
    lines.extend(model_form.summary_lines(ds))
    lines.extend(processes.summary_lines(ds))
    lines.extend(accuracy.summary_lines(ds))
    if elapsed is not None:
        lines.append(f"time: {elapsed:.1f} s ({n / max(elapsed, 1e-9):.1f} drops/s)")
    if output is not None:
        lines.append(f"wrote {output}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------
# the examples
# ---------------------------------------------------------------------------
def example_names() -> tuple[str, ...]:
    """The example scenarios, single-drop and ensemble (``mineburial example``)."""
    return cfg.example_names() + cfg.ensemble_example_names()


def example(name: str) -> tuple[str, str]:
    """(what it is, text) of the example scenario ``name``."""
    return "scenario", cfg.example_path(name).read_text()
