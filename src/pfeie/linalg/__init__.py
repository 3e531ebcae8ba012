"""Sparse linear algebra: direct factorisations behind one small interface.

``factorize(A)`` factorises once; ``solve(b)`` applies A⁻¹ to one or many right-hand
sides. Used by statics, modal analysis, the Delassus operator and time integration.
"""

from ._factor import Factorization, available_backends, factorize, nested_dissection

__all__ = ["Factorization", "available_backends", "factorize", "nested_dissection"]
