"""The generic integration core: a system reached by static dispatch, the step kernels, the one "attempt a
step" kernel that both drivers take their steps with (:func:`attempt_step`), the event locator and the
recorder of the driver that integrates a plain state vector (the multibody systems). The status codes
that every system shares are in :mod:`.status` (a leaf module: the variable registry reads them without
importing numba).

The tableaus, step kernels, continuous extensions, error norm and PI controller are in
:mod:`.integrators`; this module adds what a driver needs on top of them, knowing no mine and no ship.

**Systems by static dispatch.** A :class:`System` names a system's right-hand side
``rhs(t, y, params, dy)`` and its event ``event(t, y, params) -> float`` (numba kernels). Its numba
type (:class:`SystemType`) carries the system's name, so compiled code reaches the functions through
:func:`system_rhs` / :func:`system_event`, overloads resolved at compile time on that type (as
:func:`fixed_trial` is resolved on the mine's ``reference_paths``): no first-class function values, and
every compiled driver is cached on disk (``cache=True``) once per system instead of being compiled
again in every process and dask worker (10-60 s each before, docs/design.md "integration core").
numba checks a cached function against its own source file only; the type of a system therefore
also carries the modification time and size of the files that define its functions, so that an
edit of a system's module compiles the driver again for it.

"""

import inspect
import math
import os

import numpy as np
from numba.core import types
from numba.core.imputils import lower_constant
from numba.extending import (
    NativeValue,
    intrinsic,
    models,
    overload,
    register_model,
    typeof_impl,
    unbox,
)
from numba.np.arrayobj import make_array, populate_array

from mineburial._numba import JIT_OPTIONS, kernel, small_kernel
from mineburial.kernels.integrators import (
    DP_C,
    N_STAGES,
    ROS_ALPHA,
    ROS_ERROR_ORDER,
    ROS_GAMMA_DIAG,
    ROS_STAGES,
    dense_state,
    dopri_dense,
    dopri_solution,
    dopri_stage_state,
    error_norm,
    hermite_dense,
    illinois_next,
    illinois_update,
    j_times,
    next_step_size,
    next_step_size_order,
    ros_coupling,
    ros_solution,
    ros_stage_state,
    w_factor,
    w_solve,
)
from mineburial.kernels.methods import DOPRI5, METHOD_NAMES, RK4, ROS34PW2


# --- systems reached by static dispatch ----------------------------------------------------------------
class SystemType(types.Dummy):
    """The numba type of a :class:`System`: one type per system (and per version of its source)."""

    def __init__(self, key):
        self.system_key = key
        super().__init__(name=f"System({key})")


#: system key -> System: what the overloads of :func:`system_rhs` and :func:`system_event` call
_SYSTEMS = {}


def _source_stamp(fn) -> str:
    """Modification time and size of the file that defines ``fn`` (a numba dispatcher or function)."""
    path = inspect.getsourcefile(getattr(fn, "py_func", fn))
    st = os.stat(path)
    return f"{os.path.basename(path)}@{st.st_mtime_ns:x}.{st.st_size:x}"


