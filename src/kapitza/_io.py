"""Atomic file output: write to a temporary file in the target folder, then rename.

An interrupted run (Ctrl-C, SIGTERM) never leaves a half-written file behind, nor its temporary
file. A new file gets the permissions a normal write would give (0666 less the umask); a file
overwritten keeps what a normal write keeps: its mode and owner are copied onto the temporary
file before the rename, and a file with other hard links (or one whose owner cannot be copied)
is rewritten in place once the new content is complete, so every link sees it (atomic for
readers only in the usual case of one link). A symlink is written through to its target; a
path that is a FIFO, a device or a directory is refused, never replaced.
"""
from __future__ import annotations

import csv
import errno
import io
import json
import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

__all__ = ["atomic_path", "write_text", "write_bytes", "write_json", "write_csv", "csv_text", "to_jsonable",
           "shown_path"]

#: Longest file name (bytes) most file systems allow.
NAME_MAX = 255


@contextmanager
def atomic_path(path, suffix=None):
    """Yield a temporary path beside ``path``; on success put its content at ``path``.

    The temporary name keeps ``path``'s suffix (or ``suffix``) so that writers that infer the
    format from the name (matplotlib, Pillow) still work; it is cut short where ``path``'s own
    name is near the 255-byte limit. Usually the temporary file is renamed onto ``path`` (with
    ``path``'s mode and owner when it exists); where ``path`` has other hard links, or its owner
    cannot be given to a new file, its content is replaced in place instead (as a plain
    ``open(path, "wb")`` would), after the temporary file is complete.
    """
    path = Path(path)
    if path.is_symlink():
        # write through a link to a regular file, as a plain open() would, not over the link itself
        path = Path(os.path.realpath(path))
    if path.exists() and not path.is_file():
        raise OSError(errno.EEXIST, "exists and is not a regular file (kapitza writes only regular files)",
                      str(path))
    suffix = suffix or path.suffix
    try:
        if path.parent.exists() and not path.parent.is_dir():
            raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), str(path.parent))
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=_temporary_prefix(path, suffix), suffix=suffix, dir=path.parent)
    except OSError as exc:
        raise _about(exc, path) from None
    os.close(fd)
    try:
        in_place = _take_attributes(tmp, path)
        yield Path(tmp)
        if in_place:
            with open(tmp, "rb") as src, open(path, "r+b") as dst:
                dst.truncate(0)
                shutil.copyfileobj(src, dst, 1 << 20)
            os.unlink(tmp)
        else:
            os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError) and exc.filename in (tmp, str(path.parent)):
            raise _about(exc, path) from None
        raise


def _temporary_prefix(path: Path, suffix: str) -> str:
    """``.STEM.``, the stem cut so that the temporary name (prefix, 8 random characters, suffix)
    stays within :data:`NAME_MAX` bytes: a valid name of 246-255 bytes is still written."""
    room = NAME_MAX - len(os.fsencode(suffix)) - 8 - 2
    stem = path.name[:len(path.name) - len(path.suffix)] if path.suffix else path.name
    while stem and len(os.fsencode(stem)) > room:  # by characters: no UTF-8 sequence cut in two
        stem = stem[:-1]
    return "." + stem + "."


def _take_attributes(tmp: str, path: Path) -> bool:
    """Give ``tmp`` what a normal write leaves ``path`` with; return True where ``path`` must be
    rewritten in place (other hard links to it, or an owner this process cannot give)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        # mkstemp creates 0600; a new file gets what a normal write would: 0666 less the umask
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        return False
    if st.st_nlink > 1:
        return True
    mine = os.stat(tmp)
    if (mine.st_uid, mine.st_gid) != (st.st_uid, st.st_gid):
        try:
            os.chown(tmp, st.st_uid, st.st_gid)
        except OSError:  # not ours to give (a group-writable file of another user)
            return True
    os.chmod(tmp, st.st_mode & 0o7777)
    return False


def _about(exc: OSError, path: Path) -> OSError:
    """The same error, naming the user's ``path`` rather than the temporary file beside it."""
    return type(exc)(exc.errno, exc.strerror or str(exc), str(path))


