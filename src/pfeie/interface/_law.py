"""Pair properties and pair states (the joint law of method.md §4), with trial/commit.

Arrays are indexed by pair first; local vectors have the frame's component order
(t₁, [t₂,] n), normal last. Symbols:

- X (m, d): force on side b in the local frame (N), normal positive in compression;
- w (m, d): relative displacement T (u_b − u_a) (m), normal positive when opening;
- s (m, d): w + C X + g₀ n, the part of w not taken by the joint springs (C = 1/(k A),
  zero for a rigid contact) plus the initial gap g₀: its normal part is the gap, its
  tangential part the slip;
- state: INTACT (bonded), STICK, SLIDE or OPEN; ``broken`` is irreversible.

Strength of a pair: τ_max = c A + μ X_n with (c, μ) = (c, tan φ) while intact and
(c_r, tan φ_r) once broken; tension limit σ_t A (intact) or σ_t,r A (broken).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..element._reference import FloatArray
from ._split import PairGeometry

if TYPE_CHECKING:
    from ..model._physics import Joint

INTACT, STICK, SLIDE, OPEN = 0, 1, 2, 3
STATE_NAMES = ("intact", "stick", "slide", "open")


@dataclass(frozen=True)
class PairProperties:
    """Per-pair strength (from the joints of the interfaces) and compliance."""

    area: FloatArray  # (m,) m² (× thickness in 2D)
    c: FloatArray  # (m,) Pa
    mu: FloatArray
    tensile: FloatArray  # Pa
    c_r: FloatArray
    mu_r: FloatArray
    tensile_r: FloatArray
    initially_broken: np.ndarray  # (m,) bool
    compliance: FloatArray  # (m, d) m/N: 1/(k A), 0 for rigid contact
    gap: FloatArray  # (m,) m, initial normal gap

    @classmethod
    def from_joints(cls, pairs: PairGeometry, joints: Sequence[Joint]) -> PairProperties:
        j = pairs.interface
        A = pairs.area

        def col(fn: Callable[[Joint], float]) -> FloatArray:
            return np.array([float(fn(jt)) for jt in joints])[j]

        d = pairs.dim
        comp = np.zeros((pairs.n, d))
        kn = col(lambda jt: 0.0 if jt.kn is None else 1.0 / jt.kn)
        ks = col(lambda jt: 0.0 if jt.ks is None else 1.0 / jt.ks)
        comp[:, -1] = kn / A
        comp[:, :-1] = (ks / A)[:, None]
        return cls(A, col(lambda jt: jt.c), col(lambda jt: jt.mu), col(lambda jt: jt.tensile),
                   col(lambda jt: jt.c_r), col(lambda jt: jt.mu_r), col(lambda jt: jt.tensile_r),
                   col(lambda jt: jt.initial == "broken").astype(bool), comp,
                   col(lambda jt: jt.gap))  # fmt: skip

    @property
    def n(self) -> int:
        return int(self.area.size)

    def strength(self, broken: np.ndarray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(c A, μ, σ_t A) of each pair for its broken flag (N, -, N)."""
        c = np.where(broken, self.c_r, self.c) * self.area
        mu = np.where(broken, self.mu_r, self.mu)
        t = np.where(broken, self.tensile_r, self.tensile) * self.area
        return c, mu, t


@dataclass
class PairState:
    """Committed or trial state of all pairs (see the module docstring)."""

    state: np.ndarray  # (m,) int8 codes
    broken: np.ndarray  # (m,) bool
    X: FloatArray  # (m, d)
    w: FloatArray  # (m, d)
    s: FloatArray  # (m, d)
    slip_dir: FloatArray  # (m, d - 1) unit slip direction of sliding pairs

    @classmethod
    def initial(cls, props: PairProperties, dim: int) -> PairState:
        m = props.n
        broken = props.initially_broken.copy()
        state = np.where(broken, STICK, INTACT).astype(np.int8)
        state[props.gap > 0] = OPEN
        z = np.zeros((m, dim))
        s = z.copy()
        s[:, -1] = props.gap
        return cls(state, broken, z, z.copy(), s, np.zeros((m, dim - 1)))

    def copy(self) -> PairState:
        return replace(self, state=self.state.copy(), broken=self.broken.copy(), X=self.X.copy(),
                       w=self.w.copy(), s=self.s.copy(), slip_dir=self.slip_dir.copy())  # fmt: skip

    def counts(self) -> dict[str, int]:
        """Number of pairs in each state, and broken."""
        out = {name: int((self.state == k).sum()) for k, name in enumerate(STATE_NAMES)}
        out["broken"] = int(self.broken.sum())
        return out
