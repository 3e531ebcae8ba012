"""Physics objects (materials, blocks, supports, loads, damping) and the model."""

from ._model import LinearSystem, Model
from ._physics import Block, Elastic, Load, Rayleigh, Support

__all__ = ["Block", "Elastic", "LinearSystem", "Load", "Model", "Rayleigh", "Support"]
