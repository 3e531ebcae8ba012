"""The factor of safety by strength reduction (pfeie.strength_reduction; docs/theory.md,
"Two safety factors"), against limit equilibrium.

At the limit every pair of the joints that slide is at its reduced capacity, whatever the
blocks' elasticity, so the static analyses reproduce the closed forms of rigid blocks up
to the search's tolerance: the factor held lies below the closed form and the least
factor that fails above it, within REDUCTION_TOL (1e-4) relative.

- a block of weight W on a plane of dip β, residual cohesion c over its base area A and
  friction φ: F = (c A + W cos β tan φ) / (W sin β);
- a symmetric wedge whose planes make ξ = 45° with the vertical plane through the keel,
  plunging by ψ (Hoek and Bray 1981, ch. 7): F = tan φ / (sin ξ tan ψ), √2 at φ = ψ = 30°.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.interface import SLIDE
from pfeie.solvers import REDUCTION_TOL
from pfeie.verification._models import block_on_base
from test_cli import SMALL, _write
from test_wedge import _wedge


def _bracketed(r: pf.StrengthReduction, ref: float) -> None:
    """The closed form ``ref`` lies in the bracket [factor, factor_fail], which is at most
    REDUCTION_TOL relative wide."""
    assert r.factor is not None and r.factor_fail is not None
    assert r.factor <= ref * (1 + 1e-9) and r.factor_fail >= ref * (1 - 1e-9), (r, ref)
    assert r.factor_fail - r.factor <= REDUCTION_TOL * r.factor


@pytest.mark.parametrize(("beta", "c_r", "width", "height"),
                         [(20.0, 0.0, 1.0, 1.0), (20.0, 1e4, 2.0, 0.5), (35.0, 2e4, 2.0, 0.5)])
def test_a_block_on_an_incline(beta: float, c_r: float, width: float, height: float) -> None:
    """A block (ρ = 2400 kg/m³) on a plane of dip β, φ = 30° and residual cohesion c_r (a
    joint that starts broken has only its residual strength): the closed form within the
    bracket, sliding on the joint, whose safety factor under the reduced strengths is 1
    within the bracket; 4 static analyses (the static state, one just beyond the
    rigid-block estimate, tried warm and cold, and one just below it). The blocks with
    cohesion are flat: a 1 m × 1 m block on 35° with c_r = 20 kPa lifts its heel at the
    limit, whose cohesion then goes (F 1.935 on 2 × 2 cells, 1.63 to 1.75 finer, against
    2.306; not the closed form's mechanism)."""
    m = block_on_base(joint=pf.Joint(phi=30.0, c_r=c_r), incline_deg=beta, width=width,
                      height=height, n=int(2 * width))  # fmt: skip
    r = pf.strength_reduction(m)
    W, b = 2400.0 * 9.81 * width * height, np.radians(beta)
    ref = (c_r * width + W * np.cos(b) * np.tan(np.radians(30.0))) / (W * np.sin(b))
    _bracketed(r, ref)
    assert r.limit == "sliding" and r.joint == "joint"
    assert abs(r.safety_factors["joint"] - 1.0) <= REDUCTION_TOL
    assert r.analyses == 4


@pytest.mark.parametrize("groups", [1, 2])
def test_a_wedge_against_hoek_and_bray(groups: int) -> None:
    """The symmetric wedge of tests/test_wedge.py (ξ = 45°, ψ = 30°, φ = 30°, the rock
    fixed at its base), its planes one joint or two: F = √2 within the bracket (measured
    1.41418 and 1.41413), sliding. Its static state shows why the joints' own safety
    factors are no factor against sliding: the elastic wedge, loaded by its weight from a
    stress-free state, is held up the dip by friction at the capacity of every pair, so
    each plane's mobilised safety factor is within 4 % of 1 (measured 1.0345 and 1.0847)
    where Hoek and Bray's is 1.414."""
    m = _wedge(30.0, groups)
    static = pf.solve_static(m)
    assert static.pairs is not None
    assert np.all(static.pairs.state == SLIDE)
    r = pf.strength_reduction(m)
    _bracketed(r, float(np.sqrt(2.0)))
    assert r.limit == "sliding"
    # every pair at its reduced cone to the pair solver's tolerance 1e-8 (measured FS − 1
    # of 1.9e-9 and 9.8e-9)
    assert all(abs(f - 1.0) <= 1e-7 for f in r.safety_factors.values())


def test_a_wedge_whose_keel_is_level_holds() -> None:
    """ψ = 0: nothing drives the wedge along its keel, so it holds with its strengths
    divided by the largest factor tried (REDUCTION_F_MAX): factor None, limit 'none'."""
    r = pf.strength_reduction(_wedge(0.0, 2))
    assert r.factor is None and r.factor_fail is None and r.limit == "none"


def test_refused_without_interfaces_and_with_bad_settings() -> None:
    """No interface, a tolerance or a largest factor out of range: ModelError naming what
    was expected."""
    mesh = pf.rectangle(1.0, 1.0, 2, 2)
    m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
    with pytest.raises(pf.ModelError, match="no interfaces"):
        pf.strength_reduction(m)
    block = block_on_base(joint=pf.Joint(phi=30.0), incline_deg=10.0)
    for kw in ({"tol": 0.1}, {"f_max": 1.0}):
        with pytest.raises(pf.ModelError, match=r"expected 0 < tol < 0\.01 and 1 < f_max"):
            pf.strength_reduction(block, **kw)  # type: ignore[arg-type]


def test_in_a_model_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``analysis.strength_reduction = true`` on two blocks cut by a level joint with
    μ = tan 26.565° = 0.5 under a pseudo-static k_h = 0.25: F = μ / k_h = 2 within the
    bracket in summary.json, a line in summary.txt and the progress, a column of the
    report's static joint table. Without the static state, or without interfaces, it is
    refused, naming the key."""
    text = SMALL.replace("[analysis]", "[loads]\npseudo_static = { kh = 0.25 }\n[analysis]\n"
                         "strength_reduction = true\ndynamic = false")  # fmt: skip
    text = text.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    p = _write(tmp_path, text)
    capsys.readouterr()
    assert main(["run", str(p)]) == 0
    err = capsys.readouterr().err
    assert "strength reduction: static analyses ..." in err
    assert "(sliding), 4 static analyses in" in err, err
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    sr = s["strength_reduction"]
    ref = np.tan(np.radians(26.565)) / 0.25
    assert sr["factor"] <= ref * (1 + 1e-9) <= sr["factor_fail"] * (1 + 2e-9)
    assert sr["factor_fail"] - sr["factor"] <= REDUCTION_TOL * sr["factor"]
    assert sr["limit"] == "sliding" and sr["joint"] == "joint" and sr["analyses"] == 4
    txt = (tmp_path / "out" / "summary.txt").read_text()
    assert f"reduction    FS {sr['factor']:.4g} by strength reduction (sliding on 'joint'" in txt
    from pfeie.plot import write_report

    html = Path(write_report(tmp_path / "out" / "results.h5")).read_text()
    assert "FS by strength reduction" in html and f"{sr['factor']:.4g} (sliding)" in html
    assert "at its capacity in the static state" not in txt
    capsys.readouterr()
    assert main(["check", str(p)]) == 0  # the check names the analyses the run makes
    assert ("analyses     static state; factor of safety by strength reduction\n"
            in capsys.readouterr().out)  # fmt: skip
    bad = _write(tmp_path, text.replace("dynamic = false", "dynamic = true\nstatic = false"))
    capsys.readouterr()
    assert main(["run", str(bad), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "analysis.strength_reduction" in err and "expected static = true" in err, err


def test_a_joint_at_its_capacity_points_to_the_factor(tmp_path: Path) -> None:
    """A static state that holds with a joint within 5 % of its capacity (the level joint,
    μ = 0.5, under k_h = 0.49: FS = 0.5/0.49 = 1.02, to 5e-15, measured 4.4e-16): its
    summary line says that the factor
    against sliding is the strength reduction's, unless that was asked for."""
    text = SMALL.replace("[analysis]", "[loads]\npseudo_static = { kh = 0.49 }\n[analysis]\n"
                         "dynamic = false")  # fmt: skip
    text = text.replace("[[ground_motion]]\nfile = \"pulse.csv\"\nunits = \"g\"\n", "")
    assert main(["run", str(_write(tmp_path, text)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["static_joints"]["joint"]["safety_factor"] == pytest.approx(
        np.tan(np.radians(26.565)) / 0.49, rel=5e-15)  # fmt: skip
    txt = (tmp_path / "out" / "summary.txt").read_text()
    assert ("at its capacity in the static state, which holds: the factor against sliding "
            "is analysis.strength_reduction's") in txt  # fmt: skip


def test_a_joint_without_shear_and_the_text_lines() -> None:
    """A block on a level joint under its weight alone: no joint carries shear, so it
    holds up to REDUCTION_F_MAX with its safety factor ∞ (not the 4e16 of a round-off
    shear, as a new user saw), and the summary's line says why. A sliding limit at which a
    joint opens names it and its open share."""
    from pfeie._job import _reduction_text

    r = pf.strength_reduction(block_on_base(joint=pf.Joint(phi=30.0)))
    assert r.factor is None and r.limit == "none"
    assert r.safety_factors == {"joint": np.inf}
    line = _reduction_text({"factor": None, "safety_factors": {"joint": None}, "f_max": 20.0})
    assert line == ("FS > 20 by strength reduction (held with the joints' strengths divided "
                    "by the largest factor tried; no joint carries shear under the static "
                    "loads)")  # fmt: skip
    line = _reduction_text({"factor": 1.658, "limit": "sliding", "joint": "joint",
                            "safety_factors": {"joint": 1.0}, "open_joint": "joint",
                            "open_share": 0.44})  # fmt: skip
    assert line.endswith("'joint' is open over 44 % of its area there)"), line


def test_cohesion_lost_on_open_pairs_is_reported() -> None:
    """The 1 m × 1 m block on 35° with c_r = 20 kPa (2 × 2 cells): at the limit its heel
    pair parts (by 0.4 µm), and its c A goes with it, so F falls below the rigid block's
    2.306. The result reports the cohesive capacity lost on open pairs, and its share is
    that of force equilibrium at the limit, F W sin β = c (A − A_open) + W cos β tan φ,
    which puts A_open/A between its values at the bracket's two ends (0.249967 and
    0.250033; the heel's quarter of the base, 0.25). A new user's wedge with cohesion on
    one plane lost 4.9 % on pairs open by 1 µm and ended 1.06 % below Hoek and Bray's
    factor: the summary's line now says why."""
    from pfeie._job import _open_cohesion, _reduction_text

    m = block_on_base(joint=pf.Joint(phi=30.0, c_r=2e4), incline_deg=35.0, width=1.0,
                      height=1.0, n=2)  # fmt: skip
    r = pf.strength_reduction(m)
    assert r.limit == "sliding" and r.factor is not None and r.factor_fail is not None
    lost = _open_cohesion(m, r.static)
    W, b, mu = 2400.0 * 9.81, np.radians(35.0), np.tan(np.radians(30.0))
    open_at = {F: 1.0 - (F * W * np.sin(b) - mu * W * np.cos(b)) / 2e4
               for F in (r.factor, r.factor_fail)}  # fmt: skip
    assert open_at[r.factor_fail] <= lost["joint"]["share"] <= open_at[r.factor]
    assert 0.0 < lost["joint"]["max_opening_m"] < 1e-6
    line = _reduction_text({"factor": r.factor, "limit": r.limit, "joint": "joint",
                            "safety_factors": {"joint": 1.0}, "open_cohesion": lost})  # fmt: skip
    # the line gives the share and the opening of the state at the limit
    said = (f"; cohesion lost on open pairs: 'joint' {100 * lost['joint']['share']:.2g} % of its "
            f"c·A (openings up to {1e6 * lost['joint']['max_opening_m']:.2g} µm))")
    assert line.endswith(said), line
