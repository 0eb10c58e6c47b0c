"""Small HTML builders for the report: escaped text, tables, data URIs and the page shell.

Everything a page shows is inside the one file: CSS inline, figures as ``data:image/svg+xml``
(or PNG) URIs, the video as a ``data:video/mp4`` URI; no script, font or link to fetch.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Iterable, Sequence
from os import PathLike
from typing import Any

__all__ = ["GENERATOR", "data_uri", "fmt", "img", "is_walk3d_page", "note", "page", "section",
           "table", "text"]  # fmt: skip

GENERATOR = '<meta name="generator" content="walk3d">'
"""The marker in every page's head by which walk3d knows a page it wrote from a user's file."""

_CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 2em auto;
       max-width: 1240px; padding: 0 1em; color: #1d2125; background: #fff; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { font-size: 1.25em; margin-top: 1.6em;
border-bottom: 1px solid #ccd; padding-bottom: 0.2em; } h3 { font-size: 1.05em; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.92em; }
th, td { border: 1px solid #d0d4da; padding: 0.25em 0.6em; text-align: left; }
th { background: #f0f2f5; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
img.figure { max-width: 100%; height: auto; display: block; margin: 0.6em 0;
             border: 1px solid #e3e6ea; }
video { max-width: 100%; display: block; margin: 0.6em 0; }
.banner { padding: 0.7em 1em; border-radius: 4px; margin: 0.8em 0; font-weight: 600; }
.ok { background: #e3f4e6; border: 1px solid #6cbf7a; }
.bad { background: #fde4e1; border: 2px solid #d33a2c; color: #8a1c12; font-size: 1.1em; }
.warn { background: #fff4d6; border: 1px solid #e0b040; }
.note { color: #4a525c; font-size: 0.92em; } code { background: #f3f4f6; padding: 0 0.2em; }
"""


def text(value: Any) -> str:
    """``value`` as escaped HTML text."""
    return html.escape(str(value), quote=True)


def fmt(value: Any, spec: str = ".4g", unit: str = "") -> str:
    """A number formatted with ``spec`` (``–`` when missing or not finite), else the text."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return f"{value:{spec}}{' ' + unit if unit else ''}"
    return str(value)


def table(header: Sequence[str], rows: Iterable[Sequence[Any]], numeric: bool = True) -> str:
    """An HTML table; cells are escaped, number-looking ones right-aligned when ``numeric``."""
    head = "".join(f"<th>{text(h)}</th>" for h in header)
    body = []
    for row in rows:
        cells = []
        for cell in row:
            s = str(cell)
            right = numeric and s[:1] in "-+0123456789–" and any(c.isdigit() for c in s)
            cells.append(f'<td class="num">{text(s)}</td>' if right else f"<td>{text(s)}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def data_uri(data: bytes, mime: str) -> str:
    """``data:<mime>;base64,...``."""
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


def img(data: bytes | str, alt: str) -> str:
    """An inline figure: PNG bytes, or an SVG document as text."""
    uri = (
        data_uri(data, "image/png")
        if isinstance(data, bytes)
        else data_uri(data.encode("utf-8"), "image/svg+xml")
    )
    return f'<img class="figure" alt="{text(alt)}" src="{uri}">'


def note(message: str, kind: str = "note") -> str:
    """A paragraph (``note``) or a banner (``ok``, ``warn``, ``bad``) of escaped text."""
    cls = "note" if kind == "note" else f"banner {kind}"
    return f'<p class="{cls}">{text(message)}</p>'


def section(title: str, *parts: str, level: int = 2) -> str:
    """A heading followed by already-built HTML parts."""
    return f"<section><h{level}>{text(title)}</h{level}>{''.join(parts)}</section>"


def is_walk3d_page(path: str | PathLike[str]) -> bool:
    """Whether the file ``path`` is a page walk3d wrote: :data:`GENERATOR` in its head."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError:
        return False
    return GENERATOR.encode() in head.split(b"</head>")[0]


def page(title: str, *parts: str) -> str:
    """A complete, self-contained HTML5 document."""
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"{GENERATOR}"
        f"<title>{text(title)}</title><style>{_CSS}</style></head>\n<body>"
        f"<h1>{text(title)}</h1>" + "".join(parts) + "</body></html>\n"
    )
