"""The results summary (``summary.json``, ``summary.txt``): what its numbers are.

A block sliding down an incline from rest (β = 20°, φ = 10°, no ground motion): its
slip at time t is the closed form s(t) = ½ g (sin β − cos β tan φ) t² (a rigid block
on a Coulomb plane), and a probe on the block moves by the slip along the incline. The
probe's peak displacement in the summary is the peak of the magnitude |u|, which must
equal the joint's slip to the elastic shortening of the block (with E = 1e14 Pa, below
1e-9 relative: measured 3.6e-10), the closed form to 1e-6 (the scheme's start from an
unloaded state, measured 3.1e-7), and exceed its largest component |u_x| = |u| cos β.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import pfeie as pf
from pfeie._job import format_summary, summarize
from pfeie.io import Job
from pfeie.plot import OPEN_CRACK_MIN_M
from pfeie.verification._models import block_on_base

G = 9.81  # m/s², the builders' gravity


def _job(model: pf.Model, probe: int) -> Job:
    """A job around a model built in Python (the summary reads its model, probes and
    settings)."""
    spec = {"title": "summary test", "analysis": {"dt": 0.002}, "output": {}}
    return Job(Path("summary_test.toml"), spec, model, [], {"top": probe}, "0" * 64)


def test_peak_displacement_is_the_magnitude_on_an_incline() -> None:
    beta, phi, T = 20.0, 10.0, 0.5  # degrees, degrees, s
    model = block_on_base(joint=pf.Joint(phi=phi), incline_deg=beta, E=1e14)
    top = int(np.argmax(model.mesh.points[:, 1]))  # the block's upper corner
    res = pf.Dynamic(model, 0.002).run(T, probes=[top])
    s = summarize(_job(model, top), None, res)
    p, j = s["probes"]["top"], s["joints"]["joint"]
    b = np.radians(beta)
    exact = 0.5 * G * (np.sin(b) - np.cos(b) * np.tan(np.radians(phi))) * T**2
    assert p["peak_displacement_m"] == pytest.approx(j["residual_slip_max_m"], rel=1e-9)
    assert p["peak_displacement_m"] == pytest.approx(exact, rel=1e-6)
    assert p["peak_displacement_time_s"] == pytest.approx(T, abs=1e-12)  # slides on
    # the per-axis peaks: the slip's components along the incline (rounded to 1 µm)
    ux, uy = p["peak_displacement_xyz_m"]
    assert ux == pytest.approx(exact * np.cos(b), abs=1e-6)
    assert uy == pytest.approx(exact * np.sin(b), abs=1e-6)
    assert p["peak_displacement_m"] > ux + 0.01  # 216 mm against 203 mm
    line = next(x for x in format_summary(s).splitlines() if x.strip().startswith("top"))
    assert f"peak |u| {1e3 * exact:.1f} mm (x {1e3 * exact * np.cos(b):.1f}" in line
    # the block's permanent displacement (its centroid's rigid motion): the slip, to the
    # closed form's 1e-6 (measured 3.1e-7, as the probe), no rotation; the base stays
    blk, base = s["bodies"]["block"], s["bodies"]["base"]
    assert blk["floating"] and not base["floating"]
    assert blk["residual_displacement_m"] == pytest.approx(exact, rel=1e-6)
    assert blk["peak_displacement_m"] == pytest.approx(exact, rel=1e-6)
    assert abs(blk["residual_rotation_deg"]) < 5e-8  # measured 4.4e-9 (E = 1e14 Pa)
    assert base["peak_displacement_m"] == 0.0  # fixed at its base, rigid
    assert (f"block block      residual displacement {1e3 * exact:.1f} mm (x "
            f"{1e3 * blk['residual_displacement_xyz_m'][0]:.1f}") in format_summary(s)  # fmt: skip
    # a pre-existing joint (initial = "broken", the default) says so
    assert j["initially_broken_share"] == 1.0
    assert "broken 100 % (starts broken" in format_summary(s)
    # the slip against the spacing of the pairs (1 m wide, 2 cells: 0.5 m): 0.43 of it,
    # below LARGE_SLIP; past it the summary says that node-to-node pairs do not hold
    assert j["pair_spacing_m"] == pytest.approx(0.5, rel=1e-12)
    assert j["peak_slip_to_spacing"] == pytest.approx(j["peak_slip_max_m"] / 0.5, rel=1e-12)
    assert "large slip" not in format_summary(s)
    s["joints"]["joint"]["peak_slip_to_spacing"] = 1.6
    assert ("large slip   joint joint: the slip reaches 1.6 × the spacing of its pairs "
            "(0.5 m)") in format_summary(s)  # fmt: skip


@pytest.mark.parametrize("gap", [1e-7, 1e-4])
def test_open_crack_counts_pairs_open_beyond_the_threshold(gap: float) -> None:
    """A 2 m block held apart from its base by an initial gap, no load: every pair is
    broken and open (state OPEN) with opening = gap. The open crack counts the pairs
    open by more than OPEN_CRACK_MIN_M (1e-5 m): the whole 2 m with a 0.1 mm gap, none
    with 1e-7 m, whose pairs are open in name only; an intact joint is not
    "starts broken"."""
    model = block_on_base(joint=pf.Joint(phi=30.0, gap=gap), width=2.0, n=4, gravity=False)
    top = int(np.argmax(model.mesh.points[:, 1]))
    res = pf.Dynamic(model, 0.01).run(0.05, probes=[top])
    j = summarize(_job(model, top), None, res)["joints"]["joint"]
    assert j["max_opening_m"] == pytest.approx(gap, rel=1e-12)
    expected = 2.0 if gap > OPEN_CRACK_MIN_M else 0.0  # m
    assert j["max_open_length_m"] == pytest.approx(expected, rel=1e-14)
    assert j["cracked_length_m"] == pytest.approx(2.0, rel=1e-14)


def test_intact_joint_is_not_called_pre_existing() -> None:
    """An intact joint that does not break: broken 0 %, without the 'starts broken'
    note (a joint that starts intact is never so described)."""
    model = block_on_base(joint=pf.Joint(c=1e6, phi=30.0, tensile=1e6, initial="intact"))
    top = int(np.argmax(model.mesh.points[:, 1]))
    res = pf.Dynamic(model, 0.01).run(0.05, probes=[top], start=pf.solve_static(model))
    s = summarize(_job(model, top), None, res)
    assert s["joints"]["joint"]["initially_broken_share"] == 0.0
    assert s["joints"]["joint"]["broken_share"] == 0.0
    assert "broken 0 %," in format_summary(s) and "starts broken" not in format_summary(s)


@pytest.mark.parametrize(("dip", "start"), [(30.0, (0.0, 0.0)), (-30.0, (0.0, 0.0)),
                                            (60.0, (1.0, -np.sqrt(3.0)))])  # fmt: skip
def test_joint_map_position_zero(dip: float, start: tuple[float, float]) -> None:
    """The joint figures' positions (``_arc``): for 5 points on a straight joint of
    length 2 m from (0, 0) dipping ``dip`` towards +x (positive: downwards), whatever
    their order, position 0 is the −x end for a joint within 45° of x and the −y end
    otherwise; the positions are the distances from it (closed form: 0, 0.5, … 2 m, to
    1e-15 m); the axis label names that end."""
    from pfeie.plot._plots import _arc, _arc_label

    d = np.array([np.cos(np.radians(dip)), -np.sin(np.radians(dip))])
    x = np.outer(np.linspace(0.0, 2.0, 5), d)[[3, 0, 4, 1, 2]]
    order, s = _arc(x)
    np.testing.assert_allclose(x[order[0]], start, atol=1e-15)
    np.testing.assert_allclose(s, np.linspace(0.0, 2.0, 5), atol=1e-15)
    assert _arc_label(x, order).endswith(f"0 at the pair at ({start[0]:.4g}, {start[1]:.4g}) m")


def test_round_off_openings_are_drawn_as_zero() -> None:
    """The joint figures draw an opening of 1e-12 m (round-off of a closed pair) as 0,
    and one of 1e-6 m as it is (OPENING_FLOOR_M = 1e-9 m)."""
    from pfeie.plot._plots import OPENING_FLOOR_M, _shown_opening

    w = np.array([0.0, 1e-12, 0.5 * OPENING_FLOOR_M, 2.0 * OPENING_FLOOR_M, 1e-6])
    np.testing.assert_array_equal(_shown_opening(w), [0.0, 0.0, 0.0, 2.0 * OPENING_FLOOR_M, 1e-6])


def test_static_joint_summary_is_the_limit_equilibrium() -> None:
    """The static state per joint, for a 1 m block (2400 kg/m³) at rest on a 20° incline
    with φ = 31°: normal force W cos β and shear W sin β (equilibrium, to round-off:
    asserted 1e-12), FS = tan φ / tan β = 1.6509 (to 1e-12), mean normal stress
    W cos β / A, no opening (every pair closed; the largest opening round-off of the 1 m
    block: asserted 1e-21 m, measured 0 and 8.1e-23 m with OpenBLAS's Haswell and
    SkylakeX kernels); the summary's line prints FS and the forces. Given in a
    static-only run and before the dynamic summary alike."""
    beta, phi = 20.0, 31.0
    model = block_on_base(joint=pf.Joint(phi=phi), incline_deg=beta)
    static = pf.solve_static(model)
    s = summarize(_job(model, 0), static, None)
    j = s["static_joints"]["joint"]
    W, b = 2400.0 * G, np.radians(beta)
    assert j["normal_force_N"] == pytest.approx(W * np.cos(b), rel=1e-12)
    assert j["shear_force_N"] == pytest.approx(W * np.sin(b), rel=1e-12)
    fs = np.tan(np.radians(phi)) / np.tan(b)
    assert j["safety_factor"] == pytest.approx(fs, rel=1e-12)
    assert j["mean_normal_stress_Pa"] == pytest.approx(W * np.cos(b) / 1.0, rel=1e-12)
    assert 0.0 <= j["max_opening_m"] < 1e-21 and j["open_share"] == 0.0
    line = next(x for x in format_summary(s).splitlines() if "static joint" in x)
    assert f"FS {fs:.2f}, normal {W * np.cos(b) / 1e3:.4g} kN" in line


def test_a_joint_without_shear_has_no_safety_factor() -> None:
    """A block on a level joint without gravity or ground motion: its joint never carries
    shear, so neither the static nor the run's minimum safety factor exists: null in
    summary.json (strict JSON: no Infinity), ∞ in the text."""
    import json

    model = block_on_base(joint=pf.Joint(phi=30.0), gravity=False)
    static = pf.solve_static(model)
    res = pf.Dynamic(model, 0.002).run(0.02, start=static, probes=[0])
    s = summarize(_job(model, 0), static, res)
    assert s["static_joints"]["joint"]["safety_factor"] is None
    assert s["joints"]["joint"]["min_safety_factor"] is None
    json.dumps(s, allow_nan=False, default=str)
    assert "min FS ∞" in format_summary(s) and "FS ∞" in format_summary(s)


def test_energy_lines_of_the_summary() -> None:
    """The energy line gives the input and every dissipated term; a position correction
    above 1 % of the input gets a line of its own with its share (the Koyna demo's
    energies at Δt = 10 ms: 83.8 kJ, 11.1 % of 757 kJ), none below."""
    e = {"external_work": 756858.8, "interface": 30289.9, "impact": 32560.2,
         "damping": 707908.2, "algorithmic": 58628.1, "correction": 83783.3,
         "balance": -3.3e-10}  # fmt: skip
    model = {"title": "t", "file": "t.toml", "sha256": "0" * 64, "blocks": {}, "bodies": 1,
             "dof": 2, "pairs": {}, "records": []}  # fmt: skip
    text = format_summary({"model": model, "version": "0", "energy_J": e})
    assert ("energy       input 7.569e+05 J; friction/contact 3.029e+04, impact 3.256e+04, "
            "damping 7.079e+05, algorithmic 5.863e+04 J; balance -3.30e-10 J") in text
    assert "added 8.378e+04 J, 11.1 % of the input" in text
    quiet = {"model": model, "version": "0", "energy_J": {**e, "correction": 7000.0}}
    assert "corrections" not in format_summary(quiet)


def test_static_open_share_ignores_corner_pairs_parted_by_round_off() -> None:
    """A Tet10 block resting on its base under its weight: 9 of the 81 pairs (corners of
    the quadratic facets, which carry little of a uniform pressure) end open by 3e-9 m;
    the static summary's open share counts openings beyond 0.01 mm only: 0, and the joint
    carries the weight (W = ρ g V to 1e-12)."""
    from pfeie._job import _static_joints
    from pfeie.interface import OPEN
    from pfeie.verification._models import _groups, _model

    mesh = pf.box(2.0, 2.0, 3.0, 4, 4, 6, cell="tetra10")
    mesh.points[:, 2] -= 1.0
    _groups(mesh, 2)
    m = _model(mesh, pf.Joint(phi=45.0), pf.Elastic(30e9, 0.2, 2400.0), True)
    st = pf.solve_static(m)
    assert st.pairs is not None
    assert int((st.pairs.state == OPEN).sum()) > 0 and st.pairs.w[:, -1].max() < 1e-8
    j = _static_joints(m, st)["joint"]
    assert j["open_share"] == 0.0
    assert j["normal_force_N"] == pytest.approx(2400.0 * G * 2.0 * 2.0 * 2.0, rel=1e-12)


@pytest.mark.parametrize(("share", "shown", "unresolved"),
                         [(0.005, False, False), (0.11, True, False), (0.149, True, False),
                          (0.466, True, True), (1.45, True, True)])  # fmt: skip
def test_correction_energy_lines(share: float, shown: bool, unresolved: bool) -> None:
    """The position corrections' energy: no line up to 1 % of the input; its share above
    that (the Koyna demo's 11 % at Δt = 10 ms); above 15 %, that the run is not converged
    in Δt (a new user's 60 m dam sliding on its lift joint: 46.6 % at 10 ms, its slip 27 %
    short, and 14.9 % at 5 ms, 13 % short; the 3D monolith's 145 % at 10 ms)."""
    work = 3.4e6
    model = {"title": "t", "file": "m.toml", "sha256": "0" * 64, "blocks": ["a"],
             "bodies": 1, "dof": 6, "pairs": {}, "records": []}
    s = {"model": model, "version": pf.__version__,
         "energy_J": {"external_work": work, "correction": share * work, "balance": 0.0}}
    text = format_summary(s)
    assert ("corrections" in text) == shown
    assert (f"{100 * share:.1f} % of the input" in text) == shown
    assert ("not converged in Δt" in text) == unresolved


def test_pair_spacing_skips_pairs_at_one_point() -> None:
    """Where a joint meets two blocks on one side it has two pairs at one point: the
    spacing is the distance to the nearest pair elsewhere (0 would make the summary's
    slip ratio infinite or NaN, which summary.json cannot hold)."""
    from pfeie._job import _pair_spacing

    x = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 0.0], [1.5, 0.0], [2.0, 0.0]])
    np.testing.assert_array_equal(_pair_spacing(x), 0.5)
    np.testing.assert_array_equal(_pair_spacing(np.array([[0.0, 0.0], [0.0, 0.0], [0.0, 0.0],
                                                           [1.0, 0.0]])), 1.0)  # fmt: skip
    assert np.all(np.isinf(_pair_spacing(np.zeros((2, 2)))))  # one position: no spacing


