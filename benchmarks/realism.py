"""Realism target of issue #23: the default preset against its limits, in one command.

    python benchmarks/realism.py [--criterion natural] [--seed 0] [--free-landing] [--reference]

Runs ``walk3d predict`` (default preset and seed unless given) on:

* the Falisse et al. 2019 subject with the ``gait_1`` descriptors (62 kg, 1.70 m, female),
  judged against the 11-trial mean by ``walk3d validate`` and, when present, by the shared
  yardstick ``../shared/tools/realism.py`` with the issue's limits (:data:`LIMITS`);
* the Falisse prediction's sagittal hip, knee and ankle moments (r, RMSE in N m/kg, ``walk3d
  validate``'s Table 2 rows) against each source that has moments (:func:`moment_sources`), r
  against the 11-trial mean judged by issue #41's bar (:data:`MOMENT_LIMITS`);
* the paper's subject at 1.0 and 1.6 m/s (T, Td below) and at its own descriptors, judged by the
  checks that need no measured reference (peak vertical GRF, pelvis rotation range, step width,
  roughness, looks like walking) and the worst constraint excess on the 101-sample cycle.

``--free-landing`` solves them with the paper's switch at heel strike instead of the handover.
Predictions go to ``benchmarks/runs/realism/<criterion>[-free-landing]/`` (git-ignored; reused
when present).
The table and the environment go to ``benchmarks/runs/realism-<stamp>.json`` (``--reference``:
``benchmarks/reference/realism.json``). Exit code 0 whether or not the limits hold.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import environment  # noqa: E402
from criteria_sweep import DATA, SOURCES, _folder  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
YARDSTICK = ROOT.parent / "shared" / "tools" / "realism.py"
LIMITS = {"grf_vertical": 1.2, "grf_fore_aft": 0.5, "knee_flexion": 7.0, "hip_flexion": 6.0,
          "ankle_dorsiflexion": 6.0, "arm_flex_r_corr": 0.7, "peak_vgrf_bw": 1.3,
          "pelvis_rotation_range_deg": 12.0, "step_width_m": [0.05, 0.15],
          "roughness_worst": 0.15, "mean_R2": 0.5}  # fmt: skip
"""The issue's bar on the Falisse subject (RMSE in N/kg and deg, ranges in deg)."""
SPEEDS = {
    "paper_1.0": ["--speed", "1.0", "--period", "1.18", "--double-support", "0.20"],
    "paper_1.38": ["--period", "1.08", "--double-support", "0.16"],
    "paper_1.6": ["--speed", "1.6", "--period", "1.00", "--double-support", "0.12"],
}
"""The paper's subject at other speeds (T and Td of adults at those speeds, docs/solver.md)."""
MOMENTS = ("hip_flexion", "knee_flexion", "ankle_dorsiflexion")
"""The sagittal moments (walk3d DoF names; Table 2 rows ``moment:<name>``, N m/kg)."""
MOMENT_LIMITS = {"knee_flexion": 0.8, "ankle_dorsiflexion": 0.9, "hip_flexion": 0.6}
"""Issue #41's bar: lowest r of each sagittal moment against the 11-trial mean."""
FREE = {
    "peak_vertical_grf_bw": 1.3,
    "pelvis_rotation_range_deg": 12.0,
    "step_width_m": (0.05, 0.15),
    "roughness_worst": 0.15,
}


def _predict(args: list[str], out: Path, criterion: str, seed: int, extra: list[str]) -> dict:
    if not (out / "summary.json").exists():
        cmd = ["walk3d", "predict", *args, "--criterion", criterion, "--seed", str(seed),
               *extra, "--out", str(out)]  # fmt: skip
        subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
    return json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}


def moment_sources(data: Path = DATA) -> dict[str, list[Path]]:
    """Reference files with measured moments: the 11-trial mean, trial ``gait_1``, Winter."""
    f = data / "falisse2019"
    return {"falisse_mean": [f / "cycle_right_leg_mean_sd.csv"],
            "falisse_gait_1": [f / "gait_1_ik.mot", f / "gait_1_grf.mot", f / "gait_1_id.sto"],
            "winter": [data / "winter" / "Winter_normal.csv"]}  # fmt: skip


