"""Session-37 checks: the incompressibility warning per material, the mesh's check
fingerprint, the post-earthquake line of the summary."""

from __future__ import annotations

import dataclasses
import json
import logging
import warnings
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.errors import InputError, ModelError
from pfeie.io import load_job
from pfeie.mesh import Mesh
from pfeie.model import locking_cells
from pfeie.verification._models import block_on_base


def _q4_beside_q8() -> Mesh:
    """Two 1 m squares side by side, apart (no shared node): 'lin' of 2 × 2 Q4 at
    x ∈ [0, 1], 'quad' of 2 × 2 Q8 at x ∈ [2, 3]."""
    a = pf.rectangle(1.0, 1.0, 2, 2, cell="quad")
    b = pf.rectangle(1.0, 1.0, 2, 2, cell="quad8")
    pts = np.vstack([a.points, b.points + np.array([2.0, 0.0])])
    return Mesh(pts, {"quad": a.cells["quad"], "quad8": b.cells["quad8"] + a.n_points},
                cell_groups={"lin": {"quad": np.arange(4)}, "quad": {"quad8": np.arange(4)}})


@pytest.mark.parametrize(("soft", "warned"), [("lin", True), ("quad", False)])
def test_the_incompressibility_warning_takes_each_materials_cells(soft: str, warned: bool,
                                                                  ) -> None:  # fmt: skip
    """ν = 0.495 is warned for a material whose blocks have first-order cells, not for one
    whose blocks are all quadratic, whatever the rest of the mesh holds (the warning took
    the whole mesh: a Q8 dam beside a Q4 foundation was warned)."""
    mesh = _q4_beside_q8()
    assert locking_cells(mesh, "strain", ["lin"]) and not locking_cells(mesh, "strain", ["quad"])
    assert locking_cells(mesh) and not locking_cells(mesh, "stress", ["lin"])
    assert not locking_cells(mesh, "strain", ["no such group"])
    mats = {g: pf.Elastic(30e9, 0.495 if g == soft else 0.2, 2400.0) for g in ("lin", "quad")}
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        pf.Model(mesh, [pf.Block(g, m) for g, m in mats.items()])
    texts = [str(w.message) for w in said if "nearly incompressible" in str(w.message)]
    assert len(texts) == warned
    assert all(f"block {soft!r}: nu = 0.495" in t for t in texts)


def test_the_mesh_fingerprint_is_a_digest_of_the_arrays() -> None:
    """The check's fingerprint is a digest of the points and of each cell type's
    connectivity: a copy of the arrays has the same digest (and is not checked), a point
    moved by 1e-12 m another."""
    mesh = pf.rectangle(2.0, 1.0, 2, 1)
    mesh.check()
    assert mesh.checked
    key = mesh._fingerprint()
    other = Mesh(mesh.points.copy(), {"quad": mesh.cells["quad"].copy()})
    assert other._fingerprint() == key and not other.checked
    mesh.points[0, 0] += 1e-12
    assert not mesh.checked


def _write_msh22(path: Path, mesh: Mesh) -> None:
    """``mesh`` (Q4 and Q8 cells, each cell group a physical surface) as a gmsh 2.2 file."""
    gtype = {"quad": 3, "quad8": 16}
    groups = list(mesh.cell_groups)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(groups))]
    lines += [f'2 {i + 1} "{g}"' for i, g in enumerate(groups)]
    lines += ["$EndPhysicalNames", "$Nodes", str(mesh.n_points)]
    lines += [f"{i + 1} {x:.17g} {y:.17g} 0" for i, (x, y) in enumerate(mesh.points)]
    elems = []
    for i, g in enumerate(groups):
        for t, idx in mesh.cell_groups[g].items():
            for c in mesh.cells[t][idx]:
                elems.append(f"{gtype[t]} 2 {i + 1} {i + 1} " + " ".join(str(n + 1) for n in c))
    lines += ["$EndNodes", "$Elements", str(len(elems))]
    lines += [f"{k + 1} {e}" for k, e in enumerate(elems)]
    lines += ["$EndElements", ""]
    path.write_text("\n".join(lines))


