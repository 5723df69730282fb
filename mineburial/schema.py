"""The one schema mechanism of the input files: a field declared once, a cross-field rule
declared once, and what derives from them (issue 18 item 3).

* :class:`Field`: path, units, allowed range with open or closed ends, default, source
  (seed and equation, a published reference, or ``ASSUMPTION: ...``), kind (a number, a
  whole number, a switch, a choice among names, or an internal code of the kernels),
  whether a kernel slot carries it and whether an ensemble may sample it. The scalar check
  (:meth:`Field.check`, raising :class:`ScenarioError`), the vectorised check over sampled
  values (:meth:`Field.contains`) and the range text of every error message come from it.
* :class:`Rule`: a relation between fields, written once as a vectorised predicate over
  ``path -> values`` and evaluated both per scenario (:meth:`Rule.check`, raising) and over
  packed or sampled rows (:meth:`Rule.holds`).
* :func:`markdown_table` writes the field tables of the user documentation,
  :func:`dumps_toml` the TOML of a resolved input.

The mine scenario's table is :mod:`mineburial.systems.mine.scenario_fields`, the restraining system's
:data:`mineburial.systems.restraint.model.FIELDS`. Plain frozen dataclasses: a library
(pydantic, attrs) would add its import time to every start of the CLI and a second
vocabulary beside numpy's vectorised checks (docs/design.md, "One schema mechanism").
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from mineburial.errors import ScenarioError, unknown_name_message

__all__ = [
    "Field",
    "Rule",
    "ScenarioError",
    "check_rules",
    "check_distribution",
    "SUPPORT_TOLERANCE",
    "number",
    "dumps_toml",
    "toml_value",
    "markdown_table",
    "generated_block",
    "replace_generated",
    "fmt",
]

#: a number, a whole number, a switch, one of named choices, an internal code of the kernels; and
#: keys whose checks their reader makes: a file path or name, an inline table, a list of numbers
KINDS = ("float", "int", "bool", "choice", "code", "text", "table", "list")


def fmt(x: float) -> str:
    """A bound as the range text writes it (``1e+05`` style, ``inf``)."""
    return "inf" if x == math.inf else "-inf" if x == -math.inf else f"{x:g}"


@dataclass(frozen=True)
class Field:
    """One field of an input file, declared once.

    ``path`` is the dotted name (``mine.length``; the slot name of
    :data:`mineburial.kernels.mine.layout.PARAM_NAMES` where ``slot`` is true); ``location`` is
    where the value sits in a file when that differs (``release.position[2]`` for
    ``release.z``; ``None`` for a kernel code no file holds). ``default`` is ``None`` for a
    required field or one whose default is computed (``default_text`` then says how).
    ``kind`` is ``float``, ``int``, ``bool``, ``choice`` (one of ``choices``, packed as its
    index) or ``code`` (an internal integer of the kernels, such as a bank row); ``text``,
    ``table`` and ``list`` (a list of numbers) are keys that their section's reader checks
    itself, ``allowed_text`` saying in the documentation what it allows.
    """

    path: str
    units: str
    low: float = -math.inf
    high: float = math.inf
    low_inclusive: bool = True
    high_inclusive: bool = True
    description: str = ""
    default: Any = None
    location: str | None = ""
    source: str = ""
    kind: str = "float"
    choices: tuple = ()
    slot: bool = False
    sampled: bool = True
    default_text: str = ""
    allowed_text: str = ""

    def __post_init__(self):
        if self.kind not in KINDS:  # pragma: no cover - guards the tables
            raise ValueError(f"{self.path}: kind {self.kind!r} is not one of {KINDS}")
        if self.location == "":
            object.__setattr__(self, "location", self.path)

    # -- names ------------------------------------------------------------------
    @property
    def section(self) -> str:
        return self.path.rpartition(".")[0]

    @property
    def name(self) -> str:
        return self.path.rpartition(".")[2]

    @property
    def unit(self) -> str:
        return self.units

    @property
    def assumption(self) -> bool:
        """True where no source gives the value (``source`` starts with ``ASSUMPTION``)."""
        return self.source.startswith("ASSUMPTION")

    @property
    def numeric(self) -> bool:
        return self.kind in ("float", "int")

    # -- range --------------------------------------------------------------------
    def range_text(self, low=None, high=None, low_inclusive=None, high_inclusive=None) -> str:
        """``(0, 50] m`` style text of the allowed range (optionally with other bounds);
        the names of a choice, ``true or false`` of a switch."""
        if self.kind == "bool":
            return "true or false"
        if self.kind == "choice":
            return " or ".join(repr(v) for v in self.choices)
        lo = self.low if low is None else low
        hi = self.high if high is None else high
        li = self.low_inclusive if low_inclusive is None else low_inclusive
        hi_incl = self.high_inclusive if high_inclusive is None else high_inclusive
        left = "[" if li and lo != -math.inf else "("
        right = "]" if hi_incl and hi != math.inf else ")"
        text = f"{left}{fmt(lo)}, {fmt(hi)}{right}"
        return f"{text} {self.units}" if self.units not in ("1", "") else text

    def contains(self, values) -> np.ndarray:
        """Boolean mask: finite and inside the range (vectorised)."""
        v = np.asarray(values, dtype=np.float64)
        ok = np.isfinite(v)
        ok &= (v >= self.low) if self.low_inclusive else (v > self.low)
        ok &= (v <= self.high) if self.high_inclusive else (v < self.high)
        return ok

    def range_error(self, value, location=None, *, low=None, high=None, low_inclusive=None, note=""):
        """The :class:`ScenarioError` of ``value`` outside the range (or outside the given
        bounds of a cross-field rule): field, value, allowed range and units."""
        location = location or self.location or self.path
        label = location if location == self.path else f"{location} ({self.path})"
        units = f" {self.units}" if self.units not in ("1", "") else ""
        extra = f" ({note})" if note else ""
        return ScenarioError(
            f"{label} = {value!r}{units} is outside the allowed range "
            f"{self.range_text(low, high, low_inclusive)}{extra}"
        )

    # -- the scalar check -------------------------------------------------------
    def check(self, value, location: str | None = None):
        """``value`` converted to the field's type (float, int, bool or the name); a
        :class:`ScenarioError` naming the field, the value and what is allowed otherwise."""
        location = location or self.location or self.path
        if self.kind == "bool":
            if not isinstance(value, (bool, np.bool_)):
                raise ScenarioError(f"{location} = {value!r} must be true or false")
            return bool(value)
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise ScenarioError(f"{location}: " + unknown_name_message("name", value, self.choices))
            return value
        v = number(value, location, self.units, self.range_text())
        if self.kind == "int":
            if not math.isfinite(v):
                raise ScenarioError(
                    f"{location} = {value!r} is not a finite whole number; allowed range {self.range_text()}"
                )
            if v != int(v):
                raise ScenarioError(f"{location} = {value!r} must be a whole number in {self.range_text()}")
        if not self.contains(v):
            raise self.range_error(v, location)
        return int(v) if self.kind == "int" else v

    def pack(self, value) -> float:
        """The checked ``value`` as a kernel slot holds it: a choice's index, a switch's 0/1."""
        return float(self.choices.index(value)) if self.kind == "choice" else float(value)


def number(value, location: str, units: str = "", allowed: str = "") -> float:
    """``value`` as a float, or the :class:`ScenarioError` saying it must be a number (and
    the ``allowed`` range, when given)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        u = f" ({units})" if units and units != "1" else ""
        hint = (
            (': an inline table is a distribution only with distribution = "..." (docs/scenario.md)')
            if isinstance(value, Mapping)
            else ""
        )
        rng = f"; allowed range {allowed}" if allowed else ""
        raise ScenarioError(f"{location} = {value!r} must be a number{u}{hint}{rng}")
    return float(value)


