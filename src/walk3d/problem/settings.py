"""Validated prediction settings in three immutable groups (SI units; the CLI converts names).

* :class:`GaitSettings`: the walker and the walk (V, T, Td, mass, stature, sex);
* :class:`ModelSettings`: which problem is solved (criterion, physical assumptions, and how the
  constraints are stated). With the body it is all that shapes the model's node functions, so
  the model cache key is made of it (:mod:`walk3d.solve.solver`);
* :class:`SolverSettings`: how the problem is solved (grid and the rows stated between its
  nodes, stages, iteration limits, tolerances, threads, linear solver, starts).

:class:`PredictionSettings` holds the three. It also takes the fields flat
(``PredictionSettings(speed=1.2, nodes=12)``), each routed to its group, which is how
``summary.json`` files written before the groups existed still load. The evidence for the
defaults is in docs/solver.md.
"""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, ValidationError, field_validator, model_validator

from walk3d.problem import descriptors, terms
from walk3d.problem.setup import available_cores, body_for, ratios_for
from walk3d.problem.whatif import Changes

__all__ = ["GaitSettings", "ModelSettings", "PredictionSettings", "SolverSettings",
           "available_cores", "body_for", "first_error", "flat_settings", "ratios_for",
           "recorded_settings"]  # fmt: skip


class _Group(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")

    @field_validator("*", mode="before")
    @classmethod
    def _finite(cls, v, info):
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"{info.field_name} must be a finite number, got {v}")
        return v

    def _check(self, checks: list[tuple[bool, str]]) -> None:
        for ok, msg in checks:
            if not ok:
                raise ValueError(msg)


class GaitSettings(_Group):
    """The walker and the walk. Defaults: the paper's subject and descriptors."""

    speed: float = 1.3806
    """Walking speed V, m/s."""
    period: float = 1.08
    """Gait-cycle period T, s."""
    double_support: float = 0.16
    """Duration of one double-support phase Td, s."""
    mass: float = 68.8
    """Body mass, kg."""
    height: float = 1.77
    """Stature, m."""
    sex: Literal["male", "female"] = "male"
    """Which de Leva (1996) table scales the segments."""
    free: tuple[Literal["period", "double_support"], ...] = ()
    """Descriptors predicted with the gait (:mod:`walk3d.problem.descriptors`); their values
    above are then the first guess. Empty: T and Td are given, the paper's problem."""

    @model_validator(mode="after")
    def _ranges(self) -> GaitSettings:
        self._check([
            (0 < self.speed <= 4.0, f"speed must be in (0, 4] m/s, got {self.speed}"),
            *descriptors.given_checks(self.period, self.double_support),
            (20 <= self.mass <= 250, f"body mass must be in [20, 250] kg, got {self.mass}"),
            (1.0 <= self.height <= 2.4, f"height must be in [1.0, 2.4] m, got {self.height}"),
            (len(set(self.free)) == len(self.free), f"free descriptors repeat: {self.free}"),
        ])  # fmt: skip
        return self

    @property
    def stride_length(self) -> float:
        """V·T, m."""
        return self.speed * self.period


