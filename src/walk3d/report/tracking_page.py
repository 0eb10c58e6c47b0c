"""The report's tracking sections: how close ``walk3d track`` came (``tracking.csv``), what
held it back (``binding.csv``) and the cost audit (``audit.json``, ``walk3d audit``), for a
result folder that has them."""

from __future__ import annotations

import csv
from pathlib import Path

from walk3d.io.checks import read_json_object
from walk3d.report import html as h

PHASES = ("loading", "mid-stance", "push-off", "swing", "total")


def _csv_rows(path: Path) -> list[dict]:
    with path.open(encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def _number(text: str) -> float | str:
    try:
        return float(text)
    except (TypeError, ValueError):
        return text


def tracking_sections(folder: Path | None, level: int = 2) -> list[str]:
    """Sections for the tracking files in ``folder`` (none without them; a damaged file is
    a note, not an error: the rest of the report stands)."""
    if folder is None:
        return []
    out = []
    try:
        if (folder / "tracking.csv").is_file():
            rows = _csv_rows(folder / "tracking.csv")
            table = h.table(("quantity", "unit", "RMSE", "largest error"),
                            [(r["quantity"], r["unit"], h.fmt(_number(r["rmse"]), ".2f"),
                              h.fmt(_number(r["max_abs"]), ".2f")) for r in rows])  # fmt: skip
            parts = [table]
            if (folder / "binding.csv").is_file():
                bind = _csv_rows(folder / "binding.csv")
                parts.append(h.table(("binds", "kind", "summed |multiplier|", "nodes"),
                                     [(r["name"], r["kind"], h.fmt(_number(r["multiplier"]), ".3g"),
                                       r["nodes"]) for r in bind]))  # fmt: skip
            out.append(h.section("Tracking", *parts, level=level))
        if (folder / "audit.json").is_file():
            audit = read_json_object(folder / "audit.json", "walk3d audit")
            out.append(h.section("Cost audit", *_audit(audit), level=level))
    except (OSError, ValueError, KeyError, TypeError, IndexError, AttributeError,
            csv.Error) as exc:  # fmt: skip
        out.append(h.note(f"the tracking files could not be read: {exc}", "warning"))
    return out


def _audit(a: dict) -> list[str]:
    rows = []
    for r in a["terms"]:
        rows.append(
            (
                r["term"],
                h.fmt(r["weight"], "g"),
                *(f"{r[f'tracked {p}']:.3g} / {r[f'predicted {p}']:.3g}" for p in PHASES),
            )
        )
    parts = [h.note(f"Tracked / predicted, s, under {a['criterion']}: C_weighted "
                    f"{a['C_weighted tracked']:.4g} / {a['C_weighted predicted']:.4g}."),
             h.table(("term", "weight", *PHASES), rows, numeric=False)]  # fmt: skip
    for key, unit in (("limb_work", "J/kg per step"), ("bursts", "J/kg")):
        names = list(a[key]["tracked"])
        parts.append(h.table((f"{key.replace('_', ' ')}, {unit}", *names),
                             [(label, *(h.fmt(a[key][label][n], ".3f") for n in names))
                              for label in ("tracked", "predicted")]))  # fmt: skip
    return parts