@dataclass(frozen=True)
class Rule:
    """A relation between fields, declared once.

    ``predicate(values)`` takes ``path -> value`` (scalars or arrays of the drops) for the
    ``paths`` and returns where the relation holds, elementwise; ``text`` says the rule in
    explanations. Per scenario, :meth:`check` raises on the blamed ``field`` (its first
    path unless given): ``message(values)`` when given, else the field's range error with
    the ``bounds(values) -> (low, high, low_inclusive)`` the others allow and ``note``.
    """

    text: str
    paths: tuple[str, ...]
    predicate: Callable[[Mapping], Any]
    note: str = ""
    bounds: Callable[[Mapping], tuple] | None = None
    message: Callable[[Mapping], str] | None = None
    field: str = ""
    location: str = ""

    def holds(self, values: Mapping) -> np.ndarray:
        """Where the rule holds (vectorised over the drops; NaN never holds)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.asarray(self.predicate(values), dtype=bool)

    def check(self, values: Mapping, fields: Mapping[str, Field]) -> None:
        """Raise the rule's :class:`ScenarioError` when it fails for one scenario."""
        if bool(self.holds(values)):
            return
        if self.message is not None:
            raise ScenarioError(self.message(values))
        blamed = fields[self.field or self.paths[0]]
        low, high, low_inclusive = self.bounds(values) if self.bounds else (None, None, None)
        raise blamed.range_error(
            values[blamed.path],
            self.location or blamed.location,
            low=low,
            high=high,
            low_inclusive=low_inclusive,
            note=self.note,
        )


