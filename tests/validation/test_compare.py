"""Table 2: alignment at right heel strike, RMSE and r, missing quantities, moment conventions."""

import numpy as np
import pytest

from walk3d.body.model import build_body
from walk3d.contact.phases import GaitPhases
from walk3d.io import read_cycle_table
from walk3d.kinematics.quaternion import conjugate, multiply
from walk3d.trials.kinematics import zxy_quaternion
from walk3d.trials.trial import load_trial
from walk3d.validation.compare import align_prediction, compare, cycle_timing
from walk3d.validation.quantities import QUANTITIES, _euler_axes, generalized_moments
from walk3d.validation.reference import Reference, reference_from_table, trial_reference


def _self_reference(pred, shift=None):
    percent, series = align_prediction(pred)
    mean = {k: v + (shift.get(k, 0.0) if shift else 0.0) for k, v in series.items()}
    return Reference("self", percent, mean, {k: np.zeros_like(v) for k, v in mean.items()})


def test_prediction_against_itself_has_zero_rmse(synthetic_prediction):
    comp = compare(synthetic_prediction, _self_reference(synthetic_prediction))
    assert len(comp.rows) == len(QUANTITIES)
    for row in comp.rows:
        if row.quantity.name == "neck_flexion" and row.quantity.group == "angle":
            continue
        assert row.status == "ok"
        assert row.rmse == pytest.approx(0.0, abs=1e-12), row.quantity.key
        if np.ptp(comp.predicted[row.quantity.key]) > 1e-9:
            assert row.r == pytest.approx(1.0, abs=1e-9), row.quantity.key


def test_known_offset_and_sinusoid_give_known_rmse(synthetic_prediction):
    percent = np.linspace(0, 100, 101)
    wave = 2.0 * np.sin(2 * np.pi * percent / 100)
    ref = _self_reference(synthetic_prediction, {"angle:knee_flexion": 3.0})
    ref.mean["grf:grf_vertical"] = ref.mean["grf:grf_vertical"] + wave
    comp = compare(synthetic_prediction, ref)
    assert comp.row("angle:knee_flexion").rmse == pytest.approx(3.0, rel=1e-12)
    assert comp.row("angle:knee_flexion").r == pytest.approx(1.0)
    # 101 samples over a closed cycle: mean of sin² is 50/101, not exactly 1/2
    expected = 2.0 * np.sqrt(np.mean(np.sin(2 * np.pi * percent / 100) ** 2))
    assert comp.row("grf:grf_vertical").rmse == pytest.approx(expected, rel=1e-12)


def test_missing_quantities_are_listed_not_dropped(synthetic_prediction):
    full = _self_reference(synthetic_prediction)
    keep = {"grf:grf_vertical", "angle:knee_flexion"}
    ref = Reference("partial", full.percent, {k: full.mean[k] for k in keep},
                    {k: full.sd[k] for k in keep})  # fmt: skip
    comp = compare(synthetic_prediction, ref)
    assert [r.quantity.key for r in comp.rows] == [q.key for q in QUANTITIES]
    for row in comp.rows:
        if row.quantity.key in keep:
            assert row.status == "ok"
        else:
            assert row.status == "missing in reference" and np.isnan(row.rmse)


def test_alignment_starts_at_right_heel_strike(synthetic_prediction):
    period, t_hs = cycle_timing(synthetic_prediction)
    ph = GaitPhases(period, period / 2 - t_hs)
    assert t_hs == pytest.approx(ph.heel_strike_r)
    percent, series = align_prediction(synthetic_prediction)
    fy = series["grf:grf_vertical"]
    toe_off = 100 * (period - ph.heel_strike_r) / period  # right toe off is walk3d's t = T
    swing = (percent > toe_off + 1) & (percent < 99)
    assert np.all(fy[swing] == 0.0)  # right foot in the air
    stance = (percent > 1) & (percent < toe_off - 1)
    assert np.all(fy[stance] != 0.0)  # loaded (a random motion: sign not meaningful)


