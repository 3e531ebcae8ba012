"""Time integration: Newmark / HHT-α, and the PFE/IE step that couples it to interfaces."""

from ._newmark import History, MatrixSystem, Newmark, SecondOrderSystem, State
from ._pfeie import Dynamic, DynamicResult, StepState
from ._settings import DynamicSettings

__all__ = [
    "Dynamic", "DynamicResult", "DynamicSettings", "History", "MatrixSystem", "Newmark", "SecondOrderSystem",
    "State", "StepState",
]  # fmt: skip
