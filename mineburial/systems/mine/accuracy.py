"""The numerical self-check of an ensemble (issue 19 item 6): the accuracy of the run's
numerics measured on a small random subsample of its own drops, not assumed.

After the ensemble is assembled, :func:`self_check` re-runs ``ensemble.accuracy_check``
of its drops (default ``"auto"``: :func:`default_size`, ~15 % of the run's time, 8 to 230 drops; an
integer: that many; 0 switches it off) on a tight reference path
(:func:`reference_params`, :data:`REFERENCES` ``"check"``): ``numerics.rtol`` 3e-5 with
``numerics.atol`` 3e-6 (the defaults' ratio atol = rtol / 10, the run's own where tighter), the
reference sediment quadrature and the reference overburden quadrature, on the drop's own adaptive
integrator; a fixed step (``rk4``, ``local_linear``) is replaced by the adaptive ``dopri5`` (the
explicit reference of docs/design.md), since a tolerance does not tighten it, and so is the step of a
drop on a long sediment table (:func:`long_tables`: the Rosenbrock-W step took ~6x ``dopri5``'s steps
on the rough sampled reference force of a 20,000-row core). Why 3e-5 (issue 34;
1e-5 from issue 19 until then, still selectable as ``"accurate"``) and not the 1e-7 of issue 19's
measurement: the reference sediment quadrature's force is rough at ~1e-5 of its scale (its panels
and grading jump with the state), so that the steps grow ~2x for every 3x of rtol below ~1e-4
(the default ensemble's 8 check drops: 1,435 steps at 1e-4, 2,588 at 3e-5, 5,150 at 1e-5, 29,845 at
1e-6; the fast rule at 1e-5: 2,455), while the penetrations stay within 0.25 mm of rtol 1e-6's at
3e-5 (0.18 mm at 1e-5, 1.3 mm at 1e-4): 5 % of the 5 mm below which a change counts as 0, for
half the work of 1e-5; on fast steep entries 0.9-2.0 m deep, within 0.16 % of the penetration (1e-5:
0.12 %), a sixth of the p95 target (docs/design.md, "The numerical self-check"). The drops are chosen
reproducibly from the seed (their own generator: the sampled inputs of every drop are untouched),
among the drops that were run, and their inputs are those of the ensemble (re-packed by
:func:`~mineburial.systems.mine.ensemble.chunk_inputs` from ``(seed, drop index)``). The check
runs here, after the chunks are in (computed here, on a dask cluster or loaded by a
resume), and changes none of the run's results. The drops run one a block of the run's thread
pool (a thread takes the next drop when done with its last; those that took the most steps in the
run first), with the run's progress lines when ``progress``.

The differences are measured as ``../shared/tools/answers-vs`` and
``benchmarks/bench_fast_drops.py`` measure them: the penetration change relative to
max(reference penetration, 0.5 m), a change of at most 5 mm counting as 0, its 95th
percentile and maximum, and the drops whose burial class (on the run's class basis) or end
status changes. They go into the global attributes ``numerical_check_*`` and the printed
summary, with a warning beyond the targets of docs/design.md (p95 1 %, max 5 %).

Its size (issue 34): n drops catch a defect of a fraction q of the drops (at least one failing
drop among them) with probability 1 - (1 - q)^n; the attribute
``numerical_check_detectable_failure_percent`` and the summary state the q caught with
probability 0.9 (:func:`detectable_rate`: 25 % for 8 drops; :func:`drops_needed`: 230 drops for
1 %). A reference drop costs ~45 ensemble drops of CPU (:data:`CHECK_COST_RATIO`), so the default
size (:func:`default_size`) grows with the run, ~n/255 drops, from 8 (up to ~2,300 drops run) to
230 (from ~58,650): within ~15 % of the run's time, a 1 % defect caught only in large runs
(docs/design.md, "Sizing").
"""

from __future__ import annotations

import math
import threading
import time

