"""Post-impact processes of the mine's ensemble (issue 33 item 1): the seam a process plugs into.

A post-impact process runs after each drop's impact phase, on the drops of a chunk, and adds its
own statistics (and per-drop variables) to the run's Dataset. Scour (``[scour]``,
:mod:`mineburial.systems.mine.processes.scour`) is the first. A process is an object with the attributes and
methods of :class:`Process`, registered here under the name of its scenario section
(:data:`PROCESSES`); the mine's ensemble (:mod:`mineburial.systems.mine.ensemble`) knows processes only
through this registry: a scenario with the section gets the process's spec (:meth:`Process.load`),
every chunk runs every active process (:meth:`Process.run_chunk`, after the impact phase) and the
run's identity, resolved scenario, memory estimate, Dataset and printed summary are each the
mine's own plus a loop over the active processes.

A process's numeric inputs are ordinary fields ``<section>.<name>`` of
:data:`mineburial.systems.mine.config.FIELDS` (declared in ``mineburial/systems/mine/scenario_fields.py``):
they are checked, sampled and recorded as every input is, and the mine hands them to the process in ``inputs``
rather than into its own parameter rows (:func:`owns_input`). Its output variables are its own
declarations (:meth:`Process.variables`, names beginning with the section name), added to the
catalogue of :mod:`mineburial.io.variables` when it registers (the run's file, the map's per-cell
family and docs/notes/output.md). A map reaches what a process reads per cell of its grid
(:meth:`Process.cell_inputs`: scour's gridded forcing) and the run's lead-time figure the panels
it adds (:meth:`Process.figure_panels`: scour's forcing) through it too.

A second process (bedform migration, liquefaction) is one module that defines such an object
(``PROCESS``, importing nothing from here), registered by one :func:`register` line at the end of this
module, with its fields in the schema (docs/design.md, "Post-impact processes"); a test registers a
toy one itself, which runs in ``run`` and ``map`` and draws a panel (tests/test_processes.py).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, runtime_checkable

from mineburial.errors import ScenarioError
from mineburial.io import variables as V
from mineburial.systems.mine.processes import scour


@runtime_checkable
class Process(Protocol):
    """What a post-impact process provides (the scour stage:
    :data:`mineburial.systems.mine.processes.scour.PROCESS`).

    ``spec`` below is the process's own resolved section (picklable: chunks run on dask workers);
    ``chunks`` the chunk results in drop order, each a dict holding the process's keys."""

    #: the scenario section (``[scour]``), the prefix of its fields (``scour.<name>``), of its keys in a
    #: chunk's results (``scour:<name>``) and of its output variables (``scour_<name>``)
    section: str

    def load(self, section: Any, *, base_dir, base, template: Mapping, random: Mapping) -> Any:
        """The spec of the scenario's section ``section`` (as given; its sampled fields at a
        representative value), with the mine's resolved ``base`` scenario, the scenario ``template``
        (every distribution at its representative value) and its distributions ``random``; every
        problem a one-line :class:`~mineburial.systems.mine.config.ScenarioError` naming the field."""

    def identity(self, spec) -> bytes:
        """What decides the process's per-drop results beside its sampled inputs (a run's identity,
        :func:`mineburial.ensembles.store.run_identity`: a stored chunk is reused only if it agrees)."""

    def resolved(self, spec) -> dict:
        """The resolved section written into the output's ``scenario`` attribute."""

    def input_files(self, spec) -> tuple:
        """``((path, SHA-256), ...)`` of the files the section reads (its forcing)."""

    def run_chunk(self, spec, P, summary, status, inputs) -> dict:
        """The process's per-drop results of a chunk after its impact phase (keys
        ``<section>:<name>``, stored with the chunk): ``P`` the drops' packed parameters,
        ``summary``/``status`` their impact results, ``inputs`` their sampled inputs by path."""

    def bytes_per_drop(self, spec) -> int:
        """Bytes of the process's per-drop values kept until the statistics are computed."""

    def variables(self) -> V.ProcessVariables:
        """The process's output variables (:class:`mineburial.io.variables.ProcessVariables`: the
        run file's, in order, named ``<section>_*`` but for shared coordinates such as
        ``lead_time``; the coordinates a map shares; the per-cell note); :func:`register` adds them
        to the catalogue, and a map holds each statistic among them per cell."""

    def statistics(self, spec, chunks, class_basis: str):
        """The process's statistics of ``chunks`` as a Dataset (a map cell's; none: the empty
        template): every statistic of :meth:`variables` a map holds per cell (and lead time)."""

    def cell_inputs(self, section, *, base_dir, cells):
        """What the scenario's raw ``section`` reads per cell of a map's grid (scour: the gridded
        forcing of ``forcing_grid``), or None when every cell takes the section as given.
        ``cells()`` gives the grid's :class:`mineburial.analyses.maps.MapCells` (call it only when needed:
        the environment is read then). The object returned has ``files`` (``((path, SHA-256),
        ...)``, identifying the map's run), ``nbytes`` (its memory while the map runs),
        ``section(section, j, i)`` (the raw section of cell (j, i)) and ``base_section(section)``
        (that of the map's base scenario); a problem is one ScenarioError line."""

    def figure_panels(self, ds) -> list:
        """The panels the process adds to the run's lead-time figure of ``ds``
        (:func:`mineburial.systems.mine.figures.plot_lead_time`), above the burial panels: callables
        ``draw(ax, lead_days)``, each given a full-width axes sharing the lead-time axis ([] for none)."""

    def dataset(self, spec, chunks, ds, *, per_drop: bool, class_basis: str):
        """``ds`` (the run's Dataset) with the process's statistics, per-drop variables (with
        ``per_drop``) and global attributes."""

    def summary_lines(self, ds) -> list:
        """The process's lines of the printed run summary ([] when ``ds`` holds none of its variables)."""

    def lead_times(self, spec) -> tuple:
        """The lead times [d] at which the process reports its results."""

    def map_attributes(self, spec) -> tuple:
        """(sentence appended to a map's ``summary`` attribute, the map's further global attributes)."""


