"""The what-if options (--strength, --range, --added-mass): an empty or malformed spec is one
line and exit code 2 before any solve; repeated options merge, the same name with two values
is refused. The solve is replaced by one that records its settings and stops."""

import math

import pytest
from helpers import cli, one_line_error


class Solved(Exception):
    """walk3d.pipeline.predict was reached: the command accepted its input."""


@pytest.fixture
def solve(monkeypatch):
    """Replace the prediction by one that keeps its settings and raises :class:`Solved`."""
    import walk3d.pipeline as pipeline

    seen = {}

    def predict(settings, *args, **kwargs):
        seen["settings"] = settings
        raise Solved

    monkeypatch.setattr(pipeline, "predict", predict)
    return seen


BAD = [
    (["--strength", ""], "--strength is empty"),
    (["--strength", " "], "--strength is empty"),
    (["--range", ""], "--range is empty"),
    (["--added-mass", ""], "--added-mass is empty"),
    (["--strength", "ankle=0.5", "--strength", ""], "--strength is empty"),
    (["--strength", "ankle="], "--strength takes NAME=VALUE[,...], got 'ankle='"),
    (["--strength", "=0.5"], "--strength takes NAME=VALUE[,...], got '=0.5'"),
    (["--strength", "ankle=0.5,,knee=0.3"], "'ankle=0.5,,knee=0.3' has an empty item"),
    (["--added-mass", "torso=1,"], "--added-mass 'torso=1,' has an empty item"),
    (["--range", "knee_flexion=-5:5,"], "--range 'knee_flexion=-5:5,' has an empty item"),
    (["--strength", "ankle=0.5", "--strength", "ankle=0.4"], "names the same part twice"),
    (["--strength", "ankle=0.5", "--strength", "ankle_r=0.4"], "names the same part twice"),
    (["--added-mass", "torso=3", "--added-mass", "torso=4"], "names the same part twice"),
    # issue #60: float() reads 1_0 as 10 and Arabic-Indic digits; 1e300 overflowed the solve
    (["--strength", "ankle=1_0"], "ankle='1_0' is not a finite decimal number"),
    (["--strength", "ankle=\u0660.5"], "is not a finite decimal number"),
    (["--range", "knee_flexion=-5:1_0"], "knee_flexion='1_0' is not a finite decimal number"),
    (["--added-mass", "torso=1_0"], "torso='1_0' is not a finite decimal number"),
    (["--strength", "ankle=1e300"], "must be in [0.01, 10], got 1e+300"),
    (["--strength", "ankle=0.001"], "must be in [0.01, 10], got 0.001"),
    (["--period", "1_0"], "--period must be a positive number of seconds or auto, got '1_0'"),
]


@pytest.mark.parametrize(("args", "words"), BAD)
def test_an_empty_or_malformed_what_if_spec_is_refused_before_any_solve(
    capsys, tmp_path, solve, args, words
):
    """``--strength ''`` was no change at all; a second --strength replaced the first."""
    one_line_error(cli(capsys, "predict", "--out", tmp_path / "o", *args), words)
    assert not solve and not (tmp_path / "o").exists()


def test_sweep_refuses_an_empty_strength_spec(capsys, tmp_path, solve, monkeypatch):
    import walk3d.campaign.sweep as sweep

    monkeypatch.setattr(sweep, "run_sweep", lambda *a, **k: pytest.fail("the sweep started"))
    one_line_error(cli(capsys, "sweep", "--speeds", "1.2", "--out", tmp_path / "s",
                       "--strength", ""), "--strength is empty")  # fmt: skip
    assert not (tmp_path / "s").exists()


def _accepted(capsys, tmp_path, solve, *args):
    """The model changes of ``walk3d predict ARGS``, which reaches the solve."""
    with pytest.raises(Solved):
        cli(capsys, "predict", "--out", tmp_path / "o", *args)
    return solve["settings"].model.changes


def test_repeated_what_if_options_merge(capsys, tmp_path, solve):
    """Negative control: each joint, segment and DoF given once (or twice alike) is kept."""
    changes = _accepted(capsys, tmp_path, solve, "--strength", "ankle=0.5",
                        "--strength", "knee=0.8,hip=0.9", "--strength", "ankle=0.50",
                        "--added-mass", "torso=10", "--added-mass", "foot=1",
                        "--range", "ankle_dorsiflexion=-5:5", "--range",
                        "knee_flexion=-3:60")  # fmt: skip
    assert sorted(changes.strength) == [("ankle", 0.5), ("hip", 0.9), ("knee", 0.8)]
    assert sorted(changes.added_mass) == [("foot", 1.0), ("torso", 10.0)]
    assert sorted((n, round(math.degrees(lo)), round(math.degrees(hi)))
                  for n, lo, hi in changes.limits) == [("ankle_dorsiflexion", -5, 5),
                                                       ("knee_flexion", -3, 60)]  # fmt: skip


