"""The handover stage over the atlas's speeds: ``python benchmarks/landing.py [--sexes
male,female] [--verify]``.

For every entry of the shipped atlas (reference subject, 68.8 kg, 1.77 m, ``natural``) the
second of ``walk3d.solve.landing``'s solves runs as ``walk3d predict`` runs it: the handover
problem at the entry's own T and Td, warm from the entry (the free landing's optimum), at most
``LANDING_MAX_ITER`` iterations. It records per speed: converged, iterations, wall time, looks
like walking (and the vertical-force humps), peak vertical GRF. ``--verify`` also writes each
converged cycle and runs ``walk3d verify``'s check on it (needs ``walk3d[opensim]``): the pelvis
residual-force peaks and whether every bar holds (docs/opensim.md).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "landing"


def _residuals(pred, folder: Path) -> dict:
    """``walk3d verify``'s pelvis residual peaks (% BW) and verdict for ``pred``."""
    from walk3d.results.prediction import save_prediction
    from walk3d.verify.run import verify_folder

    v = verify_folder(save_prediction(pred, folder))
    peaks = [round(r.peak_pct_bw, 2) for r in v.whole.residuals]
    return {"residual_peak_pct_bw": peaks, "passes": bool(v.passes())}


def run_one(sex: str, i: int, verify: bool) -> dict:
    from walk3d import api
    from walk3d.pipeline import body_for, summarize
    from walk3d.results.evaluate import evaluate_cycle, make_prediction
    from walk3d.solve import atlas
    from walk3d.solve.landing import LANDING_MAX_ITER
    from walk3d.solve.solver import forget_solvers
    from walk3d.solve.starts import solve_warm

    a = atlas.load_atlas(sex, "natural")
    v, t, td = float(a.speeds[i]), float(a.periods[i]), float(a.double_supports[i])
    s = api.settings(v, period=t, double_support=td, mass=68.8, height=1.77, sex=sex,
                     threads=1, handover=True)  # fmt: skip
    t0 = time.perf_counter()
    out = solve_warm(s, a.x[i], origin="the atlas entry", max_iter=LANDING_MAX_ITER)
    wall = time.perf_counter() - t0
    forget_solvers()
    ev = evaluate_cycle(body_for(s), s, out.x)
    pred = make_prediction(ev.prediction_arrays, summarize(s, 0, out, ev, "ipopt"))
    g = pred.summary["gait_checks"]
    row = {"sex": sex, "speed": v, "period": t, "double_support": td,
           "converged": out.converged, "iterations": out.iterations, "wall_s": round(wall, 1),
           "walks": g["looks_like_walking"], "fy_humps_bw": g["fy_first_dip_second_bw"],
           "peak_vertical_grf_bw": g["peak_vertical_grf_bw"]}  # fmt: skip
    if verify and out.converged:
        with tempfile.TemporaryDirectory() as tmp:
            row["verify"] = _residuals(pred, Path(tmp) / "cycle")
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sexes", default="male,female")
    ap.add_argument("--verify", action="store_true", help="also run walk3d verify on each")
    environment.add_output_arguments(ap, NAME)
    args = ap.parse_args()
    from walk3d.solve import atlas

    rows = []
    for sex in args.sexes.split(","):
        for i in range(len(atlas.load_atlas(sex, "natural").speeds)):
            r = run_one(sex, i, args.verify)
            rows.append(r)
            humps = "/".join(f"{f:.2f}" for f in r["fy_humps_bw"])
            res = r.get("verify") or {}
            print(f"{sex:6s} {r['speed']:.2f} m/s  {r['iterations']:3d} it  {r['wall_s']:5.1f} s  "
                  f"{'converged' if r['converged'] else 'NOT converged'}  "
                  f"{'walks' if r['walks'] else 'NO WALK'}  Fy humps {humps} BW"
                  + (f"  residual peaks {res.get('residual_peak_pct_bw')} % BW" if res else ""),
                  flush=True)  # fmt: skip
    path = environment.output_path(args, NAME)
    environment.write(path, {"environment": environment.environment(), "runs": rows})
    print(json.dumps({"written": str(path)}))


if __name__ == "__main__":
    main()
