"""The Monte Carlo ensemble engine: sample, run in compiled code, reduce, write NetCDF.

An ensemble scenario is an ordinary scenario file in which any numeric input may
be a distribution (``mass = {distribution = "normal", mean = 750, std = 20}``),
``sediment.class`` / ``sediment.file`` may be a ``choice`` among catalogue
classes or core files, and an optional ``[ensemble]`` table sets ``n``, ``seed``,
``sampling``, ``chunk_size``, ``per_drop`` and ``class_basis``.

Drops are processed in chunks ``[start, stop)``. Every random input of drop *i*
is a pure function of ``(seed, i)`` (:mod:`mineburial.ensembles.sampling`), each
drop writes only its own result row, and statistics are computed from the
concatenated per-drop values, so results are bit-identical for any chunk size,
thread count or dask cluster. With an output path, each finished chunk is saved
atomically beside the output (``OUT.nc.parts/``) and a rerun with the same
arguments resumes from them; the folder is removed once the NetCDF file is
written (atomically too).
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import math
import os
import pathlib
import sys
import time
from typing import Any, Mapping

import numpy as np

from mineburial import config as cfg
from mineburial.ensembles import distributions as dist
from mineburial.ensembles.sampling import check_drop_count, sample_fields
from mineburial.kernels import layout
from mineburial.sediment_profiles import catalogue_profile, load_file, pack_banks, unknown_name_message

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

DEFAULT_SCENARIO = (pathlib.Path(__file__).resolve().parent.parent / "data" / "ensembles"
                    / "default_soft_mud.toml")

ENSEMBLE_DEFAULTS = {"n": 1000, "seed": 0, "sampling": "mc", "chunk_size": 256,
                     "per_drop": False, "class_basis": "burial_volume"}
_ENSEMBLE_KEYS = tuple(ENSEMBLE_DEFAULTS)
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
    raw: dict                      # the scenario as given (distributions as tables)
    base: cfg.Scenario             # scenario with each distribution at a representative value
    random: dict                   # path -> Distribution
    n: int
    seed: int
    sampling: str
    chunk_size: int
    per_drop: bool
    class_basis: str
    base_params: np.ndarray
    sediment_bank: np.ndarray
    current_bank: np.ndarray
    sediment_labels: tuple         # labels of a sediment choice, in bank-row order
    sediment_choice: str | None    # "sediment.class" or "sediment.file" when it varies
    recompute_inertia: bool
    angles_deg: tuple              # (roll, pitch, heading) of the base scenario

    def fingerprint(self) -> str:
        """Hash of what determines the per-drop results (for resuming)."""
        from mineburial import __version__
        blob = json.dumps({"raw": self.raw, "seed": self.seed, "n": self.n,
                           "sampling": self.sampling, "version": __version__},
                          sort_keys=True, default=str)
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    def resolved(self) -> dict:
        """The resolved scenario written into outputs: the base scenario fully
        resolved, the distributions of the random inputs, and the run settings."""
        return {"scenario": self.base.to_dict(),
                "random_inputs": {k: v.to_dict() for k, v in self.random.items()},
                "ensemble": {"n": self.n, "seed": self.seed, "sampling": self.sampling,
                             "chunk_size": self.chunk_size, "per_drop": self.per_drop,
                             "class_basis": self.class_basis}}


def load_ensemble(source=None, *, n=None, seed=None, sampling=None, chunk_size=None,
                  per_drop=None, class_basis=None, base_dir=None) -> EnsembleSpec:
    """Parse an ensemble scenario (path, TOML text dict, or None for the embedded default).

    Keyword arguments override the ``[ensemble]`` table.
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
            with open(path, "rb") as fh:
                raw = tomllib.load(fh)
        except OSError as exc:
            raise cfg.ScenarioError(f"cannot read scenario file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise cfg.ScenarioError(f"scenario file '{path}' is not valid TOML: {exc}") from None
        base_dir = base_dir or path.resolve().parent
    ens = dict(ENSEMBLE_DEFAULTS)
    given = raw.pop("ensemble", {}) or {}
    for key in given:
        if key not in _ENSEMBLE_KEYS:
            raise cfg.ScenarioError(unknown_name_message("ensemble key", key, _ENSEMBLE_KEYS))
    ens.update(given)
    for key, value in (("n", n), ("seed", seed), ("sampling", sampling),
                       ("chunk_size", chunk_size), ("per_drop", per_drop),
                       ("class_basis", class_basis)):
        if value is not None:
            ens[key] = value
    _check_ensemble(ens)

    leaves = {}
    _walk(raw, "", leaves)
    random = {}
    template = copy.deepcopy(raw)
    for path, table in leaves.items():
        d = dist.from_dict(table, path, base_dir=base_dir)
        random[path] = d
        _set_path(template, path, _representative(d))
    base = cfg.Scenario.from_dict(template, base_dir=base_dir)
    p, sed_bank, cur_bank = base.to_params()

    labels = ()
    choice = None
    for key in ("sediment.class", "sediment.file"):
        if key in random:
            d = random[key]
            if not isinstance(d, dist.Choice):
                raise EnsembleError(f"{key} can only vary as a 'choice' distribution, "
                                    f"got {type(d).__name__.lower()}")
            labels = tuple(str(v) for v in d.values)
            if key == "sediment.class":
                profiles = [catalogue_profile(v) for v in labels]
            else:
                profiles = [load_file(v, base_dir) for v in labels]
            sed_bank = pack_banks(profiles)
            choice = key
    for path in random:
        if path in (choice,) or path in _ANGLE_FIELDS:
            continue
        slot = cfg.ALIASES.get(path, path)
        if slot not in layout.INDEX:
            raise EnsembleError(
                f"{path} cannot vary in an ensemble: only numeric inputs of the kernels "
                f"(docs/scenario.md), the release angles and sediment.class/sediment.file can")
        if isinstance(random[path], dist.Choice) and not all(
                isinstance(v, (int, float)) for v in random[path].values):
            raise EnsembleError(f"{path}: a choice for a numeric input needs numeric values")
    rel = raw.get("release", {})
    explicit_inertia = any(k in raw.get("mine", {}) for k in ("inertia_axial", "inertia_transverse"))
    recompute = (not explicit_inertia) and any(k in random for k in _INERTIA_INPUTS)
    angles = tuple(float(rel.get(k.split(".")[1], 0.0)) if not isinstance(rel.get(k.split(".")[1]), Mapping)
                   else 0.0 for k in _ANGLE_FIELDS)
    if any(k in random for k in _ANGLE_FIELDS) and "quaternion" in rel:
        raise EnsembleError("release: random angles cannot be combined with a fixed quaternion")
    return EnsembleSpec(raw=raw, base=base, random=random, n=int(ens["n"]), seed=int(ens["seed"]),
                        sampling=str(ens["sampling"]), chunk_size=int(ens["chunk_size"]),
                        per_drop=bool(ens["per_drop"]), class_basis=str(ens["class_basis"]),
                        base_params=p, sediment_bank=sed_bank, current_bank=cur_bank,
                        sediment_labels=labels, sediment_choice=choice,
                        recompute_inertia=recompute, angles_deg=angles)


def _check_ensemble(ens):
    def bad(key, allowed):
        raise cfg.ScenarioError(f"ensemble.{key} = {ens[key]!r} is outside the allowed range "
                                f"{allowed}")
    if not isinstance(ens["n"], (int, np.integer)) or isinstance(ens["n"], bool) or ens["n"] < 1:
        bad("n", "[1, inf) (an integer number of drops)")
    if not isinstance(ens["seed"], (int, np.integer)) or not 0 <= ens["seed"] < 2 ** 64:
        bad("seed", "[0, 2**64) (an integer)")
    if ens["sampling"] not in ("mc", "sobol"):
        raise cfg.ScenarioError(unknown_name_message("ensemble.sampling", ens["sampling"],
                                                         ("mc", "sobol")))
    if not isinstance(ens["chunk_size"], (int, np.integer)) or ens["chunk_size"] < 1:
        bad("chunk_size", "[1, inf) (an integer number of drops)")
    if ens["class_basis"] not in ("burial_volume", "burial_height", "burial_area"):
        raise cfg.ScenarioError(unknown_name_message(
            "ensemble.class_basis", ens["class_basis"],
            ("burial_volume", "burial_height", "burial_area")))


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
            if path in _ANGLE_FIELDS:
                inputs[path] = values.astype(np.float64)
                continue
            slot = cfg.ALIASES.get(path, path)
            P[:, layout.INDEX[slot]] = values
            inputs[path] = values.astype(np.float64)
        if any(k in spec.random for k in _ANGLE_FIELDS):
            ang = [inputs.get(k, np.full(n, spec.angles_deg[j]))
                   for j, k in enumerate(_ANGLE_FIELDS)]
            q = cfg.quaternion_from_angles(*(np.radians(a) for a in ang))
            P[:, layout.P_Q00:layout.P_Q30 + 1] = q
        if spec.recompute_inertia:
            m = P[:, layout.P_MASS]
            r = 0.5 * P[:, layout.P_DIAMETER]
            length = P[:, layout.P_LENGTH]
            P[:, layout.P_J1] = 0.5 * m * r * r                       # uniform solid cylinder
            P[:, layout.P_J2] = m * (3.0 * r * r + length * length) / 12.0
    valid = cfg.check_params(P, n_sediment=spec.sediment_bank.shape[0],
                             n_current=spec.current_bank.shape[0])
    return P, valid, inputs


def compute_chunk(spec: EnsembleSpec, start: int, stop: int) -> dict:
    """Run drops [start, stop): returns a dict of per-drop arrays."""
    from mineburial.ensembles.batch import run_batch

    P, valid, inputs = chunk_inputs(spec, start, stop)
    summary, status = run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    out = {"start": np.int64(start), "stop": np.int64(stop), "summary": summary,
           "status": status}
    for k, v in inputs.items():
        out["input:" + k] = v
    return out


# ---------------------------------------------------------------------------
# chunk files (resume)
# ---------------------------------------------------------------------------
def _parts_dir(output) -> pathlib.Path:
    output = pathlib.Path(output)
    return output.with_name(output.name + ".parts")


def _chunk_path(parts: pathlib.Path, start: int, stop: int) -> pathlib.Path:
    return parts / f"chunk-{start:012d}-{stop:012d}.npz"


def save_chunk(parts: pathlib.Path, result: dict) -> pathlib.Path:
    """Write one chunk's results atomically (temporary file, fsync, rename)."""
    path = _chunk_path(parts, int(result["start"]), int(result["stop"]))
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as fh:
        np.savez(fh, **{k.replace(":", "__"): v for k, v in result.items()})
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)
    return path


