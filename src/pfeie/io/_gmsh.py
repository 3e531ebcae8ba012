"""gmsh meshes (``.msh`` 2.2 and 4.1, through meshio) with physical groups as named groups.

The physical groups of the top dimension (surfaces in 2D, volumes in 3D) become cell
groups: the blocks. Groups one dimension lower (curves in 2D, surfaces in 3D) become facet
groups: interfaces, supports, loaded faces. Lower groups (points) are ignored with a log
message. The mesh dimension is that of the highest-dimensional cells; a 2D mesh drawn in
the plane z = 0 keeps x and y (a 2D mesh with varying z is refused). The mesh is checked
(:func:`pfeie.mesh.check_cells`: degenerate, inverted, duplicated cells); cells are named
in messages by their gmsh element ids (read from ASCII files; binary files name cells by
type and index).

Example (the demo's mesh; ``tests/test_io.py`` reads MSH 2.2 and 4.1 files)::

    from pfeie.io import read_mesh
    mesh = read_mesh("examples/koyna/koyna.msh")
    sorted(mesh.cell_groups)      # ['dam_lower', 'dam_upper', 'rock']
"""

from __future__ import annotations

import contextlib
import io
import logging
import math
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..element import SUPPORTED, cell_dimension
from ..errors import MeshError
from ..mesh import Mesh, planar_points

log = logging.getLogger(__name__)

#: the dimension of the cell types gmsh writes that pfeie has no element for (to name
#: the physical group that holds them: gmsh numbers groups per dimension)
_UNSUPPORTED_DIM = {"wedge": 3, "wedge15": 3, "wedge18": 3, "pyramid": 3, "pyramid13": 3,
                    "pyramid14": 3, "hexahedron20": 3, "hexahedron24": 3, "hexahedron27": 3,
                    "tetra20": 3, "triangle10": 2, "quad16": 2, "line4": 1}  # fmt: skip
#: the cell types of gmsh's third order (Mesh.ElementOrder = 3)
_ORDER_3 = {"line4", "triangle10", "quad16", "tetra20", "hexahedron64", "wedge40", "pyramid30"}


def read_mesh(path: str | Path) -> Mesh:
    """Read a gmsh file; its named physical groups become cell and facet groups.

    A file that is empty, not a gmsh file, truncated or corrupt is refused with a
    :class:`MeshError` that names it and says why (the section not closed, the line that is
    not numbers, the node that is missing); the gmsh reader's own warnings are logged,
    naming the file."""
    p = Path(path)
    if not p.is_file():
        raise MeshError(f"{p}: mesh file not found")
    try:
        from meshio import gmsh
    except ImportError:  # pragma: no cover - meshio is in the io extra
        raise MeshError("reading gmsh files needs meshio: pip install 'pfeie[io]'") from None
    try:
        fault = _not_gmsh(p)
    except OSError as exc:
        raise MeshError(f"{p}: cannot read the mesh file: {exc.strerror or exc}") from None
    if fault is not None:
        raise MeshError(f"{p}: cannot read the gmsh file: {fault}; {EXPECTED_MSH}")
    said = io.StringIO()  # meshio prints its warnings to stderr (rich): kept and logged
    try:  # meshio's own gmsh reader: meshio.read prints and exits on a ReadError
        with contextlib.redirect_stderr(said), warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")  # numpy's, on a corrupt file: logged, not shown
            m = gmsh.read(p)
        for w in caught:
            log.debug("%s: the gmsh reader: %s", p, w.message)
    except Exception as exc:
        log.debug("%s: the gmsh reader stopped: %r", p, exc)
        try:
            why = _unsupported(p, exc) or _diagnose(p)
        except Exception:  # (a diagnosis that fails itself: the general words)
            why = None
        why = why or "the file is truncated or corrupt (the gmsh reader could not parse it)"
        raise MeshError(f"{p}: cannot read the gmsh file: {why}; {EXPECTED_MSH}") from None
    finally:
        _log_reader_warnings(p, said.getvalue())
    blocks, fault = _element_blocks(p)
    if fault is not None:
        raise MeshError(f"{p}: cannot read the gmsh file: {fault}; {EXPECTED_MSH}")
    # the ids only name cells in messages: none where the blocks are not meshio's
    ids = None
    if blocks is not None and [len(b) for b in blocks] == [len(b.data) for b in m.cells]:
        ids = [np.asarray(b, dtype=np.int64) for b in blocks]
    return from_gmsh(m, p, ids)


