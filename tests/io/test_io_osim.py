"""model.osim as XML (no OpenSim needed): 13 bodies with walk3d's masses and inertias, 30
coordinates under motion.mot's names, each joint's rotations in order."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import replace

import numpy as np
import pytest

from walk3d import G
from walk3d.body.model import build_body
from walk3d.io.osim import osim_xml, write_osim
from walk3d.results.opensim import motion_columns
from walk3d.results.osim_model import BODY_NAMES, osim_model


def parsed(text: str) -> dict:
    root = ET.fromstring(text)
    model = root.find("Model")
    bodies = {
        b.get("name"): (
            float(b.findtext("mass")),
            [float(v) for v in b.findtext("inertia").split()],
        )
        for b in model.iter("Body")
    }
    coords = [c.get("name") for c in model.iter("Coordinate")]
    axes = {}
    for joint in model.iter("CustomJoint"):
        for ta in joint.find("SpatialTransform"):
            axes[(joint.get("name"), ta.get("name"))] = (
                ta.findtext("coordinates") or None,
                [float(v) for v in ta.findtext("axis").split()],
            )
    return {"root": root, "bodies": bodies, "coordinates": coords, "axes": axes}


@pytest.fixture(scope="module")
def body():
    return build_body(81.0, 1.84, "female")


@pytest.fixture(scope="module")
def model(body):
    return osim_model(body)


def test_the_file_is_an_opensim_4_document(tmp_path, model):
    path = write_osim(tmp_path / "model.osim", model)
    root = ET.parse(path).getroot()
    assert root.tag == "OpenSimDocument" and root.get("Version") == "40000"
    assert [float(v) for v in root.find("Model/gravity").text.split()] == [0.0, -G, 0.0]
    assert len(root.findall("Model/JointSet/objects/CustomJoint")) == 13


def test_coordinates_are_exactly_motion_mots_columns(body, model):
    p = parsed(osim_xml(model))
    assert len(p["coordinates"]) == 30 == len(set(p["coordinates"]))
    assert set(p["coordinates"]) == set(motion_columns(body.dof_names))
    assert "neck_flexion" in p["coordinates"]
    # negative control: a renamed coordinate is caught
    bad = replace(model, joints=tuple(
        replace(j, rotations=(replace(j.rotations[0], name="neck_angle"),)) if j.name == "neck"
        else j for j in model.joints))  # fmt: skip
    assert set(parsed(osim_xml(bad))["coordinates"]) != set(motion_columns(body.dof_names))


def test_masses_and_inertias_are_the_body_models(body, model):
    p = parsed(osim_xml(model))
    for seg in body.segments:
        mass, inertia = p["bodies"][BODY_NAMES[seg.name]]
        assert mass == seg.mass
        assert inertia == [*seg.inertia, 0.0, 0.0, 0.0]
    total = sum(s.mass for s in body.segments)  # de Leva's female fractions sum to 0.9999
    assert sum(m for m, _ in p["bodies"].values()) == pytest.approx(total, rel=1e-12)
    # negative control: another subject's model differs
    other = parsed(osim_xml(osim_model(build_body(70.0, 1.84, "female"))))
    assert other["bodies"]["femur_r"][0] != p["bodies"]["femur_r"][0]


def test_ball_joints_rotate_flexion_then_adduction_then_rotation(model):
    p = parsed(osim_xml(model))["axes"]
    assert p[("hip_r", "rotation1")] == ("hip_flexion_r", [0.0, 0.0, 1.0])
    assert p[("hip_r", "rotation2")] == ("hip_adduction_r", [1.0, 0.0, 0.0])
    assert p[("hip_r", "rotation3")] == ("hip_rotation_r", [0.0, 1.0, 0.0])
    assert p[("hip_l", "rotation2")] == ("hip_adduction_l", [-1.0, -0.0, 0.0])
    assert p[("hip_l", "rotation3")] == ("hip_rotation_l", [-0.0, -1.0, 0.0])
    assert p[("ground_pelvis", "rotation1")][0] == "pelvis_tilt"
    assert p[("ground_pelvis", "translation1")] == ("pelvis_tx", [1.0, 0.0, 0.0])
    # the universal ankle: talocrural, subtalar, then a third axis held at zero
    assert p[("ankle_r", "rotation1")][0] == "ankle_angle_r"
    assert p[("ankle_r", "rotation2")][0] == "subtalar_angle_r"
    assert p[("ankle_r", "rotation3")][0] is None
    axes = np.array([p[("ankle_r", f"rotation{k}")][1] for k in (1, 2, 3)])
    assert abs(np.linalg.det(axes)) > 0.1
