"""Output files: permissions of a normal write, symlinks written through, special files refused."""
import os
import signal
import stat
import subprocess
import sys

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


# ------------------------------------------------------------------ overwriting keeps what a normal write keeps
def test_overwrite_keeps_the_mode_of_the_file(tmp_path, capsys):
    # a private 0600 file became world-readable 0644 (the new inode took the umask's mode)
    old = os.umask(0o022)
    try:
        p = tmp_path / "private.csv"
        p.write_text("old")
        os.chmod(p, 0o600)
        _io.write_text(p, "new")
        assert stat.S_IMODE(os.stat(p).st_mode) == 0o600 and p.read_text() == "new"
        os.chmod(p, 0o640)
        code, _, err = run(["periods", "--A", "100", "--csv", str(p)], capsys)
        assert code == 0, err
        assert stat.S_IMODE(os.stat(p).st_mode) == 0o640 and "\nname," in p.read_text()
    finally:
        os.umask(old)


@pytest.mark.skipif(os.geteuid() != 0, reason="giving a file to another user needs root")
def test_overwrite_keeps_the_owner_of_the_file(tmp_path):
    p = tmp_path / "theirs.csv"
    p.write_text("old")
    os.chown(p, 4321, 4322)
    _io.write_text(p, "new")
    st = os.stat(p)
    assert (st.st_uid, st.st_gid) == (4321, 4322) and p.read_text() == "new"


def test_an_owner_that_cannot_be_given_is_kept_by_writing_in_place(tmp_path, monkeypatch):
    # a group-writable file of another user: chown of the new file is refused, so the file itself
    # is rewritten (its inode, owner and mode stay)
    p = tmp_path / "shared.csv"
    p.write_text("old content, longer than the new one")
    inode = os.stat(p).st_ino
    real = os.stat

    class Other:
        def __init__(self, st):
            self._st = st

        def __getattr__(self, name):
            return getattr(self._st, name)

        st_uid = 4321

    monkeypatch.setattr(_io.os, "stat", lambda f, *a, **k: Other(real(f)) if str(f) == str(p) else real(f, *a, **k))

    def refuse(*args):
        raise PermissionError(1, "Operation not permitted")

    monkeypatch.setattr(_io.os, "chown", refuse)
    _io.write_text(p, "new")
    monkeypatch.undo()
    assert os.stat(p).st_ino == inode and p.read_text() == "new"
    assert [q.name for q in tmp_path.iterdir()] == ["shared.csv"]


def test_overwrite_keeps_hard_links(tmp_path):
    # the rename cut the link: the other name kept the old content
    p = tmp_path / "data.csv"
    p.write_text("old")
    os.chmod(p, 0o604)
    other = tmp_path / "also.csv"
    os.link(p, other)
    _io.write_text(p, "new content")
    assert p.read_text() == other.read_text() == "new content"
    assert os.stat(p).st_ino == os.stat(other).st_ino and os.stat(p).st_nlink == 2
    assert stat.S_IMODE(os.stat(p).st_mode) == 0o604
    assert sorted(q.name for q in tmp_path.iterdir()) == ["also.csv", "data.csv"]


# ------------------------------------------------------------------ awkward names
def test_unwritable_path_with_a_newline_is_one_line(tmp_path, capsys):
    parent = tmp_path / "a-file"
    parent.write_text("")
    target = str(parent / "two\nlines.csv")
    code, _, err = run(["periods", "--A", "100", "--csv", target], capsys)
    assert_one_line_error(code, err, "two\\nlines.csv", "Not a directory")


def test_a_name_that_is_not_utf8_is_shown_clearly(tmp_path, capsys):
    parent = tmp_path / "a-file"
    parent.write_text("")
    target = os.fsdecode(os.fsencode(str(parent)) + b"/caf\xe9.csv")  # Latin-1, not UTF-8
    code, _, err = run(["periods", "--A", "100", "--csv", target], capsys)
    assert_one_line_error(code, err, "caf\\xe9.csv", "not valid UTF-8")
    assert "\\udc" not in err
    # where it can be written, it is, under exactly those bytes
    ok = os.fsdecode(os.fsencode(str(tmp_path)) + b"/caf\xe9.csv")
    code, _, err = run(["periods", "--A", "100", "--csv", ok], capsys)
    assert code == 0 and (os.fsencode(str(tmp_path)) + b"/caf\xe9.csv") in [os.fsencode(str(q)) for q in
                                                                           tmp_path.iterdir()]


@pytest.mark.parametrize("name", ["a" * 251 + ".csv", "a" * 246 + ".csv", "é" * 125 + ".csv", "b" * 255])
def test_names_up_to_255_bytes_are_written(tmp_path, capsys, name):
    # the temporary name (".STEM." + 8 characters + suffix) passed the limit: "File name too long"
    assert len(name.encode()) <= 255
    p = tmp_path / name
    code, _, err = run(["periods", "--A", "100", "--csv", str(p)], capsys)
    assert code == 0, err
    assert "\nname," in p.read_text() and [q.name for q in tmp_path.iterdir()] == [name]
    _io.write_text(p, "again")
    assert p.read_text() == "again"


# ------------------------------------------------------------------ SIGTERM during a write
_WRITER = r"""
import pathlib, sys, time
sys.argv = ["kapitza", "periods", "--A", "100", "--csv", sys.argv[1]]
import kapitza  # the command's signal handlers: sys.argv[0] is kapitza
from kapitza.cli import main

def slow(self, data):
    with open(self, "wb") as f:
        f.write(data[: len(data) // 2])
    print("writing", flush=True)
    # short sleeps, not one long one: a signal the kernel hands to another of the process's threads
    # (numpy's) runs its handler only when the main thread next checks, after the sleep it is in
    for _ in range(6000):
        time.sleep(0.1)

pathlib.Path.write_bytes = slow
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize("existing", [False, True])
@pytest.mark.parametrize("sig, code, line", [(signal.SIGTERM, 143, "kapitza: terminated"),
                                             (signal.SIGINT, 130, "kapitza: interrupted")])
def test_a_signal_during_a_write_leaves_no_partial_file(tmp_path, sig, code, line, existing):
    # SIGTERM (a CI timeout, systemctl stop) left the temporary file behind; only SIGINT cleaned up
    out = tmp_path / "periods.csv"
    if existing:
        out.write_text("the old table\n")
    with subprocess.Popen([sys.executable, "-c", _WRITER, str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True) as p:
        assert p.stdout.readline().strip() == "writing"  # the temporary file is half written
        assert any(q.name.startswith(".periods.") for q in tmp_path.iterdir())
        p.send_signal(sig)
        err = p.stderr.read()
        status = p.wait(timeout=120)
    assert status == code and err.strip().splitlines() == [line], (status, err)
    assert [q.name for q in tmp_path.iterdir()] == (["periods.csv"] if existing else [])
    if existing:
        assert out.read_text() == "the old table\n"
