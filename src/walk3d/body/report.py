"""Tabular views of a body model (for ``walk3d body``): SI units plus degrees at this edge."""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d.body.model import BodyModel


def body_table(body: BodyModel) -> dict[str, Any]:
    """JSON-ready description: ``{"subject", "segments": [...], "joints": [...]}``."""
    segments = [
        {
            "name": s.name,
            "mass_kg": round(s.mass, 6),
            "com_m": [round(float(v), 6) for v in s.com],
            "inertia_kg_m2": [round(float(v), 7) for v in s.inertia],
            "length_m": round(s.length, 6),
        }
        for s in body.segments
    ]
    joints = []
    for j in body.joints:
        entry: dict[str, Any] = {
            "name": j.name,
            "type": j.kind,
            "parent": body.segments[j.parent].name,
            "child": body.segments[j.child].name,
            "centre_in_parent_m": [round(float(v), 6) for v in j.offset],
            "dofs": list(j.dof_names),
            "range_deg": np.round(np.degrees(j.range), 3).tolist(),
            "strength_positive_Nm": np.round(j.strength_pos, 3).tolist(),
            "strength_negative_Nm": np.round(j.strength_neg, 3).tolist(),
        }
        if j.kind == "ball":
            entry["axes"] = np.round(j.axes, 6).tolist()
        else:
            entry["axes"] = [np.round(j.axis, 6).tolist()]
            if j.axis2 is not None:
                entry["axes"].append(np.round(j.axis2, 6).tolist())
        joints.append(entry)
    return {
        "subject": {"mass_kg": body.mass, "height_m": body.height, "sex": body.sex},
        "segments": segments,
        "joints": joints,
    }
