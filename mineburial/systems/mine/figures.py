"""Figures of a run's results (issue 20): the burial over time of a run with a post-impact process
that reports at lead times (``[scour]``; :mod:`mineburial.systems.mine.processes.registry`).

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

import pathlib

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.ensembles.store import RunError, check_output_path, same_file
from mineburial.io import variables as V
from mineburial.io.files import atomic_path
from mineburial.systems.mine.processes import registry as processes

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
        # the share that would move at each lead time (the process's mobility criterion, issue 33)
        "moves": ds[x + "mobile_probability"].values if x + "mobile_probability" in ds else None,
        "volume_q05": q[:, 0],
        "volume_median": q[:, 1],
        "volume_q95": q[:, 2],
    }


def process_panels(ds: xr.Dataset) -> list:
    """The panels the registered post-impact processes whose variables ``ds`` holds add to the
    lead-time figure (:meth:`~mineburial.systems.mine.processes.registry.Process.figure_panels`: scour's
    forcing), in registration order: callables ``draw(ax, lead_days)``."""
    names = [str(k) for k in ds.variables]
    return [
        draw
        for section, process in processes.PROCESSES.items()
        if any(k.startswith(f"{section}_") for k in names)
        for draw in process.figure_panels(ds)
    ]


def plot_lead_time(ds: xr.Dataset, path, *, scenario: str, dpi: int = 100) -> None:
    """Two panels against lead time: P(burial class) with 95 % Wilson bands and the share of
    drops flagged mobile; the median and 5-95 % band of the burial by volume. Above them, each on
    a row of its own over the same days, the panels the processes add (:func:`process_panels`;
    scour's: the forcing, Hs (and Tp) and the current speed, each record held until the next, as
    the stage reads it, when the run's forcing can be read again)."""
    section = lead_time_section(ds)
    s = lead_time_series(ds, section)
    panels = process_panels(ds)
    plt = pyplot()
    if not panels:
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    else:
        k = len(panels)
        fig = plt.figure(figsize=(11, 4.2 + 2.4 * k), constrained_layout=True)
        grid = fig.add_gridspec(k + 1, 2, height_ratios=(1.0,) * k + (1.9,))
        ax0 = fig.add_subplot(grid[0, :])
        above = [ax0] + [fig.add_subplot(grid[m, :], sharex=ax0) for m in range(1, k)]
        ax1 = fig.add_subplot(grid[k, 0], sharex=ax0)
        ax2 = fig.add_subplot(grid[k, 1], sharex=ax0)
        for ax, draw in zip(above, panels):
            draw(ax, s["lead"])
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
