"""Stratified accuracy sweep (issue 19 item 6): the default numerics against the tight
reference of the numerical self-check, per stratum of mine size x entry x sediment class.

Run:  python benchmarks/accuracy_sweep.py [-n 12] [--seed 19] [--strata small-fast_steep-mixed,...]
                                          [--diagnose] [-o benchmarks/results/accuracy_sweep.txt]

Every stratum is an ensemble scenario (assumptions below, every value a choice made to span the
families, not a measured population):

* mine size: ``small`` 1.0 m x 0.30 m, 150 kg; ``medium`` 1.7 m x 0.48 m, 500 kg (the air-laid
  benchmark mine); ``large`` 2.5 m x 0.60 m, 1200 kg; mass normal with a 2 % std, COM 3 % of the
  length towards the nose;
* entry: ``slow_level`` -- laid from a ship's rail (the default ensemble's release: COM 2 m above
  the surface, 2-4 m/s horizontal, pitch 0-30 deg, tipping 0-1 rad/s, 27-33 m of water);
  ``fast_steep`` -- air-laid (the air-laid benchmark's release: COM 5 m above the surface,
  15-30 m/s horizontal and 25-40 m/s down, pitch 40-70 deg, 15-25 m of water);
* sediment: ``soft_mud`` (very_soft_clay or soft_clay), ``sand`` (sandy_silt or sand),
  ``mixed`` (very_soft_clay, soft_clay, silty_mud or firm_clay: the issue's failing family),
  catalogue classes (mineburial/sediment_profiles.py) with equal odds.

On the same sampled drops of each stratum it runs the shipped defaults and the self-check's
reference path (:func:`mineburial.ensembles.accuracy.reference_params`: rtol 1e-5, atol 1e-6,
reference sediment and overburden quadratures) and prints p95 and max of the relative penetration
change (:func:`mineburial.ensembles.accuracy.differences`: relative to max(reference, 0.5 m), at
most 5 mm counts as 0), the burial-class and status changes, and whether the stratum meets the
targets (p95 <= 1 %, max <= 5 %). ``--diagnose`` re-runs each stratum that misses with the
tolerance alone tightened (rtol 1e-5, atol 1e-6, fast rule) and with the reference quadratures
alone (default rtol): which of the two carries its error.
"""

import argparse
import itertools
import pathlib
import time

from _common import machine

from mineburial.ensembles import accuracy, engine
from mineburial.ensembles.batch import run_batch
from mineburial.kernels.mine import layout as L

HERE = pathlib.Path(__file__).resolve().parent
U = "uniform"
SIZES = {"small": (1.0, 0.30, 150.0), "medium": (1.7, 0.48, 500.0), "large": (2.5, 0.60, 1200.0)}
ENTRIES = {
    "slow_level": {
        "release": {
            "position": [0.0, 0.0, 2.0],
            "velocity": [{"distribution": U, "low": 2.0, "high": 4.0}, 0.0, 0.0],
            "pitch_deg": {"distribution": U, "low": 0.0, "high": 30.0},
            "angular_velocity": [0.0, {"distribution": U, "low": 0.0, "high": 1.0}, 0.0],
        },
        "water_depth": {"distribution": U, "low": 27.0, "high": 33.0},
    },
    "fast_steep": {
        "release": {
            "position": [0.0, 0.0, 5.0],
            "velocity": [
                {"distribution": U, "low": 15.0, "high": 30.0},
                0.0,
                {"distribution": U, "low": -40.0, "high": -25.0},
            ],
            "pitch_deg": {"distribution": U, "low": 40.0, "high": 70.0},
            "angular_velocity": [0.0, {"distribution": U, "low": -0.5, "high": 0.5}, 0.0],
        },
        "water_depth": {"distribution": U, "low": 15.0, "high": 25.0},
    },
}
SEDIMENTS = {
    "soft_mud": ["very_soft_clay", "soft_clay"],
    "sand": ["sandy_silt", "sand"],
    "mixed": ["very_soft_clay", "soft_clay", "silty_mud", "firm_clay"],
}


