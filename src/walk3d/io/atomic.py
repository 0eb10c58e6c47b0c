"""Atomic writing shared by every walk3d writer: one file (text, bytes, or a writer callback)
or a whole folder."""

from __future__ import annotations

import os
import re
import secrets
import shutil
import signal
import socket
import stat
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import IO

from walk3d.io import processes

__all__ = [
    "TMP_PREFIX",
    "atomic_folder",
    "atomic_path",
    "atomic_write",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_replaceable",
    "file_temporary_of",
    "folder_temporary_of",
    "fsync_dir",
    "remove_stale_temporaries",
    "signals_deferred",
    "temporary_beside",
    "temporary_sibling",
]


def check_replaceable(target: Path) -> None:
    """Refuse to write over anything but a regular file (or nothing): a device, FIFO or socket
    at ``target`` (a link to one included) raises :class:`FileExistsError`, and is left as it
    is (``os.replace`` would put a regular file in its place)."""
    try:
        mode = os.stat(target).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return
    if not stat.S_ISREG(mode):
        raise FileExistsError(f"{target} is not a regular file: walk3d writes only regular files")


def temporary_beside(target: Path, suffix: str = ".tmp") -> Path:
    """A fresh name ``.<name>.<12 hex><suffix>`` next to ``target``, where a writer builds what
    then replaces it (:func:`file_temporary_of` recognises the ``.tmp`` form)."""
    return target.with_name(f".{target.name}.{secrets.token_hex(6)}{suffix}")


_FILE_TEMPORARY = re.compile(r"\.(?P<name>.+)\.[0-9a-f]{12}\.tmp")


def file_temporary_of(name: str) -> str | None:
    """The output name whose temporary ``name`` has the form of (``.<output>.<12 hex>.tmp``,
    :func:`temporary_beside`), or None: what a writer killed before its rename leaves."""
    match = _FILE_TEMPORARY.fullmatch(name)
    return match["name"] if match else None


def atomic_write(path: str | PathLike[str], write: Callable[[IO[bytes]], object]) -> Path:
    """Call ``write(handle)`` on a temporary file next to ``path``, then move it over ``path``.

    The temporary file is flushed and synced before :func:`os.replace` (atomic on POSIX and
    Windows on one file system); on any failure it is removed and an existing ``path`` is left
    untouched. Returns the destination path.
    """
    target = Path(path)
    check_replaceable(target)
    tmp = temporary_beside(target)
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


@contextmanager
def atomic_path(path: str | PathLike[str], suffix: str = ".tmp") -> Iterator[Path]:
    """A temporary path next to ``path`` for a writer that takes a file name (ezc3d, ffmpeg):
    when the block ends the file is synced and moved over ``path``; on any failure it is
    removed and an existing ``path`` is left untouched. ``suffix`` ends the temporary name."""
    target = Path(path)
    check_replaceable(target)
    tmp = temporary_beside(target, suffix)
    try:
        yield tmp
        with open(tmp, "rb") as handle:
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


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


TMP_PREFIX = ".tmp_"
"""Name prefix of the temporary sibling folders that :func:`atomic_folder` builds in."""


def temporary_sibling(parent: Path, name: str) -> Path:
    """A fresh, not yet existing path ``parent/.tmp_<name>_<random>`` (parent created)."""
    parent.mkdir(parents=True, exist_ok=True)
    return parent / f"{TMP_PREFIX}{name}_{secrets.token_hex(6)}"


