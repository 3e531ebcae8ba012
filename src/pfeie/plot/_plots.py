"""Figures of a results file (matplotlib, no display needed).

``plot_all(results, folder)`` writes PNG files:

- ``mesh.png``: the mesh coloured by body, the interface pairs and the probes (2D: the
  cell outlines; 3D: the boundary faces in a fixed view, :func:`plot_mesh_3d`);
- ``input_motion.png``: the records and their 5 % PSa spectra;
- ``probe_<name>.png``: displacement (relative to the ground) and absolute acceleration
  histories of each probe;
- ``joint_<name>.png``: slip (largest and area-mean over the pairs) and opening (largest;
  below :data:`OPENING_FLOOR_M` drawn as 0) histories of each interface, with the broken,
  sliding and open shares (open by more than :data:`OPEN_CRACK_MIN_M`, as the summary
  counts them), and its cracked length (2D; area in 3D: the broken pairs), the broken pairs in
  the open state and the open crack (those open by more than the summary's threshold,
  :data:`OPEN_CRACK_MIN_M`) over time, and the sliding safety factor FS(t) (drawn up to
  :data:`FS_SHOWN_MAX`);
- ``states_<name>.png``: a space-time map of the pair states along each interface
  (position along the joint × time; intact, stick, slide, open);
- ``joint_map.png``: in 2D, along each interface, the largest opening and slip of the
  run, the residual slip, and the pair states of the static state and at the end; in
  3D, each interface in its own plane: the pair states of the static state and at the
  end, the largest opening and the residual slip (:func:`plot_joint_map_3d`);
- ``envelope.png`` (with an envelope): the largest σ₁ and the smallest σ₃ of the run at
  every node, on the mesh (3D: painted on the boundary faces, :func:`plot_fields_3d`);
- ``rigid_motion.png``: translation and rotation histories of the bodies that move;
- ``energy.png``: the energy terms and the balance residual.

The report (:func:`pfeie.plot.write_report`) adds figures that need the model:
``plot_loads`` / ``plot_loads_3d`` (the loads on the mesh) and ``plot_fields`` /
``plot_fields_3d`` (the static principal stresses).

The 3D figures are drawn with matplotlib's ``mplot3d``: the boundary faces of the cells
(the faces one cell only uses, :func:`boundary_faces`) as polygons through their corner
nodes, equal scaling along x, y, z, seen from :data:`VIEW_3D` (upstream, −x, from the −y
side and above); a nodal field paints each face with the mean of its corners' values.
Their PNG files carry the key numbers they draw (counts, extremes, the joint planes) as
JSON in the ``Description`` text chunk.

A static-only run (``analysis.dynamic = false``) has no histories: ``plot_all`` then
writes ``static_<name>.png``, the normal and shear stress of the static state along each
interface, and refuses (:class:`~pfeie.errors.ResultsError`) a file with neither
histories nor a static pair state.

``plot_spectrum(spectra, path)`` draws the elastic response spectra of records
(``pfeie spectrum``): PSa and the peak absolute acceleration, PSv and Sd against T.
"""

from __future__ import annotations

import hashlib
import json
import re
import weakref
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from ..errors import PfeieError, ResultsError
from ..interface import OPEN_CRACK_MIN_M
from ..io import PYTHON_RUN, Results, output_folder
from ..model import ResponseSpectrum
from ..typing import FloatArray

STATE_COLOURS = ["#8c8c8c", "#2b83ba", "#fdae61", "#d7191c"]  # intact, stick, slide, open
STATE_LABELS = ["intact", "stick", "slide", "open"]
AXES = "xyz"
#: the largest sliding safety factor a joint's plot draws (a joint nearly without shear
#: has a large one, which would flatten the range near 1 that matters)
FS_SHOWN_MAX = 5.0


def _below_title(fig: Any, text: str) -> float:
    """The top of the axes' area (a figure fraction) that leaves room for a figure title
    of the lines of ``text`` (10 pt: about 0.2 inch a line), so that the top row's own
    titles do not run into it."""
    lines = text.count("\n") + 1
    return max(0.5, 1.0 - (0.2 * lines + 0.1) / float(fig.get_figheight()))


def _plt() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - matplotlib is in the plot extra
        raise PfeieError("plots need matplotlib: pip install 'pfeie[plot]'") from None
    return plt


def run_title(meta: dict[str, Any]) -> str:
    """The title of a run's figures: its model's title, else the model file's name (none
    for a Python run without a title)."""
    given = meta["model_summary"].get("title")
    if given or meta.get("model_file") == PYTHON_RUN:
        return str(given or "")
    return Path(meta["model_file"]).stem


#: the characters a file name cannot hold on some system (a path separator, control
#: characters, and Windows' reserved ones)
_UNSAFE = re.compile(r'[\x00-\x1f/\\:*?"<>|]')


def figure_file(prefix: str, name: str) -> str:
    """The file name of the figure of a probe, joint or block named ``name``: the name
    with the characters a file name cannot hold (a path separator, ``:*?"<>|``, control
    characters) as ``_``, so that a probe named "crest/left" is drawn, not lost.

    A name so changed takes a short digest of itself, so that "a/b" and "a_b" keep two
    files.

    >>> figure_file("probe", "crest/left"), figure_file("probe", "crest_left")
    ('probe_crest_left-ada0a9.png', 'probe_crest_left.png')
    """
    safe = _UNSAFE.sub("_", name)
    if safe != name:
        safe += "-" + hashlib.sha256(name.encode("utf-8", "surrogateescape")).hexdigest()[:6]
    return f"{prefix}_{safe}.png"


def plot_all(results: str | Path, folder: str | Path) -> list[Path]:
    """Every figure of a results file into ``folder``; returns the files written."""
    files: list[Path] = []
    with Results(results) as res:
        title = run_title(res.meta)
        two_d = res.f["mesh/points"].shape[1] == 2
        if res.n_times == 0:
            if not (res.interface_names and "static/X" in res.f):
                raise ResultsError(
                    f"{res.path}: nothing to plot: no time history (a static-only run, or "
                    "a run stopped before its first step) and no static pair state; expected "
                    "a results file of a dynamic run or of a static run with interfaces"
                )
            out = output_folder(folder)
            files = [plot_static(res, name, out / figure_file("static", name), title)
                     for name in res.interface_names]  # fmt: skip
            files.insert(0, (plot_mesh if two_d else plot_mesh_3d)(res, out / "mesh.png", title))
            return files
        out = output_folder(folder)
        files.append((plot_mesh if two_d else plot_mesh_3d)(res, out / "mesh.png", title))
        if "records" in res.f and len(res.f["records"]):
            files.append(plot_input(res, out / "input_motion.png", title))
        for name in res.probe_names:
            files.append(plot_probe(res, name, out / figure_file("probe", name), title))
        for name in res.interface_names:
            files.append(plot_joint(res, name, out / figure_file("joint", name), title))
            files.append(plot_states(res, name, out / figure_file("states", name), title))
        if res.interface_names:
            joint_map = plot_joint_map if two_d else plot_joint_map_3d
            files.append(joint_map(res, out / "joint_map.png", title))
        if res.has_envelope:
            envelope = plot_envelope if two_d else plot_envelope_3d
            files.append(envelope(res, out / "envelope.png", title))
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
    if "pairs/x" in res.f:  # beside the axes: inside, it covered a probe at the top
        _legend(ax)
    return _finish(fig, path)


def plot_input(res: Results, path: Path, title: str = "") -> Path:
    """The input motion: each record's acceleration (g) over time and its elastic
    response spectrum PSa (5 %, g) over the period."""
    plt = _plt()
    from ..model import direction_label, response_spectrum

    fig, ax = plt.subplots(2, 1, figsize=(8, 6.5))
    periods = np.geomspace(0.02, 4.0, 150)
    # the run's end: a record longer than the run (analysis.duration) is applied up to it
    end = float(res.time[-1]) if res.time.size else None
    cut = False
    for k, key in enumerate(sorted(res.f["records"], key=int)):
        g = res.f[f"records/{key}"]
        t, a = np.asarray(g["time"]), np.asarray(g["acceleration"])
        name = g.attrs.get("name", f"record {key}")
        if "direction" in g:  # one file may drive several directions
            name = f"{name} along {direction_label(np.asarray(g['direction']))}"
        ax[0].plot(t, a / 9.81, lw=0.7, color=f"C{k % 10}", label=str(name))
        if end is not None and t[-1] > end and t[0] < end:  # the spectrum of the part applied
            keep = t < end
            t, a = np.r_[t[keep], end], np.r_[a[keep], np.interp(end, t, a)]
            cut = True
        s = response_spectrum(t, a, periods, 0.05)
        ax[1].plot(s.periods, s.psa / 9.81, lw=1.1, color=f"C{k % 10}", label=str(name))
    if cut and end is not None:
        ax[0].axvspan(end, ax[0].get_xlim()[1], color="0.85", zorder=0,
                      label=f"not applied (the run ends at {end:g} s)")  # fmt: skip
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("ground acceleration,\nas scaled (g)")
    ax[1].set_xlabel("period T (s)")
    ax[1].set_ylabel("PSa, 5 % damping (g)" + ("\nof the motion applied" if cut else ""))
    for a_ in ax:
        a_.grid(alpha=0.3)
        _legend(a_)
    ax[1].set_xlim(left=0.0)
    ax[0].set_title((f"{title}\n" if title else "") + "input motion", fontsize=10)
    return _finish(fig, path)