import numba
import numpy as np

from mineburial.ensembles.threads import BLOCK_SIZE, run_blocks
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as st
from mineburial.kernels.mine.overburden import with_long_tables
from mineburial.kernels.mine.sediment.reference import REFERENCE_LEVELS
from mineburial.kernels.mine.stepper import reference_paths
from mineburial.systems.mine import batch
from mineburial.systems.mine.statistics import burial_class

__all__ = [
    "self_check",
    "check_size",
    "default_size",
    "detectable_rate",
    "drops_needed",
    "reference_params",
    "long_tables",
    "choose_drops",
    "differences",
    "summary_lines",
    "REFERENCES",
    "TARGETS",
]

#: the reference paths by name: ``(rtol, atol)`` on the reference quadratures (the defaults' ratio
#: atol = rtol / 10). ``"check"``, the self-check's and ``benchmarks/accuracy_sweep.py``'s (issue 34):
#: rtol 3e-5 takes half the steps of 1e-5 on the reference quadratures (whose force is rough at
#: ~1e-5 of its scale: 5,150 steps against 2,455 on the fast rule at rtol 1e-5) and its penetrations stay
#: within 0.25 mm of rtol 1e-6's on the default ensemble's check drops (1e-5: 0.18 mm; docs/design.md,
#: "The numerical self-check"); ``"accurate"``: the reference of issue 19 to issue 34, rtol 1e-5.
REFERENCES = {"check": (3e-5, 3e-6), "accurate": (1e-5, 1e-6)}
#: the self-check's reference path's relative tolerance, and its absolute one
REFERENCE_RTOL, REFERENCE_ATOL = REFERENCES["check"]
#: (p95, max) of the relative penetration change, percent: the accuracy targets (issue 19)
TARGETS = (1.0, 5.0)
#: a penetration change of at most this many metres counts as 0 (answers-vs, bench_fast_drops)
FLOOR_M = 0.005
#: the penetration below which changes are taken relative to this depth instead, m
SCALE_M = 0.5
#: the probability with which the check is to see at least one failing drop (the sizing rule:
#: a failure rate q among the drops is seen with probability 1 - (1 - q)^n on n drops)
DETECTION_PROBABILITY = 0.9
#: ``ensemble.accuracy_check``'s default: the size of :func:`default_size` for the run's drops
AUTO = "auto"
#: the share of a run's wall time the default size is chosen to spend on the check (issue 34 item 2)
TIME_SHARE = 0.15
#: CPU time of one drop re-run on the reference path over that of one drop of the ensemble, the
#: default ensemble on one thread (``benchmarks/bench_check_ratio.py``, 400 drops against 16 check
#: drops, 2 seeds, the shared 2-core host: 38.9 and 49.3; the default run's 8 check drops 2.3 s of
#: CPU against 14 s for its 2,000 drops: 41); the larger side, so that the check stays within its share
CHECK_COST_RATIO = 45.0
#: the default size's floor: the check's size before issue 34's rule (a defect of 25 % of the drops)
MIN_DROPS = 8
#: the failure rate whose detection with :data:`DETECTION_PROBABILITY` caps the default size
TARGET_RATE = 0.01
#: mixed into the seed for the subsample's own generator (the drops' input streams stay untouched)
_STREAM = 0x5E1F_C4EC
_FIXED_STEP = tuple(layout.INTEGRATOR_NAMES.index(name) for name in ("rk4", "local_linear"))
_DOPRI5 = layout.INTEGRATOR_NAMES.index("dopri5")
REFERENCE_TEXT = (
    f"numerics.rtol {REFERENCE_RTOL:g}, numerics.atol {REFERENCE_ATOL:g} (or the run's own if tighter), "
    "sediment_quadrature 'reference', overburden_quadrature 'reference', the drop's own adaptive "
    f"integrator (a fixed step, and any step on a sediment table of more than {REFERENCE_LEVELS} depths, "
    "replaced by 'dopri5')"
)