def test_the_model_file_warns_the_material_whose_cells_lock(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """The model file's check takes the blocks of each material: ν = 0.495 on the Q8
    square is not warned, on the Q4 square it is, naming the key."""
    _write_msh22(tmp_path / "m.msh", _q4_beside_q8())
    for soft, warned in (("quad", False), ("lin", True)):
        (tmp_path / "model.toml").write_text(f"""
[mesh]
file = "m.msh"
[materials]
soft = {{ E = 30e9, nu = 0.495, rho = 2400 }}
hard = {{ E = 30e9, nu = 0.2, rho = 2400 }}
[blocks]
lin = "{"soft" if soft == "lin" else "hard"}"
quad = "{"soft" if soft == "quad" else "hard"}"
[[supports]]
group = "lin"
[[supports]]
group = "quad"
[analysis]
dynamic = false
""")
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="pfeie"):
            load_job(tmp_path / "model.toml")
        said = [r.getMessage() for r in caplog.records if "incompressible" in r.getMessage()]
        assert len(said) == warned
        assert all("materials.soft.nu = 0.495" in t for t in said)


def test_the_reports_static_table_gives_the_resultants(tmp_path: Path) -> None:
    """The report's static table reads the joint as the summary does: its normal force,
    the block's weight 2 m × 1 m × 2400 kg/m³ × 9.81 m/s² = 47.088 kN a metre, a shear of
    zero (4e-13 N of round-off was printed as "shear 4.263e-16 kN"), all of it in contact
    with its mean stress, the resultant under the centre of gravity (x = 1 m); the
    post-earthquake line of summary.txt gives the same reading of its own state."""
    from pfeie.io import Results
    from pfeie.plot import static_joint_table
    from pfeie.plot._report import model_of_run
    from test_post_earthquake import _run

    s = _run(tmp_path, 1.0)
    with Results(tmp_path / "out" / "results.h5") as res:
        job, _ = model_of_run(res)
        row = static_joint_table(res, job)[0]
    W = 2.0 * 1.0 * 2400.0 * 9.81
    assert row["normal force (kN a metre)"] == pytest.approx(1e-3 * W, rel=1e-12)
    assert row["shear force (kN a metre)"] == 0.0 == s["static_joints"]["joint"]["shear_force_N"]
    assert row["in contact (%)"] == 100.0
    assert row["mean stress in contact (MPa)"] == pytest.approx(1e-6 * W / 2.0, rel=1e-12)
    assert row["normal resultant at (m)"] == "(1, 1)"
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "static joint     FS ∞, normal 47.09 kN, shear 0 kN" in text
    post = next(x for x in text.splitlines() if x.strip().startswith("post-EQ joint"))
    assert post.endswith("in contact 100 % (mean 0.0235 MPa there), normal resultant at (1, 1) m; "
                         "forces a metre")  # fmt: skip


def test_the_forces_say_what_thickness_they_are_for() -> None:
    """A 2D model's forces are for its thickness: " a metre" by default, " for 2.5 m"
    otherwise, nothing in 3D (one function for the summary's text and the report's
    columns)."""
    from pfeie.plot._report import per_thickness

    for model, said in (({"dimension": 2, "thickness": 1.0}, " a metre"),
                        ({"dimension": 2, "thickness": 2.5}, " for 2.5 m"),
                        ({"dimension": 3, "thickness": 1.0}, "")):  # fmt: skip
        assert per_thickness({"model": model}) == said


def test_a_tet10_joint_is_all_in_contact_though_its_corner_pairs_part() -> None:
    """A 2 m cube of Tet10 cut at mid-height, under its weight: the corner pairs of the
    quadratic facets carry no force of a uniform pressure and part by a fraction of a
    micron (8 of 25 pairs open by 9e-8 m), yet the joint is all in contact by the crack
    threshold (0.01 mm): the share 1, the mean stress in contact the weight of the upper
    half over 4 m², 23,544 Pa, the normal resultant under its centre of gravity."""
    from pfeie._job import _static_joints
    from pfeie.interface import OPEN

    mesh = pf.box(2.0, 2.0, 2.0, 2, 2, 4, cell="tetra10")
    mesh.add_cell_group("base", lambda x: x[:, 2] < 1.0)
    mesh.add_cell_group("top", lambda x: x[:, 2] > 1.0)
    mesh.add_facet_group("j", lambda x: np.abs(x[:, 2] - 1.0) < 1e-9, boundary_only=False)
    rock = pf.Elastic(30e9, 0.2, 2400.0)
    model = pf.Model(mesh, [pf.Block("base", rock), pf.Block("top", rock)],
                     interfaces=[pf.Interface("j", pf.Joint(phi=40.0))])  # fmt: skip
    model.fix("zmin")
    model.add_gravity()
    st = pf.solve_static(model)
    assert st.pairs is not None
    parted = (st.pairs.state == OPEN) & (st.pairs.w[:, -1] > 0.0)
    assert parted.sum() >= 4 and float(st.pairs.w[parted, -1].max()) < 1e-6
    j = _static_joints(model, st)["j"]
    W = 2.0 * 2.0 * 1.0 * 2400.0 * 9.81
    assert j["contact_share"] == 1.0 and j["open_share"] == 0.0
    assert j["normal_force_N"] == pytest.approx(W, rel=1e-9)
    assert j["mean_contact_stress_Pa"] == pytest.approx(W / 4.0, rel=1e-9)
    assert j["normal_resultant_at_m"] == pytest.approx([1.0, 1.0, 1.0], abs=1e-9)


