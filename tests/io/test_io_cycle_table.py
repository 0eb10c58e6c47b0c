"""Cycle tables: Falisse et al. 2019 mean/SD and Winter's averages."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from walk3d import G
from walk3d.io import DataFileError, read_cycle_table


def test_falisse_cycle_table(falisse: Path) -> None:
    table = read_cycle_table(falisse / "cycle_right_leg_mean_sd.csv")
    assert table.mean.shape == (101, 35) and table.sd.shape == (101, 35)
    np.testing.assert_array_equal(table.percent, np.arange(101.0))
    assert (table.sd >= 0).all()
    knee, knee_sd = table.column("knee_angle_deg")
    assert table.units[table.index("knee_angle_deg")] == "deg"
    assert knee.min() < -50.0 and 60 < np.argmin(knee) < 85  # swing flexion, negative
    assert knee_sd.max() < 15.0
    fy, _ = table.column("grf_right_vertical_N_per_kg")
    toe_off = table.percent[np.argmax(fy < 20.0 / 62.0)]  # first unloaded sample
    assert 58.0 < toe_off < 70.0  # stance about 65 % of the cycle
    assert 1.0 < fy.max() / G < 1.3  # first peak above body weight


def test_winter_table(data_dir: Path) -> None:
    table = read_cycle_table(data_dir / "winter" / "Winter_normal.csv")
    assert table.mean.shape == (51, 8) and np.isnan(table.sd).all()
    np.testing.assert_allclose(table.percent, np.linspace(0, 100, 51))
    assert float(table.metadata["Gait cycle duration"].split()[0]) == pytest.approx(1.1396)
    knee, _ = table.column("knee_angle_deg")
    assert knee.max() > 55.0  # Winter's sign: flexion positive
    fy, _ = table.column("vertical_grf_N_per_kg")
    assert fy.max() / G == pytest.approx(1.1, abs=0.15)


def test_bad_cycle_table(tmp_path: Path, falisse: Path) -> None:
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    corrupt = list(lines)
    corrupt[5] = corrupt[5].replace(",", ",abc", 1)
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(corrupt) + "\n")
    with pytest.raises(DataFileError, match=r"^bad\.csv:6: value 'abc.*' in pelvis_tilt_deg_mean"):
        read_cycle_table(path)
    for token in ("nan", "inf", "-Infinity"):
        corrupt = list(lines)
        cells = lines[7].split(",")
        corrupt[7] = ",".join([*cells[:3], token, *cells[4:]])
        path.write_text("\n".join(corrupt) + "\n")
        with pytest.raises(DataFileError, match=rf"^bad\.csv:8: value '{token}' in .* not finite"):
            read_cycle_table(path)
    path.write_text("\n".join(lines[:50] + [lines[50][:40]]) + "\n")
    with pytest.raises(DataFileError, match=r"^bad\.csv:51: expected 71 values"):
        read_cycle_table(path)


@pytest.mark.parametrize(
    ("column", "value", "words"),
    [("hip_flexion_moment_Nm_per_kg_mean", "1e300", "beyond ±1e+06"),  # an angle: below
     ("hip_flexion_moment_Nm_per_kg_mean", "-2e6", "beyond ±1e+06"),
     ("hip_flexion_deg_sd", "-5", "negative SD")],
)  # fmt: skip
def test_absurd_values_and_negative_sd_are_refused(tmp_path, falisse, column, value, words):
    """A column of ±1e300 was scored with overflow warnings and RMSE inf marked 'ok'; a
    negative SD was shown as the reference SD."""
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    k = lines[0].split(",").index(column)
    path = tmp_path / "bad.csv"
    for v, refused in ((value, True), ("999999" if "mean" in column else "0", False)):
        cells = lines[7].split(",")
        path.write_text("\n".join([*lines[:7], ",".join([*cells[:k], v, *cells[k + 1 :]]),
                                   *lines[8:]]) + "\n")  # fmt: skip
        if refused:
            with pytest.raises(DataFileError, match=rf"^bad\.csv:8: value '{v}' in {column}"):
                read_cycle_table(path)
            with pytest.raises(DataFileError, match=re.escape(words)):
                read_cycle_table(path)
        else:  # control: a large but bounded mean, a zero SD
            assert read_cycle_table(path).column(column[: column.rindex("_")])[0].size > 50


def _small_table(path: Path, cell: str = "") -> Path:
    """A 51-row knee table; ``cell``, when given, takes the place of row 3's mean."""
    rows = ["percent_cycle,knee_angle_deg_mean,knee_angle_deg_sd"]
    rows += [f"{p},{-30 + 25 * np.cos(p / 16):.3f},2" for p in range(0, 101, 2)]
    if cell:
        rows[3] = f"4,{cell},2"
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_a_cell_past_the_csv_field_limit_is_one_line(tmp_path, capsys) -> None:
    """A cell of 200 000 characters, past the csv module's limit of 131 072, gave a
    ``_csv.Error`` traceback in validate, track and report (the fuzz set, ``-m fuzz``)."""
    from helpers import cli, one_line_error

    path = _small_table(tmp_path / "long.csv", "1" * 200_000)
    with pytest.raises(DataFileError, match=r"^long\.csv:4: .*longer than"):
        read_cycle_table(path)
    one_line_error(cli(capsys, "track", "--out", tmp_path / "t", "--table", path), "long.csv:4")
    # control: the same table with a plain number there reads
    assert read_cycle_table(_small_table(tmp_path / "ok.csv", "-5.5")).mean.shape == (51, 1)


def test_a_column_named_twice_is_refused(tmp_path, falisse) -> None:
    """Two ``knee_angle_deg_mean`` columns: the second was silently ignored."""
    path = _small_table(tmp_path / "t.csv")
    lines = path.read_text().splitlines()
    twice = [line + "," + line.split(",")[1] for line in lines]
    twice[0] = lines[0] + ",knee_angle_deg_mean"
    path.write_text("\n".join(twice) + "\n")
    with pytest.raises(
        DataFileError, match=r"^t\.csv:1: column 'knee_angle_deg_mean' appears twice"
    ):
        read_cycle_table(path)
    # negative control: the table less the repeat, and the whole Falisse table, are read
    assert read_cycle_table(_small_table(tmp_path / "ok.csv")).names == ("knee_angle_deg",)
    assert len(read_cycle_table(falisse / "cycle_right_leg_mean_sd.csv").names) > 30


def test_a_winter_column_named_twice_is_refused(tmp_path, data_dir) -> None:
    """Winter's layout: a second "knee angle (deg)" column, read under the same name."""
    lines = (data_dir / "winter" / "Winter_normal.csv").read_text(encoding="utf-8-sig").splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("sample,"))
    k = lines[head].split(",").index("knee angle    ")
    twice = [line + "," + line.split(",")[k] if i >= head else line for i, line in enumerate(lines)]
    path = tmp_path / "w.csv"
    path.write_text("\n".join(twice) + "\n")
    with pytest.raises(DataFileError, match=r"^w\.csv:5: column 'knee angle' appears twice"):
        read_cycle_table(path)
