"""Single-drop throughput: compile time, steps/s and drops/s of one water-column drop.

Run:  python benchmarks/bench_drop.py [--no-cache]

The water-column drop is cylinder 1 of seed 000 eq. (92) released at the surface
into deep still water (no seabed contact) for 2 s at the default time step; the
full air-water-sediment drop is the Exp-2 barrel (issue 3) and the default mine.
Compile time is measured in a fresh interpreter with numba's cache disabled, so it
is the cost a user pays once per installation (afterwards the cache is used).
"""

import argparse
import dataclasses
import subprocess
import sys

from _common import best_of, machine

COMPILE_SNIPPET = """
import time
t0 = time.perf_counter()
from mineburial.systems.mine.config import load_example
from mineburial.systems.mine.drop import run_params
sc = load_example('exp1_case92')
p, sb, cb = sc.to_params()
run_params(p, sb, cb)
print(time.perf_counter() - t0)
"""


def compile_time(no_cache: bool) -> float:
    env = None
    if no_cache:
        import os
        import tempfile

        env = dict(os.environ, NUMBA_CACHE_DIR=tempfile.mkdtemp(prefix="mb-nocache-"))
    out = subprocess.run(
        [sys.executable, "-c", COMPILE_SNIPPET], capture_output=True, text=True, env=env, check=True
    )
    return float(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    from mineburial.kernels.mine import layout
    from mineburial.systems.mine.config import load_example
    from mineburial.systems.mine.drop import run_params

    print(f"machine: {machine()}")
    print(f"compile (fresh process, empty numba cache): {compile_time(True):.1f} s")
    print(f"start-up with a warm numba cache:           {compile_time(False):.1f} s")

    cases = []
    sc = load_example("exp1_case92")
    env = dataclasses.replace(sc.environment, water_depth=1000.0)
    num = dataclasses.replace(sc.numerics, t_max=2.0)
    cases.append(
        (
            "water column (exp1_case92, 2 s, deep water)",
            dataclasses.replace(sc, environment=env, numerics=num),
        )
    )
    cases.append(("air-water-sediment (exp2_barrel)", load_example("exp2_barrel")))
    cases.append(("air-water-sediment (default_mine)", load_example("default_mine")))
    print(f"{'case':48s} {'dt [s]':>8s} {'steps':>8s} {'steps/s':>10s} {'drops/s':>9s} status")
    for name, sc in cases:
        p, sb, cb = sc.to_params()
        run_params(p, sb, cb)  # compile / warm
        t, (code, summary, _) = best_of(lambda p=p, sb=sb, cb=cb: run_params(p, sb, cb), args.repeat)
        steps = summary[layout.S_N_STEPS]
        from mineburial.kernels.mine import status

        print(
            f"{name:48s} {p[layout.P_DT]:8.0e} {int(steps):8d} {steps / t:10.0f} {1 / t:9.2f} "
            f"{status.NAMES[code]}"
        )


if __name__ == "__main__":
    main()
