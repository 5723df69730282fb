"""The integration core (kernels/core.py, issue 18 item 1) against independent references.

* systems reached by static dispatch are cached on disk: the compiled driver of a system can be loaded
  from numba's cache after one run (before, it took its system as first-class functions, which numba
  does not cache, and every process compiled it again, 10-60 s);
* the Rosenbrock-W step (ROS34PW2) of the multibody driver on a stiff system -- a pendulum with regularised
  Coulomb friction at its pin -- against scipy's Radau on the same equation written out by hand, and its
  stop event;
* the restraint of seed 004 run with ROS34PW2 stops where dopri5 at a tight tolerance does;
* one status vocabulary: the codes the mine and the multibody systems share are those issue 18 fixed, and
  the mine's are still those of its status table in docs/design.md;
* both drivers step only through the core's attempt_step (the mine kept copies of the steps before), whose
  steps have their methods' stability functions, reject a non-finite trial, and whose methods every
  system offers.
"""

import math
import pathlib
import re

import numpy as np
import pytest
from numba import njit
from scipy.integrate import solve_ivp

from mineburial import _numba
from mineburial import multibody as mbp
from mineburial.kernels import core, methods
from mineburial.kernels import multibody as mb
from mineburial.kernels.core import System
from mineburial.kernels.mine import layout, stepper
from mineburial.kernels.mine import status as st
from mineburial.systems.restraint import model as R

G = 9.81
MASS, LENGTH = 2.0, 1.0
#: friction couple at the pin, -T0 om / sqrt(om^2 + W_REG^2) (seed 004's regularised Coulomb law,
#: kernels/seabed_contact.regularised_friction): its slope T0 / W_REG / I ~ 1.5e4 1/s near om = 0 is
#: what makes the system stiff
T0, W_REG = 1.0, 1e-4
INERTIA_PIN = MASS * LENGTH**2 / 3.0


@njit
def friction_rhs(t, y, p, dy):
    desc = p
    q = y[:1]
    u = y[1:]
    f = np.zeros((2, 3))
    f[1, 1] = -MASS * G
    f[1, 2] = -T0 * u[0] / math.sqrt(u[0] * u[0] + W_REG * W_REG)
    du = mb.accelerations(q, u, f, desc)
    dy[0] = u[0]
    dy[1] = du[0]


@njit
def swing_event(t, y, p):
    # the swing's end: the angular velocity (negative while the rod falls) returns to zero
    return -y[1]


@njit
def no_event(t, y, p):
    return 1.0


FRICTION_PENDULUM = System("test friction pendulum", friction_rhs, swing_event)
FRICTION_PENDULUM_FREE = System("test friction pendulum, no stop", friction_rhs, no_event)


def reference(t_end, y0, events=None, t_eval=None):
    """The same pendulum by hand: I th'' = -m g L/2 cos th - T0 om / sqrt(om^2 + W_REG^2), Radau."""

    def f(t, y):
        th, om = y
        torque = -MASS * G * LENGTH / 2.0 * math.cos(th) - T0 * om / math.sqrt(om * om + W_REG * W_REG)
        return [om, torque / INERTIA_PIN]

    return solve_ivp(
        f, (0.0, t_end), y0, method="Radau", rtol=1e-11, atol=1e-12, events=events, t_eval=t_eval
    )


def pendulum():
    desc, q0 = mbp.chain(1, LENGTH, mbp.rigid_mass_matrix(MASS, MASS * LENGTH**2 / 12.0), [-0.3])
    return desc, desc.initial_state(q0)


def test_a_system_driver_is_cached_on_disk():
    desc, y0 = pendulum()
    res = mbp.integrate(FRICTION_PENDULUM, y0, 0.0, 0.1, desc.arrays(), record_dt=0.05)
    assert res.status_name in ("time_limit", "stopped")
    if not _numba.cache_enabled():
        return  # MINEBURIAL_NUMBA_CACHE=0: nothing is cached, by request
    sigs = mb.integrate.signatures
    assert sigs
    loaded = [mb.integrate._cache.load_overload(sig, mb.integrate.targetctx) for sig in sigs]
    assert all(c is not None for c in loaded)


