"""Ensembles of seed 004's restraining system: ``mineburial run`` over a restraint case.

An ensemble scenario of the restraining system is a restraint case file (the sections
``[case]``, ``[anchor]``, ``[chain]``, ... that ``mineburial restrain`` reads,
:mod:`mineburial.systems.restraint.model`) with the top-level key ``system = "restraint"``, in
which any real-valued field may be a distribution table
(``friction = {distribution = "uniform", low = 0.3, high = 0.7}``), and an optional
``[ensemble]`` table (``n``, ``seed``, ``sampling``, ``chunk_size``, ``per_drop``;
defaults :data:`ENSEMBLE_DEFAULTS`). docs/restraint.md describes the format.

The sampling is the mine ensemble's (:func:`mineburial.ensembles.sampling.sample_fields`):
the value of field ``section.name`` in case *i* is a pure function of
``(seed, i, "section.name")`` (Monte Carlo) or of ``(seed, i, the set of random
fields)`` (Sobol'), so a chunk of cases gives the same bits for any chunk size, thread
count or dask worker. Each case is run by :func:`mineburial.systems.restraint.model.simulate`
(no time series kept) and reduced to one row of :data:`OUTPUTS`. The run driver
(:mod:`mineburial.ensembles.runner`) runs, stores, resumes and writes these chunks
exactly as it does the mine's drops; :func:`dataset` and :func:`summarize` are this
system's output file and report.

One rule ties two fields: when the scenario samples ``anchor.mass`` and does not give
``anchor.length``, each case's anchor length follows its mass as in seed 004 §4.1
(2.0, 2.5 and 3.0 m for 40, 50 and 60 t: one anchor density over the 4.0 m x 2.1 m
section), ``anchor.length = 2.0 m x anchor.mass / 40 t`` (:data:`ANCHOR_LENGTH_PER_MASS`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Mapping
from typing import ClassVar

import numba
import numpy as np

from mineburial._version import __version__
from mineburial.ensembles import distributions as dist
from mineburial.ensembles.intervals import wilson_interval
from mineburial.ensembles.sampling import sample_fields
from mineburial.ensembles.settings import check_ensemble_settings, input_files_of, merge_invalid_reasons
from mineburial.ensembles.threads import run_blocks
from mineburial.errors import ScenarioError, unknown_names_message
from mineburial.io import netcdf as ncio
from mineburial.io.dataset import build
from mineburial.io.variables import RESTRAINT_OUTPUTS, input_variable
from mineburial.kernels import multibody as kmb
from mineburial.kernels import status as status_codes
from mineburial.schema import check_distribution
from mineburial.systems.restraint import model as rs

__all__ = [
    "SYSTEM",
    "ENSEMBLE_DEFAULTS",
    "OUTPUTS",
    "RestraintEnsembleSpec",
    "load",
    "compute_chunk",
    "dataset",
    "summarize",
    "EXAMPLE_NAME",
    "example_text",
    "example_names",
    "example",
    "warn_run",
    "bytes_a_case",
]

#: the value of the scenario's top-level ``system`` key that selects this module
SYSTEM = "restraint"
#: its status codes in the registry of :mod:`mineburial.kernels.status`: those of the multibody core
#: (the shared codes, the normal end named ``stopped``), no code of its own; none enters a statistic
#: as such (the stopping time is of the cases that stopped)
STATUS = status_codes.register(
    status_codes.Vocabulary(SYSTEM, kmb.STATUS_NAMES, kmb.STATUS_DESCRIPTIONS, (kmb.STOPPED,))
)
#: the ``[ensemble]`` settings of a restraint ensemble when the scenario does not give them
#: (cases take seconds, not milliseconds: fewer of them, small chunks so that an interrupted
#: run loses little, and the per-case values kept, since they are the product)
ENSEMBLE_DEFAULTS = {"n": 100, "seed": 0, "sampling": "mc", "chunk_size": 8, "per_drop": True}
#: seed 004 §4.1: anchor length per anchor mass, m/kg (2.0 m for the 40 t anchor)
ANCHOR_LENGTH_PER_MASS = 2.0 / 40000.0

#: the per-case results, in the column order of a chunk's ``summary``: units, long name, comment
#: (declared in the variable registry, :data:`mineburial.io.variables.RESTRAINT_OUTPUTS`)
OUTPUTS = RESTRAINT_OUTPUTS
_COLUMN = {name: k for k, name in enumerate(OUTPUTS)}
#: quantiles of the stopping time in the statistics
QUANTILES = (0.05, 0.25, 0.5, 0.75, 0.95)
_ENSEMBLE_KEYS = tuple(ENSEMBLE_DEFAULTS)
#: ``mineburial example restraint_ensemble``
EXAMPLE_NAME = "restraint_ensemble"
#: the distributions of the example: seed 004 §4.3's ranges (Table 2 cases 1-5, 14, 15)
EXAMPLE_DISTRIBUTIONS = {
    "anchor.friction": (
        '{distribution = "uniform", low = 0.3, high = 0.7}',
        "seed 004 §4.3.1: seabed friction 0.3 to 0.7 (Table 2 cases 1-3)",
    ),
    "anchor.mass": (
        '{distribution = "uniform", low = 40000.0, high = 60000.0}',
        "[kg] seed 004 §4.3.2: anchor mass 40 t to 60 t (Table 2 cases 1, 4, 5)",
    ),
    "ship.speed": (
        '{distribution = "uniform", low = 3.0, high = 5.0}',
        "[m s-1] seed 004 §4.3.4: initial ship speed 3 to 5 m/s (Table 2 cases 1, 14, 15)",
    ),
}


@dataclasses.dataclass(frozen=True)
class RestraintEnsembleSpec:
    """Everything needed to compute any chunk of a restraint ensemble (picklable)."""

    raw: dict  # the scenario as given (distributions as tables, without system and [ensemble])
    base: rs.RestraintCase  # the case with each distribution at its median
    random: dict  # field path -> Distribution
    n: int
    seed: int
    sampling: str
    chunk_size: int
    per_drop: bool
    anchor_length_follows_mass: bool
    input_files: tuple = ()  # ((path, SHA-256), ...) of the files read (empirical distributions)

    system: ClassVar[str] = SYSTEM
    #: columns of a chunk's ``summary``
    summary_width: ClassVar[int] = len(OUTPUTS)
    #: what one realization is, in messages
    unit: ClassVar[str] = "cases"

    def resolved(self) -> dict:
        """The resolved scenario written into outputs: the base case fully resolved, the
        distributions of the random fields, the derived rule, the files read and the run
        settings."""
        out = {
            "system": SYSTEM,
            "case": self.base.to_dict(),
            "random_inputs": {k: v.to_dict() for k, v in self.random.items()},
            "ensemble": {
                "n": self.n,
                "seed": self.seed,
                "sampling": self.sampling,
                "chunk_size": self.chunk_size,
                "per_drop": self.per_drop,
            },
        }
        if self.anchor_length_follows_mass:
            out["derived_inputs"] = {
                "anchor.length": "2.0 m x anchor.mass / 40000 kg (seed 004 §4.1: one anchor density)"
            }
        if self.input_files:
            out["input_files"] = {path: digest for path, digest in self.input_files}
        return out

    def identity_items(self) -> list:
        """What decides the per-case results beside the resolved case, the distributions
        and the settings (:func:`mineburial.ensembles.store.run_identity`)."""
        return [("options", repr((SYSTEM, self.anchor_length_follows_mass)))]


# ---------------------------------------------------------------------------
# the scenario
# ---------------------------------------------------------------------------
def _real_field(path: str) -> rs.FieldSpec:
    """The field ``path`` of a restraint case that may vary, or an error naming it."""
    spec = next((f for f in rs.FIELDS if f.path == path), None)
    if spec is None:
        rs.refuse_renamed([path])
        section, _, name = path.partition(".")
        if section not in rs.SECTIONS:
            raise ScenarioError(
                f"{path}: " + unknown_names_message("section", [section], rs.SECTIONS + ("case",))
            )
        allowed = [f.name for f in rs.FIELDS if f.section == section]
        raise ScenarioError(f"{path}: " + unknown_names_message(f"field of [{section}]", [name], allowed))
    if spec.kind != "float":
        what = {"int": "a whole number", "bool": "a switch"}.get(spec.kind, "a name")
        raise ScenarioError(
            f"{path} cannot vary in an ensemble: it is {what}; only real-valued fields of a restraint "
            f"case can (docs/restraint.md)"
        )
    return spec


def _median(d: dist.Distribution) -> float:
    return float(d.ppf(np.array([0.5]))[0])


def load(raw: Mapping, overrides: Mapping, base_dir=None) -> RestraintEnsembleSpec:
    """A restraint ensemble from the parsed scenario ``raw`` (without its ``system`` key;
    its ``[ensemble]`` table, if any, still in it); ``overrides``: the run's settings given
    on the command line (None where not given)."""
    raw = dict(raw)
    given = raw.pop("ensemble", {})
    if not isinstance(given, Mapping):
        raise ScenarioError(
            f"ensemble = {given!r} must be a table: [ensemble] with {', '.join(_ENSEMBLE_KEYS)}"
        )
    unknown = [key for key in given if key not in _ENSEMBLE_KEYS]
    if unknown:
        raise ScenarioError(
            "[ensemble] of a restraint ensemble: " + unknown_names_message("key", unknown, _ENSEMBLE_KEYS)
        )
    ens = dict(ENSEMBLE_DEFAULTS)
    ens.update(given)
    for key, value in overrides.items():
        if value is None:
            continue
        if key not in _ENSEMBLE_KEYS:
            raise ScenarioError(f"{key} does not apply to a restraint ensemble (system = {SYSTEM!r})")
        ens[key] = value
    check_ensemble_settings(ens)

    random = {}
    fixed: dict = {}
    for section, table in raw.items():
        if section == "case" or not isinstance(table, Mapping):
            continue  # the case's name and description, or a shape RestraintCase reports
        for name, value in table.items():
            path = f"{section}.{name}"
            if isinstance(value, Mapping) and dist.is_distribution_table(value):
                spec = _real_field(path)
                d = dist.from_dict(value, path, base_dir=base_dir)
                if getattr(d, "categorical", False):
                    raise ScenarioError(f"{path}: a choice for a number needs numeric values")
                check_distribution(spec, d)
                random[path] = d
                fixed[path] = _median(d)
    follows = "anchor.mass" in random and "length" not in raw.get("anchor", {})
    template = {
        section: (dict(table) if isinstance(table, Mapping) else table) for section, table in raw.items()
    }
    for path, value in fixed.items():
        section, name = path.split(".")
        template[section][name] = value
    if follows:
        template["anchor"]["length"] = ANCHOR_LENGTH_PER_MASS * fixed["anchor.mass"]
    base = rs.RestraintCase.from_dict(template, name="restraint_ensemble")
    return RestraintEnsembleSpec(
        raw=raw,
        base=base,
        random=random,
        n=int(ens["n"]),
        seed=int(ens["seed"]),
        sampling=str(ens["sampling"]),
        chunk_size=int(ens["chunk_size"]),
        per_drop=bool(ens["per_drop"]),
        anchor_length_follows_mass=follows,
        input_files=input_files_of({}, random, base_dir),
    )


# ---------------------------------------------------------------------------
# one chunk
# ---------------------------------------------------------------------------
def case_columns(spec: RestraintEnsembleSpec, table: Mapping) -> dict:
    """The ``section.field`` columns that the rows of the sampled ``table`` change in the base
    case (the sampled fields and the derived anchor length)."""
    columns = {path: np.asarray(table[path], dtype=np.float64) for path in spec.random}
    if spec.anchor_length_follows_mass:
        columns["anchor.length"] = ANCHOR_LENGTH_PER_MASS * columns["anchor.mass"]
    return columns


def run_case(case: rs.RestraintCase) -> tuple[int, np.ndarray]:
    """Status and the row of :data:`OUTPUTS` of one case (no time series kept)."""
    res = rs.simulate(case)
    row = np.full(len(OUTPUTS), np.nan)
    if res.stopping_time is not None:
        row[_COLUMN["stopping_time"]] = res.stopping_time
    row[_COLUMN["end_time"]] = res.t_end
    if res.times.shape[0] > 0:
        tension = np.hypot(res.pin_force[:, :, 0], res.pin_force[:, :, 1])
        row[_COLUMN["peak_chain_tension"]] = np.max(tension[:, 1])  # body 2 (first link) on the anchor
        row[_COLUMN["peak_ship_tension"]] = np.max(tension[:, -1])  # body N (ship) on the rod
        if res.times.shape[0] > 1:
            row[_COLUMN["energy_closure"]] = res.energy_closure()
    return int(res.status), row


def compute_chunk(spec: RestraintEnsembleSpec, start: int, stop: int, threads: int | None = None) -> dict:
    """Run cases [start, stop): the chunk dict of the run driver (``summary`` (n, len(OUTPUTS)),
    ``status``, ``input:<path>`` of every sampled field, ``invalid_inputs``).

    The cases run on ``threads`` Python threads (default ``numba.get_num_threads()``) taking blocks of
    cases as the mines' drops do (:func:`~mineburial.ensembles.threads.run_blocks`; on Ctrl-C no new
    block is taken and :class:`~mineburial.ensembles.interrupt.Interrupted` ends the chunk):
    the multibody integrator is compiled ``nogil``, so they run in parallel; each case writes
    only its own row, so the result does not depend on the thread count.
    """
    n = stop - start
    table = sample_fields(spec.random, spec.seed, start, stop, spec.sampling) if spec.random else {}
    summary = np.full((n, len(OUTPUTS)), np.nan)
    status = np.full(n, kmb.INVALID_INPUT, dtype=np.int8)
    reasons: dict = {}

    def refuse(text):
        text = " ".join(text.split())
        entry = reasons.setdefault(text.split(" = ")[0], [0, text])
        entry[0] += 1

    # the case rules over every sampled row at once (the schema's rules, vectorised), then the
    # checks a case makes when it is built (the initial layout's own) for the rows that passed
    columns = case_columns(spec, table)
    values = {**spec.base.values, **columns}
    allowed = np.ones(n, dtype=bool)
    for rule in rs.RULES:
        held = np.broadcast_to(rule.holds(values), (n,))
        for j in np.flatnonzero(allowed & ~held):
            refuse(rule.message({k: (v[j] if np.ndim(v) else v) for k, v in values.items()}))
        allowed &= held
    cases: list = [None] * n
    for j in np.flatnonzero(allowed):
        try:
            cases[j] = spec.base.replace(**{path: float(column[j]) for path, column in columns.items()})
        except ScenarioError as exc:
            refuse(str(exc))

    def run(j):
        status[j], summary[j] = run_case(cases[j])

    def run_cases(a, b):
        for j in todo[a:b]:
            run(j)

    todo = [j for j in range(n) if cases[j] is not None]
    threads = numba.get_num_threads() if threads is None else int(threads)
    # the mines' block runner: Ctrl-C stops taking cases at once (the chunk is not kept)
    run_blocks(len(todo), run_cases, max(1, threads))
    out = {
        "start": np.int64(start),
        "stop": np.int64(stop),
        "summary": summary,
        "status": status,
        "invalid_inputs": np.array(json.dumps(reasons, sort_keys=True)),
    }
    for path in spec.random:
        out["input:" + path] = np.asarray(table[path], dtype=np.float64)
    if spec.anchor_length_follows_mass:
        out["input:anchor.length"] = ANCHOR_LENGTH_PER_MASS * out["input:anchor.mass"]
    return out


def bytes_a_case(spec: RestraintEnsembleSpec) -> int:
    """Bytes of the per-case values of a run kept until the statistics are computed: the
    row of :data:`OUTPUTS`, the status and the sampled fields."""
    return spec.summary_width * 8 + 1 + 8 * len(spec.random)


def warn_run(spec: RestraintEnsembleSpec) -> None:
    """Nothing to warn about before computing: a restraint case's fixed step and time
    limit are checked by the case's own field ranges (:mod:`mineburial.systems.restraint.model`)."""


