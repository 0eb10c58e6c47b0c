"""Campaign throughput: ``python benchmarks/campaign.py [--starts K] [--max-iter N]``.

Runs the same multi-start campaign (default prediction settings, seeds 0..K-1) once per worker
count on a local Dask cluster and reports starts per minute. The wall time counts everything a
user waits for: cluster start-up, one model build per worker, the solves and the ranking; the
solve-only rate (summed solver wall time) is reported too. Each run uses a fresh temporary
folder. Results go to stdout and, as JSON, to ``benchmarks/runs/campaign-<UTC time>.json``
(git-ignored), or with ``--reference`` to the committed ``benchmarks/reference/campaign.json``;
the result's ``"environment"`` records where it ran (``benchmarks/environment.py``; its BLAS is
the workers').
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import environment  # noqa: E402  (benchmarks/environment.py, next to this script)

NAME = "campaign"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    ap.add_argument("--criterion", choices=("tor", "en"), default="tor")
    ap.add_argument("--nodes", type=int, default=20)
    ap.add_argument("--max-iter", type=int, default=None, help="default: the settings' default")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    out = environment.output_path(args, NAME)

    from walk3d.campaign import run_campaign
    from walk3d.problem.settings import PredictionSettings
    from walk3d.solve.solver import compiled_status

    extra = {} if args.max_iter is None else {"max_iter": args.max_iter}
    settings = PredictionSettings(criterion=args.criterion, nodes=args.nodes, **extra)
    compiled = compiled_status(settings)["compiled"]
    print(f"compiled derivatives in the cache: {', '.join(compiled) or 'none'} (walk3d compile)")
    header = environment.environment()  # at the start: the commit and date this run began at
    runs = []
    for workers in (int(w) for w in args.workers.split(",")):
        with tempfile.TemporaryDirectory(prefix="walk3d-campaign-bench-") as tmp:
            t0 = time.perf_counter()
            report = run_campaign(settings, args.starts, 0, Path(tmp) / "c", workers=workers,
                                  progress=False)  # fmt: skip
            wall = time.perf_counter() - t0
            # the BLAS the workers' IPOPT used (walk3d.solve.blas), from the first start's summary
            first = Path(tmp) / "c" / "starts" / "seed_0" / "summary.json"
            blas = json.loads(first.read_text())["blas"] if first.is_file() else None
        solve_s = sum(r["wall_time_s"] or 0.0 for r in report.rows)
        run = {
            "workers": workers,
            "starts": args.starts,
            "wall_time_s": round(wall, 2),
            "starts_per_minute": round(60 * args.starts / wall, 2),
            "solve_time_s": round(solve_s, 2),
            "blas": blas,
            "converged": report.converged,
            "errors": report.errors,
        }
        runs.append(run)
        print(f"{workers} worker(s): {args.starts} starts in {wall:7.1f} s = "
              f"{run['starts_per_minute']:6.2f} starts/min (solves {solve_s:.1f} s, "
              f"{report.converged} converged, {report.errors} errors)", flush=True)  # fmt: skip
    if len(runs) > 1:
        print(f"speed-up {runs[-1]['workers']} vs {runs[0]['workers']} workers: "
              f"{runs[-1]['starts_per_minute'] / runs[0]['starts_per_minute']:.2f}x")  # fmt: skip
    # the BLAS the workers' IPOPT used (this process never loads IPOPT)
    header["blas"] = next((r["blas"] for r in runs if r["blas"]), "not recorded by the starts")
    report_json = {environment.KEY: header, "settings": settings.model_dump(),
                   "compiled_derivatives": compiled, "runs": runs}  # fmt: skip
    environment.write(out, report_json)
    print(f"written {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
