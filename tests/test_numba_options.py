"""The numba options of every kernel: the on-disk cache switch MINEBURIAL_NUMBA_CACHE."""

import os
import subprocess
import sys

import pytest

from mineburial._numba import CACHE_ENV, cache_enabled


@pytest.mark.parametrize(
    "value, expected",
    [
        (None, True),
        ("1", True),
        ("true", True),
        (" ON ", True),
        ("", True),
        ("0", False),
        ("false", False),
        ("No", False),
        ("off", False),
    ],
)
def test_cache_switch_values(value, expected):
    environ = {} if value is None else {CACHE_ENV: value}
    assert cache_enabled(environ) is expected


def test_cache_switch_rejects_other_values():
    with pytest.raises(ValueError, match=r"MINEBURIAL_NUMBA_CACHE = 'maybe' must be 1 .* or 0"):
        cache_enabled({CACHE_ENV: "maybe"})


@pytest.mark.parametrize("value, cache_class", [("0", "NullCache"), ("1", "FunctionCache")])
def test_kernels_follow_the_switch(value, cache_class):
    """In a fresh process, the kernels' numba dispatchers carry numba's null cache when the
    switch is off and its on-disk function cache when it is on (nothing is compiled)."""
    code = (
        "from mineburial.kernels.rotation import rotation_matrix; "
        "print(type(rotation_matrix._cache).__name__)"
    )
    env = {**os.environ, CACHE_ENV: value}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == cache_class


def test_compiled_callers_call_the_twin_without_cpython_wrapper():
    """A kernel called from compiled code is called through its twin compiled without the
    CPython wrapper (docs/design.md, compile time), and the twin computes what the kernel
    computes when Python calls it (numba internals that a numba upgrade could change)."""
    import numpy as np
    from numba import njit

    from mineburial._numba import Kernel, kernel

    @kernel
    def scaled_sum(x, factor):
        total = 0.0
        for v in x:
            total += v * factor
        return total

    @njit
    def caller(x):
        return scaled_sum(x, 2), scaled_sum(x, 3)  # literal ints: one specialisation of the twin

    def reference(x, factor):  # the same sums in plain Python, in the same order
        total = 0.0
        for v in x.tolist():
            total += v * factor
        return total

    x = np.linspace(0.1, 1.7, 17)
    assert isinstance(scaled_sum, Kernel)
    assert caller(x) == (scaled_sum(x, 2), scaled_sum(x, 3)) == (reference(x, 2), reference(x, 3))
    twin = scaled_sum._callee
    assert twin.targetoptions["no_cpython_wrapper"] is True
    assert len(twin.signatures) == 1  # the constants 2 and 3 typed as one int64 argument


def test_importing_the_engine_makes_no_cache_folder_until_a_kernel_is_used(tmp_path):
    """numba's cache of a kernel is made at its first compile or load, not at import (each one
    made creates its folder and a test file in it; docs/design.md, "Warm start"): importing the
    engine leaves NUMBA_CACHE_DIR empty, and calling one kernel fills its cache there."""
    code = (
        "import os, sys\n"
        "import mineburial.ensembles.engine, mineburial.ensembles.batch\n"
        "print(sum(len(dirs) + len(files) for _, dirs, files in os.walk(sys.argv[1])))\n"
        "from mineburial.kernels.rotation import rotation_matrix\n"
        "rotation_matrix(1.0, 0.0, 0.0, 0.0)\n"
        "print(sorted(f.split('-')[0] for _, _, fs in os.walk(sys.argv[1]) for f in fs))\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), CACHE_ENV: "1"}
    out = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)], env=env, capture_output=True, text=True, check=True
    )
    before, after = out.stdout.splitlines()
    assert before == "0"
    assert after == "['rotation.rotation_matrix', 'rotation.rotation_matrix']"  # its index and its code


# --- the garbage collector is paused while numba compiles (docs/design.md, "Compile time") ---------------
def test_the_collector_pause_nests_and_restores_the_state_it_found():
    import gc
    import threading

    from mineburial._numba import collector_paused

    was = gc.isenabled()
    try:
        gc.enable()
        with collector_paused():
            assert not gc.isenabled()
            with collector_paused():  # a kernel compiling its callees
                assert not gc.isenabled()
            assert not gc.isenabled()
        assert gc.isenabled()
        # a compile that fails leaves the collector as it was
        with pytest.raises(RuntimeError), collector_paused():
            raise RuntimeError("the compile failed")
        assert gc.isenabled()
        # a caller that had switched the collector off keeps it off
        gc.disable()
        with collector_paused():
            pass
        assert not gc.isenabled()
        # two threads' compiles overlapping: on again only after the last ends
        gc.enable()
        inside, release = threading.Event(), threading.Event()

        def other():
            with collector_paused():
                inside.set()
                release.wait(10)

        thread = threading.Thread(target=other)
        thread.start()
        inside.wait(10)
        with collector_paused():
            pass
        assert not gc.isenabled()  # the other thread's compile is still running
        release.set()
        thread.join(10)
        assert gc.isenabled()
    finally:
        (gc.enable if was else gc.disable)()


def test_a_kernel_compiles_with_the_collector_paused(monkeypatch):
    import gc

    from numba.core.registry import CPUDispatcher

    from mineburial import _numba

    seen = []
    compile_ = CPUDispatcher.compile

    def recording(self, sig):
        seen.append(gc.isenabled())
        return compile_(self, sig)

    monkeypatch.setattr(CPUDispatcher, "compile", recording)

    def twice(x):
        return 2.0 * x

    k = _numba._dispatcher(_numba.Kernel, twice, False, **_numba.JIT_OPTIONS)
    was = gc.isenabled()
    gc.enable()
    try:
        assert k(1.5) == 3.0
        assert seen and not any(seen)  # numba's compile ran with the collector off
        assert gc.isenabled()  # and it is on again after
    finally:
        (gc.enable if was else gc.disable)()
