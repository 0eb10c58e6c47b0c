"""A signal that comes once ``walk3d predict``'s result folder is complete: the folder stands
(report.html and the table are what the signal stops), so the run ends with the result's own
exit code and one line saying so, never 130 or 143 beside a complete new result."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from walk3d.cli.common import exit_code


def identity(folder: str | os.PathLike[str]) -> tuple[int, int, int] | None:
    """``(device, inode, mtime_ns)`` of ``folder``, or None if it does not exist: a folder that
    walk3d's commit renamed into place has another identity than the one there before."""
    try:
        st = os.stat(folder)
    except OSError:
        return None
    return st.st_dev, st.st_ino, st.st_mtime_ns


def code_if_written(out: str | os.PathLike[str], before: tuple | None) -> int | None:
    """After Ctrl-C or SIGTERM: if ``out`` is a new complete result folder (another identity
    than ``before``), print one line and return its exit code; else None (nothing new there:
    the signal ends the run as usual, 130 or 143)."""
    from walk3d.io.checks import read_json_object
    from walk3d.io.errors import DataFileError
    from walk3d.results.prediction import check_complete

    if identity(out) in (None, before):
        return None
    try:
        check_complete(out)
        summary = read_json_object(Path(out) / "summary.json", "walk3d summary")
    except (DataFileError, OSError, ValueError):
        return None
    skipped = "the table" if (Path(out) / "report.html").is_file() else "report.html and the table"
    sys.stderr.write(f"walk3d: stopped by a signal after {out} was complete ({skipped} skipped)\n")
    return exit_code(summary)
