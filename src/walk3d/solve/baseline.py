"""Paper-style baseline solver: SciPy SLSQP with finite-difference gradients.

The paper solved its 165-coefficient problem with MATLAB's SQP and finite differences. This
baseline does the same on walk3d's problem in its dense form (coefficients only, no lifted node
variables): the same node function, the same bounds, the same two stages and the same start.
It exists to measure the speed-up of the default solver, not to be used for predictions.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import minimize

from walk3d.problem import layout, nlp, similarity
from walk3d.problem.schedule import loop_check_times, node_params, range_rows
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.ipopt import SolveOutcome, build_solver, initial_guess


def _smooth(settings: PredictionSettings) -> PredictionSettings:
    """``settings`` with the smooth criterion form, not revalidated: a reference problem's
    descriptors may lie outside the user-facing ranges (:mod:`walk3d.problem.similarity`)."""
    model = settings.model.model_copy(update={"absolute": "smooth"})
    return settings.model_copy(update={"model": model})


class _Dense:
    """Objective and constraints as plain functions of x (166) for one stage."""

    def __init__(self, settings: PredictionSettings, dynamics: bool):
        # the paper's form: the (smoothed) criterion itself is the objective, no slack variables
        settings = _smooth(settings)
        sv = build_solver(settings)
        self.sv = sv
        node = nlp.node_function(sv.body, settings.model, dynamics)
        self.n = sv.schedule.n
        self.fn = node.map(self.n)
        self.params = node_params(settings, sv.schedule)
        self.crit = nlp.criterion_row(settings.model)
        self.step = sv.schedule.step
        b = sv.bounds if dynamics else sv.bounds_balance
        n_lift = self.n * nlp.N_Y
        n_node = self.n * nlp.N_G
        self.range_mat = range_rows(sv.body, settings)[0]
        # node rows, then the linear joint-range rows (the 6 heel-strike rows are equalities)
        self.lbg = np.r_[b.lbg[n_lift : n_lift + n_node], b.lbg[n_lift + n_node + 6 :]]
        self.ubg = np.r_[b.ubg[n_lift : n_lift + n_node], b.ubg[n_lift + n_node + 6 :]]
        self.lbx = b.lbz[: layout.N_X]
        self.ubx = b.ubz[: layout.N_X]
        self.lby = b.lbz[layout.N_X : layout.N_X + n_lift]
        self.uby = b.ubz[layout.N_X : layout.N_X + n_lift]
        self.lift = sv.lift.reshape(-1, layout.N_X)
        t_loop = loop_check_times(settings, sv.schedule)
        self.loop_map = layout.coordinate_maps(t_loop, settings.gait.period)[0]  # (m, 26, N_X)
        self.loop_fn = nlp.loop_function(sv.body, settings.model).map(max(t_loop.size, 1))
        self.anchor = np.full((1, t_loop.size), -settings.gait.stride_length / 2)
        self.evals = 0

    def _loop(self, x: np.ndarray) -> np.ndarray:
        """Loop-check rows (toe-off and between double-support nodes), as in the NLP."""
        if not self.anchor.size:
            return np.zeros(0)
        c = np.einsum("mkj,j->km", self.loop_map, x[: layout.N_X])
        return np.array(self.loop_fn(c, x[layout.I_HALF_STEP], self.anchor)).T.ravel()

    def _eval(self, x: np.ndarray):
        self.evals += 1
        y = (self.lift @ x[: layout.N_X]).reshape(self.n, nlp.N_Y).T
        w0 = np.tile(x[layout.N_X :][:, None], (1, self.n))
        hw = np.full((1, self.n), x[layout.I_HALF_STEP])
        g, f = self.fn(y, w0, hw, self.params, np.zeros((nlp.N_T, self.n)))
        g, f = np.array(g), np.array(f)
        hs = g[nlp.G_ROWS["hs_wrench"], 0] - x[layout.N_X :]
        g = np.r_[g.T.ravel(), self.range_mat @ x[: layout.N_X], self._loop(x)]
        w = self.sv.schedule.weights
        total = self.step * np.sum(f[self.crit]) if w is None else np.sum(w * f[self.crit])
        return g, 2.0 * float(total), hs, y.T.ravel()

    def objective(self, x):
        return self._eval(x)[1]

    def constraints(self, x):
        """(equalities, inequalities >= 0) from the bounded rows and the lifted bounds."""
        g, _, hs, y = self._eval(x)
        eq = np.isfinite(self.lbg) & (self.lbg == self.ubg)
        lo = np.isfinite(self.lbg) & ~eq
        hi = np.isfinite(self.ubg) & ~eq
        yeq = np.isfinite(self.lby) & (self.lby == self.uby)
        ylo = np.isfinite(self.lby) & ~yeq
        yhi = np.isfinite(self.uby) & ~yeq
        e = np.concatenate([g[eq] - self.lbg[eq], hs, y[yeq] - self.lby[yeq]])
        i = np.concatenate([g[lo] - self.lbg[lo], self.ubg[hi] - g[hi], y[ylo] - self.lby[ylo],
                            self.uby[yhi] - y[yhi]])  # fmt: skip
        return e, i


RESTART_STATUS = {3, 5, 6, 7, 8, 9}
"""SciPy SLSQP exits after which the baseline restarts from its last point (fresh quasi-Newton
matrix) until its time limit: LSQ subproblem failures (3, 5, 6, 7), a positive directional
derivative in the line search (8) and the iteration limit (9). MATLAB's SQP, the paper's
solver, has no such early exits; without restarts SciPy's stopped early in the first stage
("More than 3*n iterations in LSQ subproblem"), which measures nothing (docs/solver.md)."""


def slsqp_solve(
    settings: PredictionSettings, seed: int = 0, max_iter: int = 200, time_limit_s: float = 600.0
) -> SolveOutcome:
    """Two-stage SLSQP (finite differences) from the same start as the default solver, restarted
    after early exits (:data:`RESTART_STATUS`) until ``time_limit_s``."""
    if settings.model.split_terms:
        raise ValueError("the SLSQP baseline solves the paper's split: split_terms must be 0")
    t0 = time.perf_counter()
    settings, scale = similarity.reference_problem(settings)  # as the default solver does
    sv = build_solver(_smooth(settings))
    z0 = initial_guess(sv, seed)
    x = np.concatenate([z0[: layout.N_X], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]])
    status, iters, stages = "not run", 0, []
    for dynamics in (False, True):
        prob = _Dense(settings, dynamics)
        bounds = [
            (None if not np.isfinite(lo) else lo, None if not np.isfinite(hi) else hi)
            for lo, hi in zip(np.r_[prob.lbx, np.full(6, -np.inf)],
                              np.r_[prob.ubx, np.full(6, np.inf)], strict=True)
        ]  # fmt: skip
        deadline = t0 + time_limit_s

        def cb(_xk, deadline=deadline):
            if time.perf_counter() > deadline:
                raise TimeoutError

        cons = [
            {"type": "eq", "fun": lambda v, p=prob: p.constraints(v)[0]},
            {"type": "ineq", "fun": lambda v, p=prob: p.constraints(v)[1]},
        ]
        restarts = 0
        while True:
            try:
                res = minimize(prob.objective, x, method="SLSQP", bounds=bounds,
                               constraints=cons, callback=cb,
                               options={"maxiter": max_iter, "ftol": 1e-6})  # fmt: skip
            except TimeoutError:
                status = "time limit reached"
                break
            x, iters = res.x, iters + res.nit
            status = "Solve_Succeeded" if res.success else str(res.message)
            if res.success or res.status not in RESTART_STATUS:
                break
            restarts += 1  # a failed QP subproblem or the iteration limit: restart from x
        stages.append({"stage": "full" if dynamics else "kinematic", "status": status,
                       "restarts": restarts, "function_evaluations": prob.evals})  # fmt: skip
        if status != "Solve_Succeeded":
            break
    return SolveOutcome(
        x=similarity.subject_x(x[: layout.N_X], scale),
        z=x,
        converged=status == "Solve_Succeeded",
        status=str(status),
        iterations=iters,
        wall_time_s=time.perf_counter() - t0,
        stages=stages,
        solver="slsqp-fd",
    )


__all__ = ["slsqp_solve"]
