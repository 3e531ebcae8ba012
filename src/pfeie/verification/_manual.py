"""The verification manual: one Markdown page per case with its figure, and a summary.

``write_manual(results, folder)`` writes ``<case>.md`` and ``<case>.png`` for every case
result, ``index.md`` (the summary table, linked from the README) and keeps the
hand-written ``conventions.md``. Everything but ``conventions.md`` is generated.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ._core import CASES, CaseResult

# cases of verification-cases.md that this version cannot run, with the reason
UNSUPPORTED: dict[str, tuple[str, str]] = {}


def table(results: list[CaseResult]) -> list[str]:
    """Rows of the summary table: case, quantity, reference, pfeie, error, tolerance, pass."""
    rows = ["| case | quantity | reference | pfeie | error | tolerance | pass |",
            "|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in results:
        for c in r.checks:
            rows.append(f"| [{r.name}]({r.name}.md) | {c.quantity} | {c.reference:.6g} | "
                        f"{c.value:.6g} | {c.error_text} | {c.tolerance_text} | "
                        f"{'yes' if c.passed else '**NO**'} |")  # fmt: skip
    return rows


def figure(r: CaseResult, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4))
    for s in r.series:
        ax.plot(s.x, s.y, s.style, lw=1.2 if s.style == "-" else 1.0, label=s.label)
    ax.set_xlabel(r.xlabel)
    ax.set_ylabel(r.ylabel)
    ax.set_title(f"{r.name}: {r.title}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def sketch(model: Any, title: str, path: Path) -> None:
    """The mesh (grey), the interfaces (red) and the supported nodes (black triangles)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    from ..element import reference

    mesh = model.mesh
    pts = mesh.points[:, :2]
    fig, ax = plt.subplots(figsize=(6, 3.6))
    segs = []
    for ctype, conn in mesh.cells.items():
        ref = reference(ctype)
        nc = reference(ref.linear).n_nodes
        ring = conn[:, :nc]
        for k in range(nc):
            segs.append(np.stack([pts[ring[:, k]], pts[ring[:, (k + 1) % nc]]], axis=1))
    ax.add_collection(LineCollection(list(np.concatenate(segs)), colors="0.6", linewidths=0.5))
    if model.pairs is not None:
        for name in model.pairs.names:
            for conn in mesh.facet_groups.get(f"{name}:a", {}).values():
                ax.add_collection(LineCollection(list(pts[conn[:, [0, 1]]]), colors="C3",
                                                 linewidths=2.0))  # fmt: skip
        ax.plot([], [], color="C3", lw=2, label="interface")
    fixed = np.unique(np.concatenate([s.nodes for s in model.supports] or [np.zeros(0, int)]))
    if fixed.size:
        ax.plot(pts[fixed, 0], pts[fixed, 1], "k^", ms=3, label="supported nodes")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_manual(results: list[CaseResult], folder: str | Path, fast: bool) -> list[Path]:
    """Write the pages, figures and the summary; returns the files written."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    files: list[Path] = []
    for r in results:
        c = CASES[r.name]
        page = [f"# {r.name}: {c.title}", "",
                "Conventions (units, signs, frames, ground-motion direction): "
                "[conventions](conventions.md). Summary: [index](index.md).", "",
                f"**Purpose.** {c.purpose}", "", f"**Model.** {c.sketch}", "",
                *_sketch_lines(r.name, out, files),
                f"**Reference.** {c.reference}", "",
                f"**Inputs.** `src/pfeie/verification/_cases.py`, function `{r.name.lower()}`"
                " (run it alone: `pfeie verify --case " + r.name + "`).", "",
                "**Results** (tolerances within 10× of the error this version reaches, "
                "tighter than the acceptance criteria of `verification-cases.md`):", "",
                *table([r])[:2], *table([r])[2:], ""]  # fmt: skip
        if r.series:
            png = out / f"{r.name}.png"
            figure(r, png)
            files.append(png)
            page += [f"![{r.name}]({r.name}.png)", ""]
        conv = r.extra.get("convergence")
        if conv:
            key = "dt" if "dt" in conv else "h"
            page += ["**Convergence.**", "",
                     f"| {'Δt (s)' if key == 'dt' else 'h (m)'} | "
                     f"error of the {conv['quantity']} |",
                     "|---|---|",
                     *[f"| {x:.4g} | {e:.3e} |" for x, e in zip(conv[key], conv["error"],
                                                                strict=True)], "",
                     _rate_text(r.name, conv), ""]  # fmt: skip
        tab = r.extra.get("table")
        if tab:
            head, rows = tab
            page += ["**Table.**", "", "| " + " | ".join(head) + " |",
                     "|" + "---|" * len(head), *["| " + " | ".join(row) + " |" for row in rows],
                     ""]  # fmt: skip
        if r.notes:
            page += [f"**Notes.** {r.notes}", ""]
        # no run time here: regenerating the manual must give the same files
        page += [f"pfeie {__version__}; {'fast' if fast else 'full'} suite."]
        path = out / f"{r.name}.md"
        path.write_text("\n".join(page) + "\n")
        files.append(path)
    for name, (title, why) in UNSUPPORTED.items():
        path = out / f"{name}.md"
        path.write_text(f"# {name}: {title}\n\nNot run in this version. {why}\n")
        files.append(path)
    n_pass = sum(r.passed for r in results)
    index = ["# Verification manual", "",
             "Every reference case (V-numbers; each defined once, with its closed form or "
             "independent reference and its source, in `src/pfeie/verification/_cases.py`) "
             "that this version supports, run by `pfeie verify` and regenerated by `make "
             "verify` (figures and tables are produced by the code, not by hand). "
             "Conventions: [conventions](conventions.md).",
             "", f"{n_pass} of {len(results)} cases pass "
             f"({'fast' if fast else 'full'} suite, pfeie {__version__}).", "",
             *table(results), ""]  # fmt: skip
    if UNSUPPORTED:
        index += ["Not run: " + ", ".join(f"[{k}]({k}.md) ({v[0]})"
                                          for k, v in UNSUPPORTED.items()) + ".", ""]  # fmt: skip
    path = out / "index.md"
    path.write_text("\n".join(index) + "\n")
    files.append(path)
    return files


def _sketch_lines(name: str, out: Path, files: list[Path]) -> list[str]:
    from ._cases import _MODELS

    model = _MODELS.get(name)
    if model is None or model.dim != 2:
        return []
    png = out / f"{name}_sketch.png"
    sketch(model, f"{name}: model", png)
    files.append(png)
    return [f"![{name} model]({name}_sketch.png)", ""]


_ORDER = {1: "first", 2: "second", 3: "third"}

# why a case converges as it does: (lowest rate, highest rate, explanation); the
# explanation is printed only when the measured rate lies in that range
_WHY: dict[str, tuple[float, float, str]] = {
    "V2a": (1.0, 2.0, "The pulse's jump is sampled at its mid value and the block stops with a "
            "continuous velocity, so the event costs little; the stop instant, resolved to "
            "within a step, keeps the rate below 2."),
    "V2b": (0.9, 2.0, "The start and stop instants fall inside steps and are resolved to "
            "within a step, which costs O(Δt) each."),
    "V4": (0.5, 1.7, "Each slip reversal costs up to Δt·μg of velocity (the pair force is "
           "constant over the step), depending on where the reversal falls within the step: "
           "the stick-slip switching instants limit the rate, and the errors are irregular."),
    "V7b": (1.5, 2.5, "The error is that of the lumped mass's moment of inertia, which the "
            "rocking period depends on (order h²); Δt (1 ms) contributes less."),
    "V4m": (1.5, 2.5, "Q4 cells converge at second order in the displacements, and so in "
            "the accelerations, where the motion is smooth; the slip starts and stops, where "
            "the base shear jumps and the largest changes fall, and the corner nodes, where "
            "the base traction ends abruptly, converge more slowly."),
    "V6": (0.5, 1.0, "The landing and the release of the contact node are perfectly inelastic "
           "at the node (the velocity correction, e = 0): the momentum lost vanishes with the "
           "mesh, here more slowly than h; the plateau force is exact on every mesh."),
}  # fmt: skip


def _rate_text(name: str, conv: dict[str, Any]) -> str:
    """The verdict on a convergence study, computed from the measured rate: the observed
    rate against the expected order ``conv["order"]`` and the asserted lower bound
    ``conv["bound"]``, and the explanation of the case when the rate lies where the
    explanation applies."""
    rate = float(conv["rate"])
    var = "Δt" if "dt" in conv else "h"
    out = f"Observed rate {rate:.2f} (least-squares slope of log error against log {var})"
    order, bound = conv.get("order"), conv.get("bound")
    if order is not None and bound is not None:
        word = _ORDER.get(int(order), f"order {order}") if order == int(order) else str(order)
        if rate >= order - 0.1:
            out += f": {word} order or better, as expected (asserted: rate ≥ {bound:g})."
        elif rate >= bound:
            out += (f": below the {word} order expected, above the asserted bound "
                    f"{bound:g}.")  # fmt: skip
        else:
            out += f": below the asserted bound {bound:g} (expected {word} order): FAILS."
    else:
        out += "."
    errs = np.asarray(conv["error"], float)
    if errs.size > 1 and np.any(np.diff(errs) >= 0):
        out += " The error does not decrease at every refinement."
    lo, hi, why = _WHY.get(name, (0.0, 0.0, ""))
    if why and lo <= rate <= hi:
        out += " " + why
    return out
