"""The numba options of every kernel: the on-disk cache switch MINEBURIAL_NUMBA_CACHE."""

import os
import shutil
import stat
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
        "import mineburial.ensembles.engine, mineburial.systems.mine.batch\n"
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


# --- numba's cache files checked as their folders are (issue 35, item 2) ---------------------------------
USE_KERNEL = (
    "import sys\n"
    "from mineburial.kernels.rotation import rotation_matrix\n"
    "assert rotation_matrix(1.0, 0.0, 0.0, 0.0) == (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)\n"
    "s = rotation_matrix.stats\n"
    "print(type(rotation_matrix._cache).__name__, sum(s.cache_hits.values()), sum(s.cache_misses.values()))\n"
)


def use_kernel(cache_dir, umask=None):
    """One kernel called in a fresh process with ``NUMBA_CACHE_DIR=cache_dir``: prints the kind
    of its cache, its cache hits and misses (numba's own counters)."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache_dir), CACHE_ENV: "1"}
    return subprocess.run(
        [sys.executable, "-c", USE_KERNEL],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        preexec_fn=None if umask is None else (lambda: os.umask(umask)),
    )


def cache_files(folder):
    return sorted(p for p in folder.rglob("*") if p.is_file())


@pytest.fixture(scope="module")
def cache_template(tmp_path_factory):
    """A private cache folder filled by one run under ``umask 000`` (which wrote 0666 index
    files before issue 35): the files are 0600, the folder numba made 0755, and a second run
    loads the kernel from them."""
    folder = tmp_path_factory.mktemp("numba") / "cache"
    folder.mkdir(mode=0o700)
    first = use_kernel(folder, umask=0)
    assert first.returncode == 0 and first.stdout.split() == ["FunctionCache", "0", "1"], first.stderr
    files = cache_files(folder)
    assert [p.suffix for p in files] == [".nbc", ".nbi"]
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in files)
    assert stat.S_IMODE(files[0].parent.stat().st_mode) == 0o755
    second = use_kernel(folder, umask=0)
    assert second.stdout.split() == ["FunctionCache", "1", "0"] and second.stderr == "", second.stderr
    return folder


@pytest.fixture
def filled_cache(cache_template, tmp_path):
    """A copy of the filled cache (modes kept) and its data and index files."""
    folder = tmp_path / "cache"
    shutil.copytree(cache_template, folder)
    return folder, cache_files(folder)


def test_cache_files_are_private_whatever_the_umask(cache_template):
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in cache_files(cache_template))


def plant_pickle(path, marker):
    """Overwrite the cache file ``path`` with what a hostile user would write: numba's version
    header (for an index) and a pickle that creates ``marker`` when it is loaded."""
    import pickle

    import numba

    class Payload:
        def __reduce__(self):
            return (open, (str(marker), "w"))

    head = pickle.dumps(numba.__version__, protocol=-1) if path.suffix == ".nbi" else b""
    path.write_bytes(head + pickle.dumps(Payload(), protocol=-1))


@pytest.mark.parametrize("which", ["index", "data"])
def test_a_cache_file_writable_by_every_user_is_not_loaded(filled_cache, tmp_path, which):
    """Was: the pickle a neighbour wrote into a 0666 file was executed by the next run."""
    folder, (data, index) = filled_cache
    path = {"index": index, "data": data}[which]
    marker = tmp_path / "executed"
    plant_pickle(path, marker)
    path.chmod(0o666)
    planted = path.read_bytes()
    proc = use_kernel(folder)
    assert proc.returncode == 0, proc.stderr
    assert not marker.exists()
    assert proc.stdout.split()[1] == "0"  # no cache hit: compiled in memory
    warnings = proc.stderr.splitlines()
    assert len(warnings) == 1 and f"numba's cache file '{path}' is writable by every user" in warnings[0]
    assert path.read_bytes() == planted  # neither loaded nor replaced


def test_a_cache_file_that_is_a_symbolic_link_is_not_followed(filled_cache, tmp_path):
    folder, (data, index) = filled_cache
    marker = tmp_path / "executed"
    elsewhere = tmp_path / "elsewhere.nbc"
    plant_pickle(elsewhere, marker)
    data.unlink()
    data.symlink_to(elsewhere)
    proc = use_kernel(folder)
    assert proc.returncode == 0 and not marker.exists(), proc.stderr
    assert "is a symbolic link" in proc.stderr and proc.stdout.split()[1] == "0"


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="chown to another uid needs root")
def test_a_cache_index_owned_by_another_user_is_not_loaded(filled_cache, tmp_path):
    folder, (_, index) = filled_cache
    marker = tmp_path / "executed"
    plant_pickle(index, marker)
    os.chown(index, 12345, 12345)
    index.chmod(0o600)
    proc = use_kernel(folder)
    assert proc.returncode == 0 and not marker.exists(), proc.stderr
    assert "is owned by another user (uid 12345)" in proc.stderr and proc.stdout.split()[1] == "0"


def test_cache_file_problem_without_root(tmp_path):
    """The same checks on the file's status, for a user who cannot chown (any uid)."""
    from mineburial._numba import cache_file_problem

    f = tmp_path / "k.nbi"
    assert cache_file_problem(f) is None  # none yet
    f.write_bytes(b"x")
    f.chmod(0o600)
    assert cache_file_problem(f) is None
    assert cache_file_problem(f, uid=os.geteuid() + 1).startswith("is owned by another user")
    f.chmod(0o646)
    assert cache_file_problem(f) == "is writable by every user"
    os.mkfifo(tmp_path / "fifo.nbi")
    assert cache_file_problem(tmp_path / "fifo.nbi") == "is not a regular file"


def test_numba_cache_dir_that_is_a_regular_file_is_one_line(tmp_path):
    """Was: numba silently cached beside the installed sources instead."""
    path = tmp_path / "notes.txt"
    path.write_text("a user's file")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(path), CACHE_ENV: "1"}
    proc = subprocess.run(
        [sys.executable, "-m", "mineburial.cli", "drop", str(tmp_path / "s.toml")],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    err = proc.stderr.strip()
    assert proc.returncode == 2 and len(err.splitlines()) == 1, err
    assert f"NUMBA_CACHE_DIR = '{path}' is a regular file" in err and "must be a folder" in err
    assert path.read_text() == "a user's file"
    # switched off, the variable does not matter
    env[CACHE_ENV] = "0"
    proc = subprocess.run(
        [sys.executable, "-c", USE_KERNEL], env=env, capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0 and proc.stdout.split()[0] == "NullCache", proc.stderr
