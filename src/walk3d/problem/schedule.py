"""Time nodes of the half cycle and the rows stated between them (joint ranges on a finer
grid, closed-loop checks), shared by the NLP (:mod:`walk3d.problem.nlp`), its bounds and the
SLSQP baseline."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walk3d.body.changes import limited_dofs
from walk3d.body.model import BodyModel
from walk3d.contact import free_split
from walk3d.contact.phases import GaitPhases
from walk3d.model.ranges import joint_ranges
from walk3d.problem import descriptors, layout
from walk3d.problem.settings import PredictionSettings

__all__ = ["Schedule", "lifting_maps", "loop_check_times", "nlp_layout", "node_params",
           "on_phase_grid", "range_rows", "schedule"]  # fmt: skip

LIMIT_OVERSAMPLING = 4
"""Joint-limit rows per node interval for the limited DoFs of a what-if orthosis when the
joint ranges are not oversampled: the limit then holds on the reported 101-sample cycle."""


@dataclass(frozen=True, kw_only=True)
class Schedule:
    """Node times and their phase in the half cycle with the right foot as root."""

    times: np.ndarray
    double_support: np.ndarray
    swing: np.ndarray
    decay: np.ndarray
    anchor_other_x: np.ndarray
    step: float
    """Spacing of the regular grid, s."""
    weights: np.ndarray | None = None
    """Quadrature weight of each node, s, when the grid is not regular (nodes added after heel
    strike, contact checks); None: every node weighs ``step``."""
    check: np.ndarray | None = None
    """Per node, whether it is a contact check (zero weight, no slacks); None: none."""

    @property
    def checks(self) -> np.ndarray:
        """Per node, whether it is a contact check (all False without any)."""
        return np.zeros(self.n, dtype=bool) if self.check is None else self.check

    @property
    def n(self) -> int:
        return len(self.times)


def on_phase_grid(settings: PredictionSettings) -> bool:
    """Whether the nodes follow the phases (:func:`free_schedule`): with a predicted descriptor,
    or with ``settings.solver.grid`` ``phase``."""
    return bool(settings.gait.free) or settings.solver.grid == "phase"


def schedule(settings: PredictionSettings) -> Schedule:
    """Nodes ``t_k = t_hs_r + k T/(2N)``, ``k = 0..N-1``: the half cycle with the right root,
    plus ``settings.solver.heel_strike_nodes`` evenly inside the first interval.

    No node sits at the left heel strike: by symmetry its closed loop is the same condition as
    the one at node 0 (the right heel strike seen from the other foot), and stating it twice
    makes the constraints linearly dependent.

    Why extra nodes after heel strike: there the leading foot takes its load from nothing while
    the trailing foot keeps almost all of its own (the transition function starts flat), so the
    leading foot's centre of pressure is the quotient of two small, fast-changing moments; with
    the regular grid alone it left the foot by up to 3 cm × 0.2 body weight between node 0 and
    node 1 (docs/criteria.md). With extra nodes the grid is not regular, and each node weighs
    the half-width of its two intervals (the midpoint rule of a periodic grid).

    Contact checks (``settings.solver.contact_checks`` per double-support interval, appended
    after the nodes, the last one before the trailing foot's toe off): nodes whose rows hold
    as a double-support node's but that weigh nothing in the criterion. Between the nodes of
    double support the leading foot loads from nothing to most of the body weight, and its
    centre of pressure left the heel by 3 cm at 0.8 body weight there (docs/criteria.md).
    Swing checks (``settings.solver.swing_checks`` per swing interval, from toe off to the next
    heel strike, appended after them, with one at toe off) are the same in swing, with the
    swing foot above the floor: between its nodes it dipped 3.5 mm into it (docs/criteria.md).
    """
    if on_phase_grid(settings):
        return free_schedule(settings)
    ph = GaitPhases(settings.gait.period, settings.gait.double_support, settings.model.load_ramp)
    n = settings.solver.nodes
    h = settings.gait.period / (2 * n)
    tau = np.arange(n) * h
    extra = settings.solver.heel_strike_nodes
    weights = None
    if extra:
        tau = np.sort(np.concatenate([tau, h * np.arange(1, extra + 1) / (extra + 1)]))
        gaps = np.diff(np.concatenate([tau, [settings.gait.period / 2]]))
        weights = 0.5 * (gaps + np.roll(gaps, 1))
    td = settings.gait.double_support
    ds = tau <= td + 1e-9
    checks = _check_times(tau[ds], td, settings.solver.contact_checks, settings.gait.period)
    swing = _inside(np.concatenate([[td], tau[~ds], [settings.gait.period / 2]]),
                    settings.solver.swing_checks)  # fmt: skip
    swing = np.concatenate([[td], swing]) if swing.size else swing  # and toe off itself
    check = None
    if checks.size or swing.size:
        weights = np.full(tau.size, h) if weights is None else weights
        weights = np.concatenate([weights, np.zeros(checks.size + swing.size)])
        check = np.arange(weights.size) >= tau.size
        tau = np.concatenate([tau, checks, swing])
        ds = np.concatenate([ds, np.ones(checks.size, dtype=bool),
                             np.zeros(swing.size, dtype=bool)])  # fmt: skip
    half = settings.gait.stride_length / 2
    return Schedule(
        times=ph.heel_strike_r + tau,
        double_support=ds,
        swing=~ds,
        decay=np.where(ds, ph.trailing_decay(ph.heel_strike_r + tau), 0.0),
        anchor_other_x=np.where(ds, -half, half),
        step=h,
        weights=weights,
        check=check,
    )


def _check_times(tau_ds: np.ndarray, td: float, per_interval: int, period: float) -> np.ndarray:
    """``per_interval`` instants evenly inside each interval between the double-support node
    times ``tau_ds`` (s after heel strike) and from the last of them to toe off ``td``, when
    toe off is not on a node (as :func:`loop_check_times` judges it)."""
    gap = td - tau_ds[-1] > 1e-6 * period
    return _inside(np.concatenate([tau_ds, [td]]) if gap else tau_ds, per_interval)


def _inside(ends: np.ndarray, per_interval: int) -> np.ndarray:
    """``per_interval`` instants evenly inside each interval between consecutive ``ends``."""
    frac = np.arange(1, per_interval + 1) / (per_interval + 1)
    return (ends[:-1, None] + frac[None, :] * np.diff(ends)[:, None]).ravel()


def free_schedule(settings: PredictionSettings) -> Schedule:
    """The phase-following grid of :mod:`walk3d.problem.descriptors` at the settings' T and
    Td (with a free descriptor they are the first guess). Given, they fix its node times,
    weights and the trailing foot's share at each node: the problem of a predicted T and Td
    with both pinned."""
    g = settings.gait
    grid = descriptors.grid_for(settings.solver, ramp=settings.model.load_ramp)
    t_hs = GaitPhases(g.period, g.double_support).heel_strike_r
    ds = grid.double_support
    return Schedule(
        times=t_hs + np.array(grid.tau(g.period, g.double_support)),
        double_support=ds, swing=~ds, decay=grid.decay,
        anchor_other_x=grid.anchor_sign * g.stride_length / 2,
        step=g.period / (2 * (grid.n - grid.n_checks)),
        weights=np.array(grid.weights(g.period, g.double_support)),
        check=grid.check if grid.n_checks else None,
    )  # fmt: skip


def range_rows(
    body: BodyModel, settings: PredictionSettings, full: bool = False
) -> tuple[np.ndarray, ...]:
    """Joint-range rows on a grid ``range_oversampling`` × finer than the nodes: ``(R, lo, hi)``;
    ``full``: on the full-cycle problem's ``X`` over the whole cycle, not the half cycle's ``x``
    over its half (:mod:`walk3d.problem.full_cycle`).

    Joint coordinates are linear in the coefficients, so these rows cost nothing to evaluate or
    differentiate, and they keep the series inside the anatomical ranges *between* nodes too
    (with 12 nodes and ranges at the nodes only, the optimizer found gaits swinging far outside
    them in between). Off by default: with 4× oversampling the kinematic stage reported local
    infeasibility from the standing start (docs/solver.md). What-if joint limits get rows for
    their DoFs alone on a :data:`LIMIT_OVERSAMPLING` × finer grid when the ranges have none.
    """
    ph = GaitPhases(settings.gait.period, settings.gait.double_support)
    m = settings.solver.range_oversampling * settings.solver.nodes
    dofs = np.arange(24)
    if m == 0 and settings.model.changes.limits:  # an orthosis holds between the nodes too
        m = LIMIT_OVERSAMPLING * settings.solver.nodes
        dofs = np.array(sorted(limited_dofs(body, settings.model.changes.limits)))
    n_t = 2 * m if full else m
    t = ph.heel_strike_r + np.arange(n_t) * settings.gait.period / (2 * m)
    maps = layout.full_coordinate_maps if full else layout.coordinate_maps
    a0 = maps(t, settings.gait.period)[0]
    ranges = joint_ranges(body, settings.model)[dofs]
    R = a0[:, dofs, :].reshape(-1, a0.shape[2])
    lo = np.tile(np.sin(ranges[:, 0] / 2), n_t)
    hi = np.tile(np.sin(ranges[:, 1] / 2), n_t)
    return R, lo, hi


def loop_check_times(settings: PredictionSettings, sch: Schedule) -> np.ndarray:
    """Extra loop-closure instants: ``loop_checks`` evenly between consecutive double-support
    nodes, and the trailing foot's toe-off (``loop_check_toe_off``) when no node sits there.
    The loop holds exactly at the nodes; between nodes it drifted by < 0.3 mm, but in the gap
    between the last double-support node and toe-off by up to 10 mm."""
    ds = np.flatnonzero(sch.double_support & ~sch.checks)
    m = settings.solver.loop_checks
    frac = np.arange(1, m + 1) / (m + 1)
    gap = np.diff(sch.times)
    times = [sch.times[k] + f * gap[k] for k in ds[:-1] for f in frac]
    toe_off = sch.times[0] + settings.gait.double_support
    if on_phase_grid(settings):  # a node sits at toe off
        return np.array(times)
    if (
        settings.solver.loop_check_toe_off
        and toe_off - sch.times[ds[-1]] > 1e-6 * settings.gait.period
    ):
        times.append(toe_off)
    return np.array(times)


def nlp_layout(body: BodyModel, settings: PredictionSettings, sch: Schedule) -> layout.NlpLayout:
    """The blocks of the NLP's ``z`` and ``g`` on this grid (:class:`~layout.NlpLayout`)."""
    n_range = range_rows(body, settings)[0].shape[0]
    n_s = descriptors.N_S if settings.gait.free else 0
    return layout.NlpLayout(
        sch.n,
        n_range,
        6 * loop_check_times(settings, sch).size,
        n_s,
        free_split.coefficient_count(settings.model.split_terms),
    )


def node_params(settings: PredictionSettings, sch) -> np.ndarray:
    """``(N_P, n_nodes)``: each node's ``[decay, anchor_x, ω, h, ḣ/ω, ḧ/ω²]``
    (:data:`layout.N_P`; ``h`` the handover share at the node's time)."""
    omega = 2 * np.pi / settings.gait.period
    h, hd, hdd = GaitPhases(settings.gait.period, settings.gait.double_support).handover(sch.times)
    ds = sch.double_support
    h, hd, hdd = (np.where(ds, a, 0.0) for a in (h, hd, hdd))
    return np.stack([sch.decay, sch.anchor_other_x, np.full(sch.n, omega), h, hd / omega,
                     hdd / omega**2])  # fmt: skip


def lifting_maps(settings: PredictionSettings, sch) -> np.ndarray:
    """``(n_nodes, 78, N_X)`` maps from the coefficients to each node's ``Y_k`` (values, rates
    / ω, accelerations / ω²)."""
    return lifted(layout.coordinate_maps(sch.times, settings.gait.period), settings.gait.period)


def lifted(maps: tuple[np.ndarray, ...], period: float) -> np.ndarray:
    """``(n, 78, ·)``: coordinate maps ``(A0, A1, A2)`` stacked as ``Y_k`` holds them (values,
    rates / ω, accelerations / ω²)."""
    omega = 2 * np.pi / period
    return np.concatenate([maps[0], maps[1] / omega, maps[2] / omega**2], axis=1)
