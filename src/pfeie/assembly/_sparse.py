"""Scatter of element arrays into global sparse matrices and vectors.

Global DOF numbering is node-major: ``dof = node · dim + component``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..typing import FloatArray, IntArray


def element_dofs(conn: IntArray, dim: int) -> IntArray:
    """Global DOFs (c, n·d) of cells, node-major."""
    return (conn[:, :, None] * dim + np.arange(dim)).reshape(conn.shape[0], -1)


def assemble_matrix(dofs: IntArray, blocks: FloatArray, n: int) -> sp.csr_matrix:
    """Sum element matrices (c, k, k) on DOFs (c, k) into an n × n CSR matrix."""
    k = dofs.shape[1]
    rows = np.repeat(dofs, k, axis=1).ravel()
    cols = np.tile(dofs, (1, k)).ravel()
    m = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(n, n))
    m.sum_duplicates()
    return m


def assemble_vector(dofs: IntArray, values: FloatArray, n: int) -> FloatArray:
    """Sum element vectors (c, k) on DOFs (c, k) into a vector of length n."""
    return np.bincount(dofs.ravel(), weights=values.ravel(), minlength=n).astype(float)