@runtime_checkable
class BurialProcess(Process, Protocol):
    """A process that changes the burial measures (scour): ``compare`` and ``sensitivity`` analyse
    the burial after it at one lead time (:func:`at_lead_time`). At most one is active in a run."""

    def at_lead_time(self, spec, lead_time: float | None):
        """``spec`` reporting the one lead time [d] analysed (None: its default); a lead time out of
        range is one :class:`~mineburial.systems.mine.config.ScenarioError` line."""

    def burial_after(self, spec, summary, chunks, *, missing: str = "nan"):
        """The impact ``summary`` rows of ``chunks``' drops with the burial measures after the
        process at its one lead time (``missing``: "nan", or "impact" to keep the impact's where the
        process gave no value)."""

    def lacks_value(self, spec, chunks):
        """Per drop: whether the process gave no value at its one lead time."""

    def status_text(self, chunks) -> str:
        """The counts of the process's per-drop statuses, ``"name count, ..."`` (nonzero ones)."""


#: the registered processes by section name, in the order they run (and enter a run's identity)
PROCESSES: dict[str, Process] = {}


def register(process: Process) -> Process:
    """Register ``process`` under its section name (a second registration of a name is refused)."""
    if not isinstance(process, Process):
        raise TypeError(
            f"{process!r} does not provide the Process protocol (mineburial.systems.mine.processes.registry)"
        )
    if process.section in PROCESSES and PROCESSES[process.section] is not process:
        raise ValueError(f"a post-impact process [{process.section}] is already registered")
    V.register_process_variables(process.section, process.variables())
    PROCESSES[process.section] = process
    return process


def unregister(section: str) -> None:
    """Remove the process of ``section`` and its output variables (a test's toy process)."""
    PROCESSES.pop(section, None)
    V.unregister_process_variables(section)


def owns_input(path: str) -> bool:
    """Whether the input ``path`` (``section.name``) is a registered process's own: the process reads
    it from the sampled inputs, the mine's parameter rows do not hold it."""
    return path.partition(".")[0] in PROCESSES


def load_all(raw_sections: Mapping, *, base_dir, base, template, random) -> tuple:
    """``((section, spec), ...)`` of the processes whose sections ``raw_sections`` holds, in
    registration order."""
    return tuple(
        (
            name,
            process.load(raw_sections[name], base_dir=base_dir, base=base, template=template, random=random),
        )
        for name, process in PROCESSES.items()
        if name in raw_sections
    )


def active(specs) -> list:
    """``[(process, spec), ...]`` of an ensemble's ``((section, spec), ...)``."""
    return [(PROCESSES[name], spec) for name, spec in specs]


def burial_process(spec):
    """``(process, its spec)`` of the active process of the ensemble ``spec`` that changes the
    burial (:class:`BurialProcess`), or None."""
    found = [(p, own) for p, own in active(spec.processes) if isinstance(p, BurialProcess)]
    if len(found) > 1:
        names = ", ".join(f"[{p.section}]" for p, _ in found)
        raise ScenarioError(f"{names}: at most one process that changes the burial can run in a scenario")
    return found[0] if found else None


def at_lead_time(spec, lead_time: float | None):
    """The ensemble ``spec`` whose burial-changing process reports the one lead time [d] analysed
    (``compare``/``sensitivity`` ``--lead-time``); without one its burial is the impact's and
    ``lead_time`` must be None."""
    found = burial_process(spec)
    if found is None:
        if lead_time is not None:
            names = " or ".join(f"[{n}]" for n, p in PROCESSES.items() if isinstance(p, BurialProcess))
            raise ScenarioError(
                f"--lead-time {lead_time:g}: the scenario has no {names} section; its burial is the "
                f"impact's (give a {names} section, or leave --lead-time out)"
            )
        return spec
    process, own = found
    return spec.with_process(process.section, process.at_lead_time(own, lead_time))


def analysed_lead_time(spec) -> float | None:
    """The one lead time [d] analysed of an ensemble ``spec`` made by :func:`at_lead_time` (None:
    no burial-changing process)."""
    found = burial_process(spec)
    return None if found is None else found[0].lead_times(found[1])[0]


def summary_lines(ds) -> list:
    """Every registered process's summary lines of ``ds``."""
    lines = []
    for process in PROCESSES.values():
        lines.extend(process.summary_lines(ds))
    return lines


register(scour.PROCESS)
