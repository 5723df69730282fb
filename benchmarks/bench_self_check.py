"""Cost of the numerical self-check of ``mineburial run`` (issue 34, items 1-2).

Run:  python benchmarks/bench_self_check.py write DIR [--rows 20000]
      mineburial run DIR/long_profile.toml -n 40 -o DIR/out.nc
      python benchmarks/bench_self_check.py time [--size 8] [--references check,accurate] [--threads 1,2]
                                                 [--scenario FILE] [-n DROPS] [--repeat 1]

``time`` times the self-check's re-run alone (``accuracy._rerun``, what ``mineburial run`` does after
the ensemble) on the drops it checks in the scenario (default: the embedded default ensemble; the drops
of ``accuracy.choose_drops`` with ``--size``, all drops assumed run), for each reference path by name
(``accuracy.REFERENCES``) and thread count: wall and CPU seconds (the CPU time of the process, the
steadier measure on a shared host), the steps and each drop's penetration (first pass; warm numba
cache assumed: run it twice and read the second).

``write`` writes ``DIR/long_profile.toml``: the embedded default ensemble (mine, release, water,
current and coefficients as ``mineburial run`` draws them) over a cone-penetration-like core of
``--rows`` rows on [0, 6] m (0.3 mm apart for 20,000 rows), ``DIR/core.csv``: the catalogue's soft clay
(rho = 1420 + 30 z kg m-3, S = 2000 + 1010 z Pa) with a reproducible roughness of +-1 % in density
and +-10 % in strength (a sum of a few sines and a seeded white noise: a measured log is rough at the
scale of its rows, which is what makes a reference quadrature that resolves every row costly). The run
prints the ensemble's progress and wall time and the self-check's line with its own wall time
(``numerical_check_wall_time_s``).
"""

import argparse
import pathlib
import resource
import time

import numpy as np
import tomllib

import mineburial


def core(rows: int, seed: int = 34) -> np.ndarray:
    """(depth, density, strength) of the rough soft-clay core, one row a point."""
    z = np.linspace(0.0, 6.0, rows)
    rng = np.random.default_rng(seed)
    wave = 0.5 * np.sin(2 * np.pi * z / 0.7) + 0.3 * np.sin(2 * np.pi * z / 0.13 + 1.0)
    noise = rng.standard_normal(rows)
    rho = (1420.0 + 30.0 * z) * (1.0 + 0.01 * (0.6 * wave + 0.4 * noise) / 1.5)
    su = (2000.0 + 1010.0 * z) * (1.0 + 0.1 * (0.6 * wave + 0.4 * noise) / 1.5)
    return np.column_stack([z, rho, np.maximum(su, 0.0)])


def write(folder: pathlib.Path, rows: int) -> pathlib.Path:
    folder.mkdir(parents=True, exist_ok=True)
    np.savetxt(
        folder / "core.csv",
        core(rows),
        delimiter=",",
        header="depth_m,density_kg_m3,strength_pa",
        comments="",
        fmt="%.6f",
    )
    text = (pathlib.Path(mineburial.__file__).parent / "data/ensembles/default_soft_mud.toml").read_text()
    tomllib.loads(text)  # the embedded default parses
    head, _, tail = text.partition("[sediment]")
    _, _, after = tail.partition("[numerics]")
    out = folder / "long_profile.toml"
    out.write_text(
        head.replace('description = "', f'description = "{rows}-row rough core; ', 1)
        + f'[sediment]\nfile = "core.csv"   # {rows} rows on [0, 6] m (benchmarks/bench_self_check.py)\n\n'
        + "[numerics]"
        + after
    )
    return out


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def time_check(scenario, size: int, references, threads, repeat: int, drops=None) -> None:
    """Print the wall and CPU time of the self-check's re-run per reference path and thread count."""
    import numba

    from mineburial.ensembles import engine
    from mineburial.kernels.mine import layout
    from mineburial.systems.mine import accuracy
    from mineburial.systems.mine.ensemble import chunk_inputs

    spec = engine.load_ensemble(scenario, n=drops, systems=engine.SYSTEMS)
    idx = accuracy.choose_drops(spec.seed, np.zeros(spec.n, np.int8), size)
    P = np.concatenate([chunk_inputs(spec, i, i + 1)[0] for i in idx.tolist()])
    print(
        f"scenario: {scenario or 'embedded default'}; {idx.size} drops {idx.tolist()}; numba threads max "
        f"{numba.config.NUMBA_NUM_THREADS}"
    )
    for name in references:
        Q = accuracy.reference_params(P, name, sediment_bank=spec.sediment_bank)  # as self_check does
        for nt in threads:
            numba.set_num_threads(nt)
            for rep in range(repeat):
                w0, c0 = time.perf_counter(), _cpu()
                summary, status = accuracy._rerun(Q, spec, None)
                wall, cpu = time.perf_counter() - w0, _cpu() - c0
                steps = int(np.nansum(summary[:, layout.S_N_STEPS]))
                print(
                    f"{name:9s} rtol {accuracy.REFERENCES[name][0]:g}  threads {nt}  wall {wall:6.2f} s  "
                    f"cpu {cpu:6.2f} s  steps {steps:6d}  ({wall / idx.size:.3f} s wall a drop)",
                    flush=True,
                )
                if rep == 0 and nt == threads[0]:
                    pen = ", ".join(f"{v:.5f}" for v in summary[:, layout.S_PENETRATION])
                    print(f"    penetration m: {pen}; status {status.tolist()}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    w = sub.add_parser("write", help="write the scenario and its core")
    w.add_argument("folder", type=pathlib.Path)
    w.add_argument("--rows", type=int, default=20000)
    t = sub.add_parser("time", help="time the self-check's re-run per reference path and thread count")
    t.add_argument("--scenario", default=None, help="ensemble scenario (default: the embedded default)")
    t.add_argument("--size", type=int, default=8, help="drops checked (accuracy.choose_drops)")
    t.add_argument("-n", "--drops", type=int, default=None, help="drops of the ensemble (default: its own)")
    t.add_argument("--references", default="check,accurate", help="names of accuracy.REFERENCES")
    t.add_argument("--threads", default="1,2", help="thread counts, comma-separated")
    t.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    if args.cmd == "write":
        print(write(args.folder, args.rows))
    else:
        threads = [int(x) for x in args.threads.split(",")]
        time_check(args.scenario, args.size, args.references.split(","), threads, args.repeat, args.drops)


if __name__ == "__main__":
    main()
