"""Limit equilibrium of a single rigid block's translations (block theory; Hoek and Bray's
plane and wedge sliding), for the floating blocks that rest on supported ones.

A rigid block b with the resultant R of its loads (N) touches its supports through pairs
grouped into planes, each with the unit normal n_i pointing into the block (the direction
of the force the support puts on it), the cohesive force C_i = Σ c_k A_k and the friction
coefficient μ_i (area-weighted). A translation v (unit) is admissible when it opens or
slides every plane (n_i · v ≥ 0); the planes it slides on (n_i · v = 0) carry normal
forces N_i ≥ 0 that balance R across v, friction opposes v, and a plane parallel to v
that carries no normal force (a release joint, a slot's walls) is sheared: its cohesion
resists:

    sliding on plane i:        v = R_t / |R_t|,  R_t = R − (R · n_i) n_i,  N_i = −R · n_i,
    along planes i and j (3D): v = ±(n_i × n_j) / |n_i × n_j| with R · v > 0,
                               N_i n_i + N_j n_j = −(R − (R · v) v),
    along no loaded plane:     v = R / |R| (lifting off, or sliding past parallel planes),

    F = (Σ_loaded (C_i + μ_i N_i) + Σ_sheared C_j) / (R · v),

and the block's factor is the least F over its admissible translations (a plane that
holds tension, an intact joint with a tensile strength, is not opened). No planes carry
force but those the block slides on: a plane parallel to the sliding (a wedge's release
plane, a block's side) carries none, where the elastic static analyses can pinch the block
between two planes and lean on friction that the rigid block's sliding does not mobilise
(a rock tester's block on a 30° plane beside a vertical joint: elastic factor 1.285 and
k_y 0.135, this check 1.2128 = tan 35° / tan 30° and k_y 0.0875 = tan 5°, and the dynamic
runs slide at the rigid block's rate). Rotations (toppling) and several blocks moving
together are not these mechanisms: the check bounds the factor from above where they
govern. Only blocks with no support of their own (rollers forbid translations) whose
every pair touches a supported body are checked.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import scipy.sparse as sp

from ..typing import FloatArray, IntArray
from ._static import pair_strengths

if TYPE_CHECKING:
    from ..interface import PairState
    from ._static import StaticInterfaceProblem

#: unit normals closer than this (1 − cos) are one plane
PLANE_TOL = 1e-6
#: a translation opens a plane when n · v exceeds this, slides on it when |n · v| is below
SLIDE_TOL = 1e-9
#: blocks with more planes than this are not checked (a curved joint: an arch's voussoir)
PLANES_MAX = 12


class Translation(NamedTuple):
    """The least translational factor of one floating block (:func:`translations`)."""

    body: int
    factor: float  # F (∞ where no translation is admissible; 0 where the block lifts off)
    direction: FloatArray  # (d,) the sliding direction v
    planes: tuple[str, ...]  # the interfaces of the planes it slides on


class _Block(NamedTuple):
    body: int
    normal: FloatArray  # (planes, d) into the block
    cohesion: FloatArray  # (planes,) C_i, N
    mu: FloatArray  # (planes,)
    tensile: FloatArray  # (planes,) Σ σ_t A (N): a plane that holds tension cannot open
    names: tuple[tuple[str, ...], ...]  # the interfaces of each plane
    dofs: IntArray  # the block's free DOFs (indices into the free DOFs)
    comp: IntArray  # their components

    def resultant(self, f_free: FloatArray) -> FloatArray:
        """R (d,): the sum of the free-DOF loads ``f_free`` on the block, N."""
        d = self.normal.shape[1]
        return np.asarray(np.bincount(self.comp, weights=f_free[self.dofs], minlength=d),
                          dtype=float)  # fmt: skip


def _blocks(problem: StaticInterfaceProblem, damage: PairState | None,
            factor: float) -> list[_Block]:  # fmt: skip
    """The floating blocks with no support that only supported bodies touch, their planes
    and strengths (divided by ``factor``)."""
    model, d = problem.model, problem.model.dim
    P = model.pairs
    assert P is not None
    free = problem.system.free
    body_dof = model.body_of_node[free // d]
    comp = free % d
    # the bodies with every rigid mode free (no support at all): a partly supported one
    # (rollers on a symmetry plane) has translations its supports forbid
    modes = (
        np.bincount(problem.mode_body, minlength=model.n_bodies)
        if problem.mode_body.size
        else np.zeros(model.n_bodies, dtype=np.int64)
    )
    floating = set(int(b) for b in np.unique(problem.mode_body))
    whole = {b for b in floating if modes[b] == (3 if d == 2 else 6)}
    c, mu, t = pair_strengths(problem.laws, damage)
    c, mu = c / factor, mu / factor
    ba, bb = model.body_of_node[P.node_a], model.body_of_node[P.node_b]
    G = problem.op.G
    out = []
    for b in sorted(whole):
        dofs = np.flatnonzero(body_dof == b)
        # s_k = S_k v for a translation v of b: G's columns of the body summed by component
        T = sp.csr_matrix((np.ones(dofs.size), (dofs, comp[dofs])), shape=(free.size, d))
        S = np.asarray((G @ T).toarray()).reshape(-1, d, d)
        touch = np.flatnonzero(np.abs(S).sum(axis=(1, 2)) > 0)
        if not touch.size:
            continue
        other = np.where(ba[touch] == b, bb[touch], ba[touch])
        if any(int(o) in floating for o in other):
            continue  # (a block on another floating block: not a single block's check)
        nrm = S[touch, -1, :]  # into the block: the opening per unit translation
        groups: list[list[int]] = []
        heads: list[FloatArray] = []
        for k, n in zip(touch, nrm, strict=True):
            for g, h in zip(groups, heads, strict=True):
                if 1.0 - float(h @ n) < PLANE_TOL:
                    g.append(int(k))
                    break
            else:
                groups.append([int(k)])
                heads.append(n / np.linalg.norm(n))
            if len(groups) > PLANES_MAX:
                break
        if len(groups) > PLANES_MAX:
            continue
        idx = [np.asarray(g) for g in groups]
        area = [P.area[g] for g in idx]
        normal = np.array([(S[g, -1, :] * a[:, None]).sum(axis=0) / a.sum()
                           for g, a in zip(idx, area, strict=True)])  # fmt: skip
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        out.append(_Block(
            b, normal, np.array([float(c[g].sum()) for g in idx]),
            np.array([float((mu[g] * a).sum() / a.sum()) for g, a in zip(idx, area, strict=True)]),
            np.array([float(t[g].sum()) for g in idx]),
            tuple(tuple(sorted({P.names[int(i)] for i in P.interface[g]})) for g in idx),
            dofs, comp[dofs]))  # fmt: skip
    return out


def _least(block: _Block, R: FloatArray) -> Translation:
    """The least factor over the block's admissible translations under the resultant R."""
    n, C, mu = block.normal, block.cohesion, block.mu
    d = R.size
    size = float(np.linalg.norm(R))
    best = Translation(block.body, float("inf"), np.zeros(d), ())
    if size == 0.0:
        return best
    tol = SLIDE_TOL

    def sheared(v: FloatArray, on: list[int]) -> FloatArray | None:
        """The other planes that v shears (parallel to it: their cohesion resists, with no
        normal force), or None where v presses into one or opens one holding tension."""
        others = np.setdiff1d(np.arange(len(n)), on)
        g = n[others] @ v
        if (g < -tol).any() or (block.tensile[others[g > tol]] > 0).any():
            return None
        return others[np.abs(g) <= tol]

    # every plane opened or sheared, none loaded (lifting off, or sliding past parallel ones)
    cands: list[tuple[FloatArray, list[int], FloatArray]] = [(R / size, [], np.zeros(0))]
    for i in range(len(n)):
        Rt = R - (R @ n[i]) * n[i]
        if np.linalg.norm(Rt) <= 1e-12 * size or R @ n[i] >= 0:
            continue
        cands.append((Rt / np.linalg.norm(Rt), [i], np.array([-(R @ n[i])])))
    if d == 3:
        for i in range(len(n)):
            for j in range(i + 1, len(n)):
                a = np.cross(n[i], n[j])
                if np.linalg.norm(a) < 1e-6:
                    continue
                a /= np.linalg.norm(a)
                v = a if R @ a > 0 else -a
                Rp = R - (R @ v) * v
                nf, *_ = np.linalg.lstsq(np.column_stack([n[i], n[j]]), -Rp, rcond=None)
                if (nf < -1e-12 * size).any():
                    continue
                cands.append((v, [i, j], np.maximum(nf, 0.0)))
    for v, on, nf in cands:
        drive = float(R @ v)
        side = sheared(v, on)
        if drive <= 0 or side is None:
            continue
        fs = float((C[on] + mu[on] * nf).sum() + C[side].sum()) / drive
        if fs < best.factor:
            loaded = [i for i, ni in zip(on, nf, strict=True) if ni > 1e-9 * size]
            loaded += [int(j) for j in side if C[j] > 0]
            planes = tuple(sorted({name for i in loaded for name in block.names[i]}))
            best = Translation(block.body, fs, v, planes)
    return best


