"""The measured side of ``walk3d track`` (issue #58): :func:`tracking_target` on the three
shared sources, its agreement with ``walk3d validate``'s reference, and one DataFileError line
for each kind of bad file (each with a negative control: the same copy, unmutated, passes)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from walk3d.constants import G
from walk3d.io.errors import DataFileError
from walk3d.io.storage import read_storage, write_storage
from walk3d.validation.compare import align_prediction
from walk3d.validation.run import _subject, validate
from walk3d.validation.target import TrackingTarget, tracking_target

SAGITTAL = ("hip_flexion_r", "knee_flexion_r", "ankle_dorsiflexion_r",
            "hip_flexion_l", "knee_flexion_l", "ankle_dorsiflexion_l")  # fmt: skip


def _knee_peak_in_loading(target: TrackingTarget) -> float:
    """Largest right knee flexion over the first 40 % of the cycle, deg (the realism yardstick)."""
    return float(np.degrees(target.angle("knee_flexion_r")[:41].max()))


def _trial(folder: Path, mass: float = 62.0, **kw) -> TrackingTarget:
    return tracking_target(ik=folder / "gait_1_ik.mot", grf=folder / "gait_1_grf.mot", mass=mass,
                           **kw)  # fmt: skip


# --- the three shared sources -------------------------------------------------------------


def test_falisse_table_gives_t_from_its_stride_and_the_knee_loading_peak(falisse):
    t = tracking_target(table=falisse / "cycle_right_leg_mean_sd.csv", mass=62.0, speed=1.32)
    assert t.speed == 1.32
    assert t.period == pytest.approx(1.05, abs=0.01)  # stride 1.38 m / 1.32 m/s (README)
    assert 0.12 < t.double_support < 0.18  # stance ~65 % of the cycle
    assert _knee_peak_in_loading(t) == pytest.approx(27.7, abs=0.05)
    assert t.angles.shape == (101, 24) and t.percent[0] == 0 and t.percent[-1] == 100
    assert [n for n, m in zip(t.dof_names, t.angle_mask, strict=True) if not m] == ["neck_flexion"]
    assert t.pelvis_mask.all() and t.grf.shape == (101, 2, 3) and t.grf_mask.all()
    assert 0.9 < t.grf[:, 0, 1].max() < 1.2  # body weights
    # the left side is the right one half a cycle later; the left lateral force is mirrored
    knee_r, knee_l = t.angle("knee_flexion_r"), t.angle("knee_flexion_l")
    np.testing.assert_allclose(knee_l[:50], knee_r[50:100], atol=1e-12)
    np.testing.assert_allclose(t.grf[:50, 1, 2], -t.grf[50:100, 0, 2], atol=1e-12)
    with pytest.raises(ValueError):
        t.angles[0, 0] = 1.0  # read-only


def test_falisse_table_alone_gives_no_descriptors(falisse):
    t = tracking_target(table=falisse / "cycle_right_leg_mean_sd.csv", mass=62.0)
    assert (t.speed, t.period, t.double_support) == (None, None, None)
    assert any("does not give V, T, Td" in n for n in t.notes)
    period = tracking_target(table=falisse / "cycle_right_leg_mean_sd.csv", mass=62.0, period=1.05)
    assert period.speed == pytest.approx(1.3823 / 1.05, rel=1e-3)


def test_winter_table_is_sagittal_with_its_own_speed_and_period(winter):
    t = tracking_target(table=winter, mass=70.0)
    assert (t.speed, t.period) == (1.325, 1.1396)
    assert 0.1 < t.double_support < 0.2
    assert {n for n, m in zip(t.dof_names, t.angle_mask, strict=True) if m} == set(SAGITTAL)
    assert not t.pelvis_mask.any()
    assert t.grf_mask.tolist() == [[True, True, False]] * 2
    assert not t.angles[:, ~t.angle_mask].any() and not t.grf[:, :, 2].any()


def test_falisse_trial_descriptors_are_those_of_the_validation_page(falisse):
    t = _trial(falisse)
    info = json.loads((falisse / "info.json").read_text())
    assert t.speed == pytest.approx(info["gait_1_speed_m_per_s"], rel=1e-9)
    assert t.period == pytest.approx(1.0708, abs=1e-4)  # docs/validation.md
    assert t.double_support == pytest.approx(0.1465, abs=1e-4)
    assert 20.0 < _knee_peak_in_loading(t) < 32.0
    assert t.angle_mask.sum() == 23 and t.grf_mask.all()
    given = _trial(falisse, speed=1.3, period=1.1, double_support=0.15)
    assert (given.speed, given.period, given.double_support) == (1.3, 1.1, 0.15)
    np.testing.assert_array_equal(given.angles, t.angles)


def test_subject01_treadmill_trial_needs_the_belt_speed(subject01):
    ik, grf = subject01 / "subject01_walk1_ik.mot", subject01 / "subject01_walk1_grf.mot"
    t = tracking_target(ik=ik, grf=grf, mass=72.6, speed=1.12)
    assert t.speed == 1.12
    assert t.period == pytest.approx(1.235, abs=0.02)  # README: cycle about 1.235 s
    assert t.double_support == pytest.approx(0.17, abs=0.01)
    measured = {n for n, m in zip(t.dof_names, t.angle_mask, strict=True) if m}
    assert not any(n.startswith(("arm", "elbow", "neck")) for n in measured)
    assert len(measured) == 15  # both legs' six angles and the waist's three
    # 1.20 s of IK against T = 1.224 s: no complete cycle, the IK is taken as periodic
    assert any("no complete cycle in the IK" in n for n in t.notes)
    assert np.abs(np.diff(np.degrees(t.angle("knee_flexion_r")))).max() < 5.0  # no seam jump
    with pytest.raises(DataFileError) as info:
        tracking_target(ik=ik, grf=grf, mass=72.6)
    assert ik.name in str(info.value) and "belt speed" in str(info.value)


# --- the same quantities as walk3d validate -----------------------------------------------


@pytest.mark.parametrize("kind", ["falisse table", "winter table", "falisse trial"])
def test_target_equals_the_validate_reference(kind, falisse, winter, synthetic_prediction):
    refs = {
        "falisse table": [falisse / "cycle_right_leg_mean_sd.csv"],
        "winter table": [winter],
        "falisse trial": [falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot"],
    }[kind]
    v = validate({"p": synthetic_prediction}, refs, figures=False)
    reference = v.reference
    mass = _subject(synthetic_prediction)[0]  # validate's body mass
    if kind.endswith("trial"):
        t = tracking_target(ik=refs[0], grf=refs[1], mass=mass)
    else:
        t = tracking_target(table=refs[0], mass=mass)
    compared = 0
    for k, dof in enumerate(t.dof_names):
        name = dof[:-2] if dof.endswith("_r") else dof
        if dof.endswith("_l") or f"angle:{name}" not in reference.mean:
            continue
        np.testing.assert_allclose(np.degrees(t.angles[:, k]), reference.mean[f"angle:{name}"],
                                   rtol=0, atol=1e-9)  # fmt: skip
        compared += 1
    assert compared >= 3
    # so a tracking RMSE on the prediction read as validate reads it is Table 2's RMSE
    _, aligned = align_prediction(synthetic_prediction)
    knee = np.degrees(t.angle("knee_flexion_r"))
    tracking_rmse = np.sqrt(np.mean((aligned["angle:knee_flexion"] - knee) ** 2))
    assert tracking_rmse == pytest.approx(v.comparisons[0].row("angle:knee_flexion").rmse)
    for axis, name in enumerate(("grf_fore_aft", "grf_vertical")):
        np.testing.assert_allclose(t.grf[:, 0, axis] * G, reference.mean[f"grf:{name}"],
                                   rtol=0, atol=1e-9)  # fmt: skip


# --- bad trial files: one DataFileError line each, and a negative control -----------------


def _rewrite(src: Path, dst: Path, mutate) -> Path:
    """``src`` rewritten to ``dst`` after ``mutate(time, columns, data)`` returns new ones."""
    st = read_storage(src)
    time, columns, data = mutate(st.time.copy(), list(st.columns), st.data.copy())
    return write_storage(dst, time, columns, data, in_degrees=bool(st.in_degrees))


def _drop(name):
    def mutate(time, columns, data):
        keep = [i for i, c in enumerate(columns) if c != name]
        return time, [columns[i] for i in keep], data[:, keep]

    return mutate


def _nan(name, rows):
    def mutate(time, columns, data):
        data[rows, columns.index(name)] = np.nan
        return time, columns, data

    return mutate


def _flat_vertical(time, columns, data):
    for k, c in enumerate(columns):
        if c.endswith("ground_force_vy"):
            data[:, k] = 0.0
    return time, columns, data


def _half_cycle(time, columns, data):
    keep = time <= time[0] + 0.5 * 1.07
    return time[keep], columns, data[keep]


def _constant_time(time, columns, data):
    return np.zeros_like(time), columns, data


def _hundred_seconds_later(time, columns, data):
    return time + 100.0, columns, data


def _unchanged(time, columns, data):
    return time, columns, data


TRIAL_CASES = {
    "ik column dropped": ("ik", _drop("knee_angle_r"), ("'knee_angle_r'",)),
    "pelvis_tx dropped": ("ik", _drop("pelvis_tx"), ("'pelvis_tx'", "speed")),
    "grf column dropped": ("grf", _drop("ground_force_vy"), ("'ground_force_vy'",)),
    "ik half a cycle": ("ik", _half_cycle, ("shorter than one gait cycle",)),
    "ik nan": ("ik", _nan("knee_angle_r", slice(40, 45)), ("'knee_angle_r'", "not finite")),
    "grf nan": ("grf", _nan("ground_force_vy", slice(2000, 2050)), ("'ground_force_vy'",)),
    "no heel strike": ("grf", _flat_vertical, ("no heel strike",)),
    "ik constant time": ("ik", _constant_time, ("time", "not increasing")),
    "grf constant time": ("grf", _constant_time, ("time", "not increasing")),
    "ik not beside the grf": ("ik", _hundred_seconds_later, ("do not overlap in time",)),
}


@pytest.mark.parametrize("case", sorted(TRIAL_CASES))
def test_a_bad_trial_file_is_one_line_naming_it(case, falisse, tmp_path):
    which, mutate, words = TRIAL_CASES[case]
    files = {"ik": falisse / "gait_1_ik.mot", "grf": falisse / "gait_1_grf.mot"}
    files[which] = _rewrite(files[which], tmp_path / f"bad_{which}.mot", mutate)
    with pytest.raises(DataFileError) as info:
        tracking_target(ik=files["ik"], grf=files["grf"], mass=62.0)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"bad_{which}.mot"), message
    assert all(w in message for w in words), message


@pytest.mark.parametrize("which", ["ik", "grf"])
def test_negative_control_the_rewritten_trial_files_pass(which, falisse, tmp_path):
    files = {"ik": falisse / "gait_1_ik.mot", "grf": falisse / "gait_1_grf.mot"}
    files[which] = _rewrite(files[which], tmp_path / f"same_{which}.mot", _unchanged)
    t = tracking_target(ik=files["ik"], grf=files["grf"], mass=62.0)
    np.testing.assert_allclose(t.angles, _trial(falisse).angles, atol=1e-9)


# --- bad cycle tables ---------------------------------------------------------------------


def _table_copy(src: Path, dst: Path, edit) -> Path:
    """The wide table ``src`` with ``edit(header, rows)`` applied, written to ``dst``."""
    with src.open(newline="", encoding="utf-8-sig") as f:
        header, *rows = list(csv.reader(f))
    header, rows = edit(header, rows)
    with dst.open("w", newline="") as f:
        csv.writer(f).writerows([header, *rows])
    return dst


def _table_drop(base):
    def edit(header, rows):
        keep = [i for i, c in enumerate(header) if not c.startswith(base + "_")]
        return [header[i] for i in keep], [[r[i] for i in keep] for r in rows]

    return edit


def _table_set(column, value, rows_slice=slice(None)):
    def edit(header, rows):
        k = header.index(column)
        for row in rows[rows_slice]:
            row[k] = value
        return header, rows

    return edit


def _table_shift(header, rows):
    return header, [[r[0], *s[1:]] for r, s in zip(rows, rows[40:] + rows[1:41], strict=True)]


TABLE_CASES = {
    "column dropped": (_table_drop("knee_angle_deg"), ("knee_angle_deg_mean",)),
    "nan": (_table_set("hip_flexion_deg_mean", "nan", slice(10, 11)), ("not finite",)),
    "no heel strike": (_table_set("grf_right_vertical_N_per_kg_mean", "0"), ("no heel strike",)),
    "not from heel strike": (_table_shift, ("heel strike is at", "not at 0 %")),
    "constant percent": (_table_set("percent_cycle", "0"), ("percent", "not increasing")),
}


@pytest.mark.parametrize("case", sorted(TABLE_CASES))
def test_a_bad_cycle_table_is_one_line_naming_it(case, falisse, tmp_path):
    edit, words = TABLE_CASES[case]
    bad = _table_copy(falisse / "cycle_right_leg_mean_sd.csv", tmp_path / "bad_table.csv", edit)
    with pytest.raises(DataFileError) as info:
        tracking_target(table=bad, mass=62.0, speed=1.32)
    message = str(info.value)
    assert "\n" not in message and message.startswith("bad_table.csv"), message
    assert all(w in message for w in words), message


def test_negative_control_the_rewritten_table_passes(falisse, tmp_path):
    same = _table_copy(falisse / "cycle_right_leg_mean_sd.csv", tmp_path / "same.csv",
                       lambda h, r: (h, r))  # fmt: skip
    t = tracking_target(table=same, mass=62.0, speed=1.32)
    assert _knee_peak_in_loading(t) == pytest.approx(27.7, abs=0.05)


def test_winter_table_without_its_knee_names_winters_column(winter, tmp_path):
    lines = winter.read_text(encoding="utf-8-sig").splitlines()
    cut = [",".join(c for k, c in enumerate(line.split(",")) if k != 5) for line in lines]
    bad = tmp_path / "winter_no_knee.csv"
    bad.write_text("\n".join(cut) + "\n", encoding="utf-8")
    with pytest.raises(DataFileError, match=r"^winter_no_knee\.csv: no column 'knee angle'"):
        tracking_target(table=bad, mass=70.0)
    same = tmp_path / "winter_same.csv"  # negative control
    same.write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert tracking_target(table=same, mass=70.0).period == 1.1396


def test_bad_arguments_are_refused_before_reading(tmp_path):
    missing = tmp_path / "absent.csv"
    with pytest.raises(ValueError, match="mass"):
        tracking_target(table=missing, mass=0.0)
    with pytest.raises(ValueError, match="not both"):
        tracking_target(table=missing, ik=missing, mass=70.0)
    with pytest.raises(ValueError, match="GRF"):
        tracking_target(ik=missing, mass=70.0)
    with pytest.raises(ValueError, match="half the period"):
        tracking_target(table=missing, mass=70.0, period=1.0, double_support=0.6)
    with pytest.raises(FileNotFoundError):
        tracking_target(table=missing, mass=70.0)
