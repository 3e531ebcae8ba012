"""Physics objects (materials, blocks, joints, supports, loads, ground motion, damping),
the model with its checks of values in a probable wrong unit, and the response spectra
and intensity measures of records."""

from ._frames import BodyFrames
from ._ground import G_UNITS, RECORD_DT_COARSE, RECORD_DT_MAX, GroundMotion, direction_label
from ._model import LinearSystem, Model
from ._physics import DAMPING_RATIO_MAX, Block, Elastic, Interface, Load, Rayleigh, Support
from ._plausible import (
    STIFFNESS_MIN,
    STRENGTH_MIN,
    implausible_gravity,
    implausible_joints,
    implausible_materials,
    implausible_mesh,
    implausible_silt,
    implausible_water,
    locking_cells,
    radians_meant,
    warn_implausible,
)
from ._reservoir import Reservoir
from ._spectrum import (
    INTENSITY_MEASURES,
    ResponseSpectrum,
    intensity_measures,
    response_spectrum,
    sdof_response,
)
from ._uplift import SHAKING, Stations, Uplift, uplift_force

__all__ = [
    "DAMPING_RATIO_MAX", "G_UNITS", "INTENSITY_MEASURES", "RECORD_DT_COARSE", "RECORD_DT_MAX",
    "SHAKING", "STIFFNESS_MIN", "STRENGTH_MIN", "Block",
    "BodyFrames",
    "Elastic", "GroundMotion", "Interface", "LinearSystem", "Load", "Model", "Rayleigh",
    "Reservoir", "ResponseSpectrum", "Stations", "Support",
    "Uplift", "direction_label", "implausible_gravity", "implausible_joints",
    "implausible_materials",
    "implausible_mesh",
    "implausible_silt",
    "implausible_water",
    "intensity_measures", "locking_cells", "radians_meant", "response_spectrum", "sdof_response",
    "uplift_force", "warn_implausible",
]  # fmt: skip
