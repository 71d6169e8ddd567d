"""The shape of the package: imports point one way, and no module reaches into another's private names.

The import graph of ``src/kapitza`` counts imports inside functions too (a cycle hidden in a
function is still a cycle): it must have no cycle. A private name (``_x``) of one public module
imported by another is a coupling the names do not show; none is allowed. What is shared is made
public, or lives in a private *module* (``kapitza._square``, ``kapitza.drives._api``,
``kapitza.motion._integrate``) that its package shares.
"""
from __future__ import annotations

import ast
import os
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src" / "kapitza"

def _modules(root):
    top = root.parent
    found = {}
    for d, _, files in os.walk(root):
        for f in files:
            if f.endswith(".py"):
                path = Path(d) / f
                name = ".".join(path.relative_to(top).with_suffix("").parts)
                found[name.removesuffix(".__init__")] = path
    return found


def _owner(mods, name):
    while name and name not in mods:
        name = name.rpartition(".")[0]
    return name


def _graph(mods):
    edges = {m: set() for m in mods}
    private = set()
    for m, path in mods.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                for a in node.names:
                    t = _owner(mods, a.name) if a.name.startswith("kapitza") else ""
                    if t and t != m:
                        edges[m].add(t)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = m.split(".")
                    if path.name != "__init__.py":
                        base = base[:-1]
                    base = ".".join(base[: len(base) - (node.level - 1)] + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                if not base.startswith("kapitza"):
                    continue
                for a in node.names:
                    t = _owner(mods, base + "." + a.name)
                    if t and t != m and not (path.name == "__init__.py" and t.startswith(m + ".")):
                        edges[m].add(t)
                    leaf = t.rpartition(".")[2]
                    sibling = m.rpartition(".")[0] == t.rpartition(".")[0] and leaf.startswith("_")
                    if (a.name.startswith("_") and not a.name.startswith("__") and not leaf.startswith("_")
                            and base + "." + a.name not in mods and not m.startswith(t + ".") and not sibling):
                        private.add(f"{m} imports {t}.{a.name}")
    return edges, private


def _cycles(edges):
    sys.setrecursionlimit(10000)
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 and not all(x.startswith(min(comp, key=len)) for x in comp):
                out.append(sorted(comp))

    for v in edges:
        if v not in index:
            visit(v)
    return out


def test_no_import_cycle_even_counting_imports_inside_functions():
    edges, _ = _graph(_modules(SRC))
    assert _cycles(edges) == []


def test_no_module_imports_a_private_name_of_another_public_module():
    _, private = _graph(_modules(SRC))
    assert not private, sorted(private)
