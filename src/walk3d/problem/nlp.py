"""The optimization problem (paper section 2.5) in lifted form for CasADi.

Decision variables: ``z = [x (166, see layout), vec(Y) (N nodes × 78), W0 (6), vec(T) (N × 24)]``
(column-major: node k's block is contiguous). ``Y_k``: the 26 coordinates at node k with their
first and second derivatives, tied to the coefficients by ``Y_k = A_k x`` ("lifted": the Hessian
is block-diagonal per node). ``W0``: the total ground reaction at right heel strike, the
trailing foot's initial load, in body weights (moment about the left ankle, × 1 m). ``T_k``: one
slack per DoF for the criterion's absolute values (:func:`node_function`).

Nodes cover the half cycle in which the right foot is the root: ``t_k = t_hs_r + k T/(2N)``,
``k = 0..N-1``. The closed loop in double support (the trailing left foot on its own roll-over
path, half a stride behind) also joins the mirrored second half continuously. Symmetry makes the
full-cycle criterion twice the half-cycle sum. Node rows (:data:`G_ROWS`) are bounded where they
apply.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from walk3d.body.model import BodyModel
from walk3d.constants import G
from walk3d.contact import free_split
from walk3d.contact.support import foot_points, support_rows
from walk3d.contact.transition import ratio_map
from walk3d.model import terms
from walk3d.model.criteria import POWER_SCALE_W, node_terms, signed_integrands
from walk3d.model.node import node_model, objective
from walk3d.model.state import GaitState, dof_moment_terms, evaluate, strength_weights
from walk3d.problem import layout
from walk3d.problem.derivatives import NlpPieces, NodeDerivs, derivative_functions
from walk3d.problem.jerk import coefficient_weights
from walk3d.problem.schedule import (
    lifting_maps,
    loop_check_times,
    node_params,
    range_rows,
    schedule,
)
from walk3d.problem.settings import ModelSettings, PredictionSettings, ratios_for
from walk3d.problem.tracking import track_quadratic

N_Y, G_ROWS, N_G, N_T, N_P = layout.N_Y, layout.G_ROWS, layout.N_G, layout.N_T, layout.N_P
BALL_NORM_MAX = 0.97
EN_SCALE = 100.0  # C_en is divided by this in the solver's objective (J -> O(1))


def _unpack_coords(y, omega: float) -> list[tuple]:
    n = layout.N_COORD
    return [(y[i], omega * y[n + i], omega**2 * y[2 * n + i]) for i in range(n)]


def state_at(body: BodyModel, y, w0, hw, decay, anchor_x, omega: float, dynamics: bool = True,
             balance: bool = True, split_total: bool = False,
             handover=None, share=None) -> GaitState:  # fmt: skip
    """:func:`evaluate` with the right foot as root (component inputs, any backend).

    ``y`` holds values, rates / ω and accelerations / ω² (``ω = 2π/T``), so all 78 entries have
    the size of the Fourier coefficients (better conditioning for the solver). ``handover``:
    ``(h, ḣ/ω, ḧ/ω²)``, or None without the handover. ``w0``: W0 and, with the free split, its
    coefficients (:mod:`walk3d.contact.free_split`, whose basis is the handover ``share``).
    """
    wf = body.mass * G
    if len(w0) > layout.N_W0:  # the free split: the trailing foot's whole load, decay included
        w0, decay = free_split.trailing_load(w0, decay, share, w0[layout.N_W0 :]), 1.0
    w0_wrench = (tuple(w * wf for w in w0[:3]), tuple(w * wf for w in w0[3:6]))
    if handover is not None:
        handover = (handover[0], omega * handover[1], omega**2 * handover[2])
    return evaluate(body, _unpack_coords(y, omega), "r", (0.0, hw), (anchor_x, -hw), decay,
                    w0_wrench, dynamics=dynamics, balance=balance, split_total=split_total,
                    handover=handover)  # fmt: skip


def node_outputs(body: BodyModel, model: ModelSettings, st: GaitState, moments, rates):
    """Constraint rows (list of N_G) and objective terms ``[C_tor, C_en/EN_SCALE]`` per node
    (smoothed, :mod:`walk3d.model.criteria`), from the criterion's DoF ``moments`` and
    ``rates``."""
    wf = body.mass * G
    mu = model.friction

    def force_rows(w):
        f = w[0]
        return [f[1] / wf, (f[0] - mu * f[1]) / wf, (-f[0] - mu * f[1]) / wf,
                (f[2] - mu * f[1]) / wf, (-f[2] - mu * f[1]) / wf]  # fmt: skip

    q_torso = st.torso_orientation
    y_norms = [sum(jj.n_dof for jj in body.joints[:k]) for k, j in enumerate(body.joints)
               if j.kind == "ball"]  # fmt: skip
    g = (
        list(st.loop_position) + list(st.loop_orientation) + list(st.loop_velocity)
        + list(st.loop_omega) + list(st.other_points_y)
        + [st.ankle_z["l"] - st.ankle_z["r"]] + [q_torso[1], q_torso[2], q_torso[3]]
        + force_rows(st.feet["r"]) + force_rows(st.feet["l"])
        + [c / wf for c in st.hs_wrench[0]] + [c / wf for c in st.hs_wrench[1]]
    )  # fmt: skip
    a, b = strength_weights(body)
    tor, en = node_terms(moments, rates, a, b, model.smoothing)
    return g, [sum(tor), sum(en) / EN_SCALE], y_norms


def per_foot_loads(model: ModelSettings, dynamics: bool, balance: bool) -> bool:
    """Whether a stage's NLP shares the reaction between the feet and bounds each foot's part
    under that foot: the full stage, and the balance stage with ``model.balance_split``."""
    return dynamics or balance and model.balance_split


def _support(body: BodyModel, model: ModelSettings, st: GaitState, per_foot: bool):
    """Rows of :mod:`walk3d.contact.support`: root foot, then other foot, each under its own
    load when ``per_foot`` (full stage, and the balance stage with ``balance_split``).

    Otherwise (a first stage without the split between the feet) the root rows hold the *total*
    reaction under the root foot (single stance) and the other rows the total under both feet
    (double support: the box from the trailing left heel to the leading right toe, and from the
    left to the right fifth metatarsal head).
    """
    wf, mu, r = body.mass * G, model.friction, model.free_moment_radius
    pts = {s: foot_points(st.pose, body.segment_index(f"foot_{s}"), body.foot.points(s))
           for s in ("r", "l")}  # fmt: skip
    d = model.cop_margin
    rows = support_rows(st.feet["r"], pts["r"], "r", wf, mu, r, d)
    if per_foot:
        return rows + support_rows(st.feet["l"], pts["l"], "l", wf, mu, r, d)
    both = [pts["l"][0], pts["r"][1], pts["l"][3], pts["r"][3]]
    return rows + support_rows(st.total, both, "r", wf, mu, r, d)


def node_function(
    body: BodyModel,
    model: ModelSettings,
    dynamics: bool = True,
    with_hs: bool = True,
    balance: bool = True,
) -> ca.Function:
    """``walk3d_node(y[78], w0[6 + 6 K], hw, p[6], t[24]) -> (g[N_G], f[2])`` in SX,
    ``p = [decay, anchor_x, ω, h, ḣ/ω, ḧ/ω²]`` (:data:`N_P`; the handover share is read only with
    ``model.handover``).

    Criterion form (``model.absolute``):

    * ``slack`` (default): the integrand ``|u|`` is replaced by a slack ``t ≥ u⁺, t ≥ u⁻`` per
      DoF (:func:`walk3d.model.criteria.signed_integrands`), and ``f = Σ t``. This is exact at
      the optimum and smooth: the objective is linear, and the only curvature left is that of
      the moments themselves.
      (With ``sqrt(u² + ε²)`` the curvature ``1/ε`` near ``u = 0`` kept IPOPT from converging.)
    * ``smooth``: ``f`` holds the smoothed criteria of :mod:`walk3d.model.criteria`; the
      slack rows are zeros and ``t`` is unused.

    With ``dynamics=False`` (first stage) both objective terms are the mean squared joint
    coordinate rate and acceleration (scaled by ω and ω²) plus the mean squared joint coordinate
    (``sin(θ/2)``): the smoothest walking posture sequence near upright standing, found without
    inverse dynamics. (Rates alone leave constant offsets free, and the first stage then parked
    the arms at 70° of flexion.) With ``with_hs=False`` the heel-strike wrench rows are constant
    zeros: only node 0 needs them. ``balance=False`` (with ``dynamics=False``) also drops the
    total reaction: geometry only, a cheap posture stage. The criterion's moments and terms are
    the node model's (:func:`walk3d.model.node.node_model`: passive joints and other elements).
    """
    y = ca.SX.sym("y", N_Y)
    w0 = ca.SX.sym("w0", layout.N_W0 + free_split.coefficient_count(model.split_terms))
    hw = ca.SX.sym("hw")
    p = ca.SX.sym("p", N_P)
    t = ca.SX.sym("t", N_T)
    yl, w0l = [y[i] for i in range(N_Y)], [w0[i] for i in range(w0.numel())]
    per_foot = per_foot_loads(model, dynamics, balance)
    share = (p[3], p[4], p[5]) if model.handover else None
    st = state_at(body, yl, w0l, hw, p[0], p[1], p[2], dynamics, balance, per_foot, share, p[3])
    coords = _unpack_coords(yl, p[2])
    wanted = tuple(n for n in terms.extras(model.criterion) if n in terms.node_names())
    nm = node_model(body, model, coords, st, wanted) if dynamics else None
    moments, rates, _ = (nm.moments, nm.rates, nm.axes) if nm else dof_moment_terms(body, st)
    g, f, starts = node_outputs(body, model, st, moments, rates)
    if not dynamics:
        n = layout.N_COORD
        rate = sum(y[n + i] ** 2 + y[2 * n + i] ** 2 for i in range(n)) / n
        posture = sum(y[i] ** 2 for i in range(24)) / 24
        f = [rate + posture, rate + posture]
    if not with_hs:
        g[G_ROWS["hs_wrench"]] = [0.0] * 6
    for s in starts:  # |vector part|² of each ball joint stays below 1
        g.append(y[s] ** 2 + y[s + 1] ** 2 + y[s + 2] ** 2)
    if dynamics and model.absolute == "slack":
        u_pos, u_neg = signed_integrands(body, terms.base(model.criterion), moments, rates)
        g += [t[i] - u for i, u in enumerate(u_pos)] + [t[i] - u for i, u in enumerate(u_neg)]
        total = ca.sum1(t)
        f = [total, total * POWER_SCALE_W / EN_SCALE]
    else:
        g += [0.0] * (2 * N_T)
    k = criterion_row(model)
    f[k] = objective(model, f[k], nm, row_scale(model))
    g += _support(body, model, st, per_foot)
    return ca.Function("walk3d_node", [y, w0, hw, p, t], [ca.vertcat(*g), ca.vertcat(*f)])


def loop_function(body: BodyModel, model: ModelSettings) -> ca.Function:
    """``walk3d_loop(c[26], hw, anchor_x) -> loop[6]``: closed-loop position and orientation
    residuals of the other foot from the 26 coordinate values alone (no rates needed)."""
    c = ca.SX.sym("c", layout.N_COORD)
    hw, ax = ca.SX.sym("hw"), ca.SX.sym("ax")
    zero = 0.0 * c[0]
    y = [c[i] for i in range(layout.N_COORD)] + [zero] * (2 * layout.N_COORD)
    st = state_at(body, y, [zero] * 6, hw, 0.0, ax, 1.0, dynamics=False, balance=False)
    rows = list(st.loop_position) + list(st.loop_orientation)
    return ca.Function("walk3d_loop", [c, hw, ax], [ca.vertcat(*rows)])


def loop_rows(loop: ca.Function, cmap: np.ndarray, x: ca.MX, anchor_x) -> ca.MX:
    """The closed-loop checks of :func:`loop_function` at ``m`` instants between the nodes:
    ``cmap`` (m, 26, n) maps the coefficients ``x`` (n) to their coordinates; the half step
    width is ``x``'s, the other foot's anchor ``anchor_x`` (m; a number or an MX scalar)."""
    m = cmap.shape[0]
    if m == 0:
        return ca.MX(0, 1)
    c = ca.mtimes(ca.sparsify(ca.DM(cmap.reshape(-1, cmap.shape[-1]))), x)
    hw, ax = x[layout.I_HALF_STEP], ca.repmat(ca.MX(anchor_x), 1, m)
    return ca.vec(loop.map(m)(ca.reshape(c, layout.N_COORD, m), hw, ax))


def criterion_row(model: ModelSettings) -> int:
    """The row of the node function's ``f`` that the NLP minimizes: 0 for a criterion built on
    C_tor, 1 on C_en (its extra terms, :mod:`walk3d.model.terms`, are added to that row)."""
    return 0 if terms.base(model.criterion) == "tor" else 1


def row_scale(model: ModelSettings) -> float:
    """What the objective row holds per unit of the reported weighted criterion: 1 on C_tor,
    ``1 / EN_SCALE`` on C_en (that row is C_en in units of EN_SCALE J)."""
    return 1.0 if criterion_row(model) == 0 else 1.0 / EN_SCALE


def jerk_weights(settings: PredictionSettings) -> np.ndarray | None:
    """``q`` (N_X,) with the objective's jerk part ``Σ q_i x_i²`` (weight and row scale
    included), or None without a jerk term."""
    w = terms.extras(settings.model.criterion).get("jerk")
    if not w:
        return None
    return w * row_scale(settings.model) * coefficient_weights(settings.gait.period)


STAGES = {"posture": (False, False), "balance": (False, True), "full": (True, True)}
"""``(dynamics, balance)`` of the NLP of each solver stage."""


def node_name(dynamics: bool, balance: bool, with_hs: bool) -> str:
    """The name of the node function of a stage's NLP (:func:`model_functions`)."""
    return f"node_d{int(dynamics)}b{int(balance)}h{int(with_hs)}"


