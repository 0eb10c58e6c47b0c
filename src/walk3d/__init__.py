"""walk3d: predict three-dimensional whole-body human walking.

Conventions used everywhere in the package (see ``docs/conventions.md``):

* global frame: X forward, Y up, Z to the walker's right (OpenSim);
* quaternions are scalar-first ``[w, x, y, z]``;
* SI units inside the package (radians, metres, newtons); degrees and N/kg only at the edges
  (command line, files, figures);
* time is the first axis of every array.
"""

__version__ = "0.1.0"

G = 9.81
"""Gravitational acceleration magnitude, m/s^2. Gravity is ``(0, -G, 0)`` in the global frame."""
