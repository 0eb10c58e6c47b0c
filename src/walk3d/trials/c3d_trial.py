"""A C3D walking trial as OpenSim-style storages in walk3d's ground frame.

:func:`read_c3d_trial` turns a C3D file (:func:`walk3d.io.c3d.read_c3d`) into the two storages
the OpenSim trial code reads: a GRF storage (one ``ground_force_<k>_v/p``,
``ground_torque_<k>_`` family per force platform ``k = 1, 2, ...`` that is loaded above 20 N
at some time; the others are left out and noted) and, when the file has
them, an IK-like storage of Plug-in Gait joint angles plus ``pelvis_tx`` (the forward
coordinate of the pelvis markers' centroid, m, from which the trial's speed is found).

Lab frame to walk3d's ground frame (x forward, y up, z = x × y to the walker's right, as in
OpenSim). The mapping is an axis permutation with signs, decided explicitly in this order:

* **vertical**: the lab axis along which the summed plate force is largest on average (the
  body weight); **up** is its positive direction (C3D labs are Z up, some Y up) unless the
  pelvis markers lie on average below the plate surfaces. The force a plate reports (ezc3d's filter)
  is the foot's action on the plate; when its mean vertical component points down, force and
  free moment are negated to give the ground's reaction on the foot;
* **forward**, the first that applies: the ``forward`` argument (a lab axis such as ``"-y"``);
  the mean heel-to-toe direction of the Plug-in Gait foot markers (``RHEE``/``RTOE``,
  ``LHEE``/``LTOE``; works on treadmills); the progression of the pelvis markers (``LASI``,
  ``RASI``, ``LPSI``, ``RPSI``, ``SACR``) when faster than 0.2 m/s; the
  heel-to-toe motion of the centre of pressure during the plate contacts (overground only: on
  a treadmill it moves backward, so pass ``forward``). The direction is rounded to the nearest
  horizontal lab axis.

Plug-in Gait joint angles (points named ``[Subject:]RHipAngles`` etc., in degrees whatever
``POINT:UNITS`` says; Vicon, *Lower body angles as output from Plug-in Gait*,
https://vicon-help.atlassian.net/wiki/spaces/Nexus216/pages/11605551): component 1 hip flexion,
knee flexion, ankle dorsiflexion; component 2 hip adduction; component 3 hip internal rotation;
all positive with the same anatomical meaning on both sides. They map with sign +1
(:data:`PIG_ANGLES`) onto OpenSim's ``hip_flexion``, ``hip_adduction``, ``hip_rotation``,
``knee_angle`` (so the knee is **flexion positive**, Rajagopal's sign) and ``ankle_angle``.
Plug-in Gait's ankle inversion and rotation are about the tibia's axes, not the subtalar axis,
and its pelvis angles are about the progression frame: neither is mapped.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from walk3d.io.c3d import C3dData, ForcePlatform, read_c3d
from walk3d.io.errors import DataFileError
from walk3d.io.storage import Storage
from walk3d.io.trc import LENGTH_UNITS

__all__ = ["PIG_ANGLES", "C3dTrial", "LabAxes", "lab_axes", "parse_axis", "read_c3d_trial"]

PIG_ANGLES: tuple[tuple[str, int, str, float], ...] = (
    ("HipAngles", 0, "hip_flexion", 1.0),
    ("HipAngles", 1, "hip_adduction", 1.0),
    ("HipAngles", 2, "hip_rotation", 1.0),
    ("KneeAngles", 0, "knee_angle", 1.0),
    ("AnkleAngles", 0, "ankle_angle", 1.0),
)
"""Plug-in Gait point (without side letter), component, OpenSim coordinate, sign."""

PELVIS_MARKERS = ("LASI", "RASI", "LPSI", "RPSI", "SACR")
LOADED = 20.0
"""N: a plate whose vertical reaction never exceeds this is left out (no foot on it)."""
MIN_PROGRESSION = 0.2
"""m/s: slower marker progression is taken as a treadmill (no walking direction from it)."""


@dataclass(frozen=True)
class LabAxes:
    """walk3d's ground axes in lab coordinates and how they were found."""

    forward: np.ndarray
    up: np.ndarray
    reaction_sign: float
    method: str

    @property
    def right(self) -> np.ndarray:
        return np.cross(self.forward, self.up)

    @property
    def matrix(self) -> np.ndarray:
        """``R`` with ``v_walk3d = R @ v_lab`` (rows: forward, up, right)."""
        return np.vstack([self.forward, self.up, self.right])


