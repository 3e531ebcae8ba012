"""Studies over many ground motions: one model, many records and intensities.

The factorised system is built once per process and shared by every record of that
process; the per-record demands (peak and residual slip, opening, safety factors,
stresses) go into one table (:class:`StudyTable`); runs go one after the other or on
Dask (a local cluster of processes, or a scheduler's workers); a killed study resumes
where it stopped.
"""

from ._study import RecordSource, RunSpec, Study
from ._table import StudyTable

__all__ = ["RecordSource", "RunSpec", "Study", "StudyTable"]
