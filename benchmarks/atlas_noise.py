"""What the noise of a campaign's atlas starts costs in iterations:
``python benchmarks/atlas_noise.py [--perturbations 0.25,0.1,0.05,0.025] [--seeds 8]``.

For each ``--perturbation`` value, seeds 1..N of ``walk3d.predict`` on the paper's subject
(68.8 kg, 1.77 m, male, 1.3806 m/s, T and Td predicted, ``natural``, one thread) start from the
atlas plus ``ATLAS_NOISE_FRACTION · perturbation`` of uniform noise (walk3d.solve.starts). It
prints and records iterations, the optimum per metre and whether each walks (docs/starts.md,
"Noise"). Iteration counts do not depend on the machine's load; times do.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "atlas-noise"


def run_one(perturbation: float, seed: int) -> dict:
    import walk3d
    from walk3d.solve.starts import ATLAS_NOISE_FRACTION

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # recorded as converged False
        pred = walk3d.predict(speed=1.3806, seed=seed, perturbation=perturbation, threads=1)
    s = pred.summary
    return {"perturbation": perturbation, "amplitude": ATLAS_NOISE_FRACTION * perturbation,
            "seed": seed, "iterations": s["iterations"], "converged": s["converged"],
            "walks": s["gait_checks"]["looks_like_walking"],
            "criterion_per_metre": s["objective"]["C_weighted"]["total"] / s["stride_length_m"],
            "wall_s": round(time.perf_counter() - t0, 1)}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--perturbations", default="0.25,0.1,0.05,0.025")
    ap.add_argument("--seeds", type=int, default=8, help="Seeds 1..N per perturbation.")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args()
    rows = []
    for p in (float(x) for x in args.perturbations.split(",")):
        its = []
        for seed in range(1, args.seeds + 1):
            r = run_one(p, seed)
            rows.append(r)
            its.append(r["iterations"])
            print(f"perturbation {p:g} (±{r['amplitude']:.4f})  seed {seed}  "
                  f"{r['iterations']:4d} its  {r['criterion_per_metre']:.4f} per m  "
                  f"{'walks' if r['walks'] else 'does not walk'}"
                  f"{'' if r['converged'] else '  NOT converged'}", flush=True)  # fmt: skip
        print(f"perturbation {p:g}: median {statistics.median(its):g} iterations", flush=True)
    path = environment.output_path(args, NAME)
    environment.write(path, {"environment": environment.environment(), "runs": rows})
    print(f"written {path}")


if __name__ == "__main__":
    main()
