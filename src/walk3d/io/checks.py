"""The checks every walk3d reader shares: JSON objects, NumPy archives, XML and finite arrays.

Each refuses malformed, non-finite or degenerate content with one
:class:`~walk3d.io.errors.DataFileError` line naming the file (a ``ValueError``, exit code 2
on the command line), never another exception: a reader of a file format calls these instead
of ``json.loads``, ``np.load`` or ``ET.parse`` directly.
"""

from __future__ import annotations

import io
import json
import math
import numbers
import os
import stat
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from walk3d.io.errors import DataFileError

__all__ = [
    "finite_number",
    "increasing",
    "input_problem",
    "plain_file_name",
    "not_regular",
    "open_input",
    "positive_numbers",
    "read_input",
    "read_json_object",
    "read_npz",
    "read_xml",
    "require_finite",
    "time_samples",
]


_KINDS = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"), (stat.S_ISCHR, "a device"),
          (stat.S_ISBLK, "a device"))  # fmt: skip


def not_regular(mode: int) -> str | None:
    """Why a file of ``st_mode`` ``mode`` is no input file, or None for a regular file:
    ``is a folder, not a file`` or ``is not a regular file (a FIFO)`` (a socket, a device)."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "is a folder, not a file"
    kind = next((name for test, name in _KINDS if test(mode)), "of an unknown kind")
    return f"is not a regular file ({kind})"


def input_problem(path: str | PathLike[str]) -> str | None:
    """Why ``path`` cannot be read as an input file, without opening it: a folder, FIFO,
    socket or device (:func:`not_regular`); None for a regular file (a link to one included)
    and for nothing there, which its reader reports."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):  # missing, a NUL byte: the reader's error
        return None
    return not_regular(mode)


@contextmanager
def open_input(path: str | PathLike[str]) -> Iterator[BinaryIO]:
    """The input file ``path`` (a link to one included) open for reading: every walk3d reader
    opens its files here. It must be a regular file: a FIFO or a device would block the read
    or never end it, so it is opened without blocking and refused before any read.

    Raises:
        FileNotFoundError: there is no such file.
        DataFileError: a folder, FIFO, socket or device (one line naming the file).
    """
    path = Path(path)
    why = not_regular(os.stat(path).st_mode)  # a socket cannot even be opened
    if why is None:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
        why = not_regular(os.fstat(fd).st_mode)  # replaced since the stat
        if why is None:
            with os.fdopen(fd, "rb") as f:
                yield f
            return
        os.close(fd)
    raise DataFileError(path, why)


def read_input(path: str | PathLike[str]) -> bytes:
    """The bytes of the input file ``path`` (:func:`open_input`: FileNotFoundError, or one
    DataFileError line for a folder, FIFO, socket or device)."""
    with open_input(path) as f:
        return f.read()


def read_json_object(path: str | PathLike[str], what: str = "JSON file") -> dict[str, Any]:
    """The JSON object in ``path`` (``what`` names the file's role in messages).

    Raises:
        FileNotFoundError: there is no such file.
        DataFileError: not UTF-8, not valid JSON, nested too deep, or not a JSON object.
    """
    path = Path(path)
    raw = read_input(path)
    try:
        data = json.loads(raw.decode("utf-8-sig"))
    except UnicodeDecodeError:
        raise DataFileError(path, "not a text file (invalid UTF-8)") from None
    except json.JSONDecodeError as exc:
        raise DataFileError(path, f"invalid JSON: {exc.msg}", exc.lineno) from None
    except (RecursionError, ValueError) as exc:  # nested too deep, huge integers
        raise DataFileError(path, f"invalid JSON ({type(exc).__name__})") from None
    if not isinstance(data, dict):
        raise DataFileError(path, f"not a {what}: a JSON {type(data).__name__}, not an object")
    return data


def finite_number(path: str | PathLike[str], value: Any, what: str) -> float:
    """``value`` as a finite float (a JSON number, not a bool), else one DataFileError line."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    try:
        number = float(value) if ok else math.nan
    except OverflowError:
        number = math.nan
    if not math.isfinite(number):
        raise DataFileError(path, f"{what} must be a finite number, got {value!r:.40}")
    return number


def plain_file_name(path: str | PathLike[str], name: Any, what: str) -> str:
    """``name`` if it is a plain file name (no folder part, no NUL), else a DataFileError."""
    bad = not isinstance(name, str) or name in ("", ".", "..") or any(c in name for c in "/\\\0")
    if bad:
        raise DataFileError(path, f"{what} {name!r:.60} is not a plain file name")
    return name


def read_npz(path: str | PathLike[str], what: str = "NumPy .npz archive") -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` archive ``path``, read without pickles.

    Raises:
        FileNotFoundError: there is no such file.
        DataFileError: not a zip archive of ``.npy`` arrays, or damaged (one line, whatever
            NumPy or zipfile raised).
    """
    path = Path(path)
    raw = read_input(path)
    if not raw.startswith(b"PK\x03\x04"):
        raise DataFileError(path, f"not a {what}: the file is damaged or of another kind")
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            return {name: np.asarray(data[name]) for name in data.files}
    except Exception as exc:  # whatever NumPy, zipfile or zlib raise on a damaged member
        raise DataFileError(path, f"damaged {what} ({type(exc).__name__})") from None


