"""The scour stage's panel of the run's lead-time figure
(:func:`mineburial.systems.mine.figures.plot_lead_time`): the forcing (Hs, Tp, the current) over the lead
times, above the burial panels, when the run's output records a forcing that can be read again. Moved from
:mod:`mineburial.systems.mine.figures`, which draws it through the process protocol
(:meth:`mineburial.systems.mine.processes.registry.Process.figure_panels`).
"""

from __future__ import annotations

import hashlib
import json
import pathlib

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.io import forcing as fio


def panels(ds, section: str = "scour") -> list:
    """The panels the stage adds to the lead-time figure of ``ds``: its forcing
    (:func:`forcing_series`, drawn by :func:`draw_forcing`) when it can be read again, else none."""
    f = forcing_series(ds, section)
    return [] if f is None else [lambda ax, lead: draw_forcing(ax, f, lead)]


def forcing_series(ds: xr.Dataset, section: str = "scour"):
    """The run's forcing as the figure's top panel draws it, from what the output records: the
    file (``forcing_file``, read again only while its ``forcing_sha256`` still matches) or the
    storm (``forcing_storm``): a dict of ``days`` after the first record, ``hs`` [m], ``tp`` [s]
    and ``current`` [m/s] as given (before the sampled Hs factor), and ``window_days`` (each
    drop's window in the process ``section``'s resolved record, or None); None when it cannot be
    had (nothing recorded, the file gone or changed)."""
    try:
        if "forcing_file" in ds.attrs:
            path = pathlib.Path(str(ds.attrs["forcing_file"]))
            data = path.read_bytes()
            if hashlib.sha256(data).hexdigest() != ds.attrs.get("forcing_sha256"):
                return None
            f = fio.load_forcing(path)
        elif "forcing_storm" in ds.attrs:
            f = fio.storm_series(**json.loads(str(ds.attrs["forcing_storm"])))
        else:
            return None
    except (OSError, ValueError):
        return None
    try:
        window = json.loads(str(ds.attrs.get("scenario", "{}"))).get(section, {}).get("window_days")
    except ValueError:
        window = None
    return {
        "days": f.time / 86400.0,
        "hs": f.hs,
        "tp": f.tp,
        "current": f.current_speed,
        "window_days": window,
    }


def draw_forcing(ax, f, lead) -> None:
    """The forcing panel: Hs and the current speed (right axis) as steps (each record held until
    the next), over the lead times' span, Tp written beside the Hs peak."""
    end = float(np.max(lead)) if len(lead) else float(f["days"][-1])
    keep = f["days"] <= end + 1e-9
    keep[: np.searchsorted(f["days"], end, side="right") + 1] = True  # the record in effect at the end
    d, hs, uc = f["days"][keep], f["hs"][keep], f["current"][keep]
    ax.step(d, hs, where="post", color="C3", lw=1.4, label="Hs (as given)")
    ax.set_ylabel("Hs (m)", color="C3")
    ax.set_ylim(0.0, max(float(np.max(hs)) * 1.15, 0.1))
    k = int(np.argmax(hs))
    ax.annotate(f"peak Hs {hs[k]:.2f} m, Tp {f['tp'][keep][k]:.1f} s", (d[k], hs[k]), xytext=(6, -12),
                textcoords="offset points", fontsize=8, color="C3")  # fmt: skip
    ax2 = ax.twinx()
    ax2.step(d, uc, where="post", color="C0", lw=1.2, ls="--", label="current speed")
    ax2.set_ylabel("current (m/s)", color="C0")
    ax2.set_ylim(0.0, max(float(np.max(uc)) * 1.15, 0.05))
    ax.set_xlim(-0.02 * end, end * 1.02 if end > 0 else 1.0)
    what = "forcing (each record held until the next; before the sampled Hs factor)"
    if f["window_days"] is not None:
        what += "; each drop sees its own window of it: days here are from the series' first record"
    ax.set_title(what, fontsize=10)
    ax.grid(alpha=0.3)
    ax.tick_params(labelbottom=True)
