"""From a solved decision vector to the full gait cycle (a :class:`PredictedCycle`) and its
checks.

The solver only looks at the half cycle with the right foot as root; here the whole cycle is
evaluated honestly with both roots (right from its heel strike to the left heel strike, left
otherwise), so continuity at the root switches and the closed double-support loop are measured,
not assumed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.contact import free_split
from walk3d.contact.phases import GaitPhases
from walk3d.contact.transition import apply_ratios, centre_of_pressure
from walk3d.kinematics import quaternion as qt
from walk3d.kinematics.forward import point_triple, root_foot_triples, stack_q, stack_v
from walk3d.model import terms, tracking, whatif
from walk3d.model.criteria import node_terms, split_by_axis
from walk3d.model.node import node_model
from walk3d.model.ranges import joint_ranges
from walk3d.model.state import GaitState, evaluate, strength_weights
from walk3d.problem import layout
from walk3d.problem.jerk import jerk_per_dof, jerk_per_dof_full
from walk3d.problem.settings import PredictionSettings, ratios_for
from walk3d.problem.tracking import node_phases
from walk3d.results.angles import ball_joint_angles
from walk3d.results.prediction import PredictedCycle
from walk3d.results.violations import block_violations, range_excess_deg, summarize_violations


@dataclass(frozen=True)
class CycleEvaluation:
    prediction_arrays: dict
    criteria: dict
    criteria_smoothed: dict
    contact_residual_m: float
    continuity_residual_m: float
    stride_length_m: float
    step_width_m: float
    cycle_violations: dict
    """Worst constraint excess per kind on the evaluated samples (:mod:`.violations`)."""
    integrands: dict = field(default_factory=dict, repr=False)
    """Per criterion term (``C_tor``, ``C_en``, ``C_<term>``; not ``C_jerk``, which is on the
    coefficients), its exact integrand at each sample split by axis, (n, 3) per s: the
    criteria are their sums over the periodic samples times the spacing."""


def _coords(x: np.ndarray, t: np.ndarray, period: float) -> list[tuple]:
    """The 26 coordinates with their rates and accelerations at ``t``, from a half-cycle
    decision vector or a full-cycle ``X`` (:data:`walk3d.problem.layout.N_XF`)."""
    full = np.size(x) == layout.N_XF
    a0, a1, a2 = (layout.full_coordinate_maps if full else layout.coordinate_maps)(t, period)
    c0, c1, c2 = a0 @ x, a1 @ x, a2 @ x
    return [(c0[:, i], c1[:, i], c2[:, i]) for i in range(layout.N_COORD)]


def _step_shift(x: np.ndarray) -> float:
    """The full cycle's step shift ``d`` (m; :data:`walk3d.problem.layout.I_STEP_SHIFT`), 0 for
    a half-cycle vector."""
    return float(x[layout.I_STEP_SHIFT]) if np.size(x) == layout.N_XF else 0.0


def _anchors(settings: PredictionSettings, ph: GaitPhases, t: np.ndarray, root: str, x):
    """Root and other-foot anchors (x, z) for times in one root block: the right step is half
    a stride plus ``d`` (:func:`_step_shift`), the left one half a stride minus ``d``."""
    hw, d = float(x[layout.I_HALF_STEP]), _step_shift(x)
    half = settings.gait.stride_length / 2
    # times run over [0, T] (not wrapped) so that t = T continues the last stance
    p = np.asarray(t, dtype=float)
    if root == "r":
        return (0.0 * p, hw + 0.0 * p), (-half - d + 0.0 * p, -hw + 0.0 * p)
    # left root: its stance started at t_hs_l (half − d ahead) or a cycle earlier
    later = p >= ph.heel_strike_l
    ax = np.where(later, half - d, -half - d)
    return (ax, -hw + 0.0 * p), (np.where(later, 0.0, -2 * half), hw + 0.0 * p)


def _state(body, settings, ph, x, t, root, w0=None, decay=None, handover=True,
           split=None) -> GaitState:  # fmt: skip
    """The gait at times ``t`` of one root block; with the settings' handover unless
    ``handover`` is False; ``split``: the free split's coefficients ``(K, 6)`` (body weights,
    the right root's signs), None for none."""
    a_root, a_other = _anchors(settings, ph, t, root, x)
    d = ph.trailing_decay(t) if decay is None else decay
    hand = ph.handover(t)
    if split is not None and w0 is not None:  # the trailing foot's whole load, in N
        c = np.asarray(split, float) * (1.0 if root == "r" else np.array(free_split.MIRROR))
        h = np.broadcast_to(hand[0], np.shape(t))
        load = free_split.trailing_load([*w0[0], *w0[1]], d, h, (c * body.mass * G).ravel())
        w0, d = (tuple(load[:3]), tuple(load[3:])), np.ones(np.shape(t))
    share = hand if handover and settings.model.handover else None
    coords = _coords(x, t, settings.gait.period)
    return evaluate(body, coords, root, a_root, a_other, d, w0, handover=share)


