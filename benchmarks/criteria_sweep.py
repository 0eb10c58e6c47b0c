"""Sweep criterion weights over the measured sources; print how each weight moves each figure.

    python benchmarks/criteria_sweep.py [--criteria natural 'tor=1,accel=1' ...]
                                        [--sources falisse winter subject01] [--seed 0]

For every criterion and source it runs ``walk3d predict`` with the source's descriptors and
subject (below), then ``walk3d validate`` against the source's measurement, and prints one row:
RMSE of the vertical and fore-aft GRF, knee, hip flexion and ankle angles, shoulder-flexion r,
mean R² over the quantities of issue #23, and the reference-free figures of ``gait_checks``
(peak vertical GRF, pelvis rotation range, step width, roughness) with the worst constraint
excess on the cycle. Predictions are kept in ``benchmarks/runs/criteria/<criterion>/<source>``
(git-ignored) and reused when present, so an interrupted sweep resumes. The table and the
environment go to ``benchmarks/runs/criteria_sweep-<stamp>.json``.

Sources (``../shared/data``; docs/criteria.md says which were tuned on and which held out):

* ``falisse``: Falisse et al. 2019 ``gait_1`` descriptors, 62 kg, 1.70 m, female, against the
  11-trial mean (whole body);
* ``winter``: Winter's normal cadence, V 1.325 m/s, T 1.1396 s, Td 0.114 s (stance 60 %),
  the paper's subject (68.8 kg, 1.77 m, male), against Winter's table (sagittal legs, GRF);
* ``subject01``: the OpenSim example treadmill trial, V 1.12 m/s, T 1.235 s, Td 0.17 s,
  72.6 kg, 1.80 m, male, against its IK, GRF and ID (legs, GRF, moments).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import environment  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(os.environ.get("WALK3D_SHARED_DATA", ROOT.parent / "shared" / "data"))
F, O = DATA / "falisse2019", DATA / "opensim_subject01"
SOURCES = {
    "falisse": (["--from-trial", str(F / "gait_1_ik.mot"), "--grf", str(F / "gait_1_grf.mot"),
                 "--mass", "62", "--height", "1.7", "--sex", "female"],
                [str(F / "cycle_right_leg_mean_sd.csv")], []),
    "winter": (["--speed", "1.325", "--period", "1.1396", "--double-support", "0.114"],
               [str(DATA / "winter" / "Winter_normal.csv")], []),
    "subject01": (["--speed", "1.12", "--period", "1.235", "--double-support", "0.17",
                   "--mass", "72.6", "--height", "1.8", "--sex", "male"],
                  [str(O / "subject01_walk1_ik.mot"), str(O / "subject01_walk1_grf.mot"),
                   str(O / "inverse_dynamics.sto")], ["--speed", "1.12"]),
}  # fmt: skip
ANGLES = ("knee_flexion", "hip_flexion", "ankle_dorsiflexion")
R2_KEYS = ("grf_vertical", "grf_fore_aft", "hip_flexion", "hip_adduction", "knee_flexion",
           "ankle_dorsiflexion", "arm_flex")  # fmt: skip
"""The quantities whose mean R² issue #23 asks for (those measured in a source)."""


def _folder(criterion: str) -> str:
    return criterion.replace("=", "").replace(",", "_").replace(".", "p")


