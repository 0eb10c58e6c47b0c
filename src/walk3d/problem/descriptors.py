"""The cycle period T and the double-support time Td as unknowns of the NLP.

With ``GaitSettings.free`` not empty, the NLP's variables end with ``s = [T, Td]`` (s): a
free descriptor lies within human bounds (:data:`PERIOD_RANGE_S`, :data:`DS_FRACTION_RANGE`),
a given one is pinned at its value by equal bounds, so it keeps its meaning exactly. The
posture and balance stages pin both at the first guess; the full stage frees them.

**Grid.** The nodes follow the phases, so that they move continuously with ``s``: nodes
``0..N_ds`` cover double support from the right heel strike to the left toe off (both
included, ``τ_k = k Td / N_ds``), and the other ``N - N_ds - 1`` nodes split the single stance
that follows evenly. ``N_ds`` depends on ``N`` alone (:func:`ds_intervals`), never on T or Td,
so the problem and its optimum do not depend on the first guess.

Every node time after the heel strike is ``τ_k = a_k Td + b_k (T/2 − Td)``
and every quadrature weight ``w_k = α_k Td + β_k (T/2 − Td)`` (the rectangle rule on each
phase). The trailing foot's share ``exp(−(τ/(Td/2))³)`` at a node is then a constant.

**Normalization.** A cycle's criterion integrates over T, so on its own it favours short
cycles. With a descriptor free the objective is the criterion per distance travelled, ``J /
(V T)``, times the first guess's stride ``V T0`` so that its size is that of the fixed problem:
``J T0 / T``. With both given this is ``J`` itself, and the problem is the fixed one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from walk3d.contact.phases import trailing_share
from walk3d.kinematics import fourier
from walk3d.problem import layout

N_S = 2
"""Descriptor unknowns ``s = [T, Td]``, s."""
NAMES = ("period", "double_support")
PERIOD_RANGE_S = (0.8, 1.7)
"""Bounds on T at the reference stature (1.77 m; they scale with √(h / 1.77 m)): adults'
cadence spans about 70–150 steps/min from slow to fast walking."""
DS_FRACTION_RANGE = (0.05, 0.22)
"""Bounds on Td / T: each double support is 5–22 % of the cycle, a stance of 55–72 %, which
covers adults from fast to slow walking."""
GIVEN_PERIOD_S = (0.6, 2.5)
"""Bounds on a given T, s: cadence 48–200 steps/min, slowest walking measured to race walking."""
GIVEN_DS_FRACTION = (0.02, 0.3)
"""Bounds on a given Td / T: stance 52–80 % of the cycle, race walking to very slow walking."""


def given_checks(period: float, ds: float) -> list[tuple[bool, str]]:
    """``(ok, message)`` for a given T and Td (s) against :data:`GIVEN_PERIOD_S` and
    :data:`GIVEN_DS_FRACTION`; :class:`~walk3d.problem.settings.GaitSettings` checks them."""
    (t_lo, t_hi), (f_lo, f_hi) = GIVEN_PERIOD_S, GIVEN_DS_FRACTION
    return [
        (t_lo <= period <= t_hi,
         f"period must be in [{t_lo:g}, {t_hi:g}] s (48-200 steps/min), got {period}"),
        (f_lo * period <= ds <= f_hi * period,
         f"double-support duration must be {f_lo:.0%}-{f_hi:.0%} of T, in [{f_lo * period:.3g}, "
         f"{f_hi * period:.3g}] s for T {period:g} s, got {ds}"),
    ]  # fmt: skip


@dataclass(frozen=True)
class FreeGrid:
    """The phase-following grid (module doc) of ``n`` nodes, ``n_ds`` intervals in double
    support, the last ``n_checks`` of them contact checks (:func:`free_grid`). Arrays are per
    node."""

    n_ds: int
    a: np.ndarray
    b: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    double_support: np.ndarray
    ramp: float | None = None
    """The leading foot's load ramp (:func:`walk3d.contact.phases.trailing_share`)."""
    n_checks: int = 0
    """Check nodes at the end (contact checks inside the double-support intervals, then swing
    checks inside the swing intervals): zero weight."""

    @property
    def check(self) -> np.ndarray:
        """Per node, whether it is a contact or swing check (no quadrature weight, no
        slacks)."""
        return np.arange(self.n) >= self.n - self.n_checks

    @property
    def n(self) -> int:
        return len(self.a)

    def tau(self, period: Any, ds: Any) -> list[Any]:
        """Node times after the right heel strike, s (numbers or CasADi expressions)."""
        return [a * ds + b * (period / 2 - ds) for a, b in zip(self.a, self.b, strict=True)]

    def weights(self, period: Any, ds: Any) -> list[Any]:
        """Quadrature weight of each node over the half cycle, s."""
        return [a * ds + b * (period / 2 - ds)
                for a, b in zip(self.alpha, self.beta, strict=True)]  # fmt: skip

    def phases(self, period: Any, ds: Any) -> list[Any]:
        """``θ_k = 2π t_k / T`` with ``t_k = T/2 − Td + τ_k`` (the cycle starts at right toe off,
        :mod:`walk3d.contact.phases`)."""
        return [2 * math.pi * (period / 2 - ds + t) / period for t in self.tau(period, ds)]

    @property
    def decay(self) -> np.ndarray:
        """The trailing foot's share of its heel-strike load at each node (0 in swing)."""
        return np.where(self.double_support, trailing_share(self.a, self.ramp), 0.0)

    @property
    def anchor_sign(self) -> np.ndarray:
        """The other foot's anchor is ``sign · V T / 2``: behind in double support, ahead in
        swing."""
        return np.where(self.double_support, -1.0, 1.0)


