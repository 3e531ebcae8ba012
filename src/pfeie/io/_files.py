"""Output folders: created, or a clear error naming the folder (never an ``OSError``); the
kind of a file given where a model or study file was expected."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError

#: the model file a run made through the Python API records (:meth:`Job.of_run`)
PYTHON_RUN = "<python>"


def utf8_text(text: str) -> str:
    r"""``text`` as valid UTF-8: a file name that is not UTF-8 (Latin-1 bytes, which
    Python holds as lone surrogates) keeps its bytes as ``\xe9`` escapes, where
    writing it to an HDF5 attribute or a UTF-8 table would fail.

    >>> utf8_text("lat\udce9 dir"), utf8_text("Düzce")
    ('lat\\xe9 dir', 'Düzce')
    """
    return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def output_folder(path: str | Path, where: str = "") -> Path:
    """Create the folder ``path`` (and its parents) if needed and check that it can be
    written; :class:`InputError` names the folder (after ``where``, e.g. the model file
    and key) and what was expected."""
    p = Path(path)
    head = f"{where}: " if where else ""
    expect = "expected a folder that can be created and written"
    try:
        if p.exists() and not p.is_dir():
            raise InputError(f"{head}{p}: is a file, not a folder ({expect})")
        p.mkdir(parents=True, exist_ok=True)
    except (OSError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise InputError(f"{head}{p}: cannot create the output folder: {reason} "
                         f"({expect})") from None  # fmt: skip
    if not os.access(p, os.W_OK | os.X_OK):
        raise InputError(f"{head}{p}: the output folder is not writable ({expect})")
    return p


def output_file(path: str | Path, where: str = "") -> Path:
    """The folder of an output file, created and checked by :func:`output_folder`; an
    existing file must be writable. :class:`InputError` names the file (after ``where``)."""
    p = Path(path)
    head = f"{where}: " if where else ""
    if "\x00" in str(p):
        raise InputError(f"{head}{str(p)!r}: a path with a NUL character (expected the path "
                         "of a file to write)")  # fmt: skip
    if p.is_dir():
        raise InputError(f"{head}{p}: is a folder (expected the path of a file to write)")
    try:
        output_folder(p.parent)
    except InputError as exc:
        raise InputError(f"{head}{p}: cannot write the file: {exc}") from None
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(f"{head}{p}: the file exists and is not writable (expected the path "
                         "of a file to write)")  # fmt: skip
    return p


def toml_text(path: Path, raw: bytes) -> str:
    """The text of a TOML file (a model or study file) from its bytes: UTF-8, with the
    byte-order mark that some editors (Windows Notepad) write first dropped; a UTF-16
    file is refused with a message that says so (:class:`InputError`), other bytes that
    are not UTF-8 raise UnicodeDecodeError for the caller's message."""
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    elif raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(f"{path}: the file is UTF-16 text (it starts with a UTF-16 "
                         "byte-order mark); expected UTF-8: save it as UTF-8")  # fmt: skip
    return raw.decode("utf-8")


def foreign_file(path: Path, raw: bytes) -> str | None:
    """What a file that is not TOML looks like, when it is recognisably another input of
    pfeie (a gmsh mesh, an HDF5 results file, a ground-motion record); ``None`` else."""
    head = raw[:4096].lstrip()
    suffix = path.suffix.lower()
    if head.startswith((b"$MeshFormat", b"$Comments")) or suffix == ".msh":
        return "a gmsh mesh"
    if raw.startswith(b"\x89HDF\r\n\x1a\n") or suffix in (".h5", ".hdf5"):
        return "an HDF5 file (a results file?)"
    if b"\0" in head and not head.startswith((b"\xff\xfe", b"\xfe\xff")):
        return "a binary file"
    if suffix in (".at2", ".csv") or head.startswith(b"PEER"):
        return "a ground-motion record"
    return None
