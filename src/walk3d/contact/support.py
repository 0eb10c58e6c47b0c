"""Where a foot's ground wrench can act: centre of pressure and free moment limits.

The paper constrains the vertical force and friction of each stance foot but not *where* the
reaction acts. Inverse dynamics gives each foot a wrench ``(F, M_O)`` (moment about the global
origin) that the motion demands; without further limits the optimizer can balance the body
with a centre of pressure far outside the foot, or with a twisting (free) moment of over
50 N·m that no shoe can transmit (a C_tor optimum without these limits whirled its arms to
exploit one; docs/solver.md).
A careful model keeps both physical:

* **Centre of pressure inside the footprint.** On the floor (``y = 0``) the wrench is a force at
  ``p`` plus a free moment ``T`` about vertical: ``M_O = p × F + T ŷ``, so
  ``p_x F_y = M_O,z`` and ``p_z F_y = -M_O,x``. With the foot's heel and toe giving the
  fore-aft extent and its first and fifth metatarsal heads the medio-lateral extent (all at the
  current pose), the rows ``M_O,z - x_lo F_y ≥ 0``, ``x_hi F_y - M_O,z ≥ 0``,
  ``-M_O,x - z_lo F_y ≥ 0`` and ``z_hi F_y + M_O,x ≥ 0`` hold exactly when the COP lies in the
  box (for ``F_y > 0``). They are bilinear, not divided by ``F_y``, so they stay smooth when a
  foot unloads.
* **Free moment within torsional friction.** ``T F_y = M_O,y F_y + M_O,x F_x + M_O,z F_z``,
  and ``|T| ≤ μ r F_y`` with an effective torsional radius ``r`` (default 2 cm: about 11 N·m at
  body weight for 69 kg and μ = 0.8, above the 5–8 N·m measured in walking).

All rows are divided by body weight (and by body weight² for the free-moment rows).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d.kinematics import quaternion as qt

N_SUPPORT_ROWS = 6


def foot_points(pose, segment: int, local: np.ndarray) -> list[qt.V]:
    """Global positions of the foot landmarks ``local`` (heel, toe, met1, met5 rows)."""
    q, o = pose.orientation[segment][0], pose.origin[segment][0]
    return [qt.vadd(o, qt.qrot(q, tuple(p))) for p in local]


def support_rows(
    wrench,
    points: list[qt.V],
    side: str,
    weight: float,
    mu: float,
    radius: float,
    margin: float = 0.0,
) -> list[Any]:
    """Six rows that are ``≥ 0`` when the wrench acts inside the foot (see module doc).

    ``points`` are the global heel, toe, met1 and met5 of the foot; ``side`` orders the
    metatarsals medio-laterally (global +z is the walker's right). ``margin`` (m) keeps the
    centre of pressure that far inside the heel and the toe.
    """
    f, m = wrench
    heel, toe, met1, met5 = points
    z_lo, z_hi = (met1[2], met5[2]) if side == "r" else (met5[2], met1[2])
    fy = f[1]
    torque_fy = m[1] * fy + m[0] * f[0] + m[2] * f[2]
    w2 = weight * weight
    return [
        (m[2] - (heel[0] + margin) * fy) / weight,
        ((toe[0] - margin) * fy - m[2]) / weight,
        (-m[0] - z_lo * fy) / weight,
        (z_hi * fy + m[0]) / weight,
        (mu * radius * fy * fy - torque_fy) / w2,
        (mu * radius * fy * fy + torque_fy) / w2,
    ]
