"""A stand-in C compiler that never ends, for the tests that kill a compile: it records its pid
and its child's (as gcc runs cc1) and sleeps. :func:`fake_compile` runs a script that compiles
two functions with it, and returns once both compilers and their children run."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time

FAKE_CC = """#!/bin/sh
# a compiler that never ends: itself and a child (as gcc runs cc1), their pids recorded
echo $$ >> "$WALK3D_TEST_PIDS"
sleep 300 &
echo $! >> "$WALK3D_TEST_PIDS"
wait
"""


def state(pid: int) -> str | None:
    """The process's state letter (R, S, Z...), None when it is gone."""
    try:
        stat = open(f"/proc/{pid}/stat").read()
    except FileNotFoundError:
        return None
    except OSError:  # no /proc: signal 0 tells whether it exists
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return None
        return "?"
    return stat.rsplit(")", 1)[1].split()[0]


def alive(pids) -> list[int]:
    return [p for p in pids if state(p) not in (None, "Z")]


def fake_compile(tmp_path, script: str, *args, **popen) -> tuple[subprocess.Popen, list[int]]:
    """A process running ``script`` with ``args`` (its own session), once both stand-in
    compilers and their children run; their four pids. Its output goes to ``tmp_path/log``
    unless ``popen`` says otherwise."""
    cc, pids = tmp_path / "cc", tmp_path / "pids"
    cc.write_text(FAKE_CC)
    cc.chmod(0o755)
    env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path), "CC": str(cc),
                        "WALK3D_TEST_PIDS": str(pids)}  # fmt: skip
    log = open(tmp_path / "log", "wb")
    popen = {"stdout": log, "stderr": subprocess.STDOUT} | popen
    proc = subprocess.Popen([sys.executable, "-c", script, *args], env=env,
                            start_new_session=True, **popen)  # fmt: skip
    for _ in range(600):
        found = [int(s) for s in pids.read_text().split()] if pids.exists() else []
        if len(found) == 4 or proc.poll() is not None:
            break
        time.sleep(0.1)
    assert len(found) == 4, (tmp_path / "log").read_text()
    return proc, found


def wait_gone(pids, seconds: float = 10.0) -> list[int]:
    """The processes of ``pids`` still running after up to ``seconds``."""
    for _ in range(int(seconds * 10)):
        if not alive(pids):
            break
        time.sleep(0.1)
    return alive(pids)


def end(proc, pids) -> None:
    """Teardown: the processes a test started, by their ids."""
    for pid in [proc.pid, *alive(pids)]:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    proc.wait()


def alive_after_kill_9(tmp_path, script: str) -> int:
    """How many of an unguarded fake compile's processes still run 1 s after ``kill -9`` of
    the compiling process (the negative controls of the guards: all 4)."""
    proc, pids = fake_compile(tmp_path, script, "unguarded")
    try:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        time.sleep(1.0)
        return len(alive(pids))
    finally:
        end(proc, pids)
