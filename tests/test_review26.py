"""Defects found in the twenty-sixth session's review, each against a closed form."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import pfeie as pf


def _frictionless_block() -> tuple[pf.Model, int]:
    mesh = pf.rectangle(1.0, 1.5, nx=2, ny=3)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)
    c = pf.Elastic(E=30e9, nu=0.2, rho=2400)
    model = pf.Model(mesh, [pf.Block("base", c), pf.Block("block", c)],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=0.0))])  # fmt: skip
    model.fix("base")
    return model, int(np.argmax(mesh.points[:, 1]))


@pytest.mark.parametrize("theta", [0.6, 0.8, 1.0])
def test_moreau_jean_absolute_acceleration_of_a_free_block(theta: float) -> None:
    """A block on a frictionless joint, no gravity, shaken horizontally in the relative
    form: nothing pushes it along x, so its absolute x acceleration is zero (closed form).
    The Moreau–Jean step's relative acceleration is the step average under the load
    (1 − θ) f_n + θ f_{n+1}; adding a_g(t_{n+1}) alone left (1 − θ)Δa_g: 0.150 m/s² at
    θ = 0.6 here (3 m/s² at 2 Hz, Δt = 10 ms). Reached: 8e-10 m/s² (the record's linear
    interpolation at the step times); tolerance 1e-8 of the 3 m/s² amplitude."""
    model, top = _frictionless_block()
    g = pf.GroundMotion.from_function(lambda t: 3.0 * np.sin(4 * np.pi * t), duration=1.0,
                                      dt=0.01)  # fmt: skip
    r = pf.Dynamic(model, 0.01, scheme="moreau-jean", theta=theta).run(
        0.5, ground=[g], probes=[top]
    )
    assert np.abs(r.probe_a[:, 0, 0]).max() > 2.9  # the relative motion is the record's
    assert np.abs(r.probe_a_abs[:, 0, 0]).max() < 3e-8


def _sliding_block(phi_deg: float, E: float = 30e9) -> pf.Model:
    mesh = pf.rectangle(1.0, 1.5, nx=2, ny=3)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9, boundary_only=False)
    c = pf.Elastic(E=E, nu=0.2, rho=2400)
    model = pf.Model(mesh, [pf.Block("base", c), pf.Block("block", c)],
                     interfaces=[pf.Interface("joint", pf.Joint(phi=phi_deg))])  # fmt: skip
    model.fix("base")
    model.add_gravity()
    return model


def _pulse() -> pf.GroundMotion:
    return pf.GroundMotion.from_function(
        lambda t: 0.5 * 9.81 * np.sin(np.pi * min(t, 0.4) / 0.4), duration=0.4, dt=0.002
    )


def test_run_to_folder_writes_what_a_model_file_run_writes(tmp_path: Any) -> None:
    """A Python run written to a folder: the same bits as ``Dynamic.run``, the README's
    sliding block (V2b: 0.179804 m back, the rigid-block closed form of docs/verification
    to 0.01 %), results.h5 read back by :class:`pfeie.io.Results`, summaries, ParaView
    and figures; ``pfeie export`` and ``pfeie report`` read the folder."""
    from pfeie.cli import main

    model = _sliding_block(float(np.degrees(np.arctan(0.2))))
    analysis = pf.Dynamic(model, dt=0.002)
    static = pf.solve_static(model)
    top = int(np.argmax(model.mesh.points[:, 1]))
    ref = analysis.run(1.0, ground=[_pulse()], start=static, probes=[top])
    out = tmp_path / "out"
    res = pf.run_to_folder(analysis, 1.0, out, ground=[_pulse()], start=static,
                           probes={"top": top}, title="V2b", figures=False)  # fmt: skip
    for key in ("probe_u", "probe_a_abs", "X", "s", "rigid"):
        assert np.array_equal(getattr(res, key), getattr(ref, key)), key
    b = model.body_index("block")
    from pfeie.verification._rigid import RigidBlock

    t = np.linspace(0.0, 0.4, 4001)
    exact = RigidBlock(t, 0.5 * 9.81 * np.sin(np.pi * t / 0.4), 0.2 * 9.81, t_end=1.0)
    u_ref = -float(exact.displacement([1.0])[0])  # 0.179804 m
    assert res.rigid[-1, b, 0] - res.rigid[0, b, 0] == pytest.approx(-u_ref, rel=2e-4)
    with pf.io.Results(out / "results.h5") as f:
        assert f.completed and f.meta["model_file"] == pf.io.PYTHON_RUN
        assert f.probe_names == ["top"]
        assert np.array_equal(f.probe("top")["u"], ref.probe_u[:, 0])
        assert np.array_equal(f.time, ref.t)
        assert f.has_static and f.has_envelope
        energy = f.energy()  # the balance closes to round-off of the work put in
        assert abs(energy["balance"][-1]) < 1e-9 * abs(energy["external_work"]).max()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["model"]["title"] == "V2b"
    assert summary["joints"]["joint"]["residual_slip_max_m"] == pytest.approx(u_ref, rel=2e-4)
    assert (out / "blocks.xdmf").is_file() and (out / "interfaces.xdmf").is_file()
    assert main(["export", str(out / "results.h5"), "--csv", str(tmp_path / "csv")]) == 0
    assert (tmp_path / "csv" / "probes.csv").is_file()
    pytest.importorskip("matplotlib")
    assert main(["report", str(out / "results.h5")]) == 0
    html = (out / "report.html").read_text()
    assert "made through the Python API" in html


def test_run_to_folder_digest_and_bad_probe(tmp_path: Any) -> None:
    """The digest a Python run records is that of the model: the same model built again
    gives the same SHA-256, another friction angle another; a probe that is no node is
    refused by name."""

    def digest(model: pf.Model) -> str:
        return pf.io.Job.of_run(model, pf.DynamicSettings(dt=0.002), records=[_pulse()]).digest

    a, b, c = (digest(_sliding_block(phi)) for phi in (11.0, 11.0, 12.0))
    assert a == b != c
    # what the assembled arrays do not show: every law parameter, an amplitude, the
    # damping's deformation_only, uplift (a review found these hashed alike)
    c0 = pf.Elastic(E=30e9, nu=0.2, rho=2400)

    def variant(
        joint: pf.JointLaw, ramp: float = 0.1, only: bool = False, uplift: float | None = None
    ) -> str:
        mesh = pf.rectangle(1.0, 1.5, nx=2, ny=3)
        mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
        mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
        mesh.add_facet_group("joint", lambda x: abs(x[:, 1] - 0.5) < 1e-9,
                             boundary_only=False)  # fmt: skip
        m = pf.Model(mesh, [pf.Block("base", c0), pf.Block("block", c0)],
                     interfaces=[pf.Interface("joint", joint)],
                     damping=pf.Rayleigh(1.0, 0.0, deformation_only=only))  # fmt: skip
        m.fix("base")
        m.add_gravity(amplitude=lambda t: min(t / ramp, 1.0))
        if uplift is not None:
            m.add_uplift("joint", uplift)
        return digest(m)

    base = variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01))
    others = [variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.05)),
              variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01, gap=1e-3)),
              variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01), ramp=0.5),
              variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01), only=True),
              variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01), uplift=1.0)]  # fmt: skip
    assert base == variant(pf.SlipWeakening(phi=30.0, phi_r=20.0, dc=0.01))
    assert len({base, *others}) == 6
    model = _sliding_block(11.0)
    with pytest.raises(pf.ModelError, match="probes: 'crest': expected a node index"):
        pf.run_to_folder(pf.Dynamic(model, dt=0.002), 0.01, tmp_path, probes={"crest": 999})


def _free_block() -> tuple[pf.Model, int]:
    model = pf.Model(pf.rectangle(1.0, 1.0, 2, 2), [pf.Block("all", pf.Elastic(30e9, 0.2, 2400))])
    return model, model.nearest_node([0.5, 0.5])


@pytest.mark.parametrize("kw", [{"alpha": -0.2}, {"rho_inf": 0.5}, {"rho_inf": 0.8}],
                         ids=["HHT", "rho 0.5", "rho 0.8"])  # fmt: skip
def test_newmark_family_absolute_acceleration_of_a_free_body(kw: dict[str, float]) -> None:
    """An unsupported block shaken in the relative form reads an absolute acceleration of
    zero (closed form: nothing pushes it). HHT and generalised-α balance the load at
    (α_m, α_f): adding a_g(t_{n+1}) left α_f Δa_g (0.0752 m/s² for α = −0.2 here); the
    ground term now follows the scheme's recurrence (α_m ≠ 0 at ρ∞ = 0.8). Reached
    1.5e-9 m/s² (round-off of the 30 GPa block); tolerance 3e-8 of a 3 m/s² record."""
    model, p = _free_block()
    rec = pf.GroundMotion.from_function(lambda t: 3.0 * np.sin(4 * np.pi * t), duration=1.0,
                                        dt=0.001)  # fmt: skip
    r = pf.Dynamic(model, dt=0.01, scheme="newmark", **kw).run(0.5, ground=[rec], probes=[p],
                                                                every=3)  # fmt: skip
    assert np.abs(r.probe_a[:, 0, 0]).max() > 2.9
    assert np.abs(r.probe_a_abs[:, 0, 0]).max() < 3e-8


def test_nonsmooth_alpha_records_the_start_acceleration_of_t0() -> None:
    """Row 0 of the default scheme records the equation's acceleration at t₀, not the
    scheme's start value over its first step: a free block under a_g = 1 + 30 t m/s²
    reads a = −1 and a_abs = 0 at t = 0 (it read −1.3 and −0.3 at Δt = 10 ms)."""
    model, p = _free_block()
    rec = pf.GroundMotion.from_function(lambda t: 1.0 + 30.0 * t, duration=1.0, dt=0.001)
    r = pf.Dynamic(model, dt=0.01).run(0.05, ground=[rec], probes=[p])
    assert r.probe_a[0, 0, 0] == pytest.approx(-1.0, abs=1e-9)
    assert abs(r.probe_a_abs[0, 0, 0]) < 1e-9
    assert np.abs(r.probe_a_abs[:, 0, 0]).max() < 1e-9


def _resting_block(E: float = 30e9) -> tuple[pf.Model, pf.StaticResult]:
    model = _sliding_block(float(np.degrees(np.arctan(0.2))), E)
    return model, pf.solve_static(model)


def test_moreau_jean_supports_and_event_substeps_absolute_acceleration() -> None:
    """Moreau–Jean, θ < 1, the half-sine pulse of V2b: a support node's absolute
    acceleration is the ground's a_g(t) (6e-16; the step's mix at the supports was off
    by (1 − θ)Δa_g, 0.023 m/s²); with event sub-steps, the row of the event reads the
    sliding block's μg as without them (1.96214 against 1.96202; the mix of the coarse
    step read 1.94098): tolerance 2e-4 relative, within 10× of the 7e-5 reached."""
    g = 9.81
    model, static = _resting_block()
    corner = model.nearest_node([0.0, 0.0])
    top = model.nearest_node([0.5, 1.5])

    def f(t: float) -> float:
        return 0.5 * g * np.sin(np.pi * min(t, 0.4) / 0.4)

    pulse = pf.GroundMotion.from_function(f, duration=0.4, dt=0.0005)
    r = pf.Dynamic(model, dt=0.002, scheme="moreau-jean", theta=0.7).run(
        0.2, ground=[pulse], start=static, probes=[corner]
    )
    ag = np.array([f(t) for t in r.t])
    assert np.abs(r.probe_a_abs[:, 0, 0] - ag).max() < 1e-12
    model, static = _resting_block(E=3e12)  # stiff: the rigid block's μg
    for k in (1, 4):
        r = pf.Dynamic(model, dt=0.002, scheme="moreau-jean", theta=0.6, event_substeps=k).run(
            0.1, ground=[pulse], start=static, probes=[top]
        )
        sliding = np.flatnonzero((r.state == 2).all(axis=1))
        first = sliding[0]  # the row at which the block starts to slide (an event)
        assert r.probe_a_abs[first, 0, 0] == pytest.approx(0.2 * g, rel=2e-4)


def test_moreau_jean_absolute_form_block_stays_on_a_shaken_base() -> None:
    """A block on its base under vertical shaking of 0.2 g never separates (|a_g| < g):
    the joint's normal force stays within (1 ± 0.2) W and the absolute vertical
    acceleration within 0.2 g (closed form). In the absolute form the base's exact
    motion against the blocks' first-order position update opened the gap by
    O(h² a_g) a step; the pairs dropped out and the block fell and landed: 4 rows fully
    open and peak 13.4 m/s² at Δt = 2 ms. Tolerances 1e-5 W (the step average of the
    first-order scheme reaches 1.6e-6) and 1e-4 of 0.2 g (the block's vibration, 1.4e-5)."""
    g = 9.81
    model, static = _resting_block()
    top = model.nearest_node([0.5, 1.5])
    ry = pf.GroundMotion.from_function(lambda t: 0.2 * g * np.sin(6 * np.pi * t),
                                       duration=2.0, dt=0.0005, direction=(0, 1))  # fmt: skip
    # (with large rotations too: its pair operator turns with the blocks)
    for form, lr in (("relative", False), ("absolute", False), ("absolute", True)):
        r = pf.Dynamic(model, dt=0.002, scheme="moreau-jean", large_rotation=lr).run(
            0.6, ground=[ry], form=form, start=static, probes=[top]
        )
        assert not (r.state == 3).any(), form
        n_w = r.joint_force[:, 0, 1] / (2400 * g)  # the block: 1 m² × 2400 kg/m³
        assert n_w.min() > 0.8 - 1e-5 and n_w.max() < 1.2 + 1e-5, form
        # (the 30 GPa block's own vibration adds 1.4e-5 of 0.2 g)
        assert np.abs(r.probe_a_abs[:, 0, 1]).max() < 0.2 * g * (1 + 1e-4), form


def test_yield_coefficient_leaves_out_the_models_own_horizontal_coefficient() -> None:
    """A rigid block on a level joint, μ = tan 30°: k_y = μ (closed form), also when the
    model carries a pseudo-static load of its own (k_h = 0.1 along +x: the search added to
    it and read μ − 0.1 = 0.477); a vertical coefficient k_v (upward) acts with the search:
    k_y = μ (1 − k_v). Tolerance 1e-5 (the search's bracket, tol 1e-6 relative)."""
    from pfeie.verification._models import block_on_base

    mu = np.tan(np.radians(30.0))
    g = 9.81
    for kh, kv in ((0.0, 0.0), (0.1, 0.0), (-0.2, 0.0), (0.1, 0.2)):
        m = block_on_base(joint=pf.Joint(phi=30.0), incline_deg=0.0)
        if kh or kv:
            m.add_inertia([kh * g, kv * g])  # k_v g upward: −M (k_v g) down is unloading
        y = pf.yield_coefficient(m)
        assert y.k_y == pytest.approx(mu * (1.0 - kv), rel=1e-5), (kh, kv)


def test_3d_joint_map_cells_cover_the_joint_and_no_more() -> None:
    """The tributary cells of a 3D joint's pairs (Voronoi cells clipped to the points'
    convex hull) tile the joint: their areas sum to the hull's (a 4 m × 3 m joint of
    random points, its corners among them: 12 m² to 1e-12), every cell inside it, and
    pairs at one point share a cell; points on a line fall back to squares."""
    from pfeie.plot._plots import _pair_cells, _polygon_area

    rng = np.random.default_rng(7)
    uv = np.vstack([[[0, 0], [4, 0], [4, 3], [0, 3]], rng.uniform([0, 0], [4, 3], (60, 2))])
    uv = np.vstack([uv, uv[10:12]])  # two pairs at the points of two others
    cells = _pair_cells(uv, np.ones(len(uv)))
    unique = cells[:-2]
    assert sum(_polygon_area(c) for c in unique) == pytest.approx(12.0, rel=1e-12)
    allv = np.vstack(unique)
    assert allv.min(axis=0) == pytest.approx([0, 0], abs=1e-12)
    assert allv.max(axis=0) == pytest.approx([4, 3], abs=1e-12)
    assert np.array_equal(cells[-2], cells[10]) and np.array_equal(cells[-1], cells[11])
    line = np.c_[np.linspace(0, 1, 5), np.zeros(5)]
    sq = _pair_cells(line, np.full(5, 0.04))
    assert len(sq) == 5 and _polygon_area(sq[0]) == pytest.approx(0.04)


def test_resume_of_a_model_without_interfaces_is_the_uninterrupted_run(tmp_path: Any) -> None:
    """The demo dam without its joints (Newmark, ρ∞ = 0.8): a run of 0.3 s extended by
    `--resume` to 0.6 s gives the datasets of a run of 0.6 s, shapes and values; the
    pair histories of a model without pairs keep their 0 rows (the resume cut them to
    the checkpoint's row count, 31, while history/time had 61)."""
    import re

    import h5py

    from pfeie.cli import main

    root = Path(__file__).resolve().parents[1] / "examples" / "koyna"
    text = (root / "koyna.toml").read_text()
    text = re.sub(r"\[interfaces\.[a-z_]+\][^\[]*", "", text)
    text = text.replace("rho_inf = 0.5", 'scheme = "newmark"\nrho_inf = 0.8')
    text = text.replace('file = "../data/', f'file = "{root.parent}/data/')
    text = text.replace('file = "koyna.msh"', f'file = "{root}/koyna.msh"')
    for name in ("a", "b"):
        (tmp_path / f"{name}.toml").write_text(
            text.replace('folder = "results"', f'folder = "out_{name}"')
        )
    argv = ["run", "--quiet", "--set", "output.paraview=false"]
    assert main([*argv, str(tmp_path / "a.toml"), "--duration", "0.6"]) == 0
    assert main([*argv, str(tmp_path / "b.toml"), "--duration", "0.3"]) == 0
    assert main([*argv, str(tmp_path / "b.toml"), "--duration", "0.6", "--resume"]) == 0
    with h5py.File(tmp_path / "out_a" / "results.h5") as fa, \
         h5py.File(tmp_path / "out_b" / "results.h5") as fb:  # fmt: skip
        assert fa["history/pairs/X"].shape == fb["history/pairs/X"].shape == (0, 0, 2)
        for key in (
            "history/time",
            "history/probes/u",
            "history/probes/a_abs",
            "history/energy/kinetic",
        ):
            assert np.array_equal(fa[key][...], fb[key][...]), key


def test_run_to_folder_keeps_the_folder_on_bad_input_and_stops_on_ctrl_c(
    tmp_path: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A second run into a folder that the run refuses (a static result of another
    model) leaves the first run's files as they were; probes given as a list are named
    node<i>; Ctrl-C stops the run at the end of a step, the files hold what was computed
    (completed false, the reason SIGINT) and KeyboardInterrupt follows."""
    import signal

    import pfeie._job as job

    model = _sliding_block(11.0)
    analysis = pf.Dynamic(model, dt=0.002)
    static = pf.solve_static(model)
    top = int(np.argmax(model.mesh.points[:, 1]))
    out = tmp_path / "out"
    pf.run_to_folder(analysis, 0.05, out, ground=[_pulse()], start=static, probes=[top],
                     paraview=False, figures=False)  # fmt: skip
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    small = pf.Model(pf.rectangle(1.0, 1.0, 2, 2), [pf.Block("all", pf.Elastic(30e9, 0.2, 2400))])
    small.fix("ymin")
    small.add_gravity()
    other = pf.solve_static(small)
    with pytest.raises(pf.ModelError, match="static result is of another model"):
        pf.run_to_folder(analysis, 0.05, out, ground=[_pulse()], start=other,
                         paraview=False, figures=False)  # fmt: skip
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before
    with pf.io.Results(out / "results.h5") as f:
        assert f.probe_names == [f"node{top}"] and f.completed

    append = job.ResultsWriter.append

    def append_and_interrupt(self: Any, row: dict[str, Any]) -> None:
        append(self, row)
        if self.rows == 10:
            signal.raise_signal(signal.SIGINT)

    monkeypatch.setattr(job.ResultsWriter, "append", append_and_interrupt)
    with pytest.raises(KeyboardInterrupt, match="SIGINT"):
        pf.run_to_folder(analysis, 0.5, out, ground=[_pulse()], start=static,
                         paraview=False, figures=False)  # fmt: skip
    with pf.io.Results(out / "results.h5") as f:
        assert not f.completed and "SIGINT" in f.meta["stop_reason"]
        assert f.n_times == f.f["history/probes/u"].shape[0] == f.f["history/rigid"].shape[0]
        assert 10 <= f.n_times < 250
    assert json.loads((out / "summary.json").read_text())["stopped"].startswith("stopped")


def test_run_to_folder_rerun_ground_forms_staged_post_earthquake_and_cli_folder(
    tmp_path: Any,
) -> None:
    """A new user's findings: a second run into a folder removes the first's ParaView
    series and figures; ground=None is no record and one record alone is taken; a run
    started from another run's final state judges the post-earthquake geometry from the
    undeformed one (the block has slid 0.18 m of its 1 m: skipped, as in one run);
    `pfeie report DIR` reads DIR/results.h5; read_record's scale is in its summary."""
    from pfeie.cli import main

    model = _sliding_block(float(np.degrees(np.arctan(0.2))))
    analysis = pf.Dynamic(model, dt=0.002)
    static = pf.solve_static(model)
    out = tmp_path / "out"
    pf.run_to_folder(analysis, 0.05, out, ground=_pulse(), start=static, probes={"a": 3},
                     figures=True)  # fmt: skip
    assert (out / "blocks.xdmf").is_file() and (out / "figures" / "probe_a.png").is_file()
    pf.run_to_folder(analysis, 0.05, out, ground=None, start=static, paraview=False,
                     figures=True)  # fmt: skip
    assert not (out / "blocks.xdmf").exists() and not (out / "figures" / "probe_a.png").exists()
    with pytest.raises(pf.ModelError, match=r"ground: expected a list of pfeie\.GroundMotion"):
        pf.run_to_folder(analysis, 0.05, out, ground=["x.csv"])  # type: ignore[list-item]
    r1 = pf.run_to_folder(analysis, 0.5, tmp_path / "s1", ground=[_pulse()], start=static,
                          paraview=False, figures=False)  # fmt: skip
    pf.run_to_folder(analysis, 0.5, tmp_path / "s2", ground=[_pulse()], start=r1.final,
                     paraview=False, figures=False)  # fmt: skip
    for stage in ("s1", "s2"):
        post = json.loads((tmp_path / stage / "summary.json").read_text())["post_earthquake"]
        assert "skipped" in post, (stage, post)
    assert main(["report", str(out)]) == 0 and (out / "report.html").is_file()
    csv = tmp_path / "r.csv"
    csv.write_text("".join(f"{0.01 * k},{0.1 * np.sin(k)}\n" for k in range(50)))
    rec = pf.io.read_record(csv, units="g", scale=1.5)
    assert "scaled ×1.5" in rec.summary()
