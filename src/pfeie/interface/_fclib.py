"""Frictional-contact problems in the FCLIB form (Siconos' test data), and their measure.

An FCLIB problem is a Delassus operator W, a free local velocity q and a friction
coefficient μ per contact: find r, u with u = W r + q and, per contact c,

    r_c ∈ K_c = {|r_T| ≤ μ_c r_N},   û_c = u_c + μ_c |u_T,c| e_N ∈ K_c*,   r_c · û_c = 0,

u positive when the contact opens and r positive in compression: pfeie's signs for
Δw = W X + Δw_free. FCLIB orders each contact's components normal first, pfeie normal
last (:func:`load_fclib` permutes). An answer is judged by Siconos' natural-map residual
with ρ = 1, made relative (:func:`natural_map_residual`):

    err = |r − P_K(r − û)| / max(|q|, |r|, |u|),

P_K the projection on the product of the cones; 1e-8 counts as solved.

>>> import numpy as np
>>> W, q, mu = np.eye(2), np.array([0.0, -1.0]), np.array([0.5])  # one 2D contact
>>> natural_map_residual(W, q, np.array([0.0, 1.0]), mu, 2)       # pressed shut: exact
0.0
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..typing import FloatArray
from ._laws import Joint, PairLaws


def load_fclib(path: str | Path) -> tuple[FloatArray, FloatArray, FloatArray, int]:
    """(W, q, μ, d) of an FCLIB archive (keys ``W``, ``q``, ``mu``, ``dim``), permuted to
    pfeie's order (tangential components first, normal last)."""
    pb = np.load(path)
    W, q, mu, d = pb["W"], pb["q"], pb["mu"], int(pb["dim"])
    perm = (np.arange(mu.size)[:, None] * d + np.r_[np.arange(1, d), 0][None, :]).ravel()
    return W[np.ix_(perm, perm)], q[perm], np.asarray(mu, dtype=float), d


def coulomb_laws(mu: FloatArray, d: int) -> PairLaws:
    """The laws of FCLIB contacts: existing joints (no cohesion, no tension) of unit area
    with Coulomb friction μ per contact."""
    values, interface = np.unique(mu, return_inverse=True)
    laws = [Joint(phi=float(np.degrees(np.arctan(m)))) for m in values]
    return PairLaws.from_interfaces(np.ones(mu.size), interface.astype(np.int64), laws, d)


def natural_map_residual(
    W: FloatArray, q: FloatArray, r: FloatArray, mu: FloatArray, d: int
) -> float:
    """Siconos' relative natural-map residual (ρ = 1) of the forces ``r`` (normal last;
    see the module docstring)."""
    u = W @ r + q
    R, U = r.reshape(-1, d), u.reshape(-1, d)
    Uh = U.copy()
    Uh[:, -1] += mu * np.linalg.norm(U[:, :-1], axis=1)
    z = R - Uh
    zn, zt = z[:, -1], z[:, :-1]
    nt = np.linalg.norm(zt, axis=1)
    P = np.zeros_like(z)  # the projection on the cone |r_T| ≤ μ r_N
    inside = nt <= mu * zn
    P[inside] = z[inside]
    mid = ~inside & (mu * nt > -zn)
    a = (mu[mid] * nt[mid] + zn[mid]) / (1 + mu[mid] ** 2)
    P[mid, -1] = a
    P[mid, :-1] = (mu[mid] * a / np.maximum(nt[mid], 1e-300))[:, None] * zt[mid]
    scale = max(float(np.linalg.norm(q)), float(np.linalg.norm(r)), float(np.linalg.norm(u)),
                1e-300)  # fmt: skip
    return float(np.linalg.norm(R - P)) / scale


__all__ = ["coulomb_laws", "load_fclib", "natural_map_residual"]
