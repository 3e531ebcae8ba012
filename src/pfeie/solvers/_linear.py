"""Sparse direct factorisations behind one small interface.

``factorize(A)`` returns an object with ``solve(b)`` for b of shape (n,) or (n, k).
Backends, in the order "auto" tries them:

- ``cholmod``: CHOLMOD (SuiteSparse) supernodal Cholesky, from the cvxopt wheel
  (extra ``pfeie[fast]``; no compiler needed). Symmetric positive definite only.
- ``superlu``: SciPy's SuperLU with the MMD ordering of AᵀA + A and symmetric mode,
  always available; also the backend for indefinite or unsymmetric matrices.

Measured on a 2-core machine, one thread, 2D Q4 plane strain of 100k DOF (factorise /
one back-substitution): CHOLMOD 0.76 s / 26 ms; SuperLU 1.6 s / 37 ms; cholespy
2.1 s / 21 ms but 142 s to factorise a 100k-DOF 3D matrix (CHOLMOD: 19 s), so it is not
used. The environment variable ``PFEIE_SOLVER`` overrides "auto".
"""

from __future__ import annotations

import logging
import os
from typing import Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..element._reference import FloatArray
from ..errors import MechanismError, SolverError

log = logging.getLogger(__name__)


class Factorization(Protocol):
    """A factorised square matrix: ``solve`` applies its inverse."""

    backend: str
    n: int

    def solve(self, b: FloatArray) -> FloatArray: ...


class _SuperLU:
    backend = "superlu"

    def __init__(self, A: sp.spmatrix, symmetric: bool) -> None:
        self.n = A.shape[0]
        opts = {"SymmetricMode": True} if symmetric else {}
        try:
            self._lu = spla.splu(
                sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A" if symmetric else "COLAMD",
                options=opts,
            )  # fmt: skip
        except RuntimeError as exc:
            raise MechanismError(
                f"the matrix is singular ({exc}): some part of the model is not "
                "restrained (check supports)"
            ) from None
        diag_u = np.abs(self._lu.U.diagonal())
        if diag_u.size and diag_u.min() <= 1e-13 * diag_u.max():
            raise MechanismError(
                "the matrix is numerically singular: some part of the model is not "
                "restrained (check supports)"
            )

    def solve(self, b: FloatArray) -> FloatArray:
        return np.asarray(self._lu.solve(np.asarray(b, dtype=float)))


class _Cholmod:
    backend = "cholmod"

    def __init__(self, A: sp.spmatrix) -> None:
        import cvxopt
        import cvxopt.cholmod as cholmod

        self._cvx = cvxopt
        self._cm = cholmod
        self.n = A.shape[0]
        low = sp.tril(A, format="coo")
        S = cvxopt.spmatrix(low.data, low.row.astype(np.int64), low.col.astype(np.int64),
                            (self.n, self.n))  # fmt: skip
        cholmod.options["supernodal"] = 2
        try:
            self._F = cholmod.symbolic(S)
            cholmod.numeric(S, self._F)
        except ArithmeticError:
            raise MechanismError(
                "the matrix is not positive definite: some part of the model is not "
                "restrained (check supports), or a material is invalid"
            ) from None

    def solve(self, b: FloatArray) -> FloatArray:
        arr = np.asarray(b, dtype=float)
        B = self._cvx.matrix(np.asfortranarray(arr.reshape(self.n, -1)))
        self._cm.solve(self._F, B)
        return np.asarray(B).reshape(arr.shape)


def available_backends() -> list[str]:
    """The backends that can be imported here, best first."""
    out = []
    try:
        import cvxopt.cholmod  # noqa: F401

        out.append("cholmod")
    except ImportError:
        pass
    out.append("superlu")
    return out


def factorize(A: sp.spmatrix, *, spd: bool = True, backend: str = "auto") -> Factorization:
    """Factorise a sparse matrix once; solve many times.

    ``spd`` declares A symmetric positive definite (Cholesky backends allowed);
    otherwise SuperLU is used. Raises :class:`MechanismError` when A is singular.
    """
    if A.shape[0] != A.shape[1]:
        raise SolverError(f"factorize needs a square matrix, got {A.shape}")
    choice = os.environ.get("PFEIE_SOLVER", backend) if backend == "auto" else backend
    avail = available_backends()
    if choice == "auto":
        choice = avail[0] if spd else "superlu"
    if choice not in avail:
        raise SolverError(f"solver backend {choice!r} is not available; available: {avail}")
    if choice == "cholmod" and not spd:
        choice = "superlu"
    log.debug("factorising %d x %d (nnz %d) with %s", A.shape[0], A.shape[1], A.nnz, choice)
    if A.shape[0] == 0:
        raise MechanismError("there are no free degrees of freedom")
    if choice == "cholmod":
        return _Cholmod(A)
    return _SuperLU(A, symmetric=spd)
