"""Fixtures for the walk3d.calibration tests: the measured lab data, skipped when absent."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import shared_data_dir


@pytest.fixture(scope="session")
def falisse() -> Path:
    """The Falisse et al. 2019 folder (``$WALK3D_SHARED_DATA`` or ``../shared/data``)."""
    folder = shared_data_dir() / "falisse2019"
    if not (folder / "gait_1_grf.mot").is_file():
        pytest.skip(f"measured data not found at {folder} (set WALK3D_SHARED_DATA)")
    return folder
