"""Where each foot's centre of pressure sits against where its sole touches the floor.

    python benchmarks/cop_contact.py RESULT_DIR [--side r] [--min-load 0.05]

For every sample of a result folder whose foot carries at least ``--min-load`` body weights it
prints the foot's pitch (deg, toes up +), the heel's and toe's heights (m), the centre of
pressure's place along the foot (0 heel, 1 toe) and the height of the sole plane under the
centre of pressure (m). A foot can push on the floor only where its sole touches it, so that
height should stay within a few millimetres of zero (or below it, where the roll-over arc lets
the forefoot sink). The NLP keeps the centre of pressure inside the footprint's box but does
not tie it to the contact (docs/criteria.md, "What holds the stance knee at 40°"). The
last line gives the largest height and the share of the vertical impulse applied more than
1 cm above the floor.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np


def sole_heights(folder: Path, side: str = "r", min_load: float = 0.05) -> list[tuple]:
    """Rows ``(sample, Fy/BW, pitch deg, heel y, toe y, COP place 0–1, sole height m)``."""
    import walk3d
    from walk3d.body.model import build_body
    from walk3d.kinematics.quaternion import to_matrix
    from walk3d.results.markers import Marker, marker_positions

    res = walk3d.load_result(folder)
    gait = json.loads((folder / "summary.json").read_text())["settings"]["gait"]
    body = build_body(gait["mass"], gait["height"], gait["sex"])
    segment, foot = f"foot_{side}", 0 if side == "r" else 1
    heel_local, toe_local = body.foot.points(side)[:2]
    heel, toe = marker_positions(
        res, body, [Marker("heel", segment, heel_local), Marker("toe", segment, toe_local)]
    ).transpose(1, 0, 2)
    up = to_matrix(res.segment_orientation[:, body.segment_index(segment)])[:, :, 1]
    cop, fy = res.grf_cop[:, foot], res.grf_force[:, foot, 1]
    # the sole plane through the heel, normal ``up``, at the centre of pressure's x and z
    height = (
        heel[:, 1]
        - (up[:, 0] * (cop[:, 0] - heel[:, 0]) + up[:, 2] * (cop[:, 2] - heel[:, 2])) / up[:, 1]
    )
    pitch = np.degrees(np.arctan2(toe[:, 1] - heel[:, 1], toe[:, 0] - heel[:, 0]))
    place = (cop[:, 0] - heel[:, 0]) / (toe[:, 0] - heel[:, 0])
    weight = float(np.sum(res.segment_mass)) * 9.81
    return [(k, fy[k] / weight, pitch[k], heel[k, 1], toe[k, 1], place[k], height[k])
            for k in np.flatnonzero(fy >= min_load * weight)]  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("--side", choices=("r", "l"), default="r")
    ap.add_argument("--min-load", type=float, default=0.05, help="body weights")
    a = ap.parse_args(argv)
    rows = sole_heights(a.folder, a.side, a.min_load)
    print("sample  Fy/BW  pitch°  heel_y  toe_y  COP(0 heel, 1 toe)  sole height under COP, m")
    for r in rows:
        k, fy, pitch, heel, toe, place, height = r
        print(f"{k:6d} {fy:6.2f} {pitch:7.1f} {heel:7.3f} {toe:6.3f} {place:10.2f} {height:14.3f}")
    if rows:
        h = np.array([r[6] for r in rows])
        w = np.array([r[1] for r in rows])
        off = float(np.sum(w[h > 0.01]) / np.sum(w))
        print(
            f"largest {h.max():.3f} m; share of the vertical impulse applied where the sole is "
            f"more than 1 cm above the floor: {off:.3f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
