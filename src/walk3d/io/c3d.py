"""C3D motion-capture files read with ezc3d, converted to SI units (metres, N, N m).

Points (markers) come back as ``(N, M, 3)`` arrays in metres with NaN where the marker was not
seen (negative residual); analog channels as ``(N_analog, C)`` with their labels and units;
force platforms (when the file describes them) as force, moment, centre of pressure and free
moment ``(N_analog, 3)`` in the lab frame as computed by ezc3d's force-platform filter.

Truncation is checked against the frame numbers in the file's own 512-byte header, because
ezc3d silently returns the frames it could read.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.errors import DataFileError
from walk3d.io.trc import LENGTH_UNITS

__all__ = ["AnalogData", "C3dData", "ForcePlatform", "PointData", "read_c3d"]

_MOMENT_UNITS = {"nmm": 1e-3, "n.mm": 1e-3, "n*mm": 1e-3, "nm": 1.0, "n.m": 1.0, "n*m": 1.0}


def _frozen(array: np.ndarray) -> np.ndarray:
    out = np.array(array, dtype=float)
    out.flags.writeable = False
    return out


@dataclass(frozen=True)
class PointData:
    """Marker trajectories: ``positions`` ``(N, M, 3)`` in metres, ``residuals`` ``(N, M)``."""

    labels: tuple[str, ...]
    rate: float
    positions: np.ndarray
    residuals: np.ndarray
    units: str

    def marker(self, label: str) -> np.ndarray:
        """Trajectory of one marker, ``(N, 3)`` in metres."""
        try:
            return self.positions[:, self.labels.index(label), :]
        except ValueError:
            raise KeyError(f"no point {label!r}") from None


@dataclass(frozen=True)
class AnalogData:
    """Analog channels, ``values`` ``(N_analog, C)`` scaled by ezc3d, in the file's units."""

    labels: tuple[str, ...]
    rate: float
    values: np.ndarray
    units: tuple[str, ...]

    def channel(self, label: str) -> np.ndarray:
        """Samples of one channel, ``(N_analog,)``."""
        try:
            return self.values[:, self.labels.index(label)]
        except ValueError:
            raise KeyError(f"no analog channel {label!r}") from None


@dataclass(frozen=True)
class ForcePlatform:
    """One force platform in the lab frame, sampled at the analog ``rate``.

    ``force`` in N, ``moment`` (about the lab origin, as ezc3d reports it) and ``free_moment``
    in N m, ``cop``, ``corners`` ``(4, 3)`` and ``origin`` ``(3,)`` in metres.
    """

    index: int
    type: int
    rate: float
    force: np.ndarray
    moment: np.ndarray
    cop: np.ndarray
    free_moment: np.ndarray
    corners: np.ndarray
    origin: np.ndarray


@dataclass(frozen=True)
class C3dData:
    """Contents of a C3D file. ``first_frame`` is 1-based as in the C3D header."""

    path: Path
    first_frame: int
    points: PointData
    analogs: AnalogData
    platforms: tuple[ForcePlatform, ...]

    @property
    def time(self) -> np.ndarray:
        """Time of each point frame (s), with the first frame at ``(first_frame - 1) / rate``."""
        n = self.points.positions.shape[0]
        return (np.arange(n) + self.first_frame - 1) / self.points.rate


def _raw_frames(path: Path) -> tuple[int, int] | None:
    """First and last frame from the C3D header, or ``None`` when they do not look usable."""
    with path.open("rb") as handle:
        head = handle.read(512)
        if len(head) < 512 or head[1] != 0x50:
            raise DataFileError(path, "not a C3D file (bad header block)")
        handle.seek((head[0] - 1) * 512 + 3)
        proc = handle.read(1)
    endian = ">" if proc and proc[0] == 86 else "<"  # 84 Intel, 85 DEC, 86 MIPS
    first, last = struct.unpack(endian + "HH", head[6:10])
    if last == 0xFFFF or last < first:
        return None
    return first, last


def _platforms_used(params: object) -> bool:
    """Whether the parameters declare at least one force platform."""
    if "FORCE_PLATFORM" not in params.keys():  # type: ignore[attr-defined]
        return False
    group = params["FORCE_PLATFORM"]  # type: ignore[index]
    used = np.ravel(group["USED"]["value"]) if "USED" in group else []
    return bool(len(used)) and int(used[0]) > 0


def _labels(group: dict, key: str) -> tuple[str, ...]:
    if key not in group:
        return ()
    return tuple(str(v).strip() for v in group[key]["value"])


