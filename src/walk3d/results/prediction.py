"""The result of one walking prediction, and its result folder on disk.

A :class:`PredictedCycle` holds time series sampled at ``N`` nodes (time first, SI units, radians)
and a JSON-ready ``summary`` dictionary. :func:`save_prediction` writes a result folder:

* ``result.npz``: every array of :class:`PredictedCycle` under its field name (``time``,
  ``segment_names``, ``segment_mass``, ``segment_inertia``, ``segment_com_position``,
  ``segment_orientation``, ``dof_names``, ``joint_angle``, ``joint_names``, ``joint_moment``,
  ``joint_axis_active``, ``grf_force``, ``grf_cop``, ``grf_free_moment``, ``pelvis_position``),
  names as unicode arrays (readable with ``allow_pickle=False``). The only unit change is
  ``joint_angle``, stored in **degrees**; everything else is SI as in memory;
* ``summary.json``: the summary, indented, keys sorted;
* ``motion.mot``: OpenSim coordinates in degrees (:func:`walk3d.results.opensim.write_motion`);
* ``grf.mot`` and ``grf.xml``: ground reactions and their OpenSim ExternalLoads file
  (:func:`walk3d.results.opensim.write_grf`);
* ``model.osim``: the OpenSim model of the subject's walk3d skeleton, on which ``motion.mot``
  plays (:func:`walk3d.results.osim_model.osim_model`, :func:`walk3d.io.osim.write_osim`);
* ``inverse_dynamics.sto``: walk3d's joint moments as that model's generalized forces, under
  the names of OpenSim's InverseDynamicsTool
  (:func:`walk3d.results.inverse_dynamics.write_inverse_dynamics`);
* ``markers.c3d``: virtual Plug-in Gait markers and the feet's loads on two force platforms,
  a lab trial for clinical gait software (:func:`walk3d.results.lab_trial.write_markers_c3d`).

* ``manifest.json``: written last, every file's name and size (:func:`check_complete`).

Views (:data:`VIEW_FILES`) and ``validation/`` (``walk3d validate``'s default ``--out``) may
be added later. An earlier result is replaced only when the folder holds nothing else
(:func:`check_result_folder`).

The folder is written atomically: built in a temporary sibling, then renamed into place.
:func:`load_result` reads ``result.npz`` and ``summary.json`` back; all arrays come back
bit-for-bit except ``joint_angle``, whose degree-radian round trip is exact to ~1 ulp.
"""

from __future__ import annotations

import io
import json
import os
from collections.abc import Callable, Collection
from dataclasses import dataclass, field, fields
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d import outputs
from walk3d.body.model import BodyModel
from walk3d.io.atomic import atomic_folder, atomic_write_bytes, atomic_write_text
from walk3d.io.checks import (
    file_digest,
    plain_file_name,
    read_json_object,
    read_npz,
)
from walk3d.io.errors import DataFileError
from walk3d.io.osim import write_osim
from walk3d.results.folder_kind import not_a_prediction
from walk3d.results.inverse_dynamics import write_inverse_dynamics
from walk3d.results.lab_trial import write_markers_c3d
from walk3d.results.opensim import write_grf, write_motion
from walk3d.results.osim_model import motion_extent, osim_model, prediction_body
from walk3d.results.readback import NAME_FIELDS, check_masses, read_field, readable_arrays

__all__ = [
    "C3D_FILES",
    "MANIFEST",
    "OPENSIM_FILES",
    "PredictedCycle",
    "RESULT_FILES",
    "VALIDATION_FILES",
    "VALIDATION_FOLDER",
    "check_complete",
    "check_result_folder",
    "load_result",
    "record_file",
    "save_prediction",
    "written_files",
]

RESULT_FILES = ("result.npz", "summary.json", "motion.mot", "grf.mot", "grf.xml")
"""The files every result folder has (:func:`check_complete` requires them)."""

OPENSIM_FILES = ("model.osim", "inverse_dynamics.sto")
"""Also written by :func:`save_prediction`; folders written before it wrote them lack them, so
they are checked only where the manifest lists them."""

C3D_FILES = ("markers.c3d",)
"""Also written by :func:`save_prediction`, checked like :data:`OPENSIM_FILES`."""

