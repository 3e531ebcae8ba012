"""Solvers: sparse factorisations, linear statics and modal analysis."""

from ..linalg import Factorization, available_backends, factorize
from ._modal import ModalResult, modal
from ._static import StaticResult, solve_static

__all__ = [
    "Factorization", "ModalResult", "StaticResult", "available_backends", "factorize",
    "modal", "solve_static",
]  # fmt: skip
