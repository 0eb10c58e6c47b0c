"""Elementary functions that work on NumPy arrays and on CasADi symbols alike.

The physics of walk3d is written once on *component tuples*: a 3-vector is a tuple ``(x, y, z)``
and a quaternion a tuple ``(w, x, y, z)`` whose entries are either NumPy arrays (one value per
time node, evaluated vectorised) or CasADi ``SX``/``MX`` expressions (building the symbolic graph
that the optimizer differentiates exactly). The functions here dispatch on the entry type.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

_SYMBOLIC = (ca.SX, ca.MX, ca.DM)


def _dispatch(name: str, np_fn: Any, ca_fn: Any) -> Any:
    def fn(x: Any) -> Any:
        return ca_fn(x) if isinstance(x, _SYMBOLIC) else np_fn(x)

    fn.__name__ = name
    fn.__doc__ = f"{name}(x) for NumPy arrays or CasADi expressions."
    return fn


sqrt = _dispatch("sqrt", np.sqrt, ca.sqrt)
sin = _dispatch("sin", np.sin, ca.sin)
cos = _dispatch("cos", np.cos, ca.cos)
exp = _dispatch("exp", np.exp, ca.exp)
fabs = _dispatch("fabs", np.abs, ca.fabs)
asin = _dispatch("asin", np.arcsin, ca.asin)


def fmax(a: Any, b: Any) -> Any:
    """Elementwise maximum for NumPy arrays or CasADi expressions."""
    if isinstance(a, _SYMBOLIC) or isinstance(b, _SYMBOLIC):
        return ca.fmax(a, b)
    return np.maximum(a, b)


def if_else(cond: Any, a: Any, b: Any) -> Any:
    """``a`` where ``cond`` else ``b`` (both branches are evaluated)."""
    if any(isinstance(v, _SYMBOLIC) for v in (cond, a, b)):
        return ca.if_else(cond, a, b)
    return np.where(cond, a, b)
