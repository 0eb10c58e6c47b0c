"""The effort terms and the passive joint moments (#41): NumPy references written from the
published formulas, the NLP's node rows, and the default problem left as it was."""

import numpy as np
import pytest
from helpers import random_decision

from walk3d.body.model import build_body
from walk3d.model import effort, passive, terms
from walk3d.model.settings import node_fields
from walk3d.model.state import dof_moment_terms
from walk3d.problem import nlp
from walk3d.problem.settings import ModelSettings, PredictionSettings
from walk3d.results.evaluate import _coords, evaluate_cycle
from walk3d.solve import atlas, solver

# Anderson et al. 2007 Table 3 (young males): (c2, c3) for flexor / extensor, walk3d's signs
ANDERSON_MALE = {"hip_flexion": ((0.738, -0.214), (0.958, 0.932)),
                 "knee_flexion": ((0.869, 0.522), (1.258, 1.133)),
                 "ankle_dorsiflexion": ((1.510, -0.187), (1.391, 0.408))}  # fmt: skip
# PredSim default_coord_lim_torq_coeff.csv in OpenSim's coordinates (knee_angle < 0 in flexion)
PREDSIM = {"hip_flexion": (-2.44, 5.05, 1.51, -21.88, -0.6981, 1.81),
           "hip_adduction": (-0.03, 14.94, 0.03, -14.94, -0.5, 0.5),
           "hip_rotation": (-0.03, 14.94, 0.03, -14.94, -0.92, 0.92),
           "knee_angle": (-6.09, 33.94, 11.03, -11.33, -2.4, 0.13),
           "ankle_dorsiflexion": (-2.03, 38.11, 0.18, -12.12, -0.74, 0.52),
           "subtalar_inversion": (-60.21, 16.32, 60.21, -16.32, -0.65, 0.65),
           "lumbar_extension": (-0.35, 30.72, 0.25, -20.36, -0.5236, 0.17),
           "lumbar_bending": (-0.25, 20.36, 0.25, -20.36, -0.3491, 0.3491),
           "lumbar_rotation": (-0.25, 20.36, 0.25, -20.36, -0.3491, 0.3491)}  # fmt: skip


def _predsim(row, q):
    k1, k2, k3, k4, lo, hi = row
    return k1 * np.exp(k2 * (q - hi)) + k3 * np.exp(k4 * (q - lo))


def ref_passive(body, q, rates):
    """(n, 24) passive moments from PredSim's rows, the knee mapped by θ = −knee_angle."""
    out = np.zeros_like(q)
    for i, dof in enumerate(body.dof_names):
        name, th = dof[:-2] if dof[-2:] in ("_r", "_l") else dof, 2 * np.arcsin(q[:, i])
        if name == "knee_flexion":
            out[:, i] = -_predsim(PREDSIM["knee_angle"], -th) - 0.1 * rates[:, i]
        elif name in PREDSIM:
            out[:, i] = _predsim(PREDSIM[name], th) - 0.1 * rates[:, i]
    return out


def ref_u(body, m, q, angle=True):
    """(n, 24) |M| / M_max(θ, direction) with Anderson's cosine floored at 0.3 (smoothly)."""
    pos = np.concatenate([j.strength_pos for j in body.joints])
    neg = np.concatenate([j.strength_neg for j in body.joints])
    u = np.zeros_like(m)
    for i, dof in enumerate(body.dof_names):
        fp = fn = 1.0
        coef = ANDERSON_MALE.get(dof[:-2])
        if coef is not None and angle:
            th = 2 * np.arcsin(q[:, i])
            c = [np.cos(c2 * (th - c3)) for c2, c3 in coef]
            fp, fn = (0.5 * (ci + 0.3 + np.sqrt((ci - 0.3) ** 2 + 0.05**2)) for ci in c)
        u[:, i] = np.where(m[:, i] > 0, m[:, i] / (pos[i] * fp), -m[:, i] / (neg[i] * fn))
    return u


def _cycle_u(body, s, x, ev, angle=True):
    arr = ev.prediction_arrays
    m = np.column_stack([arr["joint_moment"][:, j, k] for j, jt in enumerate(body.joints)
                         for k in jt.dof_slots])  # fmt: skip
    q = np.column_stack([c[0] for c in _coords(x, arr["time"], s.gait.period)[:24]])
    return ref_u(body, m, q, angle)[:-1]  # t = T repeats t = 0


@pytest.fixture(scope="module")
def cycle():
    s = PredictionSettings(criterion="tor=1,effort=3,effort3=2")
    body = build_body()
    x = random_decision(11)
    return s, body, x, evaluate_cycle(body, s, x)


