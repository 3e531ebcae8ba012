"""Ground-motion records from files: PEER NGA ``.AT2``, two columns, one column.

Formats (``fmt``):

- ``"at2"``: the PEER NGA format. Four header lines; the third states the units
  ("... IN UNITS OF G"; also read: "UNITS OF GAL" or "CM/S/S", cm/s², and "M/S/S"), the
  fourth NPTS and DT, either as ``NPTS=  4000, DT=   .0100 SEC``
  (NGA-West1) or as ``4000   0.0100   NPTS, DT`` (NGA-West2). Then the samples, several
  per line, in the units of the third line. Numbers written without a separating blank
  (``1.234E-02-5.678E-03``) are split. The number of samples must equal NPTS.
- ``"two-column"``: time (s) and acceleration, separated by commas, semicolons, tabs or
  blanks; an optional header line (any non-numeric first line).
- ``"one-column"``: one acceleration per line (or several per line, read row by row),
  sampled at the ``dt`` given; an optional header line.
- ``"auto"``: ``.at2`` files, and files whose first lines are a PEER header (a third
  line naming a TIME SERIES or TIME HISTORY, a fourth NPTS and DT), are AT2; otherwise
  two columns if the first data line has two numbers, else one column (which then needs
  ``dt``).

Units: ``"g"`` (×9.81 m/s²), ``"m/s2"``, ``"cm/s2"`` (= gal). Every error names the file
and, where it applies, the line.

>>> import tempfile, pathlib
>>> p = pathlib.Path(tempfile.mkdtemp()) / "rec.csv"
>>> _ = p.write_text("time,acc\\n0,0\\n0.01,0.1\\n0.02,-0.2\\n")
>>> gm = read_record(p, units="g")
>>> round(gm.pga / 9.81, 3), float(gm.time[-1])
(0.2, 0.02)
"""

from __future__ import annotations

import dataclasses
import logging
import math
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import ModelError, RecordError
from ..model import G_UNITS, RECORD_DT_COARSE, RECORD_DT_MAX, GroundMotion
from ..typing import FloatArray, is_number

log = logging.getLogger(__name__)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?")
_SEP = re.compile(r"[,;\s]+")
_ALLOWED = re.compile(r"^[\s0-9eEdD.+\-,;]*$")
# units named in a header line: "acc (g)", "[m/s2]", "m/s^2", "cm/s²", "gal", "in g"
_HEADER_UNITS = {
    "cm/s2": re.compile(r"cm\s*/\s*s(?:\s*\^?\s*2|²|\*\*2|/s)|\bgals?\b"),
    "m/s2": re.compile(r"(?<![a-z])m\s*/\s*s(?:\s*\^?\s*2|²|\*\*2|/s)|\bmps2\b"),
    "g": re.compile(r"[(\[]\s*g\s*[)\]]|\bin\s+g\b|\bunits?\s*[:=]?\s*g\b|_g\b"),
}


#: the peak ground accelerations (g) of a record that are taken as plausible: outside
#: them, the record's units are suspect (a record in g read as cm/s² peaks near 0.003 g;
#: a record in m/s² read as g 9.81 times too high, 3.1 g for El Centro's 0.32 g). The
#: strongest horizontal motions recorded peak near 2 to 3 g; a record beyond 2.5 g is
#: warned, not refused (:data:`pfeie.io.MAX_PGA_G` refuses)
PLAUSIBLE_PGA_G = (1e-3, 2.5)


def implausible_pga(path: str | Path, pga: float, units: str) -> str | None:
    """A warning when a record's peak ground acceleration ``pga`` (m/s², as read in
    ``units``) lies outside :data:`PLAUSIBLE_PGA_G`, naming the file, the units and the
    units that would give a plausible one; ``None`` when it lies inside (or is 0)."""
    lo, hi = PLAUSIBLE_PGA_G
    factor = G_UNITS.get(units.lower())
    pga_g = pga / 9.81
    if factor is None or pga_g == 0.0 or lo <= pga_g <= hi:
        return None
    side = "below" if pga_g < lo else "above"
    msg = (f"{path}: the record's PGA is {pga_g:.3g} g with its values read in {units} "
           f"(units = {units!r}): {side} the plausible {lo:g} to {hi:g} g")  # fmt: skip
    options = {u: pga_g * f / factor for u, f in G_UNITS.items() if u in ("g", "m/s2", "cm/s2")}
    fits = [u for u, v in options.items() if 0.01 <= v <= 5.0 and u != units.lower()]
    if fits:  # the units that give a PGA nearest 0.3 g, a typical design earthquake's
        best = min(fits, key=lambda u: abs(math.log(options[u] / 0.3)))
        msg += f"; are its values in {best}? (units = {best!r} gives {options[best]:.3g} g)"
    return msg


