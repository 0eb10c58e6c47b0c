"""Exact first and second derivatives of the lifted NLP, assembled from per-node functions.

CasADi differentiates the MX problem of :func:`walk3d.problem.nlp.build_nlp` itself by sweeping
directional derivatives through the mapped node function. That is exact but several times
slower per call than the route below, which is the default (``derivatives="structured"``;
docs/solver.md). The NLP's structure makes this cheaper route exact too:

* node k's rows depend only on its own variables ``v_k = [Y_k (78), W0 (6), half step width,
  T_k (24)]`` (:data:`N_V` = 109; a free split's ``6 K`` coefficients follow W0), so its
  Jacobian ``J_k`` and Lagrangian Hessian ``H_k`` are small SX functions of ``v_k``, generated
  once per node function and mapped over the nodes;
* every other row (the lifting ``Y_k = A_k x``, the heel-strike tie ``R·hs - W0``, the joint
  ranges) is linear, and adds constants to the Jacobian and nothing to the Hessian; only the
  optional loop checks (functions of ``x`` alone) are left to CasADi;
* the global nonzeros are then a constant scatter-add of the node nonzeros: ``H = Σ_k P_kᵀ H_k
  P_k`` (upper triangle in the order of ``z``), ``J = [..., J_k P_k, ...]``.

The values equal CasADi's own derivatives (``tests/problem/test_problem_derivatives.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from walk3d.problem import coupling, layout
from walk3d.problem.scatter import Scatter, per_node, triplets

N_Y, N_T = layout.N_Y, layout.N_T
NodeDerivs = tuple[ca.Function, ca.Function, ca.Function | list[ca.Function]]
"""``(jac, grad, hess)`` of a node function; ``hess`` maybe as its column blocks."""


@dataclass(frozen=True, kw_only=True)
class NlpPieces:
    """What :func:`walk3d.problem.nlp.build_nlp` hands over to assemble the derivatives."""

    z: ca.MX
    f: ca.MX
    g: ca.MX
    node0: ca.Function
    node: ca.Function
    params: np.ndarray | ca.MX
    """(N_P, n) node parameters (:data:`walk3d.problem.layout.N_P`); functions of the
    descriptors ``s`` when they are unknowns."""
    lift: np.ndarray
    """(n, 78, N_X) lifting maps."""
    range_mat: np.ndarray
    hs_rows: slice
    hs_map: np.ndarray
    """(6, 6) linear map from the heel-strike rows of node 0 to the trailing foot's load."""
    weight: float | np.ndarray | ca.MX
    """Objective = ``Σ_k weight_k · f_k[crit]`` (one weight for every node, or one per node,
    maybe functions of ``s``)."""
    crit: int
    layout: layout.NlpLayout
    """The blocks of ``z`` and ``g``."""
    g_loop: ca.MX
    x: ca.MX
    threads: int = 1
    """Threads for the mapped node derivatives (``settings.solver.threads``)."""
    quad: np.ndarray | None = None
    track: Any = None
    """The track term's quadratic on ``z`` (:class:`walk3d.problem.tracking.Quadratic`), or
    None."""
    """(N_X,) ``q`` of an objective part ``Σ q_i x_i²`` on the coefficients (the jerk term),
    or None."""
    free: coupling.FreeCoupling | None = None
    """The descriptors' part when ``s = [T, Td]`` are unknowns (:mod:`walk3d.problem.coupling`)."""
    node_derivs: NodeDerivs | None = None
    """``(jac, grad, hess)`` of the mapped node function, if built elsewhere (compiled C, from
    :func:`derivative_chunks`; ``hess`` may be the list of its column blocks, then mapped by
    :func:`map_blocks`); None builds them here with :func:`node_derivatives`."""
    node0_derivs: NodeDerivs | None = None
    """The same of node 0's function (with the heel-strike rows; compiled), or None."""
    p: ca.MX | None = None
    """The NLP's parameter ``p`` that ``params`` and ``g_loop`` may depend on (the derivative
    functions' second input); None: none (size 0)."""


