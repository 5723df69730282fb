"""``mineburial validate --quick`` (issue 10 item 1): the CI subset of the validation report,
and the committed summary table (docs/validation/summary.md) against a fresh run."""

import json
import pathlib

import pytest

from mineburial.cli import main
from mineburial.validation.cases import Row
from mineburial.validation.report import HEADER, format_row

SUMMARY = pathlib.Path(__file__).resolve().parent.parent / "docs" / "validation" / "summary.md"


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    pytest.importorskip("matplotlib")
    out = tmp_path_factory.mktemp("validation")
    assert main(["validate", "--quick", "-o", str(out)]) == 0
    return out


def test_quick_report_files(quick):
    rows = json.loads((quick / "results.json").read_text())["rows"]
    assert rows and all(r["quick"] for r in rows)
    for r in rows:
        assert r["source"] and r["result"] in ("pass", "FAIL", "info")
        if r["result"] != "info":
            assert r["tolerance"]
    report = (quick / "report.md").read_text()
    for png in ("exp1_case92_trajectory.png", "exp1_case93_trajectory.png"):
        assert (quick / png).stat().st_size > 0 and png in report


def _quick_rows(text):
    return [
        [c.strip() for c in line.strip("|").split(" | ")]
        for line in text.splitlines()
        if line.startswith("| ") and line.endswith("| yes |")
    ]


def _same_value(a, b):
    """Model values agree to 1e-3 relative (numbers, with their units) or exactly (text)."""
    try:
        (x, *ua), (y, *ub) = a.split(" ", 1), b.split(" ", 1)
        return ua == ub and abs(float(x) - float(y)) <= 1e-3 * max(abs(float(y)), 1e-12)
    except ValueError:
        return a == b


def test_committed_summary_matches_a_fresh_quick_run(quick):
    """Every quick row of the committed table is the fresh row: the same case, quantity,
    source, reference, tolerance and result, and the model value to 1e-3 (the error column,
    derived from it, is not compared: round-off-level errors differ between machines). If
    the physics changed on purpose, regenerate with `mineburial validate -o docs/validation`."""
    text = SUMMARY.read_text()
    assert HEADER in text
    committed = _quick_rows(text)
    fresh = _quick_rows((quick / "summary.md").read_text())
    assert [r[:4] for r in committed] == [r[:4] for r in fresh]
    assert [r[6:] for r in committed] == [r[6:] for r in fresh]
    for c, f in zip(committed, fresh):
        assert _same_value(c[4], f[4]), (c[1], c[4], f[4])


def test_failing_rows_are_shown_failing():
    row = Row("c", "q", "s", 1.0, 2.0, "s", "10 %", 1.0, "relative", False, True)
    assert "| **FAIL** |" in format_row(row)
    assert "+100 %" in format_row(row)
