"""Figures of a study over many ground motions (matplotlib, Agg; no display needed).

- :func:`plot_ida`: the IDA curves, IM against demand (Vamvatsikos & Cornell 2002): one
  thin line per record, the fractile curves (16, 50, 84 %) bold, an optional threshold;
- :func:`plot_fragility`: fitted fragility curves with their confidence band and the
  empirical fractions of exceedance at each stripe as points;
- :func:`save_figure`: lay out, write and close a figure.

The functions take the objects of :mod:`pfeie.study` (``IDACurves``, ``IDASummary``,
``Fragility``) by their shape only (the protocols below), so that this module does not
import the study package.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..io import output_file
from ..typing import FloatArray, IntArray
from ._plots import _plt

PERCENTILE_COLOURS = ["#2b83ba", "#d7191c", "#1a9641", "#fdae61", "#7b3294"]


class IDACurvesLike(Protocol):
    """What :func:`plot_ida` reads of ``pfeie.study.IDACurves``."""

    @property
    def n_records(self) -> int: ...
    @property
    def column(self) -> str: ...
    def curve(self, i: int) -> tuple[FloatArray, FloatArray]: ...


class IDASummaryLike(Protocol):
    """What :func:`plot_ida` reads of ``pfeie.study.IDASummary``."""

    @property
    def im(self) -> FloatArray: ...
    @property
    def percentiles(self) -> tuple[float, ...]: ...
    @property
    def demand(self) -> FloatArray: ...


class StripesLike(Protocol):
    @property
    def im(self) -> FloatArray: ...
    @property
    def n_total(self) -> IntArray: ...
    @property
    def fraction(self) -> FloatArray: ...


class FragilityLike(Protocol):
    """What :func:`plot_fragility` reads of ``pfeie.study.Fragility``."""

    @property
    def name(self) -> str: ...
    @property
    def theta(self) -> float: ...
    @property
    def beta(self) -> float: ...
    @property
    def empirical(self) -> StripesLike | None: ...
    def probability(self, im: ArrayLike) -> FloatArray: ...
    def band(
        self, im: ArrayLike, level: float = 0.95, *, simultaneous: bool = False
    ) -> tuple[FloatArray, FloatArray]: ...


def _axes(ax: Any, figsize: tuple[float, float]) -> tuple[Any, Any]:
    if ax is None:
        fig, ax = _plt().subplots(figsize=figsize)
        return fig, ax
    return ax.figure, ax


def plot_ida(
    curves: IDACurvesLike,
    summary: IDASummaryLike | None = None,
    *,
    threshold: float | None = None,
    ax: Any = None,
    title: str = "",
    im_label: str = "IM",
    demand_label: str | None = None,
) -> Any:
    """IDA curves: IM (vertical) against the demand (horizontal), one thin grey line per
    record, the fractiles of ``summary`` bold (a fractile ends where it becomes infinite,
    once that share of records has collapsed), and ``threshold`` as a dashed vertical line.
    Returns the Figure: ``n_records + len(summary.percentiles) (+ 1)`` lines.

    >>> from pfeie.study import ida_curves, ida_summary
    >>> table = {"record": [1, 1, 2, 2], "im": [0.1, 0.3] * 2, "slip": [0.0, 0.2, 0.0, 0.4]}
    >>> c = ida_curves(table, "slip")
    >>> fig = plot_ida(c, ida_summary(c), threshold=0.3)
    >>> len(fig.axes[0].lines)
    6
    """
    fig, ax = _axes(ax, (6.0, 4.5))
    for i in range(curves.n_records):
        x, d = curves.curve(i)
        ax.plot(d, x, lw=0.7, color="0.6", alpha=0.8, marker=".", ms=2.5)
    if summary is not None:
        for j, p in enumerate(summary.percentiles):
            colour = PERCENTILE_COLOURS[j % len(PERCENTILE_COLOURS)]
            ax.plot(summary.demand[j], summary.im, lw=2.2, color=colour, label=f"{p:g} %")
    if threshold is not None:
        ax.axvline(threshold, color="k", ls="--", lw=1.0, label=f"threshold {threshold:g}")
    ax.set_xlabel(demand_label or curves.column)
    ax.set_ylabel(im_label)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    if summary is not None or threshold is not None:
        ax.legend(loc="lower right", fontsize=8)
    ax.set_title(title or f"IDA: {curves.n_records} records", fontsize=10)
    return fig


def plot_fragility(
    fits: FragilityLike | Sequence[FragilityLike],
    *,
    im: ArrayLike | None = None,
    level: float = 0.95,
    simultaneous: bool = False,
    ax: Any = None,
    title: str = "",
    im_label: str = "IM",
) -> Any:
    """Fragility curves P(DS ≥ ds | IM) of one or more fits, each with its confidence band
    (``level``, pointwise or ``simultaneous``; :meth:`pfeie.study.Fragility.band`) shaded
    and its empirical fractions of exceedance at the stripes as points.
    ``im``: the IM values of the curves (default 0 to beyond the largest 98 % point and
    the last stripe). Returns the Figure: a line per fit and one per fit with empirical
    fractions, one shaded band per fit.

    >>> from pfeie.study import fit_stripes
    >>> f = fit_stripes([0.2, 0.4, 0.6, 0.8], [1, 5, 9, 10], [10] * 4, name="sliding")
    >>> fig = plot_fragility(f)
    >>> len(fig.axes[0].lines), len(fig.axes[0].collections)
    (2, 1)
    """
    seq = list(fits) if isinstance(fits, Sequence) else [fits]
    if not seq:
        raise ModelError("plot_fragility: no fragility to plot")
    if im is None:
        top = max(f.theta * float(np.exp(2.05 * f.beta)) for f in seq)
        for f in seq:
            if f.empirical is not None and f.empirical.im.size:
                top = max(top, 1.05 * float(np.max(f.empirical.im)))
        x = np.linspace(0.0, top, 301)
    else:
        x = np.asarray(im, dtype=float).ravel()
    fig, ax = _axes(ax, (6.0, 4.5))
    for i, f in enumerate(seq):
        colour = f"C{i % 10}"
        label = f"{f.name + ': ' if f.name else ''}θ = {f.theta:.3g}, β = {f.beta:.2f}"
        ax.plot(x, f.probability(x), color=colour, lw=1.8, label=label)
        lo, hi = f.band(x, level, simultaneous=simultaneous)
        ax.fill_between(x, lo, hi, color=colour, alpha=0.18, lw=0)
        e = f.empirical
        if e is not None:
            ax.plot(e.im, e.fraction, ls="none", marker="o", ms=5, mfc="none", mec=colour,
                    mew=1.2)  # fmt: skip
    ax.set_xlabel(im_label)
    ax.set_ylabel("P(DS ≥ ds | IM)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(left=float(min(x.min(), 0.0)))
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    band = "simultaneous" if simultaneous else "pointwise"
    ax.set_title(title or f"fragility ({100 * level:g} % {band} band)", fontsize=10)
    return fig


def save_figure(fig: Any, path: str | Path, *, dpi: int = 110) -> Path:
    """Lay out ``fig``, write it to ``path`` (its folder created; the format from the
    suffix) and close it; returns the path."""
    p = output_file(path)
    fig.tight_layout()
    fig.savefig(p, dpi=dpi)
    _plt().close(fig)
    return p
