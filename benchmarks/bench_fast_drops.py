"""Fast drops (issue 9): throughput and accuracy of the default path against the references.

Run:  python benchmarks/bench_fast_drops.py [-n 200] [--families default,air_laid,small_cylinders]
                                             [--paths default,reference] [--work-precision] [--png wp.png]

On the same sampled drops of each scenario family it runs

* ``default``   -- the shipped defaults: ``dopri5_ros34pw2`` (dopri5 in air and water, the
  Rosenbrock-W step in the sediment, rtol 3e-4; impact35: dopri5) and the fast sediment rule;
* ``dopri5``    -- the previous default: dopri5 throughout at rtol 1e-5 (atol 1e-6), fast rule;
* ``reference`` -- the old path: fixed RK4 at dt = 1 ms and the reference quadrature;
* ``truth``     -- fixed RK4 at dt = 0.25 ms and the reference quadrature (the accuracy
  reference the issue names);
* ``converged`` -- dopri5 at rtol 1e-8 (atol 1e-9) with the fast rule: the time integration
  converged (the fast rule is smooth, so a tight tolerance stays affordable; with the
  reference quadrature's adaptive noise it does not). On the small-cylinder family RK4 at
  0.25 ms is not converged: a few drops differ by up to 27 %, and halving its dt twice
  moves them monotonically onto dopri5 (checked with the reference quadrature at rtol
  1e-8 too, within 0.3 %). So errors are reported against both;
* ``fine``      -- with ``--fine``: fixed RK4 at dt = 0.0625 ms (a quarter of the truth's) and
  the reference quadrature, the second reference instead of ``converged``: the truth's own
  method refined, affordable on the small-cylinder family where dopri5 at rtol 1e-8 is not;

and prints drops/s (batch kernel, all threads, compile excluded), the ratio
default/reference, and the accuracy of each path against ``truth`` and against
``converged``: p95 and max of the
penetration difference (relative to max(penetration, 0.5 m), differences below 5 mm count as
0), the share of drops whose burial class
changes, the largest change of a class probability, and the status counts.

``--ladder K`` then takes the K drops of each family where the default path and ``truth``
differ most and runs them through RK4 at 0.25, 0.125, 0.0625 and 0.03125 ms (reference
quadrature), dopri5 at rtol 1e-8 with the fast rule and at rtol 1e-7 with the reference
quadrature, printing each drop's penetration: which answer the references converge to.

``--work-precision`` adds fixed RK4 at several dt, dopri5 and dopri5_ros34pw2 at several tolerances, with
the fast and the reference sediment rules, and writes the table and a PNG of error against
CPU time per drop.

Families: ``default`` (the embedded soft-mud ensemble), ``air_laid``
(benchmarks/scenarios/air_laid_mixed.toml), ``small_cylinders``
(benchmarks/scenarios/small_cylinders_impact35.toml).
"""

import argparse
import pathlib
import time

import numpy as np
from _common import machine

HERE = pathlib.Path(__file__).resolve().parent
FAMILIES = {
    "default": None,
    "air_laid": HERE / "scenarios" / "air_laid_mixed.toml",
    "small_cylinders": HERE / "scenarios" / "small_cylinders_impact35.toml",
}


def variant(P, integrator, quadrature, dt=None, rtol=None):
    from mineburial.kernels.mine import layout as L

    Q = P.copy()
    Q[:, L.P_INTEGRATOR] = L.INTEGRATOR_NAMES.index(integrator)
    Q[:, L.P_SED_QUADRATURE] = L.SEDIMENT_QUADRATURE_NAMES.index(quadrature)
    if dt is not None:
        Q[:, L.P_DT] = dt
    if rtol is not None:
        Q[:, L.P_RTOL] = rtol
        Q[:, L.P_ATOL] = rtol / 10.0
    return Q


def run(spec, P, valid):
    from mineburial.systems.mine.batch import run_batch

    t = time.perf_counter()
    summary, status = run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    return time.perf_counter() - t, summary, status


def compare(summary, status, ref_summary, ref_status):
    from mineburial.kernels.mine import layout as L
    from mineburial.kernels.mine import status as S
    from mineburial.systems.mine.statistics import burial_class

    pen = summary[:, L.S_PENETRATION]
    pen_ref = ref_summary[:, L.S_PENETRATION]
    both = np.isfinite(pen) & np.isfinite(pen_ref)
    d = np.abs(pen - pen_ref)[both]
    rel = np.where(d <= 0.005, 0.0, d / np.maximum(np.abs(pen_ref[both]), 0.5))
    used = np.isin(status, S.IN_STATISTICS)
    used_ref = np.isin(ref_status, S.IN_STATISTICS)
    cls = burial_class(summary[:, L.S_BURIAL_VOLUME])
    cls_ref = burial_class(ref_summary[:, L.S_BURIAL_VOLUME])
    both_used = used & used_ref
    changed = float(np.mean(cls[both_used] != cls_ref[both_used])) if both_used.any() else np.nan
    prob = np.bincount(cls[used].astype(int), minlength=5) / max(used.sum(), 1)
    prob_ref = np.bincount(cls_ref[used_ref].astype(int), minlength=5) / max(used_ref.sum(), 1)
    return (
        100 * np.percentile(rel, 95) if rel.size else np.nan,
        100 * rel.max() if rel.size else np.nan,
        100 * changed,
        float(np.abs(prob - prob_ref).max()),
    )


