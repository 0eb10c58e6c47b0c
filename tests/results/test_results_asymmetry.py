"""``summary.json``'s ``asymmetry``: left against right on a predicted cycle (issue #43)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from walk3d.results.asymmetry import asymmetry, asymmetry_or_none

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))


@pytest.fixture(scope="module")
def solved():
    """The shipped atlas's male cycle at 1.3 m/s: arrays, mass (kg) and its gait settings."""
    from verify_support import evaluate_atlas

    settings, body, ev = evaluate_atlas()
    return ev.prediction_arrays, body.mass, settings.gait


def _changed(arrays: dict, **scaled) -> dict:
    """A copy of ``arrays`` with the right side's column of each named field scaled."""
    out = dict(arrays)
    for name, (index, factor) in scaled.items():
        a = np.array(arrays[name], dtype=float)
        a[:, index] *= factor
        out[name] = a
    return out


def test_the_half_cycle_problem_gives_mirror_images(solved):
    arrays, mass, _ = solved
    figures = asymmetry(arrays, mass)
    assert len(figures) == 10
    for name, row in figures.items():
        assert abs(row["difference"]) < 1e-9 * max(1.0, abs(row["right"])), name


def test_the_figures_are_those_of_the_gait(solved):
    arrays, mass, gait = solved
    figures = asymmetry(arrays, mass)
    dt = gait.period / (len(arrays["time"]) - 1)
    # the trailing foot's share falls below the threshold before the double support ends
    stance = figures["stance_time_s"]["right"]
    assert gait.period / 2 < stance <= gait.period / 2 + gait.double_support + dt
    # the two steps make the stride, V T
    assert 2 * figures["step_length_m"]["right"] == pytest.approx(
        gait.speed * gait.period, rel=1e-6
    )
    assert 1.0 < figures["peak_vertical_grf_bw"]["right"] < 1.6
    assert 30 < figures["peak_knee_flexion_deg"]["right"] < 100
    # the plantarflexor peak acts in stance, the knee's flexion peak in swing
    ankle = np.asarray(arrays["joint_moment"])[:-1, list(arrays["joint_names"]).index("ankle_r"), 2]
    knee = np.asarray(arrays["joint_angle"])[:-1, list(arrays["dof_names"]).index("knee_flexion_r")]
    load = np.asarray(arrays["grf_force"])[:-1, 0, 1] / (mass * 9.81)
    assert figures["peak_ankle_plantarflexor_moment_nm_per_kg"]["right"] == -ankle.min() / mass
    assert load[np.argmin(ankle)] > 0.5
    assert load[np.argmax(knee)] == 0.0


def test_a_weaker_right_ankle_and_a_lighter_right_foot_show(solved):
    """Negative control: halving the right ankle's moments and the right foot's force."""
    arrays, mass, _ = solved
    joint = list(arrays["joint_names"]).index("ankle_r")
    changed = _changed(arrays, joint_moment=(joint, 0.5), grf_force=(0, 0.5))
    figures = asymmetry(changed, mass)
    pf = figures["peak_ankle_plantarflexor_moment_nm_per_kg"]
    assert pf["right"] == pytest.approx(0.5 * pf["left"], rel=1e-9)
    assert pf["difference"] < -0.25
    force = figures["peak_vertical_grf_bw"]
    assert force["right"] == pytest.approx(0.5 * force["left"], rel=1e-9)
    assert abs(figures["peak_knee_flexion_deg"]["difference"]) < 1e-9


def test_a_shorter_right_stance_shows(solved):
    arrays, mass, _ = solved
    force = np.array(arrays["grf_force"], dtype=float)
    on = np.flatnonzero(force[:-1, 0, 1] > 0.02 * mass * 9.81)
    force[on[-5:], 0, :] = 0.0  # the right foot leaves 5 samples early
    figures = asymmetry(dict(arrays, grf_force=force), mass)
    dt = float(arrays["time"][1] - arrays["time"][0])
    assert figures["stance_time_s"]["difference"] == pytest.approx(-5 * dt, rel=1e-6)


def test_a_foot_that_never_loads_is_refused(solved):
    arrays, mass, _ = solved
    force = np.array(arrays["grf_force"], dtype=float)
    force[:, 1, :] = 0.0
    with pytest.raises(ValueError, match="never touches down"):
        asymmetry(dict(arrays, grf_force=force), mass)


def test_standing_has_no_steps(solved):
    arrays, mass, _ = solved
    force = np.array(arrays["grf_force"], dtype=float)
    force[:, :, 1] = 0.5 * mass * 9.81  # both feet loaded all through
    assert asymmetry_or_none(dict(arrays, grf_force=force), mass) is None
    assert asymmetry_or_none(arrays, mass) is not None
