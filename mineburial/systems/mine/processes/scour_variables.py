"""The output variables of the scour stage (``[scour]``, :mod:`mineburial.systems.mine.processes.scour`): the
process's own declarations (issue 33 item 1), moved here unchanged from
:mod:`mineburial.io.variables`, which declares the mine ensemble's and knows a post-impact
process's variables only as that process registers them
(:func:`mineburial.io.variables.register_process_variables`).

:data:`DECLARED` is what :meth:`mineburial.systems.mine.processes.scour.ScourProcess.variables` gives the
process registry. It is also registered here, when this module is first imported: the stage's
statistics (:func:`mineburial.systems.mine.statistics.scour_statistics`) and its Dataset look the
declarations up through :func:`mineburial.io.variables.variable`, and every code path that reaches
them imports this module first, whether or not the process registry has been imported (a dask
worker, the catalogue of docs/notes/output.md).
"""

from __future__ import annotations

from mineburial.io.variables import NO_FILL as _NO_FILL
from mineburial.io.variables import SUMMARY_OUTPUTS, ProcessVariables, Variable, register_process_variables
from mineburial.io.variables import flag_attrs as _flag_attrs

#: the scenario section, the prefix of the variables below
SECTION = "scour"

#: burial measures the scour stage reports at each lead time (columns of the impact summary)
SCOUR_MEASURES = ("penetration_depth", "burial_volume", "burial_height", "burial_area", "height_proud")
#: status codes of the scour stage (mineburial.kernels.mine.scour_batch.STATUS_NAMES)
SCOUR_STATUS_NAMES = ("ok", "invalid_parameter", "invalid_forcing", "beyond_forcing", "not_run")
_SCOUR_BASIS = "over the drops whose scour stage ran (scour_status ok) and a finite value"


def _scour_coordinates() -> list[Variable]:
    """The scour stage's ``lead_time`` and ``burial_level`` coordinates and its status codes, their
    count and the status of each drop."""
    return [
        Variable(
            "lead_time",
            ("lead_time",),
            "float64",
            "days",
            "time after the start of the forcing",
            "Lead time of the scour stage: time after the first record of the forcing, when the "
            "mines are taken to lie on the bed with their impact burial.",
            standard_name="forecast_period",
            attrs={"axis": "T"},
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "forecast_reference_time",
            (),
            "float64",
            "seconds since 1970-01-01 00:00:00",
            "date of lead time 0",
            "Calendar date (UTC) of lead time 0: the forcing's first record, or the start of every "
            "drop's window of it (scour.window_days at a fixed scour.window_position). Absent when the "
            "forcing has no dates or the drops' windows start at different times.",
            standard_name="forecast_reference_time",
            attrs={"calendar": "proleptic_gregorian"},
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "burial_level",
            ("burial_level",),
            "float64",
            "1",
            "burial level B/D",
            "Burial of the lowest point as a fraction of the mine diameter (of its height for a body "
            "standing on its base: a frustum, docs/scour.md) whose time to reach is reported.",
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "scour_status_code",
            ("scour_status_code",),
            "int8",
            None,
            "scour-stage status code",
            "Status codes of the scour stage (mineburial.kernels.mine.scour_batch.STATUS_NAMES).",
            attrs=_flag_attrs(range(len(SCOUR_STATUS_NAMES)), SCOUR_STATUS_NAMES),
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "scour_status_count",
            ("scour_status_code",),
            "int64",
            "1",
            "number of drops with the scour-stage status",
            "Number of drops of the ensemble with each scour-stage status code.",
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "scour_status",
            ("realization",),
            "int8",
            None,
            "scour-stage status",
            "Status of the drop's scour stage; not_run: the impact phase did not leave it at rest.",
            attrs=_flag_attrs(range(len(SCOUR_STATUS_NAMES)), SCOUR_STATUS_NAMES),
            fill_value=-127,
        ),
    ]