def test_effort_terms_equal_a_numpy_reference_on_the_cycle(cycle):
    s, body, x, ev = cycle
    dt = s.gait.period / 100
    u = _cycle_u(body, s, x, ev)
    got, got3 = ev.criteria["C_effort"], ev.criteria["C_effort3"]
    want = np.sum((u / effort.EFFORT_REF) ** 2) * dt / 24
    v2 = (u / effort.EFFORT3_REF) ** 2
    want3 = np.sum((v2 + 1e-6) ** 1.5 - 1e-9) * dt / 24
    assert got["total"] == pytest.approx(want, rel=1e-9)
    assert got3["total"] == pytest.approx(want3, rel=1e-9)
    sagittal = [i for i, j in enumerate(body.dof_names) if j.startswith(("knee", "ankle_d"))]
    assert got["z"] > np.sum((u[:, sagittal] / effort.EFFORT_REF) ** 2) * dt / 24 > 0
    assert got["x"] + got["y"] + got["z"] == pytest.approx(got["total"], rel=1e-12)
    weighted = ev.criteria["C_weighted"]["parts"]
    assert weighted["effort"] == pytest.approx(3 * want, rel=1e-9)
    # p = 2 and p = 3 differ; the angle factor matters; cubes are not squares
    assert got["total"] != pytest.approx(got3["total"], rel=0.05)
    flat = np.sum((_cycle_u(body, s, x, ev, angle=False) / effort.EFFORT_REF) ** 2) * dt / 24
    assert flat != pytest.approx(want, rel=0.01)
    assert np.sum(np.abs(u / effort.EFFORT3_REF) ** 2) * dt / 24 != pytest.approx(want3, rel=0.01)


def test_the_angle_factor_is_anderson_cosine_above_the_floor_and_the_floor_below():
    c2, c3 = ANDERSON_MALE["knee_flexion"][1]  # knee extensors: 15 % of peak at full extension
    th = np.linspace(-0.4, 2.7, 400)
    cos = np.cos(c2 * (th - c3))
    f = effort.angle_factor(th, c2, c3)
    free, floored = cos > effort.STRENGTH_FLOOR + 0.25, cos < effort.STRENGTH_FLOOR - 0.25
    assert free.sum() > 100 and floored.sum() > 20
    # the smooth floor is within w²/(4 |c − floor|) = 0.0025 of the clip there
    np.testing.assert_allclose(f[free], cos[free], atol=2.6e-3)
    np.testing.assert_allclose(f[floored], effort.STRENGTH_FLOOR, atol=2.6e-3)
    assert np.min(np.abs(f[floored] - cos[floored])) > 0.1  # the floor does act there
    assert np.all(np.diff(f[th < c3]) > 0) and f.max() == pytest.approx(1.0, abs=1e-3)
    body = build_body()
    i = body.dof_names.index("knee_flexion_r")
    sp, sn = effort.strengths(body, i, 0.0)
    assert sp / body.joints[7].strength_pos[0] == pytest.approx(np.cos(0.869 * 0.522), abs=2e-3)
    assert sn / body.joints[7].strength_neg[0] == pytest.approx(0.3, abs=0.02)
    w = body.dof_names.index("lumbar_extension")
    assert effort.strengths(body, w, 0.5) == (220.0 * body.mass / 75, 150.0 * body.mass / 75)


def test_the_passive_knee_flexes_beyond_hyperextension_and_is_quiet_mid_range():
    deg = np.radians
    knee = passive.limit_moment
    assert knee("knee_flexion", deg(-5.0)) == pytest.approx(1.43, abs=0.02)
    assert knee("knee_flexion", deg(-10.0)) > 20.0  # flexing: stops the hyperextension
    assert abs(knee("knee_flexion", deg(30.0))) < 0.01
    assert knee("knee_flexion", deg(150.0)) < -5.0  # extending beyond deep flexion
    # negative control: PredSim's row unmapped (as if knee_angle were flexion) does not stop it
    assert abs(_predsim(PREDSIM["knee_angle"], deg(-5.0))) < 0.01
    body = build_body()
    q = np.zeros((1, 24))
    q[0, body.dof_names.index("knee_flexion_r")] = np.sin(deg(30.0) / 2)
    rates = np.full((1, 24), 2.0)
    got = np.array(passive.passive_moments(body, list(q.T), list(rates.T))).T
    np.testing.assert_allclose(got, ref_passive(body, q, rates), rtol=1e-12, atol=1e-14)
    i = body.dof_names.index("knee_flexion_r")
    assert got[0, i] == pytest.approx(-0.2, abs=0.01)  # damping resists flexing
    assert got[0, body.dof_names.index("elbow_flex_r")] == 0.0  # no stop, no damping