DS_NODE_FRACTION = 0.1
"""Td / T at which the free grid is even: about Winter's normal cadence (0.114 s / 1.140 s).
The double support gets ``round(2 N · 0.1)`` of the half cycle's N intervals whatever T and
Td, so the problem does not depend on the first guess; the optimum depends strongly on that
count (docs/descriptors.md)."""


def ds_intervals(nodes: int) -> int:
    """Double-support intervals of the free grid of ``nodes`` nodes (:data:`DS_NODE_FRACTION`,
    at least 2, and at least 2 single-stance nodes)."""
    return int(np.clip(round(nodes * 2 * DS_NODE_FRACTION), 2, nodes - 3))


def free_grid(
    nodes: int,
    n_ds: int | None = None,
    ramp: float | None = None,
    checks: int = 0,
    swing_checks: int = 0,
) -> FreeGrid:
    """The grid for ``nodes`` nodes with ``n_ds`` double-support intervals (default:
    :func:`ds_intervals`) and the load ramp ``ramp`` (:class:`FreeGrid`), plus ``checks``
    contact-check nodes evenly inside each double-support interval and ``swing_checks`` inside
    each swing interval (toe off to heel strike), appended after the nodes in that order
    (:mod:`walk3d.problem.schedule` says why)."""
    n_ds = ds_intervals(nodes) if n_ds is None else int(n_ds)
    if not 1 <= n_ds <= nodes - 2:
        raise ValueError(f"{n_ds} double-support intervals do not fit {nodes} nodes")
    m = nodes - n_ds
    k = np.arange(nodes)
    in_ds = k < n_ds
    frac = np.arange(1, checks + 1) / (checks + 1)
    a_check = (np.arange(n_ds)[:, None] + frac[None, :]).ravel() / n_ds
    frac_sw = np.arange(1, swing_checks + 1) / (swing_checks + 1)
    b_swing = (np.arange(m)[:, None] + frac_sw[None, :]).ravel() / m
    n_c, n_sw = a_check.size, b_swing.size
    a = np.concatenate([np.where(in_ds, k / n_ds, 1.0), a_check, np.ones(n_sw)])
    b = np.concatenate([np.where(in_ds, 0.0, (k - n_ds) / m), np.zeros(n_c), b_swing])
    zeros = np.zeros(n_c + n_sw)
    return FreeGrid(
        n_ds=n_ds, a=a, b=b,
        alpha=np.concatenate([np.where(in_ds, 1.0 / n_ds, 0.0), zeros]),
        beta=np.concatenate([np.where(in_ds, 0.0, 1.0 / m), zeros]),
        double_support=np.concatenate([k <= n_ds, np.ones(n_c, dtype=bool),
                                       np.zeros(n_sw, dtype=bool)]),
        ramp=ramp, n_checks=n_c + n_sw,
    )  # fmt: skip


