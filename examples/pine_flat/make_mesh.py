"""Write ``pine_flat.msh``: a mapped, structured quadratic mesh (Q8) of a Pine Flat-like
gravity dam monolith with a lift joint, on a rock block (gmsh MSH 2.2, ASCII).

Geometry (m; x downstream from the heel, y up from the base; README.md gives the sources):

    crest  y = 121.92 (400 ft), 9.75 m wide (32 ft), x from 1.9812 to 11.7312;
    upstream face vertical down to y = 39.624 (130 ft), then battered 0.05 H : 1 V to the
    heel (0, 0);
    downstream face vertical down to y = 108.204 (355 ft), then sloping 0.78 H : 1 V to
    the toe (96.13032, 0): base width 96.13 m (315.4 ft);
    lift joint `lift` at y = 108.204, where the downstream slope starts;
    rock 96.13032 m on either side of the dam and 96.13032 m deep (3 × 1 base widths).

Each block is a rectangle of cells mapped onto its shape: the rows are horizontal lines,
the columns divide every row into equal parts (the dam's 16 columns run from the base to
the crest, so the base, the lift joint and the crest have 16 cells each); the rows of the
lower block are as tall as 1.5 × the width of their cells, so they get thinner towards the
neck; a row boundary lies at the upstream face's kink (39.624 m) and at the reservoir
level (116.12 m, 381 ft), so that the hydrostatic pressure's kink is a node. The rock's
columns under the dam are the dam's, and grow by 1.3 upstream, downstream and down.

Physical groups: blocks `dam_lower`, `dam_upper`, `rock`; interfaces `dam_rock` and
`lift`; faces `upstream` (the dam's upstream face, both blocks), `reservoir_floor` (the
rock's surface upstream of the heel) and `rock_bottom`.

The script uses only IEEE arithmetic (no transcendental functions) and writes every
coordinate with Python's shortest round-trip repr: the same bytes on every run and
platform. Run:  python examples/pine_flat/make_mesh.py  (writes next to this file).
"""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

HERE = Path(__file__).resolve().parent

# -- geometry (m) ---------------------------------------------------------------------------
H = 121.92  # dam height, 400 ft
CREST = 9.75  # crest width, 32 ft
Y_BATTER = 39.624  # top of the upstream batter, 130 ft above the base
BATTER = 0.05  # upstream batter, H : V
Y_SLOPE = 108.204  # top of the downstream slope, 355 ft above the base (the lift joint)
SLOPE = 0.78  # downstream slope, H : V
X_UP = 1.9812  # the vertical upstream face: BATTER × Y_BATTER = 6.5 ft
X_NECK = 11.7312  # the downstream face's vertical part: X_UP + CREST
TOE = 96.13032  # X_NECK + SLOPE × Y_SLOPE: the base width, 315.4 ft
LEVEL = 116.12  # reservoir level, 381 ft (a row boundary)
ROCK_UP = TOE  # rock upstream of the heel (m)
ROCK_DOWN = TOE  # rock downstream of the toe (m)
ROCK_DEPTH = TOE  # rock depth (m)

# -- mesh -----------------------------------------------------------------------------------
N_COL = 16  # columns of the dam
ASPECT = 1.5  # row height / cell width in the lower block
GROWTH = 1.3  # growth of the rock's cells away from the dam

GROUPS = {  # physical tag: (dimension, name)
    1: (2, "dam_lower"),
    2: (2, "dam_upper"),
    3: (2, "rock"),
    4: (1, "dam_rock"),
    5: (1, "lift"),
    6: (1, "upstream"),
    7: (1, "reservoir_floor"),
    8: (1, "rock_bottom"),
}


def x_left(y: float) -> float:
    """The upstream face's x at the elevation y of the lower block."""
    if y >= Y_BATTER:
        return X_UP
    t = y / Y_BATTER
    return X_UP * t


def x_right(y: float) -> float:
    """The downstream face's x at the elevation y (below the neck)."""
    if y >= Y_SLOPE:
        return X_NECK
    t = y / Y_SLOPE
    return TOE * (1.0 - t) + X_NECK * t


def spaced(a: float, b: float, steps: list[float]) -> list[float]:
    """Points from a to b (both exact) at the relative spacing ``steps``."""
    total = 0.0
    for s in steps:
        total += s
    out, acc = [a], 0.0
    for s in steps[:-1]:
        acc += s
        out.append(a + (b - a) * (acc / total))
    out.append(b)
    return out


def graded_rows(a: float, b: float) -> list[float]:
    """Row boundaries from a to b in the lower block, each row ASPECT × its cells' width
    (taken at its bottom) tall, rescaled to end at b."""
    steps, y = [], a
    while y < b:
        h = ASPECT * (x_right(y) - x_left(y)) / N_COL
        steps.append(h)
        y += h
    if len(steps) > 1 and y - b > 0.5 * steps[-1]:  # the last row would be thin
        steps.pop()
    return spaced(a, b, steps)


def uniform(a: float, b: float, size: float) -> list[float]:
    """Boundaries from a to b in equal parts of at most about ``size``."""
    n = max(1, int((b - a) / size + 0.5))
    return spaced(a, b, [1.0] * n)


def growing(first: float, length: float) -> list[float]:
    """Cell widths from ``first`` growing by GROWTH, rescaled to sum to ``length``: the
    boundaries from 0 to length."""
    steps, total, w = [], 0.0, first
    while total < length:
        steps.append(w)
        total += w
        w *= GROWTH
    if len(steps) > 1 and total - length > 0.5 * steps[-1]:
        steps.pop()
    return spaced(0.0, length, steps)