class ModelSettings(_Group):
    """Which problem is solved: the criterion, the physical assumptions and the form of the
    constraints. Lengths are at the reference stature (1.77 m) and scale with the subject's
    (:mod:`walk3d.problem.similarity`)."""

    criterion: str = "tor"
    """C_tor (normalized joint torque), C_en (mechanical energy), the paper's two, or a weighted
    criterion (:mod:`walk3d.problem.terms`), stored in canonical form (presets expanded)."""
    friction: float = 0.8
    """Foot-floor friction coefficient for |Fx|/Fy and |Fz|/Fy (rubber sole on a lab floor)."""
    free_moment_radius: float = 0.02
    """Torsional radius of the sole, m: ``|free moment| ≤ friction × r × Fy``
    (:mod:`walk3d.contact.support`); 2 cm allows about 11 N·m at body weight."""
    cop_margin: float = 0.0
    """How far inside the heel and the toe the NLP keeps each foot's centre of pressure at its
    nodes, m. The cycle between the nodes is judged against the whole foot
    (:mod:`walk3d.results.violations`), so a margin leaves room for the motion between nodes."""
    swing_clearance: float = 0.0
    """Least height of the swing foot's heel, toe and metatarsal heads at the NLP's swing nodes,
    m (the floor is 0): room for the foot's path between nodes."""
    min_ankle_separation: float = 0.06
    """Least lateral distance between the ankle joint centres, m: the feet must not cross."""
    foot_flat_tolerance: float = math.radians(3.0)
    """Largest stance-foot rotation in single stance, rad. The paper asks for 0, which a
    5th-order Fourier series cannot hold over an interval; 3° is within the foot's sway."""
    absolute: Literal["slack", "smooth"] = "slack"
    """The criterion's absolute values as exact slack variables (default) or as the smooth
    ``sqrt(x² + ε²)``, with which IPOPT did not converge (kept for the SLSQP baseline)."""
    smoothing: float = 1e-3
    """Relative width of the smooth |x| (:mod:`walk3d.problem.criteria`)."""
    balance_split: bool = False
    """Whether the balance stage shares the reaction between the feet in double support as the
    full stage does. Off: it saved no time over the starts measured (docs/solver.md)."""
    arm_walking_ranges: bool = True
    """Narrow shoulder and elbow ranges to those of walking (:mod:`walk3d.problem.ranges`)."""
    leg_walking_ranges: bool = True
    """Narrow the knee to flexion of at most 90° (:mod:`walk3d.problem.ranges`): no kneeling
    or squatting postures."""
    rollover_s: tuple[float, ...] | None = None
    """Calibrated roll-over knots (``sin(θ/2)`` of the foot rotation; ``walk3d calibrate``).
    None: the default arc roll-over scaled by foot length."""
    rollover_ankle: tuple[tuple[float, float, float], ...] | None = None
    """Ankle displacement (m) at each calibrated roll-over knot."""
    transition_ratios: tuple[float, float, float, float] | None = None
    """Calibrated ``(μ_x, μ_z, ϖ_x, ϖ_y)`` of Eqs. 7–8 (right-foot signs). None: read at heel
    strike from the total reaction (:mod:`walk3d.contact.transition`)."""
    handover: bool = True
    """Whether the chain's root passes from the trailing to the leading foot over double support
    (:mod:`walk3d.problem.gait`), so that velocities are continuous at heel strike and OpenSim's
    inverse dynamics needs no residual force there (docs/opensim.md). On by default so results
    replay in OpenSim; T and Td are still predicted with the paper's switch at heel strike, on
    which the criterion's weights were tuned (:mod:`walk3d.solve.landing`)."""
    passive: bool = False
    """Passive joint moments, range stops and damping (:mod:`walk3d.problem.passive`): C_tor and
    the effort see the active part. Off: the paper's joints; then left out of the model keys."""

    passive_total: bool = False
    """With ``passive``, add the whole joint's passive moment at the hip, knee and ankle
    (Anderson et al. 2007, :mod:`walk3d.problem.passive`). Off: the range stops alone."""
    heel_rise: float | None = None
    """Fraction of the root foot's stance after which its heel may rise (the forefoot rocker):
    about 0.6 in people (heel-off at 61 % of stance, Chiu et al. 2013). None: flat in single
    stance, as the paper."""
    load_ramp: float | None = None
    """Initial slope ``s`` of the trailing foot's share ``(1 − x)²(1 + (2 − s)x)``, ``x`` = time
    since heel strike / Td (:mod:`walk3d.contact.phases`), in [0, 3]: the leading foot loads with
    a slope, as measured. None: the paper's ``exp(−(2x)³)``, which starts flat."""
    changes: Changes = Changes()
    """What-if changes to the body and joints (:mod:`walk3d.problem.whatif`); none: normal."""
    full_cycle: bool = False
    """Solve the full cycle, each side with its own series (:mod:`walk3d.problem.full_cycle`),
    after the half cycle. Off: the paper's half cycle, unless a change is one-sided."""
    equal_steps: bool = False
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
            ((self.rollover_s is None) == (self.rollover_ankle is None)
             and (self.rollover_s is None or len(self.rollover_s) == len(self.rollover_ankle)),
             "rollover_s and rollover_ankle go together, one ankle point per knot"),
        ])  # fmt: skip
        return self