def shown_path(name) -> str:
    """A file name as one printable line: control characters escaped (``\\n``), bytes that are not
    UTF-8 shown as ``\\xff``."""
    text = os.fsdecode(name) if isinstance(name, bytes) else str(name)
    out = []
    for c in text:
        if 0xDC80 <= ord(c) <= 0xDCFF:  # a byte that is not UTF-8 (surrogateescape)
            out.append(f"\\x{ord(c) - 0xDC00:02x}")
        elif c.isprintable() or c == " ":
            out.append(c)
        else:
            out.append(repr(c)[1:-1])
    return "".join(out)


def write_bytes(path, data: bytes) -> Path:
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_text(path, text: str) -> Path:
    return write_bytes(path, text.encode("utf-8"))


def to_jsonable(obj):
    """Convert numpy scalars/arrays, complex numbers and non-finite floats for JSON."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return [to_jsonable(float(obj.real)), to_jsonable(float(obj.imag))]
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        if np.isnan(f):
            return None
        if np.isinf(f):
            return "inf" if f > 0 else "-inf"
        return f
    return obj


def write_json(path, obj) -> Path:
    return write_text(path, json.dumps(to_jsonable(obj), indent=2) + "\n")


def _cells(col, n):
    """One column as ``n`` strings: floats as ``repr`` (shortest round-trip), truth values as
    0/1, a single value (text or number) repeated."""
    arr = np.asarray(col)
    if arr.ndim == 0:
        v = arr.item()
        text = repr(float(v)) if isinstance(v, float) else str(int(v) if isinstance(v, bool) else v)
        return [_quoted(text)] * n
    if arr.shape != (n,):
        raise ValueError(f"every column must have {n} entries; got shape {arr.shape}")
    if arr.dtype.kind == "b":
        arr = arr.astype(np.int8)
    if arr.dtype.kind == "f":
        arr = arr.astype(float)
        fmt = float.__repr__
    elif arr.dtype.kind in "USO":
        def fmt(v):
            return _quoted(str(v))
    else:
        fmt = str
    # Grid axes and labels repeat: format each distinct value once and index.
    uniq, inv = np.unique(arr, return_inverse=True)
    if uniq.size <= n // 2:
        return np.array([fmt(v) for v in uniq.tolist()], dtype=object)[inv.ravel()].tolist()
    return list(map(fmt, arr.tolist()))


def _quoted(text):
    """A text cell as the csv module writes it (quoted where it holds a separator or quote)."""
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ',"\n\r') else text


def write_csv(path, header, rows=None, comments=(), *, columns=None) -> Path:
    """Write :func:`csv_text` to ``path``."""
    return write_text(path, csv_text(header, rows, comments, columns=columns))


def csv_text(header, rows=None, comments=(), *, columns=None) -> str:
    """``rows`` (iterable of sequences), or ``columns`` (equal-length 1-D arrays, or single
    values repeated down the column), under ``header`` as CSV text; ``comments`` become ``# `` lines.

    Floats are written as ``repr`` (the shortest text that reads back to the same double). The
    ``columns`` form formats each column with a few list operations rather than a call per
    cell: about a second per million rows of five columns, where the row form takes tens.
    """
    buf = io.StringIO()
    for c in comments:
        buf.write(f"# {c}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    if columns is not None:
        n = max((np.size(c) for c in columns if np.ndim(c) > 0), default=1)
        cells = [_cells(c, n) for c in columns]
        buf.write("\n".join(map(",".join, zip(*cells))))
        if n:
            buf.write("\n")
    else:
        for r in rows:
            w.writerow([repr(float(v)) if isinstance(v, (float, np.floating)) else v for v in r])
    return buf.getvalue()
