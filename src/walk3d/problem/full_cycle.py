"""The full-cycle problem (issue #43): each side with its own series, for one-sided changes.

The unknowns are ``X = [x_R, x_L]`` (:data:`walk3d.problem.layout.N_XF`): the right side's and
the midline's series and the left side's series, each over the whole cycle. The cycle is two
steps, each the half-cycle NLP of :mod:`walk3d.problem.nlp` with its own node variables:

* step R, from right heel strike to left heel strike, with the right foot as root, for the body
  as it is; its nodes' coordinates are ``A(t) X`` (:func:`layout.full_coordinate_maps`);
* step L, the next half cycle, seen mirrored with the sides swapped, so that the left foot is
  the root of an NLP built for the body with its sides swapped (:func:`swap_changes`); its
  nodes' coordinates are the mirrored map's.

Each step's own lifting, joint-range and loop-check rows (on its half-cycle vector) are left
out: the steps' node coordinates are tied to ``X`` instead, the joint ranges and limits are rows
on ``X`` over the whole cycle, and each step's half-cycle vector is fixed at zero but for its
half step width, which equals ``X``'s; the loop checks between nodes are rows on ``X``. The
criterion is the mean of the two steps' (each counts its step twice) plus the jerk of
``X``'s series, each DoF once.

The stride splits freely between the steps: ``X``'s step shift ``d``
(:data:`walk3d.problem.layout.I_STEP_SHIFT`) makes the right step ``V T / 2 + d`` and the left
one ``V T / 2 − d``, by moving each step NLP's other-foot anchor (its parameter,
:data:`SHIFT_SIGN`). The heel strikes stay half a cycle apart, so the stance times are equal.
Unequal steps cost: the criterion is multiplied by ``1 + k SLA²``, SLA = ``d / (V T / 2)``
(:data:`walk3d.model.whatif.STEP_ASYMMETRY_COST`; ``kappa = k / (V T / 2)²``), as measured
metabolic cost grows with step-length asymmetry; without it the criterion prefers a limp
(docs/what-if.md).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from walk3d.model import terms
from walk3d.model.whatif import KINDS
from walk3d.problem import layout
from walk3d.problem.jerk import jerk_per_coefficient
from walk3d.problem.nlp import loop_rows, row_scale
from walk3d.problem.schedule import lifted

__all__ = ["FullProblem", "full_jerk_weights", "lifting", "swap_changes", "swapped_side"]

N_X, N_XF, I_D = layout.N_X, layout.N_XF, layout.I_STEP_SHIFT


def swapped_side(name: str) -> str:
    """``ankle_r`` → ``ankle_l`` and back; a midline name unchanged."""
    if name.endswith("_r"):
        return name[:-2] + "_l"
    if name.endswith("_l"):
        return name[:-2] + "_r"
    return name


def swap_changes(changes):
    """The what-if changes with the sides swapped: step L's body (its right side is the
    physical left)."""
    return changes.model_copy(update={
        k: tuple((swapped_side(item[0]), *item[1:]) for item in getattr(changes, k))
        for k in KINDS
    })  # fmt: skip


def lifting(times: np.ndarray, period: float, mirrored: bool) -> np.ndarray:
    """``(n, 78, N_XF)``: a step's node variables ``Y_k`` from ``X`` at its node times (step L:
    ``mirrored``)."""
    return lifted(layout.full_coordinate_maps(times, period, mirrored), period)


def full_jerk_weights(settings) -> np.ndarray | None:
    """``q`` (N_XF,) with the objective's jerk part ``Σ q_i X_i²``: each DoF's series once
    (weight and row scale included), or None without a jerk term."""
    w = terms.extras(settings.model.criterion).get("jerk")
    if not w:
        return None
    per = jerk_per_coefficient(settings.gait.period)
    q = np.zeros(N_XF)
    for s in range(layout.N_SERIES - 1):  # the foot's rotation is no DoF
        q[s * layout.N_COEF : (s + 1) * layout.N_COEF] = per
        if s not in layout.MIDLINE:
            q[N_X + s * layout.N_COEF : N_X + (s + 1) * layout.N_COEF] = per
    return w * row_scale(settings.model) * q


SHIFT_SIGN = (-1.0, 1.0)
"""``∂a / ∂d`` of step R and step L: each step NLP's anchor shift ``a`` (its parameter ``p``,
:func:`walk3d.problem.nlp.build_nlp`) from ``X``'s step shift ``d``
(:data:`walk3d.problem.layout.I_STEP_SHIFT`). Step R's other foot lands ``d`` short of half a
stride ahead and stood ``d`` further behind; step L, mirrored, the other way round."""


def step_functions(prob: dict) -> tuple[ca.Function, ca.Function]:
    """``f(z, a)`` and ``g(z, a)`` of a step NLP, ``a`` its anchor shift (``prob["p"]``)."""
    return tuple(ca.Function(k, [prob["x"], prob["p"]], [prob[k]]) for k in ("f", "g"))


def shift_derivatives(f_fn: ca.Function, g_fn: ca.Function) -> dict[str, ca.Function]:
    """A step NLP's derivatives in its anchor shift ``a``, from its :func:`step_functions`,
    by CasADi's AD through the mapped node function: ``jac(z, a) -> ∂g/∂a``,
    ``grad(z, a) -> ∂f/∂a`` and ``hess(z, a, λ_f, λ_g) -> (∂²L/∂z∂a, ∂²L/∂a²)``,
    ``L = λ_f f + λ_gᵀ g``."""
    zs, a = ca.MX.sym("z", f_fn.size1_in(0)), ca.MX.sym("a")
    f, g = f_fn(zs, a), g_fn(zs, a)
    lf, lg = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.numel())
    dg, df = ca.jacobian(g, a), ca.gradient(f, a)
    la = lf * df + ca.dot(lg, dg)
    return {
        "jac": ca.Function("walk3d_step_shift_jac", [zs, a], [dg]),
        "grad": ca.Function("walk3d_step_shift_grad", [zs, a], [df]),
        "hess": ca.Function("walk3d_step_shift_hess", [zs, a, lf, lg],
                            [ca.gradient(la, zs), ca.gradient(la, a)]),
    }  # fmt: skip


class FullProblem:
    """The composed NLP: ``z = [X, z_R, z_L]``, ``g = [g_R, g_L, lifting R, lifting L, widths,
    ranges, loop checks]`` (``rows``: the sizes of g_R, g_L, the linear rows and the loop
    checks), with its derivative functions. ``prob_r``, ``prob_l``: the steps' NLPs with their
    anchor shift as parameter (:data:`SHIFT_SIGN`). ``loops``: per step, ``(loop function,
    coordinate map (m, 26, N_XF), anchor_x)`` of its loop checks between the nodes
    (:func:`loop_rows`), the anchor before the shift."""

    def __init__(self, prob_r: dict, prob_l: dict, lift_r, lift_l, ranges, quad, y_slice,
                 loops=(), kappa: float = 0.0):  # fmt: skip
        n_r, n_l = prob_r["x"].numel(), prob_l["x"].numel()
        g_r, g_l = prob_r["g"].numel(), prob_l["g"].numel()
        n_z = N_XF + n_r + n_l
        off_r, off_l = N_XF, N_XF + n_r
        lin = []  # constant rows on z
        for lift, off in ((lift_r, off_r), (lift_l, off_l)):
            rows = lift.reshape(-1, N_XF)
            block = np.zeros((rows.shape[0], n_z))
            block[:, :N_XF] = -rows
            block[:, off + y_slice.start : off + y_slice.stop] = np.eye(rows.shape[0])
            lin.append(block)
        width = np.zeros((2, n_z))
        for k, off in enumerate((off_r, off_l)):
            width[k, off + layout.I_HALF_STEP] = 1.0
            width[k, layout.I_HALF_STEP] = -1.0
        lin.append(width)
        r_mat = np.zeros((ranges.shape[0], n_z))
        r_mat[:, :N_XF] = ranges
        lin.append(r_mat)
        lin_dm = ca.sparsify(ca.DM(np.vstack(lin)))
        z = ca.MX.sym("z", n_z)
        z_r, z_l = z[off_r:off_l], z[off_l:]
        p = ca.MX.sym("p", 0)
        lam_f = ca.MX.sym("lam_f")
        d_r, d_l = prob_r["derivatives"], prob_l["derivatives"]
        fns = [step_functions(pb) for pb in (prob_r, prob_l)]
        s_r, s_l = (shift_derivatives(*fg) for fg in fns)
        x = z[:N_XF]
        a_r, a_l = (sign * x[I_D] for sign in SHIFT_SIGN)
        f_r, grad_r = d_r["grad_f"](z_r, a_r)
        f_l, grad_l = d_l["grad_f"](z_l, a_l)
        gr, jac_r = d_r["jac_g"](z_r, a_r)
        gl, jac_l = d_l["jac_g"](z_l, a_l)
        q = ca.DM(np.zeros(N_XF) if quad is None else quad)
        e_d = ca.DM(ca.Sparsity.triplet(1, N_XF, [0], [I_D]), 1.0)  # the row vector of d
        e_col = ca.DM(ca.Sparsity.triplet(n_z, 1, [I_D], [0]), 1.0)  # d's column in z
        c = 0.5 * (f_r + f_l) + ca.dot(q, x * x)
        steps = tuple(zip(SHIFT_SIGN, (s_r, s_l), (z_r, z_l), (a_r, a_l), strict=True))
        df = 0.5 * sum(sign * sd["grad"](zs, a) for sign, sd, zs, a in steps)
        grad_c = ca.vertcat(2 * q * x + ca.mtimes(e_d.T, df), 0.5 * grad_r, 0.5 * grad_l)
        m = 1 + kappa * x[I_D] ** 2  # the step asymmetry's factor (module doc)
        f = m * c
        grad = m * grad_c + ca.mtimes(e_col, 2 * kappa * x[I_D] * c)
        xs = ca.MX.sym("X", N_XF)
        g_xs = ca.vertcat(ca.MX(0, 1), *(
            loop_rows(fn, cmap, xs, ax + sign * xs[I_D])
            for (fn, cmap, ax), sign in zip(loops, SHIFT_SIGN, strict=True)))  # fmt: skip
        n_loop = g_xs.numel()
        lam_s = ca.MX.sym("lam_loop", n_loop)
        loop_fn = ca.Function("walk3d_full_loops", [xs], [g_xs, ca.jacobian(g_xs, xs)])
        loop_hess = ca.Function("walk3d_full_loops_hess", [xs, lam_s],
                                [ca.triu(ca.hessian(ca.dot(lam_s, g_xs), xs)[0])])  # fmt: skip
        self.rows = (g_r, g_l, lin_dm.size1(), n_loop)
        lam_g = ca.MX.sym("lam_g", sum(self.rows))
        lam_loop = lam_g[g_r + g_l + lin_dm.size1() :]
        g_loop, j_loop = loop_fn(x)
        h_loop = loop_hess(x, lam_loop)
        g = ca.vertcat(gr, gl, ca.mtimes(lin_dm, z), g_loop)
        jac = ca.vertcat(
            ca.horzcat(
                ca.mtimes(SHIFT_SIGN[0] * s_r["jac"](z_r, a_r), e_d), jac_r, ca.MX(g_r, n_l)
            ),
            ca.horzcat(
                ca.mtimes(SHIFT_SIGN[1] * s_l["jac"](z_l, a_l), e_d), ca.MX(g_l, n_r), jac_l
            ),
            lin_dm,
            ca.horzcat(j_loop, ca.MX(n_loop, n_r + n_l)),
        )
        lam_steps = (lam_g[:g_r], lam_g[g_r : g_r + g_l])
        lam_c = lam_f * m  # the multiplier of c's own curvature
        h_r = d_r["hess_lag"](z_r, a_r, 0.5 * lam_c, lam_steps[0])
        h_l = d_l["hess_lag"](z_l, a_l, 0.5 * lam_c, lam_steps[1])
        h_d = [sd["hess"](zs, a, 0.5 * lam_c, lm)
               for (_, sd, zs, a), lm in zip(steps, lam_steps, strict=True)]  # fmt: skip
        # d's row of the upper triangle: its own entry and its products with the steps' z;
        # with the factor m also λ_f (∇m ∇cᵀ + ∇c ∇mᵀ + c ∇²m), all in d's row and column
        u = 2 * kappa * lam_f * x[I_D] * grad_c
        d_row = ca.horzcat(
            ca.mtimes(h_d[0][1] + h_d[1][1] + 2 * u[I_D] + 2 * kappa * lam_f * c, e_d),
            *(sign * h[0].T for sign, h in zip(SHIFT_SIGN, h_d, strict=True)),
        ) + ca.horzcat(ca.MX(1, I_D + 1), u[I_D + 1 :].T)
        d_col = ca.vertcat(u[:I_D], ca.MX(n_z - I_D, 1))  # rows above d (X's coefficients)
        h_x = ca.diag(2 * lam_c * q) + h_loop
        hess = (ca.diagcat(h_x, h_r, h_l) + ca.mtimes(e_col, d_row)
                + ca.mtimes(d_col, e_col.T))  # fmt: skip
        self.derivatives = {
            "grad_f": ca.Function("grad_f", [z, p], [f, grad], ["x", "p"], ["f", "grad_f_x"]),
            "jac_g": ca.Function("jac_g", [z, p], [g, jac], ["x", "p"], ["g", "jac_g_x"]),
            "hess_lag": ca.Function("hess_lag", [z, p, lam_f, lam_g], [hess],
                                    ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x"]),
        }  # fmt: skip
        zz = ca.MX.sym("z", n_z)
        xx = zz[:N_XF]
        parts = [(fn, gn, zs, sign * xx[I_D]) for (fn, gn), zs, sign
                 in zip(fns, (zz[off_r:off_l], zz[off_l:]), SHIFT_SIGN, strict=True)]  # fmt: skip
        self.nlp = {
            "x": zz,
            "f": (1 + kappa * xx[I_D] ** 2)
            * (0.5 * sum(fn(zs, a) for fn, _, zs, a in parts) + ca.dot(q, xx * xx)),
            "g": ca.vertcat(*(gn(zs, a) for _, gn, zs, a in parts), ca.mtimes(lin_dm, zz),
                            loop_fn(xx)[0]),
        }  # fmt: skip
