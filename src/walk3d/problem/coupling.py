"""Exact derivatives of the NLP in the descriptors ``s = [T, Td]`` (:mod:`.descriptors`).

With ``s`` among the unknowns the node rows still depend on their own ``v_k`` as before, but
through ``p_k(s)`` (:func:`params_of`) and the quadrature weight ``w_k(s)`` they also
depend on T and Td. :func:`walk3d.problem.derivatives.derivative_functions` keeps the blocks in
``v_k`` (evaluated at ``p_k(s)``, with ``w_k(s)`` in the objective multiplier) and adds what this
module gives:

* per node, one SX function of ``(v_k, s, c_k, λ_f, λ_k)`` (:func:`node_coupling`) with the
  columns ``∂g_k/∂s``, the gradient ``∂(w_k f_k)/∂s``, the Hessian's ``∂²L_k/∂v∂s`` and
  ``∂²L_k/∂s²``, where ``c_k`` holds the node's constants (:data:`N_C`);
* the rows that are functions of ``(x, s)`` alone, differentiated by CasADi as one small SX
  function (:func:`coefficient_coupling`): the lifting ``Y_k = lift_k(x, s)``, the per-distance
  jerk term and the two rows on ``Td / T``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from walk3d.contact.phases import handover_share
from walk3d.problem import descriptors, layout
from walk3d.problem.scatter import Scatter, per_node, triplets

N_C = 8
"""Node constants ``c_k = [decay, anchor sign × V / 2, α_k, β_k, T0, H, H', H'']``, with
``H, H', H''`` the handover share and its derivatives in ``x = τ / Td`` at the node (0 in single
stance: a double-support node's ``x`` is constant on the grid)."""


def node_constants(grid: descriptors.FreeGrid, speed: float, period0: float) -> np.ndarray:
    """``(N_C, n)``: each node's ``c_k`` (module doc)."""
    n = grid.n
    share = [np.where(grid.double_support, v, 0.0) for v in handover_share(grid.a)]
    return np.stack([grid.decay, grid.anchor_sign * speed / 2, grid.alpha, grid.beta,
                     np.full(n, period0), *share])  # fmt: skip


def params_of(c, s):
    """``p_k(s) = [decay, ±V T / 2, 2π/T, h, ḣ/ω, ḧ/ω²]`` from the node constants (any CasADi
    type): ``ḣ/ω = H' r`` and ``ḧ/ω² = H'' r²`` with ``r = T / (2π Td)``."""
    r = s[0] / (2 * math.pi * s[1])
    return ca.vertcat(c[0], c[1] * s[0], 2 * math.pi / s[0], c[5], c[6] * r, c[7] * r * r)


def weight_of(c, s):
    """``w_k(s)``: twice the node's half-cycle quadrature weight (the cycle's integral), per
    distance (× T0 / T, :func:`walk3d.problem.descriptors.objective_scale`)."""
    return 2 * (c[2] * s[1] + c[3] * (s[0] / 2 - s[1])) * descriptors.objective_scale(s[0], c[4])


def node_coupling(node: ca.Function, crit: int) -> dict[str, ca.Function]:
    """Of one node function (module doc), with ``L_k = λ_f w_k f_k + λ_kᵀ g_k``:
    ``jac(v, s, c) -> ∂g/∂s``, ``grad(v, s, c) -> ∂(w f)/∂s`` and
    ``hess(v, s, c, lam_f, lam_g) -> (∂²L/∂v∂s, ∂²L/∂s²)`` (separate functions: an MX call
    evaluates every output of the function it calls)."""
    y, w0, hw, _, t = (node.sx_in(i) for i in range(5))
    v = ca.vertcat(y, w0, hw, t)
    s = ca.SX.sym("s", descriptors.N_S)
    c = ca.SX.sym("c", N_C)
    lam_f = ca.SX.sym("lam_f")
    g, f = node(y, w0, hw, params_of(c, s), t)
    lam_g = ca.SX.sym("lam_g", g.numel())
    obj = weight_of(c, s) * f[crit]
    lag = lam_f * obj + ca.dot(lam_g, g)
    hess_vs = ca.jacobian(ca.gradient(lag, v), s)
    hess_ss = ca.densify(ca.hessian(lag, s)[0])
    return {
        "jac": ca.Function("walk3d_couple_jac", [v, s, c], [ca.jacobian(g, s)]),
        "grad": ca.Function("walk3d_couple_grad", [v, s, c], [ca.densify(ca.gradient(obj, s))]),
        "hess": ca.Function("walk3d_couple_hess", [v, s, c, lam_f, lam_g], [hess_vs, hess_ss]),
    }  # fmt: skip


def coefficient_coupling(lift: ca.Function, jerk: ca.Function) -> dict[str, ca.Function]:
    """The derivatives in ``xs = [x, s]`` of the rows and terms that depend on them alone:
    ``lift_jac(x, s)``, ``grad(x, s)`` of the jerk term and the upper-triangular
    ``hess(x, s, lam_f, lam_lift)`` of ``λ_f jerk − λ_liftᵀ lift`` (the lifting rows are
    ``Y − lift``)."""
    x = ca.SX.sym("x", layout.N_X)
    s = ca.SX.sym("s", descriptors.N_S)
    xs = ca.vertcat(x, s)
    y, j = lift(x, s), jerk(x, s)
    lam_f, lam_lift = ca.SX.sym("lam_f"), ca.SX.sym("lam_lift", y.numel())
    lag = lam_f * j - ca.dot(lam_lift, y)
    return {
        "lift_jac": ca.Function("walk3d_lift_jac", [x, s], [ca.jacobian(y, xs)]),
        "grad": ca.Function("walk3d_jerk_grad", [x, s], [ca.gradient(j, xs)]),
        "hess": ca.Function("walk3d_xs_hess", [x, s, lam_f, lam_lift],
                            [ca.triu(ca.hessian(lag, xs)[0])]),
    }  # fmt: skip


def fraction_jacobian() -> np.ndarray:
    """``∂/∂s`` of :func:`walk3d.problem.descriptors.fraction_rows` (2 × 2, constant)."""
    lo, hi = descriptors.DS_FRACTION_RANGE
    return np.array([[-lo, 1.0], [hi, -1.0]])


@dataclass(frozen=True, kw_only=True)
class FreeCoupling:
    """What the derivative assembly needs for the descriptors' part (module doc)."""

    x: ca.MX
    s: ca.MX
    """The coefficients and the descriptors, as they sit in ``z``."""
    consts: np.ndarray
    """(N_C, n) node constants (:func:`node_constants`)."""
    couple0: dict[str, ca.Function]
    couple: dict[str, ca.Function]
    """:func:`node_coupling` of node 0's function and of the other nodes' function."""
    xs: dict[str, ca.Function]
    """:func:`coefficient_coupling`."""
    threads: int = 1


@dataclass(frozen=True)
class Targets:
    """The global Jacobian, gradient and Hessian under assembly, the layout, and each node's
    positions in ``z`` (:meth:`walk3d.problem.layout.NlpLayout.node_columns`)."""

    jac: Scatter
    grad: Scatter
    hess: Scatter
    layout: layout.NlpLayout
    cols: list[np.ndarray]


def add_free(fc: FreeCoupling, tg: Targets, v, lam, hs_map: np.ndarray) -> None:
    """Add the descriptors' columns and terms to ``tg``: ``v = (v_0, [v_1..])`` and
    ``lam = (λ_f, node 0's λ with the heel-strike tie, the other nodes' λ, all of λ_g)``."""
    lay, cols = tg.layout, tg.cols
    n = lay.nodes
    v0, vr = v
    lam_f, lam0, lam_rest, lam_g = lam
    s_cols = np.arange(lay.z("s").start, lay.z("s").stop)
    const = ca.DM(fc.consts)

    def mapped(fn: ca.Function) -> ca.Function:
        return fn.map(n - 1, "thread", fc.threads) if fc.threads > 1 else fn.map(n - 1)

    s0, sr, c0, cr = fc.s, ca.repmat(fc.s, 1, n - 1), const[:, 0], const[:, 1:]
    js0, jsr = fc.couple0["jac"](v0, s0, c0), mapped(fc.couple["jac"])(vr, sr, cr)
    gs0, gsr = fc.couple0["grad"](v0, s0, c0), mapped(fc.couple["grad"])(vr, sr, cr)
    hvs0, hss0 = fc.couple0["hess"](v0, s0, c0, lam_f, lam0)
    hvsr, hssr = mapped(fc.couple["hess"])(vr, sr, cr, ca.repmat(lam_f, 1, n - 1), lam_rest)
    off = lay.g("node").start
    for k, (nz, r, c) in enumerate(per_node(js0, jsr, fc.couple["jac"].sparsity_out(0), n)):
        tg.jac.add(nz, off + k * layout.N_G + r, s_cols[c])
    hs = layout.G_ROWS["hs_wrench"]
    j_hs = ca.mtimes(ca.DM(hs_map), js0[hs.start : hs.stop, :])
    rh, ch = triplets(j_hs.sparsity())
    tg.jac.add(j_hs.nz[:], lay.g("hs").start + rh, s_cols[ch])
    desc = lay.g("desc").start
    tg.jac.add_const(desc + np.array([0, 0, 1, 1]), s_cols[[0, 1, 0, 1]],
                     fraction_jacobian().ravel())  # fmt: skip
    tg.grad.add(ca.densify(gs0 + ca.sum2(gsr)), s_cols, np.zeros(2, dtype=int))
    for k, (nz, r, c) in enumerate(per_node(hvs0, hvsr, fc.couple["hess"].sparsity_out(0), n)):
        tg.hess.add(nz, cols[k][r], s_cols[c])  # v before s in z: upper triangle
    hss = hss0 + ca.reshape(ca.sum2(ca.reshape(hssr, 4, n - 1)), 2, 2)
    tg.hess.add(ca.vertcat(hss[0, 0], hss[0, 1], hss[1, 1]), s_cols[[0, 0, 1]], s_cols[[0, 1, 1]])
    xs_z = np.concatenate([np.arange(layout.N_X), s_cols])
    jl = fc.xs["lift_jac"](fc.x, fc.s)
    r, c = triplets(jl.sparsity())
    tg.jac.add(-jl.nz[:], lay.g("lift").start + r, xs_z[c])
    gj = fc.xs["grad"](fc.x, fc.s)
    r, _ = triplets(gj.sparsity())
    tg.grad.add(gj.nz[:], xs_z[r], np.zeros(len(r), dtype=int))
    lift_rows = lay.g("lift")
    hx = fc.xs["hess"](fc.x, fc.s, lam_f, lam_g[lift_rows.start : lift_rows.stop])
    r, c = triplets(hx.sparsity())
    tg.hess.add(hx.nz[:], xs_z[r], xs_z[c])