def detectable_rate(n: int, probability: float = DETECTION_PROBABILITY) -> float:
    """The least failure rate q (a fraction of the drops) that ``n`` drops chosen at random
    catch (at least one failing drop among them) with ``probability``: 1 - (1 - q)^n =
    probability, q = 1 - (1 - probability)^(1/n) (8 drops: 25 %; 230: 1 %)."""
    return 1.0 - (1.0 - probability) ** (1.0 / n) if n > 0 else 1.0


def drops_needed(rate: float, probability: float = DETECTION_PROBABILITY) -> int:
    """The least number of drops n with 1 - (1 - rate)^n >= probability: 230 for a failure
    rate of 1 % at 90 %."""
    return math.ceil(math.log1p(-probability) / math.log1p(-rate) - 1e-12)


def default_size(n: int) -> int:
    """The self-check's size for a run of ``n`` drops with ``ensemble.accuracy_check = "auto"``
    (the default): the most drops whose reference re-runs take at most :data:`TIME_SHARE` of the
    run's time on the same threads, a reference drop costing :data:`CHECK_COST_RATIO` ensemble
    drops (k K <= s (n + k K), k <= s n / ((1 - s) K): n / 255), at least :data:`MIN_DROPS` and at
    most :func:`drops_needed` (:data:`TARGET_RATE`), the size that catches a defect of 1 % of
    the drops with 90 % probability (230): 8 drops up to 2,294 drops run (a defect of 25 % of the
    drops caught), 39 for 10^4 (5.7 %), 230 from 58,650 on (1 %). A function of ``n`` alone, so
    that a rerun checks the same drops (:func:`choose_drops`) and writes the same file."""
    share = TIME_SHARE * int(n) / ((1.0 - TIME_SHARE) * CHECK_COST_RATIO)
    return int(min(max(math.floor(share), MIN_DROPS), drops_needed(TARGET_RATE)))


def check_size(setting, n: int) -> int:
    """The number of drops the self-check of a run of ``n`` drops re-runs: ``setting``
    (``ensemble.accuracy_check``) when it is an integer (0: no check), :func:`default_size` of
    ``n`` when it is :data:`AUTO`."""
    return default_size(n) if isinstance(setting, str) and setting == AUTO else int(setting)


def long_tables(P, sediment_bank) -> np.ndarray:
    """Per row of ``P``: whether the drop's tabulated sediment profile has more tabulated depths
    below the seabed than the reference sediment quadrature resolves one by one
    (:data:`~mineburial.kernels.mine.sediment.reference.REFERENCE_LEVELS`: beyond, it samples the rows,
    and on a rough log its force is rough at the rows' scale)."""
    rows = np.asarray(P)[:, layout.P_SED_PROFILE].astype(np.int64)
    bank = np.asarray(sediment_bank, dtype=np.float64)
    depths = np.sum(bank[:, 0, :] > 0.0, axis=1) if bank.size else np.zeros(0, np.int64)
    inside = (rows >= 0) & (rows < depths.size)
    out = np.zeros(rows.size, dtype=bool)
    out[inside] = depths[rows[inside]] > REFERENCE_LEVELS
    return out


