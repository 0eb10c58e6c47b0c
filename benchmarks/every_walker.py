"""Issue #61's targets in one command: every walker, slow to fast, walks from the atlas in seconds.

    python benchmarks/every_walker.py [--fresh] [--sets NAME,...] [--reference]

Run it alone on the machine, with the derivatives compiled (``walk3d compile --sex male`` and
``--sex female``) and the model cached. :data:`SETS` holds 12 descriptor sets spread over
0.4-2.2 m/s, double supports of 6.5-23 % of the cycle, both sexes, 45-120 kg and 1.50-1.95 m:
the odd ones with T and Td given (plausible values for such a walker, not measurements), the
even ones predicted. Each runs as ``walk3d predict`` in its own process, timed end to end
(start, model load, solve, result folder). Bars: every set walks, from the atlas (no start from
standing); median ≤ 5 s; every set ≤ 15 s.

Folders go to ``benchmarks/runs/every_walker/`` (git-ignored; reused unless ``--fresh``); the
table and the environment to ``benchmarks/runs/every_walker-<stamp>.json``.
"""

from __future__ import annotations

import argparse
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

NAME = "every_walker"
SETS = (
    # name, sex, kg, m, V m/s, T s, Td s (None: predicted)
    ("woman_0.40_slow", "female", 45.0, 1.50, 0.40, 1.75, 0.40),
    ("man_0.50", "male", 120.0, 1.95, 0.50, None, None),
    ("woman_0.60_long_ds", "female", 70.0, 1.60, 0.60, 1.35, 0.25),
    ("man_0.80", "male", 90.0, 1.75, 0.80, None, None),
    ("woman_0.90_td16", "female", 62.0, 1.65, 0.90, 1.25, 0.20),
    ("man_1.10", "male", 75.0, 1.80, 1.10, None, None),
    ("woman_1.30", "female", 55.0, 1.55, 1.30, 1.00, 0.10),
    ("man_1.50", "male", 100.0, 1.90, 1.50, None, None),
    ("woman_1.70_short_ds", "female", 68.0, 1.72, 1.70, 0.92, 0.07),
    ("man_1.90", "male", 80.0, 1.85, 1.90, None, None),
    ("man_2.10_td6", "male", 72.0, 1.78, 2.10, 0.85, 0.055),
    ("woman_2.15", "female", 58.0, 1.68, 2.15, None, None),
)
BARS = {"median_end_to_end_s": 5.0, "max_end_to_end_s": 15.0}
ROOT = Path(__file__).resolve().parent / "runs" / NAME


def _args(row: tuple) -> list[str]:
    _, sex, mass, height, v, t, td = row
    a = ["--speed", str(v), "--mass", str(mass), "--height", str(height), "--sex", sex]
    return a if t is None else [*a, "--period", str(t), "--double-support", str(td)]


def run_set(row: tuple, fresh: bool) -> dict:
    """One set's ``walk3d predict``, timed, and what its summary says."""
    out = ROOT / row[0]
    if fresh or not (out / "summary.json").exists():
        shutil.rmtree(out, ignore_errors=True)
        t0 = time.perf_counter()
        done = subprocess.run(["walk3d", "predict", *_args(row), "--out", str(out)],
                              stdout=subprocess.DEVNULL, check=False)  # fmt: skip
        out.mkdir(parents=True, exist_ok=True)
        (out / "end_to_end_s").write_text(f"{time.perf_counter() - t0:.3f}\n")
        (out / "exit_code").write_text(f"{done.returncode}\n")
    s = json.loads((out / "summary.json").read_text())
    return {
        "name": row[0], "given": row[5] is not None, "speed": row[4],
        "end_to_end_s": float((out / "end_to_end_s").read_text()),
        "exit_code": int((out / "exit_code").read_text()),
        "iterations": s["iterations"], "start": s.get("start"), "converged": s["converged"],
        "walks": bool(s["converged"] and s["gait_checks"]["looks_like_walking"]),
        "period": s["descriptors"]["period"], "double_support": s["descriptors"]["double_support"],
    }  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fresh", action="store_true", help="solve again even if a result exists")
    ap.add_argument("--sets", default="", help="comma-separated set names (default: all 12)")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    names = [n for n in args.sets.split(",") if n]
    rows = []
    for row in SETS:
        if names and row[0] not in names:
            continue
        r = run_set(row, args.fresh)
        rows.append(r)
        print(f"{r['name']:22s} {'given' if r['given'] else 'auto ':5s} {r['start']!s:9s} "
              f"walks {r['walks']!s:5s} {r['iterations']:4d} it  {r['end_to_end_s']:6.1f} s  "
              f"T {r['period']:.3f} Td {r['double_support']:.3f}", flush=True)  # fmt: skip
    times = [r["end_to_end_s"] for r in rows]
    result = {
        "environment": environment.environment(), "bars": BARS, "rows": rows,
        "walk": sum(r["walks"] for r in rows), "sets": len(rows),
        "from_atlas": sum(r["start"] == "atlas" for r in rows),
        "median_end_to_end_s": statistics.median(times), "max_end_to_end_s": max(times),
    }  # fmt: skip
    print({k: v for k, v in result.items() if k not in ("environment", "rows")})
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"written {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