_NODE_FLAGS = {node_name(d, b, h): (d, b, h) for d, b in STAGES.values() for h in (True, False)}
MODEL_FUNCTIONS = ("loop", *_NODE_FLAGS)


def model_functions(
    body: BodyModel, model: ModelSettings, names: tuple[str, ...] = MODEL_FUNCTIONS
) -> dict[str, ca.Function]:
    """The SX functions the NLPs of :data:`STAGES` call, by name (``names``; default all): two
    node functions per stage (with and without the heel-strike rows) and the loop function.
    Built in Python, they are the part of a build CasADi reads back quickly, so
    :mod:`walk3d.solve.model_cache` keeps them."""
    flags = {n: None if n == "loop" else _NODE_FLAGS[n] for n in names}  # (dynamics, balance, hs)
    return {n: loop_function(body, model) if f is None else node_function(
        body, model, f[0], with_hs=f[2], balance=f[1]) for n, f in flags.items()}  # fmt: skip


@dataclass(frozen=True)
class NodeCalls:
    """The symbols of the lifted NLP and its node rows (:func:`node_calls`)."""

    node0: ca.Function
    node: ca.Function
    x: ca.MX
    ys: ca.MX
    w0: ca.MX
    ts: ca.MX
    gk: ca.MX
    fk: ca.MX
    """``g`` and ``f`` of every node, side by side."""
    hs_map: np.ndarray
    g_hs: ca.MX
    """The heel-strike tie ``R·hs − W0``."""