def ladder(spec, P, valid, summary, truth, k):
    """Penetrations of the k drops where ``summary`` and ``truth`` differ most, under RK4 at
    four steps and dopri5 at two tight tolerances with both sediment rules."""
    from mineburial.kernels.mine import layout as L

    pen, pen_t = summary[:, L.S_PENETRATION], truth[:, L.S_PENETRATION]
    d = np.abs(pen - pen_t)
    rel = np.where(d <= 0.005, 0.0, d / np.maximum(np.abs(pen_t), 0.5))
    idx = np.argsort(-np.nan_to_num(rel), kind="stable")[:k]
    Q, ok = P[idx], valid[idx]
    paths = {"default": Q}
    for dt in (2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5):
        paths[f"rk4 {dt * 1e3:g} ms ref"] = variant(Q, "rk4", "reference", dt=dt)
    paths["dopri5 1e-8 fast"] = variant(Q, "dopri5", "fast", rtol=1e-8)
    paths["dopri5 1e-7 ref"] = variant(Q, "dopri5", "reference", rtol=1e-7)
    pens = {name: run(spec, R, ok)[1][:, L.S_PENETRATION] for name, R in paths.items()}
    print(f"\npenetration (m) of the {k} drops where default and truth differ most:")
    print("drop " + " ".join(f"{name:>18s}" for name in pens))
    for j, i in enumerate(idx):
        print(f"{i:4d} " + " ".join(f"{pens[name][j]:18.4f}" for name in pens))


def counts(status):
    from mineburial.kernels.mine import status as S

    return ", ".join(f"{S.NAMES[k]} {int((status == k).sum())}" for k in np.unique(status))


def _series(name):
    """The method a work-precision point belongs to (points of one method are joined)."""
    if name.startswith("rk4 dt="):
        return "rk4 (" + name.rsplit(" ", 1)[1] + " rule)"
    if name.startswith("dopri5_ros34pw2 rtol="):
        return "dopri5_ros34pw2 (" + name.rsplit(" ", 1)[1] + " rule)"
    if name.startswith("dopri5 rtol="):
        return "dopri5 (" + name.rsplit(" ", 1)[1] + " rule)"
    return name


