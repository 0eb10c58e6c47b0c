"""The model's settings: which problem is solved (criterion, physical assumptions and the form
of the constraints), each field with its :class:`Role`.

A field's role says whether it shapes the node functions (then it is part of the model-cache
key) and which value, if any, turns it off (then that value leaves it out of the model-cache and
atlas keys, which stay those of a walk3d before the setting existed). The keys are derived from
the roles (:func:`node_fields`, :func:`keyed_fields`), so a new setting needs no key edit.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from functools import cache
from typing import Annotated, Any, Literal, get_args

import numpy as np
from pydantic import BaseModel, ConfigDict, field_validator, model_validator

from walk3d.contact.free_split import MAX_TERMS
from walk3d.model import calibrated, terms
from walk3d.model.element import Element
from walk3d.model.tracking import Tracking
from walk3d.model.whatif import Changes

__all__ = ["ModelSettings", "Role", "SettingsGroup", "elements", "equal_steps_unused", "is_on",
           "keyed_fields", "node_fields", "opt_in", "role"]  # fmt: skip

_ALWAYS = object()


@dataclass(frozen=True)
class Role:
    """How a model setting reaches the problem. Settings that reach the node functions through
    the body (the roll-over, the what-if changes) are keyed by the body, not by ``nodes``."""

    nodes: bool
    """Whether it shapes the node functions (the model-cache key holds it)."""
    off: Any = _ALWAYS
    """The value that is the problem without it (left out of the keys), if there is one."""
    element: str | None = None
    """``"module:NAME"`` of the :class:`~walk3d.model.element.Element` it turns on while it is
    not at ``off`` (:func:`elements`), or None."""

    @property
    def opt_in(self) -> bool:
        """Whether the setting has an off value."""
        return self.off is not _ALWAYS


@cache
def _numeric(annotation: Any) -> bool:
    """Whether a field's type holds numbers (int or float, also inside tuples)."""
    return annotation in (int, float) or any(_numeric(a) for a in get_args(annotation))


@cache
def _textual(annotation: Any) -> bool:
    """Whether a field's type also holds text (str or a Literal of strings)."""
    if annotation is str or isinstance(annotation, str):
        return True
    return any(_textual(a) for a in get_args(annotation))


def _leaves(v: Any) -> list[Any]:
    """``v``'s values, through nested tuples and lists (a loop: any depth)."""
    out, todo = [], [v]
    while todo:
        x = todo.pop()
        if isinstance(x, (tuple, list)):
            todo.extend(x)
        else:
            out.append(x)
    return out


