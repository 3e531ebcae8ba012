"""Reference elements: Lagrange shape functions built from monomials and nodes.

Each reference element is defined by its nodes in reference coordinates ξ and a set of
monomials m_j(ξ) = Π_d ξ_d^{p_jd}. The shape functions are the Lagrange basis of that
space, N(ξ) = m(ξ) V⁻¹ with the Vandermonde matrix V_ij = m_j(ξ_i); their gradients are
the gradients of the monomials times V⁻¹. This derives every element from its definition
instead of typing out formulas, and N_i(ξ_j) = δ_ij holds to round-off.

Node orderings are those of meshio and VTK (which gmsh files are converted to on
reading); cell type names are meshio's.

Reference domains: line [-1, 1]; quad and hexahedron [-1, 1]^d; triangle and tetra the
unit simplex with vertices at the origin and the unit points.

Axis convention (used throughout pfeie): arrays of element data are indexed
``[cell, quadrature point, node, component]``, written ``(c, q, n, d)``; any axis absent
from an array is simply dropped, keeping the order.

Example
-------
>>> from pfeie.element import reference
>>> import numpy as np
>>> q4 = reference("quad")
>>> N, dN = q4.shape_functions(np.zeros((1, 2)))
>>> N.round(3).tolist()
[[0.25, 0.25, 0.25, 0.25]]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache

import numpy as np

from ..errors import MeshError
from ..typing import FloatArray, IntArray


@dataclass(frozen=True)
class ReferenceElement:
    """A Lagrange reference element.

    Attributes
    ----------
    name: meshio cell type name.
    dim: topological dimension.
    nodes: reference coordinates of the nodes, shape (n, dim).
    exponents: monomial exponents, shape (n, dim).
    facets: local node lists of the facets, each ordered corner nodes first.
    facet_type: cell type of the facets ("" for a line).
    edges: local node pairs of the edges (corner nodes), used to add mid-edge nodes.
    degree: polynomial degree of completeness (1 linear, 2 quadratic).
    linear: the cell type of the corner nodes only.
    """

    name: str
    dim: int
    nodes: FloatArray
    exponents: IntArray
    facets: tuple[tuple[int, ...], ...]
    facet_type: str
    edges: tuple[tuple[int, int], ...]
    degree: int
    linear: str
    simplex: bool
    _vinv: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        vander = _monomials(self.nodes, self.exponents)
        object.__setattr__(self, "_vinv", np.linalg.inv(vander))

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_corners(self) -> int:
        return self.dim + 1 if self.simplex else 2**self.dim

    def shape_functions(self, xi: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Shape functions and their reference gradients at points ``xi`` (q, dim).

        Returns ``N`` with shape (q, n) and ``dN`` with shape (q, n, dim).
        """
        xi = np.atleast_2d(np.asarray(xi, dtype=float))
        values = _monomials(xi, self.exponents)
        grads = _monomial_gradients(xi, self.exponents)
        n = values @ self._vinv
        dn = np.einsum("qmd,mn->qnd", grads, self._vinv)
        return n, dn


def _monomials(xi: FloatArray, exponents: IntArray) -> FloatArray:
    return np.prod(xi[:, None, :] ** exponents[None, :, :], axis=2)


def _monomial_gradients(xi: FloatArray, exponents: IntArray) -> FloatArray:
    q, dim = xi.shape
    m = exponents.shape[0]
    out = np.empty((q, m, dim))
    for d in range(dim):
        p = exponents[:, d]
        lowered = exponents.copy()
        lowered[:, d] = np.maximum(p - 1, 0)
        out[:, :, d] = p[None, :] * _monomials(xi, lowered)
    return out


def _complete(dim: int, degree: int) -> list[tuple[int, ...]]:
    """Exponents of the complete polynomial space of a degree."""
    out = []
    for total in range(degree + 1):
        for e in np.ndindex(*(degree + 1,) * dim):
            if sum(e) == total:
                out.append(tuple(int(v) for v in e))
    return out


def _tensor(dim: int, degree: int) -> list[tuple[int, ...]]:
    return [tuple(int(v) for v in e) for e in np.ndindex(*(degree + 1,) * dim)]


