"""Generic engines: the stability data of any drive from its acceleration shape alone.

- :mod:`.magnus` — one period of ``phi'' = 8 eps^2 (mu^2 + s(tau)) phi`` as a sixth-order
  Magnus product on a grid aligned with the shape's breakpoints, in a balanced tree that carries
  the logarithmic scale (no overflow) and the Pruefer rotation angle (the exact zone index);
- :mod:`.edges` — zone edges bracketed by the rotation angle and solved on ``|tr M / 2| = 1``.

The engines know nothing of drives: they take the shape as a function of ``tau`` and its
breakpoints. :class:`kapitza.Drive` builds its default methods on them (``docs/drives.md``,
"The drive contract").
"""
from .edges import zone_edges
from .magnus import Engine, load_compiled

__all__ = ["Engine", "load_compiled", "zone_edges"]
