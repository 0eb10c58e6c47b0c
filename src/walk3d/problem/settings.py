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

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, ValidationError, field_validator, model_validator

from walk3d.model.settings import ModelSettings, SettingsGroup
from walk3d.model.subject import body_for, ratios_for
from walk3d.problem import descriptors

__all__ = ["GaitSettings", "ModelSettings", "PredictionSettings", "SolverSettings",
           "available_cores", "body_for", "first_error", "flat_settings", "ratios_for",
           "recorded_settings"]  # fmt: skip


def available_cores() -> int:
    """CPU cores this process may run on (its affinity mask where the OS has one)."""
    import os

    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # macOS, Windows
        return max(1, os.cpu_count() or 1)


class GaitSettings(SettingsGroup):
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


class SolverSettings(SettingsGroup):
    """How the problem is solved. The stages and their order are :mod:`walk3d.solve.plan`'s;
    docs/solver.md has the measurements behind each default."""

    nodes: int = 20
    """Time nodes per half cycle; by symmetry the criteria integrate over ``2 * nodes``."""
    grid: Literal["regular", "phase"] = "regular"
    """The nodes of a given T and Td: ``regular``, the paper's ``k T / (2N)``, or ``phase``,
    the grid of a predicted T and Td (:mod:`walk3d.problem.descriptors`), whose nodes keep
    their place in the phases for any T and Td and one of which sits at toe off."""
    heel_strike_nodes: int = 0
    """Extra nodes inside the first interval after heel strike (:mod:`walk3d.problem.schedule`
    says why), where the leading foot's load starts."""
    contact_checks: int = 0
    """Instants inside each double-support interval at which the node rows hold too, as
    nodes of zero weight (:mod:`walk3d.problem.schedule` says why)."""
    swing_checks: int = 0
    """Instants inside each swing interval at which the node rows hold too, as nodes of zero
    weight: the swing foot stays above the floor between its nodes."""
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
            (not (self.heel_strike_nodes and self.grid == "phase"),
             "heel_strike_nodes need the regular grid (grid = 'regular')"),
            (0 <= self.loop_checks <= 4, f"loop checks must be in [0, 4], got {self.loop_checks}"),
            (0 <= self.contact_checks <= 4,
             f"contact checks must be in [0, 4], got {self.contact_checks}"),
            (0 <= self.swing_checks <= 4,
             f"swing checks must be in [0, 4], got {self.swing_checks}"),
            (not (self.contact_checks and self.loop_checks),
             "contact checks hold the loop between the nodes too: set loop checks to 0"),
            (0 < self.loop_check_tolerance <= 0.05,
             f"loop check tolerance must be in (0, 0.05], got {self.loop_check_tolerance}"),
            (1 <= self.threads <= 64, f"threads must be in [1, 64], got {self.threads}"),
            (self.hsl_library is None or self.linear_solver != "mumps",
             "hsl_library is the library of an HSL linear_solver (ma27, ma57, ma77, ma86, ma97); "
             "mumps, the default, needs none"),
            (1e-12 <= self.tol <= 1e-2, f"tol must be in [1e-12, 0.01], got {self.tol}"),
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


GROUPS: dict[str, type[SettingsGroup]] = {
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
    are not settings); {} when it records none. An ``hsl_library`` beside MUMPS, which an
    earlier walk3d took and ignored, is read as None."""
    grouped_ = summary.get("settings")
    inputs = summary.get("inputs")
    if isinstance(grouped_, dict):
        flat = flat_settings(grouped_)
    elif isinstance(inputs, dict):
        flat = {k: v for k, v in inputs.items() if k not in ("seed", "solver")}
    else:
        return {}
    if flat.get("linear_solver", "mumps") == "mumps" and flat.get("hsl_library") is not None:
        flat["hsl_library"] = None  # recorded, though MUMPS ignored it
    return flat


def first_error(exc: Exception) -> str:
    """One-line message from a pydantic ValidationError (or any exception)."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        e = errors()[0]
        msg = str(e.get("msg", exc)).removeprefix("Value error, ")
        loc = ".".join(str(p) for p in e.get("loc", ()) if p not in GROUPS)
        return msg if not loc or loc in msg else f"{loc}: {msg}"
    return " ".join(str(exc).split())
