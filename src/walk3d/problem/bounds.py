"""Bounds of the lifted NLP (:mod:`walk3d.problem.nlp`): variables ``z`` and rows ``g``.

Per stage: the posture stage bounds only geometry, the balance stage adds the total reaction
rows, the full stage every row (joint loads, slacks, both feet's support).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.contact import free_split
from walk3d.model import whatif
from walk3d.model.ranges import joint_ranges
from walk3d.problem import descriptors, layout
from walk3d.problem.nlp import BALL_NORM_MAX, G_ROWS, N_G, N_T, N_Y, per_foot_loads
from walk3d.problem.schedule import Schedule, loop_check_times, range_rows
from walk3d.problem.settings import PredictionSettings


@dataclass(frozen=True)
class Bounds:
    lbz: np.ndarray
    ubz: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray


def bounded_rows(b: Bounds) -> np.ndarray:
    """The constraint rows with a finite bound: the only ones a solver stage sees
    (:func:`walk3d.problem.derivatives.select_rows` says why)."""
    return np.flatnonzero(np.isfinite(b.lbg) | np.isfinite(b.ubg))


def _coord_bounds(
    body: BodyModel, settings: PredictionSettings, sch: Schedule
) -> tuple[np.ndarray, np.ndarray]:
    n_nodes = sch.n
    lo = np.full((n_nodes, 3, layout.N_COORD), -np.inf)
    hi = np.full((n_nodes, 3, layout.N_COORD), np.inf)
    ranges = joint_ranges(body, settings.model)
    lo[:, 0, :24] = np.sin(ranges[:, 0] / 2)
    hi[:, 0, :24] = np.sin(ranges[:, 1] / 2)
    s_up, s_down = np.sin(np.radians(40) / 2), np.sin(np.radians(-75) / 2)
    r, lft = layout.I_FOOT_R, layout.I_FOOT_L
    ds, sw = sch.double_support, sch.swing
    # right foot (root): heel rocker in double support, flat in single stance
    lo[ds, 0, r], hi[ds, 0, r] = 0.0, s_up
    # (a 5th-order series cannot vanish over a whole interval: "flat" means within a tolerance)
    flat = np.sin(settings.model.foot_flat_tolerance / 2)
    lo[sw, 0, r], hi[sw, 0, r] = -flat, flat
    rise = whatif.heel_rise(settings.model)
    if rise is not None:  # the forefoot rocker: toes down from heel rise to toe off
        g = settings.gait
        late = sw & (sch.times - sch.times[0] >= rise * (g.period / 2 + g.double_support))
        lo[late, 0, r] = s_down
    # left foot: toe rocker while trailing, heel first at its strike, unused in swing
    lo[ds, 0, lft], hi[ds, 0, lft] = s_down, 0.0
    lo[sw, 0, lft], hi[sw, 0, lft] = s_down, s_up
    return lo.reshape(n_nodes, -1), hi.reshape(n_nodes, -1)


def bounds(
    body: BodyModel,
    settings: PredictionSettings,
    sch: Schedule,
    dynamics: bool = True,
    balance: bool = True,
    free: bool = False,
) -> Bounds:
    """Bounds on ``z`` and ``g``. Slacks are fixed at 0 when unused (kinematic stage, smooth
    criterion form) and free otherwise (``t ≥ u±`` bounds them below). For the kinematic
    stage, ``balance=False`` leaves the total-reaction rows (force, friction, COP) unbounded:
    a purely geometric first pass. With predicted descriptors (``settings.gait.free``) ``s`` is
    pinned at the first guess unless ``free``."""
    n_nodes = sch.n
    slack = dynamics and settings.model.absolute == "slack"
    per_foot = per_foot_loads(settings.model, dynamics, balance)
    # x: symmetry-fixed coefficients, half step width
    lbx = np.full(layout.N_X, -np.inf)
    ubx = np.full(layout.N_X, np.inf)
    fixed = layout.fixed_zero_mask()
    lbx[fixed], ubx[fixed] = 0.0, 0.0
    # half step width, m: loose bounds; solve() uses the reference stature's problem, so for a
    # subject they are 0.02-0.25 m times h / 1.77 m (walk3d.problem.similarity)
    lbx[layout.I_HALF_STEP], ubx[layout.I_HALF_STEP] = 0.02, 0.25
    ylo, yhi = _coord_bounds(body, settings, sch)
    t_lo, t_hi = (-np.inf, np.inf) if slack else (0.0, 0.0)
    weighted_node = np.repeat(~sch.checks, N_T)  # a check node's slacks are unused: 0
    t_lo, t_hi = np.where(weighted_node, t_lo, 0.0), np.where(weighted_node, t_hi, 0.0)
    n_split = free_split.coefficient_count(settings.model.split_terms)
    lbz = np.concatenate([lbx, ylo.ravel(), np.full(layout.N_W0 + n_split, -np.inf), t_lo])
    ubz = np.concatenate([ubx, yhi.ravel(), np.full(layout.N_W0 + n_split, np.inf), t_hi])

    glo = np.full((n_nodes, N_G), -np.inf)
    ghi = np.full((n_nodes, N_G), np.inf)
    R = G_ROWS
    loop = np.r_[R["loop_position"], R["loop_orientation"]]
    for k in range(n_nodes):
        if sch.double_support[k]:
            tol = settings.model.loop_tolerance
            if sch.checks[k]:  # as the loop checks between nodes
                tol = max(tol, settings.solver.loop_check_tolerance)
            glo[k, loop], ghi[k, loop] = 0.0 - tol, tol
        if sch.swing[k]:  # a swing check, close to toe off or heel strike: the floor
            glo[k, R["other_points_y"]] = 0.0 if sch.checks[k] else settings.model.swing_clearance
        elif settings.solver.swing_checks and _at_toe_off(settings, sch, k):
            glo[k, R["other_points_y"]] = 0.0
        if per_foot and sch.double_support[k]:  # (constant zero rows in the first stage:
            # bounding them would pin IPOPT's slacks at their bounds)
            glo[k, R["other_force"].start] = 0.0
            ghi[k, R["other_force"].start + 1 : R["other_force"].stop] = 0.0
        ghi[k, R["ankle_separation"]] = -settings.model.min_ankle_separation
        glo[k, R["torso"]] = np.sin(body.torso_range[:, 0] / 2)
        ghi[k, R["torso"]] = np.sin(body.torso_range[:, 1] / 2)
        weighted = dynamics or balance
        if k > 0 and weighted:  # at heel strike (node 0) the root foot is unloaded
            glo[k, R["root_force"].start] = 0.0
            ghi[k, R["root_force"].start + 1 : R["root_force"].stop] = 0.0
        glo[k, R["ball_norm"]], ghi[k, R["ball_norm"]] = 0.0, BALL_NORM_MAX
        if slack and not sch.checks[k]:
            glo[k, R["slack_pos"]] = glo[k, R["slack_neg"]] = 0.0
        if per_foot and k > 0 or not dynamics and balance and sch.swing[k]:
            glo[k, R["root_support"]] = 0.0
        if per_foot and sch.double_support[k]:
            glo[k, R["other_support"]] = 0.0
        if not per_foot and balance and sch.double_support[k]:  # total COP under both feet
            glo[k, R["other_support"].start : R["other_support"].start + 4] = 0.0
    n_lift = n_nodes * N_Y
    _, rlo, rhi = range_rows(body, settings)
    n_loop = 6 * loop_check_times(settings, sch).size
    tol = np.full(n_loop, settings.solver.loop_check_tolerance)
    lbg = np.concatenate([np.zeros(n_lift), glo.ravel(), np.zeros(6), rlo, -tol])
    ubg = np.concatenate([np.zeros(n_lift), ghi.ravel(), np.zeros(6), rhi, tol])
    n_s = 0
    if settings.gait.free:  # s = [T, Td]
        n_s = descriptors.N_S
        g = settings.gait
        slo, shi = descriptors.descriptor_bounds(g.free, g.period, g.double_support,
                                                 pinned=not free)  # fmt: skip
        lbz, ubz = np.concatenate([lbz, slo]), np.concatenate([ubz, shi])
        lbg, ubg = np.concatenate([lbg, np.zeros(n_s)]), np.concatenate([ubg, np.full(n_s, np.inf)])
    lay = layout.NlpLayout(n_nodes, rlo.size, n_loop, n_s, n_split)
    assert (lbz.size, lbg.size) == (lay.n_z, lay.n_g), "bounds out of the layout's blocks"
    return Bounds(lbz, ubz, lbg, ubg)


def _at_toe_off(settings: PredictionSettings, sch: Schedule, k: int) -> bool:
    """Whether node ``k`` sits at the trailing foot's toe off (the phase grid has one there),
    where that foot is about to swing and its landmarks must be above the floor too."""
    g = settings.gait
    return abs(sch.times[k] - sch.times[0] - g.double_support) < 1e-9 * g.period