class SettingsGroup(BaseModel):
    """A frozen settings group: unknown fields refused, numbers finite and not bools."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    @field_validator("*", mode="before")
    @classmethod
    def _finite(cls, v, info):
        """Refuse, before pydantic converts, a non-finite float anywhere in a value, and a bool
        or text in a numeric setting (pydantic reads ``True`` as 1.0, and ``"1_0"`` as 10)."""
        name = info.field_name
        many = isinstance(v, (tuple, list))
        for x in _leaves(v):
            if isinstance(x, float | np.floating) and not math.isfinite(x):
                what = "hold finite numbers" if many else "be a finite number"
                raise ValueError(f"{name} must {what}, got {v!r:.60}")
            annotation = cls.model_fields[name].annotation
            if isinstance(x, bool | np.bool_) and _numeric(annotation):
                what = "hold numbers" if many else "be a number"
                raise ValueError(f"{name} must {what}, not a bool: {v!r:.60}")
            if isinstance(x, str | bytes) and _numeric(annotation) and not _textual(annotation):
                what = "hold numbers" if many else "be a number"
                raise ValueError(f"{name} must {what}, not text: {v!r:.60}")
        return v

    def _check(self, checks: list[tuple[bool, str]]) -> None:
        for ok, msg in checks:
            if not ok:
                raise ValueError(msg)


class ModelSettings(SettingsGroup):
    """Which problem is solved: the criterion, the physical assumptions and the form of the
    constraints. Lengths are at the reference stature (1.77 m) and scale with the subject's
    (:mod:`walk3d.problem.similarity`)."""

    criterion: Annotated[str, Role(nodes=True)] = "tor"
    """C_tor (normalized joint torque), C_en (mechanical energy), the paper's two, or a weighted
    criterion (:mod:`walk3d.model.terms`), stored in canonical form (presets expanded)."""
    friction: Annotated[float, Role(nodes=True)] = 0.8
    """Foot-floor friction coefficient for |Fx|/Fy and |Fz|/Fy (rubber sole on a lab floor)."""
    free_moment_radius: Annotated[float, Role(nodes=True)] = 0.02
    """Torsional radius of the sole, m: ``|free moment| ≤ friction × r × Fy``
    (:mod:`walk3d.contact.support`); 2 cm allows about 11 N·m at body weight."""
    cop_margin: Annotated[float, Role(nodes=True)] = 0.0
    """How far inside the heel and the toe the NLP keeps each foot's centre of pressure at its
    nodes, m. The cycle between the nodes is judged against the whole foot
    (:mod:`walk3d.results.violations`), so a margin leaves room for the motion between nodes."""
    swing_clearance: Annotated[float, Role(nodes=False)] = 0.0
    """Least height of the swing foot's heel, toe and metatarsal heads at the NLP's swing nodes,
    m (the floor is 0): room for the foot's path between nodes."""
    min_ankle_separation: Annotated[float, Role(nodes=False)] = 0.06
    """Least lateral distance between the ankle joint centres, m: the feet must not cross."""
    foot_flat_tolerance: Annotated[float, Role(nodes=False)] = math.radians(3.0)
    """Largest stance-foot rotation in single stance, rad. The paper asks for 0, which a
    5th-order Fourier series cannot hold over an interval; 3° is within the foot's sway."""
    absolute: Annotated[Literal["slack", "smooth"], Role(nodes=True)] = "slack"
    """The criterion's absolute values as exact slack variables (default) or as the smooth
    ``sqrt(x² + ε²)``, with which IPOPT did not converge (kept for the SLSQP baseline)."""
    smoothing: Annotated[float, Role(nodes=True)] = 1e-3
    """Relative width of the smooth |x| (:mod:`walk3d.model.criteria`)."""
    balance_split: Annotated[bool, Role(nodes=True)] = False
    """Whether the balance stage shares the reaction between the feet in double support as the
    full stage does. Off: it saved no time over the starts measured (docs/solver.md)."""
    arm_walking_ranges: Annotated[bool, Role(nodes=False)] = True
    """Narrow shoulder and elbow ranges to those of walking (:mod:`walk3d.model.ranges`)."""
    leg_walking_ranges: Annotated[bool, Role(nodes=False)] = True
    """Narrow the knee to flexion of at most 90° (:mod:`walk3d.model.ranges`): no kneeling
    or squatting postures."""
    rollover_s: Annotated[tuple[float, ...] | None, Role(nodes=False)] = None
    """Calibrated roll-over knots (``sin(θ/2)`` of the foot rotation; ``walk3d calibrate``).
    None: the default arc roll-over scaled by foot length."""
    rollover_ankle: Annotated[tuple[tuple[float, float, float], ...] | None, Role(nodes=False)] = (
        None
    )
    """Ankle displacement (m) at each calibrated roll-over knot."""
    transition_ratios: Annotated[tuple[float, float, float, float] | None, Role(nodes=False)] = None
    """Calibrated ``(μ_x, μ_z, ϖ_x, ϖ_y)`` of Eqs. 7–8 (right-foot signs). None: read at heel
    strike from the total reaction (:mod:`walk3d.contact.transition`)."""
    handover: Annotated[bool, Role(nodes=True, off=False)] = True
    """Whether the chain's root passes from the trailing to the leading foot over double support
    (:mod:`walk3d.model.state`), so that velocities are continuous at heel strike and OpenSim's
    inverse dynamics needs no residual force there (docs/opensim.md). On by default so results
    replay in OpenSim; T and Td are still predicted with the paper's switch at heel strike, on
    which the criterion's weights were tuned (:mod:`walk3d.solve.landing`)."""
    passive: Annotated[
        bool, Role(nodes=True, off=False, element="walk3d.model.passive:ELEMENT")
    ] = False
    """Passive joint moments, range stops and damping (:mod:`walk3d.model.passive`): C_tor and
    the effort see the active part. Off: the paper's joints; then left out of the model keys."""

    passive_total: Annotated[bool, Role(nodes=True, off=False)] = False
    """With ``passive``, add the whole joint's passive moment at the hip, knee and ankle
    (Anderson et al. 2007, :mod:`walk3d.model.passive`). Off: the range stops alone."""
    heel_rise: Annotated[float | None, Role(nodes=False, off=None)] = None
    """Fraction of the root foot's stance after which its heel may rise (the forefoot rocker):
    about 0.6 in people (heel-off at 61 % of stance, Chiu et al. 2013). None: flat in single
    stance, as the paper."""
    load_ramp: Annotated[float | None, Role(nodes=False, off=None)] = None
    """Initial slope ``s`` of the trailing foot's share ``(1 − x)²(1 + (2 − s)x)``, ``x`` = time
    since heel strike / Td (:mod:`walk3d.contact.phases`), in [0, 3]: the leading foot loads with
    a slope, as measured. None: the paper's ``exp(−(2x)³)``, which starts flat."""
    split_terms: Annotated[int, Role(nodes=True, off=0)] = 0
    """Free terms of the trailing foot's load in double support (:mod:`walk3d.contact.
    free_split`), chosen by the solver within each foot's contact rows; 0: the paper's
    prescribed split. 2 lowered the criterion by 20–30 % and the hip's error by half on the
    shared sources (docs/criteria.md)."""
    loop_tolerance: Annotated[float, Role(nodes=False, off=0.0)] = 0.0
    """How far the trailing foot may leave its roll-over pose in double support (m for the
    position, quaternion vector units, about rad / 2, for the orientation). 0: the paper's
    closed loop; above 0 only to see what the loop costs a tracking (``walk3d track --relax``)."""
    tracking: Annotated[Tracking | None, Role(nodes=False, off=None)] = None
    """A measured gait the ``track`` criterion term follows (:mod:`walk3d.model.tracking`,
    ``walk3d track``); None: none. It reaches the NLP's objective, not its node functions."""
    changes: Annotated[Changes, Role(nodes=False, off=Changes())] = Changes()
    """What-if changes to the body and joints (:mod:`walk3d.model.whatif`); none: normal."""
    full_cycle: Annotated[bool, Role(nodes=False, off=False)] = False
    """Solve the full cycle, each side with its own series (:mod:`walk3d.problem.full_cycle`),
    after the half cycle. Off: the paper's half cycle, unless a change is one-sided."""
    equal_steps: Annotated[bool, Role(nodes=False, off=False)] = False
    """Hold the full cycle's steps equal in length (off: the stride splits freely; what-if.md)."""

    @field_validator("criterion")
    @classmethod
    def _criterion(cls, v: str) -> str:
        return terms.canonical(v)

    @model_validator(mode="after")
    def _ranges(self) -> ModelSettings:
        self._check([
            (0 < self.friction <= 2, f"friction must be in (0, 2], got {self.friction}"),
            (0 <= self.cop_margin <= 0.05,
             f"cop_margin must be in [0, 0.05] m, got {self.cop_margin}"),
            (0 <= self.loop_tolerance <= 0.1,
             f"loop_tolerance must be in [0, 0.1], got {self.loop_tolerance}"),
            (0 <= self.swing_clearance <= 0.05,
             f"swing_clearance must be in [0, 0.05] m, got {self.swing_clearance}"),
            (0 <= self.free_moment_radius <= 0.1,
             f"free-moment radius must be in [0, 0.1] m, got {self.free_moment_radius}"),
            (0 < self.smoothing < 0.1, f"smoothing must be in (0, 0.1), got {self.smoothing}"),
            (self.passive or not self.passive_total, "passive_total needs passive on"),
            (self.heel_rise is None or 0.3 <= self.heel_rise <= 1,
             f"heel_rise must be in [0.3, 1] of stance, got {self.heel_rise}"),
            (self.load_ramp is None or 0 <= self.load_ramp <= 3,
             f"load_ramp must be in [0, 3], got {self.load_ramp}"),
            (0 <= self.split_terms <= MAX_TERMS,
             f"split_terms must be in [0, {MAX_TERMS}], got {self.split_terms}"),
            (not (self.split_terms and (self.full_cycle or self.changes.one_sided)),
             "split_terms is for the half cycle: not with full_cycle or a one-sided change"),
            ((self.rollover_s is None) == (self.rollover_ankle is None)
             and (self.rollover_s is None or len(self.rollover_s) == len(self.rollover_ankle)),
             "rollover_s and rollover_ankle go together, one ankle point per knot"),
            (not (calibration := calibrated.problem(self.rollover_s, self.rollover_ankle,
                                                    self.transition_ratios)),
             f"calibration: {calibration}"),
            ("track" not in terms.parse(self.criterion) or self.tracking is not None,
             "the criterion term track needs a measured gait to follow (walk3d track)"),
        ])  # fmt: skip
        return self


