"""Values in probable wrong units through the Python API and the model file: a
:class:`pfeie.Model` warns (``logging``, :mod:`pfeie.model._plausible`) of a Young's
modulus in GPa written without its exponent, a density in t/m³, a friction angle that is a
coefficient μ or an angle in radians, a mesh in millimetres; the model file says the same
once, naming its file and key. The references are the numbers written by hand in each
message (30 Pa × 1e9 = 3e10 Pa; atan 0.5236 = 27.6°; 0.5236 rad = 30.0°)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable
from pathlib import Path

import pytest

import pfeie as pf
from pfeie.cli import main
from test_robustness import ELEMENTS, MODEL, model

LOGGER = "pfeie.model._plausible"
CONCRETE = pf.Elastic(E=30e9, nu=0.2, rho=2400.0)


def _two_blocks(bottom: pf.Elastic, top: pf.Elastic, joint: pf.Joint | None = None,
                scale: float = 1.0, **kw: object) -> pf.Model:  # fmt: skip
    """A 2 m × 2 m square (× ``scale``) of a bottom and a top block, cut by the interface
    'mid' at half height when ``joint`` is given."""
    mesh = pf.rectangle(2.0 * scale, 2.0 * scale, 2, 2)
    mesh.add_cell_group("bottom", lambda x: x[:, 1] < scale)
    mesh.add_cell_group("top", lambda x: x[:, 1] > scale)
    itf = []
    if joint is not None:
        mesh.add_facet_group("mid", lambda x: abs(x[:, 1] - scale) < 1e-9, boundary_only=False)
        itf = [pf.Interface("mid", joint)]
    blocks = [pf.Block("bottom", bottom), pf.Block("top", top)]
    return pf.Model(mesh, blocks, interfaces=itf, **kw)  # type: ignore[arg-type]


def _warnings(caplog: pytest.LogCaptureFixture, build: Callable[[], object]) -> list[str]:
    """The messages of :data:`LOGGER` while ``build()`` runs; each is also a
    :class:`UserWarning` (a script shows those without configuring logging), pointing at
    this file's call of ``pf.Model``."""
    caplog.clear()
    with caplog.at_level("WARNING", logger=LOGGER), warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        build()
    logged = [r.getMessage() for r in caplog.records if r.name == LOGGER]
    shown = [x for x in w if issubclass(x.category, UserWarning)]
    assert [str(x.message) for x in shown] == logged
    assert all(x.filename == __file__ for x in shown), [x.filename for x in shown]
    return logged


#: the messages on a modulus and a density, after the names of their blocks
E_LOW = ("E = 30 Pa lies below 1e+06 Pa (concrete and rock: 1e9 to 1e11 Pa); pfeie takes SI "
         "units: did you mean 3e+10 (GPa) or 3e+07 (MPa)?")
RHO_LOW = ("rho = {v} kg/m³ lies below 500 kg/m³ (concrete and rock: 1800 to 3200); pfeie "
           "takes SI units: did you mean {meant} kg/m³ (t/m³ × 1000)?")


