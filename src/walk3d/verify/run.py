"""The OpenSim check of one prediction (``walk3d verify DIR``).

:func:`verify_folder` runs OpenSim's InverseDynamicsTool on the folder's ``model.osim`` +
``motion.mot`` + ``grf.xml`` (the cycle extended by samples of its neighbours,
:mod:`walk3d.verify.periodic`, so that no spline ends inside it) and poses ``model.osim`` at
every sample of ``motion.mot`` (in a child process, :mod:`walk3d.verify.worker`), then
compares:

* the flexion moments and pelvis residual forces with ``inverse_dynamics.sto``
  (:func:`walk3d.verify.compare.compare_generalized_forces`), over the whole cycle (the bars)
  and, for information, away from the touch-downs and the record's ends
  (:func:`walk3d.verify.compare.smooth_mask`);
* each stance foot's drift during foot-flat: the foot's point that touches the floor at foot
  flat (the roll-over's instantaneous centre at ``s = 0``), during the loaded samples within the
  settings' ``foot_flat_tolerance`` of flat (:func:`walk3d.verify.compare.largest_drift`).
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.io.storage import read_storage
from walk3d.verify.compare import (
    BARS,
    Bars,
    Comparison,
    compare_generalized_forces,
    foot_flat_mask,
    largest_drift,
    smooth_mask,
)
from walk3d.verify.periodic import periodic_records

__all__ = [
    "OpenSimMissing",
    "check_timeout",
    "Verification",
    "contact_point",
    "opensim_available",
    "verify_folder",
    "verify_prediction",
]

INSTALL_HINT = "pip install 'walk3d[opensim]'"


class OpenSimMissing(RuntimeError):
    """OpenSim's Python package is not installed."""

    def __init__(self) -> None:
        super().__init__(f"OpenSim's Python package is not installed: {INSTALL_HINT}")


MAX_TIMEOUT_S = 86400.0


def check_timeout(timeout: float) -> float:
    """``timeout`` (s) if positive and at most a day (OpenSim takes seconds; the operating
    system's wait overflows above about 2.1e6 s), else a one-line ValueError."""
    if not (isinstance(timeout, (int, float)) and 0 < timeout <= MAX_TIMEOUT_S):
        raise ValueError(
            f"the timeout must be a number of seconds above 0 and at most {MAX_TIMEOUT_S:g} "
            f"(a day), got {timeout}"
        )
    return float(timeout)


def opensim_available() -> bool:
    """Whether ``import opensim`` can work (found, not imported: see the worker)."""
    return importlib.util.find_spec("opensim") is not None


@dataclass(frozen=True)
class Verification:
    whole: Comparison
    """Every sample of the cycle: what the bars judge."""
    smooth: Comparison
    """Away from the touch-downs and the ends (information)."""
    drift_m: dict[str, float]
    """``{"right", "left"}``: the stance foot's largest drift during foot-flat, replayed on
    the model, m."""
    walk3d_drift_m: dict[str, float]
    """The same, in walk3d's own kinematics."""
    notes: list[str] = field(default_factory=list)

    def passes(self, bars: Bars = BARS) -> bool:
        drift = all(d < bars.drift_max_m for d in self.drift_m.values())  # NaN fails
        return self.whole.passes(bars) and drift


def contact_point(body: BodyModel, side: str) -> np.ndarray:
    """The foot point (foot frame) touching the floor at foot flat: the roll-over's
    instantaneous centre of rotation at ``s = 0``, ``(-dy/dθ, -y, 0)``."""
    value, d1, _ = body.rollover.evaluate(0.0)
    point = np.array([-0.5 * float(d1[1]), -float(value[1]), 0.0])  # dθ = 2 ds at s = 0
    return point * (np.array([1.0, 1.0, -1.0]) if side == "l" else 1.0)


def _foot_pitch(q: np.ndarray) -> np.ndarray:
    """A stance foot turns about the global z axis only: its angle, rad (toes up +)."""
    return 2.0 * np.arctan2(q[:, 3], q[:, 0])


def _walk3d_points(pred: Any, body: BodyModel, segment: int, local: np.ndarray) -> np.ndarray:
    from walk3d.kinematics import quaternion

    r = quaternion.to_matrix(pred.segment_orientation[:, segment])
    com = np.asarray(body.segments[segment].com)
    return pred.segment_com_position[:, segment] + r @ (local - com)


