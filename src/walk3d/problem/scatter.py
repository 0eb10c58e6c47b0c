"""Sparse assembly of global derivative nonzeros from per-node blocks (used by
:mod:`walk3d.problem.derivatives` and :mod:`walk3d.problem.coupling`)."""

from __future__ import annotations

import casadi as ca
import numpy as np


def triplets(sp: ca.Sparsity) -> tuple[np.ndarray, np.ndarray]:
    r, c = sp.get_triplet()
    return np.asarray(r, dtype=int), np.asarray(c, dtype=int)


def per_node(first: ca.MX, rest: ca.MX, sp_rest: ca.Sparsity, n: int):
    """``(nonzeros, rows, cols)`` of node 0's block, then of each mapped node's block (the
    mapped output is the horizontal concatenation of the nodes' blocks)."""
    r0, c0 = triplets(first.sparsity())
    yield first.nz[:], r0, c0
    r, c = triplets(sp_rest)
    m = len(r)
    for k in range(1, n):
        yield rest.nz[(k - 1) * m : k * m], r, c


class Scatter:
    """Collects ``(row, col)`` targets of source nonzeros; builds ``nz_global = S @ nz_src``."""

    def __init__(self, shape: tuple[int, int]):
        self.shape = shape
        self.rows: list[np.ndarray] = []
        self.cols: list[np.ndarray] = []
        self.const_rows: list[np.ndarray] = []
        self.const_cols: list[np.ndarray] = []
        self.const_vals: list[np.ndarray] = []
        self.sources: list[ca.MX] = []

    def add(self, nz: ca.MX, rows: np.ndarray, cols: np.ndarray) -> None:
        self.sources.append(nz)
        self.rows.append(rows)
        self.cols.append(cols)

    def add_const(self, rows: np.ndarray, cols: np.ndarray, vals: np.ndarray) -> None:
        self.const_rows.append(rows)
        self.const_cols.append(cols)
        self.const_vals.append(vals)

    def build(self) -> ca.MX:
        rows = np.concatenate(self.rows + self.const_rows)
        cols = np.concatenate(self.cols + self.const_cols)
        # global nonzeros: the distinct targets in column-major order; slot = position of each
        keys, slot = np.unique(cols * self.shape[0] + rows, return_inverse=True)
        sp = ca.Sparsity.triplet(*self.shape, (keys % self.shape[0]).tolist(),
                                 (keys // self.shape[0]).tolist())  # fmt: skip
        assert sp.nnz() == len(keys)
        n_var = sum(len(r) for r in self.rows)
        src = np.arange(n_var)
        scatter = ca.DM(ca.Sparsity.triplet(sp.nnz(), n_var, slot[:n_var].tolist(),
                                            src.tolist()), 1.0)  # fmt: skip
        nz = ca.mtimes(scatter, ca.vertcat(*self.sources))
        if self.const_vals:
            const = np.zeros(sp.nnz())
            np.add.at(const, slot[n_var:], np.concatenate(self.const_vals))
            nz = nz + ca.DM(const)
        return ca.MX(sp, nz)
