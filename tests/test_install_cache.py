"""The install-time cache of compiled kernels (issue 34 item 1; ``_build_backend/``,
docs/design.md "Install-time cache"): the build backend's compile, its choice of cache files, the
wheel it writes, and the loading of that cache after installation, on a one-kernel stand-in package
(a kernel made by ``mineburial._numba.kernel``, compiled in about a second) so that each step runs
for real: numba writes the cache beside the stand-in's sources, the wheel is unpacked byte for byte
as pip installs it, and numba's own counters (``Dispatcher.stats``) say whether the kernel was loaded
or compiled. Building the real wheel compiles the engine (minutes); docs/design.md gives its
measurements and the command."""

import base64
import hashlib
import importlib
import os
import pathlib
import pickle
import subprocess
import sys
import types
import zipfile

import pytest

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "_build_backend"))
import mineburial_cache as backend  # noqa: E402 (the backend's folder, as pip puts it on sys.path)

KERNEL_SOURCE = '''"""A stand-in for mineburial's kernels."""
from mineburial._numba import kernel


@kernel
def weighted_sum(x, k):
    s = 0.0
    for v in x:
        s += k * v
    return s
'''

#: the backend's compile, for the stand-in: compile (numba's cache beside the sources) and list
TOY_COMPILE = r"""
import json, os, sys
root = os.path.abspath(sys.argv[1])
sys.path.insert(0, root)
sys.path.insert(0, sys.argv[2])
import numpy as np
import toypkg.kern, mineburial_cache
assert toypkg.kern.weighted_sum(np.arange(4.0), 2.0) == 12.0
print("CACHE " + json.dumps(mineburial_cache.current_cache_files(os.path.join(root, "toypkg"))))
"""

#: after installation: call the kernel, print its result and numba's cache hits and misses
USE = r"""
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
import toypkg.kern as k
x = np.linspace(0.0, 1.0, 11)
r = k.weighted_sum(x, 3.0)
s = k.weighted_sum.stats
print(repr(r), sum(s.cache_hits.values()), sum(s.cache_misses.values()))
"""

EXPECTED = 3.0 * sum(i / 10 for i in range(11))  # the kernel's sum in Python: 16.5


def clean_env(**extra) -> dict:
    """The subprocesses' environment: mineburial importable, numba's cache beside the sources (no
    ``NUMBA_CACHE_DIR``), caching on, plus ``extra``."""
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "NUMBA_CPU_NAME")}
    env.update(PYTHONPATH=str(REPO), MINEBURIAL_NUMBA_CACHE="1", MINEBURIAL_PRECOMPILE="1")
    env.update(extra)
    return env


@pytest.fixture
def env(monkeypatch):
    """The backend's environment (it reads ``os.environ``): :func:`clean_env`."""
    for key, value in clean_env().items():
        monkeypatch.setenv(key, value)
    for var in ("NUMBA_CACHE_DIR", "NUMBA_CPU_NAME", "NUMBA_DISABLE_JIT"):
        monkeypatch.delenv(var, raising=False)


def make_project(root: pathlib.Path) -> pathlib.Path:
    pkg = root / "toypkg"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "kern.py").write_text(KERNEL_SOURCE)
    return root


def record_hash(data: bytes) -> str:
    digest = hashlib.sha256(data).digest()
    return "sha256=" + base64.urlsafe_b64encode(digest).rstrip(b"=").decode()


def make_wheel(path: pathlib.Path, root: pathlib.Path, kern_source: str | None = None) -> pathlib.Path:
    """A wheel of the stand-in as setuptools writes one (sources, dist-info, RECORD last)."""
    members = {
        "toypkg/__init__.py": b"",
        "toypkg/kern.py": (kern_source or KERNEL_SOURCE).encode(),
        "toypkg-0.1.dist-info/METADATA": b"Metadata-Version: 2.1\nName: toypkg\nVersion: 0.1\n",
        "toypkg-0.1.dist-info/WHEEL": (
            b"Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: true\nTag: py3-none-any\n"
        ),
    }
    record = [f"{n},{record_hash(d)},{len(d)}" for n, d in members.items()]
    record.append("toypkg-0.1.dist-info/RECORD,,")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for n, d in members.items():
            zf.writestr(n, d)
        zf.writestr("toypkg-0.1.dist-info/RECORD", "\n".join(record) + "\n")
    return path


