"""The 26 coordinates of one instant, the node model's input.

The 24 joint coordinates in :attr:`walk3d.body.model.BodyModel.dof_names` order (``sin(θ/2)``
of each hinge or universal axis, the quaternion's vector part along each ball joint's axes),
then the right and left stance-foot rotations (``sin(θ_ft/2)``). Each comes as a triple
``(value, rate, acceleration)`` in 1, 1/s and 1/s².
"""

from __future__ import annotations

N_COORD = 26
"""Coordinates per instant: 24 joint DoFs and the two stance-foot rotations."""
N_DOF = 24
"""Joint degrees of freedom (the first :data:`N_COORD` entries)."""
I_FOOT_R, I_FOOT_L = 24, 25
"""Indices of the right and left stance-foot rotations."""
