"""Speed benchmark of one prediction: ``python benchmarks/run.py [--starts K] [--no-baseline]``.

Runs K random starts (seeds 0..K-1) of the default prediction (paper subject, C_tor) with the
model build cached, and reports the median wall time per converged solve, the converged share
and how many converged starts look like walking (:mod:`walk3d.results.gait_checks`). Right
after IPOPT's solve of the first seed it runs the paper-style baseline (SLSQP with finite
differences) on that same start and reports the speed ratio (``--no-baseline`` skips it).
Results go to stdout and, as JSON (rewritten after every start), to
``benchmarks/runs/run-<UTC time>.json`` (git-ignored), or with ``--reference`` to the committed
``benchmarks/reference/run.json``; the result's ``"environment"`` records where it ran
(``benchmarks/environment.py``). ``python benchmarks/compare.py`` compares the newest run with
the reference.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import environment  # noqa: E402  (benchmarks/environment.py, next to this script)

NAME = "run"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0, help="seeds first-seed .. +K-1")
    ap.add_argument("--criterion", default="tor", help="tor, en, natural or weights")
    ap.add_argument("--nodes", type=int, default=20)
    ap.add_argument(
        "--threads",
        type=int,
        default=None,
        help="threads per solve (CasADi map; default: every core, as walk3d predict)",
    )
    ap.add_argument(
        "--no-baseline",
        dest="baseline",
        action="store_false",
        help="skip the SLSQP baseline on the first seed",
    )
    ap.add_argument("--baseline-time-limit", type=float, default=900.0)
    ap.add_argument(
        "--no-compile",
        dest="compile",
        action="store_false",
        help="keep the derivatives in CasADi's VM (default: compile them to C first, as "
        "walk3d compile, if a C compiler is found; not counted per solve)",
    )
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    out_path = environment.output_path(args, NAME)

    from walk3d.model import terms
    from walk3d.problem.settings import PredictionSettings, available_cores, body_for
    from walk3d.results.evaluate import evaluate_cycle
    from walk3d.results.gait_checks import walking_checks
    from walk3d.solve import ipopt

    threads = args.threads or min(available_cores(), 64)
    settings = PredictionSettings(criterion=args.criterion, nodes=args.nodes, threads=threads)
    compile_info = None
    if args.compile:
        from walk3d.solve.compiled import compiler
        from walk3d.solve.solver import compile_solver

        if compiler() is None:
            print("no C compiler: derivatives stay in CasADi's VM")
        else:
            compile_info = compile_solver(settings)
            print(f"compiled derivatives: {compile_info['compiled']} libraries in "
                  f"{compile_info['wall_time_s']:.0f} s (0 if already in the cache)")  # fmt: skip
    t0 = time.perf_counter()
    solver = ipopt.build_solver(settings)
    from_cache = solver.from_cache
    compiled_kinds = sorted(solver.compiled)
    solver.stage(solver.plan.first)
    first_stage = time.perf_counter() - t0  # a solve's first iteration could start here
    solver.stage("full")  # the default path's stages, so no solve below pays for a build
    build = time.perf_counter() - t0
    source = "SX functions from the model cache" if from_cache else "cold"
    source += f"; compiled derivatives: {', '.join(compiled_kinds) or 'none'}"
    source += f"; BLAS: {environment.blas_status()}"
    print(
        f"model build: {build:.1f} s ({source}; first stage ready after {first_stage:.1f} s; "
        "not counted per solve)"
    )
    # after the build: IPOPT is loaded and walk3d's BLAS switch has been made
    report: dict = {environment.KEY: environment.environment()}
    runs: list[dict] = []

    def summarize() -> None:
        conv = [r["wall_time_s"] for r in runs if r["converged"]]
        report.update({
            "settings": settings.model_dump(),
            "build_time_s": build,
            "first_stage_ready_s": first_stage,
            "build_from_cache": from_cache,
            "compiled_derivatives": compiled_kinds,
            "blas": environment.blas_status(),
            "compile": compile_info,
            "starts": len(runs),
            "converged": len(conv),
            "converged_share": len(conv) / max(len(runs), 1),
            "walking": sum(r["converged"] and r["looks_like_walking"] for r in runs),
            "issue_checks_pass": sum(r["converged"] and r["issue_checks"] for r in runs),
            "median_time_per_converged_solve_s": statistics.median(conv) if conv else None,
            "runs": runs,
        })  # fmt: skip
        environment.write(out_path, report)  # after every start

    def baseline() -> None:
        """SLSQP-FD on the first seed, right after IPOPT's solve of it (same start)."""
        from walk3d.solve.baseline import slsqp_solve

        base = slsqp_solve(settings, args.first_seed, time_limit_s=args.baseline_time_limit)
        ours = runs[0]["wall_time_s"]
        report["baseline"] = {"seed": args.first_seed, "status": base.status,
                              "converged": base.converged, "wall_time_s": base.wall_time_s,
                              "stages": base.stages}  # fmt: skip
        ratio = base.wall_time_s / ours
        if base.converged:
            note = ""
        elif base.status == "time limit reached":
            note = " (baseline stopped at its time limit unconverged: a lower bound)"
        else:
            ratio, note = None, " (baseline failed: no ratio)"
        report["speedup_vs_baseline_first_seed"] = ratio
        shown = "-" if ratio is None else f"{ratio:.1f}x"
        print(f"baseline SLSQP-FD seed {args.first_seed}: {base.status}, "
              f"{base.wall_time_s:.0f} s; speed-up {shown}{note}", flush=True)  # fmt: skip

    body = body_for(settings)
    for seed in range(args.first_seed, args.first_seed + args.starts):
        out = ipopt.solve(settings, seed)
        ev = evaluate_cycle(body, settings, out.x)
        g = settings.gait
        checks = walking_checks(ev.prediction_arrays, g.period, g.double_support, g.mass, g.speed)
        label = terms.label(settings.model.criterion)
        crit = ev.criteria[label]["total"]
        runs.append({"seed": seed, "converged": out.converged, "status": out.status,
                     "iterations": out.iterations, "attempts": out.attempts,
                     "wall_time_s": out.wall_time_s, "criterion": crit, "stages": out.stages,
                     "contact_residual_m": ev.contact_residual_m, **checks})  # fmt: skip
        print(f"seed {seed:3d}: {out.status:28s} {out.iterations:4d} it {out.wall_time_s:6.1f} s "
              f"{label} {crit:8.3f} knee {checks['knee_swing_max_deg']:4.0f} "
              f"hip {checks['hip_midstance_deg']:4.0f} mid-stance "
              f"walking {checks['looks_like_walking']}", flush=True)  # fmt: skip
        summarize()
        if args.baseline and len(runs) == 1:
            baseline()
            summarize()
    print(f"converged {report['converged']}/{args.starts} ({report['walking']} look like "
          f"walking); median per converged solve: "
          f"{report['median_time_per_converged_solve_s']}")  # fmt: skip
    environment.write(out_path, report)
    print(f"written {out_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
