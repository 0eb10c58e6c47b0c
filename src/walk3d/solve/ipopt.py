"""Solving the prediction NLP with CasADi + IPOPT (exact Hessian), in stages.

0. *posture* (``settings.posture_stage``: by default only as a fallback when the balance stage
   straight from standing has not converged): every kinematic constraint (closed
   double-support loop, stride V·T, swing clearance, foot flat, ranges), minimizing joint
   rates, accelerations and coordinates;
1. *balance*: the same, plus the total ground reaction kept physical (Fy ≥ 0, friction, centre
   of pressure under the feet) — still no joint moments;
2. *full*: the criterion under all constraints, from stage 1.

All start from the paper's initial guess: upright standing (all coefficients zero) plus uniform
random numbers drawn from the seed. No measured data enters. The solvers themselves are built
in :mod:`walk3d.solve.solver`; docs/solver.md has the measurements.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from walk3d.problem import layout, nlp, similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.progress import Listener, StopRule, bound_violation
from walk3d.solve.solver import Solver, build_solver

__all__ = ["IPOPT_SUCCESS", "SolveOutcome", "Solver", "build_solver", "full_stage_start",
           "initial_guess", "solve"]  # fmt: skip

IPOPT_SUCCESS = {"Solve_Succeeded", "Solved_To_Acceptable_Level"}
"""Return statuses counted as converged (IPOPT's, and sqpmethod's ``Solve_Succeeded``)."""


@dataclass
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
    """Standing starts tried (1 + restarts used; ``settings.restarts``)."""
    max_constraint_violation: float = float("nan")
    """Largest violation of the final stage's rows and bounds, in the solved NLP's units (those
    of the reference subject: lengths differ from the subject's by the factor h / 1.77 m)."""
    compiled_derivatives: list[str] = field(default_factory=list)
    """NLPs whose node derivatives ran as compiled C (``walk3d compile``), not in CasADi's VM."""


def initial_guess(solver: Solver, seed: int, attempt: int = 0) -> np.ndarray:
    """Upright standing plus uniform noise: the NLP start vector ``z`` for ``seed``.

    ``attempt`` k ≥ 1 (a restart, ``settings.restarts``) draws the noise from the seed's k-th
    independent stream, ``numpy.random.default_rng([seed, k])``, so every attempt of every
    start is reproducible from its seed and differs from the other seeds' starts.
    """
    s = solver.settings
    rng = np.random.default_rng(seed if attempt == 0 else [seed, attempt])
    x0 = np.zeros(layout.N_X)
    x0[: layout.I_HALF_STEP] = rng.uniform(-s.perturbation, s.perturbation, layout.I_HALF_STEP)
    x0[layout.fixed_zero_mask()] = 0.0
    x0[layout.I_HALF_STEP] = 0.08  # m, at the reference stature (solve() solves that problem)
    return _z_from_x(solver, x0, np.array([0.0, 1.0, 0.0, 0.0, 0.0, 0.0]))


def _z_from_x(solver: Solver, x: np.ndarray, w0: np.ndarray) -> np.ndarray:
    y = np.einsum("kij,j->ki", solver.lift, x)
    t = np.zeros(solver.schedule.n * nlp.N_T)
    z = np.concatenate([x, y.ravel(), w0, t])
    return np.clip(z, solver.bounds_balance.lbz, solver.bounds_balance.ubz)


SLACK_MARGIN = 1e-2
"""Initial slack above the larger of ``u⁺, u⁻`` (criterion units per DoF), to start inside."""


def full_stage_start(solver: Solver, z: np.ndarray) -> np.ndarray:
    """Start of the full stage from a balance-stage solution ``z``: consistent W0 and slacks.

    W0 is set to the total reaction at node 0 (twice, since the split in double support
    depends on it), and each slack to ``max(u⁺, u⁻) + SLACK_MARGIN`` at that point.
    """
    z = z.copy()
    n, n_x, n_y = solver.schedule.n, layout.N_X, nlp.N_Y
    i_w0 = n_x + n * n_y
    i_t = i_w0 + 6
    z[i_w0:i_t] = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]
    z[i_t:] = 0.0
    rows = nlp.G_ROWS

    def node_rows(z: np.ndarray) -> np.ndarray:
        g = np.array(solver.constraints(z)).ravel()
        return g[n * n_y : n * n_y + n * nlp.N_G].reshape(n, nlp.N_G)

    for _ in range(2):
        z[i_w0:i_t] = node_rows(z)[0, rows["hs_wrench"]]
    node = node_rows(z)
    u = np.maximum(-node[:, rows["slack_pos"]], -node[:, rows["slack_neg"]])
    if solver.settings.absolute == "slack":
        z[i_t:] = (u + SLACK_MARGIN).ravel()
    return z


def _run(
    fn: ca.Function,
    solver: Solver,
    z0: np.ndarray,
    name: str,
    listener: Listener | None = None,
    stop: StopRule | None = None,
):
    """Run stage ``name``'s solver ``fn`` from ``z0`` within the stage's bounds."""
    b = solver.stage_bounds(name)
    t0 = time.perf_counter()
    with solver.reporter(name).listening(listener, b.lbg, b.ubg, stop):
        sol = fn(x0=z0, lbx=b.lbz, ubx=b.ubz, lbg=b.lbg, ubg=b.ubg)
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
    return np.array(sol["x"]).ravel(), info


