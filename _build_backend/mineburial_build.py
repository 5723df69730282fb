"""mineburial's build backend: setuptools' (``setuptools.build_meta``), plus numba's cache of the
kernels that ``mineburial run`` needs, compiled at install time and shipped in the wheel (issue 34
item 1; docs/design.md, "Install-time cache").

``pip install .`` builds a wheel and installs it. Without this, the first ``mineburial run``
compiled the engine (the default path, then the reference path of its numerical self-check): about
two minutes on a 2-core host before the first answer. Here :func:`build_wheel` first runs
``mineburial_cache.COMPILE_SCRIPT`` in a fresh interpreter with the source tree first on
``sys.path`` (``mineburial_cache.precompile``), so numba writes its cache (``__pycache__/*.nbi``,
``*.nbc``) beside the sources, and then adds to the wheel the cache files that belong to its sources
(``mineburial_cache.current_cache_files``, ``mineburial_cache.add_to_wheel``).

Why it loads after installation, and when it does not (numba then compiles, as without it):

* numba (>= 0.68) stamps a cache index with a SHA-256 hash of the source file's content, and pip
  installs the wheel's files byte for byte: the stamp still matches (checked here before a file
  is added: the stamp must be the hash of the wheel's own copy of the source). An older numba
  stamped the file's modification time, which installation changes; with it nothing is shipped.
* the index records numba's version: a different numba at run time (build and run resolve the
  same pins, ``[build-system]`` as ``[project]``, so only a preinstalled older numba) reads the
  index as empty and compiles;
* each entry is keyed by the signature, the target (triple, CPU name, CPU features: numba's
  ``codegen.magic_tuple()``) and the bytecode's hash: a wheel built on one machine and installed
  on a CPU with other features finds no entry and compiles, so the cache is built for the host
  that installs (pip builds there), at full speed for it, and checked by numba before loading;
* ``NUMBA_CACHE_DIR`` set at run time points numba elsewhere (compiled there once);
* an installation that the user cannot write (a system-wide install) makes numba choose
  ``~/.cache/numba`` instead (compiled there once).

mineburial's own checks of cache files (``mineburial/_numba.py``: owner, mode, no link; a file
that cannot be read is a miss) apply to the shipped files as to any other.

Skipped (a wheel without cache, the kernels compile at the first run as before) with
``MINEBURIAL_PRECOMPILE=0`` (also ``false``, ``no``, ``off``), with ``MINEBURIAL_NUMBA_CACHE=0`` (no
on-disk cache wanted) or ``NUMBA_DISABLE_JIT=1``. A failure of the compile (an error, or more than
``mineburial_cache.TIMEOUT_S``) never fails the build: one warning line (pip shows a backend's output with
``-v``) and the wheel is built without cache. ``pip install -e .`` (:func:`build_editable`)
compiles in the source tree, which the editable install runs.
"""

import os

from mineburial_cache import add_to_wheel, precompile, warn
from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F403 (every other hook is setuptools' own)


def _precompile(root):
    """:func:`mineburial_cache.precompile`, whatever goes wrong a warning and None: the compile
    never fails the build."""
    try:
        return precompile(root)
    except Exception as exc:
        warn(f"the install-time compile failed ({type(exc).__name__}: {exc}); kernels compile at first use")
        return None


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """setuptools' wheel, with numba's cache of the kernels ``mineburial run`` reaches."""
    root = os.getcwd()
    files = _precompile(root)
    name = _setuptools.build_wheel(wheel_directory, config_settings, metadata_directory)
    if files:
        try:  # the wheel is replaced only once rewritten whole: on an error it stays setuptools'
            added = add_to_wheel(os.path.join(wheel_directory, name), root, files)
            warn(f"{added} numba cache files added to {name}")
        except Exception as exc:
            warn(f"numba's cache not added to the wheel ({type(exc).__name__}: {exc}); compiled at first use")
    return name


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    """setuptools' editable wheel, after compiling the kernels in the source tree it points to."""
    _precompile(os.getcwd())
    return _setuptools.build_editable(wheel_directory, config_settings, metadata_directory)
