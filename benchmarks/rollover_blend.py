"""The stance foot's roll-over moved from walk3d's arc toward a subject's measured path, in steps.

    python benchmarks/rollover_blend.py CALIB.json OUT_DIR --speed V --period T \
        --double-support TD --mass KG --height M --sex S [--steps 0.25,0.5] [--components xy]
        [--arc RADIUS,CENTRE,ANKLE]

CALIB.json is ``walk3d calibrate``'s file of the same trial. At each step ``a`` the ankle path
of the roll-over is ``(1 − a)·arc + a·measured`` at the calibration's knots, in the components
named (x fore-aft, y up, z lateral; the others stay the arc's), and the prediction (T and Td
given) starts from the previous step's solution. Each step's result folder is
``OUT_DIR/a<step>``, ``OUT_DIR/a0.00`` the default's; score them with
``../shared/tools/realism.py``. It asks whether the foot's rolling geometry is what holds the
stance knee in loading (docs/fitting.md, "The model element").

With ``--arc`` the target path is not the calibration's but a rolling arc (radius and centre
forward in foot lengths, as ``body/data/parameters.toml``; the ankle's height above the floor
at foot flat in m, 0 for the body's own) at the calibration's knots.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np


def blended_paths(
    calib: dict, body, steps: list[float], components: str, arc: tuple | None = None
) -> list[tuple]:
    """``(step, s knots, ankle path (n, 3))`` of each step."""
    from walk3d.body.rollover import arc_ankle_path

    s = np.array(calib["rollover"]["s"], dtype=float)
    measured = np.array(calib["rollover"]["ankle_m"], dtype=float)
    if arc is not None:
        fl = body.foot.length
        measured = arc_ankle_path(2 * np.arcsin(s), arc[0] * fl, arc[1] * fl,
                                  arc[2] or body.foot.ankle_height)  # fmt: skip
    arc = np.array([[float(c) for c in body.rollover.evaluate(float(k))[0]] for k in s])
    keep = [i for i, c in enumerate("xyz") if c not in components]
    measured[:, keep] = arc[:, keep]
    return [(a, s, (1.0 - a) * arc + a * measured) for a in steps]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("calibration")
    ap.add_argument("out")
    for name in ("speed", "period", "double-support", "mass", "height"):
        ap.add_argument(f"--{name}", type=float, required=True)
    ap.add_argument("--sex", default="female")
    ap.add_argument("--steps", default="0.25,0.5")
    ap.add_argument("--components", default="xy")
    ap.add_argument("--arc", default=None, help="RADIUS,CENTRE,ANKLE: an arc as the target")
    a = ap.parse_args()

    from walk3d import pipeline
    from walk3d.api import settings
    from walk3d.problem.settings import body_for

    calib = json.loads(Path(a.calibration).read_text())
    base = settings(a.speed, a.period, a.double_support, mass=a.mass, height=a.height, sex=a.sex)
    out = Path(a.out)
    steps = [float(v) for v in a.steps.split(",")]
    pred = pipeline.predict(base, 0, out_dir=out / "a0.00")
    print(f"a 0.00: {pred.summary['status']}, C_weighted {_criterion(pred):.2f}", flush=True)
    arc = tuple(float(v) for v in a.arc.split(",")) if a.arc else None
    for step, s, ankle in blended_paths(calib, body_for(base), steps, a.components, arc):
        x = np.array(pred.summary["coefficients"]["x"])
        given = base.replace(rollover_s=tuple(map(float, s)),
                             rollover_ankle=tuple(tuple(map(float, p)) for p in ankle))  # fmt: skip
        t0 = time.perf_counter()
        pred = pipeline.predict(given, 0, out_dir=out / f"a{step:.2f}", warm_from=x)
        print(f"a {step:.2f}: {pred.summary['status']}, {pred.summary.get('iterations')} "
              f"iterations, C_weighted {_criterion(pred):.2f}, "
              f"{time.perf_counter() - t0:.0f} s", flush=True)  # fmt: skip


def _criterion(pred) -> float:
    return float(pred.summary["objective"]["C_weighted"]["total"])


if __name__ == "__main__":
    main()
