"""Modal analysis: lowest eigenpairs of K φ = ω² M φ by shift-invert Lanczos.

Interfaces. A model cut by interfaces is analysed with its joints ``"bonded"`` (default):
the vibration of the structure about a state in which every joint is closed and holds,
e.g. a dam before the earthquake. Rigid pairs (no joint stiffness) tie their two nodes,
u_b = u_a: the DOFs are merged, K_r = Pᵀ K P and M_r = Pᵀ M P with P the (0/1) map from
the merged to the split DOFs, so an intact interface gives the frequencies of the uncut
mesh exactly (V9). Pairs of a joint with stiffnesses k_n, k_s add the springs
Gᵀ diag(k A) G instead. ``interfaces="free"`` ignores the pairs (blocks vibrate apart;
floating blocks then have zero frequencies).

Reservoirs. M includes the added mass of the model's reservoirs (Westergaard's, or a
finite-element reservoir's M_a: :meth:`pfeie.Model.add_westergaard`), the "wet" modes;
``added_mass=False`` leaves it out, the "dry" modes of the structure alone (the same
as the model without its reservoirs; its stiffness and supports unchanged). The added
mass lowers the frequencies: ω² = φᵀKφ / φᵀ(M + M_a)φ at the wet mode.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..coupling import relative_operator
from ..errors import SolverError
from ..linalg import factorize
from ..model import Model
from ..typing import BoolArray, FloatArray, is_number

#: ω² of a rigid-body mode, relative to the reference of :attr:`ModalResult.rigid`: the
#: zero eigenvalue of a floating block comes out of the solve as round-off, of order
#: 1e-16 of the largest eigenvalue of the mesh (measured 4e-17); an elastic mode would
#: need a frequency below 3e-7 of the mesh's highest to fall under it (at 1e-10, a
#: cantilever 50 m × 0.5 m of 2 × 800 cells had its first bending mode, 0.118 Hz, under it)
RIGID_OMEGA2 = 1e-13


@dataclass(frozen=True)
class ModalResult:
    """Natural frequencies (Hz), mass-normalised mode shapes (n_modes, n_points, dim),
    and effective modal masses (n_modes, dim) in kg for unit ground motion along each
    axis (Σ over all modes = the free mass, ``total_mass`` (dim,) kg: the participation
    is φᵀ M_ff ι_f over the free DOFs, without the mass that couples them to the supports,
    a consistent mass's or Westergaard's blocks at a roller-supported wet node, which the
    time stepping's inertia load −(M_ff ι_f + M_fp ι_p) a_g keeps). ``omega2_scale``
    (rad²/s²) is max diag K / max diag M, the order of the mesh's largest eigenvalue ω²
    (0: unknown)."""

    frequencies: FloatArray
    shapes: FloatArray
    effective_mass: FloatArray
    total_mass: FloatArray = field(default_factory=lambda: np.zeros(0))  # (dim,) kg
    omega2_scale: float = 0.0  # rad²/s²
    #: the model's Rayleigh damping ratio of each mode (n_modes,), φᵀCφ/(2ω) for the
    #: mass-normalised φ: α/(2ω) + βω/2 where C = αM + βK acts in full; with
    #: ``deformation_only`` the share ρ of the mode's kinetic energy in the rigid motions
    #: that the supports leave free gets no α: (α(1 − ρ) + β φᵀKφ)/(2ω). NaN for rigid
    #: modes and without damping
    damping_ratios: FloatArray = field(default_factory=lambda: np.zeros(0))
    #: ρ per mode (n_modes,): the share of its kinetic energy in the rigid motions that
    #: the supports leave free, those of the floating bodies
    #: (:meth:`pfeie.Model.rigid_motion_projector`; 0 without any)
    rigid_share: FloatArray = field(default_factory=lambda: np.zeros(0))

    @property
    def rigid(self) -> BoolArray:
        """The rigid-body modes (a block free on its joints): ω² = (2πf)² below
        :data:`RIGID_OMEGA2` (1e-13) times the larger of ``omega2_scale`` and the
        largest ω² computed. The reference is not the computed modes alone: when every
        mode asked for is rigid (six of a free 3D block, three in 2D), the largest of
        them is round-off too. Their frequency is 0 to round-off, their period
        infinite."""
        w2 = (2 * np.pi * np.asarray(self.frequencies, dtype=float)) ** 2
        ref = max(float(w2.max(initial=0.0)), float(self.omega2_scale), 1e-300)
        return np.asarray(w2 < RIGID_OMEGA2 * ref)

    @property
    def periods(self) -> FloatArray:
        """Periods (s); ∞ for the rigid-body modes."""
        f = np.asarray(self.frequencies, dtype=float)
        return np.where(self.rigid, np.inf, 1.0 / np.where(self.rigid, 1.0, f))


def modal(
    model: Model,
    n_modes: int = 6,
    *,
    shift: float | None = None,
    lumped_mass: bool = False,
    backend: str = "auto",
    interfaces: str = "bonded",
    added_mass: bool = True,
) -> ModalResult:
    """The ``n_modes`` lowest modes of the supported model, with the reservoirs' added
    mass (``added_mass``, default) or without it (the dry structure).

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
    if not added_mass:  # the blocks' mass alone, on the same free DOFs
        M = model.mass(lumped=lumped_mass, added=False)[system.free][:, system.free].tocsr()
    M_split = M
    if not (isinstance(n_modes, (int, np.integer)) and n_modes >= 1):
        raise SolverError(f"n_modes: expected a whole number of modes >= 1, got {n_modes!r}")
    if interfaces not in ("bonded", "free"):
        raise SolverError(f"interfaces must be 'bonded' or 'free', got {interfaces!r}")
    P = None
    if interfaces == "bonded" and model.pairs is not None and model.pairs.n:
        P, K = _bond(model, system.free, K)
        K, M = (P.T @ K @ P).tocsc(), (P.T @ M @ P).tocsc()
    n = K.shape[0]
    if n_modes >= n:
        raise SolverError(f"asked for {n_modes} modes of a model with {n} free DOFs")
    if not np.any(M.diagonal() > 0):
        raise SolverError("modal: the model has no mass (rho = 0 in every block's material, "
                          "the default of pfeie.Elastic): it has no modes; give the materials "
                          "their density (kg/m³)")  # fmt: skip
    scale = float(abs(K.diagonal()).max() / max(abs(M.diagonal()).max(), 1e-300))
    if shift is None:
        shift = -1e-6 * scale
    elif not is_number(shift) or not np.isfinite(shift):
        raise SolverError(f"modal: shift: expected a finite ω² (rad²/s²) or None, got {shift!r}")
    spd = shift <= 0
    F = factorize((K - shift * M).tocsc(), spd=spd, backend=backend if spd else "superlu")
    op = spla.LinearOperator((n, n), matvec=F.solve, dtype=float)
    rng = np.random.default_rng(0)
    try:
        w2, vec = spla.eigsh(K, k=n_modes, M=M, sigma=shift, OPinv=op, which="LM",
                             v0=rng.standard_normal(n))  # fmt: skip
    except (spla.ArpackError, spla.ArpackNoConvergence) as exc:
        raise SolverError(f"modal: the eigensolver (ARPACK) failed for {n_modes} modes of "
                          f"{n} free DOFs ({exc}); blocks without mass (rho = 0) or "
                          "without supports make the problem singular") from None  # fmt: skip
    order = np.argsort(w2)
    w2, vec = w2[order], vec[:, order]
    norms = np.sqrt(np.einsum("ik,ik->k", vec, M @ vec))
    vec = vec / norms
    if P is not None:  # back to the split DOFs (M = Pᵀ M_split P keeps the normalisation)
        M = M_split
        vec = P @ vec
    freqs = np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)
    d = model.dim
    shapes = np.stack([system.expand(vec[:, k], prescribed=False) for k in range(n_modes)])
    influence = np.zeros((system.n_dof, d))
    for i in range(d):
        influence[i::d, i] = 1.0
    iota = influence[system.free]
    gamma = vec.T @ (M @ iota)  # participation factors (n_modes, d), φ mass-normalised
    total = np.einsum("ik,ik->k", iota, M @ iota)  # the free mass along each axis
    proj = model.rigid_motion_projector(M, system.free)
    share = (np.zeros(n_modes) if proj is None
             else np.einsum("ik,ik->k", vec, proj @ vec))  # fmt: skip
    res = ModalResult(freqs, shapes.reshape(n_modes, -1, d), gamma**2, total, scale)
    zeta = np.full(n_modes, np.nan)
    rd = model.damping
    if rd is not None and (rd.alpha or rd.beta):
        m_part = np.einsum("ik,ik->k", vec, M @ vec)  # 1: φ mass-normalised
        if rd.deformation_only:
            m_part = m_part - share
        k_part = np.einsum("ik,ik->k", vec, system.K @ vec)  # the blocks' K: ω² if bonded
        w = 2 * np.pi * freqs
        live = ~res.rigid
        zeta[live] = (rd.alpha * m_part[live] + rd.beta * k_part[live]) / (2 * w[live])
    return replace(res, damping_ratios=zeta, rigid_share=share)


