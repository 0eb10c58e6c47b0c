"""Unit-quaternion algebra, scalar-first ``[w, x, y, z]``, with exact time derivatives.

Two layers:

* **component tuples** (``Q = (w, x, y, z)``, ``V = (x, y, z)``) whose entries are NumPy arrays
  over time nodes or CasADi expressions; used by the model so that one code path serves numeric
  evaluation and the symbolic graph;
* **array wrappers** (``multiply``, ``conjugate``, ``rotate``) on ``(..., 4)`` arrays, scalar
  first, for users and tests.

A quaternion ``q`` describing the orientation of frame B in frame A maps B-coordinates to
A-coordinates: ``v_A = q ⊗ v_B ⊗ q*``. Joint quaternions map the child frame to the parent
frame, so ``q_child_global = q_parent_global ⊗ q_joint``.

Time derivatives travel as triples ``(q, q_dot, q_ddot)``; products and rotations use the
product rule exactly (paper Eq. 3), and the angular velocity and acceleration follow from the
paper's ``ω = 2 L Λ̇``, ``α = 2 L Λ̈`` (body frame).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from walk3d import mathops as m

_W_FLOOR = 1e-6
"""Floor under ``1 - |v|²`` in the scalar part: only reached outside the joint ranges (at an
optimizer's trial points), where it keeps values finite instead of NaN."""

Q = tuple[Any, Any, Any, Any]
V = tuple[Any, Any, Any]
QTriple = tuple[Q, Q, Q]
VTriple = tuple[V, V, V]


# --------------------------------------------------------------------------------------------
# component-tuple layer
# --------------------------------------------------------------------------------------------
def qmul(a: Q, b: Q) -> Q:
    """Hamilton product ``a ⊗ b``."""
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return (
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    )


def qconj(a: Q) -> Q:
    """Conjugate ``a*`` (the inverse of a unit quaternion)."""
    return (a[0], -a[1], -a[2], -a[3])


def vadd(a: V, b: V) -> V:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def vsub(a: V, b: V) -> V:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def vscale(s: Any, a: V) -> V:
    return (s * a[0], s * a[1], s * a[2])


def vdot(a: V, b: V) -> Any:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def vcross(a: V, b: V) -> V:
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def _pure(v: V) -> Q:
    return (0.0 * v[0], v[0], v[1], v[2])


def qrot(q: Q, v: V) -> V:
    """Rotate ``v`` by ``q``: vector part of ``q ⊗ v ⊗ q*`` (computed without the products)."""
    w, x, y, z = q
    u = (x, y, z)
    t = vscale(2.0, vcross(u, v))
    c = vcross(u, t)
    return (v[0] + w * t[0] + c[0], v[1] + w * t[1] + c[1], v[2] + w * t[2] + c[2])


def qrot_inv(q: Q, v: V) -> V:
    """Rotate ``v`` by ``q*`` (global to local)."""
    return qrot(qconj(q), v)


def L_matrix_apply(q: Q, d: Q) -> V:
    """``L(q) · d`` with the paper's 3×4 matrix L (so ``2 L q̇`` is the body-frame ω)."""
    l0, l1, l2, l3 = q
    d0, d1, d2, d3 = d
    return (
        -l1 * d0 + l0 * d1 + l3 * d2 - l2 * d3,
        -l2 * d0 - l3 * d1 + l0 * d2 + l1 * d3,
        -l3 * d0 + l2 * d1 - l1 * d2 + l0 * d3,
    )


# --------------------------------------------------------------------------------------------
# triples (value, first and second time derivative)
# --------------------------------------------------------------------------------------------
def _qadd(*qs: Q) -> Q:
    return tuple(sum(c) for c in zip(*qs, strict=True))  # type: ignore[return-value]


def _qscale(s: float, a: Q) -> Q:
    return (s * a[0], s * a[1], s * a[2], s * a[3])


def qmul_triple(A: QTriple, B: QTriple) -> QTriple:
    """Product of two quaternion trajectories with exact first and second derivatives."""
    a, ad, add = A
    b, bd, bdd = B
    return (
        qmul(a, b),
        _qadd(qmul(ad, b), qmul(a, bd)),
        _qadd(qmul(add, b), _qscale(2.0, qmul(ad, bd)), qmul(a, bdd)),
    )


def qconj_triple(A: QTriple) -> QTriple:
    return (qconj(A[0]), qconj(A[1]), qconj(A[2]))


def rotate_triple(A: QTriple, p: V) -> VTriple:
    """``q ⊗ p ⊗ q*`` for a vector ``p`` fixed in the rotating frame, with derivatives (Eq. 3)."""
    q, qd, qdd = A
    pq = _pure(p)
    qc, qdc, qddc = qconj(q), qconj(qd), qconj(qdd)
    r = qrot(q, p)
    r_d = _qadd(qmul(qmul(qd, pq), qc), qmul(qmul(q, pq), qdc))
    r_dd = _qadd(
        qmul(qmul(qdd, pq), qc),
        _qscale(2.0, qmul(qmul(qd, pq), qdc)),
        qmul(qmul(q, pq), qddc),
    )
    return (r, (r_d[1], r_d[2], r_d[3]), (r_dd[1], r_dd[2], r_dd[3]))


def rotate_moving_triple(A: QTriple, p: VTriple) -> VTriple:
    """``q ⊗ p ⊗ q*`` for a moving vector ``p`` (a triple), with derivatives."""
    pure = tuple((0.0 * c[0], *c) for c in p)
    r = qmul_triple(qmul_triple(A, pure), qconj_triple(A))  # type: ignore[arg-type]
    return tuple((c[1], c[2], c[3]) for c in r)  # type: ignore[return-value]


def scale_triple(s: tuple[Any, Any, Any], a: VTriple) -> VTriple:
    """``s · a`` for a scalar trajectory ``s`` (value, first, second derivative)."""
    return (
        vscale(s[0], a[0]),
        vadd(vscale(s[1], a[0]), vscale(s[0], a[1])),
        vadd(vadd(vscale(s[2], a[0]), vscale(2.0 * s[1], a[1])), vscale(s[0], a[2])),
    )


def vadd_triple(a: VTriple, b: VTriple) -> VTriple:
    return (vadd(a[0], b[0]), vadd(a[1], b[1]), vadd(a[2], b[2]))


def vsub_triple(a: VTriple, b: VTriple) -> VTriple:
    return (vsub(a[0], b[0]), vsub(a[1], b[1]), vsub(a[2], b[2]))


def omega_alpha_body(A: QTriple) -> tuple[V, V]:
    """Body-frame angular velocity and acceleration, ``ω = 2 L Λ̇`` and ``α = 2 L Λ̈``."""
    q, qd, qdd = A
    w = L_matrix_apply(q, qd)
    a = L_matrix_apply(q, qdd)
    return vscale(2.0, w), vscale(2.0, a)


def from_sine_triple(u: V, s: Any, sd: Any, sdd: Any) -> QTriple:
    """Hinge quaternion ``[cos(θ/2), u sin(θ/2)]`` from ``s = sin(θ/2)`` and its derivatives.

    ``u`` is a constant unit axis. Requires ``|s| < 1``.
    """
    w = m.sqrt(m.fmax(1.0 - s * s, _W_FLOOR))
    wd = -s * sd / w
    wdd = -(sd * sd + s * sdd) / w - (s * sd) ** 2 / w**3
    return (
        (w, u[0] * s, u[1] * s, u[2] * s),
        (wd, u[0] * sd, u[1] * sd, u[2] * sd),
        (wdd, u[0] * sdd, u[1] * sdd, u[2] * sdd),
    )


def from_vector_triple(v: V, vd: V, vdd: V) -> QTriple:
    """Unit quaternion from its vector part, ``w = sqrt(1 - |v|²)`` (ball joints).

    Requires ``|v| < 1`` (rotations below 180°), which the joint ranges guarantee.
    """
    vv = vdot(v, v)
    vvd = vdot(v, vd)
    w = m.sqrt(m.fmax(1.0 - vv, _W_FLOOR))
    wd = -vvd / w
    wdd = -(vdot(vd, vd) + vdot(v, vdd)) / w - vvd * vvd / w**3
    return ((w, *v), (wd, *vd), (wdd, *vdd))


# --------------------------------------------------------------------------------------------
# array layer: (..., 4) arrays, scalar first
# --------------------------------------------------------------------------------------------
def _split(a: np.ndarray) -> Q:
    a = np.asarray(a, dtype=float)
    return (a[..., 0], a[..., 1], a[..., 2], a[..., 3])


def multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of ``(..., 4)`` arrays in scalar-first order ``[w, x, y, z]``."""
    return np.stack(qmul(_split(a), _split(b)), axis=-1)


def conjugate(a: np.ndarray) -> np.ndarray:
    """Conjugate of ``(..., 4)`` scalar-first quaternions."""
    return np.stack(qconj(_split(a)), axis=-1)


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate ``(..., 3)`` vectors by ``(..., 4)`` scalar-first quaternions."""
    v = np.asarray(v, dtype=float)
    return np.stack(qrot(_split(q), (v[..., 0], v[..., 1], v[..., 2])), axis=-1)


def from_axis_angle(axis: np.ndarray, angle: np.ndarray | float) -> np.ndarray:
    """Scalar-first quaternion for a rotation by ``angle`` (rad) about unit ``axis``."""
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)[..., None]
    return np.concatenate([np.cos(angle / 2), axis * np.sin(angle / 2)], axis=-1)


def to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` of scalar-first quaternions (columns = rotated axes)."""
    eye = np.eye(3)
    q = np.asarray(q, dtype=float)
    cols = [rotate(q, np.broadcast_to(eye[i], q.shape[:-1] + (3,))) for i in range(3)]
    return np.stack(cols, axis=-1)


def mirror(q: np.ndarray) -> np.ndarray:
    """Mirror image through the sagittal (XY) plane: ``[w, x, y, z] -> [w, -x, -y, z]``."""
    return np.asarray(q, dtype=float) * np.array([1.0, -1.0, -1.0, 1.0])
