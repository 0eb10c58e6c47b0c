"""Fixtures of the fuzz set: the valid seed files, made once per session (no solve), and the
shared measured data (read in place; a case that needs it skips when it is absent)."""

from __future__ import annotations

import resource
from pathlib import Path

import fuzz_seeds
import pytest
from result_support import result_folder

MEMORY_CAP = 8 * 2**30
"""Address space a fuzz worker may take, bytes: a runaway allocation is a MemoryError (a
traceback the case reports), not the machine's out-of-memory killer."""


@pytest.fixture(scope="session")
def made_seeds(tmp_path_factory) -> dict[str, Path]:
    """The seed files made here: ``result``, ``tracked`` and ``campaign`` (folders),
    ``table``, ``c3d``, ``calibration``, ``criterion`` and ``trials``."""
    root = tmp_path_factory.mktemp("fuzz-seeds")
    table = fuzz_seeds.cycle_table(root / "cycle.csv")
    result = result_folder(root / "pred")
    return {
        "result": result,
        "tracked": fuzz_seeds.tracked_folder(result, root / "tracked"),
        "campaign": fuzz_seeds.campaign_folder(result, root / "campaign"),
        "table": table,
        "c3d": fuzz_seeds.gait_c3d(root / "walk_01.c3d"),
        "calibration": fuzz_seeds.calibration_json(root / "calib.json"),
        "criterion": fuzz_seeds.criterion_toml(root / "weights.toml"),
        "trials": fuzz_seeds.trials_toml(root / "trials.toml", table),
    }


@pytest.fixture(scope="session")
def memory_cap():
    """:data:`MEMORY_CAP` on this worker's address space while the fuzz cases run."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = MEMORY_CAP if hard == resource.RLIM_INFINITY else min(MEMORY_CAP, hard)
    if soft == resource.RLIM_INFINITY or soft > cap:
        resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    yield
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
