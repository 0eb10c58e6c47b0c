"""Helpers of the validation tests (a uniquely named module: every test folder has a conftest)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def cli_env() -> dict[str, str]:
    """Environment for ``python -m walk3d.cli`` subprocesses running this checkout's code."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO / "src"), env.get("PYTHONPATH", "")])
    return env


def run_walk3d(*args, timeout: float = 120) -> subprocess.CompletedProcess:
    """``python -m walk3d.cli ARGS`` in a subprocess of this checkout's code."""
    cmd = [sys.executable, "-m", "walk3d.cli", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=cli_env())


def exits_with_one_line(r: subprocess.CompletedProcess, *words: str) -> None:
    """Assert exit 2 with one ``walk3d: error:`` line naming every one of ``words``, and no
    traceback."""
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("walk3d: error:"), r.stderr
    assert "Traceback" not in r.stderr
    for w in words:
        assert w in lines[0], r.stderr