def _hs_wrench(body, settings, ph, x, t_hs, root):
    """The trailing foot's load at ``root``'s heel strike (calibrated ratios applied)."""
    st = _state(body, settings, ph, x, np.array([t_hs]), root, w0=None, decay=np.ones(1))
    w0 = tuple(tuple(float(c[0]) for c in v) for v in st.hs_wrench)
    return apply_ratios(w0, ratios_for(settings.model), "l" if root == "r" else "r")


def _ball_quaternion(joint, coords) -> np.ndarray:
    v = sum(np.outer(coords[k][0], joint.axes[k]) for k in range(3))
    w = np.sqrt(np.clip(1.0 - np.sum(v * v, axis=1), 0.0, None))
    return np.column_stack([w, v])


def _joint_angles(body: BodyModel, coords: list[tuple]) -> np.ndarray:
    out, i = [], 0
    for joint in body.joints:
        c = coords[i : i + joint.n_dof]
        if joint.kind == "ball":
            out.append(ball_joint_angles(_ball_quaternion(joint, c), joint.side))
        else:
            out.append(np.column_stack([2 * np.arcsin(cc[0]) for cc in c]))
        i += joint.n_dof
    return np.concatenate(out, axis=1)


def _contact_residual(body, st: GaitState, x, t, settings, ph, mask) -> float:
    """Largest distance between the trailing foot's landmarks and their roll-over pose."""
    if not np.any(mask):
        return 0.0
    other = "l" if st.root == "r" else "r"
    i_other = body.segment_index(f"foot_{other}")
    _, a_other = _anchors(settings, ph, t, st.root, x)
    coords = _coords(x, t, settings.gait.period)
    s_other = coords[layout.I_FOOT_L if other == "l" else layout.I_FOOT_R]
    q_exp, p_exp = root_foot_triples(body, other, s_other, a_other)
    worst = 0.0
    pts = np.vstack([np.zeros(3), body.foot.points(other)])
    for p in pts:
        chain = stack_v(point_triple(st.pose, i_other, p)[0])
        expect = stack_v(qt.vadd(p_exp[0], qt.qrot(q_exp[0], tuple(p))))
        worst = max(worst, float(np.max(np.linalg.norm(chain - expect, axis=1)[mask])))
    return worst


def _track(settings: PredictionSettings, t: np.ndarray, coords: list[tuple], axes: list[int]):
    """(n, 3) the track term's integrand at the samples (:mod:`walk3d.model.tracking`), or
    None without tracking."""
    tr = settings.model.tracking
    if tr is None:
        return None
    target = tr.target(node_phases(settings, t))
    return np.column_stack(tracking.integrand(tr, [c[0] for c in coords[:24]], target, axes))


