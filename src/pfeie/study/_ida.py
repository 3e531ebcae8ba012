"""Incremental dynamic analysis (IDA) curves from a demand table (Vamvatsikos & Cornell 2002).

A study's *demand table* has one row per run (a record scaled to an intensity): the record
id, the intensity measure IM of the run and one column per demand (peak or residual slip,
opening, the minimum sliding safety factor, ...). Any object with ``table[name]`` giving a
column works: a ``dict`` of arrays, a pyarrow ``Table``, a pandas ``DataFrame``.

- :func:`ida_curves`: per record, its demand against IM, sorted by IM (one IDA curve per
  record, as rows of NaN-padded arrays);
- :func:`first_exceedance`: per record, the IM at which the curve first reaches a
  threshold, by linear interpolation between the last run below it and the first run at
  or beyond it,

  IM_c = x_{k−1} + (t − d_{k−1}) (x_k − x_{k−1}) / (d_k − d_{k−1}),

  with the censoring that a fit needs: a record that never reaches the threshold up to its
  largest IM x_max is right-censored (IM_c > x_max, ``im = inf``); one that is already
  beyond at its first run x₁ is left-censored (IM_c ≤ x₁); one whose run fails (a NaN
  demand counted as exceeding, ``nan_policy="exceeded"``) is interval-censored,
  x_{k−1} < IM_c ≤ x_k;
- :func:`ida_summary`: the 16, 50 and 84 % fractiles of the demand across records on a
  common IM grid (linear interpolation along each curve). A record that has "collapsed"
  (first exceedance of a collapse limit state at or below the IM) counts as an infinite
  demand, so that it stays in the count: the 84 % curve ends (flatlines) once more than
  16 % of the records have collapsed, the median once more than half. A record neither
  run at that IM nor collapsed is unknown and left out (``n_known``).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ModelError
from ..typing import BoolArray, FloatArray, IntArray

log = logging.getLogger(__name__)

Direction = Literal[">=", "<="]
NanPolicy = Literal["raise", "exceeded", "omit"]


class Table(Protocol):
    """A table of columns: ``table[name]`` is an array-like column (a ``dict`` of arrays, a
    pyarrow ``Table``, a pandas ``DataFrame``)."""

    def __getitem__(self, key: str, /) -> Any: ...


@dataclass(frozen=True)
class LimitState:
    """A limit state on one demand column.

    Exceeded when ``demand >= threshold`` (``direction=">="``: peak slip ≥ 0.1 m) or when
    ``demand <= threshold`` (``"<="``: the minimum sliding safety factor ≤ 1.0). A NaN
    demand never compares as exceeded (see ``nan_policy`` of the functions that read a
    table).
    """

    name: str
    column: str
    threshold: float
    direction: Direction = ">="

    def __post_init__(self) -> None:
        if self.direction not in (">=", "<="):
            raise ModelError(
                f"limit state {self.name!r}: direction must be '>=' or '<=', "
                f"found {self.direction!r}"
            )
        if not np.isfinite(self.threshold):
            raise ModelError(
                f"limit state {self.name!r}: threshold must be a finite number, "
                f"found {self.threshold!r}"
            )

    def exceeded(self, demand: ArrayLike) -> BoolArray:
        """Whether each demand is at or beyond the threshold (False for NaN)."""
        d = np.asarray(demand, dtype=float)
        with np.errstate(invalid="ignore"):
            return d >= self.threshold if self.direction == ">=" else d <= self.threshold


@dataclass(frozen=True)
class Stripes:
    """Observed exceedances at IM levels: ``n_exceeded`` of ``n_total`` records at ``im``."""

    im: FloatArray
    n_exceeded: IntArray
    n_total: IntArray

    @property
    def fraction(self) -> FloatArray:
        """The empirical fraction of exceedance at each level (NaN where none is known)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.n_total > 0, self.n_exceeded / np.maximum(self.n_total, 1), np.nan)


@dataclass(frozen=True, eq=False)
class IDACurves:
    """One IDA curve per record: row ``i`` holds the ``n_points[i]`` runs of
    ``records[i]`` by increasing IM, padded with NaN to the longest curve."""

    records: NDArray[Any]
    im: FloatArray
    demand: FloatArray
    n_points: IntArray
    column: str

    @property
    def n_records(self) -> int:
        return int(self.records.size)

    @property
    def im_max(self) -> FloatArray:
        """The largest IM run of each record."""
        return self.im[np.arange(self.n_records), self.n_points - 1]

    def curve(self, i: int) -> tuple[FloatArray, FloatArray]:
        """(IM, demand) of the ``i``-th record, by increasing IM."""
        n = int(self.n_points[i])
        return self.im[i, :n].copy(), self.demand[i, :n].copy()


