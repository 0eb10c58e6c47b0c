"""The full-cycle problem's coordinate maps and side swap (:mod:`walk3d.problem.full_cycle`),
and the cycle evaluated from its ``X``."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from walk3d.body.model import build_body
from walk3d.model.whatif import STEP_ASYMMETRY_COST
from walk3d.problem import layout
from walk3d.problem.full_cycle import swap_changes, swapped_side
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.full_cycle import mirrored_start

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verify"))

PERIOD = 1.08
T = np.linspace(0.0, PERIOD, 9)


def _half_x(seed: int) -> np.ndarray:
    x = np.random.default_rng(seed).normal(0.0, 0.05, layout.N_X)
    x[layout.fixed_zero_mask()] = 0.0
    return x


@pytest.mark.parametrize("mirrored", [False, True])
def test_equal_sides_give_the_half_cycle_coordinates(mirrored):
    x = _half_x(1)
    for a, b in zip(layout.coordinate_maps(T, PERIOD),
                    layout.full_coordinate_maps(T, PERIOD, mirrored), strict=True):  # fmt: skip
        np.testing.assert_allclose(b @ mirrored_start(x), a @ x, atol=1e-12)


def test_a_changed_left_series_moves_the_left_side_only():
    """Negative control: the left knee's own series changes the left knee, not the right."""
    x = _half_x(2)
    xf = mirrored_start(x)
    xf[layout.N_X + layout.SERIES_NAMES.index("knee") * layout.N_COEF + 1] += 0.05
    a0, b0 = (
        layout.coordinate_maps(T, PERIOD)[0] @ x,
        layout.full_coordinate_maps(T, PERIOD)[0] @ xf,
    )
    dofs = list(build_body().dof_names)
    right, left = dofs.index("knee_flexion_r"), dofs.index("knee_flexion_l")
    np.testing.assert_allclose(b0[:, right], a0[:, right], atol=1e-12)
    assert np.abs(b0[:, left] - a0[:, left]).max() > 0.01
    # mirrored (step L), the roles swap: the left knee is the right-role one
    m0 = layout.full_coordinate_maps(T, PERIOD, mirrored=True)[0] @ xf
    assert np.abs(m0[:, right] - a0[:, right]).max() > 0.01
    np.testing.assert_allclose(m0[:, left], a0[:, left], atol=1e-12)


def test_a_full_cycle_warm_start_gives_its_half_cycle_vector_back():
    """A sweep warm-starts the half cycle from the previous result's ``X`` (full cycle)."""
    x = _half_x(4)
    np.testing.assert_array_equal(layout.half_cycle_x(mirrored_start(x)), x)
    np.testing.assert_array_equal(layout.half_cycle_x(x), x)
    xf = mirrored_start(x)
    xf[layout.N_X :] += 0.1  # the left side does not enter; the midline's fixed zeros return
    xf[0] = 0.3
    out = layout.half_cycle_x(xf)
    assert out.shape == (layout.N_X,) and not out[layout.fixed_zero_mask()].any()
    assert out[0] == (0.3 if not layout.fixed_zero_mask()[0] else 0.0)


def test_the_unused_entries_are_the_left_midline_and_the_step_shift_is_free():
    mask = layout.full_fixed_zero_mask()
    assert mask.sum() == 4 * layout.N_COEF and not mask[: layout.N_X].any()
    assert not mask[layout.I_STEP_SHIFT] and layout.I_STEP_SHIFT == layout.N_X + layout.I_HALF_STEP
    assert mirrored_start(_half_x(3))[layout.I_STEP_SHIFT] == 0.0


def test_step_l_sees_the_sides_swapped():
    assert swapped_side("ankle_r") == "ankle_l"
    assert swapped_side("ankle_dorsiflexion_l") == "ankle_dorsiflexion_r"
    assert swapped_side("torso") == "torso"
    s = PredictionSettings(changes={"strength": {"ankle_r": 0.3, "knee": 0.5},
                                    "added_mass": {"foot_l": 1.0},
                                    "limits": {"ankle_dorsiflexion_r": (-0.1, 0.1)}})  # fmt: skip
    swapped = swap_changes(s.model.changes)
    assert swapped.strength == (("ankle_l", 0.3), ("knee", 0.5))
    assert swapped.added_mass == (("foot_r", 1.0),)
    assert swapped.limits == (("ankle_dorsiflexion_l", -0.1, 0.1),)
    assert swap_changes(swapped) == s.model.changes


def test_the_mirrored_start_is_evaluated_as_the_half_cycle():
    from verify_support import evaluate_atlas

    from walk3d.results.evaluate import evaluate_cycle

    settings, body, ev = evaluate_atlas()
    full = evaluate_cycle(body, settings, mirrored_start(_atlas_x()))
    for key in ("joint_angle", "joint_moment", "grf_force"):
        np.testing.assert_allclose(full.prediction_arrays[key], ev.prediction_arrays[key],
                                   atol=1e-9)  # fmt: skip
    assert full.criteria["C_weighted"]["total"] == pytest.approx(
        ev.criteria["C_weighted"]["total"], rel=1e-9
    )


