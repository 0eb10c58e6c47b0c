"""C3D motion-capture files read with ezc3d, converted to SI units (metres, N, N m).

Points (markers) come back as ``(N, M, 3)`` arrays in metres with NaN where the marker was not
seen (negative residual); analog channels as ``(N_analog, C)`` with their labels and units;
force platforms (when the file describes them) as force, moment, centre of pressure and free
moment ``(N_analog, 3)`` in the lab frame as computed by ezc3d's force-platform filter.

Truncation is checked against the frame numbers in the file's own 512-byte header, because
ezc3d silently returns the frames it could read.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.io.checks import open_input
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
    """First and last frame from the C3D header, or ``None`` when they do not look usable.

    Also walks the parameter section (:func:`_check_parameters`) so that a damaged one is
    refused here rather than sending ezc3d into an endless loop.
    """
    with open_input(path) as handle:
        head = handle.read(512)
        if len(head) < 512 or head[1] != 0x50 or head[0] < 1:
            raise DataFileError(path, "not a C3D file (bad header block)")
        handle.seek((head[0] - 1) * 512)
        section = handle.read(4)
        if len(section) < 4:
            raise DataFileError(path, "the parameter section is missing (truncated file)")
        section += handle.read(max(section[2], 1) * 512 - 4)
    endian = ">" if section[3] == 86 else "<"  # 84 Intel, 85 DEC, 86 MIPS
    _check_parameters(path, section, endian)
    first, last = struct.unpack(endian + "HH", head[6:10])
    if last == 0xFFFF or last < first:
        return None
    return first, last


def _check_parameters(path: Path, section: bytes, endian: str) -> None:
    """Refuse a parameter section whose entries point backwards or outside it, or whose data
    do not fit their entry (C3D format: name length, id, name, int16 offset to the next)."""
    pos, end = 4, len(section)
    while pos + 2 <= end:
        n, ident = abs(struct.unpack("b", section[pos : pos + 1])[0]), section[pos + 1]
        if n == 0:
            return
        at = pos + 2 + n
        if at + 2 > end:
            raise DataFileError(path, "the parameter section is damaged (truncated entry)")
        (offset,) = struct.unpack(endian + "h", section[at : at + 2])
        if offset == 0:
            return
        nxt = at + offset
        if offset < 0 or nxt > end:
            raise DataFileError(path, "the parameter section is damaged (an entry points "
                                      "outside it)")  # fmt: skip
        if ident < 128 and at + 4 <= nxt:  # a parameter: type, dimensions, data
            kind, ndim = struct.unpack("bB", section[at + 2 : at + 4])
            dims = section[at + 4 : at + 4 + ndim]
            size = abs(kind) * int(np.prod(list(dims), dtype=np.int64))
            if kind not in (-1, 1, 2, 4) or at + 4 + ndim + size > nxt:
                raise DataFileError(path, "the parameter section is damaged (a parameter's "
                                          "data do not fit its entry)")  # fmt: skip
        pos = nxt


def _platforms_used(params: object) -> bool:
    """Whether the parameters declare at least one force platform."""
    if "FORCE_PLATFORM" not in params.keys():  # type: ignore[attr-defined]
        return False
    group = params["FORCE_PLATFORM"]  # type: ignore[index]
    used = np.ravel(group["USED"]["value"]) if "USED" in group else []
    return bool(len(used)) and int(used[0]) > 0


def _check_finite(path: Path, values: np.ndarray, labels: tuple[str, ...], what: str) -> None:
    """Refuse NaN or infinite samples (time first), naming the first channel and frame."""
    bad = ~np.isfinite(values)
    if not bad.any():
        return
    frame, channel = np.argwhere(bad)[0]
    name = labels[channel] if channel < len(labels) else f"#{channel + 1}"
    raise DataFileError(path, f"{what} {name!r} is not finite in {int(bad[:, channel].sum())} "
                              f"samples, first at sample {frame + 1}")  # fmt: skip


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
        DataFileError: Not a regular file (a folder, FIFO...), not a C3D file, unreadable
            parameters, unknown units, or fewer frames than the header declares (truncated
            file).
    """
    import ezc3d

    path = Path(path)
    frames = _raw_frames(path)  # FileNotFoundError, or a folder or FIFO refused
    try:
        c3d = ezc3d.c3d(str(path), extract_forceplat_data=False)
    except (RuntimeError, OSError, ValueError) as exc:
        raise DataFileError(path, f"cannot be read by ezc3d: {exc}") from None
    try:
        raw_platforms = []
        if force_platforms and _platforms_used(c3d["parameters"]):
            raw_platforms = ezc3d.c3d(str(path), extract_forceplat_data=True)["data"]["platform"]
    except (RuntimeError, OSError, ValueError, IndexError, KeyError, TypeError) as exc:
        raise DataFileError(path, f"force platform data unusable: {exc}") from None
    try:
        return _interpret(path, c3d, raw_platforms, frames)
    except DataFileError:
        raise
    except (ValueError, IndexError, KeyError, TypeError, AttributeError) as exc:
        reason = " ".join(f"{type(exc).__name__}: {exc}".split())[:200]
        raise DataFileError(path, f"inconsistent C3D content ({reason})") from None


def _interpret(
    path: Path, c3d: Any, raw_platforms: list, frames: tuple[int, int] | None
) -> C3dData:
    """Points, analogs and platforms of an ezc3d object in walk3d's units."""
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
    _check_finite(path, analog_values, analog_labels, "analog channel")
    if not (math.isfinite(point_rate) and point_rate > 0):
        raise DataFileError(path, f"the point rate {point_rate!r} is not a positive number")
    rate_ok = math.isfinite(analog_rate) and analog_rate > 0
    if (analog_values.size or raw_platforms) and not rate_ok:  # rate 0: platforms unsampled
        platforms = ": the force platforms have no samples" if raw_platforms else ""
        why = f"the analog rate {analog_rate!r} is not a positive number{platforms}"
        raise DataFileError(path, why)
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
