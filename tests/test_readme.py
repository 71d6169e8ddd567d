"""The README's Python examples run as written, and say what they print."""
import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parent.parent / "README.md"


def test_readme_python_blocks_run():
    text = README.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    ns = {}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        for b in blocks:
            exec(compile(b, str(README), "exec"), ns)
    printed = out.getvalue()
    # the rig example's comments say what it prints
    assert "stable (zone 0), motions decay 0.356" in printed
    assert "uniform rod of length 0.2 m (equivalent length l = 0.133333 m)" in printed