@pytest.mark.parametrize(("energy", "warned"), [
    # a block on a 20° plane (φ = 30°) under El Centro (pfeie run, the default scheme):
    # Δt = 5 ms, residual slip 10.7 mm (the rigid block's 10.8 mm)
    ({"external_work": 282.0, "interface": 283.7, "impact": 0.5249, "damping": 0.05852,
      "algorithmic": -2.343}, False),
    # Δt = 20 ms, 8.0 mm; Δt = 100 ms, 18 mm up the slope (a net input of −219.5 J)
    ({"external_work": 239.5, "interface": 280.0, "impact": 24.74, "damping": 0.04213,
      "algorithmic": -65.27}, True),
    ({"external_work": -219.5, "interface": 280.1, "impact": 360.3, "damping": 0.007151,
      "algorithmic": -859.9}, True),
    # Moreau-Jean's own dissipation is positive: not "created" (θ = 1, Δt = 20 ms)
    ({"external_work": 606.7, "interface": 486.6, "impact": 0.0, "damping": 0.01009,
      "algorithmic": 120.1}, False),
])  # fmt: skip
def test_energy_created_by_the_scheme_is_warned(energy: dict[str, float], warned: bool) -> None:
    """A negative algorithmic term beyond 5 % of the energy that went through the run
    (new-user finding: the block's slip 26 % short at Δt = 20 ms without a word) gets a
    `scheme` line saying that the run is not converged in Δt; measured: −0.8 % at 5 ms,
    −21 % at 20 ms, −134 % at 100 ms."""
    model = {"title": "t", "file": "m.toml", "sha256": "0" * 64, "blocks": ["a"],
             "bodies": 1, "dof": 6, "pairs": {}, "records": []}
    s = {"model": model, "version": pf.__version__, "energy_J": {**energy, "balance": 0.0}}
    text = format_summary(s)
    assert ("scheme       WARNING: the time scheme created" in text) == warned
    if warned:
        assert "not converged in Δt" in text