class System:
    """A system of the integration core: its name, right-hand side and event kernels, and optionally its
    projection and its own steps.

    ``rhs(t, y, params, dy)`` fills dy/dt; ``event(t, y, params)`` returns a float whose crossing of
    zero ends the run or is located by :func:`locate_event`; ``project(y)`` (optional) puts the end
    state of a fixed step back on the system's manifold before its rate is evaluated (the mine's unit
    quaternion); ``own_step(method, t, y, h, params, k, ytmp, out)`` (optional) takes a fixed step of
    one of the system's own methods (codes from :data:`.methods.OWN_METHOD` up: the mine's
    ``local_linear``), k[0] = f(t, y) pre-filled. Pass the System to the step kernels below,
    :func:`locate_event`, :func:`mineburial.kernels.multibody.integrate` (or
    :func:`mineburial.multibody.integrate`); ``params`` is whatever the two functions take (a driver may
    pass the event other parameters than the right-hand side, as the mine's does: numba compiles a
    kernel once per argument type).

    ``sizes = (n, m)`` (optional): the length n of the state and the number m of the Jacobian columns
    of the Rosenbrock-W step, for a system whose sizes never change (the mine's 15 and 6). They are
    part of the system's numba type, so :func:`ros34pw2_step` compiles with them as constants
    (:func:`state_size`, :func:`sized`): its loops over the state and the columns unrolled, its arrays
    indexed with constant strides, the same floating-point operations with less loop and index
    arithmetic around them (issue 34 item 4: the mine's step 10.8k instructions an attempt -> 6.1k).
    A step whose arrays do not have the declared sizes is refused (:func:`fits`)."""

    def __init__(self, name, rhs, event, project=None, own_step=None, sizes=None):
        self.name = name
        self.rhs = rhs
        self.event = event
        self.project = project
        self.own_step = own_step
        if sizes is not None:
            sizes = tuple(int(s) for s in sizes)
            if len(sizes) != 2 or not (sizes[0] >= 1 and 1 <= sizes[1] <= sizes[0]):
                raise ValueError(
                    f"sizes of a System: (state length n >= 1, Jacobian columns 1 <= m <= n), not {sizes}"
                )
        self.sizes = sizes
        functions = (rhs, event, project, own_step)
        stamps = sorted({_source_stamp(fn) for fn in functions if fn is not None})
        self.key = f"{name}:{','.join(stamps)}" + ("" if sizes is None else f":{sizes[0]}x{sizes[1]}")
        _SYSTEMS[self.key] = self
        self.numba_type = SystemType(self.key)

    def __repr__(self):
        return f"System({self.name!r})"


@typeof_impl.register(System)
def _typeof_system(val, c):
    return val.numba_type


register_model(SystemType)(models.OpaqueModel)


@unbox(SystemType)
def _unbox_system(typ, obj, c):
    return NativeValue(c.context.get_dummy_value())


@lower_constant(SystemType)
def _constant_system(context, builder, ty, pyval):
    return context.get_dummy_value()


def system_rhs(system, t, y, params, dy):
    """dy = the right-hand side of ``system`` at (t, y) (compiled code only)."""
    raise NotImplementedError("compiled code only")


def system_event(system, t, y, params):
    """The event value of ``system`` at (t, y) (compiled code only)."""
    raise NotImplementedError("compiled code only")


#: not inlined at numba's IR level: with ``inline="always"`` (-0.8 % instructions a default drop, issue 34)
#: the restraint system's Rosenbrock-W run failed (numerical_failure, tests/test_integration_core.py's
#: restraint_ros34pw2 test; the cause not pinned down: the impl's closure over each system's ``rhs`` is the
#: suspect)
@overload(system_rhs, jit_options=JIT_OPTIONS)
def _system_rhs_impl(system, t, y, params, dy):
    if isinstance(system, SystemType):
        rhs = _SYSTEMS[system.system_key].rhs

        def impl(system, t, y, params, dy):
            rhs(t, y, params, dy)

        return impl


@overload(system_event, jit_options=JIT_OPTIONS)
def _system_event_impl(system, t, y, params):
    if isinstance(system, SystemType):
        event = _SYSTEMS[system.system_key].event

        def impl(system, t, y, params):
            return event(t, y, params)

        return impl


# --- sizes known at compile time ---------------------------------------------------------------------
def state_size(system, y):
    """n: the declared state length of ``system`` (:class:`System`), a constant of its compiled code, or
    else the length of ``y`` (compiled code only)."""
    raise NotImplementedError("compiled code only")


def column_count(system, cols):
    """m: the declared number of Jacobian columns of ``system``, a constant of its compiled code, or else
    the length of ``cols`` (compiled code only)."""
    raise NotImplementedError("compiled code only")


def fits(system, a, shape):
    """Whether the array ``a`` has the shape ``shape`` (of the declared sizes) for a system that declares
    sizes; always true for one that does not (compiled code only)."""
    raise NotImplementedError("compiled code only")


def sized(system, a, shape):
    """``a`` (a C-contiguous array) seen with the shape ``shape`` of the declared sizes of ``system``,
    whose entries are constants of the compiled code; ``a`` itself for a system that declares none. The
    caller has checked the shape (:func:`fits`): only the constants are new (compiled code only)."""
    raise NotImplementedError("compiled code only")


def _declared_sizes(system):
    return _SYSTEMS[system.system_key].sizes if isinstance(system, SystemType) else None


@overload(state_size, jit_options=JIT_OPTIONS)
def _state_size_impl(system, y):
    sizes = _declared_sizes(system)
    if sizes is None:
        return lambda system, y: y.shape[0]
    n = sizes[0]
    return lambda system, y: n


