"""Errors raised by the walk3d file readers."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

__all__ = ["DataFileError", "OutputWriteError"]


class DataFileError(ValueError):
    """A data file is malformed, truncated or inconsistent with its own header.

    The message is a single line of the form ``"<file name>:<line>: <reason>"`` (or
    ``"<file name>: <reason>"`` when no line applies, e.g. for binary files), so that it can be
    shown to a person or grepped from a log as is.

    Attributes:
        path: The offending file.
        line: 1-based line number of the problem, or ``None``.
        reason: The reason without the location prefix.
    """

    def __init__(self, path: str | PathLike[str], reason: str, line: int | None = None) -> None:
        self.path = Path(path)
        self.line = line
        self.reason = " ".join(str(reason).split())
        location = self.path.name if line is None else f"{self.path.name}:{line}"
        super().__init__(f"{location}: {self.reason}")


class OutputWriteError(OSError):
    """An output folder or file could not be written (disk full, permissions, I/O error).

    The message is one line: the path and the operating system's reason. Nothing partial is
    left behind by the writer that raises it.
    """

    def __init__(self, path: str | PathLike[str], cause: BaseException) -> None:
        self.path = Path(path)
        why = getattr(cause, "strerror", None) or " ".join(str(cause).split())
        why = why or type(cause).__name__
        errno = getattr(cause, "errno", None)
        super().__init__(errno, f"could not write {self.path}: {why.lower()}")

    def __str__(self) -> str:
        return str(self.strerror)
