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
crack of length s_c: the pairs open at the heel and every pair between them) is at full
headwater, h = H_w for s ≤ s_c; below it h falls linearly from H_w at the crack tip to h_d
at the drains (or, once the crack reaches past the drains, which then no longer work, to
H_t at the toe). The pressure is p = ρ_w g max(h − z, 0) at the pair's elevation z.

During shaking (``shaking``), as the guidelines name it: ``"keep"``, the pre-earthquake
uplift stays (the usual assumption: water cannot follow a crack opening and closing in
a fraction of a second; EM 1110-2-6051); ``"full"``, the parts that open in the crack
from the heel (as above: the pairs reached from the heel through open pairs) get full
headwater pressure, the reservoir's water reaching no other opening (a toe that lifts
keeps its pressure); ``"zero"``, the parts that open lose their pressure. The last two
follow the open or closed state of each pair, lagged by one step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..interface import PairGeometry
from ..typing import BoolArray, FloatArray

SHAKING = ("keep", "full", "zero")

#: the model file's keys of ``[[loads.uplift]]`` that the Python API names otherwise
MODEL_FILE_KEYS = {"drain_efficiency": "efficiency"}
_AXES = {"-x": (0, 1.0), "+x": (0, -1.0), "-y": (1, 1.0), "+y": (1, -1.0)}


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
    efficiency: drain efficiency E in [0, 1].
    upstream: where the reservoir is: ``"-x"`` (default: upstream is towards −x, the heel
        is the joint's end of least x), ``"+x"``, or in 3D also ``"-y"``, ``"+y"``.
    shaking: ``"keep"``, ``"full"`` or ``"zero"`` (module doc).
    density: ρ_w (kg/m³); ``g`` (m/s²).
    """

    interface: str
    headwater: float
    tailwater: float | None = None
    drains: float | None = None
    efficiency: float = 0.0
    upstream: str = "-x"
    shaking: str = "keep"
    density: float = 1000.0
    g: float = 9.81

    def __post_init__(self) -> None:
        where = f"uplift in {self.interface!r}"
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


__all__ = ["SHAKING", "Uplift", "uplift_force"]