@pytest.mark.parametrize(("energy", "warned"), [
    # a new user's 60 m dam whose upper block slides 135 mm on its lift joint (pfeie run,
    # El Centro at 0.4 g for 6 s): the default scheme at Δt = 10 and 2.5 ms (slip 27 and
    # 7 % short of the 1.25 ms run's), Moreau-Jean (θ = 1) at 10 ms (76 % short)
    ({"external_work": 7.94e5, "interface": 5.193e5, "impact": 4.338e4, "damping": 1.744e5,
      "algorithmic": 4.251e5}, True),
    ({"external_work": 8.712e5, "interface": 5.743e5, "impact": 2.027e4, "damping": 2.602e5,
      "algorithmic": 4.974e4}, False),
    ({"external_work": 5.206e5, "interface": 2.111e5, "impact": 0.0, "damping": 6.49e4,
      "algorithmic": 2.456e5}, True),
    # the Koyna demo at its Δt (7.7 %), and by Moreau-Jean there (65 %; neck slip 1.16 mm
    # against 3.85)
    ({"external_work": 7.569e5, "interface": 3.029e4, "impact": 3.256e4, "damping": 7.079e5,
      "algorithmic": 5.85e4}, False),
    ({"external_work": 8.068e5, "interface": 1.063e4, "impact": 0.0, "damping": 2.595e5,
      "algorithmic": 5.273e5}, True),
    # a stiff undamped block whose joint does nothing (its ~100 Hz vibration annihilated by
    # ρ∞ = 0 at 10 ms: 313 % of an input of 1.3e-5 J): a choice of Δt for the elastic
    # response, not a contact event
    ({"external_work": -1.311e-5, "interface": 2.18e-13, "impact": 3.4e-27, "damping": 0.0,
      "algorithmic": 4.107e-5}, False),
])  # fmt: skip
def test_energy_dissipated_by_the_scheme_is_warned(
    energy: dict[str, float], warned: bool
) -> None:
    """A positive algorithmic term beyond 10 % of the input, in a run whose joints took
    more than 1 % of it, gets a `scheme` line saying that the slips, openings and peaks
    are damped by the scheme and not converged in Δt (new-user finding: the dam's slip
    27 % short at 10 ms with no line, and 76 % short by Moreau-Jean)."""
    model = {"title": "t", "file": "m.toml", "sha256": "0" * 64, "blocks": ["a"],
             "bodies": 1, "dof": 6, "pairs": {}, "records": []}
    s = {"model": model, "version": pf.__version__, "energy_J": {**energy, "balance": 0.0},
         "static_strain_energy_J": 0.086}
    text = format_summary(s)
    assert ("scheme       WARNING: the time scheme dissipated" in text) == warned
    assert ("damped by the scheme and not converged in Δt" in text) == warned


