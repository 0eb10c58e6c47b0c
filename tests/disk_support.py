"""A full disk for the writer tests, without a disk: every walk3d writer syncs a file before it
moves the file into place (walk3d.io.atomic), and a sync is where a full disk (delayed
allocation, quotas, network file systems) or an I/O error is reported. :func:`full_disk` makes
the syncs of regular files fail with ENOSPC after the first ``after``."""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path


def full_disk(monkeypatch, after: int = 0, error: type[BaseException] | None = None) -> list:
    """Make ``os.fsync`` of a regular file raise ENOSPC (or ``error()``, e.g.
    KeyboardInterrupt for a Ctrl-C) from the ``after + 1``-th call on; returns the list of the
    file descriptors' sizes synced so far (its length counts the calls)."""
    real = os.fsync
    synced: list[int] = []

    def fsync(fd: int) -> None:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            return real(fd)
        if len(synced) >= after:
            if error is not None:
                raise error()
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        synced.append(info.st_size)
        return real(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    return synced


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (hidden ones included) by relative path, with its bytes."""
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }
