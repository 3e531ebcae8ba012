"""CHOLMOD's block solve on cvxopt's factor (:mod:`pfeie.linalg._block`) against the
column-by-column solve of cvxopt, the reference it replaces for two or more columns.

The matrix: a plane-strain-like stiffness (a 9-point stencil with two DOFs a node and
a small shift, SPD) of 60 × 60 nodes, 7,200 DOF.
"""

from __future__ import annotations

import platform
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp

from pfeie.linalg import factorize
from pfeie.linalg._block import BLOCK, BLOCK_MIN_DOF, SMALL_BLOCK_MIN_DOF, block_solver, pays

pytest.importorskip("cvxopt")


def _stiffness(nx: int) -> sp.csr_matrix:
    T = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(nx, nx))
    L = -sp.kron(T, T).tocsr()
    L.setdiag(0.0)
    L.setdiag(-np.asarray(L.sum(axis=1)).ravel() + 0.01)
    return sp.csr_matrix(sp.kron(L, np.array([[2.0, 0.5], [0.5, 2.0]])))


def _fresh() -> tuple[Any, Any]:
    """The block solver (the test is skipped without one) and a new factor of 5,000 DOF
    (``BLOCK_MIN_DOF``), not yet checked."""
    solver = block_solver()
    if solver is None:
        pytest.skip("no block solve here")
    return solver, factorize(_stiffness(50), backend="cholmod")


@pytest.fixture(scope="module")
def factor():  # type: ignore[no-untyped-def]
    return factorize(_stiffness(60), backend="cholmod")


def test_the_block_solve_is_available_with_the_linux_wheel() -> None:
    """On Linux x86-64 the cvxopt wheel bundles its CHOLMOD: the accelerator must load
    (a silent loss would only show as slower steps)."""
    if platform.system() != "Linux" or platform.machine() != "x86_64":
        pytest.skip("the bundled library's layout is checked on Linux x86-64")
    assert block_solver() is not None


@pytest.mark.parametrize("k", [4, BLOCK, BLOCK + 1, 2 * BLOCK + 5])
def test_block_solve_equals_the_column_solve(factor, k: int) -> None:  # type: ignore[no-untyped-def]
    """k columns, in blocks of ``BLOCK`` (the boundaries crossed): each equals cvxopt's
    solve of that column alone to 1e-14 of its size (measured 2e-16: the same factor,
    another order of the supernodal updates); a (n, k) and an (n, 1, k) right-hand side
    keep their shapes."""
    if factor._block() is None:
        pytest.skip("no block solve here")
    rng = np.random.default_rng(k)
    B = rng.standard_normal((factor.n, k))
    X = factor.solve(B)
    ref = np.column_stack([factor.solve(B[:, j]) for j in range(k)])
    assert X.shape == B.shape
    assert np.abs(X - ref).max() <= 1e-14 * np.abs(ref).max()
    assert factor.solve(B.reshape(factor.n, 1, k)).shape == (factor.n, 1, k)


def test_one_column_keeps_cvxopts_bits(factor) -> None:  # type: ignore[no-untyped-def]
    """One column, as a vector or an (n, 1) array, is cvxopt's own solve, bit for bit;
    so are two and three columns of a factor below ``SMALL_BLOCK_MIN_DOF`` (7,200 DOF
    here), where a block would not pay."""
    assert factor.n < SMALL_BLOCK_MIN_DOF
    rng = np.random.default_rng(1)
    b = rng.standard_normal(factor.n)
    ref = factor._solve_columns(b[:, None]).ravel()
    np.testing.assert_array_equal(factor.solve(b), ref)
    np.testing.assert_array_equal(factor.solve(b[:, None]).ravel(), ref)
    B = rng.standard_normal((factor.n, 3))
    np.testing.assert_array_equal(factor.solve(B[:, :2]), factor._solve_columns(B[:, :2]))
    np.testing.assert_array_equal(factor.solve(B), factor._solve_columns(B))


