"""Sparse direct factorisations behind one small interface.

``factorize(A)`` returns an object with ``solve(b)`` for b of shape (n,) or (n, k).
Backends, in the order "auto" tries them:

- ``cholmod``: CHOLMOD (SuiteSparse) supernodal Cholesky, from the cvxopt wheel
  (extra ``pfeie[fast]``; no compiler needed). Symmetric positive definite only. A
  block of right-hand sides is solved in one sweep of the factor (:mod:`._block`), one
  column by cvxopt's own solve.
  The fill-reducing ordering is METIS nested dissection (pymetis wheel, same extra) on
  the quotient graph of rows with identical patterns (the nodes, for node-major DOFs);
  without pymetis CHOLMOD falls back to its own AMD, which fills 3D meshes far more.
- ``superlu``: SciPy's SuperLU with the MMD ordering of AᵀA + A and symmetric mode,
  always available; also the backend for indefinite or unsymmetric matrices.

Measured on a 2-core machine, one thread, 2D Q4 plane strain of 100k DOF (factorise /
one back-substitution): CHOLMOD 0.76 s / 26 ms; SuperLU 1.6 s / 37 ms; cholespy
2.1 s / 21 ms but 142 s to factorise a 100k-DOF 3D matrix (CHOLMOD: 19 s), so it is not
used. 3D Hex8 of 95k DOF with CHOLMOD: METIS ordering 9.4 s / 175 ms and 1.7 GB,
AMD ordering 42 s / 384 ms and 3.3 GB. The environment variable ``PFEIE_SOLVER`` overrides "auto".
"""

from __future__ import annotations

import ctypes
import logging
import os
import threading
from typing import Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import MechanismError, SolverError
from ..typing import FloatArray, IntArray
from ._block import BLOCK, BlockSolver, block_solver, pays
from ._lockstep import in_lockstep, pending_solve

log = logging.getLogger(__name__)

# a pivot below this fraction of the largest diagonal entry marks a singular matrix
_SINGULAR = 1e-13


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
        if diag_u.size and diag_u.min() <= _SINGULAR * diag_u.max():
            raise MechanismError(
                "the matrix is numerically singular: some part of the model is not "
                "restrained (check supports)"
            )

    def __deepcopy__(self, memo: dict[int, object]) -> _SuperLU:
        return self  # a factor never changes: copies of what holds it share it

    def solve(self, b: FloatArray) -> FloatArray:
        return np.asarray(self._lu.solve(np.asarray(b, dtype=float)))


def nested_dissection(A: sp.spmatrix) -> IntArray | None:
    """A METIS nested-dissection permutation of symmetric A, or None without pymetis (or
    where METIS fails on the graph: the factor is then ordered by CHOLMOD's AMD).

    Rows with the same sparsity pattern (the DOFs of one node) are merged first, so
    METIS orders the node graph, which is several times smaller; the permutation of
    the merged graph is then expanded, keeping the DOFs of a node together. The merge
    key is (row length, Σ col, Σ col²): a collision can only worsen the fill, never
    the result.
    """
    try:
        import pymetis
    except ImportError:
        return None
    G = sp.csr_matrix(A, copy=True)
    G.sum_duplicates()
    G.sort_indices()
    n = G.shape[0]
    if n < 64:
        return None
    cols = G.indices.astype(np.int64)
    row = np.repeat(np.arange(n), np.diff(G.indptr))
    key = np.stack([
        np.diff(G.indptr),
        np.bincount(row, cols, minlength=n).astype(np.int64),
        np.bincount(row, (cols * cols).astype(float), minlength=n).astype(np.int64),
    ], axis=1)  # fmt: skip
    _, group = np.unique(key, axis=0, return_inverse=True)
    group = group.ravel()
    n_groups = int(group.max()) + 1
    Q = sp.csr_matrix((np.ones(cols.size), (group[row], group[cols])), shape=(n_groups, n_groups))
    Q.setdiag(0)
    Q.eliminate_zeros()
    Q.sort_indices()
    if Q.nnz == 0:
        return None
    try:
        perm_g, _ = pymetis.nested_dissection(pymetis.CSRAdjacency(Q.indptr, Q.indices))
    except (RuntimeError, ValueError) as exc:  # METIS's own failure: CHOLMOD's AMD instead
        log.warning("METIS could not order the %d-node graph (%s); ordering by AMD", n_groups,
                    exc)  # fmt: skip
        return None
    rank = np.empty(n_groups, dtype=np.int64)
    rank[np.asarray(perm_g, dtype=np.int64)] = np.arange(n_groups)
    return np.lexsort((np.arange(n), rank[group]))