def solve(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome:
    """Predict one gait cycle from the standing start of ``seed``.

    ``converged`` is True only when the final (full) stage reports success. A start whose final
    stage, or whose balance stage (see ``attempt``), did not converge is tried again from a new
    standing start (the seed's next noise stream, :func:`initial_guess`), at most
    ``settings.restarts`` times; each stage's record carries its ``attempt``. Any mass and stature
    is solved as the reference subject's problem (:mod:`walk3d.problem.similarity`) and ``x`` mapped
    back. ``on_stage`` receives progress messages: each stage as it starts, then, every IPOPT
    iteration, the stage's message with its iteration, objective and largest constraint
    violation."""
    note = on_stage or (lambda _msg: None)

    def progress(label: str) -> Listener | None:
        """Per-iteration messages of one stage, on one terminal line (< 72 characters)."""
        if on_stage is None:
            return None
        return lambda it, f, viol: on_stage(
            f"{label}: iteration {it}, objective {f:.4g}, infeasibility {viol:.0e}"
        )

    note("building the model")
    # every mass and stature is solved as the reference subject's problem (same node
    # functions, cache entry and compiled derivatives); x is mapped back at the end
    ref, scale = similarity.reference_problem(settings)
    solver = build_solver(ref, method)
    t0 = time.perf_counter()
    stages: list[dict] = []

    checks = ref.progress_checks()

    def stop_rule(name: str) -> StopRule | None:
        """The direct balance stage stops early if it is still far from feasible."""
        if name != "balance_direct" or not checks:
            return None
        return lambda it, _f, viol: it in checks and viol > checks[it]

    def run(name: str, z0: np.ndarray, label: str) -> tuple[np.ndarray, dict]:
        z, info = _run(solver.stage(name), solver, z0, name, progress(label), stop_rule(name))
        stages.append(info)
        return z, info

    def through_posture(z_stand: np.ndarray) -> tuple[np.ndarray, dict]:
        note("stage 0: walking posture (geometry only)")
        z, _ = run("posture", z_stand, "stage 0 (posture)")
        note("stage 1/2: balance, from the walking posture")
        return run("balance", z, "stage 1/2 (balance)")

    crit = f"C_{ref.criterion}"

    def full(z: np.ndarray) -> tuple[np.ndarray, dict]:
        note(f"stage 2/2: minimizing {crit}")
        return run("full", full_stage_start(solver, z), f"stage 2/2 ({crit})")

    def attempt(z_stand: np.ndarray, last: bool) -> tuple[np.ndarray, dict]:
        """The stages from one standing start.

        A balance stage that did not converge (after the posture stage, or from standing
        without the fallback) ends the attempt while a restart is left. The full stage after
        such a stage seldom converged (seed 1 in session 9, seed 11's restart in session 10);
        the others ran to their 400-iteration limit, about a minute, before the restart
        (docs/solver.md). On the last attempt the full stage still runs.
        """
        fallback = ref.posture_stage == "fallback"

        def hopeless(info: dict) -> bool:
            if last or info["status"] in IPOPT_SUCCESS:
                return False
            note("the balance stage did not converge: restarting instead of the full stage")
            return True

        if ref.posture_stage == "first":
            z, info1 = through_posture(z_stand)
        else:
            name = "balance_direct" if fallback else "balance"
            solver.stage(name)
            solver.prepare("full")  # built while the balance stage solves
            note("stage 1/2: balance (walking posture, total reaction under the feet)")
            z, info1 = run(name, z_stand, "stage 1/2 (balance)")
        retry = fallback  # one retry through the posture stage, unless the fallback used it
        if fallback and info1["status"] not in IPOPT_SUCCESS:
            z, info1 = through_posture(z_stand)
            retry = False
        if hopeless(info1):
            return z, info1
        z, info2 = full(z)
        if retry and info2["status"] not in IPOPT_SUCCESS:
            note("the full stage did not converge: retrying from standing through the posture "
                 "stage")  # fmt: skip
            z, info1 = through_posture(z_stand)
            if hopeless(info1):
                return z, info1
            z, info2 = full(z)
        return z, info2

    tries = ref.restarts + 1
    for k in range(tries):
        if k:
            note(f"not converged: restarting from a new standing start ({k + 1} of {tries})")
        first = len(stages)
        z, info2 = attempt(initial_guess(solver, seed, k), last=k == tries - 1)
        for st in stages[first:]:
            st["attempt"] = k
        if info2["status"] in IPOPT_SUCCESS:
            break
    return SolveOutcome(
        x=similarity.subject_x(z[: layout.N_X], scale),
        z=z,
        converged=info2["status"] in IPOPT_SUCCESS,
        status=info2["status"],
        iterations=sum(st["iterations"] for st in stages),
        wall_time_s=time.perf_counter() - t0,
        stages=stages,
        solver=method,
        attempts=k + 1,
        max_constraint_violation=info2["max_constraint_violation"],
        compiled_derivatives=sorted(solver.compiled),
    )
