"""``mineburial validate --quick`` (issue 10 item 1): the CI subset of the validation report,
and the committed summary table (docs/validation/summary.md) against a fresh run."""

import json
import math
import pathlib
import re

import numpy as np
import pytest
import xarray as xr

from mineburial.cli import main
from mineburial.kernels.mine import status
from mineburial.systems import registry
from mineburial.systems.mine.config import example_path
from mineburial.systems.mine.scenario_fields import WATER_COLUMN_NAMES
from mineburial.systems.restraint import model as restraint
from mineburial.validation.cases import (
    ANCHOR,
    ANCHOR_K,
    CALIBRATION,
    CASES,
    EXP1,
    EXP1_POOL_DEPTH,
    EXP1_VARIANTS,
    KINDS,
    MEASUREMENT,
    MINE,
    PREDICTIVE,
    RESTRAINT,
    SYSTEMS,
    VERIFICATION,
    Case,
    Row,
    _exp1_drop,
    _summary,
    anchor_scenario,
    exp1_scenario,
    exp1_variant_label,
    run_case,
    submergence_time,
)
from mineburial.validation.report import HEADER, counts_text, format_row, kind_counts, system_counts

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
        assert r["source"] and r["result"] in ("pass", "FAIL", "info", "calibration")
        assert r["kind"] in KINDS
        assert (r["result"] == "calibration") == (r["kind"] == CALIBRATION)
        if r["result"] not in ("info", "calibration"):
            assert r["tolerance"]
    counts = json.loads((quick / "results.json").read_text())["counts"]
    assert set(counts) == set(SYSTEMS) and all(set(c) == set(KINDS) for c in counts.values())
    assert sum(sum(n.values()) for c in counts.values() for n in c.values()) == len(rows)
    for system, c in counts.items():
        assert c[CALIBRATION]["pass"] == c[CALIBRATION]["FAIL"] == 0
        for kind, n in c.items():  # each count is the number of rows of that system, kind and result
            for result, k in n.items():
                got = [r for r in rows if (r["system"], r["kind"], r["result"]) == (system, kind, result)]
                assert len(got) == k, (system, kind, result)
    summary = (quick / "summary.md").read_text()
    # the headline choice, its one calibration case and the timing origin are stated
    assert "munk_factor = 0" in summary and "one calibration case" in summary and "0.23" in summary
    assert "not synchronised" in summary
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


def _row(kind, passed, system=MINE):
    r = Row("c", "q", "s", 1.0, 1.0, "s", "1 %", 0.0, "relative", passed, False)
    r.kind = kind
    r.system = system
    return r


def test_rows_are_counted_separately_by_system_and_kind():
    rows = [
        _row(MEASUREMENT, True),
        _row(MEASUREMENT, False),
        _row(MEASUREMENT, None),
        _row(VERIFICATION, True),
        _row(VERIFICATION, True),
        _row(VERIFICATION, True),
        _row(CALIBRATION, True),  # fits, but a calibration row is never a pass
        _row(CALIBRATION, False),
        _row(CALIBRATION, None),
        _row(VERIFICATION, True, RESTRAINT),  # the restraining system's: counted apart from the mine
        _row(VERIFICATION, False, RESTRAINT),
        _row(PREDICTIVE, True),  # the hook of issue 32: counted like the others
        _row(PREDICTIVE, False),
    ]
    n = kind_counts(rows)
    assert n[MEASUREMENT] == {"pass": 1, "FAIL": 1, "info": 1, "calibration": 0}
    assert n[VERIFICATION] == {"pass": 4, "FAIL": 1, "info": 0, "calibration": 0}
    assert n[CALIBRATION] == {"pass": 0, "FAIL": 0, "info": 0, "calibration": 3}
    assert n[PREDICTIVE] == {"pass": 1, "FAIL": 1, "info": 0, "calibration": 0}
    by_system = system_counts(rows)
    assert list(by_system) == [MINE, RESTRAINT]
    assert by_system[MINE][VERIFICATION] == {"pass": 3, "FAIL": 0, "info": 0, "calibration": 0}
    assert by_system[RESTRAINT][VERIFICATION] == {"pass": 1, "FAIL": 1, "info": 0, "calibration": 0}
    assert sum(by_system[RESTRAINT][k]["pass"] for k in KINDS) == 1
    assert counts_text(rows) == (
        "mine -- measurement: 1 pass, 1 fail, 1 for information (no tolerance); "
        "verification: 3 pass, 0 fail, 0 for information (no tolerance); "
        "calibration: 3 rows (not counted as passes or failures); "
        "predictive: 1 pass, 1 fail, 0 for information (no tolerance). "
        "restraint -- verification: 1 pass, 1 fail, 0 for information (no tolerance)"
    )
    # the table says whether a calibration row fits, without calling it a pass
    assert "| calibration, within its tolerance |" in format_row(rows[6])
    assert "| calibration, outside its tolerance |" in format_row(rows[7])
    # a row that no case declared a kind or a system for cannot be counted
    with pytest.raises(ValueError, match="no kind"):
        kind_counts([Row("c", "q", "s", 1.0, 1.0)])
    with pytest.raises(ValueError, match="no system"):
        system_counts([Row("c", "q", "s", 1.0, 1.0, kind=MEASUREMENT)])


