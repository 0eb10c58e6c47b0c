"""Gait-cycle tables (mean and SD per percent of cycle) from CSV files.

Two layouts are recognised:

* *wide mean/SD* (e.g. ``falisse2019/cycle_right_leg_mean_sd.csv``): a header row whose first
  cell is the percent column (``percent_cycle``, ``percent``, ``%gait cycle``...), then pairs of
  ``<name>_mean`` and ``<name>_sd`` columns; a ``<name>_mean`` without its ``_sd`` gets NaN SD.
* *Winter* (``winter/Winter_normal.csv``): free-text lines (``Gait cycle duration:,,1.1396``)
  kept as metadata, a header row starting ``sample,%gait cycle``, a units row ``(deg)``..., then
  the numbers; empty columns are skipped and the SD is NaN. Names are made snake_case with the
  unit appended as in the wide layout (``knee_angle_deg``, ``vertical_grf_N_per_kg``).
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from walk3d.io.angle_units import check_angles
from walk3d.io.checks import increasing, read_input
from walk3d.io.errors import DataFileError

__all__ = ["COVERAGE", "MAX_ABS_VALUE", "MIN_ROWS", "CycleTable", "read_cycle_table"]

_PERCENT_NAMES = {"percent_cycle", "percent", "%gait cycle", "% gait cycle", "gait_cycle_percent"}
MIN_ROWS = 11
"""Fewest rows of a cycle table: one every 10 % of the cycle (fewer is no measured curve)."""
COVERAGE = (5.0, 95.0)
"""The percent column must start at or before the first and end at or after the second."""
MAX_ABS_VALUE = 1e6
"""Largest magnitude of a cell: far above any gait angle (deg), moment (N m/kg or N m), force
(N/kg or N) or power; a larger value is a unit or export error, and squared it overflows."""
_UNIT_SUFFIXES = ("Nm_per_kg", "N_per_kg", "W_per_kg", "deg", "rad", "m_per_s", "m", "N", "Nm")


@dataclass(frozen=True)
class CycleTable:
    """Mean and SD over a gait cycle.

    Attributes:
        percent: Percent of cycle, shape ``(n,)``.
        names: Variable names, ``k`` of them (unit suffix included, e.g. ``knee_angle_deg``).
        mean: Means, shape ``(n, k)``.
        sd: Standard deviations, shape ``(n, k)`` (NaN where the file gives none).
        units: Unit of each variable as parsed from the name (``""`` when unknown).
        metadata: Free-text ``key: value`` entries of the file (Winter layout), read-only.
    """

    percent: np.ndarray
    names: tuple[str, ...]
    mean: np.ndarray
    sd: np.ndarray
    units: tuple[str, ...] = ()
    metadata: Any = field(default_factory=dict)

    def __post_init__(self) -> None:
        for attr in ("percent", "mean", "sd"):
            value = np.array(getattr(self, attr), dtype=float)
            value.flags.writeable = False
            object.__setattr__(self, attr, value)
        n, k = self.percent.size, len(self.names)
        if self.mean.shape != (n, k) or self.sd.shape != (n, k):
            raise ValueError(f"mean and sd must have shape ({n}, {k})")
        object.__setattr__(self, "metadata", MappingProxyType(dict(self.metadata)))

    def index(self, name: str) -> int:
        """Position of variable ``name`` (``KeyError`` listing the names when absent)."""
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"no variable {name!r}; have {list(self.names)}") from None

    def column(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """``(mean, sd)`` of one variable, each ``(n,)``."""
        k = self.index(name)
        return self.mean[:, k], self.sd[:, k]


def _unit_of(name: str) -> str:
    for suffix in _UNIT_SUFFIXES:
        if name.endswith("_" + suffix):
            return suffix
    return ""


def _snake(text: str) -> str:
    return re.sub(r"[^0-9a-zA-Z]+", "_", text.strip()).strip("_").lower()


def _unit_token(text: str) -> str:
    unit = text.strip().strip("()").strip()
    return unit.replace("/", "_per_").replace(" ", "")


def _to_float(path: Path, line: int, cell: str, what: str) -> float:
    try:
        value = float(cell)
    except ValueError:
        raise DataFileError(path, f"value {cell!r} in {what} is not a number", line) from None
    if not math.isfinite(value):
        raise DataFileError(path, f"value {cell!r} in {what} is not finite", line)
    if abs(value) > MAX_ABS_VALUE:
        raise DataFileError(path, f"value {cell!r} in {what} is beyond ±{MAX_ABS_VALUE:g}", line)
    if value < 0 and what.endswith("_sd"):
        raise DataFileError(path, f"value {cell!r} in {what} is a negative SD", line)
    return value


def _no_repeats(path: Path, line: int, names: list[str], cells: list[str] | None = None) -> None:
    """Refuse a header whose ``names`` (as read; ``cells``: as written) hold one twice: the
    reader would keep one of them and silently ignore the other."""
    seen: dict[str, int] = {}
    for k, name in enumerate(names):
        if name in seen:
            shown = name if cells is None else cells[k]
            again = "" if cells is None or cells[seen[name]] == shown else (
                f" (as {cells[seen[name]]!r} and {shown!r})")  # fmt: skip
            raise DataFileError(path, f"column {shown!r} appears twice{again}", line)
        seen[name] = k


def _read_wide(path: Path, rows: list[tuple[int, list[str]]]) -> CycleTable:
    head_line, header = rows[0]
    _no_repeats(path, head_line, [c for c in header if c])
    names: list[str] = []
    for cell in header[1:]:
        if cell.endswith("_mean"):
            names.append(cell[: -len("_mean")])
        elif not cell.endswith("_sd") and cell:
            raise DataFileError(path, f"column {cell!r} is neither _mean nor _sd", head_line)
    mean_col = {name: header.index(name + "_mean") for name in names}
    sd_col = {name: header.index(name + "_sd") for name in names if name + "_sd" in header}
    percent, mean, sd = [], [], []
    for line, cells in rows[1:]:
        if len(cells) != len(header):
            raise DataFileError(path, f"expected {len(header)} values, found {len(cells)}", line)
        percent.append(_to_float(path, line, cells[0], header[0]))
        mean.append([_to_float(path, line, cells[mean_col[n]], n + "_mean") for n in names])
        sd.append(
            [
                _to_float(path, line, cells[sd_col[n]], n + "_sd") if n in sd_col else np.nan
                for n in names
            ]
        )
    if not percent:
        raise DataFileError(path, "no data rows", head_line)
    shape = (len(percent), len(names))
    return CycleTable(
        np.array(percent),
        tuple(names),
        np.array(mean, dtype=float).reshape(shape),
        np.array(sd, dtype=float).reshape(shape),
        tuple(_unit_of(n) for n in names),
    )


def _read_winter(path: Path, rows: list[tuple[int, list[str]]], start: int) -> CycleTable:
    metadata = {}
    for _, cells in rows[:start]:
        values = [c for c in cells if c]
        if values and values[0].endswith(":"):
            metadata[values[0].rstrip(":").strip()] = " ".join(values[1:])
    head_line, header = rows[start]
    if start + 1 >= len(rows):
        raise DataFileError(path, "no units row after the header", head_line)
    _, unit_cells = rows[start + 1]
    pct_col = next(i for i, c in enumerate(header) if c.strip().lower() in _PERCENT_NAMES)
    cols, names, units = [], [], []
    for i, cell in enumerate(header):
        if i == pct_col or not cell.strip() or cell.strip().lower() == "sample":
            continue
        unit = _unit_token(unit_cells[i]) if i < len(unit_cells) else ""
        cols.append(i)
        names.append(_snake(cell) + (f"_{unit}" if unit else ""))
        units.append(unit)
    _no_repeats(path, head_line, names, [header[i].strip() for i in cols])
    percent, mean = [], []
    for line, cells in rows[start + 2 :]:
        if not any(cells):
            continue
        if len(cells) < len(header):
            raise DataFileError(path, f"expected {len(header)} values, found {len(cells)}", line)
        percent.append(_to_float(path, line, cells[pct_col], "percent"))
        mean.append([_to_float(path, line, cells[i], names[j]) for j, i in enumerate(cols)])
    if not percent:
        raise DataFileError(path, "no data rows", head_line)
    means = np.array(mean, dtype=float).reshape(len(percent), len(cols))
    return CycleTable(
        np.array(percent), tuple(names), means, np.full_like(means, np.nan), tuple(units), metadata
    )


def _cycle(path: Path, table: CycleTable) -> CycleTable:
    """``table`` if it is a gait cycle: :data:`MIN_ROWS` rows or more, percent increasing
    within 0-100 and covering :data:`COVERAGE`, not every mean constant, and angles plausible
    for their ``_deg`` or ``_rad`` unit (:mod:`walk3d.io.angle_units`)."""
    n = table.percent.size
    if n < MIN_ROWS:
        raise DataFileError(path, f"{n} data rows: a cycle table needs {MIN_ROWS} or more")
    percent = increasing(path, "the percent-of-cycle column", table.percent)
    lo, hi = COVERAGE
    if percent[0] < 0 or percent[-1] > 100 or percent[0] > lo or percent[-1] < hi:
        raise DataFileError(path, f"the percent-of-cycle column runs {percent[0]:g}-"
                            f"{percent[-1]:g}, not over 0-100 % of a cycle")  # fmt: skip
    if table.names and (np.ptp(table.mean, axis=0) == 0).all():
        raise DataFileError(path, "every column is constant over the cycle")
    scale = {"deg": 1.0, "rad": np.degrees(1.0)}
    angles = {name: scale[unit] * table.mean[:, k]
              for k, (name, unit) in enumerate(zip(table.names, table.units, strict=True))
              if unit in scale}  # fmt: skip
    units = sorted({unit for unit in table.units if unit in scale})
    check_angles(path, angles, " or ".join(f"_{u} columns" for u in units) or "degrees")
    return table


def read_cycle_table(path: str | PathLike[str]) -> CycleTable:
    """Read a cycle-table CSV (wide mean/SD or Winter layout, see the module doc).

    Raises:
        DataFileError: No recognisable header, a column named twice, a row of the wrong
            length, a cell longer than
            the csv module's limit, a non-number, a non-finite value, one beyond
            :data:`MAX_ABS_VALUE` or a negative SD; or no gait cycle (:func:`_cycle`): too few
            rows, the percent not increasing over 0-100 %, every column constant.
    """
    path = Path(path)
    try:
        text = read_input(path).decode("utf-8-sig")
    except UnicodeDecodeError:
        raise DataFileError(path, "not a text file (invalid UTF-8)") from None
    rows, reader = [], csv.reader(text.splitlines())
    try:
        for number, cells in enumerate(reader, start=1):
            rows.append((number, [c.strip() for c in cells]))
    except csv.Error as exc:  # a cell longer than csv.field_size_limit(), 131 072 characters
        limit = f"longer than {csv.field_size_limit()} characters"
        reason = "a cell " + limit if "field limit" in str(exc) else f"not CSV: {exc}"
        raise DataFileError(path, reason, reader.line_num) from None
    rows = [(n, c) for n, c in rows if any(c)] or [(1, [])]
    first = rows[0][1]
    if first and first[0].lower() in _PERCENT_NAMES:
        return _cycle(path, _read_wide(path, rows))
    for k, (_, cells) in enumerate(rows):
        if any(c.lower() in _PERCENT_NAMES for c in cells[:3]):
            return _cycle(path, _read_winter(path, rows, k))
    raise DataFileError(path, "no percent-of-cycle header row found", rows[0][0])
