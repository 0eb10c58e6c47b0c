"""Measured angles against their stated unit (walk3d.io.angle_units): degrees read as radians
and radians read as degrees are one line and exit 2 in validate and calibrate; the lab's own
files pass."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import cli, one_line_error

from walk3d.io import DataFileError, read_cycle_table, read_storage, write_storage
from walk3d.io.angle_units import check_storage_angles


def _ik(falisse, path, in_degrees, scale=1.0):
    """The trial's IK with its angles times ``scale`` under the header ``in_degrees``."""
    ik = read_storage(falisse / "gait_1_ik.mot")
    data = np.array(ik.data)
    for k, c in enumerate(ik.columns):
        if not c.endswith(("_tx", "_ty", "_tz")):
            data[:, k] *= scale
    return write_storage(path, ik.time, ik.columns, data, name=ik.name, in_degrees=in_degrees)


def test_degrees_under_in_degrees_no_are_refused(falisse, tmp_path):
    bad = read_storage(_ik(falisse, tmp_path / "bad.mot", in_degrees=False))
    with pytest.raises(DataFileError, match=r"^bad\.mot: .* reaches \d+° read as inDegrees=no, "
                       r"beyond ±360°"):  # fmt: skip
        check_storage_angles(bad)
    check_storage_angles(read_storage(falisse / "gait_1_ik.mot"))  # control: the lab's file
    good = read_storage(_ik(falisse, tmp_path / "rad.mot", False, np.radians(1.0)))
    check_storage_angles(good)  # control: radians stated as such


def test_radians_under_in_degrees_yes_are_refused(falisse, tmp_path):
    bad = read_storage(_ik(falisse, tmp_path / "bad.mot", True, np.radians(1.0)))
    with pytest.raises(DataFileError, match=r"every hip, knee and ankle flexion spans less than "
                       r"3° read as inDegrees=yes \(the widest, knee_angle_"):  # fmt: skip
        check_storage_angles(bad)


def test_radians_in_deg_columns_of_a_cycle_table_are_refused(falisse, tmp_path):
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    names = lines[0].split(",")
    rows = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        rows.append(",".join(f"{np.radians(float(c)):.6g}" if "_deg_" in n else c
                             for n, c in zip(names, cells, strict=True)))  # fmt: skip
    path = tmp_path / "rad.csv"
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(DataFileError, match=r"^rad\.csv: every hip, knee and ankle .* _deg "):
        read_cycle_table(path)
    path.write_text("\n".join(rows).replace("_deg_", "_rad_") + "\n")  # control: stated so
    assert "knee_angle_rad" in read_cycle_table(path).names


def test_degrees_in_rad_columns_of_a_cycle_table_are_refused(falisse, tmp_path):
    path = tmp_path / "deg.csv"
    text = (falisse / "cycle_right_leg_mean_sd.csv").read_text()
    path.write_text(text.replace("_deg_", "_rad_"))
    with pytest.raises(DataFileError, match=r"read as _rad columns, beyond ±360°"):
        read_cycle_table(path)


def test_calibrate_refuses_a_mislabelled_ik(falisse, tmp_path, capsys):
    bad = _ik(falisse, tmp_path / "bad.mot", in_degrees=False)
    grf = falisse / "gait_1_grf.mot"
    one_line_error(cli(capsys, "calibrate", "--ik", bad, "--grf", grf, "--out",
                       tmp_path / "c.json"), "bad.mot", "inDegrees=no")  # fmt: skip
    assert not (tmp_path / "c.json").exists()