def read_xml(path: str | PathLike[str]) -> ET.ElementTree:
    """The parsed XML document ``path``.

    Raises:
        FileNotFoundError: there is no such file.
        DataFileError: not well-formed XML (with the line of the first error), or an
            encoding Python does not know.
    """
    path = Path(path)
    raw = read_input(path)
    try:
        return ET.ElementTree(ET.fromstring(raw))
    except ET.ParseError as exc:
        raise DataFileError(path, f"invalid XML: {exc.msg}", exc.position[0]) from None
    except LookupError as exc:  # the declaration's encoding="..." is no codec Python knows
        name = str(exc).removeprefix("unknown encoding: ")
        raise DataFileError(path, f"invalid XML: unknown encoding {name!r}") from None
    except (ValueError, RecursionError) as exc:
        raise DataFileError(path, f"invalid XML ({type(exc).__name__})") from None


def _index_text(shape: tuple[int, ...], flat: int) -> str:
    return ", ".join(str(int(i)) for i in np.unravel_index(flat, shape)) if shape else ""


def require_finite(
    path: str | PathLike[str], name: str, values: Any, allow_nan: bool = False
) -> np.ndarray:
    """``values`` as a float array, refused with one DataFileError line naming ``name`` and
    the first bad element when it holds NaN (unless ``allow_nan``) or an infinite value."""
    try:
        arr = np.asarray(values)
        arr = arr.astype(float) if arr.dtype.kind in "biuf" else None
    except (ValueError, TypeError, OverflowError):
        arr = None
    if arr is None:
        raise DataFileError(path, f"{name} is not numeric")
    bad = np.isinf(arr) if allow_nan else ~np.isfinite(arr)
    if bad.any():
        flat = int(np.flatnonzero(bad.reshape(-1))[0])
        at = _index_text(arr.shape, flat)
        raise DataFileError(path, f"{name} holds non-finite values ({int(bad.sum())}, the "
                            f"first {arr.reshape(-1)[flat]} at [{at}])")  # fmt: skip
    return arr


def increasing(path: str | PathLike[str], name: str, values: Iterable[float]) -> np.ndarray:
    """``values`` (finite) if strictly increasing, else one DataFileError line."""
    arr = require_finite(path, name, list(values))
    steps = np.diff(arr)
    if steps.size and not (steps > 0).all():
        k = int(np.flatnonzero(steps <= 0)[0])
        raise DataFileError(path, f"{name} is not increasing: {arr[k]:g} then {arr[k + 1]:g} "
                            f"(rows {k + 1} and {k + 2})")  # fmt: skip
    return arr


MIN_TIME_SAMPLES = 11
"""Fewest samples of a stored cycle: one every 10 % (walk3d writes 101); fewer is no motion."""


def time_samples(path: str | PathLike[str], values: Any, name: str = "time") -> np.ndarray:
    """``values``, a 1-D time axis of :data:`MIN_TIME_SAMPLES` or more finite, strictly
    increasing samples, else one DataFileError line."""
    arr = np.asarray(values)
    if arr.ndim != 1:
        raise DataFileError(path, f"{name} has shape {arr.shape}, not one axis of samples")
    if arr.size < MIN_TIME_SAMPLES:
        raise DataFileError(path, f"{name} holds {arr.size} samples: a cycle needs "
                            f"{MIN_TIME_SAMPLES} or more")  # fmt: skip
    return increasing(path, name, arr)


def positive_numbers(**values: float | None) -> None:
    """Raise a one-line ValueError naming the first keyword whose value is given (not None)
    but is not a finite number above zero (``speed=nan``, ``threshold=-1``)."""
    for name, value in values.items():
        real = isinstance(value, numbers.Real) and not isinstance(value, bool)
        if value is not None and not (real and 0 < value < math.inf):
            raise ValueError(f"{name} must be a finite positive number, got {value!r:.40}")


def file_digest(path: str | PathLike[str]) -> str:
    """SHA-256 of a file's bytes, hex."""
    import hashlib

    return hashlib.sha256(read_input(path)).hexdigest()


def read_toml(path: str | PathLike[str]) -> dict:
    """The TOML file ``path`` as a dict; DataFileError (one line) when it cannot be read or is
    not TOML."""
    import tomllib

    p = Path(path)
    try:
        return tomllib.loads(read_input(p).decode("utf-8"))
    except OSError as exc:
        raise DataFileError(p, exc.strerror or str(exc)) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise DataFileError(p, f"not a TOML file: {exc}") from None
