"""The one schema mechanism (issue 18 item 3): each scenario field declared once in
mineburial/systems/mine/scenario_fields.py, each cross-field rule once in config.RULES, and what derives
from them (the kernels' slot layout, the scalar and vectorised checks, the docs' tables).

References: the slot layout of the kernels at 6f4af93 (the compiled kernels index slots by
these constants, and numba's on-disk cache is keyed on the kernel's own file, not on
layout.py, so a slot that moves would be read at its old index by a stale cache); the
per-scenario check and the check over packed rows must refuse the same inputs.
"""

import ast
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout
from mineburial.systems.mine import config, scenario_fields
from mineburial.systems.mine.config import RULES, SCHEMA, Scenario, check_params, explain_params

ROOT = Path(__file__).resolve().parents[1]

#: (constant, slot) of the kernels' parameter vector at 6f4af93, in slot order: the
#: positional unpack ``(P_LENGTH, ...) = range(N_PARAMS)`` of layout.py as it was then
PINNED = (
    ("P_LENGTH", "mine.length"),
    ("P_DIAMETER", "mine.diameter"),
    ("P_MASS", "mine.mass"),
    ("P_CHI", "mine.com_offset"),
    ("P_J1", "mine.inertia_axial"),
    ("P_J2", "mine.inertia_transverse"),
    ("P_X0", "release.x"),
    ("P_Y0", "release.y"),
    ("P_Z0", "release.z"),
    ("P_U0", "release.u"),
    ("P_V0", "release.v"),
    ("P_W0", "release.w"),
    ("P_Q00", "release.q0"),
    ("P_Q10", "release.q1"),
    ("P_Q20", "release.q2"),
    ("P_Q30", "release.q3"),
    ("P_OM10", "release.omega1"),
    ("P_OM20", "release.omega2"),
    ("P_OM30", "release.omega3"),
    ("P_GRAVITY", "environment.gravity"),
    ("P_RHO_AIR", "environment.air_density"),
    ("P_NU_AIR", "environment.air_viscosity"),
    ("P_RHO_WATER", "environment.water_density"),
    ("P_NU_WATER", "environment.water_viscosity"),
    ("P_DEPTH", "environment.water_depth"),
    ("P_CURRENT_KIND", "current.kind"),
    ("P_CURRENT_U", "current.u"),
    ("P_CURRENT_V", "current.v"),
    ("P_CURRENT_EXPONENT", "current.exponent"),
    ("P_CURRENT_TABLE", "current.table_index"),
    ("P_SED_PROFILE", "sediment.profile_index"),
    ("P_SED_RHO", "sediment.density"),
    ("P_SED_RHO_GRAD", "sediment.density_gradient"),
    ("P_SED_S", "sediment.strength"),
    ("P_SED_S_GRAD", "sediment.strength_gradient"),
    ("P_SED_RESISTANCE", "sediment.resistance"),
    ("P_SED_RATE_LAW", "sediment.rate_law"),
    ("P_SED_A", "sediment.impact_factor"),
    ("P_SED_VREST", "sediment.rest_speed"),
    ("P_SED_BETA", "sediment.rate_coefficient"),
    ("P_SED_RATE_REF", "sediment.reference_rate"),
    ("P_SED_MU", "sediment.friction"),
    ("P_SED_NC", "sediment.bearing_factor"),
    ("P_SED_PORE", "sediment.pore_pressure"),
    ("P_SED_B", "sediment.rupture_length"),
    ("P_SED_KP", "sediment.permeability"),
    ("P_SED_EV", "sediment.void_ratio"),
    ("P_MODEL", "numerics.model"),
    ("P_INTEGRATOR", "numerics.integrator"),
    ("P_DT", "numerics.dt"),
    ("P_TMAX", "numerics.t_max"),
    ("P_REST_SPEED", "numerics.rest_speed"),
    ("P_REST_SPIN", "numerics.rest_spin"),
    ("P_DRAG", "numerics.drag"),
    ("P_MUNK", "numerics.munk_factor"),
    ("P_RTOL", "numerics.rtol"),
    ("P_ATOL", "numerics.atol"),
    ("P_SED_QUADRATURE", "numerics.sediment_quadrature"),
    ("P_SLIP_SPEED", "numerics.slip_speed"),
    ("P_SWITCH_SPEED", "numerics.switch_speed"),
    ("P_TMAX_FALL", "numerics.t_max_fall"),
    ("P_WATER_COLUMN", "numerics.water_column"),
    ("P_OB_QUADRATURE", "numerics.overburden_quadrature"),
    # appended by issue 32 (the calibration coefficients)
    ("P_SED_DEPTH_FACTOR", "sediment.bearing_depth_factor"),
    ("P_CROSSFLOW_FACTOR", "numerics.crossflow_drag_factor"),
    ("P_SED_CD", "sediment.inertial_drag"),
    ("P_CROSSFLOW_MUNK", "numerics.crossflow_munk_fraction"),
    ("P_ADDED_MASS_FACTOR", "numerics.added_mass_factor"),
    ("P_SHAPE", "mine.shape"),
    ("P_TOP_RATIO", "mine.top_ratio"),
)