EXPECTED_MSH = "expected a gmsh .msh file, format 2.2 or 4.1 (export it again from gmsh)"


def _not_gmsh(path: Path) -> str | None:
    """Why ``path`` is not a gmsh file at all (empty, binary data, another text), or
    ``None`` when it begins as one (``$MeshFormat``, after optional ``$Comments``)."""
    with path.open("rb") as fh:
        head = fh.read(4096)
    if not head.strip():
        return "the file is empty" if not head else "the file holds only blank space"
    first = head.lstrip().split(b"\n", 1)[0].strip()
    if first in (b"$MeshFormat", b"$Comments"):
        return None
    if first.removeprefix(b"\xef\xbb\xbf") in (b"$MeshFormat", b"$Comments"):
        return ("it begins with a UTF-8 byte-order mark (an editor saved it so), which the "
                "gmsh reader does not take: save it without one (or export it again from "
                "gmsh)")  # fmt: skip
    try:
        text = first.decode("utf-8")
    except UnicodeDecodeError:
        text = ""
    if not text or not text.isprintable():
        return "not a gmsh file: it begins with binary data, not $MeshFormat"
    return f"not a gmsh file: it begins with {text[:40]!r}, not $MeshFormat"


def _log_reader_warnings(path: Path, said: str) -> None:
    """Log what meshio printed while reading ``path`` (its warnings), naming the file."""
    for line in said.splitlines():
        text = line.strip().removeprefix("Warning:").strip()
        if not text:
            continue
        hit = re.fullmatch(r"\$(\w+) not closed by \$End\w+\.?", text)
        if hit:
            text = (f"the section ${hit[1]} is not closed by $End{hit[1]}: the file may be "
                    "truncated (export the mesh again from gmsh)")  # fmt: skip
        log.warning("%s: %s", path, text)


#: the largest file whose section names are scanned for a feature the reader lacks
_SCAN_BYTES = 256 * 2**20


def _unsupported(path: Path, exc: Exception) -> str | None:
    """A valid gmsh file that the reader cannot take, and how to export it instead: a
    format version other than 2.2 and 4.1, parametric nodes (``Mesh.SaveParametric``), a
    partitioned mesh, entities outside the physical groups (``Mesh.SaveAll``); ``None``
    where it is none of these (a damaged file: :func:`_diagnose`)."""
    with path.open("rb") as fh:
        head = fh.read(4096)
    hit = re.search(rb"\$MeshFormat\s+(\S+)", head)
    version = hit[1].decode("ascii", "replace") if hit else "?"
    if version not in ("2", "2.2", "4.1"):  # (2: an older 2.x header, read as 2.2)
        return (f"the file is in gmsh's format {version}, which pfeie does not read (set "
                "Mesh.MshFileVersion = 2.2 or 4.1 in gmsh and save it again)")  # fmt: skip
    said = str(exc)
    if isinstance(exc, UnicodeDecodeError):
        return ("the file holds text that is not UTF-8 (a physical group's name in Latin-1, "
                "say), which the gmsh reader does not take: name the groups in ASCII or "
                "UTF-8 and export the mesh again")  # fmt: skip
    if "parametric" in said.lower():
        return (
            "the file holds parametric node coordinates (gmsh's Mesh.SaveParametric = "
            "1), which pfeie does not read (save it again with Mesh.SaveParametric = 0)"
        )
    sections: set[bytes] = set()
    if path.stat().st_size <= _SCAN_BYTES:
        sections = set(re.findall(rb"(?m)^\$(\w+)", path.read_bytes()))
    if b"ParametricNodes" in sections:
        return ("the file holds parametric nodes ($ParametricNodes: gmsh's "
                "Mesh.SaveParametric = 1), which pfeie does not read (save it again with "
                "Mesh.SaveParametric = 0)")  # fmt: skip
    if b"PartitionedEntities" in sections or b"GhostElements" in sections:
        return (
            "the mesh is partitioned ($PartitionedEntities), which pfeie does not read "
            "(save the mesh before partitioning it, or unpartition it in gmsh)"
        )
    if "Incompatible cell data" in said:
        return (
            "the file holds entities that belong to no physical group (gmsh's "
            "Mesh.SaveAll = 1), which pfeie does not read; save it again with "
            "Mesh.SaveAll = 0: the blocks and the joints in named physical groups"
        )
    return None


