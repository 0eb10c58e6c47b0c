"""What changed between two predictions (issue #43, ``walk3d compare``): every joint angle and
joint moment, both sides, over the gait cycle, and the criteria.

Both cycles are on the same 101-sample grid from the same event, so they are compared sample by
sample. Angles are per DoF (deg at this edge); moments per DoF, on the DoF's joint axis, in
N·m/kg of each prediction's own body mass (a load changes the mass).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d.body.model import build_body
from walk3d.results.prediction import PredictedCycle

__all__ = ["COLUMNS", "compare", "dof_moments"]

COLUMNS = ("group", "quantity", "unit", "a_min", "a_max", "b_min", "b_max", "rms_change",
           "largest_change")  # fmt: skip
"""Columns of the comparison table: per quantity, each prediction's range over the cycle and
the RMS and largest change sample by sample (B − A); criteria have only ``a_max``, ``b_max``."""


def dof_moments(pred: PredictedCycle) -> np.ndarray:
    """(N, 24) each DoF's joint moment on its axis, N·m, in ``pred.dof_names`` order."""
    joints = build_body().joints  # the axis slots are the model's structure, not the subject's
    names = list(pred.joint_names)
    cols = []
    for j in joints:
        k = names.index(j.name)
        cols += [pred.joint_moment[:, k, slot] for slot in j.dof_slots]
    return np.column_stack(cols)


def _row(group: str, quantity: str, unit: str, a: np.ndarray, b: np.ndarray) -> dict[str, Any]:
    d = b - a
    return {"group": group, "quantity": quantity, "unit": unit,
            "a_min": float(a.min()), "a_max": float(a.max()),
            "b_min": float(b.min()), "b_max": float(b.max()),
            "rms_change": float(np.sqrt(np.mean(d**2))),
            "largest_change": float(d[np.argmax(np.abs(d))])}  # fmt: skip


def _total(entry: Any) -> float | None:
    value = entry.get("total") if isinstance(entry, dict) else entry
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def compare(a: PredictedCycle, b: PredictedCycle) -> list[dict[str, Any]]:
    """Rows of :data:`COLUMNS`: the criteria both report, then every DoF's angle (deg) and
    moment (N·m/kg). Raises ValueError when the two are not on the same grid or DoFs."""
    if a.dof_names != b.dof_names or a.time.shape != b.time.shape:
        raise ValueError("the two predictions do not have the same DoFs and cycle samples")
    rows = []
    ca, cb = a.summary.get("objective") or {}, b.summary.get("objective") or {}
    for key in sorted(set(ca) & set(cb)):
        va, vb = _total(ca[key]), _total(cb[key])
        if va is not None and vb is not None:
            rows.append({"group": "criterion", "quantity": key, "unit": "",
                         "a_max": va, "b_max": vb, "largest_change": vb - va})  # fmt: skip
    for mass, name in ((a.body_mass, "body_mass"),):
        rows.append({"group": "body", "quantity": name, "unit": "kg", "a_max": mass,
                     "b_max": b.body_mass, "largest_change": b.body_mass - mass})  # fmt: skip
    ma, mb = dof_moments(a) / a.body_mass, dof_moments(b) / b.body_mass
    for i, name in enumerate(a.dof_names):
        rows.append(_row("angle", name, "deg", np.degrees(a.joint_angle[:, i]),
                         np.degrees(b.joint_angle[:, i])))  # fmt: skip
    for i, name in enumerate(a.dof_names):
        rows.append(_row("moment", name, "N m/kg", ma[:, i], mb[:, i]))
    return rows
