"""The chunk store of a run: finished chunks kept on disk so that an interrupted run resumes.

A run with an output path ``OUT.nc`` keeps its working state in the folder
``OUT.nc.parts/`` until the NetCDF file is written:

* ``.mineburial-parts``: the mark of a folder mineburial created (:func:`own_folder`).
  Only a folder with this mark is used, emptied or removed: a user's folder of that
  name, or one that is a symbolic link, is refused.
* ``lock``: held by the live run (an advisory ``flock`` on the file, which records
  the process id, host and start time for the message). A second run on the same
  output path is refused while the lock is held; the kernel releases the lock when
  its process dies, so the lock file of a killed run is taken over (removed and
  created anew: the lock is only ever created exclusively, never through a link).
* ``manifest.json`` of each store (an ensemble: the parts folder itself; a map: one
  ``cell-<k>/`` sub-folder per grid cell): the *run identity* of the chunks kept there.
* ``chunk-<start>-<stop>.npz``: the per-drop arrays of drops ``[start, stop)``, written
  atomically (temporary file, fsync, rename), each carrying the identity of the run
  that wrote it.

The run identity (:func:`run_identity`) is a SHA-256 over everything that decides the
per-drop results: the resolved scenario, the distributions of the random inputs with
the values they hold (an empirical distribution's data, not only its file name), the
packed parameters and sediment/current banks handed to the kernels (the system's
``identity_items``), the seed, the
sampling method, ``n``, the chunk size, the package version and a digest of its Python
sources, and the SHA-256 of the contents of every input file the run reads (sediment
profile files, empirical-distribution files, the environment grid of a map). On
opening a store, chunks of another identity are discarded (and the run says so); on
loading, a chunk file that is unreadable, truncated or of another identity is deleted
and recomputed (and the run says so). So a rerun never mixes the drops of two runs, and
its result is bit-identical to a clean run of the same command.
"""

from __future__ import annotations

import dataclasses
import errno
import functools
import hashlib
import json
import os
import pathlib
import re
import shutil
import socket
import stat
import sys
import time
import zipfile

import numpy as np

from mineburial._version import __version__
from mineburial.errors import RunError, RunLockedError
from mineburial.io.files import atomic_path, atomic_write_bytes, check_destination
from mineburial.io.netcdf import write_netcdf

__all__ = [
    "RunError",
    "RunLockedError",
    "ChunkStore",
    "RunLock",
    "OutputRun",
    "run_identity",
    "check_output_path",
    "own_folder",
    "notice",
]

_MANIFEST = "manifest.json"
_LOCK = "lock"
#: the mark of a working folder mineburial created (module docstring)
MARK = ".mineburial-parts"
_CHUNK = re.compile(r"^chunk-(\d{12})-(\d{12})\.npz$")


