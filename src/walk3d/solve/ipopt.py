"""Solving the prediction NLP with CasADi + IPOPT (exact Hessian): the stages of
:mod:`walk3d.solve.plan`, run by :func:`walk3d.solve.plan.run_plan` on IPOPT.

Every attempt starts from the paper's initial guess: upright standing (all coefficients zero)
plus uniform random numbers drawn from the seed. No measured data enters. The solvers
themselves are built in :mod:`walk3d.solve.solver`; docs/solver.md has the measurements.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np

from walk3d.contact import crouch, free_split
from walk3d.contact.phases import GaitPhases
from walk3d.model import terms
from walk3d.problem import descriptors, layout, similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import upright
from walk3d.solve.plan import END, SUCCESS, Plan, Stage, run_plan
from walk3d.solve.progress import (
    Listener,
    StopRule,
    bound_violation,
    interruptible,
    raise_if_interrupted,
)
from walk3d.solve.solver import Solver, build_solver

__all__ = ["IPOPT_SUCCESS", "SolveOutcome", "Solver", "build_solver", "descriptor_stage",
           "full_stage_start", "initial_guess", "merged", "solve", "solve_descriptors",
           "warm_stage"]  # fmt: skip

IPOPT_SUCCESS = SUCCESS
"""Return statuses counted as converged (:data:`walk3d.solve.plan.SUCCESS`)."""


@dataclass(kw_only=True)
class SolveOutcome:
    """What a solve returns; ``converged`` is IPOPT's own verdict on the final stage."""

    x: np.ndarray
    """Decision vector (166): coefficients and half step width (see layout), the subject's."""
    z: np.ndarray
    """The NLP's variables at the end, in the units of the reference subject whose problem was
    solved (:func:`walk3d.problem.similarity.reference_problem`)."""
    converged: bool
    status: str
    iterations: int
    wall_time_s: float
    stages: list[dict] = field(default_factory=list)
    solver: str = "ipopt"
    attempts: int = 1
    """Standing starts tried (1 + restarts used; ``settings.solver.restarts``)."""
    max_constraint_violation: float = float("nan")
    """Largest violation of the final stage's rows and bounds, in the solved NLP's units (those
    of the reference subject: lengths differ from the subject's by the factor h / 1.77 m)."""
    compiled_derivatives: list[str] = field(default_factory=list)
    """NLPs whose node derivatives ran as compiled C (``walk3d compile``), not in CasADi's VM."""
    descriptors: dict[str, float] = field(default_factory=dict)
    """The subject's period and double support at the end, s, when they were unknowns
    (``settings.gait.free``); empty otherwise."""
    handover: bool = False
    """Whether ``x`` was solved with the handover (``ModelSettings.handover``,
    :mod:`walk3d.solve.landing`)."""
    split: np.ndarray | None = None
    """The free split's coefficients ``(K, 6)``, the subject's (:mod:`walk3d.contact.
    free_split`); None for the paper's split."""
    duals: dict[str, np.ndarray] | None = field(default=None, repr=False)
    """``lam_x`` and ``lam_g`` of the last stage (its solver's rows), from :func:`warm_stage`:
    with ``z``, a primal-dual start for the same problem (the atlas's, docs/starts.md)."""


def split_of(solver: Solver, z: np.ndarray, scale: float) -> np.ndarray | None:
    """The subject's free-split coefficients ``(K, 6)`` in ``z``, or None without them."""
    lay = solver.layout
    if not lay.n_split:
        return None
    w0 = lay.z("w0")
    return free_split.subject_split(z[w0.start + layout.N_W0 : w0.stop], scale)


STANDING_W0 = (0.0, 1.0, 0.0, 0.0, 0.0, 0.0)
"""The trailing foot's load W0 of quiet standing (body weights): the start before it is made
consistent (:func:`full_stage_start`)."""


def initial_guess(solver: Solver, seed: int, attempt: int = 0) -> np.ndarray:
    """Upright standing plus uniform noise: the NLP start vector ``z`` for ``seed``.

    ``attempt`` k ≥ 1 (a restart, ``settings.solver.restarts``) draws the noise from the seed's k-th
    independent stream, ``numpy.random.default_rng([seed, k])``, so every attempt of every
    start is reproducible from its seed and differs from the other seeds' starts.
    """
    s = solver.settings
    rng = np.random.default_rng(seed if attempt == 0 else [seed, attempt])
    x0 = np.zeros(layout.N_X)
    x0[: layout.I_HALF_STEP] = rng.uniform(
        -s.solver.perturbation, s.solver.perturbation, layout.I_HALF_STEP
    )
    x0[layout.fixed_zero_mask()] = 0.0
    x0[layout.I_HALF_STEP] = 0.08  # m, at the reference stature (solve() solves that problem)
    return lifted_z(solver, x0)