def load_chunk(path: pathlib.Path) -> dict:
    with np.load(path) as z:
        return {k.replace("__", ":"): z[k] for k in z.files}


def _prepare_parts(spec: EnsembleSpec, output) -> pathlib.Path:
    parts = _parts_dir(output)
    parts.mkdir(parents=True, exist_ok=True)
    manifest = parts / "manifest.json"
    fp = spec.fingerprint()
    if manifest.exists():
        old = json.loads(manifest.read_text())
        if old.get("fingerprint") != fp:
            for f in parts.glob("chunk-*.npz"):
                f.unlink()
    tmp = manifest.with_suffix(".tmp")
    tmp.write_text(json.dumps({"fingerprint": fp, "n": spec.n, "seed": spec.seed}))
    os.replace(tmp, manifest)
    return parts


def chunk_bounds(n: int, chunk_size: int):
    return [(s, min(s + chunk_size, n)) for s in range(0, n, chunk_size)]


# ---------------------------------------------------------------------------
# progress
# ---------------------------------------------------------------------------
class Progress:
    """Rate-limited progress lines: drops done, drops/s, time left.

    Every 2 s on a terminal (rewriting one line), every 30 s in a batch log.
    """

    def __init__(self, total: int, enabled: bool = True, stream=None):
        self.total = total
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.interval = 2.0 if self.tty else 30.0
        self.t0 = time.monotonic()
        self.last = -math.inf
        self.done0 = None

    def update(self, done: int, final: bool = False):
        if not self.enabled:
            return
        now = time.monotonic()
        if self.done0 is None:
            self.done0 = done
            self.t0 = now
        if not final and now - self.last < self.interval:
            return
        self.last = now
        elapsed = max(now - self.t0, 1e-9)
        rate = (done - self.done0) / elapsed
        left = (self.total - done) / rate if rate > 0 else math.inf
        eta = "--" if not math.isfinite(left) else time.strftime("%H:%M:%S", time.gmtime(left))
        line = (f"drops {done}/{self.total} ({100.0 * done / max(self.total, 1):.1f} %), "
                f"{rate:.1f} drops/s, time left {eta}")
        if self.tty:
            end = "\n" if final else ""
            self.stream.write("\r" + line + end)
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


