"""Where a drop's work goes: counts per phase and the cost of one right-hand side and of each of its terms.

Run:  python benchmarks/profile_phases.py [-n 200] [--scenario FILE] [--callgrind-drops 20] [--no-callgrind]

Two parts, both on the same drops of an ensemble (default: the embedded default ensemble):

1. **Counts** (native, load-independent): each drop runs through an *instrumented copy* of the mine's driver
   (``stepper.py``'s source with a few counting lines inserted, generated into a temporary module; every
   insertion must match the source exactly once, so an edit of the stepper makes this script fail loudly
   rather than count wrongly). It counts, by the phase at the start of the step (air, crossing the water
   surface, water, crossing the seabed, embedded): attempted, accepted, rejected and retaken steps of each
   method, right-hand sides (stages, Jacobian columns, restarts), Jacobian evaluations, event-location
   iterations and rest tests, and samples the states at which the right-hand side was evaluated (every 4th).
   The copy's per-drop summaries are checked bit for bit against ``stepper.run_drop``'s.
2. **Costs**: the right-hand side and each of its terms called in compiled loops over the sampled states of
   each phase (the derivatives' prologue -- rotation, body-frame velocity, extent, the body cut at the
   interfaces -- alone, then with one term added: the term's cost is the difference), the rest test and
   the event functions; in instructions (``valgrind --tool=callgrind``, counts between two marker calls,
   repeatable whatever the host's load) and in wall time (native, best of 3: noise on a loaded host).
   The whole drops are counted too, so the table says how much of the total the counts times the costs
   explain.

Writes the tables to stdout (``benchmarks/results/profile_phases.md`` holds a run).
"""

import argparse
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.dynamics import (
    _added_mass,
    _air_part_loads,
    _buoyancy,
    _immersed_parts,
    _mass_matrix,
    _momentum_rhs,
    _state_rates,
    _water_part_loads,
    _work_rates,
    derivatives,
    drop_body,
    solve6,
)
from mineburial.kernels.mine.geometry import e_down_body
from mineburial.kernels.mine.layout import (
    N_DIAG,
    N_EXT,
    N_WORK,
    P_CROSSFLOW_FACTOR,
    P_CROSSFLOW_MUNK,
    P_DEPTH,
    P_DRAG,
    P_GRAVITY,
    P_J1,
    P_J2,
    P_MASS,
    P_MODEL,
    P_REST_SPEED,
    P_RHO_AIR,
    P_RHO_WATER,
    P_WATER_COLUMN,
    WC_VISCOUS_CROSSFLOW,
)
from mineburial.kernels.mine.overburden import overburden_force
from mineburial.kernels.mine.rest import held_by_sediment
from mineburial.kernels.mine.sediment import pack_law, sediment_tractions
from mineburial.kernels.mine.sediment.laws import LAW_PORE, LAW_REFERENCE_PATHS, drop_bank
from mineburial.kernels.mine.stepper import event_values
from mineburial.kernels.rotation import rotation_matrix

HERE = os.path.dirname(os.path.abspath(__file__))
PHASES = ("air", "surface", "water", "seabed", "embedded")
#: counters in the instrumented work array (per phase at the start of the step)
KINDS = (
    "attempts_dopri5",
    "attempts_ros34pw2",
    "integrator_accepted_dopri5",
    "integrator_accepted_ros34pw2",
    "retaken_at_interface",
    "rhs_dopri5",
    "rhs_ros34pw2",
    "rhs_restart",
    "event_iterations",
    "rest_tests",
    "rhs_by_state_phase",
    "accepted_steps",
)
N_KINDS = len(KINDS)
#: the compiled code's target in the cost runs (numba's cache is keyed on it; valgrind runs AVX2)
CPU_NAME = "haswell"
CPU_FEATURES = (
    "+64bit,+avx,+avx2,+bmi,+bmi2,+cmov,+cx16,+f16c,+fma,+fxsr,+lzcnt,+mmx,+movbe,+popcnt,+sse,+sse2,+sse3,"
    "+sse4.1,+sse4.2,+ssse3,+xsave"
)
CAP = 400  # sampled states per phase and drop
STRIDE = 4  # every STRIDE-th right-hand side of a phase is sampled

