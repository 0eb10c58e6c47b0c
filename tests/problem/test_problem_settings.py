"""Prediction settings in three groups: validation, flat construction, copies and old files."""

import math

import numpy as np
import pytest

from walk3d.problem.settings import (
    FIELD_GROUP,
    GROUPS,
    GaitSettings,
    ModelSettings,
    PredictionSettings,
    SolverSettings,
    first_error,
    flat_settings,
    recorded_settings,
)

FLAT_BEFORE_THE_GROUPS = """speed period double_support mass height sex criterion nodes friction
free_moment_radius min_ankle_separation foot_flat_tolerance absolute derivatives smoothing
range_oversampling posture_stage balance_max_iter posture_balance_max_iter balance_progress_check
balance_split arm_walking_ranges leg_walking_ranges threads loop_checks loop_check_toe_off
loop_check_tolerance rollover_s rollover_ankle transition_ratios perturbation restarts
linear_solver hsl_library max_iter full_max_iter tol""".split()
"""The 37 fields of the flat settings that summary.json files before the groups record."""
ADDED_SINCE = [
    "cop_margin",
    "loop_tolerance",
    "tracking",
    "swing_clearance",
    "heel_strike_nodes",
    "contact_checks",
    "swing_checks",
    "split_terms",
    "reject_crouch",
    "free",
    "start",
    "handover",
    "passive",
    "passive_total",
    "heel_rise",
    "load_ramp",
    "descriptors_from",
    "changes",
    "full_cycle",
    "equal_steps",
    "grid",
]
"""Fields added later (issues #23, #24, #25, #26, #41, #42, #43, #61), with defaults, so older files
still load."""


def test_every_setting_belongs_to_exactly_one_group():
    names = [f for cls in GROUPS.values() for f in cls.model_fields]
    assert len(names) == len(set(names))  # no field in two groups
    assert sorted(names) == sorted(FLAT_BEFORE_THE_GROUPS + ADDED_SINCE) == sorted(FIELD_GROUP)
    assert {"speed", "period", "double_support", "mass", "height", "sex", "free"} == set(
        GaitSettings.model_fields
    )
    assert "criterion" in ModelSettings.model_fields and "nodes" in SolverSettings.model_fields


def test_flat_fields_are_routed_to_their_groups():
    s = PredictionSettings(speed=1.2, criterion="en", nodes=12)
    assert (s.gait.speed, s.model.criterion, s.solver.nodes) == (1.2, "en", 12)
    grouped = PredictionSettings(
        gait={"speed": 1.2}, model={"criterion": "en"}, solver={"nodes": 12}
    )
    assert grouped == s
    assert PredictionSettings(**s.flat()) == s == PredictionSettings(**s.model_dump())
    # the groups are immutable and hashable (solvers are cached per settings)
    with pytest.raises(ValueError):
        s.gait.speed = 2.0  # type: ignore[misc]
    assert hash(s) == hash(PredictionSettings(**s.flat()))


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"double_support": 0.6}, "double-support duration must be 2%-30% of T"),
        ({"speed": math.nan}, "speed must be a finite number"),
        ({"friction": 3.0}, "friction must be in (0, 2]"),
        ({"nodes": 3}, "nodes must be in [6, 200]"),
        ({"sex": "other"}, "sex: Input should be 'male' or 'female'"),
        ({"walking_style": "brisk"}, "unknown setting 'walking_style'"),
        ({"gait": 3}, "gait must be a mapping of settings"),
    ],
)
def test_bad_settings_give_one_line_naming_the_setting(kwargs, words):
    with pytest.raises(ValueError) as info:
        PredictionSettings(**kwargs)
    assert words in first_error(info.value)
    assert "\n" not in first_error(info.value)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"period": 0.1}, "period must be in [0.6, 2.5] s"),
        ({"period": 0.59, "double_support": 0.06}, "period must be in [0.6, 2.5] s"),
        ({"period": 2.6, "double_support": 0.3}, "period must be in [0.6, 2.5] s"),
        ({"period": 1.08, "double_support": 0.02}, "double-support duration must be 2%-30% of T"),
        ({"period": 1.08, "double_support": 0.33}, "double-support duration must be 2%-30% of T"),
        ({"period": 1.08, "double_support": 0.16, "free": ("period",), "speed": 1.2}, None),
        ({"period": 0.6, "double_support": 0.012}, None),
        ({"period": 2.5, "double_support": 0.75}, None),
    ],
)
def test_given_period_and_double_support_are_within_walking(kwargs, words):
    """T 0.6-2.5 s and Td 2-30 % of T (walk3d.problem.descriptors.GIVEN_*): a period of 0.1 s
    is refused before any solve; the bounds themselves pass (negative control)."""
    if words is None:
        PredictionSettings(**kwargs)
        return
    with pytest.raises(ValueError) as info:
        PredictionSettings(**kwargs)
    assert words in str(info.value) and "\n" not in str(info.value)


