"""Joint-coordinate ranges used as constraints: anatomical, with the arms and the knee narrowed
to walking."""

from __future__ import annotations

import numpy as np

from walk3d.body.changes import limited_dofs
from walk3d.body.model import BodyModel
from walk3d.model.settings import ModelSettings

ARM_WALKING_RANGE_DEG = {"shoulder": ((-30.0, 10.0), (-30.0, 30.0), (-45.0, 45.0)),
                         "elbow": ((0.0, 90.0),)}  # fmt: skip
"""Arm ranges while walking (joint axes x, y, z; elbow flexion), inside the anatomical ones.

Measured arm swing in walking stays within about ±35° of shoulder flexion and 10–60° of elbow
flexion. With the anatomical ranges (shoulder −60…170° flexion, elbow 0…150°) C_tor optima
whirled the arms through ±130° at twice the stride frequency while the hips crouched to 65°
(docs/solver.md) — the paper's own complaint about its arms, in a worse form. Set
``model.arm_walking_ranges = False`` for the anatomical ranges.
"""

LEG_WALKING_RANGE_DEG = {"knee": ((-5.0, 90.0),)}
"""Knee range while walking (flexion), inside the anatomical −5…135°.

Walking knees flex by at most about 60–75° (in swing; the walking optima here reach 74–79°),
so 90° leaves room for slow, fast and pathological-looking gaits while ruling out kneeling and
deep squats. Random starts otherwise find those postures in the geometry-only posture stage,
where the double-support loop rows become nearly degenerate and the balance stage crawls for
hundreds of iterations; with the limit it converges in under 100 iterations or not at all, and
random starts take about a third less time (docs/solver.md).
Set ``model.leg_walking_ranges = False`` for the anatomical range.
"""


def joint_ranges(body: BodyModel, model: ModelSettings) -> np.ndarray:
    """(24, 2) joint-coordinate ranges in rad, DoF order: anatomical, narrowed to walking for
    the arms (``arm_walking_ranges``) and the knees (``leg_walking_ranges``), and to the
    what-if joint limits (``changes.limits``, an orthosis)."""
    walking = {**(ARM_WALKING_RANGE_DEG if model.arm_walking_ranges else {}),
               **(LEG_WALKING_RANGE_DEG if model.leg_walking_ranges else {})}  # fmt: skip
    out = []
    for j in body.joints:
        r = np.array(j.range, dtype=float)
        kind = j.name.rsplit("_", 1)[0]
        if kind in walking:
            env = np.radians(np.array(walking[kind]))
            r = np.column_stack([np.maximum(r[:, 0], env[:, 0]), np.minimum(r[:, 1], env[:, 1])])
        out.append(r)
    ranges = np.concatenate(out)
    for i, (lo, hi) in limited_dofs(body, model.changes.limits).items():
        ranges[i] = max(ranges[i, 0], lo), min(ranges[i, 1], hi)
    return ranges
