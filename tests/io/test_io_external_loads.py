"""Ground-reaction extraction, foot assignment and GRF/ExternalLoads writing."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from walk3d import G
from walk3d.io import (
    DataFileError,
    ExternalForceSpec,
    PlateLoad,
    combine_loads,
    extract_foot_loads,
    find_plates,
    read_external_loads_xml,
    read_storage,
    write_external_loads_xml,
    write_grf_storage,
)
from walk3d.trials.events import detect_foot_events


def _vertical_events(loads):
    forces = {"right": loads.right.force[:, 1], "left": loads.left.force[:, 1]}
    return detect_foot_events(loads.time, forces)


def test_xml_assignment_subject01(subject01: Path) -> None:
    specs, datafile = read_external_loads_xml(subject01 / "subject01_walk1_grf.xml")
    assert datafile == "subject01_walk1_grf.mot"
    assert [(s.applied_to_body, s.force_identifier) for s in specs] == [
        ("calcn_r", "ground_force_v"),
        ("calcn_l", "1_ground_force_v"),
    ]
    loads = extract_foot_loads(
        subject01 / "subject01_walk1_grf.mot", subject01 / "subject01_walk1_grf.xml"
    )
    grf = read_storage(subject01 / "subject01_walk1_grf.mot")
    np.testing.assert_array_equal(loads.right.force[:, 1], grf.column("ground_force_vy"))
    np.testing.assert_array_equal(loads.left.cop[:, 2], grf.column("1_ground_force_pz"))
    np.testing.assert_array_equal(loads.left.torque[:, 2], grf.column("1_ground_torque_z"))
    # the lateral-COP rule agrees with the XML on this trial
    guessed = extract_foot_loads(grf)
    np.testing.assert_array_equal(guessed.right.force, loads.right.force)


def test_subject01_body_weight_and_stride(subject01: Path) -> None:
    loads = extract_foot_loads(
        subject01 / "subject01_walk1_grf.mot", subject01 / "subject01_walk1_grf.xml"
    )
    events = _vertical_events(loads)
    for side in ("right", "left"):
        hs = events[side].heel_strikes
        assert len(hs) == 2
        assert np.diff(hs)[0] == pytest.approx(1.235, rel=0.03)
        stride = (loads.time >= hs[0]) & (loads.time < hs[1])
        total = loads.right.force[stride, 1] + loads.left.force[stride, 1]
        assert total.mean() / G == pytest.approx(72.6, rel=0.05)
    # double support (left heel strike to right toe off) about 0.17 s
    r_off = events["right"].toe_offs
    l_hs = events["left"].heel_strikes
    assert r_off[1] - l_hs[0] == pytest.approx(0.17, abs=0.03)


def test_falisse_plates_are_assigned_by_lateral_cop(falisse: Path) -> None:
    grf = read_storage(falisse / "gait_1_grf.mot")
    assert [p.force_identifier for p in find_plates(grf)] == ["ground_force_v", "1_ground_force_v"]
    loads = extract_foot_loads(grf)
    # plate "1_" lies to the right (+z) and is loaded while the left knee swings
    np.testing.assert_array_equal(
        loads.right.force, np.column_stack([grf.column(f"1_ground_force_v{a}") for a in "xyz"])
    )
    ik = read_storage(falisse / "gait_1_ik.mot")
    events = _vertical_events(loads)
    right_stance = (ik.time > events["right"].heel_strikes[0] + 0.2) & (
        ik.time < events["right"].toe_offs[0] - 0.2
    )
    assert ik.column("knee_angle_l")[right_stance].min() < -40.0  # left swings meanwhile
    assert ik.column("knee_angle_r")[right_stance].min() > -30.0
    # explicit mapping overrides the rule
    swapped = extract_foot_loads(
        grf, mapping={"right": "ground_force_v", "left": "1_ground_force_v"}
    )
    np.testing.assert_array_equal(swapped.left.force, loads.right.force)


def test_falisse_body_weight_and_period(falisse: Path) -> None:
    info = json.loads((falisse / "info.json").read_text())
    loads = extract_foot_loads(falisse / "gait_1_grf.mot")
    events = _vertical_events(loads)
    # one plate per foot: left strikes its plate first, then the right one
    hs_l, hs_r = events["left"].heel_strikes[0], events["right"].heel_strikes[0]
    step = hs_r - hs_l
    # from the right heel strike on, one full step is measured entirely on the two plates
    window = (loads.time >= hs_r) & (loads.time < hs_r + step)
    total = loads.right.force[window, 1] + loads.left.force[window, 1]
    assert total.mean() / G == pytest.approx(info["mass_kg"], rel=0.05)
    stride = info["stride_length_m_mean"] / info["gait_1_speed_m_per_s"]
    assert 2 * step == pytest.approx(stride, rel=0.05)


def test_grf_writer_round_trip_and_xml(tmp_path: Path) -> None:
    n = 40
    time = np.linspace(0.0, 0.39, n)
    rng = np.random.default_rng(3)
    force = rng.normal(size=(n, 2, 3))
    force[:, :, 1] = np.abs(force[:, :, 1]) * 400 + 30
    cop = rng.normal(size=(n, 2, 3))
    cop[:, 0, 2], cop[:, 1, 2] = 0.1, -0.1
    free = rng.normal(size=(n, 2))
    grf_path = write_grf_storage(tmp_path / "pred_grf.mot", time, force, cop, free)
    xml_path = write_external_loads_xml(tmp_path / "pred_grf.xml", grf_path.name)
    specs, datafile = read_external_loads_xml(xml_path)
    assert datafile == "pred_grf.mot"
    assert [s.applied_to_body for s in specs] == ["calcn_r", "calcn_l"]
    storage = read_storage(grf_path)
    assert {p.side for p in find_plates(storage)} == {"right", "left"}
    for source in (xml_path, None):
        loads = extract_foot_loads(storage, source)
        for k, foot in enumerate((loads.right, loads.left)):
            np.testing.assert_array_equal(foot.force, force[:, k])
            np.testing.assert_array_equal(foot.cop, cop[:, k])
            np.testing.assert_array_equal(foot.torque[:, 1], free[:, k])
            assert not foot.torque[:, [0, 2]].any()


def test_combine_loads_preserves_resultant() -> None:
    rng = np.random.default_rng(5)
    n = 20
    loads = []
    for _ in range(2):
        force = rng.normal(size=(n, 3)) * 50
        force[:, 1] = rng.uniform(100, 500, n)
        cop = rng.uniform(-0.5, 0.5, (n, 3))
        cop[:, 1] = 0.0
        torque = np.zeros((n, 3))
        torque[:, 1] = rng.normal(size=n)
        loads.append(PlateLoad("p", force, cop, torque))
    merged = combine_loads(loads)
    moment = sum(np.cross(p.cop, p.force) + p.torque for p in loads)
    np.testing.assert_allclose(merged.force, loads[0].force + loads[1].force)
    np.testing.assert_allclose(
        np.cross(merged.cop, merged.force) + merged.torque, moment, atol=1e-9
    )
    assert not merged.torque[:, [0, 2]].any() and not merged.cop[:, 1].any()


def test_missing_columns_and_bad_xml(tmp_path: Path, subject01: Path) -> None:
    spec = ExternalForceSpec("x", "calcn_r", "nope_v", "nope_p", "nope_")
    with pytest.raises(DataFileError, match=r"subject01_walk1_grf\.mot: no columns"):
        extract_foot_loads(subject01 / "subject01_walk1_grf.mot", [spec, spec])
    bad = tmp_path / "bad.xml"
    bad.write_text("<OpenSimDocument>\n<ExternalLoads>\n<objects>\n</ExternalLoads>\n")
    with pytest.raises(DataFileError, match=r"^bad\.xml:4: invalid XML"):
        read_external_loads_xml(bad)


def test_one_plate_is_refused_with_advice_a_file_can_follow(tmp_path: Path) -> None:
    """The message names the column layouts walk3d accepts, not a Python-only argument."""
    cols = [f"ground_force_{k}{a}" for k in "vp" for a in "xyz"]
    cols += [f"ground_torque_{a}" for a in "xyz"]
    path = tmp_path / "one.mot"
    lines = ["one", "version=1", "nRows=3", f"nColumns={len(cols) + 1}", "inDegrees=no",
             "endheader", "\t".join(["time", *cols])]  # fmt: skip
    lines += ["\t".join([f"{t:.2f}"] + ["1.0"] * len(cols)) for t in (0.0, 0.01, 0.02)]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="cannot assign 1 force plate") as info:
        extract_foot_loads(path)
    assert "r_ground_force_vx" in str(info.value) and "mapping" not in str(info.value)