@overload(column_count, jit_options=JIT_OPTIONS)
def _column_count_impl(system, cols):
    sizes = _declared_sizes(system)
    if sizes is None:
        return lambda system, cols: cols.shape[0]
    m = sizes[1]
    return lambda system, cols: m


@overload(fits, jit_options=JIT_OPTIONS)
def _fits_impl(system, a, shape):
    if _declared_sizes(system) is None:
        return lambda system, a, shape: True
    return lambda system, a, shape: a.shape == shape


@intrinsic
def _with_shape(typingctx, a, shape):
    """The array ``a`` (C layout) with its shape replaced by ``shape`` (a tuple of as many integers) and
    its strides those of that shape: the same data, no reference taken (a view for the caller's frame)."""
    if not (
        isinstance(a, types.Array)
        and a.layout == "C"
        and isinstance(shape, types.BaseTuple)
        and len(shape) == a.ndim
        and all(isinstance(t, types.Integer) for t in shape)
    ):
        return None

    def codegen(context, builder, sig, args):
        aryty = sig.args[0]
        ary = make_array(aryty)(context, builder, args[0])
        intp = context.get_value_type(types.intp)
        dims = [
            context.cast(builder, builder.extract_value(args[1], i), sig.args[1][i], types.intp)
            for i in range(aryty.ndim)
        ]
        strides = []
        step = intp(context.get_abi_sizeof(context.get_data_type(aryty.dtype)))
        for d in reversed(dims):
            strides.insert(0, step)
            step = builder.mul(step, d)
        return _unowned_view(context, builder, aryty, ary, dims, strides)

    return a(a, shape), codegen


def _unowned_view(context, builder, aryty, ary, shape, strides):
    """Code of an array of type ``aryty`` over the data of ``ary`` with ``shape`` and ``strides`` and no
    meminfo (NULL: numba's reference counts on it are a test, no atomic): what :func:`_with_shape` and
    :func:`borrowed` return."""
    out = make_array(aryty)(context, builder)
    populate_array(out, data=ary.data, shape=shape, strides=strides, itemsize=ary.itemsize, meminfo=None)
    return out._getvalue()


def borrowed(a):
    """The array ``a`` itself, seen without its reference count (meminfo NULL) in compiled code: for an
    array whose owner outlives every use of the view (a driver's argument, held by its caller).

    numba counts a reference up and down (``NRT_incref``/``NRT_decref``: an atomic ``lock add`` on the
    array's meminfo) at each compiled callee's entry and exit for every array argument, at each inlined
    kernel's array parameter and at each array taken out of a tuple, wherever its pruning pass cannot
    pair them: ~68,000 atomics a default drop (issue 34 item 4). On a NULL meminfo they are a test and a
    return, no atomic; and the rows of the ensemble (``P[i]``, ``S[i]``) and the sediment and current
    banks share one meminfo between the batch's threads, whose cache line every count moved from core
    to core. The data, and so every answer, are the same. In Python (``NUMBA_DISABLE_JIT``) it is ``a``."""
    return a


@intrinsic
def _borrowed(typingctx, a):
    if not isinstance(a, types.Array):
        return None

    def codegen(context, builder, sig, args):
        aryty = sig.args[0]
        ary = make_array(aryty)(context, builder, args[0])
        return _unowned_view(context, builder, aryty, ary, ary.shape, ary.strides)

    return a(a), codegen


@overload(borrowed, jit_options=JIT_OPTIONS)
def _borrowed_impl(a):
    return lambda a: _borrowed(a)


def keep_alive(owners):
    """Nothing; in compiled code a call that numba keeps, so that ``owners`` (arrays, or tuples of them)
    are released after it and not after their last other use: the arrays of which :func:`borrowed`
    views are used up to that call. In Python it does nothing."""
    return None


@intrinsic
def _keep_alive(typingctx, owners):
    def codegen(context, builder, sig, args):
        return context.get_dummy_value()

    return types.none(owners), codegen


@overload(keep_alive, jit_options=JIT_OPTIONS)
def _keep_alive_impl(owners):
    return lambda owners: _keep_alive(owners)


@overload(sized, jit_options=JIT_OPTIONS)
def _sized_impl(system, a, shape):
    if _declared_sizes(system) is None:
        return lambda system, a, shape: a
    return lambda system, a, shape: _with_shape(a, shape)


