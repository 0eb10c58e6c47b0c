"""The one place that defines the order of the unknowns and the constraint rows.

* ``x = [c (15 × 11 Fourier coefficients, series-major), half_step_width]``: 166 entries, the
  decision vector of a prediction;
* ``z = [x, vec(Y) (nodes × 78), W0 (6), vec(T) (nodes × 24), s]``: the lifted NLP's variables,
  ``s = [T, Td]`` only when a descriptor is predicted (:mod:`walk3d.problem.descriptors`);
* ``g = [lifting (nodes × 78), node rows (nodes × N_G), heel-strike tie (6), joint ranges,
  loop checks, Td / T rows (2, with s)]``: its constraint rows, each node's block :data:`G_ROWS`.

:class:`NlpLayout` gives the ``z`` and ``g`` blocks of a grid; the NLP
(:mod:`walk3d.problem.nlp`), its bounds, its derivatives and the solver all use it.

The 15 series (paper section 2.5; one per independent quaternion element):

====  ====================  ==============================================================
 #    series                 quaternion element
====  ====================  ==============================================================
 0    ``waist_x``            waist vector part along x (frontal); odd harmonics only
 1    ``waist_y``            waist vector part along y (transverse); odd harmonics only
 2    ``waist_z``            waist vector part along z (sagittal); even harmonics only
 3    ``neck``               sin(θ/2) of the neck hinge; even harmonics only
 4–6  ``shoulder_x/y/z``     right shoulder vector part
 7    ``elbow``              sin(θ/2), right elbow
 8–10 ``hip_x/y/z``          right hip vector part
 11   ``knee``               sin(θ/2), right knee
 12   ``ankle_tc``           sin(θ/2), right talocrural (dorsiflexion) axis
 13   ``ankle_st``           sin(θ/2), right subtalar (inversion) axis
 14   ``foot``               sin(θ_ft/2), right stance-foot rotation (used during stance only)
====  ====================  ==============================================================

Each series' 11 coefficients are ``[a0, a1, b1, …, a5, b5]`` (:mod:`walk3d.kinematics.fourier`).

Left/right symmetry: the left side's series is the right side's shifted by half a cycle; the
mirrored left joint axes (``walk3d.body.model``) make equal values mirror-image postures, so the
frontal and transverse components flip sign in space and the sagittal one does not. The midline
joints must then satisfy ``q(t + T/2) = mirror(q(t))``: their frontal/transverse elements hold
only odd harmonics and their sagittal elements only even ones. Those coefficients stay in the
vector (so the layout is the paper's 165) but are fixed at zero by their bounds.

The full-cycle problem (:mod:`walk3d.problem.full_cycle`, for one-sided changes) has its own
vector ``X = [x_R, x_L]`` (:data:`N_XF`): every series over the whole cycle, each side with its
own. ``x_R`` gives the right side, the midline (all harmonics: no symmetry) and the half step
width; ``x_L`` the left side's sided series (4–14), as the left's own series shifted by half a
cycle, like the half cycle's left side; its midline series are unused (fixed at zero), and its
width entry holds the step shift ``d`` (:data:`I_STEP_SHIFT`, m): the right step (right heel
ahead of the left at right heel strike) is ``V T / 2 + d``, the left one ``V T / 2 − d``.
:func:`full_coordinate_maps` gives the coordinates from ``X``.

The extra scalar, ``half_step_width``, is the lateral distance of each foot's ankle from the
line of progression at foot flat. The paper's closed double-support loop needs it (the trailing
foot must land where the chain puts it); it is also a useful output.

Coordinates: the 26 per-node coordinates are the 24 joint coordinates in
:attr:`walk3d.body.model.BodyModel.dof_names` order followed by the right and left stance-foot
rotations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walk3d.kinematics import fourier
from walk3d.model.coordinates import I_FOOT_L as I_FOOT_L
from walk3d.model.coordinates import I_FOOT_R as I_FOOT_R
from walk3d.model.coordinates import N_COORD

SERIES_NAMES = (
    "waist_x", "waist_y", "waist_z", "neck", "shoulder_x", "shoulder_y", "shoulder_z", "elbow",
    "hip_x", "hip_y", "hip_z", "knee", "ankle_tc", "ankle_st", "foot",
)  # fmt: skip
N_SERIES = len(SERIES_NAMES)
N_COEF = fourier.N_COEF
N_X = N_SERIES * N_COEF + 1
I_HALF_STEP = N_SERIES * N_COEF
N_Y = 3 * N_COORD
"""Lifted variables per NLP node: the 26 coordinates, their rates / ω and accelerations / ω²."""
N_T = 24
"""Slack variables per NLP node, one per DoF (criterion absolute values)."""
N_W0 = 6
"""The trailing foot's load at right heel strike: force and moment, in body weights."""
N_P = 6
"""Node parameters ``p = [decay, anchor_x, ω, h, ḣ/ω, ḧ/ω²]``
(:func:`walk3d.problem.schedule.node_params`; ``h`` the handover share, unused without the
handover). The cycle frequency is a parameter, not a constant of the node function, so that one
node function, and the derivatives compiled from it, serve every V, T and Td of a body."""

