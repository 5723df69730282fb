"""Cold compile of one kernel and everything below it, with each compile unit's own CPU time.

Run:  python benchmarks/bench_kernel_compile.py derivatives|lateral_breaks [--repeat N]

Each repeat is a fresh interpreter with an empty numba cache (``NUMBA_CACHE_DIR`` a new temporary
folder, ``MINEBURIAL_NUMBA_CACHE=0``) that compiles the kernel as compiled code calls it (from a
jitted wrapper, so its ``compiled_callee`` twin): ``dynamics.derivatives`` for the default
ensemble's first drop, or ``sediment.reference._lateral_breaks`` (the reference quadrature's
breakpoints) for a fixed rotating pose. It prints the whole compile's CPU seconds and the three
costliest compile units with their top numba passes (numba's event API, as
``bench_startup.py --profile``). For A/B of two trees, put each on ``PYTHONPATH`` in turn and
alternate: single runs on a shared machine vary by +-1 s (issue 18, docs/design.md "Developing
kernels").
"""

import argparse
import os
import subprocess
import sys
import tempfile

from bench_startup import PROFILER

SETUP = {
    "derivatives": """
import numpy as np
from mineburial.ensembles.engine import load_ensemble
from mineburial.systems.mine.ensemble import chunk_inputs
from mineburial.kernels.mine import dynamics, layout
from mineburial.kernels.mine.sediment import pack_law
spec = load_ensemble(None)
P, valid, _ = chunk_inputs(spec, 0, 1)
p = P[0]
y = np.zeros(layout.N_EXT); y[6] = 1.0; y[2] = -p[layout.P_DEPTH]; y[5] = -2.0
args = (y, p, pack_law(p, p[layout.P_DIAMETER], None), spec.sediment_bank, spec.current_bank,
        np.zeros(layout.N_WORK), np.zeros(layout.N_EXT), np.zeros(layout.N_DIAG))
target = dynamics.derivatives
""",
    "lateral_breaks": """
from mineburial.kernels.mine.sediment import reference
args = ((0.3, -1.0, 1.0, 0.1, -0.5, -1.0, 0.2, 0.3, -0.1), (0.1, -0.06, -0.27, -0.1, 0.0, 0.0),
        (0.0, -0.5, -1.0, 0.0, -0.1, -0.3), (0.06, -1.0, 0.5, 0.0, -0.3, 0.1), True, (1, 0.01, 0.5),
        0.01, 0.02)
target = reference._lateral_breaks
""",
}

RUN = """
import time
from numba import njit
wrapper = njit(lambda *a: target(*a))
t0 = time.process_time()
wrapper(*args)
print(f"cold compile of {NAME} and below: {time.process_time() - t0:.2f} s CPU")
for key, u in sorted(units.items(), key=lambda kv: -kv[1]["own"])[:3]:
    passes = sorted(((k[5:], v) for k, v in u.items() if k.startswith("pass:")), key=lambda kv: -kv[1])[:4]
    print(f"  {u['own']:5.2f} s own  {key[0].replace('mineburial.', '')}: "
          + ", ".join(f"{k} {v:.2f}" for k, v in passes))
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kernel", choices=sorted(SETUP))
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    code = PROFILER + SETUP[args.kernel] + f"NAME = {args.kernel!r}\n" + RUN
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as cache:
            env = {**os.environ, "NUMBA_CACHE_DIR": cache, "MINEBURIAL_NUMBA_CACHE": "0"}
            # run in the empty folder: ``-c`` puts the working directory first on sys.path, which
            # from a checkout's root would shadow the tree on PYTHONPATH
            out = subprocess.run(
                [sys.executable, "-c", code], env=env, cwd=cache, capture_output=True, text=True, check=True
            )
            print(out.stdout, end="", flush=True)


if __name__ == "__main__":
    main()