def lifted_z(solver: Solver, x: np.ndarray, s0: tuple[float, ...] | None = None) -> np.ndarray:
    """The NLP decision vector ``z`` of the coefficients ``x``: the node coordinates lifted
    from them and W0 at standing, within the balance stage's bounds; with predicted
    descriptors, those at ``s0`` (default: the first guess), clipped to their bounds."""
    lay, g = solver.layout, solver.settings.gait
    z = np.zeros(lay.n_z)
    z[lay.z("x")] = x
    z[lay.z("w0")] = np.r_[STANDING_W0, np.zeros(lay.n_split)]  # the free split at 0
    s = [g.period, g.double_support][: lay.n_s]
    if lay.n_s and s0 is not None:
        b = solver.nlp_bounds("free")
        s = np.clip(s0[: lay.n_s], b.lbz[lay.z("s")], b.ubz[lay.z("s")])
        grid = descriptors.grid_for(solver.settings.solver)
        z[lay.z("y")] = np.array(descriptors.lift_function(grid)(x, s)).ravel()
    else:
        z[lay.z("y")] = np.einsum("kij,j->ki", solver.lift, x).ravel()
    z = np.clip(z, solver.bounds_balance.lbz, solver.bounds_balance.ubz)
    z[lay.z("s")] = s  # the balance NLP pins s at the first guess
    return z


SLACK_MARGIN = 1e-2
"""Initial slack above the larger of ``u⁺, u⁻`` (criterion units per DoF), to start inside."""


def full_stage_start(solver: Solver, z: np.ndarray) -> np.ndarray:
    """Start of the full stage from a balance-stage solution ``z``: consistent W0 and slacks.

    W0 is set to the total reaction at node 0 (twice, since the split in double support
    depends on it), and each slack to ``max(u⁺, u⁻) + SLACK_MARGIN`` at that point.
    """
    z = z.copy()
    lay, rows = solver.layout, layout.G_ROWS
    w0, t = lay.z("w0"), lay.z("t")
    z[w0] = np.r_[STANDING_W0, np.zeros(lay.n_split)]
    w0 = slice(w0.start, w0.start + layout.N_W0)  # the heel-strike load; a free split stays 0
    z[t] = 0.0

    def node_rows(z: np.ndarray) -> np.ndarray:
        return lay.node_rows(np.array(solver.constraints(z)).ravel())

    for _ in range(2):
        z[w0] = node_rows(z)[0, rows["hs_wrench"]]
    node = node_rows(z)
    u = np.maximum(-node[:, rows["slack_pos"]], -node[:, rows["slack_neg"]])
    if solver.settings.model.absolute == "slack":
        u[solver.schedule.checks] = -SLACK_MARGIN  # a contact check's slacks are fixed at 0
        z[t] = (u + SLACK_MARGIN).ravel()
    return z


def _run(
    fn: ca.Function,
    solver: Solver,
    z0: np.ndarray,
    name: str,
    kind: str,
    listener: Listener | None = None,
    stop: StopRule | None = None,
    duals: dict[str, np.ndarray] | None = None,
) -> tuple[np.ndarray, dict, dict[str, np.ndarray]]:
    """Run the stage solver ``fn`` of NLP ``kind`` from ``z0`` (and the multipliers ``duals``,
    for a solver built with :data:`walk3d.solve.solver.WARM_START`); returns its end, record
    and the end's multipliers (``lam_x``, ``lam_g``)."""
    b = solver.stage_bounds(kind)
    t0 = time.perf_counter()
    start = {"lam_x0": duals["lam_x"], "lam_g0": duals["lam_g"]} if duals else {}
    with solver.reporters[kind].listening(listener, b.lbg, b.ubg, stop):
        sol = fn(x0=z0, lbx=b.lbz, ubx=b.ubz, lbg=b.lbg, ubg=b.ubg, **start)
    raise_if_interrupted()
    stats = fn.stats()
    zz = np.array(sol["x"]).ravel()
    viol = max(bound_violation(np.array(sol["g"]).ravel(), b.lbg, b.ubg),
               bound_violation(zz, b.lbz, b.ubz))  # fmt: skip
    info = {
        "max_constraint_violation": viol,
        "stage": name,
        "status": stats["return_status"],
        "iterations": int(stats["iter_count"]),
        "wall_time_s": time.perf_counter() - t0,
        "objective": float(sol["f"]),
    }
    return zz, info, {k: np.array(sol[k]).ravel() for k in ("lam_x", "lam_g")}


