"""A linear test system y' = A y (A passed as the system's parameters) with no event, for the tests of the
integration core's Rosenbrock-W step: its Jacobian is A itself, an independent reference for the step."""

from numba import njit


@njit
def linear_rhs(t, y, a, dy):
    """dy = A y."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += a[i, j] * y[j]
        dy[i] = acc


@njit
def no_event(t, y, a):
    """An event that never happens (a positive value)."""
    return 1.0