def _diagnose(path: Path) -> str | None:
    """What is wrong with an ASCII .msh file that meshio could not read: a section that is
    not closed (a truncated file), a line of ``$Nodes`` or ``$Elements`` that is not
    numbers, a count of nodes or elements that the section does not hold (MSH 2), an
    element on a node that ``$Nodes`` lacks (MSH 2); ``None`` when none is found."""
    version, ascii_ = b"", True
    section, start, n = "", 0, 0
    rows: list[list[bytes]] = []
    nodes: set[int] = set()
    with path.open("rb") as fh:
        for n, raw in enumerate(fh, start=1):
            line = raw.strip()
            if section == "MeshFormat" and not version and line:
                fields = line.split()
                version = fields[0]
                ascii_ = len(fields) < 2 or fields[1] == b"0"
            if line.startswith(b"$") and (ascii_ or line[1:].isalpha()):
                name = line[1:].decode("ascii", "replace")
                if not section:
                    section, start, rows = name, n, []
                    continue
                if name != f"End{section}":
                    return (f"line {n}: {name!r} inside the section ${section} (from line "
                            f"{start}), which is not closed by $End{section}: the file is "
                            "truncated or corrupt")  # fmt: skip
                if ascii_ and version.startswith(b"2") and section in ("Nodes", "Elements"):
                    fault = _check_msh2_section(section, start, rows, nodes)
                    if fault:
                        return fault
                section = ""
                continue
            if section in ("Nodes", "Elements") and ascii_ and line:
                fields = line.split()
                try:
                    what = "" if all(math.isfinite(float(f)) for f in fields) else "finite numbers"
                except ValueError:
                    what = "numbers"
                if what:
                    text = line.decode("utf-8", "replace")[:40]
                    return (f"line {n} (section ${section}): {text!r} is not {what}: the file "
                            "is corrupt")  # fmt: skip
                rows.append(fields)
    if section:
        return (f"the file is truncated: the section ${section} (from line {start}) is not "
                f"closed by $End{section} (the file ends at line {n})")  # fmt: skip
    return None


def _check_msh2_section(section: str, start: int, rows: list[list[bytes]],
                        nodes: set[int]) -> str | None:  # fmt: skip
    """A fault of an MSH 2 ASCII ``$Nodes`` or ``$Elements`` section (its rows after the
    line ``start``): a count that the rows do not match, an element on a missing node."""
    what = "nodes" if section == "Nodes" else "elements"
    if not rows or len(rows[0]) != 1:
        return f"line {start + 1} (section ${section}): expected the number of {what}"
    declared = int(float(rows[0][0]))
    if declared != len(rows) - 1:
        return (f"the section ${section} (line {start}) declares {declared} {what} but holds "
                f"{len(rows) - 1}: the file is truncated or corrupt")  # fmt: skip
    if section == "Nodes":
        short = next((k for k, r in enumerate(rows[1:]) if len(r) != 4), None)
        if short is not None:
            return (f"line {start + 2 + short} (section $Nodes): expected 4 numbers (tag, x, "
                    f"y, z), found {len(rows[short + 1])}: the file is corrupt")  # fmt: skip
        nodes.update(int(float(r[0])) for r in rows[1:])
        return None
    for row in rows[1:]:
        if len(row) < 3 or len(row) < 3 + int(float(row[2])):
            return f"gmsh element {row[0].decode()}: too few fields: the file is corrupt"
        for node in row[3 + int(float(row[2])) :]:
            if int(float(node)) not in nodes:
                return (f"gmsh element {row[0].decode()} refers to node {node.decode()}, "
                        "which is not in the section $Nodes")  # fmt: skip
    return None


