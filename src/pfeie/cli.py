"""The command line: ``pfeie run``, ``check``, ``modal``, ``spectrum``, ``study``, ``plot``,
``export``, ``report``, ``verify``, ``schema``, ``pfeie --version``.

``run`` and ``check`` take settings that override the model file's (``--duration``,
``--dt``, ``--set KEY=VALUE``, the value parsed as TOML); they are validated by the
same typed settings as the file, and an invalid one is an input error naming the option.

Exit codes:

- 0: success;
- 1: the analysis failed (a mechanism in statics, an interface step that did not
  converge); the results computed so far are written; for ``check``, a model whose static
  state cannot be solved (a block that no support or joint holds);
- 2: invalid input (model file, mesh, record, command-line arguments);
- 130: interrupted (Ctrl-C or SIGTERM); the results computed so far are written;
- 141: the reader of the output closed it (``| head``); no traceback.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Literal, NoReturn

from ._version import __version__
from .errors import InputError, MechanismError, MeshError, PfeieError, RecordError, ResultsError

if TYPE_CHECKING:
    from .io import Override

EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130
#: the reader of the output closed it (``pfeie check model.toml | head``): 128 + SIGPIPE,
#: what a shell reports for a command stopped that way
EXIT_PIPE = 141


class _Parser(argparse.ArgumentParser):
    """argparse with pfeie's error line, ``pfeie: error: run: the following arguments are
    required: model`` after the usage (exit 2), as every other input error."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        sub = self.prog.removeprefix("pfeie").strip()
        self.exit(EXIT_INPUT, f"pfeie: error: {sub + ': ' if sub else ''}{message}\n")


