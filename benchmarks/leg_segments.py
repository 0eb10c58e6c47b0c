"""A walk3d command run with the thighs and shanks of the body model lengthened by fractions.

    python benchmarks/leg_segments.py THIGH SHANK -- WALK3D-ARGS...

THIGH and SHANK are fractions of walk3d's de Leva lengths (0.0997 and -0.0189 give the Falisse
subject's scaled OpenSim model: thigh 0.397 m, shank 0.416 m, against walk3d's 0.361 and
0.424 m at 1.70 m). Each knee and ankle joint and each segment's centre of mass move along the
segment; masses and inertias stay. Every body the command builds is changed, the reference
subject's of the similarity scaling included, so a fraction keeps its meaning at any stature.
The model cache keys on the body, so the changed model gets its own entries. It asks whether
the de Leva leg proportions hold the stance knee in loading (docs/fitting.md, "The subject's
segment lengths").

    F=../shared/data/falisse2019
    python benchmarks/leg_segments.py 0.0997 -0.0189 -- predict --from-trial $F/gait_1_ik.mot \
        --grf $F/gait_1_grf.mot --mass 62 --height 1.7 --sex female --out legs
    python benchmarks/leg_segments.py 0.0997 -0.0189 -- track --ik $F/gait_1_ik.mot \
        --grf $F/gait_1_grf.mot --mass 62 --height 1.7 --sex female --out legs_tracked
"""

from __future__ import annotations

import os
import sys
from dataclasses import replace

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def lengthened(build, thigh: float, shank: float):
    """``build`` (:func:`walk3d.body.model.build_body`) with both legs' segments scaled."""
    from walk3d.body.model import JOINT_NAMES, SEGMENT_NAMES

    def build_changed(*args, **kwargs):
        body = build(*args, **kwargs)
        segs, joints = list(body.segments), list(body.joints)
        for side in "rl":
            for seg, joint, frac in (("thigh", "knee", thigh), ("shank", "ankle", shank)):
                i, k = SEGMENT_NAMES.index(f"{seg}_{side}"), JOINT_NAMES.index(f"{joint}_{side}")
                s, j = segs[i], joints[k]
                segs[i] = replace(s, com=s.com * (1 + frac), length=s.length * (1 + frac))
                joints[k] = replace(j, offset=j.offset * (1 + frac))
        return replace(body, segments=tuple(segs), joints=tuple(joints))

    return build_changed


def main() -> None:
    if len(sys.argv) < 4 or sys.argv[3] != "--":
        raise SystemExit(__doc__.split("\n\n")[1])
    import walk3d.body.model as body_model

    body_model.build_body = lengthened(body_model.build_body, float(sys.argv[1]),
                                       float(sys.argv[2]))  # fmt: skip
    from walk3d.cli import main as walk3d_main

    sys.argv = ["walk3d", *sys.argv[4:]]
    walk3d_main()


if __name__ == "__main__":
    main()