# --- pieces of a driver ---------------------------------------------------------------------------------
@small_kernel
def all_finite(y):
    for i in range(y.shape[0]):
        if not math.isfinite(y[i]):
            return False
    return True


@kernel
def locate_event(system, r, t, h, ga, gb, params, ytmp, tol, max_iter):
    """Fraction theta of the step (t, t + h) at which the event of ``system`` changes sign (from ``ga`` at
    its start to ``gb`` at its end), by the Illinois root finder (:func:`.integrators.illinois_next`) on
    the continuous extension ``r``, to the bracket width ``tol`` (a fraction of the step) in at most
    ``max_iter`` iterations, both declared by the system; returns the end of the final bracket, where
    the event has happened. A non-finite event value ends the search there."""
    a = 0.0
    b = 1.0
    side = 0
    for _ in range(max_iter):
        if b - a <= tol:
            break
        th = illinois_next(a, ga, b, gb)
        dense_state(r, th, ytmp)
        gt = system_event(system, t + th * h, ytmp, params)
        if not math.isfinite(gt):
            break
        if gt == 0.0:
            return th
        a, ga, b, gb, side = illinois_update(a, ga, b, gb, th, gt, side)
    return b


@kernel
def record_until(r, t, h, t_stop, t_out, i_rec, times, states, ytmp):
    """Record the output times ``t_out[i] <= t_stop`` (those in (t, t + h]) on the continuous extension
    ``r`` of the step; returns the next output index."""
    while i_rec < t_out.shape[0] and t_out[i_rec] <= t_stop:
        th = min(1.0, max(0.0, (t_out[i_rec] - t) / h))
        dense_state(r, th, ytmp)
        times[i_rec] = t_out[i_rec]
        states[i_rec, :] = ytmp
        i_rec += 1
    return i_rec


# --- step kernels of a system reached by dispatch ------------------------------------------------------
#: one-sided differences of the Jacobian columns: relative step and smallest absolute step (units of the
#: columns' state: m s-1 and rad s-1 for the mine). Not the 1e-7 / 1e-9 of a smooth right-hand side: the
#: mine's sediment force is piecewise smooth in the state at the scale of a tabulated profile's rows (the
#: fast rule's nodes move with the velocity through the advancing switch line), so differences of
#: ~1e-8 m s-1 measured the slope of one row's kink, and the Rosenbrock-W steps, stable for any J in
#: theory, crept with that J at ~0.2 m s-1 instead of settling (issue 34: a rough 200,000-row log, 40
#: drops of the default ensemble, drop 35 1.725 m against 1.357 m by dopri5 and 1.363 m at rtol 1e-5; with
#: these steps 1.363 m, the 40 drops within max 1.8 % of dopri5). 1e-6 m s-1 is 2e-4 of the sediment's
#: regularisation speeds (numerics.switch_speed, slip_speed: 5 mm s-1); on 300 drops of the default
#: ensemble the steps were 34,472 against 34,608 (benchmarks/results/accuracy_sweep_extended.md).
JAC_REL_STEP = 1e-5
JAC_MIN_STEP = 1e-6
#: Jacobian-age policy of the Rosenbrock-W step: accepted steps before the Jacobian is evaluated
#: again, and the age above which a rejected step has it evaluated again. 50 (fewest right-hand
#: sides on the mine's default ensemble, docs/design.md) until issue 34 item 3: with the fast
#: sediment rule's crossing breakpoints, three shallow rotating slaps in firm clay (the extended
#: sweep's drops 7, 22, 36) ran off on a 50-step-old Jacobian (0.068 / 0.055 / 0.053 m against the
#: reference's 0.0017 / 0.0097 / 0.0075 m); at 10 they agree (stratum max 13.3 % -> 0.00 %), the
#: default ensemble's 200 drops take 21,050 steps against 22,354, every drop within 1.6 mm, at about
#: 4 % of the throughput (benchmarks/results/accuracy_sweep_extended.md)
JAC_MAX_AGE = 10
JAC_AGE_AT_REJECTION = 2
#: stage times of ROS34PW2 (row sums of its alpha, Hairer & Wanner II sec. IV.7 eq. (7.4'))
ROS_C = ROS_ALPHA.sum(axis=1)


