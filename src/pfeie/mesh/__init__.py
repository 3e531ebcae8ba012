"""Meshes: the in-memory mesh type and structured generators."""

from ._generators import box, elevate, graded, rectangle
from ._mesh import Mesh, facet_keys, match_rows

__all__ = ["Mesh", "box", "elevate", "facet_keys", "graded", "match_rows", "rectangle"]
