"""The quantities of the comparison (paper Table 2) and how a prediction reports them.

Every quantity is a right-side series over the gait cycle in the units of Table 2:

* ground reaction force on the right foot, N/kg, global axes (x forward, y up, z to the
  walker's right: OpenSim's ground frame, so a lateral force on the right foot is positive);
* joint moments, N m/kg, **internal** moments as OpenSim inverse dynamics reports them: the
  generalized force of each coordinate, positive when it would drive the coordinate positive;
* joint angles, degrees, with OpenSim's anatomical signs (hip/knee flexion, ankle
  dorsiflexion, subtalar inversion, adduction, internal rotation positive; lumbar extension,
  bending to the right, rotation to the left positive).

Keys are walk3d DoF names without the side suffix (``knee_flexion``) plus ``pelvis_*`` and
``grf_*``; :data:`QUANTITIES` lists them in table order.

Joint moments, walk3d versus OpenSim
-----------------------------------
walk3d reports the moment ``M`` of the parent on the child about the joint centre, resolved on
the parent's joint axes (:func:`walk3d.dynamics.newton_euler.resolve_joint_moments`). OpenSim's
inverse dynamics reports generalized forces ``τ_i = M · e_i``, where ``e_i`` is the current
axis of coordinate ``i``. Both are "parent on child", so the signs agree; what differs is the
axis. For hinges and the two ankle axes walk3d's active slot already is ``M · e_i``. For ball
joints (OpenSim's body-fixed Z-X-Y sequence, ``R = Rz(flex) Rx(add) Ry(rot)``) the axes are
``e_flex = z``, ``e_add = Rz(flex) x`` and ``e_rot = Rz(flex) Rx(add) y``, which are not the
parent axes once the joint is flexed (at 30° hip flexion half of the adduction moment would
otherwise appear as rotation moment). :func:`generalized_moments` therefore projects walk3d's
moment on the Euler axes, so that ``Σ τ_i q̇_i = M · ω_rel`` (the joint power) holds exactly.
Left joints use the mirror image of moment and rotation, which walk3d's mirrored left axes
already provide.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walk3d.body.model import build_body
from walk3d.results.angles import pelvis_angles
from walk3d.results.opensim import OPENSIM_COORDINATES
from walk3d.results.prediction import PredictedCycle

__all__ = [
    "GROUPS",
    "MIRRORED_ON_LEFT",
    "QUANTITIES",
    "Quantity",
    "generalized_moments",
    "prediction_series",
    "quantity",
]

GROUPS = ("grf", "moment", "angle")
GROUP_UNITS = {"grf": "N/kg", "moment": "N m/kg", "angle": "deg"}
GROUP_TITLES = {"grf": "Ground reaction force", "moment": "Joint moment", "angle": "Joint angle"}


@dataclass(frozen=True)
class Quantity:
    """One compared series."""

    key: str
    """Unique key, e.g. ``angle:knee_flexion``."""
    group: str
    """``grf``, ``moment`` or ``angle``."""
    name: str
    """DoF name without side (``knee_flexion``), ``pelvis_tilt``... or ``grf_vertical``."""
    label: str
    coordinate: str | None
    """OpenSim coordinate name without side (``knee_angle``); None for GRF."""
    axis: int | None = None
    """GRF axis (0 x, 1 y, 2 z)."""

    @property
    def unit(self) -> str:
        return GROUP_UNITS[self.group]


_JOINT_ROWS = (
    ("ankle_dorsiflexion", "Ankle dorsiflexion"),
    ("subtalar_inversion", "Subtalar inversion"),
    ("knee_flexion", "Knee flexion"),
    ("hip_adduction", "Hip adduction"),
    ("hip_rotation", "Hip internal rotation"),
    ("hip_flexion", "Hip flexion"),
    ("lumbar_bending", "Waist bending (right +)"),
    ("lumbar_rotation", "Waist rotation (left +)"),
    ("lumbar_extension", "Waist extension"),
    ("arm_flex", "Shoulder flexion"),
    ("arm_add", "Shoulder adduction"),
    ("arm_rot", "Shoulder internal rotation"),
    ("elbow_flex", "Elbow flexion"),
    ("neck_flexion", "Neck flexion"),
)
_PELVIS_ROWS = (
    ("pelvis_tilt", "Pelvis tilt (posterior +)"),
    ("pelvis_list", "Pelvis list"),
    ("pelvis_rotation", "Pelvis rotation"),
)
_GRF_ROWS = (
    ("grf_fore_aft", "GRF fore-aft (Fx, forward +)", 0),
    ("grf_vertical", "GRF vertical (Fy)", 1),
    ("grf_lateral", "GRF lateral (Fz, right +)", 2),
)


def _coordinate(name: str) -> str:
    """OpenSim coordinate (no side) of a walk3d DoF name (no side)."""
    if name.startswith("pelvis_"):
        return name
    full = OPENSIM_COORDINATES.get(f"{name}_r", OPENSIM_COORDINATES.get(name, name))
    return full[:-2] if full.endswith("_r") else full


def _build() -> tuple[Quantity, ...]:
    rows = [Quantity(f"grf:{n}", "grf", n, lab, None, ax) for n, lab, ax in _GRF_ROWS]
    rows += [Quantity(f"moment:{n}", "moment", n, lab, _coordinate(n)) for n, lab in _JOINT_ROWS]
    rows += [Quantity(f"angle:{n}", "angle", n, lab, _coordinate(n)) for n, lab in _PELVIS_ROWS]
    rows += [Quantity(f"angle:{n}", "angle", n, lab, _coordinate(n)) for n, lab in _JOINT_ROWS]
    return tuple(rows)


QUANTITIES: tuple[Quantity, ...] = _build()
"""Table order: GRF, joint moments, joint angles (pelvis first)."""

MIRRORED_ON_LEFT = frozenset(
    {"pelvis_list", "pelvis_rotation", "lumbar_bending", "lumbar_rotation", "grf_lateral"}
)
"""Quantities whose sign flips when a left-leg cycle stands in for the right leg (midline
frontal/transverse components and the lateral force). Limb coordinates need no flip: OpenSim's
left axes are mirrored, so ``hip_adduction_l`` already has the right leg's anatomical sign."""


