"""The generic integration core: a system reached by static dispatch, the event locator and the
recorder of the driver that integrates a plain state vector (the multibody systems).

The tableaus, step kernels, continuous extensions, error norm and PI controller are in
:mod:`.integrators`; this module adds what a driver needs on top of them, knowing no mine and no ship.

**Systems by static dispatch.** A :class:`System` names a system's right-hand side
``rhs(t, y, params, dy)`` and its event ``event(t, y, params) -> float`` (numba kernels). Its numba
type (:class:`SystemType`) carries the system's name, so compiled code reaches the functions through
:func:`system_rhs` / :func:`system_event`, overloads resolved at compile time on that type (as
``stepper._fixed_step`` is resolved on ``reference_paths``): no first-class function values, and
every compiled driver is cached on disk (``cache=True``) once per system instead of being compiled
again in every process and dask worker (10-60 s each before, docs/design.md "integration core").
numba checks a cached function against its own source file only; the type of a system therefore
also carries the modification time and size of the files that define its functions, so that an
edit of a system's module compiles the driver again for it.

"""

import inspect
import math
import os

from numba.core import types
from numba.core.imputils import lower_constant
from numba.extending import (
    NativeValue,
    models,
    overload,
    register_model,
    typeof_impl,
    unbox,
)

from mineburial._numba import JIT_OPTIONS, kernel, small_kernel
from mineburial.kernels.integrators import dense_state, illinois_next, illinois_update


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
    """A system of the integration core: its name, right-hand side and event kernels.

    ``rhs(t, y, params, dy)`` fills dy/dt; ``event(t, y, params)`` returns a float whose crossing of
    zero from above ends the run. Pass the System to :func:`integrate` (or
    :func:`mineburial.multibody.integrate`); ``params`` is whatever the two functions take."""

    def __init__(self, name, rhs, event):
        self.name = name
        self.rhs = rhs
        self.event = event
        stamps = sorted({_source_stamp(rhs), _source_stamp(event)})
        self.key = f"{name}:{','.join(stamps)}"
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


# --- pieces of a driver ---------------------------------------------------------------------------------
@small_kernel
def all_finite(y):
    for i in range(y.shape[0]):
        if not math.isfinite(y[i]):
            return False
    return True


@kernel
def locate_event(system, r, t, h, ga, gb, params, ytmp):
    """Fraction theta of the step at which the event crosses zero from above, by the Illinois root finder
    on the continuous extension ``r``; returns the end of the final bracket where the event is <= 0."""
    a = 0.0
    b = 1.0
    side = 0
    tol = 1e-13 * max(1.0, abs(t) / max(h, 1e-300))
    for _ in range(200):
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
