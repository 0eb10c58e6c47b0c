"""Splitting the total ground reaction between the feet (paper Eqs. 6–8) and reporting it.

In single stance the stance foot carries the whole reaction. In double support the trailing
(non-root) foot carries ``e(τ) · W0`` where ``e = exp(-(τ/T_ds)³)`` (:mod:`walk3d.contact.phases`)
and ``W0`` is the trailing foot's wrench at contralateral heel strike; the leading foot carries
the rest, so the sum always equals the total of Eq. 5.

``W0`` (force and moment about the trailing ankle) has two sources:

* ``ratios=None`` (default, data-free): ``W0`` is the *total* reaction at the heel-strike instant,
  when the trailing foot still carries everything. Every component then decays with the same
  ``e``, which is the paper's Eq. 6 for ``F_y, M_z`` and its linear ratios (Eqs. 7–8) with
  ``μ_x = F_x0/F_y0``, ``μ_z = F_z0/F_y0``, ``ϖ_x = M_x0/M_z0``, ``ϖ_y = M_y0/M_z0``. The forces are
  continuous at heel strike by construction.
* :class:`TransitionRatios`: fixed ``μ_x, μ_z, ϖ_x, ϖ_y`` (e.g. fitted to force plates), with
  ``F_y0`` and ``M_z0`` still taken at heel strike. Values are for the right foot; the left uses
  the mirror signs (lateral force, frontal and transverse moments flip).

Moments of the trailing foot are taken about its ankle joint centre, so that ``W0`` describes the
foot's own load and not the choice of global origin.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d.dynamics.newton_euler import Wrench, total_ground_reaction
from walk3d.kinematics.quaternion import V, vadd, vcross, vscale, vsub


@dataclass(frozen=True)
class TransitionRatios:
    """Linear transfer ratios of Eqs. 7–8 (right-foot signs)."""

    mu_x: float
    mu_z: float
    varpi_x: float
    varpi_y: float


def heel_strike_wrench(total: Wrench, trailing_ankle: V) -> Wrench:
    """Total reaction at heel strike as ``(F0, M0 about the trailing ankle)``."""
    f, m = total
    return f, vsub(m, vcross(trailing_ankle, f))


def apply_ratios(w0: Wrench, ratios: TransitionRatios | None, side: str) -> Wrench:
    """``W0`` with its horizontal force and frontal/transverse moment replaced by the ratios."""
    if ratios is None:
        return w0
    f, m = w0
    s = -1.0 if side == "l" else 1.0
    fy, mz = f[1], m[2]
    return (
        (ratios.mu_x * fy, fy, s * ratios.mu_z * fy),
        (s * ratios.varpi_x * mz, s * ratios.varpi_y * mz, mz),
    )


def ratio_map(ratios: TransitionRatios | None) -> np.ndarray:
    """The map from node 0's heel-strike rows to the trailing foot's load W0: identity, or the
    calibrated ratios of :func:`apply_ratios` (linear in the rows)."""
    if ratios is None:
        return np.eye(6)
    cols = []
    for e in np.eye(6):
        f, m = apply_ratios(((e[0], e[1], e[2]), (e[3], e[4], e[5])), ratios, "l")
        cols.append([*f, *m])
    return np.array(cols, dtype=float).T


def split(total: Wrench, decay: Any, w0: Wrench, trailing_ankle: V) -> tuple[Wrench, Wrench]:
    """``(root_foot, trailing_foot)`` wrenches, moments about the global origin."""
    f0, m0 = w0
    f_t = vscale(decay, f0)
    m_t = vadd(vscale(decay, m0), vcross(trailing_ankle, f_t))
    return (vsub(total[0], f_t), vsub(total[1], m_t)), (f_t, m_t)


def static_split(body, pose) -> dict[int, Wrench]:
    """Even split for quiet standing on both feet (each foot half the force, moments halved
    about the midpoint of the ankles)."""
    f, m = total_ground_reaction(body, pose)
    ir, il = body.segment_index("foot_r"), body.segment_index("foot_l")
    ar, al = pose.origin[ir][0], pose.origin[il][0]
    mid = vscale(0.5, vadd(ar, al))
    mc = vsub(m, vcross(mid, f))
    half = vscale(0.5, f)
    return {
        ir: (half, vadd(vscale(0.5, mc), vcross(ar, half))),
        il: (half, vadd(vscale(0.5, mc), vcross(al, half))),
    }


def centre_of_pressure(force: np.ndarray, moment_o: np.ndarray, min_fy: float = 1e-6):
    """Force, centre of pressure on the floor and free moment of a foot wrench.

    ``force``, ``moment_o`` (N, 3), moment about the origin. With the centre of pressure ``p`` on
    the floor (``p_y = 0``) the wrench is ``M_O = p × F + (0, τ, 0)``: exact whenever ``F_y > 0``.
    Where ``F_y <= min_fy`` (no contact) the centre of pressure is NaN and the free moment 0.
    """
    force, moment_o = np.asarray(force, float), np.asarray(moment_o, float)
    fy = force[:, 1]
    loaded = fy > min_fy
    safe = np.where(loaded, fy, 1.0)
    px = moment_o[:, 2] / safe
    pz = -moment_o[:, 0] / safe
    tau = moment_o[:, 1] - (pz * force[:, 0] - px * force[:, 2])
    cop = np.stack([px, np.zeros_like(px), pz], axis=-1)
    cop[~loaded] = np.nan
    return cop, np.where(loaded, tau, 0.0)
