"""Findings of the thirtieth review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.errors import InputError, ModelError
from pfeie.io import load_job
from test_cli import SMALL, _write

# -- joint stiffness and the static state's displacements ----------------------------------


def _soft(k: str) -> str:
    return SMALL.replace("friction_angle = 26.565",
                         f"friction_angle = 26.565\nnormal_stiffness = {k}\n"
                         f"shear_stiffness = {k}")  # fmt: skip


@pytest.mark.parametrize("k", ["1e-300", "0.5"])
def test_a_joint_stiffness_below_one_pascal_a_metre_is_refused(tmp_path: Path, k: str) -> None:
    """normal_stiffness = 1e-300 Pa/m ran into a bare LinAlgError ("SVD did not converge")
    of the pair operators (the compliance 1/k overflows). No joint is softer than 1 Pa/m
    (1 m of closure under 1 Pa): the model file and the Python law refuse it by name."""
    with pytest.raises(InputError, match=r"interfaces\.joint\.normal_stiffness.*\[1, 1e\+20\]"):
        load_job(_write(tmp_path, _soft(k)))
    with pytest.raises(ModelError, match=r"kn must be >= 1 Pa/m"):
        pf.Joint(phi=30.0, kn=float(k))


def test_a_static_state_beyond_small_displacements_is_a_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A weak layer of 1e3 Pa/m (a stiffness given in kPa/m, or a typo) settled the dam
    block by 23.5 m, 12 times its size, and the run's summary said nothing of it: the
    static state, the slips and the safety factors were read as results. The summary now
    warns. Independent number: the settlement of a rigid block on a uniform layer, the
    mean normal stress over k: 23,544 Pa / 1e3 Pa/m = 23.5 m."""
    assert main(["run", str(_write(tmp_path, _soft("1e3"), duration=0.01)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    sigma = s["static_joints"]["joint"]["mean_normal_stress_Pa"]
    assert s["static_far_moved"] == [
        f"block 'dam' rotated 3.01e-08° and moved {sigma / 1e3:.3g} m (2 m across)"
    ]  # rotation: the block's elastic tilt on the layer, round-off (measured)
    assert [w["label"] for w in s["warnings"]] == ["static"]
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "static       the static state: block 'dam'" in text and "Pa/m" in text
    # the joint at its documented stiffness: no warning
    assert main(["run", str(_write(tmp_path, _soft("1e10"), duration=0.01)), "--quiet"]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert "static_far_moved" not in s and s["warnings"] == []


# -- keys asked for that cannot run ----------------------------------------------------------


@pytest.mark.parametrize(
    ("analysis", "match"),
    [("static = false\npost_earthquake = true", "expected analysis.static = true"),
     ("static = true\ndynamic = false\npost_earthquake = true",
      "expected analysis.dynamic = true")],
)  # fmt: skip
def test_post_earthquake_asked_where_it_cannot_run_is_refused(
    tmp_path: Path, analysis: str, match: str
) -> None:
    """``post_earthquake = true`` written in a file with ``static = false`` (or without a
    dynamic analysis) was ignored without a word. On by default, it is still skipped
    quietly where it has no meaning; asked for, it is refused by name."""
    text = SMALL.replace("dt = 0.005", f"dt = 0.005\n{analysis}")
    with pytest.raises(InputError, match=rf"analysis\.post_earthquake: .*{match}"):
        load_job(_write(tmp_path, text))
    quiet = text.replace("post_earthquake = true", "")
    assert load_job(_write(tmp_path, quiet)).analysis.post_earthquake  # the default


def test_solve_static_takes_its_settings_as_a_dict() -> None:
    """``pfeie.Dynamic(settings={...})`` takes the settings' fields as a dict, and
    ``solve_static(settings={...})`` refused them. Now both do; the result is that of
    the typed settings, bit for bit, and a wrong field is named."""
    m = pf.Model(pf.rectangle(2.0, 1.0, 4, 2), [pf.Block("all", pf.Elastic(1e6, 0.0))])
    m.fix("xmin", 0)
    m.fix("ymin", 1)
    m.add_traction("xmax", [1e3, 0.0])
    u = pf.solve_static(m, settings={"tolerance": 1e-10}).u
    assert (u == pf.solve_static(m, settings=pf.SolverSettings(tolerance=1e-10)).u).all()
    assert abs(u[:, 0].max() - 2e-3) < 1e-15  # σ L / E
    with pytest.raises(ModelError, match="solve_static: settings: tol: Extra inputs"):
        pf.solve_static(m, settings={"tol": 1e-10})
    with pytest.raises(ModelError, match="tolerance: Input should be a valid number"):
        pf.solve_static(m, settings={"tolerance": "1e-10"})
