"""The error types of the package and the helpers of their messages (a leaf module: it
imports nothing of mineburial, so every module may import it).

Every error a user can cause is a :class:`ScenarioError` (a ``ValueError``) whose message
is one line naming the field or file, the value, and the allowed range with units; the
command line prints it as ``mineburial: error: ...`` with exit status 2
(:mod:`mineburial.cli`). :func:`unknown_name_message` and :func:`unknown_names_message`
word an unknown name with a did-you-mean suggestion.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

__all__ = [
    "ScenarioError",
    "EnsembleError",
    "RunError",
    "RunLockedError",
    "unknown_name_message",
    "unknown_names_message",
]


class ScenarioError(ValueError):
    """An invalid scenario or profile; the message names the field path, the value and
    the allowed range with units."""


class EnsembleError(ScenarioError):
    """A problem with an ensemble scenario (bad distribution, field that cannot vary)."""


class RunError(ScenarioError):
    """A run that cannot start: its output path, or another run holding it."""


class RunLockedError(RunError):
    """Another live run writes the same output path."""


def unknown_name_message(what: str, name: str, allowed: Iterable[str]) -> str:
    """``unknown <what> 'name': did you mean 'x'? Allowed: a, b, c`` (difflib suggestion)."""
    allowed = sorted(allowed)
    close = difflib.get_close_matches(str(name), allowed, n=1, cutoff=0.5)
    hint = f" did you mean '{close[0]}'?" if close else ""
    return f"unknown {what} '{name}':{hint} allowed: {', '.join(allowed)}"


def unknown_names_message(what: str, names: Iterable[str], allowed: Iterable[str]) -> str:
    """:func:`unknown_name_message` for every unknown name at once:
    ``unknown keys 'lenght' (did you mean 'length'?), 'x': allowed: a, b, c``."""
    names = list(names)
    if len(names) == 1:
        return unknown_name_message(what, names[0], allowed)
    allowed = sorted(allowed)
    parts = []
    for name in names:
        close = difflib.get_close_matches(str(name), allowed, n=1, cutoff=0.5)
        parts.append(f"'{name}'" + (f" (did you mean '{close[0]}'?)" if close else ""))
    return f"unknown {what}s {', '.join(parts)}: allowed: {', '.join(allowed)}"
