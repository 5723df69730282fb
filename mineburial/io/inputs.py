"""The one check every input file passes before it is read (issue 21).

Every file mineburial reads on a user's behalf -- a scenario or case TOML, a tabulated
profile CSV, an empirical-distribution file, a NetCDF sediment core, a map's environment
grid -- is opened through :func:`open_input` (or checked by :func:`check_input` where a
library opens it by name): it must be a **regular file** (a FIFO, a device such as a link
to ``/dev/zero``, a folder or a socket is refused at once instead of blocking or filling the
memory) no larger than the limit of its kind (:data:`LIMITS`, docs/scenario.md). The file is
opened non-blocking, so that even a FIFO is refused without waiting for a writer, and its
type and size are taken from the open descriptor (``fstat``), not from the name.

Problems raise :class:`InputFileError`, an :class:`OSError` whose ``strerror`` says what is
wrong in a few words and never quotes the file's content; readers wrap it in their one-line
``ScenarioError`` (``cannot read scenario file 's.toml': ...``). Text is decoded as UTF-8;
a file that is not UTF-8 is named with the line and column of its first bad byte.
"""

from __future__ import annotations

import csv
import os
import re
import stat

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

MiB = 1 << 20
#: Largest accepted size in bytes of each kind of input file (documented in docs/scenario.md).
LIMITS = {
    "text": 64 * MiB,  # scenario and case TOML, profile CSV, empirical-distribution CSV
    "core": 256 * MiB,  # NetCDF sediment core
    "grid": 4096 * MiB,  # NetCDF environment grid of a map
}

_TYPES = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


class InputFileError(OSError):
    """An input file that must not be read (not a regular file, too large, not UTF-8)."""

    def __init__(self, path, problem: str):
        super().__init__(None, problem, str(path))

    def __str__(self) -> str:
        return f"{self.filename}: {self.strerror}"


def _size(path, fd: int, kind: str) -> int:
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        what = next((name for test, name in _TYPES if test(st.st_mode)), "not a regular file")
        raise InputFileError(path, f"{what}, not a regular file")
    limit = LIMITS[kind]
    if st.st_size > limit:
        raise InputFileError(
            path, f"{st.st_size / MiB:.1f} MiB, larger than the {limit // MiB} MiB limit of a {kind} input"
        )
    return st.st_size


def open_input(path, kind: str = "text"):
    """Open ``path`` for reading in binary mode after checking that it is a regular file
    within the size limit of ``kind`` (:data:`LIMITS`); raises :class:`InputFileError`
    (or the :class:`OSError` of the failed open)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        _size(path, fd, kind)
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def check_input(path, kind: str) -> int:
    """Check ``path`` as :func:`open_input` does, for a library that opens it by name
    (netCDF4, xarray); returns its size in bytes."""
    with open_input(path, kind) as fh:
        return _size(path, fh.fileno(), kind)


def read_sized(fh, limit: int) -> bytes:
    """The bytes of the open file ``fh``, at most ``limit`` + 1 (one more tells that it is over
    the limit), read in a buffer of the file's own size: ``read(limit + 1)`` allocates the whole
    limit at once (64 MiB for each scenario read: a MemoryError under a 500 MB address-space
    limit, issue 35). Only a file that grows while it is read is read on, in 64 KiB pieces."""
    data = fh.read(min(os.fstat(fh.fileno()).st_size, limit) + 1)
    while len(data) <= limit:
        more = fh.read(min(1 << 16, limit + 1 - len(data)))
        if not more:
            break
        data += more
    return data


def read_text(path, kind: str = "text") -> str:
    """The content of ``path`` as UTF-8 text, checked by :func:`open_input`."""
    with open_input(path, kind) as fh:
        data = read_sized(fh, LIMITS[kind])
    if len(data) > LIMITS[kind]:  # the file grew after the check
        raise InputFileError(path, f"larger than the {LIMITS[kind] // MiB} MiB limit of a {kind} input")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise InputFileError(
            path,
            f"not UTF-8 text (byte 0x{data[exc.start]:02x} at line {line}, column {column}); "
            "save it as UTF-8",
        ) from None


def parse_toml(text: str) -> dict:
    """``tomllib.loads`` whose every failure is a ``tomllib.TOMLDecodeError`` (a nesting too
    deep for the recursive parser included, instead of a ``RecursionError``)."""
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise tomllib.TOMLDecodeError("arrays or tables nested too deeply to parse") from None


def read_toml(path) -> dict:
    """The TOML file ``path`` as a dict: :func:`read_text` then :func:`parse_toml`."""
    return parse_toml(read_text(path, "text"))


#: a plausible column name: a letter, then letters, digits, spaces or ``_.()[]/^*%+-``
_NAME = re.compile(r"[^\W\d][\w .()\[\]/^*%+-]{0,79}")
#: how the allowed column names are described in messages
COLUMN_NAME_RULE = "a letter, then up to 79 letters, digits, spaces or _.()[]/^*%+-"


def column_names(header) -> str | None:
    """The cells of a CSV header row joined for an error message, or None when any cell is
    not a plausible column name (:data:`COLUMN_NAME_RULE`): a file that is not a table of
    the expected kind is then named, never quoted."""
    cells = [str(c).strip() for c in header]
    if not cells or len(cells) > 100 or not all(_NAME.fullmatch(c) for c in cells):
        return None
    return ", ".join(cells)


def numbered_csv(text: str, *, as_wide_as_header: bool = False):
    """``(line number, cells)`` of each row of the CSV ``text``, blank lines and comment
    lines (starting with ``#``) left out; the numbers are the file's line numbers (from 1),
    so that an error can name where a bad cell is without quoting it. Raises ``csv.Error``
    naming the line (a field over the csv module's limit of 131,072 characters).

    With ``as_wide_as_header`` every row must have as many cells as the first (the header):
    a table whose columns are found by their position in the header would otherwise read a
    row with an extra or a missing cell shifted (issue 35: a forcing row with one field more
    read its speeds as directions), so such a row raises ``csv.Error`` naming its line."""
    kept = [
        (number, line)
        for number, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    reader = csv.reader(line for _, line in kept)
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise csv.Error(f"line {kept[reader.line_num - 1][0]}: {exc}") from None
        number = kept[reader.line_num - 1][0]
        if as_wide_as_header:
            if reader.line_num == 1:
                width, header_line = len(row), number
            elif len(row) != width:
                raise csv.Error(
                    f"line {number} has {len(row)} fields but the header (line {header_line}) has "
                    f"{width}: every row needs one value per column (quote a value holding a comma)"
                )
        yield number, row
