"""The package's layering, checked on its import graph (docs/architecture.md).

Subpackages depend on each other one way, from the finite element machinery up to the
command line:

    typing, errors → element → mesh → assembly, linalg → interface → model → coupling
    → solvers, dynamics → io → plot → verification → _job → study → cli

Two rules are checked on every import statement of ``src/pfeie``: no subpackage imports
one above it (so there is no cycle), and no module imports a private module (``_name``)
of another subpackage: subpackages meet through their ``__init__`` only.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "pfeie"

LAYERS = [
    {"typing", "errors", "_version"},
    {"element"},
    {"mesh"},
    {"assembly", "linalg"},
    {"interface"},
    {"model"},
    {"coupling"},
    {"solvers", "dynamics"},
    {"io"},
    {"plot"},
    {"verification"},
    {"_job"},
    {"study"},
    {"cli", "__main__", "__init__"},
]
RANK = {name: i for i, layer in enumerate(LAYERS) for name in layer}


def _unit(path: Path) -> str:
    """The top-level unit of a module: its subpackage, or the top-level module's name."""
    rel = path.relative_to(SRC).parts
    return rel[0] if len(rel) > 1 else Path(rel[0]).stem


def _imports(path: Path) -> list[tuple[str, int]]:
    """(absolute dotted target inside pfeie, line) of every import of a module."""
    tree = ast.parse(path.read_text())
    pkg = ["pfeie", *path.relative_to(SRC).parts[:-1]]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg[: len(pkg) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target == "pfeie" or target.startswith("pfeie."):
                if node.module is None or target.count(".") == 0:  # from . import x
                    out += [(f"{target}.{a.name}", node.lineno) for a in node.names]
                else:
                    out.append((target, node.lineno))
        elif isinstance(node, ast.Import):
            out += [(a.name, node.lineno) for a in node.names if a.name.startswith("pfeie")]
    return out


def _edges() -> list[tuple[str, str, str, str]]:
    """(module file, its unit, imported target, the target's unit)."""
    edges = []
    for path in SRC.rglob("*.py"):
        src = _unit(path)
        for target, line in _imports(path):
            parts = target.split(".")[1:]
            if not parts:
                continue
            edges.append((f"{path.relative_to(SRC)}:{line}", src, target, parts[0]))
    return edges


def test_every_unit_has_a_layer() -> None:
    units = {_unit(p) for p in SRC.rglob("*.py")}
    assert units <= set(RANK), f"units without a layer: {sorted(units - set(RANK))}"


def test_subpackages_depend_one_way() -> None:
    """No import points to a higher layer (which also rules out cycles between units)."""
    bad = [
        f"{where}: {src} imports {target}"
        for where, src, target, dst in _edges()
        if dst in RANK and src != dst and RANK[dst] > RANK[src]
        and src != "__init__"
    ]  # fmt: skip
    assert not bad, "\n".join(bad)


def test_no_private_module_of_another_subpackage_is_imported() -> None:
    bad = []
    for where, src, target, dst in _edges():
        parts = target.split(".")[1:]
        if src == dst or len(parts) < 2:
            continue
        if any(p.startswith("_") for p in parts[1:]):
            bad.append(f"{where}: {target}")
    assert not bad, "\n".join(bad)


def test_no_cycle_between_subpackages() -> None:
    """The unit graph is acyclic (checked directly, independently of the layer list)."""
    graph: dict[str, set[str]] = {}
    for _, src, _, dst in _edges():
        if src != dst and dst in RANK and src != "__init__":
            graph.setdefault(src, set()).add(dst)
    state: dict[str, int] = {}

    def visit(u: str, trail: list[str]) -> None:
        state[u] = 1
        for v in graph.get(u, ()):
            if state.get(v) == 1:
                pytest.fail("cycle: " + " → ".join([*trail, u, v]))
            if v not in state:
                visit(v, [*trail, u])
        state[u] = 2

    for u in list(graph):
        if u not in state:
            visit(u, [])


def test_py_typed_is_shipped() -> None:
    assert (SRC / "py.typed").is_file()
