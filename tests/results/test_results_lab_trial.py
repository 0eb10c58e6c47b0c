"""markers.c3d: the shipped atlas's 1.3 m/s prediction (no solve) as a lab trial, read back
with walk3d's own C3D readers and with ezc3d. Every check has a negative control."""

from __future__ import annotations

import shutil
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from walk3d.constants import G
from walk3d.io import DataFileError, read_c3d
from walk3d.results.lab_trial import ANALOG_RATIO, LAB_FROM_WALK3D, write_markers_c3d
from walk3d.results.markers import MARKER_LABELS, marker_positions, marker_set
from walk3d.results.prediction import check_complete, save_prediction
from walk3d.trials.c3d_trial import read_c3d_trial

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))
ezc3d = pytest.importorskip("ezc3d")


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """``(prediction, body, markers.c3d read back, expected frames)``; the frames are found
    here from the prediction alone: from the right heel strike (first nonzero right force)
    to the sample after the left toe-off that follows it, a stride on per period."""
    from verify_support import atlas_prediction

    pred, body = atlas_prediction()
    folder = save_prediction(pred, tmp_path_factory.mktemp("c3d") / "v_1.300", body=body)
    m = pred.n_nodes - 1
    on = np.any(pred.grf_force[:m] != 0.0, axis=-1)  # (M, 2)
    strike = [int(k) for k in range(m) if on[k, 0] and not on[k - 1, 0]]
    left_off = [int(k) for k in range(m) if on[k - 1, 1] and not on[k, 1]]
    assert len(strike) == len(left_off) == 1
    first = strike[0]
    last = first + (left_off[0] - first) % m
    last = last if last >= first + m else last + m  # one period at least
    frames = np.arange(first, last + 1)
    return pred, body, folder, read_c3d(folder / "markers.c3d"), frames


def _stride(pred) -> np.ndarray:
    return pred.pelvis_position[-1] - pred.pelvis_position[0]