class SolverSettings(_Group):
    """How the problem is solved. The stages and their order are :mod:`walk3d.solve.plan`'s;
    docs/solver.md has the measurements behind each default."""

    nodes: int = 20
    """Time nodes per half cycle; by symmetry the criteria integrate over ``2 * nodes``."""
    heel_strike_nodes: int = 0
    """Extra nodes inside the first interval after heel strike (:mod:`walk3d.problem.schedule`
    says why), where the leading foot's load starts."""
    derivatives: Literal["structured", "casadi"] = "structured"
    """Exact derivatives assembled from per-node blocks (:mod:`walk3d.problem.derivatives`,
    several times cheaper) or CasADi's sweeps through the whole NLP (same values)."""
    range_oversampling: int = 0
    """Extra joint-range rows on a grid this many times finer than the nodes (0: off; 4 made
    the first stage locally infeasible, docs/solver.md)."""
    loop_checks: int = 0
    """Extra closed-loop checks between consecutive double-support nodes (position level).
    Off: one check per interval kept the posture stage from converging (docs/solver.md)."""
    loop_check_toe_off: bool = True
    """Also check the closed loop at the trailing foot's toe-off, which falls between nodes;
    without it the trailing foot left its roll-over path by up to 10 mm there."""
    loop_check_tolerance: float = 1e-3
    """Half-width of the loop-check rows (m for position; quaternion vector units, 1e-3 ≈
    0.1°, for orientation). Inequalities: stated exactly they made IPOPT stall."""
    posture_stage: Literal["fallback", "first", "off"] = "fallback"
    """When the geometry-only posture stage runs: ``fallback`` (only when the balance stage
    from standing, or the full stage after it, has not converged), ``first`` or ``off``."""
    balance_max_iter: int = 250
    """Iteration limit of the balance stage from standing, before the posture fallback."""
    posture_balance_max_iter: int = 150
    """Iteration limit of the balance stage after the posture stage (at most ``max_iter``): the
    stages that converged did so well within it."""
    balance_progress_check: tuple[tuple[int, float], ...] | None = ((60, 3.0), (80, 0.1))
    """``((iteration, violation), ...)``: the balance stage from standing stops (and the
    fallback runs) if at one of these iterations its largest violation is above the value; no
    stage that converged was ever above them. None: only ``balance_max_iter`` stops it."""
    full_max_iter: int = 400
    """Iteration limit of the full stage (at most ``max_iter``); converged full stages took
    at most 230."""
    max_iter: int = 800
    """Iteration limit of every other stage."""
    tol: float = 1e-6
    """IPOPT's convergence tolerance."""
    threads: int = 1
    """Threads evaluating the node functions (CasADi ``map``); same iterates for any count.
    Campaigns run one process per core; ``walk3d predict`` uses every core."""
    linear_solver: Literal["mumps", "ma27", "ma57", "ma77", "ma86", "ma97"] = "mumps"
    """IPOPT's sparse solver: MUMPS ships with CasADi; an HSL one needs ``hsl_library``."""
    hsl_library: str | None = None
    """Path of the HSL library (``libhsl.so`` or ``libcoinhsl.so``); None: IPOPT's default
    name on the library path."""
    start: Literal["atlas", "standing"] = "atlas"
    """Where the solve starts: ``atlas``, walk3d's own solved neighbour, then the full problem
    alone (:mod:`walk3d.solve.starts`; standing when the atlas has no entry or it fails), or
    ``standing``, the paper's method: upright standing plus noise, through the stages."""
    descriptors_from: Literal["atlas", "solve"] = "atlas"
    """How a handover prediction gets predicted T and Td: ``atlas``, blended from the atlas's
    free-landing optima, then one solve; ``solve``: the free-landing solve first, then the
    handover at its T and Td (docs/descriptors.md). Without an atlas entry: ``solve``."""
    perturbation: float = 0.05
    """Amplitude of the uniform noise on the start's free coefficients (the paper does not give
    it; an atlas start adds a fifth of it, and none for seed 0). 0.1 led more standing starts
    to walking optima, but not the default seed's (docs/solver.md)."""
    restarts: int = 1
    """How often a start that did not converge is tried again from a new standing start (the
    seed's next noise stream). 0: one try, as in the paper."""
    reject_crouch: bool = True
    """Treat a converged full stage that flexes the hip more than 27° on average in mid-stance
    (a crouched local optimum, :mod:`walk3d.solve.upright`) as not converged while a retry or
    restart is left, so that the start is tried again. The last try's optimum is kept whatever its
    posture, and labelled by ``gait_checks``."""

    @field_validator("balance_progress_check", mode="before")
    @classmethod
    def _check_pairs(cls, v):
        """A single ``(iteration, violation)`` pair stands for a one-check tuple."""
        if v is not None and len(v) == 2 and not isinstance(v[0], (tuple, list)):
            return (tuple(v),)
        return v

    @model_validator(mode="after")
    def _ranges(self) -> SolverSettings:
        limits = (self.max_iter, self.balance_max_iter, self.posture_balance_max_iter,
                  self.full_max_iter)  # fmt: skip
        self._check([
            (6 <= self.nodes <= 200, f"nodes must be in [6, 200], got {self.nodes}"),
            (0 <= self.heel_strike_nodes <= 8,
             f"heel_strike_nodes must be in [0, 8], got {self.heel_strike_nodes}"),
            (0 <= self.loop_checks <= 4, f"loop checks must be in [0, 4], got {self.loop_checks}"),
            (0 < self.loop_check_tolerance <= 0.05,
             f"loop check tolerance must be in (0, 0.05], got {self.loop_check_tolerance}"),
            (1 <= self.threads <= 64, f"threads must be in [1, 64], got {self.threads}"),
            (0 <= self.perturbation <= 0.5,
             f"perturbation must be in [0, 0.5], got {self.perturbation}"),
            (0 <= self.restarts <= 10,
             f"restarts must be an integer in [0, 10], got {self.restarts}"),
            (min(limits) >= 1,
             f"iteration limits must be >= 1, got max_iter {self.max_iter}, balance_max_iter "
             f"{self.balance_max_iter}, posture_balance_max_iter "
             f"{self.posture_balance_max_iter}, full_max_iter {self.full_max_iter}"),
            (self.balance_progress_check is None
             or all(it >= 1 and viol > 0 for it, viol in self.balance_progress_check),
             "balance progress check must be pairs (iteration >= 1, violation > 0) or None, "
             f"got {self.balance_progress_check}"),
        ])  # fmt: skip
        return self

    def progress_checks(self) -> dict[int, float]:
        """``balance_progress_check`` as {iteration: violation} (empty when None)."""
        checks = self.balance_progress_check
        return {} if checks is None else dict(self._check_pairs(checks))


