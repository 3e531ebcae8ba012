"""Figures of a results file (matplotlib, no display needed).

``plot_all(results, folder)`` writes PNG files:

- ``probe_<name>.png``: displacement (relative to the ground) and absolute acceleration
  histories of each probe;
- ``joint_<name>.png``: slip (largest and area-mean over the pairs) and opening (largest)
  histories of each interface, with the broken share, and its cracked length (2D; area
  in 3D: the broken pairs) and open crack (the broken pairs that are open) over time;
- ``states_<name>.png``: a space-time map of the pair states along each interface
  (position along the joint × time; intact, stick, slide, open);
- ``joint_map.png``: along each interface, the largest opening and slip of the run, the
  residual slip, and the pair states of the static state and at the end;
- ``envelope.png`` (2D, with an envelope): the largest σ₁ and the smallest σ₃ of the run
  at every node, on the mesh;
- ``rigid_motion.png``: translation and rotation histories of the bodies that move;
- ``energy.png``: the energy terms and the balance residual.

The report (:func:`pfeie.plot.write_report`) adds figures that need the model:
``plot_loads`` (the loads on the mesh) and ``plot_fields`` (the static principal
stresses).

A static-only run (``analysis.dynamic = false``) has no histories: ``plot_all`` then
writes ``static_<name>.png``, the normal and shear stress of the static state along each
interface, and refuses (:class:`~pfeie.errors.ResultsError`) a file with neither
histories nor a static pair state.

``plot_spectrum(spectra, path)`` draws the elastic response spectra of records
(``pfeie spectrum``): PSa and the peak absolute acceleration, PSv and Sd against T.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import PfeieError, ResultsError
from ..io import Results, output_folder
from ..model import ResponseSpectrum

STATE_COLOURS = ["#8c8c8c", "#2b83ba", "#fdae61", "#d7191c"]  # intact, stick, slide, open
STATE_LABELS = ["intact", "stick", "slide", "open"]
AXES = "xyz"


def _plt() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - matplotlib is in the plot extra
        raise PfeieError("plots need matplotlib: pip install 'pfeie[plot]'") from None
    return plt


def plot_all(results: str | Path, folder: str | Path) -> list[Path]:
    """Every figure of a results file into ``folder``; returns the files written."""
    files: list[Path] = []
    with Results(results) as res:
        title = res.meta["model_summary"].get("title") or Path(res.meta["model_file"]).stem
        if res.n_times == 0:
            if not (res.interface_names and "static/X" in res.f):
                raise ResultsError(
                    f"{res.path}: nothing to plot: no time history (a static-only run, or "
                    "a run stopped before its first step) and no static pair state; expected "
                    "a results file of a dynamic run or of a static run with interfaces"
                )
            out = output_folder(folder)
            files = [plot_static(res, name, out / f"static_{name}.png", title)
                     for name in res.interface_names]  # fmt: skip
            if res.f["mesh/points"].shape[1] == 2:
                files.insert(0, plot_mesh(res, out / "mesh.png", title))
            return files
        out = output_folder(folder)
        if res.f["mesh/points"].shape[1] == 2:
            files.append(plot_mesh(res, out / "mesh.png", title))
        if "records" in res.f and len(res.f["records"]):
            files.append(plot_input(res, out / "input_motion.png", title))
        for name in res.probe_names:
            files.append(plot_probe(res, name, out / f"probe_{name}.png", title))
        for name in res.interface_names:
            files.append(plot_joint(res, name, out / f"joint_{name}.png", title))
            files.append(plot_states(res, name, out / f"states_{name}.png", title))
        if res.interface_names:
            files.append(plot_joint_map(res, out / "joint_map.png", title))
        if res.f["mesh/points"].shape[1] == 2 and res.has_envelope:
            files.append(plot_envelope(res, out / "envelope.png", title))
        files.append(plot_rigid(res, out / "rigid_motion.png", title))
        files.append(plot_energy(res, out / "energy.png", title))
    return files


def plot_mesh(res: Results, path: Path, title: str = "") -> Path:
    """The 2D mesh (cell outlines through the corner nodes) coloured by body, the
    interface pairs (red) and the probes (labelled): the geometry of the model."""
    plt = _plt()
    from matplotlib.collections import PolyCollection

    x = np.asarray(res.f["mesh/points"])[:, :2]
    body = np.asarray(res.f["mesh/body"])
    corners = {"triangle": 3, "triangle6": 3, "quad": 4, "quad8": 4, "quad9": 4}
    fig, ax = plt.subplots(figsize=(8, 6))
    for ctype in res.f["mesh/cells"]:
        k = corners.get(ctype)
        if k is None:
            continue
        conn = np.asarray(res.f[f"mesh/cells/{ctype}"])[:, :k]
        colours = plt.get_cmap("tab10")(body[conn[:, 0]] % 10)
        colours[:, 3] = 0.35
        ax.add_collection(PolyCollection(x[conn], facecolors=colours, edgecolors="0.35",
                                         linewidths=0.3))  # fmt: skip
    if "pairs/x" in res.f:
        xp = np.asarray(res.f["pairs/x"])
        ax.plot(xp[:, 0], xp[:, 1], ".", color="tab:red", ms=3, label="interface pairs")
    probes = res.probe_names
    if probes:
        nodes = json.loads(res.f["history/probes"].attrs.get("nodes", "[]"))
        for name, n in zip(probes, nodes, strict=False):
            ax.plot(*x[n], "k^", ms=6)
            ax.annotate(name, x[n], textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    names = res.body_names
    ax.set_title((f"{title}\n" if title else "") + f"mesh: {len(names)} bodies "
                 f"({', '.join(names)}), {x.shape[0]} nodes", fontsize=10)  # fmt: skip
    if "pairs/x" in res.f:
        ax.legend(loc="best", fontsize=8)
    return _finish(fig, path)


def plot_input(res: Results, path: Path, title: str = "") -> Path:
    """The input motion: each record's acceleration (g) over time and its elastic
    response spectrum PSa (5 %, g) over the period."""
    plt = _plt()
    from ..model import response_spectrum

    fig, ax = plt.subplots(2, 1, figsize=(8, 6.5))
    periods = np.geomspace(0.02, 4.0, 150)
    for k, key in enumerate(sorted(res.f["records"], key=int)):
        g = res.f[f"records/{key}"]
        t, a = np.asarray(g["time"]), np.asarray(g["acceleration"])
        name = g.attrs.get("name", f"record {key}")
        ax[0].plot(t, a / 9.81, lw=0.7, color=f"C{k % 10}", label=str(name))
        s = response_spectrum(t, a, periods, 0.05)
        ax[1].plot(s.periods, s.psa / 9.81, lw=1.1, color=f"C{k % 10}", label=str(name))
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("ground acceleration (g)")
    ax[1].set_xlabel("period T (s)")
    ax[1].set_ylabel("PSa, 5 % damping (g)")
    for a_ in ax:
        a_.grid(alpha=0.3)
        a_.legend(loc="upper right", fontsize=8)
    ax[1].set_xlim(left=0.0)
    ax[0].set_title((f"{title}\n" if title else "") + "input motion", fontsize=10)
    return _finish(fig, path)


def _finish(fig: Any, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


def _style(fig: Any, ax: Any, title: str, path: Path, legend: str) -> Path:
    """Time axis, grids, legends and the title; then save."""
    ax[-1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(loc=legend, fontsize=8)
    ax[0].set_title(title, fontsize=10)
    return _finish(fig, path)


def plot_probe(res: Results, name: str, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    p = res.probe(name)
    u = p["u"] - p["u"][:1]
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for i in range(u.shape[1]):
        ax[0].plot(t, 1e3 * u[:, i], lw=0.9, label=f"u_{AXES[i]}")
        ax[1].plot(t, p["a_abs"][:, i] / 9.81, lw=0.7, label=f"a_{AXES[i]}")
    ax[0].set_ylabel("displacement (mm)\n(relative to the ground)")
    ax[1].set_ylabel("absolute acceleration (g)")
    return _style(fig, ax, f"{title}\nprobe {name}", path, "upper right")


def plot_joint(res: Results, name: str, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    pr = res.pairs(name)
    A = pr["area"]
    slip = np.linalg.norm(pr["slip"], axis=-1)
    cracks = "joints/cracked" in res.f["history"]
    fig, ax = plt.subplots(4 if cracks else 3, 1, figsize=(8, 9 if cracks else 7), sharex=True)
    ax[0].plot(t, 1e3 * slip.max(axis=1), lw=1.0, label="largest")
    ax[0].plot(t, 1e3 * (slip * A).sum(axis=1) / A.sum(), lw=1.0, label="area mean")
    ax[0].set_ylabel("slip (mm)")
    ax[1].plot(t, 1e3 * pr["opening"].max(axis=1), lw=1.0, color="C3", label="largest")
    ax[1].set_ylabel("opening (mm)")
    ax[2].plot(t, 100 * (pr["broken"] * A).sum(axis=1) / A.sum(), lw=1.0, color="k",
               label="broken")  # fmt: skip
    for k, lab in ((2, "slide"), (3, "open")):
        ax[2].plot(t, 100 * ((pr["state"] == k) * A).sum(axis=1) / A.sum(), lw=0.8,
                   color=STATE_COLOURS[k], label=lab)  # fmt: skip
    ax[2].set_ylabel("share of the joint (%)")
    if cracks:  # the cracked extent over time
        cr = res.joint_cracks(name)
        two_d = res.f["mesh/points"].shape[1] == 2
        ax[3].plot(t, cr["cracked"], lw=1.0, color="k", label="cracked (broken)")
        ax[3].plot(t, cr["open"], lw=0.8, color=STATE_COLOURS[3], label="open crack")
        ax[3].set_ylabel("crack length (m)" if two_d else "crack area (m²)")
    return _style(fig, ax, f"{title}\njoint {name}", path, "upper left")


def _arc(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Order of the pairs along a joint (its main direction) and their positions (m)."""
    c = x - x.mean(axis=0)
    direction = np.linalg.svd(c, full_matrices=False)[2][0]
    s = c @ direction
    order = np.argsort(s)
    return order, s[order] - s[order][0]