def reference_params(P, reference: str = "check", sediment_bank=None) -> np.ndarray:
    """A copy of the packed parameters ``P`` (one row a drop) on the tight reference path
    ``reference`` (:data:`REFERENCES`: ``"check"`` rtol 3e-5, ``"accurate"`` rtol 1e-5; never
    looser than the drop's own tolerances): the reference quadratures at that rtol on
    the drop's own adaptive integrator; a fixed step (``rk4``, ``local_linear``) replaced by
    ``dopri5``, since a tolerance does not tighten it. Not another integrator family in the
    sediment (tried for issue 34: the explicit ``dopri5`` throughout took 14.9 s against 2.5 s
    on one slowly settling drop of the default ensemble, doubling the default run's time;
    docs/design.md, "The numerical self-check"), except with ``sediment_bank`` for a drop on a long
    table (:func:`long_tables`): there the Rosenbrock-W step's difference Jacobian of the sampled,
    rough reference force took ~6x the steps of ``dopri5`` (issue 34: the 20,000-row core of
    ``benchmarks/bench_self_check.py``, 8 drops at rtol 3e-5: 13,754 steps and 83 s of CPU against
    2,309 and 12 s, penetrations within 0.8 mm), so such a drop's reference takes ``dopri5``."""
    if reference not in REFERENCES:
        raise ValueError(f"reference = {reference!r}: not one of {', '.join(map(repr, REFERENCES))}")
    rtol, atol = REFERENCES[reference]
    Q = np.array(P, dtype=np.float64, copy=True)
    Q[:, layout.P_RTOL] = np.minimum(Q[:, layout.P_RTOL], rtol)
    Q[:, layout.P_ATOL] = np.minimum(Q[:, layout.P_ATOL], atol)
    Q[:, layout.P_SED_QUADRATURE] = layout.SEDIMENT_QUADRATURE_NAMES.index("reference")
    Q[:, layout.P_OB_QUADRATURE] = layout.OVERBURDEN_QUADRATURE_NAMES.index("reference")
    fixed = np.isin(Q[:, layout.P_INTEGRATOR], _FIXED_STEP)
    if sediment_bank is not None:
        fixed |= long_tables(Q, sediment_bank)
    Q[fixed, layout.P_INTEGRATOR] = _DOPRI5
    return Q


def choose_drops(seed: int, status, size: int) -> np.ndarray:
    """Indices (ascending) of ``min(size, drops run)`` drops chosen reproducibly from
    ``seed`` among the drops whose inputs were valid (``status`` != invalid_input)."""
    run = np.flatnonzero(np.asarray(status) != st.INVALID_INPUT)
    k = min(int(size), run.size)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed) % 2**64, _STREAM]))
    return np.sort(rng.choice(run, size=k, replace=False)) if k else run[:0]


def differences(summary, status, ref_summary, ref_status, class_basis="burial_volume") -> dict:
    """How the results (``summary``, ``status``) of some drops differ from their reference
    results: p95 and max of the relative penetration change (percent; :data:`FLOOR_M`,
    :data:`SCALE_M`), the position of the largest (``argmax``: -1 when no penetration changed
    beyond :data:`FLOOR_M`, so that no drop is named), and the burial-class and status changes."""
    pen, pen_ref = summary[:, layout.S_PENETRATION], ref_summary[:, layout.S_PENETRATION]
    both = np.isfinite(pen) & np.isfinite(pen_ref)
    d = np.abs(pen - pen_ref)
    rel = np.where(both & (d > FLOOR_M), d / np.maximum(np.abs(pen_ref), SCALE_M), 0.0)
    column = layout.SUMMARY_INDEX[class_basis]
    used = np.isin(status, st.IN_STATISTICS) & np.isin(ref_status, st.IN_STATISTICS)
    cls_changed = used & (burial_class(summary[:, column]) != burial_class(ref_summary[:, column]))
    return {
        "p95": 100.0 * float(np.percentile(rel[both], 95)) if both.any() else float("nan"),
        "max": 100.0 * float(rel.max()) if both.any() else float("nan"),
        "argmax": int(np.argmax(rel)) if both.any() and rel.max() > 0.0 else -1,
        "class_changes": int(cls_changed.sum()),
        "status_changes": int(np.sum(np.asarray(status) != np.asarray(ref_status))),
    }


