"""Solvers: sparse factorisations, linear statics, modal analysis, the yield coefficient and
the factor of safety by strength reduction."""

from ..linalg import Factorization, available_backends, factorize
from ._modal import ModalResult, modal
from ._static import (
    JUNCTION_RATIO,
    JUNCTION_SHARE,
    StaticResult,
    junction_share,
    leans_on_junctions,
    solve_static,
)
from ._strength import (
    REDUCTION_F_MAX,
    REDUCTION_MAX_ANALYSES,
    REDUCTION_TOL,
    StrengthReduction,
    strength_reduction,
)
from ._yield import (
    SLIDING_FS,
    YIELD_K_MAX,
    YIELD_RIGID_GAP,
    YieldCoefficient,
    horizontal,
    yield_coefficient,
)

__all__ = [
    "JUNCTION_RATIO", "JUNCTION_SHARE", "REDUCTION_F_MAX", "REDUCTION_MAX_ANALYSES",
    "REDUCTION_TOL", "SLIDING_FS", "YIELD_K_MAX", "YIELD_RIGID_GAP", "Factorization",
    "ModalResult", "StaticResult", "StrengthReduction", "YieldCoefficient",
    "available_backends", "factorize", "horizontal", "junction_share", "leans_on_junctions",
    "modal", "solve_static", "strength_reduction", "yield_coefficient",
]  # fmt: skip