HELPERS = f"""

# ---- profiling helpers (benchmarks/profile_phases.py) ----
from mineburial.kernels.mine.dynamics import derivatives as _true_derivatives
from mineburial.kernels.mine.layout import N_WORK as _NW

PROF_MODE = _NW
PROF_PHASE = _NW + 1
PROF_COUNTS = _NW + 2
PROF_NS = PROF_COUNTS + {N_KINDS} * 5
PROF_SAMPLES = PROF_NS + 5
PROF_SIZE = PROF_SAMPLES + 5 * {CAP} * N_EXT


@small_kernel
def _prof_count(work, kind):
    work[PROF_COUNTS + kind * 5 + int(work[PROF_PHASE])] += 1.0


@small_kernel
def derivatives(y, p, law, sed_bank, cur_bank, work, dy, diag):
    phase = _true_derivatives(y, p, law, sed_bank, cur_bank, work, dy, diag)
    _prof_count(work, 5 + int(work[PROF_MODE]))
    i = PROF_COUNTS + 10 * 5 + phase
    work[i] += 1.0
    c = int(work[PROF_NS + phase])
    if int(work[i]) % {STRIDE} == 1 and c < {CAP}:
        base = PROF_SAMPLES + (phase * {CAP} + c) * N_EXT
        for j in range(N_EXT):
            work[base + j] = y[j]
        work[PROF_NS + phase] += 1.0
    return phase


@small_kernel
def _prof_attempt(work, method, g0):
    if g0[0] >= 0.0:
        ph = 0
    elif g0[1] > 0.0:
        ph = 1
    elif g0[2] >= 0.0:
        ph = 2
    elif g0[3] > 0.0:
        ph = 3
    else:
        ph = 4
    work[PROF_PHASE] = ph
    work[PROF_MODE] = 1.0 if method == ROS34PW2 else 0.0
    _prof_count(work, int(work[PROF_MODE]))


@small_kernel
def _prof_rest(work, g1):
    if g1[2] < 0.0 and g1[EVENT_REST] <= 0.0:
        _prof_count(work, 9)
"""

#: (what, replacement): each must occur exactly once in stepper.py
EDITS = (
    (
        "from mineburial.kernels.mine.dynamics import derivatives, drop_body\n",
        "from mineburial.kernels.mine.dynamics import drop_body\n",
    ),
    ('MINE = System("mine",', 'MINE = System("mine_profiled",'),
    (
        "    p, e, gtmp = args\n    event_values(y, p, gtmp)\n",
        "    p, e, gtmp, work = args\n    _prof_count(work, 8)\n    event_values(y, p, gtmp)\n",
    ),
    (
        "def _first_event(r, t, h, g0, g1, p, gtmp, ytmp):",
        "def _first_event(r, t, h, g0, g1, p, gtmp, ytmp, work):",
    ),
    ("(p, e, gtmp), ytmp, EVENT_TOLERANCE", "(p, e, gtmp, work), ytmp, EVENT_TOLERANCE"),
    (
        "theta, first = _first_event(r, t, h, g0, g1, p, gtmp, ytmp)",
        "theta, first = _first_event(r, t, h, g0, g1, p, gtmp, ytmp, work)",
    ),
    (
        "            if h < 0.0:\n                status = st.NUMERICAL_FAILURE\n",
        "            if h < 0.0:\n                status = st.NUMERICAL_FAILURE\n"
        "            else:\n                _prof_attempt(ctx.args[4], method, ctx.g0)\n",
    ),
    (
        "    accepted_before = True\n    event_values(ynew, p, g1)\n",
        "    accepted_before = True\n    _prof_count(work, 2 + int(work[PROF_MODE]))\n"
        "    event_values(ynew, p, g1)\n",
    ),
    ("        redo += 1\n", "        redo += 1\n        _prof_count(work, 4)\n"),
    ("        n_steps += 1\n", "        n_steps += 1\n        _prof_count(work, 11)\n"),
    (
        "            derivatives(y, p, law, sed_bank, cur_bank, work, k[0], diag)\n"
        "            accepted_before = False\n",
        "            work[PROF_MODE] = 2.0\n"
        "            derivatives(y, p, law, sed_bank, cur_bank, work, k[0], diag)\n"
        "            accepted_before = False\n",
    ),
    (
        "        status, max_decel = _end_test(\n",
        "        _prof_rest(work, g1)\n        status, max_decel = _end_test(\n",
    ),
    (
        "def run_drop(p, sed_bank, cur_bank, summary, traj, record_dt, reference_paths):",
        "def run_drop(p, sed_bank, cur_bank, summary, traj, record_dt, reference_paths, prof_work):",
    ),
    (
        "= _work_arrays()\n",
        "= _work_arrays()\n    work = prof_work\n    work[PROF_MODE] = 2.0\n",
    ),
)


