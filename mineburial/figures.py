"""Figures of a run's results (issue 20): the burial over time of a run with a ``[scour]`` section.

:func:`check_lead_time_plot` checks before computing that the figure can be drawn (the scenario
has the section; matplotlib, the image type, the path: :func:`mineburial.maps.check_plot_path`);
:func:`plot_lead_time` draws it from the run's Dataset (or the NetCDF it wrote) after the run.
matplotlib is the optional extra ``plot``, imported only when drawing (docs/scour.md, "Figure:
burial against lead time").
"""

from __future__ import annotations

import xarray as xr

from mineburial.ensembles.store import RunError
from mineburial.io import variables as V
from mineburial.maps import check_plot_path
from mineburial.validation.compare import pyplot, save_figure

#: the lead-time figure's lines of the burial classes: viridis at 0, 0.25, 0.5, 0.75 and a darker
#: yellow for the last (viridis' own end is too pale on white); colour-blind safe, and legible as
#: lines, which the map's pale YlOrRd class fills are not
CLASS_LINE_COLOURS = ("#440154", "#3b528b", "#21918c", "#5ec962", "#e6b400")


def check_lead_time_plot(path, spec, output=None, inputs=()):
    """Before a run computes anything: ``--plot`` needs a ``[scour]`` section (the figure is the
    burial against lead time) and a path matplotlib can draw to (not the run's output)."""
    if getattr(spec, "scour", None) is None:
        raise RunError(
            f"--plot '{path}': the figure draws the burial against lead time of a scenario with a "
            "[scour] section, and this scenario has none (docs/scour.md; example: mineburial example "
            "scour_storm)"
        )
    return check_plot_path(path, output, inputs)


def lead_time_series(ds: xr.Dataset) -> dict:
    """What the figure draws, as arrays over ``lead_time`` [d]: the class probabilities and their
    Wilson bounds (lead, class), the share of drops flagged mobile by then, and the 5, 50 and
    95 % quantiles of the burial by volume [%]."""
    q = ds["scour_burial_volume_quantile"].sel(quantile=[0.05, 0.5, 0.95]).values
    return {
        "lead": ds["lead_time"].values,
        "p": ds["scour_burial_class_probability"].values,
        "lower": ds["scour_burial_class_probability_lower"].values,
        "upper": ds["scour_burial_class_probability_upper"].values,
        "mobile": ds["scour_mobile_fraction_by_lead_time"].values,
        "volume_q05": q[:, 0],
        "volume_median": q[:, 1],
        "volume_q95": q[:, 2],
    }


def plot_lead_time(ds: xr.Dataset, path, *, scenario: str, dpi: int = 100) -> None:
    """Two panels against lead time: P(burial class) with 95 % Wilson bands and the share of
    drops flagged mobile; the median and 5-95 % band of the burial by volume."""
    s = lead_time_series(ds)
    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    basis = ds["scour_burial_class_probability"].attrs.get("burial_class_basis", "burial_volume")
    for c, (label, colour) in enumerate(zip(V.BURIAL_CLASS_NAMES, CLASS_LINE_COLOURS)):
        ax1.fill_between(s["lead"], s["lower"][:, c], s["upper"][:, c], color=colour, alpha=0.2, lw=0)
        ax1.plot(s["lead"], s["p"][:, c], "o-", color=colour, ms=3.5, label=f"class {label}")
    ax1.plot(s["lead"], s["mobile"], "k--", lw=1.2, label="flagged mobile (may roll)")
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
    n = int(ds.attrs.get("scour_n_in_statistics", 0))
    total = int(ds.attrs.get("n_drops", ds.sizes.get("realization", n)))
    fig.suptitle(f"{scenario}: burial after impact and scour, n = {n} drops in the statistics (of {total})")
    try:
        save_figure(fig, path, dpi=dpi)
    finally:
        plt.close(fig)
