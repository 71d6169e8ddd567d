"""Output files: permissions of a normal write, symlinks written through, special files refused."""
import os
import stat

import pytest

from kapitza import _io
from cli_util import assert_one_line_error, run


def test_permissions_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        p = _io.write_text(tmp_path / "a.txt", "x")
        assert stat.S_IMODE(os.stat(p).st_mode) == 0o644
        os.umask(0o077)
        p = _io.write_text(tmp_path / "b.txt", "x")
        assert stat.S_IMODE(os.stat(p).st_mode) == 0o600
    finally:
        os.umask(old)


def test_symlink_is_written_through(tmp_path):
    target = tmp_path / "real.csv"
    target.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    _io.write_text(link, "new")
    assert link.is_symlink() and target.read_text() == "new"


def test_fifo_is_refused_not_replaced(tmp_path, capsys):
    fifo = tmp_path / "f.csv"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="not a regular file"):
        _io.write_text(fifo, "x")
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    code, _, err = run(["periods", "--A", "100", "--csv", str(fifo)], capsys)
    assert_one_line_error(code, err, str(fifo))
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