def test_the_step_shift_lengthens_the_right_step_and_shortens_the_left():
    """``d`` moves the feet's anchors: the right step is half a stride plus ``d``, the left one
    minus ``d``, at the same stride (the motion itself is the mirrored half cycle's). Control:
    ``d = 0`` gives equal steps."""
    from verify_support import evaluate_atlas

    from walk3d.results.asymmetry import asymmetry
    from walk3d.results.evaluate import evaluate_cycle

    settings, body, ev = evaluate_atlas()
    x = _atlas_x()
    steps, crit = {}, {}
    for d in (0.0, 0.03):
        xf = mirrored_start(x)
        xf[layout.I_STEP_SHIFT] = d
        evf = evaluate_cycle(body, settings, xf)
        steps[d] = asymmetry(evf.prediction_arrays, body.mass)["step_length_m"]
        crit[d] = evf.criteria
    assert abs(steps[0.0]["difference"]) < 0.005
    assert steps[0.03]["difference"] == pytest.approx(steps[0.0]["difference"] + 0.06, abs=0.005)
    total = {d: s["right"] + s["left"] for d, s in steps.items()}
    assert total[0.03] == pytest.approx(total[0.0], abs=1e-6)
    # the criterion's factor 1 + k SLA², SLA = d / half a stride (0 for equal steps)
    sla = 0.03 / (settings.gait.stride_length / 2)
    assert crit[0.0]["C_step_asymmetry"]["total"] == 0.0
    assert crit[0.0]["C_weighted"]["parts"]["step_asymmetry"] == 0.0
    assert crit[0.03]["C_step_asymmetry"]["total"] == pytest.approx(sla**2, rel=1e-12)
    w = crit[0.03]["C_weighted"]
    rest = w["total"] - w["parts"]["step_asymmetry"]
    assert w["total"] == pytest.approx(rest * (1 + STEP_ASYMMETRY_COST * sla**2), rel=1e-12)
    assert w["parts"]["step_asymmetry"] > 1e-3 * rest


def test_the_step_asymmetry_part_scales_the_other_parts():
    from walk3d.results.evaluate import weighted_total

    values = {"C_tor": {"total": 2.0}, "C_jerk": {"total": 1.0}}
    plain = weighted_total("tor=1,jerk=0.5", values)
    assert plain["total"] == pytest.approx(2.5) and "step_asymmetry" not in plain["parts"]
    asym = weighted_total("tor=1,jerk=0.5", values | {"C_step_asymmetry": {"total": 0.01}})
    assert asym["parts"]["step_asymmetry"] == pytest.approx(2.5 * STEP_ASYMMETRY_COST * 0.01)
    assert asym["total"] == pytest.approx(2.5 * (1 + STEP_ASYMMETRY_COST * 0.01))


def _atlas_x() -> np.ndarray:
    import json

    from verify_support import SPEED

    import walk3d.solve.atlas as atlas_module

    path = Path(atlas_module.__file__).parent / "atlas_data" / "male-natural.json"
    entry = next(e for e in json.loads(path.read_text(encoding="utf-8"))["entries"]
                 if abs(e["speed"] - SPEED) < 1e-9)  # fmt: skip
    return np.array(entry["x"])


@pytest.mark.model
def test_the_composed_derivatives_equal_casadi():
    """The full cycle's gradient, Jacobian and Hessian, composed from the steps' structured
    ones and the rows on ``X``, against CasADi's own of the same NLP; a weak right ankle puts
    the overload term in step R only (step L's body is another one). Control: the same
    Hessian without that change is another one."""
    import casadi as ca

    from walk3d.solve.full_cycle import build_full_problem

    gait = {"speed": 1.3806, "period": 1.08, "double_support": 0.16, "nodes": 6}
    weak = build_full_problem(PredictionSettings(**gait, changes={"strength": {"ankle_r": 0.3}}))
    fp = weak.problem
    z, f, g = fp.nlp["x"], fp.nlp["f"], fp.nlp["g"]
    lf, lg = ca.MX.sym("lf"), ca.MX.sym("lg", g.numel())
    jac = ca.Function("j", [z], [ca.jacobian(g, z)])
    grad = ca.Function("gf", [z], [ca.gradient(f, z)])
    hess = ca.Function("h", [z, lf, lg], [ca.triu(ca.hessian(lf * f + ca.dot(lg, g), z)[0])])
    rng = np.random.default_rng(5)
    z0 = rng.uniform(-0.05, 0.05, z.numel())
    lam = rng.normal(size=g.numel())
    d = fp.derivatives

    def dense(m):
        return np.array(ca.densify(ca.DM(m)))

    g_val, j_val = d["jac_g"](z0, [])
    np.testing.assert_allclose(dense(j_val), dense(jac(z0)), rtol=0, atol=1e-10)
    np.testing.assert_allclose(dense(g_val).ravel(), dense(ca.Function("g", [z], [g])(z0)).ravel(),
                               rtol=1e-12, atol=1e-12)  # fmt: skip
    gf_ref = dense(grad(z0))
    np.testing.assert_allclose(dense(d["grad_f"](z0, [])[1]), gf_ref, rtol=1e-12,
                               atol=1e-12 * np.abs(gf_ref).max())  # fmt: skip
    h_ref = dense(hess(z0, 0.7, lam))
    h_val = dense(d["hess_lag"](z0, [], 0.7, lam))
    np.testing.assert_allclose(h_val, h_ref, rtol=0, atol=1e-10 * np.abs(h_ref).max())
    # the step shift d enters both steps' rows and couples to their variables (not trivially 0)
    i_d = layout.I_STEP_SHIFT
    assert np.abs(dense(j_val)[:, i_d]).max() > 0.1
    assert np.abs(h_ref[i_d, layout.N_XF :]).max() > 1e-3 * np.abs(h_ref).max()
    plain = build_full_problem(PredictionSettings(**gait)).problem
    h_plain = dense(plain.derivatives["hess_lag"](z0, [], 0.7, lam))
    assert np.abs(h_plain - h_val).max() > 1e-6 * np.abs(h_val).max()
