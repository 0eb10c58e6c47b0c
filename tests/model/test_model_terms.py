"""The criterion terms beyond the paper's: parsing, exactness, and the NLP's objective row."""

import numpy as np
import pytest
from helpers import random_decision

from walk3d import G
from walk3d.body.model import build_body
from walk3d.model import builtin_terms, terms
from walk3d.problem import jerk, layout, nlp
from walk3d.problem.settings import PredictionSettings
from walk3d.results.evaluate import evaluate_cycle

WEIGHTED = "tor=1,accel=0.5,jerk=0.2,head=0.3,impact=0.5,shear=0.4,pose=0.5,pelvis=0.5"


def test_paper_criteria_and_presets_parse_to_canonical_forms():
    assert terms.canonical("tor") == "tor"
    assert terms.canonical("tor=1") == "tor"
    assert terms.canonical(" en ") == "en"
    assert terms.canonical("pelvis=0.5, tor=2 ,accel=0") == "tor=2,pelvis=0.5"
    preset = terms.canonical(terms.DEFAULT_PRESET)
    assert terms.parse(preset) == terms.PRESETS[terms.DEFAULT_PRESET]
    assert terms.preset_name(preset) == terms.DEFAULT_PRESET
    assert terms.preset_name("tor=1,accel=0.123") is None
    assert terms.label("tor") == "C_tor" and terms.label(preset) == "C_weighted"
    assert terms.base("en=1,head=1") == "en"


@pytest.mark.parametrize(
    ("spec", "words"),
    [
        ("walk", "preset"),
        ("tor=1,speed=2", "unknown criterion term 'speed'"),
        ("tor=1,accel=-1", "≥ 0"),
        ("tor=1,accel=nan", "finite"),
        ("tor=1,accel=x", "must be a finite number"),
        ("tor=1,accel=0_5", "must be a finite number"),
        ("tor=1,,accel=1", "has an empty item"),
        ("accel=1", "exactly one of tor and en"),
        ("tor=1,en=1", "exactly one of tor and en"),
        ("tor=1,tor=2", "twice"),
    ],
)
def test_bad_criteria_are_refused_with_one_line(spec, words):
    with pytest.raises(ValueError, match=words) as info:
        PredictionSettings(criterion=spec)
    assert "\n" not in str(info.value).split("\n", 1)[0]


@pytest.fixture(scope="module")
def cycle():
    s = PredictionSettings(criterion=WEIGHTED)
    body = build_body()
    x = random_decision(5)
    return s, body, x, evaluate_cycle(body, s, x, n_samples=201)


def test_accel_term_equals_the_fourier_integral(cycle):
    """∫ q̈² dt over a period is (T/2) Σ_k (kω)⁴ (a_k² + b_k²) per series (Parseval), so the
    sampled integral of the evaluated cycle must equal the coefficient sum exactly."""
    s, body, x, ev = cycle
    T = s.gait.period
    t = np.linspace(0.0, T, 4001)[:-1]
    a2 = layout.coordinate_maps(t, T)[2] @ x  # (time, 26) coordinate accelerations
    exact = np.mean(np.sum((2 * a2[:, :24] / builtin_terms.ACCEL_REF) ** 2, axis=1) / 24) * T
    got = ev.criteria["C_accel"]["total"]
    assert got == pytest.approx(exact, rel=1e-9)
    # negative control: the rectangle rule on 4 samples is far from exact for 5th harmonics
    t4 = np.linspace(0.0, T, 5)[:-1]
    a4 = layout.coordinate_maps(t4, T)[2] @ x
    coarse = np.mean(np.sum((2 * a4[:, :24] / builtin_terms.ACCEL_REF) ** 2, axis=1) / 24) * T
    assert abs(coarse - exact) > 1e-3 * exact


