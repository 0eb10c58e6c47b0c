"""C3D writing with ezc3d (walk3d.io.c3d_write): a synthetic trial read back with read_c3d."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from walk3d.io import read_c3d
from walk3d.io.c3d_write import C3dEvent, PlateLoads, file_rate, plate_axes, write_c3d

ezc3d = pytest.importorskip("ezc3d")

RATE, RATIO, FRAMES = 92.41585326673291, 10, 12  # walk3d's 100 samples over 1.082 s
LAB_Z_DOWN = np.array([[0.3, -0.2, 0], [-0.3, -0.2, 0], [-0.3, 0.2, 0], [0.3, 0.2, 0]], float)
LAB_Z_UP = LAB_Z_DOWN[[3, 2, 1, 0]]


def _synthetic(corners: np.ndarray):
    """Points (m), a plate under a 700 N load at a known centre of pressure with a 3 N m free
    moment, all in a Z-up lab; returns the arguments and the expected CoP (A, 3)."""
    rng = np.random.default_rng(3)
    points = rng.normal(size=(FRAMES, 2, 3))
    a = FRAMES * RATIO
    corners = corners + [1.0, 0.5, 0.0]
    force = np.column_stack([np.linspace(-50, 80, a), np.full(a, 20.0), np.full(a, -700.0)])
    cop = corners.mean(axis=0) + np.column_stack([np.linspace(-0.2, 0.25, a), np.full(a, 0.05),
                                                  np.zeros(a)])  # fmt: skip
    free = np.array([0.0, 0.0, 3.0])
    moment = np.cross(cop - corners.mean(axis=0), force) + free
    return points, PlateLoads(corners, force, moment), cop


@pytest.mark.parametrize("corners", [LAB_Z_DOWN, LAB_Z_UP], ids=["plate z down", "plate z up"])
def test_write_c3d_round_trip_through_read_c3d(tmp_path: Path, corners) -> None:
    points, plate, cop = _synthetic(corners)
    path = write_c3d(tmp_path / "t.c3d", ["A", "B"], points, RATE, plates=[plate],
                     analog_ratio=RATIO)  # fmt: skip
    data = read_c3d(path)
    assert data.points.labels == ("A", "B") and data.points.units == "mm"
    assert data.points.rate == file_rate(RATE) == pytest.approx(RATE, rel=1e-5)
    assert data.analogs.rate == RATIO * data.points.rate  # exact in the file's floats
    np.testing.assert_allclose(data.points.positions, points, atol=1e-6)
    (p,) = data.platforms
    assert p.type == 2 and p.force.shape == (FRAMES * RATIO, 3)
    np.testing.assert_allclose(p.force, plate.force, atol=1e-3)
    np.testing.assert_allclose(p.cop, cop, atol=1e-6)
    np.testing.assert_allclose(p.free_moment, np.tile([0.0, 0.0, 3.0], (FRAMES * RATIO, 1)),
                               atol=1e-3)  # fmt: skip
    np.testing.assert_allclose(p.corners, plate.corners, atol=1e-9)
    np.testing.assert_allclose(p.origin, 0.0)
    z = plate_axes(plate.corners)[:, 2]
    assert z[2] == (-1.0 if corners is LAB_Z_DOWN else 1.0)
    # the channels are in the plate frame: Fz flips with the plate's z axis
    assert np.all(data.analogs.channel("Fz1") * z[2] == -700.0)


def test_an_unrounded_rate_is_misread_which_file_rate_prevents(tmp_path: Path) -> None:
    """Negative control of the round trip: ezc3d derives the analog samples per frame from
    float32(ratio * rate) / float32(rate), 9.99... -> 9 at walk3d's rate, and then misreads
    every frame; :func:`file_rate` makes the quotient exact."""
    points, plate, _ = _synthetic(LAB_Z_DOWN)
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [RATE]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = ("A", "B")
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    raw = np.ones((4, 2, FRAMES))
    raw[:3] = np.transpose(points * 1000.0, (2, 1, 0))
    c3d["data"]["points"] = raw
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = [RATE * RATIO]
    c3d["parameters"]["ANALOG"]["LABELS"]["value"] = ("Fz1",)
    c3d["data"]["analogs"] = plate.force[:, 2].reshape(1, 1, -1)
    c3d.write(str(tmp_path / "raw.c3d"))
    back = ezc3d.c3d(str(tmp_path / "raw.c3d"))
    assert back["data"]["analogs"].shape[-1] == FRAMES * (RATIO - 1)  # samples lost
    assert not np.allclose(back["data"]["points"][:3], raw[:3], atol=1e-3)
    fixed = write_c3d(tmp_path / "fixed.c3d", ["A", "B"], points, RATE, plates=[plate],
                      analog_ratio=RATIO)  # fmt: skip
    assert ezc3d.c3d(str(fixed))["data"]["analogs"].shape[-1] == FRAMES * RATIO


def test_events_and_screen_axes_are_written(tmp_path: Path) -> None:
    points, plate, _ = _synthetic(LAB_Z_DOWN)
    events = [C3dEvent("Right", "Foot Strike", 0.0), C3dEvent("Left", "Foot Off", 0.0649)]
    path = write_c3d(tmp_path / "e.c3d", ["A", "B"], points, RATE, plates=[plate],
                     analog_ratio=RATIO, events=events)  # fmt: skip
    params = ezc3d.c3d(str(path))["parameters"]
    ev = params["EVENT"]
    assert ev["CONTEXTS"]["value"] == ["Right", "Left"]
    assert ev["LABELS"]["value"] == ["Foot Strike", "Foot Off"]
    np.testing.assert_allclose(ev["TIMES"]["value"][1], [0.0, 0.0649], atol=1e-6)
    assert list(ev["ICON_IDS"]["value"]) == [1, 2]
    assert params["POINT"]["X_SCREEN"]["value"] == ["+X"]
    assert params["POINT"]["Y_SCREEN"]["value"] == ["+Z"]
    assert list(params["FORCE_PLATFORM"]["ZERO"]["value"]) == [0, 0]


def test_a_failed_write_leaves_the_earlier_file_and_no_temporary(tmp_path, monkeypatch) -> None:
    points, plate, _ = _synthetic(LAB_Z_DOWN)
    path = tmp_path / "t.c3d"
    path.write_bytes(b"earlier")

    def broken(self, name, **kwargs):
        Path(name).write_bytes(b"half")
        raise OSError(28, "No space left on device")

    with monkeypatch.context() as m:
        m.setattr(ezc3d.c3d, "write", broken)
        with pytest.raises(OSError, match="No space"):
            write_c3d(path, ["A", "B"], points, RATE, plates=[plate], analog_ratio=RATIO)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.c3d"]
    assert path.read_bytes() == b"earlier"
    write_c3d(path, ["A", "B"], points, RATE, plates=[plate], analog_ratio=RATIO)
    assert read_c3d(path).points.labels == ("A", "B")  # control: a good write replaces it


@pytest.mark.parametrize(
    "change, message",
    [
        ({"points": np.full((FRAMES, 2, 3), np.nan)}, "points holds NaN"),
        ({"points": np.zeros((FRAMES, 3, 3))}, "points must have shape"),
        ({"analog_ratio": 3}, "plate 1 force must have shape"),
        ({"analog_ratio": 2.5}, "analog_ratio a positive integer"),
        ({"rate": 0.0}, "rate must be > 0"),
    ],
)
def test_inconsistent_input_is_refused_before_writing(tmp_path, change, message) -> None:
    points, plate, _ = _synthetic(LAB_Z_DOWN)
    args = {"points": points, "rate": RATE, "analog_ratio": RATIO, **change}
    with pytest.raises(ValueError, match=message):
        write_c3d(tmp_path / "t.c3d", ["A", "B"], args["points"], args["rate"], plates=[plate],
                  analog_ratio=args["analog_ratio"])  # fmt: skip
    assert list(tmp_path.iterdir()) == []