class _Cholmod:
    backend = "cholmod"

    def __init__(self, A: sp.spmatrix) -> None:
        import cvxopt
        import cvxopt.cholmod as cholmod

        self._cvx = cvxopt
        self._cm = cholmod
        self._checked = False
        self._check_lock = threading.RLock()
        self._block_solver: tuple[BlockSolver, int] | None = None
        self._invariant: bool | None = None
        self.n = A.shape[0]
        low = sp.tril(A, format="coo")
        S = cvxopt.spmatrix(low.data, low.row.astype(np.int64), low.col.astype(np.int64),
                            (self.n, self.n))  # fmt: skip
        cholmod.options["supernodal"] = 2
        perm = nested_dissection(A)
        self.ordering = "amd" if perm is None else "metis"
        try:
            if perm is None:
                self._F = cholmod.symbolic(S)
            else:
                self._F = cholmod.symbolic(S, p=cvxopt.matrix(perm.tolist(), tc="i"))
            cholmod.numeric(S, self._F)
        except ArithmeticError:
            raise MechanismError(
                "the matrix is not positive definite: some part of the model is not "
                "restrained (check supports), or a material is invalid"
            ) from None
        # a singular matrix can factorise with round-off pivots of either sign: a pivot
        # d_j = L_jj² that is tiny against the diagonal of A is a zero-energy mode
        piv = np.asarray(cholmod.diag(self._F), dtype=float).ravel() ** 2
        scale = float(np.abs(A.diagonal()).max(initial=0.0))
        if piv.size and piv.min() <= _SINGULAR * scale:
            raise MechanismError(
                "the matrix is numerically singular: some part of the model is not "
                "restrained (check supports)"
            )

    def __deepcopy__(self, memo: dict[int, object]) -> _Cholmod:
        return self  # a factor never changes: copies of what holds it share it

    def solve(self, b: FloatArray) -> FloatArray:
        arr = np.asarray(b, dtype=float)
        cols = arr.reshape(self.n, -1)
        k = cols.shape[1]
        if pays(self.n, k) and self._block() is not None:
            if k % 2 == 0 and in_lockstep() and self.batch_invariant():
                X = pending_solve(self, cols)  # with the other runs in lockstep
                if X is not None:
                    return X.reshape(arr.shape)
            return self._solve_blocks(cols).reshape(arr.shape)
        return self._solve_columns(cols).reshape(arr.shape)

    def solve_block(self, cols: FloatArray) -> FloatArray:
        """The block solve of the columns of several computations in lockstep
        (:mod:`._lockstep`); only called on a batch-invariant factor, with an even number
        of columns."""
        return self._solve_blocks(cols)

    def batch_invariant(self) -> bool:
        """Whether a column solved in an even-width block has the same bits wherever it
        sits and whatever columns are beside it (then computations in lockstep may share
        block solves and still get what each gets alone, :mod:`._lockstep`). Checked once on
        this factor: a probe column at positions 0 of 2, 1 and 3 of 4, 6 of 16 and 17 of 18
        (across the chunks of :data:`._block.BLOCK`), among random others. Measured true
        with the cvxopt wheel's CHOLMOD and OpenBLAS (columns of odd-width blocks are not:
        the last one takes another kernel)."""
        with self._check_lock:
            if self._invariant is None:
                self._invariant = self._check_invariant()
        return self._invariant

    def _check_invariant(self) -> bool:
        if self._block() is None:
            return False
        rng = np.random.default_rng(20261126)
        probe = rng.standard_normal(self.n)
        ref = self._solve_blocks(np.column_stack([probe, rng.standard_normal(self.n)]))[:, 0]
        for width, at in ((4, 1), (4, 3), (16, 6), (18, 17)):
            cols = rng.standard_normal((self.n, width))
            cols[:, at] = probe
            if not np.array_equal(self._solve_blocks(cols)[:, at], ref):
                log.info("block solves are not batch-invariant on this installation: runs "
                         "in lockstep solve their blocks one at a time")  # fmt: skip
                return False
        return True

    def _solve_columns(self, cols: FloatArray) -> FloatArray:
        """cvxopt's solve: one column at a time."""
        B = self._cvx.matrix(np.asfortranarray(cols))
        self._cm.solve(self._F, B)
        return np.asarray(B)

    def _solve_blocks(self, cols: FloatArray) -> FloatArray:
        """CHOLMOD's solve of :data:`._block.BLOCK` columns at a time (:mod:`._block`); if
        CHOLMOD fails (out of memory, say), one column at a time from then on."""
        solver, L = self._block()  # type: ignore[misc]
        k = cols.shape[1]
        try:
            return np.hstack([solver.solve(L, cols[:, j : j + BLOCK])
                              for j in range(0, k, BLOCK)])  # fmt: skip
        except (ArithmeticError, ctypes.ArgumentError) as exc:
            log.warning("CHOLMOD's block solve failed (%s); solving one column at a time", exc)
            self._block_solver = None
            return self._solve_columns(cols)

    def _block(self) -> tuple[BlockSolver, int] | None:
        """The block solver and this factor's pointer, once it has reproduced the
        column-by-column solve here (two random columns to 1e-12); None otherwise."""
        with self._check_lock:  # threads wait for the check, not take the column path
            if not self._checked:
                self._block_solver = self._check()
                self._checked = True
        return self._block_solver

    def _check(self) -> tuple[BlockSolver, int] | None:
        solver = block_solver()
        if solver is None:
            return None
        try:
            L = solver.factor_pointer(self._F)
            probe = np.random.default_rng(20261126).standard_normal((self.n, 2))
            ref = self._solve_columns(probe)
            err = float(np.abs(solver.solve(L, probe) - ref).max())
        except (TypeError, ArithmeticError, ValueError, ctypes.ArgumentError) as exc:
            log.debug("CHOLMOD block solve not used: %s", exc)
            return None
        if not err <= 1e-12 * float(np.abs(ref).max()):
            log.warning("CHOLMOD's block solve differs from its column solve by %.1e here; "
                        "solving one column at a time", err)  # fmt: skip
            return None
        return solver, L


