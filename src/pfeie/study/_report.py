"""What a study writes besides its table: IDA curves, fragility fits, one HTML report.

With limit states (``[[limit_states]]`` of the study file): per demand column its IDA
curves with the 16/50/84 % fractiles (``ida_<column>.png``); the fragility fit of each
limit state (``fragility.csv``: θ, β, their standard errors and 95 % intervals, the counts
and the method; ``fragility.png`` with the 95 % pointwise bands and the empirical
fractions). Always: ``report.html``, one self-contained page with the study (model,
records, ladder), the median and 16/84 % fractiles of the main demands per intensity,
and the figures. The intensity measure of the curves is the ladder's (PGA or Sa(T1) in
g); for a ladder of scale factors, Sa(T1) of the scaled records.
"""

from __future__ import annotations

import base64
import csv
import html
import logging
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ..typing import FloatArray
from ._fragility import Fragility, fit_limit_states
from ._ida import LimitState, ida_curves, ida_summary
from ._table import StudyTable

if TYPE_CHECKING:
    from ._study import Study

log = logging.getLogger(__name__)


def intensity_column(study: Study) -> tuple[str, str]:
    """The table column of the curves' intensity measure, and its label."""
    if study.measure == "pga":
        return "intensity", "PGA (g)"
    period = f"{study.period:.3g} s" if study.period is not None else "T1"
    return (("intensity" if study.measure == "sa" else "im.sa_t1_g"),
            f"Sa({period}, {100 * study.damping:g} %) (g)")  # fmt: skip


def limit_states(study: Study) -> list[LimitState]:
    """The study's limit states as :class:`LimitState` objects."""
    return [LimitState(ls["name"], ls["demand"], float(ls["threshold"]),
                       ">=" if ls.get("exceed", "above") == "above" else "<=")
            for ls in study.limit_states]  # fmt: skip


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_") or "x"


def write_study_outputs(study: Study, table: StudyTable, folder: Path) -> list[Path]:
    """Write the IDA and fragility outputs and ``report.html`` into ``folder``; returns
    the files written."""
    states = limit_states(study)
    for i, ls in enumerate(states):
        if ls.column not in table.columns:
            raise ModelError(f"limit_states[{i}].demand: the table has no column "
                             f"{ls.column!r}; its demand columns are "
                             f"{', '.join(c for c in table.columns if '.' in c)}")  # fmt: skip
    imcol, imlabel = intensity_column(study)
    out: list[Path] = []
    fits: dict[str, Fragility] = {}
    failed: dict[str, str] = {}
    for ls in states:
        try:
            fits.update(fit_limit_states(table, [ls], intensity=imcol))
        except ModelError as exc:
            failed[ls.name] = str(exc)
            log.warning("fragility of %r not fitted: %s", ls.name, exc)
    if states:
        out.append(_write_fits(folder / "fragility.csv", states, fits, failed))
    figures: list[tuple[str, Path]] = []
    try:
        from ..plot import plot_fragility, plot_ida, save_figure
    except ImportError:  # pragma: no cover - matplotlib is the plot extra
        log.warning("no figures: matplotlib is not installed (pip install 'pfeie[plot]')")
    else:
        for column in dict.fromkeys(ls.column for ls in states):
            curves = ida_curves(table, column, intensity=imcol, nan_policy="omit")
            thr = [ls.threshold for ls in states if ls.column == column]
            fig = plot_ida(curves, ida_summary(curves), threshold=thr[0], im_label=imlabel,
                           demand_label=column, title=f"IDA: {column}")  # fmt: skip
            p = save_figure(fig, folder / f"ida_{_slug(column)}.png")
            figures.append((f"IDA curves: {column}", p))
        if fits:
            fig = plot_fragility(list(fits.values()), im_label=imlabel,
                                 title="Fragility (95 % pointwise bands)")  # fmt: skip
            figures.append(("Fragility curves", save_figure(fig, folder / "fragility.png")))
    out += [p for _, p in figures]
    out.append(_write_html(folder / "report.html", study, table, imcol, imlabel, fits,
                           failed, figures))  # fmt: skip
    # the outputs of an earlier study in this folder that this one did not write again
    # (other limit states, none fitted): left, they would read as this study's
    for old in [*folder.glob("ida_*.png"), folder / "fragility.png", folder / "fragility.csv"]:
        if old.is_file() and old not in out:
            old.unlink()
            log.info("removed %s, an output of an earlier study in %s", old.name, folder)
    return out