def node_calls(
    body: BodyModel,
    settings: PredictionSettings,
    n: int,
    params,
    dynamics: bool = True,
    balance: bool = True,
    functions: dict[str, ca.Function] | None = None,
) -> NodeCalls:
    """The variables ``x, Y, W0, T`` of ``n`` nodes and the node functions called on them with
    ``params`` (N_P × n, numbers or functions of the descriptors): node 0 alone, the others
    through one ``map``. Shared by :func:`build_nlp` and the free NLP (:mod:`.free_nlp`)."""
    fns = functions or {}

    def node_fn(with_hs: bool) -> ca.Function:
        fn = fns.get(node_name(dynamics, balance, with_hs))
        return fn or node_function(body, settings.model, dynamics, with_hs=with_hs, balance=balance)

    # without dynamics (and without the balance split) the heel-strike rows are zeros anyway: one
    # node function (and one set of derivatives to build) serves every node
    node = node_fn(False)
    node0 = node_fn(True) if per_foot_loads(settings.model, dynamics, balance) else node
    x = ca.MX.sym("x", layout.N_X)
    ys = ca.MX.sym("Y", N_Y, n)
    n_split = free_split.coefficient_count(settings.model.split_terms)
    w0 = ca.MX.sym("W0", layout.N_W0 + n_split)
    ts = ca.MX.sym("T", N_T, n)
    hw = x[layout.I_HALF_STEP]
    g0, f0 = node0(ys[:, 0], w0, hw, params[:, 0], ts[:, 0])
    rest = n - 1
    threads = settings.solver.threads
    mapped = node.map(rest, "thread", threads) if threads > 1 else node.map(rest)
    gr, fr = mapped(ys[:, 1:], ca.repmat(w0, 1, rest), ca.repmat(hw, 1, rest),
                            params[:, 1:], ts[:, 1:])  # fmt: skip
    hs_map = ratio_map(ratios_for(settings.model))  # Eqs. 7–8 for the trailing (left) foot
    g_hs = ca.mtimes(ca.DM(hs_map), g0[G_ROWS["hs_wrench"]]) - w0[: layout.N_W0]
    return NodeCalls(node0, node, x, ys, w0, ts, ca.horzcat(g0, gr), ca.horzcat(f0, fr), hs_map,
                     g_hs)  # fmt: skip


