"""Sparse linear algebra: direct factorisations behind one small interface.

``factorize(A)`` factorises once; ``solve(b)`` applies A⁻¹ to one or many right-hand
sides. Used by statics, modal analysis, the Delassus operator and time integration.
``UpdatedFactorization`` solves with A + U B Uᵀ from the factor of A (Woodbury), for a
low-rank term such as the damping of the floating bodies' deformation only.
``symmetric_product`` multiplies by a large dense symmetric matrix (W, W_c⁻¹) reading one
triangle, ``symmetric_columns`` gathers its columns along the contiguous axis;
``null_space`` gives the null space of a tall matrix without its left singular vectors;
``Workspace`` keeps the work arrays of repeated large dense computations, ``MixedLU``
solves a large dense system by a single-precision LU refined in double precision.
``run_lockstep`` runs several computations on shared factors in turn, their block solves
made together (a study's records; the same bits as each alone).
"""

from ._block import SMALL_BLOCK_MIN_DOF
from ._dense import (
    SYMMETRIC_MIN,
    MixedLU,
    Workspace,
    null_space,
    symmetric_columns,
    symmetric_product,
)
from ._factor import (
    Factorization,
    available_backends,
    factorize,
    nested_dissection,
    shares_block_solves,
    solver_stack,
)
from ._lockstep import LockstepStats, run_lockstep
from ._lowrank import LowRankTerm, UpdatedFactorization

__all__ = [
    "SMALL_BLOCK_MIN_DOF",
    "SYMMETRIC_MIN",
    "Factorization",
    "LockstepStats",
    "LowRankTerm",
    "MixedLU",
    "UpdatedFactorization",
    "Workspace",
    "available_backends",
    "factorize",
    "nested_dissection",
    "null_space",
    "run_lockstep",
    "shares_block_solves",
    "solver_stack",
    "symmetric_columns",
    "symmetric_product",
]
