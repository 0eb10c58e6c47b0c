"""Fixtures for the walk3d.trials tests: the measured lab data, skipped when absent."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import shared_data_dir


def _folder(name: str) -> Path:
    folder = shared_data_dir() / name
    if not folder.is_dir():
        pytest.skip(f"measured data not found at {folder} (set WALK3D_SHARED_DATA)")
    return folder


@pytest.fixture(scope="session")
def subject01() -> Path:
    """The OpenSim example trial folder."""
    return _folder("opensim_subject01")


@pytest.fixture(scope="session")
def falisse() -> Path:
    """The Falisse et al. 2019 folder."""
    return _folder("falisse2019")
