"""The torpedo-anchor embedment band case of the validation (issue 19 item 4;
``mineburial.validation.cases.anchor_embedment``, assumptions in docs/validation.md), printed
as the validation report's rows. Results: benchmarks/results/anchor_embedment.txt.

    python benchmarks/anchor_embedment.py
"""

import time

from mineburial.validation import cases


def main():
    t0 = time.perf_counter()
    a = cases.ANCHOR
    print(
        f"anchor: flat-ended cylinder L = {a['length']:g} m, D = {a['diameter']:g} m, "
        f"{a['density']:g} kg/m3, axial, tip at the mudline at the impact speed, no fins"
    )
    print(
        f"clay: s_u = k z, k = {cases.ANCHOR_K[0] / 1000:.3f} and {cases.ANCHOR_K[1] / 1000:.3f} kPa/m "
        f"(s_u/sigma'_v = 0.2 and 0.3), density {cases.ANCHOR_CLAY_DENSITY:g} kg/m3"
    )
    print(f"band: {cases.ANCHOR_SOURCE}\n")
    print("quantity | reference | model | result")
    for row in cases.anchor_embedment():
        model = f"{row.model:.3f}" if isinstance(row.model, float) else row.model
        print(f"{row.quantity} | {row.reference} | {model} | {row.result}")
    print(f"\nwall time {time.perf_counter() - t0:.1f} s (compile included)")


if __name__ == "__main__":
    main()
