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
``compile-<id>.failed`` (the error of a failed compile: no background compile of that target
starts again until ``walk3d compile`` succeeds, which deletes every such file).
"""

from __future__ import annotations

import hashlib
import json
import os
import secrets
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from walk3d.io.atomic import atomic_write_text
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
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode())  # for people: who holds it
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
        with open(p["log"], "ab") as log:
            _spawn([sys.executable, "-m", "walk3d.cli.background", key, str(job)], log)
    except OSError:  # no background compile; the prediction itself is done
        job.unlink(missing_ok=True)
        return None
    return (f"compiling in the background for later predictions, about 3 minutes at low "
            f"priority (log {p['log']}; --no-compile-later turns it off)")  # fmt: skip


def _spawn(cmd: list[str], log: IO[bytes]) -> None:
    """Start ``cmd`` detached from this process (its own session), output to ``log``."""
    subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                     start_new_session=True, close_fds=True,
                     env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))  # fmt: skip


def run(key: str, job: Path) -> int:
    """The background process: compile the settings in ``job`` unless another process holds
    the lock (module doc); deletes ``job`` either way. The exit code."""
    if hasattr(os, "nice"):
        os.nice(NICE)
    p = paths(key)
    with hold(lock_path(), wait=False) as held:
        try:
            if not held:
                print(f"{time.ctime()}: another process compiles; {key} not started", flush=True)
                return 0
            try:
                text = job.read_text()
            except OSError:  # nothing to do
                return 0
            return _compile(key, text, p)
        finally:
            job.unlink(missing_ok=True)


def _compile(key: str, text: str, p: dict[str, Path]) -> int:
    t0 = time.perf_counter()
    try:
        settings = PredictionSettings.model_validate_json(text)
        from walk3d.solve.solver import compile_solver

        print(f"{time.ctime()}: compiling {key} ({settings.gait.sex})", flush=True)
        info = compile_solver(settings, jobs=JOBS)
        print(f"{time.ctime()}: {info['compiled']} libraries in "
              f"{time.perf_counter() - t0:.0f} s", flush=True)  # fmt: skip
        return 0
    except Exception as exc:  # noqa: BLE001 (recorded, so that no later prediction retries)
        atomic_write_text(p["failed"], f"{type(exc).__name__}: {exc}\n")
        print(f"{time.ctime()}: failed: {type(exc).__name__}: {exc}", flush=True)
        return 1


if __name__ == "__main__":
    sys.exit(run(sys.argv[1], Path(sys.argv[2])))
