"""Joint-coordinate ranges used as constraints: anatomical, with the arms narrowed to walking."""

from __future__ import annotations

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.problem.settings import PredictionSettings

ARM_WALKING_RANGE_DEG = {"shoulder": ((-30.0, 10.0), (-30.0, 30.0), (-45.0, 45.0)),
                         "elbow": ((0.0, 90.0),)}  # fmt: skip
"""Arm ranges while walking (joint axes x, y, z; elbow flexion), inside the anatomical ones.

Measured arm swing in walking stays within about ±35° of shoulder flexion and 10–60° of elbow
flexion. With the anatomical ranges (shoulder −60…170° flexion, elbow 0…150°) C_tor optima
whirled the arms through ±130° at twice the stride frequency while the hips crouched to 65°
(docs/solver.md) — the paper's own complaint about its arms, in a worse form. Set
``settings.arm_walking_ranges = False`` for the anatomical ranges.
"""


def joint_ranges(body: BodyModel, settings: PredictionSettings) -> np.ndarray:
    """(24, 2) joint-coordinate ranges in rad, DoF order: anatomical, arms narrowed to walking."""
    out = []
    for j in body.joints:
        r = np.array(j.range, dtype=float)
        kind = j.name.rsplit("_", 1)[0]
        if settings.arm_walking_ranges and kind in ARM_WALKING_RANGE_DEG:
            env = np.radians(np.array(ARM_WALKING_RANGE_DEG[kind]))
            r = np.column_stack([np.maximum(r[:, 0], env[:, 0]), np.minimum(r[:, 1], env[:, 1])])
        out.append(r)
    return np.concatenate(out)
