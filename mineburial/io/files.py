"""The one atomic file write of mineburial: every output (NetCDF, chunk, manifest, PNG,
GeoTIFF, report) goes through :func:`atomic_path`.

A file is written under a temporary name in the destination's folder, flushed to disk
with ``fsync``, checked (a regular file, not empty, and what the caller's ``verify`` reads
back) and moved over the destination with ``os.replace``, and the folder is
fsynced so that the rename itself is durable: a reader sees the previous file or the
complete new one, never a partial file, and a run killed at any moment loses nothing
already finished. On an error the temporary file is removed and the destination is left
untouched. The temporary names are ``.<name>.<16 hex digits>.tmp`` (:data:`TMP_PATTERN`).

A destination is written only in place of a regular file or of nothing
(:func:`check_destination`): a device (``/dev/null``, ``/dev/full``), a FIFO, a socket, a
folder or a symbolic link there is refused, checked again just before the rename, so the
rename never replaces a device node or a link. An error of the operating system that
names no file (a full disk, ``[Errno 28]``) is raised again naming the destination.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import stat
from collections.abc import Iterator
from pathlib import Path

from mineburial.errors import ScenarioError

#: glob pattern of the temporary files of :func:`atomic_path` (for cleaning up after a kill)
TMP_PATTERN = ".*.tmp"


class OutputPathError(ScenarioError):
    """An output path that must not be written (not a regular file, a link, an input)."""


_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
)


def check_destination(path, what: str = "output") -> Path:
    """Refuse a destination that is not a regular file or nothing: a folder, a device, a
    FIFO, a socket, or a symbolic link (a link is never written through nor replaced:
    docs/design.md, "Outputs"). ``what`` names the path in the message (``-o``)."""
    path = Path(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return path
    except OSError as exc:
        raise OutputPathError(f"{what} '{path}' cannot be checked: {exc.strerror}") from None
    if stat.S_ISLNK(st.st_mode):
        raise OutputPathError(
            f"{what} '{path}' is a symbolic link (to '{os.readlink(path)}'); mineburial does not "
            f"write through links: give the target's own path or remove the link"
        )
    if not stat.S_ISREG(st.st_mode):
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        raise OutputPathError(
            f"{what} '{path}' is {kind}; outputs are written only as regular files: give a file name"
        )
    return path


def _named(exc: OSError, path: Path) -> OSError:
    """``exc`` naming ``path`` when the OS error names no file (ENOSPC, EFBIG, EIO of a write)."""
    if exc.filename is None and exc.errno is not None:
        return OSError(exc.errno, f"{exc.strerror} (writing this file)", str(path))
    return exc


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


def _check_written(tmp: Path, path: Path, nonempty: bool) -> None:
    """The temporary file is still a regular file (not swapped for a link), not empty."""
    st = os.lstat(tmp)
    if not stat.S_ISREG(st.st_mode) or (nonempty and st.st_size == 0):
        raise OSError(
            errno.EIO,
            "the file written is empty or not a regular file (is the disk full?); the previous "
            "file, if any, is unchanged",
            str(path),
        )


@contextlib.contextmanager
def atomic_path(path, *, replace: bool = True, verify=None, nonempty: bool = True) -> Iterator[Path]:
    """Context manager: yields a temporary path beside ``path`` to write the file to; on a
    normal exit the file is fsynced, checked and moved over ``path``, on an error it is removed.

    The check: the temporary file must be a regular file, not empty unless ``nonempty`` is
    false (a library that reports a failed write only on stderr, as GDAL does, leaves it short
    or empty), and ``verify(tmp)``, when given, must return without raising (it reads the file
    back; :func:`atomic_write_bytes` compares the size written).

    ``path`` must be a regular file or nothing (:func:`check_destination`, checked before
    and again just before the rename). With ``replace=False`` an existing ``path`` is never
    replaced: the file is linked to its name only if that name is free
    (:class:`FileExistsError` otherwise, also when another process took it meanwhile).

    >>> with atomic_path("out.nc") as tmp:        # doctest: +SKIP
    ...     ds.to_netcdf(tmp)
    """
    path = check_destination(path)
    tmp = _fresh_tmp(path)
    try:
        try:
            yield tmp
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
            _check_written(tmp, path, nonempty)
            if verify is not None:
                verify(tmp)
        except OSError as exc:
            raise _named(exc, path) from exc
        if replace:
            check_destination(path)
            os.replace(tmp, path)
        else:
            os.link(tmp, path)  # fails if the name exists: nothing is replaced
            tmp.unlink()
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise
    _fsync_dir(tmp.parent)


def atomic_write_bytes(path, data: bytes, *, replace: bool = True) -> Path:
    """Write ``data`` to ``path`` atomically (:func:`atomic_path`), the size written checked
    against ``len(data)``; returns the path."""

    def verify(tmp: Path) -> None:
        if os.path.getsize(tmp) != len(data):
            raise OSError(
                errno.EIO,
                f"only {os.path.getsize(tmp)} of {len(data)} bytes were written (is the disk full?); "
                "the previous file, if any, is unchanged",
                str(path),
            )

    with atomic_path(path, replace=replace, verify=verify, nonempty=bool(data)) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
    return Path(path)


def atomic_write_text(path, text: str, *, replace: bool = True) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically (:func:`atomic_path`); returns the path."""
    return atomic_write_bytes(path, text.encode("utf-8"), replace=replace)
