"""Sparse linear algebra: direct factorisations behind one small interface.

``factorize(A)`` factorises once; ``solve(b)`` applies A⁻¹ to one or many right-hand
sides. Used by statics, modal analysis, the Delassus operator and time integration.
``UpdatedFactorization`` solves with A + U B Uᵀ from the factor of A (Woodbury), for a
low-rank term such as the damping of the floating bodies' deformation only.
``symmetric_product`` multiplies by a large dense symmetric matrix (W, W_c⁻¹) reading one
triangle, ``symmetric_columns`` gathers its columns along the contiguous axis;
``Workspace`` keeps the work arrays of repeated large dense computations, ``MixedLU``
solves a large dense system by a single-precision LU refined in double precision.
"""

from ._dense import SYMMETRIC_MIN, MixedLU, Workspace, symmetric_columns, symmetric_product
from ._factor import Factorization, available_backends, factorize, nested_dissection
from ._lowrank import LowRankTerm, UpdatedFactorization

__all__ = [
    "SYMMETRIC_MIN",
    "Factorization",
    "LowRankTerm",
    "MixedLU",
    "UpdatedFactorization",
    "Workspace",
    "available_backends",
    "factorize",
    "nested_dissection",
    "symmetric_columns",
    "symmetric_product",
]