#: a record that ends before the run with its last sample above this share of its PGA is
#: warned (a record cut short: the ground acceleration drops to zero in one step)
ABRUPT_END = 0.05


def abrupt_end(rec: GroundMotion, end: float) -> str | None:
    """A note when the record ends before the run's end ``end`` (s) with its last sample
    above :data:`ABRUPT_END` of its PGA: from there the run has no ground acceleration,
    and the record's last value drops to zero in one step (a record cut short, or the
    wrong file); ``None`` otherwise.

    >>> gm = GroundMotion.from_samples([0.0, 0.3, -0.2], dt=1.0, units="g")
    >>> abrupt_end(gm, 5.0)
    'the record ends at 2 s with -0.2 g (67 % of its PGA), before the end of the run (5 s): from there the ground acceleration is zero, a step of -0.2 g (a record cut short?)'
    >>> abrupt_end(gm, 2.0) is None
    True
    """  # noqa: E501
    t, a = rec.time, rec.acceleration
    last = float(a[-1])
    if t[-1] >= end or not rec.pga > 0 or abs(last) <= ABRUPT_END * rec.pga:
        return None
    g = G_UNITS["g"]
    return (f"the record ends at {t[-1]:g} s with {last / g:.3g} g "
            f"({100 * abs(last) / rec.pga:.0f} % of its PGA), before the end of the run "
            f"({end:g} s): from there the ground acceleration is zero, a step of "
            f"{last / g:.3g} g (a record cut short?)")  # fmt: skip


def coarse_step(rec: GroundMotion, dt: float) -> str | None:
    """A note when the time step ``dt`` (s) is coarser than the record's sampling (its
    median step): the load is the record interpolated at the steps, so its content above
    1/(2Δt) is not applied; ``None`` otherwise.

    >>> gm = GroundMotion.from_samples([0.0, 0.1, -0.1, 0.0], dt=0.005, units="g")
    >>> coarse_step(gm, 0.01)
    "analysis.dt = 0.01 s is coarser than the record's sampling (0.005 s): the record is read at the steps, and its content above 50 Hz is not applied"
    >>> coarse_step(gm, 0.005) is None
    True
    """  # noqa: E501
    step = rec.sampling
    if dt <= step * (1 + 1e-9):
        return None
    return (f"analysis.dt = {dt:g} s is coarser than the record's sampling ({step:g} s): the "
            f"record is read at the steps, and its content above {0.5 / dt:.4g} Hz is not "
            "applied")  # fmt: skip


def coarse_sampling(path: object, rec: GroundMotion) -> str | None:
    """A note when the record ``rec`` (read from ``path``) is sampled more coarsely than
    :data:`~pfeie.model.RECORD_DT_COARSE` (strong-motion records: 0.005 to 0.05 s; a
    coarser one is usually times or a dt in ms read as s); ``None`` otherwise.

    >>> gm = GroundMotion.from_samples([0.0, 0.1, -0.1, 0.0], dt=0.2, units="g")
    >>> coarse_sampling("r.csv", gm)
    'r.csv is sampled every 0.2 s (strong-motion records: 0.005 to 0.05 s): its times or dt in ms?'
    """
    if rec.sampling <= RECORD_DT_COARSE:
        return None
    return (f"{path} is sampled every {rec.sampling:g} s (strong-motion records: 0.005 to "
            "0.05 s): its times or dt in ms?")  # fmt: skip


#: a two-column record whose time step jumps beyond this multiple of its median step is
#: warned (samples missing, or two records joined): across the gap the acceleration is
#: interpolated linearly
TIME_GAP = 2.5


def time_gaps(t: FloatArray) -> list[tuple[int, float, float]]:
    """The steps of a record's times ``t`` (s, increasing) longer than :data:`TIME_GAP`
    times their median: (index i of the step t[i] → t[i+1], its length, the median); none
    for fewer than 10 samples.

    >>> t = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.5, 0.51, 0.52]
    >>> [(i, round(h, 6), round(m, 6)) for i, h, m in time_gaps(t)]
    [(7, 0.43, 0.01)]
    """
    steps = np.diff(np.asarray(t, dtype=float))
    if steps.size < 9:
        return []
    med = float(np.median(steps))
    big = np.flatnonzero(steps > TIME_GAP * med)
    return [(int(i), float(steps[i]), med) for i in big]


