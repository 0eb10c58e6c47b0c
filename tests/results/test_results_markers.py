"""The virtual Plug-in Gait marker set: mirror symmetry, scaling with the subject and the
geometry that makes marker-based frames coincide with walk3d's in upright standing."""

from __future__ import annotations

import numpy as np
import pytest

from walk3d.body.model import MIRROR_POINT, build_body
from walk3d.results.markers import MARKER_LABELS, Marker, marker_set


def _by_label(markers) -> dict[str, Marker]:
    return {m.label: m for m in markers}


@pytest.fixture(scope="module")
def markers():
    return _by_label(marker_set(build_body()))


def test_left_markers_are_the_mirror_images_of_the_right_ones(markers) -> None:
    assert tuple(markers) == MARKER_LABELS and len(MARKER_LABELS) == 39
    pairs = [(lab, "R" + lab[1:]) for lab in MARKER_LABELS if lab[0] == "L"]
    assert len(pairs) == 17
    for left, right in pairs:
        a, b = markers[left], markers[right]
        assert a.segment == b.segment.replace("_r", "_l")
        np.testing.assert_array_equal(a.position, b.position * MIRROR_POINT)
        assert a.position[2] <= 0.0 <= b.position[2]
    assert not np.allclose(markers["LASI"].position, markers["RASI"].position)  # control
    assert markers["RBAK"].position[2] > 0.0  # the one asymmetric marker, on the right


def test_markers_scale_with_the_subject_s_stature(markers) -> None:
    small = _by_label(marker_set(build_body(68.8, 1.60)))
    for label, m in markers.items():
        np.testing.assert_allclose(small[label].position, m.position * 1.60 / 1.77, atol=1e-12)
    moved = max(np.linalg.norm(small[k].position - m.position) for k, m in markers.items())
    assert moved > 0.01  # control: they did move


def _frames_agree(m: dict[str, Marker]) -> bool:
    """Marker frames of Plug-in Gait's kind coincide with walk3d's in standing: ASIS/PSIS level,
    HEE/TOE level, THI and KNE in the thigh's frontal plane through the hip centre, TIB and ANK
    in the shank's, WRA/WRB around the wrist, head markers level."""
    y = {k: v.position[1] for k, v in m.items()}
    x = {k: v.position[0] for k, v in m.items()}
    checks = [
        y["RASI"] == y["RPSI"] == y["LASI"] == y["LPSI"],
        y["RHEE"] == y["RTOE"],
        x["RTHI"] == x["RKNE"] == 0.0 and x["RTIB"] == x["RANK"] == 0.0,
        x["RWRA"] == -x["RWRB"] > 0.0,
        y["RFHD"] == y["RBHD"],
    ]
    return all(checks)


def test_marker_frames_coincide_with_walk3d_s_in_standing(markers) -> None:
    assert _frames_agree(markers)
    tilted = dict(markers)  # control: a PSIS 1 cm higher (a tilted marker pelvis) is caught
    tilted["RPSI"] = Marker("RPSI", "pelvis", markers["RPSI"].position + [0.0, 0.01, 0.0])
    assert not _frames_agree(tilted)


def test_anatomical_distances_are_adult_sized(markers) -> None:
    def dist(a: str, b: str) -> float:
        assert markers[a].segment == markers[b].segment
        return float(np.linalg.norm(markers[a].position - markers[b].position))

    body = build_body()
    hips = 2.0 * body.joints[body.joint_index("hip_r")].offset[2]
    iad = (0.20, 0.28)  # inter-ASIS distance of adults, m
    assert iad[0] < dist("LASI", "RASI") < iad[1]
    assert not iad[0] < hips < iad[1]  # control: the hip-centre distance is not an IAD
    assert 0.08 < 2.0 * markers["RKNE"].position[2] < 0.12  # knee width (centre at z = 0)
    assert 0.10 < dist("C7", "CLAV") < 0.18
    assert 0.15 < dist("LFHD", "LBHD") < 0.21  # head length
    assert 0.14 < dist("RHEE", "RTOE") < 0.22  # heel to second metatarsal head
