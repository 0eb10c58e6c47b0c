"""The full-cycle problem solved (issue #43), on the paper's subject with T and Td given,
seed 0: with no change it gives the half cycle back; a weak right calf and a short right leg
change their side, and the short leg's steps differ."""

import numpy as np
import pytest

import walk3d
from walk3d.api import settings as make_settings
from walk3d.problem import layout
from walk3d.problem.settings import body_for
from walk3d.results.evaluate import evaluate_cycle
from walk3d.solve import run_solver
from walk3d.solve.full_cycle import solve_full_cycle

pytestmark = pytest.mark.solve


def test_with_no_change_the_full_cycle_is_the_half_cycle():
    settings = make_settings(1.3806, 1.08, 0.16)
    half = run_solver(settings, 0)
    assert half.converged
    full = solve_full_cycle(settings, half)
    assert full.converged
    body = body_for(settings)
    a, b = evaluate_cycle(body, settings, half.x), evaluate_cycle(body, settings, full.x)
    ca, cb = (e.criteria["C_weighted"]["total"] for e in (a, b))
    assert cb == pytest.approx(ca, rel=0.005)
    diff = a.prediction_arrays["joint_angle"] - b.prediction_arrays["joint_angle"]
    assert np.degrees(np.abs(diff)).max() < 1.0
    assert full.record["iterations"] > 0  # solved, not handed back
    assert abs(full.x[layout.I_STEP_SHIFT]) < 1e-3  # steps of equal length (m)


PAPER = {"speed": 1.3806, "period": 1.08, "double_support": 0.16}


def _single_stance(pred, side: str) -> np.ndarray:
    """Samples of ``side``'s single stance (the other foot carries under 1 N)."""
    other = 1 if side == "r" else 0
    return pred.grf_force[:-1, other, 1] < 1.0


def test_a_weak_right_calf_pushes_off_less_than_the_left():
    weak = walk3d.predict(**PAPER, changes={"strength": {"ankle_r": 0.3}})
    assert weak.converged and weak.summary["problem"] == "full cycle"
    assert weak.summary["gait_checks"]["looks_like_walking"]
    pf = weak.summary["asymmetry"]["peak_ankle_plantarflexor_moment_nm_per_kg"]
    assert pf["right"] < 0.7 * pf["left"]  # the bar: at least 30 % below
    assert weak.summary["objective"]["C_overload"]["total"] > 0  # the cap is what holds it


def test_a_shorter_right_leg_tilts_the_pelvis_and_splits_the_stride_unequally():
    short = walk3d.predict(**PAPER, changes={"shank_length": {"shank_r": -0.02}})
    assert short.converged and short.summary["problem"] == "full cycle"
    assert short.summary["gait_checks"]["looks_like_walking"]
    recorded = short.summary["settings"]["model"]["changes"]["shank_length"]
    assert [list(item) for item in recorded] == [["shank_r", -0.02]]

    def stance_mean(dof: str, side: str) -> float:
        return np.degrees(short.dof(f"{dof}_{side}"))[:-1][_single_stance(short, side)].mean()

    # with no change the sides agree within 1° and the steps are equal (the test above); on the
    # long (left) leg the hip adducts more (the pelvis drops towards the short side), and the
    # steps differ
    assert stance_mean("hip_adduction", "l") > stance_mean("hip_adduction", "r") + 3.0
    assert abs(short.summary["asymmetry"]["step_length_m"]["difference"]) > 0.02
    # the evaluated feet sit where the NLP put them (a sign error in d would leave 2 d)
    assert short.summary["double_support_contact_residual_m"] < 0.003
    held = walk3d.predict(**PAPER, changes={"shank_length": {"shank_r": -0.02}},
                          equal_steps=True)  # fmt: skip
    assert held.converged and held.summary["settings"]["model"]["equal_steps"]
    assert abs(held.summary["asymmetry"]["step_length_m"]["difference"]) < 0.002