def test_ros34pw2_follows_radau_on_a_stiff_friction_pendulum():
    desc, y0 = pendulum()
    t_end = 3.0  # several swings, each ending in a stiff near-stick of the friction law
    res = mbp.integrate(
        FRICTION_PENDULUM_FREE, y0, 0.0, t_end, desc.arrays(), method="ros34pw2", dt=1e-3, rtol=1e-8,
        atol=1e-10, record_dt=0.25, jacobian_columns=[1],
    )  # fmt: skip
    assert res.status_name == "time_limit" and res.times[-1] == t_end
    ref = reference(t_end, list(y0), t_eval=res.times)
    # the records come from the step's cubic Hermite extension: ~1e-7 here
    np.testing.assert_allclose(res.states, ref.y.T, atol=1e-5)


def test_ros34pw2_locates_the_stop_event():
    desc, y0 = pendulum()
    res = mbp.integrate(
        FRICTION_PENDULUM, y0, 0.0, 3.0, desc.arrays(), method="ros34pw2", dt=1e-3, rtol=1e-9,
        atol=1e-11, record_dt=0.25,
    )  # fmt: skip
    ref = reference(3.0, list(y0), events=lambda t, y: -y[1] if t > 1e-3 else 1.0)
    t_stop = ref.t_events[0][0]
    assert res.status_name == "stopped"
    assert res.t_stop == pytest.approx(t_stop, abs=1e-6)
    assert abs(res.states[-1, 1]) < 1e-6


def test_bad_jacobian_columns_are_refused():
    desc, y0 = pendulum()
    with pytest.raises(mbp.DescriptionError, match=r"jacobian_columns = \[2\] must be indices of the state"):
        mbp.integrate(FRICTION_PENDULUM, y0, 0.0, 1.0, desc.arrays(), method="ros34pw2", jacobian_columns=[2])
    with pytest.raises(mbp.DescriptionError, match="must not repeat an index"):
        mbp.integrate(FRICTION_PENDULUM, y0, 0.0, 1.0, desc.arrays(), jacobian_columns=[1, 1])


#: ROS34PW2 at the cases' default tolerances (rtol 1e-7, atol 1e-9) against dopri5 at rtol 1e-9, atol 1e-11:
#: measured 1.2e-7 s apart on case 3 (10.0606893 against 10.0606892 s); the bound leaves a factor ~100
ROS_STOP_TOLERANCE = 1e-5


@pytest.mark.parametrize("number", [3])  # one case: a full tight dopri5 run costs ~30-70 s
def test_restraint_ros34pw2_stops_where_tight_dopri5_does(number):
    ros = R.simulate(R.table2_case(number).replace(**{"numerics.integrator": "ros34pw2"}))
    ref = R.simulate(R.table2_case(number).replace(**{"numerics.rtol": 1e-9, "numerics.atol": 1e-11}))
    assert ros.status_name == "stopped" and ref.status_name == "stopped"
    assert ros.stopping_time == pytest.approx(ref.stopping_time, abs=ROS_STOP_TOLERANCE)
    assert ros.energy_closure() < 1e-6  # the energy balance of eqs. (63)-(69) closes as with dopri5


# --- one status vocabulary ----------------------------------------------------------------------------
#: the shared codes as issue 18 fixed them: 0 the system's own normal end, then these three
SHARED = {1: "time_limit", 3: "numerical_failure", 4: "invalid_input"}


