"""OpenSim storage files (``.mot`` / ``.sto``): reading and atomic writing.

Supported layouts (all seen in OpenSim's own examples and in the lab data walk3d validates
against):

* version 1 headers: a name line, ``key=value`` lines (``version``, ``nRows``, ``nColumns``,
  ``inDegrees``, ...), optional free text and blank lines, then ``endheader``;
* the older SIMM/OpenSim-1 headers with ``datacolumns N``, ``datarows N`` and ``range a b``
  lines (and any ``key=value`` lines) before ``endheader``;
* values separated by tabs or by any whitespace, with or without trailing tabs or padding;
  header lines may carry trailing tabs (as spreadsheet-exported files do).

After ``endheader`` comes one line of column labels (the first is time) and then one row of
numbers per sample. Blank lines are ignored. ``nan``/``inf`` are accepted as numbers, except
in the time column, which must hold 2 or more finite, strictly increasing samples.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import increasing, read_input
from walk3d.io.errors import DataFileError

__all__ = ["Storage", "read_storage", "write_storage"]

_OLD_STYLE_KEYS = ("datacolumns", "datarows", "range")
_TRUE = {"yes", "true", "1", "y"}
_FALSE = {"no", "false", "0", "n"}


@dataclass(frozen=True)
class Storage:
    """Contents of an OpenSim storage file.

    Attributes:
        name: The name from the first header line (``""`` when the header has none).
        time: Sample times, shape ``(N,)``.
        columns: Labels of the data columns, time excluded.
        data: Values, shape ``(N, C)`` with ``C == len(columns)``.
        in_degrees: The ``inDegrees`` flag (``None`` when the header does not say).
        header: All ``key=value`` (and old-style ``key value``) header entries, read-only.
        path: The file the storage was read from, if any (not part of equality).
    """

    name: str
    time: np.ndarray
    columns: tuple[str, ...]
    data: np.ndarray
    in_degrees: bool | None = None
    header: Mapping[str, str] = field(default_factory=dict)
    path: Path | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        time = np.array(self.time, dtype=float).reshape(-1)
        data = np.array(self.data, dtype=float)
        if data.ndim == 1 and len(self.columns) == 1:
            data = data.reshape(-1, 1)
        if data.ndim != 2 or data.shape != (time.size, len(self.columns)):
            raise ValueError(
                f"data must have shape ({time.size}, {len(self.columns)}), got {data.shape}"
            )
        if len(set(self.columns)) != len(self.columns):
            raise ValueError("column labels must be unique")
        time.flags.writeable = False
        data.flags.writeable = False
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "data", data)
        object.__setattr__(self, "columns", tuple(str(c) for c in self.columns))
        object.__setattr__(self, "header", MappingProxyType(dict(self.header)))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Storage):
            return NotImplemented
        return (
            self.name == other.name
            and self.columns == other.columns
            and self.in_degrees == other.in_degrees
            and dict(self.header) == dict(other.header)
            and np.array_equal(self.time, other.time, equal_nan=True)
            and np.array_equal(self.data, other.data, equal_nan=True)
        )

    __hash__ = None  # type: ignore[assignment]

    def __len__(self) -> int:
        return self.time.size

    def has_column(self, name: str) -> bool:
        """Whether a data column with this exact label exists."""
        return name in self.columns

    def index(self, name: str) -> int:
        """Position of column ``name`` in :attr:`columns` (``KeyError`` when absent)."""
        try:
            return self.columns.index(name)
        except ValueError:
            where = f" in {self.path.name}" if self.path is not None else ""
            raise KeyError(f"no column {name!r}{where}") from None

    def column(self, name: str) -> np.ndarray:
        """The values of one column, shape ``(N,)`` (read-only view).

        Raises:
            DataFileError: the column holds NaN or an infinite value (naming the file, the
                column and the first such data row): a command never computes with them.
        """
        if name.lower() == "time" and name not in self.columns:
            values = self.time
        else:
            values = self.data[:, self.index(name)]
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            k = int(bad[0])
            reason = (f"column {name!r} is not finite in {bad.size} rows, first in data row "
                      f"{k + 1} (time {self.time[k]:g} s: {values[k]})")  # fmt: skip
            raise DataFileError(self.path or Path(self.name or "storage"), reason)
        return values

    @property
    def sample_rate(self) -> float:
        """Median sampling rate in Hz (``nan`` for fewer than two samples)."""
        if self.time.size < 2:
            return math.nan
        return float(1.0 / np.median(np.diff(self.time)))


def _split_labels(line: str) -> list[str]:
    if "\t" in line:
        labels = [item.strip() for item in line.rstrip("\r\n").split("\t")]
        while labels and labels[-1] == "":
            labels.pop()
        while labels and labels[0] == "":
            labels.pop(0)
        return labels
    return line.split()


def _parse_flag(value: str) -> bool | None:
    text = value.strip().lower()
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    return None


def _header_int(
    header: Mapping[str, str], keys: Sequence[str], path: Path, line: int
) -> int | None:
    lowered = {k.lower(): v for k, v in header.items()}
    for key in keys:
        if key.lower() in lowered:
            text = lowered[key.lower()].strip()
            try:
                return int(text)
            except ValueError:
                reason = f"header {key}={text!r} is not an integer"
                raise DataFileError(path, reason, line) from None
    return None


def read_storage(path: str | PathLike[str], finite: bool = False) -> Storage:
    """Read an OpenSim ``.mot``/``.sto`` file; with ``finite``, every column must be free of
    NaN and infinite values (else :meth:`Storage.column`'s one line naming the column).

    Raises:
        FileNotFoundError: The file does not exist.
        DataFileError: The file is not a regular file (a folder, FIFO...), or is malformed or
            truncated: no ``endheader``, no column labels,
            duplicate labels, a row with the wrong number of values, a value that is not a
            number, or a row/column count that disagrees with ``nRows``/``nColumns``
            (``datarows``/``datacolumns``), a time that is not finite, fewer than 2 rows, or
            a time that does not strictly increase. The message names the file (and the line).
    """
    path = Path(path)
    raw = read_input(path)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise DataFileError(path, "not a text file (invalid UTF-8)", line) from None
    lines = text.splitlines()

    header: dict[str, str] = {}
    name = ""
    end = None
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if stripped.lower() == "endheader":
            end = number
            break
        if not stripped:
            continue
        if "=" in stripped:
            key, _, value = stripped.partition("=")
            header[key.strip()] = value.strip()
            continue
        words = stripped.split()
        if words[0].lower() in _OLD_STYLE_KEYS:
            header[words[0]] = " ".join(words[1:])
        elif number == 1:
            name = stripped
    if end is None:
        raise DataFileError(path, "missing 'endheader' line", max(len(lines), 1))

    n_rows = _header_int(header, ("nRows", "datarows"), path, end)
    n_cols = _header_int(header, ("nColumns", "datacolumns"), path, end)
    in_degrees = None
    for key, value in header.items():
        if key.lower() == "indegrees":
            in_degrees = _parse_flag(value)

    label_line = end + 1
    while label_line <= len(lines) and not lines[label_line - 1].strip():
        label_line += 1
    if label_line > len(lines):
        raise DataFileError(path, "no column labels after 'endheader'", len(lines))
    labels = _split_labels(lines[label_line - 1])
    if any(not label for label in labels):
        raise DataFileError(path, "empty column label", label_line)
    if len(set(labels)) != len(labels):
        twice = next(label for k, label in enumerate(labels) if label in labels[:k])
        raise DataFileError(path, f"column {twice!r} appears twice", label_line)
    if n_cols is not None and n_cols != len(labels):
        raise DataFileError(
            path, f"header declares {n_cols} columns, label line has {len(labels)}", label_line
        )

    width = len(labels)
    rows: list[list[float]] = []
    last = label_line
    for number in range(label_line + 1, len(lines) + 1):
        tokens = lines[number - 1].split()
        if not tokens:
            continue
        last = number
        if len(tokens) != width:
            raise DataFileError(path, f"expected {width} values, found {len(tokens)}", number)
        try:
            rows.append([float(token) for token in tokens])
        except ValueError:
            for label, token in zip(labels, tokens, strict=True):
                try:
                    float(token)
                except ValueError:
                    raise DataFileError(
                        path, f"value {token!r} in column {label!r} is not a number", number
                    ) from None
    if n_rows is not None and n_rows != len(rows):
        raise DataFileError(
            path, f"header declares {n_rows} rows, found {len(rows)} (truncated file?)", last
        )

    values = np.array(rows, dtype=float).reshape(len(rows), width)
    bad_time = np.flatnonzero(~np.isfinite(values[:, 0]))
    if bad_time.size:
        raise DataFileError(path, f"time holds {values[bad_time[0], 0]} in data row "
                            f"{int(bad_time[0]) + 1}", None)  # fmt: skip
    if len(rows) < 2:  # rates and periods divide by the time steps
        raise DataFileError(path, f"{len(rows)} data rows: a motion needs 2 or more samples", last)
    increasing(path, "time", values[:, 0])  # a constant or zero time is refused
    storage = Storage(
        name=name,
        time=values[:, 0],
        columns=tuple(labels[1:]),
        data=values[:, 1:],
        in_degrees=in_degrees,
        header=header,
        path=path,
    )
    for column in storage.columns if finite else ():
        storage.column(column)
    return storage


_LABEL_OK = re.compile(r"^\S+$")


def write_storage(
    path: str | PathLike[str],
    time: ArrayLike,
    columns: Sequence[str],
    data: ArrayLike,
    *,
    name: str = "walk3d",
    in_degrees: bool = False,
    time_label: str = "time",
) -> Path:
    """Write an OpenSim version-1 storage file, atomically.

    The header is ``name``, ``version=1``, ``nRows``, ``nColumns`` (time included),
    ``inDegrees=yes|no`` and ``endheader``, followed by a tab-separated label line starting with
    ``time`` and one tab-separated row per sample. Numbers are written with Python's shortest
    round-trip representation, so :func:`read_storage` gives back exactly the same values.

    Args:
        path: Destination; the parent folder must exist.
        time: Sample times, shape ``(N,)``.
        columns: Labels of the data columns (no whitespace, unique, time excluded).
        data: Values, shape ``(N, C)`` (or ``(N,)`` for one column).
        name: First header line.
        in_degrees: Value of the ``inDegrees`` flag.
        time_label: Label of the first column.

    Returns:
        The path written.
    """
    t = np.asarray(time, dtype=float).reshape(-1)
    values = np.asarray(data, dtype=float)
    labels = [str(c) for c in columns]
    if values.ndim == 1:
        values = values.reshape(-1, 1)
    if values.shape != (t.size, len(labels)):
        raise ValueError(f"data must have shape ({t.size}, {len(labels)}), got {values.shape}")
    all_labels = [time_label, *labels]
    bad = [label for label in all_labels if not _LABEL_OK.match(label)]
    if bad:
        raise ValueError(f"column labels must be non-empty without whitespace: {bad}")
    if len(set(all_labels)) != len(all_labels):
        raise ValueError("column labels must be unique and must not repeat the time label")
    title = " ".join(str(name).split()) or "walk3d"
    if "=" in title or title.lower() == "endheader":
        raise ValueError(f"invalid storage name {name!r}")

    parts = [
        f"{title}\nversion=1\nnRows={t.size}\nnColumns={len(all_labels)}\n",
        f"inDegrees={'yes' if in_degrees else 'no'}\nendheader\n",
        "\t".join(all_labels) + "\n",
    ]
    table = np.column_stack([t, values]) if t.size else np.empty((0, len(all_labels)))
    parts.extend("\t".join(map(repr, row)) + "\n" for row in table.tolist())
    return atomic_write_text(path, "".join(parts))
