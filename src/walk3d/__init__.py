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


def load_result(out_dir):  # noqa: ANN001, ANN201 - thin lazy re-export
    """Read a prediction folder written by ``walk3d predict`` (see :mod:`walk3d.results`)."""
    from walk3d.results import load_result as _load

    return _load(out_dir)