def halves(v: list[float]) -> list[float]:
    """The corners v and their midpoints: the coordinates of a quadratic grid."""
    out = []
    for a, b in pairwise(v):
        out += [a, 0.5 * (a + b)]
    return [*out, v[-1]]


class Builder:
    """Nodes shared by exact coordinates; Q8 cells and line3 facets with their groups."""

    def __init__(self) -> None:
        self.ids: dict[tuple[float, float], int] = {}
        self.points: list[tuple[float, float]] = []
        self.cells: list[tuple[int, list[int]]] = []  # (physical tag, 8 node ids)
        self.facets: list[tuple[int, list[int]]] = []  # (physical tag, 3 node ids)

    def node(self, x: float, y: float) -> int:
        key = (x + 0.0, y + 0.0)  # -0.0 is 0.0
        if key not in self.ids:
            self.points.append(key)
            self.ids[key] = len(self.points)
        return self.ids[key]

    def block(self, tag: int, grid: list[list[tuple[float, float]]]) -> list[list[int]]:
        """Q8 cells on a quadratic grid of points grid[i][j] (i across, j up; 2n + 1 each
        way); returns the node ids (−1 at the unused cell centres)."""
        ni, nj = len(grid), len(grid[0])
        ids = [[-1] * nj for _ in range(ni)]
        for j in range(nj):  # row by row, bottom up: node numbers follow the rows
            for i in range(ni):
                if i % 2 and j % 2:
                    continue
                ids[i][j] = self.node(*grid[i][j])
        for j in range(0, nj - 2, 2):
            for i in range(0, ni - 2, 2):
                corners = [ids[i][j], ids[i + 2][j], ids[i + 2][j + 2], ids[i][j + 2]]
                mids = [ids[i + 1][j], ids[i + 2][j + 1], ids[i + 1][j + 2], ids[i][j + 1]]
                self.cells.append((tag, corners + mids))
        return ids

    def line(self, tag: int, chain: list[int]) -> None:
        """line3 facets along a chain of 2n + 1 node ids (ends, then the middle)."""
        for k in range(0, len(chain) - 2, 2):
            self.facets.append((tag, [chain[k], chain[k + 2], chain[k + 1]]))


def build() -> Builder:
    """The mesh: nodes, cells and facets with their physical tags."""
    b = Builder()
    xi = halves([k / N_COL for k in range(N_COL + 1)])
    # lower block: rows graded up to the batter's kink and up to the neck
    y_low = halves(graded_rows(0.0, Y_BATTER)[:-1] + graded_rows(Y_BATTER, Y_SLOPE))
    grid = [[(x_left(y) + s * (x_right(y) - x_left(y)), y) for y in y_low] for s in xi]
    low = b.block(1, grid)
    # upper block: rows as tall as ASPECT × the crest cells' width, a row at the level
    size = ASPECT * CREST / N_COL
    y_up = halves(uniform(Y_SLOPE, LEVEL, size)[:-1] + uniform(LEVEL, H, size))
    grid = [[(X_UP + s * (X_NECK - X_UP), y) for y in y_up] for s in xi]
    up = b.block(2, grid)
    # rock: the dam's base columns, growing outwards and down
    base = [grid_x for grid_x, _ in (b.points[low[i][0] - 1] for i in range(len(xi)))]
    first = TOE / N_COL
    left = [-v for v in reversed(growing(first, ROCK_UP))]
    right = [TOE + v for v in growing(first, ROCK_DOWN)]
    x_rock = halves(left)[:-1] + base + halves(right)[1:]
    y_rock = [-v for v in reversed(halves(growing(first, ROCK_DEPTH)))]
    rock = b.block(3, [[(x, y) for y in y_rock] for x in x_rock])
    # facets
    b.line(4, [low[i][0] for i in range(len(xi))])  # dam_rock
    b.line(5, [low[i][-1] for i in range(len(xi))])  # lift
    b.line(6, low[0] + up[0][1:])  # upstream: heel to crest
    n_left = len(halves(left))
    b.line(7, [rock[i][-1] for i in range(n_left)])  # reservoir floor, to the heel
    b.line(8, [rock[i][0] for i in range(len(x_rock))])  # rock bottom
    return b


def msh(b: Builder) -> str:
    """The gmsh MSH 2.2 ASCII text: $PhysicalNames, $Nodes, $Elements (line3 facets, type
    8, then Q8 cells, type 16; tags: physical, elementary = physical)."""
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(GROUPS))]
    lines += [f'{d} {tag} "{name}"' for tag, (d, name) in GROUPS.items()]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(b.points))]
    lines += [f"{k} {x!r} {y!r} 0" for k, (x, y) in enumerate(b.points, start=1)]
    elements = [(8, tag, ns) for tag, ns in b.facets] + [(16, tag, ns) for tag, ns in b.cells]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{k} {t} 2 {tag} {tag} " + " ".join(map(str, ns))
              for k, (t, tag, ns) in enumerate(elements, start=1)]  # fmt: skip
    lines += ["$EndElements"]
    return "\n".join(lines) + "\n"


def main(path: Path = HERE / "pine_flat.msh") -> Path:
    """Write the mesh to ``path``."""
    b = build()
    path.write_text(msh(b))
    print(f"{path}: {len(b.points)} nodes, {len(b.cells)} Q8 cells, {len(b.facets)} facets")
    return path


if __name__ == "__main__":
    main()
