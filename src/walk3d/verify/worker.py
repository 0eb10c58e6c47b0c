"""The OpenSim side of ``walk3d verify``, run as ``python -m walk3d.verify.worker SPEC.json``.

OpenSim's Python wheel ships a CasADi library under the same name as walk3d's own, and the two
cannot be loaded into one process (whichever loads second fails with undefined symbols). This
module therefore imports nothing of walk3d that imports CasADi, and :mod:`walk3d.verify.run`
calls it in a child process. ``SPEC.json`` holds::

    {"model": ".../model.osim", "motion": ".../motion.mot", "external_loads": ".../grf.xml",
     "out": "DIR", "points": {"right": ["calcn_r", [x, y, z]], ...},
     "replay": ".../motion.mot"}

It writes ``DIR/opensim_inverse_dynamics.sto`` (OpenSim's InverseDynamicsTool on the three
files, no low-pass filter, over the motion's whole time range) and ``DIR/points.npz``: each
point's global position ``(N, 3)`` at the samples of ``replay`` (default: the motion), with
the model posed by its coordinates (point kinematics, no inverse kinematics).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from walk3d.io.storage import read_storage

__all__ = ["ID_FILE", "POINTS_FILE", "main", "replay_points", "run_inverse_dynamics"]

ID_FILE = "opensim_inverse_dynamics.sto"
POINTS_FILE = "points.npz"


def _opensim():
    import opensim

    opensim.Logger.setLevelString("error")
    return opensim


def run_inverse_dynamics(model: str, motion: str, external_loads: str, out: str) -> Path:
    """OpenSim's InverseDynamicsTool on ``model`` + ``motion`` + ``external_loads``."""
    osim = _opensim()
    times = read_storage(motion).time
    tool = osim.InverseDynamicsTool()
    loaded = osim.Model(model)  # the tool keeps a raw pointer: hold the model until it ran
    tool.setModel(loaded)
    tool.setCoordinatesFileName(str(motion))
    tool.setExternalLoadsFileName(str(external_loads))
    tool.setLowpassCutoffFrequency(-1.0)
    tool.setStartTime(float(times[0]))
    tool.setEndTime(float(times[-1]))
    tool.setResultsDir(str(out))
    tool.setOutputGenForceFileName(ID_FILE)
    if not tool.run():
        raise RuntimeError("OpenSim's InverseDynamicsTool failed")
    del loaded
    return Path(out) / ID_FILE


def replay_points(
    model: str, motion: str, points: dict[str, tuple[str, list[float]]]
) -> dict[str, np.ndarray]:
    """Global positions ``(N, 3)`` of body-fixed points, the model posed at every sample."""
    osim = _opensim()
    m = osim.Model(model)
    state = m.initSystem()
    mot = read_storage(motion)
    coords = m.getCoordinateSet()
    handles = [coords.get(name) for name in mot.columns]
    degrees = bool(mot.in_degrees)
    rotational = [str(c.getMotionType()) == str(osim.Coordinate.Rotational) for c in handles]
    bodies = {k: (m.getBodySet().get(b), osim.Vec3(*p)) for k, (b, p) in points.items()}
    out = {k: np.zeros((mot.time.size, 3)) for k in points}
    for i, row in enumerate(mot.data):
        for coord, rot, value in zip(handles, rotational, row, strict=True):
            coord.setValue(state, float(np.radians(value) if rot and degrees else value), False)
        m.realizePosition(state)
        for k, (body, local) in bodies.items():
            g = body.findStationLocationInGround(state, local)
            out[k][i] = [g.get(0), g.get(1), g.get(2)]
    return out


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    spec = json.loads(Path(args[0]).read_text(encoding="utf-8"))
    out = Path(spec["out"])
    run_inverse_dynamics(spec["model"], spec["motion"], spec["external_loads"], str(out))
    replay = spec.get("replay", spec["motion"])
    points = replay_points(spec["model"], replay, spec.get("points", {}))
    np.savez(out / POINTS_FILE, **points)
    return 0


if __name__ == "__main__":
    sys.exit(main())
