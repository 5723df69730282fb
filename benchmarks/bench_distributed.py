"""Throughput of ensembles on dask.distributed, and the overhead per chunk.

    python benchmarks/bench_distributed.py [-n 8] [--chunk-size 2] [--workers 1 2]
                                           [--overhead-chunks 200] [--scenario FILE]

1. **Throughput**: the same ensemble (default: the embedded default soft-mud ensemble)
   run in this process with 1 numba thread (the single-core cost per drop) and as one
   chunk with all cores, and on a ``LocalCluster`` with 1 and 2 single-threaded worker
   processes (numba threads per chunk = cores // dask threads, as
   ``run_tasks_distributed`` chooses). Compile time is excluded: every process is
   warmed up (``warm_up``) before the clock starts. Prints drops/s, s/drop and
   core-s/drop (wall time x the cores the layout keeps busy / drops).
2. **Overhead per chunk**: chunks of ``--overhead-drops`` drops that end after one time
   step (``numerics.t_max = numerics.dt``), so the work is almost nothing: time per chunk
   in this process vs through the scheduler. The overhead is the worker-seconds per chunk
   on the cluster minus the local time per chunk.

Results are bit-identical whatever the layout (tests/test_distributed.py); only timings
differ. States the machine (cores, CPU model) with the table.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import platform
import sys
import time

# run from a source checkout without relying on the editable install's finder
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))

import numpy as np  # noqa: E402

from mineburial.ensembles import distributed as D  # noqa: E402
from mineburial.ensembles import engine  # noqa: E402


def _cpu_model() -> str:
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _instant_spec(n_drops: int, chunk_size: int):
    """The default ensemble with drops that stop after one step."""
    spec = D._warm_up_spec()
    raw = dict(spec.raw)
    return engine.load_ensemble(raw, n=n_drops, chunk_size=chunk_size, seed=1)


def _time_local(spec, bounds):
    t0 = time.perf_counter()
    results = [engine.compute_chunk(spec, s, e) for s, e in bounds]
    return time.perf_counter() - t0, results


def _time_cluster(client, spec, bounds):
    t0 = time.perf_counter()
    results = {
        b: res
        for _, b, res in D.run_tasks_distributed(
            client, [(None, spec, s, e, None) for s, e in bounds], warm=False
        )
    }
    return time.perf_counter() - t0, [results[b] for b in bounds]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", type=int, default=8, help="drops of the throughput ensemble (default 8)")
    ap.add_argument("--chunk-size", type=int, default=2, help="drops per chunk (default 2)")
    ap.add_argument(
        "--workers",
        type=int,
        nargs="+",
        default=[1, 2],
        help="numbers of single-threaded worker processes (default 1 2)",
    )
    ap.add_argument(
        "--overhead-chunks", type=int, default=200, help="chunks in the overhead measurement (default 200)"
    )
    ap.add_argument(
        "--overhead-drops",
        type=int,
        default=1,
        help="drops per chunk in the overhead measurement (default 1)",
    )
    ap.add_argument(
        "--scenario", default=None, help="ensemble scenario TOML (default: the embedded default ensemble)"
    )
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)

    from distributed import Client, LocalCluster

    cores = _cores()
    print(f"machine: {cores} cores, {_cpu_model()}, Python {platform.python_version()}, {platform.system()}")
    spec = engine.load_ensemble(args.scenario, n=args.n, chunk_size=args.chunk_size, seed=args.seed)
    bounds = engine.chunk_bounds(spec.n, spec.chunk_size)
    instant = _instant_spec(args.overhead_chunks * args.overhead_drops, args.overhead_drops)
    ibounds = engine.chunk_bounds(instant.n, instant.chunk_size)
    print(
        f"scenario: {args.scenario or 'embedded default ensemble'}, {spec.n} drops in "
        f"{len(bounds)} chunks of {spec.chunk_size}; overhead: {len(ibounds)} chunks of "
        f"{instant.chunk_size} drop(s) that stop after one step\n"
    )

    D.warm_up()  # compile outside the clock
    rows = []
    import numba

    numba.set_num_threads(1)
    wall, ref = _time_local(spec, bounds)
    rows.append(("local, 1 numba thread (single-core cost)", 1, wall, 1))
    numba.set_num_threads(min(cores, numba.config.NUMBA_NUM_THREADS))
    wall1, _ = _time_local(spec, [(0, spec.n)])
    rows.append((f"local, one chunk of {spec.n}, numba threads {cores}", 1, wall1, cores))
    iwall, _ = _time_local(instant, ibounds)
    over = [("local", 1, iwall)]

    for nw in args.workers:
        cluster = LocalCluster(
            n_workers=nw, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
        )
        client = Client(cluster)
        try:
            client.run(D._warm_up_on_worker)
            k = D.numba_threads_per_task(client)
            w, res = _time_cluster(client, spec, bounds)
            for a, b in zip(ref, res):  # same bits as the local run
                assert np.array_equal(a["summary"], b["summary"], equal_nan=True)
                assert np.array_equal(a["status"], b["status"])
            rows.append((f"dask, {nw} worker(s) x 1 thread, numba threads {k}", nw, w, min(cores, nw * k)))
            iw, _ = _time_cluster(client, instant, ibounds)
            over.append((f"dask, {nw} worker(s)", nw, iw))
        finally:
            client.close()
            cluster.close()

    print("throughput (compile excluded)")
    print(f"{'layout':48s} {'wall s':>8s} {'drops/s':>9s} {'s/drop':>8s} {'core-s/drop':>12s}")
    for label, _, w, busy in rows:  # core-s per drop: wall x cores the layout keeps busy
        print(f"{label:48s} {w:8.2f} {spec.n / w:9.3f} {w / spec.n:8.3f} {w * busy / spec.n:12.3f}")
    print("\noverhead per chunk (chunks of drops that stop after one step)")
    print(f"{'layout':48s} {'wall s':>8s} {'ms/chunk':>9s} {'overhead ms/chunk (worker-time)':>32s}")
    local_per = over[0][2] / len(ibounds)
    for label, nw, w in over:
        per = w / len(ibounds)
        extra = "" if label == "local" else f"{(per * nw - local_per) * 1e3:32.2f}"
        print(f"{label:48s} {w:8.2f} {per * 1e3:9.2f} {extra}")
    try:
        load = os.getloadavg()[0]
    except OSError:  # pragma: no cover
        load = float("nan")
    print(f"\nload average at the end: {load:.2f} on {cores} cores (other jobs inflate timings)")
    print(
        "note: the batch driver hands drops to numba threads 4 at a time "
        "(mineburial.systems.mine.batch.CHUNK_SIZE), so a chunk of <= 4 drops runs on one thread; "
        "drops differ widely in cost, so small ensembles are dominated by load imbalance."
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
