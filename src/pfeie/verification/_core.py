"""Case registry, checks and results of the verification suite."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Check:
    """One verified quantity: |value − reference| ≤ tol (absolute) or ≤ tol·|reference|
    (``relative``); with ``at_least``, a lower bound: value ≥ reference − tol (the error
    is the shortfall, e.g. an observed convergence rate against the bound it must reach)."""

    quantity: str
    reference: float
    value: float
    tol: float
    relative: bool = True
    unit: str = ""
    at_least: bool = False

    @property
    def error(self) -> float:
        if self.at_least:
            return max(self.reference - self.value, 0.0)
        d = abs(self.value - self.reference)
        return d / abs(self.reference) if self.relative and self.reference else d

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.value) and self.error <= self.tol)

    @property
    def tolerance_text(self) -> str:
        if self.at_least:
            return f"≥ {self.reference - self.tol:.3g}"
        return f"{100 * self.tol:.3g} %" if self.relative else f"{self.tol:.3g} {self.unit}"

    @property
    def error_text(self) -> str:
        if self.at_least:
            return f"{self.error:.3g}"
        return f"{100 * self.error:.3g} %" if self.relative else f"{self.error:.3g} {self.unit}"


@dataclass
class Series:
    """One curve of a case figure (pfeie or reference)."""

    label: str
    x: np.ndarray
    y: np.ndarray
    style: str = "-"


@dataclass
class CaseResult:
    name: str
    title: str
    checks: list[Check]
    series: list[Series] = field(default_factory=list)
    xlabel: str = "time (s)"
    ylabel: str = ""
    notes: str = ""
    seconds: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)


@dataclass(frozen=True)
class Case:
    name: str
    title: str
    func: Callable[[bool], CaseResult]
    purpose: str
    reference: str
    sketch: str


CASES: dict[str, Case] = {}


def case(name: str, title: str, purpose: str, reference: str, sketch: str) -> Callable[
    [Callable[[bool], CaseResult]], Callable[[bool], CaseResult]
]:  # fmt: skip
    """Register a case function ``f(fast) -> CaseResult``."""

    def deco(func: Callable[[bool], CaseResult]) -> Callable[[bool], CaseResult]:
        CASES[name] = Case(name, title, func, purpose, reference, sketch)
        return func

    return deco


def run(fast: bool = True, names: list[str] | None = None) -> list[CaseResult]:
    """Run the cases (all, or the named ones) and return their results."""
    from . import _cases  # noqa: F401 - registers the cases

    selected = names if names else list(CASES)
    unknown = [n for n in selected if n not in CASES]
    if unknown:
        from ..errors import InputError

        raise InputError(f"unknown verification case(s) {unknown}; cases: {list(CASES)}")
    out = []
    for name in selected:
        t0 = time.perf_counter()
        res = CASES[name].func(fast)
        res.title = res.title or CASES[name].title
        res.seconds = time.perf_counter() - t0
        log.info("%s: %s in %.1f s", name, "pass" if res.passed else "FAIL", res.seconds)
        out.append(res)
    return out