def _layout_constants():
    """(constant, slot path) of every ``P_X = INDEX["path"]`` in layout.py, in file order."""
    tree = ast.parse((ROOT / "mineburial" / "kernels" / "mine" / "layout.py").read_text())
    pairs = []
    for node in tree.body:
        if not isinstance(node, ast.Assign):
            continue
        for target in node.targets:
            assert not (
                isinstance(target, ast.Tuple)
                and any(getattr(e, "id", "").startswith("P_") for e in target.elts)
            ), "a positional unpack of the slot constants is back in layout.py: look them up by name"
        name = getattr(node.targets[0], "id", "")
        if name.startswith("P_"):
            value = node.value
            assert isinstance(value, ast.Subscript) and getattr(value.value, "id", "") == "INDEX", name
            pairs.append((name, value.slice.value))
    return pairs


def test_slot_layout_did_not_drift_from_the_compiled_kernels_layout():
    assert layout.PARAM_NAMES == tuple(path for _, path in PINNED)
    assert layout.PARAM_NAMES == tuple(f.path for f in scenario_fields.TABLE if f.slot)
    for constant, path in PINNED:
        assert getattr(layout, constant) == PINNED.index((constant, path)), constant


def test_every_slot_has_exactly_one_constant_looked_up_by_name():
    pairs = _layout_constants()
    assert sorted(pairs) == sorted(PINNED)
    assert len({c for c, _ in pairs}) == len({p for _, p in pairs}) == layout.N_PARAMS


def test_kernels_import_only_slot_constants_that_exist():
    """A slot constant a kernel imports (or reads as ``layout.P_X``) is one of layout's."""
    used = set()
    for path in (ROOT / "mineburial").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module == "mineburial.kernels.mine.layout":
                used |= {(path.name, a.name) for a in node.names if a.name.startswith("P_")}
            if isinstance(node, ast.Attribute) and getattr(node.value, "id", "") == "layout":
                if node.attr.startswith("P_"):
                    used.add((path.name, node.attr))
    assert used, "found no use of the slot constants: the scan is broken"
    defined = {c for c, _ in PINNED}
    assert {(f, c) for f, c in used if c not in defined} == set()


def test_every_declared_default_lies_inside_its_own_range():
    for f in scenario_fields.TABLE:
        assert f.description, f.path
        if f.default is None:
            continue
        if f.kind == "choice":
            assert f.default in f.choices, f.path
        elif f.kind == "bool":
            assert isinstance(f.default, bool), f.path
        else:  # a list's every element (scour.burial_levels)
            assert np.all(f.contains(f.default)), (f.path, f.default, f.range_text())


