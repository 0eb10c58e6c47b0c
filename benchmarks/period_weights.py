"""How the criterion's weights set the predicted period: ``python benchmarks/period_weights.py
[--weights WEIGHTS ...] [--trials falisse,subject01,winter] [--sensitivity] [--handover]``.

Each ``--weights`` item (``base``, or changes like ``jerk=1`` or ``jerk=1,impact=3``) is applied
to the ``natural`` preset; for each measured trial the reference-subject problem (dynamic
similarity) is solved warm from the atlas start that ``walk3d predict`` would take, with T and Td
predicted (with the free landing, as ``walk3d predict`` predicts them; ``--handover``: with the
handover instead), and the predicted T and Td are compared with the measured ones
(docs/descriptors.md, "The period and the criterion"). ``--sensitivity`` instead halves and
doubles every weight on Winter's case. Needs no compiled derivatives for the changed criteria
(slower, same result).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "period-weights"
TRIALS = {
    # name: (V, mass, height, sex, measured T, measured Td); as benchmarks/descriptors.py
    "falisse": (1.2704745, 62.0, 1.70, "female", 1.070785, 0.146530),
    "subject01": (1.12, 72.6, 1.80, "male", 1.235, 0.17),
    "winter": (1.325, 68.8, 1.77, "male", 1.1396, 0.114),
}
"""Falisse's T and Td are those ``walk3d.trials.descriptors`` reads from its ``gait_1`` files."""


def weights_for(change: str, base: dict[str, float]) -> str:
    """The canonical criterion of ``base`` with ``change`` (``k=v,...`` or ``base``) applied."""
    from walk3d.model import terms

    w = dict(base)
    for kv in change.split(","):
        if kv != "base":
            k, v = kv.split("=")
            w[k] = float(v)
    return terms.canonical(",".join(f"{k}={v:g}" for k, v in w.items()))


def run_one(criterion: str, trial: str, handover: bool = False) -> dict:
    import numpy as np

    from walk3d import api
    from walk3d.pipeline import body_for, summarize, with_predicted
    from walk3d.problem import similarity
    from walk3d.results.evaluate import evaluate_cycle, make_prediction
    from walk3d.solve import atlas
    from walk3d.solve.solver import forget_solvers
    from walk3d.solve.starts import solve_warm

    v, mass, height, sex, t_m, td_m = TRIALS[trial]
    ref, scale = similarity.reference_problem(
        api.settings(v, mass=mass, height=height, sex=sex, threads=1)
    )
    found, why = atlas.candidates(ref)  # the natural preset's atlas, as walk3d predict's
    if not found:
        raise SystemExit(f"no atlas start: {why}")
    start = found[0]
    t0 = time.perf_counter()
    ref = ref.replace(criterion=criterion, handover=handover)
    out = solve_warm(ref, start.x, s0=(start.period, start.double_support))
    forget_solvers()
    done = with_predicted(ref, out.descriptors)
    ev = evaluate_cycle(body_for(done), done, out.x)
    summary = summarize(done, 0, out, ev, "ipopt")
    checks = make_prediction(ev.prediction_arrays, summary).summary["gait_checks"]
    root = float(np.sqrt(scale))  # the subject's times are the reference's times √s
    t, td = out.descriptors["period"] * root, out.descriptors["double_support"] * root
    return {"trial": trial, "criterion": criterion, "converged": out.converged,
            "iterations": out.iterations, "period": t, "double_support": td,
            "period_error": t / t_m - 1, "double_support_error": td / td_m - 1,
            "walks": checks["looks_like_walking"],
            "peak_vertical_grf_bw": checks["peak_vertical_grf_bw"],
            "wall_s": round(time.perf_counter() - t0, 1)}  # fmt: skip


def main() -> None:
    from walk3d.model import terms

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--weights", nargs="*", default=["base", "accel=1", "jerk=1", "impact=2.5"])
    ap.add_argument("--trials", default="falisse,subject01,winter")
    ap.add_argument("--sensitivity", action="store_true")
    ap.add_argument("--handover", action="store_true",
                    help="predict T and Td with the handover in the problem (walk3d predict "
                    "predicts them with the free landing, walk3d.solve.landing)")  # fmt: skip
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args()
    base = dict(terms.PRESETS["natural"])
    if args.sensitivity:
        changes = ["base"] + [f"{k}={v * f:g}" for k, v in base.items() for f in (0.5, 2.0)]
        trials = ["winter"]
    else:
        changes, trials = args.weights, args.trials.split(",")
    rows = []
    for change in changes:
        for trial in trials:
            r = run_one(weights_for(change, base), trial, args.handover) | {"change": change}
            rows.append(r)
            print(f"{change:22s} {trial:10s} T {100 * r['period_error']:+6.2f} %  Td "
                  f"{100 * r['double_support_error']:+6.1f} %  peak Fy "
                  f"{r['peak_vertical_grf_bw']:.2f} BW  {'walks' if r['walks'] else 'NO WALK'}"
                  f"{'' if r['converged'] else '  NOT converged'}", flush=True)  # fmt: skip
    path = environment.output_path(args, NAME)
    environment.write(path, {"environment": environment.environment(), "base": base,
                             "handover": args.handover, "runs": rows})  # fmt: skip
    print(json.dumps({"written": str(path)}))


if __name__ == "__main__":
    main()