def test_predictive_kind_is_declared_with_its_meaning_and_no_case_uses_it():
    """Issue 32 item 5: the fourth kind is a hook for the posterior predictive checks that the
    calibration module will add; it is declared and counted, and no case of it exists yet."""
    assert list(KINDS) == [MEASUREMENT, VERIFICATION, CALIBRATION, PREDICTIVE]
    assert PREDICTIVE == "predictive"
    meaning = KINDS[PREDICTIVE]
    assert "left out of the calibration" in meaning and "predictive 90 % band" in meaning
    assert not [c for c in CASES if c.kind == PREDICTIVE]
    # a predictive case needs no calibrated parameter, and its rows pass or fail
    case = Case("p", "t", lambda quick_only, figures: [Row("c", "q", "s", 1.0, 1.0, passed=True)], PREDICTIVE)
    assert [(r.kind, r.result) for r in run_case(case)] == [(PREDICTIVE, "pass")]


def test_the_restraining_system_is_declared_apart_from_the_mine():
    assert set(SYSTEMS) == set(registry.names())  # the systems of the registry, no other
    systems = {c.key: c.system for c in CASES}
    assert systems.pop("restraint_table3") == RESTRAINT
    assert set(systems.values()) == {MINE}
    case = Case(
        "k", "t", lambda quick_only, figures: [Row("c", "q", "s", 1.0, 1.0)], VERIFICATION, system=RESTRAINT
    )
    assert [(r.kind, r.system) for r in run_case(case)] == [(VERIFICATION, RESTRAINT)]
    with pytest.raises(ValueError, match="system"):
        Case("k", "t", case.run, VERIFICATION, system="barge")


def test_every_case_declares_its_kind_and_run_case_stamps_it():
    assert all(c.kind in KINDS for c in CASES)
    kinds = {c.key: c.kind for c in CASES}
    # the Exp-1 (92) drop chose numerics.munk_factor under the mineburial model (docs/physics.md
    # section 2): calibration; IMPACT35 (no added mass) on it and both models on (93): measurement
    assert kinds["exp1_case92_mineburial_munk_factor"] == CALIBRATION
    assert "munk_factor" in next(c.calibrates for c in CASES if c.key == "exp1_case92_mineburial_munk_factor")
    assert kinds["exp1_case92_impact35"] == kinds["exp1_case93_mineburial_munk_factor"] == MEASUREMENT
    # the literature's viscous_crossflow was not tuned on Exp-1: measurement on both drops
    assert kinds["exp1_case92_mineburial_viscous_crossflow"] == MEASUREMENT
    assert kinds["exp1_case93_mineburial_viscous_crossflow"] == MEASUREMENT
    # the Exp-2 ratio compares two models with each other; Table 3 is seed 004's simulation
    assert kinds["exp2_models"] == kinds["restraint_table3"] == VERIFICATION
    assert [c.key for c in CASES if c.kind == CALIBRATION] == ["exp1_case92_mineburial_munk_factor"]
    case = Case("k", "t", lambda quick_only, figures: [Row("c", "q", "s", 1.0, 1.0)], VERIFICATION)
    assert [r.kind for r in run_case(case)] == [VERIFICATION]
    with pytest.raises(ValueError, match="kind"):
        Case("k", "t", case.run, "validation")
    with pytest.raises(ValueError, match="calibrat"):
        Case("k", "t", case.run, CALIBRATION)  # a calibration case must say what it calibrates


