"""Compiling the derivatives in the background after a prediction (``walk3d predict``'s default).

A prediction in CasADi's virtual machine takes about twice as long as one with compiled
derivatives, and compiling takes about 3 minutes on 2 cores (docs/solver.md). So when
``walk3d predict`` has solved in the VM, it starts ``walk3d compile`` for the same sex,
criterion and model options as a detached, low-priority process (``nice`` 19) and returns at
once; the predictions after it load the libraries from the model cache. ``--no-compile-later``
or ``WALK3D_COMPILE_LATER=0`` turns this off.

Files in the model cache folder, per compile target (:func:`target_id`): ``compile-<id>.json``
(the settings, for the process), ``compile-<id>.lock`` (its process id while it runs),
``compile-<id>.log`` (its output) and ``compile-<id>.failed`` (the error of a failed compile:
no other background compile of that target starts until ``walk3d compile`` succeeds).
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from walk3d.io._atomic import atomic_write_text
from walk3d.problem import similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled, model_cache

ENV_LATER = "WALK3D_COMPILE_LATER"
_OFF = {"0", "false", "no", "off"}
NICE = 19
"""Priority increment of the compile: it yields the cores to the user's own work."""


def later_enabled(flag: bool = True) -> bool:
    """Whether a VM prediction starts a background compile: ``flag`` (``--compile-later``) and
    ``$WALK3D_COMPILE_LATER`` not off."""
    return flag and os.environ.get(ENV_LATER, "1").strip().lower() not in _OFF


def target_id(settings: PredictionSettings) -> str:
    """Short key of what a compile of ``settings`` builds: the reference subject's sex, model
    options and nodes (every mass, stature and descriptor shares the libraries)."""
    ref = similarity.reference_problem(settings)[0]
    what = [ref.gait.sex, ref.model.model_dump(mode="json"), ref.solver.nodes]
    return hashlib.sha256(json.dumps(what, sort_keys=True).encode()).hexdigest()[:16]


def paths(key: str) -> dict[str, Path]:
    """The files of the compile ``key`` in the model cache folder (module doc)."""
    folder = model_cache.cache_dir()
    return {k: folder / f"compile-{key}.{k}" for k in ("json", "lock", "log", "failed")}


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def running(lock: Path) -> int | None:
    """The process id in ``lock`` if that process is alive, else None (no or a stale lock)."""
    try:
        pid = int(lock.read_text().strip())
    except (OSError, ValueError):
        return None
    return pid if pid > 0 and _alive(pid) else None


def start(settings: PredictionSettings, compiled_kinds: list[str], flag: bool = True) -> str | None:
    """Start the background compile of ``settings`` if it is worth it: derivatives not compiled
    (``compiled_kinds`` empty), enabled, the cache on, a compiler found, no compile of the same
    target running or failed before. Returns the line to show, or None when nothing applies."""
    if compiled_kinds or not later_enabled(flag) or not model_cache.cache_enabled():
        return None
    if compiled.compiler() is None:
        return None
    key = target_id(settings)
    p = paths(key)
    if p["failed"].is_file():
        return f"the background compile failed ({p['log']}); `walk3d compile` shows why"
    if running(p["lock"]) is not None:
        return "a background compile for later predictions is running"
    try:
        p["json"].parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(p["json"], settings.model_dump_json())
        with open(p["log"], "ab") as log:
            _spawn([sys.executable, "-m", "walk3d.cli.background", str(p["json"])], log)
    except OSError:  # no background compile; the prediction itself is done
        return None
    return (f"compiling in the background for later predictions, about 3 minutes at low "
            f"priority (log {p['log']}; --no-compile-later turns it off)")  # fmt: skip


def _spawn(cmd: list[str], log) -> None:
    """Start ``cmd`` detached from this process (its own session), output to ``log``."""
    subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                     start_new_session=True, close_fds=True,
                     env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))  # fmt: skip


def _take(lock: Path) -> bool:
    """Write this process's id into ``lock`` unless a live process holds it (a stale lock is
    replaced)."""
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            if running(lock) is not None:
                return False
            lock.unlink(missing_ok=True)
            continue
        with os.fdopen(fd, "w") as fh:
            fh.write(str(os.getpid()))
        return True
    return False


def run(job: Path) -> int:
    """The background process: compile the settings in ``job`` (module doc); the exit code."""
    key = job.name.removeprefix("compile-").removesuffix(".json")
    p = paths(key)
    if hasattr(os, "nice"):
        os.nice(NICE)
    if not _take(p["lock"]):
        print(f"{time.ctime()}: another process compiles {key}", flush=True)
        return 0
    t0 = time.perf_counter()
    try:
        settings = PredictionSettings.model_validate_json(job.read_text())
        from walk3d.solve.solver import compile_solver

        print(f"{time.ctime()}: compiling {key} (walk3d compile --sex {settings.gait.sex})",
              flush=True)  # fmt: skip
        info = compile_solver(settings)
        print(f"{time.ctime()}: {info['compiled']} libraries in "
              f"{time.perf_counter() - t0:.0f} s", flush=True)  # fmt: skip
        p["failed"].unlink(missing_ok=True)
        return 0
    except Exception as exc:  # noqa: BLE001 (recorded, so that no later prediction retries)
        atomic_write_text(p["failed"], f"{type(exc).__name__}: {exc}\n")
        print(f"{time.ctime()}: failed: {type(exc).__name__}: {exc}", flush=True)
        return 1
    finally:
        p["lock"].unlink(missing_ok=True)
        job.unlink(missing_ok=True)


if __name__ == "__main__":
    sys.exit(run(Path(sys.argv[1])))