# ---------------------------------------------------------------------------
# the ensemble
# ---------------------------------------------------------------------------
def run_ensemble(scenario=None, n: int | None = None, seed: int | None = None, *,
                 sampling: str | None = None, chunk_size: int | None = None,
                 output=None, per_drop: bool | None = None, threads: int | None = None,
                 progress: bool = False, client=None, class_basis: str | None = None):
    """Run a Monte Carlo ensemble and return its statistics as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scenario : path, dict, :class:`~mineburial.config.Scenario` or None
        Ensemble scenario (None: the embedded default soft-mud scenario).
    n, seed, sampling, chunk_size, per_drop, class_basis
        Override the scenario's ``[ensemble]`` table.
    output : path, optional
        Write the NetCDF file here (atomically); finished chunks are kept in
        ``OUTPUT.parts/`` until then, so an interrupted run resumes.
    threads : int, optional
        Number of numba threads (default: all cores).
    progress : bool
        Print rate-limited progress lines to stderr.
    client : dask.distributed.Client, optional
        Spread chunks over a dask cluster (:mod:`mineburial.ensembles.distributed`).
    """
    import numba

    from mineburial import __version__
    from mineburial.io.netcdf import build_dataset, write_netcdf

    spec = load_ensemble(scenario, n=n, seed=seed, sampling=sampling, chunk_size=chunk_size,
                         per_drop=per_drop, class_basis=class_basis)
    if spec.sampling == "sobol":
        check_drop_count(spec.n, "sobol")
    if threads is not None:
        numba.set_num_threads(int(threads))
    bounds = chunk_bounds(spec.n, spec.chunk_size)
    parts = _prepare_parts(spec, output) if output is not None else None
    results = {}
    if parts is not None:
        for s, e in bounds:
            path = _chunk_path(parts, s, e)
            if path.exists():
                results[(s, e)] = load_chunk(path)
    todo = [b for b in bounds if b not in results]
    bar = Progress(spec.n, enabled=progress)
    done = sum(e - s for s, e in results)
    bar.update(done)
    if client is not None:
        from mineburial.ensembles.distributed import run_chunks_distributed

        for key, res in run_chunks_distributed(client, spec, todo, parts):
            results[key] = res
            done += key[1] - key[0]
            bar.update(done)
    else:
        for s, e in todo:
            res = compute_chunk(spec, s, e)
            if parts is not None:
                save_chunk(parts, res)
            results[(s, e)] = res
            done += e - s
            bar.update(done)
    bar.update(done, final=True)

    ordered = [results[b] for b in bounds]
    summary = np.concatenate([r["summary"] for r in ordered])
    status = np.concatenate([r["status"] for r in ordered])
    inputs = {}
    for key in ordered[0]:
        if key.startswith("input:"):
            inputs[key[6:]] = np.concatenate([r[key] for r in ordered])
    meta = {}
    for path in inputs:
        slot = cfg.ALIASES.get(path, path)
        spec_f = cfg.FIELDS.get(slot)
        if path == spec.sediment_choice:
            meta[path] = ("1", f"index into the sediment choices: {', '.join(spec.sediment_labels)}")
        elif path in _ANGLE_FIELDS:
            meta[path] = ("degree", path.split(".")[1].replace("_deg", "") + " angle at release")
        elif spec_f is not None:
            meta[path] = (spec_f.units, spec_f.description)
        else:
            meta[path] = ("1", path)
    ds = build_dataset(summary, status, inputs=inputs, input_metadata=meta,
                       scenario=spec.resolved(), seed=spec.seed, version=__version__,
                       sampling_method=spec.sampling, n_drops=spec.n, per_drop=spec.per_drop,
                       statistics_options={"class_basis": spec.class_basis},
                       title=f"mineburial impact-burial ensemble: {spec.base.mine.name}")
    if output is not None:
        write_netcdf(ds, output)
        for f in parts.glob("*"):
            f.unlink()
        parts.rmdir()
    return ds


