"""Scale-out of ensembles and maps on a dask.distributed cluster.

The unit of work is a *chunk* of drops ``[start, stop)`` of one ensemble spec of any
system (:mod:`mineburial.systems.registry`). Every random input of drop
*i* is a pure function of ``(seed, i)``, so a chunk gives the same bits on any
worker, thread count or retry; the cluster only decides *where* chunks run.

* Each chunk is one dask task (:func:`chunk_task`), submitted with
  ``pure=False`` and ``retries=2`` under a key that names the chunk
  (``mineburial-chunk-[<cell>-]<start>-<stop>-<run>-<k>``; ``client.map`` is
  ``client.submit`` for many tasks at once). The worker runs
  :func:`~mineburial.ensembles.engine.compute_chunk` and, when the run's chunk
  store is on a filesystem it shares with the client (it sees the store's
  ``manifest.json`` with the run's identity), writes the chunk file itself,
  atomically (:meth:`~mineburial.ensembles.store.ChunkStore.save`). The workers of one machine
  always share it; on a cluster put the output on the shared home/scratch
  filesystem. Without a shared filesystem the results still come back through
  the scheduler, and the client saves each chunk file as its result arrives, so
  resuming still works from the client's copy.
* The numba kernels are compiled (or loaded from numba's on-disk cache) once
  per worker before the first chunk: ``client.run(warm_up)`` runs the tiny warm-up
  chunk of the run's system (the mine's: one drop of one time step) on every worker.
  The cache lives beside the sources, so the worker processes of one machine share
  it; on a cluster every node with its own copy of the package compiles once, the
  first time.
* A worker that dies (killed, out of memory, node lost) costs a retry of the
  chunks it was running: the scheduler reschedules them on the other workers
  (up to ``distributed.scheduler.allowed-failures`` times, default 3), and an
  exception raised inside a chunk is retried twice. A chunk whose file already
  exists in the shared parts folder (written before the worker died) is read
  back instead of being recomputed.
* When every worker is gone the tasks wait for new ones; the client says so
  (one line on stderr every :data:`WAITING_INTERVAL` seconds while none is there)
  instead of waiting without a word.
* Threads: each chunk runs its drops on a pool of threads calling a GIL-free
  compiled loop (:mod:`.batch`). So that dask threads and those threads do not
  oversubscribe the cores, every chunk uses ``cores of the host // dask threads on
  that host`` threads (:func:`numba_threads_per_task`; at least 1; set with
  ``numba.set_num_threads``). The recommended layout is one worker process with one
  dask thread per node (a chunk then uses every core), or one single-threaded worker
  per core.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import socket
import threading
import time
import uuid
from collections.abc import Iterable, Iterator
from concurrent.futures import CancelledError

import numba

from mineburial.ensembles import engine
from mineburial.ensembles.store import RunError, notice
from mineburial.systems import registry

__all__ = [
    "warm_up",
    "chunk_task",
    "numba_threads_per_task",
    "probe_scheduler",
    "open_client",
    "LinkLost",
    "run_tasks_distributed",
    "RETRIES",
    "WAITING_INTERVAL",
]

#: retries of a chunk whose task raised (a lost worker is rescheduled by the scheduler)
RETRIES = 2
#: seconds between the checks for a cluster without workers (and the waiting messages)
WAITING_INTERVAL = 30.0


def _available_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def warm_up(system: str = registry.DEFAULT) -> dict:
    """Compile (or load from numba's cache) the kernels of ``system`` in this process by
    computing the one-realization chunk of its ``warm_up_spec`` (the mine's: one drop
    that stops after one time step; a system without one is not warmed up).

    Returns ``{"seconds": time taken, "pid": process id, "threading_layer": numba's}``.
    Called on every worker by :func:`run_tasks_distributed` (``client.run``), where the
    work is done in a thread so that the worker's event loop keeps answering the
    scheduler during a long first compile.
    """
    t0 = time.perf_counter()
    make_spec = registry.get(system).warm_up_spec
    if make_spec is not None:
        engine.compute_chunk(make_spec(), 0, 1)
    try:
        layer = numba.threading_layer()
    except ValueError:  # pragma: no cover - no parallel region has run
        layer = "unknown"
    return {"seconds": time.perf_counter() - t0, "pid": os.getpid(), "threading_layer": layer}


async def _warm_up_on_worker(dask_worker=None, system: str = registry.DEFAULT):
    return await asyncio.to_thread(warm_up, system)


def chunk_task(spec, start: int, stop: int, store, numba_threads: int | None = None) -> dict:
    """The dask task of one chunk: compute drops ``[start, stop)`` of ``spec``.

    ``store`` is the run's :class:`~mineburial.ensembles.store.ChunkStore` (or None).
    When this worker sees the store opened by the client (its ``manifest.json`` with the
    run's identity), the folder is on a filesystem shared with the client: a valid chunk
    file already there (written by an earlier attempt) is read instead of recomputed,
    and the new chunk file is saved atomically by the worker. Otherwise (no shared
    filesystem) the worker writes nothing and the client saves the chunk when the
    result arrives (:func:`run_tasks_distributed`).
    """
    shared = store is not None and store.shared()
    if shared:
        done = store.load(start, stop)
        if done is not None:
            return done
    if numba_threads is not None:
        numba.set_num_threads(max(1, min(int(numba_threads), numba.config.NUMBA_NUM_THREADS)))
    res = engine.compute_chunk(spec, start, stop)
    if shared:
        store.save(res)
    return res


#: largest first message a dask scheduler sends on a new connection (its handshake, ~100 bytes)
GREETING_MAX_BYTES = 1 << 24


def probe_scheduler(address: str, timeout: float) -> str | None:
    """Why ``address`` is not a dask scheduler over TCP, or None when it may be one (or is
    not a ``tcp://`` address: left to dask).

    A dask scheduler greets every new connection at once: its handshake message, which
    starts with the message's length in bytes, 8 bytes little-endian
    (``distributed.comm.tcp``). A service that sends nothing within ``timeout`` s (a
    silent one, or an HTTP server waiting for a request) or whose first 8 bytes are no
    plausible length (garbage, or a text protocol) is not one. A refused or unreachable
    address is left to dask, which retries it until its own timeout.
    """
    scheme, _, rest = address.rpartition("://")
    host, _, port = rest.rpartition(":")
    if scheme not in ("", "tcp") or not host or not port.isdigit():
        return None
    deadline = time.monotonic() + timeout
    try:
        sock = socket.create_connection((host.strip("[]"), int(port)), timeout=timeout)
    except OSError:
        return None
    with sock:
        head = b""
        try:
            while len(head) < 8:
                sock.settimeout(max(deadline - time.monotonic(), 1e-3))
                got = sock.recv(8 - len(head))
                if not got:
                    return "the service there closed the connection without a word"
                head += got
        except OSError:  # socket.timeout included
            return f"a service accepted the connection and did not answer within {timeout:g} s"
    if not 0 < int.from_bytes(head, "little") <= GREETING_MAX_BYTES:
        return "what answered does not speak dask's protocol"
    return None


#: the start of dask's client message when it gives up on a lost scheduler (distributed.client
#: ``Client._reconnect``): mineburial's own line says the same and what was kept
_RECONNECT_FAILED = "Failed to reconnect to scheduler"


def _no_traceback(record: logging.LogRecord) -> bool:
    """A filter of dask's client logger: no record that carries a traceback (when the scheduler
    dies mid-run, dask logged a 30-line traceback on stderr before mineburial's one line, issue
    35) and not its "Failed to reconnect to scheduler ..." line; mineburial reports the loss
    itself. Other records pass."""
    if record.exc_info is not None or record.exc_text:
        return False
    return not str(record.msg).startswith(_RECONNECT_FAILED)


#: s: how long past its own timeout the client's connection may take before it is abandoned
CONNECT_GRACE_S = 2.0


def open_client(address: str, timeout: float):
    """``dask.distributed.Client(address, timeout=timeout)`` within a hard deadline of
    ``timeout`` + :data:`CONNECT_GRACE_S` s, or :class:`TimeoutError`.

    dask's ``timeout`` bounds the TCP connection and its retries, not a handshake that
    stalls: a service that sends a plausible 8-byte greeting (so that
    :func:`probe_scheduler` passes) and then nothing, or a scheduler whose connection to
    this client stays silent, kept ``run`` waiting for 450 s and more (issue 35). The client
    is made in a daemon thread; past the deadline it is abandoned (closed if it ever
    connects) and the caller gets the timeout."""
    from dask.distributed import Client

    logging.getLogger("distributed.client").addFilter(_no_traceback)
    box: dict = {}
    lock = threading.Lock()

    def connect():
        try:
            client = Client(address, timeout=timeout)
        except BaseException as exc:  # handed to the caller
            box["error"] = exc
            return
        with lock:
            if box.get("abandoned"):
                client.close()
            else:
                box["client"] = client

    thread = threading.Thread(target=connect, name="mineburial-dask-connect", daemon=True)
    thread.start()
    try:
        thread.join(timeout + CONNECT_GRACE_S)
    except BaseException:  # Ctrl-C while connecting: the client, if it ever connects, is closed
        with lock:
            box["abandoned"] = True
            client = box.pop("client", None)
        if client is not None:
            client.close()
        raise
    with lock:
        if "client" in box:
            return box["client"]
        if "error" in box:
            raise box["error"]
        box["abandoned"] = True
    raise TimeoutError(f"the connection's handshake did not complete within {timeout + CONNECT_GRACE_S:g} s")


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


def _watch_workers(client, stop: threading.Event, interval: float):
    """Say so while the cluster has no worker (the tasks wait for new ones)."""
    since = None
    while not stop.wait(interval):
        try:
            n = len(client.scheduler_info(n_workers=-1).get("workers", {}))
        except Exception:  # the scheduler itself is unreachable: the client reports that
            continue
        if n == 0:
            since = since or time.monotonic()
            notice(
                f"waiting for dask workers: the cluster at {client.scheduler.address} has "
                f"none (for {time.monotonic() - since:.0f} s); the run goes on when workers "
                f"join. Ctrl-C stops it; finished chunks are kept and a rerun resumes"
            )
        elif since is not None:
            notice(f"{n} dask worker(s) joined; the run goes on")
            since = None


#: s without a finished chunk after which the link to the scheduler is checked, and how long
#: the scheduler then has to answer (issue 35: a link gone silent mid-run kept ``run`` at
#: "drops 0/3000" for 300 s and more with no message)
LINK_CHECK_S = 60.0
LINK_TIMEOUT_S = 30.0


class LinkLost(RunError):
    """The scheduler did not answer over the client's link (one line; the chunks finished are kept)."""


def _check_link(client, address: str, done: int) -> None:
    """Ask the scheduler for its identity over the client's link, within :data:`LINK_TIMEOUT_S`;
    a :class:`LinkLost` when it does not answer."""
    try:
        client.sync(client.scheduler.identity, callback_timeout=LINK_TIMEOUT_S)
    except Exception as exc:  # a timeout, a closed comm: no answer either way
        reason = type(exc).__name__ if isinstance(exc, TimeoutError) else " ".join(str(exc).split())[:120]
        raise LinkLost(
            f"the dask scheduler at {address} did not answer within {LINK_TIMEOUT_S:g} s after "
            f"{LINK_CHECK_S:g} s without a finished chunk (the link to it is silent or broken: "
            f"{reason or type(exc).__name__}); the {done} chunk(s) finished are kept: rerun the same "
            f"command to resume"
        ) from None


def _as_completed_watched(client, as_completed, futures, done_count):
    """``(future, result)`` of ``futures`` as they finish (dask's ``as_completed``), with a
    watchdog: after :data:`LINK_CHECK_S` s without one, the scheduler must answer over the
    client's link (:func:`_check_link`), else the run ends in one line."""
    ac = as_completed(futures, with_results=True, raise_errors=False)
    address = client.scheduler.address
    quiet_since = time.monotonic()
    while True:
        batch = ac.next_batch(block=False)
        if batch:
            quiet_since = time.monotonic()
            yield from batch
            continue
        if ac.is_empty():
            return
        if time.monotonic() - quiet_since > LINK_CHECK_S:
            _check_link(client, address, done_count())
            quiet_since = time.monotonic()
        time.sleep(0.05)


def run_tasks_distributed(
    client, items: Iterable, *, warm: bool = True, numba_threads: int | None = None
) -> Iterator:
    """Run chunks of possibly different ensembles on a dask cluster.

    ``items``: iterable of ``(tag, spec, start, stop, store)`` (``tag`` is any label
    passed back, e.g. a map cell; ``store`` a
    :class:`~mineburial.ensembles.store.ChunkStore` or None). Yields
    ``(tag, (start, stop), result_dict)`` as chunks finish, in any order; a chunk that
    the worker could not save (no shared filesystem) is saved here. If a chunk still
    fails after its retries, the remaining tasks are cancelled and a ``RuntimeError``
    naming the chunk is raised from the task's exception. A chunk cancelled by the
    scheduler (one that stopped or restarted: dask then cancels every task, and
    ``as_completed(raise_errors=False)`` hands the ``FutureCancelledError`` back as the
    result) ends the run with a RunError, one line; the chunks finished are kept.
    """
    from distributed.comm.core import CommClosedError

    address, done = client.scheduler.address, 0
    with contextlib.closing(_run_tasks(client, items, warm=warm, numba_threads=numba_threads)) as chunks:
        try:
            for out in chunks:
                done += 1
                yield out
        except CommClosedError as exc:  # was an OSError naming dask's internal connection pool
            raise RunError(
                f"the dask scheduler at {address} closed the connection mid-run ("
                f"{str(exc).rsplit('>: ', 1)[-1]}: it stopped, or the network failed); the {done} "
                "chunk(s) finished are kept: rerun the same command to resume"
            ) from None


def _run_tasks(client, items: Iterable, *, warm: bool, numba_threads: int | None) -> Iterator:
    """The body of :func:`run_tasks_distributed` (which turns a closed connection into one line)."""
    from distributed import as_completed

    items = list(items)
    if not items:
        return
    if warm:
        for system in dict.fromkeys(spec.system for _, spec, _, _, _ in items):
            client.run(_warm_up_on_worker, system=system)
    if numba_threads is None:
        numba_threads = numba_threads_per_task(client)
    run_id = uuid.uuid4().hex[:8]
    keys, labels, stores_of = [], {}, {}
    specs, starts, stops, stores = [], [], [], []
    for k, (tag, spec, start, stop, store) in enumerate(items):
        tag_txt = "" if tag is None else f"{tag}-"
        key = f"mineburial-chunk-{tag_txt}{int(start)}-{int(stop)}-{run_id}-{k}"
        keys.append(key)
        labels[key] = (tag, (int(start), int(stop)))
        stores_of[key] = store
        specs.append(spec)
        starts.append(int(start))
        stops.append(int(stop))
        stores.append(store)
    # chunk_task is looked up here, at call time, so that tests can replace it
    futures = client.map(
        chunk_task,
        specs,
        starts,
        stops,
        stores,
        [numba_threads] * len(keys),
        key=keys,
        pure=False,
        retries=RETRIES,
    )
    pending = {f.key: f for f in futures}
    del futures
    stop_watch = threading.Event()
    watcher = threading.Thread(
        target=_watch_workers,
        args=(client, stop_watch, WAITING_INTERVAL),
        name="mineburial-worker-watch",
        daemon=True,
    )
    watcher.start()
    address, done = client.scheduler.address, 0
    link_lost = False
    try:
        finished = lambda: done  # noqa: B023, E731 -- read when the watchdog speaks: the count then
        for fut, res in _as_completed_watched(client, as_completed, list(pending.values()), finished):
            tag, bounds = labels[fut.key]
            pending.pop(fut.key, None)
            what = "the ensemble" if tag is None else str(tag)
            # Decided on the result in hand, not on fut.status: a worker that dies after
            # its chunk was gathered turns the future "lost" (dask would recompute it),
            # but the bits are already here. as_completed(raise_errors=False) hands back
            # a failed task's (type, exception, traceback) and a cancelled one's
            # CancelledError (the scheduler stopped or restarted) instead of the chunk.
            if isinstance(res, tuple):
                exc = res[1]
                raise RuntimeError(
                    f"chunk [{bounds[0]}, {bounds[1]}) of {what} failed on the dask cluster "
                    f"after {RETRIES} retries: {exc!r}"
                ) from exc
            if isinstance(res, CancelledError):
                raise RunError(
                    f"the dask scheduler at {address} lost chunk [{bounds[0]}, {bounds[1]}) of "
                    f"{what} (task {fut.status}: the scheduler stopped or restarted); the "
                    f"{done} chunk(s) finished are kept: rerun the same command to resume"
                )
            done += 1
            fut.release()
            store = stores_of.pop(fut.key)
            if store is not None and not store.has(*bounds):
                store.save(res)  # no filesystem shared with the workers
            yield tag, bounds, res
    except LinkLost:
        link_lost = True
        raise
    finally:
        stop_watch.set()
        if pending and not link_lost:  # a cancel over a silent link would wait for it
            client.cancel(list(pending.values()))
