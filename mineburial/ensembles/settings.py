"""What the ensembles of every system share: the check of the ``[ensemble]`` settings, the
files a scenario reads (with the SHA-256 of their contents, for the run identity and the
output), and the reasons why realizations were not run, added up over chunks.

Used by the systems' ensembles (:mod:`mineburial.systems.mine.ensemble`, the falling mine;
:mod:`mineburial.systems.restraint.ensemble`, seed 004's restraining system) and the run driver.
"""

from __future__ import annotations

import hashlib
import json
import pathlib
from collections.abc import Mapping

import numpy as np

from mineburial.ensembles import distributions as dist
from mineburial.errors import ScenarioError, unknown_name_message

__all__ = ["check_ensemble_settings", "file_digest", "input_files_of", "merge_invalid_reasons"]


def file_digest(path) -> str:
    """SHA-256 (hex) of the contents of the file ``path``."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _resolve(path, base_dir) -> pathlib.Path:
    """A file name of the scenario as its loaders resolve it (relative to ``base_dir``)."""
    p = pathlib.Path(path)
    if not p.is_absolute() and base_dir is not None:
        p = pathlib.Path(base_dir) / p
    return p.resolve()


def input_files_of(raw: Mapping, random: Mapping, base_dir) -> tuple:
    """((path, SHA-256), ...) of every file the scenario reads: a fixed ``sediment.file``,
    the files of a ``sediment.file`` choice, and the files of empirical distributions."""
    names = []
    sed = raw.get("sediment")
    if isinstance(sed, Mapping) and isinstance(sed.get("file"), str):
        names.append(sed["file"])
    for path, d in random.items():
        if path == "sediment.file" and isinstance(d, dist.Choice):
            names.extend(str(v) for v in d.values)
        elif getattr(d, "file", None):
            names.append(d.file)
    files = sorted({str(_resolve(name, base_dir)) for name in names})
    return tuple((f, file_digest(f)) for f in files)


def check_ensemble_settings(ens: Mapping) -> None:
    """Check the ``[ensemble]`` settings ``ens`` (after defaults and overrides); a key
    the system does not have (``class_basis`` of a restraint ensemble) is not checked."""

    def bad(key, allowed):
        raise ScenarioError(f"ensemble.{key} = {ens[key]!r} is outside the allowed range {allowed}")

    if not isinstance(ens["n"], (int, np.integer)) or isinstance(ens["n"], bool) or ens["n"] < 1:
        bad("n", "[1, inf) (an integer number of drops)")
    if (
        not isinstance(ens["seed"], (int, np.integer))
        or isinstance(ens["seed"], bool)
        or not 0 <= ens["seed"] < 2**64
    ):
        bad("seed", "[0, 2**64) (an integer)")
    if ens["sampling"] not in ("mc", "sobol"):
        raise ScenarioError(unknown_name_message("ensemble.sampling", ens["sampling"], ("mc", "sobol")))
    if (
        not isinstance(ens["chunk_size"], (int, np.integer))
        or isinstance(ens["chunk_size"], bool)
        or ens["chunk_size"] < 1
    ):
        bad("chunk_size", "[1, inf) (an integer number of drops)")
    size = ens.get("accuracy_check", 0)
    if not (isinstance(size, str) and size == "auto") and (
        not isinstance(size, (int, np.integer)) or isinstance(size, bool) or size < 0
    ):
        bad(
            "accuracy_check",
            '[0, inf) (an integer number of drops; 0 switches the self-check off) or "auto" (the '
            "default: ~15 % of the run's time, 8 to 230 drops)",
        )
    if not isinstance(ens["per_drop"], (bool, np.bool_)):
        raise ScenarioError(f"ensemble.per_drop = {ens['per_drop']!r} must be true or false")
    if "class_basis" in ens and ens["class_basis"] not in ("burial_volume", "burial_height", "burial_area"):
        raise ScenarioError(
            unknown_name_message(
                "ensemble.class_basis", ens["class_basis"], ("burial_volume", "burial_height", "burial_area")
            )
        )


def merge_invalid_reasons(chunks) -> dict:
    """The :func:`invalid_reasons` of several chunk results added up (first example kept)."""
    total: dict = {}
    for chunk in chunks:
        for rule, (count, example) in json.loads(str(chunk["invalid_inputs"])).items():
            entry = total.setdefault(rule, [0, example])
            entry[0] += int(count)
    return total
