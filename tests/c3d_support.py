"""Synthetic C3D files written with ezc3d, shared by the io and validation tests."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

PLATE_CHANNELS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def write_c3d(
    path: Path,
    *,
    point_rate: float,
    labels: Sequence[str],
    points: np.ndarray,
    analog_rate: float,
    plates: Sequence[np.ndarray] = (),
    corners: Sequence[np.ndarray] = (),
    origin: Sequence[float] = (0.0, 0.0, 0.0),
) -> Path:
    """Write a C3D file with points in mm and type-2 force platforms.

    Args:
        points: ``(N, M, 3)`` point values as stored (mm, or degrees for angle points); NaN for
            a point not seen.
        plates: Per plate ``(N * analog_rate / point_rate, 6)`` channels Fx, Fy, Fz (N) and
            Mx, My, Mz (N mm) in the plate frame.
        corners: Per plate ``(4, 3)`` corners in mm, lab frame.
        origin: Plate origin relative to the surface centre, mm (the same for every plate).
    """
    import ezc3d

    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [point_rate]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = tuple(labels)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    raw = np.ones((4, points.shape[1], points.shape[0]))
    raw[:3] = np.transpose(points, (2, 1, 0))
    c3d["data"]["points"] = raw
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = [analog_rate]
    if plates:
        labels_a = tuple(f"{c}{k + 1}" for k in range(len(plates)) for c in PLATE_CHANNELS)
        units = ("N", "N", "N", "Nmm", "Nmm", "Nmm") * len(plates)
        c3d["parameters"]["ANALOG"]["LABELS"]["value"] = labels_a
        c3d["parameters"]["ANALOG"]["UNITS"]["value"] = units
        c3d["data"]["analogs"] = np.concatenate([p.T for p in plates])[np.newaxis]
        n = len(plates)
        fp = c3d["parameters"]["FORCE_PLATFORM"]
        fp["USED"]["value"] = np.array([n])
        fp["TYPE"]["value"] = np.full(n, 2)
        fp["CORNERS"]["value"] = np.stack([np.asarray(c, float).T for c in corners], axis=-1)
        fp["ORIGIN"]["value"] = np.tile(np.asarray(origin, float).reshape(3, 1), (1, n))
        fp["CHANNEL"]["value"] = np.arange(1, 6 * n + 1).reshape(n, 6).T
        fp["CAL_MATRIX"]["value"] = np.zeros((6, 6, n))
    c3d.write(str(path))
    return path
