"""The verification suite: reference cases with closed-form or independent references.

``run(fast=True, names=None)`` runs the cases and returns :class:`CaseResult` objects,
each with its checks (quantity, reference, pfeie, error, tolerance, pass) and the series
of its figure. ``pfeie verify`` prints the table; ``pfeie verify --manual DIR`` (``make
verify``) regenerates the verification manual (one page per case, figures, the summary
table). The cases are V1–V11 (:mod:`._cases`: closed forms and sources); their builders
and the exact rigid-block integrator live here so that the tests, the command and the
manual run the same code.
"""

from ._core import CASES, CaseResult, Check, Series, run
from ._manual import write_manual

__all__ = ["CASES", "CaseResult", "Check", "Series", "run", "write_manual"]