#: a record cut at the end of a run whose applied part peaks at this share of its PGA or
#: more is said to keep its peak (a peak just beyond the end, which the interpolation at
#: the end nearly reaches, is no news to the user)
PEAK_KEPT = 0.99


def applied_part(rec: GroundMotion, end: float) -> tuple[GroundMotion, str | None]:
    """The part of the record ``rec`` that a run ending at ``end`` (s) applies, and a note
    when the record's peak lies beyond it (None when the part holds the peak).

    A run steps from t = 0 to its duration, so a record that goes on beyond is applied up
    to ``end`` only: the part is its samples before ``end`` and its acceleration
    interpolated at ``end`` (``rec`` itself when it ends by then). The scaling of a record
    to a PGA or an Sa (a study's ladder, a model file's ``pga`` and ``target_sa``) and a
    study's intensity measures are measured on it, so that they describe the motion the
    model feels. A record that starts at or after ``end`` is a :class:`RecordError`
    (nothing of it is applied).

    >>> gm = GroundMotion.from_samples([0.0, 0.2, 0.0, 1.0], dt=1.0, units="g")
    >>> part, note = applied_part(gm, 2.5)
    >>> part.time.tolist(), round(part.pga / 9.81, 12)
    ([0.0, 1.0, 2.0, 2.5], 0.5)
    >>> note
    "the record's PGA, 1 g at 3.00 s, lies beyond the end of the run (duration 2.5 s): the motion applied, up to 2.5 s, peaks at 0.5 g"
    """  # noqa: E501
    t, a = rec.time, rec.acceleration
    if t[-1] <= end:
        return rec, None
    keep = t < end
    if not keep.any():
        raise RecordError(f"the record starts at {t[0]:g} s, at or after the end of the run "
                          f"({end:g} s): nothing of it is applied; expected a record that "
                          "starts before analysis.duration")  # fmt: skip
    part = dataclasses.replace(rec, time=np.append(t[keep], end),
                               acceleration=np.append(a[keep], np.interp(end, t, a)))  # fmt: skip
    if not part.pga < PEAK_KEPT * rec.pga:  # the peak, or all but round-off of it, applied
        return part, None
    k = int(np.argmax(np.abs(a)))
    g = G_UNITS["g"]
    return part, (f"the record's PGA, {rec.pga / g:.4g} g at {t[k]:.2f} s, lies beyond the "
                  f"end of the run (duration {end:g} s): the motion applied, up to "
                  f"{end:g} s, peaks at {part.pga / g:.4g} g")  # fmt: skip


def _numbers(line: str, path: Path, lineno: int) -> list[float]:
    """All numbers of a data line, fused ones split; non-numeric text is an error."""
    if not _ALLOWED.match(line):
        text = line.strip()
        bad = next((w for w in re.split(r"[\s,;]+", text) if w and not _ALLOWED.match(w)), text)
        text = text if len(text) <= 60 else text[:57] + "..."
        raise RecordError(f"{path}: line {lineno}: non-numeric text {bad!r} in the data: {text!r}; "
                          "expected numbers (pfeie reads PEER .AT2 files and plain records of "
                          "one column, the accelerations, or two, time and acceleration: "
                          "format, dt and units in [[ground_motion]])")  # fmt: skip
    tokens = _NUMBER.findall(line)
    rest = _NUMBER.sub(" ", line)
    if rest.replace(",", " ").replace(";", " ").strip():
        raise RecordError(f"{path}: line {lineno}: cannot read numbers from {line.strip()!r}")
    values = [float(t.replace("d", "e").replace("D", "e")) for t in tokens]
    for tok, v in zip(tokens, values, strict=True):
        if not math.isfinite(v):
            raise RecordError(f"{path}: line {lineno}: {tok!r} is beyond the range of a double "
                              "(|x| < 1.8e308); expected a finite number")  # fmt: skip
    return values


