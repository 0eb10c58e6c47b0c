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
    from walk3d.kinematics import quaternion as qt

    res = walk3d.load_result(folder)
    gait = json.loads((folder / "summary.json").read_text())["settings"]["gait"]
    body = build_body(gait["mass"], gait["height"], gait["sex"])
    i = list(res.segment_names).index(f"foot_{side}")
    com = tuple(np.asarray(body.segments[i].com, float))
    pts = body.foot.points(side)
    foot = 0 if side == "r" else 1
    weight = float(np.sum(res.segment_mass)) * 9.81
    rows = []
    for k in range(len(res.time)):
        fy = float(res.grf_force[k, foot, 1])
        if fy < min_load * weight:
            continue
        q = tuple(res.segment_orientation[k, i])
        origin = res.segment_com_position[k, i] - np.array(qt.qrot(q, com))
        heel, toe = (origin + np.array(qt.qrot(q, tuple(p))) for p in pts[:2])
        n = np.array(qt.qrot(q, (0.0, 1.0, 0.0)))
        cop = res.grf_cop[k, foot]
        height = heel[1] - (n[0] * (cop[0] - heel[0]) + n[2] * (cop[2] - heel[2])) / n[1]
        pitch = np.degrees(np.arctan2(toe[1] - heel[1], toe[0] - heel[0]))
        place = (cop[0] - heel[0]) / (toe[0] - heel[0])
        rows.append((k, fy / weight, pitch, heel[1], toe[1], place, height))
    return rows


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
