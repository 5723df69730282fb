"""Status codes that a run returns: the vocabulary every system of the integration core shares, then
the falling mine's own codes (see docs/design.md "integration core").

Kernels never raise: each run ends with one of these codes, which the Python side records per drop or
case (CF ``flag_values``/``flag_meanings``) and turns into explanatory messages. The shared codes
(issue 18): 0 the system's normal end, which the system names (the mine ``at_rest``, the multibody
systems ``stopped``), 1 the time limit, 3 a numerical failure, 4 invalid inputs (nothing run); 2 and
5 and up are a system's own (2 is the mine's ``left_domain``, older than this vocabulary). This module
imports nothing, so that the variable registry and the command line read it without numba.

The mine: how each status enters the ensemble statistics is stated in ``IN_STATISTICS`` and
docs/design.md: drops at rest and drops fully buried and still sinking at the time limit carry a burial
(the latter as a lower bound of the penetration, 100 % burial); drops that floated never reached the
seabed and are counted apart; the others are left out and counted.
"""

# --- shared by every system of the integration core ----------------------------------------------------
#: the system's normal end (named by the system)
END = 0
#: the time limit was reached before the system's end
TIME_LIMIT = 1
#: a non-finite state or rate, a step-size underflow or the step budget spent
NUMERICAL_FAILURE = 3
#: the inputs were invalid; nothing was run
INVALID_INPUT = 4

# --- the falling mine's ------------------------------------------------------------------------------------
AT_REST = END
LEFT_DOMAIN = 2
FLOATED = 5
BURIED_SINKING = 6

NAMES = (
    "at_rest",
    "time_limit",
    "left_domain",
    "numerical_failure",
    "invalid_input",
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
