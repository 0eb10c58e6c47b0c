"""Full default prediction (slow: minutes). Run with ``python -m pytest -m slow``."""

import numpy as np
import pytest

from walk3d import G
from walk3d.contact.phases import GaitPhases
from walk3d.problem.settings import PredictionSettings

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def prediction(tmp_path_factory):
    from walk3d.pipeline import predict

    out = tmp_path_factory.mktemp("pred")
    return predict(PredictionSettings(), seed=0, out_dir=out), out


def test_default_prediction_converges_and_is_written(prediction):
    from walk3d import load_result

    pred, out = prediction
    assert pred.summary["converged"], pred.summary["status"]
    back = load_result(out)
    np.testing.assert_array_equal(back.grf_force, pred.grf_force)
    assert (out / "summary.png").stat().st_size > 10_000


def test_ground_reaction_equals_momentum_change(prediction):
    pred, _ = prediction
    t, com = pred.time, pred.segment_com_position
    dt = t[1] - t[0]
    acc = (com[2:] - 2 * com[1:-1] + com[:-2]) / dt**2
    m = pred.segment_mass
    expected = np.einsum("s,nsk->nk", m, acc) + [0.0, m.sum() * G, 0.0]
    total = pred.grf_force.sum(axis=1)[1:-1]
    # second differences on a 101-sample grid: allow 5 % of body weight
    assert np.max(np.abs(total - expected)) < 0.05 * m.sum() * G


def test_stride_contact_and_symmetry(prediction):
    pred, _ = prediction
    s = pred.summary
    assert s["stride_length_m"] == pytest.approx(s["stride_length_target_m"], rel=2e-3)
    assert s["double_support_contact_residual_m"] < 2e-3
    assert s["root_switch_continuity_residual_m"] < 2e-3
    # left = right half a cycle later (101 samples: index shift of 50)
    fy = pred.grf_force[:, :, 1]
    np.testing.assert_allclose(fy[:50, 1], fy[50:100, 0], atol=0.02 * pred.body_mass * G)


def test_looks_like_walking(prediction):
    pred, _ = prediction
    gait = pred.summary["settings"]["gait"]
    ph = GaitPhases(gait["period"], gait["double_support"])
    knee = np.degrees(pred.dof("knee_flexion_r"))
    swing = ~ph.in_stance(pred.time, "r")
    assert knee[swing].max() >= 40.0
    # two humps in the vertical force of the right foot during its stance: a maximum in each
    # half of the stance, both clearly (10 % of body weight) above the mid-stance minimum
    fy = pred.grf_force[:, 0, 1] / (pred.body_mass * G)
    stance = np.flatnonzero(ph.in_stance(pred.time, "r") & (fy > 0.05))
    f = fy[stance]
    n = len(f)
    first, second = f[: n // 2].max(), f[n // 2 :].max()
    i1, i2 = int(np.argmax(f[: n // 2])), n // 2 + int(np.argmax(f[n // 2 :]))
    dip = f[i1 : i2 + 1].min()
    assert first - dip > 0.1 and second - dip > 0.1, (first, dip, second)
    # and the summary's verdict agrees, with the hip upright in mid-stance (not the crouched optima)
    g = pred.summary["gait_checks"]
    assert g["looks_like_walking"] and g["hip_midstance_deg"] < 27.0, g


def test_python_api_predicts_another_subject(tmp_path):
    """The README's example: ``walk3d.predict`` with only a speed and a body, then the table."""
    import walk3d

    pred = walk3d.predict(speed=1.2, mass=75.0, height=1.8, sex="female", out=tmp_path / "p")
    assert pred.converged and pred.summary["gait_checks"]["looks_like_walking"]
    assert set(pred.descriptors["predicted"]) == {"period", "double_support"}
    df = pred.to_dataframe()
    assert df["knee_flexion_r_deg"].max() > 40.0
    assert walk3d.load_result(tmp_path / "p").summary["converged"]