def notice(message: str) -> None:
    """Tell the user about something the run did on its own (one line on stderr)."""
    print(f"mineburial: {message}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------
# run identity
# ---------------------------------------------------------------------------
@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 of the package's Python sources (names and contents): the engine version
    of a source tree whose version number did not change."""
    root = pathlib.Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _settings(spec) -> dict:
    """The run settings that decide a chunk's results, for the identity and messages."""
    return {
        "seed": spec.seed,
        "n": spec.n,
        "sampling": spec.sampling,
        "chunk_size": spec.chunk_size,
        "version": __version__,
    }


def run_identity(spec, extra_files=()) -> str:
    """Identity of the chunks of the ensemble ``spec`` (module docstring).

    ``extra_files``: ``((path, sha256), ...)`` of further files the run reads (the
    environment grid of a map). Per-drop output and the class basis are not part of
    it: they only change what is made of the chunks.
    """
    h = hashlib.sha256()

    def add(tag, data):
        h.update(tag.encode() + b"\0")
        h.update(data if isinstance(data, bytes) else str(data).encode())
        h.update(b"\0")

    add("settings", json.dumps(_settings(spec), sort_keys=True))
    add("code", code_digest())
    add("scenario", json.dumps(spec.base.to_dict(), sort_keys=True, default=repr))
    for path in sorted(spec.random):
        add(f"random:{path}", repr(spec.random[path]))
    for tag, data in spec.identity_items():  # the system's own inputs (the mine: packed parameters)
        add(tag, data)
    for path, digest in sorted(tuple(spec.input_files) + tuple(extra_files)):
        add(f"file:{path}", digest)
    return h.hexdigest()


def _differences(old: dict, new: dict) -> str:
    keys = [k for k in new if old.get(k) != new.get(k)]
    if not keys:
        return "a different scenario, input file or program"
    return ", ".join(f"{k} {old.get(k)!r} -> {new.get(k)!r}" for k in keys)


# ---------------------------------------------------------------------------
# working folders
# ---------------------------------------------------------------------------
def own_folder(folder) -> pathlib.Path:
    """``folder``, created and marked as mineburial's own (:data:`MARK`) if it does not
    exist; an existing one is used only if it bears the mark. A symbolic link, a file, or a
    folder mineburial did not create is refused (:class:`RunError`): its contents are
    never touched."""
    folder = pathlib.Path(folder)
    try:
        os.mkdir(folder)
        created = True
    except FileExistsError:
        created = False
    st = os.lstat(folder)
    if stat.S_ISLNK(st.st_mode) or not stat.S_ISDIR(st.st_mode):
        kind = "a symbolic link" if stat.S_ISLNK(st.st_mode) else "not a folder"
        raise RunError(
            f"'{folder}' (mineburial's working folder of the output) is {kind}; mineburial "
            f"works only in a folder it created: remove it or choose another output"
        )
    mark = folder / MARK
    if created:
        fd = os.open(mark, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o666)
        try:
            with os.fdopen(fd, "w") as fh:
                fh.write("mineburial's working folder: finished chunks until the output is written\n")
        except OSError as exc:  # a full disk: name the file, leave no folder behind
            mark.unlink(missing_ok=True)
            folder.rmdir()
            raise OSError(exc.errno, exc.strerror, str(mark)) from None
    elif not (mark.is_file() and not mark.is_symlink()):
        raise RunError(
            f"'{folder}' (mineburial's working folder of the output) exists but was not created "
            f"by mineburial (no {MARK} in it); it is left untouched: rename it or choose another output"
        )
    return folder


def _empty_folder(folder: pathlib.Path, keep=()) -> None:
    """Remove every entry of the marked ``folder`` but ``keep``, never following a link
    (a link is removed itself; ``shutil.rmtree`` does not follow links either)."""
    for entry in os.scandir(folder):
        if entry.name in keep:
            continue
        if entry.is_dir(follow_symlinks=False):
            shutil.rmtree(entry.path)
        else:
            os.unlink(entry.path)


# ---------------------------------------------------------------------------
# chunk store
# ---------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class ChunkStore:
    """The chunk files of one ensemble in ``folder``, tied to the run ``identity``.

    Picklable (it travels with the chunk tasks to dask workers).
    """

    folder: str
    identity: str
    #: columns of a chunk's ``summary`` (the system's ``summary_width``)
    width: int
    settings: dict = dataclasses.field(default_factory=dict, compare=False)

    @classmethod
    def for_spec(cls, spec, folder, extra_files=()) -> ChunkStore:
        return cls(str(folder), run_identity(spec, extra_files), spec.summary_width, _settings(spec))

    @property
    def path(self) -> pathlib.Path:
        return pathlib.Path(self.folder)

    def chunk_path(self, start: int, stop: int) -> pathlib.Path:
        return self.path / f"chunk-{int(start):012d}-{int(stop):012d}.npz"

    # -- opening -----------------------------------------------------------------
    def open(self) -> ChunkStore:
        """Create the folder, discard chunks of another run and stray temporary files
        (saying so), and record this run's identity. Call with the run's lock held."""
        folder = own_folder(self.path)
        manifest = folder / _MANIFEST
        old = None
        if manifest.exists():
            try:
                old = json.loads(manifest.read_text())
            except (OSError, ValueError):
                old = {}
        chunks = [f for f in folder.iterdir() if _CHUNK.match(f.name)]
        if chunks and (old is None or old.get("identity") != self.identity):
            why = (
                _differences(old.get("settings", {}), self.settings)
                if old
                else "no record of the run that wrote them"
            )
            notice(
                f"discarding {len(chunks)} finished chunk file(s) in {folder} of another "
                f"run ({why}); they are recomputed for this run"
            )
            for f in chunks:
                f.unlink(missing_ok=True)
        for f in folder.glob(".*.tmp"):  # left by a run killed while writing
            f.unlink(missing_ok=True)
        atomic_write_bytes(
            manifest, json.dumps({"identity": self.identity, "settings": self.settings}).encode()
        )
        return self

    def shared(self) -> bool:
        """Whether this process sees the store opened by the run's client (a dask worker
        on a filesystem shared with the client)."""
        try:
            return json.loads((self.path / _MANIFEST).read_text()).get("identity") == self.identity
        except (OSError, ValueError):
            return False

    # -- chunks ------------------------------------------------------------------
    def save(self, result: dict) -> pathlib.Path:
        """Write one chunk's results atomically, stamped with the run identity."""
        path = self.chunk_path(int(result["start"]), int(result["stop"]))
        arrays = {k.replace(":", "__"): v for k, v in result.items()}
        arrays["identity"] = np.array(self.identity)
        with atomic_path(path) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
        return path

    def has(self, start: int, stop: int) -> bool:
        return self.chunk_path(start, stop).exists()

    def load(self, start: int, stop: int) -> dict | None:
        """The results of chunk ``[start, stop)``, or None when there is no usable file:
        a missing file, or one that is unreadable, truncated, of another run or of the
        wrong shape (deleted, with a notice; the caller recomputes the chunk)."""
        path = self.chunk_path(start, stop)
        if not path.exists():
            return None
        try:
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
        except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
            problem = f"is unreadable ({type(exc).__name__}: {exc})"
        else:
            problem = self._check(data, start, stop)
            if problem is None:
                data.pop("identity")
                return {k.replace("__", ":"): v for k, v in data.items()}
        notice(f"chunk file {path} {problem}; recomputing drops [{start}, {stop})")
        path.unlink(missing_ok=True)
        return None

    def _check(self, data: dict, start: int, stop: int) -> str | None:
        n = stop - start
        if str(data.get("identity", "")) != self.identity:
            return "was written by another run"
        try:
            ok = (
                int(data["start"]) == start
                and int(data["stop"]) == stop
                and data["summary"].shape == (n, self.width)
                and data["status"].shape == (n,)
                and "invalid_inputs" in data
                and all(v.shape == (n,) for k, v in data.items() if k.startswith("input__"))
            )
        except (KeyError, TypeError, ValueError):
            ok = False
        return None if ok else "is incomplete or of the wrong shape"


# ---------------------------------------------------------------------------
# lock
# ---------------------------------------------------------------------------
try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: the lock records its owner only
    fcntl = None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True


class RunLock:
    """The lock of one output path: only one live run writes it.

    ``fcntl.flock`` on ``folder/lock`` (released by the kernel when the holder dies, so
    the lock file of a killed run is taken over). Where the filesystem has no ``flock``,
    the owner recorded in the file decides: a lock of a process that is no longer
    alive on this host is taken over.
    """

    def __init__(self, folder, output):
        self.path = pathlib.Path(folder) / _LOCK
        self.output = output
        self.fd = None

    def _owner(self) -> dict:
        try:
            fd = os.open(self.path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
            with os.fdopen(fd, "rb") as fh:
                return json.loads(fh.read(4096) or b"{}")
        except (OSError, ValueError):
            return {}

    def _refuse(self, owner: dict):
        who = (
            (
                f"process {owner.get('pid', '?')} on {owner.get('host', '?')}, started "
                f"{owner.get('started', '?')}"
            )
            if owner
            else "another process"
        )
        raise RunLockedError(
            f"output '{self.output}' is being written by another mineburial run ({who}); "
            f"wait for it to finish or choose another output path (lock: {self.path})"
        )

    def acquire(self) -> RunLock:
        """Take the lock: the lock file is created exclusively (``O_EXCL``, ``O_NOFOLLOW``)
        with this process's record, in the marked working folder (:func:`own_folder`); a
        lock file left by a dead run is removed and created anew (never truncated, never
        followed through a link)."""
        own_folder(self.path.parent)
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o666)
            except FileExistsError:
                self._take_over_stale()
                continue
            try:
                self._flock(fd)
                # the file may have been removed by a run that took over a stale lock
                if os.path.samestat(os.fstat(fd), os.lstat(self.path)):
                    break
            except FileNotFoundError:
                pass
            except BaseException:
                os.close(fd)
                raise
            os.close(fd)
        owner = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        }
        try:
            os.pwrite(fd, json.dumps(owner).encode(), 0)
        except OSError as exc:  # a full disk: name the file, leave no lock behind
            self.path.unlink(missing_ok=True)
            os.close(fd)
            raise OSError(exc.errno, exc.strerror, str(self.path)) from None
        self.fd = fd
        return self

    def _flock(self, fd) -> None:
        """Lock ``fd`` or refuse (another live run holds it)."""
        if fcntl is None:  # pragma: no cover
            return self._check_owner()
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._refuse(self._owner())
        except OSError:  # a filesystem without flock: the recorded owner
            self._check_owner()

    def _take_over_stale(self) -> None:
        """The lock file exists: refuse if a live run holds it, else remove it (the caller
        creates it anew). A link or anything but a regular file there is refused."""
        try:
            fd = os.open(self.path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
        except FileNotFoundError:  # removed meanwhile: try to create it again
            return
        except OSError as exc:
            if exc.errno != errno.ELOOP:
                raise RunError(f"the lock '{self.path}' of output '{self.output}': {exc.strerror}") from None
            fd = None  # a symbolic link
        try:
            if fd is None or not stat.S_ISREG(os.fstat(fd).st_mode):
                raise RunError(
                    f"the lock '{self.path}' of output '{self.output}' is not a regular file (a "
                    f"link or a device); it is not used: remove it or choose another output"
                )
            self._flock(fd)  # refuses while a live run holds it
            if os.path.samestat(os.fstat(fd), os.lstat(self.path)):
                os.unlink(self.path)
        except FileNotFoundError:
            pass
        finally:
            if fd is not None:
                os.close(fd)

    def _check_owner(self):
        owner = self._owner()
        if (
            owner.get("pid")
            and owner.get("pid") != os.getpid()
            and (owner.get("host") != socket.gethostname() or _alive(int(owner["pid"])))
        ):
            self._refuse(owner)

    def release(self, remove: bool = True):
        """Release the lock (removing the lock file first when ``remove``)."""
        if self.fd is None:
            return
        if remove:
            self.path.unlink(missing_ok=True)
        os.close(self.fd)
        self.fd = None


# ---------------------------------------------------------------------------
# the output of a run
# ---------------------------------------------------------------------------
def same_file(a: pathlib.Path, b: pathlib.Path) -> bool:
    """Whether paths ``a`` and ``b`` name the same file (also through links)."""
    try:
        return a.resolve() == b.resolve() or (a.exists() and b.exists() and os.path.samefile(a, b))
    except OSError:
        return False


def check_output_path(output, inputs=(), what: str = "output") -> pathlib.Path:
    """Check before computing that ``output`` can be written: not a folder, its parent an
    existing folder, none of the run's ``inputs`` (files the run reads, resolved through
    links: writing the output there would destroy it), and a regular file or nothing
    (:func:`mineburial.io.files.check_destination`: no device, FIFO or link). ``what``
    names the path in messages (``-o``)."""
    out = pathlib.Path(output)
    if out.is_dir() and not out.is_symlink():
        raise RunError(f"{what} '{out}' is an existing folder; give a file name (e.g. {out / 'burial.nc'})")
    parent = out.parent if str(out.parent) else pathlib.Path(".")
    if not parent.exists():
        raise RunError(f"{what} '{out}': the folder '{parent}' does not exist")
    if not parent.is_dir():
        raise RunError(f"{what} '{out}': '{parent}' is a file, not a folder")
    for path in inputs:
        if path is not None and same_file(out, pathlib.Path(path)):
            raise RunError(
                f"{what} '{out}' is an input of the run ('{path}'); writing the "
                f"output there would destroy it: choose another path"
            )
    check_destination(out, what)
    if out.exists() and not os.access(out, os.W_OK):
        raise RunError(f"{what} '{out}' exists and is not writable")
    if not os.access(parent, os.W_OK):
        raise RunError(f"{what} '{out}': the folder '{parent}' is not writable")
    return out


class OutputRun:
    """The working state of a run that writes ``output``: checks the path, holds the lock,
    removes the stray temporary files of a killed final write, hands out chunk stores
    and, on :meth:`commit`, writes the output atomically and removes the parts folder.

    Use as a context manager; an interrupted run keeps its parts folder (to resume) and
    releases the lock; a parts folder that holds nothing to resume from (no chunk store
    was opened: ``drop``, ``compare``, ...) is removed. The parts folder is used only if
    mineburial created it (:func:`own_folder`).
    """

    def __init__(self, output, inputs=(), what: str = "output"):
        self.output = check_output_path(output, inputs, what)
        self.parts = self.output.with_name(self.output.name + ".parts")
        self.lock = RunLock(self.parts, self.output)

    def __enter__(self) -> OutputRun:
        self.lock.acquire()
        try:
            pattern = re.compile(r"^\." + re.escape(self.output.name) + r"\.[0-9a-f]{16}\.tmp$")
            for f in self.output.parent.iterdir():
                if pattern.match(f.name):
                    notice(f"removing {f}, left by an interrupted write of '{self.output}'")
                    f.unlink(missing_ok=True)
        except BaseException:
            self.lock.release(remove=False)
            raise
        return self

    def __exit__(self, *exc):
        try:
            if self.lock.fd is not None and {e.name for e in os.scandir(self.parts)} <= {MARK, _LOCK}:
                self._remove_parts()  # nothing to resume from
        except OSError:  # the folder is gone or unreadable: nothing to remove
            pass
        self.lock.release(remove=False)
        return False

    def store(self, spec, name: str | None = None, extra_files=()) -> ChunkStore:
        """The opened chunk store of ensemble ``spec`` (in the sub-folder ``name``)."""
        folder = self.parts if name is None else self.parts / name
        return ChunkStore.for_spec(spec, folder, extra_files).open()

    def commit(self, ds) -> pathlib.Path:
        """Write ``ds`` to the output atomically, then remove the parts folder."""
        write_netcdf(ds, self.output)
        self._remove_parts()
        return self.output

    def _remove_parts(self) -> None:
        """Empty and remove the (marked) parts folder, releasing the lock. The mark goes
        before the lock: a run starting meanwhile is refused, never given a folder that is
        being removed."""
        _empty_folder(self.parts, keep=(MARK, _LOCK))
        (self.parts / MARK).unlink(missing_ok=True)
        self.lock.release(remove=True)
        try:
            self.parts.rmdir()
        except OSError:  # a new run took the folder in the meantime
            pass
