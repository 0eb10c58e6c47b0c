"""Gait phases from the period T and the double-support duration Td.

The cycle starts at toe off of the reference (right) leg, as in the paper:

=====================  ======================================
time                   event
=====================  ======================================
0                      right toe off (right swing starts)
T/2 - Td               right heel strike (double support 1)
T/2                    left toe off
T - Td                 left heel strike (double support 2)
T                      right toe off
=====================  ======================================

With T = 1.08 s and Td = 0.16 s this is 0–35 % swing, 35–50 % and 85–100 % double support:
the paper's 36 % and 86 %, rounded. The root of the kinematic chain is the foot that struck the
ground last (right from its heel strike to the left heel strike, then left): in double support
the root is the leading foot, and the trailing foot closes the loop.

During double support the trailing foot unloads as ``exp(-(τ/T_ds)³)`` with ``T_ds = Td/2`` and
``τ`` the time since the contralateral heel strike (paper Eq. 6), or with a load ramp
(:func:`trailing_share`).

With the handover (:func:`handover_share`) the root of the chain also passes from the trailing
to the leading foot over double support instead of at heel strike.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def handover_share(x):
    """``(h, dh/dx, d²h/dx²)`` of the trailing foot's share of the chain's root at ``x`` = time
    since heel strike / Td: ``1 − (10x³ − 15x⁴ + 6x⁵)``, 1 at heel strike and 0 at toe off with
    both derivatives 0 at either end, so the motion stays twice differentiable there."""
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    h = 1.0 - x**3 * (10.0 - 15.0 * x + 6.0 * x**2)
    d1 = -30.0 * x**2 * (1.0 - x) ** 2
    d2 = -60.0 * x * (1.0 - x) * (1.0 - 2.0 * x)
    return h, d1, d2


def trailing_share(x, ramp: float | None = None) -> np.ndarray:
    """The trailing foot's share of its heel-strike load at ``x`` = time since heel strike /
    Td in [0, 1]: the paper's ``exp(−(2x)³)`` (``ramp`` None), which starts flat, or the cubic
    ``(1 − x)²(1 + (2 − s)x)`` with initial slope ``−s`` (``ramp`` = s in [0, 3], monotone),
    which loads the leading foot at ``s·W/Td`` from heel strike and reaches 0 at toe off."""
    x = np.asarray(x, dtype=float)
    if ramp is None:
        return np.exp(-((2.0 * x) ** 3))
    x = np.clip(x, 0.0, 1.0)
    return (1.0 - x) ** 2 * (1.0 + (2.0 - ramp) * x)


@dataclass(frozen=True)
class GaitPhases:
    period: float
    double_support: float
    ramp: float | None = None
    """The leading foot's load ramp (:func:`trailing_share`); None: the paper's."""

    def __post_init__(self) -> None:
        if not (np.isfinite(self.period) and self.period > 0):
            raise ValueError(f"gait period must be positive, got {self.period}")
        if not (np.isfinite(self.double_support) and 0 < self.double_support < self.period / 2):
            raise ValueError(
                f"double-support duration must be in (0, T/2) = (0, {self.period / 2:g}) s, "
                f"got {self.double_support}"
            )

    @property
    def heel_strike_r(self) -> float:
        return self.period / 2 - self.double_support

    @property
    def heel_strike_l(self) -> float:
        return self.period - self.double_support

    @property
    def toe_off_l(self) -> float:
        return self.period / 2

    @property
    def mid_stance(self) -> tuple[float, float]:
        """The middle third of a foot's stance (``T/2 + Td`` long), as times since its heel
        strike, s: single support, with the other foot in mid-swing."""
        stance = self.period / 2 + self.double_support
        return stance / 3, 2 * stance / 3

    def _phase(self, t) -> np.ndarray:
        return np.mod(np.asarray(t, dtype=float), self.period)

    def root_is_right(self, t) -> np.ndarray:
        """True where the right foot is the root of the chain."""
        p = self._phase(t)
        return (p >= self.heel_strike_r) & (p < self.heel_strike_l)

    def in_stance(self, t, side: str) -> np.ndarray:
        """True where foot ``side`` touches the ground (both ends of stance included)."""
        p = self._phase(t)
        if side == "r":
            return (p >= self.heel_strike_r) | (p == 0.0)
        return (p <= self.toe_off_l) | (p >= self.heel_strike_l)

    def double_support_mask(self, t) -> np.ndarray:
        return self.in_stance(t, "r") & self.in_stance(t, "l")

    def time_since_heel_strike(self, t) -> np.ndarray:
        """Time since the root foot's heel strike, s."""
        p = self._phase(t)
        right = self.root_is_right(t)
        return np.where(right, p - self.heel_strike_r, np.mod(p - self.heel_strike_l, self.period))

    def trailing_decay(self, t) -> np.ndarray:
        """Share of its heel-strike load still on the trailing (non-root) foot; 0 in swing."""
        tau = self.time_since_heel_strike(t)
        share = trailing_share(tau / self.double_support, self.ramp)
        return np.where(tau <= self.double_support + 1e-12, share, 0.0)

    def handover(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(h, ḣ, ḧ)`` at ``t`` (1/s, 1/s²): the trailing foot's share of the root
        (:func:`handover_share`) in double support, 0 in single stance."""
        tau = self.time_since_heel_strike(t)
        ds = tau <= self.double_support + 1e-12
        h, d1, d2 = handover_share(tau / self.double_support)
        td = self.double_support
        return np.where(ds, h, 0.0), np.where(ds, d1 / td, 0.0), np.where(ds, d2 / td**2, 0.0)