def test_the_atlas_and_sweep_ranges_are_within_the_given_bounds():
    """Every first guess of a sweep (0.1-4 m/s, statures 1.0-2.4 m), the atlas's entries and the
    paper's case are valid settings."""
    from walk3d.problem.descriptors import first_guess
    from walk3d.solve.atlas import ATLAS_DIR, load_atlas

    for height in (1.0, 1.5, 1.77, 2.0, 2.4):
        for speed in [v / 10 for v in range(1, 41)]:
            t, td = first_guess(speed, height)
            PredictionSettings(speed=speed, height=height, period=t, double_support=td)
    entries = 0
    for path in ATLAS_DIR.glob("*.json"):
        a = load_atlas(*path.stem.split("-", 1))
        for t, td in zip(a.periods, a.double_supports, strict=True):
            PredictionSettings(period=float(t), double_support=float(td))
            entries += 1
    assert entries > 10
    PredictionSettings(period=1.08, double_support=0.16)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [({"transition_ratios": (True, 0.0, 0.1, 0.1)}, "transition_ratios must hold numbers"),
     ({"rollover_s": (-0.2, np.bool_(False), 0.2), "rollover_ankle": ((0, 0, 0),) * 3},
      "rollover_s must hold numbers, not a bool"),
     ({"friction": np.bool_(True)}, "friction must be a number, not a bool"),
     ({"nodes": True}, "nodes must be a number"),
     ({"balance_progress_check": ((60, True),)}, "balance_progress_check must hold numbers"),
     ({"rollover_s": (-0.2, math.inf, 0.2)}, "rollover_s must hold finite numbers")],
)  # fmt: skip
def test_a_bool_or_non_finite_value_in_a_numeric_setting_is_refused(kwargs, words):
    """``transition_ratios=(True, ...)`` was read as μ_x = 1.0 and solved."""
    with pytest.raises(ValueError) as info:
        PredictionSettings(**kwargs)
    assert words in str(info.value) and "\n" not in str(info.value)


def test_switches_take_bools_and_numeric_settings_numbers():
    """Negative control: a bool (numpy's too) is a switch's value, numbers are accepted."""
    s = PredictionSettings(handover=np.bool_(False), passive=True, nodes=12, friction=1,
                           transition_ratios=(0.2, 0.0, 0.1, 0.1))  # fmt: skip
    assert (s.model.handover, s.model.passive, s.solver.nodes) == (False, True, 12)
    assert s.model.transition_ratios == (0.2, 0.0, 0.1, 0.1) and s.model.friction == 1.0


def test_pydantic_errors_become_one_plain_line():
    """PredictionSettings raises a one-line ValueError, not pydantic's multi-line
    ValidationError with its web link (the CLI prints str(exc) as is)."""
    from pydantic import ValidationError

    with pytest.raises(ValueError) as info:
        PredictionSettings(speed=math.nan)
    assert not isinstance(info.value, ValidationError)
    assert str(info.value) == "speed must be a finite number, got nan"
    with pytest.raises(ValueError) as info:
        PredictionSettings(**{"gait": {"sex": "other"}})
    assert "\n" not in str(info.value) and "pydantic" not in str(info.value)
    with pytest.raises(ValidationError):  # control: a group built alone is pydantic's error
        GaitSettings(speed=math.nan)


def test_replace_validates_and_keeps_the_rest():
    base = PredictionSettings(nodes=12)
    faster = base.replace(speed=1.5, max_iter=50)
    assert (faster.gait.speed, faster.solver.max_iter, faster.solver.nodes) == (1.5, 50, 12)
    assert faster.model == base.model and base.gait.speed == 1.3806
    with pytest.raises(ValueError, match="double-support duration"):
        base.replace(double_support=0.7)


def test_recorded_settings_read_grouped_and_flat_summaries():
    s = PredictionSettings(speed=1.2, nodes=12)
    now = {"settings": s.model_dump(), "seed": 3, "method": "ipopt"}
    before_groups = {
        "inputs": dict.fromkeys(FLAT_BEFORE_THE_GROUPS) | {"seed": 3, "solver": "ipopt"}
    }
    before_groups["inputs"].update(s.flat())
    assert recorded_settings(now) == recorded_settings(before_groups) == s.flat()
    assert PredictionSettings(**recorded_settings(before_groups)) == s
    assert recorded_settings({"objective": {}}) == {}
    assert flat_settings(s.model_dump()) == flat_settings(s.flat()) == s.flat()


@pytest.mark.parametrize(
    ("linear_solver", "hsl_library", "refused"),
    [("mumps", "/opt/hsl/libhsl.so", True), ("ma27", "/opt/hsl/libhsl.so", False),
     ("mumps", None, False), ("ma57", None, False)],
)  # fmt: skip
def test_an_hsl_library_without_an_hsl_solver_is_refused(linear_solver, hsl_library, refused):
    """``--hsl-library X`` without ``--linear-solver`` was ignored (MUMPS needs no library) and
    the command exited 0. Negative control: with an HSL solver, or without a library, it passes
    (no file is read here)."""
    kwargs = {"linear_solver": linear_solver, "hsl_library": hsl_library}
    if not refused:
        assert PredictionSettings(**kwargs).solver.hsl_library == hsl_library
        return
    with pytest.raises(ValueError, match="^hsl_library is the library of an HSL linear_solver"):
        PredictionSettings(**kwargs)


@pytest.mark.parametrize("linear_solver", ["mumps", "ma27"])
def test_a_summary_that_recorded_an_ignored_hsl_library_still_loads(linear_solver):
    """An earlier walk3d recorded ``hsl_library`` beside MUMPS, which ignored it: such a summary
    loads without it. Negative control: beside an HSL solver it is kept."""
    summary = {"settings": {"solver": {"linear_solver": linear_solver, "hsl_library": "/x.so"}}}
    recorded = recorded_settings(summary)
    assert recorded["hsl_library"] == (None if linear_solver == "mumps" else "/x.so")
    assert PredictionSettings(**recorded).solver.linear_solver == linear_solver
