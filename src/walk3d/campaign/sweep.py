"""``walk3d sweep``: predictions across walking speeds with the period and double support
predicted, each started from its solved neighbour.

The folder:

* ``sweep.json``: the settings (speed aside) and the speeds; a rerun with other settings is
  refused, a rerun with the same ones resumes (:mod:`walk3d.campaign.sweep_folder` checks the
  folder first);
* ``speeds/v_<speed>/``: one ``walk3d predict`` folder per speed, written atomically, so a speed
  is either finished or absent; a resumed one must be of the speed and problem asked for;
* ``sweep.csv``: one row per speed (:data:`COLUMNS`), and ``sweep.png``
  (:func:`walk3d.plots.sweep.sweep_figure`);
* ``second_pass.json``: the second pass's tries (:func:`_second_pass`).

Order: the speed nearest :data:`PIVOT_SPEED` is solved from the settings' start (the atlas
by default, :mod:`walk3d.solve.starts`; standing for ``walk3d atlas build``); then, outwards,
each speed starts from its solved neighbour's coefficients, period and double support
(:func:`walk3d.solve.starts.solve_warm`). A warm start that does not converge, or does not look
like walking, goes through the speed halfway first (:data:`CONTINUATION_DEPTH` times at most),
and then from the settings' start. A second pass starts every speed once more from its other
neighbour and keeps the better of the two optima (:func:`_second_pass`).
"""

from __future__ import annotations

import csv
import io
import json
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from walk3d.campaign.sweep_folder import SweepMismatch, check_folder, speed_folder, stored
from walk3d.decimals import decimal
from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_json_object
from walk3d.model import terms
from walk3d.problem import descriptors
from walk3d.problem.settings import PredictionSettings

__all__ = ["COLUMNS", "SweepMismatch", "SweepReport", "parse_speeds", "per_metre", "run_sweep",
           "sweep_order", "walks"]  # fmt: skip

PIVOT_SPEED = 1.3
"""Speed (m/s) solved first, from the settings' start: the middle of adults' walking speeds."""
CONTINUATION_DEPTH = 2
"""Halvings of the speed step a warm start may take before the speed is solved from standing
(from 1.1 to 1.0 m/s the warm start stopped at its iteration limit; through 1.05 it walked in
60 + 55 iterations)."""
MAX_SPEEDS = 41
COLUMNS = (
    "speed", "period", "double_support", "stride_length", "cadence", "stance_fraction",
    "published_cadence", "cadence_error", "converged", "status", "start", "iterations",
    "wall_time_s", "via", "criterion_value", "criterion_per_metre", "looks_like_walking",
    "peak_vertical_grf_bw", "pelvis_rotation_range_deg", "step_width_m", "roughness_worst",
)  # fmt: skip
"""Columns of ``sweep.csv``: SI units, cadence in steps/min; ``published_cadence`` from
:func:`walk3d.problem.descriptors.published_cadence` and ``cadence_error`` the relative
difference; ``start``: ``standing`` or ``warm`` (from a neighbour), ``via``: the speeds solved
in between (``;``-separated), whose iterations and time are not in ``iterations`` and
``wall_time_s``."""


def _speed(text: str) -> float:
    """A speed's text as a number; ValueError unless plainly decimal (``1_2`` is not 12)."""
    v = decimal(text)
    if math.isnan(v):
        raise ValueError
    return v