def check_rules(rules, values: Mapping, fields: Mapping[str, Field]) -> None:
    """Check every rule of ``rules`` whose fields are all in ``values`` (one scenario)."""
    for rule in rules:
        if all(p in values for p in rule.paths):
            rule.check(values, fields)


# ---------------------------------------------------------------------------
# distributions of an ensemble against a field's range (every system's one check)
# ---------------------------------------------------------------------------
#: The largest probability that a continuous distribution of a numeric field may put
#: outside the field's allowed range (the tails of a normal on a positive field); more is
#: refused when the scenario is loaded (:func:`check_distribution`). A draw in the
#: tolerated tail is still caught: the mine's ``config.check_samples`` marks its drop
#: invalid, the restraint's rows are checked before they run.
SUPPORT_TOLERANCE = 1e-6


def inline_table(d: Mapping) -> str:
    """A distribution table as the inline TOML a user writes (long lists shortened)."""

    def value(v):
        if isinstance(v, (list, tuple)):
            items = [value(x) for x in v[:6]] + (["..."] if len(v) > 6 else [])
            return "[" + ", ".join(items) + "]"
        return json.dumps(v) if isinstance(v, str) else f"{v:g}"

    return "{" + ", ".join(f"{k} = {value(v)}" for k, v in d.items()) + "}"


def check_distribution(spec: Field, distribution, label: str | None = None) -> None:
    """Check the distribution of the numeric field ``spec`` against its allowed range: the one
    rule of every system's ensembles (the mine's scenario, the restraint's case).

    ``distribution`` is a :class:`mineburial.ensembles.distributions.Distribution` with
    numeric values (a categorical one is the caller's to refuse or pass). A continuous one
    may put at most :data:`SUPPORT_TOLERANCE` of its probability outside the range (a
    normal(750, 15) on a mass is fine, a uniform(-10, 10) or a normal(1, 1) is not); a
    discrete one (``choice``, ``empirical``) none at all: every value it can draw must be
    allowed. Nothing is truncated on the user's behalf: a ``truncated_normal`` or a
    ``uniform`` with its bounds inside the range is the way to say so. Raises
    :class:`ScenarioError` naming the field (``label``, default its path), the
    distribution, the probability outside and the allowed range.
    """
    p = distribution.probability_outside(spec.low, spec.high, spec.low_inclusive, spec.high_inclusive)
    tolerance = 0.0 if distribution.discrete else SUPPORT_TOLERANCE
    if p <= tolerance:
        return
    label = f"{label or spec.path} = {inline_table(distribution.to_dict())}"
    if distribution.discrete:
        values = np.asarray(distribution.values, dtype=np.float64)
        bad = values[~spec.contains(values)]
        raise ScenarioError(
            f"{label}: {bad.size} of its {values.size} values lie outside the allowed range "
            f"{spec.range_text()} (probability {p:.3g}), e.g. {float(bad[0]):g}"
        )
    raise ScenarioError(
        f"{label} puts probability {p:.3g} outside the allowed range {spec.range_text()} "
        f"(at most {SUPPORT_TOLERANCE:g} may lie outside): narrow it, or bound it inside the "
        f"range (a uniform's or a truncated_normal's low and high)"
    )