@dataclass(frozen=True, eq=False)
class Exceedance:
    """Per record, where the capacity IM_c (the IM of first exceedance) lies:
    ``lower < IM_c ≤ upper``, with ``lower == upper`` when it was interpolated between two
    runs (an exact observation), ``lower = 0`` when the first run already exceeds
    (left-censored), ``upper = inf`` when no run exceeds (right-censored at ``im_max``).
    ``stripes`` are the cumulative empirical fractions: at each IM level of the table, the
    records seen beyond the threshold at a run at or below it, out of the records known
    there (run at or above that IM, or already beyond).
    """

    records: NDArray[Any]
    lower: FloatArray
    upper: FloatArray
    im_max: FloatArray
    stripes: Stripes
    threshold: float
    direction: Direction

    @property
    def exact(self) -> BoolArray:
        """Records whose IM_c was interpolated between two runs."""
        return np.asarray(self.lower == self.upper)

    @property
    def exceeded(self) -> BoolArray:
        """Records that reach the threshold at some run."""
        return np.isfinite(self.upper)

    @property
    def im(self) -> FloatArray:
        """The IM of first exceedance: interpolated when exact, the IM of the first run
        beyond the threshold when censored on the left or in an interval, ``inf`` when the
        threshold is never reached."""
        return self.upper.copy()


@dataclass(frozen=True, eq=False)
class IDASummary:
    """Fractiles of the demand across records on an IM grid: ``demand[j, k]`` is the
    ``percentiles[j]`` % fractile at ``im[k]`` over the ``n_known[k]`` records known
    there, ``n_collapsed[k]`` of which count as collapsed (``±inf``)."""

    im: FloatArray
    percentiles: tuple[float, ...]
    demand: FloatArray
    n_known: IntArray
    n_collapsed: IntArray
    column: str


def _names(table: Table) -> list[str]:
    for attr in ("column_names", "columns"):
        cols = getattr(table, attr, None)
        if cols is not None:
            return [str(c) for c in cols]
    keys = getattr(table, "keys", None)
    return [str(k) for k in keys()] if callable(keys) else []


def _column(table: Table, name: str, what: str = "demand") -> NDArray[Any]:
    """A column of a table as a 1D array; :class:`~pfeie.errors.ModelError` naming the
    columns when there is none of that name."""
    try:
        col = table[name]
    except (KeyError, IndexError, TypeError, ValueError):
        raise ModelError(
            f"the demand table has no {what} column {name!r}; its columns: {_names(table)}"
        ) from None
    arr = np.asarray(col)
    if arr.ndim != 1:
        raise ModelError(f"the {what} column {name!r} is not one-dimensional: shape {arr.shape}")
    return arr


def _floats(arr: NDArray[Any], name: str) -> FloatArray:
    try:
        return np.asarray(arr, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"the column {name!r} holds values that are not numbers") from None