def test_jerk_term_equals_the_sampled_third_derivative(cycle):
    """Parseval on the coefficients (the NLP's form) against the integral of the third
    derivative, differentiated numerically from the exact second derivative."""
    s, _, x, ev = cycle
    T = s.gait.period
    t = np.linspace(0.0, T, 20001)[:-1]
    h = 1e-5
    a_p = layout.coordinate_maps(t + h, T)[2] @ x
    a_m = layout.coordinate_maps(t - h, T)[2] @ x
    third = (a_p - a_m)[:, :24] / (2 * h)
    sampled = np.mean(np.sum((2 * third / builtin_terms.JERK_REF) ** 2, axis=1) / 24) * T
    assert ev.criteria["C_jerk"]["total"] == pytest.approx(sampled, rel=1e-6)
    q = jerk.coefficient_weights(T)
    assert float(q @ (x * x)) == pytest.approx(sampled, rel=1e-6)
    # negative control: the left limbs' series (shifted half a cycle) counted once, not twice
    once = x.copy()
    once[4 * layout.N_COEF : 14 * layout.N_COEF] /= np.sqrt(2.0)
    assert float(q @ (once * once)) != pytest.approx(sampled, rel=0.05)


def test_every_term_is_reported_with_its_split_and_the_weighted_total(cycle):
    s, _, _, ev = cycle
    c = ev.criteria
    assert "C_track" not in c  # only a tracking has a target to deviate from
    for name in (n for n in terms.names() if n != "track"):
        split = c[f"C_{name}"]
        assert split["total"] == pytest.approx(split["x"] + split["y"] + split["z"])
        assert split["total"] > 0
    w = c["C_weighted"]
    expect = sum(wt * c[f"C_{k}"]["total"] for k, wt in terms.parse(s.model.criterion).items())
    assert w["total"] == pytest.approx(expect)
    assert c["C_impact"]["x"] == 0 and c["C_impact"]["z"] == 0


def test_arms_term_is_the_accel_term_over_the_arm_dofs_on_its_own_scale(cycle):
    s, body, x, ev = cycle
    T = s.gait.period
    t = np.linspace(0.0, T, 4001)[:-1]
    a2 = layout.coordinate_maps(t, T)[2] @ x
    arm = [i for i, n in enumerate(body.dof_names) if n.startswith(("arm_", "elbow"))]
    assert len(arm) == 8
    exact = np.mean(np.sum((2 * a2[:, arm] / builtin_terms.ARM_ACCEL_REF) ** 2, axis=1) / 8) * T
    assert ev.criteria["C_arms"]["total"] == pytest.approx(exact, rel=1e-9)
    legs = [i for i, n in enumerate(body.dof_names) if n.startswith(("hip", "knee"))]
    other = np.mean(np.sum((2 * a2[:, legs] / builtin_terms.ARM_ACCEL_REF) ** 2, axis=1) / 8) * T
    assert other != pytest.approx(exact, rel=1e-6)  # negative control: other DoFs differ


def test_spin_is_the_vertical_part_of_the_momentum_term_on_its_own_scale(cycle):
    _, _, _, ev = cycle
    spin, mom = ev.criteria["C_spin"], ev.criteria["C_momentum"]
    scale = (builtin_terms.MOMENTUM_REF / builtin_terms.SPIN_REF) ** 2
    assert spin["x"] == 0 and spin["z"] == 0
    assert spin["y"] == pytest.approx(mom["y"] * scale, rel=1e-12)
    assert spin["y"] != pytest.approx(mom["total"] * scale, rel=1e-3)  # not the whole momentum