# ---------------------------------------------------------------------------
# writers: the documentation's field tables and TOML
# ---------------------------------------------------------------------------
def default_text(f: Field) -> str:
    """The default as the documentation writes it."""
    if f.default_text:
        return f.default_text
    if f.default is None:
        return "required"
    if isinstance(f.default, bool):
        return f"`{'true' if f.default else 'false'}`"
    if isinstance(f.default, str):
        return f"`{json.dumps(f.default)}`"
    return f"{f.default:g}"


def allowed_text(f: Field, rules=()) -> str:
    """The allowed values as the documentation writes them, with the rules on the field."""
    if f.allowed_text:
        text = f.allowed_text
    elif f.kind == "bool":
        text = "`true`/`false`"
    elif f.kind == "choice":
        text = ", ".join(f"`{json.dumps(c)}`" for c in f.choices)
    else:
        text = f.range_text().removesuffix(f" {f.units}")
    extra = [r.text for r in rules if (r.field or r.paths[0]) == f.path]
    return "; ".join([text] + [f"`{e}`" for e in extra])


def markdown_table(fields, rules=()) -> str:
    """Markdown table of ``fields``: key, field, units, default, allowed (with the ``rules``
    that bound a field), and the meaning and the source where any field has one."""
    fields = list(fields)
    meanings, sources = any(f.description for f in fields), any(f.source for f in fields)
    head = ["key", "field", "units", "default", "allowed"]
    head += (["meaning"] if meanings else []) + (["source"] if sources else [])
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for f in fields:
        key = f.location.rpartition(".")[2] if f.location else "—"
        units = f.units if f.numeric or (f.kind == "list" and f.units) else "—"
        cells = [f"`{key}`", f"`{f.path}`", units, default_text(f), allowed_text(f, rules)]
        cells += ([f.description] if meanings else []) + ([f.source or "—"] if sources else [])
        rows.append("| " + " | ".join(c.replace("\n", " ").replace("|", "\\|") for c in cells) + " |")
    return "\n".join(rows) + "\n"


def replace_generated(text: str, name: str, table: str, writer: str) -> str:
    """``text`` (a Markdown document) with the generated block ``name`` replaced by
    ``table``; the block is marked by :func:`generated_block`'s comments."""
    start, end = generated_markers(name, writer)
    i, j = text.index(start), text.index(end)
    return text[: i + len(start)] + "\n" + table + text[j:]


def generated_markers(name: str, writer: str) -> tuple[str, str]:
    """The HTML comments around generated block ``name`` of a document."""
    return (f"<!-- table {name}: generated by {writer}; do not edit -->", f"<!-- end of table {name} -->")


def generated_block(name: str, table: str, writer: str) -> str:
    """Block ``name`` as a document holds it: the markers around ``table``."""
    start, end = generated_markers(name, writer)
    return f"{start}\n{table}{end}"


def toml_value(v) -> str:
    """One TOML value (bool, int, float with nan/inf, string, list)."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def dumps_toml(d: Mapping, _prefix: str = "") -> str:
    """TOML text of a nested dict of scalars, lists and sub-dicts (sub-dicts become
    ``[a.b]`` tables)."""
    lines, tables = [], []
    for key, value in d.items():
        if isinstance(value, Mapping):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {toml_value(value)}")
    out = []
    if lines:
        if _prefix:
            out.append(f"[{_prefix}]")
        out.extend(lines)
        out.append("")
    for key, value in tables:
        out.append(dumps_toml(value, f"{_prefix}.{key}" if _prefix else key))
    return "\n".join(out)