VIEW_FILES = ("summary.png", "animation.mp4", "report.html")
"""Views of the result, remade from it at any time and each replaced atomically: their listed
size may lag a rewrite that ended before the manifest was updated, so only their presence is
checked."""

UNREAD_VIEWS = ("summary.png",)
"""Views no command reads or embeds: a deleted one is accepted (:func:`check_complete`)."""

MANIFEST = "manifest.json"
"""Written last into a result folder: every file's name and size in bytes."""

VALIDATION_FOLDER = "validation"
"""``walk3d validate``'s default ``--out``, inside the result folder."""

VALIDATION_FILES = ("table2.csv", "table3.csv", "measured_fit.csv", "score.json", "grf.png",
                    "moments.png", "angles.png")  # fmt: skip
"""What :func:`walk3d.validation.run.validate` writes into its folder."""


@dataclass(frozen=True, eq=False)
class PredictedCycle:
    """A predicted walking cycle (read-only arrays, time first, SI units, radians);
    :class:`walk3d.Prediction` also tabulates, plots and saves it.

    Shapes use ``N`` time nodes, 13 segments, 24 DoF and 12 joints (the body model's orders,
    see :mod:`walk3d.body.model`); only the consistency between fields is checked, so other
    counts are accepted.
    """

    time: np.ndarray
    """(N,) s."""
    segment_names: tuple[str, ...]
    segment_mass: np.ndarray
    """(S,) kg."""
    segment_inertia: np.ndarray
    """(S, 3, 3) kg m², about the segment's centre of mass, in the segment frame."""
    segment_com_position: np.ndarray
    """(N, S, 3) m, global."""
    segment_orientation: np.ndarray
    """(N, S, 4) scalar-first unit quaternions, segment frame -> global."""
    dof_names: tuple[str, ...]
    joint_angle: np.ndarray
    """(N, D) rad, one column per DoF."""
    joint_names: tuple[str, ...]
    joint_moment: np.ndarray
    """(N, J, 3) N m on each joint's (x, y, z) axes (see ``Joint.axes``)."""
    joint_axis_active: np.ndarray
    """(J, 3) bool: which axis slots of each joint carry a DoF (the rest are constrained)."""
    grf_force: np.ndarray
    """(N, 2, 3) N on the [right, left] foot, global."""
    grf_cop: np.ndarray
    """(N, 2, 3) m centre of pressure, global; NaN where the foot is off the ground."""
    grf_free_moment: np.ndarray
    """(N, 2) N m about the vertical axis."""
    pelvis_position: np.ndarray
    """(N, 3) m: origin of the pelvis frame (midway between the hip joint centres), global."""
    summary: dict[str, Any] = field(default_factory=dict)
    """JSON-ready description of the run (inputs, convergence, criteria, ...)."""

    def __post_init__(self) -> None:
        for name in NAME_FIELDS:
            object.__setattr__(self, name, tuple(str(s) for s in getattr(self, name)))
        n_seg, n_dof, n_joint = (len(self.segment_names), len(self.dof_names),
                                 len(self.joint_names))  # fmt: skip
        time = np.asarray(self.time, dtype=float).reshape(-1)
        n = time.size
        shapes = {
            "time": (n,),
            "segment_mass": (n_seg,),
            "segment_inertia": (n_seg, 3, 3),
            "segment_com_position": (n, n_seg, 3),
            "segment_orientation": (n, n_seg, 4),
            "joint_angle": (n, n_dof),
            "joint_moment": (n, n_joint, 3),
            "joint_axis_active": (n_joint, 3),
            "grf_force": (n, 2, 3),
            "grf_cop": (n, 2, 3),
            "grf_free_moment": (n, 2),
            "pelvis_position": (n, 3),
        }
        for name, shape in shapes.items():
            dtype = bool if name == "joint_axis_active" else float
            arr = np.array(time if name == "time" else getattr(self, name), dtype=dtype)
            if arr.shape != shape:
                raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if not isinstance(self.summary, dict):
            raise TypeError(f"summary must be a dict, got {type(self.summary).__name__}")
        object.__setattr__(self, "summary", dict(self.summary))

    @property
    def n_nodes(self) -> int:
        """Number of time nodes ``N``."""
        return int(self.time.size)

    @property
    def body_mass(self) -> float:
        """Total body mass, kg (sum of the segment masses)."""
        return float(np.sum(self.segment_mass))

    def dof(self, name: str) -> np.ndarray:
        """Angle of one DoF over time, rad (``KeyError`` when absent)."""
        try:
            return self.joint_angle[:, self.dof_names.index(name)]
        except ValueError:
            raise KeyError(f"no DoF {name!r}") from None

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PredictedCycle):
            return NotImplemented
        for f in fields(self):
            a, b = getattr(self, f.name), getattr(other, f.name)
            if isinstance(a, np.ndarray):
                if not np.array_equal(a, b, equal_nan=a.dtype != bool):
                    return False
            elif a != b:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (Path, PathLike)):
        return os.fspath(value)
    raise TypeError(f"summary value of type {type(value).__name__} is not JSON serialisable")


