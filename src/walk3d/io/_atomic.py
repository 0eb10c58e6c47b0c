"""Atomic text-file writing shared by the walk3d writers."""

from __future__ import annotations

import os
import secrets
from os import PathLike
from pathlib import Path

__all__ = ["atomic_write_text"]


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
    target = Path(path)
    tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return target