#: the 60 m dam (T6) under an all-zero record, Δt = 10 ms, 4 s (new-user finding): the
#: energy terms are round-off; its static strain energy ½ f·u = 39213.5 J
ZERO_RECORD = {"external_work": -3.241e-08, "interface": -1.775e-08, "impact": 2.917e-22,
               "damping": 2.667e-21, "algorithmic": -1.058e-08, "correction": 5.5e-09,
               "balance": 2.45e-12}  # fmt: skip


@pytest.mark.parametrize(("energy", "static", "warned"), [
    (ZERO_RECORD, 39213.5, False),
    # without the static strain energy (a summary written before it was kept): no floor
    (ZERO_RECORD, None, True),
    # the block on a 20° plane at Δt = 20 ms (above): 240 J of input against a static
    # strain energy of 3.75e-3 J (a stiff 1 m block), still warned
    ({"external_work": 239.5, "interface": 280.0, "impact": 24.74, "damping": 0.04213,
      "algorithmic": -65.27, "correction": 12.0, "balance": 0.0}, 3.75e-3, True),
])  # fmt: skip
def test_round_off_energies_are_not_warned(
    energy: dict[str, float], static: float | None, warned: bool
) -> None:
    """A zero record gave "the time scheme created 5.663e-09 J, 23 %" and "corrections
    17.0 % of the input": shares of round-off. Below a millionth of the static strain
    energy (ENERGY_FLOOR; the zero run's flow is 8e-13 of it) neither line is given; a
    run that puts real energy through is still warned (the block: 280 J, 7e10 times the
    floor)."""
    model = {"title": "t", "file": "m.toml", "sha256": "0" * 64, "blocks": ["a"],
             "bodies": 1, "dof": 6, "pairs": {}, "records": []}
    s: dict[str, object] = {"model": model, "version": pf.__version__, "energy_J": energy}
    if static is not None:
        s["static_strain_energy_J"] = static
    text = format_summary(s)
    assert ("scheme       WARNING: the time scheme created" in text) == warned
    assert ("corrections  the position corrections" in text) == warned


