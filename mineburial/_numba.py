"""The one place that sets numba options for every kernel of mineburial.

Every compiled function in :mod:`mineburial.kernels` and the ensemble driver is
decorated with :func:`kernel`, and every ``numba.extending.overload`` takes
:data:`JIT_OPTIONS`, so changing an option (caching, fastmath, error model) is a
one-line change here.

* ``cache``: compiled machine code is cached on disk beside the sources (numba's
  ``__pycache__/*.nbi, *.nbc``), so the compile cost (tens of seconds for the whole
  drop stepper) is paid once per installation rather than once per process; ``pip install``
  pays it for the kernels ``mineburial run`` needs and ships their cache in the wheel
  (``_build_backend/mineburial_build.py``, docs/design.md "Install-time cache"). A cache
  file that cannot be read (garbled, truncated) is a miss with one warning line: the kernel
  compiles and numba rewrites the file. The
  environment variable ``MINEBURIAL_NUMBA_CACHE`` switches it: ``0`` (or ``false``,
  ``no``, ``off``) compiles in memory only, which is what to use while editing a
  kernel (numba checks a cached function against its own source file, not against
  the kernels it calls in other files, so a stale cache can survive an edit) or on
  a read-only installation; ``1`` (``true``, ``yes``, ``on``) or unset caches; any
  other value is an error. It is read once, when mineburial is imported (the same
  kind of switch as sgkit's ``SGKIT_DISABLE_NUMBA_CACHE``). numba loads its cache index
  with ``pickle``, so each kernel's cache folder (and ``NUMBA_CACHE_DIR``) is first checked
  (:func:`cache_folder_problem`): one that another user owns or can write is not used (one
  warning line; the kernels compile in memory), docs/cluster.md. So is each cache file
  before numba reads it (:func:`cache_file_problem`: a link, another user's file, or one
  others can write is not loaded, one warning line, and the kernel compiles in memory), and
  the files are written readable and writable by the user alone (mode 0600, whatever the
  umask). A ``NUMBA_CACHE_DIR`` that is not a folder (a regular file: numba would silently
  cache beside the installed sources instead) is refused in one line (issue 35).
* ``fastmath=False``: results must be bit-identical whatever the thread count or
  chunking; re-association of floating-point sums would break that.
* ``error_model="numpy"``: a division by zero gives inf/nan instead of raising,
  because kernels never raise (they run on worker threads); they return status codes.
* ``nogil=True``: the batch driver runs compiled drops on several Python threads.
* ``no_cfunc_wrapper=True``: numba would otherwise build, optimise and link a C-callable
  wrapper of every compiled function (for use as a first-class function value or
  ``cfunc``), which mineburial never uses.
"""

import contextlib
import errno
import gc
import os
import secrets
import stat
import sys
import threading
import types

try:
    import grp
    import pwd
except ImportError:  # pragma: no cover - not POSIX
    pass

from numba.core import config as numba_config
from numba.core import types as nbtypes
from numba.core.caching import FunctionCache, IndexDataCacheFile, NullCache
from numba.core.registry import CPUDispatcher

from mineburial.errors import ScenarioError

#: name of the environment variable that switches the on-disk cache of compiled kernels
CACHE_ENV = "MINEBURIAL_NUMBA_CACHE"


_OFF = ("0", "false", "no", "off")
_ON = ("1", "true", "yes", "on", "")


class CacheSettingError(ScenarioError):
    """``MINEBURIAL_NUMBA_CACHE`` has a value that is neither on nor off (a user's error: the
    command line prints it in one line, with exit status 2)."""


def cache_enabled(environ=os.environ) -> bool:
    """Whether compiled kernels are cached on disk (``MINEBURIAL_NUMBA_CACHE``)."""
    value = environ.get(CACHE_ENV, "1").strip().lower()
    if value in _OFF:
        return False
    if value in _ON:
        return True
    raise CacheSettingError(
        f"environment variable {CACHE_ENV} = {environ[CACHE_ENV][:40]!r} must be 1 (or "
        f"{', '.join(_ON[1:-1])}: cache compiled kernels on disk, the default) or 0 (or "
        f"{', '.join(_OFF[1:])}: compile in memory only)"
    )


