"""Meshes: the in-memory mesh type and structured generators."""

from ._generators import box, elevate, graded, rectangle
from ._mesh import Mesh, facet_keys, match_rows, planar_points
from ._quality import check_cells, shape_quality

__all__ = ["Mesh", "box", "check_cells", "elevate", "facet_keys", "graded", "match_rows",
           "planar_points", "rectangle", "shape_quality"]  # fmt: skip