def moment_rows(folder: Path, sources: dict[str, list[Path]]) -> dict[str, dict]:
    """``{source: {moment: {"r", "rmse"}}}`` from ``walk3d validate`` (nothing written), for the
    sources whose files all exist; NaN where a source lacks the moment."""
    from walk3d.results.prediction import load_result
    from walk3d.validation.run import validate

    pred = load_result(folder)
    out: dict[str, dict] = {}
    for name, files in sources.items():
        if not all(Path(f).is_file() for f in files):
            continue
        comparison = validate({"prediction": pred}, files, figures=False).comparisons[0]
        rows = {m: comparison.row(f"moment:{m}") for m in MOMENTS}
        out[name] = {m: {"r": r.r, "rmse": r.rmse} for m, r in rows.items()}
    return out


AT_LEAST = ("arm_flex_r_corr", "mean_R2")
"""Limits that are lower bounds; the others are upper bounds or ranges."""


def _holds(key: str, value, limit) -> bool:
    if not isinstance(value, (int, float)):
        return False
    if isinstance(limit, (list, tuple)):
        return limit[0] <= value <= limit[1]
    return value >= limit if key in AT_LEAST else value <= limit


def _print_moments(folder: Path) -> dict[str, dict]:
    """:func:`moment_rows` of the Falisse prediction, printed with :data:`MOMENT_LIMITS`."""
    moments = moment_rows(folder, moment_sources())
    for source, rows in moments.items():
        for m, row in rows.items():
            limit = MOMENT_LIMITS[m] if source == "falisse_mean" else None
            verdict = "" if limit is None else ("  ok" if row["r"] >= limit else "  NOT MET")
            print(f"moment {source:15s} {m:19s} r {row['r']:6.3f}  RMSE {row['rmse']:.3f} N m/kg"
                  + ("" if limit is None else f"  limit r >= {limit}") + verdict)  # fmt: skip
    return moments


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--criterion", default="natural")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--free-landing", action="store_true", help="solve without the handover")
    environment.add_output_arguments(ap, "realism")
    a = ap.parse_args(argv)
    extra = ["--free-landing"] if a.free_landing else []
    folder = _folder(a.criterion) + ("-free-landing" if a.free_landing else "")
    root = ROOT / "benchmarks" / "runs" / "realism" / folder
    result: dict = {"environment": environment.environment(), "criterion": a.criterion,
                    "seed": a.seed, "free_landing": a.free_landing, "falisse": {},
                    "speeds": {}}  # fmt: skip
    if DATA.is_dir():
        args, refs, _ = SOURCES["falisse"]
        out = root / "falisse"
        summary = _predict(args, out, a.criterion, a.seed, extra)
        if summary and YARDSTICK.exists():
            cmd = [sys.executable, str(YARDSTICK), str(out), refs[0], "--json",
                   "--limits", json.dumps(LIMITS)]  # fmt: skip
            text = subprocess.run(cmd, capture_output=True, text=True).stdout.strip()
            figures = json.loads(text.splitlines()[-1]) if text else {}
            rows = {}
            for k, limit in LIMITS.items():
                v = figures.get(k)
                good = _holds(k, v, limit)
                rows[k] = {"value": v, "limit": limit, "holds": bool(good)}
                print(f"falisse  {k:28s} {v!s:>8s}  limit {limit!s:>12s}  "
                      f"{'ok' if good else 'NOT MET'}")  # fmt: skip
            result["falisse"] = {"yardstick": rows, "all": figures}
        if summary:
            result["falisse"] |= {"moments": _print_moments(out),
                                  "cycle_violations": summary.get("cycle_violations"),
                                  "wall_time_s": summary.get("wall_time_s"),
                                  "converged": summary.get("converged")}  # fmt: skip
    else:
        print(f"no measured data at {DATA}: the Falisse rows are skipped")
    for name, args in SPEEDS.items():
        s = _predict(args, root / name, a.criterion, a.seed, extra)
        g = s.get("gait_checks", {})
        row = {k: g.get(k) for k in FREE} | {
            "looks_like_walking": g.get("looks_like_walking"), "converged": s.get("converged"),
            "worst_violation": (s.get("cycle_violations") or {}).get("worst"),
            "wall_time_s": s.get("wall_time_s"), "C_tor": s.get("objective", {}).get(
                "C_tor", {}).get("total")}  # fmt: skip
        result["speeds"][name] = row
        met = all(_holds(k, row[k], lim) for k, lim in FREE.items())
        print(
            f"{name:10s} "
            + "  ".join(
                f"{k} {row[k]:.3g}" if isinstance(row[k], float) else f"{k} {row[k]}" for k in FREE
            )  # fmt: skip
            + f"  walking {row['looks_like_walking']}  {'ok' if met else 'NOT MET'}"
        )
    path = environment.output_path(a, "realism")
    environment.write(path, result)
    print(f"written {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
