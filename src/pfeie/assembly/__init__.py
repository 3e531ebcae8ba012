"""Finite element machinery: vectorised kernels and sparse assembly (no physics objects)."""

from ._kernels import (
    VOIGT,
    CellValues,
    FacetValues,
    cell_values,
    curved_cells,
    facet_load,
    facet_values,
    load,
    lump_hrz,
    mass_degree,
    principal_extremes,
    principal_stresses,
    scalar_mass,
    stiffness,
    stiffness_degree,
    strain,
    stress,
)
from ._sparse import assemble_matrix, assemble_vector, element_dofs

__all__ = [
    "VOIGT", "CellValues", "FacetValues", "assemble_matrix", "assemble_vector", "cell_values",
    "curved_cells",
    "element_dofs", "facet_load", "facet_values", "load", "lump_hrz", "mass_degree",
    "principal_extremes", "principal_stresses", "scalar_mass", "stiffness", "stiffness_degree",
    "strain", "stress",
]  # fmt: skip
