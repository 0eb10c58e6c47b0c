"""OpenSim 4 model files (``.osim``): writing a model description as XML.

:func:`write_osim` writes an :class:`walk3d.results.osim_model.OsimModel` (any object with the
same attributes) with :mod:`xml.etree`, so no OpenSim installation is needed. The file is an
``OpenSimDocument`` of version 40000: a ``BodySet`` of ``Body`` elements (mass, centre of mass,
inertia ``Ixx Iyy Izz Ixy Ixz Iyz``, an ``Ellipsoid`` on an offset frame for display) and a
``JointSet`` of ``CustomJoint`` elements, each with its coordinates, a parent offset frame at
the joint centre, a child offset frame at the child body's origin and a ``SpatialTransform`` of
three rotations and three translations (coordinate-driven ones with a unit ``LinearFunction``,
the others held at zero by a ``Constant``). Values are in SI units (rad, m, kg).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterable
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from walk3d.io.atomic import atomic_write_text

__all__ = ["osim_xml", "write_osim"]


def _num(v: float) -> str:
    return repr(float(v))


def _nums(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


def _sub(parent: ET.Element, tag: str, text: str | None = None, **attrib: str) -> ET.Element:
    el = ET.SubElement(parent, tag, attrib)
    if text is not None:
        el.text = text
    return el


def _offset_frame(parent: ET.Element, name: str, socket: str, translation) -> ET.Element:
    frame = _sub(parent, "PhysicalOffsetFrame", name=name)
    _sub(frame, "socket_parent", socket)
    _sub(frame, "translation", _nums(translation))
    _sub(frame, "orientation", "0 0 0")
    return frame


def _body(bodies: ET.Element, b: Any) -> None:
    el = _sub(bodies, "Body", name=b.name)
    _sub(el, "mass", _num(b.mass))
    _sub(el, "mass_center", _nums(b.com))
    _sub(el, "inertia", _nums((*b.inertia, 0.0, 0.0, 0.0)))
    components = _sub(el, "components")
    frame = _offset_frame(components, f"{b.name}_shape_frame", "..", b.shape_centre)
    geometry = _sub(frame, "attached_geometry")
    shape = _sub(geometry, "Ellipsoid", name=f"{b.name}_shape")
    _sub(shape, "socket_frame", "..")
    appearance = _sub(shape, "Appearance")
    _sub(appearance, "color", "0.85 0.75 0.6")
    _sub(shape, "radii", _nums(b.shape_radii))


def _independent(axes: list[np.ndarray]) -> list[np.ndarray]:
    """Fill the list of (unit) axes up to three linearly independent ones."""
    out = list(axes)
    for e in np.eye(3):
        if len(out) == 3:
            break
        trial = np.array([*out, e])
        if np.linalg.matrix_rank(trial, tol=1e-6) == len(trial):
            out.append(e)
    return out


def _transform_axis(transform: ET.Element, name: str, axis, coordinate: str | None) -> None:
    ta = _sub(transform, "TransformAxis", name=name)
    _sub(ta, "coordinates", coordinate or "")
    _sub(ta, "axis", _nums(axis))
    if coordinate is None:
        fn = _sub(ta, "Constant", name="function")
        _sub(fn, "value", "0")
    else:
        fn = _sub(ta, "LinearFunction", name="function")
        _sub(fn, "coefficients", "1 0")


def _coordinate(coordinates: ET.Element, c: Any) -> None:
    el = _sub(coordinates, "Coordinate", name=c.name)
    _sub(el, "default_value", _num(c.default))
    _sub(el, "default_speed_value", "0")
    _sub(el, "range", _nums(c.range))
    _sub(el, "clamped", "false")
    _sub(el, "locked", "false")


def _joint(joints: ET.Element, j: Any) -> None:
    el = _sub(joints, "CustomJoint", name=j.name)
    parent_frame, child_frame = f"{j.parent}_offset", f"{j.child}_offset"
    _sub(el, "socket_parent_frame", parent_frame)
    _sub(el, "socket_child_frame", child_frame)
    coordinates = _sub(el, "coordinates")
    for c in (*j.rotations, *j.translations):
        _coordinate(coordinates, c)
    frames = _sub(el, "frames")
    parent_path = "/ground" if j.parent == "ground" else f"/bodyset/{j.parent}"
    _offset_frame(frames, parent_frame, parent_path, j.location)
    _offset_frame(frames, child_frame, f"/bodyset/{j.child}", (0.0, 0.0, 0.0))
    transform = _sub(el, "SpatialTransform")
    rot_axes = _independent([np.asarray(c.axis, float) for c in j.rotations])
    for k in range(3):
        c = j.rotations[k] if k < len(j.rotations) else None
        _transform_axis(transform, f"rotation{k + 1}", rot_axes[k], c.name if c else None)
    for k in range(3):
        c = j.translations[k] if k < len(j.translations) else None
        axis = c.axis if c is not None else np.eye(3)[k]
        _transform_axis(transform, f"translation{k + 1}", axis, c.name if c else None)


def osim_xml(model: Any) -> str:
    """The ``.osim`` text of ``model`` (see the module doc)."""
    root = ET.Element("OpenSimDocument", Version="40000")
    m = _sub(root, "Model", name=model.name)
    _sub(m, "credits", "walk3d: the body model that produced the prediction")
    _sub(m, "length_units", "meters")
    _sub(m, "force_units", "N")
    _sub(m, "gravity", _nums(model.gravity))
    bodyset = _sub(m, "BodySet", name="bodyset")
    bodies = _sub(bodyset, "objects")
    for b in model.bodies:
        _body(bodies, b)
    jointset = _sub(m, "JointSet", name="jointset")
    joints = _sub(jointset, "objects")
    for j in model.joints:
        _joint(joints, j)
    ET.indent(root, space="\t")
    return '<?xml version="1.0" encoding="UTF-8" ?>\n' + ET.tostring(root, "unicode") + "\n"


def write_osim(path: str | PathLike[str], model: Any) -> Path:
    """Write ``model`` as an OpenSim 4 ``.osim`` file, atomically; returns the path."""
    return atomic_write_text(path, osim_xml(model))
