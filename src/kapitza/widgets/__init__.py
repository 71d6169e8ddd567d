"""The explorer inside a notebook: :class:`Explorer`, the stability chart and the moving pendulum in a
Jupyter cell, computed in the kernel (no server), linked to Python.

Needs the ``widgets`` extra (``pip install 'kapitza[widgets]'``: anywidget, and the web layer whose
answers it shares). See ``docs/explorer.md``.
"""
from __future__ import annotations

try:
    import anywidget  # noqa: F401
    import fastapi  # noqa: F401
    import orjson  # noqa: F401
except ImportError as exc:  # pragma: no cover - the test environment has the extra
    raise ImportError(f"kapitza.widgets needs the 'widgets' extra ({exc.name} is missing): "
                      f"pip install 'kapitza[widgets]'") from None

from ._explorer import Explorer, answer

__all__ = ["Explorer", "answer"]