class _Mismatch(Exception):
    """The ``$Elements`` section ended (or went on) where its counts say otherwise."""


#: the message of a ``$Elements`` section whose counts do not match its lines
_COUNTS = ("the section $Elements does not hold the element lines its counts declare: the "
           "file is corrupt (an element count edited by hand?)")  # fmt: skip


def _element_blocks(path: Path) -> tuple[list[list[int]] | None, str | None]:
    """One pass over the ``$Elements`` section of an ASCII .msh file (2.2 or 4.x), read
    as its counts declare it: the gmsh element ids by block (meshio drops them; in MSH 2
    a block is a run of one element type), and the fault where the section holds more or
    fewer lines than its counts (MSH 2: the count; 4.1: each block's and the total),
    which the gmsh reader does not check: it reads the declared number and drops the
    rest (a crest's pressure on half its faces, unseen). ``(None, None)`` for a binary
    file or a section this pass cannot follow (the reader's answer stands)."""

    def element(lines: Any) -> list[bytes]:
        line = next(lines)
        if line.startswith(b"$"):  # the section's end before its counts are read
            raise _Mismatch
        return list(line.split())

    try:
        with path.open("rb") as fh:
            lines = (raw.strip() for raw in fh)
            for line in lines:
                if line == b"$MeshFormat":
                    version, ftype = next(lines).split()[:2]
                    if ftype != b"0":
                        return None, None
                    break
            else:
                return None, None
            if b"$Elements" not in lines:  # (consumes the lines up to the section)
                return None, None
            blocks: list[list[int]] = []
            if version.startswith(b"2"):
                last = None
                for _ in range(int(next(lines))):
                    fields = element(lines)
                    if fields[1] != last:
                        blocks.append([])
                        last = fields[1]
                    blocks[-1].append(int(fields[0]))
            else:
                n_blocks, n_elements = (int(x) for x in next(lines).split()[:2])
                for _ in range(n_blocks):
                    k = int(element(lines)[3])
                    blocks.append([int(element(lines)[0]) for _ in range(k)])
                if sum(len(b) for b in blocks) != n_elements:
                    raise _Mismatch
            # (the file may end here: a missing $EndElements is the reader's warning)
            if next((x for x in lines if x), b"$EndElements") != b"$EndElements":
                raise _Mismatch
    except _Mismatch:
        return None, _COUNTS
    except (OSError, ValueError, IndexError, StopIteration):
        return None, None
    return blocks, None


