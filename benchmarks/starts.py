"""Issue #25's targets in one command: every descriptor set walks, in seconds, from the atlas.

    python benchmarks/starts.py [--parts predict,campaigns,random,hundred] [--fresh]

Run it alone on the machine, with the derivatives compiled (``walk3d compile --sex male`` and
``--sex female``) and the model cached. Parts:

* ``predict``: ``walk3d predict`` with its defaults (``--start atlas``) on :data:`SETS`, 12
  descriptor sets (0.8-1.8 m/s, the published cadence and double support of
  :func:`walk3d.problem.descriptors.first_guess` given, a tall man and a short woman), each
  timed end to end as a process (start, model load, solve, result folder); then the same sets
  with T and Td predicted (``auto``). Bars: every set converges and walks; median ≤ 10 s.
* ``campaigns``: a 20-start campaign with ``walk3d campaign``'s defaults (atlas starts, T and
  Td predicted, 2 workers) on each set; bar: ``walk3d predict``'s criterion (per metre) is
  within 2 % of the campaign's best. ``--campaign-given`` runs them with T and Td given.
* ``random``: the paper's subject and descriptors (default criterion), 20 campaign starts
  with the default strategy (bar: ≥ 95 % walk) and 20 standing starts, the paper's method
  (aim 90 %).
* ``hundred``: a 100-start campaign on 2 local workers (bar: ≤ 10 min), the paper's subject
  and descriptors; ``hundred_default`` (not in the default parts): the same with
  ``walk3d campaign``'s defaults, T and Td predicted.

Folders go to ``benchmarks/runs/starts/`` (git-ignored; reused unless ``--fresh``); the table
and the environment to ``benchmarks/runs/starts-<stamp>.json``.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import environment  # noqa: E402

NAME = "starts"
PAPER_SUBJECT = ["--speed", "1.3806", "--period", "1.08", "--double-support", "0.16",
                 "--mass", "68.8", "--height", "1.77", "--sex", "male"]  # fmt: skip
"""The paper's subject and descriptors under the default criterion (``--paper`` would also
set the paper's C_tor)."""
PAPER_BODY = ["--speed", "1.3806", "--mass", "68.8", "--height", "1.77", "--sex", "male"]
"""The paper's subject and speed with ``walk3d campaign``'s defaults: T and Td predicted."""
SUBJECTS = {"man": ("male", 82.0, 1.85), "woman": ("female", 58.0, 1.60)}
"""Two statures and both sexes: a tall man and a short woman (kg, m)."""
SPEEDS = (0.8, 1.0, 1.2, 1.4, 1.6, 1.8)
BARS = {"median_end_to_end_s": 10.0, "criterion_vs_campaign": 0.02, "default_walk_share": 0.95,
        "standing_walk_share_aim": 0.90, "hundred_starts_s": 600.0}  # fmt: skip
ROOT = Path(__file__).resolve().parent / "runs" / NAME


def _sets() -> list[dict]:
    from walk3d.problem.descriptors import first_guess

    out = []
    for who, (sex, mass, height) in SUBJECTS.items():
        for v in SPEEDS:
            t, td = first_guess(v, height)
            out.append({"name": f"{who}_{v:.1f}", "sex": sex, "mass": mass,
                        "height": height, "speed": v, "period": round(t, 4),
                        "double_support": round(td, 4)})  # fmt: skip
    return out


def _args(s: dict, given: bool) -> list[str]:
    a = ["--speed", str(s["speed"]), "--mass", str(s["mass"]), "--height", str(s["height"]),
         "--sex", s["sex"]]  # fmt: skip
    return [*a, "--period", str(s["period"]), "--double-support", str(s["double_support"])] if (
        given) else a  # fmt: skip


def _walks(summary: dict) -> bool:
    return bool(summary.get("converged") and summary["gait_checks"]["looks_like_walking"])


def _criterion(summary: dict) -> float | None:
    from walk3d.model import terms

    obj = summary.get("objective") or {}
    label = terms.label(summary["settings"]["model"]["criterion"])
    value = (obj.get(label) or {}).get("total")  # the minimized criterion, as a campaign ranks
    if value is None:
        return None
    d = summary["descriptors"]
    return value / d["stride_length"] if d["predicted"] else value


def part_predict(fresh: bool) -> dict:
    rows = []
    for given in (True, False):
        for s in _sets():
            out = ROOT / "predict" / f"{s['name']}_{'given' if given else 'auto'}"
            if fresh or not (out / "summary.json").exists():
                shutil.rmtree(out, ignore_errors=True)
                t0 = time.perf_counter()
                subprocess.run(["walk3d", "predict", *_args(s, given), "--out", str(out)],
                               stdout=subprocess.DEVNULL, check=False)  # fmt: skip
                (out / "end_to_end_s").write_text(f"{time.perf_counter() - t0:.3f}\n")
            summary = json.loads((out / "summary.json").read_text())
            row = {**s, "given": given, "end_to_end_s": float((out / "end_to_end_s").read_text()),
                   "solve_s": summary["wall_time_s"], "iterations": summary["iterations"],
                   "converged": summary["converged"], "walks": _walks(summary),
                   "start": summary.get("start"), "criterion": _criterion(summary),
                   "period_found": summary["descriptors"]["period"],
                   "double_support_found": summary["descriptors"]["double_support"]}  # fmt: skip
            row["s_per_iteration"] = row["solve_s"] / max(row["iterations"], 1)
            rows.append(row)
            print(
                f"{s['name']:10s} {'given' if given else 'auto ':5s} {row['start']:8s} "
                f"walks {row['walks']!s:5s} {row['iterations']:4d} it  solve "
                f"{row['solve_s']:5.1f} s  end-to-end {row['end_to_end_s']:5.1f} s",
                flush=True,
            )
    out = {"rows": rows}
    for given in (True, False):
        sel = [r for r in rows if r["given"] is given]
        key = "given" if given else "auto"
        out[key] = {
            "all_walk": all(r["walks"] for r in sel), "walk": sum(r["walks"] for r in sel),
            "sets": len(sel), "from_atlas": sum(r["start"] == "atlas" for r in sel),
            "median_end_to_end_s": statistics.median(r["end_to_end_s"] for r in sel),
            "median_solve_s": statistics.median(r["solve_s"] for r in sel),
            "median_iterations": statistics.median(r["iterations"] for r in sel),
            "median_s_per_iteration": statistics.median(r["s_per_iteration"] for r in sel),
        }  # fmt: skip
        print(key, out[key])
    return out


