"""Gmsh physical groups are numbered per dimension: a curve 1 and a surface 1 are two
groups, each with its own name (a new user's valid MSH file, curves 1–4 and surfaces
1–2, was refused with "names used for groups of two dimensions"; a second surface named
like the first became 'physical_5' without a word)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pfeie.errors import MeshError
from pfeie.io import read_mesh

NODES = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]
QUADS = [(1, 2, 5, 4), (2, 3, 6, 5)]


def _msh(path: Path, names: list[tuple[int, int, str]], surface_tags: tuple[int, int],
         curves: list[tuple[int, tuple[int, int]]]) -> Path:  # fmt: skip
    """Two unit quads side by side, MSH 2.2 ASCII: ``names`` (dim, tag, name), the
    physical tag of each quad, and curves (tag, nodes)."""
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f'{d} {t} "{n}"' for d, t, n in names]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(NODES))]
    lines += [f"{i} {x} {y} 0" for i, (x, y) in enumerate(NODES, start=1)]
    elements = [(1, tag, nodes) for tag, nodes in curves]
    elements += [(3, tag, q) for tag, q in zip(surface_tags, QUADS, strict=True)]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{i} {t} 2 {tag} {tag} " + " ".join(map(str, ns))
              for i, (t, tag, ns) in enumerate(elements, start=1)]  # fmt: skip
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_tags_are_per_dimension(tmp_path: Path) -> None:
    """Curves 1 and 2 and surfaces 1 and 2: four groups, each with its cells or facets."""
    p = _msh(tmp_path / "m.msh", [(1, 1, "bottom"), (1, 2, "mid"), (2, 1, "left"),
                                  (2, 2, "right")], (1, 2), [(1, (1, 2)), (1, (2, 3)),
                                                             (2, (2, 5))])  # fmt: skip
    mesh = read_mesh(p)
    assert sorted(mesh.cell_groups) == ["left", "right"]
    assert sorted(mesh.facet_groups) == ["bottom", "mid"]
    assert [len(v) for v in mesh.cell_groups["left"].values()] == [1]
    assert sum(len(v) for v in mesh.facet_groups["bottom"].values()) == 2


def test_one_name_for_two_groups_of_a_dimension_is_refused(tmp_path: Path) -> None:
    p = _msh(tmp_path / "m.msh", [(1, 1, "bottom"), (2, 1, "block"), (2, 2, "block")],
             (1, 2), [(1, (1, 2))])  # fmt: skip
    with pytest.raises(MeshError, match=r"the physical name 'block' is given to two groups of "
                       r"dimension 2 \(tags 1 and 2\)"):  # fmt: skip
        read_mesh(p)