@pytest.mark.parametrize(("y", "text"), [
    # a new user's four rock columns on 15° bases: no equilibrium found beyond 0.2655, the
    # margins vanish at tan 15° = 0.2679 (0.9 % above): a sliding limit the pair solver
    # fell short of
    ({"k_y": 0.2655, "k_fail": 0.2656, "limit": "no equilibrium found", "joint": "bases",
      "safety_factor": 1.009, "k_affine": 0.2679},
     "k_y 0.2655 (no equilibrium found beyond it; 'bases' reaches its capacity at 0.2679, "
     "the margins' affine estimate (FS 1.009 at k_y): probably a sliding limit there"),
    # a new user's 3D monolith pushed upstream: its upper block overturns on the lift joint
    # at 0.6232 (by hand), while the least FS is the dam-rock joint's: the line names the
    # joint that opens
    ({"k_y": 0.6232, "k_fail": 0.6233, "limit": "no equilibrium found", "joint": "dam_rock",
      "safety_factor": 1.564, "k_affine": None, "open_joint": "lift", "open_share": 0.62},
     "least FS 1.564 on 'dam_rock'; at k_y 'lift' is the most open, 62 % of its area: the "
     "block on it rocks or overturns)"),
    # a block on an intact joint that breaks through at 0.2029 (the margins' 0.2115 lie
    # 4 % above): at its capacity (FS within AT_CAPACITY_FS of 1), breaking
    ({"k_y": 0.2029, "k_fail": 0.2030, "limit": "no equilibrium found", "joint": "joint",
      "safety_factor": 1.018, "k_affine": 0.2115},
     "k_y 0.2029 (no equilibrium found beyond it; 'joint' is at its sliding capacity there, "
     "FS 1.018: sliding as the joint opens or breaks further)"),
    # a new user's cracked dam base with uplift: at 0.0487 the base is at FS 1.029 and
    # 18 % open, and beyond it the crack grows under its uplift (their USACE cracked-base
    # iteration: FS 1 at 0.0488): sliding as the crack grows, no longer "not a sliding
    # limit"
    ({"k_y": 0.04871, "k_fail": 0.04872, "limit": "no equilibrium found", "joint": "base",
      "safety_factor": 1.029, "k_affine": 0.05897, "open_joint": "base", "open_share": 0.18},
     "k_y 0.04871 (no equilibrium found beyond it; 'base' is at its sliding capacity there, "
     "FS 1.029: sliding as the joint opens or breaks further; at k_y 'base' is the most "
     "open, 18 % of its area)"),
    # the same dam pushed upstream: its upper block overturns on the lift joint (0.474 by
    # hand), the joint with the least FS itself: named as the one that opens
    ({"k_y": 0.4744, "k_fail": 0.4745, "limit": "no equilibrium found", "joint": "lift",
      "safety_factor": 1.65, "k_affine": None, "open_joint": "lift", "open_share": 0.93},
     "least FS 1.65 on 'lift'; at k_y 'lift' is the most open, 93 % of its area: the block "
     "on it rocks or overturns)"),
    # a 3D dam whose contraction joint opens (its margin followed, FS 14.23) while the
    # dam-rock joint is at FS 1.2: the least FS is the dam-rock joint's
    ({"k_y": 0.5097, "k_fail": 0.5098, "limit": "no equilibrium found", "joint": "cj",
      "safety_factor": 14.23, "safety_factors": {"dam_rock": 1.2, "cj": 14.23},
      "k_affine": 0.517, "open_joint": "cj", "open_share": 0.73},
     "least FS 1.2 on 'dam_rock' (the margins followed 'cj', FS 14.23), the margins' affine "
     "estimate 0.517; at k_y 'cj' is the most open, 73 % of its area: the block on it "
     "rocks or overturns)"),
    # below half of the joint open, no rocking is said (the monolith above: 62 %)
    ({"k_y": 0.30, "k_fail": 0.3001, "limit": "no equilibrium found", "joint": "lift",
      "safety_factor": 1.5, "k_affine": None, "open_joint": "lift", "open_share": 0.40},
     "least FS 1.5 on 'lift'; at k_y 'lift' is the most open, 40 % of its area)"),
])  # fmt: skip
def test_yield_line_reads_a_near_sliding_limit(y: dict[str, Any], text: str) -> None:
    """The summary's yield line when no equilibrium was found beyond k_y: a sliding limit
    the solver fell short of (the margins' root within 2 % above k_y, FS within 2 % of 1)
    is said to be one; otherwise the causes are listed, the solver's failure among them."""
    model = {"title": "t", "file": "m.toml", "sha256": "0" * 64, "blocks": ["a"],
             "bodies": 1, "dof": 6, "pairs": {}, "records": []}
    out = format_summary({"model": model, "version": pf.__version__,
                          "yield_coefficient": {"+x": y}})  # fmt: skip
    assert text in out, out


