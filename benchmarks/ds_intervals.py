"""How the free problem's optimum depends on the double-support intervals of its grid:
``python benchmarks/ds_intervals.py [--speeds 1.1,1.2] [--counts 3,4,5,6]``.

For each speed, the reference subject (68.8 kg, 1.77 m, male, ``natural``, T and Td predicted)
is solved from its atlas entry (``solve_warm``, the full problem alone) on grids that differ
only in the double-support intervals ``N_ds`` of the 20 (``walk3d.problem.descriptors``; the
count is replaced for the run). It prints and records per run T, Td, iterations, the criterion
per metre evaluated on 801 samples of the cycle, its parts, and the largest support-row
violations between nodes (docs/descriptors.md, "The double-support intervals").
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "ds-intervals"


def run_one(speed: float, count: int) -> dict:
    import numpy as np

    from walk3d.campaign.atlas import atlas_settings
    from walk3d.pipeline import body_for, with_predicted
    from walk3d.problem import descriptors
    from walk3d.results.evaluate import evaluate_cycle
    from walk3d.solve.atlas import load_atlas
    from walk3d.solve.solver import forget_solvers
    from walk3d.solve.starts import solve_warm

    a = load_atlas("male", "natural")
    i = int(np.argmin(np.abs(a.speeds - speed)))
    s0 = (float(a.periods[i]), float(a.double_supports[i]))
    settings = atlas_settings("male", "natural").replace(
        speed=float(a.speeds[i]), period=s0[0], double_support=s0[1]
    )
    default = descriptors.ds_intervals
    descriptors.ds_intervals = lambda nodes: count
    try:
        forget_solvers()
        t0 = time.perf_counter()
        out = solve_warm(settings, a.x[i], s0=s0)
        wall = time.perf_counter() - t0
    finally:
        descriptors.ds_intervals = default
        forget_solvers()
    done = with_predicted(settings, out.descriptors)
    ev = evaluate_cycle(body_for(done), done, out.x, n_samples=801)
    stride = done.gait.speed * done.gait.period
    w = ev.criteria["C_weighted"]
    viol = ev.cycle_violations
    return {"speed": float(a.speeds[i]), "ds_intervals": count, "converged": out.converged,
            "iterations": out.iterations, "solve_s": round(wall, 1),
            "period": done.gait.period, "double_support": done.gait.double_support,
            "criterion_per_metre": w["total"] / stride,
            "parts_per_metre": {k: v / stride for k, v in w["parts"].items()},
            "cop_outside_bw_m": viol.get("cop_bw_m"),
            "friction_bw": viol.get("friction_bw")}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--speeds", default="1.1,1.2", help="Reference-subject speeds, m/s.")
    ap.add_argument("--counts", default="3,4,5,6", help="Double-support intervals of 20.")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args()
    rows = []
    for v in (float(x) for x in args.speeds.split(",")):
        for n in (int(x) for x in args.counts.split(",")):
            r = run_one(v, n)
            rows.append(r)
            verdict = "converged" if r["converged"] else "NOT converged"
            print(f"{r['speed']:.2f} m/s  N_ds {n}  T {r['period']:.3f}"
                  f"  Td {r['double_support']:.3f}  {r['iterations']:4d} its"
                  f"  {r['criterion_per_metre']:.3f} per m"
                  f"  CoP outside {r['cop_outside_bw_m']:.3f} BW·m  {verdict}",
                  flush=True)  # fmt: skip
    path = environment.output_path(args, NAME)
    environment.write(path, {"environment": environment.environment(), "runs": rows})
    print(f"written {path}")


if __name__ == "__main__":
    main()
