"""Static analysis: K u = f on the free DOFs, with interfaces and floating blocks.

Without interfaces this is the linear solve K u = f. With interfaces it is the static
interface problem of method.md §5.2 with the rigid unknowns of the floating blocks
(:class:`pfeie.coupling.StaticInterfaceProblem`); the support reactions follow.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..coupling import StaticInterfaceProblem, relative_operator
from ..errors import MechanismError
from ..interface import PairState, SolverSettings
from ..linalg import factorize
from ..model import Model
from ..typing import FloatArray


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


def solve_static(
    model: Model, *, t: float = 0.0, backend: str = "auto", settings: SolverSettings | None = None
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
        try:
            F = factorize(system.K, spd=True, backend=backend)
        except MechanismError as exc:
            free = model.unrestrained_modes()
            if not free:
                raise
            raise MechanismError(f"{exc}: {free}") from None
        u_free = F.solve(f_free)
        u = system.expand(u_free)
        r = model.stiffness() @ u - model.load_vector(t)
        reactions = np.zeros_like(r)
        reactions[system.prescribed] = r[system.prescribed]
        return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d))
    problem = StaticInterfaceProblem(model, system, backend=backend, settings=settings)
    u_free, st = problem.solve(f_free)
    G = relative_operator(model.pairs, model.n_dof)
    pres = system.prescribed
    u = system.expand(u_free)
    st.w = (G @ u).reshape(-1, d)
    r = model.stiffness() @ u - model.load_vector(t) - G.T @ st.X.ravel()
    reactions = np.zeros_like(r)
    reactions[pres] = r[pres]
    return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d), st)
