"""Linear static analysis: K u = f on the free DOFs."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..element._reference import FloatArray
from ..model import Model
from ._linear import factorize


@dataclass(frozen=True)
class StaticResult:
    """Displacements (n_points, dim) in m and support reactions (n_points, dim) in N."""

    model: Model
    u: FloatArray
    reactions: FloatArray

    def stress(self) -> FloatArray:
        """Nodal stresses (n_points, 3, 3), Pa."""
        return self.model.nodal_stress(self.u)


def solve_static(model: Model, *, t: float = 0.0, backend: str = "auto") -> StaticResult:
    """Solve the linear static problem under the loads at time ``t``.

    The reactions are r = K u − f on the prescribed DOFs (zero elsewhere); their sum
    balances the applied loads.

    >>> import pfeie as pf
    >>> m = pf.Model(pf.rectangle(2.0, 1.0, 4, 2), [pf.Block("all", pf.Elastic(1e6, 0.0))])
    >>> m.fix("xmin", 0); m.fix("ymin", 1); m.add_traction("xmax", [1e3, 0.0])
    >>> r = pf.solve_static(m)
    >>> round(float(r.u[:, 0].max()), 9)  # = σ L / E
    0.002
    """
    system = model.system()
    f_free = system.load(t)
    u_free = factorize(system.K, spd=True, backend=backend).solve(f_free)
    u = system.expand(u_free)
    r = model.stiffness() @ u - model.load_vector(t)
    reactions = np.zeros_like(r)
    reactions[system.prescribed] = r[system.prescribed]
    d = model.dim
    return StaticResult(model, u.reshape(-1, d), reactions.reshape(-1, d))
