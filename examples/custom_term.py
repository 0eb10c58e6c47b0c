"""A criterion term of your own: the trunk's angular velocity, added to the `natural` preset.

Run:  python examples/custom_term.py [OUT_DIR]

A term is one :class:`walk3d.Term`: a name, a formula on one instant of the gait (a
:class:`walk3d.Node`: the body, the 26 coordinates, every segment's pose, the total ground
reaction and the active joint moments), a reference scale and a one-line description.
``walk3d.register_term`` makes the name usable in any criterion spec. The solver minimizes it
exactly (CasADi differentiates the formula), and the summary, the table, report.html and a
campaign's ranking report it as ``C_trunk``.
"""

from __future__ import annotations

import sys

import walk3d

TRUNK_RATE_REF = 0.5
"""rad/s: about the RMS angular velocity of a walking adult's thorax."""


def trunk(node: walk3d.Node, ref: float) -> tuple:
    """``|ω_torso|² / ref²`` per s, split by global axis (x frontal, y transverse, z sagittal).
    The same code runs on CasADi symbols in the solver and on NumPy arrays in the reports."""
    w = node.pose.omega[node.body.segment_index("torso")]
    return tuple((w[k] / ref) ** 2 for k in range(3))


walk3d.register_term(walk3d.Term("trunk", trunk, TRUNK_RATE_REF,
                                 "the trunk's angular velocity (rad/s)"))  # fmt: skip


def main(out: str | None = None) -> int:
    pred = walk3d.predict(1.3, mass=62.0, height=1.70, sex="female",
                          criterion="natural,trunk=1", out=out)  # fmt: skip
    objective = pred.summary["objective"]
    print(f"converged: {pred.converged}")
    print(f"C_trunk: {objective['C_trunk']['total']:.4f} "
          f"(x {objective['C_trunk']['x']:.3f}, y {objective['C_trunk']['y']:.3f}, "
          f"z {objective['C_trunk']['z']:.3f})")  # fmt: skip
    print(f"C_weighted: {objective['C_weighted']['total']:.4f}, of which trunk "
          f"{objective['C_weighted']['parts']['trunk']:.4f}")  # fmt: skip
    return 0 if pred.converged else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else None))
