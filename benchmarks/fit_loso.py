"""Leave-one-source-out fits of the criterion (issue #59), in one command.

    python benchmarks/fit_loso.py [--parameters impact arms spin head accel]
                                  [--generations 6] [--popsize 6] [--all] [--runs DIR]
                                  [--reference]

For each of the three sources of ``benchmarks/fit_trials.toml`` (Falisse ``gait_1``, Winter,
OpenSim subject01) it runs ``walk3d fit-criterion`` on the other two with that source held out,
in ``benchmarks/runs/fit/loso-<source>/`` (git-ignored; ``--runs`` another folder; a rerun
resumes each fold). ``--all``
adds a fit on all three (``benchmarks/runs/fit/all/``). It then prints, per fold, the start's
(``natural``) and the best weighting's score on every source, held out or not, and the fitted
weights; the table and the environment go to ``benchmarks/runs/fit_loso-<stamp>.json``
(``--reference``: ``benchmarks/reference/fit_loso.json``). Scores: ``walk3d validate``'s
``score.json`` (the yardstick's errors over their bars, 1 = at the bar; lower is better).
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

ROOT = Path(__file__).resolve().parents[1]
TRIALS = ROOT / "benchmarks" / "fit_trials.toml"
SOURCES = ("falisse", "winter", "subject01")


def run_fold(out: Path, held: str | None, a: argparse.Namespace) -> dict:
    """One fit (resumed when its folder exists); its ``result.json``."""
    cmd = ["walk3d", "fit-criterion", str(TRIALS), "--generations", str(a.generations),
           "--popsize", str(a.popsize), "--out", str(out)]  # fmt: skip
    for p in a.parameters:
        cmd += ["--parameter", p]
    if held:
        cmd += ["--hold-out", held]
    subprocess.run(cmd, check=True)
    return json.loads((out / "result.json").read_text())


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parameters", nargs="+", default=["impact", "arms", "spin", "head", "accel"])
    ap.add_argument("--generations", type=int, default=6)
    ap.add_argument("--popsize", type=int, default=6)
    ap.add_argument("--all", action="store_true", help="also fit on all three sources")
    ap.add_argument(
        "--runs",
        type=Path,
        default=ROOT / "benchmarks" / "runs" / "fit",
        help="folder of the folds (one fit folder each)",
    )
    environment.add_output_arguments(ap, "fit_loso")
    a = ap.parse_args(argv)
    path = environment.output_path(a, "fit_loso")
    runs = a.runs
    folds = [(f"loso-{s}", s) for s in SOURCES] + ([("all", None)] if a.all else [])
    result = {"environment": environment.environment(), "parameters": a.parameters,
              "generations": a.generations, "popsize": a.popsize, "folds": {}}  # fmt: skip
    print(f"{'fold':15s} {'source':10s} {'start':>7s} {'best':>7s}  held out")
    for name, held in folds:
        r = run_fold(runs / name, held, a)
        result["folds"][name] = r
        for key, start in r["per_trial"]["start"].items():
            source = key.split("/")[0]
            print(f"{name:15s} {source:10s} {start:7.3f} {r['per_trial']['best'][key]:7.3f}  "
                  f"{'yes' if source == held else ''}")  # fmt: skip
        print(f"{'':15s} best {r['best']}")
    environment.write(path, result)
    print(f"written to {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
