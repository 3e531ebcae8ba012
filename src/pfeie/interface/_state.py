"""Pair states with explicit trial and commit (the kinematic side of method.md §4).

Arrays are indexed by pair first; local vectors have the frame's component order
(t₁, [t₂,] n), normal last. Symbols:

- X (m, d): force on side b in the local frame (N), normal positive in compression;
- w (m, d): relative displacement T (u_b − u_a) (m), normal positive when opening;
- s (m, d): w + C X + g₀ n, the part of w not taken by the joint springs (C = 1/(k A),
  zero for a rigid contact) plus the initial gap g₀: its normal part is the gap, its
  tangential part the slip;
- state: INTACT (bonded), STICK, SLIDE or OPEN; ``broken`` is irreversible;
- path (m,): the length of the slip path so far, Σ |Δs_t| over committed steps (m), the
  internal variable of slip-dependent joint laws.

Trial and commit: the interface solver returns a *trial* state for a step and never
edits the committed one it starts from; the analysis commits the trial when the step is
accepted (:meth:`PairState.committed`, which also advances the internal variables).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..typing import BoolArray, FloatArray

INTACT, STICK, SLIDE, OPEN = 0, 1, 2, 3
STATE_NAMES = ("intact", "stick", "slide", "open")


@dataclass
class PairState:
    """Committed or trial state of all pairs (see the module docstring)."""

    state: np.ndarray  # (m,) int8 codes
    broken: BoolArray  # (m,)
    X: FloatArray  # (m, d)
    w: FloatArray  # (m, d)
    s: FloatArray  # (m, d)
    slip_dir: FloatArray  # (m, d - 1) unit slip direction of sliding pairs
    path: FloatArray  # (m,) slip path length (m)

    @classmethod
    def initial(cls, broken: BoolArray, gap: FloatArray, dim: int) -> PairState:
        """The state before any load: intact or broken (closed), open where a gap is."""
        m = broken.size
        state = np.where(broken, STICK, INTACT).astype(np.int8)
        state[gap > 0] = OPEN
        z = np.zeros((m, dim))
        s = z.copy()
        s[:, -1] = gap
        return cls(state, broken.copy(), z, z.copy(), s, np.zeros((m, dim - 1)), np.zeros(m))

    @classmethod
    def empty(cls, dim: int) -> PairState:
        """The state of a model without pairs."""
        return cls.initial(np.zeros(0, dtype=bool), np.zeros(0), dim)

    @property
    def n(self) -> int:
        return int(self.state.size)

    def copy(self) -> PairState:
        return type(self)(self.state.copy(), self.broken.copy(), self.X.copy(), self.w.copy(),
                          self.s.copy(), self.slip_dir.copy(), self.path.copy())  # fmt: skip

    def select(self, idx: np.ndarray) -> PairState:
        """The state of the pairs ``idx`` only (copies)."""
        return PairState(self.state[idx], self.broken[idx], self.X[idx], self.w[idx],
                         self.s[idx], self.slip_dir[idx], self.path[idx])  # fmt: skip

    def committed(self, prev: PairState) -> PairState:
        """This trial state as the committed state of the step from ``prev``: the slip
        path of the pairs in contact at the end of the step (stick or slide) grows by
        their slip increment |s_t − s_t,prev|."""
        if not self.n:
            return replace(self)
        touch = (self.state == STICK) | (self.state == SLIDE)
        inc = np.sqrt(np.einsum("kj,kj->k", self.s[:, :-1] - prev.s[:, :-1],
                                self.s[:, :-1] - prev.s[:, :-1]))  # fmt: skip
        # a trial is not used after its commit: the committed state shares its arrays
        return replace(self, path=prev.path + np.where(touch, inc, 0.0))

    def counts(self) -> dict[str, int]:
        """Number of pairs in each state, and broken."""
        out = {name: int((self.state == k).sum()) for k, name in enumerate(STATE_NAMES)}
        out["broken"] = int(self.broken.sum())
        return out


__all__ = ["INTACT", "OPEN", "SLIDE", "STATE_NAMES", "STICK", "PairState"]
