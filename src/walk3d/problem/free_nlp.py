"""The NLP with the descriptors ``s = [T, Td]`` among its unknowns (:mod:`.descriptors`).

The same node functions as :func:`walk3d.problem.nlp.build_nlp` (and so the same compiled
derivatives), called with parameters ``p_k(s)``, on the phase-following grid; the lifting maps,
the quadrature weights and the jerk term become functions of ``s``, and the objective is per
distance. ``z`` and ``g`` end with ``s`` and the two rows on ``Td / T`` (:mod:`.layout`).
"""

from __future__ import annotations

import casadi as ca

from walk3d.body.model import BodyModel
from walk3d.contact import free_split
from walk3d.problem import coupling, descriptors, layout, nlp
from walk3d.problem.derivatives import NlpPieces, NodeDerivs, derivative_functions
from walk3d.problem.schedule import lifting_maps, range_rows, schedule
from walk3d.problem.settings import PredictionSettings

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
    node0_derivs: NodeDerivs | None = None,
):
    """Symbolic NLP dict ``{x, f, g}`` with ``s`` in ``z``, its schedule (at the first guess) and
    the lifting maps there; arguments as :func:`walk3d.problem.nlp.build_nlp`."""
    check_supported(settings)
    sch = schedule(settings)
    gait = settings.gait
    grid = descriptors.grid_for(settings.solver, ramp=settings.model.load_ramp)
    n = sch.n
    s = ca.MX.sym("s", descriptors.N_S)
    consts = coupling.node_constants(grid, gait.speed, gait.period)
    params = ca.horzcat(*(coupling.params_of(consts[:, k], s) for k in range(n)))
    weights = ca.vertcat(*(coupling.weight_of(consts[:, k], s) for k in range(n)))
    nc = nlp.node_calls(body, settings, n, params, dynamics, balance, functions)
    x = nc.x
    lift_fn = descriptors.lift_function(grid)
    g_lift = ca.vec(nc.ys) - lift_fn(x, s)
    threads = settings.solver.threads
    crit = nlp.criterion_row(settings.model)
    quad = nlp.jerk_weights(settings) if dynamics else None
    jerk = descriptors.jerk_function(quad, gait.period)
    f = ca.mtimes(nc.fk[crit, :], weights) + jerk(x, s)
    z = ca.vertcat(x, ca.vec(nc.ys), nc.w0, ca.vec(nc.ts), s)
    # joint-range rows (what-if limits): a dense half cycle of fixed phases, those of the first
    # guess; with the limits on both sides (a one-sided change solves the full cycle), any half
    # cycle of phases covers each joint's whole cycle by symmetry
    range_np = range_rows(body, settings)[0]
    g = ca.vertcat(g_lift, ca.vec(nc.gk), nc.g_hs, ca.mtimes(ca.sparsify(ca.DM(range_np)), x),
                   descriptors.fraction_rows(s))  # fmt: skip
    prob = {"x": z, "f": f, "g": g}
    lift = lifting_maps(settings, sch)
    if settings.solver.derivatives == "structured":
        free = coupling.FreeCoupling(
            x=x, s=s, consts=consts, couple0=coupling.node_coupling(nc.node0, crit),
            couple=coupling.node_coupling(nc.node, crit),
            xs=coupling.coefficient_coupling(lift_fn, jerk), threads=threads,
        )  # fmt: skip
        n_split = free_split.coefficient_count(settings.model.split_terms)
        lay = layout.NlpLayout(n, range_np.shape[0], 0, descriptors.N_S, n_split)
        pieces = NlpPieces(z=z, f=f, g=g, node0=nc.node0, node=nc.node, params=params, lift=lift,
                           range_mat=range_np, hs_rows=nlp.G_ROWS["hs_wrench"],
                           hs_map=nc.hs_map, weight=weights, crit=crit, layout=lay,
                           g_loop=ca.MX(0, 1), x=x, threads=threads, node_derivs=node_derivs,
                           node0_derivs=node0_derivs, free=free)  # fmt: skip
        prob["derivatives"] = derivative_functions(pieces)
    return prob, sch, lift