@kernel
def dopri5_step(system, t, y, h, params, k, ytmp, out, err):
    """Stages 2-7 of a Dormand-Prince step of ``system`` (k[0] = f(t, y) pre-filled): fills ``out``
    (5th order), ``err`` and k[6] = f(t + h, out) (:mod:`.integrators`)."""
    for s in range(1, N_STAGES):
        dopri_stage_state(y, k, s, h, ytmp)
        system_rhs(system, t + DP_C[s] * h, ytmp, params, k[s])
    dopri_solution(y, k, h, out, err)


@small_kernel
def rk4_step(system, t, y, h, params, k, ytmp, out):
    """One classical Runge-Kutta step of ``system`` from (t, y) to t + h (k[0] = f(t, y) pre-filled;
    k[1..3] the other stages). The weights are applied as h (k1 + 2 k2 + 2 k3 + k4) / 6, the mine's
    order of operations since its first release (the restraint's h / 6 (...) differed in the last bit).
    Inlined (``small_kernel``) into :func:`fixed_trial`'s implementation, the one compile unit of a
    fixed step: as a unit of its own it linked the system's right-hand side once more (docs/design.md)."""
    n = y.shape[0]
    for i in range(n):
        ytmp[i] = y[i] + 0.5 * h * k[0, i]
    system_rhs(system, t + 0.5 * h, ytmp, params, k[1])
    for i in range(n):
        ytmp[i] = y[i] + 0.5 * h * k[1, i]
    system_rhs(system, t + 0.5 * h, ytmp, params, k[2])
    for i in range(n):
        ytmp[i] = y[i] + h * k[2, i]
    system_rhs(system, t + h, ytmp, params, k[3])
    for i in range(n):
        out[i] = y[i] + h * (k[0, i] + 2.0 * k[1, i] + 2.0 * k[2, i] + k[3, i]) / 6.0


@kernel
def jacobian_columns(system, t, y, f0, params, cols, ytmp, ftmp, jc):
    """Columns ``cols`` of df/dy of ``system`` by one-sided differences from f0 = f(t, y):
    jc[:, j] = (f(y + d e_cols[j]) - f0) / d, d = max(JAC_REL_STEP |y_c|, JAC_MIN_STEP) as represented."""
    n = y.shape[0]
    for j in range(cols.shape[0]):
        c = cols[j]
        d = max(JAC_REL_STEP * abs(y[c]), JAC_MIN_STEP)
        for i in range(n):
            ytmp[i] = y[i]
        ytmp[c] = y[c] + d
        d = ytmp[c] - y[c]  # the difference actually represented
        system_rhs(system, t, ytmp, params, ftmp)
        for i in range(n):
            jc[i, j] = (ftmp[i] - f0[i]) / d


@kernel
def ros34pw2_step(system, t, y, h, params, f0, jc, cols, wa, piv, kr, ytmp, vtmp, ztmp, out, err):
    """One Rosenbrock-W step (ROS34PW2, :mod:`.integrators`) of ``system`` with the Jacobian columns
    ``jc`` of ``cols`` (possibly from an earlier step; f0 = f(t, y)). Fills ``out`` and ``err``; returns
    False when W is singular. The stages are evaluated at t + ROS_C[s] h without the df/dt term of a
    non-autonomous W-method (Hairer & Wanner II eq. (7.4')): exact for autonomous systems (the
    multibody systems of mineburial are). With the declared sizes of ``system`` (:class:`System`) the
    arrays are seen with constant shapes; arrays of other sizes are refused (False)."""
    n = state_size(system, y)
    m = column_count(system, cols)
    if not (
        fits(system, y, (n,))
        and fits(system, cols, (m,))
        and fits(system, jc, (n, m))
        and fits(system, wa, (m, m))
        and fits(system, kr, (ROS_STAGES, n))
    ):
        return False  # the shapes the loops and strides read are not the declared ones
    y = sized(system, y, (n,))
    f0 = sized(system, f0, (n,))
    jc = sized(system, jc, (n, m))
    cols = sized(system, cols, (m,))
    wa = sized(system, wa, (m, m))
    piv = sized(system, piv, (m,))
    kr = sized(system, kr, (ROS_STAGES, n))
    ytmp = sized(system, ytmp, (n,))
    vtmp = sized(system, vtmp, (n,))
    ztmp = sized(system, ztmp, (m,))
    out = sized(system, out, (n,))
    err = sized(system, err, (n,))
    c = h * ROS_GAMMA_DIAG
    if not w_factor(jc, cols, c, wa, piv):
        return False
    for s in range(ROS_STAGES):
        if s == 0:
            for i in range(n):
                vtmp[i] = f0[i]
        else:
            ros_stage_state(y, kr, s, ytmp)
            system_rhs(system, t + ROS_C[s] * h, ytmp, params, vtmp)
        ros_coupling(kr, s, cols, ztmp)
        j_times(jc, ztmp, kr[s])
        for i in range(n):
            kr[s, i] = h * (vtmp[i] + kr[s, i])
        w_solve(jc, cols, c, wa, piv, kr[s], ztmp)
    ros_solution(y, kr, out, err)
    return True


