"""Studies over many ground motions: one model, many records and intensities.

The factorised system is built once and shared by every record; the per-record demands
(peak and residual slip, opening, safety factors, stresses) go into one table; incremental
dynamic analysis (IDA) curves and fragility functions are fitted from it.
"""

__all__: list[str] = []

from ._fragility import (
    Fragility,
    fit_censored,
    fit_ida,
    fit_limit_states,
    fit_moments,
    fit_stripes,
)
from ._ida import (
    Exceedance,
    IDACurves,
    IDASummary,
    LimitState,
    Stripes,
    first_exceedance,
    ida_curves,
    ida_summary,
)

__all__ += ["Exceedance", "Fragility", "IDACurves", "IDASummary", "LimitState", "Stripes",
            "first_exceedance", "fit_censored", "fit_ida", "fit_limit_states", "fit_moments",
            "fit_stripes", "ida_curves", "ida_summary"]  # fmt: skip