def _expected_markers(pred, body, frames: np.ndarray) -> np.ndarray:
    """Marker positions at the trial's frames in the lab frame, computed directly."""
    m = pred.n_nodes - 1
    pos = marker_positions(pred, body)[frames % m] + (frames // m)[:, None, None] * _stride(pred)
    return pos @ LAB_FROM_WALK3D.T


def test_markers_round_trip_through_read_c3d(atlas) -> None:
    pred, body, _, data, frames = atlas
    assert data.points.labels == MARKER_LABELS and data.points.units == "mm"
    m, period = pred.n_nodes - 1, pred.time[-1] - pred.time[0]
    assert data.points.rate == pytest.approx(m / period, rel=1e-5)
    expected = _expected_markers(pred, body, frames)
    assert data.points.positions.shape == expected.shape
    assert np.max(np.abs(data.points.positions - expected)) < 1e-4  # 0.1 mm
    # controls: one frame late, or no stride per period, is far off
    assert np.max(np.abs(data.points.positions - _expected_markers(pred, body, frames + 1))) > 1e-3
    unshifted = marker_positions(pred, body)[frames % m] @ LAB_FROM_WALK3D.T
    assert np.max(np.abs(data.points.positions - unshifted)) > 1.0


def test_markers_are_rigidly_attached(atlas) -> None:
    _, body, _, data, _ = atlas
    pos = data.points.positions
    segment = {mk.label: mk.segment for mk in marker_set(body)}

    def spread(a: str, b: str) -> float:
        i, j = MARKER_LABELS.index(a), MARKER_LABELS.index(b)
        d = np.linalg.norm(pos[:, i] - pos[:, j], axis=1)
        return float(d.max() - d.min())

    pairs = [(a, b) for a in MARKER_LABELS for b in MARKER_LABELS
             if a < b and segment[a] == segment[b]]  # fmt: skip
    assert len(pairs) > 30
    assert max(spread(a, b) for a, b in pairs) < 1e-5  # 0.01 mm
    assert spread("RTHI", "RTIB") > 0.02  # control: across the knee they move apart
    assert spread("LASI", "LKNE") > 0.02  # across the hip


def test_plates_carry_each_foot_s_ground_reaction_during_its_stance(atlas) -> None:
    pred, _, _, data, frames = atlas
    m = pred.n_nodes - 1
    assert data.analogs.rate == ANALOG_RATIO * data.points.rate and len(data.platforms) == 2
    for foot, plate in enumerate(data.platforms):
        reaction = -plate.force[::ANALOG_RATIO] @ LAB_FROM_WALK3D  # lab -> walk3d, on the foot
        grf = pred.grf_force[frames % m, foot]
        on = np.any(reaction != 0.0, axis=1)
        k = np.flatnonzero(on)
        assert np.all(on[k[0] : k[-1] + 1]), "one stance per plate"
        assert np.max(np.abs(reaction[on] - grf[on])) < 0.5
        other = pred.grf_force[frames % m, 1 - foot]
        assert np.max(np.abs(reaction[on] - other[on])) > 100.0  # control: the other foot
        # the foot's force outside that stance (the trial's ends) is not on the plate
        outside = ~on & (grf[:, 1] > 100.0)
        assert outside.sum() >= 2 and np.all(reaction[outside] == 0.0)
        stance_sum = grf[on, 1].sum() / pred.grf_force[:m, foot, 1].sum()
        assert stance_sum == pytest.approx(1.0, abs=1e-12), "the whole stance"


def test_plate_centre_of_pressure_and_free_moment_are_the_predicted_ones(atlas) -> None:
    pred, _, _, data, frames = atlas
    m = pred.n_nodes - 1
    weight = pred.body_mass * G
    unshifted = []
    for foot, plate in enumerate(data.platforms):
        fz = -plate.force[::ANALOG_RATIO, 2]
        big = fz > 0.2 * weight
        cop = pred.grf_cop[frames % m, foot] + (frames // m)[:, None] * _stride(pred)
        got = plate.cop[::ANALOG_RATIO] @ LAB_FROM_WALK3D
        assert big.sum() > 40
        assert np.max(np.abs(got[big] - cop[big])) < 1e-3
        free = -plate.free_moment[::ANALOG_RATIO, 2]  # plate: -T about lab Z (walk3d's y)
        assert np.max(np.abs(free[big] - pred.grf_free_moment[frames % m, foot][big])) < 0.01
        late = pred.grf_cop[(frames + 1) % m, foot] + ((frames + 1) // m)[:, None] * _stride(pred)
        assert np.max(np.abs(got[big] - late[big])) > 5e-3  # control: one sample late
        unshifted.append(np.max(np.abs(got[big] - pred.grf_cop[frames % m, foot][big])))
    assert max(unshifted) > 0.5  # control: the left stance, in the next period, a stride on


def test_plates_carry_body_weight_over_a_period(atlas) -> None:
    pred, _, _, data, _ = atlas
    m = pred.n_nodes - 1
    period = pred.time[-1] - pred.time[0]
    impulse = [-p.force[:, 2].sum() / data.analogs.rate for p in data.platforms]
    weight = pred.body_mass * G
    mean_grf = pred.grf_force[:m, :, 1].sum(axis=1).mean()  # the prediction's own, 0.8 % low
    assert sum(impulse) / period == pytest.approx(mean_grf, rel=1e-3)
    assert sum(impulse) / period == pytest.approx(weight, rel=0.01)
    for one in impulse:  # control: one plate carries about half
        assert abs(one / period / weight - 1.0) > 0.3


def test_plates_lie_under_their_foot_and_apart(atlas) -> None:
    pred, _, _, data, _ = atlas
    boxes = [(p.corners.min(axis=0), p.corners.max(axis=0)) for p in data.platforms]
    for (lo, hi), p in zip(boxes, data.platforms, strict=True):
        assert np.all(p.corners[:, 2] == 0.0)  # on the floor
        loaded = -p.force[:, 2] > 0.2 * pred.body_mass * G  # all analog samples
        cop = p.cop[loaded]
        assert np.all((cop[:, :2] >= lo[:2]) & (cop[:, :2] <= hi[:2]))
    (lo1, hi1), (lo2, hi2) = boxes
    assert hi1[0] < lo2[0]  # the left plate lies a step ahead, no overlap
    assert hi1[1] < 0.05 and lo2[1] > -0.05  # right foot on the right (lab -Y), left on +Y
    right_cop = data.platforms[0].cop[-data.platforms[0].force[:, 2] > 100.0]
    assert not np.any(np.all((right_cop[:, :2] >= lo2[:2]) & (right_cop[:, :2] <= hi2[:2]), 1))


def test_events_mark_the_plate_contacts(atlas) -> None:
    _, _, folder, data, _ = atlas
    ev = ezc3d.c3d(str(folder / "markers.c3d"))["parameters"]["EVENT"]
    events = list(zip(ev["CONTEXTS"]["value"], ev["LABELS"]["value"], ev["TIMES"]["value"][1],
                      strict=True))  # fmt: skip
    assert [e[:2] for e in events] == [("Right", "Foot Strike"), ("Left", "Foot Off"),
                                       ("Left", "Foot Strike"), ("Right", "Foot Off"),
                                       ("Right", "Foot Strike"), ("Left", "Foot Off")]  # fmt: skip
    frame = {(c, lab, round(t * data.points.rate)) for c, lab, t in events}
    for foot, side in enumerate(("Right", "Left")):
        fz = data.platforms[foot].force[::ANALOG_RATIO, 2]
        k = np.flatnonzero(fz != 0.0)
        assert (side, "Foot Strike", k[0]) in frame and (side, "Foot Off", k[-1] + 1) in frame
        first = np.flatnonzero(data.platforms[foot].force[:, 2])[0]
        assert first == k[0] * ANALOG_RATIO  # the load starts at the strike, no ramp before
        assert (side, "Foot Strike", k[0] + 1) not in frame  # control


def test_read_c3d_trial_finds_the_walk_and_the_ground_reactions(atlas) -> None:
    pred, _, folder, data, frames = atlas
    trial = read_c3d_trial(folder / "markers.c3d")
    assert "lab +X forward, +Z up" in trial.notes[0]
    m = pred.n_nodes - 1
    for foot in range(2):
        force = trial.grf.data[::ANALOG_RATIO, 9 * foot : 9 * foot + 3]
        on = np.any(force != 0.0, axis=1)
        np.testing.assert_allclose(force[on], pred.grf_force[frames % m, foot][on], atol=0.5)
    turned = read_c3d_trial(folder / "markers.c3d", forward="-x")  # control: walking backwards
    flipped = turned.grf.data[::ANALOG_RATIO, :3]
    assert np.max(np.abs(flipped - trial.grf.data[::ANALOG_RATIO, :3])) > 100.0


def test_ezc3d_reads_labels_units_and_plates(atlas) -> None:
    _, _, folder, _, _ = atlas
    c3d = ezc3d.c3d(str(folder / "markers.c3d"), extract_forceplat_data=True)
    params = c3d["parameters"]
    assert tuple(params["POINT"]["LABELS"]["value"]) == MARKER_LABELS
    assert params["POINT"]["UNITS"]["value"] == ["mm"]
    assert list(params["FORCE_PLATFORM"]["TYPE"]["value"]) == [2, 2]
    assert params["ANALOG"]["LABELS"]["value"][:6] == ["Fx1", "Fy1", "Fz1", "Mx1", "My1", "Mz1"]
    assert len(c3d["data"]["platform"]) == 2
    assert c3d["data"]["platform"][0]["unit_moment"] == "Nmm"


def test_the_result_folder_lists_markers_c3d_and_writes_it_fast(atlas, tmp_path) -> None:
    pred, body, folder, _, _ = atlas
    check_complete(folder)
    copy = shutil.copytree(folder, tmp_path / "copy")
    (copy / "markers.c3d").unlink()
    with pytest.raises(DataFileError, match="markers.c3d is missing"):  # control
        check_complete(copy)
    best = min(_timed(lambda: write_markers_c3d(tmp_path / "m.c3d", pred, body)) for _ in range(3))
    assert best < 0.5


def _timed(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def test_plate_frame_points_down_and_the_load_on_it_is_positive_fz(atlas) -> None:
    """The documented plate frame: corners numbered so that its z axis points down (AMTI), so
    the force *on* the plate during a stance is positive Fz (the foot pushes down)."""
    pred, _, folder, _, _ = atlas
    c3d = ezc3d.c3d(str(folder / "markers.c3d"))
    corners = np.asarray(c3d["parameters"]["FORCE_PLATFORM"]["CORNERS"]["value"])  # (3, 4, n)
    labels = c3d["parameters"]["ANALOG"]["LABELS"]["value"]
    analogs = np.asarray(c3d["data"]["analogs"])[0]  # (channels, samples)

    def down(c: np.ndarray) -> float:  # z of the plate frame from its corner order
        x, y = c[:, 0] - c[:, 1], c[:, 0] - c[:, 3]
        return float(np.cross(x, y)[2])

    for k in range(corners.shape[2]):
        assert down(corners[:, :, k]) < 0  # the plate's z axis points into the floor
        fz = analogs[labels.index(f"Fz{k + 1}")]
        assert (
            fz.max() > 0.5 * pred.body_mass * G and fz.min() >= -1e-6
        )  # loaded, and never pulled up
    assert down(corners[:, ::-1, 0]) > 0  # control: the reversed corner order points up