def _read_at2(
    path: Path, lines: list[str], units: str | None
) -> tuple[FloatArray, float, str, str]:
    """The samples, DT (s), title and units (g, cm/s2 or m/s2, as its third line states
    them, :func:`_at2_units`) of a PEER .AT2 file."""
    if len(lines) < 5:
        raise RecordError(f"{path}: an AT2 file needs 4 header lines and data; it has "
                          f"{len(lines)} line(s)")  # fmt: skip
    series = re.search(r"\b(VELOCITY|DISPLACEMENT)\s+TIME\s+(SERIES|HISTORY)", lines[2], re.I)
    if series is not None:
        raise RecordError(f"{path}: line 3: a PEER {series.group(1).lower()} record "
                          f"({lines[2].strip()!r}); pfeie reads accelerations (the .AT2 "
                          "file of the same record)")  # fmt: skip
    stated = _at2_units(lines[2])
    if stated is None:
        raise RecordError(f"{path}: line 3: expected the units 'IN UNITS OF G' (or of CM/S/S, "
                          f"GAL or M/S/S), found {lines[2].strip()!r}")  # fmt: skip
    asked = (
        None
        if units is None
        else {"gal": "cm/s2", "m/s^2": "m/s2"}.get(units.lower(), units.lower())
    )
    if asked not in (None, stated):
        raise RecordError(f"{path}: line 3 states the units {stated} ({lines[2].strip()!r}); "
                          f"units {units!r} were given: give {stated!r} or "
                          "none")  # fmt: skip
    head = lines[3]
    m1 = re.search(r"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*([0-9.eE+-]+)", head, re.I)
    m2 = re.match(r"\s*(\d+)\s+([0-9.eE+-]+)\s+NPTS\s*,\s*DT", head, re.I)
    m = m1 or m2
    if m is None:
        raise RecordError(f"{path}: line 4: expected 'NPTS=..., DT=...' or '<npts> <dt> NPTS, "
                          f"DT', found {head.strip()!r}")  # fmt: skip
    npts = int(m.group(1))
    try:
        dt = float(m.group(2))
    except ValueError:
        raise RecordError(f"{path}: line 4: DT: expected a number, found {m.group(2)!r}") from None
    # the unit after DT's value (NGA-West1 writes SEC; none means seconds)
    unit = re.match(r"\s*([A-Za-z]+)", head[m.end() :]) if m is m1 else None
    word = unit.group(1).upper() if unit else "SEC"
    if word in ("MSEC", "MS"):
        dt *= 1e-3
    elif word not in ("SEC", "SECS", "S"):
        raise RecordError(f"{path}: line 4: DT: the unit {word!r} after its value "
                          "is not a time unit pfeie reads; expected SEC (or MSEC)")  # fmt: skip
    if not (math.isfinite(dt) and 0 < dt <= RECORD_DT_MAX):
        raise RecordError(f"{path}: line 4: DT: expected a number in (0, "
                          f"{RECORD_DT_MAX:g}] s, found "
                          f"{m.group(2)!r}")  # fmt: skip
    values: list[float] = []
    for i, line in enumerate(lines[4:], start=5):
        if line.strip():
            values.extend(_numbers(line, path, i))
    if len(values) != npts:
        raise RecordError(f"{path}: the header says NPTS = {npts} but the file has "
                          f"{len(values)} sample(s) (truncated or wrong header?)")  # fmt: skip
    name = lines[1].strip() or path.stem
    return np.asarray(values, dtype=float), dt, name, stated


def _peer_header(lines: list[str]) -> bool:
    """Whether a file's first lines are a PEER NGA header (an AT2 record saved under
    another name is read as one in the "auto" format): a third line naming a "TIME SERIES"
    (or, in PEER's 1999 files, a "TIME HISTORY") and a fourth stating NPTS and DT.

    >>> _peer_header(["PEER NGA", "T", "ACCELERATION TIME SERIES IN UNITS OF G",
    ...               "NPTS=  4000, DT=   .0100 SEC", "0.1"])
    True
    >>> _peer_header(["time,acc", "0,0", "0.01,0.1", "0.02,0.0", "0.03,0.1"])
    False
    """
    third = lines[2].upper() if len(lines) >= 5 else ""
    return (("TIME SERIES" in third or "TIME HISTORY" in third)
            and bool(re.search(r"NPTS\s*[=,]|NPTS\s*,\s*DT", lines[3], re.I)))  # fmt: skip