def from_gmsh(m: Any, path: Path | str = "<mesh>", ids: list[np.ndarray] | None = None) -> Mesh:
    """Build a :class:`Mesh` from a meshio mesh read from gmsh (physical groups by name),
    checked (:meth:`Mesh.check`); ``ids``: the gmsh element ids of each cell block."""
    phys = m.cell_data.get("gmsh:physical")
    # physical tags are numbered per dimension (a curve 1 and a surface 1 are two
    # groups): names by (dimension, tag), from the file's own table where it can be read
    # (meshio's field_data, keyed by name, keeps one of two groups of one name)
    table = _physical_names(Path(path)) if str(path) != "<mesh>" else None
    if table is not None:
        seen: dict[tuple[int, str], int] = {}
        names: dict[tuple[int, int], str] = {}
        for gdim, tag, gname in table:
            first = names.setdefault((gdim, tag), gname)
            if first != gname:
                raise MeshError(f"{path}: the physical group of dimension {gdim} and tag "
                                f"{tag} has two names, {first!r} and {gname!r}; expected one "
                                "name per group (the elements belong to one group: give the "
                                "second name its own group)")  # fmt: skip
            other = seen.setdefault((gdim, gname), tag)
            if other != tag:
                raise MeshError(f"{path}: the physical name {gname!r} is given to two groups "
                                f"of dimension {gdim} (tags {other} and {tag}); expected one "
                                "name per group (give the second group its own name, or "
                                "put both entities in one physical group)")  # fmt: skip
    else:
        names = {(int(v[1]), int(v[0])): str(k) for k, v in (m.field_data or {}).items()}

    def name_of(tag: Any, dim: int) -> str:
        return names.get((dim, int(tag)), f"physical_{int(tag)}")

    if phys is None or not names:
        raise MeshError(
            f"{path}: the mesh has no named physical groups; name the blocks and "
            "interfaces with Physical Surface/Curve (2D) or Volume/Surface (3D)"
        )
    if len(phys) != len(m.cells):  # MSH 4 with entities in no physical group: see cell_sets
        phys = [np.zeros(len(b.data), dtype=np.int64) for b in m.cells]
    elif not any(np.asarray(t).any() for t in phys) and not getattr(m, "cell_sets", None):
        # MSH 2.2 saved with Mesh.SaveAll = 1 (gmsh 4.x): every element in group 0
        raise MeshError(
            f"{path}: the file names physical groups ($PhysicalNames) but puts no element "
            "in any of them (physical tag 0 on every element: gmsh's Mesh.SaveAll = 1 in "
            "MSH 2.2); save it again with Mesh.SaveAll = 0: the blocks and the joints in "
            "named physical groups"
        )  # fmt: skip
    dims = [cell_dimension(b.type) if _known(b.type) else -1 for b in m.cells]
    # a cell type pfeie has no element for, in a physical group, would drop part of a
    # block or a face without a word: the highest dimension's named (a block's cells)
    foreign = [k for k, (block, tags) in enumerate(zip(m.cells, phys, strict=True))
               if dims[k] < 0 and (np.asarray(tags) != 0).any()
               and block.type not in ("vertex", "line", "line3")]  # fmt: skip
    if foreign:
        k = max(foreign, key=lambda i: _UNSUPPORTED_DIM.get(m.cells[i].type, 0))
        block, tags = m.cells[k], np.asarray(phys[k])
        tagged = tags != 0
        first = f" (gmsh element {int(ids[k][np.argmax(tagged)])})" if ids is not None else ""
        tag0 = int(tags[tagged][0])
        # gmsh numbers physical groups per dimension: the group of the cells' own
        # dimension first (a volume and a surface may both be group 2)
        dim = _UNSUPPORTED_DIM.get(block.type)
        group = names.get((dim, tag0)) if dim is not None else None
        if group is None:
            group = next((n for (_, t), n in names.items() if t == tag0), "?")
        known = ", ".join(t for t in SUPPORTED if cell_dimension(t) >= 2)
        if block.type in _ORDER_3:
            fix = ("the mesh is of the third order (gmsh's Mesh.ElementOrder = 3); pfeie's "
                   "elements are of the first and second orders: set Mesh.ElementOrder = 1 "
                   "or 2 and mesh again")  # fmt: skip
        else:
            fix = (f"pfeie has elements for {known} only: mesh this group with those ("
                   + ("triangles or quadrilaterals" if dim == 2 else
                      "tetrahedra, or hexahedra by recombination") + ", in gmsh)")  # fmt: skip
        raise MeshError(f"{path}: physical group {group!r}: {int((tags == tag0).sum())} "
                        f"{block.type} cell(s){first}; {fix}")  # fmt: skip
    top = max(dims, default=-1)
    if top not in (2, 3):
        raise MeshError(f"{path}: no 2D or 3D cells (found dimensions {sorted(set(dims))})")
    points = np.asarray(m.points, dtype=float)
    cells: dict[str, list[np.ndarray]] = {}
    cell_ids: dict[str, list[np.ndarray]] = {}
    counts: dict[str, int] = {}
    cgroups: dict[str, dict[str, list[np.ndarray]]] = {}
    fgroups: dict[str, dict[str, list[np.ndarray]]] = {}
    ignored: set[str] = set()
    offsets: list[int] = []
    for k, (block, dim, tags) in enumerate(zip(m.cells, dims, phys, strict=True)):
        data = np.asarray(block.data, dtype=np.int64)
        if data.size and (data.min() < 0 or data.max() >= points.shape[0]):
            raise MeshError(f"{path}: {block.type} elements refer to nodes that are not in the "
                            "file's node list")  # fmt: skip
        tags = np.asarray(tags, dtype=np.int64)
        offsets.append(counts.get(block.type, 0) if dim == top else 0)
        if dim == top:
            off = counts.get(block.type, 0)
            cells.setdefault(block.type, []).append(data)
            if ids is not None:
                cell_ids.setdefault(block.type, []).append(ids[k])
            counts[block.type] = off + data.shape[0]
            for tag in np.unique(tags):
                if tag == 0:
                    continue
                name = name_of(tag, dim)
                cgroups.setdefault(name, {}).setdefault(block.type, []).append(
                    off + np.flatnonzero(tags == tag))  # fmt: skip
        elif dim == top - 1:
            for tag in np.unique(tags):
                if tag == 0:
                    continue
                name = name_of(tag, dim)
                fgroups.setdefault(name, {}).setdefault(block.type, []).append(data[tags == tag])
        else:
            for tag in np.unique(tags):
                if tag:
                    ignored.add(name_of(tag, dim))
    _more_groups(m, dims, top, offsets, cgroups, fgroups)
    _merge_written_twice(cells, cell_ids, cgroups, path)
    if ignored:
        log.info("%s: physical groups of lower dimension ignored: %s", path, sorted(ignored))
    clash = set(cgroups) & set(fgroups)
    if clash:
        raise MeshError(f"{path}: names used for groups of two dimensions: {sorted(clash)}")
    used = np.unique(np.concatenate([np.concatenate(v).ravel() for v in cells.values()]))
    # keep only the nodes of the cells (gmsh may store geometry points)
    remap = np.full(points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)

    def rm(a: np.ndarray, group: str | None = None) -> np.ndarray:
        out = remap[a]
        if np.any(out < 0):
            node = int(np.asarray(a)[out < 0].ravel()[0])
            where = f"physical group {group!r}: " if group is not None else ""
            raise MeshError(f"{path}: {where}facets refer to nodes that no cell uses (node "
                            f"{node + 1} of the node list); expected facets on the faces of "
                            "the cells")  # fmt: skip
        return out

    mesh = Mesh(
        planar_points(points[used], top, str(path)),
        {t: rm(np.concatenate(v)) for t, v in cells.items()},
        {g: {t: np.unique(np.concatenate(v)) for t, v in d.items()} for g, d in cgroups.items()},
        {g: {t: rm(np.concatenate(v), g) for t, v in d.items()} for g, d in fgroups.items()},
        {t: np.concatenate(v) for t, v in cell_ids.items()} if ids is not None else {},
        {g: d for (d, _), g in names.items() if g not in cgroups and g not in fgroups},
    )
    flipped = mesh.orient()
    if flipped:
        log.info("%s: %d clockwise cell(s) reoriented", path, flipped)
    mesh.check(str(path))
    return mesh