def test_the_rule_on_sizes() -> None:
    """Blocks from ``BLOCK_MIN_DOF`` DOF and four columns; two and three columns from
    ``SMALL_BLOCK_MIN_DOF`` DOF on."""
    assert not pays(10**6, 1)
    assert not pays(BLOCK_MIN_DOF - 1, 64) and pays(BLOCK_MIN_DOF, 4)
    assert not pays(SMALL_BLOCK_MIN_DOF - 1, 3) and pays(SMALL_BLOCK_MIN_DOF, 2)


def _perturbed(real):  # type: ignore[no-untyped-def]
    return lambda self, L, B: real(self, L, B) * (1 + 1e-9)


def _failing(real):  # type: ignore[no-untyped-def]
    def fail(self, L, B):  # type: ignore[no-untyped-def]
        raise ArithmeticError("cholmod_l_solve returned no solution")

    return fail


@pytest.mark.parametrize(("fake", "checked", "message"), [
    (_perturbed, False, "differs from its column solve"),
    (_failing, True, "block solve failed"),
])  # fmt: skip
def test_a_block_solve_that_disagrees_or_fails_is_not_used(
    fake, checked: bool, message: str,  # type: ignore[no-untyped-def]
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A block solve that does not reproduce the column solve at the check on the first
    block (here: perturbed by 1e-9), or CHOLMOD failing after the check (an
    ArithmeticError, as for a NULL result when it runs out of memory), costs a warning,
    not the run: the block is solved one column at a time (cvxopt's bits), and so are
    later blocks."""
    solver, F = _fresh()
    if checked:
        assert F._block() is not None
    monkeypatch.setattr(type(solver), "solve", fake(type(solver).solve))
    B = np.random.default_rng(2).standard_normal((F.n, 5))
    with caplog.at_level("WARNING"):
        X = F.solve(B)
    assert message in caplog.text
    np.testing.assert_array_equal(X, F._solve_columns(B))
    assert F._block() is None


def test_cholmod_errors_come_back_quietly(capfd: pytest.CaptureFixture[str]) -> None:
    """A CHOLMOD error (right-hand sides of the wrong length) is an ArithmeticError, and
    nothing is printed on the C stdout (its print level is set to 0 at start)."""
    solver, F = _fresh()
    L = solver.factor_pointer(F._F)
    with pytest.raises(ArithmeticError):
        solver.solve(L, np.ones((F.n + 1, 4)))
    out, err = capfd.readouterr()
    assert "CHOLMOD" not in out + err


def test_a_failing_metis_falls_back_to_amd(monkeypatch: pytest.MonkeyPatch,
                                           caplog: pytest.LogCaptureFixture) -> None:  # fmt: skip
    """METIS can fail on a graph ("Caught an unknown exception!" from pymetis, met on a 3D
    Hex8 column of 16 × 16 cells with Westergaard's added mass): the factor is then ordered
    by CHOLMOD's AMD, with a warning, and solves as the METIS-ordered one does (to 1e-13 of
    the answer; measured 0: both orderings give the same bits on this 2D grid)."""
    pymetis = pytest.importorskip("pymetis")
    A = _stiffness(30)
    b = np.random.default_rng(5).standard_normal(A.shape[0])
    ref = factorize(A, backend="cholmod")
    assert ref.ordering == "metis"  # type: ignore[attr-defined]

    def fails(*args: Any, **kw: Any) -> Any:
        raise RuntimeError("Caught an unknown exception!")

    monkeypatch.setattr(pymetis, "nested_dissection", fails)
    F = factorize(A, backend="cholmod")
    assert F.ordering == "amd"  # type: ignore[attr-defined]
    assert "METIS could not order" in caplog.text
    x, x_ref = F.solve(b), ref.solve(b)
    assert np.abs(x - x_ref).max() < 1e-13 * np.abs(x_ref).max()