# --- one attempted step of any method: what both drivers step with -------------------------------------
def fixed_trial(fixed, system, method, t, y, h, params, k, ytmp, out):
    """The end state ``out`` of a fixed step (:data:`.methods.RK4`, then projected by the system, or one
    of the system's own methods); compiled only when ``fixed`` is not None (the mine passes its
    ``reference_paths``: its default drops never take a fixed step, and not compiling these halves its
    cold compile, docs/design.md)."""
    raise NotImplementedError("compiled code only")


@overload(fixed_trial, jit_options=JIT_OPTIONS)
def _fixed_trial_impl(fixed, system, method, t, y, h, params, k, ytmp, out):
    if isinstance(fixed, (types.NoneType, types.Omitted)):

        def not_compiled(fixed, system, method, t, y, h, params, k, ytmp, out):
            out[:] = np.nan  # never reached: the caller passes a fixed value whenever a fixed step is asked

        return not_compiled
    # the system's projection and own steps are called here directly, not through overloads of their
    # own: every overload is a compile unit of its own that links (and optimises again) the system's
    # right-hand side, 2-3 s of CPU each for the mine (docs/design.md, "Integration core")
    found = _SYSTEMS[system.system_key]
    project = found.project if found.project is not None else _no_projection
    own_step = found.own_step if found.own_step is not None else _no_own_step

    def step(fixed, system, method, t, y, h, params, k, ytmp, out):
        if method == RK4:
            rk4_step(system, t, y, h, params, k, ytmp, out)
            project(out)
        else:
            own_step(method, t, y, h, params, k, ytmp, out)

    return step


@small_kernel
def _no_projection(y):
    """The projection of a system that has none (:class:`System`): nothing."""


@small_kernel
def _no_own_step(method, t, y, h, params, k, ytmp, out):
    """The own step of a system that has none (:class:`System`): a failed step."""
    out[:] = np.nan


@small_kernel
def method_code(name):
    """The code of the core's method ``name`` (:data:`.methods.METHOD_NAMES`), -1 if there is none."""
    for i in range(len(METHOD_NAMES)):
        if METHOD_NAMES[i] == name:
            return i
    return -1