def testsubmergence_time_of_a_tilted_cylinder_by_hand():
    # axis pitched 30 deg nose up (q = (cos 15, 0, sin(-15), 0): body axis z component
    # -sin(-30 deg) = +0.5), COM 0.01 m towards the nose, L = 0.2 m, falling at 1 m/s from
    # z = 0 at t = 0: the tail end is at z - 0.11 * 0.5, the nose end at z + 0.09 * 0.5, so
    # the nose, the top end, goes under at t = 0.045 s
    t = np.arange(0.0, 0.2, 0.001)
    half = math.radians(-15.0)
    ds = xr.Dataset(
        {
            "z": ("time", -1.0 * t),
            "q0": ("time", np.full_like(t, math.cos(half))),
            "q1": ("time", np.zeros_like(t)),
            "q2": ("time", np.full_like(t, math.sin(half))),
            "q3": ("time", np.zeros_like(t)),
            "water_entry_time": 0.0,
            "impact_time": 0.15,
        },
        coords={"time": t},
    )
    assert submergence_time(ds, 0.2, 0.01) == pytest.approx(0.045, abs=1e-12)


def test_anchor_embedment_rises_with_speed_and_density_and_falls_with_strength():
    # O'Loughlin et al. 2013: embedment grows with the anchor's energy (impact speed, net
    # density) and must fall as the clay's strength gradient rises; the engine's torpedo
    # anchor of the validation case (mineburial/validation/cases.py ANCHOR) must follow
    def embedment(**kw):
        args = {"impact_speed": 25.0, "strength_gradient": ANCHOR_K[0], **kw}
        code, s = _summary(anchor_scenario(**args))
        assert status.NAMES[code] == "at_rest"
        return s["penetration_depth"]

    base = embedment()
    assert embedment(impact_speed=30.0) > base
    assert embedment(density=5850.0) > base  # 99 t: mine.mass allows at most 100 t
    assert embedment(strength_gradient=ANCHOR_K[1]) < base
    # deeper than the anchor is long, shallower than the 100 m water column's sediment
    assert ANCHOR["length"] < base < 100.0


def test_exp1_runs_every_water_column_model_at_one_common_pool_depth():
    """Issue 32 item 5: both Exp-1 drops under every numerics.water_column of the mineburial
    model (and IMPACT35, to which the choice does not apply), all in the same assumed pool."""
    assert {wc for m, wc in EXP1_VARIANTS if m == "mineburial"} == set(WATER_COLUMN_NAMES)
    keys = {c.key for c in CASES}
    for name in EXP1:
        for model, wc in EXP1_VARIANTS:
            assert f"{name}_{model}" + (f"_{wc}" if wc else "") in keys
            sc = exp1_scenario(name, model, wc)
            assert sc.environment.water_depth == EXP1_POOL_DEPTH
            assert sc.numerics.model == model
            if wc is not None:
                assert sc.numerics.water_column == wc
    # the common depth is the one both scenario files state (read here without the package's reader)
    for name in EXP1:
        (depth,) = re.findall(r"^water_depth\s*=\s*([0-9.]+)", example_path(name).read_text(), re.M)
        assert float(depth) == EXP1_POOL_DEPTH


def test_quick_summary_sets_every_water_column_model_side_by_side(quick):
    rows = json.loads((quick / "results.json").read_text())["rows"]
    summary = (quick / "summary.md").read_text()
    assert f"Exp-1 under every water-column model, pool depth {EXP1_POOL_DEPTH:g} m" in summary
    for name, info in EXP1.items():
        for model, wc in EXP1_VARIANTS:
            label = exp1_variant_label(model, wc)
            travel = [
                r
                for r in rows
                if r["case"] == info["label"]
                and r["quantity"].startswith("travel time through the water column")
                and r["quantity"].endswith(f", model {label}")
            ]
            assert len(travel) == 1, (name, label)
            assert f"{EXP1_POOL_DEPTH:g} m assumed for every model" in travel[0]["tolerance"]
            assert (travel[0]["kind"] == CALIBRATION) == (name == "exp1_case92" and wc == "munk_factor")
            # its value is in the side-by-side table, in the column of its variant
            line = next(x for x in summary.splitlines() if x.startswith("| travel time through the water"))
            assert f"| model {label} " in summary and line.count("|") == len(EXP1_VARIANTS) + 3


def test_impact35_is_the_same_drop_under_either_water_column():
    """IMPACT35 has no added mass, so numerics.water_column cannot change its drop: the reason
    its Exp-1 rows are run once, not once per water-column model."""
    a = _exp1_drop("exp1_case92", "impact35", "munk_factor")
    b = _exp1_drop("exp1_case92", "impact35", "viscous_crossflow")
    for var in ("z", "psi2", "u", "v", "w"):
        np.testing.assert_array_equal(a[var].values, b[var].values)
    assert float(a.impact_time) == float(b.impact_time)


