"""Where a solve starts: the atlas (walk3d's own solved neighbour), another prediction (a warm
start), or standing (the paper's method, :func:`walk3d.solve.ipopt.solve`).

From the atlas or a warm start only the last stage runs, the full problem of the settings
(period and double support free when predicted): the start already walks, so the posture and
balance stages that lead from standing to walking are skipped. A start from the atlas that does
not converge, or ends crouched, is followed by the standing plan.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

import walk3d.solve.atlas as atlas
import walk3d.solve.ipopt as ipopt
from walk3d.model import terms
from walk3d.problem import descriptors, layout, similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve.ipopt import SolveOutcome, build_solver, descriptor_stage, merged, warm_stage
from walk3d.solve.plan import Stage
from walk3d.solve.progress import interruptible, raise_if_interrupted

__all__ = ["atlas_noise", "solve_from_atlas", "solve_start", "solve_warm"]


ATLAS_MAX_ITER = 120
"""Iteration limit of one start from the atlas: converged ones took 23-67 iterations; one that
had not converged by 150 still had not by 400 (docs/starts.md), and the next start is cheaper."""
ATLAS_TRIES = 3
"""Atlas starts tried before standing (:func:`walk3d.solve.atlas.candidates`)."""


def _last_stage(solver, ref: PredictionSettings, origin: str, max_iter: int | None = None) -> Stage:
    """The full problem's stage (descriptors free when predicted), titled by its ``origin``."""
    if ref.gait.free:
        stage = descriptor_stage(ref)
        what = "predicting the period and double support"
    else:
        stage = solver.plan["full"]
        what = "minimizing"
    crit = terms.label(ref.model.criterion)
    return replace(stage, title=f"from {origin}: {what} ({crit})", label=f"{origin} ({crit})",
                   max_iter=max_iter or stage.max_iter)  # fmt: skip


ATLAS_NOISE_FRACTION = 0.04
"""An atlas start's noise is this fraction of ``settings.solver.perturbation`` (±0.002 by
default): a campaign's perturbed starts then take about 48 iterations (±0.01: about 76) and
reach the same optimum (docs/starts.md)."""


def atlas_noise(seed: int, perturbation: float) -> np.ndarray:
    """Uniform noise of amplitude ``ATLAS_NOISE_FRACTION · perturbation`` on the free
    coefficients for ``seed`` ≥ 1; zero for seed 0, so that seed 0 is the atlas start itself and
    a campaign from seed 0 holds ``walk3d predict``'s start."""
    noise = np.zeros(layout.N_X)
    amplitude = ATLAS_NOISE_FRACTION * perturbation
    if seed == 0 or amplitude == 0.0:
        return noise
    rng = np.random.default_rng([seed, 7919])  # not the standing start's stream
    noise[: layout.I_HALF_STEP] = rng.uniform(-amplitude, amplitude, layout.I_HALF_STEP)
    noise[layout.fixed_zero_mask()] = 0.0
    return noise


def _usable_warm(solver, warm: dict | None) -> dict | None:
    """``warm`` (an atlas start's primal-dual point) if it fits this solver's full NLP: the same
    variables and stage rows (the double-support nodes of a given grid follow Td / T). A point
    of the paper's split starts a free split at 0 (:mod:`walk3d.contact.free_split`)."""
    if warm is None:
        return None
    lay = solver.layout
    if lay.n_split and warm["z"].size + lay.n_split == lay.n_z:
        at = lay.z("w0").start + layout.N_W0
        pad = {k: np.insert(np.asarray(warm[k], float), at, np.zeros(lay.n_split))
               for k in ("z", "lam_x")}  # fmt: skip
        warm = warm | pad
    if warm["z"].size != solver.stage_bounds("full").lbz.size:
        return None
    return warm if np.array_equal(warm["rows"], solver.stage_rows["full"]) else None


def solve_from_atlas(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome | None:
    """The full problem from the atlas's starts for ``settings``
    (:func:`walk3d.solve.atlas.candidates`, each plus :func:`atlas_noise`) until one converges
    upright; the outcome of every try, or None (with a message) when the atlas has none.
    Ctrl-C or SIGTERM stops the try it comes in and raises: no other start is tried."""
    with interruptible():
        return _from_atlas(settings, seed, method, on_stage)


def _from_atlas(settings, seed, method, on_stage) -> SolveOutcome | None:
    """:func:`solve_from_atlas`, inside its :func:`interruptible` block."""
    note = on_stage or (lambda _msg: None)
    ref, scale = similarity.reference_problem(settings)
    found, why = atlas.candidates(ref, tries=ATLAS_TRIES)
    if not found:
        note(f"starting from standing: {why}")
        return None
    noise = atlas_noise(seed, ref.solver.perturbation)
    limit = min(ATLAS_MAX_ITER, ref.solver.max_iter)
    solver = build_solver(ref, method)
    stage = _last_stage(solver, ref, "the atlas", limit)
    g = ref.gait
    outcome = None
    for k, start in enumerate(found):
        s0 = tuple(getattr(start, n) if n in g.free else getattr(g, n) for n in descriptors.NAMES)
        if k:
            note(f"the atlas start did not converge: from its entry at {start.speeds[0]:.2f} m/s")
        warm = _usable_warm(solver, start.warm) if not (noise.any() or g.free) else None
        this = warm_stage(solver, stage, start.x + noise, scale, on_stage, s0, warm)
        raise_if_interrupted()
        info = start.describe()
        if warm is None:  # the optima at other periods are used only with their multipliers
            info.pop("atlas_period_ratio", None)
        this.stages[-1].update(start="atlas", **info)
        outcome = this if outcome is None else merged(outcome, this, method)
        if this.converged:
            break
    return outcome


def solve_start(
    settings: PredictionSettings,
    seed: int = 0,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
) -> SolveOutcome:
    """Solve from ``settings.solver.start``: ``atlas`` (then standing if that fails) or
    ``standing``."""
    first = None
    if settings.solver.start == "atlas":
        first = solve_from_atlas(settings, seed, method, on_stage)
        if first is not None and first.converged:
            return first
        if first is not None and on_stage:
            on_stage("the start from the atlas did not converge: solving from standing")
    standing = ipopt.solve(settings, seed, method, on_stage)
    return standing if first is None else merged(first, standing, method)


def solve_warm(
    settings: PredictionSettings,
    x_ref: np.ndarray,
    method: str = "ipopt",
    on_stage: Callable[[str], None] | None = None,
    s0: tuple[float, float] | None = None,
    origin: str = "a neighbour",
    max_iter: int | None = None,
) -> SolveOutcome:
    """The full problem of ``settings`` from another prediction's decision vector ``x_ref``
    (the reference subject's units, ``SolveOutcome.z[:N_X]``) and descriptors ``s0`` (the
    reference subject's; default: the settings' first guess): a neighbour's solution in
    ``walk3d sweep``. ``origin`` names the start in the stage's title; ``max_iter``: the
    stage's own limit when None."""
    with interruptible():
        ref, scale = similarity.reference_problem(settings)
        solver = build_solver(ref, method)
        stage = _last_stage(solver, ref, origin, max_iter)
        outcome = warm_stage(solver, stage, x_ref, scale, on_stage, s0)
        outcome.stages[-1]["start"] = "warm"
        return outcome