def grid_for(solver: Any, ramp: float | None = None) -> FreeGrid:
    """The free grid of the solver settings ``solver`` (nodes, contact and swing checks)."""
    return free_grid(solver.nodes, ramp=ramp, checks=solver.contact_checks,
                     swing_checks=solver.swing_checks)  # fmt: skip


def objective_scale(period: Any, period0: float) -> Any:
    """Per-distance normalization of a cycle's criterion (module doc): ``T0 / T``."""
    return period0 / period


def _series(theta, c) -> tuple[Any, Any, Any]:
    """Value and first two θ-derivatives of one Fourier series with coefficients ``c``."""
    v, d1, d2 = c[0], 0.0, 0.0
    for j in range(1, fourier.ORDER + 1):
        cj, sj = ca.cos(j * theta), ca.sin(j * theta)
        a, b = c[2 * j - 1], c[2 * j]
        v = v + a * cj + b * sj
        d1 = d1 + j * (b * cj - a * sj)
        d2 = d2 - j * j * (a * cj + b * sj)
    return v, d1, d2


def _lift_one() -> ca.Function:
    """``Y(x, θ)``: one node's coordinates, rates / ω and accelerations / ω² at phase θ."""
    x = ca.SX.sym("x", layout.N_X)
    theta = ca.SX.sym("theta")
    shift = np.diag(fourier.half_cycle_shift())
    vals = []
    for sr, shifted in layout.COORD_SOURCE:
        c = [x[sr * layout.N_COEF + j] * (shift[j] if shifted else 1.0)
             for j in range(layout.N_COEF)]  # fmt: skip
        vals.append(_series(theta, c))
    out = [v[0] for v in vals] + [v[1] for v in vals] + [v[2] for v in vals]
    return ca.Function("walk3d_lift_one", [x, theta], [ca.vertcat(*out)])


def lift_function(grid: FreeGrid) -> ca.Function:
    """``walk3d_lift(x[N_X], s[2]) -> Y[n · 78]``: each node's coordinates, rates / ω and
    accelerations / ω² (the lifted ``Y_k`` of :mod:`walk3d.problem.nlp`) at its phase. One
    node's expressions are built once and called at every phase (inlined: the same SX)."""
    x = ca.SX.sym("x", layout.N_X)
    s = ca.SX.sym("s", N_S)
    one = _lift_one()
    return ca.Function("walk3d_lift", [x, s],
                       [ca.vertcat(*(one(x, th) for th in grid.phases(s[0], s[1])))])  # fmt: skip


def jerk_function(quad0: np.ndarray | None, period0: float) -> ca.Function:
    """``walk3d_jerk(x, s) -> per-distance jerk term``: the fixed problem's ``Σ q_i x_i²`` at T0
    (``quad0``, None: no jerk term) is ``∝ T⁻⁵`` (Parseval), times ``T0 / T``."""
    x = ca.SX.sym("x", layout.N_X)
    s = ca.SX.sym("s", N_S)
    if quad0 is None:
        return ca.Function("walk3d_jerk", [x, s], [0.0 * s[0]])
    val = ca.dot(ca.DM(quad0), x * x) * (period0 / s[0]) ** 5 * objective_scale(s[0], period0)
    return ca.Function("walk3d_jerk", [x, s], [val])


def fraction_rows(s) -> Any:
    """``[Td − f_lo T, f_hi T − Td]`` (≥ 0 keeps Td / T in :data:`DS_FRACTION_RANGE`)."""
    lo, hi = DS_FRACTION_RANGE
    return ca.vertcat(s[1] - lo * s[0], hi * s[0] - s[1])


