"""Property-based fuzzing (Hypothesis) of the model-file loader, the mesh reader, the
record readers and the command line (random subcommands, options and values):
every input ends in success or in pfeie's typed error (:class:`PfeieError`, exit 2 with a
``pfeie: error`` line through the command line), never in another exception.

The default tests run a fixed, derandomised budget (deterministic); ``make test-slow``
runs a longer one."""

from __future__ import annotations

import contextlib
import io
import json
import math
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pfeie.cli import main
from pfeie.errors import PfeieError
from pfeie.io import Override, load_job, read_mesh, read_record, reference_rows

HERE = Path(__file__).resolve().parent
MESH = HERE / "data" / "two_blocks_v41.msh"

BASE = f"""
title = "fuzz"
[mesh]
file = "{MESH}"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
friction_angle = 30.0
[[supports]]
group = "bottom"
[loads]
[[loads.pressure]]
group = "bottom"
value = 1e5
[[loads.hydrostatic]]
groups = ["bottom"]
water_level = 1.5
[[ground_motion]]
file = "pulse.csv"
units = "g"
[analysis]
dt = 0.01
[output]
folder = "out"
probes = {{ top = [1.0, 2.0] }}
"""

FAST = settings(max_examples=40, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
LONG = settings(max_examples=1500, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow])  # fmt: skip

_NAMES = {"<name>": None}
# the keys of a model file, with <name> and [] bound to what the base file has
KEYS = sorted({
    r.key.replace("materials.<name>", "materials.concrete")
    .replace("interfaces.<name>", "interfaces.joint").replace("blocks.<name>", "blocks.dam")
    .replace("output.probes.<name>", "output.probes.top").replace("[]", "[0]")
    for r in reference_rows()
} | {"blocks.dam", "output.probes.top", "loads.pressure[0]", "ground_motion[0]",
     "analysis", "mesh", "loads", "supports[1].group", "materials.steel.E"})  # fmt: skip

SPECIAL = st.sampled_from([
    0, 0.0, -1, -0.0, 1, 1e-320, 1e308, 1.7e308, 2**63, -(2**63), math.inf, -math.inf, math.nan,
    "g", "m/s2", "x", "z", "at2", "one-column", "stress", "strain", "relative", "absolute",
    "slip-weakening", "intact", "broken", "bottom", "joint", "dam", "rock", "concrete", "",
    "pulse.csv", "none.csv", "..", "/", "a\x00b", "moreau-jean", "newmark", "auto",
    [0.0, 0.0], [1.0, 0.0], [0.0, -1.0, 0.0], [math.nan, 1.0], [1e308, 1e308], [], [[1]],
])  # fmt: skip
SCALAR = st.one_of(
    SPECIAL, st.floats(allow_nan=True, allow_infinity=True), st.integers(-(10**30), 10**30),
    st.booleans(), st.text(max_size=6),
)
VALUE = st.one_of(
    SCALAR, st.lists(SCALAR, max_size=4),
    st.dictionaries(st.sampled_from(["E", "file", "group", "x", "value"]), SCALAR, max_size=2),
)


