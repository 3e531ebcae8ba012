"""Values that are valid but probably not in the unit meant.

pfeie takes SI units (Pa, kg/m³, m) and friction angles in degrees. A Young's modulus in
GPa or MPa written without its exponent, a density in t/m³, a friction coefficient μ or an
angle in radians given as the friction angle, a mesh drawn in millimetres: each is valid
input that runs to a wrong answer (a weight 1000× off, a frictionless joint), so each gets
a warning with the value that was probably meant.

The checks have their one home here. A :class:`pfeie.Model` makes them when it is built
(:func:`warn_implausible`: warnings through this module's logger that name the block or
the interface, ``block 'dam': E = 30 Pa lies below ...``); the model file makes the same
checks naming its file and keys (``model.toml: materials.rock.E = 30 Pa lies below ...``)
and builds its model with ``check_units=False``, so that each is said once. The functions
return the messages and raise nothing: valid input stays valid.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence

import numpy as np

from ..element import reference
from ..interface import JointLaw
from ..mesh import Mesh
from ._physics import Block, Elastic, Interface

log = logging.getLogger(__name__)

#: Young's moduli outside this range (Pa) get a warning: concrete and rock lie within
#: 1 to 100 GPa, soils and weak rock down to some MPa (a modulus in GPa or MPa, written
#: without its exponent, falls far below)
E_RANGE = (1e6, 1e13)
#: densities outside this range (kg/m³) get a warning: concrete and rock lie within 1,800
#: to 3,200 kg/m³, soils down to about 1,400 (a density in t/m³ falls far below; a low
#: density beside normal ones is taken for a massless foundation and not warned, unless
#: it lies in :data:`RHO_TONNES`)
RHO_RANGE = (500.0, 2e4)
#: densities (kg/m³) that read as concrete or rock in t/m³: warned even beside normal
#: ones (a massless foundation takes 0 or about 1 % of the rock's density, 20 to 30)
RHO_TONNES = (1.0, 3.5)
#: densities (kg/m³) that read as the unit weight of concrete or rock in kN/m³ (÷ g)
UNIT_WEIGHT_KN = (14.0, 32.0)
#: friction angles below this (degrees) get a warning: joints in concrete and rock have
#: 20° to 60°, clay-filled ones down to about 10° (a friction coefficient μ, or an angle
#: in radians, entered as the angle falls below :data:`PHI_AS_NUMBER`)
PHI_MIN = 5.0
#: friction angles (degrees) below this may be another number: a friction coefficient μ
#: (0.2 to 1.7 on joints) or the angle in radians (20° to 60° are 0.35 to 1.05 rad)
PHI_AS_NUMBER = 2.0
#: the fewest decimals of an angle in radians written by hand (30° is 0.524 or 0.5236): a
#: value with fewer (a μ of 0.75 is 42.97° as radians) is not taken for radians
RADIANS_DECIMALS = 3
#: cohesions and tensile strengths of joints and materials above 0 and below this (Pa)
#: get a warning: joints in concrete and rock have 0.1 to 3 MPa, weak filled ones some
#: kPa, concrete's tensile strength 1 to 5 MPa (a strength in MPa or kPa written without
#: its factor falls below)
STRENGTH_MIN = 100.0

#: Poisson's ratios above this get a warning: a nearly incompressible material locks the
#: first-order cells (T3, Q4, Tet4, Hex8) volumetrically (a plane-strain Q4 cantilever
#: at ν = 0.4999 gave 8 to 24 % of its deflection; Q8 the exact one to 1e-3); concrete
#: and rock have 0.1 to 0.35
NU_LOCKING = 0.49
#: joint spring stiffnesses (k_n, k_s) above 0 and below this (Pa/m) get a warning: rock
#: and concrete joints have 1e9 to 1e12 Pa/m (1 to 1000 GPa/m), soft filled ones some
#: 1e8; a stiffness in MPa/m or GPa/m written without its factor falls below
STIFFNESS_MIN = 1e7
#: a mesh wider than this (m) gets a warning (a mesh in millimetres is 1000× too large)
EXTENT_MAX = 1e4
#: a mesh taller than this (m, along gravity) gets a warning: the highest dams stand about
#: 300 m on foundations modelled to a few times that, rock slopes reach about 1 km; a
#: block of 2 m or more drawn in millimetres lies above
HEIGHT_MAX = 2e3

#: the names of a joint law's parameters in the messages of the Python API (the model
#: file names its keys, ``friction_angle``, ``cohesion``, ...)
JOINT_KEYS = {
    "phi": "phi",
    "phi_r": "phi_r",
    "c": "c",
    "tensile": "tensile",
    "c_r": "c_r",
    "tensile_r": "tensile_r",
    "kn": "kn",
    "ks": "ks",
}


def locking_cells(mesh: Mesh, plane: str = "strain", groups: Iterable[str] | None = None,
                  ) -> bool:  # fmt: skip
    """Whether the ``mesh`` (or its cell ``groups``, where given: the blocks of one
    material) has first-order cells (T3, Q4, Tet4, Hex8) that a nearly incompressible
    material locks: not in 2D plane stress, where λ* stays finite. A group the mesh lacks
    counts as none (the model's own checks name it)."""
    if mesh.dim == 2 and plane == "stress":
        return False
    if groups is None:
        return any(reference(t).degree == 1 for t, conn in mesh.cells.items() if len(conn))
    return any(reference(t).degree == 1 and len(idx)
               for g in groups for t, idx in mesh.cell_groups.get(g, {}).items())  # fmt: skip


def implausible_materials(
    materials: Mapping[str, Elastic], prefix: Callable[[str], str],
    locking: bool | Callable[[str], bool] = True,
) -> list[str]:  # fmt: skip
    """Warnings on the moduli and densities of ``materials`` (name → material) outside
    :data:`E_RANGE` and :data:`RHO_RANGE`, on Poisson's ratios above :data:`NU_LOCKING`
    where the mesh has cells that lock (``locking``: :func:`locking_cells`, for all
    materials or, as a function of the name, for the cells of each) and on tensile
    strengths below :data:`STRENGTH_MIN`, with the value probably meant where there is
    one; ``prefix(name)``
    starts a material's messages (its key path, before ``E`` and ``rho``).

    A density below the range beside a material of normal density is a practically
    massless foundation, a common choice: it is warned only when it lies in
    :data:`RHO_TONNES` (t/m³) or no material has a normal density.

    >>> implausible_materials({"rock": Elastic(30.0, 0.2, 2.4)}, lambda n: f"{n}.")[0]
    'rock.E = 30 Pa lies below 1e+06 Pa (concrete and rock: 1e9 to 1e11 Pa); pfeie takes SI units: did you mean 3e+10 (GPa) or 3e+07 (MPa)?'
    """  # noqa: E501
    out = []
    lo, hi = E_RANGE
    for name, mt in materials.items():
        modulus = float(mt.E)
        if modulus < lo:
            out.append(f"{prefix(name)}E = {modulus:g} Pa lies below {lo:g} Pa (concrete and "
                       "rock: 1e9 to 1e11 Pa); pfeie takes SI units: did you mean "
                       f"{modulus * 1e9:g} (GPa) or {modulus * 1e6:g} (MPa)?")  # fmt: skip
        elif modulus > hi:
            out.append(f"{prefix(name)}E = {modulus:g} Pa lies above {hi:g} Pa (concrete and "
                       "rock: 1e9 to 1e11 Pa); pfeie takes SI units (Pa)")  # fmt: skip
    lo, hi = RHO_RANGE
    normal = any(lo <= float(mt.rho) <= hi for mt in materials.values())
    for name, mt in materials.items():
        rho = float(mt.rho)
        tonnes = RHO_TONNES[0] <= rho <= RHO_TONNES[1]
        if 0.0 < rho < lo and (not normal or tonnes):
            # the value meant where it reads as t/m³ or as a unit weight in kN/m³ (÷ g);
            # else a practically massless block on purpose?
            if tonnes:
                meant = f"did you mean {rho * 1e3:g} kg/m³ (t/m³ × 1000)?"
            elif UNIT_WEIGHT_KN[0] <= rho <= UNIT_WEIGHT_KN[1]:
                meant = (f"did you mean {rho * 1e3 / 9.81:.0f} kg/m³ (a unit weight of "
                         f"{rho:g} kN/m³ ÷ g)? A practically massless block (about 1 % of "
                         "the rock's density) is fine")  # fmt: skip
            else:
                meant = "a practically massless block (about 1 % of the rock's density) is fine"
            out.append(f"{prefix(name)}rho = {rho:g} kg/m³ lies below {lo:g} kg/m³ (concrete "
                       f"and rock: 1800 to 3200); pfeie takes SI units: {meant}")  # fmt: skip
        elif rho > hi:
            out.append(f"{prefix(name)}rho = {rho:g} kg/m³ lies above {hi:g} kg/m³ (concrete "
                       "and rock: 1800 to 3200); pfeie takes SI units (kg/m³)")  # fmt: skip
    for name, mt in materials.items():
        locks = locking(name) if callable(locking) else locking
        if locks and float(mt.nu) > NU_LOCKING:
            out.append(f"{prefix(name)}nu = {float(mt.nu):g} is nearly incompressible "
                       "(concrete and rock: 0.1 to 0.35): the mesh's first-order cells (T3, "
                       "Q4, Tet4, Hex8) lock and come out far too stiff; take quadratic "
                       "cells (T6, Q8, Tet10), which lock far less, or the material's "
                       "drained ratio")  # fmt: skip
    for name, mt in materials.items():
        ft = mt.tensile_strength
        if ft is not None and 0.0 < float(ft) < STRENGTH_MIN:  # f_t in MPa: DCR × 1e6
            ft = float(ft)
            out.append(f"{prefix(name)}tensile_strength = {ft:g} Pa is very low (concrete: "
                       "1e6 to 5e6 Pa); pfeie takes SI units: did you mean "
                       f"{ft * 1e6:g} Pa (MPa)?")  # fmt: skip
    return out


def radians_meant(phi: float) -> float | None:
    """The whole degree that a friction angle ``phi`` below :data:`PHI_AS_NUMBER` degrees
    is when read as radians, to the precision ``phi`` is written with (½ of its last
    decimal, :data:`RADIANS_DECIMALS` decimals or more); else None.

    >>> radians_meant(0.5236), radians_meant(0.6981), radians_meant(0.75), radians_meant(0.6)
    (30.0, 40.0, None, None)
    """
    if not 0.0 < phi < PHI_AS_NUMBER:
        return None
    text = repr(float(phi))
    if "e" in text:  # 1e-05: no angle in radians
        return None
    decimals = len(text.partition(".")[2])
    if decimals < RADIANS_DECIMALS:
        return None
    deg = float(np.degrees(phi))
    tol = max(float(np.degrees(0.5 * 10.0**-decimals)), 1e-9)
    return float(round(deg)) if abs(deg - round(deg)) <= tol else None


def implausible_joints(joints: Mapping[str, JointLaw], prefix: Callable[[str], str],
                       keys: Mapping[str, str] = JOINT_KEYS) -> list[str]:  # fmt: skip
    """Warnings on the strengths and friction angles of ``joints`` (name → law): a
    cohesion or tensile strength above 0 and below :data:`STRENGTH_MIN` (in MPa or kPa,
    the factor left out); for laws with a friction angle ``phi``, an angle above 0 and
    below :data:`PHI_MIN` (a friction
    coefficient μ, the angle atan μ given; or an angle in radians, :func:`radians_meant`),
    and a residual angle above the peak one (the two swapped?). ``prefix(name)`` starts a
    joint's messages, ``keys`` names ``phi``, ``phi_r``, ``c``, ``tensile``, ``c_r`` and
    ``tensile_r`` in them.

    >>> from pfeie.interface import Joint
    >>> implausible_joints({"j": Joint(phi=0.5236)}, lambda n: f"interface {n!r}: ")[0]
    "interface 'j': phi = 0.5236° is very low (joints in concrete and rock: 20° to 60°); the angle is in degrees: a friction coefficient μ = 0.5236 is φ = 27.6°; did you mean 30.0° (the value in radians)?"
    """  # noqa: E501
    out = []
    for name, law in joints.items():
        for key in ("c", "tensile", "c_r", "tensile_r"):
            value = getattr(law, key, None)
            if value is not None and 0.0 < float(value) < STRENGTH_MIN:
                value = float(value)
                mpa, kpa = value * 1e6, value * 1e3
                out.append(f"{prefix(name)}{keys[key]} = {value:g} Pa is very low (joints in "
                           "concrete and rock: 1e5 to 3e6 Pa); pfeie takes SI units: did you "
                           f"mean {mpa:g} Pa (MPa) or {kpa:g} Pa (kPa)?")  # fmt: skip
        for key in ("kn", "ks"):
            value = getattr(law, key, None)
            if value is not None and 0.0 < float(value) < STIFFNESS_MIN:
                value = float(value)
                out.append(f"{prefix(name)}{keys[key]} = {value:g} Pa/m is very low (rock and "
                           "concrete joints: 1e9 to 1e12 Pa/m); pfeie takes SI units: did "
                           f"you mean {value * 1e6:g} Pa/m (MPa/m) or {value * 1e9:g} Pa/m "
                           "(GPa/m)?")  # fmt: skip
        phi, phi_r = getattr(law, "phi", None), getattr(law, "phi_r", None)
        if phi is None:
            continue
        for key, angle in (("phi", phi), ("phi_r", phi_r)):
            if angle is None or not 0.0 < float(angle) < PHI_MIN:
                continue
            angle = float(angle)
            text = (f"{prefix(name)}{keys[key]} = {angle:g}° is very low (joints in concrete "
                    "and rock: 20° to 60°); the angle is in degrees: a friction coefficient "
                    f"μ = {angle:g} is φ = {np.degrees(np.arctan(angle)):.1f}°")  # fmt: skip
            meant = radians_meant(angle)
            if meant is not None:
                text += f"; did you mean {meant:.1f}° (the value in radians)?"
            out.append(text)
        if phi_r is not None and float(phi_r) > float(phi):
            # a residual friction above the peak: the joint would strengthen as it breaks
            out.append(f"{prefix(name)}{keys['phi_r']} = {float(phi_r):g}° exceeds its "
                       f"{keys['phi']} = {float(phi):g}°: the residual friction is usually at "
                       "most the peak (the angles swapped?)")  # fmt: skip
    return out


def implausible_gravity(g: float) -> str | None:
    """A warning on a gravity acceleration g (m/s²) far from the Earth's (below 9 or above
    11 m/s², not 0): given in g or in cm/s²?

    >>> implausible_gravity(981.0)
    "g = 981 m/s² is not the Earth's 9.81 m/s²: pfeie takes m/s² (1 g is 9.81 m/s², 981 cm/s² is 9.81 m/s²)"
    """  # noqa: E501
    if 0 < g < 9 or g > 11:
        return (
            f"g = {g:g} m/s² is not the Earth's 9.81 m/s²: pfeie takes m/s² (1 g is 9.81 "
            "m/s², 981 cm/s² is 9.81 m/s²)"
        )
    return None


#: water densities outside this range (kg/m³) get a warning: fresh water 1,000, sea water
#: 1,025, a reservoir's sediment-laden water some tens more (a density in t/m³, or a unit
#: weight in N/m³ or kN/m³ given as the density, falls far outside)
WATER_DENSITY = (950.0, 1250.0)
#: submerged unit weights of silt above this (N/m³) get a warning: silts lie at 4,000 to
#: 12,000 N/m³ submerged, 14,000 to 21,000 saturated (γ' = γ_sat − γ_w)
SILT_SUBMERGED_MAX = 14000.0


def implausible_water(density: float) -> str | None:
    """A warning on a water density (kg/m³) outside :data:`WATER_DENSITY`, with the value
    probably meant: t/m³, or a unit weight (ρ g) in N/m³ or kN/m³.

    >>> print(implausible_water(1.0))
    density = 1 kg/m³ is not water's (fresh 1000, sea 1025 kg/m³): pfeie takes kg/m³: did you mean 1000 kg/m³ (t/m³ × 1000)?
    >>> implausible_water(9810.0).endswith("did you mean 1000 kg/m³ (the unit weight ρ g = 9810 N/m³, ÷ g)?")
    True
    >>> implausible_water(1000.0) is None
    True
    """  # noqa: E501
    lo, hi = WATER_DENSITY
    if lo <= density <= hi:
        return None
    meant = ""
    if 0.9 <= density <= 1.3:
        meant = f": did you mean {density * 1e3:g} kg/m³ (t/m³ × 1000)?"
    elif 9.0 <= density <= 12.5:
        meant = (f": did you mean {density * 1e3 / 9.81:.0f} kg/m³ (the unit weight ρ g = "
                 f"{density:g} kN/m³, × 1000 ÷ g)?")  # fmt: skip
    elif 9000.0 <= density <= 12500.0:
        meant = (f": did you mean {density / 9.81:.0f} kg/m³ (the unit weight ρ g = "
                 f"{density:g} N/m³, ÷ g)?")  # fmt: skip
    return (f"density = {density:g} kg/m³ is not water's (fresh 1000, sea 1025 kg/m³): pfeie "
            f"takes kg/m³{meant}")  # fmt: skip


def implausible_silt(submerged_unit_weight: float) -> str | None:
    """A warning on a silt's submerged unit weight above :data:`SILT_SUBMERGED_MAX`
    (N/m³): its saturated unit weight, which does not subtract the water's?

    >>> implausible_silt(19000.0)[:60]
    'submerged_unit_weight = 19000 N/m³ lies above 14000 N/m³ (su'
    """
    if submerged_unit_weight <= SILT_SUBMERGED_MAX:
        return None
    return (f"submerged_unit_weight = {submerged_unit_weight:g} N/m³ lies above "
            f"{SILT_SUBMERGED_MAX:g} N/m³ (submerged silts: 4000 to 12000 N/m³): a saturated "
            "unit weight? The water's pressure is the reservoir's (its hydrostatic load); "
            f"the silt adds γ' = γ_sat − γ_w, here {submerged_unit_weight - 9810.0:g} N/m³ "
            "with γ_w = 9810")  # fmt: skip


def implausible_mesh(mesh: Mesh, prefix: str = "") -> list[str]:
    """A warning on a mesh wider than :data:`EXTENT_MAX` or taller than
    :data:`HEIGHT_MAX` (along the last axis, the vertical one): drawn in millimetres?
    ``prefix`` starts the message."""
    spans = np.ptp(mesh.points, axis=0)
    extent, height = float(spans.max(initial=0.0)), float(spans[mesh.dim - 1])
    if not (extent > EXTENT_MAX or height > HEIGHT_MAX):
        return []
    what = (f"spans {extent:.4g} m" if extent > EXTENT_MAX else
            f"is {height:.4g} m tall (along {'yz'[mesh.dim - 2]})")  # fmt: skip
    return [f"{prefix}the mesh {what}; pfeie takes coordinates in metres (a mesh drawn in "
            "millimetres must be scaled by 1e-3: gmsh's Mesh.ScalingFactor = 0.001)"]  # fmt: skip


def warn_implausible(mesh: Mesh, blocks: Sequence[Block], interfaces: Sequence[Interface],
                     plane: str = "strain") -> list[str]:  # fmt: skip
    """The checks of a model built in Python (:class:`pfeie.Model`), each a warning of
    this module's logger and a :class:`UserWarning` (shown by a plain script): the
    materials of ``blocks`` (one message per distinct material, naming the blocks that
    have it), the joint laws of ``interfaces``, the ``mesh``'s size. Returns the
    messages."""
    users: dict[Elastic, list[Block]] = {}
    for b in blocks:
        users.setdefault(b.material, []).append(b)
    mats, groups = {}, {}  # by the label "block(s) 'a', 'b'": the material, the cell groups
    for m, bs in users.items():
        label = f"block{'s' if len(bs) > 1 else ''} {', '.join(repr(b.name) for b in bs)}"
        mats[label], groups[label] = m, [b.cell_group for b in bs]
    out = [
        *implausible_materials(mats, lambda name: f"{name}: ",
                               lambda name: locking_cells(mesh, plane, groups[name])),
        *implausible_joints({i.group: i.joint for i in interfaces},
                            lambda name: f"interface {name!r}: "),
        *implausible_mesh(mesh),
    ]  # fmt: skip
    for text in out:
        log.warning("%s", text)
        # and as a Python warning, which a script shows without configuring logging (the
        # library's logger has a null handler), at the user's call that built the model
        warnings.warn(text, UserWarning, stacklevel=3)
    return out
