"""Time integration of the blocks, and the PFE/IE analysis that couples it to the
interfaces through :mod:`pfeie.coupling`.

- the integrators, knowing nothing of pairs: :class:`NonsmoothAlpha` (the default
  nonsmooth generalised-α's smooth part), :class:`MoreauJean` (the θ-method) and
  :class:`Newmark` (Newmark / HHT-α / generalised-α, for models without interfaces; with
  :class:`SecondOrderSystem`, :class:`State`, :class:`History`);
- :class:`Dynamic`: the analysis of a model, factorised once, run for any number of
  records (:meth:`Dynamic.run`), with its :class:`DynamicSettings`;
- its parts: :class:`Excitation` (relative or absolute ground motion),
  :class:`Corotation` (body frames for large rotations), :class:`Recorder` and
  :class:`EnergyAccount` (histories and the energy balance), giving a :class:`DynamicResult`.
"""

from ._corotation import Corotation
from ._driver import (
    CORRECTION_UNRESOLVED,
    ENERGY_FLOOR,
    Checkpoint,
    Dynamic,
    RunStopped,
    StepState,
)
from ._excitation import Excitation, shorter_than_a_step
from ._moreau import MoreauJean
from ._newmark import (
    History,
    MatrixSystem,
    Newmark,
    SecondOrderSystem,
    State,
    damping_product,
    factorize_step,
)
from ._nsga import NonsmoothAlpha
from ._recorder import (
    CID_LIMIT,
    DCR_KEYS,
    DCR_LIMIT,
    ENVELOPE_KEYS,
    OVERSTRESSED_LIMIT,
    DynamicResult,
    EnergyAccount,
    Recorder,
    StressEnvelope,
    demand_capacity,
    envelope_extremes,
)
from ._settings import DynamicSettings

__all__ = [
    "CID_LIMIT",
    "CORRECTION_UNRESOLVED",
    "DCR_KEYS",
    "DCR_LIMIT",
    "ENERGY_FLOOR",
    "ENVELOPE_KEYS",
    "OVERSTRESSED_LIMIT",
    "Checkpoint",
    "Corotation",
    "Dynamic",
    "DynamicResult",
    "DynamicSettings",
    "EnergyAccount",
    "Excitation",
    "History",
    "MatrixSystem",
    "MoreauJean",
    "Newmark",
    "NonsmoothAlpha",
    "Recorder",
    "RunStopped",
    "SecondOrderSystem",
    "State",
    "StepState",
    "StressEnvelope",
    "damping_product",
    "demand_capacity",
    "envelope_extremes",
    "factorize_step",
    "shorter_than_a_step",
]  # fmt: skip
