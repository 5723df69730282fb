"""Figures of a run's results (issue 20): the burial over time of a run with a post-impact process
that reports at lead times (``[scour]``; :mod:`mineburial.ensembles.processes`).

:func:`check_lead_time_plot` checks before computing that the figure can be drawn (the scenario
has such a section; matplotlib, the image type, the path: :func:`check_plot_path`);
:func:`plot_lead_time` draws it from the run's Dataset (or the NetCDF it wrote) after the run.
matplotlib is the optional extra ``plot``, imported only when drawing (docs/scour.md, "Figure:
burial against lead time").

It is also the one home of what every command that draws shares (``run``, ``map``, ``compare``,
``sensitivity``): matplotlib imported on demand with a one-line error when it is missing
(:func:`figure_class`, :func:`pyplot`), the check of a ``--plot`` path before computing
(:func:`check_plot_path`) and the atomic save (:func:`save_figure`). It imports no command module,
so each of them can import it (tests/test_imports.py).
"""

from __future__ import annotations

import hashlib
import json
import pathlib

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.ensembles.store import RunError, check_output_path, same_file
from mineburial.io import variables as V
from mineburial.io.files import atomic_path

#: the one line when matplotlib is missing
NO_MATPLOTLIB = (
    "needs matplotlib, an optional dependency: pip install 'mineburial[plot]' (or pip install matplotlib)"
)


def figure_class(what: str = "--plot"):
    """matplotlib's Figure class (no pyplot: the caller's backend and state are untouched), or a
    one-line RunError naming ``what`` needs it."""
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise RunError(f"{what} {NO_MATPLOTLIB}") from None
    return Figure


def pyplot(what: str = "--plot"):
    """matplotlib.pyplot on the Agg backend, or a one-line RunError when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        raise RunError(f"{what} {NO_MATPLOTLIB}") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def check_plot_path(path, output=None, inputs=(), what: str = "the command's output") -> pathlib.Path:
    """Check before computing that a figure can be drawn to ``path``: matplotlib is there, it can
    write the file type of the extension, the folder exists, and the path is neither the command's
    output (``what`` names it in the message) nor one of its inputs."""
    Figure = figure_class()
    path = pathlib.Path(path)
    if output is not None and same_file(path, pathlib.Path(output)):
        raise RunError(f"--plot '{path}' is also {what} (-o); choose another path")
    types = Figure().canvas.get_supported_filetypes()
    ext = path.suffix.lower().lstrip(".")
    if ext not in types:
        raise RunError(
            f"--plot '{path}': unsupported image type "
            f"'{path.suffix or '(no extension)'}'; use one of " + ", ".join(f".{t}" for t in sorted(types))
        )
    return check_output_path(path, inputs, "--plot")


def save_figure(fig, path, **kw) -> None:
    """Draw ``fig`` to ``path`` atomically (:func:`mineburial.io.files.atomic_path`: a regular file
    or nothing there, the previous image kept if drawing fails), in the image type of its extension."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=pathlib.Path(path).suffix.lstrip(".").lower(), **kw)


#: the lead-time figure's lines of the burial classes: viridis at 0, 0.25, 0.5, 0.75 and a darker
#: yellow for the last (viridis' own end is too pale on white); colour-blind safe, and legible as
#: lines, which the map's pale YlOrRd class fills are not
CLASS_LINE_COLOURS = ("#440154", "#3b528b", "#21918c", "#5ec962", "#e6b400")


def check_lead_time_plot(path, spec, output=None, inputs=()):
    """Before a run computes anything: ``--plot`` needs a post-impact process that reports at lead
    times (``[scour]``: the figure is the burial against lead time) and a path matplotlib can draw
    to (not the run's output)."""
    if not getattr(spec, "lead_time_sections", tuple)():
        raise RunError(
            f"--plot '{path}': the figure draws the burial against lead time of a scenario with a "
            "[scour] section, and this scenario has none (docs/scour.md; example: mineburial example "
            "scour_storm)"
        )
    return check_plot_path(path, output, inputs, "the run's output")


def lead_time_section(ds: xr.Dataset) -> str:
    """The section of the post-impact process whose burial over lead time ``ds`` holds (its
    variables ``<section>_burial_class_probability``, ...: the first such, ``scour``)."""
    suffix = "_burial_class_probability"
    found = [str(k)[: -len(suffix)] for k in ds.data_vars if str(k).endswith(suffix) and str(k) != suffix[1:]]
    if not found:
        raise RunError("the Dataset holds no burial against lead time of a post-impact process ([scour])")
    return found[0]


