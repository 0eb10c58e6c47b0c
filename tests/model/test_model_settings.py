"""Model settings declare their role; the model-cache key, the atlas keys and the opt-in set
are derived from the roles, so a new setting needs no key edit."""

from typing import Annotated

import pytest

from walk3d.body.model import build_body
from walk3d.model.settings import (
    ModelSettings,
    Role,
    is_on,
    keyed_fields,
    node_fields,
    opt_in,
    role,
)
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import atlas, solver

OPT_IN = {"handover": False, "passive": False, "passive_total": False, "heel_rise": None,
          "load_ramp": None, "full_cycle": False, "equal_steps": False, "loop_tolerance": 0.0,
          "tracking": None, "split_terms": 0}  # fmt: skip


def test_every_model_setting_declares_one_role():
    for name in ModelSettings.model_fields:
        assert isinstance(role(ModelSettings, name), Role)

    class Undeclared(ModelSettings):
        extra_option: bool = False

    with pytest.raises(TypeError, match="declares no Role"):  # negative control
        role(Undeclared, "extra_option")


def test_the_opt_in_settings_are_read_off_the_roles():
    found = opt_in()
    assert {k: v for k, v in found.items() if k != "changes"} == OPT_IN
    assert not found["changes"]  # no what-if change is the off value


class WithOption(ModelSettings):
    """ModelSettings with one more setting, declared as a new option is."""

    new_option: Annotated[float | None, Role(nodes=True, off=None)] = None
    bounds_only: Annotated[float, Role(nodes=False)] = 0.0


def test_a_new_setting_reaches_the_keys_without_a_key_edit():
    off, on = WithOption(), WithOption(new_option=2.0)
    assert "new_option" not in node_fields(off) and node_fields(on)["new_option"] == 2.0
    assert "new_option" not in keyed_fields(off) and keyed_fields(on)["new_option"] == 2.0
    assert opt_in(WithOption)["new_option"] is None
    assert not is_on(off, "new_option") and is_on(on, "new_option")
    body = build_body()
    assert solver.model_key(body, on) != solver.model_key(body, off)
    # a setting that does not shape the node functions stays out of the cache key ...
    moved = WithOption(bounds_only=0.01)
    assert solver.model_key(body, moved) == solver.model_key(body, off)
    assert keyed_fields(moved)["bounds_only"] == 0.01  # ... but not out of the atlas key
    # control: a node setting of ModelSettings itself changes the key
    assert solver.model_key(body, WithOption(friction=0.7)) != solver.model_key(body, off)


def test_an_off_value_is_matched_by_type_not_by_truth():
    zero = PredictionSettings(load_ramp=0.0)  # a ramp of slope 0, not the paper's default
    assert atlas.settings_key(zero)["model"]["load_ramp"] == 0.0
    assert "load_ramp" not in atlas.settings_key(PredictionSettings())["model"]
    assert "handover" not in atlas.settings_key(PredictionSettings(handover=False))["model"]
    assert atlas.settings_key(PredictionSettings())["model"]["handover"] is True
    braced = PredictionSettings(changes={"strength": {"ankle": 0.5}})
    assert "changes" in atlas.settings_key(braced)["model"]
    assert "changes" not in node_fields(braced.model)  # the body carries it into the cache key
