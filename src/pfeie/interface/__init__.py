"""Interfaces: cutting the mesh into blocks, point pairs, joint laws and the pair solver.

- :func:`split` duplicates the nodes of named facet groups and pairs the copies
  (:class:`PairGeometry`: nodes, frames, tributary areas);
- joint laws behind the :class:`JointLaw` protocol (:class:`MohrCoulomb`, alias
  :class:`Joint`; :class:`SlipWeakening`; :class:`Reduced`, a law's strength divided by
  a factor), gathered per pair by :class:`PairLaws`;
- :func:`block_pieces`: a joint's pairs grouped by the two blocks they join;
- :class:`PairState`: the pair states with explicit trial and commit (the solver returns
  a trial state; the analysis commits it when the step is accepted);
- :func:`load_fclib`, :func:`coulomb_laws`, :func:`natural_map_residual`: frictional-
  contact problems in the FCLIB form and Siconos' measure of an answer;
- :class:`InterfaceSolver`: the interface problem of one step for a given Delassus
  operator W (method.md §5.3), with its :class:`SolverSettings`.

The operators that couple blocks and pairs (G, W, the static and one-step interface
problems) live in :mod:`pfeie.coupling`.
"""

from ._fclib import coulomb_laws, load_fclib, natural_map_residual
from ._laws import (
    COHESION_RAMP,
    FS_ROUNDOFF,
    JOINT_STIFFNESS_MIN,
    MODEL_FILE_KEYS,
    OPEN_CRACK_MIN_M,
    Joint,
    JointLaw,
    MohrCoulomb,
    PairLaws,
    Reduced,
    SlipWeakening,
    Strength,
    check_law,
    cohesion_ramp,
    cohesion_ramp_tangent,
    law_fields,
    law_key,
)
from ._settings import SolverSettings, Tolerance
from ._solver import (
    FACTOR_CACHE_BYTES,
    FACTOR_CACHE_COUNT,
    PROXIMAL_FIRST_3D,
    SECOND_STAGE_PROXIMAL,
    FactorCache,
    InterfaceSolver,
    SolveInfo,
)
from ._split import PairGeometry, SplitMesh, block_pieces, split
from ._state import INTACT, OPEN, SLIDE, STATE_NAMES, STICK, PairState

__all__ = [
    "COHESION_RAMP",
    "FACTOR_CACHE_BYTES",
    "FACTOR_CACHE_COUNT",
    "FS_ROUNDOFF",
    "INTACT",
    "JOINT_STIFFNESS_MIN",
    "MODEL_FILE_KEYS",
    "OPEN",
    "OPEN_CRACK_MIN_M",
    "PROXIMAL_FIRST_3D",
    "SECOND_STAGE_PROXIMAL",
    "SLIDE",
    "STATE_NAMES",
    "STICK",
    "FactorCache",
    "InterfaceSolver",
    "Joint",
    "JointLaw",
    "MohrCoulomb",
    "PairGeometry",
    "PairLaws",
    "PairState",
    "Reduced",
    "SlipWeakening",
    "SolveInfo",
    "SolverSettings",
    "SplitMesh",
    "Strength",
    "Tolerance",
    "block_pieces",
    "check_law",
    "cohesion_ramp",
    "cohesion_ramp_tangent",
    "coulomb_laws",
    "law_fields",
    "law_key",
    "load_fclib",
    "natural_map_residual",
    "split",
]  # fmt: skip
