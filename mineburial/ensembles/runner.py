"""The run driver: one mechanism that runs the chunks of ensembles, resumes them and
reduces them, for both :func:`run_ensemble` and :func:`mineburial.maps.run_map`.

A run is a list of :class:`Job` s, each an ensemble (:class:`~mineburial.ensembles.
engine.EnsembleSpec`) with an optional chunk store
(:class:`~mineburial.ensembles.store.ChunkStore`). :func:`run_jobs` loads the valid
chunk files already in the stores, computes the other chunks here (a thread pool over
compiled drops per chunk) or on a dask cluster (:mod:`mineburial.ensembles.distributed`), saves
each finished chunk atomically, prints rate-limited progress, and yields each job's
chunk results, in drop order, as soon as the job is complete. Everything that can be
checked before computing is checked first (:func:`check_run`).

:func:`run_ensemble` is one job: its statistics and per-drop values go into one
Dataset (:func:`mineburial.ensembles.dataset.build_dataset`), written atomically to the
output path under the run's lock (:class:`~mineburial.ensembles.store.OutputRun`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import pathlib
import re
import sys
import time
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

from mineburial._version import __version__
from mineburial.ensembles import accuracy, engine, model_form, scour
from mineburial.ensembles.interrupt import Interrupted
from mineburial.ensembles.sampling import check_drop_count
from mineburial.ensembles.settings import merge_invalid_reasons
from mineburial.ensembles.store import ChunkStore, OutputRun, RunError, notice
from mineburial.kernels.stepper import MAX_STEPS
from mineburial.resources import memory_refusal

__all__ = [
    "Job",
    "run_jobs",
    "run_ensemble",
    "summarize",
    "run_ensemble_cli",
    "Progress",
    "check_run",
    "warn_run",
    "check_threads",
    "connect_scheduler",
    "STEPS_WARNING",
]

#: time steps a drop above which a fixed-step integrator gets a warning: the stepper's step
#: budget, after which a drop still moving ends ``time_limit``
STEPS_WARNING = float(MAX_STEPS)
#: seconds to wait for a dask scheduler to answer before giving up
SCHEDULER_TIMEOUT = 10.0
_FIXED_STEP = ("rk4", "local_linear")
_CHUNK_NAME = re.compile(r"^chunk-\d{12}-(\d{12})\.npz$")


# ---------------------------------------------------------------------------
# progress
# ---------------------------------------------------------------------------
class Progress:
    """Rate-limited progress lines: drops done, drops/s, time left.

    Every 2 s on a terminal (rewriting one line), every 30 s in a batch log.
    """

    def __init__(self, total: int, enabled: bool = True, stream=None, unit: str = "drops"):
        self.total = total
        self.unit = unit
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
        line = (
            f"{self.unit} {done}/{self.total} ({100.0 * done / max(self.total, 1):.1f} %), "
            f"{rate:.{1 if rate >= 1 else 2}f} {self.unit}/s, time left {eta}"
        )
        if self.tty:
            end = "\n" if final else ""
            self.stream.write("\r" + line + end)
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


# ---------------------------------------------------------------------------
# checks before computing
# ---------------------------------------------------------------------------
#: bytes of bookkeeping a chunk costs in memory beside its per-drop arrays (its dict, the
#: small arrays, the task), measured order of magnitude
CHUNK_OVERHEAD = 4096


def memory_needed(spec) -> int:
    """Bytes a run of ``spec`` needs for its per-drop values: the summary row, status and
    sampled inputs of every drop, kept until the statistics are computed, with room for
    the copies made while reducing them (a factor of 4), and the bookkeeping of every
    chunk (:data:`CHUNK_OVERHEAD`)."""
    chunks = -(-int(spec.n) // int(spec.chunk_size))
    return 4 * _bytes_a_drop(spec) * int(spec.n) + CHUNK_OVERHEAD * chunks


def _bytes_a_drop(spec) -> int:
    return spec.summary_width * 8 + 1 + 8 * len(spec.random) + scour.bytes_a_drop(spec)


def _extremes(spec, path, fixed):
    """(smallest, largest) value of input ``path`` (its distribution's central 1 - 2e-9)."""
    d = spec.random.get(path)
    if d is None:
        return fixed, fixed
    lo, hi = d.ppf(np.array([1e-9, 1.0 - 1e-9]))
    return float(lo), float(hi)


def check_run(spec, *, what: str = "the ensemble") -> None:
    """Checks of an ensemble that can be made before computing: the Sobol drop count and
    the memory for the per-drop values (a run that cannot fit is refused with the memory
    it would need)."""
    if spec.sampling == "sobol":
        check_drop_count(spec.n, "sobol")
    refusal = memory_refusal(
        memory_needed(spec),
        f"ensemble.n = {spec.n} drops: {what} ({_bytes_a_drop(spec)} bytes a drop for the "
        f"per-drop values, kept until the statistics are computed)",
        "run fewer drops (several runs with different seeds can be combined)",
    )
    if refusal:
        raise RunError(refusal)


def warn_run(spec) -> None:
    """A warning when a fixed-step integrator would take more than :data:`STEPS_WARNING`
    steps a drop (the adaptive default ``dopri5`` is not warned about). A restraint case's
    fixed step is checked by its own field ranges."""
    if spec.system != "mine":
        return
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


def check_threads(threads, what: str = "threads") -> int | None:
    """``threads`` as an int in 1..(the cores numba can use), or a RunError."""
    if threads is None:
        return None
    import numba

    cores = int(numba.config.NUMBA_NUM_THREADS)
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= cores:
        raise RunError(
            f"{what} = {threads!r} is outside the allowed range 1..{cores} "
            f"(the cores numba can use on this machine)"
        )
    return int(threads)


def connect_scheduler(address: str, timeout: float | None = None):
    """A dask client of the scheduler at ``address``, or a RunError (one line) within
    ``timeout`` s (default :data:`SCHEDULER_TIMEOUT`).

    dask's own ``timeout`` bounds the TCP connection (a refused one is retried until then),
    but not a service that accepts and never answers (measured: no end after 120 s), and
    the reply of a service that is not dask is read as a frame length (an HTTP server, a
    dashboard port given by mistake: ``MemoryError: Unable to allocate 3.07 EiB``). So a
    ``tcp://`` address is first probed (:func:`~mineburial.ensembles.distributed.
    probe_scheduler`: the scheduler's greeting within ``timeout`` s), and anything the
    client then raises is one line.
    """
    from dask.distributed import Client

    from mineburial.ensembles.distributed import probe_scheduler

    timeout = SCHEDULER_TIMEOUT if timeout is None else timeout
    problem = probe_scheduler(address, timeout)
    if problem is not None:
        raise RunError(
            f"--scheduler {address}: no dask scheduler there ({problem}); give the "
            f"scheduler's address, e.g. tcp://host:8786, not its dashboard's"
        )
    where = f"--scheduler {address}: cannot reach a dask scheduler there within {timeout:g} s"
    try:
        return Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise RunError(f"{where} ({reason})") from None
    except Exception as exc:  # whatever a service that is not a dask scheduler causes
        raise RunError(
            f"--scheduler {address}: what answered there is not a dask scheduler ({type(exc).__name__})"
        ) from None


# ---------------------------------------------------------------------------
# the driver
# ---------------------------------------------------------------------------
@dataclasses.dataclass
class Job:
    """One ensemble of a run: ``tag`` names it (None for a lone ensemble, the cell index
    of a map), ``store`` keeps its finished chunks (None: nothing on disk)."""

    tag: Any
    spec: Any
    store: ChunkStore | None = None


def _run_local(todo):
    for tag, spec, start, stop, store in todo:
        head = _finished_head(store, start, stop)
        begin = start if head is None else int(head["stop"])
        try:
            res = engine.compute_chunk(spec, begin, stop)
        except Interrupted as exc:  # keep the drops finished: a rerun starts after them
            if store is not None and exc.partial is not None and exc.done > 0:
                store.save(exc.partial if head is None else _joined(head, exc.partial))
            raise
        if head is not None:
            res = _joined(head, res)
        if store is not None:
            store.save(res)
            if head is not None:
                store.chunk_path(start, int(head["stop"])).unlink(missing_ok=True)
        yield tag, (start, stop), res


def _finished_head(store, start: int, stop: int) -> dict | None:
    """The longest valid file of the first drops of chunk ``[start, stop)`` that an
    interrupted run saved (``chunk-<start>-<k>.npz``, ``start < k < stop``), or None."""
    if store is None or not store.path.is_dir():
        return None
    ends = []
    for f in store.path.glob(f"chunk-{int(start):012d}-*.npz"):
        m = _CHUNK_NAME.match(f.name)
        if m and start < int(m.group(1)) < stop:
            ends.append(int(m.group(1)))
    for k in sorted(ends, reverse=True):
        head = store.load(start, k)
        if head is not None:
            return head
    return None


def _joined(head: dict, tail: dict) -> dict:
    """The chunk dict of drops ``[head.start, tail.stop)`` from two consecutive ones: the
    per-drop arrays concatenated, the reasons for invalid drops added up (in drop order,
    as :func:`~mineburial.ensembles.engine.invalid_reasons` of the whole would give)."""
    out = {}
    for key, value in head.items():
        if key == "invalid_inputs":
            out[key] = np.array(json.dumps(merge_invalid_reasons([head, tail]), sort_keys=True))
        elif key in ("start", "stop"):
            out[key] = np.int64(head["start"] if key == "start" else tail["stop"])
        else:
            out[key] = np.concatenate([value, tail[key]])
    return out


def run_jobs(jobs: Iterable[Job], *, client=None, progress: bool = False) -> Iterator:
    """Run every chunk of every job; yield ``(tag, [chunk results in drop order])`` as
    each job completes (jobs resumed in full first).

    Chunk files in a job's store that are valid for the run are loaded instead of
    computed; the others are computed here or, with a dask ``client``, on its cluster,
    and saved as they finish.
    """
    jobs = list(jobs)
    bounds = {job.tag: engine.chunk_bounds(job.spec.n, job.spec.chunk_size) for job in jobs}
    if len(bounds) != len(jobs):
        raise ValueError("the jobs of a run need distinct tags")
    results: dict = {job.tag: {} for job in jobs}
    for job in jobs:
        if job.store is not None:
            for s, e in bounds[job.tag]:
                res = job.store.load(s, e)
                if res is not None:
                    results[job.tag][(s, e)] = res
    done = sum(e - s for r in results.values() for s, e in r)
    unit = jobs[0].spec.unit if jobs else "drops"
    bar = Progress(sum(job.spec.n for job in jobs), enabled=progress, unit=unit)
    bar.update(done)

    def complete(tag):
        got = results.pop(tag)
        return [got[b] for b in bounds[tag]]

    todo = [
        (job.tag, job.spec, s, e, job.store)
        for job in jobs
        for s, e in bounds[job.tag]
        if (s, e) not in results[job.tag]
    ]
    for job in jobs:
        if len(results[job.tag]) == len(bounds[job.tag]):
            yield job.tag, complete(job.tag)
    if client is not None:
        from mineburial.ensembles.distributed import run_tasks_distributed

        stream = run_tasks_distributed(client, todo)
    else:
        stream = _run_local(todo)
    for tag, b, res in stream:
        results[tag][b] = res
        done += b[1] - b[0]
        bar.update(done)
        if len(results[tag]) == len(bounds[tag]):
            yield tag, complete(tag)
    bar.update(done, final=True)


# ---------------------------------------------------------------------------
# the ensemble
# ---------------------------------------------------------------------------
def _scenario_path(scenario):
    return pathlib.Path(scenario) if isinstance(scenario, (str, os.PathLike)) else None


def input_paths(scenario, spec) -> list:
    """The files a run of ``spec`` reads (the scenario file and the files it names)."""
    paths = [_scenario_path(scenario)] + [pathlib.Path(f) for f, _ in spec.input_files]
    return [p for p in paths if p is not None]


def invalid_inputs_text(reasons: dict) -> str:
    """One line for the drops whose sampled inputs were invalid (empty if none)."""
    return "; ".join(
        f"{rule}: {count} drop{'s' * (count != 1)} (e.g. {example})"
        for rule, (count, example) in sorted(reasons.items(), key=lambda kv: -kv[1][0])
    )


def ensemble_dataset(spec, chunks):
    """The output Dataset of ensemble ``spec`` from its chunk results in drop order (of a
    restraint ensemble: :func:`mineburial.ensembles.restraint.dataset`)."""
    if spec.system == "restraint":
        from mineburial.ensembles import restraint

        return restraint.dataset(spec, chunks)
    from mineburial.ensembles.dataset import build_dataset

    summary = np.concatenate([r["summary"] for r in chunks])
    status = np.concatenate([r["status"] for r in chunks])
    inputs = {
        key[6:]: np.concatenate([r[key] for r in chunks]) for key in chunks[0] if key.startswith("input:")
    }
    meta = {path: engine.input_metadata(spec, path) for path in inputs}
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
    if spec.scour is not None:
        ds = scour.dataset(spec.scour, chunks, ds, per_drop=spec.per_drop, class_basis=spec.class_basis)
    return ds


def run_ensemble(
    scenario=None,
    n: int | None = None,
    seed: int | None = None,
    *,
    sampling: str | None = None,
    chunk_size: int | None = None,
    output=None,
    per_drop: bool | None = None,
    threads: int | None = None,
    progress: bool = False,
    client=None,
    class_basis: str | None = None,
    self_check: bool = False,
):
    """Run a Monte Carlo ensemble and return its statistics as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scenario : path, dict, :class:`~mineburial.config.Scenario` or None
        Ensemble scenario (None: the embedded default soft-mud scenario); with
        ``system = "restraint"`` an ensemble of seed 004's restraining system
        (:mod:`mineburial.ensembles.restraint`: its statistics are of the stopping time).
    n, seed, sampling, chunk_size, per_drop, class_basis
        Override the scenario's ``[ensemble]`` table.
    output : path, optional
        Write the NetCDF file here (atomically); finished chunks are kept in
        ``OUTPUT.parts/`` until then, so an interrupted run resumes
        (:mod:`mineburial.ensembles.store`: a rerun reuses only chunks of the same run
        identity; a second live run on the same output is refused).
    threads : int, optional
        Number of numba threads (default: all cores).
    progress : bool
        Print rate-limited progress lines to stderr.
    client : dask.distributed.Client, optional
        Spread chunks over a dask cluster (:mod:`mineburial.ensembles.distributed`).
    self_check : bool
        Re-run ``ensemble.accuracy_check`` drops on a tight reference path here, after the
        chunks are in, and record the differences in the ``numerical_check_*`` attributes
        (:mod:`mineburial.ensembles.accuracy`; ``mineburial run`` does).
    """
    spec = engine.load_ensemble(
        scenario,
        n=n,
        seed=seed,
        sampling=sampling,
        chunk_size=chunk_size,
        per_drop=per_drop,
        class_basis=class_basis,
        systems=engine.SYSTEMS,
    )
    threads = check_threads(threads)
    check_run(spec)
    warn_run(spec)
    if threads is not None:
        import numba

        numba.set_num_threads(threads)
    if output is None:
        ((_, chunks),) = run_jobs([Job(None, spec)], client=client, progress=progress)
        return _checked(ensemble_dataset(spec, chunks), spec, chunks, self_check)
    with OutputRun(output, input_paths(scenario, spec)) as out:
        ((_, chunks),) = run_jobs([Job(None, spec, out.store(spec))], client=client, progress=progress)
        ds = _checked(ensemble_dataset(spec, chunks), spec, chunks, self_check)
        out.commit(ds)
    return ds


def _checked(ds, spec, chunks, self_check: bool):
    """``ds`` with the numerical self-check's attributes when asked (results untouched)."""
    if self_check:
        ds.attrs.update(accuracy.self_check(spec, chunks))
    return ds


def run_ensemble_cli(args) -> int:
    """``mineburial run``: the main job. Every check that can be made before computing is
    made first (scenario, output path, threads, scheduler)."""
    from mineburial.ensembles.store import check_output_path

    check_threads(args.threads, "--threads")
    spec = engine.load_ensemble(
        args.scenario,
        n=args.drops,
        seed=args.seed,
        sampling=args.sampling,
        chunk_size=args.chunk_size,
        per_drop=args.per_drop,
        systems=engine.SYSTEMS,
    )
    check_output_path(args.output, input_paths(args.scenario, spec), "-o")
    check_run(spec)
    client = connect_scheduler(args.scheduler) if args.scheduler else None
    t0 = time.monotonic()
    try:
        ds = run_ensemble(
            args.scenario,
            n=args.drops,
            seed=args.seed,
            sampling=args.sampling,
            chunk_size=args.chunk_size,
            output=args.output,
            per_drop=args.per_drop,
            threads=args.threads,
            progress=not args.quiet,
            client=client,
            self_check=True,
        )
    finally:
        if client is not None:
            client.close()
    elapsed = time.monotonic() - t0
    if spec.system == "restraint":
        from mineburial.ensembles import restraint

        print(restraint.summarize(ds, elapsed, args.output))
    else:
        print(summarize(ds, elapsed, args.output))
    return 0


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
    from mineburial.kernels import status as st

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
    lines.extend(model_form.summary_lines(ds))
    lines.extend(scour.summary_lines(ds))
    lines.extend(accuracy.summary_lines(ds))
    if elapsed is not None:
        lines.append(f"time: {elapsed:.1f} s ({n / max(elapsed, 1e-9):.1f} drops/s)")
    if output is not None:
        lines.append(f"wrote {output}")
    return "\n".join(lines)
