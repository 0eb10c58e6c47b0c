"""Validated prediction settings (SI units; the CLI converts nothing but names)."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, field_validator, model_validator


class PredictionSettings(BaseModel):
    """Inputs of one prediction. Defaults: the paper's subject, descriptors and C_tor.

    ``nodes`` counts time nodes per half cycle: left/right symmetry means the other half is the
    mirror image, so the criteria integrate over ``2 * nodes`` equally spaced instants.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    speed: float = 1.3806
    """Walking speed V, m/s."""
    period: float = 1.08
    """Gait-cycle period T, s."""
    double_support: float = 0.16
    """Duration of one double-support phase Td, s."""
    mass: float = 68.8
    height: float = 1.77
    sex: Literal["male", "female"] = "male"
    criterion: Literal["tor", "en"] = "tor"
    nodes: int = 20
    friction: float = 0.8
    """Foot-floor friction coefficient for |Fx|/Fy and |Fz|/Fy (rubber sole on a lab floor)."""
    free_moment_radius: float = 0.02
    """Effective torsional radius of the shoe sole, m: ``|free moment| ≤ friction × r × Fy``
    (see :mod:`walk3d.contact.support`; 2 cm allows ~11 N·m at body weight). At the reference
    stature (1.77 m); it scales with stature, like the foot (:mod:`walk3d.problem.similarity`)."""
    min_ankle_separation: float = 0.06
    """Minimum lateral distance between the ankle joint centres, m (feet must not cross). At the
    reference stature (1.77 m); it scales with stature, like the hips."""
    foot_flat_tolerance: float = math.radians(3.0)
    """Largest stance-foot rotation allowed in single stance, rad. The paper asks for exactly 0,
    which a 5th-order Fourier series cannot hold over a whole interval without vanishing
    everywhere; 3° is within the foot's measured sway in mid-stance."""
    absolute: Literal["slack", "smooth"] = "slack"
    """How the solver sees the criterion's absolute values: exact slack variables (default) or
    the smooth ``sqrt(x² + ε²)`` (kept for comparison; it did not converge, docs/solver.md)."""
    derivatives: Literal["structured", "casadi"] = "structured"
    """How the solver gets exact derivatives: assembled from per-node Jacobians and Hessians
    (``structured``, :mod:`walk3d.problem.derivatives`) or CasADi's sweeps through the whole
    problem (``casadi``). Same values; the structured ones are several times cheaper."""
    smoothing: float = 1e-3
    """Relative width of the smooth |x| used by the solver (see :mod:`walk3d.problem.criteria`)."""
    range_oversampling: int = 0
    """Extra linear joint-range rows on a grid this many times finer than the nodes (0: off)."""
    posture_stage: Literal["fallback", "first", "off"] = "fallback"
    """When the geometry-only posture stage runs. ``fallback`` (default): the balance stage
    starts from standing, and only if it has not converged within ``balance_max_iter``
    iterations, or if the full stage after it has not converged, does the solve restart from
    standing through the posture stage. ``first``: always posture, then balance. ``off``: never.
    From the fallback the paper's subject mostly ended in a crouched optimum (seeds 1–4, 6, 7),
    while the Falisse descriptors walked. The retry after a failed full stage rescued seed 15 of
    the benchmark (direct path: 800 iterations without converging; retry: converged in 48 s),
    docs/solver.md."""
    balance_max_iter: int = 250
    """Iteration limit of the balance stage started straight from standing before the posture
    fallback (it converged in 102–285 iterations when it converged; 600 did not lead more
    starts to walking)."""
    posture_balance_max_iter: int = 150
    """Iteration limit of the balance stage that follows the posture stage (with ``posture_stage =
    "off"``: of the only balance stage), at most ``max_iter``. Where it stops without converging,
    the attempt ends and the start restarts (``restarts``); only on the last attempt does the full
    stage start from where it stopped. Why 150: over seeds 0-39 (session 13) this stage converged
    37 times, in 39-121 iterations, and the 8 stages that did not converge by 121 did not converge
    by 250 either (violation still 0.02-0.34 at iteration 100, or oscillating); 250 cost those
    starts 100 more iterations (about 12 s) each before the restart. In session 8, with the knee's
    walking range, it converged in 42-88 iterations on 16 of 18 starts (docs/solver.md)."""
    balance_progress_check: tuple[tuple[int, float], ...] | None = ((60, 3.0), (80, 0.1))
    """``((iteration, violation), ...)``: the balance stage started straight from standing is
    stopped (and the posture fallback taken) if at one of these iterations its largest constraint
    violation is still above the paired value. None: only ``balance_max_iter`` stops it. A single
    pair is accepted too. Why: this stage converges on few starts (3 of 48 runs over seeds 0-39),
    and the others spent 80 iterations (about 7 s) here before the fallback, which starts again
    from the same standing start, so stopping them earlier changes no path. At iteration 80 the
    stages that converged were at 8e-5-0.03 and the others at 0.4-26 (session 6, and again in
    session 13). At 60 the groups overlap below 2 (converging: up to 1.61 at V = 1.0 m/s, T =
    1.18 s, Td = 0.20 s and 1.8 in session 7; not converging: from 0.5), so the check at 60 only
    stops stages still above 3.0, which no converging stage has been: 40 of the 45 failing stages
    of seeds 0-39, 20 iterations (about 2 s) each (docs/solver.md, "Session 13")."""
    balance_split: bool = False
    """The balance stage shares the total ground reaction between the feet in double support as
    the full stage does (transition function and heel-strike wrench, no joint moments needed)
    and bounds each foot's load under that foot. Off by default: the full stage then starts
    outside its per-foot rows (seed 0: twelve centre-of-pressure and friction rows of the root
    foot in double support, violated by up to 0.52) and restores them in its first ~20
    iterations. On, seeds 0-11: full stages of 45-89 iterations instead of 70-110, but longer
    balance stages, seed 0's balance stage from standing no longer converges (it ends crouched)
    and seed 1 fails; no time gained (docs/solver.md, "Session 9")."""
    arm_walking_ranges: bool = True
    """Narrow shoulder and elbow ranges to those of walking (walk3d.problem.ranges)."""
    leg_walking_ranges: bool = True
    """Narrow the knee range to that of walking, flexion up to 90° (walk3d.problem.ranges):
    it rules out the kneeling and squatting postures that made the slow tail of the solves."""
    threads: int = 1
    """Threads evaluating the node functions and their derivatives (CasADi ``map``). Campaigns
    already use one process per core; ``walk3d predict`` uses every core
    (:func:`available_cores`). Same iterates for any count; seed 0 of the defaults took 100.4 s
    with 1 thread and 77.9 s with 2 on this 2-core machine (231 iterations each)."""
    loop_checks: int = 0
    """Extra closed-loop checks between consecutive double-support nodes (position level).
    Off by default: with one check per interval the posture stage hit its iteration limit
    (800) where it converges in 62 iterations without (docs/solver.md)."""
    loop_check_toe_off: bool = True
    """Also check the closed loop at the trailing foot's toe-off. The last double-support node
    falls up to one node step before toe-off, and without this check the trailing foot left
    its roll-over path by up to 10 mm in that gap (20 nodes, seed 0)."""
    loop_check_tolerance: float = 1e-3
    """Half-width of the loop-check rows (m for position at the reference stature, scaling with
    stature like ``free_moment_radius``; quaternion vector units for orientation; 1e-3 ≈ 0.1°).
    Inequalities, not equalities: stated exactly, these rows nearly repeat the node rows and made
    IPOPT stall."""
    rollover_s: tuple[float, ...] | None = None
    """Calibrated roll-over knots (``sin(θ/2)`` of the foot rotation; ``walk3d calibrate``).
    None: the default arc roll-over scaled by foot length."""
    rollover_ankle: tuple[tuple[float, float, float], ...] | None = None
    """Ankle displacement (m) at each calibrated roll-over knot."""
    transition_ratios: tuple[float, float, float, float] | None = None
    """Calibrated ``(μ_x, μ_z, ϖ_x, ϖ_y)`` of Eqs. 7–8 (right-foot signs). None: read at heel
    strike from the total reaction (:mod:`walk3d.contact.transition`)."""
    perturbation: float = 0.05
    """Amplitude of the uniform random perturbation of the standing initial guess (each free
    Fourier coefficient of the quaternion elements, ``sin(θ/2)``). The paper does not give it.
    On seeds 0-19, 0.1 led 10 starts to walking optima (7 to C_tor 1.78, 3 to 2.80) and 19
    converged, against 8 (7 and 1) and 18 with 0.05, at about the same time per start; but seed
    0, the default prediction, then reaches the 2.80 optimum instead of 1.78, so the default stays
    0.05 (docs/solver.md, "Session 9")."""
    restarts: int = 1
    """How often a start whose final stage did not converge is tried again, each time from a new
    standing start (the seed's next independent noise stream, so still reproducible from the seed;
    :func:`walk3d.solve.ipopt.initial_guess`). 0: one try, as in the paper. While a restart is left,
    a balance stage that did not converge also ends its attempt, without the full stage that seldom
    converged after it; so a start's result can depend on this setting (the same settings always
    give the same result). Measured (session 10): seeds 11 and 17 of the defaults, the benchmark's
    two failures, converged on their second attempt (C_tor 6.87 and the walking 1.777; 180 and 190 s
    with one thread), and so did seed 0 at V = 1.4 m/s, T = 1.2 s, Td = 0.18 s (4.52, 145 s); seed 0
    at V = 0.8 m/s, T = 1.25 s, Td = 0.25 s failed both attempts (226 s)."""
    linear_solver: Literal["mumps", "ma27", "ma57", "ma77", "ma86", "ma97"] = "mumps"
    """IPOPT's sparse symmetric indefinite solver for its Newton systems. MUMPS ships inside
    CasADi's wheel and is what every figure in docs/solver.md used: it is 56-62 % of a stage's
    time here. The HSL solvers are IPOPT's usual faster choice but are not
    redistributable: they need an HSL library the user obtains (free for academic use), found
    on the library path or at ``hsl_library``. Not measured on this machine (none available)."""
    hsl_library: str | None = None
    """Path of the HSL shared library (``libhsl.so`` or ``libcoinhsl.so``) for an HSL
    ``linear_solver``; None: IPOPT's default name on the library path."""
    max_iter: int = 800
    full_max_iter: int = 400
    """Iteration limit of the full stage, at most ``max_iter``. With the knee's walking range
    every full stage that converged did so within 230 iterations (seeds 0-19 in session 8's
    benchmark and sweeps, seeds 0-9 again in session 9), most within 110; the two that failed
    wandered to 800 and 574 (about 100 s each) without converging. A full stage on the direct
    path that stops here is retried through the posture stage (``posture_stage``)
    (docs/solver.md, "Session 9")."""
    tol: float = 1e-6

    @field_validator("*", mode="before")
    @classmethod
    def _finite(cls, v, info):
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"{info.field_name} must be a finite number, got {v}")
        return v

    @field_validator("balance_progress_check", mode="before")
    @classmethod
    def _check_pairs(cls, v):
        """A single ``(iteration, violation)`` pair stands for a one-check tuple."""
        if v is not None and len(v) == 2 and not isinstance(v[0], (tuple, list)):
            return (tuple(v),)
        return v

    @model_validator(mode="after")
    def _ranges(self) -> PredictionSettings:
        checks = [
            (0 < self.speed <= 4.0, f"speed must be in (0, 4] m/s, got {self.speed}"),
            (0 < self.period <= 4.0, f"period must be in (0, 4] s, got {self.period}"),
            (
                0 < self.double_support < self.period / 2,
                f"double-support duration must be in (0, T/2) = (0, {self.period / 2:g}) s, "
                f"got {self.double_support}",
            ),
            (20 <= self.mass <= 250, f"body mass must be in [20, 250] kg, got {self.mass}"),
            (1.0 <= self.height <= 2.4, f"height must be in [1.0, 2.4] m, got {self.height}"),
            (6 <= self.nodes <= 200, f"nodes must be in [6, 200], got {self.nodes}"),
            (1 <= self.threads <= 64, f"threads must be in [1, 64], got {self.threads}"),
            (0 <= self.loop_checks <= 4, f"loop checks must be in [0, 4], got {self.loop_checks}"),
            (
                0 < self.loop_check_tolerance <= 0.05,
                f"loop check tolerance must be in (0, 0.05], got {self.loop_check_tolerance}",
            ),
            (0 < self.friction <= 2, f"friction must be in (0, 2], got {self.friction}"),
            (
                0 <= self.free_moment_radius <= 0.1,
                f"free-moment radius must be in [0, 0.1] m, got {self.free_moment_radius}",
            ),
            (0 < self.smoothing < 0.1, f"smoothing must be in (0, 0.1), got {self.smoothing}"),
            (
                0 <= self.perturbation <= 0.5,
                f"perturbation must be in [0, 0.5], got {self.perturbation}",
            ),
            (
                0 <= self.restarts <= 10,
                f"restarts must be an integer in [0, 10], got {self.restarts}",
            ),
            (
                min(
                    self.max_iter,
                    self.balance_max_iter,
                    self.posture_balance_max_iter,
                    self.full_max_iter,
                )
                >= 1,
                "iteration limits must be >= 1, got max_iter "
                f"{self.max_iter}, balance_max_iter {self.balance_max_iter}, "
                f"posture_balance_max_iter {self.posture_balance_max_iter}, "
                f"full_max_iter {self.full_max_iter}",
            ),
            (
                self.balance_progress_check is None
                or all(it >= 1 and viol > 0 for it, viol in self.balance_progress_check),
                "balance progress check must be pairs (iteration >= 1, violation > 0) or None, "
                f"got {self.balance_progress_check}",
            ),
        ]
        checks.append(
            (
                (self.rollover_s is None) == (self.rollover_ankle is None)
                and (self.rollover_s is None or len(self.rollover_s) == len(self.rollover_ankle)),
                "rollover_s and rollover_ankle go together, one ankle point per knot",
            )
        )
        for ok, msg in checks:
            if not ok:
                raise ValueError(msg)
        return self

    def progress_checks(self) -> dict[int, float]:
        """``balance_progress_check`` as {iteration: violation} (empty when None); a single pair
        is read as one check, also where a copy bypassed validation (``model_copy``)."""
        checks = self.balance_progress_check
        if checks is None:
            return {}
        return dict(self._check_pairs(checks))

    @property
    def stride_length(self) -> float:
        return self.speed * self.period