def node_symbols(node: ca.Function, crit: int):
    """SX inputs and expressions of ``node``: ``(v, p, sf, lam_g, g, f[crit])``; the
    Lagrangian is ``sf·f[crit] + lam_gᵀ g``."""
    y, w0, hw, p, t = (node.sx_in(i) for i in range(5))
    g, f = node(y, w0, hw, p, t)
    lam_g = ca.SX.sym("lam_g", g.numel())
    return ca.vertcat(y, w0, hw, t), p, ca.SX.sym("sf"), lam_g, g, f[crit]


def node_derivatives(node: ca.Function, crit: int) -> tuple[ca.Function, ...]:
    """Node k's constraint Jacobian, objective gradient and Lagrangian Hessian in ``v_k``
    (separate functions: an MX call evaluates every output of the function it calls).
    Signatures: ``jac(v, p)``, ``grad(v, p)``, ``hess(v, p, sf, lam_g)``."""
    v, p, sf, lam_g, g, fc = node_symbols(node, crit)
    jac = ca.Function("walk3d_node_jac", [v, p], [ca.jacobian(g, v)])
    hess = ca.hessian(sf * fc + ca.dot(lam_g, g), v)[0]
    return jac, node_gradient(node, crit), ca.Function("walk3d_node_hess", [v, p, sf, lam_g],
                                                       [hess])  # fmt: skip


def with_rows(derivs: NodeDerivs, node0: ca.Function, crit: int, rows: slice) -> NodeDerivs:
    """Node 0's ``(jac, grad, hess)`` from the other nodes' ``derivs``: node 0's function is
    theirs with the heel-strike ``rows`` filled in (zeros there), so only those rows'
    derivatives are new. Why: their Hessian takes a quarter of the time of node 0's whole one
    (0.4 s against 1.9 s), and a first prediction builds both."""
    jn, dn, hn = derivs
    v, p, sf, lam_g, g, _ = node_symbols(node0, crit)
    g_rows, lam_rows = g[rows.start : rows.stop], lam_g[rows.start : rows.stop]
    j_rows = ca.SX(g.numel(), v.numel())
    j_rows[rows.start : rows.stop, :] = ca.jacobian(g_rows, v)
    h_rows = ca.hessian(ca.dot(lam_rows, g_rows), v)[0]
    vm, pm = ca.MX.sym("v", v.sparsity()), ca.MX.sym("p", p.sparsity())
    sfm, lm = ca.MX.sym("sf"), ca.MX.sym("lam_g", lam_g.sparsity())
    jac_rows = ca.Function("walk3d_node0_rows_jac", [v, p], [j_rows])
    hess_rows = ca.Function("walk3d_node0_rows_hess", [v, p, lam_g], [h_rows])
    jac = ca.Function("walk3d_node0_jac", [vm, pm], [jn(vm, pm) + jac_rows(vm, pm)])
    hess = ca.Function("walk3d_node0_hess", [vm, pm, sfm, lm],
                       [hn(vm, pm, sfm, lm) + hess_rows(vm, pm, lm)])  # fmt: skip
    return jac, dn, hess


def node_gradient(node: ca.Function, crit: int) -> ca.Function:
    """``grad(v, p)``: the gradient of the node's criterion term (small)."""
    v, p, _, _, _, fc = node_symbols(node, crit)
    return ca.Function("walk3d_node_grad", [v, p], [ca.gradient(fc, v)])


def derivative_chunks(
    node: ca.Function, crit: int, chunks: int = 8, prefix: str = "walk3d_node"
) -> dict[str, list[ca.Function]]:
    """The node Jacobian and Lagrangian Hessian as ``chunks`` SX functions each, every one a
    block of columns (``jacobian(·, v[c0:c1])``), named ``<prefix>_jac_<i>`` and
    ``<prefix>_hess_<i>``, with the signatures of :func:`node_derivatives`.

    Why: to compile them to C (:mod:`walk3d.solve.compiled`). The full stage's node Hessian
    (about 1.7 million SX instructions) does not compile as one C function in reasonable time
    and memory; 8 column blocks compile in minutes (docs/solver.md, "Compiled derivatives").
    :func:`assemble` joins the blocks back; the values are those of :func:`node_derivatives`
    (tested)."""
    v, p, sf, lam_g, g, fc = node_symbols(node, crit)
    grad = ca.gradient(sf * fc + ca.dot(lam_g, g), v)
    edges = np.linspace(0, v.numel(), chunks + 1).astype(int)
    out: dict[str, list[ca.Function]] = {"jac": [], "hess": []}
    for i, (c0, c1) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        cols = v[int(c0) : int(c1)]
        out["jac"].append(ca.Function(f"{prefix}_jac_{i}", [v, p], [ca.jacobian(g, cols)]))
        out["hess"].append(ca.Function(f"{prefix}_hess_{i}", [v, p, sf, lam_g],
                                       [ca.jacobian(grad, cols)]))  # fmt: skip
    return out


