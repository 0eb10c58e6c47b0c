"""TRC marker files: metres, geometry facts, damaged copies."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from walk3d.io import DataFileError, read_trc


def test_subject01_markers(subject01: Path) -> None:
    trc = read_trc(subject01 / "subject01_walk1.trc")
    assert trc.units == "mm" and trc.rate == 60.0
    assert trc.positions.shape == (151, 41, 3) and len(trc.labels) == 41
    assert {"R.Heel", "L.Heel", "Top.Head", "R.Wrist.Lat"} <= set(trc.labels)
    assert trc.time[-1] == pytest.approx(150 / 60.0, abs=1e-3)
    # metres: pelvis width, head height, heels near the floor, right markers at +z
    width = np.linalg.norm(trc.marker("R.ASIS") - trc.marker("L.ASIS"), axis=1)
    assert 0.18 < np.median(width) < 0.32
    assert 1.6 < np.median(trc.marker("Top.Head")[:, 1]) < 1.9
    assert trc.marker("R.Heel")[:, 1].min() < 0.08
    assert np.median(trc.marker("R.ASIS")[:, 2]) > np.median(trc.marker("L.ASIS")[:, 2])


def test_missing_marker_cells_become_nan(tmp_path: Path, subject01: Path) -> None:
    lines = (subject01 / "subject01_walk1.trc").read_text().splitlines()
    cells = lines[8].split("\t")
    cells[2:5] = ["", "", ""]  # R.ASIS occluded in the third frame
    lines[8] = "\t".join(cells)
    path = tmp_path / "occluded.trc"
    path.write_text("\n".join(lines) + "\n")
    trc = read_trc(path)
    assert np.isnan(trc.marker("R.ASIS")[2]).all()
    assert np.isfinite(trc.marker("R.ASIS")[[1, 3]]).all()


def test_truncated_trc(tmp_path: Path, subject01: Path) -> None:
    text = (subject01 / "subject01_walk1.trc").read_text()
    path = tmp_path / "cut.trc"
    path.write_text(text[: len(text) // 2])
    with pytest.raises(DataFileError) as info:
        read_trc(path)
    message = str(info.value)
    line = text[: len(text) // 2].count("\n") + 1
    assert message.startswith(f"cut.trc:{line}: expected 125 values, found") and "\n" not in message


def test_trc_frame_count_and_number(tmp_path: Path, subject01: Path) -> None:
    lines = (subject01 / "subject01_walk1.trc").read_text().splitlines()
    short = tmp_path / "short.trc"
    short.write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(DataFileError, match=r"^short\.trc:\d+: NumFrames is 151 but 150"):
        read_trc(short)
    bad = tmp_path / "bad.trc"
    lines[10] = lines[10].replace("\t", "\tx", 1)
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataFileError, match=r"^bad\.trc:11: value 'x0.\d+' in column 2"):
        read_trc(bad)


def test_an_infinite_marker_value_is_refused(tmp_path: Path, subject01: Path) -> None:
    lines = (subject01 / "subject01_walk1.trc").read_text().splitlines()
    cells = lines[8].split("\t")
    cells[4] = "inf"
    bad = tmp_path / "bad.trc"
    bad.write_text("\n".join([*lines[:8], "\t".join(cells), *lines[9:]]) + "\n")
    with pytest.raises(DataFileError, match=r"^bad\.trc:9: value 'inf' in column 5 is not finite"):
        read_trc(bad)
    cells[4] = "nan"  # control: an explicit NaN is a gap, as an empty cell is
    bad.write_text("\n".join([*lines[:8], "\t".join(cells), *lines[9:]]) + "\n")
    assert np.isnan(read_trc(bad).positions[2, 0, 2])