def descriptor_bounds(
    free: tuple[str, ...], period: float, ds: float, scale: float = 1.0, pinned: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, hi)`` of ``s``: a given descriptor (or every one when ``pinned``) at its value, a
    free one in human bounds; ``scale`` is √(h / 1.77 m) of the solved body (1 for the
    reference subject)."""
    lo, hi = np.array([period, ds]), np.array([period, ds])
    if not pinned:
        if "period" in free:
            lo[0], hi[0] = PERIOD_RANGE_S[0] * scale, PERIOD_RANGE_S[1] * scale
        if "double_support" in free:
            lo[1], hi[1] = DS_FRACTION_RANGE[0] * lo[0], DS_FRACTION_RANGE[1] * hi[0]
    return lo, hi


WALK_RATIO_PER_HEIGHT = 0.0037
"""Step length / cadence per stature, m/(steps/min)/m: Murray's adults (1964, men: 0.79 m at
117 steps/min; 1970, women: 0.66 m at 117 steps/min; about 0.0039 and 0.0034 per metre of
stature), constant from comfortable to fast speeds (Terrier & Schutz 2003)."""


def published_cadence(speed: Any, height: float) -> Any:
    """Adults' cadence at ``speed``, steps/min, from a constant walk ratio
    (:data:`WALK_RATIO_PER_HEIGHT`): ``V = L C / 60`` with ``L = W h C`` gives
    ``C = √(60 V / (W h))``."""
    return np.sqrt(60.0 * np.asarray(speed, dtype=float) / (WALK_RATIO_PER_HEIGHT * height))


def published_ds_fraction(speed: Any) -> Any:
    """Adults' ``Td / T`` at ``speed``: stance ``64.2 − 3.5 V`` % of the cycle (Kirtley, Whittle &
    Jefferson 1985, 0.5–2 m/s), so one double support is ``0.142 − 0.035 V`` of it."""
    return 0.142 - 0.035 * np.asarray(speed, dtype=float)


def first_guess(speed: float, height: float) -> tuple[float, float]:
    """``(T, Td)``, s: :func:`published_cadence` and :func:`published_ds_fraction`, within the
    bounds."""
    root = math.sqrt(height / 1.77)
    cadence = float(published_cadence(speed, height))
    period = float(np.clip(120.0 / cadence, PERIOD_RANGE_S[0] * root, PERIOD_RANGE_S[1] * root))
    frac = float(np.clip(published_ds_fraction(speed), *DS_FRACTION_RANGE))
    return period, frac * period


def auto_descriptors(
    speed: float, height: float, period: float | None = None, ds: float | None = None
) -> tuple[float, float, tuple[str, ...]]:
    """``(T, Td, free)``: the given descriptors as they are, first guesses (:func:`first_guess`)
    for the others (None), which are then listed in ``free``. Raises ValueError when a given Td
    fits no period within the bounds."""
    free = tuple(name for name, v in zip(NAMES, (period, ds), strict=True) if v is None)
    t0, td0 = first_guess(speed, height)
    root = math.sqrt(height / 1.77)  # the bounds are the reference stature's
    if period is None and ds is not None:
        lo = max(PERIOD_RANGE_S[0] * root, ds / DS_FRACTION_RANGE[1])
        hi = min(PERIOD_RANGE_S[1] * root, ds / DS_FRACTION_RANGE[0])
        if lo > hi:
            raise ValueError(
                f"double support {ds:g} s fits no predicted period: Td/T must be within "
                f"{DS_FRACTION_RANGE[0]:g}-{DS_FRACTION_RANGE[1]:g} and T within "
                f"{PERIOD_RANGE_S[0] * root:.2f}-{PERIOD_RANGE_S[1] * root:.2f} s"
            )
        return float(np.clip(t0, lo, hi)), ds, free
    if period is not None and ds is None:
        return period, td0 / t0 * period, free
    if period is None:
        return t0, td0, free
    return period, float(ds), free