def test_ball_joint_generalized_forces_give_the_joint_power():
    rng = np.random.default_rng(3)
    t = np.linspace(0, 1, 2001)
    ang = np.column_stack([0.3 * np.sin(2 * np.pi * (t + p)) for p in rng.uniform(0, 1, 3)])
    q = zxy_quaternion(ang[:, 2], ang[:, 0], ang[:, 1])  # slot order: add, rot, flex
    dq = np.gradient(q, t, axis=0)
    omega = 2 * multiply(dq, conjugate(q))[:, 1:]  # parent frame
    moment = rng.normal(size=3)
    tau = np.einsum("k,nik->ni", moment, _euler_axes(ang))
    power_q = np.sum(tau * np.gradient(ang, t, axis=0), axis=1)
    np.testing.assert_allclose(power_q[5:-5], (omega @ moment)[5:-5], atol=1e-5)


@pytest.mark.parametrize("side", ["r", "l"])
def test_walk3d_moments_map_to_generalized_forces_on_both_sides(synthetic_prediction, side):
    """Σ τ_i q̇_i equals the joint power M·ω_rel from segment orientations (hip, knee)."""
    pred, body = synthetic_prediction, build_body()
    tau = generalized_moments(pred)
    dt = pred.time[1] - pred.time[0]
    for name in (f"hip_{side}", f"knee_{side}"):
        j = body.joint_index(name)
        joint = body.joints[j]
        qp = pred.segment_orientation[:, joint.parent]
        qc = pred.segment_orientation[:, joint.child]
        qj = multiply(conjugate(qp), qc)
        omega_p = 2 * multiply(np.gradient(qj, dt, axis=0), conjugate(qj))[:, 1:]
        if joint.kind == "ball":  # slots back to the parent frame
            power = np.sum((pred.joint_moment[:, j] @ joint.axes) * omega_p, axis=1)
        else:  # hinge: slot z is the moment about the hinge axis
            power = pred.joint_moment[:, j, 2] * (omega_p @ joint.axis)
        dofs = list(joint.dof_names)
        idx = [pred.dof_names.index(d) for d in dofs]
        rates = np.gradient(pred.joint_angle[:, idx], dt, axis=0)
        power_q = sum(tau[d] * rates[:, k] for k, d in enumerate(dofs))
        inner = slice(3, -3)
        scale = np.max(np.abs(power[inner]))
        assert np.max(np.abs(power_q[inner] - power[inner])) < 0.02 * scale, name


def test_falisse_table_sign_conventions(falisse):
    table = read_cycle_table(falisse / "cycle_right_leg_mean_sd.csv")
    ref = reference_from_table(table, mass=62.0)
    knee = ref.mean["angle:knee_flexion"]
    raw_knee, _ = table.column("knee_angle_deg")
    np.testing.assert_array_equal(knee, -raw_knee)  # knee_angle negative in flexion
    assert knee.max() > 55 and 60 < np.argmax(knee) < 85  # swing flexion positive in walk3d
    raw_m, _ = table.column("knee_angle_moment_Nm_per_kg")
    np.testing.assert_array_equal(ref.mean["moment:knee_flexion"], -raw_m)
    # early stance: internal knee extensor moment, i.e. negative flexion moment in walk3d
    assert ref.mean["moment:knee_flexion"][10:20].mean() < -0.3
    raw_h, _ = table.column("hip_flexion_deg")
    np.testing.assert_array_equal(ref.mean["angle:hip_flexion"], raw_h)
    # right foot: medial (-z) shear through mid-stance, forward push-off, braking first
    assert ref.mean["grf:grf_lateral"][15:45].mean() < 0
    assert (
        ref.mean["grf:grf_fore_aft"][5:20].mean() < 0 < ref.mean["grf:grf_fore_aft"][45:58].mean()
    )
    assert "moment:neck_flexion" not in ref.mean


def test_winter_table_flips_extensor_moments(winter):
    table = read_cycle_table(winter)
    ref = reference_from_table(table)
    raw, _ = table.column("ankle_moment_Nm_per_kg")
    ankle = ref.mean["moment:ankle_dorsiflexion"]
    assert ankle.min() < -1.2 and raw.max() > 1.2  # push-off: plantarflexor moment, negative
    assert ref.mean["angle:knee_flexion"].max() > 55  # Winter's knee angle is flexion-positive
    assert set(ref.mean) == {
        "angle:hip_flexion", "angle:knee_flexion", "angle:ankle_dorsiflexion",
        "grf:grf_fore_aft", "grf:grf_vertical", "moment:hip_flexion",
        "moment:knee_flexion", "moment:ankle_dorsiflexion",
    }  # fmt: skip


