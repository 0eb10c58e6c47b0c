"""Ground reaction loads in OpenSim storage files and ExternalLoads XML.

Column naming (OpenSim's ExternalForce convention): a load is located by three identifiers,
each completed by ``x``, ``y`` and ``z``: the force identifier (e.g. ``ground_force_v`` ->
``ground_force_vx``...), the point identifier (``ground_force_p``) and the torque identifier
(``ground_torque_``). :func:`find_plates` recognises every column family of the form
``<prefix>ground_force_<infix>v<axis>`` / ``...p<axis>`` / ``<prefix>ground_torque_<infix><axis>``,
which covers ``ground_force_vx``, ``1_ground_force_vx``, ``r_ground_force_vx``,
``ground_force_1_vx`` and ``ground_force_r_vx``.

Foot assignment (:func:`extract_foot_loads`), first rule that applies:

1. an explicit ``mapping`` ``{"right": force_identifier, "left": force_identifier}``;
2. an ExternalLoads XML: each ExternalForce's ``applied_to_body`` (``calcn_r``/``calcn_l``, or
   any body ending in ``_r``/``_l`` or containing ``right``/``left``) names the side;
3. side tokens in the column names (prefix or infix ``r_``/``l_``/``right_``/``left_``);
4. exactly two plates without side tokens: the plate whose loaded centre of pressure lies
   further along the lateral axis (``+z`` in OpenSim's ground frame, x forward, y up, z to the
   subject's right) is the right foot. Pass ``lateral_sign=-1`` for trials walked along ``-x``.

Several plates assigned to one foot are merged with :func:`combine_loads`.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from walk3d.io.atomic import atomic_write_text
from walk3d.io.checks import read_xml
from walk3d.io.errors import DataFileError
from walk3d.io.storage import Storage, read_storage, write_storage

__all__ = [
    "ExternalForceSpec",
    "FootLoads",
    "PlateColumns",
    "PlateLoad",
    "combine_loads",
    "extract_foot_loads",
    "find_plates",
    "grf_column_names",
    "plate_load",
    "read_external_loads_xml",
    "side_of_body",
    "write_external_loads_xml",
    "write_grf_storage",
]

SIDES = ("right", "left")
_FORCE_RE = re.compile(r"^(?P<pre>.*?)ground_force_(?P<mid>(?:.*_)?)v[xyz]$")
_SIDE_TOKENS = {"r": "right", "right": "right", "l": "left", "left": "left"}


@dataclass(frozen=True)
class PlateColumns:
    """Identifiers of one load in a storage (OpenSim ExternalForce style)."""

    force_identifier: str
    point_identifier: str
    torque_identifier: str | None
    side: str | None = None


@dataclass(frozen=True)
class PlateLoad:
    """Force (N), centre of pressure (m) and torque (N m), each ``(N, 3)``, in ground."""

    name: str
    force: np.ndarray
    cop: np.ndarray
    torque: np.ndarray


@dataclass(frozen=True)
class FootLoads:
    """Per-foot ground reaction loads sampled at ``time``."""

    time: np.ndarray
    right: PlateLoad
    left: PlateLoad

    def foot(self, side: str) -> PlateLoad:
        """The load of ``"right"`` or ``"left"``."""
        if side not in SIDES:
            raise ValueError(f"side must be 'right' or 'left', got {side!r}")
        return self.right if side == "right" else self.left


@dataclass(frozen=True)
class ExternalForceSpec:
    """One ``<ExternalForce>`` of an OpenSim ExternalLoads file."""

    name: str
    applied_to_body: str
    force_identifier: str
    point_identifier: str
    torque_identifier: str
    force_expressed_in_body: str = "ground"
    point_expressed_in_body: str = "ground"
    enabled: bool = True


def _side_token(text: str) -> str | None:
    for token in text.lower().strip("_").split("_"):
        if token in _SIDE_TOKENS:
            return _SIDE_TOKENS[token]
    return None


def side_of_body(body: str) -> str | None:
    """``"right"``/``"left"`` for a body name such as ``calcn_r``/``toes_l``, else ``None``."""
    low = body.strip().lower()
    if low.endswith("_r") or "right" in low:
        return "right"
    if low.endswith("_l") or "left" in low:
        return "left"
    return None


def find_plates(storage: Storage) -> tuple[PlateColumns, ...]:
    """Every complete force/point(/torque) column family in ``storage``, in column order."""
    cols = set(storage.columns)
    found: list[PlateColumns] = []
    for column in storage.columns:
        match = _FORCE_RE.match(column)
        if not match or not column.endswith("vx"):
            continue
        pre, mid = match["pre"], match["mid"]
        force_id = f"{pre}ground_force_{mid}v"
        point_id = f"{pre}ground_force_{mid}p"
        torque_id = f"{pre}ground_torque_{mid}"
        if not all(f"{ident}{a}" in cols for ident in (force_id, point_id) for a in "xyz"):
            continue
        has_torque = all(f"{torque_id}{a}" in cols for a in "xyz")
        side = _side_token(pre) or _side_token(mid)
        found.append(PlateColumns(force_id, point_id, torque_id if has_torque else None, side))
    return tuple(found)


def _triplet(storage: Storage, ident: str) -> np.ndarray:
    names = [f"{ident}{a}" for a in "xyz"]
    missing = [n for n in names if not storage.has_column(n)]
    if missing:
        where = storage.path if storage.path is not None else Path(storage.name or "storage")
        raise DataFileError(where, f"no columns {missing} for identifier {ident!r}")
    return np.column_stack([storage.column(n) for n in names])


def plate_load(
    storage: Storage, force_identifier: str, point_identifier: str, torque_identifier: str | None
) -> PlateLoad:
    """Read one load by its identifiers; a missing torque family gives zero torque."""
    force = _triplet(storage, force_identifier)
    cop = _triplet(storage, point_identifier)
    if torque_identifier and all(storage.has_column(f"{torque_identifier}{a}") for a in "xyz"):
        torque = _triplet(storage, torque_identifier)
    else:
        torque = np.zeros_like(force)
    return PlateLoad(force_identifier, force, cop, torque)


def combine_loads(loads: Sequence[PlateLoad], name: str = "combined") -> PlateLoad:
    """Merge loads acting on one foot into one force, centre of pressure and free torque.

    The resultant force and moment about the origin are preserved. The combined centre of
    pressure lies in the horizontal plane (``y`` = mean plate height) where the horizontal
    moment components vanish; the remaining torque is vertical. Where the summed vertical force
    is below 1e-6 N the centre of pressure and torque are set to zero.
    """
    if len(loads) == 1:
        return loads[0]
    force = sum(load.force for load in loads)
    moment = sum(np.cross(load.cop, load.force) + load.torque for load in loads)
    loaded = [load.cop[np.abs(load.force[:, 1]) > 1e-6, 1] for load in loads]
    heights = np.concatenate(loaded) if loaded else np.zeros(0)
    h = float(np.mean(heights)) if heights.size else 0.0
    fy = force[:, 1]
    ok = np.abs(fy) > 1e-6
    safe = np.where(ok, fy, 1.0)
    cop = np.zeros_like(force)
    cop[:, 0] = np.where(ok, (moment[:, 2] + h * force[:, 0]) / safe, 0.0)
    cop[:, 1] = np.where(ok, h, 0.0)
    cop[:, 2] = np.where(ok, (h * force[:, 2] - moment[:, 0]) / safe, 0.0)
    torque = np.zeros_like(force)
    torque[:, 1] = np.where(ok, moment[:, 1] - np.cross(cop, force)[:, 1], 0.0)
    return PlateLoad(name, force, cop, torque)


def _text(element: ET.Element, tag: str, default: str = "") -> str:
    child = element.find(tag)
    return default if child is None or child.text is None else child.text.strip()


def read_external_loads_xml(path: str | PathLike[str]) -> tuple[tuple[ExternalForceSpec, ...], str]:
    """Parse an OpenSim ExternalLoads file (3.x or 4.x).

    Returns:
        The ExternalForce entries and the ``datafile`` text (``""`` when absent).

    Raises:
        DataFileError: Not well-formed XML, or no ``ExternalLoads`` element.
    """
    path = Path(path)
    root = read_xml(path).getroot()
    loads = root if root.tag == "ExternalLoads" else root.find(".//ExternalLoads")
    if loads is None:
        raise DataFileError(path, "no <ExternalLoads> element")
    specs = []
    for item in loads.iter("ExternalForce"):
        disabled = _text(item, "isDisabled", "false").lower() == "true"
        applies = _text(item, "appliesForce", "true").lower() != "false"
        specs.append(
            ExternalForceSpec(
                name=item.get("name", ""),
                applied_to_body=_text(item, "applied_to_body"),
                force_identifier=_text(item, "force_identifier"),
                point_identifier=_text(item, "point_identifier"),
                torque_identifier=_text(item, "torque_identifier"),
                force_expressed_in_body=_text(item, "force_expressed_in_body", "ground"),
                point_expressed_in_body=_text(item, "point_expressed_in_body", "ground"),
                enabled=applies and not disabled,
            )
        )
    return tuple(specs), _text(loads, "datafile")


def _lateral_rule(storage: Storage, plates: Sequence[PlateColumns], sign: float) -> list[str]:
    lateral = []
    for plate in plates:
        load = plate_load(storage, plate.force_identifier, plate.point_identifier, None)
        loaded = load.force[:, 1] > 20.0
        if not loaded.any():
            raise ValueError(f"plate {plate.force_identifier!r} is never loaded above 20 N")
        lateral.append(sign * float(np.mean(load.cop[loaded, 2])))
    return ["right", "left"] if lateral[0] > lateral[1] else ["left", "right"]


def extract_foot_loads(
    storage: Storage | str | PathLike[str],
    external_loads: str | PathLike[str] | Sequence[ExternalForceSpec] | None = None,
    *,
    mapping: Mapping[str, str | Sequence[str]] | None = None,
    lateral_sign: float = 1.0,
) -> FootLoads:
    """Right and left foot loads from a GRF storage (see the module doc for the rules).

    Args:
        storage: A :class:`Storage` or the path of a GRF ``.mot``/``.sto``.
        external_loads: An ExternalLoads XML path or its parsed entries.
        mapping: ``{"right": ids, "left": ids}`` with one force identifier or a list of them.
        lateral_sign: ``+1`` when ``+z`` points to the subject's right, ``-1`` otherwise.

    Raises:
        ValueError: The plates cannot be assigned unambiguously to the two feet.
    """
    if not isinstance(storage, Storage):
        storage = read_storage(storage)
    plates = find_plates(storage)
    by_force = {p.force_identifier: p for p in plates}
    chosen: dict[str, list[PlateColumns]] = {"right": [], "left": []}

    if mapping is not None:
        for side in SIDES:
            ids = mapping.get(side, ())
            for ident in [ids] if isinstance(ids, str) else list(ids):
                if ident not in by_force:
                    raise ValueError(f"{ident!r} is not one of {sorted(by_force)}")
                chosen[side].append(by_force[ident])
    elif external_loads is not None:
        specs = external_loads
        if isinstance(specs, (str, PathLike)):
            specs = read_external_loads_xml(specs)[0]
        for spec in specs:
            side = side_of_body(spec.applied_to_body)
            if spec.enabled and side is not None:
                torque = spec.torque_identifier or None
                chosen[side].append(
                    PlateColumns(spec.force_identifier, spec.point_identifier, torque, side)
                )
    elif plates and all(p.side is not None for p in plates):
        for plate in plates:
            chosen[plate.side].append(plate)  # type: ignore[index]
    elif len(plates) == 2:
        for side, plate in zip(_lateral_rule(storage, plates, lateral_sign), plates, strict=True):
            chosen[side].append(plate)
    else:
        raise ValueError(
            f"cannot assign {len(plates)} force plate(s) to the feet: walk3d needs one load "
            "per foot, as two plates or as columns named by side (r_ground_force_vx and "
            "l_ground_force_vx, or ground_force_r_vx and ground_force_l_vx)"
        )

    feet = {}
    for side in SIDES:
        if not chosen[side]:
            raise ValueError(f"no load assigned to the {side} foot")
        loads = [
            plate_load(storage, p.force_identifier, p.point_identifier, p.torque_identifier)
            for p in chosen[side]
        ]
        feet[side] = combine_loads(loads, name=side)
    return FootLoads(storage.time, feet["right"], feet["left"])


def grf_column_names(side: str) -> tuple[str, ...]:
    """The nine walk3d GRF columns of ``side`` (``"r"``/``"l"``): ``ground_force_r_vx`` ..."""
    force = tuple(f"ground_force_{side}_v{a}" for a in "xyz")
    point = tuple(f"ground_force_{side}_p{a}" for a in "xyz")
    torque = tuple(f"ground_torque_{side}_{a}" for a in "xyz")
    return force + point + torque


def write_grf_storage(
    path: str | PathLike[str],
    time: ArrayLike,
    force: ArrayLike,
    cop: ArrayLike,
    free_moment: ArrayLike,
    *,
    name: str = "walk3d_grf",
) -> Path:
    """Write right and left ground reactions as an OpenSim GRF storage, atomically.

    Args:
        time: ``(N,)`` seconds.
        force: ``(N, 2, 3)`` ground reaction force on [right, left] foot, N, ground frame.
        cop: ``(N, 2, 3)`` centre of pressure, m, ground frame.
        free_moment: ``(N, 2)`` free moment about the vertical (``y``) axis, N m.

    The columns are ``ground_force_r_v{x,y,z}``, ``ground_force_r_p{x,y,z}``,
    ``ground_torque_r_{x,y,z}`` and the same with ``_l_``, i.e. the identifiers
    ``ground_force_r_v``, ``ground_force_r_p``, ``ground_torque_r_`` (and ``_l_``) that
    :func:`write_external_loads_xml` refers to. The torque is ``(0, free_moment, 0)``.
    """
    t = np.asarray(time, dtype=float).reshape(-1)
    f = np.asarray(force, dtype=float)
    p = np.asarray(cop, dtype=float)
    m = np.asarray(free_moment, dtype=float)
    n = t.size
    if f.shape != (n, 2, 3) or p.shape != (n, 2, 3) or m.shape != (n, 2):
        raise ValueError(
            f"expected force/cop (N, 2, 3) and free_moment (N, 2) with N={n}; "
            f"got {f.shape}, {p.shape}, {m.shape}"
        )
    blocks, columns = [], []
    for k, side in enumerate("rl"):
        torque = np.zeros((n, 3))
        torque[:, 1] = m[:, k]
        blocks.extend([f[:, k, :], p[:, k, :], torque])
        columns.extend(grf_column_names(side))
    return write_storage(path, t, columns, np.hstack(blocks), name=name, in_degrees=False)


def write_external_loads_xml(
    path: str | PathLike[str],
    grf_filename: str | PathLike[str],
    *,
    right_body: str = "calcn_r",
    left_body: str = "calcn_l",
    name: str = "externalloads",
) -> Path:
    """Write the OpenSim 4 ExternalLoads XML matching :func:`write_grf_storage`, atomically.

    ``grf_filename`` is written as given into ``<datafile>`` (OpenSim resolves a relative name
    against the XML's folder).
    """
    root = ET.Element("OpenSimDocument", Version="40000")
    loads = ET.SubElement(root, "ExternalLoads", name=name)
    objects = ET.SubElement(loads, "objects")
    for side, body in (("r", right_body), ("l", left_body)):
        item = ET.SubElement(objects, "ExternalForce", name="right" if side == "r" else "left")
        for tag, value in (
            ("appliesForce", "true"),
            ("applied_to_body", body),
            ("force_expressed_in_body", "ground"),
            ("point_expressed_in_body", "ground"),
            ("force_identifier", f"ground_force_{side}_v"),
            ("point_identifier", f"ground_force_{side}_p"),
            ("torque_identifier", f"ground_torque_{side}_"),
            ("data_source_name", "Unassigned"),
        ):
            ET.SubElement(item, tag).text = value
    ET.SubElement(loads, "groups")
    ET.SubElement(loads, "datafile").text = str(grf_filename)
    ET.indent(root, space="\t")
    body_text = ET.tostring(root, encoding="unicode")
    return atomic_write_text(path, '<?xml version="1.0" encoding="UTF-8" ?>\n' + body_text + "\n")