def cache_dir_problem(cache_dir) -> str | None:
    """Why ``NUMBA_CACHE_DIR`` = ``cache_dir`` cannot be numba's cache, or None: a path that
    exists and is not a folder (a regular file, a device, a dangling link). numba would fall
    back silently to caching beside the installed sources (issue 35)."""
    if cache_dir and os.path.lexists(cache_dir) and not os.path.isdir(cache_dir):
        kind = "a regular file" if os.path.isfile(cache_dir) else "not a folder"
        return (
            f"environment variable NUMBA_CACHE_DIR = '{cache_dir}' is {kind}; numba's cache of "
            f"compiled kernels must be a folder: give a private folder (docs/cluster.md) or set "
            f"{CACHE_ENV}=0 to compile in memory"
        )
    return None


def _cache_setting():
    try:
        enabled = cache_enabled()
    except CacheSettingError as exc:
        return str(exc)
    return (enabled and cache_dir_problem(numba_config.CACHE_DIR)) or enabled


#: True, False, or the message of a bad ``MINEBURIAL_NUMBA_CACHE``, raised as a
#: :class:`CacheSettingError` when the first kernel is made (so that the command line can
#: import this module and report it in one line)
_CACHE = _cache_setting()


def _cache() -> bool:
    if isinstance(_CACHE, str):
        raise CacheSettingError(_CACHE)
    return _CACHE


def _private_group(gid: int, uid: int) -> bool:
    """Whether group ``gid`` is the user's own private group (named as the user, no other
    member): a folder writable by it is writable by the user alone (umask 002 systems)."""
    try:
        group = grp.getgrgid(gid)
        user = pwd.getpwuid(uid).pw_name
    except (KeyError, NameError):  # unknown ids, or no grp/pwd (not POSIX)
        return False
    return group.gr_name == user and set(group.gr_mem) <= {user}


def cache_folder_problem(path, uid: int | None = None) -> str | None:
    """Why numba must not use ``path`` as its cache folder, or None if it may.

    numba loads its index files with ``pickle``: whoever can write to the folder can make
    every later run execute their code (issue 21). The folder must be owned by the user
    (``uid``, default the effective user) and writable by no one else: not by all users,
    and not by its group unless that is the user's private group.
    """
    try:
        st = os.stat(path)
    except OSError as exc:
        return f"cannot be examined ({exc.strerror})"
    return _owner_mode_problem(st, uid)


def _owner_mode_problem(st: os.stat_result, uid: int | None = None) -> str | None:
    """Why a cache folder or file of status ``st`` is not the user's alone, or None."""
    uid = os.geteuid() if uid is None else uid
    if st.st_uid != uid:
        return f"is owned by another user (uid {st.st_uid})"
    if st.st_mode & stat.S_IWOTH:
        return "is writable by every user"
    if st.st_mode & stat.S_IWGRP and not _private_group(st.st_gid, uid):
        return f"is writable by its group (gid {st.st_gid})"
    return None


def cache_file_problem(path, uid: int | None = None) -> str | None:
    """Why numba must not load the cache file (index ``.nbi`` or data ``.nbc``) ``path``, or
    None if it may (also when there is none): numba unpickles it, so it must be a regular
    file, not a link, owned by the user (``uid``) and writable by no one else, as its folder
    (:func:`cache_folder_problem`). A job run under ``umask 000`` by an older version wrote
    such files mode 0666; another user could replace their contents with a pickle."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"cannot be examined ({exc.strerror})"
    if stat.S_ISLNK(st.st_mode):
        return "is a symbolic link"
    if not stat.S_ISREG(st.st_mode):
        return "is not a regular file"
    return _owner_mode_problem(st, uid)


#: cache file -> reported already (one warning line per file)
_FILES: set = set()


def _warn_file(path, problem: str) -> None:
    if path not in _FILES:
        _FILES.add(path)
        print(
            f"mineburial: warning: numba's cache file '{path}' {problem}; compiling in memory "
            "instead of loading code from it (remove the file, or set NUMBA_CACHE_DIR to a "
            "private folder, docs/cluster.md)",
            file=sys.stderr,
        )


def _warn_unreadable(path, exc: BaseException, what: str = "cache file") -> None:
    """One warning line for a cache file that cannot be read (garbled, truncated): numba would
    raise out of the kernel's first call; it is compiled instead and the file rewritten."""
    if path not in _FILES:
        _FILES.add(path)
        print(
            f"mineburial: warning: numba's {what} '{path}' cannot be read "
            f"({type(exc).__name__}: {str(exc)[:80]}); compiling instead (the file is rewritten)",
            file=sys.stderr,
        )


