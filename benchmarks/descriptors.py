"""Issue #24's targets in one command: the predicted period and double support against measured
trials, and the cost of predicting them.

    python benchmarks/descriptors.py [--criterion natural] [--seed 0] [--fresh] [--reference]

For each trial below, ``walk3d predict`` runs twice with the same seed:

* **free**: only V, mass, height and sex given (T and Td predicted); the predicted T and Td
  against the measured ones (bars: 5 % and 25 %);
* **given**: the measured T and Td given, as before T and Td could be predicted.

The cost is the ratio of the median wall times (``summary.json``'s ``wall_time_s``, the solve;
bar: at most 1.5). Solves run one at a time. Predictions go to
``benchmarks/runs/descriptors/<criterion>/`` (git-ignored; reused unless ``--fresh``); the
table and the environment to ``benchmarks/runs/descriptors-<stamp>.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import environment  # noqa: E402
from criteria_sweep import DATA  # noqa: E402

NAME = "descriptors"
F = DATA / "falisse2019"
TRIALS = {
    # name: (V, mass, height, sex, measured T, measured Td)
    "falisse_gait_1": (1.2704745, 62.0, 1.70, "female", None, None),  # T, Td read from the trial
    "subject01": (1.12, 72.6, 1.80, "male", 1.235, 0.17),
    "winter_normal": (1.325, 68.8, 1.77, "male", 1.1396, 0.114),
}
"""V, T and Td of subject01 and Winter as in benchmarks/criteria_sweep.py; Falisse's from its
``gait_1`` IK and GRF files (walk3d.trials.descriptors)."""
BARS = {"period": 0.05, "double_support": 0.25, "cost_ratio": 1.5}


def _measured(name: str) -> tuple[float, float]:
    _, _, _, _, t, td = TRIALS[name]
    if t is not None:
        return t, td
    from walk3d.trials.descriptors import descriptors_from_trial

    d = descriptors_from_trial(F / "gait_1_ik.mot", F / "gait_1_grf.mot")
    return d.period, d.double_support


def _predict(out: Path, args: list[str], fresh: bool) -> dict:
    if fresh and out.exists():
        shutil.rmtree(out)
    if not (out / "summary.json").exists():
        subprocess.run(["walk3d", "predict", *args, "--out", str(out)], check=False,
                       stdout=subprocess.DEVNULL)  # fmt: skip
    path = out / "summary.json"
    return json.loads(path.read_text()) if path.exists() else {}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--criterion", default="natural")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--fresh", action="store_true", help="solve again even if a result exists")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    root = Path(__file__).resolve().parent / "runs" / NAME / args.criterion
    rows, times = [], {"free": [], "given": []}
    for name, (v, mass, height, sex, _, _) in TRIALS.items():
        t_m, td_m = _measured(name)
        common = ["--speed", str(v), "--mass", str(mass), "--height", str(height), "--sex", sex,
                  "--criterion", args.criterion, "--seed", str(args.seed)]  # fmt: skip
        free = _predict(root / f"{name}_free", common, args.fresh)
        fixed = [*common, "--period", str(t_m), "--double-support", str(td_m)]
        given = _predict(root / f"{name}_given", fixed, args.fresh)
        d = free.get("descriptors") or {}
        row = {
            "trial": name, "speed": v, "measured_period": t_m, "measured_double_support": td_m,
            "period": d.get("period"), "double_support": d.get("double_support"),
            "period_error": d["period"] / t_m - 1 if d else None,
            "double_support_error": d["double_support"] / td_m - 1 if d else None,
            "converged": free.get("converged"),
            "walks": (free.get("gait_checks") or {}).get("looks_like_walking"),
            "free_time_s": free.get("wall_time_s"), "given_time_s": given.get("wall_time_s"),
            "given_converged": given.get("converged"),
            "free_stages": [(s["stage"], s["iterations"]) for s in free.get("stages", [])],
        }  # fmt: skip
        row["period_ok"] = row["period_error"] is not None and abs(row["period_error"]) <= 0.05
        row["double_support_ok"] = (row["double_support_error"] is not None
                                    and abs(row["double_support_error"]) <= 0.25)  # fmt: skip
        rows.append(row)
        for key in times:
            if row[f"{key}_time_s"] is not None:
                times[key].append(row[f"{key}_time_s"])
        print(f"{name:15s} T {row['period'] or float('nan'):.4f} vs {t_m:.4f} "
              f"({100 * (row['period_error'] or float('nan')):+.1f} %)  Td "
              f"{row['double_support'] or float('nan'):.4f} vs {td_m:.4f} "
              f"({100 * (row['double_support_error'] or float('nan')):+.1f} %)  walks "
              f"{row['walks']}  time free {row['free_time_s']} s, given {row['given_time_s']} s",
              flush=True)  # fmt: skip
    medians = {k: statistics.median(v) if v else None for k, v in times.items()}
    ratio = medians["free"] / medians["given"] if all(medians.values()) else None
    print(
        f"median solve time: free {medians['free']} s, given {medians['given']} s, "
        f"ratio {ratio if ratio is None else round(ratio, 2)} (bar {BARS['cost_ratio']})"
    )
    result = {"environment": environment.environment(), "criterion": args.criterion,
              "seed": args.seed, "bars": BARS, "trials": rows, "median_time_s": medians,
              "cost_ratio": ratio}  # fmt: skip
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"written {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