def use(site: pathlib.Path, **extra):
    """(result, cache hits, cache misses, stderr) of the kernel called in a fresh process."""
    proc = subprocess.run(
        [sys.executable, "-c", USE, str(site)],
        capture_output=True,
        text=True,
        timeout=300,
        env=clean_env(**extra),
    )
    assert proc.returncode == 0, proc.stderr
    r, hits, misses = proc.stdout.split()
    return float(r), int(hits), int(misses), proc.stderr


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The stand-in compiled by the backend (once for the module) and its wheel with the cache."""
    tmp = tmp_path_factory.mktemp("install_cache")
    root = make_project(tmp / "src")
    with pytest.MonkeyPatch.context() as mp:
        for key, value in clean_env().items():
            mp.setenv(key, value)
        for var in ("NUMBA_CACHE_DIR", "NUMBA_CPU_NAME", "NUMBA_DISABLE_JIT"):
            mp.delenv(var, raising=False)
        files = backend.precompile(root, timeout=300, script=TOY_COMPILE)
    assert files, "the stand-in's compile listed no cache file"
    wheel = make_wheel(tmp / "toypkg-0.1-py3-none-any.whl", root)
    added = backend.add_to_wheel(wheel, root, files)
    return root, files, wheel, added


def install(wheel: pathlib.Path, site: pathlib.Path) -> pathlib.Path:
    """Unpack the wheel as pip installs it (the files byte for byte)."""
    with zipfile.ZipFile(wheel) as zf:
        zf.extractall(site)
    return site


def test_the_compile_lists_the_cache_numba_wrote_for_the_sources(built):
    root, files, _, _ = built
    assert len(files) == 1
    (entry,) = files
    assert entry["source"] == os.path.join("toypkg", "kern.py")
    assert entry["sha256"] == hashlib.sha256(KERNEL_SOURCE.encode()).hexdigest()
    assert entry["index"].startswith(os.path.join("toypkg", "__pycache__", "kern.weighted_sum-"))
    assert entry["index"].endswith(f".py{sys.version_info[0]}{sys.version_info[1]}.nbi")
    assert len(entry["data"]) == 1 and entry["data"][0].endswith(".1.nbc")
    assert all((root / p).is_file() for p in [entry["index"], *entry["data"]])


def test_the_wheel_carries_the_cache_with_its_record(built):
    root, files, wheel, added = built
    assert added == 2
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        record = zf.read("toypkg-0.1.dist-info/RECORD").decode().splitlines()
        contents = {n: zf.read(n) for n in names}
    cache = [files[0]["index"], *files[0]["data"]]
    assert all(p in names for p in cache)
    assert names[-1] == "toypkg-0.1.dist-info/RECORD"  # the dist-info after the package, RECORD last
    # every member but RECORD itself has a line with its hash and size, as the wheel format says
    lines = {line.split(",")[0]: line for line in record}
    assert set(lines) == set(names)
    for n in names[:-1]:
        assert lines[n] == f"{n},{record_hash(contents[n])},{len(contents[n])}"
    for p in cache:
        assert contents[p] == (root / p).read_bytes()


def test_a_wheel_whose_source_differs_gets_no_cache(built, tmp_path):
    """The index is stamped with its source's hash: for another source numba would not load it."""
    root, files, _, _ = built
    other = make_wheel(tmp_path / "other.whl", root, KERNEL_SOURCE + "# edited\n")
    assert backend.add_to_wheel(other, root, files) == 0
    with zipfile.ZipFile(other) as zf:
        assert not [n for n in zf.namelist() if n.endswith((".nbi", ".nbc"))]


def test_installed_kernels_load_from_the_shipped_cache(built, tmp_path):
    _, files, wheel, _ = built
    site = install(wheel, tmp_path / "site")
    before = {p: p.read_bytes() for p in site.rglob("__pycache__/*.nb?")}
    r, hits, misses, err = use(site)
    assert r == pytest.approx(EXPECTED, rel=1e-15)
    assert (hits, misses) == (1, 0) and err == ""
    assert {p: p.read_bytes() for p in site.rglob("__pycache__/*.nb?")} == before  # nothing written