def _mid(nodes: list[list[float]], edges: tuple[tuple[int, int], ...]) -> list[list[float]]:
    arr = np.asarray(nodes, dtype=float)
    return [list(0.5 * (arr[a] + arr[b])) for a, b in edges]


_TRI_EDGES = ((0, 1), (1, 2), (2, 0))
_QUAD_EDGES = ((0, 1), (1, 2), (2, 3), (3, 0))
_TET_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))
_HEX_EDGES = (
    (0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
    (0, 4), (1, 5), (2, 6), (3, 7),
)  # fmt: skip


def _build(name: str) -> ReferenceElement:
    line = [[-1.0], [1.0]]
    tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    quad = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
    tet = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    hexa = [
        [-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, 1.0], [-1.0, 1.0, 1.0],
    ]  # fmt: skip
    tet_faces = ((0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2))
    hex_faces = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
    specs: dict[str, tuple] = {
        # name: (dim, nodes, exponents, facets, facet_type, edges, degree, linear, simplex)
        "vertex": (0, [[]], [()], (), "", (), 1, "vertex", True),
        "line": (1, line, _complete(1, 1), ((0,), (1,)), "vertex", ((0, 1),), 1, "line", False),
        "line3": (1, [*line, [0.0]], _complete(1, 2), ((0,), (1,)), "vertex", ((0, 1),), 2,
                  "line", False),
        "triangle": (2, tri, _complete(2, 1), _TRI_EDGES, "line", _TRI_EDGES, 1, "triangle", True),
        "triangle6": (2, tri + _mid(tri, _TRI_EDGES), _complete(2, 2),
                      ((0, 1, 3), (1, 2, 4), (2, 0, 5)), "line3", _TRI_EDGES, 2, "triangle",
                      True),
        "quad": (2, quad, _tensor(2, 1), _QUAD_EDGES, "line", _QUAD_EDGES, 1, "quad", False),
        "quad8": (2, quad + _mid(quad, _QUAD_EDGES),
                  [e for e in _tensor(2, 2) if e != (2, 2)],
                  ((0, 1, 4), (1, 2, 5), (2, 3, 6), (3, 0, 7)), "line3", _QUAD_EDGES, 2, "quad",
                  False),
        "quad9": (2, [*quad, *_mid(quad, _QUAD_EDGES), [0.0, 0.0]], _tensor(2, 2),
                  ((0, 1, 4), (1, 2, 5), (2, 3, 6), (3, 0, 7)), "line3", _QUAD_EDGES, 2, "quad",
                  False),
        "tetra": (3, tet, _complete(3, 1), tet_faces, "triangle", _TET_EDGES, 1, "tetra", True),
        "tetra10": (3, tet + _mid(tet, _TET_EDGES), _complete(3, 2),
                    ((0, 2, 1, 6, 5, 4), (0, 1, 3, 4, 8, 7), (1, 2, 3, 5, 9, 8),
                     (0, 3, 2, 7, 9, 6)), "triangle6", _TET_EDGES, 2, "tetra", True),
        "hexahedron": (3, hexa, _tensor(3, 1), hex_faces, "quad", _HEX_EDGES, 1, "hexahedron",
                       False),
    }  # fmt: skip
    if name not in specs:
        raise MeshError(
            f"unsupported cell type {name!r}; supported: {', '.join(sorted(SUPPORTED))}"
        )
    dim, nodes, exps, facets, ftype, edges, degree, linear, simplex = specs[name]
    return ReferenceElement(
        name=name,
        dim=dim,
        nodes=np.asarray(nodes, dtype=float).reshape(len(nodes), dim),
        exponents=np.asarray(exps, dtype=np.int64).reshape(len(exps), dim),
        facets=tuple(tuple(f) for f in facets),
        facet_type=ftype,
        edges=edges,
        degree=degree,
        linear=linear,
        simplex=simplex,
    )


SUPPORTED = (
    "vertex", "line", "line3", "triangle", "triangle6", "quad", "quad8", "quad9",
    "tetra", "tetra10", "hexahedron",
)  # fmt: skip


@cache
def reference(name: str) -> ReferenceElement:
    """The reference element of a meshio cell type name (cached)."""
    return _build(name)


def cell_dimension(name: str) -> int:
    """Topological dimension of a cell type."""
    return reference(name).dim