def shares_block_solves(F: Factorization) -> bool:
    """Whether runs in lockstep on the factor ``F`` (:func:`run_lockstep`) gain from
    sharing its block solves and still get their own bits: a CHOLMOD factor (or a
    low-rank update of one) large enough for two-column blocks (:func:`._block.pays`),
    whose block solves are batch-invariant (:meth:`_Cholmod.batch_invariant`)."""
    base = getattr(F, "base", F)
    check = getattr(base, "batch_invariant", None)
    return check is not None and pays(F.n, 2) and bool(check())


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


def _backend(backend: str, spd: bool) -> str:
    """The backend that ``factorize`` takes: ``backend``, or for "auto" ``PFEIE_SOLVER``
    or the best available; SuperLU for a matrix that is not SPD."""
    choice = os.environ.get("PFEIE_SOLVER", backend) if backend == "auto" else backend
    avail = available_backends()
    if choice == "auto":
        choice = avail[0] if spd else "superlu"
    if choice not in avail:
        raise SolverError(f"solver backend {choice!r} is not available; available: {avail}")
    return "superlu" if choice == "cholmod" and not spd else choice


def solver_stack(backend: str = "auto") -> str:
    """The sparse solver that ``factorize(A, backend=backend)`` uses here for a
    symmetric positive definite matrix, and its ordering: ``"cholmod+metis"``,
    ``"cholmod+amd"`` (without pymetis; CHOLMOD also orders by AMD a matrix below 64 rows
    or whose graph METIS cannot split, the same way on every install) or ``"superlu"``
    (without cvxopt, ``PFEIE_SOLVER=superlu`` or ``backend="superlu"``). The results of
    a run depend on it in their last bits: a run's key holds it, so that a resume or a
    study does not mix two.

    >>> solver_stack() in ("cholmod+metis", "cholmod+amd", "superlu")
    True
    >>> solver_stack("superlu")
    'superlu'
    """
    choice = _backend(backend, spd=True)
    if choice != "cholmod":
        return choice
    try:
        import pymetis  # noqa: F401
    except ImportError:
        return "cholmod+amd"
    return "cholmod+metis"


def factorize(A: sp.spmatrix, *, spd: bool = True, backend: str = "auto") -> Factorization:
    """Factorise a sparse matrix once; solve many times.

    ``spd`` declares A symmetric positive definite (Cholesky backends allowed);
    otherwise SuperLU is used. Raises :class:`MechanismError` when A is singular.
    """
    if not sp.issparse(A):
        if not (isinstance(A, np.ndarray) and A.ndim == 2 and A.dtype.kind in "fiu"):
            raise SolverError(f"factorize: expected a sparse matrix (scipy.sparse), got "
                              f"{type(A).__name__}")  # fmt: skip
        A = sp.csc_matrix(A, dtype=float)  # a dense array: its sparse copy
    if A.shape[0] != A.shape[1]:
        raise SolverError(f"factorize needs a square matrix, got {A.shape}")
    choice = _backend(backend, spd)
    log.debug("factorising %d x %d (nnz %d) with %s", A.shape[0], A.shape[1], A.nnz, choice)
    if A.shape[0] == 0:
        raise MechanismError("there are no free degrees of freedom")
    if choice == "cholmod":
        return _Cholmod(A)
    return _SuperLU(A, symmetric=spd)