class _CheckedCacheFile(IndexDataCacheFile):
    """numba's index and data files of one kernel, each checked before numba unpickles it
    (:func:`cache_file_problem`) and written mode 0600 (not through the umask). After a file
    is refused, the kernel neither loads nor saves its cache: it compiles in memory. A file that
    cannot be read (garbled or truncated: numba's unpickling error would end the run; issue 34, a
    cache shipped in the wheel) counts as no entry: the kernel compiles and numba rewrites it."""

    _refused = False

    def _trusted(self, path) -> bool:
        problem = None if self._refused else cache_file_problem(path)
        if problem:
            self._refused = True
            _warn_file(path, problem)
        return not self._refused

    def _load_index(self):
        if not self._trusted(self._index_path):
            return {}
        try:
            return super()._load_index()
        except Exception as exc:  # any unpickling error; numba's save() then writes a new index
            _warn_unreadable(self._index_path, exc)
            return {}

    def _load_data(self, name):
        path = self._data_path(name)
        if not self._trusted(path):  # numba's load() treats an OSError as no entry
            raise OSError(errno.EPERM, "refused numba cache file", path)
        try:
            return super()._load_data(name)
        except OSError:
            raise
        except Exception as exc:  # unpickling: no entry, compiled and the file overwritten
            _warn_unreadable(path, exc)
            raise OSError(errno.EIO, "unreadable numba cache file", path) from exc

    def save(self, key, data):
        if self._trusted(self._index_path):
            super().save(key, data)

    @contextlib.contextmanager
    def _open_for_write(self, filepath):
        """numba's write to a fresh name and rename, the file created mode 0600 (O_EXCL, no
        link followed) whatever the process' umask."""
        tmpname = f"{filepath}.tmp.{secrets.token_hex(8)}"
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
        try:
            with os.fdopen(os.open(tmpname, flags, 0o600), "wb") as f:
                os.fchmod(f.fileno(), 0o600)  # the umask can only clear bits: 0600 exactly
                yield f
            os.replace(tmpname, filepath)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmpname)
            raise


def _checked_load_overload(cache, sig, target_context):
    """numba's ``load_overload`` of ``cache`` (a kernel's ``FunctionCache``), an entry that numba
    cannot rebuild compiled code from (unpickled, but not what numba wrote) counted as no entry:
    the kernel is compiled (set on the instance by :func:`_safe_cache`; the class stays numba's)."""
    try:
        return type(cache).load_overload(cache, sig, target_context)
    except Exception as exc:
        _warn_unreadable(cache._cache_file._index_path, exc, "cache entry indexed in")
        return None


#: cache folder -> its problem (None: safe), each folder examined and reported once
_FOLDERS: dict[str, str | None] = {}


def _safe_cache(disp) -> None:
    """Turn off the on-disk cache of dispatcher ``disp`` when the folder numba chose for it
    (or ``NUMBA_CACHE_DIR`` above it) is unsafe (:func:`cache_folder_problem`), with one
    warning line on stderr per folder; the kernel is then compiled in memory."""
    cache = getattr(disp, "_cache", None)
    if not isinstance(cache, FunctionCache):
        return
    if type(cache._cache_file) is IndexDataCacheFile:  # the same state, checked loads and saves
        cache._cache_file.__class__ = _CheckedCacheFile
    cache.load_overload = types.MethodType(_checked_load_overload, cache)
    folders = [cache.cache_path]
    if numba_config.CACHE_DIR:
        folders.append(numba_config.CACHE_DIR)
    for folder in folders:
        if folder not in _FOLDERS:
            _FOLDERS[folder] = cache_folder_problem(folder)
            if _FOLDERS[folder]:
                print(
                    f"mineburial: warning: numba's cache folder '{folder}' {_FOLDERS[folder]}; "
                    "compiling in memory instead of loading code from it (set NUMBA_CACHE_DIR "
                    "to a private folder, docs/cluster.md)",
                    file=sys.stderr,
                )
        if _FOLDERS[folder]:
            disp._cache = NullCache()
            return