def evaluate_cycle(
    body: BodyModel,
    settings: PredictionSettings,
    x: np.ndarray,
    n_samples: int = 101,
    split: np.ndarray | None = None,
) -> CycleEvaluation:
    """Evaluate the cycle at ``n_samples`` equally spaced times from 0 to T (inclusive), from a
    half-cycle decision vector ``x`` or the full-cycle problem's ``X``
    (:mod:`walk3d.problem.full_cycle`); ``split``: the free split's coefficients ``(K, 6)``
    (``SolveOutcome.split``), None for the paper's split."""
    ph = GaitPhases(settings.gait.period, settings.gait.double_support, settings.model.load_ramp)
    T = settings.gait.period
    t = np.linspace(0.0, T, n_samples)
    right = ph.root_is_right(t)
    blocks = {"r": np.flatnonzero(right), "l": np.flatnonzero(~right)}
    w0 = {
        "r": _hs_wrench(body, settings, ph, x, ph.heel_strike_r, "r"),
        "l": _hs_wrench(body, settings, ph, x, ph.heel_strike_l, "l"),
    }
    n = len(t)
    com = np.zeros((n, 13, 3))
    ori = np.zeros((n, 13, 4))
    pelvis = np.zeros((n, 3))
    pelvis_vx = np.zeros(n)
    moments = np.zeros((n, 12, 3))
    force = np.zeros((n, 2, 3))
    mom_o = np.zeros((n, 2, 3))
    dof_m = np.zeros((n, 24))
    dof_w = np.zeros((n, 24))
    contact = 0.0
    axes = None
    extra = {name: np.zeros((n, 3)) for name in terms.node_names()}
    if whatif.weakened_dofs(body, settings.model.changes):
        extra["overload"] = np.zeros((n, 3))
    viol: list[dict[str, float]] = []
    coords = _coords(x, t, T)
    for root, idx in blocks.items():
        if idx.size == 0:
            continue
        tb = t[idx]
        st = _state(body, settings, ph, x, tb, root, w0=w0[root], split=split)
        for i in range(13):
            com[idx, i] = stack_v(st.pose.com[i][0])
            ori[idx, i] = stack_q(st.pose.orientation[i][0])
        pelvis[idx] = stack_v(st.pose.origin[0][0])
        pelvis_vx[idx] = st.pose.origin[0][1][0]
        for j in range(12):
            moments[idx, j] = stack_v(st.moments[j])
        for k, side in enumerate(("r", "l")):
            force[idx, k] = stack_v(st.feet[side][0])
            mom_o[idx, k] = stack_v(st.feet[side][1])
        nm = node_model(body, settings.model, [tuple(v[idx] for v in c) for c in coords], st)
        axes = nm.axes
        dof_m[idx] = np.column_stack([np.broadcast_to(v, tb.shape) for v in nm.moments])
        dof_w[idx] = np.column_stack([np.broadcast_to(v, tb.shape) for v in nm.rates])
        parts = nm.terms | ({} if nm.overload is None else {"overload": nm.overload})
        for name, values in parts.items():
            extra[name][idx] = np.column_stack([np.broadcast_to(v, tb.shape) for v in values])
        ds = ph.double_support_mask(tb) & (
            ph.time_since_heel_strike(tb) <= settings.gait.double_support
        )
        contact = max(contact, _contact_residual(body, st, x, tb, settings, ph, ds))
        viol.append(block_violations(body, settings.model, st, body.mass * G, ds))
    # continuity at the switch of root (left heel strike): pelvis from either root's chain
    t_sw = np.array([ph.heel_strike_l])
    p_r, p_l = (stack_v(_state(body, settings, ph, x, t_sw, r, w0=w0[r], handover=False,
                               split=split)
                        .pose.origin[0][0]) for r in ("r", "l"))  # fmt: skip
    continuity = float(np.linalg.norm(p_r - p_l))
    cop = np.zeros_like(force)
    free = np.zeros((n, 2))
    for k in range(2):
        cop[:, k], free[:, k] = centre_of_pressure(force[:, k], mom_o[:, k], min_fy=1e-6)
    a, b = strength_weights(body)
    track = _track(settings, t, coords, axes)
    periodic = slice(0, n - 1)  # t = T repeats t = 0
    dt = T / (n - 1)
    crit = {}
    for name, smooth in (("exact", None), ("smoothed", settings.model.smoothing)):
        tor, en = node_terms(list(dof_m.T), list(dof_w.T), a, b, smooth)
        tor_i = np.array([np.sum(v[periodic]) * dt for v in tor])
        en_i = np.array([np.sum(v[periodic]) * dt for v in en])
        crit[name] = {"C_tor": split_by_axis(tor_i, axes), "C_en": split_by_axis(en_i, axes)}
        if smooth is None:
            per_sample = {"C_tor": _by_axis(tor, axes, n), "C_en": _by_axis(en, axes, n)}
            per_sample |= {f"C_{k}": v for k, v in extra.items()}
            per_sample |= {} if track is None else {"C_track": track}
        for term, v in extra.items():
            crit[name][f"C_{term}"] = split_by_axis(np.sum(v[periodic], axis=0) * dt, [0, 1, 2])
        jerk = (jerk_per_dof_full if np.size(x) == layout.N_XF else jerk_per_dof)(x, T)
        crit[name]["C_jerk"] = split_by_axis(jerk, axes)
        if track is not None:
            crit[name]["C_track"] = split_by_axis(np.sum(track[periodic], axis=0) * dt, [0, 1, 2])
        if np.size(x) == layout.N_XF:  # the full cycle's unequal steps (SLA², dimensionless)
            sla = _step_shift(x) / (settings.gait.stride_length / 2)
            crit[name]["C_step_asymmetry"] = {"total": sla * sla}
        crit[name]["C_weighted"] = weighted_total(settings.model.criterion, crit[name])
    coord_angles = np.column_stack([2 * np.arcsin(np.clip(c[0], -1, 1)) for c in coords[:24]])
    violations = summarize_violations(
        viol, range_excess_deg(coord_angles, joint_ranges(body, settings.model))
    )
    arrays = {
        "time": t,
        "segment_names": body.segment_names,
        "segment_mass": np.array([s.mass for s in body.segments]),
        "segment_inertia": np.array([np.diag(s.inertia) for s in body.segments]),
        "segment_com_position": com,
        "segment_orientation": ori,
        "dof_names": body.dof_names,
        "joint_angle": _joint_angles(body, coords),
        "joint_names": tuple(j.name for j in body.joints),
        "joint_moment": moments,
        "joint_axis_active": np.array([[k in j.dof_slots for k in range(3)] for j in body.joints]),
        "grf_force": force,
        "grf_cop": cop,
        "grf_free_moment": free,
        "pelvis_position": pelvis,
    }
    return CycleEvaluation(
        prediction_arrays=arrays,
        criteria=crit["exact"],
        criteria_smoothed=crit["smoothed"],
        contact_residual_m=contact,
        continuity_residual_m=continuity,
        stride_length_m=float(np.sum(pelvis_vx[periodic]) * dt),
        step_width_m=2 * float(x[layout.I_HALF_STEP]),
        cycle_violations=violations,
        integrands=per_sample,
    )


