"""The self-check's reference and the fast path against a sediment table's rows (issue 34 item 2).

Run:  python benchmarks/bench_check_rows.py [--rows 2,200,2000,20000,200000] [--fast-drops 200]
                                            [--folder /tmp/rows]

For each row count R it writes the rough soft-clay core of ``bench_self_check.py`` with R rows on
[0, 6] m under the embedded default ensemble (``bench_self_check.write``), then, on one thread, CPU
seconds (process time, the steadier measure on a shared host):

* the self-check's re-run (``accuracy._rerun`` on ``accuracy.reference_params(..., "check")``, what
  ``mineburial run`` does after its ensemble) of the 8 drops ``accuracy.choose_drops`` picks from
  400, second pass (warm);
* the fast path (``stepper.run_drop`` with the batch's paths, ``overburden.with_long_tables``) on the
  ensemble's first ``--fast-drops`` drops: CPU a drop and mean steps.

The reference is O(1) in rows when its column stays flat as R grows; the fast path's column shows
what a rough table costs the default numerics (its steps: the Rosenbrock-W step resolves the force's
row-scale kinks).
"""

import argparse
import pathlib
import resource

import bench_self_check
import numba
import numpy as np


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", default="2,200,2000,20000,200000")
    ap.add_argument("--fast-drops", type=int, default=200)
    ap.add_argument("--folder", type=pathlib.Path, default=pathlib.Path("/tmp/rows"))
    args = ap.parse_args()
    from mineburial.ensembles import engine
    from mineburial.kernels.mine import layout
    from mineburial.kernels.mine.overburden import with_long_tables
    from mineburial.kernels.mine.stepper import reference_paths, run_drop
    from mineburial.systems.mine import accuracy
    from mineburial.systems.mine.ensemble import chunk_inputs

    numba.set_num_threads(1)
    print("rows     reference: 8 drops CPU s (a drop, steps)      fast path: CPU ms a drop (steps a drop)")
    for rows in (int(r) for r in args.rows.split(",")):
        scenario = bench_self_check.write(args.folder / str(rows), rows)
        spec = engine.load_ensemble(str(scenario), n=400, systems=engine.SYSTEMS)
        idx = accuracy.choose_drops(spec.seed, np.zeros(spec.n, np.int8), 8)
        P = np.concatenate([chunk_inputs(spec, i, i + 1)[0] for i in idx.tolist()])
        Q = accuracy.reference_params(P, "check", sediment_bank=spec.sediment_bank)
        for _ in range(2):  # the first pass may compile
            c0 = _cpu()
            summary, _status = accuracy._rerun(Q, spec, None)
            c_ref = _cpu() - c0
        ref_steps = int(np.nansum(summary[:, layout.S_N_STEPS]))
        Pn, valid, _ = chunk_inputs(spec, 0, args.fast_drops)
        Pn = Pn[valid.astype(bool)]
        sb = np.ascontiguousarray(spec.sediment_bank)
        cb = np.ascontiguousarray(spec.current_bank)
        paths = with_long_tables(reference_paths(Pn), Pn, sb)
        S = np.empty((len(Pn), layout.N_SUMMARY))
        run_drop(Pn[0], sb, cb, S[0], None, 1.0, paths)  # compiled or loaded before the clock
        c0 = _cpu()
        for i, p in enumerate(Pn):
            run_drop(p, sb, cb, S[i], None, 1.0, paths)
        c_fast = (_cpu() - c0) / len(Pn)
        print(
            f"{rows:7d}  {c_ref:7.2f} ({c_ref / 8:.3f} s, {ref_steps / 8:6.0f})"
            f"                    {c_fast * 1e3:8.2f} ({S[:, layout.S_N_STEPS].mean():6.0f})",
            flush=True,
        )


if __name__ == "__main__":
    main()
