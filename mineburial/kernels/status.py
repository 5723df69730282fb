"""Status codes that a drop kernel returns (see docs/design.md).

Kernels never raise: each drop ends with one of these codes, which the Python
side records per drop (CF ``flag_values``/``flag_meanings``) and turns into
explanatory messages.
"""

AT_REST = 0
TIME_LIMIT = 1
LEFT_DOMAIN = 2
NUMERICAL_FAILURE = 3
INVALID_INPUT = 4

NAMES = ("at_rest", "time_limit", "left_domain", "numerical_failure", "invalid_input")

DESCRIPTIONS = (
    "the mine came to rest in or on the sediment (seed 000 eq. (89), speed criterion)",
    "the mine was still moving when the time limit was reached",
    "the mine left the modelled domain",
    "a non-finite value appeared in the state (numerical failure)",
    "a sampled input was outside its physical range; the drop was not run",
)
