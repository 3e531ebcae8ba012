"""A small declarative validator for TOML model files, with precise messages.

A :class:`Table` lists its keys as :class:`Key` (type, required, default, check, doc); a
:class:`Named` table holds user-named sub-tables of one spec (``[materials.concrete]``);
a :class:`Many` is an array of tables (``[[supports]]``). Validation returns plain dicts
with defaults filled in and raises :class:`InputError` naming the file, the key path, what
was expected and what was found. Unknown keys are errors.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import InputError

Check = Callable[[Any], str | None]  # returns an error text, or None when fine


@dataclass(frozen=True)
class Key:
    """One key: expected type(s), whether required, default, extra check, doc line."""

    types: tuple[type, ...]
    doc: str
    required: bool = False
    default: Any = None
    check: Check | None = None
    expect: str = ""


@dataclass(frozen=True)
class Table:
    keys: Mapping[str, Key | Table | Named | Many]
    doc: str = ""
    required: bool = False


@dataclass(frozen=True)
class Named:
    """User-named sub-tables (or values) that all follow ``item``."""

    item: Key | Table
    doc: str = ""
    required: bool = False


@dataclass(frozen=True)
class Many:
    """An array of tables that all follow ``item``."""

    item: Table
    doc: str = ""
    required: bool = False
    default: list[Any] = field(default_factory=list)


def _tname(x: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
            list: "an array", dict: "a table"}.get(type(x), type(x).__name__)  # fmt: skip


def _expected(k: Key) -> str:
    if k.expect:
        return k.expect
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
             list: "an array", dict: "a table"}  # fmt: skip
    return " or ".join(names.get(t, t.__name__) for t in k.types)


def validate(spec: Table, data: Any, where: str, path: str = "") -> dict[str, Any]:
    """Validate ``data`` against a table spec; ``where`` is the file name for messages."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: [{path or 'top level'}] must be a table, found {_tname(data)}")
    out: dict[str, Any] = {}
    unknown = sorted(set(data) - set(spec.keys))
    if unknown:
        raise InputError(
            f"{where}: {_join(path, unknown[0])}: unknown key; expected one of: "
            f"{', '.join(sorted(spec.keys))}"
        )
    for name, sub in spec.keys.items():
        p = _join(path, name)
        if name not in data:
            if getattr(sub, "required", False):
                raise InputError(f"{where}: {p}: missing (required)")
            if isinstance(sub, Key):
                out[name] = sub.default
            elif isinstance(sub, Many):
                out[name] = list(sub.default)
            elif isinstance(sub, Named):
                out[name] = {}
            else:
                out[name] = validate(sub, {}, where, p)
            continue
        out[name] = _value(sub, data[name], where, p)
    return out


def _value(sub: Key | Table | Named | Many, value: Any, where: str, p: str) -> Any:
    if isinstance(sub, Key):
        ok = isinstance(value, sub.types) and not (
            isinstance(value, bool) and bool not in sub.types
        )
        if not ok and float in sub.types and isinstance(value, int) and not isinstance(value, bool):
            value, ok = float(value), True
        if not ok:
            raise InputError(f"{where}: {p}: expected {_expected(sub)}, found {_tname(value)} "
                             f"{value!r}")  # fmt: skip
        if sub.check is not None:
            err = sub.check(value)
            if err:
                raise InputError(f"{where}: {p}: expected {err}, found {value!r}")
        return value
    if isinstance(sub, Table):
        return validate(sub, value, where, p)
    if isinstance(sub, Named):
        if not isinstance(value, dict):
            raise InputError(f"{where}: {p}: expected a table, found {_tname(value)}")
        return {k: _value(sub.item, v, where, _join(p, k)) for k, v in value.items()}
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise InputError(f"{where}: {p}: expected an array of tables ([[{p}]]), found "
                         f"{_tname(value)}")  # fmt: skip
    return [validate(sub.item, v, where, f"{p}[{i}]") for i, v in enumerate(value)]


def _join(path: str, name: str) -> str:
    return f"{path}.{name}" if path else name


# -- checks ------------------------------------------------------------------------------------
def positive(x: Any) -> str | None:
    return None if x > 0 else "a number > 0"


def non_negative(x: Any) -> str | None:
    return None if x >= 0 else "a number >= 0"


def one_of(*choices: str) -> Check:
    def check(x: Any) -> str | None:
        return None if x in choices else "one of " + ", ".join(repr(c) for c in choices)

    return check


def vector(n_min: int = 2, n_max: int = 3) -> Check:
    def check(x: Any) -> str | None:
        good = n_min <= len(x) <= n_max and all(
            isinstance(v, int | float) and not isinstance(v, bool) for v in x
        )
        return None if good else f"an array of {n_min} to {n_max} numbers"

    return check


def angle(x: Any) -> str | None:
    return None if 0 <= x < 90 else "an angle in [0, 90) degrees"


def describe(spec: Table | Named | Many | Key, path: str = "") -> list[tuple[str, str, str]]:
    """(key path, expected, doc) for every key of a spec: the model-file reference."""
    rows: list[tuple[str, str, str]] = []
    if isinstance(spec, Key):
        req = "required" if spec.required else f"default {spec.default!r}"
        rows.append((path, f"{_expected(spec)}; {req}", spec.doc))
    elif isinstance(spec, Table):
        for k, sub in spec.keys.items():
            rows += describe(sub, _join(path, k))
    elif isinstance(spec, Named):
        rows += describe(spec.item, _join(path, "<name>"))
    else:
        rows += describe(spec.item, f"{path}[]")
    return rows