def _listener(on_stage: Callable[[str], None] | None, stage: Stage) -> Listener | None:
    """The per-iteration progress message of ``stage``, or None without ``on_stage``."""
    if on_stage is None:
        return None
    return lambda it, f, viol: on_stage(
        f"{stage.label}: iteration {it}, objective {f:.4g}, infeasibility {viol:.0e}"
    )


def _descriptors(solver: Solver, z: np.ndarray, scale: float) -> dict[str, float]:
    """The subject's ``{period, double_support}`` in ``z`` (empty without ``s``): the solved
    problem's times by √scale (:mod:`walk3d.problem.similarity`)."""
    found = z[solver.layout.z("s")] * np.sqrt(scale)
    return dict(zip(descriptors.NAMES, map(float, found), strict=False))


def _reject_crouch(solver: Solver, z: np.ndarray, record: dict, note) -> None:
    """Relabel a crouched optimum as not converged (``settings.solver.reject_crouch``)."""
    if not solver.settings.solver.reject_crouch:
        return
    gait, lay = solver.settings.gait, solver.layout
    phases = GaitPhases(gait.period, gait.double_support)
    tau = solver.schedule.times - phases.heel_strike_r
    if lay.n_s:  # the phase-following grid at the solved T and Td
        phases = GaitPhases(*map(float, np.asarray(z)[lay.z("s")]))
        grid = descriptors.grid_for(solver.settings.solver)
        tau = np.array(grid.tau(phases.period, phases.double_support), dtype=float)
    hip = upright.midstance_hip_flexion_deg(z, lay, tau, phases)
    if crouch.upright(hip):
        return
    record["optimum_status"], record["status"] = record["status"], upright.CROUCHED
    record["midstance_hip_flexion_deg"] = hip
    note(f"the optimum is crouched (hip flexed {hip:.0f} deg in mid-stance): trying again")


