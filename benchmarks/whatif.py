"""The what-if predictions of issue #43, one at a time: ``python benchmarks/whatif.py [--cases
normal,weak_r,...] [--reference]``.

Each case is ``walk3d predict --out DIR --period 1.08 --double-support 0.16 OPTIONS`` on the
paper's subject (V 1.3806 m/s, seed 0), in a fresh process with a shared model cache. It
records, per case, the wall time from process start to exit, convergence, the solve stages
(iterations and seconds: the half cycle, then the full cycle for a one-sided change), the
full cycle's time over the half cycle's, ``looks_like_walking``, the body mass, ``C_overload``,
the right ankle's range (deg), ``summary.json``'s ``asymmetry`` and the full cycle's step
shift ``d`` (m). docs/what-if.md has the
figures.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "whatif"
CASES: dict[str, list[str]] = {
    "normal": [],
    "full_cycle": ["--full-cycle"],
    "weak_right_calf": ["--strength", "ankle_r=0.3"],
    "weak_calves": ["--strength", "ankle=0.3"],
    "right_brace": ["--range", "ankle_dorsiflexion_r=-5:5"],
    "short_right_leg": ["--leg-length-difference", "-0.02"],
    "backpack": ["--added-mass", "torso=10"],
}
"""Each case's ``walk3d predict`` options (the issue's done-when list, and the normal gait)."""
GIVEN = ["--period", "1.08", "--double-support", "0.16"]


def one_case(out: Path, cache: Path, options: list[str]) -> dict:
    """``walk3d predict`` for one case in a child process; its figures from the result."""
    env = dict(os.environ, WALK3D_CACHE_DIR=str(cache), OPENBLAS_NUM_THREADS="1")
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--out", str(out), *GIVEN, *options]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    row: dict = {"wall_s": round(time.perf_counter() - t0, 2), "exit_code": proc.returncode}
    if not (out / "summary.json").is_file():
        return row | {"stderr_tail": proc.stderr[-400:]}
    import walk3d
    from walk3d.problem import layout

    pred = walk3d.load_result(out)
    s = pred.summary
    stages = [{"stage": st.get("stage"), "iterations": st.get("iterations"),
               "wall_time_s": round(st.get("wall_time_s", float("nan")), 2)}
              for st in s.get("stages", [])]  # fmt: skip
    ankle = np.degrees(pred.dof("ankle_dorsiflexion_r"))
    row.update(
        converged=s.get("converged"),
        problem=s.get("problem"),
        stages=stages,
        full_over_half=(round(stages[-1]["wall_time_s"] / stages[0]["wall_time_s"], 2)
                        if len(stages) > 1 and stages[-1]["stage"] == "full cycle" else None),
        looks_like_walking=s.get("gait_checks", {}).get("looks_like_walking"),
        body_mass_kg=s.get("body_mass_kg"),
        criterion=s["objective"]["C_weighted"]["total"],
        overload=(s["objective"].get("C_overload") or {}).get("total"),
        right_ankle_range_deg=[round(float(ankle.min()), 2), round(float(ankle.max()), 2)],
        asymmetry=s.get("asymmetry"),
        step_shift_m=(float(s["coefficients"]["x"][layout.I_STEP_SHIFT])
                      if s.get("problem") == "full cycle" else None),
    )  # fmt: skip
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated, of: "
                    + ", ".join(CASES))  # fmt: skip
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args(argv)
    names = [c.strip() for c in args.cases.split(",") if c.strip()]
    unknown = [c for c in names if c not in CASES]
    if unknown:
        print(f"whatif.py: unknown case {unknown[0]!r}; known: {', '.join(CASES)}", file=sys.stderr)
        return 2
    runs = {}
    with tempfile.TemporaryDirectory(prefix="walk3d-whatif-") as tmp:
        root = Path(tmp)
        for name in names:
            runs[name] = one_case(root / name, root / "cache", CASES[name])
            r = runs[name]
            print(f"{name}: {r['wall_s']} s, converged {r.get('converged')}, stages "
                  f"{r.get('stages')}, walks {r.get('looks_like_walking')}",
                  flush=True)  # fmt: skip
    result = {
        environment.KEY: environment.environment(),
        "command": ["walk3d", "predict", "--out", "DIR", *GIVEN, "CASE OPTIONS"],
        "cases": {n: CASES[n] for n in names},
        "runs": runs,
    }
    path = environment.output_path(args, NAME)
    environment.write(path, result)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