def _node(body, criterion, passive_on, rng_seed=4):
    rng = np.random.default_rng(rng_seed)
    y = rng.uniform(-0.15, 0.15, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    model = ModelSettings(criterion=criterion, passive=passive_on, handover=False)
    fn = nlp.node_function(body, model)
    g, f = (np.array(v).ravel() for v in fn(y, w0, 0.07, p, t))
    return g, f, (y, w0, p, t, fn)


def test_the_node_rows_see_the_active_moments_and_the_effort():
    body = build_body()
    g_t, f_t, (y, w0, p, t, _) = _node(body, "tor", True)
    g_e, f_e, _ = _node(body, "tor=1,effort=2", True)
    st = nlp.state_at(body, [np.array([v]) for v in y], [np.array([v]) for v in w0], 0.07,
                      p[0], p[1], p[2])  # fmt: skip
    m, rates, _ = (np.array([np.ravel(v) for v in part]).T for part in dof_moment_terms(body, st))
    q = y[None, :24]
    m_act = m - ref_passive(body, q, rates)
    u = ref_u(body, m_act, q)
    assert f_e[0] - f_t[0] == pytest.approx(2 * np.sum((u / effort.EFFORT_REF) ** 2) / 24)
    pos = np.concatenate([j.strength_pos for j in body.joints])
    np.testing.assert_allclose(g_t[nlp.G_ROWS["slack_pos"]], t - m_act[0] / pos, rtol=1e-10)
    # negative controls: the net moments are not what the rows see
    assert np.max(np.abs(g_t[nlp.G_ROWS["slack_pos"]] - (t - m[0] / pos))) > 1e-4
    u_net = ref_u(body, m, q)
    assert f_e[0] - f_t[0] != pytest.approx(2 * np.sum((u_net / effort.EFFORT_REF) ** 2) / 24)


def test_passive_off_leaves_the_node_function_and_the_keys_as_they_were(monkeypatch):
    body = build_body()
    crit = "natural"
    g_on, _, _ = _node(body, crit, True)
    g, f, args = _node(body, crit, False)
    # the call before the effort existed: no moments reach the terms
    old = terms.integrands
    monkeypatch.setattr(terms, "integrands", lambda b, c, pose, force, moments=None, wanted=None:
                        old(b, c, pose, force, None, wanted))  # fmt: skip
    g_old, f_old, old_args = _node(body, crit, False)
    monkeypatch.undo()
    np.testing.assert_array_equal(f, f_old)
    np.testing.assert_array_equal(g, g_old)
    assert args[-1].n_instructions() == old_args[-1].n_instructions()
    slack = nlp.G_ROWS["slack_pos"]
    assert np.max(np.abs(g_on[slack] - g[slack])) > 1e-4  # control: passive on changes the rows
    # the cache and atlas keys are those of the settings without the field
    s = PredictionSettings()
    opt_in = {"passive", "passive_total", "heel_rise", "load_ramp", "changes", "full_cycle",
              "equal_steps"}  # fmt: skip
    assert not opt_in & set(node_fields(s.model))
    assert not opt_in & set(atlas.settings_key(s)["model"])
    equal = PredictionSettings(equal_steps=True)  # the full cycle's bounds only
    assert solver.model_key(body, equal.model) == solver.model_key(body, s.model)
    # control: a what-if change is in the atlas key (its body is in the model key)
    braced = PredictionSettings(changes={"strength": {"ankle": 0.5}})
    assert "changes" in atlas.settings_key(braced)["model"]
    on = PredictionSettings(passive=True)
    assert solver.model_key(body, on.model) != solver.model_key(body, s.model)
    assert atlas.settings_key(on)["model"]["passive"] is True


def test_the_whole_joint_passive_moments_are_anderson_2007_and_add_to_the_stops():
    deg = np.radians
    jm = passive.joint_moment
    assert jm("knee_flexion", 0.0, "male") == pytest.approx(6.25)
    assert jm("knee_flexion", 0.0, "female") == pytest.approx(8.033)
    assert jm("hip_flexion", deg(-20.0), "male") == pytest.approx(11.1, abs=0.1)  # flexing
    assert jm("ankle_dorsiflexion", deg(20.0), "male") == pytest.approx(-8.1, abs=0.1)
    assert jm("hip_adduction", 0.3, "male") == 0.0  # not covered
    body = build_body(sex="female")
    q = np.zeros((1, 24))
    i = body.dof_names.index("knee_flexion_r")
    q[0, i] = np.sin(deg(5.0) / 2)
    rates = np.zeros((1, 24))
    stops = np.array(passive.passive_moments(body, list(q.T), list(rates.T))).T
    total = np.array(passive.passive_moments(body, list(q.T), list(rates.T), total=True)).T
    assert total[0, i] - stops[0, i] == pytest.approx(8.033 * np.exp(-5.25 * deg(5.0)))
    elbow = body.dof_names.index("elbow_flex_r")
    assert total[0, elbow] == stops[0, elbow] == 0.0
    assert stops[0, i] == pytest.approx(0.0, abs=0.01)  # control: the stops alone are quiet


def test_the_node_rows_see_the_whole_joint_passive_moments():
    body = build_body()
    rng = np.random.default_rng(4)
    y = rng.uniform(-0.15, 0.15, nlp.N_Y)
    w0 = np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03])
    p = np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.0, 0.0, 0.0])
    t = rng.uniform(0.0, 0.5, nlp.N_T)
    rows = []
    for total in (False, True):
        model = ModelSettings(criterion="natural", passive=True, passive_total=total,
                              handover=False)  # fmt: skip
        g, _ = (np.array(v).ravel() for v in nlp.node_function(body, model)(y, w0, 0.07, p, t))
        rows.append(g[nlp.G_ROWS["slack_pos"]])
    assert np.max(np.abs(rows[1] - rows[0])) > 1e-3
    with pytest.raises(ValueError, match="passive_total needs passive"):
        ModelSettings(passive_total=True)
