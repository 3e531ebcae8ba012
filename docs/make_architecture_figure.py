"""Draw docs/img/architecture.png: the package layers and one time step's data flow.

    python docs/make_architecture_figure.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch

OUT = Path(__file__).resolve().parent / "img" / "architecture.png"

LAYERS = [  # bottom to top: (names, what they hold)
    (["element", "mesh"], "reference elements, quadrature; meshes, groups"),
    (["assembly", "linalg"], "vectorised kernels, sparse assembly; factorisations"),
    (["interface"], "split into pairs, joint laws, pair states, interface solver"),
    (["model"], "physics objects: blocks, materials, loads, ground motion; Model"),
    (["coupling"], "G, Delassus W, static problem (§5.2), one-step problem (§5.1)"),
    (["solvers", "dynamics"], "statics, modal; integrators, excitation, corotation, recorder"),
    (["io", "plot"], "gmsh, records, model files, results (HDF5, ParaView); figures, report"),
    (["verification", "_job"], "reference cases V1–V10, the manual; a model file's run"),
    (["study", "cli"], "many records: system once per process, Dask, table, fragility; pfeie"),
]

STEP = [  # the data flow of one step, top to bottom: (box text, owner)
    ("Excitation.load(t₁): f = f_model − M ι a_g", "dynamics"),
    ("NonsmoothAlpha.free_acceleration: q̈_free = Ŝ⁻¹ r   (1 back-substitution)", "dynamics"),
    ("InterfaceStep: smooth forces λ, law on c_q G q̈ (springs: on G q_{n+1})", "coupling"),
    ("InterfaceSolver: w = w_free + s c_q W λ, joint law → λ, states (trial)", "interface"),
    ("velocity correction: impulses P (same W, impulse units), if needed", "coupling"),
    ("Delassus.correct [λ, P − hλ]; advance; position correction", "dynamics"),
    ("commit the trial pairs; Recorder + EnergyAccount", "dynamics"),
]

COLOURS = {"interface": "#f4d6a0", "coupling": "#f2b5b5", "dynamics": "#b9d7ea",
           "model": "#cfe8c6"}  # fmt: skip


def _box(ax, x, y, w, h, text, colour, size=9):  # type: ignore[no-untyped-def]
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02", fc=colour,
                                ec="0.3", lw=0.8))  # fmt: skip
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=size)


def main() -> None:
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(14, 7), gridspec_kw={"width_ratios": [1, 1.15]})
    for ax in (a1, a2):
        ax.set_xlim(0, 10)
        ax.set_ylim(0, 10)
        ax.axis("off")
    a1.set_title("Packages of pfeie (imports point down only)", fontsize=11)
    h, gap = 0.72, 0.33  # nine layers in the axes' height of 10
    for i, (names, what) in enumerate(LAYERS):
        y = 0.3 + i * (h + gap)
        w = 4.2 / len(names)
        for j, name in enumerate(names):
            _box(a1, 0.2 + j * (w + 0.1), y, w, h, name, COLOURS.get(name, "#e6e6e6"), 10)
        a1.text(4.75, y + h / 2, what, va="center", fontsize=8.2)
        if i:
            a1.add_patch(FancyArrowPatch((2.3, y), (2.3, y - gap), arrowstyle="-|>",
                                         mutation_scale=10, color="0.35"))  # fmt: skip
    a2.set_title("One time step t_n → t_{n+1} (method.md §5.1)", fontsize=11)
    h, gap = 0.95, 0.35
    for i, (text, owner) in enumerate(STEP):
        y = 9.3 - (i + 1) * (h + gap) + gap
        _box(a2, 0.2, y, 7.6, h, text, COLOURS[owner], 9)
        a2.text(8.0, y + h / 2, owner, va="center", fontsize=9, style="italic")
        if i:
            a2.add_patch(FancyArrowPatch((4.0, y + h + gap), (4.0, y + h), arrowstyle="-|>",
                                         mutation_scale=10, color="0.35"))  # fmt: skip
    fig.tight_layout()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=110)


if __name__ == "__main__":
    main()