def _scour_time_variables() -> list[Variable]:
    """When the mines of the scour stage are first flagged mobile and reach the burial levels."""
    return [
        Variable(
            "scour_mobile_fraction",
            (),
            "float64",
            "1",
            "share of drops flagged mobile",
            "Fraction of the drops whose scour stage ran in which the object mobility parameter passed "
            "the threshold of Rennie et al. (2017) at some time of the forcing: the mine may roll or "
            "migrate (an upper bound; the burial is not changed, docs/scour.md).",
            group="statistics",
        ),
        Variable(
            "scour_not_modelled_fraction",
            (),
            "float64",
            "1",
            "share of drops where no post-impact process is modelled",
            "Fraction of the drops whose scour stage ran that lie on a cohesive bed (mud, clay; "
            "scour.cohesive or the sediment class): no scour law holds there, the stage keeps the "
            "impact burial at every lead time. Not a prediction that the mine stays unburied: 1 means "
            "not modelled (maps hatch such cells, docs/maps.md).",
            group="statistics",
        ),
        Variable(
            "scour_mobile_fraction_by_lead_time",
            ("lead_time",),
            "float64",
            "1",
            "share of drops flagged mobile by the lead time",
            "Fraction of the drops whose scour stage ran that were first flagged mobile (Rennie et al. "
            "2017 threshold) at or before each lead time; at the forcing's end it is scour_mobile_fraction.",
            group="statistics",
        ),
        Variable(
            "scour_mobile_probability",
            ("lead_time",),
            "float64",
            "1",
            "share of drops that would move at the lead time",
            "Fraction of the drops whose scour stage ran whose mine would move at each lead time: the "
            "object mobility parameter of the forcing then above the criterion of scour.mobility, with "
            "the burial then (`proud`: Rennie et al. 2017 on a rigid bottom while B/D <= 0.1; `pocket`: "
            "raised by the burial, docs/scour.md, Mobility). What follows is not modelled but split: "
            "a mine in an open pit rolls back into it, its burial unchanged "
            "(scour_mobile_into_pit_probability), one on a flat bed may migrate away "
            "(scour_mobile_away_probability).",
            group="statistics",
        ),
        Variable(
            "scour_mobile_into_pit_probability",
            ("lead_time",),
            "float64",
            "1",
            "share of drops that would move and roll back into their pit at the lead time",
            "Fraction of the drops whose scour stage ran whose mine would move at the lead time "
            "(scour_mobile_probability) while it lies in an open scour pit, the pit at least 0.1 of its "
            "diameter deep (scour.PIT_OPEN, our choice): it rolls back into the pit, its burial unchanged "
            "(mines that fell into their own scour pits: Traykovski et al. 2007; objects rolling into "
            "their scour holes: Rennie et al. 2017; docs/scour.md, Mobility).",
            group="statistics",
        ),
        Variable(
            "scour_mobile_away_probability",
            ("lead_time",),
            "float64",
            "1",
            "share of drops that would move off a flat bed at the lead time",
            "Fraction of the drops whose scour stage ran whose mine would move at the lead time "
            "(scour_mobile_probability) with no open scour pit beside it (pit shallower than 0.1 of "
            "its diameter): it may migrate away, out of the model's reach (Rennie et al. 2017); "
            "scour_mobile_probability less scour_mobile_into_pit_probability.",
            group="statistics",
        ),
        Variable(
            "scour_pit_depth_mean",
            ("lead_time",),
            "float64",
            "m",
            "mean depth of the scour pit beside the mine",
            "Arithmetic mean of scour_pit_depth over the drops whose scour stage ran (scour_status ok). "
            "Under scour.burial_law = rennie the one state is both pit and burial.",
            group="statistics",
        ),
        Variable(
            "scour_pit_depth",
            ("realization", "lead_time"),
            "float64",
            "m",
            "depth of the scour pit beside the mine",
            "Depth of the scour pit beside the mine below the far-field bed at each lead time "
            "(scour.burial_law = scour_settle: a state of its own, which infills in calm spells while "
            "the mine's burial stays; rennie: the burial itself); NaN where the stage did not run.",
        ),
        Variable(
            "scour_mobile_at_lead_time",
            ("realization", "lead_time"),
            "float64",
            "1",
            "whether the mine would move at the lead time",
            "1 where the mine would move at the lead time (criterion of scour.mobility with the forcing "
            "and the burial then), else 0; NaN where the stage did not run.",
        ),
        Variable(
            "scour_mobile_time",
            ("realization",),
            "float64",
            "days",
            "first time the mine is flagged mobile",
            "Time after the start of the forcing at which the mobility threshold of Rennie et al. (2017) "
            "was first passed; inf: never.",
        ),
        Variable(
            "scour_time_to_level",
            ("realization", "burial_level"),
            "float64",
            "days",
            "time to reach the burial level",
            "Time after the start of the forcing at which the burial B/D (B/h for a body standing on its "
            "base) first reaches the level; 0: the "
            "impact burial is there already; inf: not within the forcing.",
        ),
        Variable(
            "scour_time_to_level_quantile",
            ("burial_level", "quantile"),
            "float64",
            "days",
            "quantile of the time to reach the burial level",
            f"Quantiles (numpy linear) of scour_time_to_level {_SCOUR_BASIS}; inf where that share of "
            "the drops does not reach the level within the forcing.",
            group="statistics",
        ),
        Variable(
            "scour_level_reached_fraction",
            ("burial_level",),
            "float64",
            "1",
            "share of drops reaching the burial level",
            f"Fraction of the drops {_SCOUR_BASIS} that reach the level within the forcing.",
            group="statistics",
        ),
    ]