def profiled_stepper(folder):
    """Import the instrumented copy of the stepper (written to ``folder``)."""
    from mineburial.kernels.mine import stepper

    src = open(stepper.__file__).read()
    for old, new in EDITS:
        n = src.count(old)
        if n != 1:
            raise SystemExit(f"profile_phases: the stepper changed: {old[:60]!r} occurs {n} times, not once")
        src = src.replace(old, new)
    path = os.path.join(folder, "_profiled_stepper.py")
    with open(path, "w") as fh:
        fh.write(src + HELPERS)
    sys.path.insert(0, folder)
    import _profiled_stepper

    return _profiled_stepper


def load(scenario, n):
    from mineburial.ensembles.engine import load_ensemble
    from mineburial.systems.mine.ensemble import chunk_inputs

    spec = load_ensemble(scenario)
    P, valid, _ = chunk_inputs(spec, 0, n)
    return (
        P[valid.astype(bool)],
        np.ascontiguousarray(spec.sediment_bank),
        np.ascontiguousarray(spec.current_bank),
    )


def count_drops(mod, P, sb, cb):
    """Counts (drops, kinds, phases) and sampled states (list of (drop, phase, state))."""
    from mineburial.kernels.mine.layout import N_SUMMARY
    from mineburial.kernels.mine.stepper import run_drop

    counts = np.zeros((len(P), N_KINDS, 5))
    samples = []
    mismatched = 0
    for d, p in enumerate(P):
        work = np.zeros(mod.PROF_SIZE)
        s1 = np.empty(N_SUMMARY)
        s0 = np.empty(N_SUMMARY)
        c1, _ = mod.run_drop(p, sb, cb, s1, None, 1.0, None, work)
        c0, _ = run_drop(p, sb, cb, s0, None, 1.0, None)
        if c0 != c1 or not np.array_equal(s0, s1, equal_nan=True):
            mismatched += 1
        counts[d] = work[mod.PROF_COUNTS : mod.PROF_NS].reshape(N_KINDS, 5)
        for ph in range(5):
            for c in range(int(work[mod.PROF_NS + ph])):
                base = mod.PROF_SAMPLES + (ph * CAP + c) * 15
                samples.append((d, ph, work[base : base + 15].copy()))
    return counts, samples, mismatched


# ---- the cost of one right-hand side and of its terms ----------------------------------------------
TERMS = (
    "call_overhead",  # the loop over the states alone: the Python call, drop_bank, pack_law
    "prologue",  # rotation, body-frame velocity, volume, extent, cut at the interfaces, e_down
    "buoyancy",
    "water_fluid",  # equivalent water part, current, strip drag (exact crossflow integrals), lift, roll
    "air_fluid",
    "sediment_tractions",  # the surface rule (fast) and the pore law
    "pore_law",
    "overburden",
    "assembly",  # added mass, mass matrix, Kirchhoff terms, 6x6 Cholesky, state and work rates
    "derivatives",  # the whole right-hand side
    "rest_test",  # held_by_sediment (rest.py)
    "event_values",
)


