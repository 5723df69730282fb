"""What one drop of the numerical self-check costs against one drop of the ensemble (issue 34 item 2).

Run:  python benchmarks/bench_check_ratio.py [--scenario FILE] [-n 400] [--size 16] [--seed S]

On one thread (``numba.set_num_threads(1)``), warm numba cache assumed (run it twice, read the
second): the CPU seconds (process time) and the steps of the first ``-n`` drops of the ensemble on
its own path (``batch.run_batch``), and of the ``--size`` drops that the self-check would choose
among them (``accuracy.choose_drops``, all drops taken as run) on the reference path
(``accuracy._rerun`` of ``accuracy.reference_params``), the same drops on the default path too.
Prints the mean CPU of a drop of each and their ratio ``K`` = (mean reference drop) / (mean
ensemble drop): the constant of the self-check's size rule (``accuracy.CHECK_COST_RATIO``,
``accuracy.default_size``). The reference drops are a random sample, so ``K`` scatters with
``--size`` and the seed: give several seeds.
"""

import argparse
import time

import numba
import numpy as np

from mineburial.ensembles import engine
from mineburial.kernels.mine import layout
from mineburial.systems.mine import accuracy, batch
from mineburial.systems.mine.ensemble import chunk_inputs


def _cpu() -> float:
    return time.process_time()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=None)
    ap.add_argument("-n", "--drops", type=int, default=400)
    ap.add_argument("--size", type=int, default=16)
    ap.add_argument("--seed", type=int, action="append", default=None, help="ensemble seed(s), repeatable")
    args = ap.parse_args()
    numba.set_num_threads(1)
    for seed in args.seed or [None]:
        spec = engine.load_ensemble(args.scenario, n=args.drops, seed=seed, systems=engine.SYSTEMS)
        P, valid, _ = chunk_inputs(spec, 0, spec.n)
        batch.run_batch(P[:1], valid[:1], spec.sediment_bank, spec.current_bank)  # kernels loaded
        t = _cpu()
        summary, status = batch.run_batch(P, valid, spec.sediment_bank, spec.current_bank)
        ens_cpu = _cpu() - t
        ran = int(np.count_nonzero(valid))
        idx = accuracy.choose_drops(spec.seed, status, args.size)
        Q = accuracy.reference_params(P[idx], sediment_bank=spec.sediment_bank)
        accuracy._rerun(Q[:1], spec, None)  # the reference kernels loaded
        t = _cpu()
        ref_summary, _ = accuracy._rerun(Q, spec, None)
        ref_cpu = _cpu() - t
        e_steps = np.nanmean(summary[:, layout.S_N_STEPS])
        r_steps = np.nanmean(ref_summary[:, layout.S_N_STEPS])
        same_steps = np.nanmean(summary[idx, layout.S_N_STEPS])
        per_ens, per_ref = ens_cpu / max(ran, 1), ref_cpu / max(idx.size, 1)
        print(
            f"seed {spec.seed}: ensemble {ran} drops {ens_cpu:.2f} s CPU ({1e3 * per_ens:.2f} ms a drop, "
            f"{e_steps:.0f} steps); self-check {idx.size} drops {ref_cpu:.2f} s CPU "
            f"({1e3 * per_ref:.0f} ms a drop, {r_steps:.0f} steps; {same_steps:.0f} on the default path); "
            f"K = {per_ref / per_ens:.1f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
