"""Studies over many ground motions: one model, many records and intensities.

The factorised system is built once per process and shared by every record of that
process; the per-record demands (peak and residual slip, opening, safety factors,
stresses) go into one table (:class:`StudyTable`); runs go one after the other or on
Dask (a local cluster of processes, or a scheduler's workers); a killed study resumes
where it stopped. From the table: IDA curves (:func:`ida_curves`, :func:`ida_summary`)
and lognormal fragility functions per limit state (:func:`fit_limit_states`,
docs/fragility.md).
"""

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
from ._report import median_lines, run_label, warning_line
from ._study import RecordSource, RunSpec, Study
from ._table import StudyTable

__all__ = ["Exceedance", "Fragility", "IDACurves", "IDASummary", "LimitState", "RecordSource",
           "RunSpec", "Stripes", "Study", "StudyTable", "first_exceedance", "fit_censored",
           "fit_ida", "fit_limit_states", "fit_moments", "fit_stripes", "ida_curves",
           "ida_summary", "median_lines", "run_label", "warning_line"]  # fmt: skip
