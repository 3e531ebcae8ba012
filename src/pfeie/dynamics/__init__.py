"""Time integration, apart from the spatial operators."""

from ._newmark import History, MatrixSystem, Newmark, SecondOrderSystem, State

__all__ = ["History", "MatrixSystem", "Newmark", "SecondOrderSystem", "State"]
