"""Where walk3d writes: one check of an output path, shared by the command line and the Python
API, and one way to write a group of files (build aside, then replace), so that an output is
either complete or as it was, and nothing walk3d did not write is ever deleted.

Single files go through :func:`walk3d.io._atomic.atomic_write` or ``atomic_path``, whole
folders through ``atomic_folder``; :func:`replace_files` puts several files into an existing
folder together. An :class:`OSError` while writing becomes one
:class:`~walk3d.io.errors.OutputWriteError` line (:func:`write_errors`).
"""

from __future__ import annotations

import errno
import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from os import PathLike
from pathlib import Path

from walk3d.io._atomic import fsync_dir, temporary_sibling
from walk3d.io.errors import OutputWriteError

__all__ = ["check_output_file", "check_output_folder", "replace_files", "write_errors"]


def _writable_base(out: Path, option: str, path: str) -> None:
    """Raise ValueError unless the nearest existing ancestor of ``out`` is a writable folder."""
    base = out
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise ValueError(f"{option} {path} cannot be created: {base} is a file")
    if not os.access(base, os.W_OK | os.X_OK):
        try:
            read_only = os.statvfs(base).f_flag & os.ST_RDONLY
        except OSError:
            read_only = False
        why = os.strerror(errno.EROFS if read_only else errno.EACCES).lower()
        raise ValueError(f"{option} {path} cannot be written ({base}: {why})")


def check_output_folder(
    path: str | PathLike[str], option: str = "--out", replaces: str | None = None
) -> Path:
    """Refuse, before any work starts, an output folder that is an existing file or cannot be
    created or written: ValueError with one line naming ``option``. With ``replaces`` (a file
    name), an existing non-empty folder must hold that file, so that only an earlier result is
    ever replaced, never a folder of other files. Returns the folder."""
    out = Path(path)
    shown = os.fspath(path)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{option} {shown} is an existing file, not a folder")
    if replaces and out.is_dir() and any(out.iterdir()) and not (out / replaces).is_file():
        raise ValueError(
            f"{option} {shown} is a folder of other files (no {replaces}); use a new folder"
        )
    _writable_base(out, option, shown)
    return out


def check_output_file(
    path: str | PathLike[str], option: str = "--out", suffix: str | None = None
) -> Path:
    """Refuse, before any work starts, an output file that is a folder, lacks ``suffix``
    (``".mp4"``...) or cannot be created: ValueError with one line. Returns the file's path."""
    out = Path(path)
    shown = os.fspath(path)
    if suffix is not None and out.suffix.lower() != suffix:
        raise ValueError(f"{option} must name a {suffix} file, got {shown}")
    if out.is_dir():
        raise ValueError(f"{option} {shown} is a folder")
    _writable_base(out.parent, option, shown)
    return out


@contextmanager
def write_errors(path: str | PathLike[str]) -> Iterator[None]:
    """Turn an :class:`OSError` raised in the block into one :class:`OutputWriteError` line
    naming ``path`` (one already of that kind passes as it is)."""
    try:
        yield
    except OutputWriteError:
        raise
    except OSError as exc:
        raise OutputWriteError(path, exc) from exc


@contextmanager
def replace_files(folder: str | PathLike[str], last: str | None = None) -> Iterator[Path]:
    """Build files in a temporary folder inside ``folder`` (hidden, same file system), then
    move each over its namesake in ``folder`` (the one named ``last`` last, e.g. a manifest
    or the file that the others belong to). On any failure, Ctrl-C included, the temporary
    folder is deleted and ``folder`` is left as it was; other files in it are never touched."""
    target = Path(folder)
    tmp = temporary_sibling(target, "files")
    tmp.mkdir()
    try:
        yield tmp
        built = sorted(p.name for p in tmp.iterdir())
        for name in sorted(built, key=lambda n: n == last):
            os.replace(tmp / name, target / name)
        fsync_dir(target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