def _npz_arrays(pred: PredictedCycle) -> dict[str, np.ndarray]:
    arrays: dict[str, np.ndarray] = {}
    for f in fields(pred):
        if f.name == "summary":
            continue
        value = getattr(pred, f.name)
        if f.name in NAME_FIELDS:
            arrays[f.name] = np.array(value, dtype=str)
        elif f.name == "joint_angle":
            arrays[f.name] = np.degrees(value)
        else:
            arrays[f.name] = np.asarray(value)
    return arrays


def save_prediction(
    pred: PredictedCycle,
    out_dir: str | PathLike[str],
    extra: Callable[[Path], object] | None = None,
    body: BodyModel | None = None,
) -> Path:
    """Write the result folder of ``pred`` (see the module doc) as one atomic step and return
    it; ``body`` is the body model it was evaluated with (default: rebuilt from its settings).

    The files are built in a temporary sibling folder; ``extra(folder)`` may add more (the
    summary figure); ``manifest.json`` is written last and the folder is then renamed to
    ``out_dir``, replacing an earlier result. On any failure nothing is left behind.

    Raises:
        ValueError: an array :func:`load_result` would refuse (non-finite, time not a cycle).
    """
    out = Path(out_dir)
    arrays = readable_arrays(_npz_arrays(pred), out, pred.summary)  # refused before writing
    with atomic_folder(out) as tmp:
        buffer = io.BytesIO()
        np.savez(buffer, **arrays)
        atomic_write_bytes(tmp / "result.npz", buffer.getvalue())
        text = json.dumps(pred.summary, indent=2, sort_keys=True, default=_json_default)
        atomic_write_text(tmp / "summary.json", text + "\n")
        write_motion(tmp / "motion.mot", pred)
        write_grf(tmp / "grf.mot", pred, xml_path=tmp / "grf.xml")
        body = body or prediction_body(pred)
        write_osim(tmp / "model.osim", osim_model(body, motion_extent(pred)))
        write_inverse_dynamics(tmp / "inverse_dynamics.sto", pred, body)
        write_markers_c3d(tmp / "markers.c3d", pred, body)
        if extra is not None:
            extra(tmp)
        files = {p.name: p.stat().st_size for p in sorted(tmp.iterdir()) if p.is_file()}
        manifest = {"files": files, "sha256": {n: file_digest(tmp / n) for n in DIGESTED}}
        atomic_write_text(tmp / MANIFEST, json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    return out


DIGESTED = ("result.npz",)
"""Files whose SHA-256 the manifest holds, checked by :func:`check_complete`: the arrays,
which nothing else ties to their summary (a ``result.npz`` swapped between two folders of the
same size passes every other check). About 1 ms per check."""


def check_complete(out_dir: str | PathLike[str], remade: Collection[str] = ()) -> None:
    """Raise :class:`DataFileError` unless ``out_dir`` is a complete result folder: its
    ``manifest.json`` is readable and every file it lists is there with the listed size (for
    :data:`VIEW_FILES`, only there; the views in ``remade``, about to be made again, and the
    :data:`UNREAD_VIEWS` may be missing)."""
    out = Path(out_dir)
    path = out / MANIFEST
    if not out.is_dir():
        raise DataFileError(out, "not a result folder")
    if not path.is_file():
        not_a_prediction(out)
        raise DataFileError(
            out, f"incomplete result folder: no {MANIFEST} (written last by walk3d predict)"
        )
    manifest = read_json_object(path, "walk3d manifest")
    files = manifest.get("files")
    if not isinstance(files, dict):
        raise DataFileError(path, "not a walk3d manifest: no 'files' object")
    for name, size in files.items():
        plain_file_name(path, name, "listed file")
        if not isinstance(size, int) or isinstance(size, bool) or size < 0:
            raise DataFileError(path, f"the size of {name} is {size!r:.40}, not a byte count")
    digests = manifest.get("sha256", {})
    for name in (*RESULT_FILES, *files):
        f = out / name
        optional = name in VIEW_FILES and (name in remade or name in UNREAD_VIEWS)
        if not f.is_file() and not optional:
            raise DataFileError(out, f"incomplete result folder: {name} is missing")
        if name in files and name not in VIEW_FILES and f.stat().st_size != files[name]:
            raise DataFileError(
                f, f"incomplete result file: {f.stat().st_size} bytes, manifest says {files[name]}"
            )
    if not isinstance(digests, dict):
        raise DataFileError(path, "not a walk3d manifest: 'sha256' is not an object")
    for name, digest in digests.items():
        if name in DIGESTED and (out / name).is_file() and file_digest(out / name) != digest:
            raise DataFileError(out / name, "changed since walk3d wrote it (its SHA-256 is not "
                                "the manifest's): not this folder's result")  # fmt: skip


def written_files(out_dir: str | PathLike[str]) -> set[str]:
    """The paths walk3d writes in the result folder ``out_dir``: the files its manifest lists
    (unread if damaged), those of every result, the views and ``validation/``'s files."""
    try:
        listed = read_json_object(Path(out_dir) / MANIFEST, "walk3d manifest").get("files")
    except (OSError, ValueError):
        listed = None
    names = {*RESULT_FILES, *OPENSIM_FILES, *C3D_FILES, *VIEW_FILES, MANIFEST}
    if isinstance(listed, dict):
        names |= {name for name in listed if isinstance(name, str)}
    return names | {f"{VALIDATION_FOLDER}/{name}" for name in VALIDATION_FILES}


def check_result_folder(out_dir: str | PathLike[str], option: str = "out") -> Path:
    """Refuse a result folder that is an existing file, cannot be written, or holds other files
    than an earlier result (:func:`written_files`): ValueError, one line naming them. The
    check of ``walk3d predict --out`` and the API (:func:`walk3d.outputs.check_output_folder`)."""
    return outputs.check_output_folder(out_dir, option, replaces="summary.json", own=written_files)


def record_file(out_dir: str | PathLike[str], name: str) -> None:
    """List (or update) ``out_dir/name``'s size in a complete result folder's manifest, after
    an optional file such as ``animation.mp4`` was (re)written there, so that
    :func:`check_complete` keeps accepting the folder. The manifest is rewritten atomically.

    Raises:
        DataFileError: the folder is not complete apart from ``name``.
    """
    out = Path(out_dir)
    path = out / MANIFEST
    manifest = json.loads(path.read_text(encoding="utf-8"))
    manifest["files"][name] = (out / name).stat().st_size
    atomic_write_text(path, json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    check_complete(out)


def load_result(out_dir: str | PathLike[str], remade: Collection[str] = ()) -> PredictedCycle:
    """Read a result folder written by :func:`save_prediction` back into a
    :class:`PredictedCycle` (the views in ``remade`` may be missing, see :func:`check_complete`).

    Raises:
        DataFileError: the folder is incomplete (:func:`check_complete`), ``result.npz`` is
            damaged, lacks an array, holds NaN or infinite values (NaN centres of pressure
            aside) or a ``time`` that is not a cycle (:func:`~walk3d.io.checks.time_samples`:
            fewer than 11 samples, not increasing), segment masses that are not positive or
            not the summary's body mass (:func:`~walk3d.results.readback.check_masses`), or
            ``summary.json`` is not a JSON object.
    """
    check_complete(out_dir, remade)
    out = Path(out_dir)
    npz_path = out / "result.npz"
    values: dict[str, Any] = {"summary": read_json_object(out / "summary.json", "walk3d summary")}
    arrays = read_npz(npz_path, "walk3d result")
    for f in fields(PredictedCycle):
        if f.name != "summary":
            values[f.name] = read_field(npz_path, f.name, arrays.get(f.name))
    check_masses(npz_path, values["segment_mass"], values["summary"])
    try:
        return PredictedCycle(**values)
    except ValueError as exc:
        raise DataFileError(npz_path, str(exc)) from None