def _parser() -> argparse.ArgumentParser:
    ap = _Parser(
        prog="pfeie",
        description="Dynamic analysis of jointed structures by the PFE/IE method.",
        epilog="Exit codes: 0 success, 1 analysis failed, 2 invalid input (or results file), "
        "130 interrupted, 141 the reader of the output closed it (| head).",
    )
    ap.add_argument("--version", action="version", version=f"pfeie {__version__}")
    ap.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")
    run = sub.add_parser(
        "run",
        help="run a model file (static state, then the earthquake)",
        description="Run a model file: the static state, then the dynamic "
        "analysis; writes results.h5, summary.json and summary.txt (and the ParaView "
        "series) to the output folder. Ctrl-C stops cleanly and keeps what was computed; "
        "--resume continues from the last checkpoint (written every 30 s and at the end).",
    )
    run.add_argument("model", help="model file (TOML)")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.add_argument("--resume", action="store_true", help="continue a stopped run from the "
                     "checkpoint in its results file (same model file and --set options; a "
                     "longer --duration extends a completed run)")  # fmt: skip
    chk = sub.add_parser("check", help="validate a model file and print its summary",
                         description="Validate a model file (mesh, groups, records) and print "
                         "the model summary: blocks, DOF, pairs per interface, records, "
                         "estimated memory.")  # fmt: skip
    chk.add_argument("model", help="model file (TOML)")
    chk.add_argument("--json", action="store_true", help="print the summary as JSON")
    mod = sub.add_parser(
        "modal", help="natural frequencies, effective modal masses and mode shapes",
        description="Modal analysis of a model file with its joints bonded (default) or "
        "free, with the added mass of its reservoirs ([[loads.westergaard]]; default) or "
        "without it (--dry): prints mode, frequency, period and the effective modal mass "
        "along each axis (share of the free mass, and cumulative), and which mass it used; "
        "writes modes.csv and the mode shapes as a ParaView series (modes.xdmf, one frame "
        "per mode) to the output folder.",
    )  # fmt: skip
    mod.add_argument("model", help="model file (TOML)")
    mod.add_argument("-n", "--modes", type=int, default=10, metavar="N",
                     help="number of modes (default 10)")  # fmt: skip
    mod.add_argument(
        "--interfaces",
        choices=["bonded", "free"],
        default="bonded",
        help="joints bonded (default) or free (their springs, if any, ignored)",
    )
    mod.add_argument("--dry", action="store_true", help="without the reservoirs' added mass "
                     "(the structure alone; default: with it, the wet modes)")  # fmt: skip
    mod.add_argument("--out", metavar="DIR", help="output folder (default: output.folder)")
    for p in (run, chk, mod):
        p.add_argument("--duration", metavar="T", help="duration (s), instead of "
                       "analysis.duration (> 0)")  # fmt: skip
        p.add_argument("--dt", metavar="DT", help="time step (s), instead of analysis.dt (> 0)")
        p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       dest="settings", help="override a key of the model file, the value "
                       "in TOML (repeatable), e.g. --set analysis.alpha=-0.1")  # fmt: skip
    spc = sub.add_parser(
        "spectrum", help="elastic response spectra and intensity measures of records",
        description="Elastic response spectra of a record file (AT2, CSV) or of the "
        "records of a model file (as scaled by scale, pga or target_sa): writes "
        "spectrum.csv (T, Sd, PSv, PSa, peak absolute acceleration; SI units; "
        "spectrum_<i>.csv for the record ground_motion[i] of a model with several) and "
        "spectrum.png, and prints the intensity measures (PGA, PGV, PGD, Arias intensity, "
        "CAV, D5-95, Sa(T1)). Exact recurrence for the piecewise-linear record.",
    )  # fmt: skip
    spc.add_argument(
        "source",
        metavar="RECORD_OR_MODEL",
        help="record file (.AT2, two or one column) or model file (.toml)",
    )
    spc.add_argument("--damping", default="0.05", metavar="ZETA",
                     help="damping ratio in [0, 1) (default 0.05)")  # fmt: skip
    spc.add_argument("--periods", default="0.02:4:200", metavar="START:STOP:N",
                     help="periods (s): N log-spaced from START to STOP (default 0.02:4:200),"
                     " or a comma-separated list, e.g. 0.1,0.5,1")  # fmt: skip
    spc.add_argument("--t1", metavar="T", help="period (s) of the intensity measure Sa(T1) "
                     "(default: the target_sa period of a model's record, if any)")  # fmt: skip
    spc.add_argument("--units", choices=["g", "m/s2", "cm/s2", "gal"],
                     help="units of a record file that is not AT2 (required for it; an AT2 "
                     "file states its own: given, they must be the same)")  # fmt: skip
    spc.add_argument("--dt", metavar="DT", help="time step of a one-column record file (s)")
    spc.add_argument("-o", "--out", default=".", metavar="DIR",
                     help="output folder (default: the current folder)")  # fmt: skip
    sch = sub.add_parser("schema", help="write the JSON Schema of model files",
                         description="Write the JSON Schema of model files, for editors "
                         "(taplo, Even Better TOML: put '#:schema ./pfeie-model.schema.json' "
                         "at the top of a model file). See docs/model-file.md.")  # fmt: skip
    sch.add_argument("-o", "--output", metavar="FILE", help="output file (default: stdout)")
    post = {
        "plot": ("figures of a results file (PNG)", "Write the figures of a results file: "
                 "the mesh, the input motion, probe histories, joint slip and opening, "
                 "pair-state maps, the joint map, the stress envelope, rigid motions, energy "
                 "(2D and 3D).", ("--out", "output folder (default: figures/ beside the results)")),
        "export": ("tidy CSV tables of a results file", "Write tidy CSV tables (one "
                   "observation per row): probes, bodies, energy, joints, and the final state "
                   "of every pair.", ("--csv", "output folder (required)")),
        "report": ("a self-contained HTML report of a results file", "Write report.html: "
                   "model and record summaries, the figures and a table of joint results.",
                   ("--out", "HTML file (default: report.html beside the results)")),
    }  # fmt: skip
    stu = sub.add_parser(
        "study", help="run a model under many records and intensities (a study file)",
        description="Run a study file: one model under many records, each at the "
        "intensities of a ladder; the factorised system is built once per process. Writes "
        "table.csv (and table.parquet) with one row per record and intensity: intensity "
        "measures and demands; and, with limit states, the IDA and fragility figures. A "
        "study run again skips the runs already done (resume).",
    )  # fmt: skip
    stu.add_argument("study", help="study file (TOML)")
    stu.add_argument(
        "--workers",
        metavar="N|auto",
        help="worker processes of a local Dask cluster; 'auto': one per available core "
        "(in this process when Dask is not installed, or with one core or one run to do); "
        "0: in this process, one after the other (default: the study file's run.workers, "
        "itself 'auto' by default)",
    )
    stu.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask "
        "scheduler, e.g. tcp://host:8786 (instead of a local cluster)",
    )
    stu.add_argument(
        "--batch",
        metavar="N",
        help="the runs a worker steps together, their block solves made in one call a "
        "step (each row the same bits as alone; from 20,000 DOF); 1: one after the other "
        "(default: the study file's run.batch, itself 8 by default)",
    )
    stu.add_argument("--restart", action="store_true", help="run every record again, "
                     "ignoring the rows of runs already done")  # fmt: skip
    stu.add_argument("--quiet", action="store_true", help="no progress line")
    ver = sub.add_parser("verify", help="run the verification suite and print its table",
                         description="Run the verification cases (V1-V11 of the verification "
                         "manual) and print: case, quantity, reference, pfeie, error, "
                         "tolerance, pass. Exits 1 if any check fails.")  # fmt: skip
    ver.add_argument("--fast", action="store_true", help="the fast subset (short runs)")
    ver.add_argument("--case", action="append", metavar="NAME", help="run only this case "
                     "(repeatable), e.g. --case V4")  # fmt: skip
    ver.add_argument("--manual", metavar="DIR", help="also write the manual (pages, figures, "
                     "summary) to DIR")  # fmt: skip
    for name, (short, long, (flag, flag_help)) in post.items():
        p = sub.add_parser(name, help=short, description=long)
        p.add_argument("results", help="results file (results.h5)")
        p.add_argument(flag, required=flag == "--csv", metavar="PATH", help=flag_help)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``pfeie`` command; returns the exit code (:data:`EXIT_PIPE`,
    without a traceback, when the reader of the output closes it)."""
    # SIGINT and SIGTERM stop the command wherever the time stepping (which handles both)
    # is not running: reading, factorising, the static analysis, the yield search (SIGINT
    # too: a process started in the background inherits it ignored)
    old: dict[int, Any] = {}
    if threading.current_thread() is threading.main_thread():
        old = {sig: signal.signal(sig, _interrupt) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        code = _main(argv)
        sys.stdout.flush()  # here, not at exit, where a closed pipe would print a traceback
        return code
    except KeyboardInterrupt as exc:
        why = str(exc) or "SIGINT"
        print(f"pfeie: interrupted ({why})", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # nothing more can be written there: send what Python still holds to /dev/null,
        # so that the flush at exit does not fail again
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return EXIT_PIPE
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)


def _interrupt(signum: int, _frame: object) -> None:
    """A signal handler that stops as Ctrl-C does (the signal's name as the reason)."""
    raise KeyboardInterrupt(signal.Signals(signum).name)


def _main(argv: Sequence[str] | None) -> int:
    ap = _parser()
    try:
        args, extra = ap.parse_known_args(argv)
        if extra:  # with the usage of the command they follow, not the top level's
            sub = next((a for a in ap._actions if isinstance(a, argparse._SubParsersAction)),
                       None)  # fmt: skip
            own = sub.choices.get(args.command) if sub is not None and args.command else None
            (own or ap).error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # argparse: --help, --version (0) or usage errors (2)
        return int(exc.code or 0)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")  # fmt: skip
    if args.command is None:
        ap.print_help(sys.stderr)
        print("pfeie: error: expected a command, e.g. pfeie check model.toml", file=sys.stderr)
        return EXIT_INPUT
    for key, value in vars(args).items():  # no file name can hold a NUL character (the
        # fuzzer's `schema --out 'a\x00b'`: a ValueError traceback from open)
        for v in value if isinstance(value, list) else [value]:
            if isinstance(v, str | os.PathLike) and "\x00" in os.fspath(v):
                print(f"pfeie: error: {args.command}: {key.replace('_', '-')}: {str(v)!r} "
                      "holds a NUL character; expected a file name or a value",
                      file=sys.stderr)  # fmt: skip
                return EXIT_INPUT
    if args.command in ("plot", "export", "report"):
        return _post(args)
    if args.command == "verify":
        return _verify(args)
    if args.command == "schema":
        return _schema(args)
    if args.command == "spectrum":
        return _spectrum(args)
    if args.command == "study":
        return _study(args)
    from ._job import format_summary, run_job
    from .io import load_job

    try:
        job = load_job(args.model, _overrides(args), modal=args.command == "modal")
    except PfeieError as exc:
        return _input_failure(exc, args.model)
    if args.command == "modal":
        return _modal(args, job)
    if args.command == "check":
        from .plot import load_rows

        s = job.summary()
        s["loads"] = load_rows(None, job)
        if args.json:
            print(json.dumps(s, indent=2, default=str))
        else:
            print(_format_check(s))
        unheld = s.get("unsupported") or []
        if unheld and "static state" in (s.get("analyses") or []):
            # `pfeie run` would stop at the static state with this mechanism (exit 1)
            print(f"pfeie: error: {args.model}: the static state cannot be solved: "
                  f"{', '.join(unheld)} has no support and no joint to a supported block "
                  "(add [[supports]], or analysis.static = false for a block that falls "
                  "freely)", file=sys.stderr)  # fmt: skip
            return EXIT_FAILED
        return EXIT_OK
    for line in job.record_lines():
        print(f"record: {line}", file=sys.stderr)
    try:
        summary = run_job(job, progress=not args.quiet, resume=args.resume,
                          resume_with=_resume_command(args))  # fmt: skip
    except (InputError, MeshError, RecordError, ResultsError) as exc:
        # a mesh error met while building the operators names the model file it came from
        where = f"{args.model}: " if isinstance(exc, MeshError) and not str(exc).startswith(
            str(job.path)) else ""  # fmt: skip
        print(f"pfeie: error: {where}{exc}", file=sys.stderr)
        return EXIT_INPUT
    except MechanismError as exc:
        print(f"pfeie: analysis failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except PfeieError as exc:
        print(f"pfeie: analysis failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    print(format_summary(summary))
    print(f"results in {job.folder}")
    stopped = summary.get("stopped")
    if stopped and stopped.startswith("stopped"):
        print(f"pfeie: the run stopped at t = {summary.get('time_reached_s', 0.0):.6g} s; "
              f"{_resume_command(args)} continues it", file=sys.stderr)  # fmt: skip
        return EXIT_INTERRUPTED
    if stopped:
        print(f"pfeie: analysis failed: {stopped}", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


def _resume_command(args: argparse.Namespace) -> str:
    """The command that resumes the run of ``args``: its model file and its options
    (the same settings give the same run key; an extension's own ``--duration``)."""
    import shlex

    words = ["pfeie", "run", args.model, "--resume"]
    for opt in ("duration", "dt"):
        if (text := getattr(args, opt)) is not None:
            words += [f"--{opt}", text]
    for text in args.settings:
        words += ["--set", text]
    return "`" + shlex.join(words) + "`"


def _overrides(args: argparse.Namespace) -> list[Override]:
    """The settings of the command line, in the order they apply (--set last)."""
    from .io import Override, parse_override, parse_value

    out = []
    for opt, key in (("duration", "analysis.duration"), ("dt", "analysis.dt")):
        text = getattr(args, opt)
        if text is not None:
            out.append(Override(key, parse_value(text), f"--{opt} {text}"))
    out += [parse_override(text) for text in args.settings]
    return out


def _schema(args: argparse.Namespace) -> int:
    from .io import json_schema

    text = json.dumps(json_schema(), indent=2, ensure_ascii=False) + "\n"
    if args.output is None:
        sys.stdout.write(text)
        return EXIT_OK
    try:
        with open(args.output, "w", encoding="utf-8") as fh:
            fh.write(text)
    except OSError as exc:
        print(f"pfeie: error: {args.output}: {exc.strerror}", file=sys.stderr)
        return EXIT_INPUT
    print(args.output)
    return EXIT_OK


def _verify(args: argparse.Namespace) -> int:
    from .io import output_folder
    from .verification import run, write_manual

    try:
        if args.manual:  # before the cases run (minutes), not after them
            output_folder(args.manual, "--manual")
        results = run(fast=args.fast, names=args.case)
    except PfeieError as exc:
        print(f"pfeie: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    head = (f"{'case':<5} {'quantity':<46} {'reference':>12} {'pfeie':>12} {'error':>10} "
            f"{'tolerance':>10}  pass")  # fmt: skip
    print(head)
    print("-" * len(head))
    for r in results:
        for c in r.checks:
            print(
                f"{r.name:<5} {c.quantity[:46]:<46} {c.reference:>12.6g} {c.value:>12.6g} "
                f"{c.error_text:>10} {c.tolerance_text:>10}  {'yes' if c.passed else 'NO'}"
            )
    n_fail = sum(not r.passed for r in results)
    print(f"{len(results) - n_fail} of {len(results)} cases pass")
    if args.manual:
        for f in write_manual(results, args.manual, args.fast):
            print(f)
    return EXIT_FAILED if n_fail else EXIT_OK


def _post(args: argparse.Namespace) -> int:
    from pathlib import Path

    if Path(args.results).is_dir():  # the run's output folder: its results file
        args.results = str(Path(args.results) / "results.h5")
    try:
        if args.command == "plot":
            from .plot import plot_run

            out = Path(args.out) if args.out else Path(args.results).parent / "figures"
            files = plot_run(args.results, out)
        elif args.command == "export":
            from .io import export_csv

            if not str(args.csv).strip():
                raise InputError("--csv: expected an output folder, got an empty path")
            files = export_csv(args.results, args.csv)
        else:
            from .plot import write_report

            files = [write_report(args.results, args.out, "--out" if args.out else "")]
    except PfeieError as exc:
        print(f"pfeie: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except (KeyError, IndexError, ValueError, TypeError) as exc:
        if isinstance(exc, UnicodeError):  # (writing, not the file: its own message)
            raise
        # a results file that opens but lacks a dataset or holds damaged values (a file
        # edited, or cut by a copy): said, with what is missing, not a traceback
        print(f"pfeie: error: {args.results}: the results file is incomplete or damaged "
              f"({type(exc).__name__}: {exc}); expected a results.h5 written by pfeie run "
              "(run it again, or resume it with pfeie run --resume)", file=sys.stderr)  # fmt: skip
        return EXIT_INPUT
    except OSError as exc:
        if exc.filename is not None:  # a file written (a figure, a table): the system's word
            print(f"pfeie: error: {exc.filename}: {exc.strerror or exc}", file=sys.stderr)
            return EXIT_INPUT
        # HDF5's read errors: a file that a run still writes (opened with file locking
        # off), or one damaged past its header
        print(f"pfeie: error: {args.results}: reading the results file failed ({exc}); a "
              "file that a run is still writing is read reliably only when the run ends "
              "(HDF5_USE_FILE_LOCKING=FALSE opens it, but the rows being appended may not "
              "read), and a damaged one not at all", file=sys.stderr)  # fmt: skip
        return EXIT_INPUT
    for f in files:
        print(f)
    return EXIT_OK


def _modal(args: argparse.Namespace, job: object) -> int:
    """``pfeie modal``: the table, modes.csv and the ParaView series of the mode shapes."""
    from pathlib import Path

    import numpy as np

    from .io import output_folder, write_modes
    from .solvers import modal

    model = job.model  # type: ignore[attr-defined]
    if not args.modes >= 1:
        print(f"pfeie: error: --modes: expected a number of modes >= 1, got {args.modes}",
              file=sys.stderr)  # fmt: skip
        return EXIT_INPUT
    try:
        res = modal(model, args.modes, interfaces=args.interfaces, added_mass=not args.dry)
        folder = output_folder(Path(args.out) if args.out else job.folder,  # type: ignore[attr-defined]
                               "--out" if args.out else "output.folder")  # fmt: skip
        files = write_modes(res, model, folder)
    except PfeieError as exc:
        print(f"pfeie: error: {args.model}: modal: {exc}", file=sys.stderr)
        return EXIT_INPUT
    axes = "xyz"[: model.dim]
    total = res.total_mass
    damped = bool(np.isfinite(res.damping_ratios).any())
    head = (f"{'mode':>4} {'f (Hz)':>10} {'T (s)':>9} "
            + " ".join(f"{'m_' + a + ' %':>8} {'cum %':>7}" for a in axes)
            + (f" {'zeta %':>7}" if damped else ""))  # fmt: skip
    print(head)
    print("-" * len(head))
    cum = np.cumsum(res.effective_mass, axis=0)
    rigid = res.rigid
    for k, f in enumerate(res.frequencies):
        cols = " ".join(f"{100 * res.effective_mass[k, i] / max(total[i], 1e-300):>8.2f} "
                        f"{100 * cum[k, i] / max(total[i], 1e-300):>7.2f}"
                        for i in range(model.dim))  # fmt: skip
        ft = f"{'rigid':>10} {'-':>9}" if rigid[k] else f"{f:>10.4f} {1 / f:>9.4f}"
        z = res.damping_ratios[k]
        zt = (f" {'-':>7}" if not np.isfinite(z) else f" {100 * z:>7.2f}") if damped else ""
        print(f"{k + 1:>4} {ft} {cols}{zt}")
    if damped:
        d = model.damping
        what = ("the deformation only: no α on the floating blocks' rigid motion"
                if d.deformation_only else "α/(2ω) + βω/2")  # fmt: skip
        print(f"zeta: the Rayleigh damping ratio of each mode, {what} (docs/model-file.md, "
              f"Damping)")  # fmt: skip
    n_res = len(model.reservoirs) + len(model.fe_reservoirs)
    some = f"{n_res} reservoir{'s' if n_res > 1 else ''} ([[loads.westergaard]])"
    if not n_res:
        print("mass: the blocks' only (the model has no reservoir: no [[loads.westergaard]])")
    elif args.dry:
        print(f"mass: dry, the blocks' only, without the added mass of {some} (--dry)")
    else:
        print(f"mass: wet, the blocks' and the added mass of {some}; --dry leaves it out")
    for f in files:
        print(f)
    return EXIT_OK


def _number(option: str, text: str, low: float, high: float = float("inf"),
            closed: bool = False) -> float:  # fmt: skip
    """A number of the command line in [low, high) (``closed``) or (low, high)."""
    try:
        x = float(text)
    except ValueError:
        x = float("nan")
    ok = (low <= x if closed else low < x) and x < high
    if not ok:
        lo = f"[{low:g}" if closed else f"({low:g}"
        raise InputError(f"{option}: expected a number in {lo}, {high:g}), found {text!r}")
    return x


#: the most periods of ``pfeie spectrum --periods START:STOP:N`` (10 million took 85 s and
#: 4.7 GB; a spectrum needs a few hundred)
PERIODS_MAX = 10_000


def _period_list(text: str) -> list[float]:
    """``START:STOP:N`` (N periods log-spaced) or ``T1,T2,...`` (s)."""
    import numpy as np

    expect = ("expected START:STOP:N (N periods log-spaced from START to STOP, "
              f"0 < START < STOP, 2 <= N <= {PERIODS_MAX}) or a comma-separated list of "
              "periods >= 0 s")  # fmt: skip
    try:
        if ":" in text:
            a, b, n = text.split(":")
            lo, hi, count = float(a), float(b), int(n)
            if not (0 < lo < hi < float("inf") and 2 <= count <= PERIODS_MAX):
                raise ValueError
            return [float(x) for x in np.geomspace(lo, hi, count)]
        out = [float(x) for x in text.split(",")]
        if not all(0 <= x < float("inf") for x in out):
            raise ValueError
        return out
    except ValueError:
        raise InputError(f"--periods: {expect}, found {text!r}") from None


def _spectrum(args: argparse.Namespace) -> int:
    """``pfeie spectrum``: spectrum.csv, spectrum.png and the intensity measures."""
    from pathlib import Path

    from .io import applied_part, implausible_pga, load_job, output_folder, read_record
    from .model import INTENSITY_MEASURES, GroundMotion

    try:
        damping = _number("--damping", args.damping, 0.0, 1.0, closed=True)
        periods = _period_list(args.periods)
        t1 = None if args.t1 is None else _number("--t1", args.t1, 0.0)
        src = Path(args.source)
        records: dict[str, tuple[GroundMotion, float | None]] = {}
        parts: dict[str, str] = {}  # the records cut at the run's end: what the line adds
        if src.suffix.lower() == ".toml":
            job = load_job(src)
            targets = [g.get("target_sa") for g in job.spec["ground_motion"]]
            end = job.analysis.duration if job.analysis.dynamic else None
            for i, (rec, tgt) in enumerate(zip(job.records, targets, strict=True)):
                key = "" if len(job.records) == 1 else f"_{i}"
                if end is not None and rec.time[-1] > end:  # the motion the run applies
                    rec = applied_part(rec, end)[0]
                    parts[key] = f" (the motion applied: up to {end:g} s, analysis.duration)"
                records[key] = (rec, t1 if t1 is not None or not tgt else tgt["period"])
        else:
            dt = None if args.dt is None else _number("--dt", args.dt, 0.0)
            records[""] = (read_record(src, units=args.units, dt=dt), t1)
            odd = implausible_pga(src, records[""][0].pga, records[""][0].read_units)
            if odd is not None:
                logging.getLogger("pfeie.cli").warning("%s", odd)
        out = output_folder(args.out, "--out")
        spectra = {}
        for key, (rec, period) in records.items():
            s = rec.spectrum(periods, damping)
            ims = rec.intensity_measures(period, damping)
            spectra[rec.name + key] = s
            print(f"record: {rec.summary()}{parts.get(key, '')}")
            for name, value in ims.items():
                label, unit = INTENSITY_MEASURES[name]
                if name == "sa":
                    label = f"Sa({period:g} s, {100 * damping:g} %)"
                extra = f" ({value / 9.81:.4g} g)" if name in ("pga", "sa") else ""
                print(f"  {label:<22} {value:>12.6g} {unit}{extra}")
            path = out / f"spectrum{key}.csv"
            rows = ["T_s,Sd_m,PSv_m_per_s,PSa_m_per_s2,Sa_abs_m_per_s2"]
            rows += [f"{T:.9g},{d:.9g},{v:.9g},{a:.9g},{b:.9g}" for T, d, v, a, b in
                     zip(s.periods, s.sd, s.psv, s.psa, s.sa_abs, strict=True)]  # fmt: skip
            path.write_text("\n".join(rows) + "\n")
            print(path)
        from .plot import plot_spectrum

        print(plot_spectrum(spectra, out / "spectrum.png", src.name))
    except PfeieError as exc:
        return _input_failure(exc, args.source)
    return EXIT_OK


def _study(args: argparse.Namespace) -> int:
    import signal
    import time

    from .study import Study

    workers: int | Literal["auto"] | None = None
    if args.workers == "auto":
        workers = "auto"
    elif args.workers is not None:
        if not (args.workers.isdigit() and int(args.workers) <= 4096):
            print(f"pfeie: error: --workers: expected a whole number in [0, 4096], found "
                  f"{args.workers!r} (or 'auto': one process per core)",
                  file=sys.stderr)  # fmt: skip
            return EXIT_INPUT
        workers = int(args.workers)
    from .io import MAX_BATCH

    if args.batch is not None and not (args.batch.isdigit()
                                       and 1 <= int(args.batch) <= MAX_BATCH):  # fmt: skip
        print(f"pfeie: error: --batch: expected a whole number in [1, {MAX_BATCH}], found "
              f"{args.batch!r}", file=sys.stderr)  # fmt: skip
        return EXIT_INPUT
    try:
        st = Study.from_file(args.study)
        if args.batch is not None:
            st.batch = int(args.batch)
        st.prepare_folder()
        specs = st.runs()
    except PfeieError as exc:
        return _input_failure(exc, args.study)
    t0 = time.perf_counter()

    tty = sys.stderr.isatty()
    first: list[int] = []  # the runs already done when this command started (resumed)

    def progress(done: int, total: int, row: dict[str, object]) -> None:
        """A bar over the runs on a terminal (one line rewritten), a line a run else:
        runs done, elapsed time, the ETA from this command's pace, the last run."""
        if args.quiet:
            return
        if not first:
            first.append(done - 1)
        el = time.perf_counter() - t0
        eta = el / max(done - first[0], 1) * (total - done)
        width = 24
        fill = width * done // max(total, 1)
        last = (
            f"{row['record']} at {row['intensity']:g} "
            f"({'completed' if row['completed'] else 'STOPPED'}, {row['wall_s']:.1f} s)"
        )
        line = (f"[{'#' * fill}{'.' * (width - fill)}] {done}/{total} runs  elapsed "
                f"{el:.0f} s  ETA {eta:.0f} s  last: {last}")  # fmt: skip
        if tty:
            sys.stderr.write("\r" + line.ljust(110) + ("\n" if done >= total else ""))
        else:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()

    print(f"study: {len(st.records)} records x {len(st.values)} intensities = {len(specs)} "
          f"runs; output {st.folder}", file=sys.stderr)  # fmt: skip

    def on_term(signum: int, _frame: object) -> None:
        """SIGTERM stops a study as Ctrl-C does: the rows written so far are kept."""
        raise KeyboardInterrupt(signal.Signals(signum).name)

    old_term = signal.signal(signal.SIGTERM, on_term)
    try:
        table = st.run(workers=workers, scheduler=args.scheduler, resume=not args.restart,
                       progress=progress)  # fmt: skip
    except KeyboardInterrupt as exc:
        why = f" ({exc.args[0]})" if exc.args else ""
        again = ("the same command without --restart resumes the study" if args.restart
                 else "the same command resumes the study")  # fmt: skip
        print(f"pfeie: interrupted{why}; the runs finished so far are kept: {again}",
              file=sys.stderr)  # fmt: skip
        return EXIT_INTERRUPTED
    except (InputError, MeshError, RecordError, ResultsError) as exc:
        return _input_failure(exc, args.study)
    except PfeieError as exc:
        print(f"pfeie: analysis failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    finally:
        signal.signal(signal.SIGTERM, old_term)
    from .study import median_lines, run_label, warning_line

    stopped = [run_label(r) for r in table.rows if not r["completed"]]
    if st.kept:  # (a result, not progress: --quiet keeps it)
        print(f"study: {st.kept} of {len({s.key for s in specs})} runs kept from before "
              f"({st.folder / 'rows'}); --restart runs them again", file=sys.stderr)  # fmt: skip
    for line in median_lines(table, extra=[str(ls["demand"]) for ls in st.limit_states]):
        print(line)
    print(f"{len(table)} runs in {st.folder / 'table.csv'}")
    warned = warning_line(table, st.folder / "table.csv")
    if warned is not None:
        print(warned)
    for f in st.outputs():
        print(f"wrote {f}")
    if stopped:
        print(f"pfeie: {len(stopped)} run(s) stopped before their end (the interface step did "
              f"not converge): {', '.join(stopped)}", file=sys.stderr)  # fmt: skip
        return EXIT_FAILED
    return EXIT_OK


def _input_failure(exc: PfeieError, source: str) -> int:
    """Report a failure to read the inputs: the ``pfeie: error`` lines of an input error
    (which names its file), or the error with the file it came from; exit 2."""
    if isinstance(exc, (InputError, MeshError, RecordError)):
        for line in str(exc).splitlines():
            print(f"pfeie: error: {line}", file=sys.stderr)
    else:
        print(f"pfeie: error: {source}: {exc}", file=sys.stderr)
    return EXIT_INPUT


def _law_text(law: dict[str, Any] | None) -> str:
    """A joint law of ``pfeie check``'s summary as text: the strengths in force at the
    start (intact, then residual; or those of a joint that starts broken), MPa and
    degrees."""
    if not law or "initial" not in law:
        return f"; {law['law']}" if law else ""

    def mc(c: str, phi: str, t: str) -> str:
        return (f"c {law.get(c, 0.0) / 1e6:g} MPa, φ {law.get(phi, 0.0):g}°, tensile "
                f"{law.get(t, 0.0) / 1e6:g} MPa")  # fmt: skip

    residual = mc("residual_cohesion", "residual_friction_angle", "residual_tensile_strength")
    if law["initial"] == "intact":
        text = (f"; intact: {mc('cohesion', 'friction_angle', 'tensile_strength')}; "
                f"residual: {residual}")  # fmt: skip
    else:
        text = f"; starts broken: {residual}"
    springs = [f"{k} {law[k]:g} Pa/m" for k in ("normal_stiffness", "shear_stiffness") if k in law]
    return text + (f"; {', '.join(springs)}" if springs else "")


def _steps_line(steps: int, dt: float, duration: float) -> str:
    """The check's time-step line: the steps, Δt and the time the run reaches, steps × Δt
    (the steps are round(duration / Δt), as the run takes them); where Δt does not divide
    the duration, what is left out or run beyond it.

    >>> print(_steps_line(133, 0.03, 4.0))  # doctest: +NORMALIZE_WHITESPACE
    time steps   133 of 0.03 s, to t = 3.99 s (the duration, 4 s, is not a multiple of Δt:
    the last 0.01 s is not run)
    >>> print(_steps_line(400, 0.01, 4.0))
    time steps   400 of 0.01 s, to t = 4 s
    >>> print(_steps_line(0, 0.01, 0.0))
    time steps   none (no dynamic analysis: analysis.dynamic = false)
    """
    if not steps and not duration:
        return "time steps   none (no dynamic analysis: analysis.dynamic = false)"
    end = steps * dt
    line = f"time steps   {steps} of {dt:g} s, to t = {end:.6g} s"
    gap = duration - end
    if steps and abs(gap) > 1e-9 * max(duration, dt):
        line += (f" (the duration, {duration:.6g} s, is not a multiple of Δt: "
                 + (f"the last {gap:.6g} s is not run)" if gap > 0 else
                    f"the run goes {-gap:.6g} s beyond it)"))  # fmt: skip
    return line


def _format_check(s: dict[str, object]) -> str:
    lines = [f"model file   {s['file']}", f"title        {s['title']}",
             f"dimension    {s['dimension']}D"]  # fmt: skip
    blocks = s["blocks"]
    assert isinstance(blocks, dict)
    for name, mat in blocks.items():
        lines.append(
            f"block        {name}: E = {mat.E:.4g} Pa, nu = {mat.nu}, rho = {mat.rho} kg/m³"
        )
    extent = s.get("extent_m")
    if isinstance(extent, list):
        lines.append(f"extent       {' x '.join(f'{v:.4g}' for v in extent)} m; mass "
                     f"{float(s['mass_kg']):.4g} kg"  # type: ignore[arg-type]
                     + (" (2D: the slice of the model's thickness)" if s["dimension"] == 2
                        else ""))  # fmt: skip
    floating, unheld = s.get("floating") or [], s.get("unsupported") or []
    assert isinstance(floating, list) and isinstance(unheld, list)
    held = [b for b in floating if b not in unheld]
    lines.append(
        f"bodies       {s['bodies']}"
        + (f"; floating (held by their joints only): {', '.join(held)}" if held else "")
    )
    if unheld:
        lines.append(f"unsupported  {', '.join(unheld)}: no support, and no joint to a "
                     "supported block (add [[supports]])")  # fmt: skip
    free = s.get("free_modes") or []
    assert isinstance(free, list)
    for grp in free:
        lines.append(f"free motion  {', '.join(grp['blocks'])}: the supports leave "
                     f"{'; '.join(grp['modes'])} free (no joint can hold it)")  # fmt: skip
    massless = s.get("massless_floating") or []
    assert isinstance(massless, list)
    if massless:
        lines.append(f"massless     {', '.join(massless)}: floating with rho = 0; a dynamic "
                     "analysis needs a density or a support")  # fmt: skip
    lines.append(f"cells        {s['cells']}")
    lines.append(f"nodes        {s['nodes']}, DOF {s['dof']} ({s['free_dof']} free)")
    quality = s.get("quality", {})
    assert isinstance(quality, dict)
    for ctype, q in quality.items():
        lines.append(f"shape        {ctype}: worst quality {q['worst']} ({q['cell']}; 1 for "
                     f"the ideal cell), {q['below_0.3']} cell(s) below 0.3")  # fmt: skip
    pairs = s["pairs"]
    assert isinstance(pairs, dict)
    laws = s.get("joint_laws") or {}
    assert isinstance(laws, dict)
    for name, n in pairs.items():
        lines.append(f"interface    {name}: {n} pairs" + _law_text(laws.get(name)))
    for row in s.get("loads") or []:  # type: ignore[attr-defined]
        F = [(k[2:-5], v) for k, v in row.items() if k.startswith("F_")]
        lines.append(f"load         {row['load']} on {row['where']}: {row['parameters']}"
                     + ("; resultant " + ", ".join(f"{a} {v:.4g}" for a, v in F) + " kN"
                        if F else ""))  # fmt: skip
    damping = s.get("damping")
    if isinstance(damping, dict):
        floating = damping["floating"]
        line = (f"damping      Rayleigh alpha = {damping['alpha']:.4g} 1/s, "
                f"beta = {damping['beta']:.4g} s")  # fmt: skip
        if damping["alpha"] > 0 and floating and damping["deformation_only"]:
            line += (f"; the deformation only: the rigid motion of the floating block(s) "
                     f"{', '.join(floating)} is not damped")  # fmt: skip
        elif damping["alpha"] > 0 and floating:
            line += (f"; the mass-proportional part brakes the rigid motion of the floating "
                     f"block(s) {', '.join(floating)} (docs/model-file.md, Damping; "
                     f"deformation_only = true spares it)")  # fmt: skip
        lines.append(line)
    records = s["records"]
    assert isinstance(records, list)
    for r in records:
        lines.append(f"record       {r}")
    steps, dt, duration = s["steps"], s["dt"], s["duration"]
    assert isinstance(steps, int) and isinstance(dt, int | float)
    assert isinstance(duration, int | float)
    lines.append(_steps_line(steps, float(dt), float(duration)))
    analyses = s.get("analyses")
    if isinstance(analyses, list) and analyses:
        lines.append(f"analyses     {'; '.join(analyses)}")
    lines.append(
        f"memory       at most about {s['estimated_memory_mb']} MB (the pair solvers' "
        "caches full; a run usually needs less)"
    )
    return "\n".join(lines)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
