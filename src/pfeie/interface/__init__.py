"""Interfaces: cutting the mesh into blocks, point pairs, the joint law and its solver.

- :func:`split` duplicates the nodes of named facet groups and pairs the copies;
- :class:`PairProperties`, :class:`PairState`: the joint law's data, with trial/commit
  (the solver returns a trial state; the analysis commits it when the step is accepted);
- :func:`delassus`: the interface flexibility W = G K̂⁻¹ Gᵀ;
- :class:`InterfaceSolver`: the per-step state iteration of method.md §5.3.
"""

from ._delassus import delassus
from ._law import INTACT, OPEN, SLIDE, STATE_NAMES, STICK, PairProperties, PairState
from ._settings import SolverSettings
from ._solver import InterfaceSolver, SolveInfo
from ._split import PairGeometry, SplitMesh, split

__all__ = [
    "INTACT", "OPEN", "SLIDE", "STATE_NAMES", "STICK", "InterfaceSolver", "PairGeometry",
    "PairProperties", "PairState", "SolveInfo", "SolverSettings", "SplitMesh", "delassus", "split",
]  # fmt: skip
