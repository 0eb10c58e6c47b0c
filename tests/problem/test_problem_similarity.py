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


@pytest.mark.parametrize("criterion", ["tor", "en"])
def test_the_subjects_node_rows_are_the_reference_subjects_in_other_units(criterion):
    subject = PredictionSettings(criterion=criterion, **SUBJECT)
    ref, s = sim.reference_problem(subject)
    assert (ref.mass, ref.height) == (sim.REFERENCE_MASS_KG, sim.REFERENCE_HEIGHT_M)
    assert ref.speed * ref.period == pytest.approx(subject.stride_length / s)
    # the subject's own problem, with the settings' lengths at the subject's stature
    own = subject.model_copy(update={"free_moment_radius": subject.free_moment_radius * s})
    f_ref = nlp.node_function(body_for(ref), ref)
    f_own = nlp.node_function(body_for(subject), own)
    rng = np.random.default_rng(3)
    y = rng.uniform(-0.3, 0.3, nlp.N_Y)
    w0 = rng.uniform(-0.5, 0.5, 6)
    t = rng.uniform(0.0, 1.0, nlp.N_T)
    p_ref = np.array([0.3, -0.7, 2 * np.pi / ref.period])
    p_own = np.array([0.3, -0.7 * s, 2 * np.pi / subject.period])
    w0_own = np.concatenate([w0[:3], w0[3:] * s])  # moments in body weight × m
    # the criterion's unit: C_tor's integrand scales with s, C_en's with (m / m_ref) √s
    c = s if criterion == "tor" else subject.mass / sim.REFERENCE_MASS_KG * math.sqrt(s)
    g_ref, obj_ref = (np.array(v).ravel() for v in f_ref(y, w0, 0.08, p_ref, t))
    g_own, obj_own = (np.array(v).ravel() for v in f_own(y, w0_own, 0.08 * s, p_own, t * c))
    scale = _row_scale(s)
    for name in ("slack_pos", "slack_neg"):
        scale[nlp.G_ROWS[name]] = c
    assert np.abs(g_ref).max() > 0.1
    np.testing.assert_allclose(g_own, scale * g_ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(obj_own, c * obj_ref, rtol=1e-12)


def test_a_wrong_scale_is_caught():
    """The check above can fail: the same rows at another stature without the time scaling
    differ from the scaled reference rows."""
    subject = PredictionSettings(**SUBJECT)
    ref, s = sim.reference_problem(subject)
    f_ref = nlp.node_function(body_for(ref), ref)
    f_own = nlp.node_function(body_for(subject), subject)
    rng = np.random.default_rng(3)
    y, w0, t = rng.uniform(-0.3, 0.3, nlp.N_Y), rng.uniform(-0.5, 0.5, 6), np.zeros(nlp.N_T)
    p = np.array([0.3, -0.7, 2 * np.pi / ref.period])
    g_ref = np.array(f_ref(y, w0, 0.08, p, t)[0]).ravel()
    g_own = np.array(f_own(y, w0, 0.08 * s, p * [1, s, 1], t)[0]).ravel()  # ω not scaled
    assert not np.allclose(g_own, _row_scale(s) * g_ref, rtol=1e-6)


def test_the_subjects_cycle_is_the_reference_cycle_scaled():
    """Evaluated with each body's own model: the same joint angles, positions × s, time × √s,
    ground reactions per body weight unchanged, moments × (m / m_ref) s, and the criteria by
    constant factors (so they have the same minimizer)."""
    subject = PredictionSettings(**SUBJECT)
    ref, s = sim.reference_problem(subject)
    rng = np.random.default_rng(5)
    x = np.zeros(layout.N_X)
    x[: layout.I_HALF_STEP] = rng.uniform(-0.05, 0.05, layout.I_HALF_STEP)
    x[layout.fixed_zero_mask()] = 0.0
    x[layout.I_HALF_STEP] = 0.08
    a = evaluate_cycle(body_for(ref), ref, x)
    b = evaluate_cycle(body_for(subject), subject, sim.subject_x(x, s))
    pa, pb = a.prediction_arrays, b.prediction_arrays
    k_m = subject.mass / sim.REFERENCE_MASS_KG
    np.testing.assert_allclose(pb["time"], pa["time"] * math.sqrt(s), rtol=1e-12)
    np.testing.assert_allclose(pb["joint_angle"], pa["joint_angle"], atol=1e-9)
    np.testing.assert_allclose(pb["segment_com_position"], pa["segment_com_position"] * s,
                               atol=1e-9)  # fmt: skip
    np.testing.assert_allclose(pb["grf_force"] / (subject.mass * G),
                               pa["grf_force"] / (ref.mass * G), atol=1e-9)  # fmt: skip
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
    heavier, s = sim.reference_problem(base.model_copy(update={"mass": 90.0}))
    assert s == 1.0 and heavier == base  # only the mass differed
    calibrated = PredictionSettings(
        height=1.6, rollover_s=[0.0, 0.1], rollover_ankle=[(0.0, 0.08, 0.0), (0.1, 0.07, 0.0)]
    )
    ref, s = sim.reference_problem(calibrated)
    assert s == 1.0 and ref.height == 1.6 and ref.mass == sim.REFERENCE_MASS_KG
    x = np.zeros(layout.N_X)
    x[layout.I_HALF_STEP] = 0.05
    assert sim.subject_x(x, 1.1)[layout.I_HALF_STEP] == pytest.approx(0.055)
    assert x[layout.I_HALF_STEP] == 0.05
