"""Settings of the interface solver: the one source of its options and defaults."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from ..typing import Settings

#: the interface solver's tolerance as a settings field: its range, its one definition
#: (:class:`SolverSettings` and the analysis settings that pass it on)
Tolerance = Annotated[float, Field(gt=0.0, le=1e-2, allow_inf_nan=False)]


class SolverSettings(Settings):
    """Options of :class:`pfeie.interface.InterfaceSolver` (method.md §5.3).

    >>> SolverSettings().tolerance
    1e-08
    """

    tolerance: Annotated[Tolerance, Field(
        description="interface complementarity tolerance: the largest scaled residual of "
        "the joint law accepted at a pair (relative to the pair forces)",
    )] = 1e-8  # fmt: skip
    max_iter: Annotated[int, Field(
        gt=0, le=10_000, description="state-iteration limit of the interface solver before "
        "its semismooth Newton, then its fallbacks (proximal Newton, projected Gauss-Seidel), "
        "take over",
    )] = 60  # fmt: skip


__all__ = ["SolverSettings", "Tolerance"]