@kernel
def term_loop(which, p0, sb0, cb, states, reps):
    p, sb = drop_bank(p0, sb0)
    body = drop_body(p)
    law = pack_law(p, bodies.reference_lengths(body)[0], None)
    R, L = bodies.strip_section(body)
    crossflow_model = int(p[P_WATER_COLUMN]) == WC_VISCOUS_CROSSFLOW
    eta = bodies.crossflow_efficiency(body) if crossflow_model else 1.0
    model = (int(p[P_MODEL]) == 1, R, L, int(p[P_DRAG]), eta, p[P_CROSSFLOW_FACTOR])
    work = np.empty(N_WORK)
    dy = np.empty(N_EXT)
    diag = np.zeros(N_DIAG)
    g = np.empty(5)
    depth = p[P_DEPTH]
    acc = 0.0
    for _ in range(reps):
        for i in range(states.shape[0]):
            y = states[i]
            if which == 0:
                acc += y[0]
                continue
            if which == 9:
                acc += derivatives(y, p, law, sb, cb, work, dy, diag) + dy[5]
                continue
            if which == 10:
                acc += held_by_sediment(y, p, law, sb, p[P_REST_SPEED])
                continue
            if which == 11:
                event_values(y, p, g)
                acc += g[4]
                continue
            qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
            w = (y[10], y[11], y[12])
            r = rotation_matrix(y[6] / qn, y[7] / qn, y[8] / qn, y[9] / qn)
            a_z = r[6]
            kb = (r[6], r[7], r[8])
            u = (
                r[0] * y[3] + r[3] * y[4] + r[6] * y[5],
                r[1] * y[3] + r[4] * y[4] + r[7] * y[5],
                r[2] * y[3] + r[5] * y[4] + r[8] * y[5],
            )
            z = y[2]
            v_total, x_total = bodies.volume(body)
            z_lo, z_hi = bodies.extent(body, a_z, z)
            parts = _immersed_parts(body, a_z, z, depth, z_lo, v_total)
            _, dn2, dn3 = e_down_body(kb[0], kb[1], kb[2])
            acc += parts[0] + dn2 + u[0]
            loads = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            if which == 2:
                vs, xs, es, vb, _, va, _ = parts
                loads = _buoyancy(
                    p[P_RHO_WATER], p[P_RHO_AIR], p[P_GRAVITY], vs, xs, es, va, v_total, x_total,
                    dn2, dn3, kb[0], kb[1], kb[2],
                )  # fmt: skip
            elif which == 3:
                loads, wa, wb, cur = _water_part_loads(
                    body, p, cb, model, r, z, a_z, u, w, parts, v_total, loads
                )
                acc += wb + cur[0]
            elif which == 4:
                loads, aa, ab = _air_part_loads(body, p, model, u, w, parts, v_total, x_total, loads)
                acc += ab
            elif which == 5 and z_lo < -depth:
                f = sediment_tractions(
                    body, r, (y[0], y[1], y[2]), (y[3], y[4], y[5]), (y[10], y[11], y[12]), -depth, law, sb
                )
                acc += f[0] + f[2] + f[4] + f[6]
            elif which == 6 and z_lo < -depth and law[LAW_PORE]:
                d0 = -depth - z
                zeta_tip = d0 - bodies.lowest_offset(body, kb[0], kb[1], kb[2])
                if zeta_tip > 0.0:
                    f = bodies.pore(
                        body, kb[0], kb[1], kb[2], d0, zeta_tip, y[5], law[:LAW_REFERENCE_PATHS], sb
                    )
                    acc += f[0] + f[3]
            elif which == 7 and z_lo < -depth:
                f = overburden_force(body, a_z, z, -depth, z_lo, p[P_RHO_WATER], p[P_GRAVITY], p, sb, law)
                acc += f[0] + f[1]
            elif which == 8:
                added = _added_mass(body, p, model, crossflow_model, 0.0, 0.5 * L, -0.5 * L, 0.0)
                mass = work[0:36]
                rhs = work[36:42]
                dnu = work[42:48]
                _mass_matrix(mass, p[P_MASS], p[P_J1], p[P_J2], added, 0.0, kb)
                crb = _momentum_rhs(
                    rhs, loads, p[P_MASS], p[P_J1], p[P_J2], model, crossflow_model, p[P_CROSSFLOW_MUNK],
                    added, u, w, (0.0, 0.0, 0.0),
                )  # fmt: skip
                solve6(mass, rhs, dnu)
                _state_rates(dy, y, r, (y[6] / qn, y[7] / qn, y[8] / qn, y[9] / qn), u, w, dnu)
                ft = _work_rates(
                    dy, r, p[P_MASS], p[P_GRAVITY], p[P_J1], p[P_J2], kb, u, w, dnu, crb,
                    (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                )  # fmt: skip
                acc += ft[0] + dy[5]
            acc += loads[0] + loads[4]
    return acc


def term_runs(P, sb, cb, samples, reps, max_states):
    """(phase, term, drops' rows, states) of each measurement: up to ``max_states`` sampled states of each
    phase, spread over the drops, grouped by drop."""
    rng = np.random.default_rng(1)
    runs = []
    for ph in range(5):
        idx = [i for i, s in enumerate(samples) if s[1] == ph]
        if not idx:
            continue
        if len(idx) > max_states:
            idx = sorted(rng.choice(idx, max_states, replace=False).tolist())
        groups = {}
        for i in idx:
            groups.setdefault(samples[i][0], []).append(samples[i][2])
        batches = [(d, np.ascontiguousarray(np.array(v))) for d, v in sorted(groups.items())]
        for term in range(len(TERMS)):
            if ph < 3 and TERMS[term] in ("sediment_tractions", "pore_law", "overburden", "rest_test"):
                continue
            runs.append((ph, term, batches, len(idx)))
    return runs


def run_one(term_loop, P, sb, cb, run, reps):
    ph, term, batches, n = run
    acc = 0.0
    for d, states in batches:
        acc += term_loop(term, P[d], sb, cb, states, reps)
    return acc


def drops_total(P, sb, cb, n):
    from mineburial.kernels.mine.layout import N_SUMMARY
    from mineburial.kernels.mine.stepper import run_drop

    s = np.empty(N_SUMMARY)
    for p in P[:n]:
        run_drop(p, sb, cb, s, None, 1.0, None)


def worker(args):
    """Measure every run: natively by wall time, or (``--callgrind-worker``) between marker calls."""
    P, sb, cb = load(args.scenario, args.n)
    with open(args.samples, "rb") as fh:
        data = np.load(fh, allow_pickle=True)
        samples = list(data["samples"])
    runs = term_runs(P, sb, cb, samples, args.reps, args.max_states)
    for run in runs:  # compiled or loaded before anything is measured
        run_one(term_loop, P, sb, cb, (run[0], run[1], run[2][:1], 1), 1)
    drops_total(P, sb, cb, 1)
    out = []
    marked = args.callgrind_worker
    if marked:  # a first dump, discarded: it holds what ran before the first zeroing
        os.getpgrp()
        os.getsid(0)
    for run in runs:
        best = np.inf
        for _ in range(1 if marked else 3):
            if marked:
                os.getpgrp()  # callgrind: --zero-before=getpgrp
            t = time.perf_counter()
            run_one(term_loop, P, sb, cb, run, args.reps)
            best = min(best, time.perf_counter() - t)
            if marked:
                os.getsid(0)  # callgrind: --dump-before=getsid
        out.append((run[0], TERMS[run[1]], run[3] * args.reps, best))
    nd = args.callgrind_drops
    best = np.inf
    for _ in range(1 if marked else 3):
        if marked:
            os.getpgrp()
        t = time.perf_counter()
        drops_total(P, sb, cb, nd)
        best = min(best, time.perf_counter() - t)
        if marked:
            os.getsid(0)
    out.append((-1, "drops", nd, best))
    with open(args.result, "w") as fh:
        json.dump(out, fh)


def callgrind_counts(folder, n_marks):
    """Instructions (Ir) of each dump of a callgrind run, in order."""
    dumps = []
    for f in glob.glob(os.path.join(folder, "cg.out.*")):
        m = re.search(r"cg\.out\.\d+\.(\d+)$", f)
        if m:
            dumps.append((int(m.group(1)), f))
    dumps = [f for _, f in sorted(dumps)]
    irs = []
    for f in dumps:
        text = open(f).read()
        m = re.search(r"^(?:summary|totals):\s+(\d+)", text, re.M)
        reason = re.search(r"^desc: Trigger: (.*)$", text, re.M)
        if reason and "getsid" in reason.group(1):
            irs.append(int(m.group(1)))
    return irs[1 : n_marks + 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=200, help="drops counted")
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--callgrind-drops", type=int, default=20, help="drops run whole under callgrind")
    ap.add_argument("--reps", type=int, default=1, help="passes over the sampled states per cost")
    ap.add_argument("--max-states", type=int, default=300, help="sampled states per phase in the costs")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--keep", help="folder for the counts and samples (reused when present)")
    ap.add_argument("--reuse-costs", action="store_true", help="report the costs measured before in --keep")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--callgrind-worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--samples", help=argparse.SUPPRESS)
    ap.add_argument("--result", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker or args.callgrind_worker:
        return worker(args)

    folder = args.keep or tempfile.mkdtemp(prefix="mb-profile-")
    os.makedirs(folder, exist_ok=True)
    samples_path = os.path.join(folder, "samples.npz")
    P, sb, cb = load(args.scenario, args.n)
    if args.keep and os.path.exists(samples_path):
        with open(samples_path, "rb") as fh:
            counts = np.load(fh, allow_pickle=True)["counts"]
        print(
            f"scenario: {args.scenario or 'embedded default'}; "
            f"counts of {len(counts)} drops from {samples_path}"
        )
    else:
        mod = profiled_stepper(folder)
        t = time.perf_counter()
        counts, samples, mismatched = count_drops(mod, P, sb, cb)
        same = "bit-identical to run_drop" if mismatched == 0 else f"DIFFER on {mismatched} drops"
        print(
            f"scenario: {args.scenario or 'embedded default'}; {len(P)} drops counted "
            f"({time.perf_counter() - t:.0f} s with the compile); instrumented driver's summaries {same}"
        )
        arr = np.empty(len(samples), dtype=object)
        for i, smp in enumerate(samples):
            arr[i] = smp
        np.savez(samples_path, samples=arr, counts=counts)

    base = [
        sys.executable,
        os.path.abspath(__file__),
        "-n",
        str(args.n),
        "--samples",
        samples_path,
        "--reps",
        str(args.reps),
        "--max-states",
        str(args.max_states),
        "--callgrind-drops",
        str(args.callgrind_drops),
    ]
    if args.scenario:
        base += ["--scenario", args.scenario]
    native = os.path.join(folder, "native.json")
    # one CPU target for the native and the callgrind runs: valgrind's CPU reports other features than the
    # host, so numba would miss its cache (keyed on the target) and compile everything under valgrind
    env = dict(os.environ, NUMBA_NUM_THREADS="1", NUMBA_CPU_NAME=CPU_NAME, NUMBA_CPU_FEATURES=CPU_FEATURES)
    reuse = args.reuse_costs and os.path.exists(native)
    if not reuse:
        subprocess.run([*base, "--worker", "--result", native], check=True, env=env)
    wall = json.load(open(native))
    irs = None
    cg = os.path.join(folder, "cg")
    if reuse and os.path.isdir(cg):
        irs = callgrind_counts(cg, len(wall))
        if len(irs) != len(wall):
            irs = None
    elif not args.no_callgrind and shutil.which("valgrind"):
        os.makedirs(cg)
        cgres = os.path.join(folder, "cg.json")
        t = time.perf_counter()
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                f"--callgrind-out-file={cg}/cg.out.%p",
                "--zero-before=getpgrp",
                "--dump-before=getsid",
                "--dump-instr=no",
                "--compress-strings=no",
                *base,
                "--callgrind-worker",
                "--result",
                cgres,
            ],
            check=True,
            env=env,
            stderr=subprocess.DEVNULL,
        )
        irs = callgrind_counts(cg, len(wall))
        print(f"callgrind run: {time.perf_counter() - t:.0f} s wall; {len(irs)} of {len(wall)} marks read")
        if len(irs) != len(wall):
            irs = None
    report(counts, wall, irs, args)
    if not args.keep:
        shutil.rmtree(folder, ignore_errors=True)