def build_nlp(
    body: BodyModel,
    settings: PredictionSettings,
    dynamics: bool = True,
    balance: bool = True,
    functions: dict[str, ca.Function] | None = None,
    node_derivs: NodeDerivs | None = None,
    node0_derivs: NodeDerivs | None = None,
    shift: bool = False,
):
    """Symbolic NLP dict ``{x, f, g}`` (MX calling the per-node SX function), its
    :class:`Schedule` and the lifting maps ``(n_nodes, 78, N_X)``.

    ``g = [lifting (n × 78), node rows (n × N_G), heel-strike wrench (6), joint-range rows,
    loop checks (6 per :func:`loop_check_times`)]``. The node function is called once through
    ``map``, so derivatives are generated once per node function. ``functions``: prebuilt SX
    functions (:func:`model_functions`, maybe from the cache); ``node_derivs``,
    ``node0_derivs``: ``(jac, grad, hess)`` of the mapped node function and of node 0's, if
    compiled (:class:`walk3d.problem.derivatives.NlpPieces`). ``shift``: a full-cycle step
    (:mod:`.full_cycle`), with ``prob["p"]`` (m) added to the other foot's anchor throughout."""
    sch = schedule(settings)
    lift = lifting_maps(settings, sch)
    a = ca.MX.sym("p", int(shift))
    params = ca.DM(node_params(settings, sch))
    params = params + ca.repmat(ca.vertcat(0, a, ca.MX(4, 1)), 1, sch.n) if shift else params
    nc = node_calls(body, settings, sch.n, params, dynamics, balance, functions)
    x, fk = nc.x, nc.fk
    lift_mat = ca.sparsify(ca.DM(lift.reshape(-1, layout.N_X)))
    g_lift = ca.vec(nc.ys) - ca.mtimes(lift_mat, x)
    crit = criterion_row(settings.model)
    if sch.weights is None:  # one weight for every node: the paper's regular grid
        weight = 2.0 * sch.step
        f = weight * ca.sum2(fk[crit, :])
    else:
        weight = 2.0 * sch.weights
        f = ca.mtimes(fk[crit, :], ca.DM(weight))
    quad = jerk_weights(settings) if dynamics else None
    if quad is not None:
        f = f + ca.dot(ca.DM(quad), x * x)
    z = ca.vertcat(x, ca.vec(nc.ys), nc.w0, ca.vec(nc.ts))
    weights = np.broadcast_to(np.asarray(weight, dtype=float), (sch.n,))
    track = track_quadratic(settings, sch.times, weights, row_scale(settings.model))
    track = track if dynamics else None
    if track is not None:
        zt = z[track.index.tolist()]
        f = f + ca.dot(ca.DM(track.q), zt * zt) + ca.dot(ca.DM(track.c), zt) + track.const
    range_np = range_rows(body, settings)[0]
    t_loop = loop_check_times(settings, sch)
    loop = (functions or {}).get("loop")
    loop = loop or (loop_function(body, settings.model) if t_loop.size else None)
    c_map = layout.coordinate_maps(t_loop, settings.gait.period)[0]
    g_loop = loop_rows(loop, c_map, x, -settings.gait.stride_length / 2 + (a if shift else 0.0))
    g = ca.vertcat(g_lift, ca.vec(nc.gk), nc.g_hs, ca.mtimes(ca.sparsify(ca.DM(range_np)), x),
                   g_loop)  # fmt: skip
    prob = {"x": z, "f": f, "g": g} | ({"p": a} if shift else {})
    if settings.solver.derivatives == "structured":
        n_split = free_split.coefficient_count(settings.model.split_terms)
        lay = layout.NlpLayout(sch.n, range_np.shape[0], g_loop.numel(), n_split=n_split)
        pieces = NlpPieces(z=z, f=f, g=g, node0=nc.node0, node=nc.node, p=a,
                           params=params if shift else np.asarray(params), lift=lift,
                           range_mat=range_np, hs_rows=G_ROWS["hs_wrench"],
                           hs_map=nc.hs_map, weight=weight, crit=crit, layout=lay,
                           g_loop=g_loop, x=x, threads=settings.solver.threads,
                           node_derivs=node_derivs, node0_derivs=node0_derivs,
                           quad=quad, track=track)  # fmt: skip
        prob["derivatives"] = derivative_functions(pieces)
    return prob, sch, lift