G_ROWS = {
    "loop_position": slice(0, 3),
    "loop_orientation": slice(3, 6),
    "loop_velocity": slice(6, 9),
    "loop_omega": slice(9, 12),
    "other_points_y": slice(12, 16),
    "ankle_separation": slice(16, 17),
    "torso": slice(17, 20),
    "root_force": slice(20, 25),
    "other_force": slice(25, 30),
    "hs_wrench": slice(30, 36),
    "ball_norm": slice(36, 41),
    "slack_pos": slice(41, 65),
    "slack_neg": slice(65, 89),
    "root_support": slice(89, 95),
    "other_support": slice(95, 101),
}
"""Rows of one node's block of ``g`` (:func:`walk3d.problem.nlp.node_function`), contiguous."""
N_G = max(r.stop for r in G_ROWS.values())
"""Rows per node."""
N_V = N_Y + N_W0 + 1 + N_T
"""Variables one node's rows depend on: ``[Y_k, W0, half step width, T_k]``."""

# coordinate index -> (series index, shifted by half a cycle?)
COORD_SOURCE: tuple[tuple[int, bool], ...] = (
    (0, False), (1, False), (2, False), (3, False),              # waist, neck
    (4, False), (5, False), (6, False), (7, False),              # right arm
    (4, True), (5, True), (6, True), (7, True),                  # left arm
    (8, False), (9, False), (10, False), (11, False), (12, False), (13, False),  # right leg
    (8, True), (9, True), (10, True), (11, True), (12, True), (13, True),        # left leg
    (14, False), (14, True),                                      # feet
)  # fmt: skip
PARITY = {0: "odd", 1: "odd", 2: "even", 3: "even"}


def coefficients(x: np.ndarray) -> np.ndarray:
    """(15, 11) coefficient matrix from the decision vector."""
    return np.asarray(x[: N_SERIES * N_COEF]).reshape(N_SERIES, N_COEF)


def fixed_zero_mask() -> np.ndarray:
    """Boolean (N_X,) mask of coefficients fixed at zero by the midline symmetry."""
    mask = np.zeros(N_X, dtype=bool)
    for s, parity in PARITY.items():
        other = "even" if parity == "odd" else "odd"
        mask[s * N_COEF : (s + 1) * N_COEF] = fourier.harmonic_parity_mask(other)
    return mask