def test_min_safety_factor_is_dated_when_the_joint_first_slides() -> None:
    """A block on a level joint (φ = 20°) under a ground acceleration ramp a(t) = 0.8 g t/s:
    it holds while a < μ g and slides from t_s = tan 20°/0.8 = 0.455 s, its FS then 1 to
    round-off at every step. The summary dates the minimum at the first of those steps
    (argmin had picked any of them: a new user's block read 9.11, 14.07 and 1.39 s as Δt
    fell, sliding from 1.315 s in every run)."""
    model = block_on_base(joint=pf.Joint(phi=20.0), E=1e12, check_units=False)
    static = pf.solve_static(model)
    t = np.linspace(0.0, 1.0, 101)
    gm = pf.GroundMotion.from_samples(0.8 * t, time=t, units="g")
    res = pf.Dynamic(model, 0.002).run(1.0, start=static, ground=[gm], probes=[0])
    s = summarize(_job(model, 0), static, res)
    j = s["joints"]["joint"]
    t_s = np.tan(np.radians(20.0)) / 0.8
    assert j["min_safety_factor"] == 1.0  # 1 to round-off: given as 1 (a limit state FS ≤ 1)
    # the first recorded step at FS = 1 (Δt = 2 ms; the block is rigid to 1e-12)
    assert j["min_safety_factor_time_s"] == pytest.approx(t_s, abs=0.0021)
    fs = res.safety_factor[:, 0]
    assert (fs[res.t > t_s + 0.01] < 1.0 + 1e-9).all()  # it slides on to the end


