"""Contact stabilisation: the velocity projection at closed pairs (docs/theory.md).

With the contact-stabilised step, the relative velocity of the pair components that are
closed at t_{n+1} (intact and sticking pairs: all components; sliding pairs: the normal
one) is projected to zero in the mass metric,

    v ← v − M⁻¹ G_cᵀ λ,     H_c λ = G_c v + g_p,     H = G M⁻¹ Gᵀ,

which keeps momentum and removes the velocity flip of a just-closed pair (a perfectly
inelastic impact at the pair level, in the spirit of the contact-stabilised Newmark of
Deuflhard, Krause and Ertel 2008). It needs a lumped mass. g_p is the prescribed side's
relative velocity (absolute form). The factorisation of H_c is cached per pattern of
closed components.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..coupling import PairOperator
from ..errors import ModelError
from ..interface import INTACT, SLIDE, STICK, PairState
from ..typing import BoolArray, FloatArray


class VelocityProjection:
    """The projection of the module docstring for the operator ``op`` and the inverse
    lumped mass ``minv`` (0 on massless DOFs); ``junction``: redundant constraints (T and
    X junctions), regularised."""

    def __init__(self, op: PairOperator, minv: FloatArray, mass: FloatArray, junction: bool):
        touched = np.flatnonzero(np.abs(op.G).sum(axis=0).A1 > 0)
        if np.any(mass[touched] <= 0):
            raise ModelError(
                "the contact-stabilised scheme needs mass on both sides of every "
                "interface: give massless blocks a small density (e.g. 1 % of the "
                "structure's) to model a massless foundation"
            )
        self.minv, self.junction = minv, junction
        self.m, self.d = op.m, op.d
        self._cache: dict[bytes, tuple[Any, ...]] = {}
        self.update(op)

    def update(self, op: PairOperator) -> None:
        """New pair frames (large rotations): H is rebuilt and the cache emptied."""
        self.op = op
        self.H = op.mass_delassus(self.minv)
        # components with no free mass on either side (e.g. a wall against rollers)
        self.movable: BoolArray = self.H.diagonal() > 0
        self._cache.clear()

    def closed(self, ps: PairState) -> BoolArray:
        """The closed components (m·d,) of a pair state."""
        c = np.zeros((self.m, self.d), dtype=bool)
        full = (ps.state == INTACT) | (ps.state == STICK)
        c[full] = True
        c[ps.state == SLIDE, -1] = True
        return c.ravel()

    def __call__(
        self, x: FloatArray, ps: PairState, offset: FloatArray | None = None
    ) -> tuple[FloatArray, FloatArray]:
        """x projected so that G_c x + offset_c = 0 on the closed components, and the
        multipliers λ per component (M,)."""
        closed = self.closed(ps) & self.movable
        lam = np.zeros(self.m * self.d)
        if not closed.any():
            return x, lam
        key = closed.tobytes()
        hit = self._cache.get(key)
        if hit is None:
            c = np.flatnonzero(closed)
            Gc = self.op.G[c].tocsr()
            GcT = Gc.T.tocsr()
            Hc = self.H[c][:, c].tocsc()
            solve: Callable[[FloatArray], FloatArray]
            if self.junction:
                eps = 1e-12 * float(Hc.diagonal().mean())
                solve = spla.factorized((Hc + eps * sp.eye(c.size)).tocsc())
            elif Hc.nnz == c.size:
                hd = Hc.diagonal()
                hinv = np.divide(1.0, hd, out=np.zeros_like(hd), where=hd > 0)
                solve = lambda g: g * hinv  # noqa: E731
            else:
                solve = spla.factorized(Hc)
            if len(self._cache) > 256:
                self._cache.clear()
            hit = (c, Gc, GcT, solve)
            self._cache[key] = hit
        c, Gc, GcT, solve = hit
        g = Gc @ x
        if offset is not None:
            g = g + offset[c]
        lam_c = solve(g)
        lam[c] = lam_c
        return x - self.minv * (GcT @ lam_c), lam


__all__ = ["VelocityProjection"]