@small_kernel
def attempt_step(
    system, method, t, y, h, params, fixed, groups, rtol, atol, err_prev, accepted_before, jac_age, ws
):
    """Attempt one step of ``method`` (:mod:`.methods`) of ``system`` from (t, y) of size h: the trial
    step, its error norm (:func:`.integrators.error_norm` over ``groups`` with rtol, atol; NaN, so a
    rejection, for a non-finite trial or a singular W) and the PI controller; when accepted, k[6] = f(t +
    h, ynew) and the continuous extension ``r`` of the step. ``ws`` = (k, ynew, err, r, ytmp, cols, jc,
    wa, piv, kr, ztmp) are the work arrays (k[0] = f(t, y) pre-filled; cols the Jacobian columns of the
    Rosenbrock-W step, jc their values, kept between steps under the Jacobian-age policy). A fixed step
    (:func:`fixed_trial`) is always accepted. Returns (accepted, next step, error memory, Jacobian age).

    Adding a method of the core: its name in :mod:`.methods` and its branch here; every system offers it.
    Inlined into each driver (``small_kernel``): as a compile unit of its own it cost the mine's cold
    compile 4.4 s CPU of its own against 1.5 s less in ``run_drop`` (docs/design.md).
    """
    k, ynew, err, r, ytmp, cols, jc, wa, piv, kr, ztmp = ws
    if method == DOPRI5:
        dopri5_step(system, t, y, h, params, k, ytmp, ynew, err)
        en = np.nan
        if all_finite(ynew) and all_finite(k[N_STAGES - 1]):
            en = error_norm(y, ynew, err, groups, rtol, atol)
        h_next, accept, err_prev = next_step_size(h, en, err_prev, accepted_before)
        if accept:
            dopri_dense(y, ynew, k, h, r)
        return accept, h_next, err_prev, jac_age
    if method == ROS34PW2:
        if jac_age >= JAC_MAX_AGE:
            jacobian_columns(system, t, y, k[0], params, cols, ytmp, k[1], jc)
            jac_age = 0
        en = np.nan
        if ros34pw2_step(system, t, y, h, params, k[0], jc, cols, wa, piv, kr, ytmp, k[1], ztmp, ynew, err):
            if all_finite(ynew):
                en = error_norm(y, ynew, err, groups, rtol, atol)
        h_next, accept, err_prev = next_step_size_order(h, en, err_prev, accepted_before, ROS_ERROR_ORDER)
        if not accept:
            if jac_age > JAC_AGE_AT_REJECTION:
                jac_age = JAC_MAX_AGE  # a stale Jacobian may be why: evaluate it again
            return False, h_next, err_prev, jac_age
        system_rhs(system, t + h, ynew, params, k[N_STAGES - 1])
        hermite_dense(y, ynew, k[0], k[N_STAGES - 1], h, r)
        return True, h_next, err_prev, jac_age + 1
    fixed_trial(fixed, system, method, t, y, h, params, k, ytmp, ynew)
    system_rhs(system, t + h, ynew, params, k[N_STAGES - 1])
    hermite_dense(y, ynew, k[0], k[N_STAGES - 1], h, r)
    return True, h, err_prev, jac_age


# --- the one driver loop ---------------------------------------------------------------------------------
#: a driver hook's answer while the run goes on (any other value is the status the run ends with: the
#: statuses of :mod:`.status` are all >= 0)
GO_ON = -1


@small_kernel
def driver_loop(
    next_step, accepted, system, t, y, h_try, params, fixed, groups, rtol, atol, ws, out, ctx, loop
):
    """The one driver loop of the integration core: from (t, y), the driver's hooks choose each step's
    method and size, :func:`attempt_step` takes it, and the hooks act on each accepted step (events,
    records, end tests) until one of them ends the run. Returns (status, t, loop).

    The hooks are a system's inlined kernels (``small_kernel``), passed as the first two arguments
    straight from the driver's own global names (``driver_loop(_next_step, _accepted, ...)``): numba
    inlines this loop into the driver, and then the hooks there, where each call's function is the
    driver's global. So the loop is compiled into each driver and cached with it, and the hooks are
    never first-class functions nor compile units of their own (docs/design.md, "One driver loop"):

    ``next_step(t, h_try, out, ctx, loop) -> (status, method, h, loop)``
        before each attempt: the end tests of the loop's head (time and step budgets), the method
        (:mod:`.methods`) and the size h of the step to attempt, h_try being the controller's proposal
        (the driver's first step at the start); status :data:`GO_ON` to attempt it.
    ``accepted(t, h, out, ctx, loop) -> (status, t, accepted_before, loop)``
        after an accepted step (its end state, rate and continuous extension in ``ws``): locate events,
        record, move the state on (or leave it to take the step again), test the end; returns the
        time reached, and whether the next attempt follows an accepted step (False after a restart:
        the PI controller's memory is not used across it).

    ``out`` is the driver's output (the mine's trajectory, possibly ``None``: passed as an argument
    down to the hooks so that numba prunes a recorder it does not need), ``ctx`` a tuple of what the
    hooks read (parameters, work arrays, settings) and ``loop`` a tuple (or named tuple) of the scalars
    they carry from step to step. The Jacobian age, the PI controller's memory and the proposed step
    belong to the loop itself. The rest of the arguments are :func:`attempt_step`'s.
    """
    err_prev = 1e-4
    accepted_before = True
    jac_age = JAC_MAX_AGE
    while True:
        status, method, h, loop = next_step(t, h_try, out, ctx, loop)
        if status != GO_ON:
            return status, t, loop
        accept, h_try, err_prev, jac_age = attempt_step(
            system, method, t, y, h, params, fixed, groups, rtol, atol, err_prev, accepted_before, jac_age, ws
        )
        accepted_before = accept
        if accept:
            status, t, accepted_before, loop = accepted(t, h, out, ctx, loop)
            if status != GO_ON:
                return status, t, loop
