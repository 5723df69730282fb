"""The work of mineburial's build backend (``mineburial_build``): compile the kernels that
``mineburial run`` reaches into numba's cache beside the sources (:func:`precompile`), list the
cache files that belong to the sources (:func:`current_cache_files`) and add them to a wheel
(:func:`add_to_wheel`). No setuptools here: the tests import it in any environment, and the
compile's interpreter imports it beside mineburial. docs/design.md, "Install-time cache"."""

import base64
import hashlib
import json
import os
import subprocess
import sys
import time
import zipfile

#: the package whose kernels are compiled and shipped
PACKAGE = "mineburial"
#: the environment variable that skips the install-time compile
SKIP_ENV = "MINEBURIAL_PRECOMPILE"
_OFF = ("0", "false", "no", "off")
#: the most seconds the compile may take (about two minutes of CPU on the 2-core host)
TIMEOUT_S = 1800

#: run as ``python -c COMPILE_SCRIPT ROOT``: compile (or load) every kernel that ``mineburial run``
#: reaches with the embedded scenarios, then print one line ``CACHE <json>`` naming the cache files
#: that belong to the sources (:func:`current_cache_files`)
COMPILE_SCRIPT = r"""
import json, os, sys, time
root = os.path.abspath(sys.argv[1])
sys.path.insert(0, root)
import mineburial
here = os.path.dirname(os.path.abspath(mineburial.__file__))
if here != os.path.join(root, "mineburial"):
    raise SystemExit(f"imported mineburial from {here}, not from the source tree {root}")
sys.path.insert(0, sys.argv[2])
import mineburial_cache

print("SECONDS " + json.dumps(mineburial_cache.compile_paths()), flush=True)
print("CACHE " + json.dumps(mineburial_cache.current_cache_files(os.path.join(root, "mineburial"))))
"""