def available_cores() -> int:
    """CPU cores this process may run on (its affinity mask where the OS has one)."""
    import os

    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # macOS, Windows
        return max(1, os.cpu_count() or 1)


def body_for(settings: PredictionSettings):
    """The body model of these settings (with the calibrated roll-over, if any)."""
    from dataclasses import replace

    import numpy as np

    from walk3d.body.model import build_body
    from walk3d.kinematics.rollover import RollOver

    body = build_body(settings.mass, settings.height, settings.sex)
    if settings.rollover_s is None:
        return body
    ro = RollOver.from_samples(np.array(settings.rollover_s), np.array(settings.rollover_ankle))
    return replace(body, rollover=ro)


def ratios_for(settings: PredictionSettings):
    """The calibrated :class:`~walk3d.contact.transition.TransitionRatios`, or None."""
    from walk3d.contact.transition import TransitionRatios

    r = settings.transition_ratios
    return None if r is None else TransitionRatios(*r)


def first_error(exc: Exception) -> str:
    """One-line message from a pydantic ValidationError (or any exception)."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        e = errors()[0]
        msg = str(e.get("msg", exc)).removeprefix("Value error, ")
        loc = ".".join(str(p) for p in e.get("loc", ()))
        return msg if not loc or loc in msg else f"{loc}: {msg}"
    return " ".join(str(exc).split())
