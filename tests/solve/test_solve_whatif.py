"""What-if predictions solved (issue #43), on the paper's subject with T and Td given, seed 0:
a backpack, a braced ankle and weak calves change what they should, against the normal gait
solved the same way."""

import math

import numpy as np
import pytest

import walk3d

pytestmark = pytest.mark.solve
PAPER = {"speed": 1.3806, "period": 1.08, "double_support": 0.16, "threads": 1}
FIVE = math.radians(5.0)


@pytest.fixture(scope="module")
def normal():
    return walk3d.predict(**PAPER)


def _stance(pred, joint: str) -> np.ndarray:
    """The right joint's sagittal moment over the right foot's stance, N·m."""
    f = pred.grf_force[:-1, 0, 1]
    m = pred.joint_moment[:-1, list(pred.joint_names).index(joint), 2]
    return m[f > 0.05 * f.max()]


def test_backpack_adds_its_mass_and_raises_the_stance_knee_and_ankle_moments(normal):
    pack = walk3d.predict(**PAPER, changes={"added_mass": {"torso": 10.0}})
    assert normal.converged and pack.converged
    assert pack.summary["body_mass_kg"] == pytest.approx(normal.summary["body_mass_kg"] + 10.0)
    assert pack.summary["gait_checks"]["looks_like_walking"]
    for joint in ("knee_r", "ankle_r"):  # extensor / plantarflexor peaks, N·m
        assert -_stance(pack, joint).min() > 1.05 * -_stance(normal, joint).min()


def test_a_brace_holds_the_ankle_on_the_whole_cycle(normal):
    brace = walk3d.predict(**PAPER, changes={"limits": {"ankle_dorsiflexion": (-FIVE, FIVE)}})
    assert brace.converged and brace.summary["gait_checks"]["looks_like_walking"]
    for side in ("r", "l"):
        a = np.degrees(brace.dof(f"ankle_dorsiflexion_{side}"))
        assert a.min() >= -5.5 and a.max() <= 5.5
        b = np.degrees(normal.dof(f"ankle_dorsiflexion_{side}"))
        assert b.max() > 10.0  # control: unbraced, the ankle dorsiflexes beyond the brace


def test_weak_calves_cost_more_and_carry_less_plantarflexor_moment_in_stance(normal):
    weak = walk3d.predict(**PAPER, changes={"strength": {"ankle": 0.3}})
    assert weak.converged and weak.summary["gait_checks"]["looks_like_walking"]
    mean_pf = [-np.minimum(_stance(p, "ankle_r"), 0).mean() for p in (normal, weak)]
    assert mean_pf[1] < 0.85 * mean_pf[0]
    c = [p.summary["objective"]["C_tor"]["total"] for p in (normal, weak)]
    assert c[1] > c[0]