# ---------------------------------------------------------------------------
# the output
# ---------------------------------------------------------------------------
def _status_attrs() -> dict:
    return {
        "flag_values": np.asarray(STATUS.codes, dtype=np.int8),
        "flag_meanings": STATUS.flag_meanings,
    }


def statistics(summary: np.ndarray, status: np.ndarray) -> dict:
    """The statistics of a restraint ensemble as plain numbers: the status counts, the
    share of the cases run that stopped (with its 95 % Wilson interval), and the mean,
    standard deviation (n - 1), extremes and :data:`QUANTILES` of the stopping time and
    the means and maxima of the peak tensions over the cases that stopped."""
    counts = np.bincount(status.astype(np.int64), minlength=int(kmb.STATUS_CODES.max()) + 1)
    ran = int(status.size - counts[kmb.INVALID_INPUT])
    stopped = status == kmb.STOPPED
    k = int(np.count_nonzero(stopped))
    lo, hi = wilson_interval(k, ran)
    out = {
        "status_count": counts[kmb.STATUS_CODES],  # along kmb.STATUS_CODES
        "n_run": ran,
        "n_stopped": k,
        "stopped_fraction": k / ran if ran else math.nan,
        "stopped_fraction_lower": float(lo),
        "stopped_fraction_upper": float(hi),
    }
    t = summary[stopped, _COLUMN["stopping_time"]]
    out["stopping_time_mean"] = float(np.mean(t)) if k else math.nan
    out["stopping_time_std"] = float(np.std(t, ddof=1)) if k > 1 else math.nan
    out["stopping_time_min"] = float(np.min(t)) if k else math.nan
    out["stopping_time_max"] = float(np.max(t)) if k else math.nan
    out["stopping_time_quantile"] = (
        np.quantile(t, QUANTILES, method="linear") if k else np.full(len(QUANTILES), math.nan)
    )
    for name in ("peak_chain_tension", "peak_ship_tension"):
        v = summary[stopped, _COLUMN[name]]
        out[f"{name}_mean"] = float(np.mean(v)) if k else math.nan
        out[f"{name}_max"] = float(np.max(v)) if k else math.nan
    return out


