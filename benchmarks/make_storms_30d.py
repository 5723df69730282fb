"""Write the shipped 30-day forcing ``mineburial/data/forcing/storms_30d.csv`` (issue 20: Sobol'
indices at a 30-day lead time): three synthetic winter storms in 30 days, hourly, each a
:func:`mineburial.io.forcing.storm_series` over its own 10-day piece, the pieces joined end to end.

Not a measurement: three moderate storms (peak Hs 1.0, 1.4 and 1.2 m, Tp 8-9 s, currents 0.2-0.3
m/s, surges 0.1-0.2 m; off Oahu burial followed single events with Hs > 1.25 m, DTIC ADA513729),
sized so that the scour_storm example's mine is not yet at its cap (B = D) after 30 days: under the
example's 2.5 m storm every drop ends fully buried, the burial is then constant and its Sobol'
indices undefined. Every piece starts and ends at the same background (Hs 0.4 m, current
0.05 m/s, no surge), so the joins are continuous in Hs, current and level; Tp at the background
differs between pieces by its constant-steepness rule (4.8-5.1 s).

    python benchmarks/make_storms_30d.py [OUT.csv]
"""

import sys

import numpy as np

from mineburial.io.forcing import Forcing, storm_series, write_csv
from mineburial.systems.mine.processes.scour import SHIPPED

START = np.datetime64("2003-01-05T00:00:00", "ns")
PIECE_H = 240.0
#: (peak_hs m, peak_tp s, duration_h, peak_h within the piece, current m/s, surge m)
STORMS = (
    (1.0, 8.0, 36.0, 96.0, 0.2, 0.1),
    (1.4, 9.0, 48.0, 120.0, 0.3, 0.2),
    (1.2, 8.5, 36.0, 96.0, 0.25, 0.15),
)
COMMON = dict(background_hs=0.4, background_current=0.05, wave_from=270.0, current_to=0.0, total_h=PIECE_H)


def join_storms(storms, source: str) -> Forcing:
    """The storms' pieces joined: each piece (a storm_series of one ``storms`` row) holds hours
    0..240, and the next starts where it ends (its first record, equal in Hs, current and level,
    replaces the piece's last)."""
    pieces = [
        storm_series(hs, tp, dur, peak_h=peak, current=cur, surge=surge, **COMMON)
        for hs, tp, dur, peak, cur, surge in storms
    ]
    last = len(pieces) - 1
    keep = [slice(None) if k == last else slice(None, -1) for k in range(len(pieces))]
    time = np.concatenate([p.time[s] + k * PIECE_H * 3600.0 for k, (p, s) in enumerate(zip(pieces, keep))])
    names = ("hs", "tp", "wave_from", "current_speed", "current_to", "water_level")
    arrays = {n: np.concatenate([getattr(p, n)[s] for p, s in zip(pieces, keep)]) for n in names}
    return Forcing(time=time, start=START, source=source, **arrays)


def storms_30d() -> Forcing:
    """The three storms joined (:func:`join_storms`)."""
    return join_storms(STORMS, "storms_30d (three synthetic storms)")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else SHIPPED / "storms_30d.csv"
    comment = (
        "Three synthetic winter storms in 30 days for mineburial (not a measurement), written by\n"
        "  python benchmarks/make_storms_30d.py: each mineburial.io.forcing.storm_series(peak_hs, peak_tp,\n"
        "  duration_h, peak_h, current, surge, background_hs=0.4, background_current=0.05, wave_from=270,\n"
        "  current_to=0, total_h=240) over its own 10 days, joined end to end; storms\n"
        "  (peak_hs m, peak_tp s, duration_h, peak_h, current m/s, surge m):\n"
        + "".join(f"  {s}\n" for s in STORMS)
        + "hourly from 2003-01-05; waves from the west, current towards the north; level above the datum"
    )
    print(write_csv(storms_30d(), out, comment))
