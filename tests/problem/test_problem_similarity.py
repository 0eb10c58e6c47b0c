"""Dynamic similarity (walk3d.problem.similarity): another mass or stature is the reference
subject's problem in other units, checked on the NLP's node rows and on the evaluated cycle."""

import math

import numpy as np
import pytest

from walk3d import G
from walk3d.problem import layout, nlp
from walk3d.problem import similarity as sim
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.results.evaluate import evaluate_cycle

SUBJECT = dict(mass=52.0, height=1.58, speed=1.2, period=1.05, double_support=0.14)


def _row_scale(s: float) -> np.ndarray:
    """How each node row of the subject's NLP relates to the reference's: lengths by s,
    velocities by √s, angular velocities by 1/√s, forces per body weight unchanged."""
    scale = np.ones(nlp.N_G)
    by = {
        "loop_position": s,
        "loop_velocity": math.sqrt(s),
        "loop_omega": 1 / math.sqrt(s),
        "other_points_y": s,
        "ankle_separation": s,
        "root_support": s,
        "other_support": s,
    }
    for name, k in by.items():
        scale[nlp.G_ROWS[name]] = k
    scale[nlp.G_ROWS["hs_wrench"].start + 3 : nlp.G_ROWS["hs_wrench"].stop] = s  # moments
    return scale


def _rows(criterion: str, scale_omega: bool = True):
    """Node rows of the reference problem and of the subject's own problem (with the settings'
    lengths at the subject's stature) at corresponding inputs, the expected scale per row, and
    the row-group names whose scale involves time."""
    subject = PredictionSettings(criterion=criterion, **SUBJECT)
    ref, s = sim.reference_problem(subject)
    own = subject.replace(**{"free_moment_radius": subject.model.free_moment_radius * s})
    f_ref = nlp.node_function(body_for(ref), ref.model)
    f_own = nlp.node_function(body_for(subject), own.model)
    rng = np.random.default_rng(3)
    y = rng.uniform(-0.3, 0.3, nlp.N_Y)
    w0 = rng.uniform(-0.5, 0.5, 6)
    t = rng.uniform(0.0, 1.0, nlp.N_T)
    p_ref = np.array([0.3, -0.7, 2 * np.pi / ref.gait.period, 0.5, -0.3, 0.2])
    omega = 2 * np.pi / (subject.gait.period if scale_omega else ref.gait.period)
    p_own = np.array([0.3, -0.7 * s, omega, 0.5, -0.3, 0.2])
    w0_own = np.concatenate([w0[:3], w0[3:] * s])  # moments in body weight × m
    # the criterion's unit: C_tor's integrand scales with s, C_en's with (m / m_ref) √s
    c = s if criterion == "tor" else subject.gait.mass / sim.REFERENCE_MASS_KG * math.sqrt(s)
    g_ref, obj_ref = (np.array(v).ravel() for v in f_ref(y, w0, 0.08, p_ref, t))
    g_own, obj_own = (np.array(v).ravel() for v in f_own(y, w0_own, 0.08 * s, p_own, t * c))
    scale = _row_scale(s)
    for name in ("slack_pos", "slack_neg"):
        scale[nlp.G_ROWS[name]] = c
    return g_ref, obj_ref, g_own, obj_own, scale, c