#: the units a PEER .AT2 header's third line may state after "UNITS OF" (NGA writes G)
_AT2_UNITS = {"G": "g", "GAL": "cm/s2", "GALS": "cm/s2", "CM/S/S": "cm/s2", "CM/S2": "cm/s2",
              "CM/S^2": "cm/s2", "CM/SEC/SEC": "cm/s2", "CM/SEC2": "cm/s2", "CM/SEC^2": "cm/s2",
              "M/S/S": "m/s2", "M/S2": "m/s2", "M/S^2": "m/s2", "M/SEC/SEC": "m/s2"}  # fmt: skip


def _at2_units(line: str) -> str | None:
    """The units of an AT2 record from its third header line: the first word after
    "UNITS OF" or "IN" that names units (:data:`_AT2_UNITS`: "IN UNITS OF G", "UNITS OF
    GAL", "IN CM/SEC/SEC"), matched whole ("UNITS OF GAL" is cm/s², not g); ``None`` if
    there is none.

    >>> _at2_units("ACCELERATION TIME SERIES IN UNITS OF G"), _at2_units("UNITS OF GAL")
    ('g', 'cm/s2')
    >>> _at2_units("ACCELERATION IN CM/SEC/SEC (G = 981 CM/S/S)"), _at2_units("IN G.")
    ('cm/s2', 'g')
    >>> _at2_units("UNITS OF MG") is None
    True
    """
    for m in re.finditer(r"(?=(?:UNITS\s+OF|\bIN)\s+([A-Z/^0-9]+))", line.upper()):
        if m.group(1).rstrip(".") in _AT2_UNITS:
            return _AT2_UNITS[m.group(1).rstrip(".")]
    return None


