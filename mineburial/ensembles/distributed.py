"""Scale-out of ensembles and maps on a dask.distributed cluster.

The unit of work is a *chunk* of drops ``[start, stop)`` of one
:class:`~mineburial.ensembles.engine.EnsembleSpec`. Every random input of drop
*i* is a pure function of ``(seed, i)``, so a chunk gives the same bits on any
worker, thread count or retry; the cluster only decides *where* chunks run.

* Each chunk is one dask task (:func:`chunk_task`), submitted with
  ``pure=False`` and ``retries=2`` under a key that names the chunk
  (``mineburial-chunk-[<cell>-]<start>-<stop>-<run>-<k>``; ``client.map`` is
  ``client.submit`` for many tasks at once). The worker runs
  :func:`~mineburial.ensembles.engine.compute_chunk` and, when the run's parts
  folder is on a filesystem it shares with the client (it sees the folder's
  ``manifest.json``), writes the chunk file itself, atomically
  (:func:`~mineburial.ensembles.engine.save_chunk`). The workers of one machine
  always share it; on a cluster put the output on the shared home/scratch
  filesystem. Without a shared filesystem the results still come back through
  the scheduler, and the client saves each chunk file as its result arrives, so
  resuming still works from the client's copy.
* The numba kernels are compiled (or loaded from numba's on-disk cache) once
  per worker before the first chunk: ``client.run(warm_up)`` runs one tiny drop
  on every worker. The cache lives beside the sources, so the worker processes of
  one machine share it; on a cluster every node with its own copy of the
  package compiles once, the first time.
* A worker that dies (killed, out of memory, node lost) costs a retry of the
  chunks it was running: the scheduler reschedules them on the other workers
  (up to ``distributed.scheduler.allowed-failures`` times, default 3), and an
  exception raised inside a chunk is retried twice. A chunk whose file already
  exists in the shared parts folder (written before the worker died) is read
  back instead of being recomputed.
* numba threads: each chunk runs its drops in a parallel numba loop. So that
  dask threads and numba threads do not oversubscribe the cores, every chunk
  uses ``cores of the host // dask threads on that host`` numba threads
  (:func:`numba_threads_per_task`; at least 1). The recommended layout is one
  worker process with one dask thread per node (numba then uses every core), or
  one single-threaded worker per core.
"""

from __future__ import annotations

import asyncio
import os
import pathlib
import threading
import time
import uuid
from collections.abc import Iterable, Iterator

from mineburial.ensembles import engine

__all__ = ["warm_up", "chunk_task", "numba_threads_per_task", "run_tasks_distributed",
           "run_chunks_distributed", "RETRIES"]

#: retries of a chunk whose task raised (a lost worker is rescheduled by the scheduler)
RETRIES = 2

_LOCK = threading.Lock()   # serialises parallel launches under numba's workqueue layer


def _available_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def _warm_up_spec():
    """A one-drop ensemble that ends after one time step (the embedded default scenario,
    whose random inputs exercise every sampler, with ``numerics.t_max = numerics.dt``)."""
    with open(engine.DEFAULT_SCENARIO, "rb") as fh:
        raw = engine.tomllib.load(fh)
    numerics = raw.setdefault("numerics", {})
    numerics["t_max"] = float(numerics.get("dt", 1e-3))
    return engine.load_ensemble(raw, n=1, chunk_size=1)


def warm_up() -> dict:
    """Compile (or load from numba's cache) the batch kernel and the samplers in this
    process by running one drop that stops after one time step.

    Returns ``{"seconds": time taken, "pid": process id, "threading_layer": numba's}``.
    Called on every worker by :func:`run_tasks_distributed` (``client.run``), where the
    work is done in a thread so that the worker's event loop keeps answering the
    scheduler during a long first compile.
    """
    import numba

    t0 = time.perf_counter()
    engine.compute_chunk(_warm_up_spec(), 0, 1)
    try:
        layer = numba.threading_layer()
    except ValueError:  # pragma: no cover - no parallel region has run
        layer = "unknown"
    return {"seconds": time.perf_counter() - t0, "pid": os.getpid(), "threading_layer": layer}


async def _warm_up_on_worker(dask_worker=None):
    return await asyncio.to_thread(warm_up)


def chunk_task(spec, start: int, stop: int, parts, numba_threads: int | None = None) -> dict:
    """The dask task of one chunk: compute drops ``[start, stop)`` of ``spec``.

    ``parts`` is the chunk folder of the run (or None). When this worker sees the run's
    ``manifest.json`` there, the folder is on a filesystem shared with the client: a
    chunk file already present (written by an earlier attempt) is read instead of
    recomputed, and the new chunk file is saved atomically by the worker. Otherwise
    (no shared filesystem) the worker writes nothing and the client saves the chunk
    when the result arrives (:func:`run_tasks_distributed`).
    """
    import numba

    shared = False
    if parts is not None:
        parts = pathlib.Path(parts)
        shared = (parts / "manifest.json").exists()
        path = engine._chunk_path(parts, start, stop)
        if shared and path.exists():
            return engine.load_chunk(path)
    if numba_threads is not None:
        numba.set_num_threads(max(1, min(int(numba_threads), numba.config.NUMBA_NUM_THREADS)))
    if _workqueue():
        with _LOCK:
            res = engine.compute_chunk(spec, start, stop)
    else:
        res = engine.compute_chunk(spec, start, stop)
    if shared:
        engine.save_chunk(parts, res)
    return res


