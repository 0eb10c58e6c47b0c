"""Ranking the starts of a campaign: ``ranking.csv``, ``best/`` and the table of the best.

Order: converged starts first, by the chosen criterion ascending; then the others (failed
solves and errors), also by the criterion; starts without a finite value come last in their
group; ties are broken by seed.
"""

from __future__ import annotations

import csv
import io
import math
import shutil
from pathlib import Path
from typing import Any

from rich.table import Table

from walk3d.campaign import store
from walk3d.io.atomic import atomic_write_text
from walk3d.model import terms

__all__ = ["COLUMNS", "order_records", "rank", "top_table", "update_best", "write_ranking"]

RANKING_FILE = "ranking.csv"
BEST_DIR = "best"
COLUMNS = (
    "rank", "seed", "converged", "status", "failure", "criterion_value",
    "C_tor_total", "C_tor_x", "C_tor_y", "C_tor_z",
    "C_en_total", "C_en_x", "C_en_y", "C_en_z",
    "iterations", "wall_time_s", "looks_like_walking",
)  # fmt: skip
"""Columns of ``ranking.csv`` (``failure`` is empty for a converged start, ``numerics`` for a
solve that failed or raised, which a rerun would repeat, and ``environment`` for a start stopped
by disk, memory or a lost worker, which a resume runs again; ``criterion_value`` is the
campaign's chosen criterion, per cycle, or per metre walked when the period or double support is
predicted (the solver's own objective, :mod:`walk3d.problem.descriptors`);
``looks_like_walking`` is :func:`walk3d.results.gait_checks.walking_checks`' verdict, empty
for a start without a result)."""


def _value(record: dict) -> float | None:
    v = record.get("criterion_value")
    return float(v) if isinstance(v, (int, float)) and math.isfinite(v) else None


def sort_key(record: dict) -> tuple:
    """Converged first, then by finite criterion value ascending, then by seed."""
    v = _value(record)
    return (not record.get("converged"), v is None, v if v is not None else 0.0,
            int(record.get("seed", 0)))  # fmt: skip


def order_records(records: list[dict]) -> list[dict]:
    """Flat ranking rows (see :data:`COLUMNS`) of ``records``, best first."""
    rows = []
    for k, r in enumerate(sorted(records, key=sort_key), start=1):
        row: dict[str, Any] = {
            "rank": k,
            "seed": int(r["seed"]),
            "converged": bool(r.get("converged")),
            "status": str(r.get("status")),
            "failure": r.get("failure", "" if r.get("converged") else "numerics"),
            "criterion_value": _value(r),
        }
        for crit in ("C_tor", "C_en"):
            split = r.get(crit) or {}
            for part in ("total", "x", "y", "z"):
                row[f"{crit}_{part}"] = split.get(part)
        row["iterations"] = r.get("iterations")
        row["wall_time_s"] = r.get("wall_time_s")
        row["looks_like_walking"] = r.get("looks_like_walking")
        rows.append(row)
    return rows


def rank(out_dir: str | Path) -> list[dict]:
    """Ranking rows of every finished start stored in the campaign folder, best first.

    Reads the records only; :func:`write_ranking` and :func:`update_best` write the outcome.
    """
    return order_records(list(store.finished_records(out_dir).values()))


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def write_ranking(out_dir: str | Path, rows: list[dict]) -> Path:
    """Write ``ranking.csv`` atomically; returns its path."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in rows:
        writer.writerow([_cell(row.get(c)) for c in COLUMNS])
    return atomic_write_text(Path(out_dir) / RANKING_FILE, buffer.getvalue())


def best_seed(rows: list[dict]) -> int | None:
    """Seed of the best converged start, or None when no start converged."""
    return rows[0]["seed"] if rows and rows[0]["converged"] else None


def _manifest(folder: Path) -> bytes | None:
    """The bytes of a result folder's manifest (it holds the arrays' digest), None if absent."""
    try:
        return (folder / "manifest.json").read_bytes()
    except OSError:
        return None


def update_best(out_dir: str | Path, rows: list[dict]) -> int | None:
    """Make ``best/`` a copy of the best converged start's folder (removed if none); a
    ``best/`` of another seed, or whose manifest is not the start's, is replaced.

    Returns the best seed, or None.
    """
    out = Path(out_dir)
    target = out / BEST_DIR
    seed = best_seed(rows)
    if seed is None:
        if target.exists():
            shutil.rmtree(target)
        return None
    source = store.starts_dir(out) / store.start_name(seed)
    current = store.read_record(target) if target.is_dir() else None
    if current is None or current.get("seed") != seed or _manifest(target) != _manifest(source):
        store.replace_folder(source, target)
    return seed


def _fmt(value: Any) -> str:
    return "-" if value is None else f"{value:.4g}"


def _yes_no(value: Any) -> str:
    return "-" if value is None else ("yes" if value else "no")


def top_table(
    rows: list[dict], criterion: str, n: int = 5, title: str | None = None, per_metre: bool = False
) -> Table:
    """A Rich table of the ``n`` best starts: the chosen criterion, and the x/y/z split of its
    base (C_tor or C_en). ``per_metre``: the criterion values are per metre walked (T or Td
    predicted, :data:`COLUMNS`), and the column says so; the split is per cycle."""
    key, split = terms.label(criterion), f"C_{terms.base(criterion)}"
    key = f"{key} per m" if per_metre else key
    t = Table(title=title or f"best {min(n, len(rows))} of {len(rows)} starts by {key}")
    xyz = ("x", "y", "z") if key == split else (f"{split} x", "y", "z")
    for col in ("rank", "seed", "conv.", key, *xyz, "iter", "walking"):
        t.add_column(col)
    t.add_column("status", overflow="ellipsis", no_wrap=True, max_width=32)
    for row in rows[:n]:
        t.add_row(
            str(row["rank"]), str(row["seed"]), "yes" if row["converged"] else "no",
            _fmt(row["criterion_value"]), _fmt(row[f"{split}_x"]), _fmt(row[f"{split}_y"]),
            _fmt(row[f"{split}_z"]), "-" if row["iterations"] is None else str(row["iterations"]),
            _yes_no(row.get("looks_like_walking")), row["status"],
        )  # fmt: skip
    return t
