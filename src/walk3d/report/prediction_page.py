"""The report of one prediction: inputs, convergence, criteria, figures over normative bands,
and the animation, as sections of a self-contained HTML page (docs/report.md).

Read from the :class:`~walk3d.results.prediction.PredictedCycle` and its ``summary`` (what
``summary.json`` holds); a field the summary lacks is shown as ``–``, never guessed. Curves
run 0–100 % from right heel strike (:func:`walk3d.validation.compare.align_prediction`), in
Table 2's units (degrees, N m/kg, N/kg); bands come from :mod:`walk3d.report.norms`.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

from walk3d.model import terms
from walk3d.plots.cycles import Panel, cycle_figure
from walk3d.problem.settings import recorded_settings
from walk3d.report import html as h
from walk3d.report.norms import Norms
from walk3d.report.tracking_page import tracking_sections
from walk3d.results.labels import did_not_converge, is_converged
from walk3d.results.prediction import PredictedCycle
from walk3d.validation.compare import align_prediction
from walk3d.validation.quantities import GROUP_UNITS, QUANTITIES

__all__ = [
    "ANIMATION",
    "MAX_VIDEO_BYTES",
    "REPORT",
    "prediction_page",
    "prediction_sections",
]

ANIMATION = "animation.mp4"
REPORT = "report.html"
"""The report's file name in a result or campaign folder."""
MAX_VIDEO_BYTES = 64_000_000
"""Larger videos are linked, not embedded: a page of hundreds of MB would not open well."""

_FIGURES = (("angle", "Joint angles"), ("moment", "Joint moments"), ("grf", "Ground reaction"))


def _get(d: object, *path: str) -> object:
    for key in path:
        if not isinstance(d, dict):
            return None
        d = d.get(key)
    return d


def status_banners(summary: dict) -> list[str]:
    """The convergence banner (a failed solve in red) and a warning for a non-walking gait."""
    out = []
    status = summary.get("status", "unknown status")
    if is_converged(summary):
        out.append(h.note(f"Converged ({status}).", "ok"))
    elif did_not_converge(summary):  # False, or any other recorded value ("no")
        out.append(h.note(f"NOT CONVERGED ({status}): this is not a valid prediction; the page "
                          "shows the solver's last iterate.", "bad"))  # fmt: skip
    else:
        out.append(h.note("Convergence not recorded (no solve: e.g. a fitted or atlas motion).",
                          "warn"))  # fmt: skip
    if _get(summary, "gait_checks", "looks_like_walking") is False:
        out.append(h.note("The gait checks say this does not look like walking (see below).",
                          "warn"))  # fmt: skip
    return out


def _inputs(summary: dict) -> str:
    flat = recorded_settings(summary)
    d = summary.get("descriptors") if isinstance(summary.get("descriptors"), dict) else {}
    predicted = set(d.get("predicted") or flat.get("free") or [])

    def desc(name: str, unit: str, spec: str = ".4f") -> str:
        value = d.get(name, flat.get(name))
        return h.fmt(value, spec, unit) + (" (predicted)" if name in predicted else " (given)")

    crit = flat.get("criterion")
    preset = summary.get("criterion_preset") or (terms.preset_name(crit) if crit else None)
    rows = [
        ("subject", f"{h.fmt(flat.get('mass'), 'g', 'kg')}, {h.fmt(flat.get('height'), 'g', 'm')}"
                    f", {flat.get('sex', '–')}"),
        ("speed V", h.fmt(d.get("speed", flat.get("speed")), ".4f", "m/s")),
        ("gait-cycle period T", desc("period", "s")),
        ("double support Td", desc("double_support", "s")),
        ("stride length", h.fmt(d.get("stride_length"), ".4f", "m")),
        ("cadence", h.fmt(d.get("cadence"), ".1f", "steps/min")),
        ("stance", h.fmt(100 * d["stance_fraction"], ".1f", "% of the cycle")
         if isinstance(d.get("stance_fraction"), float) else "–"),
        ("criterion", f"{crit or '–'}" + (f" (preset {preset})" if preset else "")),
        ("start, seed", f"{summary.get('start', '–')}, {summary.get('seed', '–')}"),
        ("solver, nodes", f"{summary.get('method', '–')}, {flat.get('nodes', '–')}"),
        ("calibrated roll-over", "yes" if flat.get("rollover_s") else "no"),
    ]  # fmt: skip
    return h.table(("input", "value"), rows, numeric=False)


