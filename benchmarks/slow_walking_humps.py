"""The vertical-force humps of measured walking by speed: the reference of walk3d's walking
check (``walk3d.results.gait_checks.SLOW_HUMPS``; docs/validation.md), in one command.

    python benchmarks/slow_walking_humps.py WBDS_DIR SPEEDS.csv

``WBDS_DIR`` holds the treadmill files ``WBDSxxwalkTyyknt.txt`` of Fukuchi, Fukuchi & Duarte
(2018), PeerJ 6:e4640 (figshare doi:10.6084/m9.figshare.5722711, not in walk3d's repository):
per trial, the mean cycle at 1 % steps, vertical force ``RGRFY``/``LGRFY`` in N/kg.
``SPEEDS.csv`` has the columns ``subject,trial,speed`` (m/s, from the dataset's WBDSinfo
table). Per limb: F1 the largest force in the first half of stance, F2 in the second, Fmin
the least between them; stance ends at the first sample after 40 % of the cycle below 0.05
body weight. Prints the table by speed bin and each bin's smallest hump against walk3d's bar.
"""

from __future__ import annotations

import argparse
import csv
import re
import sys
from pathlib import Path

import numpy as np

from walk3d.constants import G
from walk3d.results.gait_checks import hump_min_bw

BINS = (0.35, 0.50, 0.60, 0.75, 0.90, 1.06, 1.25, 1.45)
"""Speed bins, m/s."""


def humps(fy_bw: np.ndarray) -> tuple[float, float, float]:
    """``(F1, Fmin, F2)`` of one limb's cycle of vertical force (body weights, 1 % steps)."""
    after = np.flatnonzero((np.arange(fy_bw.size) > 40) & (fy_bw < 0.05))
    end = int(after[0]) if after.size else fy_bw.size
    f = fy_bw[:end]
    mid = end // 2
    i1 = int(np.argmax(f[: mid + 1]))
    i2 = mid + 1 + int(np.argmax(f[mid + 1 :]))
    return float(f[i1]), float(f[i1 : i2 + 1].min()), float(f[i2])


def read_limbs(folder: Path, speeds: dict[tuple[str, str], float]) -> list[tuple]:
    """``(speed, F1, Fmin, F2)`` of each limb of each trial file with a known speed."""
    out = []
    for path in sorted(folder.glob("WBDS*walkT*knt.txt")):
        m = re.match(r"WBDS(\d+)walk(T\d+)knt", path.stem)
        key = m and (m.group(1), m.group(2))
        if key not in speeds:
            continue
        table = np.genfromtxt(path, names=True, delimiter="\t")
        for col in ("RGRFY", "LGRFY"):
            out.append((speeds[key], *humps(np.asarray(table[col]) / G)))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("speeds", type=Path)
    a = ap.parse_args(argv)
    with a.speeds.open() as fh:
        speeds = {(f"{int(r['subject']):02d}", r["trial"]): float(r["speed"])
                  for r in csv.DictReader(fh)}  # fmt: skip
    limbs = np.array(read_limbs(a.folder, speeds))
    if limbs.size == 0:
        print("no WBDS treadmill file with a known speed", file=sys.stderr)
        return 2
    print("speed m/s  limbs   F1     Fmin   F2    smaller hump (range)   walk3d's bar")
    for lo, hi in zip(BINS[:-1], BINS[1:], strict=True):
        b = limbs[(limbs[:, 0] >= lo) & (limbs[:, 0] < hi)]
        if not b.size:
            continue
        v, f1, fm, f2 = b.mean(axis=0)
        small = np.minimum(b[:, 1], b[:, 3]) - b[:, 2]
        print(f"{v:9.2f}  {len(b):5d}  {f1:.3f}  {fm:.3f}  {f2:.3f}  {small.mean():.3f} "
              f"({small.min():.3f}-{small.max():.3f})  {hump_min_bw(v):.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