def test_a_block_thrown_off_its_joint_is_warned() -> None:
    """The base dropped at 1.5 g (a ground acceleration of −1.5 g along y from t = 0.05 s,
    beyond gravity): the block on it flies, every pair of its joint open, from the first
    step the base outruns it; the summary names the block, the rows and the first time,
    with the warning that says what else throws a block (a new user's 30 m rock block on
    35° under El Centro, undamped E = 20 GPa: its joint open over its whole length at
    Δt = 1.25 ms, the slip 160 mm against 102 at 2.5 ms and 86 mm with damping beta
    2e-3 s at 2.5, 1.25 and 0.625 ms). The block held on its joint by gravity alone (the
    ground at rest) is never airborne."""
    from pfeie._job import format_summary, reliability

    model = block_on_base(joint=pf.Joint(phi=30.0), n=2)
    top = int(np.argmax(model.mesh.points[:, 1]))
    drop = pf.GroundMotion.from_samples([0.0, 0.0, -1.5, -1.5], time=[0.0, 0.05, 0.0501, 1.0],
                                        units="g", direction=(0.0, 1.0))  # fmt: skip
    static = pf.solve_static(model)
    res = pf.Dynamic(model, 0.002).run(0.1, start=static, ground=[drop], probes=[top])
    s = summarize(_job(model, top), static, res)
    b = s["bodies"]["block"]
    flying = res.t[(res.state == 3).all(axis=1)]  # every pair of the (one) joint open
    assert b["airborne_rows"] == flying.size > 0
    # (the summary's times to the nanosecond: 0.052, not 0.052000000000000005)
    assert b["first_airborne_s"] == round(float(flying[0]), 9) and 0.05 < flying[0] <= 0.056
    text = format_summary(s)
    assert "  airborne     block block lost contact with all its joints at" in text
    first = next(w for w in reliability(s) if w.label == "airborne")
    assert s["damping"]["beta_s"] == 0.0 and "friction-excited vibration" in first.text
    # with stiffness-proportional damping the advice is not to add it (a new user's
    # damped Pine Flat read "add damping"): rocking or impacts, compare two Δt
    damped = {**s, "damping": {**s["damping"], "beta_s": 1e-3}}
    other = next(w for w in reliability(damped) if w.label == "airborne")
    assert "(β = 0.001 s): a block that rocks or bounces" in other.text
    assert "add damping" not in other.text + other.short
    calm = pf.Dynamic(model, 0.002).run(0.1, start=static, probes=[top])
    assert "airborne_rows" not in summarize(_job(model, top), static, calm)["bodies"]["block"]


