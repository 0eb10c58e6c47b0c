"""What-if changes to the body (issue #43): strength factors, added point masses, joint limits
and shank lengths, their checks, and how the reference-subject problem scales them."""

import math
import re

import numpy as np
import pytest

from walk3d.body.changes import apply_changes, check_changes, limited_dofs
from walk3d.body.model import SEGMENT_NAMES, build_body
from walk3d.kinematics.forward import forward, joint_quaternions, root_foot_triples, stack_v
from walk3d.model.ranges import joint_ranges
from walk3d.model.whatif import BRACE_HEEL_RISE, heel_rise
from walk3d.problem.full_cycle import swap_changes
from walk3d.problem.schedule import range_rows
from walk3d.problem.settings import PredictionSettings, body_for, first_error
from walk3d.problem.similarity import REFERENCE_MASS_KG, reference_problem

FIVE = math.radians(5.0)


def _total_mass(body):
    return sum(s.mass for s in body.segments)


def test_no_change_is_the_same_body():
    body = build_body()
    assert apply_changes(body) is body
    assert apply_changes(body, (), ()) is body


def test_strength_factor_scales_both_sides_and_both_directions_of_that_joint_only():
    body = build_body(62.0, 1.70, "female")
    weak = apply_changes(body, strength=(("ankle", 0.3),))
    for old, new in zip(body.joints, weak.joints, strict=True):
        k = 0.3 if old.name in ("ankle_r", "ankle_l") else 1.0
        np.testing.assert_allclose(new.strength_pos, k * old.strength_pos, rtol=1e-12)
        np.testing.assert_allclose(new.strength_neg, k * old.strength_neg, rtol=1e-12)
    # negative control: the factor really changed the ankle
    assert not np.allclose(weak.joints[8].strength_pos, body.joints[8].strength_pos)


def test_added_mass_sits_at_the_centre_of_mass_and_adds_to_the_body_mass():
    body = build_body()
    pack = apply_changes(body, added_mass=(("torso", 10.0), ("foot", 1.0)))
    assert pack.mass == pytest.approx(body.mass + 12.0)  # foot: 1 kg on each foot
    assert _total_mass(pack) == pytest.approx(pack.mass, rel=1e-12)
    for old, new in zip(body.segments, pack.segments, strict=True):
        extra = {"torso": 10.0, "foot_r": 1.0, "foot_l": 1.0}.get(old.name, 0.0)
        assert new.mass == pytest.approx(old.mass + extra)
        np.testing.assert_array_equal(new.com, old.com)  # a point mass at the centre of mass
        np.testing.assert_array_equal(new.inertia, old.inertia)
    assert _total_mass(body) == pytest.approx(body.mass, rel=1e-12)  # the original is untouched


@pytest.mark.parametrize(
    ("strength", "mass", "limits", "words"),
    [
        ((("waist_r", 0.5),), (), (), "unknown joint 'waist_r'"),
        ((("toe", 0.5),), (), (), "unknown joint 'toe'"),
        ((("knee", 0.0),), (), (), "must be in [0.01, 10], got 0"),
        ((("knee", 1e300),), (), (), "must be in [0.01, 10], got 1e+300"),
        ((("knee", 1e-300),), (), (), "must be in [0.01, 10], got 1e-300"),
        ((), (("torso", -1.0),), (), "added mass at 'torso'"),
        ((), (("torso", 61.0),), (), "added mass at 'torso'"),
        ((), (("torso_l", 1.0),), (), "unknown segment 'torso_l'"),
        ((), (), (("ankle_dorsiflexion", FIVE, -FIVE),), "is empty"),
        ((), (), (("ankle_dorsiflexion", FIVE, 2 * FIVE),), "excludes standing"),
        ((), (), (("knee_flexion_x", -FIVE, FIVE),), "unknown DoF 'knee_flexion_x'"),
        ((("ankle", 0.5), ("ankle_r", 0.6)), (), (), "same part twice"),
        ((("knee", 0.5), ("knee", 0.6)), (), (), "same part twice"),
    ],
)
def test_bad_changes_are_refused_with_one_line(strength, mass, limits, words):
    with pytest.raises(ValueError, match=re.escape(words)):
        check_changes(strength, mass, limits)
    with pytest.raises(ValueError) as info:
        PredictionSettings(changes={"strength": strength, "added_mass": mass, "limits": limits})
    assert words.split("'")[0].strip() in first_error(info.value)
    assert "\n" not in first_error(info.value)