def fsync_dir(folder: Path) -> None:
    """Flush a folder's entries to disk (a no-op where folders cannot be opened)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


OWNER_SUFFIX = ".owner"
"""Beside a temporary folder while it is built (``.tmp_<name>_<random>.owner``): ``<host>
<pid> <start time>`` of the process building it (:mod:`walk3d.io.processes`; no start time
where it cannot be read), so that a later run removes both once that process has ended, and
nothing else."""


_FOLDER_TEMPORARY = re.compile(
    r"\.tmp_(?P<old>old_)?(?P<name>.+)_(?P<key>[0-9a-f]{12})(?P<owner>\.owner)?"
)


def folder_temporary_of(path: Path) -> str | None:
    """The folder name whose :func:`atomic_folder` temporary ``path`` is, or None: the folder
    ``.tmp_<name>_<12 hex>``, the old folder ``.tmp_old_<name>_<12 hex>`` or the owner file
    ``.tmp_<name>_<12 hex>.owner``, each only beside that owner file (a killed run leaves it;
    a user's folder of such a name has none)."""
    match = _FOLDER_TEMPORARY.fullmatch(path.name)
    if match is None or (match["old"] and match["owner"]):
        return None
    owner = path.with_name(f"{TMP_PREFIX}{match['name']}_{match['key']}{OWNER_SUFFIX}")
    try:
        kind, owner_kind = os.lstat(path).st_mode, os.lstat(owner).st_mode
    except OSError:  # gone, or no owner file
        return None
    expected = stat.S_ISREG(kind) if match["owner"] else stat.S_ISDIR(kind)
    return match["name"] if expected and stat.S_ISREG(owner_kind) else None


def _owner_line() -> str:
    """This process's owner file line (:data:`OWNER_SUFFIX`)."""
    started = processes.start_time(os.getpid())
    tail = "" if started is None else f" {started}"
    return f"{socket.gethostname()} {os.getpid()}{tail}\n"


def _ended(owner: Path) -> bool:
    """Whether the process named in an owner file has ended on this host (a pid that another
    process now has counts as ended)."""
    try:
        host, pid, *started = owner.read_text(encoding="ascii").split()
    except (OSError, ValueError, UnicodeError):  # unreadable, or not an owner line
        return False
    numbers = [pid, *started]
    if host != socket.gethostname() or len(started) > 1 or not all(n.isdigit() for n in numbers):
        return False
    return not processes.running(int(pid), int(started[0]) if started else None)


def remove_stale_temporaries(parent: Path, name: str) -> list[Path]:
    """Remove the temporary folders ``parent/.tmp_<name>_*`` that a walk3d process killed
    while building ``name`` left: those whose owner file names an ended process; returns
    them. A user's folder of such a name has no owner file and stays. An old folder that such a
    run had moved aside to commit is put back, or removed once the new one is in place."""
    removed = []
    for owner in parent.glob(f"{TMP_PREFIX}{name}_*{OWNER_SUFFIX}"):
        folder = owner.with_name(owner.name.removesuffix(OWNER_SUFFIX))
        if not owner.is_file() or not _ended(owner):
            continue
        if folder.is_dir() and not folder.is_symlink():
            shutil.rmtree(folder, ignore_errors=True)
            removed.append(folder)
        _settle_old(parent / name, _old_name(folder))
        owner.unlink(missing_ok=True)
    return removed


def _old_name(tmp: Path) -> Path:
    """Where :func:`atomic_folder` moves the folder that ``tmp`` replaces, while it commits:
    ``.tmp_old_<name>_<random>``, the random part of ``tmp``'s own."""
    return tmp.with_name(f"{TMP_PREFIX}old_{tmp.name.removeprefix(TMP_PREFIX)}")


def _settle_old(target: Path, old: Path) -> None:
    """After a run killed while it committed: the old folder goes back to ``target`` if the
    kill came between the two renames (``target`` is missing), else it is removed."""
    if not old.is_dir() or old.is_symlink():
        return
    if os.path.lexists(target):
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.rename(old, target)


@contextmanager
def signals_deferred() -> Iterator[None]:
    """Inside this block Ctrl-C (SIGINT) and SIGTERM are held, and delivered again as it ends:
    a commit (two renames) is never cut in half, so the old folder is never left aside. Only
    the main thread can set handlers; elsewhere, and for an ignored signal, it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(sig) not in (signal.SIG_IGN, None):
            previous[sig] = signal.signal(sig, lambda signum, _frame: held.append(signum))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for sig in dict.fromkeys(held):
            signal.raise_signal(sig)


def _refuse_link(target: Path) -> None:
    """Raise :class:`FileExistsError` if ``target`` is a symbolic link: renamed aside, the link
    itself would be moved (and never removed), and the user's link replaced by a folder."""
    if target.is_symlink():
        raise FileExistsError(f"{target} is a symbolic link: walk3d does not replace a link "
                              "with a folder")  # fmt: skip


@contextmanager
def atomic_folder(path: str | PathLike[str]) -> Iterator[Path]:
    """Build a folder in a temporary sibling ``.tmp_<name>_<random>``, then rename it to ``path``.

    On success an existing ``path`` is moved aside and removed just after the new folder takes
    its name, so a reader sees the old folder or the new one, never a partial one. On any
    failure the temporary is deleted and ``path`` is left as it was. A symbolic link at
    ``path`` is never replaced: :class:`FileExistsError`, before the build and at the commit.
    """
    target = Path(path)
    _refuse_link(target)
    tmp = temporary_sibling(target.parent, target.name)
    owner = tmp.with_name(tmp.name + OWNER_SUFFIX)
    owner.write_text(_owner_line(), encoding="ascii")
    try:
        tmp.mkdir()
        remove_stale_temporaries(target.parent, target.name)
        yield tmp
        fsync_dir(tmp)
        with signals_deferred():  # the two renames and the old folder's removal: all or none
            _refuse_link(target)  # made while the folder was built
            if target.exists():
                old = _old_name(tmp)
                os.rename(target, old)
                os.rename(tmp, target)
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.rename(tmp, target)
            owner.unlink(missing_ok=True)
            fsync_dir(target.parent)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    finally:
        owner.unlink(missing_ok=True)
