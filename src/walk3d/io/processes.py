"""Whether the process that left a file behind still runs: its pid, and its start time.

A pid alone does not name a process for long: after a crash the system may give it to another
process, and a leftover judged by the pid alone would count as in progress for ever. So the
owner of a temporary also records its start time (:func:`start_time`), and a process whose
start time differs is another one. Where there is no ``/proc`` (macOS) the pid alone decides.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["running", "start_time"]


def _stat_fields(pid: int) -> list[str] | None:
    """The fields of ``/proc/<pid>/stat`` from the state on (field 3), or None without it."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text(encoding="ascii", errors="replace")
    except OSError:
        return None
    fields = text.rsplit(")", 1)[-1].split()  # the name, in parentheses, may hold spaces
    return fields if len(fields) >= 20 else None


def start_time(pid: int) -> int | None:
    """The start time of process ``pid``, clock ticks after boot (Linux ``/proc/<pid>/stat``
    field 22), or None where it cannot be read: it tells a reused pid from its first owner."""
    fields = _stat_fields(pid)
    return int(fields[19]) if fields and fields[19].isdigit() else None


def running(pid: int, started: int | None = None) -> bool:
    """Whether process ``pid`` runs on this machine, and, given its start time ``started``
    (:func:`start_time`), is the one that started then. A zombie (ended, not reaped) does not
    run; another user's process does."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's: it exists
        pass
    except (OSError, OverflowError):  # a pid out of range
        return False
    fields = _stat_fields(pid)
    if fields is None:  # no /proc (macOS): the pid decides
        return True
    if fields[0] == "Z":
        return False
    return started is None or fields[19] == str(started)
