"""walk3d: predict three-dimensional whole-body human walking.

Conventions used everywhere in the package (see ``docs/conventions.md``):

* global frame: X forward, Y up, Z to the walker's right (OpenSim);
* quaternions are scalar-first ``[w, x, y, z]``;
* SI units inside the package (radians, metres, newtons); degrees and N/kg only at the edges
  (command line, files, figures);
* time is the first axis of every array.
"""

from walk3d.constants import G, __version__

__all__ = ["G", "Node", "Prediction", "Term", "__version__", "load_result", "predict",
           "register_term", "track"]  # fmt: skip

_API = ("Prediction", "load_result", "predict", "track")
_TERMS = {"Term": "Term", "Node": "Node", "register_term": "register"}


def __getattr__(name: str):  # noqa: ANN202 - lazy: ``import walk3d`` stays light for the CLI
    """``predict``, ``load_result`` and ``Prediction`` from :mod:`walk3d.api`; ``Term``,
    ``Node`` and ``register_term`` (:func:`walk3d.model.terms.register`), on first use."""
    if name in _API:
        from walk3d import api

        return getattr(api, name)
    if name in _TERMS:
        from walk3d.model import terms

        return getattr(terms, _TERMS[name])
    raise AttributeError(f"module 'walk3d' has no attribute {name!r}")