def _write_fits(path: Path, states: list[LimitState], fits: dict[str, Fragility],
                failed: dict[str, str]) -> Path:  # fmt: skip
    cols = ["limit_state", "demand", "threshold", "exceeded_when", "theta", "beta",
            "se_theta", "se_beta", "theta_lo95", "theta_hi95", "beta_lo95", "beta_hi95",
            "n_records", "n_exceeded", "n_censored", "method", "note"]  # fmt: skip
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for ls in states:
            head = [ls.name, ls.column, repr(ls.threshold), ls.direction]
            f = fits.get(ls.name)
            if f is None:
                w.writerow(head + [""] * 12 + [failed.get(ls.name, "")])
                continue
            (tl, th), (bl, bh) = f.interval(0.95)
            w.writerow(head + [repr(x) for x in (f.theta, f.beta, f.se_theta, f.se_beta,
                                                 tl, th, bl, bh)]
                       + [f.n_records, f.n_exceeded, f.n_censored, f.method, ""])  # fmt: skip
    return path


def per_intensity(
    table: StudyTable, columns: list[str], percentiles: tuple[float, ...]
) -> list[tuple[int, float, list[FloatArray | None]]]:
    """For each level of the ladder: the level, the intensity of its first row, and per
    column the ``percentiles`` over the records (None where no record has a value)."""
    levels, value = table.column("level"), table.column("intensity")
    data = [table.column(c) for c in columns]
    out = []
    for lv in np.unique(levels):
        sel = levels == lv
        stats: list[FloatArray | None] = []
        for col in data:
            v = col[sel]
            v = v[np.isfinite(v)]
            stats.append(np.percentile(v, percentiles) if v.size else None)
        out.append((int(lv), float(value[sel][0]), stats))
    return out


def median_lines(table: StudyTable, columns: int = 4, extra: Sequence[str] = ()) -> list[str]:
    """Text lines: the median over the records of the main demands at each intensity
    (the first ``columns`` demand columns, then the ``extra`` columns of the table not
    among them: the limit states' demands), for a summary on the terminal."""
    demands = _demand_columns(table)[:columns]
    demands += [c for c in dict.fromkeys(extra) if c in table.columns and c not in demands]
    if not demands or not len(table):
        return []
    widths = [max(len(c), 11) for c in demands]  # the columns' names in full
    head = f"{'level':>5} {'intensity':>10} " + " ".join(
        f"{c:>{w}}" for c, w in zip(demands, widths, strict=True))  # fmt: skip
    out = ["median over the records:", head]
    for lv, im, stats in per_intensity(table, demands, (50.0,)):
        cells = [f"{p[0]:>{w}.4g}" if p is not None else " " * w
                 for p, w in zip(stats, widths, strict=True)]  # fmt: skip
        out.append(f"{lv:>5} {im:>10.4g} " + " ".join(cells))
    return out


#: the most runs that the terminal's line on the runs with warnings names (the table's
#: ``warnings`` column has them all)
WARNED_NAMED = 10


def run_label(row: dict[str, Any]) -> str:
    """A run as the terminal names it: its record and intensity, ``r1@0.5``."""
    return f"{row['record']}@{row['intensity']:g}"


def warning_line(table: StudyTable, where: Path) -> str | None:
    """The terminal's line on the runs that finished with reliability warnings (a
    ``warnings`` cell not empty: `pfeie run`'s "large slip", "corrections" and "scheme"
    lines): how many, of which kinds, which runs (:func:`run_label`, the first
    :data:`WARNED_NAMED`) and where the warnings are, the table ``where``; None when no
    run has any.

    >>> t = StudyTable([{"record": "r0", "intensity": 0.5, "warnings": ""},
    ...                 {"record": "r1", "intensity": 0.5, "warnings": "large slip: ..."}])
    >>> warning_line(t, Path("study/table.csv"))
    '1 of 2 runs finished with warnings (large slip 1): r1@0.5; see the warnings column of study/table.csv'
    """  # noqa: E501
    warned = _warned(table)
    if not warned:
        return None
    kinds = _warning_kinds(warned)
    names = ", ".join(run_label(r) for r in warned[:WARNED_NAMED])
    more = f" and {len(warned) - WARNED_NAMED} more" if len(warned) > WARNED_NAMED else ""
    return (f"{len(warned)} of {len(table)} runs finished with warnings "
            f"({', '.join(f'{k} {n}' for k, n in kinds.items())}): {names}{more}; see the "
            f"warnings column of {where}")  # fmt: skip