def _merge_written_twice(
    cells: dict[str, list[np.ndarray]], cell_ids: dict[str, list[np.ndarray]],
    cgroups: dict[str, dict[str, list[np.ndarray]]], path: Path | str,
) -> None:  # fmt: skip
    """Merge the cells that MSH 2 writes once per physical group of their entity (a
    surface in the groups 'dam' and 'concrete': each element twice, on the same nodes,
    with two element ids and two tags) into one cell in both groups, as MSH 4 gives them
    (one element, an entity in two groups). Only copies whose groups are all different
    merge; a cell written twice in one group (or in none) stays, for
    :meth:`Mesh.check` to refuse as duplicated. In place."""
    for ctype in list(cells):
        conn = np.concatenate(cells[ctype])
        if conn.shape[0] < 2:
            continue
        _, first, inv = np.unique(conn, axis=0, return_index=True, return_inverse=True)
        inv = inv.ravel()
        head = first[inv]  # each cell's first copy
        copies = np.flatnonzero(head != np.arange(conn.shape[0]))
        if not copies.size:
            continue
        involved = np.flatnonzero(np.isin(head, head[copies]))  # every copy, first ones too
        member: dict[int, set[str]] = {int(i): set() for i in involved}
        for name, by_type in cgroups.items():
            for idx in by_type.get(ctype, []):
                for i in np.intersect1d(np.asarray(idx).ravel(), involved).tolist():
                    member[int(i)].add(name)
        # a cell's copies merge where each is in groups of its own; copies in one group
        # (or in none) stay, for Mesh.check to refuse as duplicated
        seen: dict[int, set[str]] = {}
        distinct: dict[int, bool] = {}
        for i in involved.tolist():
            first_i = int(head[i])
            got = seen.setdefault(first_i, set())
            ok = bool(member[i]) and not got & member[i]
            distinct[first_i] = distinct.get(first_i, True) and ok
            got |= member[i]
        merged = np.isin(head, [h for h, ok in distinct.items() if ok])
        keep = (head == np.arange(conn.shape[0])) | ~merged
        if keep.all():
            continue
        new_index = np.cumsum(keep) - 1
        target = np.where(merged, new_index[head], new_index)
        log.info("%s: %d %s cell(s) written once per physical group (MSH 2) taken as one cell "
                 "in each of their groups", path, int((~keep).sum()), ctype)  # fmt: skip
        cells[ctype] = [conn[keep]]
        if ctype in cell_ids:
            cell_ids[ctype] = [np.concatenate(cell_ids[ctype])[keep]]
        for by_type in cgroups.values():
            if ctype in by_type:
                by_type[ctype] = [np.unique(target[np.concatenate(by_type[ctype])])]