#: the same options for ``numba.extending.overload`` implementations (compiled into their
#: caller, which caches them)
JIT_OPTIONS = dict(nogil=True, fastmath=False, error_model="numpy", no_cfunc_wrapper=True)


def _dispatcher(cls, fn, cache, **options):
    """A numba dispatcher of class ``cls`` (a :class:`_LazyCacheDispatcher`) for ``fn``, as
    ``njit`` builds one."""
    disp = cls(py_func=fn, locals={}, targetoptions=dict(nopython=True, boundscheck=None, **options))
    if cache:
        disp.enable_caching()
    return disp


@contextlib.contextmanager
def _no_group_or_other_write():
    """The umask with group and other write cleared while the block runs: the folders numba
    creates for its cache (``os.makedirs``) are then never writable by others, even for a job
    run under ``umask 000`` (the folder check would refuse them: compiled in memory at every
    run). The umask is the process's: another thread creating a file meanwhile gets, at most,
    fewer permissions."""
    old = os.umask(0o022)
    os.umask(old | 0o022)
    try:
        yield
    finally:
        os.umask(old)


class _LazyCache:
    """The ``_cache`` attribute of a :class:`_LazyCacheDispatcher`: numba's on-disk cache of the
    dispatcher, made at its first use (a compile, or a load from the cache) and checked then
    (:func:`_safe_cache`)."""

    _lock = threading.RLock()

    def __get__(self, disp, owner=None):
        if disp is None:
            return self
        if disp.__dict__.get("_cache_wanted"):
            with self._lock:
                if disp.__dict__.pop("_cache_wanted", False):
                    with _no_group_or_other_write():  # numba creates the folder: never 0777
                        CPUDispatcher.enable_caching(disp)
                    _safe_cache(disp)
        return disp.__dict__["_cache"]

    def __set__(self, disp, value):
        disp.__dict__["_cache"] = value


_COLLECTOR_LOCK = threading.Lock()
#: [compiles in progress, whether the cyclic garbage collector was enabled when the first began]
_COLLECTOR_PAUSE = [0, False]


@contextlib.contextmanager
def collector_paused():
    """Python's cyclic garbage collector off while the block runs (nested and concurrent blocks: on
    again, if it was on, when the last ends).

    numba's compiler builds large graphs of Python objects (its IR, typing and lowering state, a
    deep copy of a callee's IR at each inlining), and the collector's full passes walk all of them
    again and again while one kernel compiles: with the collector on, a cold compile of the default
    path spent 5.9 of its 48.4 CPU s in collections (``gc.callbacks``), and compiled in 36.6 s with it
    off (docs/design.md, "Compile time"). The garbage a compile leaves (reference cycles) is freed by
    the collector's first pass after the block."""
    with _COLLECTOR_LOCK:
        if _COLLECTOR_PAUSE[0] == 0:
            _COLLECTOR_PAUSE[1] = gc.isenabled()
            gc.disable()
        _COLLECTOR_PAUSE[0] += 1
    try:
        yield
    finally:
        with _COLLECTOR_LOCK:
            _COLLECTOR_PAUSE[0] -= 1
            if _COLLECTOR_PAUSE[0] == 0 and _COLLECTOR_PAUSE[1]:
                gc.enable()