def test_api_warns_of_units(caplog: pytest.LogCaptureFixture) -> None:
    """Each mistake gives one warning with the numbers meant: E = 30 "GPa" (3e10 Pa or
    3e7 Pa), ρ = 2.4 "t/m³" (2400 kg/m³), E = 3e14 Pa (above 1e13 Pa), φ = 0.6 (μ = 0.6
    is atan 0.6 = 30.96° → 31.0°), φ = 0.5236 (μ: 27.64° → 27.6°; radians: 30.0004° →
    30.0°), φ = 0.6981 (μ: 34.92° → 34.9°; radians: 39.9985° → 40.0°), φ = radians(30)
    written out by Python, a residual angle of 40° above a peak of 30°, a mesh drawn in
    millimetres (2000 mm → 2e+04 m across with the scale 1e4 used here). A material shared
    by two blocks is warned once, naming both. A low density beside a normal one is a
    practically massless foundation (20 kg/m³, about 1 % of the rock's, or 0): not warned;
    2.4 kg/m³ beside it reads as t/m³ (in [1, 3.5]) and is; 20 kg/m³ alone is too (no
    normal density beside it: a unit weight of 20 kN/m³, 2039 kg/m³, meant? 20,000 kg/m³
    is no rock's). A concrete model gives none, nor the mistakes
    with ``check_units=False``."""
    soft = pf.Elastic(E=30.0, nu=0.2, rho=2400.0)
    tonnes = pf.Elastic(E=30e9, nu=0.2, rho=2.4)
    light = pf.Elastic(E=30e9, nu=0.2, rho=20.0)
    low = ("interface 'mid': phi = {v}° is very low (joints in concrete and rock: 20° to "
           "60°); the angle is in degrees: a friction coefficient μ = {v} is φ = {mu}°")
    meant = "; did you mean {deg}° (the value in radians)?"
    cases: list[tuple[dict[str, object], list[str]]] = [
        ({"bottom": soft}, [f"block 'bottom': {E_LOW}"]),
        ({"bottom": soft, "top": soft}, [f"blocks 'bottom', 'top': {E_LOW}"]),
        ({"bottom": tonnes, "top": tonnes},
         ["blocks 'bottom', 'top': " + RHO_LOW.format(v=2.4, meant=2400)]),
        ({"top": pf.Elastic(E=3e14, nu=0.2, rho=2400.0)},
         ["block 'top': E = 3e+14 Pa lies above 1e+13 Pa (concrete and rock: 1e9 to 1e11 "
          "Pa); pfeie takes SI units (Pa)"]),
        ({"bottom": light}, []),
        ({"bottom": pf.Elastic(E=30e9, nu=0.2, rho=0.0)}, []),
        ({"bottom": tonnes}, ["block 'bottom': " + RHO_LOW.format(v=2.4, meant=2400)]),
        ({"bottom": light, "top": light},
         ["blocks 'bottom', 'top': rho = 20 kg/m³ lies below 500 kg/m³ (concrete and rock: "
          "1800 to 3200); pfeie takes SI units: did you mean 2039 kg/m³ (a unit weight of 20 "
          "kN/m³ ÷ g)? A practically massless block (about 1 % of the rock's density) is "
          "fine"]),
        ({"joint": pf.Joint(phi=0.6)}, [low.format(v=0.6, mu="31.0")]),
        ({"joint": pf.Joint(phi=0.5236)},
         [low.format(v=0.5236, mu="27.6") + meant.format(deg="30.0")]),
        ({"joint": pf.Joint(phi=0.6981)},
         [low.format(v=0.6981, mu="34.9") + meant.format(deg="40.0")]),
        ({"joint": pf.Joint(phi=math.radians(30.0))},
         [low.format(v=0.523599, mu="27.6") + meant.format(deg="30.0")]),
        ({"joint": pf.Joint(phi=30.0, phi_r=40.0)},
         ["interface 'mid': phi_r = 40° exceeds its phi = 30°: the residual friction is "
          "usually at most the peak (the angles swapped?)"]),
        ({"scale": 1e4},
         ["the mesh spans 2e+04 m; pfeie takes coordinates in metres (a mesh drawn in "
          "millimetres must be scaled by 1e-3: gmsh's Mesh.ScalingFactor = 0.001)"]),
        ({"joint": pf.Joint(phi=30.0)}, []),
        # a cohesion and a tensile strength in MPa without their factor (0.3 and 0.2 MPa)
        ({"joint": pf.Joint(c=0.3, phi=40.0, tensile=0.2, initial="intact")},
         ["interface 'mid': c = 0.3 Pa is very low (joints in concrete and rock: 1e5 to 3e6 "
          "Pa); pfeie takes SI units: did you mean 300000 Pa (MPa) or 300 Pa (kPa)?",
          "interface 'mid': tensile = 0.2 Pa is very low (joints in concrete and rock: 1e5 "
          "to 3e6 Pa); pfeie takes SI units: did you mean 200000 Pa (MPa) or 200 Pa (kPa)?"]),
        ({"joint": pf.Joint(c=0.3e6, phi=40.0, tensile=0.2e6, initial="intact")}, []),
        # a concrete's tensile strength f_t in MPa (the DCR would be 1e6 times too large)
        ({"top": pf.Elastic(E=30e9, nu=0.2, rho=2400.0, tensile_strength=2.9)},
         ["block 'top': tensile_strength = 2.9 Pa is very low (concrete: 1e6 to 5e6 Pa); "
          "pfeie takes SI units: did you mean 2.9e+06 Pa (MPa)?"]),
        ({"bottom": soft, "top": tonnes, "joint": pf.Joint(phi=0.5236), "scale": 1e4,
          "check_units": False}, []),
    ]  # fmt: skip
    for kw, want in cases:
        args = {"bottom": CONCRETE, "top": CONCRETE, **kw}
        got = _warnings(caplog, lambda: _two_blocks(**args))  # type: ignore[arg-type]  # noqa: B023
        assert got == want, (kw, got)