def _workqueue() -> bool:
    """True when numba runs on its workqueue threading layer, which aborts the process
    if two threads launch parallel regions at once (dask workers with nthreads > 1)."""
    import numba

    try:
        return numba.threading_layer() == "workqueue"
    except ValueError:
        return numba.config.THREADING_LAYER == "workqueue"


def numba_threads_per_task(client) -> int:
    """numba threads for one chunk so that a host's dask threads times numba threads does
    not exceed its cores: min over hosts of ``cores // dask threads on the host``, >= 1."""
    workers = client.scheduler_info(n_workers=-1).get("workers", {})
    if not workers:
        return 1
    cores = client.run(_available_cores, on_error="ignore")
    per_host_threads: dict[str, int] = {}
    per_host_cores: dict[str, int] = {}
    for addr, info in workers.items():
        host = info.get("host", addr)
        per_host_threads[host] = per_host_threads.get(host, 0) + int(info.get("nthreads", 1))
        c = cores.get(addr)
        if isinstance(c, int):
            per_host_cores[host] = c
    ks = [max(1, per_host_cores.get(h, 1) // max(t, 1)) for h, t in per_host_threads.items()]
    return max(1, min(ks))


def run_tasks_distributed(client, items: Iterable, *, warm: bool = True,
                          numba_threads: int | None = None) -> Iterator:
    """Run chunks of possibly different ensembles on a dask cluster.

    ``items``: iterable of ``(tag, spec, start, stop, parts)`` (``tag`` is any label
    passed back, e.g. a map cell; ``parts`` a folder or None). Yields
    ``(tag, (start, stop), result_dict)`` as chunks finish, in any order. If a chunk
    still fails after its retries, the remaining tasks are cancelled and a
    ``RuntimeError`` naming the chunk is raised from the task's exception.
    """
    from distributed import as_completed

    items = list(items)
    if not items:
        return
    if warm:
        client.run(_warm_up_on_worker)
    if numba_threads is None:
        numba_threads = numba_threads_per_task(client)
    run_id = uuid.uuid4().hex[:8]
    keys, labels, folders_of = [], {}, {}
    specs, starts, stops, folders = [], [], [], []
    for k, (tag, spec, start, stop, parts) in enumerate(items):
        tag_txt = "" if tag is None else f"{tag}-"
        key = f"mineburial-chunk-{tag_txt}{int(start)}-{int(stop)}-{run_id}-{k}"
        keys.append(key)
        labels[key] = (tag, (int(start), int(stop)))
        folders_of[key] = parts
        specs.append(spec)
        starts.append(int(start))
        stops.append(int(stop))
        folders.append(None if parts is None else str(parts))
    # chunk_task is looked up here, at call time, so that tests can replace it
    futures = client.map(chunk_task, specs, starts, stops, folders,
                         [numba_threads] * len(keys), key=keys, pure=False, retries=RETRIES)
    pending = {f.key: f for f in futures}
    del futures
    try:
        for fut, res in as_completed(list(pending.values()), with_results=True,
                                     raise_errors=False):
            tag, bounds = labels[fut.key]
            pending.pop(fut.key, None)
            if fut.status == "error":
                exc = fut.exception()
                what = "the ensemble" if tag is None else str(tag)
                raise RuntimeError(
                    f"chunk [{bounds[0]}, {bounds[1]}) of {what} failed on the dask cluster "
                    f"after {RETRIES} retries: {exc!r}") from exc
            fut.release()
            parts = folders_of.pop(fut.key)
            if parts is not None and not engine._chunk_path(pathlib.Path(parts), *bounds).exists():
                engine.save_chunk(pathlib.Path(parts), res)   # no filesystem shared with workers
            yield tag, bounds, res
    finally:
        if pending:
            client.cancel(list(pending.values()))


def run_chunks_distributed(client, spec, todo, parts, *, warm: bool = True,
                           numba_threads: int | None = None) -> Iterator:
    """Chunks ``todo`` (list of ``(start, stop)``) of ``spec`` on the cluster of ``client``.

    Yields ``((start, stop), result_dict)`` as chunks finish (any order); with ``parts``
    (a folder on a filesystem shared with the workers) every worker also saves its chunk
    file there. Called by :func:`mineburial.ensembles.engine.run_ensemble` when given a
    ``client``.
    """
    items = [(None, spec, s, e, parts) for s, e in todo]
    for _, bounds, res in run_tasks_distributed(client, items, warm=warm,
                                                numba_threads=numba_threads):
        yield bounds, res