def test_fields_is_the_numeric_part_of_the_table_and_codes_are_not_sampled():
    assert set(config.FIELDS) == {f.path for f in scenario_fields.TABLE if f.kind == "float" and f.sampled}
    assert all(config.ALIASES[a] in config.FIELDS for a in config.ALIASES)
    assert {f.path for f in scenario_fields.TABLE if f.kind == "code"} == {
        "sediment.profile_index",
        "current.table_index",
    }
    assert not any(f.sampled for f in scenario_fields.TABLE if f.kind == "code")


def test_range_text_shows_open_and_closed_ends():
    assert SCHEMA["mine.length"].range_text() == "(0, 50] m"
    assert SCHEMA["mine.com_offset"].range_text() == "(-25, 25) m"
    assert SCHEMA["environment.air_density"].range_text() == "[0, 10] kg m-3"
    assert SCHEMA["numerics.drag"].range_text() == "true or false"


# ---------------------------------------------------------------------------
# cross-field rules: one declaration, the same verdict per scenario and over packed rows
# ---------------------------------------------------------------------------
def _scenario_dict(v):
    return {
        "mine": {
            "length": v["length"],
            "diameter": 0.5,
            "mass": 700.0,
            "com_offset": v["com_offset"],
            "inertia_axial": v["j1"],
            "inertia_transverse": v["j2"],
        },
        "release": {"position": [0.0, 0.0, v["z"]], "pitch_deg": v["pitch"], "embedded": v["embedded"]},
        "environment": {"water_depth": v["depth"]},
        "sediment": {"density": 1500.0, "strength": 2000.0},
        "numerics": {"dt": v["dt"], "t_max": v["t_max"], "t_max_fall": v["t_max_fall"]},
    }


_BASE = Scenario.from_dict(
    _scenario_dict(
        {
            "length": 2.0,
            "com_offset": 0.0,
            "j1": 20.0,
            "j2": 200.0,
            "z": 1.0,
            "pitch": 0.0,
            "embedded": False,
            "depth": 30.0,
            "dt": 1e-3,
            "t_max": 60.0,
            "t_max_fall": 600.0,
        }
    )
).to_params()[0]


def _packed_row(v):
    p = _BASE.copy()
    q = config.quaternion_from_angles(0.0, math.radians(v["pitch"]), 0.0)
    slots = {
        "mine.length": v["length"],
        "mine.com_offset": v["com_offset"],
        "mine.inertia_axial": v["j1"],
        "mine.inertia_transverse": v["j2"],
        "release.z": v["z"],
        "environment.water_depth": v["depth"],
        "numerics.dt": v["dt"],
        "numerics.t_max": v["t_max"],
        "numerics.t_max_fall": v["t_max_fall"],
    }
    slots.update({f"release.q{i}": q[i] for i in range(4)})
    for path, value in slots.items():
        p[layout.INDEX[path]] = value
    return p


_inputs = st.fixed_dictionaries(
    {
        "length": st.floats(0.2, 4.0),
        "com_offset": st.floats(-2.5, 2.5),
        "j1": st.floats(1.0, 400.0),
        "j2": st.floats(1.0, 200.0),
        "z": st.floats(-25.0, 3.0),
        "pitch": st.floats(-90.0, 90.0),
        "embedded": st.booleans(),
        "depth": st.floats(1.0, 20.0),
        "dt": st.floats(1e-4, 1.0),
        "t_max": st.floats(1e-3, 2.0),
        "t_max_fall": st.floats(1e-3, 2.0),
    }
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_inputs)
def test_each_rule_refuses_the_same_inputs_per_scenario_and_over_packed_rows(v):
    try:
        Scenario.from_dict(_scenario_dict(v))
        scalar_ok = True
    except ScenarioError:
        scalar_ok = False
    row = _packed_row(v)
    assert bool(check_params(row, 0, 0, embedded=v["embedded"])[0]) == scalar_ok, explain_params(
        row, 0, 0, embedded=v["embedded"]
    )