def _length_scale(unit: str, path: Path) -> float:
    key = unit.strip().lower()
    if key not in LENGTH_UNITS:
        raise DataFileError(path, f"unknown length unit {unit!r}")
    return LENGTH_UNITS[key]


def read_c3d(path: str | PathLike[str], *, force_platforms: bool = True) -> C3dData:
    """Read a C3D file with ezc3d.

    Args:
        path: The ``.c3d`` file.
        force_platforms: Also compute force-platform data (needs a ``FORCE_PLATFORM`` group).

    Raises:
        FileNotFoundError: No such file.
        DataFileError: Not a C3D file, unreadable parameters, unknown units, or fewer frames
            than the header declares (truncated file).
    """
    import ezc3d

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(path)
    frames = _raw_frames(path)
    try:
        c3d = ezc3d.c3d(str(path), extract_forceplat_data=False)
    except (RuntimeError, OSError, ValueError) as exc:
        raise DataFileError(path, f"cannot be read by ezc3d: {exc}") from None
    try:
        raw_platforms = []
        if force_platforms and _platforms_used(c3d["parameters"]):
            raw_platforms = ezc3d.c3d(str(path), extract_forceplat_data=True)["data"]["platform"]
    except (RuntimeError, OSError, ValueError) as exc:
        raise DataFileError(path, f"force platform data unusable: {exc}") from None
    params = c3d["parameters"]
    raw_points = np.asarray(c3d["data"]["points"], dtype=float)
    n = raw_points.shape[2]
    if frames is not None and n < frames[1] - frames[0] + 1:
        declared = frames[1] - frames[0] + 1
        raise DataFileError(path, f"header declares {declared} frames, found {n} (truncated file)")

    point_group = params["POINT"]
    units = _labels(point_group, "UNITS")
    unit = units[0] if units else "mm"
    scale = _length_scale(unit, path)
    positions = np.transpose(raw_points[:3], (2, 1, 0)) * scale
    residuals = np.asarray(c3d["data"]["meta_points"]["residuals"], dtype=float)
    residuals = residuals.reshape(-1, raw_points.shape[1], n)[0].T
    positions[residuals < 0] = np.nan
    point_rate = float(np.ravel(point_group["RATE"]["value"])[0])
    points = PointData(
        _labels(point_group, "LABELS")[: raw_points.shape[1]],
        point_rate,
        _frozen(positions),
        _frozen(residuals),
        unit,
    )

    analog_group = params["ANALOG"]
    raw_analogs = np.asarray(c3d["data"]["analogs"], dtype=float)
    values = raw_analogs.reshape(-1, raw_analogs.shape[-1]) if raw_analogs.size else None
    rate_values = np.ravel(analog_group["RATE"]["value"]) if "RATE" in analog_group else []
    analog_rate = float(rate_values[0]) if len(rate_values) else 0.0
    analog_values = np.zeros((0, 0)) if values is None else values.T
    analog_labels = _labels(analog_group, "LABELS")[: analog_values.shape[1]]
    analogs = AnalogData(
        analog_labels,
        analog_rate,
        _frozen(analog_values),
        _labels(analog_group, "UNITS")[: analog_values.shape[1]],
    )

    platforms: list[ForcePlatform] = []
    if raw_platforms:
        fp_group = params["FORCE_PLATFORM"]
        types = np.ravel(fp_group["TYPE"]["value"]) if "TYPE" in fp_group else []
        for k, pf in enumerate(raw_platforms):
            lscale = _length_scale(str(pf["unit_position"]), path)
            munit = str(pf["unit_moment"]).strip().lower()
            if munit not in _MOMENT_UNITS:
                raise DataFileError(path, f"unknown moment unit {pf['unit_moment']!r}")
            mscale = _MOMENT_UNITS[munit]
            platforms.append(
                ForcePlatform(
                    index=k,
                    type=int(types[k]) if k < len(types) else 0,
                    rate=analog_rate,
                    force=_frozen(np.asarray(pf["force"]).T),
                    moment=_frozen(np.asarray(pf["moment"]).T * mscale),
                    cop=_frozen(np.asarray(pf["center_of_pressure"]).T * lscale),
                    free_moment=_frozen(np.asarray(pf["Tz"]).T * mscale),
                    corners=_frozen(np.asarray(pf["corners"]).T * lscale),
                    origin=_frozen(np.asarray(pf["origin"]).reshape(3) * lscale),
                )
            )
    first = frames[0] if frames is not None else int(c3d["header"]["points"]["first_frame"]) + 1
    return C3dData(path, first, points, analogs, tuple(platforms))