def dataset(spec: RestraintEnsembleSpec, chunks):
    """The CF NetCDF dataset of a restraint ensemble from its chunk results in case order:
    the statistics (:func:`statistics`), with ``per_drop`` the per-case results and sampled
    inputs along ``realization``, and the resolved scenario, seed, sampling method and
    mineburial version in the global attributes. Every variable's metadata comes from the
    registry's ``restraint_ensemble`` family (:mod:`mineburial.io.variables`), the file
    through :func:`mineburial.io.dataset.build`."""
    summary = np.concatenate([r["summary"] for r in chunks])
    status = np.concatenate([r["status"] for r in chunks])
    st = statistics(summary, status)
    names = ("stopped_fraction", "stopped_fraction_lower", "stopped_fraction_upper")
    names += tuple(f"stopping_time_{s}" for s in ("mean", "std", "min", "max", "quantile"))
    names += tuple(f"{o}_{s}" for o in ("peak_chain_tension", "peak_ship_tension") for s in ("mean", "max"))
    data = {"status_count": st["status_count"], **{name: st[name] for name in names}}
    coords = {
        "status": (kmb.STATUS_CODES, _status_attrs()),
        "quantile": np.asarray(QUANTILES),
    }
    if spec.per_drop:
        coords["realization"] = np.arange(summary.shape[0])
        data.update({name: summary[:, _COLUMN[name]] for name in OUTPUTS})
        data["case_status"] = (status, _status_attrs())
        data.update(_sampled_inputs(chunks))
    scen = ncio.scenario_json(spec.resolved())
    created = ncio.utc_now()
    attrs = {
        "title": f"mineburial restraining-system ensemble (seed 004): {spec.base.name}",
        "summary": "Monte Carlo ensemble of seed 004's restraining system (a powerless ship stopped by an "
        "overhead restraining system, planar Kane-method multibody model): the stopping time of each "
        "sampled case and its statistics; docs/restraint.md.",
        "id": "mineburial-"
        + hashlib.sha256(
            json.dumps([scen, str(spec.seed), spec.sampling, spec.n, __version__]).encode()
        ).hexdigest()[:16],
        "history": f"{created} mineburial {__version__}: ensemble of {spec.n} cases of the restraining "
        f"system, {spec.sampling} sampling, seed {spec.seed}",
        "date_created": created,
        "product_version": __version__,
        "source": f"mineburial {__version__} (numba-compiled multibody model of seed 004)",
        "mineburial_system": SYSTEM,
        "scenario": scen,
        "random_seed": ncio.seed_attr(spec.seed),
        "sampling_method": spec.sampling,
        "n_cases": np.int64(spec.n),
        "n_stopped": np.int64(st["n_stopped"]),
        "comment": "Statistics of the stopping time use only the cases whose ship stopped (status "
        "stopped); status_count gives the number of cases with every status.",
    }
    invalid = merge_invalid_reasons(chunks)
    if invalid:
        attrs["invalid_inputs"] = "; ".join(
            f"{field}: {count} case{'s' * (count != 1)} (e.g. {example})"
            for field, (count, example) in sorted(invalid.items(), key=lambda kv: -kv[1][0])
        )
    return build(data, coords, attrs, kind="restraint_ensemble")