def parse_speeds(text: str) -> np.ndarray:
    """``start:stop:step`` (stop included) or a comma list, m/s; ValueError for a range that is
    empty, reversed, outside (0, 4] m/s or of more than :data:`MAX_SPEEDS` speeds (counted
    before any array is made), for a list with an empty item (``1.2,,1.3``), and for a speed
    given twice or within 0.001 m/s of another (each speed has its own folder,
    :func:`speed_folder`)."""
    try:
        if ":" in text:
            parts = [_speed(p) for p in text.split(":")]
            if len(parts) != 3:
                raise ValueError
            a, b, step = parts
            if not all(map(math.isfinite, parts)) or step <= 0 or b < a:
                raise ValueError(f"--speeds {text}: the range is empty or reversed "
                                 "(start:stop:step with start <= stop and step > 0)")  # fmt: skip
            q = (b - a) / step + 1e-9  # the count first: 0.1:4:1e-10 would need 291 GiB
            if not q < MAX_SPEEDS:
                many = f"{math.floor(q) + 1:.3g}" if math.isfinite(q) else "countless"
                raise ValueError(f"--speeds {text}: {many} speeds, at most {MAX_SPEEDS} "
                                 "(a larger step)")  # fmt: skip
            speeds = a + step * np.arange(math.floor(q) + 1)
            speeds = np.round(speeds, 6) if np.all(speeds <= 4.0) else speeds
        elif text.strip():
            items = text.split(",")
            if not all(p.strip() for p in items):
                raise ValueError(f"--speeds {text}: an empty item (a list like 1.0,1.2,1.4)")
            speeds = np.array([_speed(p) for p in items])
        else:
            speeds = np.array([])
    except ValueError as exc:
        expected = f"--speeds {text}: expected start:stop:step or a list like 1.0,1.2,1.4 (m/s)"
        raise ValueError(str(exc) if str(exc).startswith("--speeds") else expected) from None
    if speeds.size == 0:
        raise ValueError(f"--speeds {text}: no speed")
    if not np.all((speeds > 0) & (speeds <= 4.0)):
        raise ValueError(f"--speeds {text}: every speed must be in (0, 4] m/s")
    if speeds.size > MAX_SPEEDS:
        raise ValueError(f"--speeds {text}: {speeds.size} speeds, at most {MAX_SPEEDS}")
    speeds = np.sort(speeds)
    for u, v in zip(speeds[:-1], speeds[1:], strict=True):
        if u == v:
            raise ValueError(f"--speeds {text}: {u:g} m/s is given twice (each speed once)")
        if f"{u:.3f}" == f"{v:.3f}":
            raise ValueError(f"--speeds {text}: {u:g} and {v:g} m/s are closer than 0.001 m/s, "
                             "which would share a folder")  # fmt: skip
    return speeds


def sweep_order(speeds: np.ndarray) -> list[tuple[int, int | None]]:
    """``(index, neighbour index or None)`` in solving order: the speed nearest
    :data:`PIVOT_SPEED` first (no neighbour), then outwards, each after its neighbour."""
    first = int(np.argmin(np.abs(speeds - PIVOT_SPEED)))
    order: list[tuple[int, int | None]] = [(first, None)]
    lo, hi = first - 1, first + 1
    while lo >= 0 or hi < len(speeds):
        if hi < len(speeds):
            order.append((hi, hi - 1))
            hi += 1
        if lo >= 0:
            order.append((lo, lo + 1))
            lo -= 1
    return order


def _at_speed(settings: PredictionSettings, speed: float, guess: tuple[float, float] | None):
    t, td = guess or descriptors.first_guess(speed, settings.gait.height)
    gait = settings.gait.model_copy(update={"speed": speed, "period": t, "double_support": td,
                                            "free": descriptors.NAMES})  # fmt: skip
    return settings.model_copy(update={"gait": gait})


def walks(summary: dict) -> bool:
    """Whether a prediction's summary converged and looks like walking."""
    return bool(summary["converged"] and summary["gait_checks"]["looks_like_walking"])