def solve(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome:
    """:func:`solve_stages` with Ctrl-C turned into KeyboardInterrupt between CasADi calls
    (:func:`walk3d.solve.progress.interruptible`): raised inside CasADi, it would be swallowed
    (by its argument conversion while the model builds, by IPOPT's callback while it solves)."""
    with interruptible():
        if settings.gait.free:
            return solve_descriptors(settings, seed, method, on_stage)
        return solve_stages(settings, seed, method, on_stage)


def descriptor_stage(settings: PredictionSettings) -> Stage:
    """The last stage of a prediction with predicted descriptors: the full NLP, ``s`` free."""
    crit = terms.label(settings.model.criterion)
    limit = min(settings.solver.max_iter, settings.solver.full_max_iter)
    return Stage(key="descriptors", name="descriptors", problem="free", start="previous",
                 max_iter=limit, title=f"stage 3/3: predicting the period and double support "
                 f"({crit})", label="stage 3/3 (T, Td)")  # fmt: skip


def solve_descriptors(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome:
    """Predict the gait with ``settings.gait.free`` among the unknowns: :func:`solve_stages` of
    the problem with every descriptor given (its first guess), then :func:`descriptor_stage`
    from that optimum on the phase-following grid (:mod:`walk3d.problem.descriptors`). Why not
    at once: from standing, the free problem ended crouched or at the bounds where the given one
    walks (docs/descriptors.md)."""
    fixed = settings.model_copy(update={"gait": settings.gait.model_copy(update={"free": ()})})
    ref, scale = similarity.reference_problem(settings)
    solver = build_solver(ref, method)
    stage = descriptor_stage(ref)
    first = solve_stages(fixed, seed, method, on_stage)
    if first.converged:
        free = warm_stage(solver, stage, first.z[: layout.N_X], scale, on_stage)
        if free.converged:
            return merged(first, free, method)
    if on_stage:
        on_stage("predicting the period and double support from standing")
    return merged(first, solve_stages(settings, seed, method, on_stage, free_plan=True), method)


def warm_stage(
    solver: Solver,
    stage: Stage,
    x_ref: np.ndarray,
    scale: float,
    on_stage: Callable[[str], None] | None = None,
    s0: tuple[float, ...] | None = None,
    warm: dict[str, np.ndarray] | None = None,
) -> SolveOutcome:
    """Run the full-NLP ``stage`` (``problem`` full or free) from the decision vector ``x_ref``
    (reference subject's units) with the descriptors ``s0`` (the solver's first guess when
    None; ignored when every descriptor is given); or, with ``warm`` (``z``, ``lam_x``,
    ``lam_g`` of this NLP's stage solver, e.g. an atlas entry's), from that primal-dual point
    with IPOPT's warm start (:data:`walk3d.solve.solver.WARM_START`)."""
    note = on_stage or (lambda _msg: None)
    t0 = time.perf_counter()
    note(stage.title)
    if warm is not None:
        z0, fn = np.asarray(warm["z"], dtype=float), solver.stage(stage, warm=True)
    else:
        z0 = full_stage_start(solver, lifted_z(solver, np.asarray(x_ref, dtype=float), s0))
        fn = solver.stage(stage)
    z, record, duals = _run(fn, solver, z0, stage.name, stage.problem,
                            _listener(on_stage, stage), duals=warm)  # fmt: skip
    if warm is not None:
        record["warm_start"] = True
    record["attempt"] = 0
    if record["status"] in SUCCESS:
        _reject_crouch(solver, z, record, note)
    return SolveOutcome(
        x=similarity.subject_x(z[: layout.N_X], scale), z=z, split=split_of(solver, z, scale),
        converged=record["status"] in SUCCESS, status=record["status"],
        iterations=record["iterations"], wall_time_s=time.perf_counter() - t0,
        stages=[record], max_constraint_violation=record["max_constraint_violation"],
        compiled_derivatives=sorted(solver.compiled),
        descriptors=_descriptors(solver, z, scale), handover=solver.settings.model.handover,
        duals=duals,
    )  # fmt: skip


def merged(first: SolveOutcome, free: SolveOutcome, method: str) -> SolveOutcome:
    """The outcome of ``first``'s stages followed by ``free``'s."""
    for record in free.stages:
        record["attempt"] = record.get("attempt", 0) + first.attempts
    return SolveOutcome(
        x=free.x, z=free.z, converged=free.converged, status=free.status,
        iterations=first.iterations + free.iterations,
        wall_time_s=first.wall_time_s + free.wall_time_s,
        stages=[*first.stages, *free.stages], solver=method,
        attempts=first.attempts + free.attempts,
        max_constraint_violation=free.max_constraint_violation,
        compiled_derivatives=sorted(set(first.compiled_derivatives)
                                    | set(free.compiled_derivatives)),
        descriptors=free.descriptors, handover=free.handover, split=free.split,
    )  # fmt: skip


def solve_stages(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
    free_plan: bool = False,
) -> SolveOutcome:
    """Predict one gait cycle from the standing start of ``seed``.

    Runs the solver's plan (:mod:`walk3d.solve.plan`); ``converged`` is True only when the
    final stage reports success. Any mass and stature is solved as the reference subject's
    problem (:mod:`walk3d.problem.similarity`) and ``x`` mapped back. ``on_stage`` receives
    progress messages: each stage as it starts, then, every IPOPT iteration, the stage's
    label with its iteration, objective and largest constraint violation. ``free_plan``: the
    full stages free the predicted descriptors (``settings.gait.free``)."""
    note = on_stage or (lambda _msg: None)
    note("building the model")
    ref, scale = similarity.reference_problem(settings)
    solver = build_solver(ref, method)
    plan = solver.plan
    if free_plan:
        plan = Plan(tuple(replace(st, problem="free") if st.problem == "full" else st
                          for st in plan.stages))  # fmt: skip
    raise_if_interrupted()
    t0 = time.perf_counter()
    ends: dict[str, np.ndarray] = {}  # the attempt's standing start and the last stage's end

    def run_stage(stage: Stage, attempt: int) -> dict:
        if stage is plan.first:
            ends["standing"] = initial_guess(solver, seed, attempt)
        if stage.start == "criterion":
            z0 = full_stage_start(solver, ends["previous"])
        else:
            z0 = ends[stage.start]
        note(stage.title)
        fn = solver.stage(stage)  # the next stage is built when asked for: symbolics in one thread
        listener = _listener(on_stage, stage)
        stop = (lambda it, _f, viol: stage.stops(it, viol)) if stage.checks else None
        ends["previous"], record, _ = _run(fn, solver, z0, stage.name, stage.problem, listener,
                                           stop)  # fmt: skip
        again = stage.on_failure != END or attempt < ref.solver.restarts
        if stage.problem in ("full", "free") and record["status"] in SUCCESS and again:
            _reject_crouch(solver, ends["previous"], record, note)
        return record

    result = run_plan(plan, ref.solver.restarts, run_stage, note)
    last = result.records[-1]
    return SolveOutcome(
        x=similarity.subject_x(ends["previous"][: layout.N_X], scale),
        z=ends["previous"],
        split=split_of(solver, ends["previous"], scale),
        converged=result.converged,
        status=last["status"],
        iterations=sum(st["iterations"] for st in result.records),
        wall_time_s=time.perf_counter() - t0,
        stages=result.records,
        solver=method,
        attempts=result.attempts,
        max_constraint_violation=last["max_constraint_violation"],
        compiled_derivatives=sorted(solver.compiled),
        descriptors=_descriptors(solver, ends["previous"], scale),
        handover=ref.model.handover,
    )
