"""Every example in the README and in ``docs/*.md`` runs as written.

Python blocks (```` ```python ````) run top to bottom, one namespace per page, in a scratch folder; the
convention of ``tests/test_readme.py`` holds: a comment after an expression statement is the output a
user sees (the printed text for ``print(...)``, else the ``repr``), ``...`` standing for any
continuation; a comment beginning with ``prints`` describes the output; comments after assignments
describe the line. The README's Python blocks are run by ``tests/test_readme.py`` and the shrunken sweep
example of ``docs/sweeps.md`` there too; blocks that set up a cluster (``dask_jobqueue``,
``dask_kubernetes``) need a cluster and are only compiled.

Command lines (``kapitza ...`` in text and bash blocks of the pages and of the tutorials' Markdown cells,
and in inline code spans of those and of the gallery's scripts and the API pages) must be accepted by the
real parser, and those that answer at once and write nothing (``stability``, ``periods``, ``nonlinear``,
``simulate`` without ``--out``) are run through the real entry point and must succeed. The slow test at
the end runs every one of them as written, in a scratch folder, except the few listed in ``NOT_RUN`` with
the reason (``pytest -m slow tests/test_docs_examples.py``), and checks the files and outputs the pages
say they give.
"""
from __future__ import annotations

import ast
import contextlib
import io
import json
import os
import re
import shlex
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = sorted((ROOT / "docs").glob("*.md"))
PAGES = [ROOT / "README.md", *DOCS]
#: The tutorials: their Markdown cells show command lines too.
NOTEBOOKS = sorted((ROOT / "docs" / "tutorials").glob("*.ipynb"))

#: Blocks that need a cluster to run: compiled, not run.
CLUSTER = ("dask_jobqueue", "dask_kubernetes")
#: Command lines run to completion: quick, and writing nothing.
RUN_COMMANDS = {"stability", "periods", "nonlinear", "simulate"}


def _text(path):
    """The Markdown of ``path``: the file itself, or a notebook's Markdown cells one after another."""
    if path.suffix != ".ipynb":
        return path.read_text()
    cells = json.loads(path.read_text())["cells"]
    return "\n".join("".join(c["source"]) + "\n" for c in cells if c["cell_type"] == "markdown")


def _blocks(path, langs):
    """(language, code) of each fenced block of ``path`` whose language is in ``langs``."""
    blocks, lang, lines = [], None, []
    for line in _text(path).splitlines():
        if line.startswith("```"):
            if lang is None:  # an opening fence: its info string is the language (or a MyST directive)
                lang, lines = line[3:].strip(), []
            else:
                blocks.append((lang, "\n".join(lines) + "\n"))
                lang = None
        elif lang is not None:
            lines.append(line)
    return [(lang, code) for lang, code in blocks if lang in langs]


def _comments(code):
    out = {}
    for tok in tokenize.generate_tokens(io.StringIO(code).readline):
        if tok.type == tokenize.COMMENT:
            out[tok.start[0]] = tok.string[1:].strip()
    return out


def _matches(expected, got):
    pattern = ".*".join(re.escape(part) for part in expected.split("..."))
    return re.fullmatch(pattern, got, flags=re.S) is not None


def _python_pages():
    return [p for p in DOCS if _blocks(p, {"python"})]


def _run_page(path):
    """Run every Python block of ``path``; return [(expected, got)] for the output comments."""
    ns = {"__name__": "__main__"}
    pairs = []
    blocks = [code for _, code in _blocks(path, {"python"})]
    if path.name == "sweeps.md":
        blocks = blocks[1:]  # the first runs, shrunk, in tests/test_readme.py
    for code in blocks:
        if any(name in code for name in CLUSTER):
            compile(code, str(path), "exec")
            continue
        comments = _comments(code)
        for stmt in ast.parse(code).body:
            out = io.StringIO()
            is_expr = isinstance(stmt, ast.Expr)
            is_print = is_expr and isinstance(stmt.value, ast.Call) and getattr(stmt.value.func, "id", "") == "print"
            with contextlib.redirect_stdout(out):
                if is_expr and not is_print:
                    value = eval(compile(ast.Expression(stmt.value), str(path), "eval"), ns)
                else:
                    exec(compile(ast.Module([stmt], type_ignores=[]), str(path), "exec"), ns)
            comment = comments.get(stmt.end_lineno)
            if not is_expr or comment is None or comment.startswith("prints"):
                continue
            got = out.getvalue().rstrip("\n") if is_print else repr(value)
            pairs.append((comment, got))
    return pairs


