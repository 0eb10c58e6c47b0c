"""Compiling the derivatives in the background after a prediction (``walk3d predict``'s default).

A prediction in CasADi's virtual machine takes about twice as long as one with compiled
derivatives, and compiling takes about 3 minutes on 2 cores (docs/solver.md). So when
``walk3d predict`` has solved in the VM, it compiles the derivatives of the same sex, criterion
and model options (:func:`walk3d.solve.solver.compile_solver`) in a detached, low-priority
process (``nice`` 19, :data:`JOBS` compilers) and returns at once; the predictions after it
load the libraries from the model cache. ``--no-compile-later`` or ``WALK3D_COMPILE_LATER=0``
turns this off. Linux and macOS only: elsewhere the hint names ``walk3d compile``.

Files in the model cache folder: ``compile.lock``, which the compiling process holds with an
OS file lock (released by the OS however the process ends; ``walk3d compile`` holds it too),
so one compile runs at a time; per start, ``compile-<id>-<token>.json`` (the settings, deleted
by its process); per compile target (:func:`target_id`), ``compile-<id>.log`` (the output) and
``compile-<id>.failed`` (the error of a failed compile, whatever failed, one line: no background
compile of that target starts again until ``walk3d compile`` succeeds, which deletes every such
file).

The compilers (and theirs: gcc's ``cc1``) run in a guarded process group of their own, ended
when the compiling process dies (:mod:`walk3d.solve.compiler_group`). The compiling process
leads its own group too, with a guard process (:func:`_group_guard`) that writes the failure
marker and ends that group when the process dies without saying it is done (``kill -9``,
SIGTERM, out of memory). Build folders left by a killed compile are removed when the
next compile starts (:func:`walk3d.solve.compiled.remove_leftover_builds`).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import secrets
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from walk3d.io.atomic import atomic_write_text, signals_deferred
from walk3d.problem import similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled, model_cache

ENV_LATER = "WALK3D_COMPILE_LATER"
NICE = 19
"""Priority increment of the compile: it yields the cores to the user's own work."""
JOBS = 2
"""Compilers at a time. Why 2: each needs up to about 2 GB (4.3 GB for 2 on 2 cores), and a
background compile must not take a many-core machine's memory."""
POSIX = os.name == "posix"


def later_enabled(flag: bool = True) -> bool:
    """Whether a VM prediction starts a background compile: ``flag`` (``--compile-later``),
    ``$WALK3D_COMPILE_LATER`` not off, and a POSIX system."""
    return flag and POSIX and model_cache.switched_on(ENV_LATER)


def target_id(settings: PredictionSettings) -> str:
    """Short key of what a compile of ``settings`` builds: the reference subject's sex, model
    options and nodes (every mass, stature and descriptor shares the libraries)."""
    ref = similarity.reference_problem(settings)[0]
    what = [ref.gait.sex, ref.model.model_dump(mode="json"), ref.solver.nodes]
    return hashlib.sha256(json.dumps(what, sort_keys=True).encode()).hexdigest()[:16]


def lock_path() -> Path:
    """The lock that a compiling process holds (module doc)."""
    return model_cache.cache_dir() / "compile.lock"


def paths(key: str) -> dict[str, Path]:
    """The log and failure marker of the compile target ``key`` (module doc)."""
    folder = model_cache.cache_dir()
    return {k: folder / f"compile-{key}.{k}" for k in ("log", "failed")}


@contextmanager
def hold(lock: Path, wait: bool) -> Iterator[bool]:
    """Hold ``lock`` (an exclusive ``flock``) for the block, waiting for it if ``wait``; yields
    whether it is held (always True off POSIX, where nothing is locked)."""
    if not POSIX:
        yield True
        return
    import fcntl

    lock.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock, os.O_CREAT | os.O_RDWR, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            yield False
            return
        with contextlib.suppress(OSError):  # for people: who holds it (not on a full disk)
            os.ftruncate(fd, 0)
            os.write(fd, str(os.getpid()).encode())
        yield True
    finally:
        os.close(fd)  # releases the lock


def running(lock: Path) -> bool:
    """Whether a process holds ``lock`` now (False off POSIX)."""
    if not POSIX or not lock.is_file():
        return False
    import fcntl

    try:
        fd = os.open(lock, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
    return False


def clear_failed() -> int:
    """Delete every failure marker (after a successful ``walk3d compile``); how many."""
    found = list(model_cache.cache_dir().glob("compile-*.failed"))
    for path in found:
        path.unlink(missing_ok=True)
    return len(found)


def start(settings: PredictionSettings, compiled_kinds: list[str], flag: bool = True) -> str | None:
    """Start the background compile of ``settings`` if it is worth it: derivatives not compiled
    (``compiled_kinds`` empty), enabled, the cache on, a compiler found, no compile running and
    none of this target failed before. Returns the line to show, or None when nothing applies."""
    if compiled_kinds or not later_enabled(flag) or not model_cache.cache_enabled():
        return None
    if compiled.compiler() is None:
        return None
    key = target_id(settings)
    p = paths(key)
    if p["failed"].is_file():
        return (f"the background compile failed (log {p['log']}); `walk3d compile` with this "
                "prediction's options retries it")  # fmt: skip
    if running(lock_path()):
        return "a background compile for later predictions is running"
    job = p["log"].with_name(f"compile-{key}-{secrets.token_hex(4)}.json")
    try:
        job.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(job, settings.model_dump_json())
        with open(p["log"], "ab") as log, signals_deferred():  # started and recorded, or not
            proc = _spawn([sys.executable, "-m", "walk3d.cli.background", key, str(job)], log)
            if proc is not None:
                LAUNCHED.append((proc, job))
    except OSError:  # no background compile; the prediction itself is done
        job.unlink(missing_ok=True)
        return None
    return (f"compiling in the background for later predictions, about 3 minutes at low "
            f"priority (log {p['log']}; --no-compile-later turns it off)")  # fmt: skip


LAUNCHED: list[tuple[subprocess.Popen, Path]] = []
"""The background compiles this process started, with their job files (:func:`withdraw`)."""


def withdraw() -> None:
    """Stop the background compiles this process started and remove their job files: a run
    that Ctrl-C or SIGTERM ends does not leave minutes of compiling behind it."""
    while LAUNCHED:
        proc, job = LAUNCHED.pop()
        with contextlib.suppress(OSError):
            os.killpg(proc.pid, signal.SIGTERM)  # its own session: the compilers too
        job.unlink(missing_ok=True)


def _spawn(cmd: list[str], log: IO[bytes]) -> subprocess.Popen:
    """Start ``cmd`` detached from this process (its own session), output to ``log``."""
    return subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True, close_fds=True,
                            env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))  # fmt: skip