def assemble(blocks: list[ca.Function], name: str) -> ca.Function:
    """One function from column blocks (:func:`derivative_chunks`, maybe compiled): the same
    inputs, the blocks' outputs side by side."""
    first = blocks[0]
    args = [ca.MX.sym(first.name_in(i), first.sparsity_in(i)) for i in range(first.n_in())]
    return ca.Function(name, args, [ca.horzcat(*(b(*args) for b in blocks))])


def map_blocks(blocks: list[ca.Function], n: int, threads: int = 1) -> ca.Function:
    """``assemble(blocks).map(n)``, evaluated block by block: each block over all ``n``
    nodes, then the nodes' columns put side by side (the same output, bit for bit).

    Why: compiled, each Hessian block of the full stage is about 4 MB of straight-line
    machine code. Node by node, the 8 blocks evict each other's code from the CPU cache; block
    by block, each block's code stays there, and the mapped Hessian is markedly faster
    (docs/solver.md, "Compiled derivatives"). The Jacobian blocks are small: there the extra
    slicing costs more than it saves, so they are mapped node by node."""
    first = blocks[0]
    args = [ca.MX.sym(first.name_in(i), ca.repmat(first.sparsity_in(i), 1, n))
            for i in range(first.n_in())]  # fmt: skip
    outs = [(b.map(n, "thread", threads) if threads > 1 else b.map(n))(*args) for b in blocks]
    width = [b.size2_out(0) for b in blocks]
    cols = [o[:, k * w : (k + 1) * w] for k in range(n) for o, w in zip(outs, width, strict=True)]
    return ca.Function(f"map{n}_blocks_{first.name()}", args, [ca.horzcat(*cols)])