def role(model_cls: type[BaseModel], name: str) -> Role:
    """The :class:`Role` of field ``name`` of ``model_cls`` (a ModelSettings or a subclass).
    Raises TypeError for a field declared without one: every model setting states its role."""
    found = [m for m in model_cls.model_fields[name].metadata if isinstance(m, Role)]
    if len(found) != 1:
        raise TypeError(f"model setting {name!r} declares no Role (walk3d.model.settings)")
    return found[0]


def _is_off(value: Any, r: Role) -> bool:
    off = r.off
    return r.opt_in and (value is off or type(value) is type(off) and value == off)


def is_on(model: BaseModel, name: str) -> bool:
    """Whether setting ``name`` of ``model`` is not at its off value (always, without one)."""
    return not _is_off(getattr(model, name), role(type(model), name))


def elements(model: BaseModel) -> list[Element]:
    """The elements the settings of ``model`` turn on, in field order (:class:`Role`)."""
    out = []
    for name in type(model).model_fields:
        r = role(type(model), name)
        if r.element and is_on(model, name):
            out.append(_element(r.element))
    return out


@cache
def _element(path: str) -> Element:
    module, _, attr = path.partition(":")
    found = getattr(importlib.import_module(module), attr)
    if not isinstance(found, Element):
        raise TypeError(f"{path} is not a walk3d.model.element.Element")
    return found