def test_the_shared_status_codes_mean_the_same_in_every_system():
    for code, name in SHARED.items():
        assert st.NAMES[code] == name and mb.STATUS_NAMES[code] == name, code
    assert (st.END, st.TIME_LIMIT, st.NUMERICAL_FAILURE, st.INVALID_INPUT) == (0, 1, 3, 4)
    assert st.NAMES[0] == "at_rest" and mb.STATUS_NAMES[0] == "stopped"  # each names its own end
    # the multibody systems use no code of their own; their CF flags list exactly the shared ones
    assert mb.STATUS_CODES.tolist() == [0, 1, 3, 4]
    assert mb.STATUS_MEANINGS.split() == ["stopped", "time_limit", "numerical_failure", "invalid_input"]


def test_the_mine_status_codes_are_those_of_its_documented_table():
    """The mine's codes are in its NetCDF files: they must not move (docs/design.md, "Status codes")."""
    text = (pathlib.Path(__file__).parents[1] / "docs" / "design.md").read_text(encoding="utf-8")
    table = dict((int(c), n) for c, n in re.findall(r"^\| (\d) \| `(\w+)` \|", text, flags=re.M))
    assert table == dict(enumerate(st.NAMES)) and len(table) == 7


def test_both_drivers_run_the_cores_one_loop():
    """The mine's stepper kept copies of the core's steps, then called them and its own accept/reject;
    issue 18 item 1 made both drivers take every step through :func:`core.attempt_step`, and then run
    the core's one driver loop (:func:`core.driver_loop`) with their own hooks: neither has a loop or a
    step of its own."""
    for driver, entry in ((stepper, stepper.run_drop), (mb, mb.integrate)):
        names = entry.py_func.__code__.co_names
        assert {"driver_loop", "_next_step", "_accepted"} <= set(names), driver.__name__
        assert driver.driver_loop is core.driver_loop
        assert driver._next_step.py_func.__module__ == driver.__name__
        for name in (
            "attempt_step",
            "dopri5_step",
            "rk4_step",
            "ros34pw2_step",
            "next_step_size",
            "error_norm",
        ):
            assert not hasattr(driver, name), (driver.__name__, name)
    assert not hasattr(stepper, "velocity_jacobian")
    assert stepper.MINE.rhs is stepper.mine_rhs


# --- one table of methods: every system offers each of the core's -----------------------------------
def test_every_method_of_the_core_is_offered_by_both_systems():
    assert mb.METHODS == methods.METHOD_NAMES
    field = next(f for f in R.FIELDS if f.path == "numerics.integrator")
    assert field.choices == methods.METHOD_NAMES
    assert set(methods.METHOD_NAMES) <= set(layout.INTEGRATOR_NAMES)
    # the mine's first four codes are its parameter vector's P_INTEGRATOR since its first release
    assert layout.INTEGRATOR_NAMES[:4] == ("rk4", "local_linear", "dopri5", "dopri5_ros34pw2")
    assert len(set(layout.INTEGRATOR_NAMES)) == len(layout.INTEGRATOR_NAMES)


@njit
def linear_rhs(t, y, p, dy):
    # y' = lam y, p = (lam, limit): finite up to y = limit, infinite at any (trial) state above it
    dy[0] = p[0] * y[0] if y[0] <= p[1] else math.inf


@njit
def clamp_at_limit(y):
    # the projection of the linear test system: the state put back to at most 1 (a no-op for the decaying
    # states of the other tests)
    y[0] = min(y[0], 1.0)


@njit
def exact_linear_step(method, t, y, h, p, k, ytmp, out):
    # the linear test system's own fixed step: exact, y exp(lam h)
    out[0] = y[0] * math.exp(p[0] * h)


#: one test system for every attempt_step test (one compile of the kernel for it)
LINEAR = System("test linear", linear_rhs, no_event, project=clamp_at_limit, own_step=exact_linear_step)


