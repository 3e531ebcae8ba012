"""Quadrature rules on the reference elements.

Lines, quadrilaterals and hexahedra use tensor Gauss-Legendre rules with
n = ⌈(p + 1)/2⌉ points per direction, exact for polynomials of degree p in each
variable. Triangles and tetrahedra use the closed-form symmetric rules for degree ≤ 2
(centroid; 3 points at (1/6, 1/6); 4 points at a = (5 − √5)/20) and, above, collapsed
(Duffy) Gauss-Jacobi rules: x = s(1 − t)(1 − r), y = t(1 − r), z = r, with the Jacobian
factors absorbed into Gauss-Jacobi weights, exact to degree 2n − 1 (Stroud 1971;
Karniadakis & Sherwin 2005, §4.1).

Weights sum to the measure of the reference domain (2^d for the cube, 1/d! for the
simplex).
"""

from __future__ import annotations

from functools import cache
from itertools import product

import numpy as np
from scipy.special import roots_jacobi, roots_legendre

from ..typing import FloatArray
from ._reference import reference


@cache
def quadrature(cell_type: str, degree: int) -> tuple[FloatArray, FloatArray]:
    """Points (q, dim) and weights (q,) integrating degree ``degree`` exactly."""
    ref = reference(cell_type)
    dim = ref.dim
    n = max(1, int(np.ceil((degree + 1) / 2)))
    if dim == 0:
        return np.zeros((1, 0)), np.ones(1)
    if not ref.simplex:
        x, w = roots_legendre(n)
        pts = np.array(list(product(x, repeat=dim)), dtype=float)
        wts = np.array([np.prod(c) for c in product(w, repeat=dim)], dtype=float)
        return pts, wts
    if degree <= 1:
        return np.full((1, dim), 1.0 / (dim + 1)), np.array([1.0 / np.prod(range(1, dim + 1))])
    if degree == 2 and dim == 2:
        pts = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])
        return pts, np.full(3, 1 / 6)
    if degree == 2 and dim == 3:
        a = (5.0 - np.sqrt(5.0)) / 20.0
        b = 1.0 - 3.0 * a
        pts = np.array([[a, a, a], [b, a, a], [a, b, a], [a, a, b]])
        return pts, np.full(4, 1 / 24)
    return _collapsed(dim, n)


def _jacobi01(n: int, alpha: int) -> tuple[FloatArray, FloatArray]:
    """Gauss-Jacobi on [0, 1] for the weight (1 − t)^alpha."""
    x, w = roots_jacobi(n, alpha, 0.0)
    return 0.5 * (1.0 + x), w / 2.0 ** (alpha + 1)


def _collapsed(dim: int, n: int) -> tuple[FloatArray, FloatArray]:
    s, ws = _jacobi01(n, 0)
    t, wt = _jacobi01(n, 1)
    if dim == 2:
        S, T = np.meshgrid(s, t, indexing="ij")
        pts = np.stack([S * (1 - T), T], axis=-1).reshape(-1, 2)
        return pts, np.outer(ws, wt).ravel()
    r, wr = _jacobi01(n, 2)
    S3, T3, R3 = np.meshgrid(s, t, r, indexing="ij")
    w3 = ws[:, None, None] * wt[None, :, None] * wr[None, None, :]
    pts = np.stack([S3 * (1 - T3) * (1 - R3), T3 * (1 - R3), R3], axis=-1).reshape(-1, 3)
    return pts, w3.ravel()
