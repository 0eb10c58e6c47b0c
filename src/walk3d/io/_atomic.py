"""Atomic file writing shared by every walk3d writer (text, bytes, or a writer callback)."""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from os import PathLike
from pathlib import Path
from typing import IO

__all__ = ["atomic_write", "atomic_write_bytes", "atomic_write_text"]


def atomic_write(path: str | PathLike[str], write: Callable[[IO[bytes]], object]) -> Path:
    """Call ``write(handle)`` on a temporary file next to ``path``, then move it over ``path``.

    The temporary file is flushed and synced before :func:`os.replace` (atomic on POSIX and
    Windows on one file system); on any failure it is removed and an existing ``path`` is left
    untouched. Returns the destination path.
    """
    target = Path(path)
    tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return target


def atomic_write_bytes(path: str | PathLike[str], data: bytes) -> Path:
    """Write ``data`` atomically (see :func:`atomic_write`)."""
    return atomic_write(path, lambda handle: handle.write(data))


def atomic_write_text(path: str | PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` so that readers never see a partial file.

    The text goes to a uniquely named temporary file in the same folder, which is flushed,
    synced and then moved over ``path`` with :func:`os.replace` (atomic on POSIX and Windows
    when both are on the same file system). On any failure the temporary file is removed and
    an existing ``path`` is left untouched. The new file gets the usual permissions
    (``0o666`` less the umask).

    Returns:
        The destination path.
    """
    return atomic_write_bytes(path, text.encode("utf-8"))
