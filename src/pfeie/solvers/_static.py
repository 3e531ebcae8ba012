"""Static analysis: K u = f on the free DOFs, with interfaces and floating blocks.

Without interfaces this is the linear solve K u = f. With interfaces it is the static
interface problem of method.md §5.2: the rigid modes Φ of every body that its supports
do not restrain are removed by temporary pins (a pivoted QR picks well-separated pin
DOFs), the pinned flexibility W_pin = G K_pin⁻¹ Gᵀ is formed, and the rigid amplitudes q
join the pair forces X in the bordered system

    [ W_pin  E ] [X]   [ −w_free,pin ]        E = G Φ,
    [ Eᵀ     0 ] [q] = [ −Φᵀ f       ]

solved with the pair law (state iteration). Then u = u_pin + K_pin⁻¹ Gᵀ X + Φ q. A balanced
load on a pinned body leaves zero pin reactions, so u is exact. When the pairs cannot
hold a body (it would slide or fall), :class:`MechanismError` says so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..element._reference import FloatArray, IntArray
from ..errors import MechanismError
from ..interface import InterfaceSolver, PairState
from ..model import Model
from ._linear import factorize


@dataclass(frozen=True)
class StaticResult:
    """Displacements (n_points, dim) in m and support reactions (n_points, dim) in N; with
    interfaces, the pair state (forces, states) and the rigid motion of each body."""

    model: Model
    u: FloatArray
    reactions: FloatArray
    pairs: PairState | None = None

    def stress(self) -> FloatArray:
        """Nodal stresses (n_points, 3, 3), Pa."""
        return self.model.nodal_stress(self.u)

    def rigid_motion(self) -> FloatArray:
        """Rigid motion of every body (n_bodies, 3 or 6): centroid translation, rotation."""
        return self.model.rigid_motion(self.u)


def floating_modes(model: Model, prescribed: IntArray) -> FloatArray:
    """The rigid modes (n_dof, k) of the bodies that the supports leave free."""
    Phi = model.rigid_modes()
    r = 3 if model.dim == 2 else 6
    Pp = Phi[prescribed].toarray() if prescribed.size else np.zeros((0, Phi.shape[1]))
    cols = []
    for b in range(model.n_bodies):
        sl = slice(b * r, (b + 1) * r)
        N = sla.null_space(Pp[:, sl]) if Pp.shape[0] else np.eye(r)
        if N.shape[1]:
            cols.append(Phi[:, sl] @ N)
    return np.hstack(cols) if cols else np.zeros((model.n_dof, 0))


def _pins(F: FloatArray) -> IntArray:
    """Rows of F (n, k) whose k × k block is best conditioned (pivoted QR of Fᵀ)."""
    if F.shape[1] == 0:
        return np.zeros(0, dtype=np.int64)
    _, _, piv = sla.qr(F.T, mode="economic", pivoting=True)
    return np.sort(piv[: F.shape[1]])


def solve_static(
    model: Model, *, t: float = 0.0, backend: str = "auto", tol: float = 1e-8
) -> StaticResult:
    """Solve the static problem under the loads at time ``t``.

    The reactions are r = K u − f − Gᵀ X on the prescribed DOFs (zero elsewhere); their
    sum balances the applied loads.

    >>> import pfeie as pf
    >>> m = pf.Model(pf.rectangle(2.0, 1.0, 4, 2), [pf.Block("all", pf.Elastic(1e6, 0.0))])
    >>> m.fix("xmin", 0); m.fix("ymin", 1); m.add_traction("xmax", [1e3, 0.0])
    >>> r = pf.solve_static(m)
    >>> round(float(r.u[:, 0].max()), 9)  # = σ L / E
    0.002
    """
    system = model.system()
    f_free = system.load(t)
    d = model.dim
    if model.pairs is None:
        u_free = factorize(system.K, spd=True, backend=backend).solve(f_free)
        u = system.expand(u_free)
        r = model.stiffness() @ u - model.load_vector(t)
        reactions = np.zeros_like(r)
        reactions[system.prescribed] = r[system.prescribed]
        return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d))
    free, pres = system.free, system.prescribed
    Phi = floating_modes(model, pres)[free]
    k = Phi.shape[1]
    pins = _pins(Phi) if k else np.zeros(0, dtype=np.int64)
    keep = np.setdiff1d(np.arange(free.size), pins)
    Kp = system.K[keep][:, keep]
    try:
        factor = factorize(Kp, spd=True, backend=backend)
    except MechanismError as exc:
        raise MechanismError(f"static analysis: {exc}") from None
    G = model.relative_operator()
    Gf = G[:, free].tocsr()
    w_pres = G[:, pres] @ system.prescribed_values if pres.size else np.zeros(G.shape[0])
    Gk = Gf[:, keep]
    Z = factor.solve(Gk.T.toarray())
    W = Gk @ Z
    W = 0.5 * (W + W.T)
    u_pin = np.zeros(free.size)
    u_pin[keep] = factor.solve(f_free[keep])
    w_free = (Gf @ u_pin + w_pres).reshape(-1, d)
    props = model.pair_properties
    E = Gf @ Phi if k else None
    e = -(Phi.T @ f_free) if k else None
    pairs = model.pairs
    solver = InterfaceSolver(W, props, border=E, tol=tol, regularize=pairs.regularization)
    st, q = solver.solve(w_free, PairState.initial(props, d), e, label="static analysis")
    u_free = u_pin
    u_free[keep] += Z @ st.X.ravel()
    if k:
        u_free = u_free + Phi @ q
    u = system.expand(u_free)
    st.w = (G @ u).reshape(-1, d)
    r = model.stiffness() @ u - model.load_vector(t) - G.T @ st.X.ravel()
    reactions = np.zeros_like(r)
    reactions[pres] = r[pres]
    return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d), st)