def _by_axis(per_dof: list, axes: list[int], n: int) -> np.ndarray:
    """(n, 3) the per-DoF integrands ``per_dof`` (24 arrays) summed by axis label."""
    out = np.zeros((n, 3))
    for v, ax in zip(per_dof, axes, strict=True):
        out[:, ax] += np.broadcast_to(v, (n,))
    return out


def weighted_total(criterion: str, values: dict) -> dict:
    """The criterion as minimized: ``{"total", "weights", and per term its weighted part}`` from
    the per-term values ``values`` (``{"C_tor": {"total": ...}, ...}``)."""
    weights = terms.parse(criterion)
    parts = {k: w * values[f"C_{k}"]["total"] for k, w in weights.items()}
    if "C_overload" in values:  # weakened joints' moments over their strengths (what-if)
        parts["overload"] = values["C_overload"]["total"]
    if "C_step_asymmetry" in values:  # the full cycle's factor 1 + k SLA² (what-if)
        k_sla2 = whatif.STEP_ASYMMETRY_COST * values["C_step_asymmetry"]["total"]
        parts["step_asymmetry"] = k_sla2 * float(sum(parts.values()))
    return {"total": float(sum(parts.values())), "weights": weights, "parts": parts}


def make_prediction(arrays: dict, summary: dict) -> PredictedCycle:
    return PredictedCycle(**arrays, summary=summary)