@pytest.mark.parametrize("criterion", ["tor", "en"])
def test_the_subjects_node_rows_are_the_reference_subjects_in_other_units(criterion):
    subject = PredictionSettings(criterion=criterion, **SUBJECT)
    ref, s = sim.reference_problem(subject)
    assert (ref.gait.mass, ref.gait.height) == (sim.REFERENCE_MASS_KG, sim.REFERENCE_HEIGHT_M)
    assert ref.gait.speed * ref.gait.period == pytest.approx(subject.gait.stride_length / s)
    g_ref, obj_ref, g_own, obj_own, scale, c = _rows(criterion)
    assert np.abs(g_ref).max() > 0.1
    np.testing.assert_allclose(g_own, scale * g_ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(obj_own, c * obj_ref, rtol=1e-12)


def test_without_the_time_scaling_the_rows_that_involve_time_differ():
    """The check above can fail: with the subject's cycle frequency left at the reference's,
    the geometric rows still agree but the velocity rows, the reaction (accelerations) and the
    moments do not."""
    g_ref, _, g_own, _, scale, _ = _rows("tor", scale_omega=False)
    same = np.isclose(g_own, scale * g_ref, rtol=1e-9, atol=1e-12)
    geometric = ["loop_position", "loop_orientation", "other_points_y", "ankle_separation",
                 "torso", "ball_norm"]  # fmt: skip
    for name in geometric:
        assert same[nlp.G_ROWS[name]].all(), name
    for name in ("loop_velocity", "root_force", "slack_pos", "root_support"):
        assert not same[nlp.G_ROWS[name]].any(), name


def _calibrated() -> dict:
    """A roll-over calibration of the subject's own size (its model foot's path, perturbed)."""
    ro = body_for(PredictionSettings(**SUBJECT)).rollover
    knots = np.array(ro.knots)
    ankle = np.array(ro.evaluate(knots)[0]).T * [1.0, 1.05, 1.0]
    return {"rollover_s": tuple(knots), "rollover_ankle": tuple(map(tuple, ankle))}


@pytest.mark.parametrize("calibrated", [False, True])
def test_the_subjects_cycle_is_the_reference_cycle_scaled(calibrated):
    """Evaluated with each body's own model: the same joint angles, positions × s, time × √s,
    ground reactions per body weight unchanged, moments × (m / m_ref) s, and the criteria by
    constant factors (so they have the same minimizer); with a calibrated roll-over too."""
    subject = PredictionSettings(**SUBJECT, **(_calibrated() if calibrated else {}))
    ref, s = sim.reference_problem(subject)
    rng = np.random.default_rng(5)
    x = np.zeros(layout.N_X)
    x[: layout.I_HALF_STEP] = rng.uniform(-0.05, 0.05, layout.I_HALF_STEP)
    x[layout.fixed_zero_mask()] = 0.0
    x[layout.I_HALF_STEP] = 0.08
    a = evaluate_cycle(body_for(ref), ref, x)
    b = evaluate_cycle(body_for(subject), subject, sim.subject_x(x, s))
    pa, pb = a.prediction_arrays, b.prediction_arrays
    k_m = subject.gait.mass / sim.REFERENCE_MASS_KG
    np.testing.assert_allclose(pb["time"], pa["time"] * math.sqrt(s), rtol=1e-12)
    np.testing.assert_allclose(pb["joint_angle"], pa["joint_angle"], atol=1e-9)
    np.testing.assert_allclose(pb["segment_com_position"], pa["segment_com_position"] * s,
                               atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(pb["grf_force"] / (subject.gait.mass * G),
                               pa["grf_force"] / (ref.gait.mass * G), atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(pb["joint_moment"], pa["joint_moment"] * k_m * s, atol=1e-7)
    assert np.abs(pa["joint_moment"]).max() > 1.0
    ca, cb = a.criteria, b.criteria
    assert cb["C_tor"]["total"] == pytest.approx(ca["C_tor"]["total"] * s * math.sqrt(s))
    assert cb["C_en"]["total"] == pytest.approx(ca["C_en"]["total"] * k_m * s)
    assert b.stride_length_m == pytest.approx(a.stride_length_m * s)
    assert b.contact_residual_m == pytest.approx(a.contact_residual_m * s)


def test_the_reference_subject_is_solved_as_given():
    base = PredictionSettings()
    ref, s = sim.reference_problem(base)
    assert ref is base and s == 1.0
    heavier, s = sim.reference_problem(base.replace(**{"mass": 90.0}))
    assert s == 1.0 and heavier == base  # only the mass differed
    ankle = [(0.0, 0.08, 0.0), (0.05, 0.075, 0.0), (0.1, 0.07, 0.0)]
    calibrated = PredictionSettings(height=1.6, rollover_s=[-0.1, 0.1, 0.2], rollover_ankle=ankle)
    ref, s = sim.reference_problem(calibrated)
    assert s == pytest.approx(1.6 / 1.77) and ref.gait.height == sim.REFERENCE_HEIGHT_M
    assert ref.model.rollover_s == calibrated.model.rollover_s  # foot rotations: no unit
    np.testing.assert_allclose(np.array(ref.model.rollover_ankle) * s, ankle, rtol=1e-15)
    x = np.zeros(layout.N_X)
    x[layout.I_HALF_STEP] = 0.05
    assert sim.subject_x(x, 1.1)[layout.I_HALF_STEP] == pytest.approx(0.055)
    assert x[layout.I_HALF_STEP] == 0.05
