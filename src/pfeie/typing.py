"""Array types used throughout pfeie (one home for the aliases), and the base of its typed
settings.

Axis convention: element data are indexed ``(cell, quadrature point, node, component)``
(``(c, q, n, d)``); pair data ``(pair, component)`` with the local components ordered
(t₁, [t₂,] n), normal last; nodal fields ``(node, component)`` or flat node-major vectors
(``dof = node · d + component``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import BaseModel, ConfigDict, ValidationError

from .errors import SettingsError

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


class Settings(BaseModel):
    """Base of pfeie's typed settings (:class:`pfeie.SolverSettings`,
    :class:`pfeie.DynamicSettings`): frozen, no unknown field, and strict, as where an
    analysis takes them (a string for a number is refused, not converted). A wrong field
    raises :class:`pfeie.errors.SettingsError`, a :class:`pfeie.ModelError` (and a
    ``ValueError``) naming each field, what was expected and what was given. NumPy
    scalars are taken as the Python numbers they hold.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    def __init__(self, /, **data: Any) -> None:
        # NumPy scalars as the Python numbers they hold (a script that loops over an array
        # of settings passes np.int64, np.bool_), strings still refused
        data = {k: v.item() if isinstance(v, np.generic) and not isinstance(v, np.str_ | np.bytes_)
                else v for k, v in data.items()}  # fmt: skip
        try:
            self.__pydantic_validator__.validate_python(data, self_instance=self, strict=True)
        except ValidationError as exc:
            raise SettingsError(f"{type(self).__name__}: {settings_message(exc)}") from None

    # validation inside another model (the model file's [analysis], a subclass) goes on
    # with pydantic's own errors, which name the key path: pydantic calls an __init__ that
    # is not marked as the base one there
    __init__.__pydantic_base_init__ = True  # type: ignore[attr-defined]


__all__ = [
    "BoolArray", "FloatArray", "IntArray", "Settings", "Unit", "is_number", "settings_message",
]  # fmt: skip