def _run_worker(spec: dict, workdir: Path, timeout: float) -> None:
    if not opensim_available():
        raise OpenSimMissing()
    path = workdir / "spec.json"
    path.write_text(json.dumps(spec), encoding="utf-8")
    src = str(Path(__file__).resolve().parents[2])  # where this walk3d is imported from
    env = dict(os.environ, OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
    env["PYTHONPATH"] = os.pathsep.join(p for p in (env.get("PYTHONPATH"), src) if p)
    done = subprocess.run(
        [sys.executable, "-m", "walk3d.verify.worker", str(path)],
        cwd=workdir, env=env, capture_output=True, text=True, errors="replace",
        timeout=timeout, check=False,
    )  # fmt: skip
    if done.returncode != 0:
        lines = [ln for ln in (done.stderr or done.stdout).splitlines() if ln.strip()]
        raise RuntimeError(
            f"OpenSim failed (exit code {done.returncode}): {lines[-1] if lines else 'no output'}"
        )


def verify_prediction(
    pred: Any,
    body: BodyModel,
    model: str | PathLike[str],
    motion: str | PathLike[str],
    external_loads: str | PathLike[str],
    inverse_dynamics: str | PathLike[str],
    *,
    timeout: float = 300.0,
) -> Verification:
    """Check ``pred`` with OpenSim on these files (see the module doc)."""
    from walk3d.verify.worker import ID_FILE, POINTS_FILE

    check_timeout(timeout)
    feet = {"right": ("calcn_r", "foot_r", "r"), "left": ("calcn_l", "foot_l", "l")}
    points = {k: (b, contact_point(body, s).tolist()) for k, (b, _, s) in feet.items()}
    with tempfile.TemporaryDirectory(prefix="walk3d-verify-") as tmp:
        work = Path(tmp)
        padded = work / "periodic"
        padded.mkdir()
        ext_motion, ext_loads = periodic_records(motion, external_loads, padded)
        spec = {
            "model": str(Path(model).resolve()),
            "motion": str(ext_motion.resolve()),
            "external_loads": str(ext_loads.resolve()),
            "replay": str(Path(motion).resolve()),
            "out": str(work),
            "points": points,
        }
        _run_worker(spec, work, timeout)
        theirs = read_storage(work / ID_FILE)
        with np.load(work / POINTS_FILE) as data:
            replayed = {k: data[k] for k in feet}
    ours = read_storage(inverse_dynamics, finite=True)
    t = ours.time
    if theirs.time.size < 2 or theirs.time[0] > t[0] + 1e-6 or theirs.time[-1] < t[-1] - 1e-6:
        raise ValueError("OpenSim's inverse dynamics does not cover the motion's time range")
    opensim = {
        c: np.interp(t, theirs.time, theirs.data[:, k]) for k, c in enumerate(theirs.columns)
    }
    walk3d = {c: ours.data[:, k] for k, c in enumerate(ours.columns)}
    weight = float(np.sum(pred.segment_mass)) * G
    whole = compare_generalized_forces(walk3d, opensim, weight)
    smooth = compare_generalized_forces(
        walk3d, opensim, weight, smooth_mask(pred.grf_force[:, :, 1])
    )
    model_settings = (pred.summary.get("settings") or {}).get("model") or {}
    tolerance = float(model_settings.get("foot_flat_tolerance", np.radians(3.0)))
    drift, own = {}, {}
    for k, (name, (_, segment, side)) in enumerate(feet.items()):
        i = pred.segment_names.index(segment)
        flat = foot_flat_mask(
            _foot_pitch(pred.segment_orientation[:, i]), pred.grf_force[:, k, 1] > 0, tolerance
        )
        drift[name] = largest_drift(replayed[name], flat)
        own[name] = largest_drift(_walk3d_points(pred, body, i, contact_point(body, side)), flat)
    return Verification(whole, smooth, drift, own)


def verify_folder(folder: str | PathLike[str], *, timeout: float = 300.0) -> Verification:
    """Check a prediction folder (``walk3d predict --out``) with OpenSim.

    A folder written before walk3d wrote ``model.osim`` and ``inverse_dynamics.sto`` is checked
    on both made afresh from its ``result.npz`` (a note says so).

    Raises:
        OpenSimMissing: OpenSim is not installed.
        DataFileError: the folder is not a complete result folder.
        ValueError, RuntimeError: OpenSim failed or its output does not fit.
    """
    from walk3d.io.osim import write_osim
    from walk3d.results.inverse_dynamics import write_inverse_dynamics
    from walk3d.results.osim_model import motion_extent, osim_model, prediction_body
    from walk3d.results.prediction import load_result

    check_timeout(timeout)
    out = Path(folder)
    pred = load_result(out)
    if not opensim_available():
        raise OpenSimMissing()
    body = prediction_body(pred)
    model, sto = out / "model.osim", out / "inverse_dynamics.sto"
    with tempfile.TemporaryDirectory(prefix="walk3d-files-") as tmp:
        notes = []
        if not (model.is_file() and sto.is_file()):
            model, sto = Path(tmp) / model.name, Path(tmp) / sto.name
            write_osim(model, osim_model(body, motion_extent(pred)))
            write_inverse_dynamics(sto, pred, body)
            notes.append("the folder has no model.osim or inverse_dynamics.sto (written before "
                         "walk3d made them): both were made from its result.npz")  # fmt: skip
        v = verify_prediction(
            pred, body, model, out / "motion.mot", out / "grf.xml", sto, timeout=timeout
        )
    return Verification(v.whole, v.smooth, v.drift_m, v.walk3d_drift_m, notes)