def self_check(spec, chunks, chunk_inputs, progress=None) -> dict:
    """The ``numerical_check_*`` global attributes of mine ensemble ``spec`` from its chunk
    results in drop order: the subsample re-run on the reference path and its differences,
    or why it was skipped. ``chunk_inputs(spec, start, stop)`` packs drops' parameters
    (:func:`mineburial.systems.mine.ensemble.chunk_inputs`). ``progress``: None, or the class of the
    run's rate-limited progress lines (:class:`~mineburial.ensembles.runner.Progress`, handed
    down so that this module does not import the runner) for lines while the drops are re-run
    (:func:`_rerun`)."""
    size = check_size(spec.accuracy_check, spec.n)
    if size == 0:
        return {"numerical_check": "skipped (ensemble.accuracy_check = 0)"}
    summary = np.concatenate([r["summary"] for r in chunks])
    status = np.concatenate([r["status"] for r in chunks])
    idx = choose_drops(spec.seed, status, size)
    if idx.size == 0:
        return {"numerical_check": "skipped (no drop was run: every drop's inputs were invalid)"}
    t0 = time.monotonic()
    P = np.concatenate([chunk_inputs(spec, i, i + 1)[0] for i in idx.tolist()])
    P = reference_params(P, sediment_bank=spec.sediment_bank)
    # the drops that took the most steps in the run first, so that a long one does not start last
    ref_summary, ref_status = _rerun(P, spec, progress, cost=summary[idx, layout.S_N_STEPS])
    wall = time.monotonic() - t0
    ended = np.isin(status[idx], st.IN_STATISTICS) & np.isin(ref_status, st.IN_STATISTICS)
    if not ended.any():  # e.g. every drop timed out: nothing measured, so no pass (issue 35)
        return _inconclusive(idx, status[idx], ref_status, wall)
    diff = differences(summary[idx], status[idx], ref_summary, ref_status, spec.class_basis)
    worst = int(idx[diff["argmax"]]) if diff["argmax"] >= 0 else -1
    exceeded = diff["p95"] > TARGETS[0] or diff["max"] > TARGETS[1]  # NaN (no penetration): False
    return {
        "numerical_check": "done",
        "numerical_check_reference": REFERENCE_TEXT,
        "numerical_check_drops": np.int64(idx.size),
        "numerical_check_drop_indices": idx.astype(np.int64),
        "numerical_check_detectable_failure_percent": round(100.0 * detectable_rate(idx.size), 3),
        "numerical_check_penetration_p95_percent": diff["p95"],
        "numerical_check_penetration_max_percent": diff["max"],
        "numerical_check_penetration_max_drop": np.int64(worst),
        "numerical_check_class_changes": np.int64(diff["class_changes"]),
        "numerical_check_status_changes": np.int64(diff["status_changes"]),
        "numerical_check_targets_percent": np.array(TARGETS),
        "numerical_check_exceeds_targets": np.int8(exceeded),
        "numerical_check_wall_time_s": round(wall, 3),
    }


