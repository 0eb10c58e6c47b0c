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
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from walk3d.problem import layout, terms
from walk3d.problem.nlp import loop_rows, row_scale
from walk3d.problem.schedule import lifted
from walk3d.problem.whatif import KINDS

__all__ = ["FullProblem", "full_jerk_weights", "lifting", "swap_changes", "swapped_side"]

N_X, N_XF = layout.N_X, layout.N_XF


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
    per = terms.jerk_per_coefficient(settings.gait.period)
    q = np.zeros(N_XF)
    for s in range(layout.N_SERIES - 1):  # the foot's rotation is no DoF
        q[s * layout.N_COEF : (s + 1) * layout.N_COEF] = per
        if s not in layout.MIDLINE:
            q[N_X + s * layout.N_COEF : N_X + (s + 1) * layout.N_COEF] = per
    return w * row_scale(settings.model) * q


class FullProblem:
    """The composed NLP: ``z = [X, z_R, z_L]``, ``g = [g_R, g_L, lifting R, lifting L, widths,
    ranges, loop checks]`` (``rows``: the sizes of g_R, g_L, the linear rows and the loop
    checks), with its derivative functions. ``loops``: per step, ``(loop function, coordinate
    map (m, 26, N_XF), anchor_x)`` of its loop checks between the nodes (:func:`loop_rows`)."""

    def __init__(self, prob_r: dict, prob_l: dict, lift_r, lift_l, ranges, quad, y_slice,
                 loops=()):  # fmt: skip
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
        f_r, grad_r = d_r["grad_f"](z_r, p)
        f_l, grad_l = d_l["grad_f"](z_l, p)
        gr, jac_r = d_r["jac_g"](z_r, p)
        gl, jac_l = d_l["jac_g"](z_l, p)
        q = ca.DM(np.zeros(N_XF) if quad is None else quad)
        x = z[:N_XF]
        f = 0.5 * (f_r + f_l) + ca.dot(q, x * x)
        grad = ca.vertcat(2 * q * x, 0.5 * grad_r, 0.5 * grad_l)
        xs = ca.MX.sym("X", N_XF)
        g_xs = ca.vertcat(ca.MX(0, 1), *(loop_rows(fn, cmap, xs, ax) for fn, cmap, ax in loops))
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
            ca.horzcat(ca.MX(g_r, N_XF), jac_r, ca.MX(g_r, n_l)),
            ca.horzcat(ca.MX(g_l, N_XF + n_r), jac_l),
            lin_dm,
            ca.horzcat(j_loop, ca.MX(n_loop, n_r + n_l)),
        )
        h_r = d_r["hess_lag"](z_r, p, 0.5 * lam_f, lam_g[:g_r])
        h_l = d_l["hess_lag"](z_l, p, 0.5 * lam_f, lam_g[g_r : g_r + g_l])
        h_x = ca.diag(2 * lam_f * q) + h_loop
        hess = ca.diagcat(h_x, h_r, h_l)
        self.derivatives = {
            "grad_f": ca.Function("grad_f", [z, p], [f, grad], ["x", "p"], ["f", "grad_f_x"]),
            "jac_g": ca.Function("jac_g", [z, p], [g, jac], ["x", "p"], ["g", "jac_g_x"]),
            "hess_lag": ca.Function("hess_lag", [z, p, lam_f, lam_g], [hess],
                                    ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x"]),
        }  # fmt: skip
        zz = ca.MX.sym("z", n_z)
        f_fr = ca.Function("f_r", [prob_r["x"]], [prob_r["f"]])
        f_fl = ca.Function("f_l", [prob_l["x"]], [prob_l["f"]])
        g_fr = ca.Function("g_r", [prob_r["x"]], [prob_r["g"]])
        g_fl = ca.Function("g_l", [prob_l["x"]], [prob_l["g"]])
        xx = zz[:N_XF]
        self.nlp = {
            "x": zz,
            "f": 0.5 * (f_fr(zz[off_r:off_l]) + f_fl(zz[off_l:])) + ca.dot(q, xx * xx),
            "g": ca.vertcat(g_fr(zz[off_r:off_l]), g_fl(zz[off_l:]), ca.mtimes(lin_dm, zz),
                            loop_fn(xx)[0]),
        }  # fmt: skip