def quantity(key: str) -> Quantity:
    """The quantity with this key (``KeyError`` when unknown)."""
    for q in QUANTITIES:
        if q.key == key:
            return q
    raise KeyError(f"no quantity {key!r}")


def _euler_axes(angles: np.ndarray) -> np.ndarray:
    """(N, 3, 3) axes ``e_add, e_rot, e_flex`` (rows) of Z-X-Y angles in slot order."""
    add, _, flex = angles[:, 0], angles[:, 1], angles[:, 2]
    cf, sf, ca, sa = np.cos(flex), np.sin(flex), np.cos(add), np.sin(add)
    zero, one = np.zeros_like(flex), np.ones_like(flex)
    e_add = np.stack([cf, sf, zero], axis=-1)
    e_rot = np.stack([-sf * ca, cf * ca, sa], axis=-1)
    e_flex = np.stack([zero, zero, one], axis=-1)
    return np.stack([e_add, e_rot, e_flex], axis=1)


def generalized_moments(pred: PredictedCycle) -> dict[str, np.ndarray]:
    """OpenSim-style generalized forces (N m) of every DoF, keyed by walk3d DoF name.

    See the module doc: ball joints are projected on their Z-X-Y Euler axes, hinges and the
    universal ankle report their active slots as they are.
    """
    body = build_body()
    if tuple(pred.dof_names) != body.dof_names or tuple(pred.joint_names) != tuple(
        j.name for j in body.joints
    ):
        raise ValueError("the prediction's DoF or joint names differ from walk3d's body model")
    out: dict[str, np.ndarray] = {}
    i = 0
    for j, joint in enumerate(body.joints):
        m = pred.joint_moment[:, j, :]
        if joint.kind == "ball":
            axes = _euler_axes(pred.joint_angle[:, i : i + 3])
            tau = np.einsum("nk,nik->ni", m, axes)
            for k, name in enumerate(joint.dof_names):
                out[name] = tau[:, k]
        else:
            for name, slot in zip(joint.dof_names, joint.dof_slots, strict=True):
                out[name] = m[:, slot].copy()
        i += joint.n_dof
    return out


def prediction_series(pred: PredictedCycle) -> dict[str, np.ndarray]:
    """Every quantity of :data:`QUANTITIES` for the prediction's right side, on ``pred.time``.

    Units as in the module doc (N/kg, N m/kg, degrees); body mass is the sum of the segment
    masses.
    """
    mass = pred.body_mass
    tau = generalized_moments(pred)
    pelvis = np.degrees(pelvis_angles(pred.segment_orientation[:, 0, :]))
    out: dict[str, np.ndarray] = {}
    for q in QUANTITIES:
        if q.group == "grf":
            out[q.key] = pred.grf_force[:, 0, q.axis] / mass
        elif q.name.startswith("pelvis_"):
            out[q.key] = pelvis[:, ("pelvis_tilt", "pelvis_list", "pelvis_rotation").index(q.name)]
        else:
            dof = q.name if q.name in pred.dof_names else f"{q.name}_r"
            if q.group == "moment":
                out[q.key] = tau[dof] / mass
            else:
                out[q.key] = np.degrees(pred.dof(dof))
    return out