def test_impact_and_shear_terms_integrate_the_reported_ground_reactions(cycle):
    """C_impact = ∫ (max(ΣF_y / (m g) − 1, 0) / 0.25)² dt and C_shear = ∫ (ΣF_x² + ΣF_z²) /
    (0.25 m g)² dt over the feet's reported forces (which tests/results check against the
    segments' momentum rate)."""
    _, body, _, ev = cycle
    a = ev.prediction_arrays
    dt = a["time"][1] - a["time"][0]
    f = np.sum(a["grf_force"][:-1], axis=1) / (body.mass * G)
    got = ev.criteria["C_impact"]["total"]
    above = np.maximum(f[:, 1] - 1, 0)
    assert (f[:, 1] < 1).any() and (f[:, 1] > 1).any()  # both sides of body weight occur
    assert np.sum((above / builtin_terms.IMPACT_REF) ** 2) * dt == pytest.approx(got, rel=1e-9)
    both = np.sum(((f[:, 1] - 1) / builtin_terms.IMPACT_REF) ** 2) * dt  # two-sided: not this term
    assert both != pytest.approx(got, rel=1e-3)
    below = np.maximum(1 - f[:, 1], 0)
    assert np.sum((below / builtin_terms.IMPACT_REF) ** 2) * dt == pytest.approx(
        ev.criteria["C_sag"]["total"], rel=1e-9
    )
    assert both == pytest.approx(got + ev.criteria["C_sag"]["total"], rel=1e-9)  # the two halves
    shear = np.sum((f[:, 0] ** 2 + f[:, 2] ** 2) / builtin_terms.SHEAR_REF**2) * dt
    assert ev.criteria["C_shear"]["total"] == pytest.approx(shear, rel=1e-9)
    assert ev.criteria["C_shear"]["y"] == 0


def test_the_nlp_objective_row_adds_the_weighted_terms_to_the_base():
    """Node function of the weighted criterion minus that of C_tor = Σ w·term (NumPy)."""
    body = build_body()
    base = PredictionSettings(criterion="tor").model
    weighted = PredictionSettings(criterion=WEIGHTED).model
    rng = np.random.default_rng(2)
    y = rng.uniform(-0.1, 0.1, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    f_tor = np.array(nlp.node_function(body, base)(y, w0, 0.07, p, t)[1]).ravel()
    f_w = np.array(nlp.node_function(body, weighted)(y, w0, 0.07, p, t)[1]).ravel()
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], 0.07,
                      p[0], p[1], p[2])  # fmt: skip
    coords = nlp._unpack_coords([np.array([v]) for v in y], p[2])
    it = terms.integrands(body, coords, st.pose, st.total[0])
    extra = float(np.squeeze(terms.weighted(terms.extras(WEIGHTED), it)))
    assert extra > 0
    assert f_w[0] - f_tor[0] == pytest.approx(extra, rel=1e-10)
    assert f_w[1] == f_tor[1]  # the C_en row is untouched


def test_angular_momentum_rate_equals_the_ground_moment_about_the_centre_of_mass(cycle):
    """dH_com/dt = Σ (r_i − r_c) × F_ground: gravity has no moment about the centre of mass.
    Checked by central differences of the momentum the ``momentum`` term squares."""
    from walk3d.contact.phases import GaitPhases
    from walk3d.results import evaluate as ev_mod

    s, body, x, _ = cycle
    ph = GaitPhases(s.gait.period, s.gait.double_support)
    t0, h = ph.heel_strike_r + 0.2, 1e-5
    t = np.array([t0 - h, t0, t0 + h])
    st = ev_mod._state(body, s, ph, x, t, "r", w0=((0, 0, 0), (0, 0, 0)), decay=np.zeros(3))
    hm = np.array(builtin_terms.angular_momentum(body, st.pose))  # (3, 3 times)
    rate = (hm[:, 2] - hm[:, 0]) / (2 * h)
    m = np.array([seg.mass for seg in body.segments])
    com = np.array([[c[0][k][1] for k in range(3)] for c in st.pose.com])  # (13, 3) at t0
    rc = m @ com / m.sum()
    f, mo = (np.array([v[1] for v in part]) for part in st.total)  # about the origin, at t0
    about_com = mo - np.cross(rc, f)
    np.testing.assert_allclose(rate, about_com, atol=1e-5 * np.abs(about_com).max())
    assert not np.allclose(rate, mo, atol=1e-3 * np.abs(about_com).max())  # origin ≠ COM
