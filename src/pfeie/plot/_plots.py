"""Figures of a results file (matplotlib, no display needed).

``plot_all(results, folder)`` writes PNG files:

- ``probe_<name>.png``: displacement (relative to the ground) and absolute acceleration
  histories of each probe;
- ``joint_<name>.png``: slip (largest and area-mean over the pairs) and opening (largest)
  histories of each interface, with the broken share, and its cracked length (2D; area
  in 3D: the broken pairs) and open crack (the broken pairs that are open) over time;
- ``states_<name>.png``: a space-time map of the pair states along each interface
  (position along the joint × time; intact, stick, slide, open);
- ``rigid_motion.png``: translation and rotation histories of the bodies that move;
- ``energy.png``: the energy terms and the balance residual.

A static-only run (``analysis.dynamic = false``) has no histories: ``plot_all`` then
writes ``static_<name>.png``, the normal and shear stress of the static state along each
interface, and refuses (:class:`~pfeie.errors.ResultsError`) a file with neither
histories nor a static pair state.

``plot_spectrum(spectra, path)`` draws the elastic response spectra of records
(``pfeie spectrum``): PSa and the peak absolute acceleration, PSv and Sd against T.
"""

from __future__ import annotations

import json
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