def _physical_names(path: Path) -> list[tuple[int, int, str]] | None:
    """The ``$PhysicalNames`` table of a gmsh file, as (dimension, tag, name) rows (the
    section is text in ASCII and binary files alike); None where the file or the section
    cannot be read that way."""
    try:
        with path.open("rb") as fh:
            for line in fh:
                if line.strip() == b"$PhysicalNames":
                    break
            else:
                return None
            n = int(fh.readline().split()[0])
            rows = []
            for _ in range(n):
                parts = fh.readline().decode("utf-8", "replace").split(maxsplit=2)
                rows.append((int(parts[0]), int(parts[1]), parts[2].strip().strip('"')))
            return rows
    except (OSError, ValueError, IndexError):
        return None


def _more_groups(
    m: Any, dims: list[int], top: int, offsets: list[int],
    cgroups: dict[str, dict[str, list[np.ndarray]]],
    fgroups: dict[str, dict[str, list[np.ndarray]]],
) -> None:  # fmt: skip
    """Add the memberships of entities in several physical groups (MSH 4: meshio's
    ``gmsh:physical`` keeps the first group of an entity, its ``cell_sets`` all of them;
    MSH 2 writes such elements once per group)."""
    sets = getattr(m, "cell_sets", None) or {}
    for name, value in (m.field_data or {}).items():
        per_block = sets.get(name)
        if per_block is None or len(per_block) != len(m.cells):
            continue
        gdim = int(value[1])
        for block, dim, off, idx in zip(m.cells, dims, offsets, per_block, strict=True):
            if idx is None or len(idx) == 0 or dim != gdim:
                continue
            idx = np.asarray(idx, dtype=np.int64)
            if dim == top:
                cgroups.setdefault(str(name), {}).setdefault(block.type, []).append(off + idx)
            elif dim == top - 1:
                data = np.asarray(block.data, dtype=np.int64)[idx]
                fgroups.setdefault(str(name), {}).setdefault(block.type, []).append(data)


def _known(cell_type: str) -> bool:
    try:
        cell_dimension(cell_type)
    except MeshError:
        return False
    return True