def test_a_toppling_column_is_warned() -> None:
    """A 1 m × 4 m column on a 20° plane (b/h = 0.25 < tan 20°: it topples) released from
    rest, large rotations: the pairs, node to node as meshed, cannot follow it past the
    tipping and it turns through the rock beneath (a 3D rock engineer's column, 188°,
    reported as completed with no word). The summary gives its peak rotation and the
    line "large motion" from the first recorded time past 30° (the rigid rotation read
    from the histories, here, independently); a short stand of the column (0.4 s, a few
    degrees) has none."""
    from pfeie._job import LARGE_TURN_DEG, reliability

    model = block_on_base(joint=pf.Joint(phi=45.0), width=1.0, height=4.0, n=2, ny=4,
                          incline_deg=20.0, E=30e9)  # fmt: skip
    top = int(np.argmax(model.mesh.points[:, 1]))
    res = pf.Dynamic(model, 4e-3, large_rotation=True).run(2.6, probes=[top])
    s = summarize(_job(model, top), None, res)
    b = s["bodies"]["block"]
    turn = np.degrees(np.abs(res.rigid[:, 1, 2] - res.rigid[0, 1, 2]))
    assert b["peak_rotation_deg"] == pytest.approx(turn.max(), rel=1e-12) and turn.max() > 90
    # the residual rotation signed in 2D, counter-clockwise + as history/rigid (it was
    # the magnitude: a tester's dam block read +0.0156° where the history gave −0.0156°)
    signed = np.degrees(res.rigid[-1, 1, 2] - res.rigid[0, 1, 2])
    assert b["residual_rotation_deg"] == pytest.approx(signed, rel=1e-12) and abs(signed) > 90
    assert b["beyond_pairs_s"] == res.t[np.argmax(turn > LARGE_TURN_DEG)]
    line = next(w for w in reliability(s) if w.label == "large motion")
    assert line.text.startswith(f"block block turned by up to {turn.max():.3g}°")
    assert "  large motion block block turned by up to" in format_summary(s)
    short = pf.Dynamic(model, 4e-3, large_rotation=True).run(0.4, probes=[top])
    assert "beyond_pairs_s" not in summarize(_job(model, top), None, short)["bodies"]["block"]
