"""The README's Python examples run as written, and print what their comments say.

In the README's ``python`` blocks a comment after an expression statement is the output a user
sees: for ``print(...)`` the printed text, for a bare expression its ``repr`` (as the interactive
prompt shows it). ``...`` in such a comment stands for any continuation (as in doctest). A comment
that begins with ``prints`` describes the output instead of quoting it; comments after
assignments describe the line.
"""
import ast
import contextlib
import functools
import io
import re
import tokenize
from pathlib import Path

README = Path(__file__).resolve().parent.parent / "README.md"


def _comments(code):
    """Line number -> the text of the comment on that line."""
    out = {}
    for tok in tokenize.generate_tokens(io.StringIO(code).readline):
        if tok.type == tokenize.COMMENT:
            out[tok.start[0]] = tok.string[1:].strip()
    return out


def _matches(expected, got):
    pattern = ".*".join(re.escape(part) for part in expected.split("..."))
    return re.fullmatch(pattern, got, flags=re.S) is not None


@functools.lru_cache(maxsize=1)
def _checked_statements():
    """(expected, printed or repr) for every expression statement with an output comment."""
    text = README.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    ns = {}
    pairs, described = [], []
    for block in blocks:
        comments = _comments(block)
        for stmt in ast.parse(block).body:
            code = compile(ast.Module([stmt], type_ignores=[]), str(README), "exec")
            out = io.StringIO()
            is_expr = isinstance(stmt, ast.Expr)
            is_print = is_expr and isinstance(stmt.value, ast.Call) and getattr(stmt.value.func, "id", "") == "print"
            with contextlib.redirect_stdout(out):
                if is_expr and not is_print:
                    value = eval(compile(ast.Expression(stmt.value), str(README), "eval"), ns)
                else:
                    exec(code, ns)
            comment = comments.get(stmt.end_lineno)
            if not is_expr or comment is None:
                continue
            got = out.getvalue().rstrip("\n") if is_print else repr(value)
            if comment.startswith("prints"):
                described.append(got)
            else:
                pairs.append((comment, got))
    return pairs, described


def test_readme_python_blocks_print_what_their_comments_say():
    pairs, described = _checked_statements()
    assert len(pairs) >= 5
    wrong = [(want, got) for want, got in pairs if not _matches(want, got)]
    assert not wrong, wrong
    assert described and all(d.strip() for d in described)


def test_readme_rig_example_names_the_pendulum():
    pairs, described = _checked_statements()
    assert any("uniform rod of length 0.2 m (equivalent length l = 0.133333 m)" in d for d in described)


SWEEPS_DOC = README.parent / "docs" / "sweeps.md"


def test_sweeps_doc_python_example_runs(tmp_path, monkeypatch):
    """docs/sweeps.md's Python example runs as written, on a tiny grid (local Dask cluster, store, xarray,
    plot)."""
    import pytest

    for module in ("distributed", "zarr", "xarray", "tqdm", "matplotlib"):
        pytest.importorskip(module)
    import matplotlib

    matplotlib.use("Agg")
    block = re.findall(r"```python\n(.*?)```", SWEEPS_DOC.read_text(), flags=re.S)[0]
    tiny = block.replace("(40, 30), periods=200", "(3, 2), periods=5")
    assert tiny != block  # the example still has the size this test shrinks
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(tiny, str(SWEEPS_DOC), "exec"), {})
    assert "of 1 chunks computed" in out.getvalue()
    assert (tmp_path / "small.zarr").is_dir()
