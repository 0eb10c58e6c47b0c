"""C3D files written with ezc3d: markers in mm, type-2 force platforms, gait events.

:func:`write_c3d` takes points and platform loads in SI units in the lab frame (any axes; the
caller says which lab axes face right and up on screen) and writes what a lab's file holds:

* ``POINT``: the trajectories in **mm** (``UNITS "mm"``), stored as floats;
* ``FORCE_PLATFORM``: per platform ``TYPE 2`` with six analog channels ``Fx Fy Fz`` (N) and
  ``Mx My Mz`` (N mm) in the plate frame, the frame C3D derives from ``CORNERS`` (x along
  corner 1 - corner 2, y along corner 1 - corner 4, z = x × y), moments about ``ORIGIN (0, 0, 0)``,
  the centre of the plate surface. A zero origin avoids the readers' differing sign conventions
  for it; ``ZERO (0, 0)`` asks for no baseline subtraction (the signals have no offset);
* ``ANALOG``: those channels at ``analog_ratio`` samples per point frame. The point rate is
  rounded to a multiple of :data:`RATE_STEP` (:func:`file_rate`), so that the analog rate is
  exactly ``analog_ratio`` times it in the file's 32-bit floats: readers (ezc3d among them)
  derive the samples per frame from the quotient of the two and truncate it;
* ``EVENT``: optional events (context, label, time in s), as clinical software marks gait events.

The file is written atomically (:mod:`walk3d.io.atomic`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.atomic import atomic_path

__all__ = ["RATE_STEP", "C3dEvent", "PlateLoads", "file_rate", "plate_axes", "write_c3d"]

RATE_STEP = 1.0 / 1024.0
"""Hz: point rates are written as multiples of this, exact in 32-bit floats with their analog
rates below 16 kHz; at 100 Hz the rounding changes times by at most 5 ppm."""

PLATE_CHANNELS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
EVENT_ICONS = {"Foot Strike": 1, "Foot Off": 2}
"""Icon ids of the gait events in Vicon's convention (0 for other labels)."""


@dataclass(frozen=True)
class PlateLoads:
    """One force platform: ``corners`` (4, 3) m in the lab frame, numbered as C3D's plate-frame
    quadrants (+x+y, -x+y, -x-y, +x-y); ``force`` (A, 3) N and ``moment`` (A, 3) N m about the
    centre of the plate surface, the load **on the plate**, lab frame, at the analog rate."""

    corners: np.ndarray
    force: np.ndarray
    moment: np.ndarray


@dataclass(frozen=True)
class C3dEvent:
    """An event: ``context`` ``"Right"``, ``"Left"`` or ``"General"``; ``time`` s from frame 1."""

    context: str
    label: str
    time: float


def file_rate(rate: float) -> float:
    """``rate`` (Hz) as written: rounded to a multiple of :data:`RATE_STEP`."""
    return round(float(rate) / RATE_STEP) * RATE_STEP


def plate_axes(corners: np.ndarray) -> np.ndarray:
    """(3, 3) plate-frame axes as columns in the lab frame, from C3D-numbered ``corners``."""
    c = np.asarray(corners, dtype=float)
    x = c[0] - c[1]
    z = np.cross(x, c[0] - c[3])
    y = np.cross(z, x)
    axes = np.column_stack([x, y, z])
    return axes / np.linalg.norm(axes, axis=0)


def _check(name: str, array: np.ndarray, shape: tuple[int | None, ...]) -> np.ndarray:
    a = np.asarray(array, dtype=float)
    if a.ndim != len(shape) or any(s not in (None, d) for s, d in zip(shape, a.shape, strict=True)):
        raise ValueError(f"{name} must have shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} holds NaN or infinite values")
    return a


