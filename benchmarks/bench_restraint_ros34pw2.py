"""Seed 004 Table 3 with the Rosenbrock-W step (numerics.integrator = "ros34pw2") beside dopri5.

Run:  python benchmarks/bench_restraint_ros34pw2.py [--cases 1,2,3] [--out FILE]

Each case of Table 2 (``mineburial example restraint_caseN``) is run with ``numerics.integrator = "ros34pw2"``
at its own tolerances (rtol 1e-7, atol 1e-9); one line per case is printed as it finishes. The dopri5
column is read from the committed dopri5 table, benchmarks/results/restraint_table3.txt (same cases, same
tolerances). Written to benchmarks/results/restraint_table3_ros34pw2.txt.
"""

import argparse
import re
import sys
import time
from pathlib import Path

from _common import machine

from mineburial.systems.restraint import model as R

RESULTS = Path(__file__).parent / "results"


def dopri5_column(path=RESULTS / "restraint_table3.txt"):
    """case -> (dopri5 stopping time s, Table 3 s) from the committed dopri5 table."""
    out = {}
    for line in path.read_text().splitlines():
        m = re.match(r"\s*(\d+)\s+([\d.]+)\s+([\d.]+)\s", line)
        if m:
            out[int(m.group(1))] = (float(m.group(2)), float(m.group(3)))
    return out


def run_case(number):
    """(status, stopping time, energy closure, wall s) of case ``number`` with ros34pw2."""
    t0 = time.perf_counter()
    res = R.simulate(R.table2_case(number).replace(**{"numerics.integrator": "ros34pw2"}))
    return res.status_name, res.stopping_time, res.energy_closure(), time.perf_counter() - t0


def write_table(rows, out, command):
    ref = dopri5_column()
    lines = [
        "Seed 004 Table 3 with ROS34PW2 beside dopri5 (benchmarks/bench_restraint_ros34pw2.py)",
        f"command: {command}",
        machine(),
        "ros34pw2 and dopri5 at the cases' tolerances (rtol 1e-7, atol 1e-9); dopri5 column from "
        "benchmarks/results/restraint_table3.txt",
        "",
        "case  dopri5 s    ros34pw2 s    diff ms  Table 3 s  status    energy closure  wall s",
    ]
    for number, (status, t_stop, closure, wall) in sorted(rows.items()):
        d5, t3 = ref[number]
        diff = (t_stop - d5) * 1e3 if t_stop is not None else float("nan")
        lines.append(
            f"{number:4d}  {d5:8.3f}  {t_stop if t_stop is not None else float('nan'):12.6f}  {diff:+8.2f}  "
            f"{t3:9.3f}  {status:8s}  {closure:14.3g}  {wall:6.1f}"
        )
    diffs = [abs(r[1] - ref[n][0]) * 1e3 for n, r in rows.items() if r[1] is not None]
    lines += ["", f"largest |ros34pw2 - dopri5|: {max(diffs):.2f} ms (dopri5 printed to 1 ms)"]
    Path(out).write_text("\n".join(lines) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default=None, help="comma-separated case numbers (default all 19)")
    ap.add_argument("--out", default=RESULTS / "restraint_table3_ros34pw2.txt", help="output file")
    args = ap.parse_args(argv)
    cases = [int(c) for c in args.cases.split(",")] if args.cases else range(1, 20)
    rows = {}
    for number in cases:
        rows[number] = run_case(number)
        status, t_stop, closure, wall = rows[number]
        print(f"{number:3d} {status:18s} {t_stop!r:>22} {closure:.3g} {wall:.1f}s", flush=True)
    write_table(rows, args.out, "python benchmarks/bench_restraint_ros34pw2.py " + " ".join(sys.argv[1:]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
