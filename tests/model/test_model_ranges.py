"""Joint ranges: anatomical, with the arms and knees narrowed to walking (and only those)."""

import numpy as np

from walk3d.body.model import build_body
from walk3d.model.ranges import joint_ranges
from walk3d.problem.settings import PredictionSettings


def test_arm_and_knee_ranges_are_narrowed_inside_the_anatomical_ones_and_nothing_else_changes():
    body = build_body()
    anatomical = np.concatenate([j.range for j in body.joints])
    walking = joint_ranges(body, PredictionSettings().model)
    assert np.all(walking[:, 0] >= anatomical[:, 0]) and np.all(walking[:, 1] <= anatomical[:, 1])
    changed = np.flatnonzero(np.any(walking != anatomical, axis=1))
    names = [j.name for j in body.joints for _ in range(j.n_dof)]
    assert {names[i] for i in changed} == {
        "shoulder_r",
        "elbow_r",
        "shoulder_l",
        "elbow_l",
        "knee_r",
        "knee_l",
    }
    # shoulder flexion (sagittal axis) within ±45°, elbow within 0–90°
    i_sh = names.index("shoulder_r") + 2
    np.testing.assert_allclose(np.degrees(walking[i_sh]), [-45.0, 45.0])
    np.testing.assert_allclose(np.degrees(walking[names.index("elbow_r")]), [0.0, 90.0])
    # knee flexion up to 90° (anatomical 135°); its 5° of hyperextension kept
    for knee in ("knee_r", "knee_l"):
        np.testing.assert_allclose(np.degrees(walking[names.index(knee)]), [-5.0, 90.0])
        np.testing.assert_allclose(np.degrees(anatomical[names.index(knee)]), [-5.0, 135.0])
    arms_only = joint_ranges(body, PredictionSettings(leg_walking_ranges=False).model)
    np.testing.assert_array_equal(
        arms_only[names.index("knee_r")], anatomical[names.index("knee_r")]
    )
    np.testing.assert_array_equal(arms_only[i_sh], walking[i_sh])
    off = joint_ranges(
        body, PredictionSettings(arm_walking_ranges=False, leg_walking_ranges=False).model
    )
    np.testing.assert_array_equal(off, anatomical)
