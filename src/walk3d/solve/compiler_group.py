"""A process group of its own for the C compilers of one compile, ended if the compile is.

A compiler (gcc, and its ``cc1``) takes up to 2 GB for minutes. Killed with ``kill -9``, the
compiling process cannot end its compilers: they ran on, orphaned. So they run in a process
group led by a small guard process (:data:`_GUARD`) that reads a pipe whose write end only the
compiling process holds. An end of the pipe without ``done`` means that the process died
(``kill -9``, SIGTERM, out of memory) or left the compile on an exception (Ctrl-C, a failed
compiler): the guard then ends the group. The group is a new one, not the compiling process's
own, which may be its shell job's or its caller's. POSIX only.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["guarded_group"]

POSIX = os.name == "posix"
GRACE_S = 2.0
"""Seconds between the SIGTERM that ends the group and the SIGKILL after it. Why: gcc removes
its temporary files on SIGTERM."""

_GUARD = f"""
import os, signal, sys, time
for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(sig, signal.SIG_IGN)
if sys.stdin.buffer.read() != b"done":
    os.killpg(0, signal.SIGTERM)
    time.sleep({GRACE_S})
    os.killpg(0, signal.SIGKILL)
"""
"""The guard process: it leads the group, and ends it unless the pipe on its stdin says done."""


@contextmanager
def guarded_group() -> Iterator[int | None]:
    """For the block, a guarded process group (module doc); yields its id, for the compilers
    (``subprocess.run(..., process_group=group)``), or None off POSIX. Leaving the block on an
    exception ends the compilers still in the group."""
    if not POSIX:
        yield None
        return
    read, write = os.pipe()  # not inherited: only the guard reads, only this process writes
    try:
        guard = subprocess.Popen([sys.executable, "-c", _GUARD], stdin=read,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                 close_fds=True, process_group=0)  # fmt: skip
    except BaseException:
        os.close(write)
        raise
    finally:
        os.close(read)
    done = False
    try:
        yield guard.pid
        done = True
    finally:
        if done:
            with contextlib.suppress(OSError):
                os.write(write, b"done")
        os.close(write)
        if done:
            with contextlib.suppress(subprocess.TimeoutExpired):
                guard.wait(timeout=5)
        else:  # reaped once it has ended the group, without holding up the exception
            threading.Thread(target=guard.wait, daemon=True).start()