class _LazyCacheDispatcher(CPUDispatcher):
    """A numba dispatcher whose on-disk cache is made when it is first used, not when the kernel
    is defined. numba's ``enable_caching`` makes a ``FunctionCache`` at once, which finds the
    cache folder (creating it and a test file in it) and stamps the source, for each of the 185
    dispatchers mineburial defines, while a run loads a handful from the cache: importing the
    engine after its dependencies took 0.149 s of CPU before, 0.120 s after (best of 8,
    alternated, bytecode cached; 185 fewer file creations where the cache folder is on a network
    file system; docs/design.md, "Warm start"). The code compiled and the cache files are the same."""

    _cache = _LazyCache()

    def enable_caching(self):
        self.__dict__["_cache_wanted"] = True

    def compile(self, sig):
        """numba's compile (or load from the cache) of ``sig``, with the garbage collector paused
        (:func:`collector_paused`): the kernels it calls compile inside it."""
        with collector_paused():
            return super().compile(sig)


class _CompiledCallee(_LazyCacheDispatcher):
    """The twin of a :class:`Kernel` that compiled code calls: compiled without the
    CPython wrapper, for argument types without literal values (a call with the constant
    1 and one with 2 share one specialisation instead of compiling two). A kernel that
    needs a literal argument (to index a heterogeneous tuple, or switch on a string) would
    not compile through it: make such a helper a ``small_kernel`` or an overload."""

    def get_call_template(self, args, kws):
        args = tuple(nbtypes.unliteral(a) for a in args)
        kws = {k: nbtypes.unliteral(v) for k, v in kws.items()}
        return super().get_call_template(args, kws)


class Kernel(_LazyCacheDispatcher):
    """A numba dispatcher that compiled code calls through a twin compiled without
    numba's CPython wrapper.

    numba builds, for every function it compiles, a wrapper that unboxes the Python
    arguments (for a kernel that takes the packed sediment law, a 30-element tuple) and
    boxes the result, and links it, with the function's own code, into the module of every
    compiled caller above it, where LLVM optimises it again at each level. Only a call
    from Python needs it. This dispatcher is what Python calls (tests, the batch driver,
    config.py), with the wrapper; compiled code sees it as its twin
    (:attr:`_numba_type_`, a :class:`_CompiledCallee`), the same function compiled with
    ``no_cpython_wrapper``, cached under its own name (``<name>.compiled_callee``). A
    kernel called only from compiled code is compiled once, without a wrapper; one called
    from both is compiled twice, once each way (docs/design.md, compile time).
    """

    _twin_lock = threading.RLock()

    @property
    def _numba_type_(self):
        with self._twin_lock:  # Python-side typeof() may run on several threads
            return nbtypes.Dispatcher(self._twin())

    def _twin(self):
        callee = self.__dict__.get("_callee")
        if callee is None:
            fn = self.py_func
            twin = types.FunctionType(
                fn.__code__, fn.__globals__, fn.__name__, fn.__defaults__, fn.__closure__
            )
            twin.__qualname__ = fn.__qualname__ + ".compiled_callee"
            twin.__doc__ = fn.__doc__
            twin.__kwdefaults__ = fn.__kwdefaults__
            cache = self.__dict__.get("_cache_wanted") or isinstance(self._cache, FunctionCache)
            callee = _dispatcher(_CompiledCallee, twin, cache, no_cpython_wrapper=True, **JIT_OPTIONS)
            self._callee = callee
        return callee


def kernel(fn):
    """Compile ``fn`` as a serial numba kernel with the project's options (a
    :class:`Kernel`: compiled callers call it without a CPython wrapper). Under
    ``NUMBA_DISABLE_JIT=1`` it is ``fn`` itself, as ``njit`` would give (the whole engine
    then runs as plain Python, for debugging)."""
    if numba_config.DISABLE_JIT:
        return fn
    return _dispatcher(Kernel, fn, _cache(), **JIT_OPTIONS)


def small_kernel(fn):
    """A kernel inlined into its callers at numba's IR level (``inline="always"``): no
    compile unit of its own. For small helpers (a few loops over a state vector) whose
    separate compile, link and cache cost more than their body (docs/design.md). Under
    ``NUMBA_DISABLE_JIT=1`` it is ``fn`` itself."""
    if numba_config.DISABLE_JIT:
        return fn
    return _dispatcher(_LazyCacheDispatcher, fn, _cache(), inline="always", **JIT_OPTIONS)
