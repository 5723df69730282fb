"""Compare the per-drop answers of two runs (``mineburial run ... --per-drop -o FILE``).

Run:  python benchmarks/compare_answers.py OLD.nc NEW.nc

Prints, for the per-drop penetration, whether the two runs are bit-identical, and otherwise the
largest and 95th-percentile change relative to max(|old|, 0.5 m) (``answers-vs``'s scale), the
largest absolute change and the drops that changed; then the numeric variables that are not
bit-identical (NaN equal to NaN).
"""

import argparse

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    args = ap.parse_args()
    import xarray as xr

    a = xr.open_dataset(args.old)
    b = xr.open_dataset(args.new)
    name = next(v for v in ("penetration_depth", "penetration") if v in a)
    pa = a[name].values.astype(float)
    pb = b[name].values.astype(float)
    if np.array_equal(pa, pb, equal_nan=True):
        print(f"{name}: bit-identical on {pa.size} drops")
    else:
        d = np.abs(pb - pa)
        rel = d / np.maximum(np.abs(pa), 0.5)
        rel = np.where(np.isnan(rel), 0.0, rel)
        changed = np.nonzero(~((pa == pb) | (np.isnan(pa) & np.isnan(pb))))[0]
        p95 = 100 * np.percentile(rel, 95)
        worst = int(np.nanargmax(d))
        print(
            f"{name}: {changed.size} of {pa.size} drops changed; relative change p95 {p95:.2e} %, "
            f"max {100 * rel.max():.2e} %; largest |change| {d[worst]:.3e} m (drop {worst})"
        )
    differ = []
    for v in a.data_vars:
        if v not in b or not np.issubdtype(a[v].dtype, np.number):
            continue
        if a[v].shape != b[v].shape or not np.array_equal(a[v].values, b[v].values, equal_nan=True):
            differ.append(v)
    n = sum(1 for v in a.data_vars if np.issubdtype(a[v].dtype, np.number))
    print(
        f"numeric variables not bit-identical: {len(differ)} of {n}"
        + (f": {', '.join(differ)}" if differ else "")
    )


if __name__ == "__main__":
    main()