def write_c3d(
    path: str | PathLike[str],
    labels: Sequence[str],
    points: np.ndarray,
    rate: float,
    *,
    plates: Sequence[PlateLoads] = (),
    analog_ratio: int = 1,
    events: Sequence[C3dEvent] = (),
    descriptions: Sequence[str] | None = None,
    screen: tuple[str, str] = ("+X", "+Z"),
    software: str = "walk3d",
) -> Path:
    """Write a C3D file (module doc) and return its path.

    Args:
        points: ``(F, M, 3)`` m, lab frame, one row per frame at ``rate`` Hz (finite); the
            file says :func:`file_rate` ``(rate)``.
        plates: Each with ``F * analog_ratio`` samples.
        screen: ``POINT:X_SCREEN`` and ``Y_SCREEN``: the lab axes drawn rightward and upward
            (default: a Z-up lab seen from its side).

    Raises:
        ValueError: Inconsistent shapes, non-finite values or a non-positive rate or ratio.
    """
    import ezc3d

    pts = _check("points", points, (None, len(labels), 3))
    n = pts.shape[0]
    ratio_ok = int(analog_ratio) == analog_ratio and analog_ratio >= 1
    if not (np.isfinite(rate) and file_rate(rate) > 0 and ratio_ok):
        raise ValueError(f"rate must be > 0 and analog_ratio a positive integer, got {rate}, "
                         f"{analog_ratio}")  # fmt: skip
    rate = file_rate(rate)
    c3d = ezc3d.c3d()
    point = c3d["parameters"]["POINT"]
    point["RATE"]["value"] = [rate]
    point["LABELS"]["value"] = tuple(labels)
    point["UNITS"]["value"] = ["mm"]
    raw = np.ones((4, pts.shape[1], n))
    raw[:3] = np.transpose(pts * 1000.0, (2, 1, 0))
    c3d["data"]["points"] = raw
    if descriptions is not None:
        point["DESCRIPTIONS"]["value"] = tuple(descriptions)
    c3d.add_parameter("POINT", "X_SCREEN", [screen[0]])
    c3d.add_parameter("POINT", "Y_SCREEN", [screen[1]])
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = [rate * int(analog_ratio)]
    if plates:
        _add_plates(c3d, plates, n * int(analog_ratio))
    for e in events:
        minutes = int(e.time // 60.0)
        c3d.add_event([minutes, e.time - 60.0 * minutes], context=e.context, label=e.label,
                      icon_id=EVENT_ICONS.get(e.label, 0))  # fmt: skip
    c3d.add_parameter("MANUFACTURER", "COMPANY", [software])
    c3d.add_parameter("MANUFACTURER", "SOFTWARE", [software])

    with atomic_path(path, suffix=".tmp.c3d") as tmp:  # ezc3d writes by file name
        c3d.write(str(tmp))
    return Path(path)


def _add_plates(c3d: object, plates: Sequence[PlateLoads], n_analog: int) -> None:
    """The ``FORCE_PLATFORM`` group and the plates' analog channels (module doc)."""
    channels, labels, corners = [], [], []
    for k, plate in enumerate(plates):
        c = _check(f"plate {k + 1} corners", plate.corners, (4, 3))
        axes = plate_axes(c)
        force = _check(f"plate {k + 1} force", plate.force, (n_analog, 3))
        moment = _check(f"plate {k + 1} moment", plate.moment, (n_analog, 3))
        channels += [force @ axes, moment @ axes * 1000.0]  # lab -> plate frame; N m -> N mm
        labels += [f"{name}{k + 1}" for name in PLATE_CHANNELS]
        corners.append(c.T * 1000.0)
    n = len(plates)
    analog = c3d["parameters"]["ANALOG"]  # type: ignore[index]
    analog["LABELS"]["value"] = tuple(labels)
    analog["UNITS"]["value"] = ("N", "N", "N", "Nmm", "Nmm", "Nmm") * n
    analog["DESCRIPTIONS"]["value"] = tuple(f"force plate {k + 1} {name}" for k in range(n)
                                            for name in PLATE_CHANNELS)  # fmt: skip
    c3d["data"]["analogs"] = np.hstack(channels).T[np.newaxis]  # type: ignore[index]
    fp = c3d["parameters"]["FORCE_PLATFORM"]  # type: ignore[index]
    fp["USED"]["value"] = np.array([n])
    fp["TYPE"]["value"] = np.full(n, 2)
    fp["ZERO"]["value"] = np.array([0, 0])
    fp["CORNERS"]["value"] = np.stack(corners, axis=-1)
    fp["ORIGIN"]["value"] = np.zeros((3, n))
    fp["CHANNEL"]["value"] = np.arange(1, 6 * n + 1).reshape(n, 6).T
    fp["CAL_MATRIX"]["value"] = np.zeros((6, 6, n))