def report(counts, wall, irs, args):
    tot = counts.sum(axis=0)
    K = {k: i for i, k in enumerate(KINDS)}
    nd = counts.shape[0]
    print(f"\n### Counts per drop (mean over {nd} drops), by the phase at the start of the step\n")
    print(
        "| phase | attempts dopri5 | attempts ros34pw2 | accepted | rejected | retaken at an interface "
        "| rhs | of which Jacobian columns | Jacobians | event iterations | rest tests |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for ph in range(5):
        att = tot[K["attempts_dopri5"], ph] + tot[K["attempts_ros34pw2"], ph]
        ok = tot[K["integrator_accepted_dopri5"], ph] + tot[K["integrator_accepted_ros34pw2"], ph]
        redo = tot[K["retaken_at_interface"], ph]
        rhs = tot[K["rhs_dopri5"], ph] + tot[K["rhs_ros34pw2"], ph] + tot[K["rhs_restart"], ph]
        # a ros34pw2 attempt: 3 stage rhs, +1 at the end when accepted, +6 per Jacobian
        jac = (
            tot[K["rhs_ros34pw2"], ph]
            - 3 * tot[K["attempts_ros34pw2"], ph]
            - tot[K["integrator_accepted_ros34pw2"], ph]
        ) / 6
        print(
            f"| {PHASES[ph]} | {tot[K['attempts_dopri5'], ph] / nd:.1f} "
            f"| {tot[K['attempts_ros34pw2'], ph] / nd:.1f} | {tot[K['accepted_steps'], ph] / nd:.1f} "
            f"| {(att - ok) / nd:.1f} | {redo / nd:.1f} | {rhs / nd:.1f} "
            f"| {6 * jac / nd:.1f} | {jac / nd:.2f} | {tot[K['event_iterations'], ph] / nd:.1f} "
            f"| {tot[K['rest_tests'], ph] / nd:.1f} |"
        )
    print(
        "\nright-hand sides by the phase of the evaluated state, per drop: "
        + ", ".join(f"{PHASES[ph]} {tot[K['rhs_by_state_phase'], ph] / nd:.1f}" for ph in range(5))
    )

    # costs
    per = {}
    for i, (ph, term, n, sec) in enumerate(wall):
        per[(ph, term)] = (n, sec, irs[i] if irs else None)
    print(
        f"\n### Cost of one call, by the phase of the state (wall: native best of 3, noisy under load"
        f"{'; Ir: callgrind instructions' if irs else ''})\n"
    )
    print("| phase | states | " + " | ".join(TERMS) + " |")
    print("|---|---|" + "---|" * len(TERMS))
    for ph in range(5):
        cells = []
        nstates = None
        for term in TERMS:
            v = per.get((ph, term))
            if v is None:
                cells.append("-")
                continue
            n, sec, ir = v
            nstates = n
            if term == "call_overhead":
                base = (n, 0.0, 0)
            elif term in ("prologue", "derivatives", "rest_test", "event_values"):
                base = per[(ph, "call_overhead")]
            else:
                base = per[(ph, "prologue")]
            us = 1e6 * (sec - base[1]) / n
            if ir is not None:
                ins = (ir - base[2]) / n
                cells.append(f"{ins:,.0f} Ir / {us:.2f} µs")
            else:
                cells.append(f"{us:.2f} µs")
        if nstates is not None:
            print(f"| {PHASES[ph]} | {nstates} | " + " | ".join(cells) + " |")
    print(
        "\n(each term: the prologue with the term, less the prologue alone; `prologue`, `derivatives`, "
        "`rest_test`, `event_values`: less the call overhead)"
    )

    # the sum check on the callgrind drops
    nd_cg = args.callgrind_drops
    sub = counts[:nd_cg].sum(axis=0)
    n_drops, sec_drops, ir_drops = per[(-1, "drops")]
    print(f"\n### Does counts x cost add up? ({nd_cg} drops, the same drops both ways)\n")
    rows = []
    use_ir = ir_drops is not None
    unit = "Ir" if use_ir else "µs"
    scale = 1.0 if use_ir else 1e6
    explained = 0.0
    for ph in range(5):
        v = per.get((ph, "derivatives"))
        if v is None:
            continue
        o = per[(ph, "call_overhead")]
        c = (v[2] - o[2]) / v[0] if use_ir else (v[1] - o[1]) / v[0]
        nrhs = sub[K["rhs_by_state_phase"], ph]
        rows.append((f"right-hand sides, {PHASES[ph]}", nrhs, c))
    ev = [per[(ph, "event_values")] for ph in range(5) if (ph, "event_values") in per]
    ov = [per[(ph, "call_overhead")] for ph in range(5) if (ph, "event_values") in per]
    evc = np.mean([((v[2] - o[2]) if use_ir else (v[1] - o[1])) / v[0] for v, o in zip(ev, ov)])
    nev = sub[K["event_iterations"]].sum() + sub[K["accepted_steps"]].sum()
    rows.append(("event functions (iterations + one per accepted step)", nev, evc))
    rt = [(per[(ph, "rest_test")], per[(ph, "call_overhead")]) for ph in (3, 4) if (ph, "rest_test") in per]
    if rt:
        rtc = np.mean([((v[2] - o[2]) if use_ir else (v[1] - o[1])) / v[0] for v, o in rt])
        rows.append(("rest tests (held_by_sediment)", sub[K["rest_tests"]].sum(), rtc))
    total = ir_drops if use_ir else sec_drops
    print(f"| item | count | cost per call ({unit}) | product | share of the measured total |")
    print("|---|---|---|---|---|")
    for name, n, c in rows:
        explained += n * c
        print(
            f"| {name} | {n:,.0f} | {scale * c:,.2f} | {scale * n * c:,.0f} | {100 * n * c / total:.1f} % |"
        )
    print(f"| **sum** | | | {scale * explained:,.0f} | **{100 * explained / total:.1f} %** |")
    print(f"| measured: {nd_cg} whole drops (`run_drop`) | | | {scale * total:,.0f} | 100 % |")
    print(
        f"\nthe rest ({100 - 100 * explained / total:.1f} %): the integrators' algebra (stage states, error "
        "norm, W factor and solves, dense output), event bookkeeping, per-drop set-up (profile bank, law)"
    )
    print(
        f"native wall for the {nd_cg} drops: {sec_drops:.3f} s ({nd_cg / sec_drops:.0f} drops/s, loaded host)"
    )


if __name__ == "__main__":
    main()
