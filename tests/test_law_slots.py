"""The packed sediment law's slots are named by the scenario schema (issue 36 item 4).

Independent reference: the parameter vector's own layout (``layout.INDEX``, built from the scenario fields)
and the documented rules of the derived slots; :func:`pack_law` must put each field's value from its
parameter slot into the slot :data:`laws.LAW_NAMES` names for it.
"""

import math

import numpy as np
import pytest

from mineburial.kernels.mine import layout
from mineburial.kernels.mine.sediment import laws
from mineburial.systems.mine.scenario_fields import TABLE

FIELDS = {f.path for f in TABLE}
INTEGER_FIELDS = {"sediment.rate_law", "sediment.profile_index", "numerics.sediment_quadrature"}


def test_every_slot_is_a_field_a_derived_value_or_a_type_code():
    assert len(set(laws.LAW_NAMES)) == len(laws.LAW_NAMES)
    for name in laws.LAW_NAMES:
        kind = name.split(".")[0]
        assert name in FIELDS and name in layout.INDEX or kind in ("derived", "code"), name


def _params(rng, resistance=2.0, bearing=9.0, pore=1.0):
    p = rng.uniform(0.1, 2.0, layout.N_PARAMS)
    for name in INTEGER_FIELDS:
        p[layout.INDEX[name]] = float(rng.integers(0, 2))
    p[layout.P_SED_RESISTANCE] = resistance
    p[layout.P_SED_NC] = bearing
    p[layout.P_SED_PORE] = pore
    return p


def test_pack_law_fills_each_field_slot_from_its_parameter_slot():
    rng = np.random.default_rng(36)
    for _ in range(3):
        p = _params(rng)
        law = laws.pack_law(p, 0.53, None)
        assert len(law) == len(laws.LAW_NAMES)
        for k, name in enumerate(laws.LAW_NAMES):
            if name in layout.INDEX:
                want = p[layout.INDEX[name]]
                assert law[k] == (int(want) if name in INTEGER_FIELDS else want), name


@pytest.mark.parametrize(
    "resistance, bearing, pore, model, n0, pore_on",
    [
        (2.0, 9.0, 1.0, laws.RES_BEARING, 9.0, True),
        (1.0, 7.5, 0.0, laws.RES_FRICTION, 7.5, False),
        (5.0, -1.0, 0.0, laws.RES_DELTA, math.pi + 2.0, False),  # unknown code: delta; N_c <= 0: Prandtl
    ],
)
def test_derived_slots_follow_their_rules(resistance, bearing, pore, model, n0, pore_on):
    p = _params(np.random.default_rng(1), resistance, bearing, pore)
    law = laws.pack_law(p, 0.53, None)
    assert law[laws.LAW_MODEL] == model
    assert law[laws.LAW_N0] == n0
    assert law[laws.LAW_DIAMETER] == 0.53
    assert law[laws.LAW_PORE] is pore_on
    assert law[laws.LAW_REFERENCE_PATHS] is None
