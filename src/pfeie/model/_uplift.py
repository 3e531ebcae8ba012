"""Uplift: the pore-water pressure in a joint (dam–rock contact, a lift joint, a crack).

The pressure acts on both faces of the joint and pushes them apart; it is an external
load on the pair nodes, equal and opposite on the two sides,

    f_b = + p A n,    f_a = − p A n        (N; n the pair normal from side a to side b),

so the contact forces of the pairs are effective forces: a joint with uplift carries
N' = N − U, and its sliding capacity is c A + μ N' (USACE EM 1110-2-2100, §4; FERC
Engineering Guidelines, Chapter III).

Distribution (USACE EM 1110-2-2200, §3-3; EM 1110-2-2100): along the joint,
from the heel (its upstream end, s = 0) to the toe (s = L), the piezometric level h(s)
falls linearly from the headwater level H_w to the tailwater level H_t; with a line of
drains at s_d of efficiency E, the level at the drains is

    h_d = H_t + (1 − E) (H_w − H_t) (L − s_d) / L,

and h is piecewise linear H_w → h_d → H_t. The part of the joint open from the heel (a
crack of length s_c: the pairs open at the heel and every pair between them; in 3D the
crack open across the whole width, station by station along the abscissa) is at full
headwater, h = H_w for s ≤ s_c; below it h falls linearly from H_w at the crack tip to h_d
at the drains (or, once the crack reaches past the drains, which then no longer work, to
H_t at the toe). The pressure is p = ρ_w g max(h − z, 0) at the pair's elevation z.

During shaking (``shaking``), as the guidelines name it: ``"keep"``, the pre-earthquake
uplift stays (the usual assumption: water cannot follow a crack opening and closing in
a fraction of a second; EM 1110-2-6051); ``"full"``, the parts that open in the crack
from the heel (the pairs reached from the heel through open pairs: along the joint in
2D, as above; across its face in 3D, :meth:`Uplift.stations`) get full headwater
pressure, the reservoir's water reaching no other opening (a toe that lifts keeps its
pressure); ``"zero"``, the parts that open lose their pressure. The last two
follow the open or closed state of each pair, lagged by one step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..interface import PairGeometry
from ..typing import BoolArray, FloatArray, IntArray

SHAKING = ("keep", "full", "zero")

#: the model file's keys of ``[[loads.uplift]]`` that the Python API names otherwise
MODEL_FILE_KEYS = {"drain_efficiency": "efficiency"}
_AXES = {"-x": (0, 1.0), "+x": (0, -1.0), "-y": (1, 1.0), "+y": (1, -1.0)}


def _hole_edges(ab: IntArray, edge: BoolArray, uv: FloatArray) -> BoolArray:
    """Which of the edges ``ab`` (e, 2) (stations) flagged ``edge`` (on the joint's
    boundary) bound a hole of the joint (a gallery, a shaft): the loops of boundary edges
    whose extent in the plane ``uv`` lies inside another loop's. Water from the reservoir
    reaches the outer boundary only."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    k = uv.shape[0]
    a, b = ab[edge, 0], ab[edge, 1]
    g = coo_matrix((np.ones(a.size), (a, b)), shape=(k, k))
    _, loop = connected_components(g, directed=False)
    on = np.unique(np.r_[a, b])
    loops = np.unique(loop[on])
    lo = np.array([uv[on[loop[on] == c]].min(axis=0) for c in loops])
    hi = np.array([uv[on[loop[on] == c]].max(axis=0) for c in loops])
    tol = 1e-9 * max(float(np.ptp(uv, axis=0).max()), 1e-300)
    inside = np.all((lo[:, None] > lo[None, :] + tol) & (hi[:, None] < hi[None, :] - tol), axis=2)
    hole = loops[np.any(inside, axis=1)]
    out = np.zeros(ab.shape[0], dtype=bool)
    out[edge] = np.isin(loop[a], hole)
    return out


#: a boundary edge of a 3D joint whose outward normal lies within this angle (degrees) of
#: the upstream direction in the joint's plane is at the heel (:meth:`Uplift.stations`)
HEEL_FACING_DEG = 60.0