@pytest.mark.parametrize("path", _python_pages(), ids=lambda p: p.name)
def test_docs_python_examples_run_and_print_what_their_comments_say(path, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    try:
        pairs = _run_page(path)
    finally:
        import matplotlib.pyplot as plt

        plt.close("all")
    wrong = [(want, got) for want, got in pairs if not _matches(want, got)]
    assert not wrong, wrong


def test_the_pages_with_examples_are_found():
    names = {p.name for p in _python_pages()}
    assert {"getting-started.md", "motion.md", "figures.md"} <= names


#: Pages whose inline code spans (`...` in Markdown, ``...`` in reStructuredText and docstrings) show command
#: lines too: the gallery's scripts and the API pages besides the pages and tutorials.
INLINE_PAGES = [*PAGES, *NOTEBOOKS, *sorted((ROOT / "docs" / "gallery_src").glob("*.*")),
                *sorted((ROOT / "docs" / "api").glob("*.rst"))]


def _page_name(path):
    return path.name if path.parent in {ROOT, ROOT / "docs"} else f"{path.parent.name}/{path.name}"


def _inline_command_lines(path):
    """``kapitza COMMAND`` with options in an inline code span of ``path``. A span with a single word after
    the command (`kapitza chart --chain`, `kapitza simulate --json`) names an option in prose, one with
    ``...`` elides part of a line: neither is a command line."""
    lines = []
    for span in re.findall(r"(?<!`)``?(kapitza [^`\n]+?)``?(?!`)", _text(path)):
        words = shlex.split(span)[1:]
        if len(words) >= 3 and "..." not in words:
            lines.append((_page_name(path), words))
    return lines


def _command_lines():
    """Every ``kapitza ...`` line of a text, bash or unmarked block, continuation lines joined, then every
    command line of an inline code span."""
    lines = []
    for path in [*PAGES, *NOTEBOOKS]:
        name = _page_name(path)
        for _, code in _blocks(path, {"", "text", "bash", "sh", "console"}):
            code = code.replace("\\\n", " ")
            for line in code.splitlines():
                lex = shlex.shlex(line, posix=True, punctuation_chars=True)
                lex.whitespace_split = True
                try:
                    tokens = [*lex, ";"]
                except ValueError:  # not a shell line (a file tree, prose with an apostrophe)
                    assert "kapitza " not in line.split("#")[0].lstrip()[:9], (path.name, line)
                    continue
                words = []
                for token in tokens:
                    if token not in {"&&", "||", ";", "|", "(", ")", ">", "<", ">>"}:
                        words.append(token)
                        continue
                    if words[:1] == [".venv/bin/kapitza"]:
                        words[0] = "kapitza"
                    if words[:1] == ["kapitza"] and len(words) > 1:
                        lines.append((name, words[1:]))
                    words = []
    for path in INLINE_PAGES:
        lines += _inline_command_lines(path)
    return lines


def test_command_lines_are_found():
    commands = {words[0] for _, words in _command_lines()}
    assert {"stability", "periods", "chart", "simulate", "basin", "nonlinear", "sweep", "paper", "serve"} <= commands


@pytest.mark.parametrize("page,words", _command_lines(), ids=lambda v: v if isinstance(v, str) else " ".join(v))
def test_docs_command_lines_are_accepted_and_quick_ones_succeed(page, words, tmp_path, monkeypatch, capsys):
    from kapitza.cli import build_parser, main

    try:
        args = build_parser().parse_args(words)
    except SystemExit as exc:  # argparse refused the line: the page shows a command that does not exist
        pytest.fail(f"{page}: 'kapitza {' '.join(words)}' is refused by the parser (exit {exc.code}): "
                    f"{capsys.readouterr().err.strip()}")
    assert getattr(args, "func", None) is not None
    # the damped sine's report takes tens of seconds today: parsed here, run by tests/test_readme.py's rig example
    slow = "sine" in words and "--damping" in words
    if words[0] in RUN_COMMANDS and not {"--chart", "--rotation", "--out"} & set(words) and not slow:
        monkeypatch.chdir(tmp_path)
        code = main(words)
        out = capsys.readouterr()
        assert code == 0 or ("--check" in words and code == 1), (code, out.err)
        assert out.out.strip()


# --- Every command line runs (slow) -------------------------------------------------------------------

#: Command lines shown in the docs that the slow tests below do not run, and why. Each is still parsed
#: by the test above. (``kapitza serve`` runs until stopped: it is run as written in its own process, asked
#: for its page, and stopped with Ctrl-C; the paper lines run in full, which takes seconds.)
NOT_RUN = {
    # sends the work to a Dask scheduler at a placeholder address of a cluster
    ("sweep", "--eps", "0.05", "3", "--mu", "0.02", "0.98", "--resolution", "512", "--periods", "1000",
     "--chunk", "32", "--scheduler", "tcp://10.0.0.5:8786", "--out", "map.zarr", "--netcdf", "map.nc"):
        "needs the cluster's Dask scheduler",
}
#: Options naming a file (or a name the files written take) that a command must write.
OUT_OPTIONS = ("--out", "--animate", "--simulate", "--netcdf")
#: What the pages say the paper writes into its folder (docs/paper.md's table, the README).
PAPER_FILES = [f"figure{n}{ext}" for n in range(1, 9) for ext in (".png", ".svg", ".json", ".csv")] + [
    "checks.json", "periods.csv", "report.html", "report.md"]
#: What the pages quote of a command's output (a regular expression searched in what it prints).
DOCUMENTED_OUTPUT = {
    # README: "the second recomputes only the chunks not yet finished and says how many
    # (`computed K of 20 chunks (M already done)`)"
    ("sweep", "--eps", "0.05", "1.6", "--mu", "0.02", "0.9", "--resolution", "40", "30", "--periods", "200",
     "--out", "small.zarr", "--resume"): r"computed \d+ of 20 chunks \(\d+ already done\)",
}

#: Whether the tower falls, as the comments beside docs/tower.md's lines say ("# stands", "# falls"): the
#: ``motion.toppled`` of the JSON printed (--json) or written (OUT.json).
DOCUMENTED_TOPPLED = {
    ("simulate", "--chain", "0.2,0.2,0.2", "--frequency", "150", "--stroke", "0.008", "--theta0", "0.1",
     "--out", "run"): False,
    ("simulate", "--chain", "0.2,0.2", "--T", "0.025", "--A", "128", "--along-mode", "--theta0", "0.2",
     "--json"): True,
}


def _documented_files(argv):
    """The files the pages say ``kapitza *argv`` writes: by the comments beside the lines (``PNG, SVG, CSV``,
    ``tower.png/.svg/.csv/.json``) and the lists of docs/motion.md, docs/tower.md, docs/nonlinear.md and
    docs/paper.md. A name given to an option is written in any case (checked by the caller)."""
    opts = {w: argv[i + 1] for i, w in enumerate(argv[:-1]) if w.startswith("--")}
    command, chain, out = argv[0], "--chain" in argv, opts.get("--out")
    files = []
    if command == "paper":
        files += [f"{out}/{name}" for name in PAPER_FILES]
    elif out is None:
        pass
    elif command == "simulate" and chain:
        files += [f"{out}{end}" for end in (".csv", ".json", "-series.png", "-series.svg")]
    elif command == "simulate":
        files += [f"{out}{end}" for end in (".csv", "-strobe.csv", ".json", "-series.png", "-series.svg",
                                            "-phase.png", "-phase.svg", "-strobe.png", "-strobe.svg")]
    elif command == "basin":
        files += [f"{out}{end}" for end in (".png", ".svg", ".csv", ".json")]
    elif command == "chart" or (command == "nonlinear" and "--chart" in argv):
        ends = (".png", ".svg", ".csv") + ((".json",) if chain or command == "nonlinear" else ())
        files += [f"{out}{end}" for end in ends]
    elif command == "tower" and "--no-chart" not in argv:
        files += [f"{out}{end}" for end in (".png", ".svg", ".csv", ".json")]
    elif command == "sweep":
        stem = out.removesuffix(".zarr")
        files += [out, f"{stem}.png", f"{stem}.svg"]
    if command == "tower" and "--simulate" in opts:  # the motion as data (its help): the figures are simulate's
        files.append(f"{opts['--simulate']}.csv")
    return files


def _runnable_command_lines():
    """Each distinct command line not in ``NOT_RUN``, with the pages that show it."""
    pages = {}
    for page, words in _command_lines():
        pages.setdefault(tuple(words), []).append(page)
    return [(",".join(dict.fromkeys(p)), list(w)) for w, p in pages.items() if w not in NOT_RUN]


def _in_process_lines():
    """The lines run through ``kapitza.cli.main``: all but ``serve``, which runs until stopped and so gets
    its own process (``test_docs_serve_lines_serve_the_page_until_stopped``)."""
    return [(page, words) for page, words in _runnable_command_lines() if words[0] != "serve"]


def test_the_lines_not_run_are_shown_in_the_docs():
    shown = {tuple(words) for _, words in _command_lines()}
    assert set(NOT_RUN) <= shown, set(NOT_RUN) - shown
    assert set(DOCUMENTED_OUTPUT) | set(DOCUMENTED_TOPPLED) <= shown


def _in_scratch(words, scratch):
    """The line with an absolute path under /tmp (``--out /tmp/p``) moved into the scratch folder."""
    return [str(scratch / Path(w).relative_to("/tmp")) if w.startswith("/tmp/") else w for w in words]


@pytest.fixture(scope="module")
def command_times():
    """Seconds per line run so far: each line prints its time and the running count and total."""
    return []


@pytest.mark.slow
@pytest.mark.parametrize("page,words", _in_process_lines(), ids=lambda v: v if isinstance(v, str) else " ".join(v))
def test_docs_command_lines_run_as_written(page, words, tmp_path, monkeypatch, capsys, command_times):
    """The line runs through the real entry point in a scratch folder, exits 0 (1 allowed for --check, as
    documented) and writes the files it names."""
    pytest.importorskip("matplotlib")
    import time

    import matplotlib

    matplotlib.use("Agg")
    from kapitza.cli import main

    monkeypatch.chdir(tmp_path)
    argv = _in_scratch(words, tmp_path)
    start = time.perf_counter()
    try:
        code = main(argv)
    finally:
        import matplotlib.pyplot as plt

        plt.close("all")
    seconds = time.perf_counter() - start
    command_times.append(seconds)
    out = capsys.readouterr()
    with capsys.disabled():
        print(f"\n[{seconds:6.1f} s; {len(command_times)} lines, {sum(command_times):6.1f} s in all] "
              f"{page}: kapitza {' '.join(words)}")
    assert code == 0 or ("--check" in words and code == 1), (code, out.err)
    named = [argv[i + 1] for i, w in enumerate(argv[:-1]) if w in OUT_OPTIONS]
    from kapitza.figures.animation import ffmpeg_available

    if not ffmpeg_available():  # "MP4 if ffmpeg is installed": else the GIF beside it
        named = [n.removesuffix(".mp4") + ".gif" if n.endswith(".mp4") else n for n in named]
    for name in named:
        path = Path(name) if os.path.isabs(name) else tmp_path / name
        written = [p for p in path.parent.glob(f"{path.name}*") if p.is_dir() or p.stat().st_size > 0]
        assert written, f"kapitza {' '.join(words)} wrote nothing named {name}: {sorted(os.listdir(path.parent))}"
    missing = [name for name in _documented_files(argv) if not (tmp_path / name).exists()]
    assert not missing, f"kapitza {' '.join(words)} did not write {missing}: {sorted(os.listdir(tmp_path))}"
    if not named:
        assert out.out.strip(), f"kapitza {' '.join(words)} printed nothing"
    if tuple(words) in DOCUMENTED_TOPPLED:
        stem = None if "--json" in words else argv[argv.index("--out") + 1]
        summary = json.loads(out.out if stem is None else (tmp_path / f"{stem}.json").read_text())
        assert summary["motion"]["toppled"] is DOCUMENTED_TOPPLED[tuple(words)], summary["motion"]
    if tuple(words) in DOCUMENTED_OUTPUT:
        assert re.search(DOCUMENTED_OUTPUT[tuple(words)], out.out + out.err), (out.out, out.err)


@pytest.mark.slow
@pytest.mark.parametrize("page,words", [(p, w) for p, w in _runnable_command_lines() if w[0] == "serve"],
                         ids=lambda v: v if isinstance(v, str) else " ".join(v))
def test_docs_serve_lines_serve_the_page_until_stopped(page, words, tmp_path):
    """``kapitza serve`` as written, in its own process: it prints its address (a free port), serves the
    page there, and Ctrl-C stops it quietly."""
    pytest.importorskip("fastapi")
    import signal
    import subprocess
    import sys
    import urllib.request

    proc = subprocess.Popen([sys.executable, "-m", "kapitza", *words], cwd=tmp_path, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=dict(os.environ, PYTHONUNBUFFERED="1"))
    try:
        line = proc.stdout.readline()
        url = re.search(r"http://\S+/", line)
        assert url, (line, proc.poll())
        page_text = None
        for _ in range(600):  # the workers start under any load: up to a minute
            try:
                with urllib.request.urlopen(url.group(0), timeout=10) as r:
                    page_text = r.read().decode()
                break
            except OSError:
                if proc.poll() is not None:
                    break
                import time

                time.sleep(0.1)
        assert page_text and "kapitza" in page_text.lower(), (line, proc.poll())
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(60)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        err = proc.stderr.read()
        proc.stdout.close()
        proc.stderr.close()
    assert proc.returncode in (0, 130), (proc.returncode, err)
    assert "Traceback" not in err, err


def test_the_readme_sweep_says_how_many_chunks_the_command_makes():
    """The README's resumable sweep quotes its chunk count; the default chunk gives that many (quick: no
    sweep is run; the slow test above runs the line)."""
    from kapitza.cli.sweep import default_chunk

    text = (ROOT / "README.md").read_text()
    quoted = int(re.search(r"computed K of (\d+) chunks", text).group(1))
    (_, words), = [(p, w) for p, w in _command_lines() if w[0] == "sweep" and "--resume" in w]
    nx, ny = (int(v) for v in words[words.index("--resolution") + 1:][:2])
    side = default_chunk(nx, ny)
    assert -(-nx // side) * -(-ny // side) == quoted
