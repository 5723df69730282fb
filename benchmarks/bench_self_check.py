"""Cost of the numerical self-check of ``mineburial run`` on a long sediment profile (issue 34, item 2).

Run:  python benchmarks/bench_self_check.py write DIR [--rows 20000]
      mineburial run DIR/long_profile.toml -n 40 -o DIR/out.nc

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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    w = sub.add_parser("write", help="write the scenario and its core")
    w.add_argument("folder", type=pathlib.Path)
    w.add_argument("--rows", type=int, default=20000)
    args = ap.parse_args()
    print(write(args.folder, args.rows))


if __name__ == "__main__":
    main()
