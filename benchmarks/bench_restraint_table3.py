"""Seed 004 Table 3: the stopping time of the 19 cases of Table 2, computed and compared.

Run:  python benchmarks/bench_restraint_table3.py [--cases 1,2,3] [--set FIELD=VALUE ...] [--out FILE]
      python benchmarks/bench_restraint_table3.py --drag-forms [--cases ...] [--out FILE]

``--drag-forms`` runs every case under the four combinations of the two drag-form model
choices (``water.tangential_drag_form`` = diameter / perimeter, ``ship.resistance_form`` =
ittc / printed; docs/restraint.md section 6) and writes one table of all four to
benchmarks/results/restraint_table3_drag_forms.txt.

``--set`` changes a field of every case (a sensitivity, e.g. ``--set ship.resistance_form=ittc``;
the committed table is the run without it).

Each case of Table 2 (``mineburial example restraint_caseN``; every value the seed does
not print is an assumption stated in the case file and in docs/restraint.md, chosen
before any result was seen) is run to the instant the ship's surge speed first reaches
zero. Written to benchmarks/results/restraint_table3.txt: case, computed stopping time,
seed 004's Table 3 value, relative difference, status, energy-balance closure (max
|E(t) - E(0)| over the initial kinetic energy, E = kinetic + potential + dissipated,
eqs. (63)-(69)), and
the trends of seed 004 §4.3 (friction, anchor mass, ship speed, ship mass, current): the
sign and the order of each group's change against case 1, computed and printed.

When case 1 is run and ``numerics.solver`` is not overridden, case 1 is run a second time
with ``numerics.solver = "kane"`` (the assembled Kane equations A du/dt = f, solved by
Cholesky) and printed as row ``1k``: the same stopping time as the O(N) recursion.
"""

import argparse
import sys
import time
from pathlib import Path

from _common import machine

TREND_GROUPS = (
    ("seabed friction 0.3 -> 0.5 -> 0.7", (1, 2, 3)),
    ("anchor mass 40 -> 50 -> 60 t", (1, 4, 5)),
    ("chain radius 0.0763 -> 0.0863 -> 0.0970 m", (1, 6, 7)),
    ("cable length 152 -> 172 -> 192 m", (1, 8, 9)),
    ("cable horizontal 148 -> 149 -> 150 m", (1, 10, 11)),
    ("cable vertical 6 -> 8 -> 10 m", (1, 12, 13)),
    ("ship speed 3 -> 4 -> 5 m/s", (1, 14, 15)),
    ("ship mass 500 -> 750 -> 1000 t", (1, 16, 17)),
    ("current 0 -> 1 -> 2 m/s", (1, 18, 19)),
)


def _direction(values):
    d = [b - a for a, b in zip(values[:-1], values[1:])]
    if all(x > 0 for x in d):
        return "rising"
    if all(x < 0 for x in d):
        return "falling"
    return "not monotonic"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default=None, help="comma-separated case numbers (default all 19)")
    ap.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE", help="override a case field")
    ap.add_argument("--out", default=None, help="output file (default results/restraint_table3.txt)")
    ap.add_argument(
        "--drag-forms", action="store_true", help="the four drag-form combinations in one table (section 6)"
    )
    args = ap.parse_args(argv)
    if args.drag_forms:
        return drag_forms(args)
    import tomllib

    overrides = {}
    for item in args.set:
        key, _, value = item.partition("=")
        try:  # a TOML value (number, true/false, quoted string); else the bare text
            overrides[key] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            overrides[key] = value
    default_out = Path(__file__).parent / "results" / "restraint_table3.txt"
    out = Path(args.out) if args.out else (None if overrides else default_out)
    from mineburial import __version__
    from mineburial.systems.restraint import model as R

    numbers = range(1, R.N_CASES + 1) if args.cases is None else [int(c) for c in args.cases.split(",")]
    rows = {}
    lines = []
    header = (
        f"{'case':>4}  {'computed s':>10}  {'Table 3 s':>9}  {'diff %':>7}  {'status':<10}  "
        f"{'energy closure':>14}  {'wall s':>6}  change against case 1"
    )
    print(header, flush=True)
    runs = [(k, k, {}) for k in numbers]
    if 1 in numbers and "numerics.solver" not in overrides:
        runs.insert(list(numbers).index(1) + 1, ("1k", 1, {"numerics.solver": "kane"}))
    first = None
    for label, k, extra in runs:
        case = R.table2_case(k)
        if overrides or extra:
            case = case.replace(**{**overrides, **extra})
        first = first or case
        t0 = time.perf_counter()
        res = R.simulate(case)
        wall = time.perf_counter() - t0
        t_ref = R.TABLE3[k - 1]
        t_stop = res.stopping_time
        diff = "" if t_stop is None else f"{100.0 * (t_stop - t_ref) / t_ref:+7.2f}"
        shown = f"{res.t_end:10.3f}" if t_stop is None else f"{t_stop:10.3f}"
        change = (
            R.TABLE3_CHANGE[k - 1] if not extra else "case 1 by the assembled Kane solve (numerics.solver)"
        )
        line = (
            f"{label:>4}  {shown}  {t_ref:9.3f}  {diff:>7}  {res.status_name:<10}  "
            f"{res.energy_closure():14.2e}  {wall:6.1f}  {change}"
        )
        print(line, flush=True)
        lines.append(line)
        if not extra:
            rows[k] = t_stop
    trend_lines = []
    for label, group in TREND_GROUPS:
        if not all(rows.get(k) is not None for k in group):
            continue
        ours = [rows[k] for k in group]
        seed = [R.TABLE3[k - 1] for k in group]
        d_ours, d_seed = _direction(ours), _direction(seed)
        agree = "same" if d_ours == d_seed else "DIFFERENT"
        trend_lines.append(
            f"{label:<42} computed {d_ours:<13} ({' -> '.join(f'{t:.3f}' for t in ours)}); "
            f"seed {d_seed:<13} ({' -> '.join(f'{t:.3f}' for t in seed)}): {agree}"
        )
    within = [k for k in rows if rows[k] is not None and abs(rows[k] / R.TABLE3[k - 1] - 1.0) <= 0.05]
    text = "\n".join(
        [
            ("SENSITIVITY (fields changed, see below; not the model's Table 3): " if overrides else "")
            + "Seed 004 Table 3: stopping time of the restraining system "
            "(benchmarks/bench_restraint_table3.py)",
            f"mineburial {__version__}; {machine()}",
            f"method {first['numerics.integrator']} (rtol {first['numerics.rtol']:g}, atol "
            f"{first['numerics.atol']:g}, dt {first['numerics.dt']:g} s), solver {first['numerics.solver']}, "
            "stop located on the continuous extension; energy closure = max |E(t) - E(0)| / E^K(0), "
            "E = kinetic + potential + dissipated (eqs. (63)-(69))",
            f"fields changed from the case files: {overrides or 'none'}",
            "",
            header,
            *lines,
            "",
            f"within 5 % of Table 3: {len(within)} of {len(rows)} cases",
            "",
            "Trends of seed 004 §4.3 (direction of the stopping time along each group):",
            *trend_lines,
        ]
    )
    print("\n".join(["", *trend_lines]))
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text + "\n")
        print(f"wrote {out}", file=sys.stderr)