@pytest.fixture(scope="module")
def base(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("fuzz")
    (d / "pulse.csv").write_text("time,acc\n0,0\n0.1,0.2\n0.2,-0.1\n0.3,0\n")
    p = d / "model.toml"
    p.write_text(BASE)
    assert load_job(p).model.n_bodies == 2  # the base file is valid
    return p


def _load(path: Path, pairs: list[tuple[str, Any]]) -> None:
    """Load with the overrides; a job that loads must also give its summary and steps."""
    try:
        job = load_job(path, [Override(k, v, f"--set {k}=...") for k, v in pairs])
        job.summary()
        _ = job.folder, job.n_steps, job.analysis.newmark()
    except PfeieError as exc:
        assert str(exc).strip()


def toml_value(v: Any) -> str:
    """A value as TOML text (for ``--set KEY=VALUE``)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        return ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string: the same escapes
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return "{" + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + "}"


def _check_cli(path: Path, pairs: list[tuple[str, Any]]) -> None:
    """``pfeie check --set KEY=VALUE ...``: exit 0, or 2 with ``pfeie: error`` lines."""
    argv = ["check", str(path)]
    for k, v in pairs:
        argv += ["--set", f"{k}={toml_value(v)}"]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    assert code in (0, 2), (code, err.getvalue())
    if code == 2:
        assert err.getvalue().startswith("pfeie: error"), err.getvalue()


def _model_file_case(budget: settings) -> Callable[[Path], None]:
    @budget
    @given(pairs=st.lists(st.tuples(st.sampled_from(KEYS), VALUE), min_size=1, max_size=3))
    @example(pairs=[("output.folder", "o\x00ut")])  # found: a ValueError from the OS
    @example(pairs=[("mesh.file", "a\x00b")])
    @example(pairs=[("mesh.file", "pulse.csv")])  # found: meshio.read exits the process
    @example(pairs=[("analysis.duration", 1e300)])
    @example(pairs=[("analysis.dt", 1e-320)])  # found: steps of the records' duration
    @example(pairs=[("ground_motion[0].scale", 1e308)])
    @example(pairs=[("ground_motion[0].direction", [1e308, 1e308])])
    @example(pairs=[("loads.pressure[0].group", "joint")])
    @example(pairs=[("plane", "stress"), ("thickness", 0.5)])
    def case(base: Path, pairs: list[tuple[str, Any]]) -> None:
        _load(base, pairs)
        _check_cli(base, pairs)

    return case  # type: ignore[no-any-return]


_TOKENS = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, width=32).map(lambda x: f"{x:.6g}"),
    st.sampled_from(["1e400", "-1e999", "nan", "inf", "1.0E-02-5.0E-03", "1d-3", "0", ",",
                     ";", "NPTS=", "DT=", "3", "0.01", "SEC", "g", "#", "..", "1e", "+-1",
                     "\t", "NPTS, DT", "UNITS OF G"]),
    st.text(max_size=4),
)  # fmt: skip
_LINES = st.lists(st.lists(_TOKENS, max_size=5).map(" ".join), max_size=8)
_FIELD = st.one_of(st.sampled_from(["4", "0.01", "1e400", "..", "-1", "0", "1e", "+", "3.5"]),
                   st.text(alphabet="0123456789.eE+-", max_size=5))  # fmt: skip
_HEADER = st.one_of(
    st.sampled_from([[], ["time,acc"]]),
    st.tuples(_FIELD, _FIELD).map(lambda f: ["PEER", "t", "ACCELERATION IN UNITS OF G",
                                             f"NPTS= {f[0]}, DT= {f[1]} SEC"]),
    st.tuples(_FIELD, _FIELD).map(lambda f: ["PEER", "t", "IN UNITS OF G",
                                             f"{f[0]}   {f[1]}   NPTS, DT"]),
)  # fmt: skip


def _record_case(budget: settings) -> Callable[[], None]:
    @budget
    @given(
        head=_HEADER, lines=_LINES, raw=st.one_of(st.none(), st.binary(max_size=64)),
        suffix=st.sampled_from([".at2", ".csv", ".txt"]),
        fmt=st.sampled_from(["auto", "at2", "two-column", "one-column", "bogus"]),
        units=st.sampled_from([None, "g", "m/s2", "cm/s2", "furlongs"]),
        dt=st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True)),
        scale=st.one_of(st.just(1.0), st.floats(allow_nan=True, allow_infinity=True)),
        baseline=st.booleans(),
    )  # fmt: skip
    @example(head=["PEER", "t", "IN UNITS OF G", "NPTS= 2, DT= .. SEC"], lines=["0.1 0.2"],
             raw=None, suffix=".at2", fmt="auto", units=None, dt=None, scale=1.0,
             baseline=False)  # found: a ValueError on the DT of the header
    @example(head=["t,a"], lines=["0 0", "1e400 1"], raw=None, suffix=".csv", fmt="auto",
             units="g", dt=None, scale=1.0, baseline=True)
    def case(head: list[str], lines: list[str], raw: bytes | None, suffix: str, fmt: str,
             units: str | None, dt: float | None, scale: float,
             baseline: bool) -> None:  # fmt: skip
        with tempfile.TemporaryDirectory() as tmp:
            p = Path(tmp) / f"rec{suffix}"
            if raw is None:
                p.write_text("\n".join([*head, *lines]) + "\n")
            else:
                p.write_bytes(raw)
            try:
                gm = read_record(p, fmt=fmt, units=units, dt=dt, scale=scale,
                                 baseline=baseline)  # fmt: skip
            except PfeieError as exc:
                assert str(p) in str(exc) or "ground motion" in str(exc)
            else:
                assert gm.time.size >= 2
                assert all(math.isfinite(x) for x in gm.acceleration)

    return case  # type: ignore[no-any-return]


_MSH = [(HERE / "data" / f"two_blocks_v{v}.msh").read_text().splitlines() for v in (22, 41)]
_EDIT = st.tuples(
    st.integers(0, 10**4), st.sampled_from(["delete", "repeat", "replace"]),
    st.sampled_from(["0", "-1", "99999", "1e400", "nan", "x", "", "2", "$EndNodes", "3 1 2",
                     "$Elements", "1.5"]),
)  # fmt: skip


def _mesh_case(budget: settings) -> Callable[[], None]:
    @budget
    @given(which=st.integers(0, 1), edits=st.lists(_EDIT, min_size=1, max_size=4))
    def case(which: int, edits: list[tuple[int, str, str]]) -> None:
        """A gmsh file with lines deleted, repeated, or a field replaced: read, or a
        MeshError naming the file."""
        lines = list(_MSH[which])
        for i, op, token in edits:
            i %= len(lines)
            if op == "delete" and len(lines) > 1:
                del lines[i]
            elif op == "repeat":
                lines.insert(i, lines[i])
            else:
                fields = lines[i].split() or [""]
                fields[i % len(fields)] = token
                lines[i] = " ".join(fields)
        with tempfile.TemporaryDirectory() as tmp:
            p = Path(tmp) / "m.msh"
            p.write_text("\n".join(lines) + "\n")
            try:
                mesh = read_mesh(p)
            except PfeieError as exc:
                assert str(p) in str(exc)
            else:
                assert mesh.n_cells > 0 and np.all(np.isfinite(mesh.points))

    return case  # type: ignore[no-any-return]


_TOKENS = st.sampled_from([
    "--duration", "--dt", "--set", "--quiet", "--resume", "--out", "--csv", "--json", "-o",
    "-v", "--help", "0", "-1", "nan", "inf", "1e400", "0.05", "1e-9", "analysis.dt=0.02",
    "analysis.dt=-1", "analysis=1", "x", "", "=", "MODEL", "RESULTS", "none.toml", "none.h5",
    "out2", "/", "a\x00b",
])  # fmt: skip


def _cli_case(budget: settings) -> Callable[..., None]:
    @budget
    @given(command=st.sampled_from(["run", "check", "plot", "report", "export", "schema", "zz"]),
           rest=st.lists(_TOKENS, max_size=5))  # fmt: skip
    def case(command: str, rest: list[str], cli_dir: tuple[Path, Path]) -> None:
        """``pfeie COMMAND ...`` with random options and values (the model file, a results
        file, missing files, bad numbers): exit 0, 1 or 2 (argparse's own exit 2
        included), never another exception."""
        model, results = cli_dir
        argv = [command] + [{"MODEL": str(model), "RESULTS": str(results)}.get(t, t)
                            for t in rest]  # fmt: skip
        if command in ("run", "check") and "MODEL" not in rest:
            argv.insert(1, str(model))
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
                code = exc.code if isinstance(exc.code, int) else 2
        assert code in (0, 1, 2), (argv, code, err.getvalue())
        if code == 2 and "usage:" not in err.getvalue():
            assert "pfeie: error" in err.getvalue(), (argv, err.getvalue())
        assert "Traceback" not in err.getvalue()

    return case  # type: ignore[no-any-return]


@pytest.fixture(scope="module")
def cli_dir(base: Path) -> tuple[Path, Path]:
    """The fuzz model (a short run) and a results file of it."""
    d = base.parent
    text = base.read_text().replace("dt = 0.01", "dt = 0.05\nduration = 0.1")
    model = d / "cli.toml"
    model.write_text(text.replace('folder = "out"', 'folder = "cli_out"'))
    assert main(["run", str(model), "--quiet"]) == 0
    return model, d / "cli_out" / "results.h5"


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # --out and -o with relative paths write here


STUDY_KEYS = [
    "title", "model", "records", "records[0].file", "records[0].folder", "records[0].pattern",
    "records[0].format", "records[0].units", "records[0].dt", "records[0].component",
    "records[0].direction", "records[0].baseline", "records[1].file", "intensity",
    "intensity.measure", "intensity.values", "intensity.period", "intensity.damping",
    "analysis.duration", "analysis.set", "output.folder", "output.histories",
    "output.parquet", "run.workers", "run.scheduler", "limit_states[0].name",
    "limit_states[0].demand", "limit_states[0].threshold", "limit_states[0].exceed", "bogus",
]  # fmt: skip
STUDY_VALUES = st.one_of(VALUE, st.sampled_from([
    "model.toml", "pulse.csv", ".", "*.csv", "sa", "pga", "scale", [0.1, 0.2], [1e308],
    ["analysis.dt=0.02"], ["analysis.dt=-1"], ["x"], ["analysis.dt"],
]))  # fmt: skip


def _dump(d: dict[str, Any]) -> str:
    """A study file's data as TOML: scalars, then tables, then arrays of tables."""
    out = [f"{k} = {toml_value(v)}" for k, v in d.items()
           if not isinstance(v, dict) and not (isinstance(v, list) and v
                                               and all(isinstance(x, dict) for x in v))]
    for k, v in d.items():
        if isinstance(v, dict):
            out += [f"[{k}]"] + [f"{a} = {toml_value(b)}" for a, b in v.items()]
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for x in v:
                out += [f"[[{k}]]"] + [f"{a} = {toml_value(b)}" for a, b in x.items()]
    return "\n".join(out) + "\n"


def _set(d: dict[str, Any], key: str, value: Any) -> None:
    """Set ``records[0].file``-like keys in nested data (skipped where a part is not a
    table or an array of tables)."""
    node: Any = d
    parts = [p for part in key.split(".") for p in part.replace("]", "").split("[")]
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if part.isdigit():
            if not isinstance(node, list):
                return
            k = int(part)
            while len(node) <= k:
                node.append({})
            if last:
                node[k] = value
            node = node[k]
        else:
            if not isinstance(node, dict):
                return
            if last:
                node[part] = value
            else:
                node = node.setdefault(part, [] if parts[i + 1].isdigit() else {})


def _study_case(budget: settings) -> Callable[[Path], None]:
    @budget
    @given(pairs=st.lists(st.tuples(st.sampled_from(STUDY_KEYS), STUDY_VALUES), min_size=1,
                          max_size=3))  # fmt: skip
    @example(pairs=[("records[0].folder", ".")])  # a folder and a file
    @example(pairs=[("analysis.set", ["analysis.dt"])])
    @example(pairs=[("intensity.measure", "sa"), ("intensity.period", 1e308)])
    def case(base: Path, pairs: list[tuple[str, Any]]) -> None:
        """A study file with random keys and values: its runs are set up (model, records,
        T1, scale factors, keys), or a PfeieError names the file; never another error."""
        from pfeie.study import Study

        data: dict[str, Any] = {
            "model": "model.toml", "records": [{"file": "pulse.csv", "units": "g"}],
            "intensity": {"measure": "pga", "values": [0.1, 0.2]},
            "analysis": {"duration": 0.1}, "output": {"folder": "study"},
        }  # fmt: skip
        for k, v in pairs:
            _set(data, k, v)
        p = base.parent / "study.toml"
        p.write_text(_dump(data))
        try:
            runs = Study.from_file(p).runs()
        except PfeieError as exc:
            assert str(exc).strip()
        else:
            assert runs and all(math.isfinite(r.factor) and r.factor > 0 for r in runs)

    return case  # type: ignore[no-any-return]


test_study_fuzz = _study_case(settings(FAST, max_examples=30))
test_study_fuzz_long = pytest.mark.slow(_study_case(settings(LONG, max_examples=400)))
test_cli_fuzz = _cli_case(settings(FAST, max_examples=25))
test_cli_fuzz_long = pytest.mark.slow(_cli_case(settings(LONG, max_examples=400)))
test_model_file_fuzz = _model_file_case(FAST)
test_mesh_fuzz = _mesh_case(FAST)
test_mesh_fuzz_long = pytest.mark.slow(_mesh_case(LONG))
test_record_fuzz = _record_case(FAST)
test_model_file_fuzz_long = pytest.mark.slow(_model_file_case(LONG))
test_record_fuzz_long = pytest.mark.slow(_record_case(LONG))


def test_fuzz_can_fail(base: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The property is not vacuous: an exception that is not a PfeieError escapes it."""
    import pfeie.io._modelfile as mf

    def boom(*_a: Any, **_k: Any) -> Any:
        raise ZeroDivisionError("bug")

    monkeypatch.setattr(mf, "read_mesh", boom)
    with pytest.raises(ZeroDivisionError):
        _load(base, [("title", "x")])
