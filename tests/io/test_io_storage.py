"""OpenSim storage reading/writing on the lab files and on damaged copies."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from walk3d.io import DataFileError, Storage, read_storage, write_storage

EXPECTED = {
    # file: (rows, data columns, inDegrees, sample rate Hz)
    "falisse2019/gait_1_grf.mot": (6420, 18, False, 1000.0),
    "falisse2019/gait_1_ik.mot": (146, 37, True, 100.0),
    "falisse2019/gait_1_id.sto": (146, 37, False, 100.0),
    "opensim_subject01/subject01_walk1_grf.mot": (1501, 18, True, 600.0),
    "opensim_subject01/subject01_walk1_ik.mot": (73, 23, True, 60.0),
    "opensim_subject01/inverse_dynamics.sto": (73, 23, False, 60.0),
}


def test_every_storage_file_in_shared_data_is_covered(data_dir: Path) -> None:
    found = {p.relative_to(data_dir).as_posix() for p in data_dir.rglob("*.mot")}
    found |= {p.relative_to(data_dir).as_posix() for p in data_dir.rglob("*.sto")}
    assert found == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_read_lab_storage(data_dir: Path, name: str) -> None:
    rows, cols, degrees, rate = EXPECTED[name]
    s = read_storage(data_dir / name)
    assert s.data.shape == (rows, cols) and len(s.columns) == cols
    assert s.in_degrees is degrees
    assert int(s.header["nRows"]) == rows and int(s.header["nColumns"]) == cols + 1
    assert np.all(np.diff(s.time) > 0)
    assert s.sample_rate == pytest.approx(rate, rel=0.03)
    assert np.isfinite(s.data).all()
    assert not s.data.flags.writeable


def test_header_variants_of_subject01(subject01: Path) -> None:
    ik = read_storage(subject01 / "subject01_walk1_ik.mot")  # free text + blank header lines
    assert ik.name == "Coordinates"
    assert ik.time[0] == pytest.approx(0.4) and ik.time[-1] == pytest.approx(1.6)
    grf = read_storage(subject01 / "subject01_walk1_grf.mot")  # trailing tabs in header
    assert grf.header["version"] == "1"
    assert grf.column("ground_force_vy").max() == pytest.approx(804.859797)


def test_ik_knee_flexes_negative_in_swing(falisse: Path, subject01: Path) -> None:
    for path in (falisse / "gait_1_ik.mot", subject01 / "subject01_walk1_ik.mot"):
        ik = read_storage(path)
        for side in "rl":
            knee = ik.column(f"knee_angle_{side}")
            assert knee.min() < -40.0, path.name  # swing flexion, OpenSim sign
            assert knee.max() < 5.0, path.name  # never hyper-extended much


def test_old_style_whitespace_header(tmp_path: Path) -> None:
    path = tmp_path / "old.mot"
    path.write_text(
        "old trial\ndatacolumns 3\ndatarows 2\nrange 0 0.01\nendheader\n"
        "time  hip_flexion_r   knee_angle_r\n  0.00   1.5  -2\n  0.01   1.75  -3e1\n\n"
    )
    s = read_storage(path)
    assert s.name == "old trial" and s.in_degrees is None
    assert s.columns == ("hip_flexion_r", "knee_angle_r")
    np.testing.assert_array_equal(s.column("knee_angle_r"), [-2.0, -30.0])
    np.testing.assert_array_equal(s.column("time"), [0.0, 0.01])


def test_round_trip_is_exact_and_atomic(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    time = np.cumsum(rng.uniform(0.001, 0.01, 50))
    data = rng.normal(size=(50, 3)) * 10.0 ** rng.integers(-8, 8, size=(50, 3))
    data[3, 1] = np.nan
    path = tmp_path / "x.sto"
    write_storage(path, time, ["a", "b_r", "c"], data, name="round trip", in_degrees=True)
    s = read_storage(path)
    expected = Storage("round trip", time, ("a", "b_r", "c"), data, True, s.header)
    assert s == expected
    assert np.array_equal(s.data, data, equal_nan=True) and np.array_equal(s.time, time)
    assert s.header["nRows"] == "50" and s.header["nColumns"] == "4"
    assert path.read_text().splitlines()[6].split("\t")[0] == "time"
    assert sorted(os.listdir(tmp_path)) == ["x.sto"]  # no temporary file left


def test_failed_write_keeps_the_old_file(tmp_path: Path) -> None:
    path = tmp_path / "keep.mot"
    write_storage(path, [0.0, 1.0], ["q"], [[1.0], [2.0]])
    before = path.read_bytes()
    with pytest.raises(ValueError):
        write_storage(path, [0.0, 1.0], ["q"], [[1.0], [2.0], [3.0]])
    with pytest.raises(ValueError):
        write_storage(path, [0.0], ["bad label"], [[1.0]])
    assert path.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["keep.mot"]


def _damaged(tmp_path: Path, source: Path, edit) -> Path:
    lines = source.read_text().splitlines(keepends=True)
    target = tmp_path / source.name
    target.write_text("".join(edit(lines)))
    return target


def _assert_error(path: Path, line: int | None, fragment: str) -> None:
    with pytest.raises(DataFileError) as info:
        read_storage(path)
    message = str(info.value)
    assert "\n" not in message
    assert isinstance(info.value, ValueError)
    prefix = path.name if line is None else f"{path.name}:{line}:"
    assert message.startswith(prefix), message
    assert fragment in message, message


def test_truncated_mid_row(tmp_path: Path, subject01: Path) -> None:
    src = subject01 / "subject01_walk1_ik.mot"
    text = src.read_text()
    cut = (
        text[: text.index("\n", len(text) // 2) + 1]
        + text[text.index("\n", len(text) // 2) + 1 :][:60]
    )
    path = tmp_path / src.name
    path.write_text(cut)
    last = cut.count("\n") + 1
    _assert_error(path, last, "expected 24 values, found")


def test_truncated_at_line_end_violates_nrows(tmp_path: Path, falisse: Path) -> None:
    path = _damaged(tmp_path, falisse / "gait_1_ik.mot", lambda lines: lines[:-10])
    _assert_error(path, 143, "header declares 146 rows, found 136")


def test_non_numeric_value(tmp_path: Path, falisse: Path) -> None:
    def corrupt(lines: list[str]) -> list[str]:
        cells = lines[11].split("\t")
        cells[10] = "1.2.3"
        lines[11] = "\t".join(cells)
        return lines

    path = _damaged(tmp_path, falisse / "gait_1_id.sto", corrupt)
    _assert_error(path, 12, "'1.2.3' in column 'knee_angle_r_moment' is not a number")


def test_missing_endheader(tmp_path: Path, falisse: Path) -> None:
    path = _damaged(
        tmp_path, falisse / "gait_1_ik.mot", lambda ls: [x for x in ls if "endheader" not in x]
    )
    _assert_error(path, 152, "missing 'endheader'")


def test_column_count_disagrees_with_header(tmp_path: Path, falisse: Path) -> None:
    path = _damaged(
        tmp_path,
        falisse / "gait_1_ik.mot",
        lambda ls: [ls[0], ls[1], ls[2], "nColumns=37\n", *ls[4:]],
    )
    _assert_error(path, 7, "header declares 37 columns, label line has 38")


def test_non_finite_values_are_refused_in_the_columns_used(tmp_path: Path) -> None:
    """NaN or inf in a column a command reads is refused naming the file, the column and the
    first row; other columns of the same file stay readable (negative control)."""
    t = np.arange(5) * 0.01
    data = np.column_stack([np.arange(5.0), np.arange(5.0) * 2])
    path = tmp_path / "grf.mot"
    write_storage(path, t, ("fx", "fy"), data, name="grf")
    text = path.read_text().splitlines()
    text[-3] = text[-3].rsplit(maxsplit=1)[0] + " nan"  # fy, data row 3
    text[-1] = text[-1].rsplit(maxsplit=1)[0] + " inf"
    path.write_text("\n".join(text) + "\n")
    storage = read_storage(path)
    np.testing.assert_array_equal(storage.column("fx"), np.arange(5.0))
    with pytest.raises(DataFileError) as info:
        storage.column("fy")
    msg = str(info.value)
    assert msg.startswith("grf.mot: column 'fy'") and "2 rows" in msg and "data row 3" in msg
    text[-2] = "nan " + text[-2].split(maxsplit=1)[1]  # a time that is not finite
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(DataFileError, match="time holds nan in data row 4"):
        read_storage(path)


@pytest.mark.parametrize(
    ("time", "words"),
    [([1.5, 1.5, 1.5], "time is not increasing: 1.5 then 1.5 (rows 1 and 2)"),
     ([0.0, 0.0, 0.0], "time is not increasing: 0 then 0 (rows 1 and 2)"),
     ([0.0, 0.01, 0.01, 0.02], "0.01 then 0.01 (rows 2 and 3)"),
     ([0.0, 0.02, 0.01], "0.02 then 0.01 (rows 2 and 3)"),
     ([0.3], "1 data rows: a motion needs 2 or more"),
     ([], "0 data rows")],
)  # fmt: skip
def test_a_time_that_does_not_increase_is_refused_naming_the_file(tmp_path, time, words):
    """A constant or zero time column divided by zero in validate, calibrate and predict
    --from-trial (sampling rates, periods); now one DataFileError line at reading."""
    path = tmp_path / "ik.mot"
    write_storage(path, time, ("knee",), np.zeros(len(time)), name="ik")
    with pytest.raises(DataFileError) as info:
        read_storage(path)
    assert str(info.value).startswith("ik.mot") and words in str(info.value), info.value


def test_two_increasing_samples_are_the_fewest_read(tmp_path):
    """Negative control: the smallest valid time column, unevenly sampled."""
    path = tmp_path / "ik.mot"
    write_storage(path, [0.0, 0.001], ("knee",), [1.0, 2.0], name="ik")
    assert read_storage(path).time.tolist() == [0.0, 0.001]


def test_a_column_named_twice_is_one_plain_line(tmp_path: Path) -> None:
    path = tmp_path / "twice.mot"
    head = "trial\nnRows=2\nnColumns=3\ninDegrees=yes\nendheader\n"
    path.write_text(head + "time\tknee_angle_r\tknee_angle_r\n0\t1\t2\n0.01\t1\t2\n")
    with pytest.raises(DataFileError, match=r"^twice\.mot:6: column 'knee_angle_r' appears twice$"):
        read_storage(path)
    path.write_text(head + "time\tknee_angle_r\thip_flexion_r\n0\t1\t2\n0.01\t1\t2\n")  # control
    assert read_storage(path).columns == ("knee_angle_r", "hip_flexion_r")
