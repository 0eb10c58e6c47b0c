"""One figure of cycle curves (0–100 % of the gait cycle) as an SVG document: a prediction over
a measured band, panel by panel.

Written directly as SVG text rather than through Matplotlib: some thirty panels take a few
milliseconds instead of about two seconds, and the curves stay sharp at any zoom. Data in,
text out: the caller supplies every curve in display units (the report, :mod:`walk3d.report`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape

import numpy as np

__all__ = ["Panel", "cycle_figure", "nice_ticks"]

PANEL_W, PANEL_H = 300, 200
"""Pixel size of one panel (4 per row: 1200 px, the page's width)."""
_LEFT, _RIGHT, _TOP, _BOTTOM = 46, 10, 24, 34
_HEAD = 56
_COLORS = {"band": "#cfd3d8", "mean": "#4a4f55", "other": "#1f77b4", "pred": "#d62728"}


@dataclass(frozen=True)
class Panel:
    """One axes: the predicted curve and, when measured, a band and other reference means."""

    label: str
    unit: str
    predicted: np.ndarray
    band: tuple[np.ndarray, np.ndarray] | None = None
    """(low, high) of the normative band, or None when nothing was measured."""
    band_mean: np.ndarray | None = None
    others: tuple[tuple[str, np.ndarray], ...] = ()
    """(label, mean) of further references, drawn as dotted lines."""


def nice_ticks(lo: float, hi: float, target: int = 4) -> tuple[np.ndarray, int]:
    """Round tick values covering ``[lo, hi]`` (steps 1, 2, 2.5, 5 × 10^k) and the decimals to
    print them with."""
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        lo, hi = (lo - 1, lo + 1) if math.isfinite(lo) else (-1.0, 1.0)
    raw = (hi - lo) / target
    k = math.floor(math.log10(raw))
    step = next(m * 10.0**k for m in (1, 2, 2.5, 5, 10) if m * 10.0**k >= raw)
    first = math.floor(lo / step + 1e-9) * step
    ticks = np.arange(first, hi + step * 0.999, step)
    decimals = max(0, -math.floor(math.log10(step) + 1e-9) + (1 if step / 10.0**k == 2.5 else 0))
    return ticks, decimals


def _path(x: np.ndarray, y: np.ndarray) -> str:
    """SVG path data through the finite points, broken where a value is missing."""
    parts, pen = [], False
    for xi, yi in zip(x, y, strict=True):
        if not math.isfinite(yi):
            pen = False
            continue
        parts.append(f"{'L' if pen else 'M'}{xi:.1f} {yi:.1f}")
        pen = True
    return "".join(parts)


def _panel(percent: np.ndarray, p: Panel, ox: float, oy: float, xlabel: bool) -> list[str]:
    w, hgt = PANEL_W - _LEFT - _RIGHT, PANEL_H - _TOP - _BOTTOM
    x0, y0 = ox + _LEFT, oy + _TOP
    curves = [p.predicted, p.band_mean, *(m for _, m in p.others), *(p.band or ())]
    values = np.concatenate([np.asarray(c, float) for c in curves if c is not None])
    values = values[np.isfinite(values)]
    lo, hi = (float(values.min()), float(values.max())) if values.size else (-1.0, 1.0)
    ticks, decimals = nice_ticks(lo, hi)
    lo, hi = float(ticks[0]), float(ticks[-1]) if ticks[-1] > ticks[0] else float(ticks[0]) + 1

    def sx(v):
        return x0 + w * np.asarray(v, float) / 100.0

    def sy(v):
        return y0 + hgt * (hi - np.asarray(v, float)) / (hi - lo)

    px = sx(percent)
    out = [f'<text x="{ox + PANEL_W / 2:.1f}" y="{oy + 15}" text-anchor="middle" '
           f'font-size="12" font-weight="600">{escape(p.label)}</text>']  # fmt: skip
    for t in ticks:
        yy = float(sy(t))
        out.append(f'<line x1="{x0}" x2="{x0 + w}" y1="{yy:.1f}" y2="{yy:.1f}" stroke="#e6e8eb"/>'
                   f'<text x="{x0 - 4}" y="{yy + 3.5:.1f}" text-anchor="end" font-size="10">'
                   f"{t:.{decimals}f}</text>")  # fmt: skip
    for t in (0, 25, 50, 75, 100):
        xx = float(sx(t))
        out.append(f'<line x1="{xx:.1f}" x2="{xx:.1f}" y1="{y0}" y2="{y0 + hgt}" '
                   f'stroke="#e6e8eb"/><text x="{xx:.1f}" y="{y0 + hgt + 13}" '
                   f'text-anchor="middle" font-size="10">{t}</text>')  # fmt: skip
    if p.band is not None:
        low, high = np.asarray(p.band[0], float), np.asarray(p.band[1], float)
        ok = np.isfinite(low) & np.isfinite(high)
        pts = [f"{a:.1f},{b:.1f}" for a, b in zip(px[ok], sy(high[ok]), strict=True)]
        pts += [f"{a:.1f},{b:.1f}" for a, b in zip(px[ok][::-1], sy(low[ok][::-1]), strict=True)]
        out.append(f'<polygon points="{" ".join(pts)}" fill="{_COLORS["band"]}"/>')
    if p.band_mean is not None:
        out.append(
            f'<path d="{_path(px, sy(p.band_mean))}" fill="none" '
            f'stroke="{_COLORS["mean"]}" stroke-width="1.2" stroke-dasharray="5 3"/>'
        )
    for _, mean in p.others:
        out.append(f'<path d="{_path(px, sy(mean))}" fill="none" stroke="{_COLORS["other"]}" '
                   'stroke-width="1.4" stroke-dasharray="1.5 2.5"/>')  # fmt: skip
    if p.band is None and p.band_mean is None and not p.others:
        out.append(f'<text x="{x0 + w / 2:.1f}" y="{y0 + 14}" text-anchor="middle" '
                   'font-size="10" fill="#6b7280">no measurement</text>')  # fmt: skip
    out.append(f'<path d="{_path(px, sy(p.predicted))}" fill="none" stroke="{_COLORS["pred"]}" '
               'stroke-width="1.8"/>')  # fmt: skip
    out.append(f'<rect x="{x0}" y="{y0}" width="{w}" height="{hgt}" fill="none" '
               'stroke="#6b7280"/>')  # fmt: skip
    cy = y0 + hgt / 2
    out.append(f'<text x="{ox + 11}" y="{cy:.1f}" font-size="10" text-anchor="middle" '
               f'transform="rotate(-90 {ox + 11} {cy:.1f})">{escape(p.unit)}</text>')  # fmt: skip
    if xlabel:
        out.append(f'<text x="{x0 + w / 2:.1f}" y="{y0 + hgt + 27}" text-anchor="middle" '
                   'font-size="10">% gait cycle (0 = right heel strike)</text>')  # fmt: skip
    return out


def _legend(band_label: str, others: Sequence[str], width: int) -> list[str]:
    items = [("band", band_label), ("mean", "measured mean"),
             *(("other", name) for name in others), ("pred", "prediction")]  # fmt: skip
    out, x = [], 12.0
    for kind, label in items:
        if kind == "band":
            out.append(f'<rect x="{x}" y="34" width="22" height="10" fill="{_COLORS["band"]}"/>')
        else:
            dash = {"mean": ' stroke-dasharray="5 3"', "other": ' stroke-dasharray="1.5 2.5"'}
            out.append(f'<line x1="{x}" x2="{x + 22}" y1="39" y2="39" stroke="{_COLORS[kind]}" '
                       f'stroke-width="1.8"{dash.get(kind, "")}/>')  # fmt: skip
        out.append(f'<text x="{x + 28}" y="43" font-size="11">{escape(label)}</text>')
        x += 40 + 6.2 * len(label)
        if x > width - 150:
            break
    return out


def cycle_figure(
    percent: np.ndarray, panels: Sequence[Panel], title: str, band_label: str = "measured"
) -> str:
    """A grid of panels (4 per row) over ``percent`` as a standalone SVG document (pixels)."""
    if not panels:
        raise ValueError("no panel to draw")
    cols = min(4, len(panels))
    rows = math.ceil(len(panels) / cols)
    width, height = cols * PANEL_W, _HEAD + rows * PANEL_H
    body = [
        f'<rect width="{width}" height="{height}" fill="#ffffff"/>',
        f'<text x="12" y="20" font-size="15" font-weight="700">{escape(title)}</text>',
    ]
    if any(p.band is not None for p in panels):
        names = sorted({n for p in panels for n, _ in p.others})
        body += _legend(band_label, names, width)
    for k, p in enumerate(panels):
        r, c = divmod(k, cols)
        body += _panel(np.asarray(percent, float), p, c * PANEL_W, _HEAD + r * PANEL_H,
                       xlabel=k >= len(panels) - cols)  # fmt: skip
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
            f'viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Arial, sans-serif">'
            + "".join(body) + "</svg>\n")  # fmt: skip