def plot_work_precision(rows, png):
    """Error (p95 of the penetration difference) against CPU time per drop, one panel per family,
    one line per method through its step sizes or tolerances."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fams = sorted({r[0] for r in rows})
    fig, axes = plt.subplots(1, len(fams), figsize=(5.2 * len(fams), 4.6), squeeze=False)
    styles = {}
    for ax, fam in zip(axes[0], fams):
        series = {}
        for r in rows:
            if r[0] == fam and r[1] not in ("truth", "converged", "fine"):
                series.setdefault(_series(r[1]), []).append((r[3], max(r[4], 1e-3)))
        for name, pts in series.items():
            pts.sort()
            if name not in styles:
                styles[name] = dict(marker="os^vDP*X"[len(styles) % 8], color=f"C{len(styles) % 10}")
            ax.loglog(*zip(*pts), ls="-" if len(pts) > 1 else "none", label=name, **styles[name])
        ax.set_xlabel("CPU time per drop [ms]")
        ax.set_ylabel("p95 penetration error [%]")
        ax.set_title(f"{fam}: error vs RK4 0.25 ms + reference rule\n(< 5 mm drawn at 1e-3 %)", fontsize=9)
        ax.grid(True, which="major", alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    for ax in axes[0][1:]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.14, 1, 1))
    fig.savefig(png, dpi=120)
    print(f"wrote {png}")


def rows_from_table(path):
    """The (family, path, drops/s, ms/drop, p95, max, class, dP) rows of a saved run's table."""
    rows, fam = [], None
    for line in pathlib.Path(path).read_text().splitlines():
        if line.startswith("== "):
            fam = line[3:].split(":")[0]
        elif fam and line and not line.startswith(("path", "#", "speed-up", "machine", "wrote")):
            head, _, _ = line.partition("|")
            parts = head.split()
            try:
                nums = [float(x) for x in parts[-6:]]
            except ValueError:
                continue
            rows.append((fam, " ".join(parts[:-6]), *nums))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=200, help="drops per family")
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--work-precision", action="store_true")
    ap.add_argument(
        "--paths",
        default="default,reference",
        help="paths to time besides the two references (default: default,reference)",
    )
    ap.add_argument("--png", default="work_precision.png")
    ap.add_argument("--plot-from", default=None, help="redraw the PNG from a saved --work-precision table")
    ap.add_argument(
        "--no-converged",
        action="store_true",
        help="skip the dopri5 rtol 1e-8 reference (slow on the small-cylinder family's delta law)",
    )
    ap.add_argument(
        "--fine",
        action="store_true",
        help="second reference: RK4 at 0.0625 ms with the reference quadrature instead of 'converged'",
    )
    ap.add_argument(
        "--ladder",
        type=int,
        default=0,
        metavar="K",
        help="refine RK4 and dopri5 on the K drops where default and truth differ most",
    )
    args = ap.parse_args()
    if args.plot_from:
        plot_work_precision(rows_from_table(args.plot_from), args.png)
        return
    import numba

    from mineburial.ensembles.engine import load_ensemble
    from mineburial.systems.mine.ensemble import chunk_inputs

    print(f"machine: {machine()}; threads: {numba.get_num_threads()}")
    rows = []
    for fam in args.families.split(","):
        spec = load_ensemble(FAMILIES[fam])
        P, valid, _ = chunk_inputs(spec, 0, args.n)
        paths = {
            "default": P,
            "dopri5": variant(P, "dopri5", "fast", rtol=1e-5),
            "reference": variant(P, "rk4", "reference", dt=1e-3),
            "truth": variant(P, "rk4", "reference", dt=2.5e-4),
            "converged": variant(P, "dopri5", "fast", rtol=1e-8),
            "fine": variant(P, "rk4", "reference", dt=6.25e-5),
        }
        second = "fine" if args.fine else "converged"
        keep = set(args.paths.split(",")) | {"truth"}
        if args.fine or not args.no_converged:
            keep.add(second)
        paths = {k: v for k, v in paths.items() if k in keep}
        if args.work_precision:
            for dt in (2e-3, 1e-3, 5e-4):
                paths[f"rk4 dt={dt:g} fast"] = variant(P, "rk4", "fast", dt=dt)
            paths["rk4 dt=0.0005 reference"] = variant(P, "rk4", "reference", dt=5e-4)
            for rtol in (1e-3, 1e-4, 1e-6):
                paths[f"dopri5 rtol={rtol:g} fast"] = variant(P, "dopri5", "fast", rtol=rtol)
            paths["dopri5 rtol=1e-05 reference"] = variant(P, "dopri5", "reference", rtol=1e-5)
            for rtol in (1e-3, 3e-4, 1e-4, 1e-5):
                name = f"dopri5_ros34pw2 rtol={rtol:g} fast"
                paths[name] = variant(P, "dopri5_ros34pw2", "fast", rtol=rtol)
        # compile (or load from the cache) outside the timed runs
        run(spec, P[:1], valid[:1])
        results = {name: run(spec, Q, valid) for name, Q in paths.items()}
        _, ref_s, ref_st = results["truth"]
        _, conv_s, conv_st = results.get(second, (None, None, None))
        second_name = (
            "fine = RK4 0.0625 ms, reference quadrature"
            if args.fine
            else "converged = dopri5 1e-8 with the fast rule"
        )
        print(f"\n== {fam}: {args.n} drops   (errors: vs truth = RK4 0.25 ms | vs {second_name})")
        print(
            f"{'path':28s} {'drops/s':>8s} {'ms/drop':>8s} {'p95 %':>6s} {'max %':>6s} "
            f"{'class %':>7s} {'dP':>6s} | {'p95 %':>6s} {'max %':>6s} {'class %':>7s} "
            f"{'dP':>6s}  status"
        )
        for name, (el, s, st) in results.items():
            p95, mx, ch, dp = compare(s, st, ref_s, ref_st)
            if conv_s is None:
                cp95 = cmx = cch = cdp = float("nan")
            else:
                cp95, cmx, cch, cdp = compare(s, st, conv_s, conv_st)
            rate = args.n / el
            cpu_ms = 1e3 * el * numba.get_num_threads() / args.n
            rows.append((fam, name, rate, cpu_ms, p95, mx, ch, dp))
            print(
                f"{name:28s} {rate:8.1f} {cpu_ms:8.2f} {p95:6.2f} {mx:6.2f} {ch:7.2f} "
                f"{dp:6.3f} | {cp95:6.2f} {cmx:6.2f} {cch:7.2f} {cdp:6.3f}  {counts(st)}"
            )
        if args.ladder and "default" in results:
            ladder(spec, P, valid, results["default"][1], ref_s, args.ladder)
        if "default" in results and "reference" in results:
            r_def = args.n / results["default"][0]
            r_ref = args.n / results["reference"][0]
            print(f"speed-up default / reference (RK4 1 ms, reference quadrature): {r_def / r_ref:.1f}x")
    if args.work_precision:
        plot_work_precision(rows, args.png)


if __name__ == "__main__":
    main()