# -- an aftershock after a mainshock: a run from a state reads its records at its time ----


def _sliding_block() -> tuple[pf.Model, pf.GroundMotion, pf.GroundMotion]:
    """A 1 m block on a base (φ = 30°, no cohesion), a mainshock of 0.5 s (1.5 g sin² of
    4 Hz, one way) and an aftershock of 0.3 s (1.2 g sin² of 5 Hz, times from 0), both
    starting and ending at rest."""
    model = block_on_base(joint=pf.Joint(phi=30.0))
    main = pf.GroundMotion.from_function(lambda t: 1.5 * 9.81 * np.sin(2 * np.pi * 4 * t) ** 2,
                                         0.5, 0.005, name="main")  # fmt: skip
    after = pf.GroundMotion.from_function(lambda t: 1.2 * 9.81 * np.sin(2 * np.pi * 5 * t) ** 2,
                                          0.3, 0.005, name="after")  # fmt: skip
    return model, main, after


def test_an_aftershock_that_ended_before_the_start_state_is_refused(
    caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A run from the mainshock's final state (t = 0.5 s) goes on at the state's time and
    reads its records there: an aftershock whose times run from 0 to 0.3 s was applied as
    ground at rest, silently (a dam engineer's sequence: external work −12 kJ instead of
    +62 kJ). Refused, naming the record, both times and the fix; shifted to start at the
    state's time, it is applied, and the two runs give the run of the concatenated record
    (the mainshock, then the aftershock from 0.5 s) bit for bit."""
    model, main, after = _sliding_block()
    an = pf.Dynamic(model, 0.005)
    r1 = an.run(0.5, ground=[main], start=pf.solve_static(model))
    assert r1.final is not None and r1.final.kin.t == pytest.approx(0.5)
    with pytest.raises(ModelError, match=r"ground motion 'after': the record ends at 0.3 s, "
                       r"and this run starts at t = 0.5 s.*record.shifted\(0.5\)"):  # fmt: skip
        an.run(0.3, ground=[after], start=r1.final)
    # the mainshock's own record, ended, continues the run (the ground at rest); a state
    # whose records are unknown (built or read elsewhere) is warned, not refused
    an.run(0.01, ground=[main], start=r1.final)
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        an.run(0.01, ground=[after], start=dataclasses.replace(r1.final, records=None))
    assert "ground motion 'after': the record ends at 0.3 s" in caplog.text
    r2 = an.run(0.3, ground=[after.shifted(0.5)], start=r1.final)
    both = pf.GroundMotion(np.concatenate([main.time, after.time[1:] + 0.5]),
                           np.concatenate([main.acceleration, after.acceleration[1:]]),
                           main.direction, name="both")  # fmt: skip
    r12 = an.run(0.8, ground=[both], start=pf.solve_static(model))
    assert r2.final is not None and r12.final is not None
    slip = float(np.abs(r12.final.pairs.s[:, 0]).max())
    assert slip > 0.5  # (it slid 0.26 m in the mainshock, 0.55 m in all)
    # the same steps from the same state under the same samples: the same bits
    assert np.array_equal(r2.final.pairs.s, r12.final.pairs.s)
    assert np.array_equal(r2.final.kin.u, r12.final.kin.u)


def test_a_record_whose_beginning_a_start_state_skips_is_warned(
    caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """From a state at 0.2 s that ended a run under other records, a record from t = 0
    loses its first 0.2 s: warned, with the fix; the same record continued from a state of
    its own run is not (that is a run continued)."""
    model, main, after = _sliding_block()
    an = pf.Dynamic(model, 0.005)
    r1 = an.run(0.2, ground=[main], start=pf.solve_static(model))
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        an.run(0.05, ground=[after], start=r1.final)
    assert "ground motion 'after': this run starts at t = 0.2 s" in caplog.text
    assert "skips its first 0.2 s" in caplog.text and "record.shifted(0.2)" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        an.run(0.05, ground=[main], start=r1.final)
    assert "skips its first" not in caplog.text


def test_a_start_state_of_another_model_with_uplift_is_refused() -> None:
    """A state of another model as ``start`` raised a bare ValueError ("operands could not
    be broadcast") from the uplift of its static state, read before the state was checked.
    Now the error of a state of another model, naming both sizes."""
    from test_review36 import _wet_block

    model = _wet_block()
    other = block_on_base(joint=pf.Joint(phi=30.0))
    gm = pf.GroundMotion.from_function(lambda t: 0.0 * t, 0.02, 0.01)
    r = pf.Dynamic(other, 0.01).run(0.02, ground=[gm], start=pf.solve_static(other))
    assert r.final is not None
    with pytest.raises(ModelError, match=r"start: the state is of another model"):
        pf.Dynamic(model, 0.01).run(0.02, ground=[gm], start=r.final)


# -- the outputs' conventions (a consistency auditor's findings) ------------------------------


def test_paraview_gives_3d_tangential_components_as_scalars(tmp_path: Path) -> None:
    """In 3D the tangential slip and shear (t₁, t₂ of each pair's frame) were written as
    one 2-component array, which ParaView pads to (t₁, t₂, 0) and draws as a vector in
    global axes (a slip along x read as one along −y). Now ``slip`` and ``shear_stress``
    are magnitudes, the components the scalars ``*_t1``, ``*_t2``; ``slip_vector`` (global)
    has the same length. A cube shaken along x at 1 g (μ = tan 30°) slides along x."""
    import meshio

    from pfeie.verification._models import block_on_base_3d

    model = block_on_base_3d(joint=pf.Joint(phi=30.0))
    gm = pf.GroundMotion.from_function(lambda t: 9.81 * np.sin(2 * np.pi * 4 * t) ** 2, 0.1,
                                       0.005, direction=(1.0, 0.0, 0.0))  # fmt: skip
    out = tmp_path / "out"
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.1, out, ground=[gm],
                     start=pf.solve_static(model), figures=False, paraview=True)  # fmt: skip
    with meshio.xdmf.TimeSeriesReader(str(out / "interfaces.xdmf")) as rd:
        rd.read_points_cells()
        _t, pd, _cd = rd.read_data(rd.num_steps - 1)
    for name in ("slip", "slip_t1", "slip_t2", "shear_stress", "shear_stress_t1",
                 "shear_stress_t2"):  # fmt: skip
        assert pd[name].ndim == 1, name
    ok = np.isfinite(pd["slip"])
    s1, s2, vec = pd["slip_t1"][ok], pd["slip_t2"][ok], pd["slip_vector"][ok]
    assert float(pd["slip"][ok].max()) > 1e-3  # (it slid)
    np.testing.assert_allclose(pd["slip"][ok], np.hypot(s1, s2), rtol=1e-6)  # (float32)
    np.testing.assert_allclose(np.linalg.norm(vec, axis=1), pd["slip"][ok], rtol=1e-6)
    # the global vector along −x: the base accelerates towards +x (one way, sin²) and the
    # block lags behind it (5.57 mm); across, the deformable cube's 1.9e-7 m (3.4e-5)
    assert (vec[:, 0] < -5e-3).all()
    assert np.abs(vec[:, 1:]).max() <= 1e-4 * np.abs(vec[:, 0]).max()


def test_pairs_final_csv_gives_the_relative_displacement_since_the_start(tmp_path: Path) -> None:
    """pairs_final.csv's ``final_w_*_m`` were the total relative displacement (the joint
    springs' closure under the static loads included: −2.2e-5 m of ``final_w_n_m`` on a
    block at rest), where ``residual_slip_m`` of the same row and joints.csv's
    ``w_*_mean`` are since the start of the run. Now since the start too: a block on
    springs (kn = ks = 1e9 Pa/m) shaken below its sliding capacity ends near its static
    state (|w_n| below 1e-3 of its static closure ρgh/kn = 2.35e-5 m), and the columns are
    the results file's w at the end less w at the start."""
    import csv

    from pfeie.cli import main
    from pfeie.io import Results

    model = block_on_base(joint=pf.Joint(phi=40.0, kn=1e9, ks=1e9))
    gm = pf.GroundMotion.from_function(lambda t: 0.1 * 9.81 * np.sin(2 * np.pi * 5 * t),
                                       0.2, 0.005)  # fmt: skip
    out = tmp_path / "out"
    st = pf.solve_static(model)
    assert st.pairs is not None
    closure = 2400.0 * 9.81 / 1e9  # ρ g h / kn: the springs' static closure (m)
    assert float(st.pairs.w[:, -1].mean()) == pytest.approx(-closure, rel=0.1)
    pf.run_to_folder(pf.Dynamic(model, 0.005), 0.2, out, ground=[gm], start=st,
                     figures=False, paraview=False)  # fmt: skip
    assert main(["export", str(out / "results.h5"), "--csv", str(tmp_path / "csv")]) == 0
    with (tmp_path / "csv" / "pairs_final.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    # (and no crack opened: no time for it, null, where 0.0 read as "at t = 0")
    j = json.loads((out / "summary.json").read_text())["joints"]["joint"]
    assert j["max_open_length_m"] == 0.0 and j["max_open_time_s"] is None
    w = np.array([[float(r[f"final_w_{a}_m"]) for a in ("t1", "n")] for r in rows])
    assert np.abs(w[:, 1]).max() < 1e-3 * closure  # (the motion since the start only)
    with Results(out / "results.h5") as res:
        pr = res.pairs("joint")
    np.testing.assert_allclose(w, pr["w"][-1] - pr["w"][0], rtol=1e-8, atol=1e-18)


def test_the_static_joint_gives_its_uplift_resultant() -> None:
    """summary.json's static joint gives the uplift's resultant, which the engineer's hand
    check needs beside the effective normal force (it was only in the per-pair pressures
    of the results file): the block of tests/test_review36.py, a linear uplift from 8 m of
    head at the heel to none at the toe of its 10 m base, U = ½ γ_w 8 m × 10 m =
    392.4 kN a metre, and N′ = W − U; the text names it."""
    from pfeie._job import _compression_text, _static_joints
    from test_review36 import _wet_block

    model = _wet_block()
    st = pf.solve_static(model)
    j = _static_joints(model, st)["base"]
    U, W = 0.5 * 9810.0 * 8.0 * 10.0, 2400.0 * 9.81 * 100.0
    assert j["uplift_force_N"] == pytest.approx(U, rel=1e-9)
    assert j["normal_force_N"] == pytest.approx(W - U, rel=1e-9)
    assert ", uplift 392.4 kN, no crack (normal: effective" in _compression_text(j, " a metre")


def test_a_run_from_a_cracked_state_says_what_was_broken_when_it_started() -> None:
    """The aftershock's summary read "broken 52 %" with ``initially_broken_share`` 0,
    though all of it broke in the mainshock: ``broken_at_start_share`` holds the share at
    the run's first row, and the text says it."""
    from pfeie._job import _broken

    j = {"broken_share": 0.52, "initially_broken_share": 0.0, "broken_at_start_share": 0.52}
    assert _broken(j) == "broken 52 % (52 % when this run started, from its start state)"
    j |= {"broken_at_start_share": 0.0}
    assert _broken(j) == "broken 52 %"
    assert _broken({"broken_share": 1.0, "initially_broken_share": 1.0,
                    "broken_at_start_share": 1.0}) == (
        "broken 100 % (starts broken: a pre-existing joint)")  # fmt: skip


def test_the_aftershocks_summary_counts_the_mainshocks_cracks(tmp_path: Path) -> None:
    """End to end: a bonded 1 m block (c = 5 kPa, σ_t = 5 kPa, φ = 30°) broken through by
    the mainshock (1.5 g), then the aftershock from its final state through
    ``run_to_folder``: summary.json has it broken at the end and when it started, none of
    it broken by its law from the start."""
    model = block_on_base(joint=pf.Joint(c=5e3, tensile=5e3, phi=30.0, initial="intact"))
    _, main, after = _sliding_block()
    an = pf.Dynamic(model, 0.005)
    r1 = an.run(0.5, ground=[main], start=pf.solve_static(model))
    assert r1.final is not None and r1.final.pairs.broken.all()
    pf.run_to_folder(an, 0.3, tmp_path / "out", ground=[after.shifted(0.5)], start=r1.final,
                     figures=False, paraview=False)  # fmt: skip
    j = json.loads((tmp_path / "out" / "summary.json").read_text())["joints"]["joint"]
    assert (j["broken_share"], j["broken_at_start_share"], j["initially_broken_share"]) == (
        1.0, 1.0, 0.0)  # fmt: skip
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "broken 100 % (100 % when this run started, from its start state)" in text


def test_a_run_does_not_write_on_its_start_state_and_the_absolute_form_is_refused() -> None:
    """A run of no step (or one stopped at its first) returned the caller's start state
    itself and wrote its records on it, so that the mainshock's state then read as the
    aftershock's (a reviewer's finding): the start is left as it was. A sequence of records
    in the absolute form is refused: the supports would jump from where the mainshock's
    ground left them (a slip of 0.99 m against 0.55 m for the concatenated record)."""
    model, main, after = _sliding_block()
    an = pf.Dynamic(model, 0.005)
    r1 = an.run(0.5, ground=[main], start=pf.solve_static(model))
    assert r1.final is not None
    key = r1.final.records
    r0 = an.run(n_steps=0, ground=[after.shifted(0.5)], start=r1.final)
    assert r1.final.records == key and r0.final is not r1.final
    an.run(0.01, ground=[main], start=r1.final)  # (still the mainshock's: continued)
    ra = an.run(0.5, ground=[main], form="absolute", start=pf.solve_static(model))
    with pytest.raises(ModelError, match=r"start: this run's records move the supports"):
        an.run(0.3, ground=[after.shifted(0.5)], form="absolute", start=ra.final)


def test_a_run_from_the_static_state_keeps_its_static_cracks_in_the_static_line(
    tmp_path: Path,
) -> None:  # fmt: skip
    """A joint that the static loads cracked (a bonded base with a low tensile strength
    under a 10 m pool: statics broke 7 of its 9 pairs) read "broken 79 % (79 % when this
    run started, from its start state)" in a plain run from the static state (a reviewer's
    finding): only a run from another run's state (its first row after t = 0) says so."""
    mesh = pf.rectangle(4.0, 12.0, nx=8, ny=6)
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 2.0)
    mesh.add_cell_group("dam", lambda x: x[:, 1] > 2.0)
    mesh.add_facet_group("base", lambda x: abs(x[:, 1] - 2.0) < 1e-9, boundary_only=False)
    mesh.add_facet_group("up", lambda x: (abs(x[:, 0]) < 1e-9) & (x[:, 1] > 2.0 - 1e-9))
    concrete = pf.Elastic(25e9, 0.2, 2400.0)
    model = pf.Model(mesh, [pf.Block("rock", concrete), pf.Block("dam", concrete)],
                     interfaces=[pf.Interface("base", pf.Joint(c=1e6, tensile=1e4, phi=45.0,
                                                               initial="intact"))])  # fmt: skip
    model.fix("ymin")
    model.add_gravity()
    model.add_pressure("up", lambda x: 9810.0 * np.maximum(12.0 - x[..., 1], 0.0), level=12.0)
    st = pf.solve_static(model)
    assert st.pairs is not None and 0 < st.pairs.broken.sum() < st.pairs.broken.size
    gm = pf.GroundMotion.from_function(lambda t: 0.0 * t, 0.02, 0.01)
    pf.run_to_folder(pf.Dynamic(model, 0.01), 0.02, tmp_path / "out", ground=[gm], start=st,
                     figures=False, paraview=False)  # fmt: skip
    j = json.loads((tmp_path / "out" / "summary.json").read_text())["joints"]["base"]
    assert j["broken_share"] > 0.0 and "broken_at_start_share" not in j
    assert "when this run started" not in (tmp_path / "out" / "summary.txt").read_text()


def test_a_checkpoint_read_from_a_file_knows_its_records(tmp_path: Path) -> None:
    """A results file's checkpoint keeps the records of its run (the attribute ``records``
    of ``/checkpoint``), so that a run started from its state under an aftershock that
    ended by then is refused, as from the run's own final state (it was only warned: the
    state's records were unknown). The run: tests/test_post_earthquake.py's block, 1 s of
    a 2 Hz sine through ``pfeie run``."""
    import h5py

    from pfeie.io._checkpoint import read_checkpoint
    from test_post_earthquake import _run

    _run(tmp_path, 1.0)
    with h5py.File(tmp_path / "out" / "results.h5") as f:
        state = read_checkpoint(f).state
    assert state.records is not None and "'rec'" in state.records[1]
    assert state.kin.t == pytest.approx(1.0)
    job = load_job(tmp_path / "model.toml")
    after = pf.GroundMotion.from_function(lambda t: 0.0 * t, 0.3, 0.005, name="after")
    with pytest.raises(ModelError, match=r"ground motion 'after': the record ends at 0.3 s"):
        pf.Dynamic(job.model, 0.005).run(0.3, ground=[after], start=state)


def test_a_static_state_that_leans_on_junctions_is_warned() -> None:
    """A plain static analysis of Goodman and Bray's three columns (2.5, 3.5, 3 m on a base
    dipping 20°, φ = 50°; limit equilibrium: toppling, F = 0.61) held with four cells
    across, by the friction of the node pairs at the columns' feet, and said nothing
    (only the limit searches warned). Now the static joint records its junction share
    where it passes the searches' thresholds (41 % of the normal force of 'sides' on
    4.5 % of its area; the bases' 63 % on 17 % does not, 3.8 times its area), and the
    summary warns; the dams, wedges and arches of these tests do not."""
    from pfeie._job import _static_joints, reliability
    from test_review34 import _monoliths
    from test_review36 import _columns

    model = _columns([2.5, 3.5, 3.0], 0.0, 20.0, 50.0, across=4)
    joints = _static_joints(model, pf.solve_static(model))
    assert "junction_share" not in joints["bases"]
    assert 0.35 < joints["sides"]["junction_share"] < 0.5
    assert joints["sides"]["junction_area_share"] == pytest.approx(1 / 22)
    said = reliability({"static_joints": joints})
    assert [w.label for w in said] == ["static"]
    assert "joint 'sides' leans on its pairs at junctions" in said[0].text
    calm = _monoliths()
    assert not any("junction_share" in j for j in _static_joints(calm, pf.solve_static(calm))
                   .values())  # fmt: skip


def test_set_takes_a_blocks_pattern_and_refuses_one_that_would_do_nothing(tmp_path: Path) -> None:
    """``--set blocks.d*=soft`` was refused as no key path, though [blocks] takes patterns.
    Now taken: on a file whose [blocks] uses a pattern it replaces it (the dam's E is the
    soft material's); on a file that names the groups outright it would change nothing
    (a group named outright keeps its material), so it is refused with the key to set."""
    from pfeie.io import parse_override
    from test_cli import SMALL, _write

    soft = SMALL.replace("[blocks]", '[materials.soft]\nE = 10e9\nnu = 0.2\nrho = 2400.0\n'
                         "[blocks]")  # fmt: skip
    named = _write(tmp_path, soft)
    with pytest.raises(InputError, match=r"blocks\.d\* \(--set blocks\.d\*=soft\): the group "
                       r"'dam' is named outright .* --set blocks\.dam=soft"):  # fmt: skip
        load_job(named, [parse_override("blocks.d*=soft")])
    pattern = _write(tmp_path, soft.replace('dam = "concrete"', '"d*" = "concrete"'))
    job = load_job(pattern, [parse_override("blocks.d*=soft")])
    E = {b.name: float(b.material.E) for b in job.model.blocks}
    assert E == {"rock": 30e9, "dam": 10e9}


# -- impacts (a rockfall tester's findings) -----------------------------------------------------


def test_a_drop_whose_corrections_outweigh_the_fall_is_warned_in_python(
    caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A 1 m block released 50 mm above its base (a joint with that gap), run at Δt = 4 ms
    by the default scheme: the position corrections of its landing add far more than the
    1,177 J the fall releases (3.1e5 J; the block bounces back 65 mm), and a script's run
    said nothing (``pfeie run``'s summary did). Warned now, with the advice; Moreau-Jean
    (θ = 1), which has no position correction, lands without it."""
    def drop(scheme: str) -> pf.DynamicResult:
        model = block_on_base(joint=pf.Joint(phi=30.0, gap=0.05))
        an = pf.Dynamic(model, 0.004, scheme=scheme)
        return an.run(0.3, start=an.initial())

    with caplog.at_level(logging.WARNING, logger="pfeie"):
        r = drop("nonsmooth-alpha")
    fall = 2400.0 * 9.81 * 0.05
    assert float(r.energy["correction"][-1]) > 10 * fall
    assert "the position corrections of penetrating pairs added" in caplog.text
    assert "scheme = 'moreau-jean'" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="pfeie"):
        r = drop("moreau-jean")
    assert float(r.energy["correction"][-1]) == 0.0
    assert "position corrections" not in caplog.text


@pytest.mark.parametrize("dim", [2, 3])
def test_a_rigid_position_correction_lands_a_dropped_block(dim: int) -> None:
    """The same drop (50 mm, Δt = 4 ms) with ``position_correction = "rigid"``: the
    penetrating pairs are moved apart by a rigid motion of the falling block (in the metric
    of its mass) instead of their nodes alone, so the landing stores no strain: the block
    stays down (its largest opening after the landing 0 to round-off, against 65 mm with
    the local correction), and the correction adds 72 J, the weight's work over the
    penetration it removes (about v h = 4 mm), against 3.1e5 J; the balance closes. In 2D
    and 3D alike (a cube of 2 × 2 × 2 hexahedra)."""
    from pfeie.verification._models import block_on_base_3d

    def drop(correction: str) -> pf.DynamicResult:
        joint = pf.Joint(phi=30.0, gap=0.05)
        model = block_on_base(joint=joint) if dim == 2 else block_on_base_3d(joint=joint)
        an = pf.Dynamic(model, 0.004, position_correction=correction)
        return an.run(0.3, start=an.initial())

    fall = 2400.0 * 9.81 * 0.05  # J (a 1 m cube in 3D, a 1 m block a metre thick in 2D)
    for correction, rebound in (("local", 0.06), ("rigid", 0.0)):
        r = drop(correction)
        after = r.t > np.sqrt(2 * 0.05 / 9.81) + 5 * 0.004
        top = float(r.s[after, :, -1].max())
        if correction == "local":
            assert top > rebound  # (65 mm)
        else:
            assert top <= 1e-9  # (0 to round-off)
            assert 0.0 < float(r.energy["correction"][-1]) < 0.1 * fall  # (72 J)
        assert abs(float(r.energy["balance"][-1])) <= 1e-9 * fall


def test_a_rigid_position_correction_is_the_nonsmooth_alpha_schemes() -> None:
    """``position_correction = "rigid"`` with Moreau-Jean (no position correction) or
    with large rotations (the rigid modes are the undeformed geometry's) is refused."""
    model = block_on_base(joint=pf.Joint(phi=30.0))
    for extra in ({"scheme": "moreau-jean"}, {"large_rotation": True}):
        with pytest.raises(ModelError, match=r"position_correction = 'rigid' is the "):
            pf.Dynamic(model, 0.01, position_correction="rigid", **extra)


def test_theta_without_the_moreau_jean_scheme_is_refused() -> None:
    """θ is the Moreau-Jean scheme's; given to the default scheme it was ignored without a
    word (a tester's θ = 0.5)."""
    model = block_on_base(joint=pf.Joint(phi=30.0))
    with pytest.raises(ModelError, match=r"theta = 0.5 is the Moreau-Jean scheme's"):
        pf.Dynamic(model, 0.01, theta=0.5)
    assert pf.Dynamic(model, 0.01, scheme="moreau-jean", theta=0.8).settings.theta == 0.8


def test_the_new_setting_leaves_the_run_keys_of_earlier_files(tmp_path: Path) -> None:
    """``analysis.position_correction`` at its default ("local") is left out of the run
    key, so that runs written before the setting existed are resumed and a study's rows
    are not run again; "rigid" is another run."""
    import copy

    from pfeie.io._checkpoint import run_key
    from test_cli import SMALL, _write

    job = load_job(_write(tmp_path, SMALL))
    assert job.spec["analysis"]["position_correction"] == "local"
    before = copy.copy(job)
    before.spec = copy.deepcopy(job.spec)
    del before.spec["analysis"]["position_correction"]
    assert run_key(before) == run_key(job)
    before.spec["analysis"]["position_correction"] = "rigid"
    assert run_key(before) != run_key(job)