def _warning_kinds(warned: list[dict[str, Any]]) -> dict[str, int]:
    """How many of the runs ``warned`` have each kind of warning (its label: "large
    slip", "scheme", ...)."""
    kinds: dict[str, int] = {}
    for r in warned:
        for kind in dict.fromkeys(n.partition(":")[0] for n in r["warnings"].split("; ")):
            kinds[kind] = kinds.get(kind, 0) + 1
    return kinds


def _demand_columns(table: StudyTable) -> list[str]:
    keep = ("peak_displacement_m", "residual_slip_max_m", "max_opening_m",
            "min_safety_factor", "max_principal_Pa")  # fmt: skip
    return [c for c in table.columns if c.endswith(keep)]


def _record_cells(table: StudyTable, name: str) -> str:
    """A record's cells of the report's records table: the PGA of its applied motion
    before scaling (its runs' ``im.pga_g`` over their scale factors) and the factors by
    level; empty where the table has no run of it."""
    rows = sorted((r for r in table.rows if r.get("record") == name),
                  key=lambda r: int(r["level"]))  # fmt: skip
    rows = [r for r in rows if isinstance(r.get("scale_factor"), int | float)
            and np.isfinite(r["scale_factor"]) and r["scale_factor"]]  # fmt: skip
    if not rows:
        return "<td></td><td></td>"
    pga = abs(float(rows[0]["im.pga_g"]) / float(rows[0]["scale_factor"]))
    return (
        f"<td>{pga:.4g}</td><td>"
        + ", ".join(f"{float(r['scale_factor']):.4g}" for r in rows)
        + "</td>"
    )


def _warned(table: StudyTable) -> list[dict[str, Any]]:
    """The rows of the runs with a reliability warning (a ``warnings`` cell not empty)."""
    return [r for r in table.rows if isinstance(r.get("warnings"), str) and r["warnings"]]


def _warning_section(table: StudyTable) -> list[str]:
    """The report's reliability section: the runs that finished with warnings, by kind,
    each run's warnings (as the table's ``warnings`` column); none when no run has any."""
    warned = _warned(table)
    if not warned:
        return []
    esc = html.escape
    kinds = _warning_kinds(warned)
    out = [f"<h2>Reliability</h2><p>{len(warned)} of {len(table)} runs finished with "
           "warnings (" + ", ".join(f"{esc(k)} {n}" for k, n in kinds.items())
           + "; the summary lines of <code>pfeie run</code>, docs/results.md): read their "
           "demands with care, and run the record again with Δt halved where the warning "
           "says so.</p><table><tr><th>run</th><th>warnings</th></tr>"]  # fmt: skip
    out += [
        f"<tr><td>{esc(run_label(r))}</td><td style='text-align:left'>"
        f"{esc(r['warnings'])}</td></tr>"
        for r in warned
    ]
    out.append("</table>")
    return out


