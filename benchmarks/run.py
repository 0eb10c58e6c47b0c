"""Speed benchmark of one prediction: ``python benchmarks/run.py [--starts K] [--baseline]``.

Runs K random starts (seeds 0..K-1) of the default prediction (paper subject, C_tor) with the
model build cached, and reports the median wall time per converged solve and the converged
share. With ``--baseline`` it also runs the paper-style SLSQP (finite differences) on seed 0 and
reports the speed ratio on that same start. Results go to stdout and, as JSON, to
``benchmarks/results/solve.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=20)
    ap.add_argument("--criterion", choices=("tor", "en"), default="tor")
    ap.add_argument("--nodes", type=int, default=20)
    ap.add_argument("--threads", type=int, default=1, help="threads per solve (CasADi map)")
    ap.add_argument("--baseline", action="store_true", help="also run SLSQP on seed 0")
    ap.add_argument("--baseline-time-limit", type=float, default=900.0)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "solve.json"))
    args = ap.parse_args(argv)

    from walk3d.problem.settings import PredictionSettings
    from walk3d.solve import ipopt

    settings = PredictionSettings(criterion=args.criterion, nodes=args.nodes, threads=args.threads)
    t0 = time.perf_counter()
    ipopt.build_solver(settings)
    build = time.perf_counter() - t0
    print(f"model build: {build:.1f} s (not counted per solve)")
    runs = []
    for seed in range(args.starts):
        out = ipopt.solve(settings, seed)
        runs.append({"seed": seed, "converged": out.converged, "status": out.status,
                     "iterations": out.iterations, "wall_time_s": out.wall_time_s})  # fmt: skip
        print(f"seed {seed:3d}: {out.status:32s} {out.iterations:5d} it  {out.wall_time_s:7.1f} s",
              flush=True)  # fmt: skip
    conv = [r["wall_time_s"] for r in runs if r["converged"]]
    report = {
        "settings": settings.model_dump(),
        "build_time_s": build,
        "starts": args.starts,
        "converged": len(conv),
        "converged_share": len(conv) / max(args.starts, 1),
        "median_time_per_converged_solve_s": statistics.median(conv) if conv else None,
        "runs": runs,
    }
    print(f"converged {len(conv)}/{args.starts}; median per converged solve: "
          f"{report['median_time_per_converged_solve_s']}")  # fmt: skip
    if args.baseline:
        from walk3d.solve.baseline import slsqp_solve

        base = slsqp_solve(settings, 0, time_limit_s=args.baseline_time_limit)
        ours = runs[0]["wall_time_s"]
        report["baseline"] = {"status": base.status, "converged": base.converged,
                              "wall_time_s": base.wall_time_s, "stages": base.stages}  # fmt: skip
        ratio = base.wall_time_s / ours
        bound = "" if base.converged else " (baseline did not converge: a lower bound)"
        report["speedup_vs_baseline_seed0"] = ratio
        print(f"baseline SLSQP-FD seed 0: {base.status}, {base.wall_time_s:.0f} s; "
              f"speed-up {ratio:.1f}x{bound}")  # fmt: skip
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