def _scour_class_variables() -> list[Variable]:
    """The burial-class counts and probabilities (with the Wilson interval) at each lead time."""
    out = [
        Variable(
            "scour_burial_class_count",
            ("lead_time", "impact_burial_class"),
            "int64",
            "1",
            "number of drops in the burial class at the lead time",
            f"Number of drops {_SCOUR_BASIS} in each burial class (the impact classes) at each lead time.",
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            "scour_burial_class_probability",
            ("lead_time", "impact_burial_class"),
            "float64",
            "1",
            "probability of the burial class at the lead time",
            f"Fraction k/n of the drops {_SCOUR_BASIS} in each burial class at each lead time.",
            group="statistics",
            attrs={
                "ancillary_variables": "scour_burial_class_probability_lower "
                "scour_burial_class_probability_upper scour_burial_class_count"
            },
        ),
    ]
    for side in ("lower", "upper"):
        out.append(
            Variable(
                f"scour_burial_class_probability_{side}",
                ("lead_time", "impact_burial_class"),
                "float64",
                "1",
                f"{side} confidence limit of the burial-class probability at the lead time",
                f"{side.capitalize()} limit of the Wilson score interval (Wilson 1927) at the "
                "confidence level given by the attribute confidence_level.",
                group="statistics",
            )
        )
    return out


#: why the measures at lead time 0 differ from the impact's (issue 33): the stage lays the mine flat
_LAY_FLAT = (
    "The scour stage lays the mine flat: from lead time 0 it is the same cylinder lying horizontal with "
    "the same fraction of its volume below the bed as at its impact rest attitude (the scour laws are "
    "those of a lying cylinder; docs/scour.md, Rest attitude). Burial by volume at lead 0 equals the "
    "impact's; height proud, burial by height and area, and penetration depth (the lowest point) of a "
    "mine that came to rest tilted or nose-down differ from the impact's (a mine standing on its "
    'nose is much less proud once lying). Under scour.rest_attitude = "impact" the stage keeps the '
    "impact's attitude instead (scour_tilt): every measure at lead 0 equals the impact's."
)


