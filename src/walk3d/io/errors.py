"""Errors raised by the walk3d file readers."""

from __future__ import annotations

from os import PathLike
from pathlib import Path

__all__ = ["DataFileError"]


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
