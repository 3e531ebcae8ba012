"""Silt load (USACE EM 1110-2-2200 §3-4): the horizontal pressure K γ' (z_s − z) on the
vertical projection of the wet face and the silt's weight γ' (z_s − z) on its horizontal
projection. References: the resultant and its line of action in closed form, on a
vertical face (K γ' H²/2 at H/3) and on an inclined face (the same horizontal thrust, and
the weight of the silt wedge γ' m H²/2 through the wedge's centroid, m H/3 from the heel),
in 2D and on a face of a 3D box; the model file and its messages."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.errors import ModelError

GAMMA = 9000.0  # submerged unit weight of the silt (N/m³)


def _block(slope: float, dim: int = 2) -> pf.Model:
    """A block 4 m wide and 12 m high (Q8, or Hex8 2 m deep in 3D) whose upstream face x =
    −slope (12 − y) leans upstream with the batter ``slope`` (horizontal per vertical)."""
    if dim == 2:
        mesh = pf.rectangle(4.0, 12.0, 2, 12, cell="quad8")
    else:
        mesh = pf.box(4.0, 2.0, 12.0, 2, 2, 12)
    up = dim - 1
    mesh.points[:, 0] -= slope * (12.0 - mesh.points[:, up]) * (1.0 - mesh.points[:, 0] / 4.0)
    return pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])


def _resultant(model: pf.Model, heel: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The load's resultant force, the height above the heel of the line of action of its
    horizontal (x) part, and the distance from the heel of that of its vertical part."""
    d = model.dim
    f = model.load_vector().reshape(-1, d)
    r = model.mesh.points - heel
    F = f.sum(axis=0)
    return F, float((r[:, -1] * f[:, 0]).sum() / F[0]), float((r[:, 0] * f[:, -1]).sum() / F[-1])


@pytest.mark.parametrize("dim", [2, 3])
def test_vertical_face(dim: int) -> None:
    """Silt 7 m deep against a vertical face, K0 = 1 − sin 30° = 0.5: the horizontal
    thrust K γ' H²/2 (× the width in 3D) acting H/3 above the base, no vertical force; to
    5e-15 (the pressure is linear on each face below the silt surface, which lies on an
    element edge: the face quadrature is exact, round-off only; measured 1.3e-16 in 2D
    and 3D, the height of the line of action to the bit)."""
    model = _block(0.0, dim)
    H, width = 7.0, 1.0 if dim == 2 else 2.0
    k = model.add_silt("xmin", level=H, submerged_unit_weight=GAMMA, friction_angle=30.0)
    assert k == pytest.approx(0.5, rel=1e-15)
    f = model.load_vector().reshape(-1, dim)
    F = f.sum(axis=0)
    thrust = k * GAMMA * H**2 / 2 * width
    assert abs(F[0] - thrust) < 5e-15 * thrust
    assert np.abs(F[1:]).max() < 5e-15 * thrust
    height = float((model.mesh.points[:, -1] * f[:, 0]).sum() / F[0])
    assert abs(height - H / 3) < 5e-15 * H


def test_inclined_face() -> None:
    """An upstream face with a batter m = 0.25, silt H = 9 m deep, Ka = 0.3 given
    directly: F_x = Ka γ' H²/2 at H/3 above the heel; F_y = −γ' m H²/2, the weight of the
    silt wedge above the face, whose line of action is the wedge's centroid, m H/3 from
    the heel; to 5e-15 (measured 4e-17 to 4.8e-16)."""
    m, H, ka = 0.25, 9.0, 0.3
    model = _block(m)
    heel = np.array([-m * 12.0, 0.0])
    model.add_silt("xmin", level=H, submerged_unit_weight=GAMMA, k=ka)
    F, y_x, x_y = _resultant(model, heel)
    fx, fy = ka * GAMMA * H**2 / 2, -GAMMA * m * H**2 / 2
    assert abs(F[0] - fx) < 5e-15 * fx and abs(F[1] - fy) < 5e-15 * abs(fy)
    assert abs(y_x - H / 3) < 5e-15 * H  # the horizontal thrust's height above the heel
    assert abs(x_y - m * H / 3) < 5e-15 * H  # the weight's distance from the heel


def test_refused_arguments() -> None:
    model = _block(0.0)
    for kw in ({}, {"k": 0.5, "friction_angle": 30.0}, {"k": -1.0}, {"friction_angle": 95.0}):
        with pytest.raises(ModelError, match="silt"):
            model.add_silt("xmin", 5.0, GAMMA, **kw)  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="unit weight"):
        model.add_silt("xmin", 5.0, -1.0, k=0.5)


MODEL = """
[mesh]
file = "{mesh}"
[materials.concrete]
E = 30e9
nu = 0.2
rho = 2400.0
[blocks]
rock = "concrete"
dam = "concrete"
[interfaces.joint]
friction_angle = 45.0
[[supports]]
group = "bottom"
[[loads.silt]]
SILT
[analysis]
dynamic = false
[output]
folder = "out"
"""


def test_model_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """[[loads.silt]] in a model file builds the Python load (the same load vector); a
    table without a coefficient, with both, a bad group or a negative unit weight exits 2
    with a message naming the file and the key."""
    from pfeie.io import load_job
    from test_robustness import msh22

    nodes = [(x, y, 0) for y in (0, 1, 2) for x in (0, 1, 2)]
    names = {1: (2, "rock"), 2: (2, "dam"), 3: (1, "bottom"), 4: (1, "joint"),
             5: (1, "upstream")}  # fmt: skip
    els = [(1, 1, 3, [1, 2]), (2, 1, 3, [2, 3]), (3, 1, 4, [4, 5]), (4, 1, 4, [5, 6]),
           (5, 1, 5, [4, 7]), (10, 3, 1, [1, 2, 5, 4]), (11, 3, 1, [2, 3, 6, 5]),
           (12, 3, 2, [4, 5, 8, 7]), (13, 3, 2, [5, 6, 9, 8])]  # fmt: skip
    mesh = msh22(tmp_path / "m.msh", nodes, els, names)
    p = tmp_path / "model.toml"
    good = ('groups = ["upstream"]\nlevel = 2.5\nsubmerged_unit_weight = 9000.0\n'
            "friction_angle = 30.0")
    p.write_text(MODEL.format(mesh=mesh).replace("SILT", good))
    job = load_job(p)
    mdl = job.model
    ref = pf.Model(mdl.input_mesh, mdl.blocks, interfaces=mdl.interfaces)
    ref.add_gravity()
    ref.add_silt("upstream", 2.5, 9000.0, friction_angle=30.0)
    np.testing.assert_array_equal(mdl.load_vector(), ref.load_vector())
    assert np.abs(mdl.load_vector()).max() > 0
    assert main(["run", str(p), "--quiet"]) == 0
    capsys.readouterr()
    bad = {
        'groups = ["top"]\nlevel = 2.5\nsubmerged_unit_weight = 9000.0':
            "loads.silt[0].k: missing: give k (e.g. Ka) or friction_angle",
        good + "\nk = 0.4": "loads.silt[0]: give either k or friction_angle, not both",
        good.replace('"upstream"', '"nowhere"'):
            "loads.silt[0].groups: no physical group 'nowhere'",
        good.replace("9000.0", "-9000.0"): "loads.silt[0].submerged_unit_weight: expected a "
                                           "number in (0, 1e+06] N/m³",
    }  # fmt: skip
    for text, words in bad.items():
        p.write_text(MODEL.format(mesh=mesh).replace("SILT", text))
        assert main(["check", str(p)]) == 2
        err = capsys.readouterr().err
        assert str(p) in err and words in err, err
