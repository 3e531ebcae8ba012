"""Input and output: gmsh meshes, ground-motion records, model files."""

from ._checkpoint import (
    CheckpointWriter,
    NothingToResume,
    history,
    reopen_results,
    resumable,
    run_key,
    same_run,
)
from ._export import export_csv
from ._files import PYTHON_RUN, output_file, output_folder, utf8_text
from ._gmsh import from_gmsh, read_mesh
from ._modelfile import (
    MAX_PGA_G,
    Job,
    ModelFile,
    Override,
    json_schema,
    load_job,
    parse_override,
    parse_value,
    read_model_file,
    reference_markdown,
    reference_rows,
)
from ._paraview import write_modes, write_paraview
from ._records import (
    TIME_GAP,
    abrupt_end,
    applied_part,
    coarse_sampling,
    coarse_step,
    implausible_pga,
    read_record,
    time_gaps,
    write_at2,
)
from ._results import Results, ResultsWriter
from ._schema import yield_label
from ._studyfile import BATCH, MAX_BATCH, MAX_WORKERS, StudyFile, read_study_file

__all__ = [
    "BATCH",
    "MAX_BATCH",
    "MAX_PGA_G",
    "MAX_WORKERS",
    "PYTHON_RUN",
    "TIME_GAP",
    "CheckpointWriter",
    "Job",
    "ModelFile",
    "NothingToResume",
    "Override",
    "Results",
    "ResultsWriter",
    "StudyFile",
    "abrupt_end",
    "applied_part",
    "coarse_sampling",
    "coarse_step",
    "export_csv",
    "from_gmsh",
    "history",
    "implausible_pga",
    "json_schema",
    "load_job",
    "output_file",
    "output_folder",
    "parse_override",
    "parse_value",
    "read_mesh",
    "read_model_file",
    "read_record",
    "read_study_file",
    "reference_markdown",
    "reference_rows",
    "reopen_results",
    "resumable",
    "run_key",
    "same_run",
    "time_gaps",
    "utf8_text",
    "write_at2",
    "write_modes",
    "write_paraview",
    "yield_label",
]  # fmt: skip
