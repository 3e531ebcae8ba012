"""Coupling of blocks and pairs: one home for the operators of the PFE/IE method.

- :class:`PairOperator` (and :func:`relative_operator`): G, block displacements → pair
  relative displacements, on the free and prescribed DOFs, and its body-frame variant;
- :func:`delassus`: the Delassus operator W = G K̂⁻¹ Gᵀ (dense, matrix-free, per joint
  with compressed couplings, or gathered from a :class:`NodalFlexibility`), built once
  from one multi-RHS solve;
- :class:`StaticInterfaceProblem`: the static problem with the rigid unknowns of
  floating blocks (method.md §5.2);
- :func:`translations`, :func:`translation_limit`: limit equilibrium of single rigid
  blocks' translations (Hoek and Bray's plane and wedge sliding), beside the static
  problem's own answers;
- :class:`InterfaceStep`: the one-step problem, predictor → interface solve → corrector,
  that a time integrator calls (method.md §5.1).

Dependencies point one way: mesh, element, assembly → interface → model → coupling →
solvers, dynamics → io, plot → the command line.
"""

from ._delassus import (
    BlockDelassus,
    Delassus,
    DenseDelassus,
    GatheredDelassus,
    MatrixFreeDelassus,
    NodalFlexibility,
    delassus,
)  # fmt: skip
from ._operators import PairOperator, relative_operator
from ._static import (
    RIGID_FACTOR_RANGE,
    RIGID_FACTOR_TOL,
    RIGID_SHARE_MIN,
    RigidCheck,
    StaticInterfaceProblem,
    pins,
)
from ._step import SUBSOLVER_BYTES, SUBSOLVERS, InterfaceStep, SolveStats, StepSolution
from ._translation import Translation, translation_limit, translations

__all__ = [
    "RIGID_FACTOR_RANGE", "RIGID_FACTOR_TOL", "RIGID_SHARE_MIN", "SUBSOLVERS",
    "SUBSOLVER_BYTES", "BlockDelassus", "Delassus", "DenseDelassus", "GatheredDelassus",
    "InterfaceStep", "MatrixFreeDelassus", "NodalFlexibility", "PairOperator", "RigidCheck",
    "SolveStats", "StaticInterfaceProblem", "StepSolution", "Translation", "delassus", "pins",
    "relative_operator", "translation_limit", "translations",
]  # fmt: skip
