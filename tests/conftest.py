"""Shared fixtures: smooth random motions evaluated numerically, and the measured lab data."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from helpers import shared_data_dir

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
# no test starts a background compile (walk3d.cli.background) unless it asks for one
os.environ["WALK3D_COMPILE_LATER"] = "0"

from walk3d.body.model import build_body  # noqa: E402
from walk3d.kinematics import fourier  # noqa: E402
from walk3d.kinematics.forward import (  # noqa: E402
    forward,
    joint_quaternions,
    root_foot_triples,
)

PERIOD = 1.08


@pytest.fixture(scope="session")
def data_dir() -> Path:
    """The shared data folder; skips the test when it is absent."""
    root = shared_data_dir()
    if not (root / "README.md").is_file():
        pytest.skip(f"measured data not found at {root} (set WALK3D_SHARED_DATA)")
    return root


@pytest.fixture(scope="session", autouse=True)
def _model_cache_dir(tmp_path_factory):
    """Keep the on-disk model cache (walk3d.solve.model_cache) of the tests out of the user's:
    ``$WALK3D_TEST_CACHE_DIR`` (CI shares one across its test steps), else a new folder."""
    old = os.environ.get("WALK3D_CACHE_DIR")
    shared = os.environ.get("WALK3D_TEST_CACHE_DIR")
    os.environ["WALK3D_CACHE_DIR"] = shared or str(tmp_path_factory.mktemp("model-cache"))
    yield
    if old is None:
        os.environ.pop("WALK3D_CACHE_DIR", None)
    else:
        os.environ["WALK3D_CACHE_DIR"] = old


@pytest.fixture(scope="session")
def body():
    return build_body()


def random_coefficients(rng: np.random.Generator, n: int, scale: float) -> np.ndarray:
    """Fourier coefficients (n, 11) of smooth signals with amplitude ~scale."""
    decay = np.array([1.0] + [1.0 / k for k in range(1, 6) for _ in range(2)])
    return rng.uniform(-1, 1, (n, fourier.N_COEF)) * decay * scale


def evaluate_motion(body, coef_dof, coef_foot, t, root="foot_r", anchor=(0.0, 0.1)):
    """Pose at times t for DoF series (24, 11) and stance-foot series (11,)."""
    b0, b1, b2 = fourier.basis(t, PERIOD)
    dof = [(b0 @ c, b1 @ c, b2 @ c) for c in coef_dof]
    s_ft = (b0 @ coef_foot, b1 @ coef_foot, b2 @ coef_foot)
    jq = joint_quaternions(body, dof)
    side = root[-1]
    q_root, p_root = root_foot_triples(body, side, s_ft, anchor)
    return forward(body, jq, body.segment_index(root), q_root, p_root)


@pytest.fixture(scope="session")
def random_motion(body):
    rng = np.random.default_rng(7)
    coef_dof = random_coefficients(rng, 24, 0.15)
    coef_foot = random_coefficients(rng, 1, 0.1)[0]

    def at(t):
        return evaluate_motion(body, coef_dof, coef_foot, np.atleast_1d(t))

    return at
