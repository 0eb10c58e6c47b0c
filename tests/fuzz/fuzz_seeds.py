"""Valid seed files of the fuzz set, made without a solve: a result folder
(:func:`result_support.result_folder`) and a copy with what ``walk3d track`` and ``walk3d
audit`` add, a synthetic walking C3D trial, a cycle
table, a calibration, a criterion and a trials file. Measured files come from the shared data
folder (:func:`helpers.shared_data_dir`) and are only read there."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def cycle_table(path: Path) -> Path:
    """A cycle table of the pelvis's and the right leg's sagittal angles (deg), 51 samples, as
    ``walk3d validate`` reads them."""
    p = np.linspace(0.0, 100.0, 51)
    c = np.cos(2 * np.pi * p / 100)
    cols = {
        "hip_flexion": 10 + 20 * c,
        "knee_angle": -(32 - 28 * c),
        "ankle_angle": 5 * c,
        "pelvis_tilt": 2 * c,
        "pelvis_list": 1 + 0.5 * c,
        "pelvis_rotation": 4 * c,
    }
    head = ["percent_cycle"] + [f"{k}_deg_{s}" for k in cols for s in ("mean", "sd")]
    rows = [",".join(head)]
    for i in range(p.size):
        rows.append(",".join([f"{p[i]:g}"] + [f"{v[i]:.4f},3" for v in cols.values()]))
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def calibration_json(path: Path) -> Path:
    """A plausible calibration file (``walk3d calibrate``'s format)."""
    from helpers import sample_calibration

    from walk3d.io.calibration import write_calibration

    return write_calibration(path, sample_calibration().to_dict())


def criterion_toml(path: Path) -> Path:
    """A criterion file of weights (``walk3d fit-criterion``'s output)."""
    from walk3d.io.criterion import write_criterion

    weights = {"tor": 1.0, "accel": 0.5, "jerk": 1.0, "head": 0.5, "impact": 2.5}
    return write_criterion(path, weights, ["a fuzz seed"])


def trials_toml(path: Path, reference: Path) -> Path:
    """A ``walk3d fit-criterion`` trials file of two trials given by their descriptors."""
    text = f"""[[trial]]
name = "one"
mass = 70.0
height = 1.75
sex = "male"
speed = 1.3
period = 1.1
double_support = 0.13
reference = ["{reference}"]

[[trial]]
name = "two"
speed = 1.1
period = 1.2
double_support = 0.15
reference = ["{reference}"]
reference_speed = 1.1
"""
    path.write_text(text, encoding="utf-8")
    return path


# -- a synthetic walking C3D trial (the shape of tests/validation/test_c3d_reference.py's) ------

PERIOD, STANCE, MASS = 1.1, 0.62 * 1.1, 70.0
STRIKES = {"R": (0.1, 1.2, 2.3), "L": (-0.45, 0.65, 1.75)}
PLATE_X = {"R": -350.0, "L": 350.0}  # mm; Z up, the walker faces -Y: right is -X


def _phase(t: np.ndarray, side: str) -> np.ndarray:
    out = np.full(t.shape, np.nan)
    for hs in STRIKES[side]:
        out[t >= hs] = t[t >= hs] - hs
    return out


def _plate(side: str, t: np.ndarray) -> np.ndarray:
    s = _phase(t, side)
    on = np.isfinite(s) & (s < STANCE)
    u = np.where(on, np.nan_to_num(s) / STANCE, 0.0)
    ch = np.zeros((t.size, 6))
    ch[:, 1] = np.where(on, -0.2 * MASS * 9.81 * np.sin(2 * np.pi * u), 0.0)
    ch[:, 2] = -np.where(on, MASS * 9.81 * np.pi / 2.48 * np.sin(np.pi * u), 0.0)
    ch[:, 3] = (100.0 - 250.0 * u) * ch[:, 2]
    return ch


def gait_c3d(path: Path) -> Path:
    """A 2.6 s walk at 1.3 m/s: pelvis and foot markers, Plug-in Gait angles, two plates."""
    from c3d_support import write_c3d

    t = np.arange(260) / 100.0
    y = 500.0 - 1300.0 * t
    labels, points = [], []

    def add(label, x, yy, z) -> None:  # noqa: ANN001
        labels.append(label)
        points.append(np.column_stack(np.broadcast_arrays(x, yy, z)))

    for name, dx, dy in (("LASI", 120, -60), ("RASI", -120, -60), ("LPSI", 50, 90),
                         ("RPSI", -50, 90)):  # fmt: skip
        add(name, dx, y + dy, 950.0)
    for side in "RL":
        add(f"{side}HEE", PLATE_X[side], y + 100.0, 50.0)
        add(f"{side}TOE", PLATE_X[side], y - 150.0, 30.0)
        s = _phase(t, side)
        s = np.where(np.isfinite(s), s, t - STRIKES[side][0] + PERIOD)
        w = 2 * np.pi * s / PERIOD
        add(f"Subj:{side}HipAngles", 20 * np.cos(w), 0.0, 0.0)
        add(f"Subj:{side}KneeAngles", 32.5 - 27.5 * np.cos(w), 0.0, 0.0)
        add(f"Subj:{side}AnkleAngles", 10 * np.sin(w), 0.0, 0.0)
    base = np.array([[300, 200, 0], [-300, 200, 0], [-300, -200, 0], [300, -200, 0]], float)
    ta = np.arange(2600) / 1000.0
    return write_c3d(path, point_rate=100.0, labels=labels, points=np.stack(points, 1),
                     analog_rate=1000.0, plates=[_plate("R", ta), _plate("L", ta)],
                     corners=[base + [PLATE_X[s], 0.0, 0.0] for s in "RL"])  # fmt: skip


def tracked_folder(result: Path, folder: Path) -> Path:
    """A copy of ``result`` with the files ``walk3d track`` and ``walk3d audit`` add, listed
    in its manifest: ``tracking.csv``, ``binding.csv`` and ``audit.json``."""
    import shutil

    from walk3d.results.prediction import record_file
    from walk3d.tracking import audit

    shutil.copytree(result, folder)
    rows = ["quantity,unit,rmse,max_abs", "hip_flexion_r,deg,2.1,5.3", "knee_flexion_r,deg,4.2,9.9",
            "grf_r_y,N/kg,0.31,1.2"]  # fmt: skip
    binding = ["kind,name,multiplier,nodes", "bound,knee_flexion_r,0.41,3-7",
               "constraint,foot_flat,0.12,12"]  # fmt: skip
    (folder / "tracking.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    (folder / "binding.csv").write_text("\n".join(binding) + "\n", encoding="utf-8")
    (folder / "audit.json").write_text(json.dumps(audit(result, result)), encoding="utf-8")
    for name in ("tracking.csv", "binding.csv", "audit.json"):
        record_file(folder, name)
    return folder


def campaign_folder(result: Path, out: Path) -> Path:
    """A campaign folder (``walk3d campaign``'s layout) of three starts, copies of ``result``
    (one not converged), ranked, with ``best/``."""
    from result_support import make_campaign

    return make_campaign(out, result, {0: True, 1: False, 2: True}, 3)
