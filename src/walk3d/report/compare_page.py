"""The page of ``walk3d compare A B --out DIR``: what changed from A to B, as
``DIR/report.html`` beside ``compare.csv`` and ``compare.png`` (docs/what-if.md)."""

from __future__ import annotations

from typing import Any

from walk3d.report import html as h
from walk3d.results.labels import did_not_converge, invalid_reason

__all__ = ["compare_page"]


def _number(row: dict[str, Any], key: str, spec: str) -> str:
    return h.fmt(row.get(key), spec)


def _banners(labels: tuple[str, str], summaries: tuple[dict, dict]) -> list[str]:
    """A red banner for a result that did not converge, a yellow one for a gait that does not
    walk (as ``walk3d report``'s)."""
    out = []
    for side, name, summary in zip("AB", labels, summaries, strict=True):
        reason = invalid_reason(summary)
        if reason is not None:
            out.append(h.note(f"{side} = {name}: {reason}.",
                              "bad" if did_not_converge(summary) else "warn"))  # fmt: skip
    return out


def compare_page(rows: list[dict[str, Any]], figure_png: bytes, labels: tuple[str, str],
                 summaries: tuple[dict, dict] = ({}, {})) -> str:  # fmt: skip
    """The self-contained HTML page of :func:`walk3d.results.compare.compare`'s ``rows`` and
    the figure of :func:`walk3d.plots.compare.compare_figure` (PNG bytes); ``labels``: the
    names of A and B, whose ``summaries`` mark one that is not a valid walking prediction."""
    a, b = labels
    scalars = [(r["quantity"], r["unit"] or "–", _number(r, "a_max", ".4g"),
                _number(r, "b_max", ".4g"), _number(r, "largest_change", "+.4g"))
               for r in rows if r["group"] in ("criterion", "body")]  # fmt: skip
    curves = [(r["quantity"], r["group"], r["unit"],
               f"{_number(r, 'a_min', '.3g')} … {_number(r, 'a_max', '.3g')}",
               f"{_number(r, 'b_min', '.3g')} … {_number(r, 'b_max', '.3g')}",
               _number(r, "rms_change", ".2g"), _number(r, "largest_change", "+.2g"))
              for r in rows if r["group"] in ("angle", "moment")]  # fmt: skip
    return h.page(
        f"walk3d compare: {a} against {b}",
        *_banners(labels, summaries),
        h.note(f"A = {a}, B = {b}. Changes are B − A, sample by sample on the 101-sample cycle "
               "from right heel strike; moments per kg of each prediction's own body mass."),
        h.section("Criteria and body", h.table(("quantity", "unit", "A", "B", "B − A"), scalars)),
        h.section(
            "Joint angles and moments, both sides",
            h.img(figure_png, f"{a} (solid) against {b} (dashed) over the gait cycle"),
            h.table(("DoF", "kind", "unit", "A range", "B range", "RMS change",
                     "largest change"), curves),
        ),
    )  # fmt: skip