@dataclass(frozen=True)
class Stations:
    """The pairs of a joint with uplift as stations and their neighbours
    (:meth:`Uplift.stations`): ``of`` (k,) the station of each pair, ``edges`` (e, 2) the
    neighbouring stations, ``heel`` (n_stations,) the stations at the heel."""

    of: IntArray
    edges: IntArray
    heel: BoolArray

    def reached(self, open_: BoolArray) -> BoolArray:
        """The pairs (k,) reached from the heel through open stations (a station is open
        when all its pairs are): the crack from the heel, which the reservoir's water
        fills. In 2D the pairs up to :meth:`Uplift.crack`; in 3D across the joint's face,
        so a crack over part of the width, or along a lateral edge, is reached.

        >>> st = Stations(np.arange(4), np.array([[0, 1], [1, 2], [2, 3]]),
        ...               np.array([True, False, False, False]))
        >>> st.reached(np.array([True, True, False, True])).tolist()
        [True, True, False, False]
        """
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        n = self.heel.size
        count = np.bincount(self.of, minlength=n)
        st_open = np.bincount(self.of, weights=open_.astype(float), minlength=n) == count
        a, b = self.edges[:, 0], self.edges[:, 1]
        keep = st_open[a] & st_open[b]
        heel = np.flatnonzero(self.heel & st_open)
        # the stations and a source joined to the open heel stations
        rows = np.r_[a[keep], np.full(heel.size, n)]
        cols = np.r_[b[keep], heel]
        graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n + 1, n + 1))
        _, label = connected_components(graph, directed=False)
        wet = (label[:n] == label[n]) & st_open
        return np.asarray(wet[self.of] & open_)


#: the default of :attr:`Uplift.efficiency`, told from any value given by its identity (a
#: NaN given is refused as not finite)
_NOT_GIVEN = float("nan")


