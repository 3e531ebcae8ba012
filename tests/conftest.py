"""Shared helpers for the verification tests."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.element import reference

CELLS_2D = ["triangle", "quad", "triangle6", "quad8", "quad9"]
CELLS_3D = ["tetra", "hexahedron", "tetra10"]


def unit_mesh(cell: str, n: int) -> pf.Mesh:
    """A unit square or cube of n elements per side."""
    if cell in CELLS_2D:
        return pf.rectangle(1.0, 1.0, n, n, cell=cell)
    return pf.box(1.0, 1.0, 1.0, n, n, n, cell=cell)


def distort(mesh: pf.Mesh, amount: float, seed: int = 0) -> pf.Mesh:
    """Move interior nodes randomly by up to ``amount`` × the smallest spacing."""
    rng = np.random.default_rng(seed)
    pts = mesh.points.copy()
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    interior = np.all((pts > lo + 1e-9) & (pts < hi - 1e-9), axis=1)
    pts[interior] += amount * rng.uniform(-1, 1, size=(interior.sum(), mesh.dim))
    for ctype, conn in mesh.cells.items():  # straight edges: mid-edge nodes at midpoints
        ref = reference(ctype)
        if ref.degree == 1:
            continue
        ne = len(ref.edges)
        nc = ref.n_corners
        edges = np.asarray(ref.edges)
        pts[conn[:, nc : nc + ne]] = 0.5 * (pts[conn[:, edges[:, 0]]] + pts[conn[:, edges[:, 1]]])
        if ref.n_nodes > nc + ne:
            pts[conn[:, -1]] = pts[conn[:, :nc]].mean(axis=1)
    return pf.Mesh(pts, mesh.cells, mesh.cell_groups, mesh.facet_groups)


@pytest.fixture(params=CELLS_2D + CELLS_3D)
def cell(request: pytest.FixtureRequest) -> str:
    return str(request.param)


_CASE_RESULTS: dict[str, object] = {}


def case_result(name: str):  # type: ignore[no-untyped-def]
    """The fast run of a verification case (pfeie.verification), run once per session and
    shared by the tests of the case and of the manual."""
    from pfeie.verification import run

    if name not in _CASE_RESULTS:
        _CASE_RESULTS[name] = run(fast=True, names=[name])[0]
    return _CASE_RESULTS[name]


def cli_fails(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> str:
    """``pfeie ARGV`` exits with 2, one or more ``pfeie: error`` lines holding every word,
    no traceback; returns the error output."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "pfeie: error" in err and "Traceback" not in err, err
    for w in words:
        assert w in err, (w, err)
    return err


def hold_folder(folder: Path, model: str = "other.toml") -> subprocess.Popen[str]:
    """Another process that holds the output folder ``folder`` as a run does
    (``pfeie._job.FolderLock``: the lock file, locked by the operating system), returned
    once it holds it; it lets go when its stdin is closed (or it is killed)."""
    code = ("import sys; from pathlib import Path; from pfeie._job import FolderLock; "
            f"lock = FolderLock(Path({str(folder)!r}), Path({model!r})); lock.__enter__(); "
            "print('held', flush=True); sys.stdin.read(); lock.__exit__()")  # fmt: skip
    proc = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)  # fmt: skip
    assert proc.stdout is not None and proc.stdout.readline().strip() == "held"
    return proc
