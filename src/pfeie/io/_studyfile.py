"""The study file: one model, many ground motions, an intensity ladder (TOML).

A study runs one model file under many records, each at several intensities
(:mod:`pfeie.study`). Its file names the model, the records and the intensities::

    title = "Koyna-like dam under a suite of records"
    model = "../koyna/koyna.toml"      # the model's own [[ground_motion]] is not used

    [[records]]                         # one file, or a folder with a pattern
    folder = "records"
    pattern = "*.csv"
    units = "g"
    component = "x"

    [intensity]                         # each record at each value
    measure = "pga"                     # "scale", "pga" (g) or "sa" (Sa(T, ζ) in g)
    values = [0.1, 0.2, 0.3]

    [output]
    folder = "study"

    [run]
    workers = "auto"                    # the default: one process per core (0: serial)

Relative paths are relative to the study file. Every table refuses unknown keys and
non-finite numbers, and an error names the file, the key path and what was expected
(the same messages as the model file, :mod:`pfeie.io._schema`).
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, ValidationError, model_validator

from ..errors import InputError
from ._files import foreign_file, toml_text
from ._schema import PathText, Positive, RecordReading, _check, _found, _Table, problems


class StudyRecords(RecordReading):
    """``[[records]]``: a record file, or every file of a folder that matches a pattern,
    and how to read them (as ``[[ground_motion]]`` of a model file)."""

    file: Annotated[PathText | None, Field(description="a record file")] = None
    folder: Annotated[
        PathText | None, Field(description="a folder of record files (instead of file)")
    ] = None
    pattern: Annotated[
        str, Field(description="file name pattern of the records in folder (glob)")
    ] = "*.AT2"

    @model_validator(mode="after")
    def _one_source(self) -> StudyRecords:
        if self.file is None and self.folder is None:
            raise _check("file", "expected a record file (file = ...) or a folder of them "
                         "(folder = ..., with pattern); found neither")  # fmt: skip
        if self.file is not None and self.folder is not None:
            raise _check("file", "give either file or folder (with pattern), not both")
        if self.file is not None and not str(self.file).strip():
            raise _check("file", "expected the path of a record file, found an empty string")
        return self


class StudyIntensity(_Table):
    """``[intensity]``: the intensities at which every record runs."""

    measure: Annotated[
        Literal["scale", "pga", "sa"],
        Field(description="'scale' (values are scale factors), 'pga' (values in g) or 'sa' "
              "(values are Sa(period, damping) in g)"),
    ] = "scale"  # fmt: skip
    values: Annotated[
        list[Annotated[float, Field(gt=0.0)]],
        Field(min_length=1, description="the intensities, each > 0 and each once (an IDA "
              "ladder: increasing); with measure 'pga' or 'sa' at most 20 g"),
    ] = [1.0]  # fmt: skip  # noqa: RUF012 (pydantic copies defaults)
    period: Annotated[
        Annotated[float, Field(gt=0.0, le=100.0)] | None,
        Field(description="period T1 (s) of Sa: of the 'sa' measure, and of the Sa(T1) column "
              "(default: the model's first period, joints bonded)"),
    ] = None  # fmt: skip
    damping: Annotated[
        float, Field(gt=0.0, lt=1.0, description="damping ratio ζ of Sa")
    ] = 0.05  # fmt: skip


class StudyAnalysis(_Table):
    """``[analysis]``: what a study changes in the model file."""

    duration: Annotated[
        Positive | None,
        Field(description="duration of every run (s); default each record's own length"),
    ] = None
    set: Annotated[
        list[str],
        Field(description="overrides of keys of the model file, as 'KEY=VALUE' with the "
              "value in TOML (as pfeie run --set), e.g. 'analysis.dt=0.02'"),
    ] = []  # fmt: skip  # noqa: RUF012 (pydantic copies defaults)


class StudyOutput(_Table):
    """``[output]``: where the table goes and what else is kept."""

    folder: Annotated[PathText, Field(description="output folder")] = "study"
    histories: Annotated[
        bool,
        Field(
            description="also keep every run's results file (runs/<record>_<intensity>/results.h5)"
        ),
    ] = False
    parquet: Annotated[
        bool, Field(description="write the table as Parquet (needs pyarrow) beside the CSV")
    ] = True


#: the largest number of worker processes of ``run.workers`` (as ``pfeie study --workers``
#: and :class:`pfeie.study.Study`)
MAX_WORKERS = 4096

#: the runs a worker steps together by default (``run.batch``; where the system gains
#: from it, :func:`pfeie.study._study.run_batch`): eight records of two block columns
#: each make a block of sixteen, per column 0.19 of a lone column's cost at 49k DOF
BATCH = 8

#: the largest ``run.batch``
MAX_BATCH = 64


class StudyRun(_Table):
    """``[run]``: how the runs are spread."""

    workers: Annotated[
        int | Literal["auto"],
        Field(description="worker processes of a local Dask cluster; 'auto': one per core "
              "available to this process (in this process when Dask is not installed, "
              "or with one core or one run to do); 0 runs every record in this process, "
              "one after the other"),
    ] = "auto"  # fmt: skip
    scheduler: Annotated[
        str | None,
        Field(description="address of a running Dask scheduler (e.g. 'tcp://host:8786'), "
              "instead of a local cluster"),
    ] = None  # fmt: skip
    batch: Annotated[
        int,
        Field(ge=1, le=MAX_BATCH,
              description="the runs a worker steps together, their block solves made in one "
              "call a step (each run's row the same bits as alone; only where the system "
              "gains from it, 20,000 DOF and more); 1 runs them one after the other"),
    ] = BATCH  # fmt: skip

    @model_validator(mode="before")
    @classmethod
    def _workers(cls, data: object) -> object:
        """``workers``: a whole number in [0, 4096] or "auto" (one message, not one per
        member of the union)."""
        if isinstance(data, dict) and "workers" in data:
            w = data["workers"]
            if not (w == "auto" or (type(w) is int and 0 <= w <= MAX_WORKERS)):
                found = repr(w) if type(w) is int else _found(w)
                raise _check("workers", f"expected an integer in [0, {MAX_WORKERS}] or "
                             f"'auto', found {found}")  # fmt: skip
        return data


class StudyLimitState(_Table):
    """``[[limit_states]]``: a limit state for the fragility curves: a demand column of
    the table against a threshold."""

    name: Annotated[str, Field(min_length=1, description="name of the limit state")]
    demand: Annotated[
        str, Field(min_length=1, description="column of the table, e.g. "
                   "'joint.neck.residual_slip_max_m'"),
    ]  # fmt: skip
    threshold: Annotated[float, Field(description="threshold of the demand (its units)")]
    exceed: Annotated[
        Literal["above", "below"],
        Field(description="the state is reached when the demand is 'above' (slip, opening) "
              "or 'below' (a safety factor) the threshold"),
    ] = "above"  # fmt: skip


class StudyFile(_Table):
    """A study file: one model, many records, an intensity ladder."""

    title: Annotated[str, Field(description="title of the study")] = ""
    model: Annotated[PathText, Field(description="the model file (TOML)")]
    records: Annotated[list[StudyRecords], Field(min_length=1, description="the records")]
    intensity: StudyIntensity = StudyIntensity()
    analysis: StudyAnalysis = StudyAnalysis()
    output: StudyOutput = StudyOutput()
    run: StudyRun = StudyRun()
    limit_states: Annotated[
        list[StudyLimitState], Field(description="limit states of the fragility curves")
    ] = []  # fmt: skip  # noqa: RUF012 (pydantic copies defaults)


def read_study_file(path: str | Path) -> StudyFile:
    """Read and validate a study file; :class:`InputError` names the file, the key path,
    what was expected and what was found."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: study file not found")
    raw = p.read_bytes()
    try:
        data = tomllib.loads(toml_text(p, raw))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        kind = foreign_file(p, raw)
        if kind is not None:
            msg = f"{p}: expected a study file (.toml); this looks like {kind}"
            raise InputError(msg) from None
        raise InputError(f"{p}: not valid TOML: {exc}") from None
    if "mesh" in data and "model" not in data and "records" not in data:
        # a model file given to pfeie study: one line, not an error for every table
        raise InputError(f"{p}: expected a study file; this is a model file ([mesh], no "
                         "model = or [[records]]): run it with `pfeie run`, or write a "
                         "study file whose model = names it (docs/study.md)")  # fmt: skip
    try:
        return StudyFile.model_validate(data)
    except ValidationError as exc:
        raise InputError("\n".join(f"{p}: {pb.key}: {pb.text}"
                                   for pb in problems(exc, data, StudyFile))) from None  # fmt: skip


__all__ = ["StudyFile", "StudyIntensity", "StudyLimitState", "StudyRecords", "read_study_file"]
