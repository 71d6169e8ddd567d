"""Saving a figure in several formats: the layout run once by the PNG's renderer, the ticks and
titles then fixed -- the same files as matplotlib writes by itself, and a failure reported as the
error it was."""
import os
import re

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from kapitza.figures import _style  # noqa: E402
from kapitza.figures.chart import chart_figure  # noqa: E402


def _chart(**kw):
    return chart_figure(points=150, **kw)[0]


def _svg(path):
    return re.sub(r"<dc:date>.*?</dc:date>", "", path.read_text())


@pytest.mark.parametrize("kw", [{}, {"plane": "physical", "l": 0.5}])
def test_saved_files_are_those_written_one_after_the_other(tmp_path, monkeypatch, kw):
    import matplotlib.pyplot as plt

    monkeypatch.setitem(matplotlib.rcParams, "svg.hashsalt", "test")
    monkeypatch.setattr(_style, "_LEGACY", True)
    fig = _chart(**kw)
    old = _style.save(fig, tmp_path / "old", ("png", "svg", "pdf"))
    plt.close(fig)
    monkeypatch.setattr(_style, "_LEGACY", False)
    fig = _chart(**kw)
    new = _style.save(fig, tmp_path / "new", ("png", "svg", "pdf"))
    # the ticks were fixed at what the layout settled: every axis of the chart has them
    assert any(isinstance(ax.xaxis.get_major_locator(), matplotlib.ticker.FixedLocator) for ax in fig.axes)
    plt.close(fig)
    assert [p.name for p in new] == ["new.png", "new.svg", "new.pdf"] and all(p.is_file() for p in new)
    a, b = (np.asarray(Image.open(p)) for p in (old[0], new[0]))
    assert a.shape == b.shape and np.array_equal(a, b)
    assert _svg(old[1]) == _svg(new[1])
    pdf = [re.sub(rb"/CreationDate \(.*?\)", b"", p.read_bytes()) for p in (old[2], new[2])]
    assert pdf[0] == pdf[1]
    # nothing half-written is left beside them
    assert sorted(os.listdir(tmp_path)) == sorted(p.name for p in old + new)


def test_a_format_that_cannot_be_written_is_raised_with_its_message(tmp_path):
    import matplotlib.pyplot as plt

    (tmp_path / "x.svg").mkdir()  # only the SVG cannot be written
    fig = _chart()
    with pytest.raises(OSError, match=r"not a regular file.*x\.svg"):
        _style.save(fig, tmp_path / "x")
    plt.close(fig)
    assert (tmp_path / "x.png").is_file()  # the PNG first
    assert sorted(os.listdir(tmp_path)) == ["x.png", "x.svg"]  # and no temporary file left