def ida_curves(
    table: Table,
    demand: str,
    *,
    record: str = "record",
    intensity: str = "im",
    nan_policy: NanPolicy = "raise",
) -> IDACurves:
    """The IDA curve of every record: its ``demand`` column against IM, sorted by IM.

    ``nan_policy`` says what a NaN demand (a run that failed) is: ``"raise"``
    (:class:`~pfeie.errors.ModelError`), ``"exceeded"`` (kept: it counts as beyond every
    threshold, see :func:`first_exceedance`) or ``"omit"`` (the row is dropped).

    >>> table = {"record": ["a", "a", "b", "b"], "im": [0.2, 0.1, 0.1, 0.2],
    ...          "slip": [0.05, 0.01, 0.0, 0.02]}
    >>> c = ida_curves(table, "slip")
    >>> c.curve(0)
    (array([0.1, 0.2]), array([0.01, 0.05]))
    """
    ids = _column(table, record, "record")
    x = _floats(_column(table, intensity, "intensity"), intensity)
    d = _floats(_column(table, demand, "demand"), demand)
    if not (ids.size == x.size == d.size):
        raise ModelError(
            f"the columns {record!r}, {intensity!r} and {demand!r} have different lengths: "
            f"{ids.size}, {x.size}, {d.size}"
        )
    if x.size == 0:
        raise ModelError("the demand table has no rows")
    bad = ~(np.isfinite(x) & (x > 0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ModelError(
            f"the intensity column {intensity!r} must hold finite numbers > 0; row {i} "
            f"(record {ids[i]!r}) has {x[i]!r}"
        )
    nan = np.isnan(d)
    if nan.any():
        if nan_policy == "raise":
            i = int(np.flatnonzero(nan)[0])
            raise ModelError(
                f"the demand column {demand!r} has {int(nan.sum())} NaN values (runs that "
                f"failed?), first at row {i} (record {ids[i]!r}, IM {x[i]:g}); pass "
                "nan_policy='exceeded' to count a failed run as beyond every threshold, or "
                "'omit' to drop it"
            )
        if nan_policy == "omit":
            log.info("dropping %d rows with a NaN %r", int(nan.sum()), demand)
            ids, x, d = ids[~nan], x[~nan], d[~nan]
            if x.size == 0:
                raise ModelError(f"every row of the demand column {demand!r} is NaN")
        elif nan_policy != "exceeded":
            raise ModelError(
                f"nan_policy must be 'raise', 'exceeded' or 'omit', found {nan_policy!r}"
            )
    try:
        records, inv = np.unique(ids, return_inverse=True)
    except TypeError:
        raise ModelError(f"the record ids of column {record!r} cannot be sorted") from None
    inv = inv.reshape(-1)
    order = np.lexsort((x, inv))
    inv_s, x_s, d_s = inv[order], x[order], d[order]
    dup = np.flatnonzero((inv_s[1:] == inv_s[:-1]) & (x_s[1:] == x_s[:-1]))
    if dup.size:
        i = int(dup[0])
        raise ModelError(
            f"record {records[inv_s[i]]!r} has two rows at the intensity {x_s[i]:g}: one "
            "run per record and intensity is expected"
        )
    counts = np.bincount(inv_s, minlength=records.size).astype(np.int64)
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    pos = np.arange(x_s.size) - start[inv_s]
    im = np.full((records.size, int(counts.max())), np.nan)
    dem = np.full_like(im, np.nan)
    im[inv_s, pos] = x_s
    dem[inv_s, pos] = d_s
    return IDACurves(records, im, dem, counts, demand)


def first_exceedance(
    curves: IDACurves, threshold: float, direction: Direction = ">="
) -> Exceedance:
    """Per record, the IM at which its curve first reaches ``threshold``.

    With x_k the first run at or beyond the threshold t (``d ≥ t`` or ``d ≤ t``), linear
    interpolation from the run before it gives IM_c = x_{k−1} + (t − d_{k−1})
    (x_k − x_{k−1}) / (d_k − d_{k−1}). A record never beyond t is right-censored at its
    largest IM (``im = inf``); one beyond t at its first run is left-censored,
    0 < IM_c ≤ x₁; a NaN or infinite demand at x_k leaves x_{k−1} < IM_c ≤ x_k.

    >>> table = {"record": [1, 1, 1, 2, 2, 2], "im": [0.1, 0.2, 0.3] * 2,
    ...          "slip": [0.0, 0.04, 0.12, 0.0, 0.01, 0.02]}
    >>> e = first_exceedance(ida_curves(table, "slip"), 0.1)
    >>> e.im  # 0.2 + (0.1 - 0.04) / (0.12 - 0.04) * 0.1; record 2 never reaches 0.1
    array([0.275,   inf])
    """
    ls = LimitState("threshold", curves.column, float(threshold), direction)
    n, k = curves.im.shape
    rows = np.arange(n)
    valid = np.arange(k)[None, :] < curves.n_points[:, None]
    beyond = valid & (ls.exceeded(curves.demand) | np.isnan(curves.demand))
    hit = beyond.any(axis=1)
    j = np.argmax(beyond, axis=1)  # first run beyond (0 when none)
    jp = np.maximum(j - 1, 0)
    x0, x1 = curves.im[rows, jp], curves.im[rows, j]
    d0, d1 = curves.demand[rows, jp], curves.demand[rows, j]
    im_max = curves.im_max
    lower = im_max.copy()
    upper = np.full(n, np.inf)
    first = hit & (j == 0)
    inner = hit & (j > 0)
    lower[first], upper[first] = 0.0, x1[first]
    exact = inner & np.isfinite(d0) & np.isfinite(d1)
    with np.errstate(invalid="ignore", divide="ignore"):
        xc = x0 + (threshold - d0) / (d1 - d0) * (x1 - x0)
    lower[exact] = upper[exact] = np.clip(xc[exact], x0[exact], x1[exact])
    gap = inner & ~exact
    lower[gap], upper[gap] = x0[gap], x1[gap]
    # cumulative empirical fractions at the IM levels of the table
    seen = np.where(hit, x1, np.inf)
    levels = np.unique(curves.im[valid])
    beyond_at = seen[None, :] <= levels[:, None]
    known = beyond_at | (im_max[None, :] >= levels[:, None])
    stripes = Stripes(
        levels, beyond_at.sum(axis=1).astype(np.int64), known.sum(axis=1).astype(np.int64)
    )
    log.debug(
        "%s %s %g: %d of %d records beyond (%d exact)",
        curves.column,
        direction,
        threshold,
        int(hit.sum()),
        n,
        int(exact.sum()),
    )
    return Exceedance(curves.records, lower, upper, im_max, stripes, float(threshold), direction)


def _fractiles(values: FloatArray, q: FloatArray) -> FloatArray:
    """Fractiles (``q`` in %) of each column over its non-NaN entries, linear between
    order statistics (numpy's default), ``±inf`` entries included: a fractile between a
    finite value and ``+inf`` is ``+inf``."""
    v = np.sort(values, axis=0)  # NaN last
    n = np.sum(~np.isnan(values), axis=0)
    h = (n - 1)[None, :] * (q[:, None] / 100.0)
    lo = np.clip(np.floor(h).astype(np.int64), 0, None)
    hi = np.clip(np.ceil(h).astype(np.int64), 0, None)
    a = np.take_along_axis(v, lo, axis=0)
    b = np.take_along_axis(v, hi, axis=0)
    t = h - lo
    with np.errstate(invalid="ignore"):
        out = np.where(t == 0, a, (1 - t) * a + t * b)
    return np.where(n[None, :] > 0, out, np.nan)


def ida_summary(
    curves: IDACurves,
    *,
    grid: ArrayLike | None = None,
    percentiles: tuple[float, ...] = (16.0, 50.0, 84.0),
    collapse: Exceedance | None = None,
    collapsed_value: float = np.inf,
) -> IDASummary:
    """Fractiles of the demand across records at each IM of ``grid`` (default: every IM
    level of the table).

    Each curve is interpolated linearly in IM between its runs; outside its runs it is
    unknown (NaN, left out of the fractiles). With ``collapse`` (the
    :func:`first_exceedance` of a collapse limit state, on any column of the same table), a
    record counts as ``collapsed_value`` (``+inf``; ``-inf`` for a demand that falls, as a
    safety factor) at and above its IM_c, run or not: it stays in the count, so that the
    fractiles above the share of collapsed records become infinite (the flatline of
    Vamvatsikos & Cornell 2002).

    >>> table = {"record": [1, 1, 2, 2, 3, 3], "im": [0.1, 0.3] * 3,
    ...          "slip": [0.0, 0.2, 0.0, 0.4, 0.0, 0.6]}
    >>> s = ida_summary(ida_curves(table, "slip"), grid=[0.2])
    >>> s.demand[:, 0]  # the 16, 50 and 84 % fractiles of (0.1, 0.2, 0.3)
    array([0.132, 0.2  , 0.268])
    """
    q = np.asarray(percentiles, dtype=float)
    if q.ndim != 1 or q.size == 0 or np.any((q < 0) | (q > 100)):
        raise ModelError(f"percentiles must be numbers in [0, 100], found {percentiles!r}")
    valid = np.arange(curves.im.shape[1])[None, :] < curves.n_points[:, None]
    g = np.unique(curves.im[valid]) if grid is None else np.asarray(grid, dtype=float).ravel()
    if g.size == 0 or not np.all(np.isfinite(g) & (g > 0)):
        raise ModelError("the IM grid must hold finite numbers > 0")
    n = curves.n_records
    rows = np.arange(n)[:, None]
    cnt = np.sum(curves.im[:, :, None] <= g[None, None, :], axis=1)  # runs at or below x
    j = np.clip(cnt - 1, 0, None)
    ju = np.minimum(j + 1, (curves.n_points - 1)[:, None])
    x0, x1 = curves.im[rows, j], curves.im[rows, ju]
    d0, d1 = curves.demand[rows, j], curves.demand[rows, ju]
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(x1 > x0, (g[None, :] - x0) / (x1 - x0), 0.0)
        val = np.where(t == 0, d0, (1 - t) * d0 + t * d1)
    inside = (cnt >= 1) & (g[None, :] <= curves.im_max[:, None])
    val = np.where(inside, val, np.nan)
    collapsed = np.zeros(val.shape, dtype=bool)
    if collapse is not None:
        if collapse.records.shape != curves.records.shape or np.any(
            collapse.records != curves.records
        ):
            raise ModelError("the collapse exceedance is not of the records of these curves")
        collapsed = g[None, :] >= collapse.im[:, None]
        val = np.where(collapsed, collapsed_value, val)
    known = ~np.isnan(val)
    return IDASummary(
        g,
        tuple(float(p) for p in q),
        _fractiles(val, q),
        known.sum(axis=0).astype(np.int64),
        (collapsed & known).sum(axis=0).astype(np.int64),
        curves.column,
    )