#: the four combinations of the drag-form choices (docs/restraint.md section 6), the default first
DRAG_FORMS = (
    ("d, 1/2 (default)", {"water.tangential_drag_form": "diameter", "ship.resistance_form": "ittc"}),
    ("d, no 1/2", {"water.tangential_drag_form": "diameter", "ship.resistance_form": "printed"}),
    ("pi D, 1/2", {"water.tangential_drag_form": "perimeter", "ship.resistance_form": "ittc"}),
    (
        "pi D, no 1/2 (printed)",
        {"water.tangential_drag_form": "perimeter", "ship.resistance_form": "printed"},
    ),
)


def drag_forms(args):
    """Table 3 under each combination of tangential-drag form and ship-resistance form."""
    from mineburial import __version__
    from mineburial.systems.restraint import model as R

    numbers = range(1, R.N_CASES + 1) if args.cases is None else [int(c) for c in args.cases.split(",")]
    out = (
        Path(args.out) if args.out else Path(__file__).parent / "results" / "restraint_table3_drag_forms.txt"
    )
    t0 = time.perf_counter()
    times = {}
    for label, fields in DRAG_FORMS:
        for k in numbers:
            res = R.simulate(R.table2_case(k).replace(**fields))
            times[label, k] = res.stopping_time if res.status_name == "stopped" else None
            print(f"{label:<24} case {k:2d}: {res.status_name} {res.stopping_time}", flush=True)
    width = 19
    head = f"{'case':>4}  {'Table 3 s':>9}  " + "  ".join(f"{label:>{width}}" for label, _ in DRAG_FORMS)
    lines = [head]
    for k in numbers:
        t_ref = R.TABLE3[k - 1]
        cells = []
        for label, _ in DRAG_FORMS:
            t = times[label, k]
            cells.append(
                f"{'no stop':>{width}}" if t is None else f"{t:9.3f} ({100 * (t / t_ref - 1):+6.2f} %)"
            )
        lines.append(f"{k:>4}  {t_ref:9.3f}  " + "  ".join(f"{c:>{width}}" for c in cells))
    lines.append("")
    for label, _ in DRAG_FORMS:
        d = [100 * (times[label, k] / R.TABLE3[k - 1] - 1) for k in numbers if times[label, k] is not None]
        within = sum(abs(x) <= 5.0 for x in d)
        lines.append(
            f"{label:<24} difference to Table 3 from {min(d):+.2f} to {max(d):+.2f} %, "
            f"largest |difference| {max(abs(x) for x in d):.2f} %, within 5 %: {within} of {len(d)}"
        )
    text = "\n".join(
        [
            "Seed 004 Table 3 under the four drag-form combinations "
            "(python benchmarks/bench_restraint_table3.py --drag-forms)",
            f"mineburial {__version__}; {machine()}; {time.perf_counter() - t0:.0f} s in all",
            "stopping time s (difference to seed 004 Table 3); every other field as in the case files "
            "(dopri5, rtol 1e-7, atol 1e-9)",
            "d = water.tangential_drag_form 'diameter': C_T rho d L v|v|/2, seed 001 eqs. (4), (50); "
            "pi D = 'perimeter': pi rho D L C_F v|v|/2, seed 004 eqs. (44)-(45) as printed",
            "1/2 = ship.resistance_form 'ittc': (C_f + C_sf) rho S_W v|v|/2 (ITTC 1957); "
            "no 1/2 = 'printed': seed 004 eq. (62) as printed",
            "",
            *lines,
        ]
    )
    print(text)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text + "\n")
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