def _campaign(out: Path, args: list[str], starts: int, fresh: bool, extra=()) -> tuple[list, float]:
    if fresh:
        shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    if not (out / "ranking.csv").exists():
        subprocess.run(["walk3d", "campaign", *args, "--starts", str(starts), "--workers", "2",
                        *extra, "--out", str(out)], stdout=subprocess.DEVNULL,
                       check=False)  # fmt: skip
    wall = time.perf_counter() - t0
    with open(out / "ranking.csv") as fh:
        return list(csv.DictReader(fh)), wall


def _walked(row: dict) -> bool:
    """A ranking.csv row that converged and looks like walking (the file writes ``true``)."""
    return row["converged"].lower() == "true" and row["looks_like_walking"].lower() == "true"


def _best(rows: list[dict]) -> float | None:
    vals = [float(r["criterion_value"]) for r in rows if _walked(r)]
    return min(vals) if vals else None


def _share(rows: list[dict]) -> float:
    return sum(_walked(r) for r in rows) / len(rows)


def part_campaigns(fresh: bool, predicted: dict, names: list[str] | None, given: bool) -> dict:
    rows = []
    by_name = {r["name"]: r for r in predicted["rows"] if r["given"] is given}
    for s in _sets():
        if names and s["name"] not in names:
            continue
        folder = ROOT / "campaigns" / f"{s['name']}_{'given' if given else 'auto'}"
        ranking, wall = _campaign(folder, _args(s, given), 20, fresh)
        best, mine = _best(ranking), by_name[s["name"]]["criterion"]
        gap = None if best is None or mine is None else mine / best - 1.0
        rows.append({"name": s["name"], "campaign_best": best, "predict": mine, "gap": gap,
                     "campaign_walk_share": _share(ranking), "wall_s": wall})  # fmt: skip
        print(
            f"{s['name']:10s} predict {mine}  campaign best {best}  gap "
            f"{'-' if gap is None else f'{100 * gap:+.2f} %'}",
            flush=True,
        )
    gaps = [r["gap"] for r in rows if r["gap"] is not None]
    return {"given": given, "rows": rows, "within_2_percent": sum(g <= 0.02 for g in gaps),
            "sets": len(rows), "worst_gap": max(gaps) if gaps else None}  # fmt: skip


def part_random(fresh: bool) -> dict:
    out = {}
    for start in ("atlas", "standing"):
        ranking, wall = _campaign(ROOT / f"random_{start}", PAPER_SUBJECT, 20, fresh,
                                  ("--start", start))  # fmt: skip
        out[start] = {"walk_share": _share(ranking), "starts": len(ranking), "wall_s": wall}
        print(start, out[start], flush=True)
    return out


def part_hundred(fresh: bool, given: bool = True) -> dict:
    """100 starts on the paper's subject: with its T and Td given (``given``), or with
    ``walk3d campaign``'s defaults (T and Td predicted)."""
    args = PAPER_SUBJECT if given else PAPER_BODY
    ranking, wall = _campaign(ROOT / ("hundred" if given else "hundred_default"), args, 100, True)
    out = {"wall_s": wall, "walk_share": _share(ranking), "starts": len(ranking),
           "descriptors": "given" if given else "predicted"}  # fmt: skip
    print("100 starts", out, flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", default="predict,campaigns,random,hundred")
    ap.add_argument("--fresh", action="store_true", help="solve again even if a result exists")
    ap.add_argument("--sets", default="", help="comma-separated set names for the campaigns "
                    "(default: all 12)")  # fmt: skip
    ap.add_argument(
        "--campaign-given",
        action="store_true",
        help="campaigns with the published T and Td given (default: predicted)",
    )
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    parts = args.parts.split(",")
    result = {"environment": environment.environment(), "bars": BARS}
    if "predict" in parts or "campaigns" in parts:
        result["predict"] = part_predict(args.fresh)
    if "campaigns" in parts:
        names = [n for n in args.sets.split(",") if n]
        result["campaigns"] = part_campaigns(args.fresh, result["predict"], names,
                                             args.campaign_given)  # fmt: skip
    if "random" in parts:
        result["random"] = part_random(args.fresh)
    if "hundred" in parts:
        result["hundred"] = part_hundred(args.fresh)
    if "hundred_default" in parts:
        result["hundred_default"] = part_hundred(args.fresh, given=False)
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"written {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
