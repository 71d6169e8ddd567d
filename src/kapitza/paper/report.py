"""The reproduction report, written as Markdown and as self-contained HTML.

The report is assembled from blocks (headings, paragraphs, tables, figures) built
from computed results, and each block is rendered both ways, so the two files say
the same thing. Nothing in it is typed in by hand except the prose around the numbers.
"""
from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Heading", "Para", "Table", "Image", "Code", "to_markdown", "to_html", "plain_math",
           "nonlinear_section"]


@dataclass(frozen=True)
class Heading:
    text: str
    level: int = 2


@dataclass(frozen=True)
class Para:
    """A paragraph; ``code`` spans in backticks, ``**bold**`` allowed."""

    text: str


@dataclass(frozen=True)
class Table:
    header: tuple
    rows: tuple
    status_column: int | None = None  # a column holding PASSED/FAILED, coloured in HTML


@dataclass(frozen=True)
class Image:
    """A figure file (PNG) shown with its caption; ``links`` are the files beside it."""

    path: Path
    caption: str
    links: tuple = ()


@dataclass(frozen=True)
class Code:
    text: str


# ------------------------------------------------------------------ mathtext -> text
_SYMBOLS = {
    r"\varepsilon": "ε", r"\varphi": "φ", r"\alpha": "α", r"\beta": "β", r"\theta": "θ", r"\mu": "μ",
    r"\omega": "ω", r"\pi": "π", r"\psi": "ψ", r"\zeta": "ζ", r"\leq": "≤", r"\geq": "≥", r"\to": "→",
    r"\times": "×", r"\pm": "±", r"\langle": "⟨", r"\rangle": "⟩", r"\mapsto": "↦", r"\infty": "∞",
    r"\cdot": "·", r"\sqrt": "√", r"\,": " ", r"\;": " ", r"\!": "",
}


def plain_math(text: str) -> str:
    """A caption's mathtext (``$\\omega_h T$``) as readable Unicode text (``ω_h T``) for the report.

    The figures typeset the same caption with matplotlib's mathtext; Markdown and HTML show it
    as plain text: Greek letters and relations as characters, ``\\tilde T`` as ``T~``,
    ``\\frac{a}{b}`` as ``(a/b)``, ``\\dot\\theta`` as ``θ'``, braces and ``\\mathrm`` dropped.
    """

    def one(m):
        s = m.group(1)
        s = re.sub(r"\\frac\{([^{}]*)\}\{([^{}]*)\}", r"(\1/\2)", s)
        s = re.sub(r"\\sqrt\{([A-Za-z0-9]+)\}", r"√\1", s)
        s = re.sub(r"\\sqrt\{([^{}]*)\}", r"√(\1)", s)
        s = re.sub(r"\\langle\s*", "⟨", s)
        s = re.sub(r"\\(?:tilde|widetilde)\s*\{?([A-Za-z])\}?", r"\1~", s)
        s = re.sub(r"\\dot\s*\{?(\\?[A-Za-z]+)\}?", r"\1'", s)
        s = re.sub(r"\\(?:mathrm|mathit|mathbf|operatorname)\s*", "", s)
        for k in sorted(_SYMBOLS, key=len, reverse=True):
            s = s.replace(k, _SYMBOLS[k])
        return s.replace("{", "").replace("}", "").replace("\\", "")

    return re.sub(r"\$([^$]*)\$", one, text)


# ------------------------------------------------------------------ Markdown
def _md_cell(v) -> str:
    return str(v).replace("|", "\\|").replace("\n", " ")


def to_markdown(blocks, base: Path) -> str:
    """Markdown text; image and file links are relative to ``base``."""
    out = []
    for b in blocks:
        if isinstance(b, Heading):
            out.append("#" * b.level + " " + b.text)
        elif isinstance(b, Para):
            out.append(b.text)
        elif isinstance(b, Table):
            out.append("| " + " | ".join(_md_cell(h) for h in b.header) + " |")
            out.append("|" + "---|" * len(b.header))
            out += ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in b.rows]
        elif isinstance(b, Image):
            rel = Path(b.path).relative_to(base).as_posix()
            out.append(f"![{_md_cell(b.caption)[:80]}]({rel})")
            out.append("")
            out.append(f"*{b.caption}*")
            if b.links:
                out.append("")
                out.append("Files: " + ", ".join(f"[{Path(p).name}]({Path(p).relative_to(base).as_posix()})"
                                                 for p in b.links))
        elif isinstance(b, Code):
            out.append("```text\n" + b.text.rstrip("\n") + "\n```")
        out.append("")
    return "\n".join(out)