def test_a_single_what_if_spec_is_accepted(capsys, tmp_path, solve):
    """Negative control: one --strength list, as before."""
    changes = _accepted(capsys, tmp_path, solve, "--strength", "ankle=0.5,knee=0.8")
    assert sorted(changes.strength) == [("ankle", 0.5), ("knee", 0.8)]


def test_decimal_numbers_at_the_ends_of_the_strength_range_are_accepted(capsys, tmp_path, solve):
    """Negative control of 1_0 and 1e300: plain decimals, with an exponent or a sign, and the
    range's ends are read as written."""
    changes = _accepted(capsys, tmp_path, solve, "--strength", "ankle=1e1,knee=+.01,hip=2E-1",
                        "--range", "knee_flexion=-5.:60")  # fmt: skip
    assert sorted(changes.strength) == [("ankle", 10.0), ("hip", 0.2), ("knee", 0.01)]
    assert [round(math.degrees(lo), 9) for _, lo, _ in changes.limits] == [-5.0]


def test_sweep_refuses_a_speed_with_an_underscore(capsys, tmp_path, monkeypatch):
    """``--speeds 1_2`` was read as 12 m/s and refused as out of range; ``1_0,1_1`` as 10, 11."""
    import walk3d.campaign.sweep as sweep

    monkeypatch.setattr(sweep, "run_sweep", lambda *a, **k: pytest.fail("the sweep started"))
    one_line_error(cli(capsys, "sweep", "--speeds", "0_1,1.2", "--out", tmp_path / "s"),
                   "--speeds 0_1,1.2: expected start:stop:step")  # fmt: skip
    assert not (tmp_path / "s").exists()
    assert list(sweep.parse_speeds("0.1, 1.2")) == [0.1, 1.2]  # control


@pytest.mark.parametrize("values", [("-0.01", "-0.02"), ("-0.02", "-0.02")], ids=["two", "same"])
def test_a_repeated_leg_length_difference_is_refused_before_any_solve(capsys, tmp_path, solve,
                                                                      values):  # fmt: skip
    """One number cannot merge: the second --leg-length-difference replaced the first."""
    args = [a for v in values for a in ("--leg-length-difference", v)]
    one_line_error(cli(capsys, "predict", "--out", tmp_path / "o", *args),
                   "--leg-length-difference", "once")  # fmt: skip
    assert not solve and not (tmp_path / "o").exists()


def test_a_single_leg_length_difference_is_accepted(capsys, tmp_path, solve):
    """Negative control: given once, the right shank changes by that much."""
    changes = _accepted(capsys, tmp_path, solve, "--leg-length-difference", "-0.02")
    assert list(changes.shank_length) == [("shank_r", -0.02)]


@pytest.mark.parametrize("command", ["predict", "sweep", "campaign"])
@pytest.mark.parametrize("others", [[], ["--strength", "ankle=0.5"]], ids=["alone", "both-sides"])
def test_equal_steps_without_a_full_cycle_is_refused_before_any_solve(capsys, tmp_path, solve,
                                                                     command, others):  # fmt: skip
    """--equal-steps alone solved the half cycle (one step, mirrored) and recorded
    ``equal_steps: true`` in summary.json, though it did nothing."""
    extra = {"predict": [], "sweep": ["--speeds", "1.3"], "campaign": ["--starts", "1"]}
    one_line_error(cli(capsys, command, *extra[command], "--out", tmp_path / "o",
                       "--equal-steps", *others),
                   "--equal-steps needs --full-cycle or a one-sided change")  # fmt: skip
    assert not solve and not (tmp_path / "o").exists()


@pytest.mark.parametrize("args", [["--full-cycle"], ["--strength", "ankle_r=0.5"],
                                  ["--leg-length-difference", "-0.02"]],
                         ids=["full-cycle", "one-sided", "leg-length"])  # fmt: skip
def test_equal_steps_with_a_full_cycle_reaches_the_solve(capsys, tmp_path, solve, args):
    """Negative control: with --full-cycle or a one-sided change the steps may differ, and
    --equal-steps holds them equal."""
    _accepted(capsys, tmp_path, solve, "--equal-steps", *args)
    assert solve["settings"].model.equal_steps


def test_the_api_refuses_equal_steps_without_a_full_cycle():
    """walk3d.predict(equal_steps=True) alike, before any solve (its settings refuse it)."""
    import walk3d
    from walk3d.api import settings

    with pytest.raises(ValueError, match=r"^equal_steps needs full_cycle=True or a one-sided"):
        walk3d.predict(1.3, equal_steps=True)
    assert settings(1.3, equal_steps=True, full_cycle=True).model.equal_steps  # controls
    assert settings(1.3, equal_steps=True, changes={"strength": {"ankle_r": 0.5}})