def test_model_file_warns_once_with_its_key(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    """The model file's checks are the model's (one home), said once with the file and the
    key: ``friction_angle = 0.5236`` gives one warning naming
    ``interfaces.mid.friction_angle`` with μ = 0.5236 → 27.6° and 0.5236 rad → 30.0°,
    ``cohesion = 0.3`` one naming ``interfaces.mid.cohesion`` (0.3 MPa meant), ``E = 25``
    one naming ``materials.rock.E`` (2.5e+10 Pa meant); the model's own logger
    says nothing."""
    names = {1: (2, "left"), 2: (2, "right"), 3: (1, "bottom"), 4: (1, "mid"), 5: (1, "top")}
    elements = [*ELEMENTS[:-2], (10, 3, 1, [1, 2, 5, 4]), (11, 3, 2, [2, 3, 6, 5])]
    text = (MODEL.replace('all = "rock"', 'left = "rock"\nright = "rock"')
            .replace("E = 1e9", "E = 25")
            .replace("[[supports]]", "[interfaces.mid]\nfriction_angle = 0.5236\ncohesion = 0.3\n"
                     "[[supports]]"))
    p = model(tmp_path, text=text, elements=elements, names=names)
    caplog.clear()
    with caplog.at_level("WARNING"):
        assert main(["check", str(p)]) == 0
    capsys.readouterr()
    low = (f"{p}: interfaces.mid.friction_angle = 0.5236° is very low (joints in concrete and "
           "rock: 20° to 60°); the angle is in degrees: a friction coefficient μ = 0.5236 is "
           "φ = 27.6°; did you mean 30.0° (the value in radians)?")
    modulus = (f"{p}: materials.rock.E = 25 Pa lies below 1e+06 Pa (concrete and rock: 1e9 to "
               "1e11 Pa); pfeie takes SI units: did you mean 2.5e+10 (GPa) or 2.5e+07 (MPa)?")
    cohesion = (f"{p}: interfaces.mid.cohesion = 0.3 Pa is very low (joints in concrete and "
                "rock: 1e5 to 3e6 Pa); pfeie takes SI units: did you mean 300000 Pa (MPa) or "
                "300 Pa (kPa)?")
    messages = [r.getMessage() for r in caplog.records]
    assert messages.count(low) == 1 and messages.count(modulus) == 1, messages
    assert messages.count(cohesion) == 1, messages
    assert sum("is very low" in m for m in messages) == 2
    assert sum("lies below 1e+06 Pa" in m for m in messages) == 1
    assert not [r for r in caplog.records if r.name == LOGGER]


def test_a_damping_ratio_given_as_a_percentage_is_refused() -> None:
    """``Rayleigh.from_ratio(5.0, ...)`` (5 % meant) is refused, as the model file's
    ``damping.ratio = 5`` is, with the largest ratio and an example; 1 (critical damping)
    is taken: its ratio at the two frequencies is 1 to round-off."""
    with pytest.raises(pf.ModelError, match=r"zeta is a ratio of critical damping, at most "
                       r"1 \(0\.05 for 5 %\), got 5"):  # fmt: skip
        pf.Rayleigh.from_ratio(5.0, 3.0, 15.0)
    critical = pf.Rayleigh.from_ratio(1.0, 3.0, 15.0)
    assert critical.ratio(3.0) == pytest.approx(1.0, rel=1e-14)
    assert critical.ratio(15.0) == pytest.approx(1.0, rel=1e-14)


def test_the_model_files_joint_keys_name_the_python_ones() -> None:
    """``pf.Joint(cohesion=...)``, a key of the model file's ``[interfaces.<name>]``, is
    refused with the Python keyword (new-user finding: a bare TypeError with no hint);
    the model file's messages name its keys from the same table."""
    from pfeie.interface import MODEL_FILE_KEYS

    with pytest.raises(pf.ModelError, match=r"Joint: 'cohesion' is the model file's name; "
                       r"the Python keyword is 'c'"):  # fmt: skip
        pf.Joint(cohesion=0.3e6, phi=40.0)  # type: ignore[call-arg]
    for key, api in MODEL_FILE_KEYS.items():
        with pytest.raises(pf.ModelError, match=f"the Python keyword is '{api}'"):
            pf.Joint(**{key: 1.0})
        assert api in {f.name for f in dataclasses.fields(pf.Joint)}
    assert pf.Joint(c=0.3e6, phi=40.0).c == 0.3e6