def coordinate_maps(t: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear maps ``A0, A1, A2`` of shape (len(t), 26, N_X) with ``coords = A @ x``.

    ``A0 @ x`` gives the 26 coordinates at each time, ``A1``, ``A2`` their time derivatives:
    :func:`full_coordinate_maps` with both sides on the one vector ``x``.
    """
    return tuple(a[:, :, :N_X] + a[:, :, N_X:] for a in full_coordinate_maps(t, period))


N_XF = 2 * N_X
"""Entries of the full-cycle problem's ``X = [x_R, x_L]``."""
MIDLINE = (0, 1, 2, 3)
"""The midline series (waist, neck): one per cycle, in ``x_R``."""
MIRROR_SIGN = (-1.0, -1.0, 1.0, 1.0)
"""Sign of each midline series under left/right mirroring: the frontal and transverse waist
elements flip, the sagittal ones do not."""


I_STEP_SHIFT = N_X + I_HALF_STEP
"""``X``'s step shift ``d`` (m, module doc): 0 for steps of equal length."""


def half_cycle_x(x: np.ndarray) -> np.ndarray:
    """A half-cycle decision vector from ``x`` or a full cycle's ``X`` (a warm start): ``X``'s
    right side, midline and width, with the half cycle's fixed zeros (the inverse of
    :func:`walk3d.solve.full_cycle.mirrored_start` on a symmetric ``X``)."""
    out = np.array(x, dtype=float)[:N_X].copy()
    out[fixed_zero_mask()] = 0.0
    return out


def full_fixed_zero_mask() -> np.ndarray:
    """Boolean (N_XF,) mask of ``X``'s unused entries: ``x_L``'s midline series."""
    mask = np.zeros(N_XF, dtype=bool)
    mask[N_X : N_X + len(MIDLINE) * N_COEF] = True
    return mask


def full_coordinate_maps(
    t: np.ndarray, period: float, mirrored: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear maps ``(len(t), 26, N_XF)`` with ``coords = A @ X`` (full-cycle problem).

    ``mirrored`` False: the coordinates at ``t``. True: the coordinates half a cycle later seen
    mirrored, sides swapped (the left foot's step as the right's), at ``t``: the sided rows
    take the other side's series, the midline ones the series half a cycle on, mirrored.
    """
    b = fourier.basis(t, period)
    shift = fourier.half_cycle_shift()
    maps = []
    for bk in b:
        a = np.zeros((len(t), N_COORD, N_XF))
        for i, (s, shifted) in enumerate(COORD_SOURCE):
            if s in MIDLINE:
                block, part = (bk @ shift * MIRROR_SIGN[s], 0) if mirrored else (bk, 0)
            else:  # right rows: x_R unshifted; left rows: x_L shifted (swapped when mirrored)
                block, part = (bk @ shift if shifted else bk), (int(shifted) ^ int(mirrored))
            cols = part * N_X + s * N_COEF
            a[:, i, cols : cols + N_COEF] = block
        maps.append(a)
    return maps[0], maps[1], maps[2]


@dataclass(frozen=True)
class NlpLayout:
    """The blocks of ``z`` and ``g`` (module doc) for ``nodes`` nodes, ``n_range`` joint-range
    rows and ``n_loop`` loop-check rows."""

    nodes: int
    n_range: int = 0
    n_loop: int = 0
    n_s: int = 0
    """Descriptor unknowns ``s = [T, Td]`` at the end of ``z`` (:mod:`walk3d.problem.descriptors`),
    with their two rows on ``Td / T`` at the end of ``g``; 0 when T and Td are given."""
    n_split: int = 0
    """The free split's coefficients (``6 K``, :mod:`walk3d.contact.free_split`), right after
    ``W0`` in its block; 0 for the paper's split."""

    @property
    def n_w0(self) -> int:
        """Size of the ``w0`` block: ``W0`` and the free split's coefficients."""
        return N_W0 + self.n_split

    @property
    def n_v(self) -> int:
        """Variables one node's rows depend on: ``[Y_k, W0 (and C), half step width, T_k]``."""
        return N_V + self.n_split

    def _z(self) -> dict[str, int]:
        return {"x": N_X, "y": self.nodes * N_Y, "w0": self.n_w0, "t": self.nodes * N_T,
                "s": self.n_s}  # fmt: skip

    def _g(self) -> dict[str, int]:
        return {"lift": self.nodes * N_Y, "node": self.nodes * N_G, "hs": N_W0,
                "range": self.n_range, "loop": self.n_loop, "desc": self.n_s}  # fmt: skip

    @staticmethod
    def _block(sizes: dict[str, int], name: str) -> slice:
        start = 0
        for key, size in sizes.items():
            if key == name:
                return slice(start, start + size)
            start += size
        raise KeyError(name)

    def z(self, name: str) -> slice:
        """Block ``x``, ``y``, ``w0``, ``t`` or ``s`` of ``z``."""
        return self._block(self._z(), name)

    def g(self, name: str) -> slice:
        """Block ``lift``, ``node``, ``hs``, ``range``, ``loop`` or ``desc`` of ``g``."""
        return self._block(self._g(), name)

    @property
    def n_z(self) -> int:
        return sum(self._z().values())

    @property
    def n_g(self) -> int:
        return sum(self._g().values())

    def g_names(self) -> list[str]:
        """A name for each row of ``g``: ``node 3 root_support[2]``, ``range 5``, ..."""
        per_node = [f"{name}[{i}]" for name, rows in G_ROWS.items()
                    for i in range(rows.stop - rows.start)]  # fmt: skip
        out = [f"lift {k} {i}" for k in range(self.nodes) for i in range(N_Y)]
        out += [f"node {k} {r}" for k in range(self.nodes) for r in per_node]
        out += [f"heel-strike wrench[{i}]" for i in range(N_W0)]
        out += [f"range {i}" for i in range(self.n_range)]
        out += [f"loop check {i}" for i in range(self.n_loop)]
        return out + [f"descriptor {i}" for i in range(self.n_s)]

    def z_names(self, dofs: tuple[str, ...]) -> list[str]:
        """A name for each entry of ``z`` (``dofs``: the 24 DoF names): ``Y 3 knee_flexion_r``
        (a node's coordinate value; ``rate``, ``accel`` for the others), ``x 12``, ..."""
        coords = [*dofs, "foot_r", "foot_l"]
        kinds = ("", " rate", " accel")
        y = [f"Y {k} {c}{kind}" for k in range(self.nodes) for kind in kinds for c in coords]
        return ([f"x {i}" for i in range(N_X)] + y + [f"W0[{i}]" for i in range(N_W0)]
                + [f"C{j}[{i}]" for j in range(self.n_split // 6) for i in range(6)]
                + [f"slack {k} {d}" for k in range(self.nodes) for d in dofs]
                + [f"s {i}" for i in range(self.n_s)])  # fmt: skip

    def node_columns(self, k: int) -> np.ndarray:
        """Positions in ``z`` of node k's variables ``[Y_k, W0, half step width, T_k]``."""
        y, w0, t = self.z("y").start, self.z("w0").start, self.z("t").start
        return np.concatenate([y + k * N_Y + np.arange(N_Y), w0 + np.arange(self.n_w0),
                               [I_HALF_STEP], t + k * N_T + np.arange(N_T)])  # fmt: skip

    def node_rows(self, g: np.ndarray) -> np.ndarray:
        """The node rows of a full ``g`` as ``(nodes, N_G)``."""
        return np.asarray(g)[self.g("node")].reshape(self.nodes, N_G)