def opt_in(model_cls: type[BaseModel] | None = None) -> dict[str, Any]:
    """``{name: off value}`` of the settings that have one (``model_cls``: ModelSettings)."""
    cls = model_cls or ModelSettings
    roles = {n: role(cls, n) for n in cls.model_fields}
    return {n: r.off for n, r in roles.items() if r.opt_in}


def keyed_fields(model: BaseModel, mode: str = "python") -> dict[str, Any]:
    """Every setting of ``model`` but those at their off value: what an atlas entry depends on
    (``mode`` as pydantic's ``model_dump``)."""
    values = model.model_dump(mode=mode)
    cls = type(model)
    return {n: v for n, v in values.items() if not _is_off(getattr(model, n), role(cls, n))}


def node_fields(model: BaseModel) -> dict[str, Any]:
    """The settings that shape the node functions, less those at their off value, plus the
    formulas of any user-registered criterion terms: the model-cache key's settings."""
    cls = type(model)
    out = {n: v for n, v in keyed_fields(model).items() if role(cls, n).nodes}
    user = terms.fingerprint(model.criterion)
    return out | ({"criterion_terms": user} if user else {})


def equal_steps_unused(model: ModelSettings) -> bool:
    """Whether ``equal_steps`` is set where it does nothing: without ``full_cycle`` or a
    one-sided change the prediction solves the half cycle, one step mirrored, whose two steps
    are equal already. Not a settings error, so that results recorded with it still load."""
    return model.equal_steps and not (model.full_cycle or model.changes.one_sided)
