"""Shared fixtures for the walk3d.io tests: location of the measured lab data."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import shared_data_dir


@pytest.fixture(scope="session")
def data_dir() -> Path:
    """The shared data folder; skips the test when it is absent."""
    root = shared_data_dir()
    if not (root / "README.md").is_file():
        pytest.skip(f"measured data not found at {root} (set WALK3D_SHARED_DATA)")
    return root


@pytest.fixture(scope="session")
def subject01(data_dir: Path) -> Path:
    """The OpenSim example trial folder."""
    folder = data_dir / "opensim_subject01"
    if not folder.is_dir():
        pytest.skip(f"{folder} missing")
    return folder


@pytest.fixture(scope="session")
def falisse(data_dir: Path) -> Path:
    """The Falisse et al. 2019 folder."""
    folder = data_dir / "falisse2019"
    if not folder.is_dir():
        pytest.skip(f"{folder} missing")
    return folder