@dataclass(frozen=True)
class C3dTrial:
    """A C3D file as storages: ``grf`` always, ``ik`` when it has angles or markers."""

    path: Path
    grf: Storage
    ik: Storage | None
    axes: LabAxes
    notes: tuple[str, ...] = ()


def _find_point(data: C3dData, name: str) -> np.ndarray | None:
    """Trajectory of the point labelled ``name`` or ``<subject>:name``, or None."""
    for k, label in enumerate(data.points.labels):
        if label == name or label.rsplit(":", 1)[-1] == name:
            return data.points.positions[:, k, :]
    return None


def _unit(axis: int, sign: float) -> np.ndarray:
    out = np.zeros(3)
    out[axis] = 1.0 if sign >= 0 else -1.0
    return out


def parse_axis(text: str) -> np.ndarray:
    """The lab axis ``text`` (``"+x"``, ``"-y"``, ``"z"``...) as a unit vector; ValueError (one
    line) for any other text."""
    t = text.strip().lower()
    sign = -1.0 if t.startswith("-") else 1.0
    name = t.lstrip("+-")
    if name not in ("x", "y", "z"):
        raise ValueError(f"forward axis must be one of +x, -x, +y, -y, +z, -z, got {text!r}")
    return _unit("xyz".index(name), sign)


def _horizontal(vector: np.ndarray, vertical: int) -> np.ndarray | None:
    """``vector`` rounded to the nearest horizontal lab axis, or None when it has no size."""
    v = np.array(vector, dtype=float)
    v[vertical] = 0.0
    if not np.all(np.isfinite(v)) or np.linalg.norm(v) < 1e-9:
        return None
    k = int(np.argmax(np.abs(v)))
    return _unit(k, v[k])


