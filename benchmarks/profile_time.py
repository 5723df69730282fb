"""Where the drops' *time* goes, by compiled function and libm routine: ``perf`` samples (issue 34 item 4).

Run:  python benchmarks/profile_time.py [-n 200] [--reps 4] [--scenario FILE] [--tree DIR] [--top 40]
      [--frequency 4000]

``profile_speed.py`` counts instructions (load-independent, exact); this counts time. The two differ where
the processor waits: a chain of divisions, square roots and libm calls that each need the one before runs
at a fraction of the instructions a cycle that independent arithmetic does. Their ratio says where fewer
instructions would not be faster and where shorter chains would (on main 9b98827: asinh and its log1p are
~2 % of the instructions and ~6.5 % of the time, ``_quartic_roots`` 2.5 % and ~4.5 %, the crossflow series
``_unit_interval_norms`` 1.5 % and ~3.5 %).

The tree's first ``n`` drops run ``--reps`` times on one thread, natively (the host's CPU target and the
tree's own numba cache, filled first), under ``perf record -e cpu-clock`` (a timer, so no hardware
counters are needed: it works in a virtual machine), its events enabled only around the drops
(``--control``). Each sample's address is placed in the compiled functions of ``stepper.run_drop``'s
machine code (``profile_speed.function_ranges``: the compile units of ``kernel``, with what is inlined into
them) or in the shared library perf names (libm's routines). Printed: the share of the samples and the
milliseconds a drop of each. Needs ``perf`` (``linux-perf``) and ``readelf``.
"""

import argparse
import bisect
import collections
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def worker(args):
    """Load the tree's drops, write the compiled functions' ranges, then run the drops ``reps`` times with
    perf's events enabled (control fifo) around them; print the drops and the seconds as JSON."""
    sys.path.insert(0, HERE)
    from profile_speed import Drops, _stash_object_code, function_ranges

    stash = _stash_object_code()  # before the kernels load
    import numba

    numba.set_num_threads(1)
    drops = Drops(args.scenario, args.n)  # compiled or loaded before the samples
    with open(args.ranges, "w") as fh:
        json.dump(function_ranges(drops.run_drop, stash), fh)
    ctl = open(args.ctl, "w") if args.ctl else None
    ack = open(args.ack) if args.ack else None

    def perf_control(cmd):
        if ctl:
            ctl.write(cmd + "\n")
            ctl.flush()
            ack.readline()

    perf_control("enable")
    t = time.perf_counter()
    for _ in range(args.reps):
        for i in range(len(drops)):
            drops.run(i)
    seconds = time.perf_counter() - t
    perf_control("disable")
    print(
        json.dumps(
            {"drops": len(drops) * args.reps, "seconds": seconds, "penetrations": drops.penetrations()}
        )
    )


def attribute(data, ranges):
    """Samples of perf's file ``data`` by function: {name: samples}."""
    ranges = sorted(ranges)
    starts = [r[0] for r in ranges]
    out = subprocess.run(
        ["perf", "script", "-i", data, "-F", "ip,sym,dso"], capture_output=True, text=True, check=True
    ).stdout
    counts = collections.Counter()
    for line in out.splitlines():
        parts = line.split(None, 1)
        if not parts:
            continue
        ip = int(parts[0], 16)
        k = bisect.bisect_right(starts, ip) - 1
        if k >= 0 and ip < ranges[k][0] + ranges[k][1]:
            counts[ranges[k][2]] += 1
            continue
        rest = parts[1] if len(parts) > 1 else ""
        sym, _, dso = rest.rpartition(" (")
        lib = os.path.basename(dso.rstrip(")")) or "?"
        if sym.strip() in ("", "[unknown]"):
            # JIT code outside run_drop's own library (perf's map of the process): numba's runtime (its
            # reference counts), or an older tree's kernels compiled as libraries of their own
            name = "[other compiled code]" if lib.startswith("perf-") else f"[{lib}]"
            counts[name] += 1
        else:
            counts[f"{sym.strip().split('+')[0]} ({lib.split('.so')[0]})"] += 1
    return counts


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=200, help="drops (the ensemble's first n)")
    ap.add_argument("--reps", type=int, default=4, help="times the drops run")
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--tree", default=os.path.dirname(HERE), help="the tree to measure (default: this one)")
    ap.add_argument("--top", type=int, default=40, help="functions listed")
    ap.add_argument("--frequency", type=int, default=4000, help="samples a second")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--ranges", help=argparse.SUPPRESS)
    ap.add_argument("--ctl", help=argparse.SUPPRESS)
    ap.add_argument("--ack", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    for tool in ("perf", "readelf"):
        if shutil.which(tool) is None:
            raise SystemExit(f"profile_time: needs {tool} on PATH")
    tree = os.path.abspath(args.tree)
    env = dict(os.environ, PYTHONPATH=tree, NUMBA_NUM_THREADS="1")
    base = [sys.executable, os.path.abspath(__file__), "--worker", "-n", str(args.n)]
    if args.scenario:
        base += ["--scenario", os.path.abspath(args.scenario)]
    with tempfile.TemporaryDirectory(prefix="mb-time-") as folder:
        ranges = os.path.join(folder, "ranges.json")
        # fill the tree's cache first, outside perf
        subprocess.run(
            [*base, "--reps", "1", "--ranges", ranges], env=env, cwd=tree, check=True, capture_output=True
        )
        ctl, ack, data = (os.path.join(folder, x) for x in ("ctl", "ack", "perf.data"))
        os.mkfifo(ctl)
        os.mkfifo(ack)
        cmd = ["perf", "record", "-q", "-e", "cpu-clock", "-F", str(args.frequency), "-D", "-1"]
        cmd += ["--control", f"fifo:{ctl},{ack}", "-o", data, "--", *base, "--reps", str(args.reps)]
        cmd += ["--ranges", ranges, "--ctl", ctl, "--ack", ack]
        out = subprocess.run(cmd, env=env, cwd=tree, check=True, capture_output=True, text=True).stdout
        run = json.loads(out.strip().splitlines()[-1])
        with open(ranges) as fh:
            counts = attribute(data, [tuple(r) for r in json.load(fh)])
    total = sum(counts.values())
    ms = 1e3 * run["seconds"] / run["drops"]
    print(f"## {tree}, scenario {args.scenario or 'embedded default'}")
    print(
        f"{run['drops']} drops ({args.n} x {args.reps}) in {run['seconds']:.2f} s on one thread: "
        f"{run['drops'] / run['seconds']:.1f} drops/s, {ms:.3f} ms a drop; {total} samples; "
        f"sum of penetrations (last pass) {run['penetrations']:.9f} m\n"
    )
    print("| function | share of the time | ms a drop |\n|---|---|---|")
    for name, n in counts.most_common(args.top):
        print(f"| `{name}` | {100.0 * n / total:.2f} % | {ms * n / total:.4f} |")


if __name__ == "__main__":
    main()