def _bond(model: Model, free: np.ndarray, K: sp.spmatrix) -> tuple[sp.csr_matrix, sp.spmatrix]:
    """(P, K with joint springs): P maps merged DOFs to the split free DOFs, tying the
    nodes of rigid pairs; pairs of joints with stiffness add their springs to K."""
    from scipy.sparse.csgraph import connected_components

    pairs, props = model.pairs, model.pair_laws
    assert pairs is not None
    d, n_dof = model.dim, model.n_dof
    comp = props.compliance
    rigid = np.all(comp == 0.0, axis=1)
    spring = np.all(comp > 0.0, axis=1)
    if not np.all(rigid | spring):
        raise SolverError("modal analysis with bonded interfaces needs joints either rigid or "
                          "with both stiffnesses k_n and k_s; give both, or none")  # fmt: skip
    if spring.any():
        G = relative_operator(pairs, n_dof)[:, free]
        k = np.where(np.repeat(spring, d), 1.0 / np.where(comp > 0, comp, 1.0).ravel(), 0.0)
        K = K + (G.T @ sp.diags(k) @ G)
    a = (pairs.node_a[rigid, None] * d + np.arange(d)).ravel()
    b = (pairs.node_b[rigid, None] * d + np.arange(d)).ravel()
    graph = sp.coo_matrix((np.ones(a.size), (a, b)), shape=(n_dof, n_dof))
    _, label = connected_components(graph, directed=False)
    fixed = np.ones(n_dof, dtype=bool)
    fixed[free] = False
    held = np.zeros(label.max() + 1, dtype=bool)
    held[label[fixed]] = True  # a class tied to a prescribed DOF is prescribed
    keep = ~held[label[free]]
    cls, col = np.unique(label[free][keep], return_inverse=True)
    rows = np.flatnonzero(keep)
    P = sp.csr_matrix((np.ones(rows.size), (rows, col.ravel())), shape=(free.size, cls.size))
    return P, K
