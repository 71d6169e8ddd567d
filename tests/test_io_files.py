"""Output files: permissions of a normal write, symlinks written through, special files refused."""
import os
import stat

import numpy as np

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


def test_csv_columns_write_the_same_text_as_rows(tmp_path):
    from kapitza import _io

    rng = np.random.default_rng(3)
    n = 500
    cols = [np.array(["linear", "a,b", 'say "x"', "nonlinear"] * (n // 4)), rng.normal(size=n) * 10.0 ** rng.integers(-300, 300, n),
            np.repeat(np.linspace(-0.5, 0.5, n // 10), 10), rng.integers(-5, 50, n), rng.random(n) < 0.5]
    rows = [[c[i].item() if isinstance(c[i], np.generic) else c[i] for c in cols] for i in range(n)]
    rows = [[int(v) if isinstance(v, bool) else v for v in r] for r in rows]
    a = _io.write_csv(tmp_path / "rows.csv", ["m", "x", "y", "k", "ok"], rows, comments=["c"])
    b = _io.write_csv(tmp_path / "cols.csv", ["m", "x", "y", "k", "ok"], columns=cols, comments=["c"])
    assert a.read_bytes() == b.read_bytes()
    import csv

    back = list(csv.reader(b.read_text().splitlines()[2:]))
    assert [r[0] for r in back] == cols[0].tolist()  # text with separators and quotes survives
    assert np.array_equal([float(r[1]) for r in back], cols[1])  # floats read back to the same doubles
    # a single value fills its column
    c = _io.write_csv(tmp_path / "one.csv", ["m", "x"], columns=["linear", np.arange(3.0)])
    assert c.read_text() == "m,x\nlinear,0.0\nlinear,1.0\nlinear,2.0\n"