def test_one_sided_changes_act_on_their_side_only():
    body = build_body()
    weak = apply_changes(body, strength=(("ankle_r", 0.5),), added_mass=(("foot_l", 1.0),))
    joints = {j.name: j for j in weak.joints}
    base = {j.name: j for j in body.joints}
    np.testing.assert_allclose(joints["ankle_r"].strength_neg, 0.5 * base["ankle_r"].strength_neg)
    np.testing.assert_array_equal(joints["ankle_l"].strength_neg, base["ankle_l"].strength_neg)
    masses = {s.name: s.mass for s in weak.segments}
    assert masses["foot_l"] == pytest.approx(body.segments[SEGMENT_NAMES.index("foot_l")].mass + 1)
    assert masses["foot_r"] == body.segments[SEGMENT_NAMES.index("foot_r")].mass
    s = PredictionSettings(changes={"strength": {"ankle_r": 0.5, "knee": 0.8},
                                    "limits": {"ankle_dorsiflexion_r": (-FIVE, FIVE)}})  # fmt: skip
    assert s.model.changes.one_sided
    both = s.model.changes.both_sided()
    assert both.strength == (("knee", 0.8),) and not both.limits and not both.one_sided
    assert not PredictionSettings(changes={"strength": {"knee": 0.8}}).model.changes.one_sided
    # the half cycle that starts the full cycle keeps a one-sided limit, on both sides
    half = s.model.changes.half_cycle()
    assert half.strength == (("knee", 0.8),) and not half.one_sided
    assert half.limits == (("ankle_dorsiflexion", -FIVE, FIVE),)
    two = PredictionSettings(
        changes={
            "limits": {
                "ankle_dorsiflexion_r": (-FIVE, 2 * FIVE),
                "ankle_dorsiflexion_l": (-2 * FIVE, FIVE),
            }
        }
    )
    assert two.model.changes.half_cycle().limits == (("ankle_dorsiflexion", -FIVE, FIVE),)


def test_good_changes_pass_and_mappings_are_accepted():
    s = PredictionSettings(changes={"strength": {"ankle": 0.5}, "added_mass": {"torso": 10},
                                    "limits": {"ankle_dorsiflexion": (-FIVE, FIVE)}})  # fmt: skip
    c = s.model.changes
    assert c.strength == (("ankle", 0.5),) and c.added_mass == (("torso", 10.0),)
    assert c.limits == (("ankle_dorsiflexion", -FIVE, FIVE),) and bool(c)
    assert not PredictionSettings().model.changes


def test_limits_narrow_both_sides_and_get_rows_between_the_nodes():
    s = PredictionSettings(changes={"limits": {"ankle_dorsiflexion": (-FIVE, FIVE)}})
    body = body_for(s)
    dofs = limited_dofs(body, s.model.changes.limits)
    assert sorted(body.dof_names[i] for i in dofs) == ["ankle_dorsiflexion_l",
                                                       "ankle_dorsiflexion_r"]  # fmt: skip
    ranges, plain = joint_ranges(body, s.model), joint_ranges(body, PredictionSettings().model)
    for i in range(24):
        expect = (-FIVE, FIVE) if i in dofs else tuple(plain[i])
        np.testing.assert_allclose(ranges[i], expect)
    R, lo, hi = range_rows(body, s)
    assert R.shape[0] == lo.size == hi.size > 0
    np.testing.assert_allclose(hi, math.sin(FIVE / 2))
    # negative control: without limits (and without oversampling) there are no such rows
    assert range_rows(body, PredictionSettings())[0].shape[0] == 0


def test_an_ankle_limit_lets_the_heel_rise_unless_heel_rise_is_given():
    braced = PredictionSettings(changes={"limits": {"ankle_dorsiflexion": (-FIVE, FIVE)}})
    assert heel_rise(braced.model) == BRACE_HEEL_RISE
    knee = PredictionSettings(changes={"limits": {"knee_flexion": (-FIVE, 1.2)}})
    assert heel_rise(knee.model) is None
    given = PredictionSettings(heel_rise=0.6, changes=braced.model.changes)
    assert heel_rise(given.model) == 0.6


def test_reference_problem_keeps_the_added_mass_a_fraction_of_the_body_mass():
    changes = {"added_mass": {"torso": 10.0}, "strength": {"knee": 0.5}}
    s = PredictionSettings(mass=62.0, height=1.70, sex="female", changes=changes)
    ref, _ = reference_problem(s)
    ((name, kg),) = ref.model.changes.added_mass
    assert name == "torso" and kg == pytest.approx(10.0 * REFERENCE_MASS_KG / 62.0)
    assert ref.model.changes.strength == (("knee", 0.5),)
    sub, rb = body_for(s), body_for(ref)
    assert (sub.mass - 62.0) / 62.0 == pytest.approx(
        (rb.mass - REFERENCE_MASS_KG) / REFERENCE_MASS_KG
    )


