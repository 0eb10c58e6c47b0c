"""Marker trajectories in ``.trc`` (track row column) files, converted to metres.

Layout: line 1 ``PathFileType ...``; line 2 header keys (``DataRate``, ``CameraRate``,
``NumFrames``, ``NumMarkers``, ``Units``, ...); line 3 their values; line 4 ``Frame#``, ``Time``
and the marker labels (each followed by two empty cells); line 5 the ``X1 Y1 Z1 ...`` labels;
then one row per frame (blank lines are ignored). Cells are tab separated; an empty cell is a
missing (occluded) coordinate and becomes NaN. Files without any tab are split on whitespace
(then no cell can be empty).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from walk3d.io.checks import read_input
from walk3d.io.errors import DataFileError

__all__ = ["LENGTH_UNITS", "TrcData", "read_trc"]

#: Metres per unit for the length units found in lab files.
LENGTH_UNITS = {"mm": 1e-3, "cm": 1e-2, "dm": 1e-1, "m": 1.0, "in": 0.0254, "inch": 0.0254}


@dataclass(frozen=True)
class TrcData:
    """Marker trajectories.

    Attributes:
        name: File name given in the first line (or the file's name).
        rate: ``DataRate`` in Hz.
        frame: Frame numbers, shape ``(N,)``.
        time: Sample times in s, shape ``(N,)``.
        labels: Marker labels, ``M`` of them.
        positions: Marker positions in metres, shape ``(N, M, 3)``; NaN where missing.
        units: The file's original length unit (``"mm"``...).
        header: The header keys and values of lines 2-3, read-only.
    """

    name: str
    rate: float
    frame: np.ndarray
    time: np.ndarray
    labels: tuple[str, ...]
    positions: np.ndarray
    units: str
    header: Any = field(default_factory=dict)

    def __post_init__(self) -> None:
        for attr in ("frame", "time", "positions"):
            value = np.array(getattr(self, attr), dtype=float)
            value.flags.writeable = False
            object.__setattr__(self, attr, value)
        object.__setattr__(self, "header", MappingProxyType(dict(self.header)))

    def marker(self, label: str) -> np.ndarray:
        """Trajectory of one marker in metres, shape ``(N, 3)``."""
        try:
            return self.positions[:, self.labels.index(label), :]
        except ValueError:
            raise KeyError(f"no marker {label!r}") from None


def _cells(line: str) -> list[str]:
    text = line.rstrip("\r\n")
    return [c.strip() for c in text.split("\t")] if "\t" in text else text.split()


def read_trc(path: str | PathLike[str]) -> TrcData:
    """Read a ``.trc`` file; positions are returned in metres.

    Raises:
        DataFileError: Missing header lines, unknown units, marker count disagreeing with
            ``NumMarkers``, a row with too few or too many values, a non-numeric value, or a
            frame count disagreeing with ``NumFrames`` (truncated file). The message names the
            file and line.
    """
    path = Path(path)
    try:
        lines = read_input(path).decode("utf-8-sig").splitlines()
    except UnicodeDecodeError:
        raise DataFileError(path, "not a text file (invalid UTF-8)") from None
    if len(lines) < 5 or not lines[0].strip().lower().startswith("pathfiletype"):
        raise DataFileError(path, "not a TRC file: expected 'PathFileType' and 5 header lines", 1)
    keys, values = _cells(lines[1]), _cells(lines[2])
    header = {k: v for k, v in zip(keys, values, strict=False) if k}
    lowered = {k.lower(): v for k, v in header.items()}

    def number(key: str, kind: type) -> Any:
        try:
            return kind(float(lowered[key.lower()]))
        except (KeyError, ValueError):
            raise DataFileError(path, f"header value {key} missing or not a number", 3) from None

    rate = number("DataRate", float)
    n_frames = number("NumFrames", int)
    n_markers = number("NumMarkers", int)
    units = lowered.get("units", "").strip()
    if units.lower() not in LENGTH_UNITS:
        raise DataFileError(path, f"unknown length unit {units!r}", 3)
    scale = LENGTH_UNITS[units.lower()]

    label_cells = _cells(lines[3])
    if len(label_cells) < 2 or label_cells[0].lower() != "frame#":
        raise DataFileError(path, "expected 'Frame#' and 'Time' labels", 4)
    labels = tuple(c for c in label_cells[2:] if c)
    if len(labels) != n_markers:
        raise DataFileError(path, f"NumMarkers is {n_markers} but {len(labels)} labels found", 4)

    width = 2 + 3 * n_markers
    rows: list[list[float]] = []
    last = 5
    for number_, line in enumerate(lines[5:], start=6):
        if not line.strip():
            continue
        last = number_
        cells = _cells(line)
        extra = cells[width:]
        if len(cells) < width or any(extra):
            found = len(cells)
            while found > width and not cells[found - 1]:
                found -= 1
            raise DataFileError(path, f"expected {width} values, found {found}", number_)
        row = []
        for k, cell in enumerate(cells[:width]):
            if not cell and k >= 2:
                row.append(np.nan)
                continue
            try:
                value = float(cell)
            except ValueError:
                raise DataFileError(
                    path, f"value {cell!r} in column {k + 1} is not a number", number_
                ) from None
            if math.isinf(value) or (k < 2 and math.isnan(value)):
                raise DataFileError(path, f"value {cell!r} in column {k + 1} is not finite",
                                    number_)  # fmt: skip
            row.append(value)
        rows.append(row)
    if len(rows) != n_frames:
        raise DataFileError(path, f"NumFrames is {n_frames} but {len(rows)} rows found", last)

    table = np.array(rows, dtype=float).reshape(len(rows), width)
    name_cells = _cells(lines[0])
    return TrcData(
        name=name_cells[-1] if len(name_cells) > 3 else path.name,
        rate=rate,
        frame=table[:, 0],
        time=table[:, 1],
        labels=labels,
        positions=table[:, 2:].reshape(len(rows), n_markers, 3) * scale,
        units=units,
        header=header,
    )