def attempt(method, h, lam, limit=math.inf, jac_age=core.JAC_MAX_AGE, err_prev=1e-4):
    """One attempt_step of y' = lam y from y = 1; returns (accepted, h_next, err_prev, jac_age, ynew, ws)."""
    n = 1
    y = np.ones(n)
    k = np.empty((7, n))
    k[0, 0] = lam
    ws = (k, np.empty(n), np.empty(n), np.empty((5, n)), np.empty(n), np.array([0]), np.zeros((n, 1)),
          np.empty((1, 1)), np.empty(1, np.int64), np.empty((4, n)), np.empty(1))  # fmt: skip
    groups = np.array([[0, 1]])
    p = np.array([lam, limit])
    out = core.attempt_step(
        LINEAR, method, 0.0, y, h, p, True, groups, 1e-6, 1e-9, err_prev, True, jac_age, ws
    )
    return (*out, ws[1][0], ws)


@pytest.mark.parametrize(
    ("method", "polynomial"),
    [
        # the stability functions R(z), y1 = R(h lam) y0: classical RK4 sum_{j<=4} z^j / j!; the 5th-order
        # solution of Dormand-Prince 5(4) sum_{j<=5} z^j / j! + z^6 / 600 (Hairer, Norsett & Wanner I,
        # sec. IV.2, the stability domain of DOPRI5)
        (methods.RK4, [1, 1, 1 / 2, 1 / 6, 1 / 24]),
        (methods.DOPRI5, [1, 1, 1 / 2, 1 / 6, 1 / 24, 1 / 120, 1 / 600]),
    ],
)
def test_attempt_step_gives_each_explicit_methods_stability_function(method, polynomial):
    lam, h = -1.0, 0.05
    accepted, h_next, _, _, ynew, ws = attempt(method, h, lam)
    z = h * lam
    assert accepted
    assert ynew == pytest.approx(sum(c * z**j for j, c in enumerate(polynomial)), rel=1e-14)
    # the continuous extension of the accepted step runs from y0 to y1, and k[6] = f(y1)
    r = ws[3]
    out = np.empty(1)
    for theta, want in ((0.0, 1.0), (1.0, ynew)):
        core.dense_state(r, theta, out)
        assert out[0] == pytest.approx(want, rel=1e-14)
    assert ws[0][6, 0] == pytest.approx(lam * ynew, rel=1e-14)


def test_attempt_step_rosenbrock_w_is_l_stable_and_evaluates_its_jacobian_once():
    """ROS34PW2 is L-stable (Rang & Angermann 2005): R(z) -> 0 as z -> -inf; with the exact Jacobian of a
    linear equation (differences are exact for it) a huge step of a very stiff decay lands near 0."""
    accepted, _, _, age, ynew, ws = attempt(methods.ROS34PW2, 1.0, -1e8)
    assert ws[6][0, 0] == pytest.approx(-1e8, rel=1e-7)  # the Jacobian column by differences
    assert abs(ynew) < 1e-6
    assert age == (1 if accepted else 0)  # evaluated now (age 0), one accepted step on it


@pytest.mark.parametrize("method", [methods.DOPRI5, methods.ROS34PW2])
def test_attempt_step_rejects_a_non_finite_trial_by_the_largest_shrink(method):
    """A trial that reaches an infinite rate is rejected and the step cut by the controller's largest
    shrink factor (0.2, Hairer, Norsett & Wanner I sec. II.4 'facmin')."""
    accepted, h_next, err_prev, _, _, _ = attempt(method, 0.5, 1.0, limit=1.0, err_prev=3e-3)
    assert not accepted
    assert h_next == pytest.approx(0.1, rel=1e-15)
    assert err_prev == 3e-3  # the error memory of the PI controller is kept over a rejection