def _standing_ankles(body):
    """Both ankle joint centres, global, standing upright on the right foot."""
    zero = np.zeros(1)
    jq = joint_quaternions(body, [(zero, zero, zero)] * 24)
    q, p = root_foot_triples(body, "r", (zero, zero, zero), (0.0, body.joints[6].offset[2]))
    pose = forward(body, jq, body.segment_index("foot_r"), q, p)
    return (stack_v(pose.origin[body.segment_index(f"foot_{s}")][0])[0] for s in "rl")


def test_a_shorter_right_shank_raises_the_right_ankle_in_standing_by_as_much():
    body = build_body()
    short = apply_changes(body, shank_length=(("shank_r", -0.02),))
    assert short.mass == body.mass
    i_r, i_l = SEGMENT_NAMES.index("shank_r"), SEGMENT_NAMES.index("shank_l")
    assert short.segments[i_r].length == pytest.approx(body.segments[i_r].length - 0.02)
    assert short.segments[i_r].mass == body.segments[i_r].mass
    # the ankle joint (its parent is the shank) and the centre of mass move up the shank
    np.testing.assert_allclose(short.joints[i_r].offset, body.joints[i_r].offset + [0, 0.02, 0])
    k = (body.segments[i_r].length - 0.02) / body.segments[i_r].length
    np.testing.assert_allclose(short.segments[i_r].com, body.segments[i_r].com * k)
    # control: the left shank is the body's own
    assert short.segments[i_l] == body.segments[i_l] and short.joints[i_l] == body.joints[i_l]
    # standing on the short leg, the pelvis is 2 cm lower and the other foot 2 cm lower too
    (r, l_), (r0, l0) = _standing_ankles(short), _standing_ankles(body)
    np.testing.assert_allclose(r, r0, atol=1e-12)
    assert l0[1] - l_[1] == pytest.approx(0.02, abs=1e-12)
    assert l0[1] == pytest.approx(r0[1], abs=1e-12)  # control: level feet on equal legs


def test_shank_length_changes_are_checked_swapped_and_scaled():
    for bad, words in (((("thigh_r", -0.02),), "names a shank"),
                       ((("shank_r", 0.2),), "within ±0.1 m")):  # fmt: skip
        with pytest.raises(ValueError, match=words):
            check_changes((), (), (), bad)
    c = PredictionSettings(changes={"shank_length": {"shank_r": -0.02}}).model.changes
    assert c.one_sided and not c.both_sided() and bool(c)
    assert swap_changes(c).shank_length == (("shank_l", -0.02),)
    s = PredictionSettings(mass=62.0, height=1.70, sex="female", changes=c)
    ref, scale = reference_problem(s)
    assert ref.model.changes.shank_length == (("shank_r", pytest.approx(-0.02 / scale)),)


@pytest.mark.parametrize(("changes", "words"), [
    ({"strength": {"ankle": float("inf")}}, "finite number"),
    ({"strength": {"ankle": True}}, "must be a factor, not a bool"),
    ({"strength": {"ankle": np.bool_(True)}}, "must be a factor, not a bool"),
    ({"limits": {"knee_flexion": (-0.1, 0, 0.1)}}, r"must be \(low, high\) in rad"),
    ({"limits": [("knee_flexion",)]}, r"must be \(low, high\) in rad, got \(\)"),
    ({"strength": [(0.5, "ankle")]}, r"each strength item is \(joint, factor\)"),
    ({"added_mass": {"torso": float("nan")}}, "finite number"),
    ({"limits": {"ankle_dorsiflexion": (-float("inf"), float("inf"))}}, "finite number"),
    ({"limits": {"ankle_dorsiflexion": (-1e300, 1e300)}}, "beyond ±π"),
    ({"limits": {"ankle_dorsiflexion": (-5, 5)}}, "in degrees that is"),
])  # fmt: skip
def test_the_api_refuses_what_the_command_line_refuses(changes, words):
    """The changes' one validator (walk3d.body.changes.check_changes) sees every value, before
    any solve; a bool is refused before pydantic would read it as 1."""
    from walk3d.api import settings

    with pytest.raises(ValueError, match=words):
        settings(1.2, changes=changes)
    settings(
        1.2, changes={"strength": {"ankle": 0.5}, "limits": {"ankle_dorsiflexion": (-0.1, 0.1)}}
    )  # control
