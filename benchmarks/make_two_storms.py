"""Write the shipped 20-day forcing ``mineburial/data/forcing/two_storms.csv`` (issue 33: the
scour-and-settle law's two-storm example, ``mineburial/data/ensembles/scour_two_storms.toml``): two
similar synthetic winter storms ten days apart, hourly, each a
:func:`mineburial.io.forcing.storm_series` over its own 10-day piece, the pieces joined end to end as
``benchmarks/make_storms_30d.py`` joins its three.

Not a measurement: two moderate storms (peak Hs 1.4 and 1.6 m, Tp 9 and 10 s, 48 h; currents 0.2 m/s,
surges 0.1 m) over a calm background (Hs 0.4 m, current 0.05 m/s) that is below the threshold of motion
of 0.2 mm sand in 12 m of water, so the pit infills between them while the mine keeps its burial.

    python benchmarks/make_two_storms.py [OUT.csv]
"""

import sys

from make_storms_30d import join_storms

from mineburial.io.forcing import Forcing, write_csv
from mineburial.systems.mine.processes.scour import SHIPPED

#: (peak_hs m, peak_tp s, duration_h, peak_h within the piece, current m/s, surge m)
STORMS = (
    (1.4, 9.0, 48.0, 72.0, 0.2, 0.1),
    (1.6, 10.0, 48.0, 72.0, 0.2, 0.1),
)


def two_storms() -> Forcing:
    """The two storms' pieces joined as make_storms_30d.py joins its three (:func:`join_storms`)."""
    return join_storms(STORMS, "two_storms (two synthetic storms)")


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else SHIPPED / "two_storms.csv"
    comment = (
        "Two similar synthetic winter storms ten days apart for mineburial (not a measurement), written by\n"
        "  python benchmarks/make_two_storms.py: each mineburial.io.forcing.storm_series(peak_hs, peak_tp,\n"
        "  duration_h, peak_h, current, surge, background_hs=0.4, background_current=0.05, wave_from=270,\n"
        "  current_to=0, total_h=240) over its own 10 days, joined end to end; storms\n"
        "  (peak_hs m, peak_tp s, duration_h, peak_h, current m/s, surge m):\n"
        + "".join(f"  {s}\n" for s in STORMS)
        + "hourly from 2003-01-05; waves from the west, current towards the north; level above the datum"
    )
    print(write_csv(two_storms(), out, comment))
