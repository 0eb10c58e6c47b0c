"""The cost audit's pieces on a solved gait (the shipped atlas's entry): the phases split the
criteria exactly, each leg's work in double support has the sign of its role, and the
push-off and loading bursts have theirs."""

import numpy as np
import pytest

from walk3d.problem import similarity
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.results import audit
from walk3d.results.evaluate import evaluate_cycle
from walk3d.solve.atlas import load_atlas


@pytest.fixture(scope="module")
def gait():
    a = load_atlas("female", "natural")
    k = int(np.argmin(np.abs(a.speeds - 1.3)))
    if a.x_handover is None or np.isnan(a.x_handover[k]).any():
        pytest.skip("the atlas has no handover optimum there")
    s = PredictionSettings(criterion="natural", sex="female", speed=float(a.speeds[k]),
                           period=float(a.periods[k]),
                           double_support=float(a.double_supports[k]))  # fmt: skip
    x = similarity.subject_x(a.x_handover[k], 1.0)
    return s, evaluate_cycle(body_for(s), s, x)


def test_the_phases_split_each_term_exactly(gait):
    s, ev = gait
    g = s.gait
    masks = audit.phase_masks(ev.prediction_arrays["time"], g.period, g.double_support)
    assert np.all(sum(m.astype(int) for m in masks.values()) == 1)  # a partition
    rows = audit.term_table({"a": ev}, s.model.criterion, g.period, g.double_support)
    for row in rows:
        parts = sum(row[f"a {p}"] for p in audit.PHASES)
        assert parts == pytest.approx(row["a total"], rel=1e-12)
        assert row["a total"] == pytest.approx(ev.criteria[row["term"]]["total"], rel=1e-9)


def test_each_leg_works_as_its_role_in_double_support(gait):
    s, ev = gait
    w = audit.limb_work(ev, s.gait.period, s.gait.double_support)
    assert w["trailing positive"] > 0.05 and w["leading negative"] < -0.05
    assert w["trailing positive"] > -w["trailing negative"]
    # negative control: the phase shifted by half a cycle swaps the legs' roles
    shifted = audit.limb_work(ev, s.gait.period, s.gait.double_support - s.gait.period / 2)
    assert shifted["trailing positive"] != pytest.approx(w["trailing positive"], rel=0.05)


def test_the_bursts_have_their_signs(gait):
    s, ev = gait
    body = body_for(s)
    b = audit.power_bursts(ev, body.dof_names, tuple(j.name for j in body.joints), s.gait.period,
                           s.gait.double_support)  # fmt: skip
    assert b["A2"] > 0.05 and b["A1"] < 0 and b["K1"] < 0 and b["H1"] > 0
    assert all(np.sign(v) in (0, audit.BURSTS[k][1]) for k, v in b.items())