def test_a_fixed_step_is_projected_by_its_system_and_a_systems_own_step_is_its_own():
    """core.fixed_trial calls the system's projection after an RK4 step and its own step for the codes from
    methods.OWN_METHOD up, directly (no overload of their own: each cost a compile unit linking the
    system's right-hand side, 2-3 s CPU for the mine, docs/design.md)."""
    h, lam = 0.1, 2.0
    accepted, h_next, _, _, ynew, ws = attempt(methods.RK4, h, lam)
    assert accepted and h_next == h
    z = h * lam
    assert 1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24 > 1.0  # RK4's y1, above 1 ...
    assert ynew == 1.0  # ... put back to 1 by the projection
    assert ws[0][6, 0] == lam  # f at the projected state
    accepted, h_next, _, _, ynew, ws = attempt(methods.OWN_METHOD, h, -lam)
    assert accepted and h_next == h
    assert ynew == pytest.approx(math.exp(-lam * h), rel=1e-15)
    assert ws[0][6, 0] == pytest.approx(-lam * ynew, rel=1e-15)  # f at the step's end, for the next step


# --- the one driver loop: a new system's driver is its two hooks --------------------------------------
@_numba.small_kernel
def decay_next_step(t, h_try, out, ctx, loop):
    # the end at t_end, else the controller's proposal cut to end there
    t_end, method = ctx[0], ctx[1]
    if t >= t_end:
        return st.TIME_LIMIT, method, h_try, loop
    return core.GO_ON, method, min(h_try, t_end - t), loop


@_numba.small_kernel
def decay_accepted(t, h, out, ctx, loop):
    # move on, record the step's end time, and end the run (the system's own end, 0) below the floor
    y, ynew, k, floor = ctx[2], ctx[3], ctx[4], ctx[5]
    y[:] = ynew
    k[0, :] = k[6]
    loop += 1
    out[loop] = t + h
    return (st.END if y[0] < floor else core.GO_ON), t + h, True, loop


@njit
def drive_decay(method, lam, t_end, floor, out):
    """y' = lam y from y(0) = 1 (the test system LINEAR) by the core's loop with the hooks above."""
    y, ynew, k = np.ones(1), np.empty(1), np.empty((7, 1))
    p = np.array([lam, np.inf])
    linear_rhs(0.0, y, p, k[0])
    ws = (k, ynew, np.empty(1), np.empty((5, 1)), np.empty(1), np.array([0]), np.zeros((1, 1)),
          np.empty((1, 1)), np.empty(1, np.int64), np.empty((4, 1)), np.empty(1))  # fmt: skip
    ctx = (t_end, method, y, ynew, k, floor)
    status, t, n = core.driver_loop(
        decay_next_step, decay_accepted, LINEAR, 0.0, y, 0.01, p, None, np.array([[0, 1]]), 1e-9, 1e-12, ws,
        out, ctx, 0,
    )  # fmt: skip
    return status, t, n, y[0]


@pytest.mark.parametrize("method", [methods.DOPRI5, methods.ROS34PW2])
def test_a_new_systems_driver_is_two_hooks_on_the_cores_loop(method):
    """The core's loop with two hooks integrates y' = -y to the closed form exp(-t), its steps chosen by
    the core's controller, and ends with the status a hook returns (issue 18: "one driver loop")."""
    out = np.zeros(10_000)
    status, t, n, y = drive_decay(method, -1.0, 3.0, -1.0, out)
    assert status == st.TIME_LIMIT and t == 3.0
    assert y == pytest.approx(math.exp(-3.0), rel=1e-6)
    times = out[: n + 1]
    assert np.all(np.diff(times) > 0) and times[-1] == 3.0
    assert 5 < n < 2000  # error-controlled steps, neither one step nor the 0.01 of the first
    status, t, n, y = drive_decay(method, -1.0, 3.0, 0.5, out)
    assert status == st.END  # the hook's end, at the first accepted step below the floor
    assert y < 0.5 <= math.exp(-out[n - 1]) * (1 + 1e-6)
    assert y == pytest.approx(math.exp(-t), rel=1e-6)
    # the hooks, passed to the loop as arguments, were inlined where the loop was: never compiled as
    # units of their own (nor called as first-class functions)
    assert not decay_next_step.overloads and not decay_accepted.overloads
