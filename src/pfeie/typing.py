"""Array types used throughout pfeie (one home for the aliases).

Axis convention: element data are indexed ``(cell, quadrature point, node, component)``
(``(c, q, n, d)``); pair data ``(pair, component)`` with the local components ordered
(t₁, [t₂,] n), normal last; nodal fields ``(node, component)`` or flat node-major vectors
(``dof = node · d + component``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

__all__ = ["BoolArray", "FloatArray", "IntArray"]
