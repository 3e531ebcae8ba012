"""Meshes: the in-memory mesh type and structured generators."""

from ._generators import box, elevate, graded, rectangle
from ._mesh import Mesh

__all__ = ["Mesh", "box", "elevate", "graded", "rectangle"]
