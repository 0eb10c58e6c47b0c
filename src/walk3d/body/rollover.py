"""Stance-foot roll-over (paper Eq. 1): ankle position as a function of the foot's rotation.

The stance foot rolls on the floor without slipping. Its orientation is a single rotation by
``θ_ft`` about the foot axis ``u_ft`` (positive = toes up), carried by ``s = sin(θ_ft/2)`` (the
paper's ``λ3(ft)`` for an axis along z). The ankle joint centre then follows

    Δx = f(s),   y = g(s),   Δz = h(s)

where ``Δx, Δz`` are measured from the ankle position at foot flat (``s = 0``). The paper
measures them from heel strike instead; the two differ by a constant, and foot flat is the
natural anchor of a foot that stays put during single stance.

Each of ``f, g, h`` is a cubic spline through knots. It is stored in truncated-power form,
``c0 + c1 s + c2 s² + c3 s³ + Σ_k d_k max(s - s_k, 0)³``, which evaluates with the same
arithmetic on NumPy arrays and CasADi symbols and gives exact first and second derivatives
without branching.

Data-free default: Hansen et al. (2004) found able-bodied ankle-foot roll-over shapes close to
a circular arc; :func:`arc_rollover` rolls such an arc (radius and centre scaled by foot length)
and samples the ankle path at knots.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from walk3d import mathops as m


@dataclass(frozen=True)
class RollOver:
    """Cubic-spline roll-over shape, ``s -> (Δx, y, Δz)`` of the ankle joint centre.

    Attributes
    ----------
    knots: interior and end knots in ``s`` (increasing).
    poly: ``(4, 3)`` polynomial part ``c0..c3`` for (Δx, y, Δz).
    jumps: ``(n_knots - 2, 3)`` third-derivative jumps / 6 at the interior knots.
    """

    knots: tuple[float, ...]
    poly: tuple[tuple[float, float, float], ...]
    jumps: tuple[tuple[float, float, float], ...]

    @classmethod
    def from_samples(cls, s: np.ndarray, xyz: np.ndarray) -> RollOver:
        """Natural cubic spline through samples ``xyz`` (n, 3) at increasing ``s`` (n,)."""
        s = np.asarray(s, dtype=float)
        xyz = np.asarray(xyz, dtype=float)
        if s.ndim != 1 or xyz.shape != (s.size, 3) or s.size < 3:
            raise ValueError("roll-over needs at least 3 samples of shape (n,) and (n, 3)")
        if np.any(np.diff(s) <= 0):
            raise ValueError("roll-over knots must be strictly increasing")
        from scipy.interpolate import CubicSpline  # 0.3 s to import: only when a body is built

        sp = CubicSpline(s, xyz, bc_type="natural")
        c = sp.c  # (4, n-1, 3), highest power first, local in (s - s_i)
        s0 = s[0]
        # polynomial of the first piece re-expanded about s = 0
        a3, a2, a1, a0 = c[0, 0], c[1, 0], c[2, 0], c[3, 0]
        p0 = a0 - a1 * s0 + a2 * s0**2 - a3 * s0**3
        p1 = a1 - 2 * a2 * s0 + 3 * a3 * s0**2
        p2 = a2 - 3 * a3 * s0
        p3 = a3
        jumps = c[0, 1:] - c[0, :-1]
        return cls(
            knots=tuple(float(v) for v in s),
            poly=tuple(tuple(float(v) for v in row) for row in (p0, p1, p2, p3)),
            jumps=tuple(tuple(float(v) for v in row) for row in jumps),
        )

    def evaluate(self, s: Any) -> tuple[list[Any], list[Any], list[Any]]:
        """Values, first and second derivatives w.r.t. ``s``, each a list over (x, y, z)."""
        val, d1, d2 = [], [], []
        interior = self.knots[1:-1]
        for j in range(3):
            c0, c1, c2, c3 = (self.poly[i][j] for i in range(4))
            v = c0 + c1 * s + c2 * s * s + c3 * s * s * s
            dv = c1 + 2 * c2 * s + 3 * c3 * s * s
            ddv = 2 * c2 + 6 * c3 * s
            for sk, jump in zip(interior, self.jumps, strict=True):
                h = m.fmax(s - sk, 0.0)
                v = v + jump[j] * h * h * h
                dv = dv + 3 * jump[j] * h * h
                ddv = ddv + 6 * jump[j] * h
            val.append(v)
            d1.append(dv)
            d2.append(ddv)
        return val, d1, d2

    def ankle_triple(self, s: Any, sd: Any, sdd: Any):
        """Ankle displacement triple ``(p, p_dot, p_ddot)`` for ``s(t)`` with derivatives."""
        v, d1, d2 = self.evaluate(s)
        p = tuple(v)
        pd = tuple(d * sd for d in d1)
        pdd = tuple(dd * sd * sd + d * sdd for d, dd in zip(d1, d2, strict=True))
        return p, pd, pdd


def arc_ankle_path(
    theta: np.ndarray, radius: float, centre_forward: float, ankle_height: float
) -> np.ndarray:
    """Ankle path (n, 3) of a foot whose sole is a circular arc rolling without slip.

    The arc has ``radius``; its centre sits ``centre_forward`` ahead of the ankle and ``radius``
    above the floor at foot flat, where the ankle is ``ankle_height`` above the floor. Rotation
    ``theta`` (rad) about +z (toes up) rolls the centre back by ``radius * theta``.
    """
    theta = np.asarray(theta, dtype=float)
    cx, cy = centre_forward, radius - ankle_height
    x = -radius * theta - (cx * np.cos(theta) - cy * np.sin(theta)) + cx
    y = radius - (cx * np.sin(theta) + cy * np.cos(theta))
    return np.stack([x, y, np.zeros_like(x)], axis=-1)


def arc_rollover(
    radius: float,
    centre_forward: float,
    ankle_height: float,
    theta_range_deg: tuple[float, float] = (-60.0, 40.0),
    n_knots: int = 11,
) -> RollOver:
    """Default roll-over: the arc model sampled at ``n_knots`` foot angles."""
    theta = np.radians(np.linspace(*theta_range_deg, n_knots))
    return RollOver.from_samples(
        np.sin(theta / 2), arc_ankle_path(theta, radius, centre_forward, ankle_height)
    )


def fit_rollover(
    heel: np.ndarray,
    ankle: np.ndarray,
    toe: np.ndarray,
    n_knots: int = 9,
    flat_pitch: float | None = None,
) -> RollOver:
    """Fit the roll-over spline to measured stance trajectories (global, time first, (n, 3)).

    The foot's sagittal rotation is the pitch of the heel-to-toe line relative to its pitch at
    foot flat. Markers rarely sit at equal heights, so foot flat is not "pitch = 0": it is
    ``flat_pitch`` (rad) when given, else the pitch where the foot rotates slowest (mid-stance).
    Ankle displacements are taken from the sample closest to foot flat. Samples are binned on
    ``s = sin(θ/2)`` and averaged into at most ``n_knots`` knots.
    """
    heel, ankle, toe = (np.asarray(a, dtype=float) for a in (heel, ankle, toe))
    d = toe - heel
    pitch = np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2]))
    if flat_pitch is None:
        flat_pitch = float(pitch[int(np.argmin(np.abs(np.gradient(pitch))))])
    theta = pitch - flat_pitch
    flat = int(np.argmin(np.abs(theta)))
    s = np.sin(theta / 2)
    rel = ankle - ankle[flat]
    rel[:, 1] = ankle[:, 1]
    order = np.argsort(s)
    s, rel = s[order], rel[order]
    edges = np.linspace(s[0], s[-1], n_knots + 1)
    ks, kv = [], []
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        sel = (s >= lo) & (s <= hi)
        if sel.any():
            ks.append(s[sel].mean())
            kv.append(rel[sel].mean(axis=0))
    return RollOver.from_samples(np.array(ks), np.array(kv))
