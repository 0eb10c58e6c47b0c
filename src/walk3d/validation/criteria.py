"""Table 3: the criteria C_en and C_tor with their x/y/z split, from any source.

* :func:`criteria_from_reference`: from measured inverse-dynamics moments and measured joint
  angles (a cycle table or normalised trial cycles), with walk3d's strengths. The reference holds
  the right side (and the midline); a symmetric gait gives the left limbs the same integrals, so
  limb DoFs count twice. Rates are the time derivatives of the measured angles (periodic central
  differences over ``T``). Moments are OpenSim generalized forces and rates coordinate rates, so
  ``|M q̇|`` is each coordinate's power; walk3d's own C_en uses the moment and rate about each
  parent axis instead, which sums to the same joint power but splits it slightly differently
  over a ball joint's three terms. DoFs without a measured moment (the neck) are left out and
  listed.
* walk3d's own evaluation (a prediction's ``summary["objective"]``, or a fitted measured gait's
  :attr:`walk3d.validation.measured.GaitFit.criteria`).

:func:`table3_rows` lays one criteria dictionary out as the paper's Table 3 (total, then z, x,
y with their share of the total).
"""

from __future__ import annotations

import numpy as np

from walk3d.body.model import BodyModel
from walk3d.model.criteria import node_terms, split_by_axis
from walk3d.model.state import strength_weights
from walk3d.validation.reference import Reference

__all__ = ["criteria_from_reference", "table3_rows"]


def _periodic_rate(values: np.ndarray, period: float) -> np.ndarray:
    """d/dt of samples over one closed cycle (first and last sample the same instant)."""
    v = np.asarray(values, float)[:-1]
    dt = period / v.size
    return (np.roll(v, -1) - np.roll(v, 1)) / (2 * dt)


def criteria_from_reference(
    reference: Reference, body: BodyModel, period: float
) -> tuple[dict, tuple[str, ...]]:
    """``({"C_tor": split, "C_en": split}, missing DoF names)`` (module doc)."""
    a, b = strength_weights(body)
    axes, moments, rates, weight, missing = [], [], [], [], []
    for joint in body.joints:
        if joint.side == "l":
            continue
        for name, slot in zip(joint.dof_names, joint.dof_slots, strict=True):
            base = name[:-2] if name.endswith("_r") else name
            m_key, q_key = f"moment:{base}", f"angle:{base}"
            if not (reference.has(m_key) and reference.has(q_key)):
                missing.append(name)
                continue
            i = body.dof_names.index(name)
            m = reference.mean[m_key][:-1] * body.mass
            moments.append((i, m))
            rates.append(_periodic_rate(np.radians(reference.mean[q_key]), period))
            axes.append(slot)
            weight.append(2.0 if joint.side == "r" else 1.0)
    idx = [i for i, _ in moments]
    tor, en = node_terms([m for _, m in moments], rates, a[idx], b[idx], None)
    dt = period / (reference.percent.size - 1)
    w = np.array(weight)
    tor_i = np.array([np.sum(v) * dt for v in tor]) * w
    en_i = np.array([np.sum(v) * dt for v in en]) * w
    crit = {"C_tor": split_by_axis(tor_i, axes), "C_en": split_by_axis(en_i, axes)}
    return crit, tuple(missing)


def table3_rows(criteria: dict, label: str) -> list[dict]:
    """Table 3 lines of one criteria dict: total, z, x, y with their share (paper's order)."""
    rows = []
    for key, unit in (("C_en", "J"), ("C_tor", "N m/N m")):
        c = criteria[key]
        total = float(c["total"])
        for comp in ("total", "z", "x", "y"):
            value = float(c[comp])
            share = 100.0 * value / total if total else float("nan")
            rows.append({"source": label, "criterion": key, "component": comp, "value": value,
                         "percent": share, "unit": unit})  # fmt: skip
    return rows
