"""The scour stage's parameter vector, named by the scenario schema (issue 33 item 1: a process's
fields schema-declared, its parameter layout derived; issue 36 item 4): each slot of
``kernels/mine/scour.PARAM_NAMES`` is a ``[scour]`` field of mineburial/systems/mine/scenario_fields.py, a
value derived per drop, or a constant of the code; the kernel's defaults of the field slots are the
schema's defaults (the kernel restates none of its own); a run fills each field slot with that
field's value, by name."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mineburial.io import forcing as fio
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as sc
from mineburial.systems.mine import config as cfg
from mineburial.systems.mine.processes import scour

#: the fields given in days whose slots hold seconds (s per day, or days per s for a rate)
SECONDS = {"scour.infill_days": 86400.0, "scour.bed_lowering_rate": 1.0 / 86400.0}


def test_every_slot_is_a_field_a_derived_value_or_a_constant_and_slots_are_distinct():
    assert len(set(sc.PARAM_NAMES)) == len(sc.PARAM_NAMES) == sc.N_PARAMS
    for name in sc.PARAM_NAMES:
        kind, _, rest = name.partition(".")
        assert kind in ("scour", "derived", "code") and rest, name
        assert (name in cfg.SCHEMA) == (kind == "scour"), name
        if kind == "scour":
            assert cfg.SCHEMA[name].section == "scour"
    constants = {k: v for k, v in vars(sc).items() if k.startswith("S_") and isinstance(v, int)}
    assert sorted(constants.values()) == list(range(sc.N_PARAMS))
    assert sc.S_D50 == sc.slot("scour.d50") and sc.S_AXIS_SPAN == sc.slot("derived.axis_span")
    with pytest.raises(KeyError, match="no stage parameter 'scour.nonsense'"):
        sc.slot("scour.nonsense")


def test_the_kernel_defaults_of_the_field_slots_are_the_schema_defaults():
    """default_parameters() (the kernel's standalone defaults, used by tests and the calibration's
    scour case) holds, in every field slot, the schema's default as the slot holds it: a choice's
    code, a switch's 0/1, days in seconds, no value (no mobile-layer limit) as inf, and the T*
    exponent of the default T* law where the schema leaves it to the law."""
    p = sc.default_parameters()
    law = cfg.SCHEMA["scour.tstar_law"].default
    for k, name in enumerate(sc.PARAM_NAMES):
        if not name.startswith("scour."):
            continue
        field = cfg.SCHEMA[name]
        if field.kind == "choice":
            want = float(field.choices.index(field.default))
        elif field.default is None:
            want = sc.TSTAR_LAWS[law][2] if name == "scour.theta_exponent" else math.inf
        else:
            want = float(field.default) * SECONDS.get(name, 1.0)
        assert p[k] == want, (name, p[k], want)


def test_a_run_fills_each_field_slot_with_the_field_s_value_by_name(tmp_path):
    """A section giving every numeric field and every choice a value other than its default: the
    stage's parameter row holds each value in the slot named by the field, converted as the slot
    holds it (the packing written out here)."""
    forcing = fio.storm_series(1.5, 9.0, 12.0, current=0.2)
    path = fio.write_csv(forcing, tmp_path / "storm.csv")
    given = {
        "d50": 3.1e-4,
        "grain_density": 2700.0,
        "mobile_layer": 0.4,
        "beq_a": 1.11,
        "beq_b": 0.33,
        "theta_exponent": -1.5,
        "ripple_exposure": 1.25,
        "wave_a": 0.21,
        "wave_kc_exponent": 0.61,
        "infill_days": 7.5,
        "bed_lowering_rate": 0.002,
        "mobility_drag": 1.05,
    }
    choices = {
        "orbital": "hrms",
        "friction": "soulsby",
        "burial_law": "scour_settle",
        "mobility": "pocket",
        "rest_attitude": "impact",
    }
    sec = {"forcing": str(path), "lead_times_days": [0.0, 0.5], "cohesive": False, **given, **choices}
    spec = scour.parse(sec)
    n = 3
    P = np.zeros((n, layout.N_PARAMS))
    P[:, layout.P_MASS] = 750.0
    P[:, layout.P_RHO_WATER] = 1025.0
    P[:, layout.P_NU_WATER] = 1.05e-6
    P[:, layout.P_GRAVITY] = 9.81
    P[:, layout.P_LENGTH] = 2.0
    P[:, layout.P_DIAMETER] = 0.53
    S, _ = scour.stage_parameters(spec, P, {})
    for name, value in given.items():
        want = value * SECONDS.get(f"scour.{name}", 1.0)
        np.testing.assert_array_equal(S[:, sc.slot(f"scour.{name}")], want, err_msg=name)
    for name, label in choices.items():
        code = float(cfg.SCHEMA[f"scour.{name}"].choices.index(label))
        np.testing.assert_array_equal(S[:, sc.slot(f"scour.{name}")], code, err_msg=name)
    np.testing.assert_array_equal(S[:, sc.slot("scour.cohesive")], 0.0)
    assert set(scour.NUMERIC) - {"hs_scale", "window_position"} == set(given)
    assert set(scour.CHOICES) == set(choices)