def _convergence(summary: dict) -> str:
    worst = _get(summary, "cycle_violations", "worst")
    cycle = "–"
    if isinstance(worst, dict):
        holds = "holds" if worst.get("holds") else "EXCEEDED"
        cycle = (f"worst {worst.get('kind')}: {h.fmt(worst.get('value'), '.3g')} (limit "
                 f"{h.fmt(worst.get('limit'), 'g')}, {holds})")  # fmt: skip
    g = summary.get("gait_checks") if isinstance(summary.get("gait_checks"), dict) else {}
    rows = [
        ("status", f"{summary.get('status', '–')}"),
        ("converged", h.fmt(summary.get("converged"))),
        ("iterations", h.fmt(summary.get("iterations"), "d")),
        ("attempts", h.fmt(summary.get("attempts"), "d")),
        ("wall time", h.fmt(summary.get("wall_time_s"), ".1f", "s")),
        ("max constraint violation (at the nodes)", h.fmt(summary.get("max_constraint_violation"),
                                                         ".2e")),
        ("constraints on the 101-sample cycle", cycle),
        ("double-support contact residual", h.fmt(
            1000 * v if isinstance(v := summary.get("double_support_contact_residual_m"), float)
            else None, ".3f", "mm")),
        ("looks like walking", h.fmt(g.get("looks_like_walking"))),
        ("knee flexion in swing, hip flexion in mid-stance",
         f"{h.fmt(g.get('knee_swing_max_deg'), '.0f', 'deg')}, "
         f"{h.fmt(g.get('hip_midstance_deg'), '.0f', 'deg')}"),
        ("peak vertical GRF", h.fmt(g.get("peak_vertical_grf_bw"), ".2f", "body weights")),
    ]  # fmt: skip
    return h.table(("quantity", "value"), rows, numeric=False)


def _criteria(summary: dict) -> str:
    objective = summary.get("objective")
    if not isinstance(objective, dict) or not objective:
        return h.note("The summary records no criteria.")
    weighted = objective.get("C_weighted") if isinstance(objective.get("C_weighted"), dict) else {}
    weights, parts = weighted.get("weights") or {}, weighted.get("parts") or {}
    total = weighted.get("total")
    crit = recorded_settings(summary).get("criterion")
    minimized = terms.label(crit) if isinstance(crit, str) else None
    rows = []
    for key in terms.reported(objective):
        c = objective.get(key)
        if not isinstance(c, dict):
            continue
        name = key[2:]
        part = parts.get(name)
        share = 100 * part / total if isinstance(part, float) and total else None
        mark = " (minimized)" if key == minimized else ""
        rows.append((key + mark, h.fmt(c.get("total")), h.fmt(c.get("x")), h.fmt(c.get("y")),
                     h.fmt(c.get("z")), h.fmt(weights.get(name), "g"), h.fmt(part),
                     h.fmt(share, ".1f", "%")))  # fmt: skip
    for name, part in parts.items():  # what-if parts outside the weights (overload, steps)
        if name not in weights and isinstance(part, float):
            share = 100 * part / total if total else None
            rows.append((f"{name} (what-if)", "", "", "", "", "", h.fmt(part),
                         h.fmt(share, ".1f", "%")))  # fmt: skip
    out = [h.table(("criterion", "total", "x", "y", "z", "weight", "weight × value",
                    "share of the sum"), rows)]  # fmt: skip
    if isinstance(total, float):
        out.append(
            h.note(f"Minimized C_weighted = Σ weight × value (and what-if parts) = {total:.4g}.")
        )
    stride = _get(summary, "descriptors", "stride_length")
    if _get(summary, "descriptors", "predicted") and isinstance(stride, float):
        out.append(h.note("With T or Td predicted the solver minimizes the criterion per metre "
                          f"walked: divide by the stride length ({stride:.4f} m)."))  # fmt: skip
    out.append(h.note("x, y, z: each term split over the joint axes (x ab/adduction, y axial "
                      "rotation, z flexion) or the global ones (x forward, y up, z right), as "
                      "docs/criteria.md says per term."))  # fmt: skip
    return "".join(out)


_UNITS = (("_nm_per_kg", "N m/kg", ".2f"), ("_deg", "deg", ".1f"), ("_bw", "BW", ".2f"),
          ("_m", "m", ".3f"), ("_s", "s", ".3f"))  # fmt: skip
"""``asymmetry`` key suffixes: the unit shown and the number format."""


def _sides(summary: dict) -> str:
    """``summary.json``'s ``asymmetry``: right, left and right − left per quantity."""
    asym = summary.get("asymmetry")
    if not isinstance(asym, dict) or not asym:
        return h.note("No left-against-right figures in the summary (a result without steps).")
    rows = []
    for key, entry in asym.items():
        suffix, unit, spec = next((u for u in _UNITS if key.endswith(u[0])), ("", "", ".3g"))
        if not isinstance(entry, dict):
            continue
        label = key.removesuffix(suffix).replace("_", " ")
        rows.append((label, unit, h.fmt(entry.get("right"), spec), h.fmt(entry.get("left"), spec),
                     h.fmt(entry.get("difference"), "+" + spec)))  # fmt: skip
    problem = summary.get("problem", "half cycle")
    why = ("each side has its own series" if problem == "full cycle" else
           "the left side mirrors the right, so the differences are sampling only")  # fmt: skip
    return h.table(("quantity", "unit", "right", "left", "right − left"), rows) + h.note(
        f"Problem: {problem} ({why}). Stance: vertical force above 2 % of body weight; peaks "
        "over the cycle (docs/what-if.md)."
    )


