"""Physics objects (materials, blocks, joints, supports, loads, ground motion, damping)
and the model."""

from ._frames import BodyFrames
from ._ground import GroundMotion
from ._model import LinearSystem, Model
from ._physics import Block, Elastic, Interface, Load, Rayleigh, Support

__all__ = [
    "Block", "BodyFrames", "Elastic", "GroundMotion", "Interface", "LinearSystem", "Load",
    "Model", "Rayleigh", "Support",
]  # fmt: skip
