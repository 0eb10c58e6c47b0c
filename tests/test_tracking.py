"""``walk3d track``'s target: the measured angles as the track term's coordinates, back to the
same angles; the settings it solves; the ``--relax`` names."""

import math

import numpy as np
import pytest
from helpers import shared_data_dir

from walk3d.body.model import build_body
from walk3d.results.angles import ball_joint_angles
from walk3d.tracking import only_dofs, relaxations, track_settings, tracking_spec
from walk3d.validation.target import tracking_target

FALISSE = shared_data_dir() / "falisse2019"
needs_data = pytest.mark.skipif(not FALISSE.is_dir(), reason=f"no shared data at {FALISSE}")


@pytest.fixture(scope="module")
def target():
    if not FALISSE.is_dir():
        pytest.skip(f"no shared data at {FALISSE}")
    return tracking_target(ik=FALISSE / "gait_1_ik.mot", grf=FALISSE / "gait_1_grf.mot", mass=62)


def _angles_back(body, tau: np.ndarray) -> np.ndarray:
    """Angles (n, 24) from the coordinates ``2 q`` as walk3d reports them."""
    out, i = [], 0
    for joint in body.joints:
        c = tau[:, i : i + joint.n_dof] / 2
        if joint.kind == "ball":
            v = c @ np.asarray(joint.axes, dtype=float)
            w = np.sqrt(np.clip(1 - np.sum(v * v, axis=1), 0, None))
            out.append(ball_joint_angles(np.column_stack([w, v]), joint.side))
        else:
            out.append(2 * np.arcsin(c))
        i += joint.n_dof
    return np.concatenate(out, axis=1)


def test_the_target_coordinates_give_back_the_measured_angles(target):
    body = build_body(62, 1.7, "female")
    spec = tracking_spec(target, body)
    back = _angles_back(body, spec.target(target.percent / 100))
    m = target.angle_mask
    err = np.degrees(np.abs(back - target.angles))[:, m]
    assert np.max(np.sqrt(np.mean(err**2, axis=0))) < 0.5  # the 10-harmonic fit's error
    assert np.array_equal(np.asarray(spec.weights) > 0, m)
    # negative control: read as hinges, the ball joints' angles are not given back
    hinge = 2 * np.arcsin(spec.target(target.percent / 100) / 2)
    hips = [target.dof_names.index(d) for d in ("hip_adduction_r", "hip_rotation_r")]
    assert np.max(np.abs(np.degrees(hinge[:, hips] - target.angles[:, hips]))) > 0.5


def test_the_settings_track_at_the_trials_descriptors(target):
    s = track_settings(target, mass=62, height=1.7, sex="female", weight=50)
    assert (s.gait.speed, s.gait.period) == (target.speed, target.period)
    assert s.model.criterion.endswith("track=50") and s.model.tracking is not None
    given = track_settings(target, mass=62, height=1.7, sex="female", period=1.2)
    assert given.gait.period == 1.2
    tor = track_settings(target, mass=62, height=1.7, sex="female", criterion="tor")
    assert tor.model.criterion == "tor=1,track=100"


def test_relax_names_map_to_settings_in_si():
    got = relaxations(["loop=0.03,foot-flat=20", "heel-rise=0.3"])
    assert got == {"loop_tolerance": 0.03, "foot_flat_tolerance": pytest.approx(math.radians(20)),
                   "heel_rise": 0.3}  # fmt: skip
    for bad in (
        ["loop"],
        ["toe=1"],
        ["loop=nan"],
        ["loop=1", "loop=2"],
        ["foot-flat=1_0"],
        ["foot-flat=２０"],
    ):
        with pytest.raises(ValueError, match="--relax"):
            relaxations(bad)


def test_only_some_dofs_are_tracked(target):
    legs = only_dofs(target, ["knee_flexion", "hip_flexion_r"])
    names = [d for d, m in zip(legs.dof_names, legs.angle_mask, strict=True) if m]
    assert names == ["hip_flexion_r", "knee_flexion_r", "knee_flexion_l"]
    assert target.angle_mask.sum() > 3  # control: the target itself keeps its DoFs
    with pytest.raises(ValueError, match="not a DoF"):
        only_dofs(target, ["knee"])
    with pytest.raises(ValueError, match="does not measure"):
        only_dofs(target, ["neck_flexion"])