def _data_lines(
    path: Path, lines: list[str]
) -> tuple[list[tuple[int, list[float]]], tuple[int, str] | None]:
    """Numeric rows (line number, numbers), skipping one header line and blank lines;
    the header line (its number and text), if any."""
    rows: list[tuple[int, list[float]]] = []
    header: tuple[int, str] | None = None
    for i, line in enumerate(lines, start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        if not rows and header is None and not _ALLOWED.match(line):
            header = (i, line)  # a text header line
            continue
        rows.append((i, _numbers(line, path, i)))
    if not rows:
        raise RecordError(f"{path}: no numeric data")
    return rows, header


def _header_units(path: Path, header: tuple[int, str], units: str, level: int) -> None:
    """A warning (at ``level``) when the text header line (number, text) names other
    units than ``units`` (a record in g read as m/s² is 9.81 times too weak, and runs
    without any other sign)."""
    i, line = header
    named = [u for u, pat in _HEADER_UNITS.items() if pat.search(line.lower())]
    given = {"gal": "cm/s2", "m/s^2": "m/s2"}.get(units.lower(), units.lower())
    if len(named) == 1 and named[0] != given:
        log.log(level, "%s: line %d: the header %r names the units %s but the record is "
                "read in %s (units = %r): check the units", path, i, line.strip()[:60],
                named[0], units, units)  # fmt: skip


def _one_column(path: Path, lines: list[str], rows: list[tuple[int, list[float]]]) -> None:
    """Refuse a table read as one column: several numbers per line are a wrapped sequence
    only when blanks separate them and the first numbers of the lines do not march on
    like times (a table of time and several channels separated by blanks); commas,
    semicolons or tabs make a table (time and acceleration, several channels, or decimal
    commas), whose values would be interleaved."""
    k = len(rows[0][1])
    if k > 1 and len(rows) >= 3 and all(len(r) == k for _, r in rows[:-1]):
        first = np.array([r[0] for _, r in rows[:-1]] if len(rows[-1][1]) != k
                         else [r[0] for _, r in rows])  # fmt: skip
        step = np.diff(first)
        if first.size >= 3 and step.min() > 0 and step.min() > 0.5 * step.max():
            i, line = rows[0][0], lines[rows[0][0] - 1].strip()
            raise RecordError(f"{path}: line {i}: {k} numbers a line ({line[:40]!r}) whose "
                              f"first ones step on like times ({first[0]:g}, {first[1]:g}, "
                              f"{first[2]:g}, ...): a table of time and {k - 1} column(s), not "
                              "one column of accelerations; expected two columns, time and "
                              "acceleration (or one acceleration a line, with dt)")  # fmt: skip
    for i, r in rows:
        if len(r) > 1 and re.search(r"[,;\t]", lines[i - 1].strip()):
            line = lines[i - 1].strip()
            hint = (" (decimal commas? write numbers with a decimal point)"
                    if re.search(r"\d,\d", line) and ";" in line else
                    "; a record of time and acceleration is read as two columns")  # fmt: skip
            raise RecordError(f"{path}: line {i}: {len(r)} numbers separated by ',', ';' or "
                              f"tabs ({line[:40]!r}): a table, not one column of "
                              f"accelerations{hint}")  # fmt: skip


_COMMA_DECIMAL = re.compile(r"\d,\d")
_LEADING_ZERO = re.compile(r"(?<![\d.])[-+]?\d+,0\d")


def _decimal_commas(path: Path, lines: list[str], rows: list[tuple[int, list[float]]],
                    loose: bool = False) -> None:  # fmt: skip
    """Refuse numbers written with decimal commas (``0,0123``), which would be read as
    two numbers: the data has no decimal point anywhere, and a line has a comma between
    digits beside another separator (``0;0,01``, ``0<tab>0,01``), or a comma followed by
    a leading zero (``0,0123``), or (``loose``: two columns whose times do not increase,
    or that were given a ``dt``) one comma on every line."""
    text = [(i, lines[i - 1].strip()) for i, _ in rows]
    if any("." in t for _, t in text):
        return

    def evident(t: str) -> bool:
        other = re.search(r"[;\t]|\d\s+[-+]?\d", t) is not None
        return bool(_COMMA_DECIMAL.search(t)) and (other or bool(_LEADING_ZERO.search(t)))

    hit = next(((i, t) for i, t in text if evident(t)), None)
    if hit is None and loose and all(t.count(",") == 1 and _COMMA_DECIMAL.search(t)
                                     for _, t in text):  # fmt: skip
        hit = text[0]
    if hit is None:
        return
    i, t = hit
    raise RecordError(f"{path}: line {i}: decimal commas in {t[:40]!r}; expected numbers with a "
                      "decimal point (0.0123, not 0,0123)")  # fmt: skip


def read_record(
    path: str | Path,
    *,
    fmt: str = "auto",
    dt: float | None = None,
    units: str | None = None,
    scale: float = 1.0,
    direction: Sequence[float] = (1.0, 0.0),
    baseline: bool = False,
    name: str | None = None,
    highpass: float | None = None,
    lowpass: float | None = None,
    order: int = 4,
    quiet: bool = False,
) -> GroundMotion:
    """Read an acceleration record into a :class:`GroundMotion` (see the module doc).

    ``units`` defaults to the units an AT2 file states (g in PEER's files) and must be given
    otherwise (no guessing).
    The record is scaled by ``scale``, then, with ``highpass`` or ``lowpass`` (corner
    frequencies, Hz), filtered by :meth:`GroundMotion.filtered` (zero-phase Butterworth of
    order ``order``), then, with ``baseline``, corrected by
    :meth:`GroundMotion.baseline_corrected`: the baseline correction comes last, so that
    the record as applied ends at rest (the filter would change its final velocity).
    With ``quiet`` its warnings (a header naming other units, gaps in the times) are logged
    at DEBUG: a record read again after a reading that warned (a study's runs).
    """
    level = logging.DEBUG if quiet else logging.WARNING
    p = Path(path)
    if not is_number(scale) or not (np.isfinite(scale) and scale != 0):
        # (as the model file's ground_motion[].scale: a record scaled to nothing)
        raise RecordError(f"{p}: scale: expected a finite factor other than 0, got {scale!r}")
    if not p.is_file():
        raise RecordError(f"{p}: record file not found")
    raw = p.read_bytes()
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):  # a byte-order mark of UTF-16
        try:
            raw = raw.decode("utf-16").encode("utf-8")
        except UnicodeDecodeError:
            raise RecordError(
                f"{p}: a UTF-16 text file that does not decode; expected "
                "a text file (save it as UTF-8)"
            ) from None
    if b"\0" in raw:
        raise RecordError(
            f"{p}: not a text file (it holds NUL bytes); expected a text "
            "record (PEER .AT2, or columns of numbers)"
        )
    try:  # UTF-8, a byte-order mark dropped; else Latin-1 (titles such as 'DÜZCE')
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    if text.lstrip().startswith(("$MeshFormat", "$Comments")):
        raise RecordError(f"{p}: expected a ground-motion record; this looks like a gmsh mesh")
    lines = text.splitlines()
    kind = fmt.lower()
    if kind not in ("auto", "at2", "two-column", "one-column"):
        raise RecordError(f"{p}: format must be auto, at2, two-column or one-column, got {fmt!r}")
    if kind == "auto" and (p.suffix.lower() == ".at2" or _peer_header(lines)):
        kind = "at2"
    if kind != "at2":
        rows, _ = _data_lines(p, lines)
        _decimal_commas(p, lines, rows)
    if kind == "auto":
        kind = "two-column" if len(rows[0][1]) == 2 else "one-column"
    label = name or p.stem
    if kind == "at2":
        acc, step, title, at2_units = _read_at2(p, lines, units)
        if dt is not None and dt != step:
            raise RecordError(
                f"{p}: a PEER .AT2 record states its own time step (DT = "
                f"{step:g} s in its header); do not give dt (given {dt:g})"
            )
        gm = _make(p, acc, step, None, at2_units, scale, direction, name or title)
    else:
        if units is None:
            raise RecordError(f"{p}: give the units of the record (g, m/s2 or cm/s2)")
        rows, header = _data_lines(p, lines)
        if header is not None:
            _header_units(p, header, units, level)
        if kind == "two-column":
            bad = [i for i, r in rows if len(r) != 2]
            if bad:
                raise RecordError(f"{p}: line {bad[0]}: expected 2 columns (time, acceleration)")
            data = np.array([r for _, r in rows])
            if dt is not None:
                _decimal_commas(p, lines, rows, loose=True)
                raise RecordError(f"{p}: a two-column record has its own times; do not give dt")
            if np.any(np.diff(data[:, 0]) <= 0):
                _decimal_commas(p, lines, rows, loose=True)
                i = int(np.argmax(np.diff(data[:, 0]) <= 0)) + 1
                raise RecordError(f"{p}: line {rows[i][0]}: times must increase")
            t, acc = data[:, 0], data[:, 1]
            gaps = time_gaps(t)
            if gaps:
                where = "; ".join(f"line {rows[i + 1][0]}: {h:g} s after t = {t[i]:g} s"
                                  for i, h, _ in gaps[:3])  # fmt: skip
                n = len(gaps)
                log.log(level, "%s: the time step jumps beyond %g × its median of %g s at "
                        "%d place(s) (%s): samples missing, or records joined? The "
                        "acceleration is interpolated linearly across each gap", p,
                        TIME_GAP, gaps[0][2], n, where)  # fmt: skip
            gm = _make(p, acc, None, t, units, scale, direction, label)
        else:
            _one_column(p, lines, rows)
            if dt is None:
                raise RecordError(f"{p}: a one-column record needs its time step dt")
            acc = np.array([x for _, r in rows for x in r])
            gm = _make(p, acc, dt, None, units, scale, direction, label)
    if scale != 1.0:  # said in its summary line, as a model file's scale is
        how = "flipped (scale -1)" if scale == -1.0 else f"scaled ×{scale:g}"
        gm = dataclasses.replace(gm, scaling=how)
    if highpass is not None or lowpass is not None:
        try:
            gm = gm.filtered(highpass=highpass, lowpass=lowpass, order=order)
        except ModelError as exc:
            raise RecordError(f"{p}: {exc}") from None
    return gm.baseline_corrected() if baseline else gm


def _make(
    p: Path, acc: FloatArray, dt: float | None, t: FloatArray | None, units: str, scale: float,
    direction: Sequence[float], label: str,
) -> GroundMotion:  # fmt: skip
    try:
        return GroundMotion.from_samples(acc, dt=dt, time=t, units=units, scale=scale,
                                         direction=direction, name=label)  # fmt: skip
    except ModelError as exc:  # the reason
        raise RecordError(f"{p}: {exc}") from None


def write_at2(path: str | Path, acc_g: FloatArray, dt: float, title: str = "record") -> None:
    """Write a record (in g) in the PEER NGA AT2 format (NGA-West1 header, 5 per line)."""
    acc = np.asarray(acc_g, dtype=float)
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", title,
             "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {acc.size:5d}, DT= {dt:9.4f} SEC"]  # fmt: skip
    for i in range(0, acc.size, 5):
        lines.append("".join(f"{x:15.7E}" for x in acc[i : i + 5]))
    Path(path).write_text("\n".join(lines) + "\n")
