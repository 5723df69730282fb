"""Cost of a tabulated sediment profile against its number of rows (issue 21, item 11).

Run:  python benchmarks/bench_profile_rows.py [--rows 3,30000] [--drops 4] [--repeat 3]
                                              [--resistance bearing] [--overburden fast|reference]

The default mine (mineburial/data/default_mine.toml) is dropped ``--drops`` times (release
pitch 0, 10, 20, ... degrees) onto the catalogue's soft clay (rho = 1420 + 30 z kg m-3,
S = 2000 + 1010 z Pa) given as a tabulated profile on [0, 10] m with each number of rows:
the same profile, resampled on equally spaced depths (the values between rows are linear,
so every table describes the same seabed). It prints the best of ``--repeat`` wall times of
the drops (compile excluded: one untimed drop first), their ratio to the first table's and
the penetrations (which agree to rounding, the tables being the same profile).

``--resistance`` sets ``sediment.resistance`` (default: the model's, ``bearing``; ``delta`` has
no geostatic force, so no slicing of the body at the table's depths). With ``bearing`` the
geostatic force takes ``numerics.overburden_quadrature = "fast"`` (the default): the body is
sliced at the table's depths while at most 12 lie inside it, in 12 equal slices beyond
(kernels/mine/overburden.py); ``--overburden reference`` slices at every depth (the cost that grows).

Target (issue 21): the 30,000-row profile within 20 % of the speed of the 3-row one.
"""

import argparse
import pathlib
import time

import numpy as np
from _common import best_of, machine

from mineburial.kernels.mine import layout
from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.drop import run_params

DEFAULT = pathlib.Path(__file__).resolve().parents[1] / "mineburial" / "data" / "default_mine.toml"


def scenario(
    rows: int, pitch: float, resistance: str | None = None, overburden: str | None = None
) -> Scenario:
    d = Scenario.from_toml(DEFAULT).to_dict()
    z = np.linspace(0.0, 10.0, rows)
    d["sediment"]["profile"] = {
        "name": f"soft clay, {rows} rows",
        "depth": z.tolist(),
        "density": (1420.0 + 30.0 * z).tolist(),
        "strength": (2000.0 + 1010.0 * z).tolist(),
    }
    d["release"]["pitch_deg"] = pitch
    if resistance:
        d["sediment"]["resistance"] = resistance
    if overburden:
        d["numerics"]["overburden_quadrature"] = overburden
    return Scenario.from_dict(d)


def drops(rows: int, n: int, resistance: str | None = None, overburden: str | None = None):
    packed = [scenario(rows, 10.0 * i, resistance, overburden).to_params() for i in range(n)]

    def run():
        return [run_params(*p)[1][layout.S_PENETRATION] for p in packed]

    return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", default="3,30000")
    ap.add_argument("--drops", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--resistance", default=None)
    ap.add_argument("--overburden", default=None, help="numerics.overburden_quadrature (default: fast)")
    args = ap.parse_args()
    print(machine())
    print(f"sediment.resistance = {args.resistance or 'the default (bearing)'}")
    print(f"numerics.overburden_quadrature = {args.overburden or 'the default (fast)'}")
    base = None
    for rows in (int(r) for r in args.rows.split(",")):
        run = drops(rows, args.drops, args.resistance, args.overburden)
        t0 = time.perf_counter()
        run()  # compile (or load the cache) and warm up
        first = time.perf_counter() - t0
        t, pen = best_of(run, args.repeat)
        base = t if base is None else base
        print(
            f"{rows:7d} rows: {args.drops} drops in {t:.3f} s (best of {args.repeat}; first call "
            f"{first:.1f} s), {t / base:.2f} x the first table; penetration "
            + ", ".join(f"{x:.4f}" for x in pen)
            + " m"
        )


if __name__ == "__main__":
    main()