def _warm(settings, prev: dict, v: float, seed: int, solver: str, note, depth: int):
    """The prediction at ``v`` started from the solved ``prev`` (a summary), or None if it does
    not walk even through ``depth`` halvings of the speed step (each intermediate speed is
    solved the same way and only its solution kept). The result's summary gets ``sweep``:
    the speed it came from, the speeds in between and their iterations and solve time."""
    from walk3d.pipeline import predict

    d = prev["descriptors"]
    pred = predict(_at_speed(settings, v, (d["period"], d["double_support"])), seed, solver,
                   on_stage=note, warm_from=np.array(prev["coefficients"]["x"]))  # fmt: skip
    if walks(pred.summary):
        pred.summary["sweep"] = {"from_speed": d["speed"], "via": [], "extra_iterations": 0,
                                 "extra_wall_time_s": 0.0}  # fmt: skip
        return pred
    if depth == 0:
        return None
    mid = round((d["speed"] + v) / 2, 6)
    note(f"the warm start did not walk: through {mid:.3f} m/s first")
    half = _warm(settings, prev, mid, seed, solver, note, depth - 1)
    if half is None:
        return None
    pred = _warm(settings, half.summary, v, seed, solver, note, depth - 1)
    if pred is not None:
        a, b = half.summary["sweep"], pred.summary["sweep"]
        b["from_speed"], b["via"] = d["speed"], [*a["via"], mid, *b["via"]]
        b["extra_iterations"] += a["extra_iterations"] + half.summary["iterations"]
        b["extra_wall_time_s"] += a["extra_wall_time_s"] + half.summary["wall_time_s"]
    return pred


def _criterion(summary: dict, criterion: str) -> float | None:
    """The minimized criterion over the cycle, or None."""
    return terms.minimized(summary.get("objective") or {}, criterion)


def per_metre(summary: dict, criterion: str) -> float | None:
    """The criterion per metre walked (what the solver minimizes), or None."""
    value = _criterion(summary, criterion)
    return None if value is None else value / summary["descriptors"]["stride_length"]


def _second_pass(settings, speeds, out, summaries, first_from, seed, solver, on_progress, report):
    """Each speed once more from its other neighbour (the one the first pass did not start it
    from), if that one walks: the result replaces the speed's when it walks and the speed's did
    not, or its criterion per metre is lower (the better of two local optima, as a campaign
    keeps its best start). What was tried is kept in ``second_pass.json``, so a resumed sweep
    does not try it again."""
    from walk3d.pipeline import write_result
    from walk3d.solve.solver import forget_solvers

    path = out / "second_pass.json"
    try:  # a damaged record only means that the tries are made again
        done = read_json_object(path, "walk3d second-pass record") if path.is_file() else {}
    except (OSError, ValueError) as exc:
        why = getattr(exc, "reason", None) or " ".join(str(exc).split())
        warnings.warn(f"{path} cannot be read ({why}): its second-pass tries are made again",
                      RuntimeWarning, stacklevel=2)  # fmt: skip
        done = {}
    crit = settings.model.criterion
    for i, v in enumerate(map(float, speeds)):
        others = [nb for nb in (i - 1, i + 1) if 0 <= nb < len(speeds) and nb != first_from[i]]
        for nb in others:
            key = f"{v:.3f}<{float(speeds[nb]):.3f}"
            if key in done or not walks(summaries[nb]):
                continue
            if on_progress:
                on_progress(f"{v:.2f} m/s again, from {speeds[nb]:.2f} m/s", len(speeds),
                            len(speeds))  # fmt: skip
            depth = 0 if walks(summaries[i]) else CONTINUATION_DEPTH
            pred = _warm(settings, summaries[nb], v, seed, solver, lambda _m: None, depth)
            forget_solvers()
            report.tries += 1
            ours = per_metre(summaries[i], crit)
            new = None if pred is None else per_metre(pred.summary, crit)
            better = new is not None and (ours is None or new < ours)
            keep = pred is not None and (not walks(summaries[i]) or better)
            if keep:
                write_result(pred, speed_folder(out, v))
                summaries[i] = pred.summary
                report.ran += 1
            done[key] = {"walks": pred is not None, "kept": keep, "criterion_per_metre": new}
            atomic_write_text(path, json.dumps(done, indent=1) + "\n")


