"""The system registry: the systems an ensemble scenario may name with its top-level
``system`` key, each declared once as a :class:`System`.

A system is what one realization of an ensemble simulates: the falling mine
(``"mine"``, the default: :mod:`mineburial.systems.mine.ensemble`) or seed 004's restraining
system (``"restraint"``: :mod:`mineburial.systems.restraint.ensemble`). Its :class:`System`
names the functions by which the generic layer reaches it: the scenario reader
(:func:`mineburial.ensembles.engine.load_ensemble`), the run driver and its checks
(:mod:`mineburial.ensembles.runner`), the chunk store and the dask layer, which hand on
the system's ensemble spec, and the command line (``mineburial run`` and ``mineburial
example``). None of them names a system; adding one is a module with these functions and
one entry in :data:`SYSTEMS` (docs/design.md, "Adding a system").

A spec of a system carries the system's name in its class attribute ``system``
(:func:`of` finds the system of a spec), the width of a chunk's ``summary`` in
``summary_width`` and what one realization is called in ``unit`` ("drops", "cases").
"""

from __future__ import annotations

import dataclasses
import pathlib
from collections.abc import Callable

from mineburial.errors import ScenarioError, unknown_name_message
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import figures
from mineburial.systems.restraint import ensemble as restraint

__all__ = ["System", "SYSTEMS", "DEFAULT", "get", "of", "is_spec", "names", "example"]


@dataclasses.dataclass(frozen=True)
class System:
    """One system of an ensemble: its name and the functions the generic layer calls."""

    #: the value of the scenario's top-level ``system`` key
    name: str
    #: ``load(raw, overrides, base_dir) -> spec``: the ensemble spec from the parsed scenario
    #: (without its ``system`` key) and the settings given by the caller (None where not given)
    load: Callable
    #: ``compute_chunk(spec, start, stop) -> dict``: the per-realization arrays of a chunk
    #: (``summary``, ``status``, ``input:<path>``, ``invalid_inputs``, ``start``, ``stop``)
    compute_chunk: Callable
    #: ``dataset(spec, chunks) -> xarray.Dataset``: the output file from the chunks in order
    dataset: Callable
    #: ``summarize(ds, elapsed, output) -> str``: the report ``mineburial run`` prints
    summarize: Callable
    #: ``bytes_a_realization(spec) -> int``: memory the per-realization values of a run take
    bytes_a_realization: Callable
    #: ``warn_run(spec) -> None``: warnings before computing (one line each, on stderr)
    warn_run: Callable
    #: ``example_names() -> tuple``: the examples ``mineburial example`` writes for this system
    example_names: Callable
    #: ``example(name) -> (what it is, text)``: one of them
    example: Callable
    #: ``warm_up_spec() -> spec``: a one-realization ensemble whose chunk compiles the
    #: system's kernels on a dask worker before its tasks arrive (None: none)
    warm_up_spec: Callable | None = None
    #: the scenario file :func:`~mineburial.ensembles.engine.load_ensemble` reads when given
    #: none (used of the default system only; None: the system has none)
    default_scenario: pathlib.Path | None = None
    #: ``check_plot(path, spec, output, inputs) -> None``: before a run computes, refuses a
    #: ``mineburial run --plot`` the system cannot draw (RunError) or a path it cannot draw to
    check_plot: Callable | None = None
    #: ``plot(ds, path, scenario=) -> None``: the figure of ``mineburial run --plot``
    plot: Callable | None = None
    #: ``check_accuracy(spec, chunks, progress=None) -> dict``: global attributes of a numerical
    #: self-check of the finished run, made after its chunks are in (``progress``: None or the
    #: runner's Progress class, for its progress lines; None: the system has no check)
    check_accuracy: Callable | None = None


SYSTEMS = {
    system.name: system
    for system in (
        System(
            name=mine.SYSTEM,
            load=mine.load,
            compute_chunk=mine.compute_chunk,
            dataset=mine.dataset,
            summarize=mine.summarize,
            bytes_a_realization=mine.bytes_a_drop,
            warn_run=mine.warn_run,
            example_names=mine.example_names,
            example=mine.example,
            warm_up_spec=mine.warm_up_spec,
            default_scenario=mine.DEFAULT_SCENARIO,
            check_plot=figures.check_lead_time_plot,  # the lead-time figure of a post-impact process
            plot=figures.plot_lead_time,
            check_accuracy=mine.check_accuracy,
        ),
        System(
            name=restraint.SYSTEM,
            load=restraint.load,
            compute_chunk=restraint.compute_chunk,
            dataset=restraint.dataset,
            summarize=restraint.summarize,
            bytes_a_realization=restraint.bytes_a_case,
            warn_run=restraint.warn_run,
            example_names=restraint.example_names,
            example=restraint.example,
            # it has no lead times: the lead-time figure's check refuses --plot, naming [scour]
            check_plot=figures.check_lead_time_plot,
        ),
    )
}
#: the system of a scenario without a ``system`` key
DEFAULT = mine.SYSTEM


def names() -> tuple[str, ...]:
    """The names of the registered systems, the default first."""
    return tuple(SYSTEMS)


def get(name: str) -> System:
    """The system ``name``, or a ScenarioError with a did-you-mean suggestion."""
    system = SYSTEMS.get(name) if isinstance(name, str) else None
    if system is None:
        raise ScenarioError(unknown_name_message("system", name, SYSTEMS))
    return system


def of(spec) -> System:
    """The system of an ensemble spec (its class attribute ``system``)."""
    return SYSTEMS[spec.system]


def is_spec(obj) -> bool:
    """Whether ``obj`` is an ensemble spec of a registered system (its class attribute
    ``system`` names one, and it keeps the scenario it was read from in ``raw``)."""
    return getattr(type(obj), "system", None) in SYSTEMS and hasattr(obj, "raw")


def example(name: str) -> tuple[str, str]:
    """(what it is, text) of the example ``name`` of any system, or a ScenarioError with a
    did-you-mean suggestion among the examples of every system."""
    for system in SYSTEMS.values():
        if name in system.example_names():
            return system.example(name)
    every = [n for system in SYSTEMS.values() for n in system.example_names()]
    raise ScenarioError(unknown_name_message("example scenario", name, every))