def _rerun(P, spec, progress, cost=None):
    """``(summary, status)`` of the drops whose reference parameters are the rows of ``P``, one
    drop a block of the run's thread pool (:func:`~mineburial.ensembles.threads.run_blocks`: a
    thread takes the next drop when done with its last; blocks of two drops, or a batch a
    thread, left a thread idle while the other ran a long drop, and the progress blocks of
    ``threads`` drops each ran on one thread: the 8 drops serially). With ``progress`` (the
    run's progress-line class, ``progress(total, unit=...)``, handed down by the runner, which
    imports this module's callers) a line when one is due as the drops finish. ``cost``: an estimate
    per drop (the run's own steps); the costliest start first (NaN last), so that the threads end
    together. Each drop writes only its own row, so the results do not depend on the threads, the
    order or the schedule."""
    n = P.shape[0]
    params = np.ascontiguousarray(P, dtype=np.float64)
    sediment_bank = np.ascontiguousarray(spec.sediment_bank, dtype=np.float64)
    current_bank = np.ascontiguousarray(spec.current_bank, dtype=np.float64)
    summary = np.empty((n, layout.N_SUMMARY))
    codes = np.empty(n, dtype=np.int8)
    valid = np.ones(n, dtype=np.uint8)
    paths = with_long_tables(reference_paths(params), params, sediment_bank)
    bar = progress(n, unit="self-check drops") if progress else None
    if bar is not None:
        bar.update(0)
    lock = threading.Lock()
    done = [0]
    order = np.arange(n)
    if cost is not None:
        key = np.where(np.isfinite(cost), -np.asarray(cost, dtype=np.float64), np.inf)
        order = np.argsort(key, kind="stable")

    def one(start, _stop):  # block k of BLOCK_SIZE items is the k-th drop of ``order``
        i = int(order[start // BLOCK_SIZE])
        batch._run_drops(params, valid, sediment_bank, current_bank, summary, codes, paths, i, i + 1)
        if bar is not None:
            with lock:
                done[0] += 1
                bar.update(done[0], final=done[0] == n)

    run_blocks(n * BLOCK_SIZE, one, numba.get_num_threads())
    return summary, codes


def _inconclusive(idx, status, ref_status, wall: float) -> dict:
    """The attributes of a self-check that measured nothing: none of the drops re-run ended
    at rest or buried (the statuses whose burial is counted) in both runs, e.g. every drop
    timed out. Was reported as done, with no warning: a pass."""
    names = sorted({st.NAMES[int(s)] for s in np.concatenate([status, ref_status])})
    return {
        "numerical_check": (
            f"INCONCLUSIVE: none of the {idx.size} drops re-run ended at rest or buried in both "
            f"runs (statuses: {', '.join(names)}), so the accuracy was not measured; see the "
            "status counts (a longer numerics.t_max?)"
        ),
        "numerical_check_reference": REFERENCE_TEXT,
        "numerical_check_drops": np.int64(idx.size),
        "numerical_check_drop_indices": idx.astype(np.int64),
        "numerical_check_status_changes": np.int64(np.sum(np.asarray(status) != np.asarray(ref_status))),
        "numerical_check_wall_time_s": round(wall, 3),
    }


def _worst_drop(index: int) -> str:
    """The drop named beside the largest change: -1 means no drop changed (docs/notes/output.md)."""
    return f"drop {index}" if index >= 0 else "no drop changed"


def summary_lines(ds) -> list[str]:
    """The printed summary's lines for the self-check recorded in ``ds``'s attributes."""
    a = ds.attrs
    state = a.get("numerical_check")
    if state is None:
        return []
    if state != "done":
        return [f"numerical self-check: {state}"]
    n = int(a["numerical_check_drops"])
    lines = [
        f"numerical self-check ({n} drop{'s' * (n != 1)} against rtol {REFERENCE_RTOL:g} with the reference "
        "quadratures): "
        f"penetration change p95 {float(a['numerical_check_penetration_p95_percent']):.2f} %, "
        f"max {float(a['numerical_check_penetration_max_percent']):.2f} % "
        f"({_worst_drop(int(a['numerical_check_penetration_max_drop']))}), burial class changed on "
        f"{int(a['numerical_check_class_changes'])}, status on {int(a['numerical_check_status_changes'])}; "
        f"{float(a['numerical_check_wall_time_s']):.1f} s"
    ]
    if "numerical_check_detectable_failure_percent" in a:
        lines[0] += (
            f"; {n} drops catch a defect of "
            f"{float(a['numerical_check_detectable_failure_percent']):.3g} % of drops with "
            f"{DETECTION_PROBABILITY:.0%} probability ({drops_needed(0.01)} drops for 1 %)"
        )
    if int(a["numerical_check_exceeds_targets"]):
        lines.append(
            f"WARNING: the numerical error exceeds its targets (p95 <= {TARGETS[0]:g} %, max <= "
            f"{TARGETS[1]:g} % of penetration): tighten numerics.rtol or use "
            "numerics.sediment_quadrature = 'reference' (docs/design.md, 'The numerical self-check')"
        )
    return lines