OPT_IN: dict[str, Any] = {"passive": False, "passive_total": False, "heel_rise": None,
                          "load_ramp": None, "changes": Changes(), "full_cycle": False,
                          "equal_steps": False}  # fmt: skip
"""Model settings whose value here leaves them out of the model-cache and atlas keys: the
problem of a walk3d before they existed."""
GROUPS: dict[str, type[_Group]] = {
    "gait": GaitSettings,
    "model": ModelSettings,
    "solver": SolverSettings,
}
"""The groups of :class:`PredictionSettings`, by field name."""
FIELD_GROUP: dict[str, str] = {f: g for g, cls in GROUPS.items() for f in cls.model_fields}
"""Each setting's group, read off the groups' fields."""


def grouped(values: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """``values`` with flat settings moved into their groups (group dicts are merged, flat
    keys last). Raises ValueError naming an unknown key."""
    out: dict[str, dict[str, Any]] = {g: {} for g in GROUPS}
    for key, value in values.items():
        if key in GROUPS:
            if isinstance(value, BaseModel):
                value = value.model_dump()
            if not isinstance(value, dict):
                raise ValueError(f"{key} must be a mapping of settings, got {value!r}")
            out[key].update(value)
    for key, value in values.items():
        if key in GROUPS:
            continue
        if key not in FIELD_GROUP:
            raise ValueError(f"unknown setting {key!r}")
        out[FIELD_GROUP[key]][key] = value
    return out


class PredictionSettings(BaseModel):
    """Inputs of one prediction: :class:`GaitSettings`, :class:`ModelSettings` and
    :class:`SolverSettings`. Defaults: the paper's subject, descriptors and C_tor."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    gait: GaitSettings = GaitSettings()
    model: ModelSettings = ModelSettings()
    solver: SolverSettings = SolverSettings()

    def __init__(self, /, **data: Any) -> None:
        try:
            super().__init__(**data)
        except ValidationError as exc:  # one line (first_error), never pydantic's own
            raise ValueError(first_error(exc)) from None

    @model_validator(mode="before")
    @classmethod
    def _route_flat(cls, data: Any) -> Any:
        return grouped(data) if isinstance(data, dict) else data

    def replace(self, **changes: Any) -> PredictionSettings:
        """A validated copy with ``changes`` (flat settings, or group mappings) applied."""
        merged = self.model_dump()
        for group, values in grouped(changes).items():
            merged[group].update(values)
        return PredictionSettings(**merged)

    def flat(self) -> dict[str, Any]:
        """Every setting by its own name, groups dissolved."""
        return flat_settings(self.model_dump())


def flat_settings(values: dict[str, Any]) -> dict[str, Any]:
    """Settings by their own names from a grouped or a flat mapping (as any walk3d stored)."""
    out: dict[str, Any] = {}
    for key, value in values.items():
        if key in GROUPS and isinstance(value, dict):
            out.update(value)
        else:
            out[key] = value
    return out


def recorded_settings(summary: dict[str, Any]) -> dict[str, Any]:
    """The flat settings a ``summary.json`` dict records: its grouped ``settings``, or the
    flat ``inputs`` of a walk3d before the groups (less their ``seed`` and ``solver``, which
    are not settings); {} when it records none."""
    grouped_ = summary.get("settings")
    if isinstance(grouped_, dict):
        return flat_settings(grouped_)
    inputs = summary.get("inputs")
    if isinstance(inputs, dict):
        return {k: v for k, v in inputs.items() if k not in ("seed", "solver")}
    return {}


def first_error(exc: Exception) -> str:
    """One-line message from a pydantic ValidationError (or any exception)."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        e = errors()[0]
        msg = str(e.get("msg", exc)).removeprefix("Value error, ")
        loc = ".".join(str(p) for p in e.get("loc", ()) if p not in GROUPS)
        return msg if not loc or loc in msg else f"{loc}: {msg}"
    return " ".join(str(exc).split())
