"""Helpers of the validation tests (a uniquely named module: every test folder has a conftest)."""

from __future__ import annotations

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def shared_data_dir() -> Path:
    """``$WALK3D_SHARED_DATA`` if set, else ``../shared/data`` beside the repository."""
    env = os.environ.get("WALK3D_SHARED_DATA")
    return Path(env) if env else REPO.parent / "shared" / "data"


def cli_env() -> dict[str, str]:
    """Environment for ``python -m walk3d.cli`` subprocesses running this checkout's code."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO / "src"), env.get("PYTHONPATH", "")])
    return env
