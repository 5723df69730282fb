"""The run driver: one mechanism that runs the chunks of ensembles, resumes them and
reduces them, for both :func:`run_ensemble` and :func:`mineburial.analyses.maps.run_map`.

A run is a list of :class:`Job` s, each an ensemble (the spec of any system of the
registry, :mod:`mineburial.systems.registry`) with an optional chunk store
(:class:`~mineburial.ensembles.store.ChunkStore`). :func:`run_jobs` loads the valid
chunk files already in the stores, computes the other chunks here (a thread pool over
compiled drops per chunk) or on a dask cluster (:mod:`mineburial.ensembles.distributed`), saves
each finished chunk atomically, prints rate-limited progress, and yields each job's
chunk results, in drop order, as soon as the job is complete. Everything that can be
checked before computing is checked first (:func:`check_run`).

:func:`run_ensemble` is one job: its statistics and per-drop values go into one
Dataset (its system's ``dataset``), written atomically to the
output path under the run's lock (:class:`~mineburial.ensembles.store.OutputRun`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import os
import pathlib
import re
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from typing import Any

import numba
import numpy as np

from mineburial.ensembles import engine
from mineburial.ensembles.distributed import open_client, probe_scheduler, run_tasks_distributed
from mineburial.ensembles.interrupt import Interrupted
from mineburial.ensembles.sampling import check_drop_count
from mineburial.ensembles.settings import merge_invalid_reasons
from mineburial.ensembles.store import ChunkStore, OutputRun, RunError, check_output_path
from mineburial.ensembles.threads import POLL
from mineburial.resources import memory_refusal
from mineburial.systems import registry

__all__ = [
    "Job",
    "run_jobs",
    "run_ensemble",
    "run_ensemble_cli",
    "Progress",
    "check_run",
    "warn_run",
    "check_threads",
    "numba_threads",
    "connect_scheduler",
]

#: seconds to wait for a dask scheduler to answer before giving up
SCHEDULER_TIMEOUT = 10.0
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
    return registry.of(spec).bytes_a_realization(spec)


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
    """Warnings of the ensemble's system before computing (the mine's: a fixed-step
    integrator that would take more than ``mine.STEPS_WARNING`` steps a drop)."""
    registry.of(spec).warn_run(spec)


def check_threads(threads, what: str = "threads") -> int | None:
    """``threads`` as an int in 1..(the cores numba can use), or a RunError."""
    if threads is None:
        return None
    cores = int(numba.config.NUMBA_NUM_THREADS)
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= cores:
        raise RunError(
            f"{what} = {threads!r} is outside the allowed range 1..{cores} "
            f"(the cores numba can use on this machine)"
        )
    return int(threads)


@contextlib.contextmanager
def numba_threads(threads: int | None):
    """numba's thread count set to ``threads`` (None: left as it is) in the calling thread
    while the block runs, then restored: the run driver's chunks use it
    (:func:`run_jobs`), the rest of the process keeps its own (numba's count is per thread)."""
    if threads is None:
        yield
        return
    before = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        yield
    finally:
        numba.set_num_threads(before)


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
    timeout = SCHEDULER_TIMEOUT if timeout is None else timeout
    problem = probe_scheduler(address, timeout)
    if problem is not None:
        raise RunError(
            f"--scheduler {address}: no dask scheduler there ({problem}); give the "
            f"scheduler's address, e.g. tcp://host:8786, not its dashboard's"
        )
    where = f"--scheduler {address}: cannot reach a dask scheduler there within {timeout:g} s"
    try:
        return open_client(address, timeout)  # a hard deadline on the handshake too (issue 35)
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


def _run_local(todo, threads=None):
    with numba_threads(threads):
        yield from _run_chunks(todo)


def _run_chunks(todo):
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
    as the system's ``invalid_reasons`` of the whole would give)."""
    out = {}
    for key, value in head.items():
        if key == "invalid_inputs":
            out[key] = np.array(json.dumps(merge_invalid_reasons([head, tail]), sort_keys=True))
        elif key in ("start", "stop"):
            out[key] = np.int64(head["start"] if key == "start" else tail["stop"])
        else:
            out[key] = np.concatenate([value, tail[key]])
    return out


def run_jobs(
    jobs: Iterable[Job], *, client=None, progress: bool = False, threads: int | None = None
) -> Iterator:
    """Run every chunk of every job; yield ``(tag, [chunk results in drop order])`` as
    each job completes (jobs resumed in full first).

    Chunk files in a job's store that are valid for the run are loaded instead of
    computed; the others are computed here or, with a dask ``client``, on its cluster,
    and saved as they finish. ``threads``: numba threads of the chunks computed here
    (default: numba's count, all cores; :func:`numba_threads`); a dask worker gives each
    chunk its cores over its dask threads (:mod:`~mineburial.ensembles.distributed`).
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
        stream = run_tasks_distributed(client, todo)
    else:
        stream = _run_local(todo, threads)
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


def ensemble_dataset(spec, chunks):
    """The output Dataset of ensemble ``spec`` from its chunk results in drop order (its
    system's ``dataset``)."""
    return registry.of(spec).dataset(spec, chunks)


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
    loaded=None,
):
    """Run a Monte Carlo ensemble and return its statistics as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scenario : path, dict, :class:`~mineburial.systems.mine.config.Scenario` or None
        Ensemble scenario (None: the embedded default soft-mud scenario); with
        ``system = "restraint"`` an ensemble of seed 004's restraining system
        (:mod:`mineburial.systems.restraint.ensemble`: its statistics are of the stopping time).
    n, seed, sampling, chunk_size, per_drop, class_basis
        Override the scenario's ``[ensemble]`` table.
    output : path, optional
        Write the NetCDF file here (atomically); finished chunks are kept in
        ``OUTPUT.parts/`` until then, so an interrupted run resumes
        (:mod:`mineburial.ensembles.store`: a rerun reuses only chunks of the same run
        identity; a second live run on the same output is refused).
    threads : int, optional
        Number of numba threads of the chunks computed in this process (default: all
        cores; :func:`run_jobs`).
    progress : bool
        Print rate-limited progress lines to stderr.
    client : dask.distributed.Client, optional
        Spread chunks over a dask cluster (:mod:`mineburial.ensembles.distributed`).
    self_check : bool
        Re-run ``ensemble.accuracy_check`` realizations on a tight reference path here, after
        the chunks are in, and record the differences in global attributes (the system's
        ``check_accuracy``, :mod:`mineburial.systems.mine.accuracy` for the mine; ``mineburial
        run`` does), beside the building of the Dataset (:func:`_dataset_checked`).
    loaded : optional
        The spec that ``engine.load_ensemble`` gives for ``scenario`` with these overrides,
        when the caller has loaded it already (``mineburial run``): it is not resolved again.
    """
    spec = loaded
    if spec is None:
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
    if output is None:
        ((_, chunks),) = run_jobs([Job(None, spec)], client=client, progress=progress, threads=threads)
        return _dataset_checked(spec, chunks, self_check, progress)
    with OutputRun(output, input_paths(scenario, spec)) as out:
        job = Job(None, spec, out.store(spec))
        ((_, chunks),) = run_jobs([job], client=client, progress=progress, threads=threads)
        ds = _dataset_checked(spec, chunks, self_check, progress)
        out.commit(ds)
    return ds


def _dataset_checked(spec, chunks, self_check: bool, progress: bool = False):
    """The output Dataset of ``spec`` from its chunks (:func:`ensemble_dataset`), with the
    system's numerical self-check attributes when asked (results untouched; ``progress``: the
    check's own progress lines, like the run's).

    The check runs beside the Dataset's building (issue 34 item 1): its drops on the thread
    pool (:class:`_Beside`), the statistics and variables here. The building is Python on one
    core (~1 s of CPU on the default run, most of it importing xarray, pandas and dask.array),
    and the check's last drops leave a core idle (the default run's 8 drops on 2 threads: the
    longest takes ~0.7 s of its ~1.5 s), so the two together take about the check's time
    where they took the sum. Its attributes are added when both are done, as before."""
    check = registry.of(spec).check_accuracy
    if not self_check or check is None:
        return ensemble_dataset(spec, chunks)
    beside = _Beside(check, spec, chunks, progress=Progress if progress else None)
    try:
        ds = ensemble_dataset(spec, chunks)
    except Exception:
        beside.wait()  # its drops' threads end first; then the building's error is raised
        raise
    ds.attrs.update(beside.result())
    return ds


class _Beside:
    """``fn(*args, **kwargs)`` on a daemon thread started now, with the calling thread's numba
    thread count (numba's count is per thread: the thread pool of a check sized by
    ``numba.get_num_threads()`` gets the caller's); :meth:`result` waits for it (in steps of
    :data:`~mineburial.ensembles.threads.POLL` s, so that Ctrl-C is seen in the main thread at
    once) and returns its value or raises its exception. A Ctrl-C leaves the thread to end
    with the process (a daemon: its drops cannot be stopped inside compiled code), as the
    thread pool's own threads do."""

    def __init__(self, fn, *args, **kwargs):
        self._value = self._error = None
        self._done = threading.Event()
        threads = numba.get_num_threads()

        def target():
            try:
                numba.set_num_threads(threads)
                self._value = fn(*args, **kwargs)
            except BaseException as exc:  # raised in the caller's thread by result()
                self._error = exc
            finally:
                self._done.set()

        threading.Thread(target=target, name="mineburial-beside", daemon=True).start()

    def wait(self) -> None:
        while not self._done.wait(POLL):
            pass

    def result(self):
        self.wait()
        if self._error is not None:
            raise self._error
        return self._value


def run_ensemble_cli(args) -> int:
    """``mineburial run``: the main job. Every check that can be made before computing is
    made first (scenario, output path, threads, scheduler)."""
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
    system = registry.of(spec)
    if getattr(args, "plot", None):  # the system's figure (the mine's: burial against lead time)
        if system.check_plot is None:
            raise RunError(f"--plot '{args.plot}': a {system.name!r} ensemble draws no figure")
        system.check_plot(args.plot, spec, args.output, input_paths(args.scenario, spec))
    check_run(spec)
    client = connect_scheduler(args.scheduler) if args.scheduler else None
    t0 = time.monotonic()
    try:
        ds = run_ensemble(
            args.scenario,
            loaded=spec,
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
    print(system.summarize(ds, elapsed, args.output))
    if getattr(args, "plot", None):
        system.plot(ds, args.plot, scenario=pathlib.Path(args.scenario or "default").stem)
        print(f"wrote {args.plot}")
    return 0