def run_ensemble_cli(args) -> int:
    """``mineburial run``: the main job."""
    client = None
    if args.scheduler:
        from dask.distributed import Client

        client = Client(args.scheduler)
    t0 = time.monotonic()
    try:
        ds = run_ensemble(args.scenario, n=args.drops, seed=args.seed, sampling=args.sampling,
                          chunk_size=args.chunk_size, output=args.output,
                          per_drop=args.per_drop, threads=args.threads,
                          progress=not args.quiet, client=client)
    finally:
        if client is not None:
            client.close()
    elapsed = time.monotonic() - t0
    print(summarize(ds, elapsed, args.output))
    return 0


def summarize(ds, elapsed: float | None = None, output=None) -> str:
    """A short human-readable report of an ensemble Dataset."""
    from mineburial.kernels import status as st

    lines = [ds.attrs.get("title", "mineburial ensemble")]
    n = int(ds.attrs.get("n_drops", ds.sizes.get("realization", 0)) or 0)
    counts = ds["status_count"].values if "status_count" in ds else None
    if counts is not None:
        parts = [f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c]
        lines.append(f"drops: {n} (" + ", ".join(parts) + ")")
        used = int(sum(int(counts[k]) for k in st.IN_STATISTICS if k < len(counts)))
        lines.append(f"burial statistics over {used} of {n} drops (at_rest and buried_sinking; "
                     f"a buried_sinking penetration is a lower bound)")
        left = [f"{st.NAMES[k]} {int(c)}" for k, c in enumerate(counts)
                if c and k not in st.IN_STATISTICS]
        if left:
            lines.append("warning: left out of the burial statistics: " + ", ".join(left)
                         + " (floated: lighter than the water, never reached the seabed)"
                         * bool(counts[st.FLOATED] if st.FLOATED < len(counts) else 0))
    for name, label, unit in (("burial_volume", "burial by volume", "%"),
                              ("penetration_depth", "penetration depth", "m")):
        mean = ds.get(f"{name}_mean")
        if mean is not None:
            q = ds.get(f"{name}_quantile")
            qtxt = ""
            if q is not None:
                qtxt = ", 5-50-95 % quantiles " + " / ".join(
                    f"{float(v):.3g}" for v in q.sel(quantile=[0.05, 0.5, 0.95]).values)
            lines.append(f"{label}: mean {float(mean):.3g} {unit}{qtxt} {unit}")
    if "burial_class_probability" in ds:
        p = ds["burial_class_probability"].values
        lo = ds["burial_class_probability_lower"].values if "burial_class_probability_lower" in ds else None
        hi = ds["burial_class_probability_upper"].values if "burial_class_probability_upper" in ds else None
        names = ds["burial_class"].attrs.get("flag_meanings", "").split() if "burial_class" in ds else []
        if not names:
            names = ["0 %", "0-10 %", "10-20 %", "20-75 %", ">75 %"]
        for k, pk in enumerate(p):
            ci = f" [{lo[k]:.3f}, {hi[k]:.3f}]" if lo is not None else ""
            lines.append(f"  P(class {names[k] if k < len(names) else k}) = {pk:.3f}{ci}")
    if elapsed is not None:
        lines.append(f"time: {elapsed:.1f} s ({n / max(elapsed, 1e-9):.1f} drops/s)")
    if output is not None:
        lines.append(f"wrote {output}")
    return "\n".join(lines)