def test_each_rule_is_exercised_and_named_in_explanations():
    """Every rule that a scenario can break shows up by its text when its row is broken."""
    broken = {
        "|mine.com_offset| < mine.length/2": {"mine.com_offset": 1.5},
        "mine.inertia_axial <= 2 mine.inertia_transverse": {"mine.inertia_axial": 500.0},
        "release.z > -environment.water_depth": {"release.z": -31.0},
        "the mine starts entirely above the seabed (release.embedded = false)": {"release.z": -29.9},
        "numerics.dt <= numerics.t_max": {"numerics.t_max": 1e-4},
        "numerics.dt <= numerics.t_max_fall": {"numerics.t_max_fall": 1e-4},
        "the release quaternion has unit norm (within 1e-9)": {"release.q0": 0.5},
        "current.table_index >= 0 exactly when current.kind is 'table'": {"current.table_index": 0.0},
        # the frustum's (issue 36): mine.shape's code 1
        "the COM inside the frustum: -h_c < mine.com_offset < mine.length - h_c": {
            "mine.shape": 1.0,
            "mine.com_offset": 1.5,
        },
        "mine.top_ratio = 1 unless mine.shape is 'frustum'": {"mine.top_ratio": 0.5},
        "numerics.model is 'mineburial' when mine.shape is 'frustum'": {
            "mine.shape": 1.0,
            "numerics.model": 1.0,
        },
    }
    assert set(broken) == {r.text for r in RULES}
    for text, changes in broken.items():
        p = _BASE.copy()
        for path, value in changes.items():
            p[layout.INDEX[path]] = value
        reasons = explain_params(p, 0, 1)
        assert any(r.startswith(text) for r in reasons), (text, reasons)


def test_scalar_rule_message_names_field_value_range_and_unit():
    d = _scenario_dict(
        {
            "length": 2.0,
            "com_offset": 1.0,
            "j1": 20.0,
            "j2": 200.0,
            "z": 1.0,
            "pitch": 0.0,
            "embedded": False,
            "depth": 30.0,
            "dt": 1e-3,
            "t_max": 60.0,
            "t_max_fall": 600.0,
        }
    )
    with pytest.raises(
        ScenarioError, match=r"mine\.com_offset = 1\.0 m is outside the allowed range \(-1, 1\) m"
    ):
        Scenario.from_dict(d)
    d["mine"]["com_offset"] = 0.0
    d["numerics"]["t_max"] = 1e-4
    with pytest.raises(
        ScenarioError, match=r"numerics\.dt = 0\.001 s is outside the allowed range \(0, 0\.0001\] s"
    ):
        Scenario.from_dict(d)


# ---------------------------------------------------------------------------
# the documentation's field tables are generated from the declarations
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(config.DOC_BLOCKS))
def test_scenario_doc_field_table_did_not_drift_from_the_table(name):
    doc = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    assert config.field_table_block(name) in doc, (
        "regenerate: python -c "
        "'from mineburial.systems.mine.config import write_field_tables; write_field_tables()'"
    )


def test_restraint_doc_field_table_did_not_drift_from_its_fields():
    from mineburial.systems.restraint import model as restraint

    doc = (ROOT / "docs" / "restraint.md").read_text(encoding="utf-8")
    assert restraint.field_table_block() in doc, (
        "regenerate: python -c 'from mineburial.systems.restraint.model import write_field_table; "
        "write_field_table()'"
    )


def test_every_field_a_user_sets_is_in_one_doc_table():
    listed = [p for paths in config.DOC_TABLES.values() for p in paths]
    assert sorted(listed) == sorted(f.path for f in scenario_fields.TABLE if f.kind != "code")


def test_write_field_tables_restores_an_edited_table(tmp_path):
    original = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    edited = original.replace("| `length` | `mine.length` | m | required | (0, 50] |", "| `length` | x |", 1)
    assert edited != original
    path = tmp_path / "scenario.md"
    path.write_text(edited, encoding="utf-8")
    config.write_field_tables(path)
    assert path.read_text(encoding="utf-8") == original