def test_trial_cycles_reproduce_the_eleven_trial_mean(falisse):
    """One trial cut at plate heel strikes, left leg mirrored, lands on the 11-trial mean."""
    trial = load_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot",
                       falisse / "gait_1_id.sto")  # fmt: skip
    ref = trial_reference([trial], mass=62.0)
    table = reference_from_table(read_cycle_table(falisse / "cycle_right_leg_mean_sd.csv"))
    assert ref.n_cycles["grf:grf_vertical"] == 2  # right and left plate cycles
    limits = {"grf": 0.3, "moment": 0.25, "angle": 6.0}
    for key, mean in ref.mean.items():
        err = np.sqrt(np.mean((mean - table.mean[key]) ** 2))
        assert err < limits[key.split(":")[0]], (key, err)


def test_r_squared_is_one_for_a_perfect_fit_and_zero_for_the_mean():
    from walk3d.validation.compare import r_squared

    m = np.sin(np.linspace(0.0, 2 * np.pi, 101))
    assert r_squared(m, m) == 1.0
    assert abs(r_squared(np.full_like(m, m.mean()), m)) < 1e-12
    assert r_squared(m + 1.0, m) < 0  # an offset explains less than the mean does
    assert np.isnan(r_squared(m, np.ones_like(m)))  # a flat reference has no variance


def test_a_constant_column_is_not_ok_but_says_why(synthetic_prediction, falisse, tmp_path):
    """A table whose hip flexion is 10 everywhere gave a row 'ok' with r and R² NaN."""
    lines = (falisse / "cycle_right_leg_mean_sd.csv").read_text().splitlines()
    k = lines[0].split(",").index("hip_flexion_deg_mean")
    rows = [lines[0]] + [",".join(c[:k] + ["10"] + c[k + 1 :]) for c in
                         (line.split(",") for line in lines[1:])]  # fmt: skip
    (tmp_path / "c.csv").write_text("\n".join(rows) + "\n")
    ref = reference_from_table(read_cycle_table(tmp_path / "c.csv"), mass=62.0)
    row = compare(synthetic_prediction, ref).row("angle:hip_flexion")
    assert row.status == "constant reference" and np.isnan(row.r) and np.isnan(row.r2)
    flat = _self_reference(synthetic_prediction)
    flat.mean["angle:knee_flexion"] = flat.mean["angle:knee_flexion"] + np.arange(101.0)
    comp = compare(synthetic_prediction, flat)
    for row in comp.rows:
        p = comp.predicted.get(row.quantity.key)
        if row.status == "ok":  # control: every ok row has its scores
            assert np.isfinite(row.r) and np.isfinite(row.r2), row.quantity.key
        elif p is not None and np.ptp(p) == 0:
            assert row.status == "constant prediction", row.quantity.key
    assert comp.row("angle:knee_flexion").status == "ok"
    assert compare(synthetic_prediction, ref).row("angle:knee_flexion").status == "ok"


def _with_gait(pred, **gait):
    from dataclasses import replace

    settings = pred.summary["settings"]
    summary = {**pred.summary, "settings": {**settings, "gait": {**settings["gait"], **gait}}}
    return replace(pred, summary=summary)


@pytest.mark.parametrize("period", [float("inf"), float("nan"), 1e7, 1e-6, "x", [1], True])
def test_a_recorded_period_that_is_not_the_time_span_is_refused(synthetic_prediction, period):
    """Infinity once gave two RuntimeWarnings and "array of sample points is empty"."""
    with pytest.raises(ValueError, match=r"settings\.gait\.period .* is not the cycle's period"):
        cycle_timing(_with_gait(synthetic_prediction, period=period))


@pytest.mark.parametrize("td", [float("inf"), float("nan"), -0.1, 5.0, "x"])
def test_a_bad_recorded_double_support_is_refused(synthetic_prediction, td):
    with pytest.raises(ValueError, match=r"settings\.gait\.double_support .* is not a duration"):
        cycle_timing(_with_gait(synthetic_prediction, double_support=td))


def test_the_recorded_period_is_the_time_span(synthetic_prediction):
    """Negative control of the two refusals above: walk3d's own summary is accepted."""
    span = float(synthetic_prediction.time[-1] - synthetic_prediction.time[0])
    gait = synthetic_prediction.summary["settings"]["gait"]
    assert gait["period"] == pytest.approx(span, rel=1e-12)
    assert cycle_timing(_with_gait(synthetic_prediction, period=span))[0] == span