def stratum(size: str, entry: str, sediment: str) -> dict:
    """The ensemble scenario (a dict) of one stratum."""
    length, diameter, mass = SIZES[size]
    e = ENTRIES[entry]
    return {
        "mine": {
            "name": f"{size}_mine",
            "length": length,
            "diameter": diameter,
            "mass": {"distribution": "normal", "mean": mass, "std": 0.02 * mass},
            "com_offset": 0.03 * length,
        },
        "release": {"roll_deg": 0.0, "heading_deg": 0.0, **e["release"]},
        "environment": {"water_depth": e["water_depth"]},
        "sediment": {"class": {"distribution": "choice", "values": SEDIMENTS[sediment]}},
        "numerics": {"t_max": 30.0},
    }


def variant(P, rtol=None, quadrature=None):
    Q = P.copy()
    if rtol is not None:
        Q[:, L.P_RTOL], Q[:, L.P_ATOL] = rtol, rtol / 10.0
    if quadrature is not None:
        Q[:, L.P_SED_QUADRATURE] = L.SEDIMENT_QUADRATURE_NAMES.index(quadrature)
        Q[:, L.P_OB_QUADRATURE] = L.OVERBURDEN_QUADRATURE_NAMES.index(quadrature)
    return Q


def timed(spec, P, valid):
    t = time.perf_counter()
    summary, status = run_batch(P, valid, spec.sediment_bank, spec.current_bank)
    return time.perf_counter() - t, summary, status


def row(name, diff, t_def, t_ref, n) -> str:
    ok = diff["p95"] <= accuracy.TARGETS[0] and diff["max"] <= accuracy.TARGETS[1]
    return (
        f"{name:30s} {n:3d} {diff['p95']:7.2f} {diff['max']:7.2f} {diff['class_changes']:5d} "
        f"{diff['status_changes']:5d} {t_def:7.1f} {t_ref:7.1f}  {'ok' if ok else 'MISS'}"
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-n", type=int, default=12, help="drops a stratum (default 12)")
    ap.add_argument("--seed", type=int, default=19)
    ap.add_argument(
        "--strata", default="", help="comma-separated size-entry-sediment names (default: all 18)"
    )
    ap.add_argument("--diagnose", action="store_true", help="split the error of a missing stratum")
    ap.add_argument("-o", "--output", type=pathlib.Path, default=None, help="also write the table here")
    args = ap.parse_args()
    names = (
        args.strata.split(",")
        if args.strata
        else ["-".join(k) for k in itertools.product(SIZES, ENTRIES, SEDIMENTS)]
    )
    out = [
        f"# accuracy sweep: default numerics against the self-check's reference ({accuracy.REFERENCE_TEXT})",
        f"# {args.n} drops a stratum, seed {args.seed}; {machine()}",
        "# penetration change relative to max(reference, 0.5 m), <= 5 mm counts 0; "
        "targets p95 <= 1 %, max <= 5 %",
        f"# {'stratum':28s}   n  p95 %   max %  class status  t_def s t_ref s",
    ]
    print("\n".join(out), flush=True)
    for name in names:
        spec = engine.load_ensemble(stratum(*name.split("-")), n=args.n, seed=args.seed)
        P, valid, _ = engine.chunk_inputs(spec, 0, args.n)
        t_def, s_def, st_def = timed(spec, P, valid)
        t_ref, s_ref, st_ref = timed(spec, accuracy.reference_params(P), valid)
        diff = accuracy.differences(s_def, st_def, s_ref, st_ref)
        lines = [row(name, diff, t_def, t_ref, int(valid.sum()))]
        if args.diagnose and not lines[0].endswith("ok"):
            for label, Q in (
                ("  rtol 1e-5, fast rule", variant(P, rtol=1e-5)),
                ("  default rtol, reference rule", variant(P, quadrature="reference")),
            ):
                t, s, st = timed(spec, Q, valid)
                lines.append(
                    row(label, accuracy.differences(s, st, s_ref, st_ref), t, t_ref, int(valid.sum()))
                )
        print("\n".join(lines), flush=True)
        out.extend(lines)
    if args.output is not None:
        args.output.write_text("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