def _legend(ax: Any, *args: Any, **kw: Any) -> None:
    """A legend to the right of the axes, where it hides no curve (inside, a legend in a
    corner covered peaks and breaks of the histories); nothing without labelled
    artists."""
    if not args and not ax.get_legend_handles_labels()[0]:
        return
    kw.setdefault("fontsize", 8)
    ax.legend(*args, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **kw)


def _finish(fig: Any, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


def _style(fig: Any, ax: Any, title: str, path: Path) -> Path:
    """Time axis, grids, legends and the title; then save."""
    ax[-1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
        _legend(a)
    ax[0].set_title(title, fontsize=10)
    return _finish(fig, path)


def _ground_of(res: Results) -> tuple[FloatArray | None, str]:
    """The ground displacement (n_t, d) to take off the motions of an absolute-form run
    (``history/ground``; None in the relative form, whose motions are relative already)
    and the words for what the motions then are: "relative to the ground", or, for an
    absolute-form file of format 1.9 or older, which records no ground motion,
    "absolute"."""
    if res.meta.get("form") != "absolute":
        return None, "relative to the ground"
    ground = res.ground
    return ground, "relative to the ground" if ground is not None else "absolute"


def plot_probe(res: Results, name: str, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    p = res.probe(name)
    ground, frame = _ground_of(res)
    u = p["u"] if ground is None else p["u"] - ground  # (absolute: the probes move with it)
    u = u - u[:1]
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for i in range(u.shape[1]):
        ax[0].plot(t, 1e3 * u[:, i], lw=0.9, label=f"u_{AXES[i]}")
        ax[1].plot(t, p["a_abs"][:, i] / 9.81, lw=0.7, label=f"a_{AXES[i]}")
    ax[0].set_ylabel(f"displacement (mm)\n({frame},\nsince the start of the run)")
    ax[1].set_ylabel("absolute acceleration (g)")
    return _style(fig, ax, f"{title}\nprobe {name}", path)


def plot_joint(res: Results, name: str, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    pr = res.pairs(name)
    A = pr["area"]
    slip = np.linalg.norm(pr["slip"], axis=-1)
    cracks = "joints/cracked" in res.f["history"]
    fs = res.joint_safety_factor(name)
    n = 3 + int(cracks) + int(fs is not None)
    fig, ax = plt.subplots(n, 1, figsize=(8, 1.75 * n + 1.75), sharex=True)
    ax[0].plot(t, 1e3 * slip.max(axis=1), lw=1.0, label="largest")
    ax[0].plot(t, 1e3 * (slip * A).sum(axis=1) / A.sum(), lw=1.0, label="area mean")
    ax[0].set_ylabel("slip magnitude (mm)\n(since the start of the run)")
    ax[1].plot(t, 1e3 * _shown_opening(pr["opening"].max(axis=1)), lw=1.0, color="C3",
               label="largest")  # fmt: skip
    ax[1].set_ylabel(f"opening (mm)\n(below {1e3 * OPENING_FLOOR_M:g} mm: 0)")
    share = res.joint_shares(name)  # (open: by more than OPEN_CRACK_MIN_M, as the CSV)
    ax[2].plot(t, 100 * share["broken"], lw=1.0, color="k", label="broken")
    for k, key, lab in ((2, "sliding", "slide"),
                        (3, "open", f"open (> {1e3 * OPEN_CRACK_MIN_M:g} mm)")):  # fmt: skip
        ax[2].plot(t, 100 * share[key], lw=0.8, color=STATE_COLOURS[k], label=lab)
    ax[2].set_ylabel("share of the joint (%)")
    if cracks:  # the cracked extent over time
        cr = res.joint_cracks(name)
        two_d = res.f["mesh/points"].shape[1] == 2
        ax[3].plot(t, cr["cracked"], lw=1.0, color="k", label="cracked (broken)")
        ax[3].plot(t, cr["open"], lw=0.8, color=STATE_COLOURS[3], ls=":",
                   label="broken and in the open state")  # fmt: skip
        wide = open_crack(pr, cr)
        ax[3].plot(t, wide, lw=1.0, color=STATE_COLOURS[3],
                   label=f"open crack (open > {1e3 * OPEN_CRACK_MIN_M:g} mm)")  # fmt: skip
        ax[3].set_ylabel("crack length (m)" if two_d else "crack area (m²)")
    if fs is not None:  # FS(t), drawn up to FS_SHOWN_MAX (inf while no shear: a gap)
        shown = np.where(np.isfinite(fs), np.minimum(fs, FS_SHOWN_MAX), np.nan)
        ax[-1].plot(t, shown, lw=1.0, color="C0", label="FS = Σ(cA + μN) / |ΣT|")
        ax[-1].axhline(1.0, color="C3", lw=0.8, ls="--", label="FS = 1")
        top = float(np.nanmax(shown)) if np.any(np.isfinite(shown)) else 2.0
        ax[-1].set_ylim(0.0, max(1.2, 1.05 * top))
        ax[-1].set_ylabel(f"sliding safety factor\n(shown up to {FS_SHOWN_MAX:g})")
    return _style(fig, ax, f"{title}\njoint {name}", path)


def open_crack(pr: dict[str, np.ndarray], cr: dict[str, np.ndarray]) -> np.ndarray:
    """The open crack of a joint over time (n_t,), as the summary counts it
    (``max_open_length_m``, ``max_open_area_m2``): its broken pairs in the open state and
    open by more than :data:`OPEN_CRACK_MIN_M`; the history's extent of the broken open
    pairs scaled by their share of its area (the same thickness). ``pr`` and ``cr``: the
    joint's :meth:`Results.pairs` and :meth:`Results.joint_cracks`."""
    A = pr["area"]
    gone = pr["broken"] & (pr["state"] == 3)
    a_open = (gone * A).sum(axis=1)
    a_wide = ((gone & (pr["opening"] > OPEN_CRACK_MIN_M)) * A).sum(axis=1)
    return np.where(a_open > 0, cr["open"] * a_wide / np.where(a_open > 0, a_open, 1.0), 0.0)


def _arc(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Order of the pairs along a joint and their positions (m) along its main direction
    (the first principal axis of the pair points), oriented so that its largest
    component is positive: position 0 is the pair at the joint's end towards −x when
    that direction is closest to x (a dam base, a 2D joint dipping less than 45°),
    towards −y when closest to y, −z when closest to z. :func:`_arc_label` names that
    end on the axis."""
    c = x - x.mean(axis=0)
    direction = np.linalg.svd(c, full_matrices=False)[2][0]
    direction = direction * np.sign(direction[int(np.argmax(np.abs(direction)))])
    s = c @ direction
    order = np.argsort(s)
    return order, s[order] - s[order][0]


def _arc_label(x: np.ndarray, order: np.ndarray) -> str:
    """The axis label of a position along a joint (:func:`_arc`), naming position 0."""
    start = ", ".join(f"{v + 0.0:.4g}" for v in x[order[0]])  # no "-0"
    return f"position along the joint (m), 0 at the pair at ({start}) m"


#: m, the least opening drawn as such in the joint figures: a smaller one (round-off of
#: a closed pair, 1e-12 m and below) is drawn as 0. The figures only: the results file
#: and the summary keep the computed openings.
OPENING_FLOOR_M = 1e-9


def _shown_opening(w: np.ndarray) -> np.ndarray:
    """Openings (m) as drawn: below :data:`OPENING_FLOOR_M` shown as 0."""
    return np.where(w > OPENING_FLOOR_M, w, 0.0)


def plot_states(res: Results, name: str, path: Path, title: str = "") -> Path:
    """The pair states of a joint over time, the pairs in the order of their position along
    the joint (:func:`_arc`); a joint in several pieces (:func:`joint_pieces`) a panel per
    piece."""
    plt = _plt()
    from matplotlib.colors import BoundaryNorm, ListedColormap

    t = res.time
    pr = res.pairs(name)
    pieces = joint_pieces(res, name)
    surface = pr["x"].shape[1] == 3  # a 3D joint: many pairs at one position along it
    fig, axes = plt.subplots(len(pieces), 1, figsize=(8, 1.0 + 3.5 * len(pieces)),
                             squeeze=False)  # fmt: skip
    cmap = ListedColormap(STATE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
    tedges = (
        np.concatenate([[t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]]) if t.size > 1 else np.r_[0, 1]
    )
    for j, (ax, idx) in enumerate(zip(axes[:, 0], pieces, strict=True)):
        x = pr["x"][idx]
        order, s = _arc(x)
        if surface:
            s = np.arange(order.size, dtype=float)  # a column per pair, in that order
        st = pr["state"][:, idx[order]]
        edges = (np.concatenate([[s[0]], 0.5 * (s[1:] + s[:-1]), [s[-1]]]) if s.size > 1
                 else np.r_[0, 1])  # fmt: skip
        im = ax.pcolormesh(edges, tedges, st, cmap=cmap, norm=norm, shading="flat")
        cb = fig.colorbar(im, ax=ax, ticks=[0, 1, 2, 3])
        cb.ax.set_yticklabels(STATE_LABELS)
        ax.set_xlabel("pairs, in the order of their position along the joint's main direction"
                      if surface else _arc_label(x, order))  # fmt: skip
        ax.set_ylabel("time (s)")
        ax.set_title((f"{title}\n" if title and j == 0 else "") + f"pair states along {name}"
                     + _piece_label(j, len(pieces), x.mean(axis=0)), fontsize=10)  # fmt: skip
    return _finish(fig, path)


def _piece_label(j: int, n: int, centre: np.ndarray) -> str:
    """The suffix naming piece ``j`` of ``n`` of a joint in a panel's title, with the
    centroid of its pairs (m); empty for a joint in one piece."""
    if n == 1:
        return ""
    where = ", ".join(f"{v + 0.0:.4g}" for v in centre)
    return f"\npiece {j + 1} of {n}, about ({where}) m"


def plot_rigid(res: Results, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    q = np.asarray(res.f["history/rigid"][...])
    d = int(res.f["mesh/points"].shape[1])
    ground, frame = _ground_of(res)
    if ground is not None:  # the absolute form: the bodies' motion relative to the ground
        q[..., :d] -= ground[:, None, :]
    q = q - q[:1]
    moving = [b for b in range(q.shape[1]) if np.abs(q[:, b]).max() > 0]
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    styles = ("-", "--", ":")  # one per component; one colour per body in both panels
    for b in moving:
        name, colour = res.body_names[b], f"C{b % 10}"
        for i in range(d):
            ax[0].plot(t, 1e3 * q[:, b, i], lw=0.9, color=colour, ls=styles[i],
                       label=f"{name} u_{AXES[i]}")  # fmt: skip
        rot = q[:, b, d:] if d == 3 else q[:, b, 2:3]
        for i in range(rot.shape[1]):
            lab = f"{name} θ_{AXES[i] if d == 3 else 'z'}"
            ax[1].plot(t, 1e3 * rot[:, i], lw=0.9, color=colour, ls=styles[i], label=lab)
    ax[0].set_ylabel("centroid translation (mm)")
    ax[1].set_ylabel("rotation (mrad),\ncounter-clockwise +" if d == 2 else "rotation (mrad)")
    ax[1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
        _legend(a, fontsize=7)
    ax[0].set_title(f"{title}\nrigid motion of the bodies ({frame}, since the start)",
                    fontsize=10)  # fmt: skip
    return _finish(fig, path)


def plot_energy(res: Results, path: Path, title: str = "") -> Path:
    plt = _plt()
    t = res.time
    e = res.energy()
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True,
                           gridspec_kw={"height_ratios": [3, 1]})  # fmt: skip
    for key, lab in (("kinetic", "kinetic"), ("strain", "strain"), ("damping", "damping"),
                     ("interface", "friction and contact"), ("impact", "impact"),
                     ("algorithmic", "time scheme"), ("modified", "scheme's stored term Φ"),
                     ("correction", "position correction"),
                     ("external_work", "work of the loads")):  # fmt: skip
        if key in e and (key not in ("algorithmic", "correction", "modified")
                         or np.any(e[key])):  # fmt: skip
            ax[0].plot(t, e[key] - (e[key][0] if key == "strain" else 0.0), lw=1.0, label=lab)
    ax[0].set_ylabel("energy (J)\n(strain: change)")
    _legend(ax[0])
    ax[1].plot(t, e.get("balance", np.zeros_like(t)), lw=0.9, color="k")
    ax[1].set_ylabel("balance (J)")
    ax[1].set_xlabel("time (s)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].set_title(f"{title}\nenergy balance", fontsize=10)
    return _finish(fig, path)


def plot_static(res: Results, name: str, path: Path, title: str = "") -> Path:
    """Normal and shear stress of the static state along an interface, with the pair
    states; a joint of a 3D model is drawn in its plane (:func:`_plot_static_3d`)."""
    plt = _plt()
    pr = res.static_pairs(name)
    if pr["x"].shape[1] == 3:
        return _plot_static_3d(res, name, path, title)
    pieces = joint_pieces(res, name)
    fig, axes = plt.subplots(2 * len(pieces), 1, figsize=(8, 5.5 * len(pieces)), squeeze=False)
    # 2D: the signed shear stress along the pair's tangent t
    tau = pr["shear_stress"][:, 0]
    for j, idx in enumerate(pieces):
        ax = axes[2 * j : 2 * j + 2, 0]
        x = pr["x"][idx]
        order, s = _arc(x)
        at = idx[order]
        ax[0].plot(s, 1e-6 * pr["normal_stress"][at], lw=1.0, marker=".",
                   label="normal (compression +)")  # fmt: skip
        ax[0].set_ylabel("normal stress (MPa)")
        ax[1].plot(s, 1e-6 * tau[at], lw=1.0, marker=".", color="C1", label="shear")
        state = pr["state"][at]
        for k, lab in enumerate(STATE_LABELS):
            hit = state == k
            if hit.any():
                ax[1].scatter(s[hit], 1e-6 * tau[at][hit], s=18, color=STATE_COLOURS[k],
                              label=lab, zorder=3)  # fmt: skip
        ax[1].set_ylabel("shear stress along t (MPa)")
        ax[1].set_xlabel(_arc_label(x, order))
        ax[1].sharex(ax[0])
        for a in ax:
            a.grid(alpha=0.3)
            _legend(a)
        frames = ("; the stresses on side b, t the normal n (from side a into side b) turned "
                  "clockwise")  # fmt: skip
        ax[0].set_title((f"{title}\n" if title and j == 0 else "")
                        + f"static state of {name}{frames}"
                        + _piece_label(j, len(pieces), x.mean(axis=0)), fontsize=10)  # fmt: skip
    return _finish(fig, path)


def _pair_squares(uv: np.ndarray, area: np.ndarray) -> np.ndarray:
    """Each pair of a 3D joint drawn in the joint's plane: a square of its tributary
    ``area`` about its in-plane point ``uv`` (m, m²), corners (m, 4, 2)."""
    corners = 0.5 * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    return uv[:, None, :] + np.sqrt(area)[:, None, None] * corners[None, :, :]


def _pair_cells(
    uv: np.ndarray,
    area: np.ndarray,
    neighbours: np.ndarray | None = None,
    clip: np.ndarray | None = None,
) -> list[np.ndarray]:
    """Each pair of a 3D joint drawn in the joint's plane as its tributary cell: the
    Voronoi cell of its point ``uv`` (m) among the joint's pairs and the points
    ``neighbours`` (the pairs of other interfaces along a seam: they take their share of
    the faces there), clipped to the convex polygon ``clip`` (counter-clockwise; by default
    the pairs' convex hull), so that the map of a convex joint covers it and no more
    (squares of the tributary area about the points stood out by half a square beyond the
    joint's edges). Pairs at one point share its cell. Falls back to
    :func:`_pair_squares` where the points span no area (all on a line). Polygons (k, 2), m.

    >>> uv = np.array([[x, y] for y in (0.0, 1.0, 2.0) for x in (0.0, 1.0, 2.0)])
    >>> cells = _pair_cells(uv, np.ones(9))
    >>> [round(_polygon_area(c), 6) for c in cells]  # corners ¼, edges ½, centre 1
    [0.25, 0.5, 0.25, 0.5, 1.0, 0.5, 0.25, 0.5, 0.25]
    """
    from scipy.spatial import ConvexHull, QhullError, Voronoi

    pts, inverse = np.unique(np.round(uv, 9), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    try:
        hull = pts[ConvexHull(pts).vertices] if clip is None else clip  # counter-clockwise
    except (QhullError, ValueError):
        return list(_pair_squares(uv, area))
    others = np.zeros((0, 2)) if neighbours is None else np.round(neighbours, 9)
    if others.size:
        from scipy.spatial import cKDTree

        others = np.unique(others, axis=0)
        others = others[cKDTree(pts).query(others)[0] > 1e-9]
    span = float(np.ptp(np.vstack([pts, hull]), axis=0).max())
    centre = pts.mean(axis=0)
    far = centre + 10.0 * span * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    vor = Voronoi(np.vstack([pts, others, far]))
    cells = []
    for i in range(pts.shape[0]):
        region = vor.regions[vor.point_region[i]]
        poly = vor.vertices[region]
        # the cell's vertices counter-clockwise about its point (a convex polygon)
        ang = np.arctan2(*(poly - pts[i]).T[::-1])
        cells.append(_clip_convex(poly[np.argsort(ang)], hull))
    return [cells[k] for k in inverse]


class JointPatch(NamedTuple):
    """A connected, drawable piece of a 3D joint: ``members`` its pairs (positions among the
    joint's pairs), ``uv`` their coordinates in the patch's plane (m), ``basis`` the plane's
    axes and normal (3, 3), ``labels`` the axes' names, ``cells`` each pair's tributary
    polygon in the plane (:func:`_pair_cells`), ``outline`` the patch's faces in the
    plane (corner polygons, m), the region the cells are clipped to when drawn, and
    ``centre`` the centroid of its pairs (3,), m."""

    members: np.ndarray
    uv: np.ndarray
    basis: np.ndarray
    labels: list[str]
    cells: list[np.ndarray]
    outline: list[np.ndarray]
    centre: np.ndarray


#: |cos| of the angle between two faces of a joint that share a node, above which they are
#: one piece (30°): a bent joint's neighbouring faces stay together, the arms of a T or a
#: cross, and the steps of a keyed base, are pieces of their own
PIECE_COS = np.cos(np.radians(30.0))


#: per results file, its cut faces (:func:`_cut_faces`): every joint's figures read them
_CUT_FACES: weakref.WeakKeyDictionary[Results, list[tuple[np.ndarray, int, np.ndarray]]] = (
    weakref.WeakKeyDictionary()
)


def _cut_faces(res: Results) -> list[tuple[np.ndarray, int, np.ndarray]]:
    """The faces of the mesh's cuts, per face type: the blocks' boundary faces that
    coincide with another boundary face (the other side of a joint or crack; an outer face
    has no twin; corner coordinates rounded to 1e-9 of the model's size), as (nodes,
    corners first; the number of corners; unit normals (f, d)). Formed once per results
    file, for all its joints' figures."""
    hit = _CUT_FACES.get(res)
    if hit is not None:
        return hit
    from ..element import reference
    from ..mesh import Mesh

    f = res.f
    points = np.asarray(f["mesh/points"], dtype=float)
    cells = {ctype: np.asarray(f[f"mesh/cells/{ctype}"]) for ctype in f["mesh/cells"]}
    span = float(np.ptp(points, axis=0).max()) or 1.0
    out = []
    for ftype, conn in Mesh(points, cells).facets(boundary_only=True).items():
        c = np.asarray(conn)
        k = reference(reference(ftype).linear).n_nodes
        xyz = np.round(points[c[:, :k]] / (1e-9 * span)).astype(np.int64)  # (f, k, d)
        order = np.lexsort(xyz.transpose(2, 0, 1)[::-1], axis=-1)
        key = np.take_along_axis(xyz, order[..., None], axis=1).reshape(len(c), -1)
        _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        c = c[cnt[inv.ravel()] >= 2]
        p = points[c[:, :k]]
        fn = (np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) if points.shape[1] == 3
              else (p[:, 1] - p[:, 0]) @ np.array([[0.0, -1.0], [1.0, 0.0]]))  # fmt: skip
        out.append((c, k, fn / np.maximum(np.linalg.norm(fn, axis=1, keepdims=True), 1e-300)))
    _CUT_FACES[res] = out
    return out


def _joint_faces(res: Results, name: str) -> dict[str, Any]:
    """The faces of a joint and its pieces, for :func:`joint_pieces` and
    :func:`joint_patches`: ``label`` (m,) the piece of each of the joint's pairs (pieces
    numbered in the order of their first pairs), ``corners`` the faces' corner coordinates
    (a list of (k, d) arrays), ``face_piece`` each face's piece, ``seam`` (s, 2) the nodes of
    pairs of other interfaces on the faces with their face's piece, and the joint's
    pairs' ``x``, ``frame``, ``area``, and the mesh's ``points``.

    The joint's faces are the cut faces (:func:`_cut_faces`) that hold a side-a node of a
    pair of the joint (at a crack's front the other nodes are whole, of no pair) and lie
    within 60° of the plane of a pair of the joint at one of their nodes (a face of
    another joint through a junction node is not one). Faces that share a node and whose
    planes differ by less than 30° (:data:`PIECE_COS`) are one piece; a pair belongs to
    the piece of the face at its node whose plane is closest to its own (at a junction a
    node carries pairs of each joint that meets there), a pair on no face to a piece of
    its own. See :func:`joint_patches`."""
    from scipy.sparse import coo_matrix, csr_matrix
    from scipy.sparse.csgraph import connected_components

    f = res.f
    sel = res._select(name)
    x_pair = np.asarray(f["pairs/x"])[sel]
    frame = np.asarray(f["pairs/frame"])[sel]
    node = np.asarray(f["pairs/node_a"])[sel]
    points = np.asarray(f["mesh/points"], dtype=float)
    n_pts, m, dim = points.shape[0], node.size, points.shape[1]
    normal = frame[:, -1, :]
    # node → the joint's pairs there (several at a junction)
    at_node = csr_matrix((np.ones(m), (node, np.arange(m))), shape=(n_pts, m))
    other = np.zeros(n_pts, dtype=bool)  # nodes of pairs of other interfaces
    names = res.interface_names
    k_if = names.index(name)
    iface = np.asarray(f["pairs/interface"])
    other[np.asarray(f["pairs/node_a"])[iface != k_if]] = True
    other[np.asarray(f["pairs/node_b"])[iface != k_if]] = True
    other[node] = False
    table = _cut_faces(res)
    if not table or m == 0:
        return {"label": np.arange(m), "corners": [], "seam": np.zeros((0, 2), dtype=int),
                "x": x_pair, "frame": frame, "area": np.asarray(f["pairs/area"])[sel],
                "points": points, "face_piece": np.zeros(0, dtype=int)}  # fmt: skip
    kept: list[np.ndarray] = []
    kept_k: list[int] = []
    fns: list[np.ndarray] = []
    for c, k, fn in table:
        # the best alignment with a pair of the joint at one of the face's nodes (0 on a
        # face without one)
        rows, pairs = (at_node[c.ravel()]).nonzero()
        face_of = rows // c.shape[1]
        cos = np.abs(np.einsum("id,id->i", fn[face_of], normal[pairs]))
        best = np.zeros(len(c))
        np.maximum.at(best, face_of, cos)
        ok = best > 0.5
        kept.append(c[ok])
        kept_k.append(k)
        fns.append(fn[ok])
    corner_of = [k for c, k in zip(kept, kept_k, strict=True) if len(c)]
    faces = [c for c in kept if len(c)]
    fn_all = (
        np.concatenate([n for n, c in zip(fns, kept, strict=True) if len(c)])
        if faces
        else np.zeros((0, dim))
    )
    n_f = int(sum(len(c) for c in faces))
    # face–node incidence, then faces sharing a node within 30° of each other
    fi = np.concatenate([np.repeat(np.arange(len(c)), c.shape[1]) + off for c, off in
                         zip(faces, np.cumsum([0] + [len(c) for c in faces])[:-1],
                             strict=True)]) if faces else np.zeros(0, dtype=int)  # fmt: skip
    ni = np.concatenate([c.ravel() for c in faces]) if faces else np.zeros(0, dtype=int)
    B = csr_matrix((np.ones(fi.size), (fi, ni)), shape=(n_f, n_pts))
    A = (B @ B.T).tocoo()
    near = np.abs(np.einsum("id,id->i", fn_all[A.row], fn_all[A.col])) > PIECE_COS
    graph = coo_matrix((np.ones(int(near.sum())), (A.row[near], A.col[near])), shape=(n_f, n_f))
    _, face_label = connected_components(graph, directed=False)
    # each pair: the face at its node closest to its plane
    P = B[:, node].T.tocoo()  # (pair, face) for the faces at the pair's node
    score = np.abs(np.einsum("id,id->i", normal[P.row], fn_all[P.col]))
    order = np.lexsort((-score, P.row))
    first = np.r_[True, P.row[order][1:] != P.row[order][:-1]]
    pair_face = np.full(m, -1)
    pair_face[P.row[order][first]] = P.col[order][first]
    raw = np.where(pair_face >= 0, face_label[np.maximum(pair_face, 0)], -1)
    lone = raw < 0  # a pair on no face: a piece of its own
    raw[lone] = face_label.max(initial=-1) + 1 + np.arange(int(lone.sum()))
    # the pieces numbered in the order of their first pairs (pieces without pairs dropped)
    uniq, first_pair = np.unique(raw, return_index=True)
    rank = np.full(int(raw.max(initial=-1)) + 1, -1)
    rank[uniq[np.argsort(first_pair)]] = np.arange(uniq.size)
    label = rank[raw]
    face_piece = rank[face_label] if n_f else np.zeros(0, dtype=int)
    corners = [points[c[:k]] for arr, k in zip(faces, corner_of, strict=True) for c in arr]
    # the nodes of other interfaces' pairs on each face, with its piece
    on = other[ni]
    seam = np.column_stack([ni[on], face_piece[fi[on]]]) if faces else np.zeros((0, 2), int)
    keep = face_piece >= 0
    if not keep.all():  # faces of no pair's piece
        corners = [c for c, k in zip(corners, keep, strict=True) if k]
        face_piece = face_piece[keep]
        seam = seam[seam[:, 1] >= 0]
    return {"label": label, "corners": corners, "seam": seam, "x": x_pair, "frame": frame,
            "area": np.asarray(f["pairs/area"])[sel], "points": points,
            "face_piece": face_piece}  # fmt: skip


def joint_pieces(res: Results, name: str) -> list[np.ndarray]:
    """The connected pieces of a joint (:func:`joint_patches`), as the positions of their
    pairs among the joint's, pieces in the order of their first pairs. A 2D group holding
    two lift joints is two pieces; a joint is one.

    The figures along a joint draw each piece apart: laid along one axis, the pairs of two
    parallel joints interleave, and a line through them zigzags between the joints."""
    label = _joint_faces(res, name)["label"]
    return [np.flatnonzero(label == j) for j in range(int(label.max(initial=-1)) + 1)]


def joint_patches(res: Results, name: str) -> list[JointPatch]:
    """The pieces of a 3D joint that are drawn apart, each in its own plane
    (:func:`joint_plane`): one physical group may hold several joints (the contraction
    joints of a dam, parallel planes, or a T), which projected on one plane would lie on
    top of each other. The faces and pieces are :func:`_joint_faces`'s. Each pair's cell is
    its Voronoi cell in the piece (:func:`_pair_cells`) among the piece's pairs and the
    other interfaces' pair nodes on its faces (a seam's pairs belong to one of the
    interfaces that meet there, and their tributary area spans both), clipped to the box
    of the piece's faces and drawn clipped to the faces themselves (``outline``), so that
    a joint with a re-entrant corner is not painted over its convex hull and a crack is
    drawn to its front."""
    jf = _joint_faces(res, name)
    label, corners, seam = jf["label"], jf["corners"], jf["seam"]
    out = []
    for j in range(int(label.max(initial=-1)) + 1):
        idx = np.flatnonzero(label == j)
        uv, basis, labels = joint_plane(jf["x"][idx], jf["frame"][idx])
        outline = [corners[i] @ basis[:2].T for i in np.flatnonzero(jf["face_piece"] == j)]
        clip = None
        if outline:  # the faces' bounding box: the outline clips the drawing
            lo, hi = np.vstack(outline).min(axis=0), np.vstack(outline).max(axis=0)
            clip = np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])
        near = jf["points"][seam[seam[:, 1] == j, 0]] @ basis[:2].T
        cells_j = _pair_cells(uv, jf["area"][idx], near, clip)
        out.append(JointPatch(idx, uv, basis, labels, cells_j, outline,
                              jf["x"][idx].mean(axis=0)))  # fmt: skip
    return out


def _clip_to(pc: Any, ax: Any, outline: list[np.ndarray]) -> None:
    """Clip a collection drawn on ``ax`` to the union of the polygons ``outline`` (data
    coordinates; none: no clipping)."""
    if not outline:
        return
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    path = MplPath.make_compound_path(*[MplPath(np.vstack([p, p[:1]]), closed=True)
                                        for p in outline])  # fmt: skip
    pc.set_clip_path(PathPatch(path, transform=ax.transData))


def _clip_convex(poly: np.ndarray, clip: np.ndarray) -> np.ndarray:
    """The convex polygon ``poly`` clipped to the convex polygon ``clip`` (both
    counter-clockwise, (k, 2)): Sutherland–Hodgman."""
    out = poly
    for a, b in zip(clip, np.roll(clip, -1, axis=0), strict=True):
        if not len(out):
            break
        edge = b - a
        side = edge[0] * (out[:, 1] - a[1]) - edge[1] * (out[:, 0] - a[0])  # ≥ 0: inside
        kept = []
        for k in range(len(out)):
            p, q = out[k], out[(k + 1) % len(out)]
            sp, sq = side[k], side[(k + 1) % len(out)]
            if sp >= 0:
                kept.append(p)
            if (sp >= 0) != (sq >= 0):
                kept.append(p + (q - p) * (sp / (sp - sq)))
        out = np.array(kept).reshape(-1, 2)
    return out


def _polygon_area(poly: np.ndarray) -> float:
    """The area of a polygon (k, 2) by the shoelace formula (m²)."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * abs(float(x @ np.roll(y, -1) - y @ np.roll(x, -1)))


def _plot_static_3d(res: Results, name: str, path: Path, title: str) -> Path:
    """The static state of a 3D joint in its plane, each connected piece in its own
    (:func:`joint_patches`; a pair: its tributary cell, as the joint map): the normal
    stress (compression +), the magnitude of the shear stress (MPa) and the pair states,
    a row per piece."""
    plt = _plt()
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import BoundaryNorm, ListedColormap

    pr = res.static_pairs(name)
    patches = joint_patches(res, name)
    fig, axes = plt.subplots(len(patches), 3, figsize=(15, 4.8 * len(patches)), squeeze=False)
    normal = 1e-6 * pr["normal_stress"]
    shear = 1e-6 * np.linalg.norm(pr["shear_stress"], axis=-1)
    for j, (row, patch) in enumerate(zip(axes, patches, strict=True)):
        at = _piece_label(j, len(patches), patch.centre)
        for ax, v, what, cmap in ((row[0], normal, "normal stress (compression +)", "viridis"),
                                  (row[1], shear, "|shear stress|", "magma")):  # fmt: skip
            pc = PolyCollection(patch.cells, array=v[patch.members], cmap=cmap, edgecolors="0.6",
                                linewidths=0.3)  # fmt: skip
            pc.set_clim(float(v.min()), float(v.max()))  # one scale over the pieces
            ax.add_collection(pc)
            _clip_to(pc, ax, patch.outline)
            fig.colorbar(pc, ax=ax, shrink=0.8, label="MPa")
            ax.set_title(what + at, fontsize=9)
        pc = PolyCollection(patch.cells, array=pr["state"][patch.members],
                            cmap=ListedColormap(STATE_COLOURS),
                            norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4), edgecolors="w",
                            linewidths=0.3)  # fmt: skip
        row[2].add_collection(pc)
        _clip_to(pc, row[2], patch.outline)
        bar = fig.colorbar(pc, ax=row[2], shrink=0.8, ticks=[0, 1, 2, 3])
        bar.ax.set_yticklabels(STATE_LABELS, fontsize=7)
        row[2].set_title("pair states" + at, fontsize=9)
        for ax in row:
            ax.set_aspect("equal")
            ax.autoscale_view()
            ax.set_xlabel(f"{patch.labels[0]} (m)")
            ax.set_ylabel(f"{patch.labels[1]} (m)")
    fig.suptitle((f"{title}\n" if title else "") + f"static state of {name}, in its plane"
                 + (f" ({len(patches)} pieces, each in its own)" if len(patches) > 1 else ""),
                 fontsize=10)  # fmt: skip
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
        _legend(a)
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


#: the percentile of the nodal values where a stress map's colours stop (and the other
#: side's, 100 minus it): a stress concentration at one node (a joint's corner where a
#: block lands) set the scale of the whole map, which then read white everywhere else
COLOUR_CLIP_PERCENT = 99.5


def _colour_range(v: np.ndarray) -> tuple[float, float, str]:
    """The colour limits of a signed stress map (MPa) and the colour bar's ``extend``:
    symmetric about 0 (white) over the values' range between the percentiles
    :data:`COLOUR_CLIP_PERCENT` and 100 minus it; one-sided (0 to the limit) where the
    values keep one sign to a twentieth of their range, as σ₃ in compression.

    >>> lo, hi, extend = _colour_range(np.r_[np.linspace(-2.0, -1.0, 999), -50.0])  # a spike
    >>> round(lo, 2), hi, extend
    (-2.0, 0.0, 'min')
    """
    if not v.size:
        return -1.0, 1.0, "neither"
    lo = float(np.percentile(v, 100.0 - COLOUR_CLIP_PERCENT))
    hi = float(np.percentile(v, COLOUR_CLIP_PERCENT))
    if lo >= -0.05 * abs(hi):  # (one sign, to a twentieth: σ₃ with a few MPa·1e-3 of
        lo = 0.0  # tension at a free corner reads as compression only)
    elif hi <= 0.05 * abs(lo):
        hi = 0.0
    else:
        hi = max(abs(lo), abs(hi))
        lo = -hi
    if hi - lo <= 0.0:
        lo, hi = lo - 1.0, hi + 1.0
    below, above = bool(v.min() < lo - 1e-12 * (hi - lo)), bool(v.max() > hi + 1e-12 * (hi - lo))
    extend = "both" if below and above else "min" if below else "max" if above else "neither"
    return round(lo, 12), round(hi, 12), extend


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
        lo, hi, extend = _colour_range(vv[np.unique(tri[ok])] if ok.any() else vv[:0])
        # red tension, blue compression, white zero: one-sided maps take one of the halves
        cmap = "Blues_r" if hi == 0.0 else "Reds" if lo == 0.0 else "RdBu_r"
        im = ax.tripcolor(tr, vv, shading="gouraud", cmap=cmap, vmin=lo, vmax=hi)
        clipped = (f" (colours to the {COLOUR_CLIP_PERCENT:g}th percentile)"
                   if extend != "neither" else "")  # fmt: skip
        fig.colorbar(im, ax=ax, shrink=0.8, label="MPa" + clipped, extend=extend)
        at = None if marks is None else marks[k]
        if at is not None:
            ax.plot(at[0], at[1], "k*", ms=10, mec="w")
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        if extend != "neither" and ok.any():  # say what the clipped colours hide
            used = vv[np.unique(tri[ok])]
            label += f"\n(extremes {used.min():.3g} to {used.max():.3g} MPa)"
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
    rows = [(name, j, idx, len(pieces)) for name in names
            for pieces in [joint_pieces(res, name)] for j, idx in enumerate(pieces)]  # fmt: skip
    fig, axes = plt.subplots(2 * len(rows), 1, figsize=(8, 3.6 * len(rows)), squeeze=False,
                             gridspec_kw={"height_ratios": [4, 1] * len(rows)})  # fmt: skip
    cmap = ListedColormap(STATE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
    for i, (name, j, idx, n) in enumerate(rows):
        ax, strip = axes[2 * i, 0], axes[2 * i + 1, 0]
        pr = res.pairs(name)
        x = pr["x"][idx]
        order, s = _arc(x)
        at = idx[order]
        slip = np.linalg.norm(pr["slip"], axis=-1)[:, at]
        ax.plot(s, 1e3 * _shown_opening(pr["opening"][:, at].max(axis=0)), ".-", lw=1.0,
                color="C3", label="largest opening")  # fmt: skip
        ax.plot(s, 1e3 * slip.max(axis=0), ".-", lw=1.0, color="C0", label="largest slip")
        ax.plot(s, 1e3 * slip[-1], "--", lw=1.0, color="C0", label="residual slip")
        ax.set_ylabel("opening, slip (mm)")
        ax.set_ylim(bottom=0.0)  # magnitudes: a small slip is not read as none
        ax.grid(alpha=0.3)
        _legend(ax)
        ax.set_title(f"joint {name}" + _piece_label(j, n, x.mean(axis=0)), fontsize=9)
        first = (res.static_pairs(name)["state"][at] if "static/state" in res.f
                 else pr["state"][0, at])  # fmt: skip
        st = np.stack([first, pr["state"][-1, at]])
        edges = (np.concatenate([[s[0]], 0.5 * (s[1:] + s[:-1]), [s[-1]]]) if s.size > 1
                 else np.r_[-0.5, 0.5])  # fmt: skip
        strip.pcolormesh(edges, [0, 1, 2], st, cmap=cmap, norm=norm, shading="flat")
        broken = pr["broken"][-1, at]
        strip.plot(s[broken], np.full(int(broken.sum()), 1.5), "kx", ms=4)
        strip.set_yticks([0.5, 1.5], ["static", "end"], fontsize=8)
        strip.set_xlim(ax.get_xlim())
        strip.set_xlabel(_arc_label(x, order))
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in STATE_COLOURS]
    handles.append(plt.Line2D([], [], color="k", marker="x", ls=""))
    fig.legend(handles, [*STATE_LABELS, "broken"], loc="lower center", ncol=5, fontsize=8)
    head = fig.suptitle((f"{title}\n" if title else "") + "joint maps", fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, _below_title(fig, head.get_text())))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _load_group(mesh: Any, group: str) -> str:
    """The facet group a load on ``group`` is drawn on: the group itself, or an
    interface's first face (``<group>:a``: water in a joint, a pressure in it), which
    the cut mesh holds instead of the group."""
    if group not in mesh.facet_groups and f"{group}:a" in mesh.facet_groups:
        return f"{group}:a"
    return group


def _facet_polylines(model: Any, group: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The facets of a 2D group as (points (5, 2) along the facet, outward normal (2,));
    an interface's (a pressure in the joint) drawn on its first face."""
    mesh = model.mesh
    out = []
    for ftype, conn in mesh.facet_group(_load_group(mesh, group)).items():
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
        if ld.kind == "gravity":  # the first: pseudo-static forces come after it
            if gravity is None:
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
    if ax.get_legend_handles_labels()[0]:  # (none: no supports, no water)
        ax.legend(loc="upper right", fontsize=8)
    ax.set_title(
        (f"{title}\n" if title else "") + "loads (the pressure diagrams to one "
        "scale, drawn on the side of the water; uplift below its joint)",
        fontsize=10,
    )
    return _finish(fig, path)


# -- figures of 3D models: boundary faces in a fixed view, joints in their planes -----------
#: the view of the 3D figures (degrees): elevation above the x-y plane and azimuth from
#: +x; the camera is upstream (−x, the reservoir's side by the model file's convention),
#: on the −y side and above, so a dam's upstream face, its crest and one flank show
VIEW_3D = (25.0, -135.0)
#: marks of the 3D figures drawn over the faces (the axes keep the drawing order)
_ON_TOP = 5


def boundary_faces(points: np.ndarray, cells: dict[str, np.ndarray]) -> list[np.ndarray]:
    """The boundary faces of a 3D mesh: the faces that one cell only uses, as their corner
    node ids (one array (n_faces, 3 or 4) per corner count, triangles first).

    A face is keyed by its sorted corner ids and counted over every cell of the mesh
    (:meth:`pfeie.mesh.Mesh.facets`, ``numpy.unique`` with counts); the faces counted
    once are the boundary. The nodes of a joint are split (each side its own), so each
    block shows its own boundary, its faces on the joint included (a structured
    ``nx × ny × nz`` hexahedral block has 2 (nx ny + ny nz + nz nx) of them)."""
    from ..element import reference
    from ..mesh import Mesh

    faces = Mesh(np.asarray(points, dtype=float), dict(cells)).facets(boundary_only=True)
    out: dict[int, list[np.ndarray]] = {}
    for ftype, conn in faces.items():
        k = reference(reference(ftype).linear).n_nodes
        out.setdefault(k, []).append(np.asarray(conn)[:, :k])
    return [np.concatenate(out[k]) for k in sorted(out)]


def _faces_of(res: Results) -> tuple[np.ndarray, list[np.ndarray]]:
    """The points (n, 3) and the boundary faces (:func:`boundary_faces`) of a results
    file's mesh."""
    x = np.asarray(res.f["mesh/points"])
    cells = {ctype: np.asarray(res.f[f"mesh/cells/{ctype}"]) for ctype in res.f["mesh/cells"]}
    return x, boundary_faces(x, cells)


def _polygons(x: np.ndarray, faces: list[np.ndarray]) -> Any:
    """The corner coordinates of the faces: an array (n_faces, k, 3) when they all have k
    corners, else a list of (k, 3) arrays (triangles and quadrilaterals together)."""
    if len(faces) == 1:
        return x[faces[0]]
    return [p for f in faces for p in x[f]]


def _art3d() -> Any:
    """matplotlib's 3D collections (``mpl_toolkits.mplot3d.art3d``)."""
    _plt()
    from mpl_toolkits.mplot3d import art3d  # type: ignore[import-untyped]

    return art3d


def _axes3d(fig: Any, *where: int) -> Any:
    """A 3D axes (subplot ``where``: rows, columns, index) in the fixed view
    :data:`VIEW_3D`, drawn in the order of the artists (faces first, the marks over
    them)."""
    ax = fig.add_subplot(*where, projection="3d", computed_zorder=False)
    ax.view_init(elev=VIEW_3D[0], azim=VIEW_3D[1])
    return ax


def _frame3d(ax: Any, x: np.ndarray) -> None:
    """Equal scaling along x, y, z: the axes' box in proportion to the mesh's extent."""
    lo, hi = x.min(axis=0), x.max(axis=0)
    span = np.maximum(hi - lo, 1e-3 * max(float((hi - lo).max()), 1e-12))
    mid = 0.5 * (lo + hi)
    ax.set_xlim(mid[0] - span[0] / 2, mid[0] + span[0] / 2)
    ax.set_ylim(mid[1] - span[1] / 2, mid[1] + span[1] / 2)
    ax.set_zlim(mid[2] - span[2] / 2, mid[2] + span[2] / 2)
    ax.set_box_aspect(tuple(span))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")


def _finish_described(fig: Any, path: Path, description: dict[str, Any]) -> Path:
    """Save like :func:`_finish`, the figure's key numbers (what it draws) in the PNG's
    ``Description`` text chunk as JSON, for a reader or a check without the model."""
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Description": json.dumps(description)})
    _plt().close(fig)
    return path


def plot_mesh_3d(res: Results, path: Path, title: str = "") -> Path:
    """The 3D mesh: its boundary faces (:func:`boundary_faces`) coloured by body in the
    view :data:`VIEW_3D`, equal scaling, the interface pairs (red, drawn through the
    faces) and the probes (labelled). The PNG's description gives the counts drawn."""
    plt = _plt()
    x, faces = _faces_of(res)
    body = np.asarray(res.f["mesh/body"])
    fig = plt.figure(figsize=(8.5, 7))
    ax = _axes3d(fig, 1, 1, 1)
    first = np.concatenate([f[:, 0] for f in faces]) if faces else np.zeros(0, dtype=int)
    colours = plt.get_cmap("tab10")(np.maximum(body[first], 0) % 10)
    colours[:, 3] = 0.45
    ax.add_collection3d(_art3d().Poly3DCollection(_polygons(x, faces), facecolors=colours,
                                         edgecolors="0.3", linewidths=0.3))  # fmt: skip
    n_pairs = 0
    if "pairs/x" in res.f:
        xp = np.asarray(res.f["pairs/x"])
        n_pairs = int(xp.shape[0])
        ax.scatter(*xp.T, s=4, color="tab:red", depthshade=False, zorder=_ON_TOP,
                   label="interface pairs")  # fmt: skip
    probes = res.probe_names
    if probes:
        nodes = json.loads(res.f["history/probes"].attrs.get("nodes", "[]"))
        xn = x[np.asarray(nodes, dtype=int)]
        ax.scatter(*xn.T, marker="^", s=40, color="k", depthshade=False, zorder=_ON_TOP + 1)
        for name, at in zip(probes, xn, strict=False):
            ax.text(*at, f" {name}", fontsize=8, zorder=_ON_TOP + 1)
    _frame3d(ax, x)
    names = res.body_names
    handles = [plt.Rectangle((0, 0), 1, 1, color=plt.get_cmap("tab10")(b % 10), alpha=0.45)
               for b in range(len(names))]  # fmt: skip
    labels = list(names)
    if n_pairs:
        handles.append(plt.Line2D([], [], color="tab:red", marker=".", ls=""))
        labels.append("interface pairs")
    ax.legend(handles, labels, loc="upper left", fontsize=8)
    n_faces = int(sum(f.shape[0] for f in faces))
    ax.set_title((f"{title}\n" if title else "") + f"mesh: {len(names)} bodies "
                 f"({', '.join(names)}), {x.shape[0]} nodes, {n_faces} boundary faces",
                 fontsize=10)  # fmt: skip
    return _finish_described(fig, path, {"boundary_faces": n_faces, "pairs": n_pairs,
                                         "probes": len(probes), "view": list(VIEW_3D)})  # fmt: skip


def plot_fields_3d(
    res: Results, fields: list[tuple[str, np.ndarray]], path: Path, title: str = "",
) -> Path:  # fmt: skip
    """Nodal scalar fields (label, values (n_points,) in MPa) painted on the boundary
    faces of a 3D mesh, one panel each: a face's colour is the mean of its corner nodes'
    values (a face with a missing value grey); the colours follow the 2D maps'
    (:func:`_colour_range` over the face means: red tension, blue compression, white
    zero, one-sided where the values keep one sign, clipped at the percentile
    :data:`COLOUR_CLIP_PERCENT` with the colour bar extended), and the extreme of each
    field over all the nodes (the largest of the first panel, the smallest of the others)
    is starred at its node, drawn through the faces (it may lie inside) and given in the
    panel's title. The PNG's description gives, per panel, the colour limits and the
    extreme (MPa) with its node's position (m)."""
    plt = _plt()
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    x, faces = _faces_of(res)
    fig = plt.figure(figsize=(6.0 * len(fields), 6.0))
    panels = []
    for k, (label, v) in enumerate(fields):
        ax = _axes3d(fig, 1, len(fields), k + 1)
        v = np.asarray(v, dtype=float)
        finite = np.isfinite(v)
        mean = np.concatenate([v[f].mean(axis=1) for f in faces]) if faces else np.zeros(0)
        shown = np.isfinite(mean)
        lo, hi, extend = _colour_range(mean[shown])
        # red tension, blue compression, white zero: one-sided maps take one of the halves
        cmap = plt.get_cmap("Blues_r" if hi == 0.0 else "Reds" if lo == 0.0 else "RdBu_r")
        norm = Normalize(lo, hi)
        colours = cmap(norm(np.where(shown, mean, 0.0)))
        colours[~shown] = (0.8, 0.8, 0.8, 1.0)
        ax.add_collection3d(_art3d().Poly3DCollection(_polygons(x, faces), facecolors=colours,
                                             edgecolors="0.4", linewidths=0.15))  # fmt: skip
        clipped = (f" (colours to the {COLOUR_CLIP_PERCENT:g}th percentile)"
                   if extend != "neither" else "")  # fmt: skip
        fig.colorbar(ScalarMappable(norm, cmap), ax=ax, shrink=0.6, pad=0.1,
                     label="MPa" + clipped, extend=extend)  # fmt: skip
        panel: dict[str, Any] = {"label": label, "colour_range_MPa": [lo, hi]}
        if finite.any():
            at = int(np.nanargmax(v) if k == 0 else np.nanargmin(v))
            ax.scatter(*x[at], marker="*", s=160, color="k", edgecolors="w", depthshade=False,
                       zorder=_ON_TOP)  # fmt: skip
            where = ", ".join(f"{c:.4g}" for c in x[at])
            label = (f"{label}\n{'max' if k == 0 else 'min'} {v[at]:.4g} MPa at ({where}) m\n"
                     "(★ drawn through the faces: it may lie inside or behind)")  # fmt: skip
            panel.update({"extreme_MPa": float(v[at]), "at_m": x[at].tolist()})
        panels.append(panel)
        _frame3d(ax, x)
        ax.set_title(label, fontsize=9)
    fig.suptitle(title, fontsize=10)
    return _finish_described(fig, path, {"panels": panels, "view": list(VIEW_3D)})


def plot_envelope_3d(res: Results, path: Path, title: str = "") -> Path:
    """The stress envelope of a 3D model on its boundary faces: the largest σ₁ and the
    smallest σ₃ of the run at every node (MPa, tension positive; the total stress, static
    state included), :func:`plot_fields_3d`; the stars mark the extremes."""
    env = res.envelope()
    fields = [("largest σ1 over the run", 1e-6 * env["node_max"]),
              ("smallest σ3 over the run", 1e-6 * env["node_min"])]  # fmt: skip
    return plot_fields_3d(res, fields, path, (f"{title}\n" if title else "") + "stress "
                          "envelope (tension +), on the boundary faces")  # fmt: skip


def joint_plane(x: np.ndarray, frame: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """The plane of a 3D joint and its pairs' coordinates in it.

    The plane's normal n is the mean of the pairs' normals (the last row of their frames,
    oriented as the first pair's); if they cancel, the direction of least spread of the
    points (the last right singular vector of the centred points). Its in-plane axes are
    the two global axes least aligned with n, in the order x, y, z, made orthonormal to n
    (Gram–Schmidt): a horizontal joint is mapped on (x, y), a gently dipping one on
    (≈x, y) or (x, ≈y), the same order (a dip along x swapped the axes to (y, ≈x)), a
    joint normal to x on (y, z). Returns the
    coordinates (n_pairs, 2) = (x · a₁, x · a₂) in m, the axes (3, 3) = (a₁, a₂, n), and
    the axes' labels ("x" for an axis along x, "≈x" for one only close to it)."""
    nrm = np.asarray(frame)[:, -1, :]
    nrm = nrm * np.where(nrm @ nrm[0] < 0, -1.0, 1.0)[:, None]
    n = nrm.mean(axis=0)
    if np.linalg.norm(n) < 1e-9:
        # Vᵀ only (3 × 3): the left vectors of thousands of pairs are not needed
        n = np.linalg.svd(x - x.mean(axis=0), full_matrices=x.shape[0] < 3)[2][-1]
    n = n / np.linalg.norm(n)
    axes = [n]
    labels = []
    for i in sorted(np.argsort(np.abs(n), kind="stable")[:2]):
        a = np.eye(3)[i] - sum((np.eye(3)[i] @ b) * b for b in axes)
        a = a / np.linalg.norm(a)
        axes.insert(len(axes) - 1, a)
        labels.append(("" if abs(abs(a[i]) - 1.0) < 1e-9 else "≈") + AXES[i])
    basis = np.stack(axes)
    return x @ basis[:2].T, basis, labels


#: the least top of the colour scales of the 3D joint map (mm): a joint that stays shut
#: (openings of round-off size) is drawn white, not at a full scale of noise
MAP_FLOOR_MM = 1e-3


def plot_joint_map_3d(res: Results, path: Path, title: str = "") -> Path:
    """Per joint of a 3D model, each connected piece of it in its plane
    (:func:`joint_patches`: a physical group may hold several parallel joints), each pair
    its tributary cell clipped to the joint's faces: the pair states of the static state
    and at the end (the colours of the 2D map; broken pairs crossed), the largest opening
    of the run and the residual slip (mm; each colour scale from 0 to the joint's largest
    value, at least :data:`MAP_FLOOR_MM`). The PNG's description gives, per joint, the
    pairs drawn, the mean plane's normal, the largest values shown and its pieces (pairs,
    normal, centroid)."""
    plt = _plt()
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import BoundaryNorm, ListedColormap

    names = res.interface_names
    pieces = [
        (name, j, patch, len(patches))
        for name in names
        for patches in [joint_patches(res, name)]
        for j, patch in enumerate(patches)
    ]
    fig, axes = plt.subplots(2 * len(pieces), 2, figsize=(11, 8.4 * len(pieces)),
                             squeeze=False)  # fmt: skip
    cmap = ListedColormap(STATE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
    described: dict[str, Any] = {}
    data: dict[str, tuple[np.ndarray, ...]] = {}
    for name in names:
        pr = res.pairs(name)
        first = (res.static_pairs(name)["state"] if "static/state" in res.f
                 else pr["state"][0])  # fmt: skip
        opening = 1e3 * _shown_opening(pr["opening"].max(axis=0))
        residual = 1e3 * np.linalg.norm(pr["slip"][-1], axis=-1)
        data[name] = (first, pr["state"][-1], opening, residual, pr["broken"][-1])
        uv, basis, labels = joint_plane(pr["x"], pr["frame"])
        described[name] = {"pairs": int(uv.shape[0]), "normal": basis[-1].tolist(),
                           "axes": labels, "largest_opening_mm": float(opening.max()),
                           "largest_residual_slip_mm": float(residual.max()),
                           "pieces": []}  # fmt: skip
    for i, (name, j, patch, n) in enumerate(pieces):
        first, last, opening, residual, broken = (v[patch.members] for v in data[name])
        at = _piece_label(j, n, patch.centre)
        panels = (
            (first, "pair states, static", None),
            (last, "pair states at the end (× broken)", None),
            (opening, "largest opening of the run", "Reds"),
            (residual, "residual slip", "Blues"),
        )  # fmt: skip
        for k, (v, what, seq) in enumerate(panels):
            ax = axes[2 * i + k // 2, k % 2]
            if seq is None:
                pc = PolyCollection(patch.cells, array=v, cmap=cmap, norm=norm, edgecolors="w",
                                    linewidths=0.3)  # fmt: skip
                # a colour bar of the states too, so that the four panels of a joint are
                # drawn at one scale (a panel without one was drawn larger)
                bar = fig.colorbar(pc, ax=ax, shrink=0.8, ticks=[0, 1, 2, 3])
                bar.ax.set_yticklabels(STATE_LABELS, fontsize=7)
            else:
                whole = data[name][2 if seq == "Reds" else 3]  # one scale over the pieces
                pc = PolyCollection(patch.cells, array=v, cmap=seq, edgecolors="0.6",
                                    linewidths=0.3)  # fmt: skip
                pc.set_clim(0.0, max(float(whole.max()), MAP_FLOOR_MM))
                fig.colorbar(pc, ax=ax, shrink=0.8, label="mm")
            ax.add_collection(pc)
            _clip_to(pc, ax, patch.outline)
            if k == 1 and broken.any():
                ax.plot(patch.uv[broken, 0], patch.uv[broken, 1], "kx", ms=4)
            ax.set_aspect("equal")
            ax.autoscale_view()
            ax.set_xlabel(f"{patch.labels[0]} (m)")
            ax.set_ylabel(f"{patch.labels[1]} (m)")
            ax.set_title(f"joint {name}: {what}{at}", fontsize=9)
        described[name]["pieces"].append(
            {"pairs": int(patch.members.size), "normal": patch.basis[-1].tolist(),
             "centre": patch.centre.tolist(), "axes": patch.labels})  # fmt: skip
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in STATE_COLOURS]
    handles.append(plt.Line2D([], [], color="k", marker="x", ls=""))
    fig.legend(handles, [*STATE_LABELS, "broken"], loc="lower center", ncol=5, fontsize=8)
    head = fig.suptitle((f"{title}\n" if title else "") + "joint maps, each joint in its "
                        "plane (a pair: its tributary cell)", fontsize=10)  # fmt: skip
    fig.tight_layout(rect=(0, 0.03, 1, _below_title(fig, head.get_text())))
    fig.savefig(path, dpi=110, metadata={"Description": json.dumps({"joints": described})})
    plt.close(fig)
    return path


def _face_normals(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit normals (n_faces, 3) of faces of 3 or 4 corners: the cross product of the
    diagonals (of two edges for a triangle); the sign is not fixed."""
    p = x[faces]
    if faces.shape[1] == 4:
        n = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    else:
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def plot_loads_3d(res: Results, model: Any, spec: dict[str, Any], path: Path,
                  title: str = "") -> Path:  # fmt: skip
    """The loads of a 3D model on its boundary faces (:data:`VIEW_3D`): each face shaded
    by the normal pressure the model's loads put on it at its centroid (kPa; pressures,
    hydrostatic pressure and the silt's normal pressure σ·n² summed, positive pushing
    in), the faces that carry the reservoir's added mass edged in cyan, the water levels
    as outlines over the wet faces, the pairs with a static uplift (purple), the
    supports (black) and gravity (an arrow at the centre of mass). The PNG's description
    gives the largest face pressure, the loaded faces, the supported nodes and the
    centre of mass."""
    plt = _plt()
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    from ..element import reference
    from ..mesh import match_rows

    x, faces = _faces_of(res)
    size = float(np.ptp(x, axis=0).max()) or 1.0
    keys = [np.sort(f, axis=1) for f in faces]
    p = [np.zeros(f.shape[0]) for f in faces]
    loaded = [np.zeros(f.shape[0], dtype=bool) for f in faces]
    wet = [np.zeros(f.shape[0], dtype=bool) for f in faces]

    def group_faces(group: str) -> list[tuple[int, np.ndarray]]:
        """The boundary faces of a facet group (an interface's first face): (index into
        ``faces``, rows)."""
        out = []
        for ftype, conn in model.mesh.facet_group(_load_group(model.mesh, group)).items():
            k = reference(reference(ftype).linear).n_nodes
            gk = np.sort(np.asarray(conn)[:, :k], axis=1)
            for i, table in enumerate(keys):
                if table.shape[1] == k and table.shape[0] and gk.shape[0]:
                    at, found = match_rows(table, gk)
                    out.append((i, at[found]))
        return out

    gravity = None
    for ld in model.loads:
        if ld.kind == "gravity":  # the first: pseudo-static forces come after it
            if gravity is None:
                gravity = np.asarray(ld.value, dtype=float)
        elif ld.kind in ("pressure", "silt") and ld.target is not None:
            for i, rows in group_faces(ld.target):
                c = x[faces[i][rows]].mean(axis=1)
                if ld.kind == "silt":
                    n = _face_normals(x, faces[i][rows])
                    v = (np.asarray(ld.value(c), dtype=float) * n**2).sum(axis=1)
                elif callable(ld.value):
                    v = np.asarray(ld.value(c), dtype=float)
                else:
                    v = np.full(rows.size, float(ld.value))
                p[i][rows] += v
                loaded[i][rows] = True
    loads_spec = spec.get("loads", {})
    for wg in loads_spec.get("westergaard", []):
        for g in wg["groups"]:
            for i, rows in group_faces(g):
                wet[i][rows] = True
    kpa = 1e-3 * np.concatenate(p) if p else np.zeros(0)
    on = np.concatenate(loaded) if loaded else np.zeros(0, dtype=bool)
    peak = float(np.abs(kpa[on]).max()) if on.any() else 0.0
    cmap = plt.get_cmap("Blues")
    norm = Normalize(0.0, peak if peak > 0 else 1.0)
    colours = np.tile([0.85, 0.85, 0.85, 0.25], (kpa.size, 1))
    colours[on] = cmap(norm(np.maximum(kpa[on], 0.0)))
    edges = np.tile([0.5, 0.5, 0.5, 0.6], (kpa.size, 1))
    edges[np.concatenate(wet)] = (0.0, 0.75, 0.75, 1.0)
    fig = plt.figure(figsize=(9, 7))
    ax = _axes3d(fig, 1, 1, 1)
    ax.add_collection3d(_art3d().Poly3DCollection(_polygons(x, faces), facecolors=colours,
                                         edgecolors=edges, linewidths=0.4))  # fmt: skip
    if on.any():
        fig.colorbar(ScalarMappable(norm, cmap), ax=ax, shrink=0.6, pad=0.1,
                     label="normal pressure on the face (kPa)")  # fmt: skip
    handles: list[Any] = []
    labels: list[str] = []
    for hy in loads_spec.get("hydrostatic", []):
        rows_all = [x[faces[i][rows]].reshape(-1, 3) for g in hy["groups"]
                    for i, rows in group_faces(g)]  # fmt: skip
        if not rows_all:
            continue
        pts = np.concatenate(rows_all)
        (x0, y0), (x1, y1) = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
        z = float(hy["water_level"])
        ring = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z], [x0, y0, z]])
        ax.add_collection3d(_art3d().Line3DCollection([ring], colors="tab:blue", linestyles="--",
                                             linewidths=1.0, zorder=_ON_TOP))  # fmt: skip
        handles.append(plt.Line2D([], [], color="tab:blue", ls="--"))
        labels.append(f"water {z:g} m")
    n_uplift = 0
    if "static/uplift" in res.f and "pairs/x" in res.f:
        up = np.asarray(res.f["static/uplift"]) > 0
        n_uplift = int(up.sum())
        if n_uplift:
            xp = np.asarray(res.f["pairs/x"])[up]
            ax.scatter(*xp.T, s=6, color="tab:purple", depthshade=False, zorder=_ON_TOP)
            handles.append(plt.Line2D([], [], color="tab:purple", marker=".", ls=""))
            peak_up = 1e-3 * float(np.asarray(res.f["static/uplift"]).max())
            labels.append(f"uplift (static), up to {peak_up:.4g} kPa")
    fixed = np.unique(np.concatenate([s.nodes for s in model.supports] or [np.zeros(0, int)]))
    if fixed.size:
        ax.scatter(*x[fixed].T, marker="^", s=8, color="k", depthshade=False, zorder=_ON_TOP)
        handles.append(plt.Line2D([], [], color="k", marker="^", ls=""))
        labels.append("supports")
    if any(w.any() for w in wet):
        handles.append(plt.Line2D([], [], color="c", lw=2))
        labels.append("added mass (Westergaard)")
    centre = None
    if gravity is not None and np.any(gravity):
        w = np.asarray(model.body_weights)
        centre = (w[:, None] * x).sum(axis=0) / w.sum() if w.sum() > 0 else x.mean(axis=0)
        g = 0.2 * size * gravity / np.linalg.norm(gravity)
        ax.quiver(*centre, *g, color="k", linewidth=1.5, arrow_length_ratio=0.25,
                  zorder=_ON_TOP + 1)  # fmt: skip
        ax.text(*centre, f" g = {np.linalg.norm(gravity):g} m/s²", fontsize=8,
                zorder=_ON_TOP + 1)  # fmt: skip
    _frame3d(ax, x)
    if handles:
        ax.legend(handles, labels, loc="upper left", fontsize=8)
    ax.set_title((f"{title}\n" if title else "") + "loads: the faces shaded by their normal "
                 "pressure (hydrostatic, silt, pressures)", fontsize=10)  # fmt: skip
    return _finish_described(fig, path, {
        "largest_face_pressure_kPa": peak, "loaded_faces": int(on.sum()),
        "supported_nodes": int(fixed.size), "uplift_pairs": n_uplift,
        "centre_of_mass_m": None if centre is None else centre.tolist(),
        "view": list(VIEW_3D)})  # fmt: skip
