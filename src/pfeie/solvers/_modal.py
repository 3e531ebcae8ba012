"""Modal analysis: lowest eigenpairs of K φ = ω² M φ by shift-invert Lanczos."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from ..element._reference import FloatArray
from ..errors import SolverError
from ..model import Model
from ._linear import factorize


@dataclass(frozen=True)
class ModalResult:
    """Natural frequencies (Hz), mass-normalised mode shapes (n_modes, n_points, dim),
    and effective modal masses (n_modes, dim) in kg for unit ground motion along each
    axis (Σ over all modes = the free mass)."""

    frequencies: FloatArray
    shapes: FloatArray
    effective_mass: FloatArray

    @property
    def periods(self) -> FloatArray:
        return 1.0 / self.frequencies


def modal(
    model: Model,
    n_modes: int = 6,
    *,
    shift: float | None = None,
    lumped_mass: bool = False,
    backend: str = "auto",
) -> ModalResult:
    """The ``n_modes`` lowest modes of the supported model.

    Shift-invert about σ (default: slightly below zero, so that K − σM stays positive
    definite and Cholesky applies); the factorisation of K − σM is the project's own.

    >>> import pfeie as pf
    >>> m = pf.Model(pf.rectangle(1.0, 0.1, 20, 2, cell="quad8"),
    ...              [pf.Block("all", pf.Elastic(1e9, 0.0, 1000.0))], plane="stress")
    >>> m.fix("xmin")
    >>> f = pf.modal(m, 1).frequencies[0]
    >>> bool(abs(f / (1.875104**2 / (2*3.14159265) * (1e9 * 0.1**2 / 12 / 1000)**0.5) - 1) < 0.01)
    True
    """
    system = model.system(lumped_mass=lumped_mass)
    K, M = system.K, system.M
    n = K.shape[0]
    if n_modes >= n:
        raise SolverError(f"asked for {n_modes} modes of a model with {n} free DOFs")
    if shift is None:
        scale = float(abs(K.diagonal()).max() / max(abs(M.diagonal()).max(), 1e-300))
        shift = -1e-6 * scale
    spd = shift <= 0
    F = factorize((K - shift * M).tocsc(), spd=spd, backend=backend if spd else "superlu")
    op = spla.LinearOperator((n, n), matvec=F.solve, dtype=float)
    rng = np.random.default_rng(0)
    w2, vec = spla.eigsh(K, k=n_modes, M=M, sigma=shift, OPinv=op, which="LM",
                         v0=rng.standard_normal(n))  # fmt: skip
    order = np.argsort(w2)
    w2, vec = w2[order], vec[:, order]
    norms = np.sqrt(np.einsum("ik,ik->k", vec, M @ vec))
    vec = vec / norms
    freqs = np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)
    d = model.dim
    shapes = np.stack([system.expand(vec[:, k], prescribed=False) for k in range(n_modes)])
    influence = np.zeros((system.n_dof, d))
    for i in range(d):
        influence[i::d, i] = 1.0
    iota = influence[system.free]
    gamma = vec.T @ (M @ iota)  # participation factors (n_modes, d), φ mass-normalised
    return ModalResult(freqs, shapes.reshape(n_modes, -1, d), gamma**2)