# --- issue 32 item 5: every count in the docs is generated -----------------------------------
# The counts come from the full suite (minutes, with the restraint's Table 3), too slow to
# regenerate in CI, so the hand-written docs quote none: they point to the generated summary
# (docs/validation/summary.md), whose counts must be the counts of its own tables.
DOCS = SUMMARY.parent.parent
_KIND = r"(?:calibration|measurement|verification|predictive)"
#: a count of validation rows by kind, anywhere in the hand-written docs
KIND_COUNT = re.compile(
    rf"\b\d+\s+{_KIND}\s+(?:rows|pass(?:es)?)\b"
    rf"|\b{_KIND}\W{{0,4}}\s+\d+\s+(?:rows|pass)\b"
    rf"|\b\d+\s+of\s+the\s+\d+\s+{_KIND}\b",
    re.I,
)
#: a bare pass/fail count, in the pages about the validation (elsewhere "N passed" counts tests)
PASS_FAIL = re.compile(r"\b\d+\s+(?:pass(?:es|ed)?|fail(?:s|ed|ures?)?)\b|\b\d+\s+for\s+information\b", re.I)


def _hand_written_docs():
    generated = DOCS / "validation"
    return [p for p in sorted(DOCS.rglob("*.md")) if generated not in p.parents] + [DOCS.parent / "README.md"]


def test_the_count_patterns_catch_the_counts_once_quoted():
    # what docs/validation.md and the issue quoted before issue 32: each must be caught
    stale = (
        "(see the summary; counts by kind): **measurement** 4 pass, 5 fail, 21 for\ninformation; "
        '**verification** 33 pass, 1 fail; **calibration** 5 rows. ... counted as "20 pass, 5 fail"'
    )
    assert len(KIND_COUNT.findall(stale)) == 3
    assert len(PASS_FAIL.findall(stale)) == 7
    assert KIND_COUNT.search("19 of the 33 verification passes are the restraining system")
    assert not KIND_COUNT.search("the validation report counts the Table 3 rows as verification")


def test_hand_written_docs_quote_no_validation_counts():
    docs = _hand_written_docs()
    assert DOCS / "validation.md" in docs and len(docs) > 5
    for path in docs:
        text = path.read_text()
        assert not KIND_COUNT.findall(text), (path.name, KIND_COUNT.findall(text))
        if path.name in ("validation.md", "README.md"):
            assert not PASS_FAIL.findall(text), (path.name, PASS_FAIL.findall(text))
    # and they point to the generated counts instead
    assert "validation/summary.md" in (DOCS / "validation.md").read_text()
    assert "docs/validation/summary.md" in (DOCS.parent / "README.md").read_text()


def _table_counts(text):
    """``{(system, kind): {result: n}}`` recounted from the result column of each table of a
    summary, under the section headers the report writes for each system and kind."""
    heads = {
        f"## {what[0].upper()}{what[1:]}: {meaning}": (system, kind)
        for system, what in SYSTEMS.items()
        for kind, meaning in KINDS.items()
    }
    out, section = {}, None
    for line in text.splitlines():
        if line.startswith("## "):
            section = heads.get(line)
        elif section and line.startswith("| ") and not line.startswith(HEADER[:10]):
            cell = line.strip("|").split(" | ")[7].strip()
            result = {"pass": "pass", "**FAIL**": "FAIL", "info": "info"}.get(cell, "calibration")
            assert result != "calibration" or cell.startswith("calibration"), cell
            n = out.setdefault(section, {"pass": 0, "FAIL": 0, "info": 0, "calibration": 0})
            n[result] += 1
    return out


def test_committed_summary_counts_are_the_counts_of_its_tables():
    text = SUMMARY.read_text()
    counted = _table_counts(text)
    committed = json.loads((SUMMARY.parent / "results.json").read_text())
    assert len(committed["rows"]) == sum(sum(n.values()) for n in counted.values())
    head = next(x for x in text.splitlines() if x.startswith("Generated by"))
    clauses = dict(re.findall(r"(\w+) -- (.*?)(?=\. \w+ -- |\.$)", head))
    assert set(clauses) == set(SYSTEMS)  # the mine's and the restraint's counts, apart
    for system, kinds in committed["counts"].items():
        for kind, n in kinds.items():
            assert n == counted.get((system, kind), {"pass": 0, "FAIL": 0, "info": 0, "calibration": 0})
            if kind == CALIBRATION and n["calibration"]:
                assert f"calibration: {n['calibration']} rows" in clauses[system]
            elif sum(n.values()):
                said = f"{kind}: {n['pass']} pass, {n['FAIL']} fail, {n['info']} for information"
                assert said in clauses[system], (system, said)
            else:
                assert f"{kind}:" not in clauses[system]
    # every Table 2 case of seed 004 is a restraint row, and none is the mine's
    assert sum(counted[(RESTRAINT, VERIFICATION)].values()) == restraint.N_CASES
