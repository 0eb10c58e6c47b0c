"""The Python API (walk3d.predict, walk3d.load_result, walk3d.Prediction): names, bad input as
one-line ValueErrors, the table's units and physics, saving and plotting (no solve; the slow
end-to-end call is in test_slow_predict.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import trapezoid

import walk3d
from walk3d import G, api

sys.path.insert(0, str(Path(__file__).resolve().parent / "verify"))


@pytest.fixture(scope="module")
def prediction():
    """The shipped atlas solution at 1.3 m/s as an API Prediction, labelled converged."""
    from verify_support import atlas_prediction

    pred, _ = atlas_prediction()
    pred = api.Prediction.of(pred)
    summary = dict(pred.summary, converged=True, status="Solve_Succeeded")
    return api.Prediction.of(type(pred)(**{**_fields(pred), "summary": summary}))


def _fields(pred):
    from dataclasses import fields

    return {f.name: getattr(pred, f.name) for f in fields(pred)}


def test_root_names_are_the_api_even_after_the_pipeline_module_is_imported():
    import walk3d.pipeline  # noqa: F401 - a submodule import must not shadow walk3d.predict

    assert walk3d.predict is api.predict and callable(walk3d.predict)
    assert walk3d.load_result is api.load_result and walk3d.Prediction is api.Prediction
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        walk3d.nonsense  # noqa: B018


BOOL_STRENGTH = {"changes": {"strength": {"ankle": np.bool_(True)}}}
LIMITS_OF_THREE = {"changes": {"limits": {"knee_flexion": (-0.1, 0, 0.1)}}}


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"speed": -1.0}, r"speed must be in \(0, 4\] m/s"),
        ({"speed": 1.3, "period": 1.0, "double_support": 0.6}, "double-support duration"),
        ({"speed": 1.3, "period": 0.1}, r"period must be in \[0.6, 2.5\] s"),
        ({"speed": 1.3, "period": 1.0, "double_support": 0.01}, "double-support duration"),
        ({"speed": 1.3, "double_support": 0.9}, "fits no predicted period"),
        ({"speed": 1.3, "mass": 5.0}, "body mass"),
        ({"speed": 1.3, "criterion": "nonsense"}, "criterion"),
        ({"speed": 1.3, "seed": -1}, "seed must be a non-negative integer"),
        ({"speed": 1.3, "colour": "red"}, "unknown setting 'colour'"),
        ({"speed": "1.2"}, "speed must be a finite number"),
        ({"speed": 1.3, "height": None}, "height must be a finite number"),
        ({"speed": 1.3, "seed": True}, "seed must be a non-negative integer"),
        # issue #60: numpy bools, bools in calibration ratios, absurd factors, malformed limits
        (BOOL_STRENGTH, r"strength of ankle must be a factor, not a bool"),
        ({"transition_ratios": (True, 0.0, 0.1, 0.1)}, "transition_ratios must hold numbers"),
        ({"friction": np.bool_(True)}, "friction must be a number, not a bool"),
        ({"changes": {"strength": {"ankle": 1e300}}}, r"must be in \[0.01, 10\], got 1e\+300"),
        (LIMITS_OF_THREE, r"limits of knee_flexion must be \(low, high\) in rad"),
        # text where a number goes: pydantic would read "1_0" as 10
        ({"changes": {"strength": {"ankle": "1_0"}}}, "strength of ankle must be a factor"),
        ({"transition_ratios": (" 0.5 ", 0.0, 0.1, 0.1)}, "must hold numbers, not text"),
        ({"friction": "0.8"}, "friction must be a number, not text"),
        ({"changes": {"strength": {("ankle", "1_0")}}}, "strength must be a mapping or a list"),
        ({"changes": {"added_mass": frozenset({("torso", True)})}}, "must be a mapping or a"),
        ({"speed": 1.3, "double_support": 10**400}, "double_support must be a finite number"),
        ({"speed": 1.3, "tol": 0.0}, r"tol must be in \[1e-12, 0.01\]"),
    ],
)
def test_bad_input_is_one_line_value_error_before_any_solve(monkeypatch, kwargs, message):
    import walk3d.pipeline

    def no_solve(*a, **k):
        raise AssertionError("solved despite bad input")

    monkeypatch.setattr(walk3d.pipeline, "predict", no_solve)
    with pytest.raises(ValueError, match=message) as info:
        walk3d.predict(**kwargs)
    assert "\n" not in str(info.value)


class _Solved(Exception):
    """walk3d.pipeline.predict was reached: the options were accepted."""


@pytest.mark.parametrize(
    "kwargs",
    [{"changes": {"strength": {"ankle": np.float64(0.5)}}},
     {"transition_ratios": (0.2, 0.0, 0.1, 0.1)}, {"handover": np.bool_(False)},
     {"changes": {"strength": {"ankle": 10.0}, "limits": {"knee_flexion": (-0.1, 1.5)}}},
     {"changes": {"limits": {"knee_flexion": (np.int64(0), 1)}}}, {"seed": np.int64(3)},
     {"criterion": "tor", "sex": "female"}],
)  # fmt: skip
def test_numbers_in_range_reach_the_solve(monkeypatch, kwargs):
    """Negative control of the bools, texts and absurd values above: numbers, NumPy numbers
    among them, a NumPy bool for a switch and text in text settings are accepted."""
    import walk3d.pipeline

    def solve(settings, *a, **k):
        raise _Solved(settings)

    monkeypatch.setattr(walk3d.pipeline, "predict", solve)
    with pytest.raises(_Solved):
        walk3d.predict(speed=1.3, **kwargs)


def test_settings_defaults_are_the_command_line_defaults():
    s = api.settings()
    assert s.gait.free == ("period", "double_support")
    assert (s.gait.mass, s.gait.height, s.gait.sex, s.gait.speed) == (68.8, 1.77, "male", 1.3806)
    assert s.solver.start == "atlas"
    from walk3d.model import terms

    assert terms.preset_name(s.model.criterion) == terms.DEFAULT_PRESET
    given = api.settings(1.2, period=1.1, double_support=0.12, criterion="tor")
    assert given.gait.free == () and (given.gait.period, given.gait.double_support) == (1.1, 0.12)


def test_a_solve_that_did_not_converge_is_labelled_and_warned(monkeypatch, prediction):
    import walk3d.pipeline

    summary = {"converged": False, "status": "Maximum_Iterations_Exceeded"}
    failed = type(prediction)(**{**_fields(prediction), "summary": summary})
    monkeypatch.setattr(walk3d.pipeline, "predict", lambda *a, **k: failed)
    with pytest.warns(RuntimeWarning, match="did not converge"):
        pred = walk3d.predict(speed=1.3)
    assert not pred.converged
    monkeypatch.setattr(walk3d.pipeline, "predict", lambda *a, **k: prediction)  # control
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert walk3d.predict(speed=1.3).converged


def test_dataframe_units_and_columns(prediction):
    df = prediction.to_dataframe()
    assert df.index.name == "time_s" and len(df) == prediction.n_nodes
    # 0 % at right heel strike (T/2 - Td after the clock's right toe-off), as walk3d validate
    gait = prediction.summary["settings"]["gait"]
    t_hs = gait["period"] / 2 - gait["double_support"]
    k = int(np.argmin(df["percent_cycle"].to_numpy()))
    assert df.index[k] - df.index[0] == pytest.approx(t_hs, abs=gait["period"] / 100)
    assert df["percent_cycle"].iloc[0] > 50  # control: the clock's 0 is not the cycle's 0 %
    hip = prediction.dof("hip_flexion_r")
    np.testing.assert_allclose(df["hip_flexion_r_deg"], np.degrees(hip))
    assert not np.allclose(df["hip_flexion_r_deg"], hip)  # control: radians would differ
    # one column per active moment axis: 24 DoF, so 24 moment columns
    moments = [c for c in df.columns if "_moment_" in c and not c.startswith("free_")]
    assert len(moments) == 24
    assert df["cop_r_x_m"].isna().any() and df["cop_r_x_m"].notna().any()  # NaN in swing only


def test_dataframe_vertical_forces_carry_the_weight_over_the_cycle(prediction):
    """Mean vertical ground reaction over a periodic cycle equals body weight (momentum)."""
    df = prediction.to_dataframe()
    t = df.index.to_numpy()
    weight = prediction.body_mass * G
    both = trapezoid(df["grf_r_y_N"] + df["grf_l_y_N"], t) / (t[-1] - t[0])
    assert both == pytest.approx(weight, rel=0.01)
    one = trapezoid(df["grf_r_y_N"], t) / (t[-1] - t[0])  # control: one foot alone is not
    assert abs(one / weight - 1) > 0.3


def test_save_and_load_round_trip_as_api_prediction(prediction, tmp_path):
    folder = prediction.save(tmp_path / "pred", figure=True)
    assert (folder / "summary.png").stat().st_size > 10_000 and (folder / "report.html").exists()
    back = walk3d.load_result(folder)
    assert isinstance(back, api.Prediction) and back.converged
    for name, value in _fields(prediction).items():
        if isinstance(value, np.ndarray):  # joint angles are recomputed on load: 1e-12
            np.testing.assert_allclose(getattr(back, name), value, rtol=0, atol=1e-12)
    with pytest.raises(AssertionError):  # control: the comparison sees a change
        np.testing.assert_allclose(back.time * 2, prediction.time, rtol=0, atol=1e-12)


def test_plot_returns_a_figure_and_writes_a_png(prediction, tmp_path):
    fig = prediction.plot(tmp_path / "fig.png")
    assert len(fig.axes) >= 10
    assert (tmp_path / "fig.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("value", ["no", "yes", 1, None, False])
def test_only_a_recorded_true_is_converged(prediction, value):
    """``{"converged": "no"}`` was converged (bool() of a non-empty string)."""
    from dataclasses import replace

    assert not replace(prediction, summary={**prediction.summary, "converged": value}).converged
    assert prediction.converged and prediction.summary["converged"] is True  # control


def test_save_refuses_an_array_walk3d_could_not_read_back(prediction, tmp_path):
    from dataclasses import replace

    angle = prediction.joint_angle.copy()
    angle[5, 3] = np.nan
    with pytest.raises(ValueError, match=r"joint_angle holds non-finite values .* read it back"):
        replace(prediction, joint_angle=angle).save(tmp_path / "s1")
    assert not (tmp_path / "s1").exists()
    walk3d.load_result(prediction.save(tmp_path / "s2", figure=False, report=False))  # control
