"""Solve the full-cycle problem (:mod:`walk3d.problem.full_cycle`) from a half-cycle solution.

The start is the half cycle's decision vector mirrored onto both sides (``x_R`` and ``x_L``
equal, the midline as it is), each step's node variables lifted from it and its loads and
slacks made consistent for its own body (:func:`walk3d.solve.ipopt.full_stage_start`). With no
change that start is already the optimum's neighbourhood; a one-sided change moves from it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import casadi as ca
import numpy as np

from walk3d.model.whatif import STEP_ASYMMETRY_COST
from walk3d.problem import layout, similarity
from walk3d.problem.full_cycle import (
    FullProblem,
    full_jerk_weights,
    lifting,
    swap_changes,
)
from walk3d.problem.layout import full_coordinate_maps
from walk3d.problem.schedule import loop_check_times, range_rows
from walk3d.problem.settings import PredictionSettings, body_for
from walk3d.solve.ipopt import SolveOutcome, full_stage_start, lifted_z
from walk3d.solve.options import ipopt_options
from walk3d.solve.plan import SUCCESS
from walk3d.solve.progress import bound_violation, interruptible, raise_if_interrupted
from walk3d.solve.solver import Solver, build_solver

__all__ = [
    "FULL_CYCLE_MAX_ITER",
    "FullCycleOutcome",
    "FullNlp",
    "build_full_problem",
    "left_settings",
    "solve_full_cycle",
]

FULL_CYCLE_MAX_ITER = 300
"""Iteration limit of the full-cycle solve (from the mirrored half cycle)."""
STEP_SHIFT_LIMIT = 0.25
"""Bound on the step shift ``|d|`` (:data:`walk3d.problem.layout.I_STEP_SHIFT`) as a fraction
of half a stride: steps within 0.75–1.25 of the mean, beyond the largest step asymmetry that a
one-sided change here should call for, but never a foot that stays behind the other."""
N_X = layout.N_X


@dataclass(frozen=True)
class FullCycleOutcome:
    """``X = [x_R, x_L]`` (the subject's units; :data:`walk3d.problem.layout.N_XF`) and
    IPOPT's verdict."""

    x: np.ndarray
    record: dict
    """The stage record (status, iterations, wall time, objective, violation)."""

    @property
    def converged(self) -> bool:
        return self.record["status"] in SUCCESS


def left_settings(settings: PredictionSettings) -> PredictionSettings:
    """Step L's settings: the changes with their sides swapped (step L's right is the
    physical left)."""
    changes = swap_changes(settings.model.changes)
    return settings.model_copy(
        update={"model": settings.model.model_copy(update={"changes": changes})}
    )


def _kept_rows(solver: Solver) -> np.ndarray:
    """The full stage's rows without the step's own lifting, range and loop rows."""
    lay, rows = solver.layout, solver.stage_rows["full"]
    drop = np.zeros(lay.n_g, dtype=bool)
    for block in ("lift", "range", "loop"):
        drop[lay.g(block)] = True
    return rows[~drop[rows]]


def mirrored_start(x_half: np.ndarray) -> np.ndarray:
    """``X`` of a half-cycle decision vector: both sides' series equal, the midline as it is."""
    xf = np.r_[x_half, x_half]
    xf[layout.full_fixed_zero_mask()] = 0.0
    xf[layout.I_STEP_SHIFT] = 0.0  # steps of equal length
    return xf


@dataclass(frozen=True)
class FullNlp:
    """The full-cycle NLP of the reference subject's settings, with its bounds."""

    problem: FullProblem
    lbz: np.ndarray
    ubz: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    steps: tuple[Solver, Solver]
    """Step R's and step L's half-cycle solvers."""
    own: np.ndarray
    """A step's own vector entries that are fixed at zero (all but its half step width)."""


def build_full_problem(ref: PredictionSettings) -> FullNlp:
    """The full-cycle NLP (:class:`FullProblem`) of ``ref`` (the reference subject's settings,
    T and Td given), from the half-cycle NLPs of both steps."""
    ref_l = left_settings(ref)
    s_r = build_solver(ref)
    s_l = s_r if ref_l == ref else build_solver(ref_l)
    keep = [_kept_rows(s) for s in (s_r, s_l)]
    probs = [s.stage_problem("step", k) for s, k in zip((s_r, s_l), keep, strict=True)]
    times = s_r.schedule.times
    lifts = [lifting(times, ref.gait.period, m) for m in (False, True)]
    ranges, lo, hi = range_rows(body_for(ref), ref, full=True)
    t_loop = loop_check_times(ref, s_r.schedule)
    anchor = -ref.gait.stride_length / 2
    loops = [(s.functions["loop"], full_coordinate_maps(t_loop, ref.gait.period, m)[0], anchor)
             for s, m in ((s_r, False), (s_l, True))]  # fmt: skip
    half = ref.gait.stride_length / 2  # SLA = d / half
    fp = FullProblem(probs[0], probs[1], lifts[0], lifts[1], ranges, full_jerk_weights(ref),
                     s_r.layout.z("y"), loops, STEP_ASYMMETRY_COST / half**2)  # fmt: skip
    n_lift = sum(lf.shape[0] * lf.shape[1] for lf in lifts)
    b = [s.nlp_bounds("full") for s in (s_r, s_l)]
    fixed = layout.full_fixed_zero_mask()
    lbz, ubz = [np.where(fixed, 0.0, -np.inf)], [np.where(fixed, 0.0, np.inf)]
    d_max = 0.0 if ref.model.equal_steps else STEP_SHIFT_LIMIT * half
    lbz[0][layout.I_STEP_SHIFT], ubz[0][layout.I_STEP_SHIFT] = -d_max, d_max
    own = np.arange(N_X) != layout.I_HALF_STEP
    for bb in b:  # fixed at zero; the width is tied to X's
        lo_s, hi_s = bb.lbz.copy(), bb.ubz.copy()
        lo_s[:N_X][own], hi_s[:N_X][own] = 0.0, 0.0
        lbz.append(lo_s)
        ubz.append(hi_s)
    zeros = np.zeros(n_lift + 2)
    loop_b = [s.layout.g("loop") for s in (s_r, s_l)]
    lbg = np.r_[b[0].lbg[keep[0]], b[1].lbg[keep[1]], zeros, lo,
                b[0].lbg[loop_b[0]], b[1].lbg[loop_b[1]]]  # fmt: skip
    ubg = np.r_[b[0].ubg[keep[0]], b[1].ubg[keep[1]], zeros, hi,
                b[0].ubg[loop_b[0]], b[1].ubg[loop_b[1]]]  # fmt: skip
    return FullNlp(fp, np.concatenate(lbz), np.concatenate(ubz), lbg, ubg, (s_r, s_l), own)


def solve_full_cycle(
    settings: PredictionSettings,
    half: SolveOutcome,
    on_stage: Callable[[str], None] | None = None,
    max_iter: int = FULL_CYCLE_MAX_ITER,
    start: np.ndarray | None = None,
) -> FullCycleOutcome:
    """Solve ``settings`` (T and Td given) on the full cycle, started from ``half``, a
    half-cycle outcome of the same gait (with :meth:`Changes.half_cycle
    <walk3d.model.whatif.Changes.half_cycle>`). ``start``: the ``X`` (subject's units) to start
    from instead of ``half`` mirrored (the steps' variables still come from ``half``)."""
    if settings.gait.free:
        raise ValueError("the full-cycle problem needs T and Td (solve the half cycle first)")
    ref, scale = similarity.reference_problem(settings)
    with interruptible():
        if on_stage:
            on_stage("building the full-cycle problem (both steps)")
        full = build_full_problem(ref)
        fp, lbz, ubz, lbg, ubg, own = full.problem, full.lbz, full.ubz, full.lbg, full.ubg, full.own
        x_ref = similarity.subject_x(half.x, 1.0 / scale)
        z0 = [mirrored_start(x_ref) if start is None else similarity.subject_x(start, 1 / scale)]
        for s in full.steps:
            zs = full_stage_start(s, lifted_z(s, x_ref))
            zs[:N_X][own] = 0.0
            z0.append(zs)
        z0 = np.concatenate(z0)
        opts = ipopt_options(ref) | {"ipopt.max_iter": max_iter} | fp.derivatives
        fn = ca.nlpsol("walk3d_full_cycle", "ipopt", fp.nlp, opts)
        if on_stage:
            on_stage("solving the full cycle (both steps, from the mirrored half cycle)")
        t0 = time.perf_counter()
        sol = fn(x0=z0, lbx=lbz, ubx=ubz, lbg=lbg, ubg=ubg)
        raise_if_interrupted()
    stats = fn.stats()
    z = np.array(sol["x"]).ravel()
    viol = max(bound_violation(np.array(sol["g"]).ravel(), lbg, ubg),
               bound_violation(z, lbz, ubz))  # fmt: skip
    record = {
        "stage": "full cycle",
        "start": "mirrored half cycle",
        "status": stats["return_status"],
        "iterations": int(stats["iter_count"]),
        "wall_time_s": time.perf_counter() - t0,
        "objective": float(sol["f"]),
        "max_constraint_violation": viol,
    }
    return FullCycleOutcome(x=similarity.subject_x(z[: layout.N_XF], scale), record=record)
