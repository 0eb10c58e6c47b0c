"""Joint ranges: anatomical, with the arms narrowed to walking (and only the arms)."""

import numpy as np

from walk3d.body.model import build_body
from walk3d.problem.ranges import joint_ranges
from walk3d.problem.settings import PredictionSettings


def test_arm_ranges_are_narrowed_inside_the_anatomical_ones_and_nothing_else_changes():
    body = build_body()
    anatomical = np.concatenate([j.range for j in body.joints])
    walking = joint_ranges(body, PredictionSettings())
    assert np.all(walking[:, 0] >= anatomical[:, 0]) and np.all(walking[:, 1] <= anatomical[:, 1])
    changed = np.flatnonzero(np.any(walking != anatomical, axis=1))
    names = [j.name for j in body.joints for _ in range(j.n_dof)]
    assert {names[i] for i in changed} == {"shoulder_r", "elbow_r", "shoulder_l", "elbow_l"}
    # shoulder flexion (sagittal axis) within ±45°, elbow within 0–90°
    i_sh = names.index("shoulder_r") + 2
    np.testing.assert_allclose(np.degrees(walking[i_sh]), [-45.0, 45.0])
    np.testing.assert_allclose(np.degrees(walking[names.index("elbow_r")]), [0.0, 90.0])
    off = joint_ranges(body, PredictionSettings(arm_walking_ranges=False))
    np.testing.assert_array_equal(off, anatomical)
