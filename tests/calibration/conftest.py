"""Fixtures for the walk3d.calibration tests: the measured lab data, skipped when absent."""

from __future__ import annotations

import os
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def falisse() -> Path:
    """The Falisse et al. 2019 folder (``$WALK3D_SHARED_DATA`` or ``../shared/data``)."""
    env = os.environ.get("WALK3D_SHARED_DATA")
    root = Path(env) if env else Path(__file__).resolve().parents[2].parent / "shared" / "data"
    folder = root / "falisse2019"
    if not (folder / "gait_1_grf.mot").is_file():
        pytest.skip(f"measured data not found at {folder} (set WALK3D_SHARED_DATA)")
    return folder
