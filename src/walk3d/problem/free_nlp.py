"""The NLP with the descriptors ``s = [T, Td]`` among its unknowns (:mod:`.descriptors`).

The same node functions as :func:`walk3d.problem.nlp.build_nlp` (and so the same compiled
derivatives), called with parameters ``p_k(s)``, on the phase-following grid; the lifting maps,
the quadrature weights and the jerk term become functions of ``s``, and the objective is per
distance. ``z`` and ``g`` end with ``s`` and the two rows on ``Td / T`` (:mod:`.layout`).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from walk3d.body.model import BodyModel
from walk3d.problem import coupling, descriptors, layout, nlp
from walk3d.problem.derivatives import NlpPieces, NodeDerivs, derivative_functions
from walk3d.problem.schedule import schedule
from walk3d.problem.settings import PredictionSettings, ratios_for

UNSUPPORTED = ("range_oversampling", "loop_checks", "heel_strike_nodes")
"""Solver settings that must be 0 with a predicted descriptor: their rows sit at fixed times."""


def check_supported(settings: PredictionSettings) -> None:
    """Raise ValueError for settings that cannot predict a descriptor."""
    used = [name for name in UNSUPPORTED if getattr(settings.solver, name)]
    if used:
        raise ValueError(f"a predicted period or double support needs {', '.join(used)} = 0")


def build_free_nlp(
    body: BodyModel,
    settings: PredictionSettings,
    dynamics: bool = True,
    balance: bool = True,
    functions: dict[str, ca.Function] | None = None,
    node_derivs: NodeDerivs | None = None,
):
    """Symbolic NLP dict ``{x, f, g}`` with ``s`` in ``z``, its schedule (at the first guess) and
    the lifting maps there; arguments as :func:`walk3d.problem.nlp.build_nlp`."""
    check_supported(settings)
    sch = schedule(settings)
    gait = settings.gait
    grid = descriptors.free_grid(settings.solver.nodes, gait.period, gait.double_support)
    fns = functions or {}

    def node_fn(with_hs: bool) -> ca.Function:
        fn = fns.get(nlp._node_name(dynamics, balance, with_hs))
        return fn or nlp.node_function(body, settings.model, dynamics, with_hs, balance)

    node = node_fn(False)
    node0 = node_fn(True) if nlp.per_foot_loads(settings.model, dynamics, balance) else node
    n = sch.n
    x = ca.MX.sym("x", layout.N_X)
    ys = ca.MX.sym("Y", nlp.N_Y, n)
    w0 = ca.MX.sym("W0", 6)
    ts = ca.MX.sym("T", nlp.N_T, n)
    s = ca.MX.sym("s", descriptors.N_S)
    hw = x[layout.I_HALF_STEP]
    lift_fn = descriptors.lift_function(grid)
    g_lift = ca.vec(ys) - lift_fn(x, s)
    consts = coupling.node_constants(grid, gait.speed, gait.period)
    params = ca.horzcat(*(coupling.params_of(consts[:, k], s) for k in range(n)))
    weights = ca.vertcat(*(coupling.weight_of(consts[:, k], s) for k in range(n)))
    g0, f0 = node0(ys[:, 0], w0, hw, params[:, 0], ts[:, 0])
    threads = settings.solver.threads
    mapped = node.map(n - 1, "thread", threads) if threads > 1 else node.map(n - 1)
    gr, fr = mapped(ys[:, 1:], ca.repmat(w0, 1, n - 1), ca.repmat(hw, 1, n - 1),
                    params[:, 1:], ts[:, 1:])  # fmt: skip
    gk, fk = ca.horzcat(g0, gr), ca.horzcat(f0, fr)
    hs_map = nlp._hs_map(ratios_for(settings.model))
    g_hs = ca.mtimes(ca.DM(hs_map), g0[nlp.G_ROWS["hs_wrench"]]) - w0
    crit = nlp.criterion_row(settings.model)
    quad = nlp.jerk_weights(settings) if dynamics else None
    jerk = descriptors.jerk_function(quad, gait.period)
    f = ca.mtimes(fk[crit, :], weights) + jerk(x, s)
    z = ca.vertcat(x, ca.vec(ys), w0, ca.vec(ts), s)
    g = ca.vertcat(g_lift, ca.vec(gk), g_hs, descriptors.fraction_rows(s))
    prob = {"x": z, "f": f, "g": g}
    lift = nlp.lifting_maps(settings, sch)
    if settings.solver.derivatives == "structured":
        free = coupling.FreeCoupling(
            x=x, s=s, consts=consts, couple0=coupling.node_coupling(node0, crit),
            couple=coupling.node_coupling(node, crit),
            xs=coupling.coefficient_coupling(lift_fn, jerk), threads=threads,
        )  # fmt: skip
        lay = layout.NlpLayout(n, 0, 0, descriptors.N_S)
        pieces = NlpPieces(z=z, f=f, g=g, node0=node0, node=node, params=params, lift=lift,
                           range_mat=np.zeros((0, layout.N_X)), hs_rows=nlp.G_ROWS["hs_wrench"],
                           hs_map=hs_map, weight=weights, crit=crit, layout=lay,
                           g_loop=ca.MX(0, 1), x=x, threads=threads, node_derivs=node_derivs,
                           free=free)  # fmt: skip
        prob["derivatives"] = derivative_functions(pieces)
    return prob, sch, lift