def derivative_functions(pc: NlpPieces) -> dict[str, ca.Function]:
    """``grad_f``, ``jac_g`` and ``hess_lag`` for ``ca.nlpsol`` (its option names)."""
    lay = pc.layout
    n = lay.nodes
    z, n_z, n_g = pc.z, pc.z.numel(), pc.g.numel()
    assert (n_z, n_g) == (lay.n_z, lay.n_g), "the NLP does not have the layout's blocks"
    p = ca.MX.sym("p", 0) if pc.p is None else pc.p
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", n_g)
    cols = [lay.node_columns(k) for k in range(n)]
    v0 = z[cols[0].tolist()]
    vr = ca.reshape(z[np.concatenate(cols[1:]).tolist()], lay.n_v, n - 1)
    same = pc.node0 is pc.node
    # one thread: CasADi's symbolic operations are not thread-safe (two Hessians built at once
    # crashed; docs/solver.md, "Symbolics in one thread")
    jn, dn, hn = pc.node_derivs or node_derivatives(pc.node, pc.crit)
    h_one = assemble(hn, "walk3d_node_hess") if isinstance(hn, list) else hn  # one node
    if same:
        j0, d0, h0 = jn, dn, h_one
    elif pc.node0_derivs is not None:
        j0, d0, h0 = pc.node0_derivs
        h0 = assemble(h0, "walk3d_node0_hess") if isinstance(h0, list) else h0
    elif isinstance(hn, ca.Function):
        j0, d0, h0 = with_rows((jn, dn, hn), pc.node0, pc.crit, pc.hs_rows)
    else:
        j0, d0, h0 = node_derivatives(pc.node0, pc.crit)
    params = pc.params if isinstance(pc.params, ca.MX) else ca.DM(pc.params)
    pr, p0 = params[:, 1:], params[:, 0]

    def mapped(fn: ca.Function | list[ca.Function]) -> ca.Function:
        if isinstance(fn, list):  # column blocks (compiled)
            return map_blocks(fn, n - 1, pc.threads)
        return fn.map(n - 1, "thread", pc.threads) if pc.threads > 1 else fn.map(n - 1)

    J0, Jr = j0(v0, p0), mapped(jn)(vr, pr)
    gf0, gfr = d0(v0, p0), mapped(dn)(vr, pr)

    # Jacobian rows: the g blocks of the layout
    jac = Scatter((n_g, n_z))
    if pc.free is None:  # otherwise the lifting depends on s (coupling.add_free)
        lift = pc.lift.reshape(-1, layout.N_X)
        lr, lc = np.nonzero(lift)
        jac.add_const(lr, lc, -lift[lr, lc])
    n_y = n * N_Y
    jac.add_const(lay.g("lift").start + np.arange(n_y), lay.z("y").start + np.arange(n_y),
                  np.ones(n_y))  # fmt: skip
    off = lay.g("node").start
    for k, (nz, r, c) in enumerate(per_node(J0, Jr, jn.sparsity_out(0), n)):
        jac.add(nz, off + k * layout.N_G + r, cols[k][c])
    off = lay.g("hs").start
    j_hs = ca.mtimes(ca.DM(pc.hs_map), J0[pc.hs_rows.start : pc.hs_rows.stop, :])
    rh, ch = triplets(j_hs.sparsity())
    jac.add(j_hs.nz[:], off + rh, cols[0][ch])
    jac.add_const(off + np.arange(6), lay.z("w0").start + np.arange(6), -np.ones(6))
    off = lay.g("range").start
    rg, cg = np.nonzero(pc.range_mat)
    jac.add_const(off + rg, cg, pc.range_mat[rg, cg])
    off = lay.g("loop").start
    lam_loop = lam_g[off:]
    hess_extra = None
    if pc.g_loop.numel():
        j_loop = ca.jacobian(pc.g_loop, pc.x)
        rl, cl = triplets(j_loop.sparsity())
        jac.add(j_loop.nz[:], off + rl, cl)
        hess_extra = ca.triu(ca.hessian(ca.dot(lam_loop, pc.g_loop), pc.x)[0])

    # gradient of the objective
    grad = Scatter((n_z, 1))
    uniform = not isinstance(pc.weight, ca.MX) and np.ndim(pc.weight) == 0
    w = (pc.weight if isinstance(pc.weight, ca.MX)
         else ca.DM(np.broadcast_to(np.asarray(pc.weight, dtype=float), (n,))))  # fmt: skip
    for k, (nz, r, _) in enumerate(per_node(gf0, gfr, dn.sparsity_out(0), n)):
        grad.add((pc.weight if uniform else w[k]) * nz, cols[k][r], np.zeros(len(r), dtype=int))
    grad.add_const(np.arange(n_z), np.zeros(n_z, dtype=int), np.zeros(n_z))
    iq = np.flatnonzero(pc.quad) if pc.quad is not None else np.zeros(0, dtype=int)
    if iq.size:
        grad.add(2 * ca.DM(pc.quad[iq]) * pc.x[iq.tolist()], iq, np.zeros(iq.size, dtype=int))
    tq = pc.track
    if tq is not None:
        zt = pc.z[tq.index.tolist()]
        grad.add(2 * ca.DM(tq.q) * zt + ca.DM(tq.c), tq.index, np.zeros(tq.index.size, dtype=int))

    # Hessian of the Lagrangian: node 0 also carries the heel-strike rows (through hs_map)
    rows_nodes, rows_hs = lay.g("node"), lay.g("hs")
    lam_nodes = ca.reshape(lam_g[rows_nodes.start : rows_nodes.stop], layout.N_G, n)
    lam_hs = lam_g[rows_hs.start : rows_hs.stop]
    hs = pc.hs_rows
    lam0 = lam_nodes[:, 0] + ca.vertcat(
        ca.MX(hs.start, 1), ca.mtimes(ca.DM(pc.hs_map).T, lam_hs), ca.MX(layout.N_G - hs.stop, 1)
    )
    if uniform:
        sf = pc.weight * lam_f
        sf0, sfr = sf, ca.repmat(sf, 1, n - 1)
    else:
        sf0, sfr = w[0] * lam_f, ca.reshape(w[1:], 1, n - 1) * lam_f
    H0 = h0(v0, p0, sf0, lam0)
    Hr = mapped(hn)(vr, pr, sfr, lam_nodes[:, 1:])
    hess = Scatter((n_z, n_z))
    for k, (nz, r, c) in enumerate(per_node(H0, Hr, h_one.sparsity_out(0), n)):
        gr, gc = cols[k][r], cols[k][c]
        keep = gr <= gc  # upper triangle in z's order (node order differs: hw comes first)
        hess.add(nz[np.flatnonzero(keep).tolist()], gr[keep], gc[keep])
    if iq.size:
        hess.add(2 * lam_f * ca.DM(pc.quad[iq]), iq, iq)
    if tq is not None:
        hess.add(2 * lam_f * ca.DM(tq.q), tq.index, tq.index)
    if hess_extra is not None:
        rx, cx = triplets(hess_extra.sparsity())
        hess.add(hess_extra.nz[:], rx, cx)
    if pc.free is not None:
        coupling.add_free(pc.free, coupling.Targets(jac, grad, hess, lay, cols),
                          (v0, vr), (lam_f, lam0, lam_nodes[:, 1:], lam_g), pc.hs_map)  # fmt: skip
    return {
        "grad_f": ca.Function("grad_f", [z, p], [pc.f, grad.build()], ["x", "p"],
                              ["f", "grad_f_x"]),
        "jac_g": ca.Function("jac_g", [z, p], [pc.g, jac.build()], ["x", "p"],
                             ["g", "jac_g_x"]),
        "hess_lag": ca.Function("hess_lag", [z, p, lam_f, lam_g], [hess.build()],
                                ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x"]),
    }  # fmt: skip


def constraint_function(prob: dict) -> ca.Function:
    """``walk3d_g(z)``: the rows of the NLP dict ``prob``, its parameter (if any) at zero."""
    z = ca.MX.sym("z", prob["x"].numel())
    p = [prob["p"]] if "p" in prob else []
    g = ca.Function("g", [prob["x"], *p], [prob["g"]])
    return ca.Function("walk3d_g", [z], [g(z, *(ca.DM.zeros(q.sparsity()) for q in p))])


def select_rows(prob: dict, rows: np.ndarray) -> dict:
    """The NLP dict ``prob`` (``x, f, g`` and maybe ``derivatives``) with only the constraint
    rows ``rows`` (indices into ``g``, increasing).

    Why: a solver stage passes IPOPT only the rows that some bound applies to. The node
    function gives every row at every node, but many rows are bounded only at some nodes
    (the closed loop in double support, the heel-strike wrench at node 0, the second foot's
    force in double support...). IPOPT keeps a free row as an inequality with a free slack, so
    it still enlarges the KKT system and its linearization residual counts as infeasibility;
    leaving them out makes IPOPT's linear algebra about a fifth cheaper per iteration
    (docs/solver.md). Their multipliers are zero at any KKT point, so the Hessian gets zeros
    in their place."""
    rows = np.asarray(rows, dtype=int)
    x, g = prob["x"], prob["g"]
    n_g = g.numel()
    out = {"x": x, "f": prob["f"], "g": g[rows.tolist()]}
    if "p" in prob:  # a parameter (a full-cycle step's anchor shift)
        out["p"] = prob["p"]
    if "derivatives" in prob:
        d = prob["derivatives"]
        x = ca.MX.sym("x", x.sparsity())  # the functions' own input (``prob["x"]`` is a vertcat)
        p = ca.MX.sym("p", d["jac_g"].sparsity_in(1))
        lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", rows.size)
        g_rows, jac = d["jac_g"](x, p)
        spread = ca.DM(ca.Sparsity.triplet(n_g, rows.size, rows.tolist(),
                                           list(range(rows.size))), 1.0)  # fmt: skip
        hess = d["hess_lag"](x, p, lam_f, ca.mtimes(spread, lam_g))
        out["derivatives"] = {
            "grad_f": d["grad_f"],
            "jac_g": ca.Function("jac_g", [x, p], [g_rows[rows.tolist()], jac[rows.tolist(), :]],
                                 ["x", "p"], ["g", "jac_g_x"]),
            "hess_lag": ca.Function("hess_lag", [x, p, lam_f, lam_g], [hess],
                                    ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x"]),
        }  # fmt: skip
    return out