def table_row(summary: dict, criterion: str) -> dict:
    """One row of ``sweep.csv`` (:data:`COLUMNS`) from a prediction's summary."""
    d, g = summary["descriptors"], summary.get("gait_checks") or {}
    value = _criterion(summary, criterion)
    height = summary["settings"]["gait"]["height"]
    published = float(descriptors.published_cadence(d["speed"], height))
    return {
        **{k: d[k] for k in ("speed", "period", "double_support", "stride_length", "cadence",
                             "stance_fraction")},
        "published_cadence": published, "cadence_error": d["cadence"] / published - 1.0,
        "converged": summary["converged"], "status": summary["status"],
        "start": summary.get("start", "standing"), "iterations": summary["iterations"],
        "wall_time_s": summary["wall_time_s"],
        "via": ";".join(f"{u:g}" for u in (summary.get("sweep") or {}).get("via", [])),
        "criterion_value": value,
        "criterion_per_metre": per_metre(summary, criterion),
        "looks_like_walking": g.get("looks_like_walking"),
        "peak_vertical_grf_bw": g.get("peak_vertical_grf_bw"),
        "pelvis_rotation_range_deg": g.get("pelvis_rotation_range_deg"),
        "step_width_m": summary.get("step_width_m"), "roughness_worst": g.get("roughness_worst"),
    }  # fmt: skip


def write_table(path: Path, rows: list[dict]) -> None:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r[k] is None else r[k]) for k in COLUMNS})
    atomic_write_text(path, buf.getvalue())


@dataclass
class SweepReport:
    rows: list[dict] = field(default_factory=list)
    """Table rows by increasing speed."""
    ran: int = 0
    skipped: int = 0
    """Speeds solved now (a second-pass result kept included), and speeds read from an earlier
    run."""
    tries: int = 0
    """Second-pass solves made now, kept or not (:func:`_second_pass`)."""
    wall_time_s: float = 0.0


def run_sweep(
    settings: PredictionSettings,
    speeds: np.ndarray,
    out: str | Path,
    seed: int = 0,
    solver: str = "ipopt",
    on_progress: Callable[[str, int, int], None] | None = None,
) -> SweepReport:
    """Predict at each speed (module doc) and write the folder; ``on_progress(message, done,
    total)`` after each speed and ``(message, done, total)`` with solver messages meanwhile."""
    from walk3d.pipeline import predict, write_result
    from walk3d.solve.solver import forget_solvers

    t0 = time.perf_counter()
    out, criterion = Path(out), settings.model.criterion
    check_folder(out, settings)
    report = SweepReport()
    summaries = stored(out, settings, speeds, lambda s: (table_row(s, criterion), walks(s)))
    report.skipped = len(summaries)
    order = sweep_order(speeds)
    for done, (i, nb) in enumerate(order):
        v = float(speeds[i])
        folder = speed_folder(out, v)
        if i in summaries:
            continue

        def note(msg: str, v=v, done=done) -> None:
            if on_progress:
                on_progress(f"{v:.2f} m/s: {msg}", done, len(order))

        pred = None
        if nb is not None and summaries[nb]["converged"]:
            pred = _warm(settings, summaries[nb], v, seed, solver, note, CONTINUATION_DEPTH)
            if pred is None:
                note("the warm start did not walk: solving from the settings' start")
        if pred is None:
            pred = predict(_at_speed(settings, v, None), seed, solver, on_stage=note)
        write_result(pred, folder)
        forget_solvers()  # the next speed's are other solvers
        summaries[i] = pred.summary
        report.ran += 1
        if on_progress:
            on_progress(f"{v:.2f} m/s done", done + 1, len(order))
    _second_pass(settings, speeds, out, summaries, dict(order), seed, solver, on_progress, report)
    report.rows = [table_row(summaries[i], settings.model.criterion) for i in range(len(speeds))]
    write_table(out / "sweep.csv", report.rows)
    from walk3d.plots.sweep import sweep_figure

    sweep_figure(report.rows, settings.gait.height, out / "sweep.png")
    report.wall_time_s = time.perf_counter() - t0
    return report
