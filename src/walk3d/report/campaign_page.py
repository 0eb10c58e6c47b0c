"""The report of a campaign folder (``walk3d campaign``): its inputs, how many starts converged
and walk, the five best, and the best prediction's sections (:mod:`.prediction_page`).

Read from ``campaign.json``, the starts' records (ranked as ``ranking.csv`` is, by
:func:`walk3d.campaign.ranking.rank`) and ``best/`` (else the best converged start's folder).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

from walk3d.campaign import store
from walk3d.campaign.ranking import BEST_DIR, best_seed, rank
from walk3d.io.errors import DataFileError
from walk3d.model import terms
from walk3d.problem.settings import flat_settings
from walk3d.report import html as h
from walk3d.report.norms import Norms
from walk3d.report.prediction_page import prediction_sections
from walk3d.results.prediction import load_result

__all__ = ["TOP", "campaign_page"]

TOP = 5
"""Rows of the table of the best starts (as ``walk3d campaign`` prints)."""


def _inputs(campaign: dict) -> str:
    flat = flat_settings(campaign.get("settings") or {})
    free = set(flat.get("free") or [])

    def desc(name: str) -> str:
        return "predicted per start" if name in free else h.fmt(flat.get(name), ".4f", "s")

    crit = campaign.get("criterion", flat.get("criterion"))
    preset = terms.preset_name(crit) if isinstance(crit, str) else None
    rows = [
        ("subject", f"{h.fmt(flat.get('mass'), 'g', 'kg')}, {h.fmt(flat.get('height'), 'g', 'm')}"
                    f", {flat.get('sex', '–')}"),
        ("speed V", h.fmt(flat.get("speed"), ".4f", "m/s")),
        ("gait-cycle period T", desc("period")),
        ("double support Td", desc("double_support")),
        ("criterion", f"{crit or '–'}" + (f" (preset {preset})" if preset else "")),
        ("starts requested, base seed", f"{campaign.get('starts', '–')}, "
                                        f"{campaign.get('base_seed', '–')} (start k: seed + k)"),
        ("solver, nodes, start", f"{campaign.get('solver', '–')}, {flat.get('nodes', '–')}, "
                                 f"{flat.get('start', '–')}"),
        ("perturbation, restarts", f"{flat.get('perturbation', '–')}, {flat.get('restarts', '–')}"),
        ("walk3d, solver revision", f"{campaign.get('walk3d_version', '–')}, "
                                    f"{campaign.get('solve_revision', '–')}"),
    ]  # fmt: skip
    return h.table(("input", "value"), rows, numeric=False)


def _outcome(rows: list[dict], requested: object) -> str:
    converged = [r for r in rows if r["converged"]]
    walking = [r for r in converged if r.get("looks_like_walking") is True]
    env = sum(r.get("failure") == "environment" for r in rows)
    times = [r["wall_time_s"] for r in rows if isinstance(r.get("wall_time_s"), (int, float))]
    table = h.table(("starts", "count"), [
        ("finished (stored)", f"{len(rows)} of {requested}"),
        ("converged", str(len(converged))),
        ("converged and look like walking", str(len(walking))),
        ("did not converge or raised (numerics)", str(len(rows) - len(converged) - env)),
        ("stopped by the environment (rerun resumes them)", str(env)),
        ("solve time, all starts", h.fmt(sum(times), ".1f", "s") if times else "–"),
    ])  # fmt: skip
    return table


def _top(rows: list[dict], criterion: str) -> str:
    key, split = terms.label(criterion), f"C_{terms.base(criterion)}"
    header = ("rank", "seed", "converged", key, f"{split} x", "y", "z", "iterations",
              "walking", "status")  # fmt: skip
    body = [(r["rank"], r["seed"], h.fmt(r["converged"]), h.fmt(r["criterion_value"]),
             h.fmt(r.get(f"{split}_x")), h.fmt(r.get(f"{split}_y")), h.fmt(r.get(f"{split}_z")),
             h.fmt(r.get("iterations"), "d"), h.fmt(r.get("looks_like_walking")), r["status"])
            for r in rows[:TOP]]  # fmt: skip
    return h.table(header, body) + h.note(
        f"{key}: the campaign's criterion per cycle, or per metre walked when T or Td is "
        "predicted; the full ranking is in ranking.csv."
    )


def _best(folder: Path, rows: list[dict], norms: Norms) -> list[str]:
    seed = best_seed(rows)
    if seed is None:
        return [h.note("No start converged: there is no best prediction to show.", "bad")]
    candidates = [folder / BEST_DIR, store.starts_dir(folder) / store.start_name(seed)]
    for where in candidates:
        record = store.read_record(where)
        if record is None or record.get("seed") != seed:
            continue
        try:
            pred = load_result(where)
        except (OSError, DataFileError) as exc:
            return [h.note(f"The best start's folder {where} is unreadable: {exc}", "bad")]
        intro = h.note(f"Best converged start: seed {seed}, from {where}.")
        return [intro, *prediction_sections(pred, where, norms, level=3)]
    return [h.note(f"The best start (seed {seed}) has no result folder here.", "warn")]


def campaign_page(folder: str | PathLike[str], norms: Norms) -> str:
    """The complete HTML page of a campaign folder.

    Raises:
        OSError, ValueError: ``campaign.json`` is missing or not JSON.
    """
    root = Path(folder)
    campaign = store.read_campaign(root)
    if not isinstance(campaign, dict):
        raise ValueError(f"{root / store.CAMPAIGN_FILE} is not a JSON object")
    rows = rank(root)
    criterion = str(campaign.get("criterion") or "tor")
    parts = [
        h.section("Inputs", _inputs(campaign)),
        h.section("Starts", _outcome(rows, campaign.get("starts", "–"))),
        h.section(f"The {min(TOP, len(rows))} best starts", _top(rows, criterion)
                  if rows else h.note("No start has finished yet.")),
        h.section("Best prediction", *_best(root, rows, norms)),
        h.note(f"walk3d {campaign.get('walk3d_version', '–')}; campaign folder {root}."),
    ]  # fmt: skip
    return h.page(f"walk3d campaign: {root.resolve().name}", *parts)
