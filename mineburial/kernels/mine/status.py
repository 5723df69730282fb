"""The falling mine's status codes: the integration core's shared codes (:mod:`mineburial.kernels.status`)
with the mine's name for the normal end, and the mine's own codes; registered as the mine's
:class:`~mineburial.kernels.status.Vocabulary` (issue 36 item 5). The kernels compare the codes as
these module-level ints (numba globals: compile-time constants).

How each status enters the ensemble statistics is stated in ``IN_STATISTICS`` and docs/design.md:
drops at rest and drops fully buried and still sinking at the time limit carry a burial (the latter as
a lower bound of the penetration, 100 % burial); drops that floated never reached the seabed and are
counted apart; the others are left out and counted.

The codes, names and their order are those every output file holds (``status``'s ``flag_values`` and
``flag_meanings``): a new code is only ever appended. Imports only the shared vocabulary (no numba).
"""

from mineburial.kernels import status as _core
from mineburial.kernels.status import END, INVALID_INPUT, NUMERICAL_FAILURE, TIME_LIMIT

__all__ = [
    "END",
    "TIME_LIMIT",
    "NUMERICAL_FAILURE",
    "INVALID_INPUT",
    "AT_REST",
    "LEFT_DOMAIN",
    "FLOATED",
    "BURIED_SINKING",
    "NAMES",
    "DESCRIPTIONS",
    "IN_STATISTICS",
    "VOCABULARY",
]

#: the value of the scenario's ``system`` key of the mine (mineburial.systems.mine.ensemble.SYSTEM)
SYSTEM = "mine"

AT_REST = END
LEFT_DOMAIN = 2
FLOATED = 5
BURIED_SINKING = 6

#: the names of the codes 0, 1, 2, ... (a code is its index)
NAMES = (
    "at_rest",
    _core.SHARED_NAMES[TIME_LIMIT],
    "left_domain",
    _core.SHARED_NAMES[NUMERICAL_FAILURE],
    _core.SHARED_NAMES[INVALID_INPUT],
    "floated",
    "buried_sinking",
)

DESCRIPTIONS = (
    "the mine came to rest in or on the sediment (seed 000 eq. (89) speed criterion and "
    "the rigid-plastic hold test, kernels/mine/rest.py)",
    "the mine was still moving, not fully buried, when its time limit was reached "
    "(numerics.t_max after its first seabed contact; numerics.t_max_fall if it was still falling), "
    "or after the stepper's budget of 5e7 steps",
    "the mine left the modelled domain",
    "a non-finite value appeared in the state, or the step size underflowed (numerical failure)",
    "a sampled input was outside its physical range; the drop was not run",
    "the mine is lighter than the water and rose back before reaching the seabed",
    "the mine was fully buried and still sinking at the time limit (numerics.t_max after its first "
    "seabed contact; penetration is a lower bound)",
)

#: statuses whose burial enters the burial statistics
IN_STATISTICS = (AT_REST, BURIED_SINKING)

#: the mine's vocabulary in the registry of :mod:`mineburial.kernels.status`
VOCABULARY = _core.register(
    _core.Vocabulary(SYSTEM, dict(enumerate(NAMES)), dict(enumerate(DESCRIPTIONS)), IN_STATISTICS)
)