def plot_states(res: Results, name: str, path: Path, title: str = "") -> Path:
    plt = _plt()
    from matplotlib.colors import BoundaryNorm, ListedColormap

    t = res.time
    pr = res.pairs(name)
    order, s = _arc(pr["x"])
    st = pr["state"][:, order]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    cmap = ListedColormap(STATE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
    edges = np.concatenate([[s[0]], 0.5 * (s[1:] + s[:-1]), [s[-1]]]) if s.size > 1 else np.r_[0, 1]
    tedges = (
        np.concatenate([[t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]]) if t.size > 1 else np.r_[0, 1]
    )
    im = ax.pcolormesh(edges, tedges, st, cmap=cmap, norm=norm, shading="flat")
    cb = fig.colorbar(im, ax=ax, ticks=[0, 1, 2, 3])
    cb.ax.set_yticklabels(STATE_LABELS)
    ax.set_xlabel("position along the joint (m)")
    ax.set_ylabel("time (s)")
    ax.set_title(f"{title}\npair states along {name}", fontsize=10)
    return _finish(fig, path)


def plot_rigid(res: Results, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    q = np.asarray(res.f["history/rigid"][...])
    q = q - q[:1]
    d = int(res.f["mesh/points"].shape[1])
    moving = [b for b in range(q.shape[1]) if np.abs(q[:, b]).max() > 0]
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for b in moving:
        name = res.body_names[b]
        for i in range(d):
            ax[0].plot(t, 1e3 * q[:, b, i], lw=0.9, label=f"{name} u_{AXES[i]}")
        rot = q[:, b, d:] if d == 3 else q[:, b, 2:3]
        for i in range(rot.shape[1]):
            lab = f"{name} θ_{AXES[i] if d == 3 else 'z'}"
            ax[1].plot(t, 1e3 * rot[:, i], lw=0.9, label=lab)
    ax[0].set_ylabel("centroid translation (mm)")
    ax[1].set_ylabel("rotation (mrad)")
    ax[1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
        if a.lines:
            a.legend(loc="upper left", fontsize=7, ncol=2)
    ax[0].set_title(f"{title}\nrigid motion of the bodies (relative to the start)", fontsize=10)
    return _finish(fig, path)


def plot_energy(res: Results, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    e = res.energy()
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True,
                           gridspec_kw={"height_ratios": [3, 1]})  # fmt: skip
    for key, lab in (("kinetic", "kinetic"), ("strain", "strain"), ("damping", "damping"),
                     ("interface", "friction and contact"), ("impact", "impact"),
                     ("algorithmic", "time scheme"), ("correction", "position correction"),
                     ("external_work", "work of the loads")):  # fmt: skip
        if key in e and (key not in ("algorithmic", "correction") or np.any(e[key])):
            ax[0].plot(t, e[key] - (e[key][0] if key == "strain" else 0.0), lw=1.0, label=lab)
    ax[0].set_ylabel("energy (J)\n(strain: change)")
    ax[0].legend(loc="upper left", fontsize=8)
    ax[1].plot(t, e.get("balance", np.zeros_like(t)), lw=0.9, color="k")
    ax[1].set_ylabel("balance (J)")
    ax[1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].set_title(f"{title}\nenergy balance", fontsize=10)
    return _finish(fig, path)


def plot_static(res: Results, name: str, path: Path, title: str = "") -> Path:
    """Normal and shear stress of the static state along an interface, with the pair
    states."""
    plt = _plt()
    pr = res.static_pairs(name)
    order, s = _arc(pr["x"])
    shear = np.linalg.norm(pr["shear_stress"], axis=-1)[order]
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    ax[0].plot(s, 1e-6 * pr["normal_stress"][order], lw=1.0, marker=".",
               label="normal (compression +)")  # fmt: skip
    ax[0].set_ylabel("normal stress (MPa)")
    ax[1].plot(s, 1e-6 * shear, lw=1.0, marker=".", color="C1", label="shear")
    state = pr["state"][order]
    for k, lab in enumerate(STATE_LABELS):
        hit = state == k
        if hit.any():
            ax[1].scatter(s[hit], 1e-6 * shear[hit], s=18, color=STATE_COLOURS[k], label=lab,
                          zorder=3)  # fmt: skip
    ax[1].set_ylabel("shear stress (MPa)")
    ax[1].set_xlabel("position along the joint (m)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
    ax[0].set_title(f"{title}\nstatic state of {name}", fontsize=10)
    return _finish(fig, path)


def plot_spectrum(spectra: dict[str, ResponseSpectrum], path: str | Path,
                  title: str = "") -> Path:  # fmt: skip
    """The response spectra of records (name → spectrum) against the period: PSa and
    the peak absolute acceleration (g), PSv (m/s), Sd (m)."""
    plt = _plt()
    fig, ax = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for k, (name, s) in enumerate(spectra.items()):
        colour = f"C{k % 10}"
        ax[0].plot(s.periods, s.psa / 9.81, lw=1.1, color=colour, label=f"{name}: PSa")
        ax[0].plot(s.periods, s.sa_abs / 9.81, lw=0.8, ls="--", color=colour,
                   label=f"{name}: peak absolute")  # fmt: skip
        ax[1].plot(s.periods, s.psv, lw=1.1, color=colour, label=name)
        ax[2].plot(s.periods, s.sd, lw=1.1, color=colour, label=name)
    damping = ", ".join(sorted({f"{100 * s.damping:g} %" for s in spectra.values()}))
    ax[0].set_ylabel("acceleration (g)")
    ax[1].set_ylabel("pseudo-velocity PSv (m/s)")
    ax[2].set_ylabel("displacement Sd (m)")
    ax[2].set_xlabel("period T (s)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
        a.set_xlim(left=0.0)
        a.set_ylim(bottom=0.0)
    head = f"{title}\n" if title else ""
    ax[0].set_title(f"{head}elastic response spectra, damping {damping}", fontsize=10)
    return _finish(fig, Path(path))


# -- figures of the report: the loads, stress fields on the mesh, joint maps ---------------
CORNERS = {"triangle": 3, "triangle6": 3, "quad": 4, "quad8": 4, "quad9": 4}


def _cells2d(res: Results) -> list[np.ndarray]:
    """The corner connectivities of the 2D cells of a results file, one array per type."""
    return [np.asarray(res.f[f"mesh/cells/{ctype}"])[:, : CORNERS[ctype]]
            for ctype in res.f["mesh/cells"] if ctype in CORNERS]  # fmt: skip


def _outline(ax: Any, res: Results, alpha: float = 0.35, edges: str = "0.35") -> None:
    """The 2D mesh drawn as cell outlines coloured by body."""
    plt = _plt()
    from matplotlib.collections import PolyCollection

    x = np.asarray(res.f["mesh/points"])[:, :2]
    body = np.asarray(res.f["mesh/body"])
    for conn in _cells2d(res):
        colours = plt.get_cmap("tab10")(body[conn[:, 0]] % 10)
        colours[:, 3] = alpha
        ax.add_collection(PolyCollection(x[conn], facecolors=colours, edgecolors=edges,
                                         linewidths=0.3))  # fmt: skip
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _triangles(res: Results) -> np.ndarray:
    """The 2D cells cut into triangles through their corners (for nodal colour fields)."""
    tris = []
    for conn in _cells2d(res):
        tris.append(conn[:, :3])
        if conn.shape[1] == 4:
            tris.append(conn[:, [0, 2, 3]])
    return np.concatenate(tris) if tris else np.zeros((0, 3), dtype=np.int64)


def plot_fields(
    res: Results, fields: list[tuple[str, np.ndarray]], path: Path, title: str = "",
    marks: Sequence[Sequence[float] | None] | None = None,
) -> Path:  # fmt: skip
    """Nodal scalar fields (label, values (n_points,) in MPa) on the 2D mesh, one panel
    each, interpolated linearly over the cells' corners; ``marks``: a point to mark per
    panel (the extreme)."""
    plt = _plt()
    import matplotlib.tri as mtri

    x = np.asarray(res.f["mesh/points"])[:, :2]
    tri = _triangles(res)
    fig, axes = plt.subplots(1, len(fields), figsize=(5.2 * len(fields), 5.0), squeeze=False)
    for k, (label, v) in enumerate(fields):
        ax = axes[0, k]
        ok = np.all(np.isfinite(v[tri]), axis=1)
        tr = mtri.Triangulation(x[:, 0], x[:, 1], tri[ok])
        vv = np.where(np.isfinite(v), v, 0.0)
        lim = float(np.abs(vv[tri[ok]]).max()) if ok.any() else 1.0
        im = ax.tripcolor(tr, vv, shading="gouraud", cmap="RdBu_r", vmin=-lim, vmax=lim)
        fig.colorbar(im, ax=ax, shrink=0.8, label="MPa")
        at = None if marks is None else marks[k]
        if at is not None:
            ax.plot(at[0], at[1], "k*", ms=10, mec="w")
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(label, fontsize=9)
    fig.suptitle(title, fontsize=10)
    return _finish(fig, path)


def plot_envelope(res: Results, path: Path, title: str = "") -> Path:
    """The stress envelope on the 2D mesh: the largest σ₁ and the smallest σ₃ of the run
    at every node (MPa, tension positive; the total stress, static state included), the
    extremes starred."""
    env = res.envelope()
    fields, marks = [], []
    x = np.asarray(res.f["mesh/points"])
    for key, label in (("node_max", "largest σ1 over the run"),
                       ("node_min", "smallest σ3 over the run")):  # fmt: skip
        v = 1e-6 * env[key]
        fields.append((label, v))
        fin = np.where(np.isfinite(v), v, 0.0)
        marks.append(tuple(x[int(np.argmax(fin) if key == "node_max" else np.argmin(fin))]))
    return plot_fields(res, fields, path, (f"{title}\n" if title else "") + "stress envelope "
                       "(tension +)", marks)  # fmt: skip


def plot_joint_map(res: Results, path: Path, title: str = "") -> Path:
    """Per joint, along the joint: the largest opening and slip of the run, the residual
    slip, and strips of the pair states at the start (the static state) and at the end
    (broken pairs crossed)."""
    plt = _plt()
    from matplotlib.colors import BoundaryNorm, ListedColormap

    names = res.interface_names
    fig, axes = plt.subplots(2 * len(names), 1, figsize=(8, 3.6 * len(names)), squeeze=False,
                             gridspec_kw={"height_ratios": [4, 1] * len(names)})  # fmt: skip
    cmap = ListedColormap(STATE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
    for j, name in enumerate(names):
        ax, strip = axes[2 * j, 0], axes[2 * j + 1, 0]
        pr = res.pairs(name)
        order, s = _arc(pr["x"])
        slip = np.linalg.norm(pr["slip"], axis=-1)[:, order]
        ax.plot(s, 1e3 * pr["opening"][:, order].max(axis=0), ".-", lw=1.0, color="C3",
                label="largest opening")  # fmt: skip
        ax.plot(s, 1e3 * slip.max(axis=0), ".-", lw=1.0, color="C0", label="largest slip")
        ax.plot(s, 1e3 * slip[-1], "--", lw=1.0, color="C0", label="residual slip")
        ax.set_ylabel("mm")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
        ax.set_title(f"joint {name}", fontsize=9)
        first = (res.static_pairs(name)["state"][order] if "static/state" in res.f
                 else pr["state"][0, order])  # fmt: skip
        st = np.stack([first, pr["state"][-1, order]])
        edges = (np.concatenate([[s[0]], 0.5 * (s[1:] + s[:-1]), [s[-1]]]) if s.size > 1
                 else np.r_[-0.5, 0.5])  # fmt: skip
        strip.pcolormesh(edges, [0, 1, 2], st, cmap=cmap, norm=norm, shading="flat")
        broken = pr["broken"][-1, order]
        strip.plot(s[broken], np.full(int(broken.sum()), 1.5), "kx", ms=4)
        strip.set_yticks([0.5, 1.5], ["static", "end"], fontsize=8)
        strip.set_xlim(ax.get_xlim())
        strip.set_xlabel("position along the joint (m)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in STATE_COLOURS]
    handles.append(plt.Line2D([], [], color="k", marker="x", ls=""))
    fig.legend(handles, [*STATE_LABELS, "broken"], loc="lower center", ncol=5, fontsize=8)
    fig.suptitle((f"{title}\n" if title else "") + "joint maps", fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _facet_polylines(model: Any, group: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The facets of a 2D group as (points (5, 2) along the facet, outward normal (2,))."""
    mesh = model.mesh
    out = []
    for ftype, conn in mesh.facet_group(group).items():
        conn = np.asarray(conn)
        centre = mesh.facet_cell_centres(ftype, conn)[:, :2]
        a, b = mesh.points[conn[:, 0], :2], mesh.points[conn[:, 1], :2]
        t = b - a
        n = np.stack([t[:, 1], -t[:, 0]], axis=1) / np.linalg.norm(t, axis=1)[:, None]
        n *= np.where(np.einsum("fd,fd->f", 0.5 * (a + b) - centre, n) >= 0, 1.0, -1.0)[:, None]
        r = np.linspace(0.0, 1.0, 5)
        for k in range(conn.shape[0]):
            out.append((a[k] + r[:, None] * t[k], n[k]))
    return out


def _diagram(ax: Any, lines: list[tuple[np.ndarray, np.ndarray, np.ndarray]], scale: float,
             colour: str, label: str) -> None:  # fmt: skip
    """A pressure diagram: on each polyline (points, normal, values) the values drawn
    along the normal ``scale`` m per Pa, filled; arrows towards the face."""
    from matplotlib.patches import Polygon

    first = True
    for pts, n, v in lines:
        if not np.any(v > 0):
            continue
        tip = pts + scale * v[:, None] * n[None, :]
        ax.add_patch(Polygon(np.concatenate([pts, tip[::-1]]), closed=True, fc=colour,
                             ec=colour, alpha=0.35, lw=0.6,
                             label=label if first else None))  # fmt: skip
        first = False
        k = len(pts) // 2
        if v[k] > 0:
            ax.annotate("", pts[k], tip[k], arrowprops={"arrowstyle": "->", "color": colour,
                                                        "lw": 0.7})  # fmt: skip


def plot_loads(res: Results, model: Any, spec: dict[str, Any], path: Path,
               title: str = "") -> Path:  # fmt: skip
    """The loads of a 2D model on its mesh: gravity (an arrow at the centre of mass),
    the pressure diagrams of the hydrostatic and other pressures and of the silt (its
    normal pressure), drawn outside the faces they push on, the water levels, the faces
    that carry the reservoir's added mass, the static uplift along the joints (drawn
    below them) and the supports."""
    plt = _plt()
    from ..model import Load

    x = np.asarray(res.f["mesh/points"])[:, :2]
    size = float(np.ptp(x, axis=0).max()) or 1.0
    fig, ax = plt.subplots(figsize=(9, 6.5))
    _outline(ax, res, alpha=0.12, edges="0.7")
    pressure: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    silt: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    loads: list[Load] = list(model.loads)
    gravity = None
    for ld in loads:
        if ld.kind == "gravity":
            gravity = np.asarray(ld.value, dtype=float)
        elif ld.kind == "pressure" and ld.target is not None:
            for pts, n in _facet_polylines(model, ld.target):
                v = (np.asarray(ld.value(pts), dtype=float) if callable(ld.value)
                     else np.full(len(pts), np.asarray(ld.value, dtype=float)))  # fmt: skip
                pressure.append((pts, n, v))
        elif ld.kind == "silt" and ld.target is not None and callable(ld.value):
            for pts, n in _facet_polylines(model, ld.target):
                sig = np.asarray(ld.value(pts), dtype=float)  # (5, 2) principal pressures
                silt.append((pts, n, (sig * n**2).sum(axis=1)))
    uplift = []
    if "static/uplift" in res.f and "pairs/x" in res.f:
        p = np.asarray(res.f["static/uplift"])
        xp = np.asarray(res.f["pairs/x"])[:, :2]
        frame = np.asarray(res.f["pairs/frame"])
        iface = np.asarray(res.f["pairs/interface"])
        for k in np.unique(iface):
            idx = np.flatnonzero((iface == k) & (p > 0))
            if idx.size < 1:
                continue
            order, _ = _arc(xp[idx]) if idx.size > 1 else (np.zeros(1, dtype=int), None)
            idx = idx[order]
            n = frame[idx[0], -1, :2]
            n = -n if n[1] > 0 else n  # drawn below the joint
            uplift.append((xp[idx], n, p[idx]))
    peak = max([float(v.max()) for _, _, v in pressure + silt + uplift] or [1.0])
    scale = 0.15 * size / peak if peak > 0 else 0.0
    _diagram(ax, pressure, scale, "tab:blue", f"pressure (hydrostatic), up to "
             f"{1e-3 * max([float(v.max()) for *_, v in pressure] or [0.0]):.4g} kPa")  # fmt: skip
    _diagram(ax, silt, scale, "saddlebrown", "silt (normal pressure), up to "
             f"{1e-3 * max([float(v.max()) for *_, v in silt] or [0.0]):.4g} kPa")  # fmt: skip
    _diagram(ax, uplift, scale, "tab:purple", "uplift (static), up to "
             f"{1e-3 * max([float(v.max()) for *_, v in uplift] or [0.0]):.4g} kPa")  # fmt: skip
    loads_spec = spec.get("loads", {})
    first = True
    for wg in loads_spec.get("westergaard", []):
        what = "FE reservoir" if wg.get("model") == "fe" else "Westergaard"
        for g in wg["groups"]:
            for pts, _n in _facet_polylines(model, g):
                ax.plot(pts[:, 0], pts[:, 1], "-", color="c", lw=4, alpha=0.7,
                        solid_capstyle="butt",
                        label=f"added mass ({what})" if first else None)  # fmt: skip
                first = False
    levels = [(hy["water_level"], hy["groups"]) for hy in loads_spec.get("hydrostatic", [])]
    for level, groups in levels:
        pts = np.concatenate([p for g in groups for p, _ in _facet_polylines(model, g)])
        lo, hi = float(pts[:, 0].min()), float(pts[:, 0].max())
        ax.plot([lo - 0.2 * size, hi], [level, level], "--", color="tab:blue", lw=0.8)
        ax.plot(lo - 0.1 * size, level, "v", color="tab:blue", ms=7)
        ax.annotate(f"water {level:g} m", (lo - 0.2 * size, level), xytext=(0, 4),
                    textcoords="offset points", fontsize=8, color="tab:blue")  # fmt: skip
    for sl in loads_spec.get("silt", []):
        pts = np.concatenate([p for g in sl["groups"] for p, _ in _facet_polylines(model, g)])
        lo, hi = float(pts[:, 0].min()), float(pts[:, 0].max())
        ax.plot([lo - 0.2 * size, hi], [sl["level"]] * 2, ":", color="saddlebrown", lw=0.9)
        ax.annotate(f"silt {sl['level']:g} m", (lo - 0.2 * size, sl["level"]), xytext=(0, -10),
                    textcoords="offset points", fontsize=8, color="saddlebrown")  # fmt: skip
    fixed = np.unique(np.concatenate([s.nodes for s in model.supports] or [np.zeros(0, int)]))
    if fixed.size:
        ax.plot(x[fixed, 0], x[fixed, 1], "^", color="k", ms=3, label="supports")
    if gravity is not None and np.any(gravity):
        w = np.asarray(model.body_weights)
        c = (w[:, None] * x).sum(axis=0) / w.sum() if w.sum() > 0 else x.mean(axis=0)
        g = gravity[:2] / np.linalg.norm(gravity[:2])
        ax.annotate("", c + 0.12 * size * g, c, arrowprops={"arrowstyle": "-|>", "color": "k",
                                                            "lw": 1.5})  # fmt: skip
        ax.annotate(f"g = {np.linalg.norm(gravity):g} m/s²", c, xytext=(6, 0),
                    textcoords="offset points", fontsize=8)  # fmt: skip
    ax.autoscale_view()
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(
        (f"{title}\n" if title else "") + "loads (the pressure diagrams to one "
        "scale, drawn on the side of the water; uplift below its joint)",
        fontsize=10,
    )
    return _finish(fig, path)