def run_one(criterion: str, source: str, seed: int, root: Path,
            args: list[str] | None = None) -> dict:  # fmt: skip
    """Predict (unless present) and validate one criterion on one source; its figures.
    ``args``: the prediction's descriptor and subject options instead of the source's."""
    given, refs, vargs = SOURCES[source]
    args = given if args is None else args
    out = root / _folder(criterion) / source
    if not (out / "summary.json").exists():
        cmd = ["walk3d", "predict", *args, "--criterion", criterion, "--seed", str(seed),
               "--out", str(out)]  # fmt: skip
        subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
    if not (out / "summary.json").exists():
        return {"criterion": criterion, "source": source, "error": "no result"}
    val = out / "validation"
    cmd = ["walk3d", "validate", str(out), "--out", str(val), *vargs]
    for r in refs:
        cmd += ["--reference", r]
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
    summary = json.loads((out / "summary.json").read_text())
    gc = summary.get("gait_checks", {})
    row = {"criterion": criterion, "source": source, "converged": summary.get("converged"),
           "iterations": summary.get("iterations"), "wall_time_s": summary.get("wall_time_s"),
           "walking": gc.get("looks_like_walking")}  # fmt: skip
    table = {}
    if (val / "table2.csv").exists():
        with open(val / "table2.csv") as fh:
            table = {f"{r['group']}:{r['quantity']}": r for r in csv.DictReader(fh)}

    def get(key: str, col: str) -> float | None:
        v = table.get(key, {}).get(col)
        return float(v) if v not in (None, "", "nan") else None

    row["grf_vertical"] = get("grf:grf_vertical", "rmse")
    row["grf_fore_aft"] = get("grf:grf_fore_aft", "rmse")
    for a in ANGLES:
        row[a] = get(f"angle:{a}", "rmse")
    row["arm_flex_r"] = get("angle:arm_flex", "r")
    r2 = [get(("grf:" if k.startswith("grf") else "angle:") + k, "r2") for k in R2_KEYS]
    r2 = [v for v in r2 if v is not None]
    row["mean_r2"] = sum(r2) / len(r2) if r2 else None
    for k in (
        "peak_vertical_grf_bw",
        "pelvis_rotation_range_deg",
        "step_width_m",
        "roughness_worst",
        "roughness_worst_dof",
    ):
        row[k] = gc.get(k)
    worst = (summary.get("cycle_violations") or {}).get("worst") or {}
    row["worst_violation"] = f"{worst.get('kind')}={worst.get('value', float('nan')):.3g}"
    row["objective"] = {k: v.get("total") for k, v in summary.get("objective", {}).items()}
    return row


COLUMNS = ("grf_vertical", "grf_fore_aft", "knee_flexion", "hip_flexion", "ankle_dorsiflexion",
           "arm_flex_r", "mean_r2", "peak_vertical_grf_bw", "pelvis_rotation_range_deg",
           "step_width_m", "roughness_worst")  # fmt: skip
SHORT = ("vGRF", "fGRF", "knee", "hip", "ankle", "arm r", "R2", "peakBW", "pelv°", "width",
         "rough")  # fmt: skip


def print_table(rows: list[dict]) -> None:
    print(f"{'criterion':44s} {'source':10s} " + " ".join(f"{s:>6s}" for s in SHORT)
          + "  conv walk worst")  # fmt: skip
    for r in rows:
        cells = []
        for c in COLUMNS:
            v = r.get(c)
            cells.append(f"{v:6.2f}" if isinstance(v, float) else f"{'-':>6s}")
        print(f"{r['criterion'][:44]:44s} {r['source']:10s} " + " ".join(cells)
              + f"  {str(r.get('converged'))[:4]:4s} {str(r.get('walking'))[:4]:4s} "
              f"{r.get('worst_violation', r.get('error'))}")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--criteria", nargs="+", default=["tor", "natural"])
    ap.add_argument("--sources", nargs="+", default=["falisse", "winter", "subject01"],
                    choices=sorted(SOURCES))  # fmt: skip
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--runs", type=Path, default=ROOT / "benchmarks" / "runs" / "criteria")
    a = ap.parse_args(argv)
    if not DATA.is_dir():
        print(f"no measured data at {DATA}", file=sys.stderr)
        return 2
    rows = []
    for crit in a.criteria:
        for src in a.sources:
            rows.append(run_one(crit, src, a.seed, a.runs))
            print_table(rows[-1:])
            sys.stdout.flush()
    print()
    print_table(rows)
    result = {"environment": environment.environment(), "seed": a.seed, "rows": rows}
    path = environment.run_path("criteria_sweep")
    environment.write(path, result)
    print(f"written {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
