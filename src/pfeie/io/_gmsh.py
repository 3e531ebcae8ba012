"""gmsh meshes (``.msh`` 2.2 and 4.1, through meshio) with physical groups as named groups.

The physical groups of the top dimension (surfaces in 2D, volumes in 3D) become cell
groups: the blocks. Groups one dimension lower (curves in 2D, surfaces in 3D) become facet
groups: interfaces, supports, loaded faces. Lower groups (points) are ignored with a log
message. The mesh dimension is that of the highest-dimensional cells; a 2D mesh drawn in
the plane z = 0 keeps x and y.

Example (the demo's mesh; ``tests/test_io.py`` reads MSH 2.2 and 4.1 files)::

    from pfeie.io import read_mesh
    mesh = read_mesh("examples/koyna/koyna.msh")
    sorted(mesh.cell_groups)      # ['dam_lower', 'dam_upper', 'rock']
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import numpy as np

from ..element import cell_dimension
from ..errors import MeshError
from ..mesh import Mesh

log = logging.getLogger(__name__)


def read_mesh(path: str | Path) -> Mesh:
    """Read a gmsh file; its named physical groups become cell and facet groups."""
    p = Path(path)
    if not p.is_file():
        raise MeshError(f"{p}: mesh file not found")
    try:
        import meshio
    except ImportError:  # pragma: no cover - meshio is in the io extra
        raise MeshError("reading gmsh files needs meshio: pip install 'pfeie[io]'") from None
    try:
        m = meshio.read(p, file_format="gmsh")
    except Exception as exc:
        raise MeshError(f"{p}: cannot read the gmsh file ({type(exc).__name__}: {exc})") from None
    return from_gmsh(m, p)


def from_gmsh(m: Any, path: Path | str = "<mesh>") -> Mesh:
    """Build a :class:`Mesh` from a meshio mesh read from gmsh (physical groups by name)."""
    phys = m.cell_data.get("gmsh:physical")
    names = {int(v[0]): (str(k), int(v[1])) for k, v in (m.field_data or {}).items()}
    if phys is None or not names:
        raise MeshError(
            f"{path}: the mesh has no named physical groups; name the blocks and "
            "interfaces with Physical Surface/Curve (2D) or Volume/Surface (3D)"
        )
    dims = [cell_dimension(b.type) if _known(b.type) else -1 for b in m.cells]
    top = max(dims)
    if top not in (2, 3):
        raise MeshError(f"{path}: no 2D or 3D cells (found dimensions {sorted(set(dims))})")
    points = np.asarray(m.points, dtype=float)[:, :top]
    cells: dict[str, list[np.ndarray]] = {}
    counts: dict[str, int] = {}
    cgroups: dict[str, dict[str, list[np.ndarray]]] = {}
    fgroups: dict[str, dict[str, list[np.ndarray]]] = {}
    ignored: set[str] = set()
    for block, dim, tags in zip(m.cells, dims, phys, strict=True):
        data = np.asarray(block.data, dtype=np.int64)
        tags = np.asarray(tags, dtype=np.int64)
        if dim == top:
            off = counts.get(block.type, 0)
            cells.setdefault(block.type, []).append(data)
            counts[block.type] = off + data.shape[0]
            for tag in np.unique(tags):
                name = names.get(int(tag), (f"physical_{tag}", dim))[0]
                cgroups.setdefault(name, {}).setdefault(block.type, []).append(
                    off + np.flatnonzero(tags == tag))  # fmt: skip
        elif dim == top - 1:
            for tag in np.unique(tags):
                if tag == 0:
                    continue
                name = names.get(int(tag), (f"physical_{tag}", dim))[0]
                fgroups.setdefault(name, {}).setdefault(block.type, []).append(data[tags == tag])
        else:
            for tag in np.unique(tags):
                if tag:
                    ignored.add(names.get(int(tag), (f"physical_{tag}", dim))[0])
    if ignored:
        log.info("%s: physical groups of lower dimension ignored: %s", path, sorted(ignored))
    clash = set(cgroups) & set(fgroups)
    if clash:
        raise MeshError(f"{path}: names used for groups of two dimensions: {sorted(clash)}")
    used = np.unique(np.concatenate([np.concatenate(v).ravel() for v in cells.values()]))
    # keep only the nodes of the cells (gmsh may store geometry points)
    remap = np.full(points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)

    def rm(a: np.ndarray) -> np.ndarray:
        out = remap[a]
        if np.any(out < 0):
            raise MeshError(f"{path}: facets refer to nodes that no cell uses")
        return out

    mesh = Mesh(
        points[used],
        {t: rm(np.concatenate(v)) for t, v in cells.items()},
        {g: {t: np.concatenate(v) for t, v in d.items()} for g, d in cgroups.items()},
        {g: {t: rm(np.concatenate(v)) for t, v in d.items()} for g, d in fgroups.items()},
    )
    flipped = mesh.orient()
    if flipped:
        log.info("%s: %d clockwise cell(s) reoriented", path, flipped)
    return mesh


def _known(cell_type: str) -> bool:
    try:
        cell_dimension(cell_type)
    except Exception:
        return False
    return True
