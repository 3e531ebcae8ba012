"""Finite elements: reference shape functions and quadrature (no mesh, no physics)."""

from ._quadrature import quadrature
from ._reference import SUPPORTED, ReferenceElement, cell_dimension, reference

__all__ = ["SUPPORTED", "ReferenceElement", "cell_dimension", "quadrature", "reference"]