def _centroid(data: C3dData) -> np.ndarray | None:
    """``(N, 3)`` centroid of the pelvis markers, gaps interpolated; None without them.

    Other points are not used: a C3D's points also hold model outputs (angles, moments...)."""
    found = [p for p in (_find_point(data, m) for m in PELVIS_MARKERS) if p is not None]
    if not found:
        return None
    pos = np.stack(found, axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # frames with no marker seen
        mean = np.nanmean(pos, axis=1)
    ok = np.all(np.isfinite(mean), axis=1)
    if ok.sum() < 2:
        return None
    t = data.time
    return np.column_stack([np.interp(t, t[ok], mean[ok, a]) for a in range(3)])


def _slope(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Least-squares slopes of the columns of ``y`` against ``t``."""
    tc = t - t.mean()
    return (tc @ (y - y.mean(axis=0))) / float(tc @ tc)


def _cop_motion(data: C3dData, vertical: int, up_sign: float) -> np.ndarray:
    """Sum over the plates' contacts (> 20 N, at least 0.1 s) of the CoP's mean velocity."""
    total = np.zeros(3)
    for p in data.platforms:
        loaded = np.concatenate([[False], up_sign * p.force[:, vertical] > LOADED, [False]])
        edges = np.flatnonzero(np.diff(loaded.astype(int)))
        t = np.arange(p.force.shape[0]) / p.rate
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            cop = p.cop[a:b]
            if b - a >= 0.1 * p.rate and np.all(np.isfinite(cop)):
                total += _slope(t[a:b], cop)
    return total


def lab_axes(data: C3dData, forward: str | None = None) -> LabAxes:
    """walk3d's ground axes in the lab frame of ``data`` (see the module doc).

    Raises:
        DataFileError: No force platform, no load on the plates, or no walking direction.
    """
    if not data.platforms:
        raise DataFileError(data.path, "no force platform (cycles are cut at plate heel strikes)")
    total = np.nan_to_num(sum(p.force for p in data.platforms))
    vertical = int(np.argmax(np.mean(np.abs(total), axis=0)))
    up_sign = 1.0
    centre = _centroid(data)
    if centre is not None:
        plate_h = np.mean([p.corners[:, vertical].mean() for p in data.platforms])
        if np.mean(centre[:, vertical]) < plate_h:
            up_sign = -1.0
    up = _unit(vertical, up_sign)
    mean_up = float(np.mean(total[:, vertical])) * up_sign
    if mean_up == 0.0:
        raise DataFileError(data.path, "the force platforms are never loaded")
    reaction = 1.0 if mean_up > 0 else -1.0

    fwd, method = None, ""
    if forward is not None:
        fwd, method = _horizontal(parse_axis(forward), vertical), f"forward given as {forward}"
        if fwd is None:
            raise ValueError(f"forward axis {forward!r} is the vertical axis of {data.path.name}")
    if fwd is None:
        steps = []
        for side in "RL":
            heel, toe = _find_point(data, f"{side}HEE"), _find_point(data, f"{side}TOE")
            if heel is not None and toe is not None:
                steps.append(toe - heel)
        if steps:
            d = np.concatenate(steps)
            d = d[np.all(np.isfinite(d), axis=1)]
            fwd = _horizontal(d.mean(axis=0), vertical) if d.size else None
            method = "forward from the heel-to-toe markers"
    if fwd is None:
        if centre is not None:
            v = _slope(data.time, centre)
            v[vertical] = 0.0
            if np.linalg.norm(v) >= MIN_PROGRESSION:
                fwd, method = _horizontal(v, vertical), "forward from the marker progression"
    if fwd is None:
        fwd = _horizontal(_cop_motion(data, vertical, reaction * up_sign), vertical)
        method = "forward from the centre-of-pressure motion in contacts"
    if fwd is None:
        raise DataFileError(data.path, "cannot tell the walking direction: pass forward")
    return LabAxes(fwd, up, reaction, method)


def _grf_storage(data: C3dData, axes: LabAxes, plates: Sequence[ForcePlatform]) -> Storage:
    rot = axes.matrix
    n = min(p.force.shape[0] for p in plates)
    time = (data.first_frame - 1) / data.points.rate + np.arange(n) / plates[0].rate
    columns, blocks = [], []
    for p in plates:
        k = p.index + 1
        force = axes.reaction_sign * p.force[:n] @ rot.T
        cop = p.cop[:n] @ rot.T
        torque = axes.reaction_sign * p.free_moment[:n] @ rot.T
        off = ~(np.abs(force[:, 1]) > 1e-6) | ~np.all(np.isfinite(cop), axis=1)
        cop[off], torque[off] = 0.0, 0.0
        blocks += [np.nan_to_num(force), cop, np.nan_to_num(torque)]
        columns += [f"ground_force_{k}_v{a}" for a in "xyz"]
        columns += [f"ground_force_{k}_p{a}" for a in "xyz"]
        columns += [f"ground_torque_{k}_{a}" for a in "xyz"]
    return Storage(data.path.stem, time, columns, np.hstack(blocks), False, path=data.path)


def _ik_storage(data: C3dData, axes: LabAxes) -> Storage | None:
    scale = LENGTH_UNITS.get(data.points.units.strip().lower(), 1.0)
    columns, values = [], []
    for side in "RL":
        for point, comp, coord, sign in PIG_ANGLES:
            traj = _find_point(data, f"{side}{point}")
            if traj is not None:
                columns.append(f"{coord}_{side.lower()}")
                values.append(sign * traj[:, comp] / scale)  # degrees, undo read_c3d's scaling
    centre = _centroid(data)
    if centre is not None:
        columns.append("pelvis_tx")
        values.append(centre @ axes.forward)
    if not columns:
        return None
    values = np.column_stack(values)
    return Storage(data.path.stem, data.time, columns, values, True, path=data.path)


def read_c3d_trial(path: str | PathLike[str], *, forward: str | None = None) -> C3dTrial:
    """Read a C3D walking trial into a GRF storage and an angle storage (module doc).

    Args:
        path: The ``.c3d`` file.
        forward: The lab axis the walker faces (``"+x"``, ``"-y"``...); detected when None.

    Raises:
        FileNotFoundError: No such file.
        DataFileError: Malformed file, no force platform or no walking direction.
    """
    data = read_c3d(path)
    axes = lab_axes(data, forward)
    notes = [f"{data.path.name}: lab {_axis_name(axes.forward)} forward, "
             f"{_axis_name(axes.up)} up ({axes.method})"]  # fmt: skip
    vertical = [axes.reaction_sign * p.force @ axes.up for p in data.platforms]
    used = [p for p, f in zip(data.platforms, vertical, strict=True) if np.nanmax(f) > LOADED]
    if not used:
        raise DataFileError(data.path, f"no force platform is loaded above {LOADED:g} N")
    unused = [str(p.index + 1) for p in data.platforms if p.index not in {u.index for u in used}]
    if unused:
        notes.append(f"{data.path.name}: plate(s) {', '.join(unused)} never loaded, left out")
    ik = _ik_storage(data, axes)
    if ik is None or not any(c != "pelvis_tx" for c in ik.columns):
        notes.append(f"{data.path.name}: no Plug-in Gait joint angles")
    return C3dTrial(data.path, _grf_storage(data, axes, used), ik, axes, tuple(notes))


def _axis_name(v: np.ndarray) -> str:
    k = int(np.argmax(np.abs(v)))
    return ("+" if v[k] > 0 else "-") + "XYZ"[k]