def compile_paths(drops: int = 4) -> dict:
    """Compile (or load from numba's cache) the kernels that ``mineburial run`` reaches: the default
    ensemble's chunk (its sampling and the drops' default path), its numerical self-check (the
    reference path, ``systems/mine/accuracy.py``) and the scour stage of the embedded scour scenario.
    ``drops`` drops each; returns the seconds each part took. Runs in the source tree's interpreter
    (:data:`COMPILE_SCRIPT`), with mineburial importable."""
    from mineburial.ensembles import engine  # local import: only in the compile's interpreter
    from mineburial.kernels import status as st  # local import: as above
    from mineburial.systems.mine import ensemble as mine  # local import: only in the compile's interpreter

    seconds = {}
    t0 = time.perf_counter()
    spec = engine.load_ensemble(None, n=drops, chunk_size=drops)
    chunk = engine.compute_chunk(spec, 0, drops)
    if not (chunk["status"] != st.INVALID_INPUT).any():
        raise RuntimeError("no drop of the default ensemble was run: nothing compiled")
    seconds["default"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    attrs = mine.check_accuracy(spec, [chunk])
    if attrs.get("numerical_check") != "done":
        raise RuntimeError(f"the self-check compiled nothing: {attrs.get('numerical_check')}")
    seconds["self_check"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    scour = os.path.join(os.path.dirname(mine.DEFAULT_SCENARIO), "scour_storm.toml")
    spec = engine.load_ensemble(scour, n=drops, chunk_size=drops)
    engine.compute_chunk(spec, 0, drops)
    seconds["scour"] = time.perf_counter() - t0
    return {k: round(v, 2) for k, v in seconds.items()}


def current_cache_files(package_dir) -> list:
    """The numba cache files under ``package_dir`` that numba would load for its sources now: each
    index (``__pycache__/<module>.<function>-<line>.pyXY.nbi``) written by this numba for the current
    content of ``<module>.py`` (numba's own check, ``IndexDataCacheFile._load_index``), with the data
    files it names. A list of ``{"index", "data": [...], "source", "sha256"}``, paths relative to
    ``package_dir``'s parent, ``sha256`` the hex hash of the source the index is stamped with.
    Stale, garbled and other versions' files are left out."""
    from numba.core.caching import IndexDataCacheFile  # local import: needs numba (the build env)

    base = os.path.dirname(os.path.abspath(package_dir))
    found = []
    for folder, dirs, files in os.walk(package_dir):
        dirs.sort()
        if os.path.basename(folder) != "__pycache__":
            continue
        for name in sorted(f for f in files if f.endswith(".nbi")):
            source = os.path.join(os.path.dirname(folder), name.split(".")[0] + ".py")
            if not os.path.isfile(source):
                continue
            with open(source, "rb") as fh:
                digest = hashlib.sha256(fh.read()).digest()
            try:
                overloads = IndexDataCacheFile(folder, name[: -len(".nbi")], digest)._load_index()
            except Exception:  # garbled: numba would not load it either (mineburial/_numba.py)
                continue
            data = sorted(d for d in overloads.values() if os.path.isfile(os.path.join(folder, d)))
            if data:
                rel = os.path.relpath(folder, base)
                found.append(
                    {
                        "index": os.path.join(rel, name),
                        "data": [os.path.join(rel, d) for d in data],
                        "source": os.path.relpath(source, base),
                        "sha256": digest.hex(),
                    }
                )
    return found


def _skip_reason(environ=os.environ) -> str | None:
    """Why the install-time compile is not wanted, or None."""
    for var in (SKIP_ENV, "MINEBURIAL_NUMBA_CACHE"):
        if environ.get(var, "1").strip().lower() in _OFF:
            return f"{var}={environ[var]}"
    if environ.get("NUMBA_DISABLE_JIT", "0").strip() not in ("", "0"):
        return "NUMBA_DISABLE_JIT is set"
    return None


def warn(message: str) -> None:
    print(f"mineburial build: {message}", file=sys.stderr, flush=True)


def precompile(root, timeout: float = TIMEOUT_S, script: str = COMPILE_SCRIPT) -> list | None:
    """Compile the kernels of the source tree ``root`` into numba's cache beside its sources (a
    fresh interpreter running ``script``); the cache files that belong to the sources
    (:func:`current_cache_files`), or None when skipped or failed (one warning line: the build goes
    on, and the kernels compile at the first run instead)."""
    reason = _skip_reason()
    if reason:
        warn(f"numba kernels not compiled at install time ({reason}); they compile at the first run")
        return None
    try:
        from numba.core import caching  # local import: the build env's numba, only here
    except ImportError as exc:
        warn(f"numba kernels not compiled at install time (numba cannot be imported: {exc})")
        return None
    if not hasattr(caching, "_hash_source_file"):  # numba < 0.68 stamps the file's mtime
        warn("numba kernels not compiled at install time: this numba stamps its cache with the "
              "source's modification time, which installation changes")  # fmt: skip
        return None
    env = dict(os.environ, MINEBURIAL_NUMBA_CACHE="1")
    for var in ("NUMBA_CACHE_DIR", "NUMBA_CACHE_LOCATOR_CLASSES"):  # the cache beside the sources
        env.pop(var, None)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    here = os.path.dirname(os.path.abspath(__file__))
    warn("compiling numba kernels for the install-time cache (a few minutes on 2 cores; "
          f"{SKIP_ENV}=0 skips it)")  # fmt: skip
    t0 = time.perf_counter()
    try:
        out = subprocess.run(
            [sys.executable, "-c", script, os.path.abspath(root), here],
            env=env,
            cwd=os.path.abspath(root),
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except (OSError, subprocess.SubprocessError) as exc:
        warn(f"the install-time compile failed ({exc}); the kernels compile at the first run")
        return None
    lines = out.stdout.splitlines()
    cache = [line[len("CACHE ") :] for line in lines if line.startswith("CACHE ")]
    seconds = [line[len("SECONDS ") :] for line in lines if line.startswith("SECONDS ")]
    if out.returncode != 0 or not cache:
        tail = (out.stderr.strip().splitlines() or ["no output"])[-1]
        warn(f"the install-time compile failed (exit {out.returncode}: {tail}); kernels compile at first use")
        return None
    try:
        files = json.loads(cache[-1])
    except ValueError as exc:
        warn(f"the install-time compile's list of cache files cannot be read ({exc}); compiled at first use")
        return None
    each = seconds[-1] if seconds else "?"
    warn(f"compiled in {time.perf_counter() - t0:.0f} s (seconds each: {each}), {len(files)} cache indexes")
    return files


def _record_hash(data: bytes) -> str:
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def add_to_wheel(wheel_path, root, files) -> int:
    """Add the cache files ``files`` (:func:`current_cache_files`, relative to ``root``) to the wheel
    ``wheel_path``, each index only where its stamp is the hash of the wheel's own copy of its source
    (the file numba will hash after installation), with RECORD lines (hash, size). Returns the number
    of files added. The wheel is rewritten in place (through a temporary file)."""
    tmp = f"{wheel_path}.cache.tmp"
    try:
        added = _rewrite(wheel_path, tmp, root, files)
        os.replace(tmp, wheel_path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return added


def _rewrite(wheel_path, tmp, root, files) -> int:
    """:func:`add_to_wheel`'s work: the wheel with the cache files written to ``tmp``."""
    added = 0
    with zipfile.ZipFile(wheel_path) as zin:
        names = set(zin.namelist())
        record = next(n for n in names if n.endswith(".dist-info/RECORD"))
        stamp = zin.getinfo(record).date_time
        extra = []
        for entry in files:
            source = entry["source"].replace(os.sep, "/")
            if source not in names or hashlib.sha256(zin.read(source)).hexdigest() != entry["sha256"]:
                continue
            for rel in [entry["index"], *entry["data"]]:
                arc = rel.replace(os.sep, "/")
                if arc not in names:
                    with open(os.path.join(root, rel), "rb") as fh:
                        extra.append((arc, fh.read()))
                    names.add(arc)
        lines = zin.read(record).decode().splitlines()
        with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zout:
            infos = [i for i in zin.infolist() if i.filename != record]
            dist = [i for i in infos if ".dist-info/" in i.filename]
            for info in [i for i in infos if ".dist-info/" not in i.filename]:
                zout.writestr(info, zin.read(info.filename))
            for arc, data in extra:
                info = zipfile.ZipInfo(arc, date_time=stamp)
                info.external_attr = 0o644 << 16
                info.compress_type = zipfile.ZIP_DEFLATED
                zout.writestr(info, data)
                lines.insert(len(lines) - 1, f"{arc},{_record_hash(data)},{len(data)}")
                added += 1
            for info in dist:
                zout.writestr(info, zin.read(info.filename))
            zout.writestr(zin.getinfo(record), "\n".join(lines) + "\n")
    return added