@dataclass(frozen=True)
class Uplift:
    """Uplift in one interface (see the module doc).

    Parameters
    ----------
    interface: the interface (its pairs).
    headwater: headwater level H_w (m, on the vertical axis: y in 2D, z in 3D).
    tailwater: tailwater level H_t (m); None: no tailwater (the level of the toe).
    drains: distance s_d (m) of the line of drains from the heel, along the flow as the
        joint's abscissa measures it (:meth:`abscissa`: along the upstream axis, the
        horizontal projection on an inclined joint); None:
        no drains.
    efficiency: drain efficiency E in [0, 1]; required with ``drains`` (0 for drains that
        remove nothing), without them 0.
    upstream: where the reservoir is: ``"-x"`` (default: upstream is towards −x, the heel
        is the joint's end of least x), ``"+x"``, or in 3D also ``"-y"``, ``"+y"``.
    shaking: ``"keep"``, ``"full"`` or ``"zero"`` (module doc).
    density: ρ_w (kg/m³); ``g`` (m/s²).
    """

    interface: str
    headwater: float
    tailwater: float | None = None
    drains: float | None = None
    efficiency: float = _NOT_GIVEN  # (not given: 0 without drains, an error with them)
    upstream: str = "-x"
    shaking: str = "keep"
    density: float = 1000.0
    g: float = 9.81

    def __post_init__(self) -> None:
        where = f"uplift in {self.interface!r}"
        if self.efficiency is _NOT_GIVEN:
            if self.drains is not None:
                # drains with the default efficiency of 0 change nothing, silently
                raise ModelError(f"{where}: drains given without their efficiency: give "
                                 "efficiency, the fraction E of the head the drains remove "
                                 "(e.g. 0.5; 0 for drains that remove nothing)")  # fmt: skip
            object.__setattr__(self, "efficiency", 0.0)
        for name in ("headwater", "efficiency", "density", "g"):
            if not np.isfinite(getattr(self, name)):
                raise ModelError(f"{where}: {name} must be a finite number")
        if self.tailwater is not None and not np.isfinite(self.tailwater):
            raise ModelError(f"{where}: tailwater must be a finite number")
        if not 0.0 <= self.efficiency <= 1.0:
            raise ModelError(f"{where}: the drain efficiency must be in [0, 1], got "
                             f"{self.efficiency}")  # fmt: skip
        if self.drains is not None and not (np.isfinite(self.drains) and self.drains >= 0):
            raise ModelError(f"{where}: drains must be a distance >= 0 from the heel (m), got "
                             f"{self.drains}")  # fmt: skip
        if self.upstream not in _AXES:
            raise ModelError(f"{where}: upstream must be one of {', '.join(_AXES)}, got "
                             f"{self.upstream!r}")  # fmt: skip
        if self.shaking not in SHAKING:
            raise ModelError(f"{where}: shaking must be one of {', '.join(SHAKING)}, got "
                             f"{self.shaking!r}")  # fmt: skip
        if self.density <= 0 or self.g <= 0:
            raise ModelError(f"{where}: density and g must be > 0")
        if self.tailwater is not None and self.tailwater > self.headwater:
            raise ModelError(f"{where}: the tailwater level {self.tailwater} m is above the "
                             f"headwater level {self.headwater} m")  # fmt: skip

    def abscissa(self, pairs: PairGeometry, idx: np.ndarray) -> tuple[FloatArray, float]:
        """The distance s (m) of each pair ``idx`` from the heel along the flow, and L:
        measured along the upstream axis (``upstream``), so on an inclined or stepped
        joint the horizontal projection (on a planar joint proportional to the distance
        along it, so that the linear profiles are the same; the drains' ``s_d`` is in the
        same measure)."""
        axis, sign = _AXES[self.upstream]
        if axis >= pairs.dim - 1:
            raise ModelError(f"uplift in {self.interface!r}: upstream {self.upstream!r} in a "
                             f"{pairs.dim}D model (the vertical axis is the last)")  # fmt: skip
        x = sign * pairs.x[idx, axis]
        s = x - x.min()
        return s, float(s.max())

    def crack(self, pairs: PairGeometry, idx: np.ndarray, open_: BoolArray | None) -> float:
        """The crack length s_c (m): the farthest open pair reached from the heel through
        open pairs only (0 when the heel is closed)."""
        if open_ is None:
            return 0.0
        s, _ = self.abscissa(pairs, idx)
        o = open_[idx]
        order = np.argsort(s, kind="stable")
        ss, oo = s[order], o[order]
        if not oo.size or not oo[0]:
            return 0.0
        # pairs at the same abscissa (two sides of a junction) count as one station
        stations, first = np.unique(ss, return_index=True)
        st_open = np.logical_and.reduceat(oo, first)
        k = int(np.argmin(st_open)) if not st_open.all() else stations.size
        return float(stations[k - 1]) if k > 0 else 0.0

    def stations(
        self, pairs: PairGeometry, idx: np.ndarray,
        facets: Sequence[tuple[IntArray, int]] = (),
    ) -> Stations:  # fmt: skip
        """The joint's pairs ``idx`` as stations (pairs at one point, the two sides of a
        junction, are one) and their neighbours, for :meth:`Stations.reached`. In 2D
        consecutive along the abscissa, the heel the first. In 3D, given the joint's
        ``facets`` (each a connectivity (n_f, nodes) of the split mesh and its corner
        count), the stations joined along the facets' edges (corner, mid-side node,
        corner), so that water crosses only where the joint is (an L-shaped joint, a
        joint around a gallery); the heel the stations on the joint's boundary edges that
        face upstream (outward normal within 60° of the upstream direction in the joint's
        plane: a skewed or curved upstream edge too). Without facets, the Delaunay
        triangulation of the stations in the joint's mean plane, the heel the stations
        with no neighbour nearer the heel. Built once a run."""
        s, L = self.abscissa(pairs, idx)
        tol = 1e-9 * max(L, 1e-300)
        if pairs.dim == 2:
            key = np.round(s / tol)[:, None] if L > 0 else np.zeros((s.size, 1))
        else:
            # coordinates in the joint's mean plane (any planar joint, not only level ones)
            n = pairs.frame[idx, -1, :].mean(axis=0)
            _, _, vt = np.linalg.svd(np.eye(3) - np.outer(n, n) / max(n @ n, 1e-300))
            key = np.round(pairs.x[idx] @ vt[:2].T / tol) if L > 0 else np.zeros((s.size, 2))
        uniq, inv = np.unique(key, axis=0, return_inverse=True)
        inv = inv.ravel()
        k = uniq.shape[0]
        s_st = np.full(k, np.inf)
        np.minimum.at(s_st, inv, s)
        edges = np.zeros((0, 2), dtype=np.int64)
        if k > 1 and pairs.dim == 2:
            order = np.argsort(s_st, kind="stable")
            edges = np.column_stack([order[:-1], order[1:]])
        elif k > 2 and facets:
            return self._facet_stations(pairs, idx, facets, inv, uniq * tol, s_st)
        elif k > 2:
            from scipy.spatial import Delaunay, QhullError

            try:
                tri = Delaunay(uniq * tol).simplices
                e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
                edges = np.unique(np.sort(e, axis=1), axis=0)
            except QhullError:  # the stations on a line: consecutive along it
                order = np.lexsort(uniq.T[::-1])
                edges = np.column_stack([order[:-1], order[1:]])
        # the heel: stations with no neighbour nearer the heel (in 2D the first)
        nearer = np.zeros(k, dtype=bool)
        if edges.size:
            a, b = edges[:, 0], edges[:, 1]
            nearer[a[s_st[b] < s_st[a] - tol]] = True
            nearer[b[s_st[a] < s_st[b] - tol]] = True
        return Stations(inv, edges, ~nearer)

    @staticmethod
    def _facet_stations(
        pairs: PairGeometry, idx: np.ndarray, facets: Sequence[tuple[IntArray, int]],
        inv: IntArray, uv: FloatArray, s_st: FloatArray,
    ) -> Stations:  # fmt: skip
        """:meth:`stations` in 3D from the joint's facets: ``inv`` the station of each
        pair, ``uv`` (n_st, 2) the stations in the joint's plane, ``s_st`` their
        abscissae."""
        k = uv.shape[0]
        station = np.full(int(max(pairs.node_a.max(), pairs.node_b.max())) + 1, -1)
        station[pairs.node_a[idx]] = inv
        side_a = np.zeros(station.size, dtype=bool)
        side_a[pairs.node_a[idx]] = True
        station[pairs.node_b[idx]] = inv
        pieces, bound = [], []
        for conn, nc in facets:
            conn = conn[np.all(side_a[conn], axis=1)]  # one side's facets: each edge once
            if not conn.size:
                continue
            st = station[conn]  # (f, nodes)
            centre = uv[st[:, :nc]].mean(axis=1)
            for c in range(nc):
                a, b = st[:, c], st[:, (c + 1) % nc]
                if conn.shape[1] > nc:  # a mid-side node between them (quadratic facets)
                    mid = st[:, nc + c]
                    pieces += [np.column_stack([a, mid]), np.column_stack([mid, b])]
                else:
                    pieces.append(np.column_stack([a, b]))
                # the edge's outward normal in the plane, away from its facet's centre
                e = uv[b] - uv[a]
                nu = np.column_stack([e[:, 1], -e[:, 0]])
                out = np.einsum("fi,fi->f", nu, 0.5 * (uv[a] + uv[b]) - centre) < 0
                nu[out] *= -1.0
                bound.append((np.sort(np.column_stack([a, b]), axis=1), nu,
                              mid if conn.shape[1] > nc else a))  # fmt: skip
            if conn.shape[1] == 2 * nc + 1:  # a centre node (Q9): joined to the mid-sides
                pieces += [np.column_stack([st[:, nc + c], st[:, -1]]) for c in range(nc)]
        e_all = np.concatenate(pieces) if pieces else np.zeros((0, 2), dtype=np.int64)
        e_all = e_all[(e_all >= 0).all(axis=1) & (e_all[:, 0] != e_all[:, 1])]
        edges = np.unique(np.sort(e_all, axis=1), axis=0)
        # the joint's boundary: corner edges of one facet only; the heel those that face
        # upstream, against the flow's direction in the plane (the gradient of s)
        heel = np.zeros(k, dtype=bool)
        if bound:
            ab = np.concatenate([b[0] for b in bound])
            nu = np.concatenate([b[1] for b in bound])
            mids = np.concatenate([b[2] for b in bound])
            _, first, count = np.unique(ab, axis=0, return_index=True, return_counts=True)
            edge = np.zeros(ab.shape[0], dtype=bool)
            edge[first[count == 1]] = True
            A = np.column_stack([uv, np.ones(k)])
            grad = np.linalg.lstsq(A, np.where(np.isfinite(s_st), s_st, 0.0), rcond=None)[0][:2]
            flow = grad / max(float(np.linalg.norm(grad)), 1e-300)
            nn = nu / np.maximum(np.linalg.norm(nu, axis=1), 1e-300)[:, None]
            up = edge & (nn @ flow < -np.cos(np.radians(HEEL_FACING_DEG)))
            up &= ~_hole_edges(ab, edge, uv)  # the rim of a hole (a gallery) is no heel
            heel[ab[up].ravel()] = True
            heel[mids[up]] = True
        if not heel.any():  # (a degenerate joint) the stations nearest the heel
            heel = s_st <= s_st.min() + 1e-9 * max(float(np.ptp(s_st)), 1e-300)
        return Stations(inv, edges, heel)

    def level(self, s: FloatArray, L: float, crack: float, z_toe: float) -> FloatArray:
        """The piezometric level h(s) (m) for a crack of length ``crack`` (module doc)."""
        hw = self.headwater
        ht = z_toe if self.tailwater is None else max(self.tailwater, z_toe)
        ht = min(ht, hw)
        if L <= 0:
            return np.full_like(s, hw)
        sd = self.drains
        drains = sd is not None and self.efficiency > 0 and crack < sd < L
        if drains:
            assert sd is not None
            hd = ht + (1.0 - self.efficiency) * (hw - ht) * (L - sd) / L
            pts_s, pts_h = [crack, sd, L], [hw, hd, ht]
        else:
            pts_s, pts_h = [crack, L], [hw, ht]
        h = np.interp(s, pts_s, pts_h)
        return np.where(s <= crack, hw, h)

    def pressure(self, pairs: PairGeometry, open_: BoolArray | None = None,
                 crack: float | None = None) -> tuple[FloatArray, float]:  # fmt: skip
        """The pressure p (Pa) at every pair of the model (zero off this interface) and
        the crack length used: ``crack``, else the one of the open pairs ``open_``."""
        idx = pairs.of(self.interface)
        p = np.zeros(pairs.n)
        if not idx.size:
            return p, 0.0
        s, L = self.abscissa(pairs, idx)
        c = self.crack(pairs, idx, open_) if crack is None else float(crack)
        z = pairs.x[idx, -1]
        z_toe = float(z[np.argmax(s)])
        h = self.level(s, L, c, z_toe)
        p[idx] = self.density * self.g * np.maximum(h - z, 0.0)
        return p, c


def uplift_force(pairs: PairGeometry, p: FloatArray, n_dof: int) -> FloatArray:
    """The nodal load (n_dof,) of the pair pressures ``p`` (Pa): + p A n on side b, − p A n
    on side a (n the pair normal, the last row of its frame)."""
    d = pairs.dim
    F = (p * pairs.area)[:, None] * pairs.frame[:, -1, :]
    f = np.zeros(n_dof)
    for k in range(d):  # d components, vectorised over the pairs
        np.add.at(f, pairs.node_b * d + k, F[:, k])
        np.add.at(f, pairs.node_a * d + k, -F[:, k])
    return f


__all__ = ["SHAKING", "Stations", "Uplift", "uplift_force"]