def run(key: str, job: Path) -> int:
    """The background process: compile the settings in ``job`` unless another process holds
    the lock (module doc); deletes ``job`` either way. Every failure, the lock's included, is
    one line in the failure marker and the log. The exit code."""
    p = paths(key)
    try:
        _lead_group()
        if hasattr(os, "nice"):
            os.nice(NICE)
        with hold(lock_path(), wait=False) as held:
            if not held:
                _say(f"another process compiles; {key} not started")
                return 0
            try:
                text = job.read_text()
            except OSError:  # nothing to do
                return 0
            folders, size = compiled.remove_leftover_builds()
            if folders:
                plural = "" if folders == 1 else "s"
                _say(f"removed {folders} build folder{plural} of an ended compile, "
                     f"{size / 1e6:.1f} MB")  # fmt: skip
            with _group_guard(p["failed"], job):
                return _compile(key, text)
    except Exception as exc:  # noqa: BLE001 (recorded, so that no later prediction retries)
        line = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
        _mark_failed(p["failed"], line)
        _say(f"failed: {line}")
        return 1
    finally:
        with contextlib.suppress(OSError):
            job.unlink(missing_ok=True)


def _compile(key: str, text: str) -> int:
    t0 = time.perf_counter()
    settings = PredictionSettings.model_validate_json(text)
    from walk3d.solve.solver import compile_solver

    _say(f"compiling {key} ({settings.gait.sex})")
    info = compile_solver(settings, jobs=JOBS)
    _say(f"{info['compiled']} libraries in {time.perf_counter() - t0:.0f} s")
    return 0


def _say(line: str) -> None:
    """One timed line in the log (lost if the log cannot be written: a full disk)."""
    with contextlib.suppress(OSError):
        print(f"{time.ctime()}: {line}", flush=True)


def _mark_failed(marker: Path, line: str) -> None:
    """Write the failure marker ``marker``; on a full disk at least an empty one, which blocks
    the retries as well."""
    try:
        atomic_write_text(marker, line + "\n")
    except OSError:
        with contextlib.suppress(OSError), open(marker, "a", encoding="utf-8") as f:
            f.write(line + "\n")


def _lead_group() -> None:
    """Make this process its process group's leader (:func:`_spawn` starts it as one already),
    so that the group holds this process and its children only."""
    if os.getpgrp() != os.getpid():
        os.setpgid(0, 0)


_GUARD = """
import os, signal, sys, time
signal.signal(signal.SIGTERM, signal.SIG_IGN)
if sys.stdin.buffer.read() != b"done":
    line = "Killed: the compiling process was ended by a signal; its compilers with it"
    try:
        os.unlink(sys.argv[2])
    except OSError:
        pass
    try:
        with open(sys.argv[1], "a", encoding="utf-8") as marker:
            marker.write(line + "\\n")
        print(f"{time.ctime()}: {line}", flush=True)
    except OSError:
        pass
    os.killpg(os.getpgrp(), signal.SIGTERM)  # gcc removes its temporary files
    time.sleep(2.0)
    os.killpg(os.getpgrp(), signal.SIGKILL)
"""
"""The guard: it reads a pipe whose other end only the compiling process holds. An end without
``done`` means that the process died (``kill -9``, SIGTERM, out of memory): the guard ends the
process group, writes the failure marker (argument 1) and removes the job file (argument 2)."""


@contextmanager
def _group_guard(marker: Path, job: Path) -> Iterator[None]:
    """For the block, a guard process in this process group (:data:`_GUARD`): should this
    process die, however, the failure marker says so, the ``job`` file goes and the group ends
    with it (its compilers
    end by their own guard, :mod:`walk3d.solve.compiler_group`). The caller leads the group."""
    read, write = os.pipe()  # not inherited by the compilers: only the guard reads it
    try:
        guard = subprocess.Popen([sys.executable, "-c", _GUARD, str(marker), str(job)], stdin=read,
                                 stderr=subprocess.DEVNULL, close_fds=True)  # fmt: skip
    finally:
        os.close(read)
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.write(write, b"done")
        os.close(write)
        with contextlib.suppress(subprocess.TimeoutExpired):
            guard.wait(timeout=5)


if __name__ == "__main__":
    sys.exit(run(sys.argv[1], Path(sys.argv[2])))