def translations(
    problem: StaticInterfaceProblem, f_free: FloatArray, damage: PairState | None = None,
    factor: float = 1.0,
) -> list[Translation]:  # fmt: skip
    """Per checked block (see the module docstring), its least translational factor under
    the free-DOF loads ``f_free`` with every strength divided by ``factor``."""
    return [_least(bk, bk.resultant(f_free)) for bk in _blocks(problem, damage, factor)]


def translation_limit(
    problem: StaticInterfaceProblem, f0: FloatArray, f1: FloatArray, k_max: float,
    tol: float = 1e-6,
) -> tuple[float, Translation] | None:  # fmt: skip
    """The least k in [0, ``k_max``] at which some checked block's translational factor
    under f0 + k f1 falls to 1 (bisection to a relative ``tol``), with that block's
    translation there; None where none falls within the range or no block is checked."""
    blocks = _blocks(problem, None, 1.0)
    if not blocks:
        return None
    R0 = [bk.resultant(f0) for bk in blocks]
    R1 = [bk.resultant(f1) for bk in blocks]

    def least(k: float) -> Translation:
        return min((_least(bk, a + k * b) for bk, a, b in zip(blocks, R0, R1, strict=True)),
                   key=lambda t: t.factor)  # fmt: skip

    if least(0.0).factor <= 1.0:
        return 0.0, least(0.0)
    if least(k_max).factor > 1.0:
        return None
    lo, hi = 0.0, k_max
    while hi - lo > tol * max(hi, 1e-9):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if least(mid).factor > 1.0 else (lo, mid)
    return lo, least(hi)


__all__ = ["Translation", "translation_limit", "translations"]