def test_the_model_defaults_table_says_what_a_scenario_of_each_model_resolves_to():
    doc = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    block = doc.split("<!-- table model-defaults")[1].split("<!-- end of table")[0]
    rows = [[c.strip().strip("`").split('"')[1] for c in line.strip("|").split("|")]
            for line in block.splitlines()[3:]]  # fmt: skip
    assert {r[0] for r in rows} == {"mineburial", "impact35"}
    for model, resistance, rate_law, integrator in rows:
        d = {"mine": {"length": 2.0, "diameter": 0.5, "mass": 700.0}, "environment": {"water_depth": 30.0}}
        s = Scenario.from_dict({**d, "sediment": {"class": "soft_clay"}, "numerics": {"model": model}})
        assert (s.sediment.resistance, s.sediment.rate_law) == (resistance, rate_law)
        assert s.numerics.integrator == integrator


def test_every_key_of_the_scour_section_is_a_declared_field_listed_in_its_doc_table():
    from mineburial.systems.mine.processes import scour

    doc = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    block = doc.split("<!-- table scour:")[1].split("<!-- end of table scour")[0]
    listed = [line.split("|")[1].strip().strip("`") for line in block.splitlines()[3:]]
    # the keys its reader accepted before they were declared (mineburial/systems/mine/processes/scour.py,
    # ee0fb46); issue 33 added burial_law ... mobility_drag (the scour-and-settle law's; rest_attitude: the
    # tilt)
    assert listed == list(scour.KEYS) == [
        "forcing", "storm", "forcing_grid", "forcing_location", "lead_times_days", "burial_levels",
        "cohesive", "tstar_law", "window_days", "d50", "grain_density", "mobile_layer", "beq_a", "beq_b",
        "theta_exponent", "ripple_exposure", "burial_law", "wave_a", "wave_kc_exponent", "infill_days",
        "bed_lowering_rate", "mobility", "rest_attitude", "mobility_drag", "hs_scale", "window_position",
        "orbital", "friction",
    ]  # fmt: skip


def test_the_dataclasses_take_keys_defaults_and_resolved_order_from_the_declarations():
    # as config.py wrote them by hand at ee0fb46 (the resolved scenario's key order is in every output file)
    assert set(config._RELEASE_KEYS) == {
        "position", "velocity", "angular_velocity", "roll_deg", "pitch_deg", "heading_deg", "quaternion",
        "embedded",
    }  # fmt: skip
    d = {"mine": {"length": 2.0, "diameter": 0.5, "mass": 700.0}, "environment": {"water_depth": 30.0}}
    s = Scenario.from_dict({**d, "sediment": {"class": "soft_clay"}})
    out = s.to_dict()
    assert list(out["mine"]) == [
        "name", "length", "diameter", "mass", "com_offset", "inertia_axial", "inertia_transverse",
        "shape", "top_ratio",  # issue 36: the body's shape, declared after the last slotted field
    ]  # fmt: skip
    assert list(out["environment"]) == [
        "gravity", "air_density", "air_viscosity", "water_density", "water_viscosity", "water_depth",
        "current",
    ]  # fmt: skip
    # defaults written once, in scenario_fields.py (docs/scenario.md: 9.81, 1025, 0.3, 0.05, false)
    assert (s.environment.gravity, s.environment.water_density) == (9.81, 1025.0)
    assert (s.sediment.friction, s.numerics.rest_spin, s.release.embedded) == (0.3, 0.05, False)
    with pytest.raises(ScenarioError, match=r"^mine\.mass \[kg\] is required$"):
        Scenario.from_dict(
            {**d, "mine": {"length": 2.0, "diameter": 0.5}, "sediment": {"class": "soft_clay"}}
        )
    p, _, _ = Scenario.from_dict(
        {**d, "sediment": {"class": "soft_clay"}, "release": {"position": [1, 2, 3]}}
    ).to_params()
    assert [p[layout.INDEX[k]] for k in ("release.x", "release.y", "release.z")] == [1.0, 2.0, 3.0]