def _write_html(path: Path, study: Study, table: StudyTable, imcol: str, imlabel: str,
                fits: dict[str, Fragility], failed: dict[str, str],
                figures: list[tuple[str, Path]]) -> Path:  # fmt: skip
    esc = html.escape
    title = study.title or f"Study of {study.model.name}"
    completed = table.column("completed")
    ctx = study.context()
    job = study._job  # set by context()
    duration = (f"{ctx.duration:g} s" if ctx.duration is not None
                else "each record's own length")  # fmt: skip
    rows = [("model file", str(study.model)), ("records", str(len(study.records))),
            ("intensity measure", study.measure), ("intensities", ", ".join(
                f"{v:g}" for v in study.values)), ("runs", f"{len(table)} "
            f"({int(np.sum(completed))} completed)"),
            ("T1 of Sa", f"{study.period:.4g} s" if study.period else ""),
            ("duration of each run", duration),
            ("time step Δt", f"{job.analysis.dt:g} s" if job is not None else ""),
            ("keys set (analysis.set)", "; ".join(study.overrides) or "none")]  # fmt: skip
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>", f"<title>{esc(title)}</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
        "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid "
        "#ccc;padding:3px 6px;text-align:right}th{background:#f3f3f3}img{max-width:100%}"
        "</style></head><body>", f"<h1>{esc(title)}</h1>", "<h2>Study</h2><table>",
        *[f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in rows], "</table>",
        "<h2>Records</h2><p>Each record as read (its units), the PGA of the motion a run "
        "applies before scaling (the record up to the run's duration), and the factor that "
        "scales it to each intensity of the ladder.</p><table><tr><th>record</th>"
        "<th>file</th><th>units</th><th>PGA applied, unscaled (g)</th>"
        "<th>scale factors</th></tr>",
        *[f"<tr><td>{esc(r.name)}</td><td>{esc(str(r.path))}</td><td>{esc(r.units or 'g')}"
          f"</td>{_record_cells(table, r.name)}</tr>" for r in study.records],
        "</table>",
    ]  # fmt: skip
    parts += _warning_section(table)
    demands = _demand_columns(table)
    if demands:
        same_im = imcol == "intensity"  # the ladder's value, the same for every record
        what = (f"the intensity, {esc(imlabel)}" if same_im else
                f"the scale factor, and the median {esc(imlabel)} over the records")  # fmt: skip
        parts.append(f"<h2>Demands per intensity</h2><p>Median [16 %, 84 %] over the records "
                     f"at each level of the ladder ({what}).</p><table><tr><th>level</th>"
                     + ("<th>IM</th>" if same_im else "<th>scale</th><th>IM median</th>")
                     + "".join(f"<th>{esc(c)}</th>" for c in demands) + "</tr>")  # fmt: skip
        im = table.column(imcol)
        levels = table.column("level")
        for lv, value, stats in per_intensity(table, demands, (16.0, 50.0, 84.0)):
            cells = "".join(f"<td>{p[1]:.4g} [{p[0]:.3g}, {p[2]:.3g}]</td>" if p is not None
                            else "<td></td>" for p in stats)  # fmt: skip
            head = (
                f"<td>{value:.4g}</td>"
                if same_im
                else f"<td>{value:.4g}</td><td>{float(np.median(im[levels == lv])):.4g}</td>"
            )
            parts.append(f"<tr><td>{lv}</td>{head}{cells}</tr>")
        parts.append("</table>")
    if fits or failed:
        warned = _warned(table)
        if warned:
            parts.append(
                f"<p>{len(warned)} of the {len(table)} runs carry reliability "
                "warnings (above); the fits take their demands as they are.</p>"
            )
        parts.append("<h2>Fragility</h2><table><tr><th>limit state</th><th>demand</th>"
                     "<th>threshold</th><th>θ (g)</th>"
                     "<th>β</th><th>θ 95 %</th><th>β 95 %</th><th>records</th>"
                     "<th>exceeded</th><th>censored</th><th>method</th></tr>")  # fmt: skip
        states = {ls.name: ls for ls in limit_states(study)}
        for name, f in fits.items():
            (tl, th), (bl, bh) = f.interval(0.95)
            ls = states[name]
            parts.append(f"<tr><td>{esc(name)}</td><td>{esc(ls.column)}</td><td>"
                         f"{esc(ls.direction)} {ls.threshold:g}</td><td>{f.theta:.4g}</td>"
                         f"<td>{f.beta:.3g}"
                         f"</td><td>[{tl:.3g}, {th:.3g}]</td><td>[{bl:.3g}, {bh:.3g}]</td>"
                         f"<td>{f.n_records}</td><td>{f.n_exceeded}</td><td>{f.n_censored}"
                         f"</td><td>{esc(f.method)}</td></tr>")  # fmt: skip
        for name, why in failed.items():
            ls = states[name]
            parts.append(f"<tr><td>{esc(name)}</td><td>{esc(ls.column)}</td><td>"
                         f"{esc(ls.direction)} {ls.threshold:g}</td><td colspan='8'>not "
                         f"fitted: {esc(why)}</td></tr>")  # fmt: skip
        parts.append("</table>")
    for caption, p in figures:
        data = base64.b64encode(p.read_bytes()).decode()
        parts.append(f"<h3>{esc(caption)}</h3><img alt='{esc(caption)}' "
                     f"src='data:image/png;base64,{data}'>")  # fmt: skip
    parts.append("</body></html>")
    path.write_text("\n".join(parts), encoding="utf-8", errors="backslashreplace")
    return path


__all__ = ["intensity_column", "limit_states", "median_lines", "write_study_outputs"]