def _figures(pred: PredictedCycle, norms: Norms) -> str:
    try:
        percent, predicted = align_prediction(pred)
    except (ValueError, KeyError) as exc:
        return h.note(f"Figures unavailable: {' '.join(str(exc).split())}.", "warn")
    if norms.bands:
        kinds = sorted({norms.bands[k].kind for k in norms.bands})
        intro = h.note("Grey band: measured normative data (" + "; ".join(kinds) + "). Sources: "
                       + "; ".join(norms.sources) + f" (read from {norms.folder}). Dotted: "
                       "other measured means. Red: this prediction.")  # fmt: skip
    else:
        where = f" in {norms.folder}" if norms.folder else ""
        intro = h.note(f"No measured normative data found{where} (looked for ../shared/data, "
                       "or give --data DIR / $WALK3D_SHARED_DATA): the prediction is shown "
                       "alone.", "warn")  # fmt: skip
    parts = [intro] + [h.note(n) for n in norms.notes]
    sd = all(b.kind.startswith("mean ± SD") for b in norms.bands.values())
    label = "measured mean ± SD" if sd else "measured band"
    for group, title in _FIGURES:
        panels = []
        for q in QUANTITIES:
            if q.group != group or q.key not in predicted:
                continue
            b = norms.bands.get(q.key)
            panels.append(Panel(q.label, q.unit, predicted[q.key],
                                None if b is None else (b.low, b.high),
                                None if b is None else b.mean,
                                () if b is None else b.others))  # fmt: skip
        if panels:
            svg = cycle_figure(percent, panels, f"{title} ({GROUP_UNITS[group]})", label)
            parts.append(h.img(svg, f"{title} over the gait cycle"))
    return "".join(parts)


def _animation(folder: Path | None, where: str) -> str:
    video = folder / ANIMATION if folder is not None else None
    if video is None or not video.is_file():
        return h.note(f"No {ANIMATION} in this folder. Make it with `walk3d animate {where}` "
                      f"(or `walk3d predict --animate`), then `walk3d report {where}` to embed "
                      "it.")  # fmt: skip
    size = video.stat().st_size
    if size > MAX_VIDEO_BYTES:
        return h.note(f"{ANIMATION} is {size / 1e6:.0f} MB, too large to embed: open "
                      f"{where}/{ANIMATION} beside this page.")  # fmt: skip
    uri = h.data_uri(video.read_bytes(), "video/mp4")
    return (f'<video controls loop muted playsinline src="{uri}"></video>'
            + h.note(f"{ANIMATION} ({size / 1e6:.2f} MB), embedded."))  # fmt: skip


def prediction_sections(
    pred: PredictedCycle,
    folder: str | PathLike[str] | None,
    norms: Norms,
    level: int = 2,
    shown_as: str | None = None,
) -> list[str]:
    """The sections of a prediction's report; ``folder`` is where ``animation.mp4`` may be,
    ``shown_as`` the folder's name in the text (default ``folder``)."""
    s = pred.summary
    where = shown_as or (str(folder) if folder is not None else "DIR")
    video_dir = None if folder is None else Path(folder)
    return [
        *status_banners(s),
        h.section("Inputs", _inputs(s), level=level),
        h.section("Convergence", _convergence(s), level=level),
        h.section("Criteria", _criteria(s), level=level),
        h.section("Left and right", _sides(s), level=level),
        h.section("Gait cycle against measured walking", _figures(pred, norms), level=level),
        h.section("Animation", _animation(video_dir, where), level=level),
        *tracking_sections(video_dir, level=level),
    ]


def prediction_page(
    pred: PredictedCycle,
    folder: str | PathLike[str] | None,
    norms: Norms,
    shown_as: str | None = None,
) -> str:
    """The complete HTML page of one prediction (arguments as :func:`prediction_sections`)."""
    where = shown_as or (str(folder) if folder is not None else "prediction")
    version = pred.summary.get("walk3d_version", "–")
    footer = h.note(f"walk3d {version}; result folder {where}; units: degrees, N m/kg, N/kg "
                    "(per kg of body mass); 0 % = right heel strike.")  # fmt: skip
    sections = prediction_sections(pred, folder, norms, shown_as=where)
    return h.page(f"walk3d prediction: {Path(where).name or where}", *sections, footer)
