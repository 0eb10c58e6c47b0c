"""Whether walk3d's criterion prefers equal steps, with no change: ``python benchmarks/limp.py
[--d0 0.03] [--reference]``.

On the paper's subject (V 1.3806 m/s, T 1.08 s and Td 0.16 s given, ``natural``, seed 0) it
solves the half cycle, then the full cycle with no change three times:

* ``mirrored``: from the half cycle mirrored, steps equal (``d`` = 0): the symmetric gait;
* ``shifted``: from the same start with the step shift ``d`` = ``--d0`` m, steps free;
* ``held``: steps held equal (``equal_steps``), from the mirrored start with the left side's
  series perturbed by ±0.01 (seeded), to see whether other asymmetries pay.

Each records the end's ``d``, its status and iterations, the step lengths, ``C_weighted``,
``C_tor``, ``C_step_asymmetry`` and the cycle's contact residual and centre-of-pressure excess
on the 101 samples. docs/what-if.md ("The criterion prefers a limp") has the figures.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "limp"


def _row(body, settings, outcome) -> dict:
    from walk3d.problem import layout
    from walk3d.results.asymmetry import asymmetry
    from walk3d.results.evaluate import evaluate_cycle

    ev = evaluate_cycle(body, settings, outcome.x)
    crit = ev.criteria
    return {
        "status": outcome.record["status"],
        "iterations": outcome.record["iterations"],
        "d_m": float(outcome.x[layout.I_STEP_SHIFT]),
        "steps_m": asymmetry(ev.prediction_arrays, body.mass)["step_length_m"],
        "C_weighted": crit["C_weighted"]["total"],
        "C_tor": crit["C_tor"]["total"],
        "C_step_asymmetry": crit["C_step_asymmetry"]["total"],
        "contact_residual_m": ev.contact_residual_m,
        "cop_bw_m": ev.cycle_violations["cop_bw_m"],
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d0", type=float, default=0.03, help="the shifted start's d, m")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    from walk3d.api import settings as make_settings
    from walk3d.problem import layout
    from walk3d.problem.settings import body_for
    from walk3d.solve import run_solver
    from walk3d.solve.full_cycle import mirrored_start, solve_full_cycle

    settings = make_settings(1.3806, 1.08, 0.16)
    body = body_for(settings)
    half = run_solver(settings, 0)
    runs: dict = {"half": {"status": half.status, "iterations": half.iterations}}
    start = mirrored_start(half.x)
    runs["mirrored"] = _row(body, settings, solve_full_cycle(settings, half))
    shifted = start.copy()
    shifted[layout.I_STEP_SHIFT] = args.d0
    runs["shifted"] = _row(body, settings, solve_full_cycle(settings, half, start=shifted))
    held = start.copy()
    sided = slice(layout.N_X + 4 * layout.N_COEF, layout.N_X + 14 * layout.N_COEF)
    held[sided] += np.random.default_rng(1).uniform(-0.01, 0.01, sided.stop - sided.start)
    equal = settings.replace(equal_steps=True)
    runs["held"] = _row(body, equal, solve_full_cycle(equal, half, start=held))
    for name, r in runs.items():
        print(name, r, flush=True)
    result = {environment.KEY: environment.environment(), "d0_m": args.d0, "runs": runs}
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