def _sampled_inputs(chunks) -> dict:
    """The sampled case fields of the chunks as registry input variables (``input_<path>``)."""
    out = {}
    for key in chunks[0]:
        if not key.startswith("input:"):
            continue
        path = key[6:]
        field = next(f for f in rs.FIELDS if f.path == path)
        var = input_variable(path, field.unit)
        values = np.concatenate([r[key] for r in chunks])
        comment = f"value of the restraint case field {path} in each case ({field.source})"
        out[var.name] = var.data_array(values, comment=comment)
    return out


def summarize(ds, elapsed: float | None = None, output=None) -> str:
    """A short human-readable report of a restraint-ensemble dataset."""
    n = int(ds.attrs.get("n_cases", 0))
    counts = dict(zip(ds["status"].values.tolist(), ds["status_count"].values.tolist()))
    parts = [f"{STATUS.name(k)} {int(c)}" for k, c in counts.items() if c]
    lines = [
        str(ds.attrs.get("title", "mineburial restraint ensemble")),
        f"cases: {n} (" + ", ".join(parts) + ")",
    ]
    frac = float(ds["stopped_fraction"])
    lines.append(
        f"stopped within the time limit: {frac:.3f} of the cases run "
        f"[{float(ds['stopped_fraction_lower']):.3f}, {float(ds['stopped_fraction_upper']):.3f}]"
    )
    if int(ds.attrs.get("n_stopped", 0)):
        q = ds["stopping_time_quantile"].sel(quantile=[0.05, 0.5, 0.95]).values
        lines.append(
            f"stopping time: mean {float(ds['stopping_time_mean']):.3f} s, "
            f"std {float(ds['stopping_time_std']):.3g} s, "
            f"5-50-95 % quantiles {' / '.join(f'{v:.3f}' for v in q)} s, "
            f"range [{float(ds['stopping_time_min']):.3f}, {float(ds['stopping_time_max']):.3f}] s"
        )
        lines.append(
            "peak tension, mean (max): chain at the anchor "
            f"{float(ds['peak_chain_tension_mean']) / 1e3:.4g} "
            f"({float(ds['peak_chain_tension_max']) / 1e3:.4g}) kN, at the ship "
            f"{float(ds['peak_ship_tension_mean']) / 1e3:.4g} "
            f"({float(ds['peak_ship_tension_max']) / 1e3:.4g}) kN"
        )
    invalid = ds.attrs.get("invalid_inputs")
    if invalid:
        k = int(counts[kmb.INVALID_INPUT])
        lines.append(
            f"warning: {k} of {n} cases were not run because their sampled inputs are invalid: {invalid}"
        )
    if elapsed is not None:
        lines.append(f"time: {elapsed:.1f} s ({n / max(elapsed, 1e-9):.2f} cases/s)")
    if output is not None:
        lines.append(f"wrote {output}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------
# the example
# ---------------------------------------------------------------------------
def example_text(name: str = EXAMPLE_NAME) -> str:
    """The example ensemble ``restraint_ensemble``: Table 2 case 1 (every value with its
    source, :func:`mineburial.systems.restraint.model.example_text`) with uniform distributions
    over the seabed friction, the anchor mass and the initial ship speed across seed 004
    §4.3's ranges (:data:`EXAMPLE_DISTRIBUTIONS`)."""
    if name != EXAMPLE_NAME:
        raise ScenarioError(f"restraint ensemble example {name!r} does not exist; it is {EXAMPLE_NAME!r}")
    case_lines = rs.example_text("restraint_case1").splitlines()
    body = case_lines[case_lines.index("[case]") :]
    out = [
        "# Ensemble of seed 004's restraining system (Liu, Hearn, Chen et al., Kane method) over",
        "# Table 2's uncertain parameters: Table 2 case 1 (Table 3: 20.010 s) with the seabed friction,",
        "# the anchor mass and the initial ship speed drawn uniformly over the ranges of seed 004 §4.3.",
        "# Run with: mineburial run THIS_FILE.toml -o OUT.nc   (SI units; docs/restraint.md)",
        "# Any real-valued field below may be a distribution, as in a mine ensemble (docs/scenario.md).",
        "# Every fixed value names its source; values seed 004 does not print are marked ASSUMPTION.",
        "",
        '# the system this scenario describes: "restraint" (this file) or "mine" (the default)',
        f'system = "{SYSTEM}"',
        "",
        "[ensemble]",
        "n = 64  # cases (2-4 s of computing each, on all cores at once)",
        "seed = 0",
        'sampling = "mc"  # or "sobol" (n a power of two)',
        "chunk_size = 8  # cases written to OUT.nc.parts/ at a time (an interrupted run resumes)",
        "per_drop = true  # also write every case's stopping time, status and sampled inputs",
        "",
    ]
    current = "case"
    for line in body:
        if line.startswith("["):
            current = line.strip("[]")
        key = line.split(" = ")[0] if " = " in line else None
        path = f"{current}.{key}" if key else None
        if line.startswith("name = "):
            line = f'name = "{EXAMPLE_NAME}"'
        elif line.startswith("description = "):
            line = 'description = "seed 004 Table 2 case 1, friction, anchor mass and ship speed uncertain"'
        if path == "anchor.length":
            out.append(
                "# length: not given, so that each case's anchor length follows its sampled mass as in seed "
                "004 §4.1"
            )
            out.append("# (2.0, 2.5, 3.0 m for 40, 50, 60 t): length = 2.0 m x mass / 40 t")
            continue
        if path in EXAMPLE_DISTRIBUTIONS:
            value, source = EXAMPLE_DISTRIBUTIONS[path]
            line = f"{key} = {value}  # {source}"
        out.append(line)
    return "\n".join(out) + "\n"


def example_names() -> tuple[str, ...]:
    """The examples of this system: the ensemble :data:`EXAMPLE_NAME` and the cases of
    seed 004's Table 2 (for ``mineburial restrain``)."""
    return (EXAMPLE_NAME,) + rs.example_names()


def example(name: str) -> tuple[str, str]:
    """(what it is, text) of example ``name`` (:func:`example_names`)."""
    if name == EXAMPLE_NAME:
        return "restraint ensemble", example_text(name)
    return "restraint case", rs.example_text(name)
