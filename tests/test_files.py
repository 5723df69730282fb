"""The one atomic write (mineburial.io.files): all or nothing, no temporary file left."""

import os
import stat

import pytest

from mineburial.io.files import TMP_PATTERN, atomic_path, atomic_write_text


def test_writes_and_leaves_no_temporary_file(tmp_path):
    path = tmp_path / "out.json"
    atomic_write_text(path, "first")
    atomic_write_text(path, "second")
    assert path.read_text() == "second"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]


def test_an_error_keeps_the_previous_file_and_removes_the_temporary(tmp_path):
    path = tmp_path / "out.nc"
    path.write_text("previous")
    with pytest.raises(RuntimeError, match="killed"):
        with atomic_path(path) as tmp:
            tmp.write_text("half")
            assert tmp.parent == tmp_path and tmp.match(TMP_PATTERN)
            raise RuntimeError("killed")
    assert path.read_text() == "previous"
    assert list(tmp_path.glob(TMP_PATTERN)) == []


def test_permissions_follow_the_umask(tmp_path):
    old = os.umask(0o027)
    try:
        path = atomic_write_text(tmp_path / "f.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~0o027