def _scour_measure_variables() -> list[Variable]:
    """Each burial measure after the scour stage: per drop at each lead time, its mean and quantiles."""
    lt = ("lead_time",)
    out = []
    for name in SCOUR_MEASURES:
        o = SUMMARY_OUTPUTS[name]
        out.append(
            Variable(
                f"scour_{name}",
                ("realization", "lead_time"),
                "float64",
                o.units,
                f"{o.long_name} at the lead time",
                f"{o.description} After the scour stage, at each lead time; NaN where the stage did "
                f"not run (scour_status). {_LAY_FLAT}",
            )
        )
        out.append(
            Variable(
                f"scour_{name}_mean",
                lt,
                "float64",
                o.units,
                f"mean of {o.long_name} at the lead time",
                f"Arithmetic mean of scour_{name} {_SCOUR_BASIS}. {_LAY_FLAT}",
                attrs={"cell_methods": "realization: mean"},
                group="statistics",
            )
        )
        out.append(
            Variable(
                f"scour_{name}_quantile",
                ("lead_time", "quantile"),
                "float64",
                o.units,
                f"quantile of {o.long_name} at the lead time",
                f"Quantiles (numpy linear, Hyndman & Fan type 7) of scour_{name} {_SCOUR_BASIS}. {_LAY_FLAT}",
                group="statistics",
            )
        )
    return out


# --- the tilt state of scour.rest_attitude = "impact" (issue 33 item 2; docs/scour.md, Tilt) --------
#: the tilt's statistics: in a run's file only (maps do not carry them)
SCOUR_TILT_STATISTICS = ("scour_tilt_mean", "scour_tilt_quantile")
_TILT = (
    "Tilt of the mine's axis to the horizontal after the scour stage under scour.rest_attitude = "
    '"impact" (absent under "flat", where the mine lies level): from the impact\'s rest attitude at '
    "lead time 0, levelling as the scour pit undermines the higher end and 0 once the mine lies in its "
    "pit (docs/scour.md, Tilt)."
)


def _scour_tilt_variables() -> list[Variable]:
    """The tilt state per drop at each lead time, its mean and quantiles."""
    return [
        Variable(
            "scour_tilt",
            ("realization", "lead_time"),
            "float64",
            "degree",
            "tilt of the mine's axis at the lead time",
            f"{_TILT} NaN where the stage did not run (scour_status).",
        ),
        Variable(
            "scour_tilt_mean",
            ("lead_time",),
            "float64",
            "degree",
            "mean tilt of the mine's axis at the lead time",
            f"Arithmetic mean of scour_tilt {_SCOUR_BASIS}. {_TILT}",
            attrs={"cell_methods": "realization: mean"},
            group="statistics",
        ),
        Variable(
            "scour_tilt_quantile",
            ("lead_time", "quantile"),
            "float64",
            "degree",
            "quantile of the tilt of the mine's axis at the lead time",
            f"Quantiles (numpy linear, Hyndman & Fan type 7) of scour_tilt {_SCOUR_BASIS}. {_TILT}",
            group="statistics",
        ),
    ]


def _scour_variables() -> list[Variable]:
    """The variables of the scour stage: the ``lead_time`` and ``burial_level`` coordinates, the
    statistics of each burial measure at each lead time, the burial-class probabilities per lead
    time, the times to reach the burial levels, the share of drops flagged mobile; per drop the
    measures, times and statuses."""
    return [
        *_scour_coordinates(),
        *_scour_time_variables(),
        *_scour_class_variables(),
        *_scour_measure_variables(),
        *_scour_tilt_variables(),
    ]


#: appended to the description of each of the stage's statistics on a map (per cell)
_PER_CELL_SCOUR = (
    " Per cell, over the drops of the cell's ensemble whose scour stage ran (scour_status "
    "ok); NaN on land or where no drop's stage ran."
)

#: the stage's declarations: the variables of a run's file, in order; the coordinates a map
#: shares with its cells' template run; the per-cell note and quality variables of a map
DECLARED = ProcessVariables(
    variables=tuple(_scour_variables()),
    map_coordinates=("lead_time", "burial_level", "scour_status_code", "forecast_reference_time"),
    map_note=_PER_CELL_SCOUR,
    map_quality=("scour_status_count",),
    run_only=SCOUR_TILT_STATISTICS,
)
register_process_variables(SECTION, DECLARED)
