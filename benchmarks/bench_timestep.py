"""Is the default time step small enough? Landing position and travel time vs dt.

Run:  python benchmarks/bench_timestep.py

For each example scenario the drop is run at the default dt and at dt/2, dt/4,
dt/8, dt/16 (RK4). The converged answer is the dt/16 run (its difference to dt/8
is printed to show it is converged). Reported: time of seabed impact (travel
time), horizontal landing position (x, y at impact; relative to the horizontal
distance travelled) and, for the drops that end in the sediment, penetration.
The issue's criterion: default dt within 0.5 % of the converged answer.
"""

import dataclasses
import math

from _common import machine


def run(sc, dt):
    from mineburial.kernels.mine import layout
    from mineburial.systems.mine.drop import run_params

    p, sb, cb = sc.to_params()
    p = p.copy()
    p[layout.P_DT] = dt
    # record densely enough to read the impact position
    code, s, traj = run_params(p, sb, cb, record_interval=dt)
    t_imp = s[layout.S_IMPACT_TIME]
    # COM position at the first recorded time at or after impact
    import numpy as np

    k = int(np.searchsorted(traj[:, 0], t_imp - 1e-12))
    k = min(k, traj.shape[0] - 1)
    return dict(
        t=t_imp,
        x=traj[k, 1],
        y=traj[k, 2],
        x0=traj[0, 1],
        y0=traj[0, 2],
        pen=s[layout.S_PENETRATION],
        status=code,
    )


def main():
    from mineburial.systems.mine.config import load_example

    print(f"machine: {machine()}")
    print(
        f"{'scenario':14s} {'dt':>8s} {'impact t [s]':>12s} {'err t':>8s} {'err xy':>8s} "
        f"{'penetr. [m]':>11s} {'err pen':>8s}"
    )
    for name in ("exp1_case92", "exp1_case93", "exp2_barrel", "default_mine"):
        sc = load_example(name)
        dt0 = sc.numerics.dt
        sc = dataclasses.replace(
            sc, numerics=dataclasses.replace(sc.numerics, t_max=min(sc.numerics.t_max, 20.0))
        )
        runs = {f: run(sc, dt0 / f) for f in (1, 2, 4, 8, 16)}
        ref = runs[16]
        travel = math.hypot(ref["x"] - ref["x0"], ref["y"] - ref["y0"])
        for f, r in runs.items():
            et = abs(r["t"] - ref["t"]) / ref["t"]
            exy = math.hypot(r["x"] - ref["x"], r["y"] - ref["y"]) / max(travel, 1e-9)
            ep = abs(r["pen"] - ref["pen"]) / max(abs(ref["pen"]), 1e-9)
            print(
                f"{name:14s} {dt0 / f:8.1e} {r['t']:12.5f} {100 * et:7.3f}% {100 * exy:7.3f}% "
                f"{r['pen']:11.4f} {100 * ep:7.3f}%"
            )


if __name__ == "__main__":
    main()
