"""C3D reading with ezc3d: synthetic round trip in metres, force platform, damaged files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from c3d_support import write_c3d

from walk3d.io import DataFileError, read_c3d

ezc3d = pytest.importorskip("ezc3d")

N_FRAMES, POINT_RATE, ANALOG_RATE = 20, 100.0, 1000.0


def _write_synthetic(path: Path, bad_fz: float | None = None) -> np.ndarray:
    """Two markers in mm moving 1 m/s along x, six plate channels; returns positions (m).
    ``bad_fz`` replaces Fz in analog samples 31-40."""
    t = np.arange(N_FRAMES) / POINT_RATE
    pos_m = np.zeros((N_FRAMES, 2, 3))
    pos_m[:, 0] = np.column_stack([t, np.full_like(t, 0.05), np.full_like(t, 0.1)])
    pos_m[:, 1] = pos_m[:, 0] + [0.2, -0.02, 0.0]
    points = pos_m * 1000.0
    points[5, 1] = np.nan  # TOE not seen in frame 5
    channels = np.zeros((N_FRAMES * int(ANALOG_RATE / POINT_RATE), 6))
    channels[:, 2] = -700.0  # plate pushed down by 700 N
    channels[:, 3] = 700.0 * 50.0  # Mx, N mm: centre of pressure 50 mm off centre in y
    channels[:, 4] = -700.0 * 100.0  # My, N mm: 100 mm off centre in x
    if bad_fz is not None:
        channels[30:40, 2] = bad_fz
    corners = np.array([[300, 200, 0], [-300, 200, 0], [-300, -200, 0], [300, -200, 0]], float)
    write_c3d(path, point_rate=POINT_RATE, labels=("HEEL", "TOE"), points=points,
              analog_rate=ANALOG_RATE, plates=[channels], corners=[corners],
              origin=(0.0, 0.0, -40.0))  # fmt: skip
    return pos_m


def test_c3d_round_trip_in_metres(tmp_path: Path) -> None:
    path = tmp_path / "walk.c3d"
    expected = _write_synthetic(path)
    data = read_c3d(path)
    assert data.points.labels == ("HEEL", "TOE") and data.points.units == "mm"
    assert data.points.rate == POINT_RATE and data.points.positions.shape == (N_FRAMES, 2, 3)
    ok = np.ones((N_FRAMES, 2), bool)
    ok[5, 1] = False
    np.testing.assert_allclose(data.points.positions[ok], expected[ok], atol=1e-6)
    assert np.isnan(data.points.positions[5, 1]).all()
    speed = np.diff(data.points.marker("HEEL")[:, 0]) * data.points.rate
    np.testing.assert_allclose(speed, 1.0, atol=1e-4)  # 1 m/s after mm -> m
    assert data.first_frame == 1 and data.time[1] == pytest.approx(0.01)

    assert data.analogs.rate == ANALOG_RATE and data.analogs.values.shape == (200, 6)
    np.testing.assert_allclose(data.analogs.channel("Fz1"), -700.0)
    assert data.analogs.units[3] == "Nmm"

    (plate,) = data.platforms
    assert plate.type == 2 and plate.force.shape == (200, 3)
    np.testing.assert_allclose(np.abs(plate.force[0]), [0.0, 0.0, 700.0], atol=1e-9)
    np.testing.assert_allclose(plate.corners[0], [0.3, 0.2, 0.0])  # metres
    np.testing.assert_allclose(np.abs(plate.moment[0, :2]), [35.0, 70.0], rtol=1e-9)  # N m
    assert np.all(np.abs(plate.cop[:, :2]) < 0.3)  # on the plate, in metres
    assert np.linalg.norm(plate.cop[0, :2]) == pytest.approx(np.hypot(0.05, 0.1), abs=0.05)


def test_c3d_without_platforms(tmp_path: Path) -> None:
    path = tmp_path / "walk.c3d"
    _write_synthetic(path)
    assert read_c3d(path, force_platforms=False).platforms == ()


@pytest.mark.parametrize("keep", [0.3, 0.7])
def test_truncated_c3d(tmp_path: Path, keep: float) -> None:
    path = tmp_path / "walk.c3d"
    _write_synthetic(path)
    blob = path.read_bytes()
    cut = tmp_path / "cut.c3d"
    cut.write_bytes(blob[: int(len(blob) * keep)])
    with pytest.raises(DataFileError) as info:
        read_c3d(cut)
    assert str(info.value).startswith("cut.c3d: ") and "\n" not in str(info.value)


def test_not_a_c3d(tmp_path: Path) -> None:
    path = tmp_path / "text.c3d"
    path.write_text("hello\n" * 200)
    with pytest.raises(DataFileError, match=r"^text\.c3d: "):
        read_c3d(path)
    with pytest.raises(FileNotFoundError):
        read_c3d(tmp_path / "missing.c3d")


@pytest.mark.parametrize("bad", [np.nan, np.inf, -500.0])
def test_non_finite_analog_samples_are_refused_naming_channel_and_sample(tmp_path, bad) -> None:
    path = tmp_path / "walk.c3d"
    _write_synthetic(path, bad_fz=bad)
    if np.isfinite(bad):  # control: a finite odd value is data, not an error
        assert read_c3d(path).analogs.channel("Fz1")[30] == bad
        return
    with pytest.raises(DataFileError, match=r"^walk\.c3d: analog channel 'Fz1' is not finite "
                       r"in 10 samples, first at sample 31$"):  # fmt: skip
        read_c3d(path)


def _analog_rate(path: Path, rate: float) -> None:
    """Set the ANALOG:RATE parameter of ``path`` in place (ezc3d writes no such file)."""
    import struct

    blob = bytearray(path.read_bytes())
    groups = {}  # group id -> name, from the group records (negative ids)
    at = blob.find(b"ANALOG", 512)
    groups[256 - blob[at - 1]] = "ANALOG"
    at = blob.find(b"RATE", 512)
    while at > 0:
        if blob[at - 1] in groups:  # this group's RATE: offset, type, no dimension, a float
            blob[at + 8 : at + 12] = struct.pack("<f", rate)
        at = blob.find(b"RATE", at + 4)
    path.write_bytes(bytes(blob))


@pytest.mark.parametrize("rate", [0.0, ANALOG_RATE])
def test_force_platforms_without_analog_samples_are_one_line(tmp_path, rate) -> None:
    """An analog rate of 0 leaves the force platforms without samples: a numpy message
    ('zero-size array to reduction operation fmax...') and two RuntimeWarnings in walk3d
    validate (found while fuzzing C3D rates). Control: the rate it was written with."""
    path = tmp_path / "walk.c3d"
    _write_synthetic(path)
    _analog_rate(path, rate)
    assert ezc3d.c3d(str(path))["parameters"]["ANALOG"]["RATE"]["value"][0] == rate
    if rate:
        assert read_c3d(path).platforms[0].force.shape == (200, 3)
        return
    with pytest.raises(DataFileError, match=r"^walk\.c3d: the analog rate 0\.0 is not a positive "
                       r"number: the force platforms have no samples$"):  # fmt: skip
        read_c3d(path)