# ------------------------------------------------------------------ HTML
_CSS = """
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; max-width: 60rem;
       margin: 2rem auto; padding: 0 1rem; line-height: 1.5; color: #222; }
h1, h2, h3 { line-height: 1.25; }
table { border-collapse: collapse; margin: 0.8rem 0; font-size: 0.9rem; }
th, td { border: 1px solid #ccc; padding: 0.25rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f0f3f7; }
td.pass { color: #116611; font-weight: bold; } td.fail { color: #b00000; font-weight: bold; }
figure { margin: 1.5rem 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9rem; color: #444; }
code, pre { background: #f6f6f6; font-size: 0.88rem; } pre { padding: 0.6rem; overflow-x: auto; }
"""


def _inline(text: str) -> str:
    s = html.escape(text)
    s = re.sub(r"`([^`]+)`", r"<code>\1</code>", s)
    s = re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", s)
    s = re.sub(r"(?<![*\w])\*([^*\s][^*]*?)\*(?![*\w])", r"<em>\1</em>", s)
    return s


def to_html(blocks, base: Path, title: str) -> str:
    """Self-contained HTML: every figure is embedded as a base64 PNG."""
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>"]
    for b in blocks:
        if isinstance(b, Heading):
            out.append(f"<h{b.level}>{_inline(b.text)}</h{b.level}>")
        elif isinstance(b, Para):
            out.append(f"<p>{_inline(b.text)}</p>")
        elif isinstance(b, Table):
            out.append("<table><thead><tr>" + "".join(f"<th>{_inline(str(h))}</th>" for h in b.header)
                       + "</tr></thead><tbody>")
            for r in b.rows:
                cells = []
                for i, c in enumerate(r):
                    cls = ""
                    if i == b.status_column:
                        cls = ' class="pass"' if str(c) in ("PASS", "PASSED") else ' class="fail"'
                    cells.append(f"<td{cls}>{_inline(str(c))}</td>")
                out.append("<tr>" + "".join(cells) + "</tr>")
            out.append("</tbody></table>")
        elif isinstance(b, Image):
            data = base64.b64encode(Path(b.path).read_bytes()).decode("ascii")
            links = ""
            if b.links:
                links = "<br>Files: " + ", ".join(
                    f'<a href="{html.escape(Path(p).relative_to(base).as_posix())}">{html.escape(Path(p).name)}</a>'
                    for p in b.links)
            out.append(f'<figure><img alt="{html.escape(b.caption[:80])}" src="data:image/png;base64,{data}">'
                       f"<figcaption>{_inline(b.caption)}{links}</figcaption></figure>")
        elif isinstance(b, Code):
            out.append(f"<pre>{html.escape(b.text)}</pre>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ what the zones guarantee
def nonlinear_section(mu=(0.1, 0.3, 0.5), zones=(0, 1, 2)):
    """Blocks stating what the linear zones do and do not guarantee for the real pendulum, with
    the numbers of the nonlinear analysis (``docs/nonlinear.md``) computed on the spot."""
    import numpy as np

    from ..normal_form import nonlinear_stability
    from ..parameters import to_arnold
    from ..resonances import nonlinear_chart

    chart = nonlinear_chart(mu, zones, scan=0)
    rows = []
    for z in chart.zones:
        ratio = np.abs(z.twist_1to4) / z.resonant_1to4
        rows.append((z.n, ", ".join(f"{m:g}" for m in z.mu), "+" if z.twist_sign > 0 else "-",
                     f"{ratio.min():.4f} .. {ratio.max():.4f}",
                     "stable" if z.markeev_stable.all() else "unstable somewhere"))
    eps, m = (float(v) for v in to_arnold(0.15, 100.0))
    v = nonlinear_stability(eps, m)
    return [
        Heading("What the linear zones guarantee for the real pendulum"),
        Para("The zones are where the linearised equation (2.3) is stable: there the upright of the full equation "
             "`theta'' = (g + a(t))/l sin(theta)` is an elliptic fixed point of its period map, and small motions stay "
             "close to the linear ones for times of order 1/r^2. Elliptic alone does not mean Lyapunov stable; the "
             "nonlinear terms decide. kapitza computes the period map to third order in closed form and its Birkhoff "
             "normal form (docs/nonlinear.md): the map is odd, so 1:3 (tr M = −1) is no obstacle and only 1:4 "
             "(tr M = 0) competes with the twist. By Moser's twist theorem every zone point with twist τ ≠ 0 off "
             "1:4 is Lyapunov stable; on 1:4 Markeev's criterion |τ| > |c4| decides. The zone edges (1:1, 1:2) and "
             "the size of the stable neighbourhood are not covered, and near any resonance it can be small."),
        Para(f"At T = 0.15 s, A = 100 m/s^2 (l = 1 m): {v}."),
        Table(("zone", "mu", "sign of twist", "|τ|/|c4| on 1:4", "Markeev on 1:4"), tuple(rows)),
    ]
