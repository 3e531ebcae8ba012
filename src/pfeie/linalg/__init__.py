"""Sparse linear algebra: direct factorisations behind one small interface.

``factorize(A)`` factorises once; ``solve(b)`` applies A⁻¹ to one or many right-hand
sides. Used by statics, modal analysis, the Delassus operator and time integration.
``UpdatedFactorization`` solves with A + U B Uᵀ from the factor of A (Woodbury), for a
low-rank term such as the damping of the floating bodies' deformation only.
"""

from ._factor import Factorization, available_backends, factorize, nested_dissection
from ._lowrank import LowRankTerm, UpdatedFactorization

__all__ = [
    "Factorization",
    "LowRankTerm",
    "UpdatedFactorization",
    "available_backends",
    "factorize",
    "nested_dissection",
]
