"""The Monte Carlo ensemble engine, generic over the systems of the registry
(:mod:`mineburial.systems.registry`): an ensemble scenario of any system, and the
per-realization results of any chunk of it.

The optional top-level key ``system`` of an ensemble scenario names the system the
ensemble runs (:data:`SYSTEMS`): ``"mine"`` (the default: the falling mine,
:mod:`mineburial.systems.mine.ensemble`) or ``"restraint"`` (seed 004's restraining system:
the scenario is then a restraint case file with distributions,
:mod:`mineburial.systems.restraint.ensemble`). :func:`load_ensemble` reads the file and hands
it to its system; :func:`compute_chunk` runs a chunk ``[start, stop)`` of any system's
spec. Running the chunks, keeping finished ones on disk and reducing them to statistics
is the run driver's job (:mod:`mineburial.ensembles.runner`, with the chunk store
:mod:`mineburial.ensembles.store`).

This module names no system and imports none of a system's modules (issue 36 item 5,
``tests/test_generic_layer.py``): the default scenario, the specs and scenario objects
it accepts and everything a system does are reached through the registry. A system's own
names (the mine's :class:`~mineburial.systems.mine.ensemble.EnsembleSpec`,
:func:`~mineburial.systems.mine.ensemble.chunk_inputs`, ...) are imported from its module.
"""

from __future__ import annotations

import copy
import pathlib
from collections.abc import Mapping

from mineburial.errors import EnsembleError, ScenarioError
from mineburial.io.inputs import read_toml
from mineburial.systems import registry

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "SYSTEMS",
    "load_ensemble",
    "compute_chunk",
    "chunk_bounds",
    "EnsembleError",
]

#: the systems an ensemble scenario may name with its top-level ``system`` key
SYSTEMS = registry.names()


def load_ensemble(
    source=None,
    *,
    n=None,
    seed=None,
    sampling=None,
    chunk_size=None,
    per_drop=None,
    class_basis=None,
    base_dir=None,
    systems=(registry.DEFAULT,),
):
    """Parse an ensemble scenario: a path, a dict, a spec of any system (its ``raw``
    scenario), an object of the default system with ``to_dict()`` (the mine's
    :class:`~mineburial.systems.mine.config.Scenario`), or None for the default system's embedded
    default scenario (:attr:`~mineburial.systems.registry.System.default_scenario`).

    Keyword arguments override the ``[ensemble]`` table. ``systems``: the values of the
    scenario's ``system`` key the caller can run (default only the default system, the
    falling mine: maps, comparisons and sensitivity indices are of burial); ``mineburial run``
    passes :data:`SYSTEMS`. Returns the spec the system's ``load`` makes (the mine's:
    :class:`~mineburial.systems.mine.ensemble.EnsembleSpec`).
    """
    if source is None:
        source = registry.get(registry.DEFAULT).default_scenario
    if registry.is_spec(source):
        raw = copy.deepcopy(source.raw)
        raw["system"] = source.system  # its raw scenario is without the key (popped below)
    elif isinstance(source, Mapping):
        raw = copy.deepcopy(dict(source))
    elif callable(getattr(source, "to_dict", None)):  # the default system's scenario object
        raw = source.to_dict()
    else:
        path = pathlib.Path(source)
        try:
            raw = read_toml(path)
        except OSError as exc:
            raise ScenarioError(f"cannot read scenario file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"scenario file '{path}' is not valid TOML: {exc}") from None
        base_dir = base_dir or path.resolve().parent
    system = registry.get(raw.pop("system", registry.DEFAULT))
    if system.name not in systems:
        raise ScenarioError(
            f"system = {system.name!r}: this command runs only {' or '.join(repr(s) for s in systems)} "
            f"ensembles; run a {system.name!r} ensemble with 'mineburial run'"
        )
    overrides = {"n": n, "seed": seed, "sampling": sampling, "chunk_size": chunk_size}
    overrides.update(per_drop=per_drop, class_basis=class_basis)
    return system.load(raw, overrides, base_dir)


def compute_chunk(spec, start: int, stop: int) -> dict:
    """Run realizations [start, stop) of ensemble ``spec`` by its system's
    ``compute_chunk``: a dict of per-realization arrays (``summary``, ``status``,
    ``input:<path>`` of every sampled input), ``invalid_inputs``, the reasons why
    realizations were not run, and ``start``/``stop``.

    On Ctrl-C the :class:`~mineburial.ensembles.interrupt.Interrupted` raised carries in
    ``partial`` the dict of the realizations finished first, ``[start, start + done)``
    (None where the system keeps none)."""
    return registry.of(spec).compute_chunk(spec, start, stop)


def chunk_bounds(n: int, chunk_size: int):
    """The chunks ``[(start, stop), ...]`` of ``n`` drops, ``chunk_size`` drops each (the
    last may be shorter)."""
    return [(s, min(s + chunk_size, n)) for s in range(0, n, chunk_size)]