# ---------------------------------------------------------------------------
# to_dict and the rules per scenario read every declared field (no hand-written key lists)
# ---------------------------------------------------------------------------
#: every field a scenario holds: the field table less the [scour] stage's keys (its own reader's)
_DECLARED = [f for f in scenario_fields.TABLE if f.section != "scour"]

_LINEAR = {"density": 1500.0, "strength": 2000.0}
#: scenarios that together give each alternative form once: the orientation as angles and as a
#: quaternion, the profile linear and tabulated, and each kind of current
_VARIANTS = [
    {"release": {"pitch_deg": 10.0}, "sediment": _LINEAR, "current": {"kind": "power_law"}},
    {"release": {"quaternion": [1.0, 0.0, 0.0, 0.0]}, "sediment": {"class": "soft_clay"}},
    {"sediment": _LINEAR, "current": {"kind": "uniform", "velocity": [0.3, 0.1]}},
    {
        "sediment": _LINEAR,
        "current": {"kind": "table", "depth": [0.0, 5.0], "u": [0.1, 0.2], "v": [0.0, 0.0]},
    },
]


def _variant(v) -> Scenario:
    current = v.get("current", {"kind": "none"})
    if current["kind"] == "power_law":
        current = {**current, "surface_velocity": [0.5, 0.0], "exponent": 0.2}
    return Scenario.from_dict(
        {
            "mine": {"length": 2.0, "diameter": 0.5, "mass": 700.0},
            "release": {"position": [0.0, 0.0, 1.0], **v.get("release", {})},
            "environment": {"water_depth": 30.0, "current": current},
            "sediment": v["sediment"],
        }
    )


def _at(d, location: str):
    """The value at a file location (``release.position[2]``) of a nested dict, or KeyError."""
    for part in location.split("."):
        key, _, index = part.partition("[")
        d = d[key] if not index else d[key][int(index.rstrip("]"))]
    return d


def test_to_dict_writes_every_declared_field_at_its_declared_location():
    """Each field with a file location (scenario_fields.TABLE) is written there by some
    resolved scenario, with its value; a field added to the table but left out of to_dict fails."""
    found = set()
    for v in _VARIANTS:
        s = _variant(v)
        d, values = s.to_dict(), s.field_values()
        for f in _DECLARED:
            # a power-law current writes its (u, v) as surface_velocity (docs/scenario.md)
            locations = (
                {f.location, f.location.replace("velocity[", "surface_velocity[")} if f.location else ()
            )
            for location in locations:
                try:
                    value = _at(d, location)
                except (KeyError, IndexError):
                    continue
                found.add(f.path)
                assert f.pack(value) == values[f.path], (f.path, value)
        assert Scenario.from_dict(d) == s
    assert found == {f.path for f in _DECLARED if f.location}


def test_field_values_hold_exactly_the_declared_fields():
    s = _variant(_VARIANTS[1])
    assert set(s.field_values()) == {f.path for f in _DECLARED}
    assert {p for rule in RULES for p in rule.paths} <= {f.path for f in _DECLARED}
    p, _, _ = s.to_params()
    values = s.field_values()
    assert [p[layout.INDEX[name]] for name in layout.PARAM_NAMES] == [values[n] for n in layout.PARAM_NAMES]


def test_a_rule_on_any_declared_fields_is_evaluated_per_scenario(monkeypatch):
    """A new rule is declared in RULES only: the scenario's check reads every declared field,
    so a rule over all of them (here one that never holds) is evaluated, not skipped as one
    whose fields the check was not handed."""
    every = config.Rule(
        "a rule over every field",
        tuple(f.path for f in _DECLARED),
        lambda v: np.zeros(np.shape(v["mine.length"]), dtype=bool),
        message=lambda v: "the rule over every field was evaluated",
    )
    for v in _VARIANTS:
        _variant(v)  # valid without it
    monkeypatch.setattr(config, "RULES", (*RULES, every))
    for v in _VARIANTS:
        with pytest.raises(ScenarioError, match="^the rule over every field was evaluated$"):
            _variant(v)