@pytest.mark.parametrize("which", ["index", "data", "data-unpicklable-content"])
def test_a_garbled_cache_file_is_compiled_over(built, tmp_path, which):
    """A truncated or garbled file is a miss with one warning line, not an error: the kernel
    compiles, numba rewrites the file, and the next process loads it."""
    _, files, wheel, _ = built
    site = install(wheel, tmp_path / "site")
    index = site / files[0]["index"]
    data = site / files[0]["data"][0]
    path = index if which == "index" else data
    if which == "data-unpicklable-content":  # unpickles, but is not numba's compile result
        path.write_bytes(pickle.dumps("not a compile result"))
    else:
        path.write_bytes(path.read_bytes()[: len(path.read_bytes()) // 3])
    r, hits, misses, err = use(site)
    assert r == pytest.approx(EXPECTED, rel=1e-15)
    assert (hits, misses) == (0, 1)
    named = index if which == "data-unpicklable-content" else path  # the entry's index, or the file
    assert err.count("warning") == 1 and f"'{named}' cannot be read" in err, err
    assert use(site)[1:] == (1, 0, "")  # rewritten: loaded by the next process


def test_another_numba_version_reads_the_cache_as_empty(built, tmp_path):
    """The index's first pickle is numba's version: another version compiles (numba's own rule)."""
    _, files, wheel, _ = built
    site = install(wheel, tmp_path / "site")
    index = site / files[0]["index"]
    raw = index.read_bytes()
    head = pickle.dumps(pickle.loads(raw), protocol=-1)  # the version string's pickle
    assert raw.startswith(head)
    index.write_bytes(pickle.dumps("0.1.0", protocol=-1) + raw[len(head) :])
    r, hits, misses, err = use(site)
    assert r == pytest.approx(EXPECTED, rel=1e-15) and (hits, misses) == (0, 1) and err == ""


def test_another_cpu_target_finds_no_entry(built, tmp_path):
    """The entry's key holds the CPU name and features (numba's magic tuple): a process that
    targets another CPU compiles, as on another machine."""
    _, _, wheel, _ = built
    site = install(wheel, tmp_path / "site")
    r, hits, misses, err = use(site, NUMBA_CPU_NAME="generic")
    assert r == pytest.approx(EXPECTED, rel=1e-15) and (hits, misses) == (0, 1)


@pytest.mark.parametrize(
    "var, value",
    [("MINEBURIAL_PRECOMPILE", "0"), ("MINEBURIAL_PRECOMPILE", "off"), ("MINEBURIAL_NUMBA_CACHE", "0")],
)
def test_the_compile_is_skipped_on_request(env, tmp_path, monkeypatch, capsys, var, value):
    monkeypatch.setenv(var, value)
    root = make_project(tmp_path / "src")
    assert backend.precompile(root, timeout=60, script="raise SystemExit('must not run')") is None
    assert f"not compiled at install time ({var}={value})" in capsys.readouterr().err
    assert not list(root.rglob("*.nb?"))


@pytest.mark.parametrize(
    "script, timeout, message",
    [
        ("raise RuntimeError('the compile broke')", 60, "RuntimeError: the compile broke"),
        ("print('no cache line')", 60, "exit 0: no output"),
        ("import time; time.sleep(30)", 1, "timed out after 1"),
    ],
)
def test_a_failed_compile_warns_and_builds_on(env, tmp_path, capsys, script, timeout, message):
    root = make_project(tmp_path / "src")
    assert backend.precompile(root, timeout=timeout, script=script) is None
    err = capsys.readouterr().err
    assert "the install-time compile failed" in err and message in err


def backend_hooks(monkeypatch, root):
    """``mineburial_build`` imported over a stand-in for setuptools' backend whose ``build_wheel``
    writes the stand-in's wheel as setuptools would (its folder as cwd, as pip runs a backend)."""
    fake = types.ModuleType("setuptools.build_meta")
    fake.__all__ = ["build_wheel"]

    def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
        assert pathlib.Path.cwd() == root
        return make_wheel(pathlib.Path(wheel_directory) / "toypkg-0.1-py3-none-any.whl", root).name

    fake.build_wheel = build_wheel
    package = types.ModuleType("setuptools")
    package.build_meta = fake
    monkeypatch.setitem(sys.modules, "setuptools", package)
    monkeypatch.setitem(sys.modules, "setuptools.build_meta", fake)
    monkeypatch.delitem(sys.modules, "mineburial_build", raising=False)
    monkeypatch.chdir(root)
    return importlib.import_module("mineburial_build")


def test_the_backend_adds_the_cache_and_builds_on_whatever_the_compile_does(
    built, monkeypatch, tmp_path, capsys
):
    root, files, _, _ = built
    hooks = backend_hooks(monkeypatch, root)
    monkeypatch.setattr(hooks, "precompile", lambda where: files if pathlib.Path(where) == root else None)
    name = hooks.build_wheel(str(tmp_path))
    with zipfile.ZipFile(tmp_path / name) as zf:
        assert files[0]["index"] in zf.namelist() and files[0]["data"][0] in zf.namelist()

    def broken(where):
        raise RuntimeError("the compile broke")

    monkeypatch.setattr(hooks, "precompile", broken)
    (tmp_path / name).unlink()
    assert hooks.build_wheel(str(tmp_path)) == name
    with zipfile.ZipFile(tmp_path / name) as zf:
        assert not [n for n in zf.namelist() if n.endswith((".nbi", ".nbc"))]
    assert "the install-time compile failed (RuntimeError: the compile broke)" in capsys.readouterr().err


def test_the_build_resolves_the_runtime_pins():
    """The build's numba, numpy, scipy (and tomli) carry the [project] dependencies' pins, so that a
    fresh install resolves the same numba for the compile and for the runs."""
    meta = tomllib.loads((REPO / "pyproject.toml").read_text())
    build = meta["build-system"]
    assert build["build-backend"] == "mineburial_build" and build["backend-path"] == ["_build_backend"]
    runtime = {r.split(">")[0].split("[")[0]: r for r in meta["project"]["dependencies"]}
    for name in ("numpy", "numba", "scipy", "tomli"):
        assert runtime[name] in build["requires"], name