def lead_time_series(ds: xr.Dataset, section: str | None = None) -> dict:
    """What the figure draws, as arrays over ``lead_time`` [d]: the class probabilities and their
    Wilson bounds (lead, class), the share of drops flagged mobile by then and (``moves``) the share
    that would move at the lead time, and the 5, 50 and 95 % quantiles of the burial by volume [%],
    of the process ``section`` (None: :func:`lead_time_section`)."""
    x = (section or lead_time_section(ds)) + "_"
    q = ds[x + "burial_volume_quantile"].sel(quantile=[0.05, 0.5, 0.95]).values
    return {
        "lead": ds["lead_time"].values,
        "p": ds[x + "burial_class_probability"].values,
        "lower": ds[x + "burial_class_probability_lower"].values,
        "upper": ds[x + "burial_class_probability_upper"].values,
        "mobile": ds[x + "mobile_fraction_by_lead_time"].values,
        # the share that would move at each lead time (scour.mobility's criterion, issue 33)
        "moves": ds[x + "mobile_probability"].values if x + "mobile_probability" in ds else None,
        "volume_q05": q[:, 0],
        "volume_median": q[:, 1],
        "volume_q95": q[:, 2],
    }


def forcing_series(ds: xr.Dataset, section: str = "scour"):
    """The run's forcing as the figure's top panel draws it, from what the output records: the
    file (``forcing_file``, read again only while its ``forcing_sha256`` still matches) or the
    storm (``forcing_storm``): a dict of ``days`` after the first record, ``hs`` [m], ``tp`` [s]
    and ``current`` [m/s] as given (before the sampled Hs factor), and ``window_days`` (each
    drop's window in the process ``section``'s resolved record, or None); None when it cannot be
    had (nothing recorded, the file gone or changed)."""
    from mineburial.io import forcing as fio  # local import: xarray's reader, only for a figure with forcing

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


def plot_lead_time(ds: xr.Dataset, path, *, scenario: str, dpi: int = 100) -> None:
    """Two panels against lead time: P(burial class) with 95 % Wilson bands and the share of
    drops flagged mobile; the median and 5-95 % band of the burial by volume. Above them, when
    the run's forcing can be read again (:func:`forcing_series`), the forcing over the same days:
    Hs (and Tp) and the current speed, each record held until the next, as the stage reads it."""
    section = lead_time_section(ds)
    s = lead_time_series(ds, section)
    f = forcing_series(ds, section)
    plt = pyplot()
    if f is None:
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    else:
        fig = plt.figure(figsize=(11, 6.6), constrained_layout=True)
        grid = fig.add_gridspec(2, 2, height_ratios=(1.0, 1.9))
        ax0 = fig.add_subplot(grid[0, :])
        ax1 = fig.add_subplot(grid[1, 0], sharex=ax0)
        ax2 = fig.add_subplot(grid[1, 1], sharex=ax0)
        _draw_forcing(ax0, f, s["lead"])
    basis = ds[f"{section}_burial_class_probability"].attrs.get("burial_class_basis", "burial_volume")
    for c, (label, colour) in enumerate(zip(V.BURIAL_CLASS_NAMES, CLASS_LINE_COLOURS)):
        ax1.fill_between(s["lead"], s["lower"][:, c], s["upper"][:, c], color=colour, alpha=0.2, lw=0)
        ax1.plot(s["lead"], s["p"][:, c], "o-", color=colour, ms=3.5, label=f"class {label}")
    ax1.plot(s["lead"], s["mobile"], "k--", lw=1.2, label="flagged mobile by then (may roll)")
    if s["moves"] is not None:
        ax1.plot(s["lead"], s["moves"], "k:", lw=1.5, label=f"would move then ({section}.mobility)")
    ax1.set_ylim(-0.02, 1.02)
    ax1.set_xlabel("lead time after the forcing's start (days)")
    ax1.set_ylabel(f"probability (by {basis.replace('_', ' ')})")
    ax1.set_title("burial classes, 95 % Wilson bands", fontsize=10)
    ax1.legend(fontsize=8, loc="best")
    band = dict(color="C0", alpha=0.25, lw=0, label="5-95 %")
    ax2.fill_between(s["lead"], s["volume_q05"], s["volume_q95"], **band)
    ax2.plot(s["lead"], s["volume_median"], "o-", color="C0", ms=3.5, label="median")
    ax2.set_ylim(-2.0, 102.0)
    ax2.set_xlabel("lead time after the forcing's start (days)")
    ax2.set_ylabel("burial by volume (%)")
    ax2.set_title("burial by volume", fontsize=10)
    ax2.legend(fontsize=8, loc="upper left")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    n = int(ds.attrs.get(f"{section}_n_in_statistics", 0))
    total = int(ds.attrs.get("n_drops", ds.sizes.get("realization", n)))
    title = f"{scenario}: burial after impact and {section}, n = {n} drops in the statistics (of {total})"
    if "forecast_reference_time" in ds.coords:
        value = ds["forecast_reference_time"].values
        if not np.issubdtype(value.dtype, np.datetime64):  # as written: seconds since 1970 (UTC)
            value = np.datetime64("1970-01-01T00:00:00") + np.timedelta64(int(round(float(value))), "s")
        when = np.datetime64(value, "m")
        title += f"\nlead time 0 = {str(when).replace('T', ' ')} UTC"
    fig.suptitle(title)
    try:
        save_figure(fig, path, dpi=dpi)
    finally:
        plt.close(fig)


def _draw_forcing(ax, f, lead) -> None:
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
