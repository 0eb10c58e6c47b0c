"""How far the evaluated cycle breaks the walking constraints between the NLP's nodes.

The NLP bounds its rows at the nodes only. Here the same rows are evaluated on the cycle the user
sees (every sample of :func:`walk3d.results.evaluate.evaluate_cycle`) and the worst excess of
each kind is reported, in the unit a reader can judge:

* ``vertical_force_bw``: a loaded foot pulling on the floor, body weights;
* ``friction_bw``: ``|F_x|`` or ``|F_z|`` above ``μ F_y``, body weights;
* ``cop_bw_m``: the centre of pressure outside the foot's box, as the moment ``distance × F_y``
  in body weight × m (1 mm at full load, or 1 cm at a tenth of it, is 0.001);
* ``free_moment_bw_m``: the free moment above ``μ r F_y``, body weight × m;
* ``swing_clearance_m``: a swing-foot landmark below the floor, m;
* ``joint_range_deg``: a joint angle outside its range, deg.

``worst`` names the largest one relative to its limit (:data:`LIMITS`: 1 mm or 1 % of body
weight, the bar of issue #23; 1° for joint ranges).
"""

from __future__ import annotations

import numpy as np

from walk3d.contact.support import foot_points, support_rows

LIMITS = {
    "vertical_force_bw": 0.01, "friction_bw": 0.01, "cop_bw_m": 0.001,
    "free_moment_bw_m": 0.001, "swing_clearance_m": 0.001, "joint_range_deg": 1.0,
}  # fmt: skip
"""What counts as holding on the cycle, per kind."""


def _excess(rows, mask) -> float:
    if not np.any(mask):
        return 0.0
    worst = max(float(np.max(-np.broadcast_to(r, mask.shape)[mask])) for r in rows)
    return max(worst, 0.0)


def block_violations(body, model, st, wf: float, other_loaded: np.ndarray) -> dict[str, float]:
    """Worst excess per kind over one root block of samples (``st`` from
    :func:`walk3d.model.state.evaluate`); ``other_loaded`` marks the samples where the
    non-root foot is on the floor (double support), elsewhere it swings."""
    everywhere = np.ones_like(other_loaded, dtype=bool)
    out = dict.fromkeys(LIMITS, 0.0)
    mu, r = model.friction, model.free_moment_radius
    for side, mask in ((st.root, everywhere), ("l" if st.root == "r" else "r", other_loaded)):
        f = st.feet[side][0]
        out["vertical_force_bw"] = max(out["vertical_force_bw"], _excess([f[1] / wf], mask))
        fr = [(mu * f[1] - np.abs(f[0])) / wf, (mu * f[1] - np.abs(f[2])) / wf]
        out["friction_bw"] = max(out["friction_bw"], _excess(fr, mask))
        pts = foot_points(st.pose, body.segment_index(f"foot_{side}"), body.foot.points(side))
        rows = support_rows(st.feet[side], pts, side, wf, mu, r)
        out["cop_bw_m"] = max(out["cop_bw_m"], _excess(rows[:4], mask))
        out["free_moment_bw_m"] = max(out["free_moment_bw_m"],
                                      _excess([v * wf / (f[1] + 1e-9 * wf) for v in rows[4:]],
                                              mask & (f[1] > 0.01 * wf)))  # fmt: skip
    swing = ~other_loaded
    out["swing_clearance_m"] = _excess(list(st.other_points_y), swing)
    return out


def range_excess_deg(angles_rad: np.ndarray, ranges_rad: np.ndarray) -> float:
    """Largest excursion of ``angles_rad`` (time × 24) outside ``ranges_rad`` (24 × 2), deg."""
    lo = ranges_rad[:, 0] - angles_rad
    hi = angles_rad - ranges_rad[:, 1]
    return float(np.degrees(max(0.0, lo.max(), hi.max())))


def summarize_violations(parts: list[dict[str, float]], range_deg: float) -> dict:
    """The worst of each kind over blocks, and ``worst``: ``{kind, value, limit, holds}``."""
    out = {k: max(p[k] for p in parts) for k in LIMITS if k != "joint_range_deg"}
    out["joint_range_deg"] = range_deg
    kind = max(LIMITS, key=lambda k: out[k] / LIMITS[k])
    out["worst"] = {"kind": kind, "value": out[kind], "limit": LIMITS[kind],
                    "holds": bool(all(out[k] <= LIMITS[k] for k in LIMITS))}  # fmt: skip
    return out
