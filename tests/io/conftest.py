"""Shared fixtures for the walk3d.io tests: location of the measured lab data."""

from __future__ import annotations

from pathlib import Path

import pytest


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
