"""Solvers: sparse factorisations, linear statics and modal analysis."""

from ..linalg import Factorization, available_backends, factorize
from ._modal import ModalResult, modal
from ._static import StaticResult, solve_static
from ._yield import YIELD_K_MAX, YieldCoefficient, horizontal, yield_coefficient

__all__ = [
    "YIELD_K_MAX", "Factorization", "ModalResult", "StaticResult", "YieldCoefficient",
    "available_backends", "factorize", "horizontal", "modal", "solve_static",
    "yield_coefficient",
]  # fmt: skip
