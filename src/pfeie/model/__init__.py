"""Physics objects (materials, blocks, joints, supports, loads, ground motion, damping)
and the model."""

from ._ground import GroundMotion
from ._model import LinearSystem, Model
from ._physics import Block, Elastic, Interface, Joint, Load, Rayleigh, Support

__all__ = [
    "Block", "Elastic", "GroundMotion", "Interface", "Joint", "LinearSystem", "Load", "Model",
    "Rayleigh", "Support",
]  # fmt: skip
