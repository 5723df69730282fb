"""The one atomic file write of mineburial: every output (NetCDF, chunk, manifest) goes
through :func:`atomic_path`.

A file is written under a temporary name in the destination's folder, flushed to disk
with ``fsync`` and moved over the destination with ``os.replace``, and the folder is
fsynced so that the rename itself is durable: a reader sees the previous file or the
complete new one, never a partial file, and a run killed at any moment loses nothing
already finished. On an error the temporary file is removed and the destination is left
untouched. The temporary names are ``.<name>.<16 hex digits>.tmp`` (:data:`TMP_PATTERN`).
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

#: glob pattern of the temporary files of :func:`atomic_path` (for cleaning up after a kill)
TMP_PATTERN = ".*.tmp"


def _fsync_dir(directory: Path) -> None:
    """fsync a directory so that a rename in it is durable (POSIX; a no-op elsewhere)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - e.g. Windows cannot open directories
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - some file systems refuse directory fsync
        pass
    finally:
        os.close(fd)


def _fresh_tmp(path: Path) -> Path:
    # O_EXCL with mode 0o666 creates a fresh name and lets the umask set the permissions
    # (tempfile.mkstemp would leave the final file readable by its owner only)
    directory = path.parent if str(path.parent) else Path(".")
    while True:
        tmp = directory / f".{path.name}.{secrets.token_hex(8)}.tmp"
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return tmp
        except FileExistsError:  # pragma: no cover - 64 random bits
            continue


@contextlib.contextmanager
def atomic_path(path) -> Iterator[Path]:
    """Context manager: yields a temporary path beside ``path`` to write the file to; on a
    normal exit the file is fsynced and moved over ``path``, on an error it is removed.

    >>> with atomic_path("out.nc") as tmp:        # doctest: +SKIP
    ...     ds.to_netcdf(tmp)
    """
    path = Path(path)
    tmp = _fresh_tmp(path)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise
    _fsync_dir(tmp.parent)


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; returns the path."""
    return atomic_write_bytes(path, text.encode("utf-8"))
