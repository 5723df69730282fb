"""Compile time and start-up: the engine from an empty numba cache, then with a warm one.

Run:  python benchmarks/bench_startup.py [--repeat 3]

Each measurement is a fresh interpreter that imports the engine, samples one drop of
the embedded default ensemble and runs it through the batch driver (what
``mineburial run`` does before its first chunk), timed from the start of the
interpreter's first import to the end of the drop:

* **cold**: numba's cache pointed at an empty folder (``NUMBA_CACHE_DIR``), so every
  kernel the default path needs is compiled: the cost a user pays once per installation;
* **warm**: the same again with the cache that the cold run filled: the start-up of
  every later run (imports + loading the compiled kernels).

The reference paths (``rk4``, ``local_linear``, the reference sediment quadrature) are
compiled only when a drop asks for one (``stepper.reference_paths``); their cold compile
is measured separately ("cold, reference paths"). Issue 9 targets: cold <= 20 s,
warm <= 1 s on the 2-core development machine.
"""

import argparse
import os
import subprocess
import sys
import tempfile

from _common import machine

SNIPPET = """
import time
t0 = time.perf_counter()
from mineburial.ensembles.batch import run_batch
from mineburial.ensembles.engine import chunk_inputs, load_ensemble
t_import = time.perf_counter() - t0
spec = load_ensemble(None)
P, valid, _ = chunk_inputs(spec, 0, 1)
if {reference}:
    from mineburial.kernels import layout
    P[:, layout.P_INTEGRATOR] = layout.INTEGRATOR_NAMES.index("rk4")
    P[:, layout.P_SED_QUADRATURE] = layout.SEDIMENT_QUADRATURE_NAMES.index("reference")
run_batch(P, valid, spec.sediment_bank, spec.current_bank)
print(t_import, time.perf_counter() - t0)
"""


def measure(cache_dir, reference=False):
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir, "MINEBURIAL_NUMBA_CACHE": "1"}
    out = subprocess.run(
        [sys.executable, "-c", SNIPPET.format(reference=reference)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    t_import, total = map(float, out.stdout.split())
    return t_import, total


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="warm start-ups to time (best kept)")
    args = ap.parse_args()
    print(f"machine: {machine()}")
    with tempfile.TemporaryDirectory() as cache:
        imp, cold = measure(cache)
        print(f"cold (empty cache), default paths: {cold:6.2f} s  (imports {imp:.2f} s)")
        warm = min(measure(cache) for _ in range(args.repeat))
        print(f"warm (cache filled), default paths: {warm[1]:6.2f} s  (imports {warm[0]:.2f} s)")
        imp, cold_ref = measure(cache, reference=True)
        print(f"cold, reference paths (compiled on first use): {cold_ref:6.2f} s")


if __name__ == "__main__":
    main()
