"""Array types used throughout pfeie (one home for the aliases).

Axis convention: element data are indexed ``(cell, quadrature point, node, component)``
(``(c, q, n, d)``); pair data ``(pair, component)`` with the local components ordered
(t₁, [t₂,] n), normal last; nodal fields ``(node, component)`` or flat node-major vectors
(``dof = node · d + component``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from pydantic import ValidationError

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class Unit:
    """The unit of a number in typed settings (``Annotated[float, Field(...), Unit("Pa")]``),
    printed by the model file's messages and reference (``Pa``, ``m``, ``s``)."""

    text: str


def is_number(v: object) -> bool:
    """A real number given to the API: an int or a float, NumPy's scalars and 0-d
    numeric arrays included; not a bool, a string or None.

    >>> is_number(2), is_number(np.float32(2.0)), is_number(np.array(2.0)), is_number("2")
    (True, True, True, False)
    """
    if isinstance(v, np.ndarray):
        return v.ndim == 0 and v.dtype.kind in "iuf"
    return isinstance(v, int | float | np.integer | np.floating) and not isinstance(
        v, bool | np.bool_)  # fmt: skip


def settings_message(exc: ValidationError) -> str:
    """A one-line message of a settings error: each field, what was expected, what was
    given."""
    parts = []
    for err in exc.errors():
        where = ".".join(str(x) for x in err["loc"]) or "settings"
        given = f", got {err['input']!r}" if err["type"] != "missing" else ""
        msg = err["msg"].removeprefix("Value error, ")
        parts.append(f"{where}: {msg}{given}")
    return "; ".join(parts)


__all__ = ["BoolArray", "FloatArray", "IntArray", "Unit", "is_number", "settings_message"]
