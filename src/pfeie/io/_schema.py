"""The model file as typed settings: pydantic models, their messages, their reference.

:class:`ModelFile` is the whole TOML file; each table is a frozen model that refuses
unknown keys and non-finite numbers (``inf``, ``nan``, ``1e400``). The ``[analysis]``
table is :class:`Analysis`, a :class:`pfeie.dynamics.DynamicSettings` (so its defaults
are the Python API's) with the keys only a model file has (static, dynamic, duration,
form). Three views derive from the models and from nothing else:

- :func:`messages`: a pydantic ``ValidationError`` as lines that name the key path, what
  was expected and what was found (``materials.concrete.E: expected a number, found a
  string 'stiff'``);
- :func:`reference_rows`: key path, expected, default and meaning of every key (the
  table of docs/model-file.md);
- :func:`json_schema`: the JSON Schema of a model file (for editors: taplo, Even Better
  TOML).
"""

from __future__ import annotations

import math
import types
import typing
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Annotated, Any, Literal, NamedTuple, Union

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    WithJsonSchema,
    model_validator,
)
from pydantic.fields import FieldInfo
from pydantic.json_schema import GenerateJsonSchema, JsonSchemaValue
from pydantic_core import PydanticCustomError, core_schema

from ..dynamics import DynamicSettings
from ..interface import JOINT_STIFFNESS_MIN
from ..model import DAMPING_RATIO_MAX, STRENGTH_MIN
from ..typing import Unit


@dataclass(frozen=True)
class Expect:
    """What a value must be, in words, when the type and bounds do not say it well."""

    text: str


_CONFIG = ConfigDict(frozen=True, extra="forbid", strict=True, allow_inf_nan=False)


def _distinct(v: list[str]) -> list[str]:
    twice = sorted({g for g in v if v.count(g) > 1})
    if twice:
        raise ValueError(f"{', '.join(repr(g) for g in twice)} listed twice: a group's load "
                         "would count twice; expected each group once")  # fmt: skip
    return v


def _nonzero(v: float) -> float:
    if v == 0.0:
        raise ValueError("a scale of 0 removes the record; expected a non-zero number")
    return v


Vector = Annotated[list[float], Field(min_length=2, max_length=3),
                   Expect("an array of 2 to 3 numbers")]  # fmt: skip
Angle = Annotated[float, Field(ge=0.0, lt=90.0), Expect("an angle in [0, 90) degrees")]
Positive = Annotated[float, Field(gt=0.0)]
NonNegative = Annotated[float, Field(ge=0.0)]
# physical ranges wide enough for any structure on Earth (and for stiff penalty blocks and
# joints), so that a slip of the exponent is caught here, not as a "numerically singular"
# system or a silent nonsense later; each with its unit, which the messages print
Modulus = Annotated[float, Field(gt=0.0, le=1e16), Unit("Pa")]
Density = Annotated[float, Field(ge=0.0, le=1e6), Unit("kg/m³")]
FluidDensity = Annotated[float, Field(gt=0.0, le=1e5), Unit("kg/m³")]
Elevation = Annotated[float, Field(ge=-1e6, le=1e6), Unit("m")]
Distance = Annotated[float, Field(ge=0.0, le=1e6), Unit("m")]
Length = Annotated[float, Field(gt=0.0, le=1e6), Unit("m")]
#: a 2D model's out-of-plane thickness: a micrometre to 1000 km (a thinner one underflows
#: the facets' area-weighted normals, 1e-202 m gave NaN normals)
Thickness = Annotated[float, Field(ge=1e-6, le=1e6), Unit("m")]
Displacement = Annotated[float, Field(ge=-1e3, le=1e3), Unit("m")]
Stress = Annotated[float, Field(ge=-1e10, le=1e10), Unit("Pa")]
Strength = Annotated[float, Field(ge=0.0, le=1e10), Unit("Pa")]
PositiveStrength = Annotated[float, Field(gt=0.0, le=1e10), Unit("Pa")]
JointStiffness = Annotated[float, Field(ge=JOINT_STIFFNESS_MIN, le=1e20), Unit("Pa/m")]
UnitWeight = Annotated[float, Field(gt=0.0, le=1e6), Unit("N/m³")]
#: N/m³, the least submerged unit weight of a silt (a value in kN/m³ falls below)
SILT_UNIT_WEIGHT_MIN = 1000.0


def yield_label(direction: str | Sequence[float]) -> str:
    """The label of a yield coefficient's direction as the model file gives it (its key
    in summary.json): '+x' as written, a vector as "[0.6, 0.8, 0]"."""
    if isinstance(direction, str):
        return direction
    return "[" + ", ".join(f"{float(v):g}" for v in direction) + "]"


def _path_text(v: str) -> str:
    if not v.strip():
        raise ValueError(f"expected a path, found {'an empty' if not v else 'a blank'} string")
    if "\x00" in v:
        raise ValueError(f"expected a path, found a string with a NUL character {v!r}")
    return v


#: a file or folder name: any string but a blank one or one with a NUL character (no OS
#: takes it)
PathText = Annotated[str, AfterValidator(_path_text)]


def _folder_text(v: str) -> str:
    if not v.strip():
        raise ValueError(
            "expected a folder path, found an empty string (the default: "
            '"results" beside the model file)'
        )
    return _path_text(v)


def _check(key: str, text: str) -> PydanticCustomError:
    """A cross-key error of a table, reported at ``<table>.<key>``."""
    return PydanticCustomError("pfeie_check", "{key}: {text}", {"key": key, "text": text})


class _Table(BaseModel):
    model_config = _CONFIG


class MeshFile(_Table):
    """``[mesh]``: the gmsh mesh."""

    file: Annotated[
        PathText,
        Field(
            description="gmsh mesh (.msh 2.2 or 4.1) whose physical groups name the blocks "
            "(surfaces in 2D, volumes in 3D) and the interfaces and faces (curves in 2D, "
            "surfaces in 3D)"
        ),
    ]


class Material(_Table):
    """``[materials.<name>]``: an isotropic elastic material."""

    E: Annotated[Modulus, Field(description="Young's modulus (Pa)")]
    nu: Annotated[float, Field(gt=-1.0, lt=0.5, description="Poisson's ratio")]
    rho: Annotated[Density, Field(description="density (kg/m³)")]
    tensile_strength: Annotated[
        PositiveStrength | None,
        Field(description="tensile strength f_t (Pa) for the demand-capacity ratio σ₁/f_t "
              "and the cumulative inelastic duration of USACE EM 1110-2-6053 (for an "
              "earthquake the dynamic strength, about 1.5 × the static); changes no "
              "stiffness; default none: not evaluated"),
    ] = None  # fmt: skip


class Damping(_Table):
    """``[damping]``: Rayleigh damping, by its coefficients or by a ratio at two
    frequencies."""

    alpha: Annotated[
        float, Field(ge=0.0, le=1e4), Unit("1/s"),
        Field(description="Rayleigh mass coefficient α (1/s)"),
    ] = 0.0  # fmt: skip
    beta: Annotated[
        float, Field(ge=0.0, le=1.0), Unit("s"),
        Field(description="Rayleigh stiffness coefficient β (s)"),
    ] = 0.0  # fmt: skip
    ratio: Annotated[
        float | None, Field(ge=0.0, le=DAMPING_RATIO_MAX),
        Field(description="damping ratio ζ at the two frequencies (instead of alpha, beta)"),
    ] = None  # fmt: skip
    frequencies: Annotated[
        list[float] | None, Field(min_length=2, max_length=2),
        Expect("an array of 2 numbers"), Field(description="the two frequencies (Hz) for 'ratio'"),
    ] = None  # fmt: skip
    deformation_only: Annotated[
        bool,
        Field(description="the mass-proportional part spares the rigid motion of the "
              "floating blocks (no drag on sliding or rocking; their deformation keeps its "
              "ratio)"),
    ] = False  # fmt: skip

    @model_validator(mode="after")
    def _ratio_or_coefficients(self) -> Damping:
        if self.ratio is not None:
            if self.frequencies is None:
                raise _check("frequencies", "missing (required with ratio)")
            f1, f2 = self.frequencies
            if not (0 < f1 <= 1e4 and 0 < f2 <= 1e4 and f1 != f2):
                raise _check("frequencies", f"expected two distinct frequencies in (0, 1e+04] Hz, "
                             f"found {list(self.frequencies)}")  # fmt: skip
            if self.alpha or self.beta:
                raise _check("", "give either ratio and frequencies or alpha and beta, not both")
        elif self.frequencies is not None:  # else ignored: no damping, or alpha and beta only
            raise _check("ratio", "missing (required with frequencies: the damping ratio at "
                         "the two frequencies, e.g. ratio = 0.05)")  # fmt: skip
        return self


class Joint(_Table):
    """``[interfaces.<name>]``: the joint of a physical group (Mohr-Coulomb with a
    tension cut-off, or slip weakening)."""

    friction_angle: Annotated[Angle, Field(description="friction angle φ (degrees)")]
    cohesion: Annotated[Strength, Field(description="cohesion c of the intact joint (Pa)")] = 0.0
    tensile_strength: Annotated[
        Strength,
        Field(description="tensile strength σ_t of the intact joint (Pa), at most cohesion / "
              "tan(friction_angle)"),
    ] = 0.0  # fmt: skip
    residual_cohesion: Annotated[Strength, Field(description="cohesion once broken (Pa)")] = 0.0
    residual_friction_angle: Annotated[
        Angle | None,
        Field(
            description="friction angle once broken (degrees); default: friction_angle; with "
            "law = 'slip-weakening', the angle reached after weakening_distance of slip"
        ),
    ] = None
    residual_tensile_strength: Annotated[
        Strength,
        Field(description="tensile strength once broken (Pa), at most residual_cohesion / "
              "tan(residual_friction_angle)"),
    ] = 0.0  # fmt: skip
    initial: Annotated[
        Literal["intact", "broken"],
        Field(description="initial state: 'intact' (bonded) or 'broken' (an existing joint)"),
    ] = "broken"
    normal_stiffness: Annotated[
        JointStiffness | None,
        Field(description="normal stiffness k_n of a weak layer (Pa/m); none: rigid contact"),
    ] = None
    shear_stiffness: Annotated[
        JointStiffness | None, Field(description="shear stiffness k_s of a weak layer (Pa/m)")
    ] = None
    law: Annotated[
        Literal["mohr-coulomb", "slip-weakening"],
        Field(
            description="friction law: 'mohr-coulomb' (constant residual friction angle) or "
            "'slip-weakening' (the friction angle falls linearly from friction_angle to "
            "residual_friction_angle over weakening_distance of slip)"
        ),
    ] = "mohr-coulomb"
    weakening_distance: Annotated[
        Length | None,
        Field(
            description="slip over which the friction angle weakens (m); required with "
            "law = 'slip-weakening', refused otherwise"
        ),
    ] = None

    @model_validator(mode="after")
    def _weakening(self) -> Joint:
        if self.law == "slip-weakening" and self.weakening_distance is None:
            raise _check("weakening_distance", "missing (required with law = 'slip-weakening')")
        if self.law != "slip-weakening" and self.weakening_distance is not None:
            raise _check("weakening_distance", f"only with law = 'slip-weakening' (law is "
                         f"{self.law!r})")  # fmt: skip
        return self

    @model_validator(mode="after")
    def _apex(self) -> Joint:
        """A tensile strength beyond the apex of its Mohr-Coulomb cone, c / tan φ, is
        refused: a pair in tension beyond it has no shear capacity (it would break in shear
        first, so the strength given would never act). The intact strength is checked for
        an intact joint, the residual one always (a broken pair's friction is at most the
        peak's with slip weakening)."""
        phi_r = self.friction_angle if self.residual_friction_angle is None else (
            self.residual_friction_angle)  # fmt: skip
        broken = ("residual_friction_angle" if self.residual_friction_angle is not None else
                  "friction_angle", phi_r)  # fmt: skip
        if self.law == "slip-weakening" and self.friction_angle > phi_r:
            broken = ("friction_angle", self.friction_angle)  # the peak, where it starts
        checks = [("tensile_strength", "cohesion", "an intact", ("friction_angle",
                   self.friction_angle))] if self.initial == "intact" else []  # fmt: skip
        checks.append(("residual_tensile_strength", "residual_cohesion", "a broken", broken))
        for tkey, ckey, which, (pkey, phi) in checks:
            t, c = float(getattr(self, tkey)), float(getattr(self, ckey))
            mu = math.tan(math.radians(phi))
            if t * mu > c * (1.0 + 1e-12):
                apex = c / mu
                state = "intact" if tkey == "tensile_strength" else "residual"
                # a cohesion in MPa or kPa written without its factor: say so first
                unit = (f"{ckey} = {c:g} Pa is very low: given in MPa ({c * 1e6:g} Pa) or "
                        f"kPa ({c * 1e3:g} Pa)? pfeie takes SI units. "
                        if 0.0 < c < STRENGTH_MIN <= t else "")  # fmt: skip
                raise _check(tkey, f"{unit}{t:g} Pa lies beyond the apex of the {state} "
                             f"strength, {ckey} / tan({pkey}) = {apex:g} Pa ({ckey} = {c:g} "
                             f"Pa, {pkey} = {phi:g}°): {which} pair in tension beyond it has "
                             f"no shear capacity; expected {tkey} <= {apex:g} Pa (0 without "
                             f"{ckey})")  # fmt: skip
        return self


class Support(_Table):
    """``[[supports]]``: fixed or prescribed displacements of a physical group."""

    group: Annotated[str, Field(description="physical group whose nodes are supported")]
    components: Annotated[
        list[Literal["x", "y", "z"]] | None, Field(min_length=1),
        Expect("an array of 'x', 'y', 'z'"),
        Field(description="supported components, e.g. ['x', 'y']; default: all"),
    ] = None  # fmt: skip
    value: Annotated[Displacement, Field(description="prescribed displacement (m)")] = 0.0


class Pressure(_Table):
    """``[[loads.pressure]]``: a uniform pressure on faces."""

    group: Annotated[str, Field(description="physical group of faces, or an interface: the "
                                "pressure acts in the joint, on both its faces (water in "
                                "the joint, pushing the blocks apart)")]  # fmt: skip
    value: Annotated[Stress, Field(description="pressure (Pa), positive pushing into the body")]


class Hydrostatic(_Table):
    """``[[loads.hydrostatic]]``: water pressure on faces."""

    groups: Annotated[list[str], Field(min_length=1), Expect("an array of group names"),
                      AfterValidator(_distinct),
                      Field(description="physical groups of wetted faces, or interfaces: "
                            "the water pressure ρ g (h − z) in the joint, on both its faces "
                            "(a water table in a rock slope's joints)")]  # fmt: skip
    water_level: Annotated[Elevation, Field(description="water level (m, on the vertical axis)")]
    density: Annotated[FluidDensity, Field(description="water density (kg/m³)")] = 1000.0


class Silt(_Table):
    """``[[loads.silt]]``: silt against faces (pfeie.Model.add_silt)."""

    groups: Annotated[list[str], Field(min_length=1), Expect("an array of group names"),
                      AfterValidator(_distinct),
                      Field(description="physical groups of the faces the silt lies "
                            "against (the upstream face, the reservoir floor)")]  # fmt: skip
    level: Annotated[Elevation, Field(description="elevation of the silt surface (m, on the "
                                  "vertical axis)")]  # fmt: skip
    submerged_unit_weight: Annotated[
        UnitWeight, Field(description="submerged unit weight γ' of the silt (N/m³): its "
                        "saturated unit weight less the water's")
    ]  # fmt: skip
    k: Annotated[
        float | None, Field(gt=0.0, le=100.0),
        Field(description="lateral pressure coefficient K (e.g. the active Ka): horizontal "
              "pressure K γ' (level − z); instead of friction_angle"),
    ] = None  # fmt: skip
    friction_angle: Annotated[
        Angle | None,
        Field(description="friction angle φ of the silt (degrees): K at rest, "
              "K0 = 1 − sin φ; instead of k"),
    ] = None  # fmt: skip

    @model_validator(mode="after")
    def _one_coefficient(self) -> Silt:
        if self.k is None and self.friction_angle is None:
            raise _check("k", "missing: give k (e.g. Ka) or friction_angle (at rest: "
                         "K0 = 1 − sin φ)")  # fmt: skip
        if self.k is not None and self.friction_angle is not None:
            raise _check("", "give either k or friction_angle, not both")
        if self.submerged_unit_weight < SILT_UNIT_WEIGHT_MIN:
            w = self.submerged_unit_weight
            raise _check("submerged_unit_weight", f"{w:g} N/m³ is below "
                         f"{SILT_UNIT_WEIGHT_MIN:g} N/m³ (silts: about 4000 to 12000 N/m³); "
                         f"pfeie takes N/m³: did you mean {1e3 * w:g} (kN/m³)?")  # fmt: skip
        return self


class Westergaard(_Table):
    """``[[loads.westergaard]]``: the reservoir's added mass on wet faces, by Westergaard's
    closed form or by an incompressible finite-element reservoir."""

    groups: Annotated[list[str], Field(min_length=1), Expect("an array of group names"),
                      AfterValidator(_distinct),
                      Field(description="physical groups of the wet faces of the dam")]  # fmt: skip
    water_level: Annotated[Elevation, Field(description="water level (m, on the vertical axis)")]
    model: Annotated[
        Literal["westergaard", "fe"],
        Field(description="'westergaard': the closed form 7/8 ρ_w √(H (level − z)) along the "
              "faces' normal, lumped; 'fe': an incompressible finite-element reservoir on a "
              "mesh of the water drawn from the wet face (2D only), its full added-mass "
              "matrix in the modal analysis and in the time stepping (only the position "
              "correction's metric takes its row sums)"),
    ] = "westergaard"  # fmt: skip
    bottom: Annotated[
        Elevation | None,
        Field(description="elevation of the reservoir bottom (m); default the lowest point "
              "of the wet faces; the faces below it (in the foundation or the silt) get no "
              "added mass (model = 'westergaard' only: the finite-element reservoir's "
              "bottom is the lowest point of its wet faces)"),
    ] = None  # fmt: skip
    density: Annotated[FluidDensity, Field(description="water density (kg/m³)")] = 1000.0
    length: Annotated[
        Length | None,
        Field(description="model = 'fe': the reservoir length (m) from the most upstream "
              "point of the wet face to the far end, where p = 0; default 3 × the depth"),
    ] = None  # fmt: skip
    refine: Annotated[
        int | None, Field(ge=1),
        Field(description="model = 'fe': pieces of the water mesh per wet facet (default 1: "
              "the water mesh's nodes on the face are the facets' nodes)"),
    ] = None  # fmt: skip

    @model_validator(mode="after")
    def _fe_options(self) -> Westergaard:
        if self.model == "westergaard":
            for key in ("length", "refine"):
                if getattr(self, key) is not None:
                    raise _check(key, "only with model = 'fe'")
        elif self.bottom is not None:
            raise _check("bottom", "not with model = 'fe': the finite-element reservoir's "
                         "bottom is the lowest point of its wet faces")  # fmt: skip
        return self


class UpliftTable(_Table):
    """``[[loads.uplift]]``: the pore pressure in a joint (pfeie.model.Uplift)."""

    interface: Annotated[str, Field(description="the interface (a group of [interfaces])")]
    headwater: Annotated[Elevation, Field(description="headwater level (m, vertical axis)")]
    tailwater: Annotated[
        Elevation | None, Field(description="tailwater level (m); default none (the toe's level)")
    ] = None
    drains: Annotated[
        Distance | None,
        Field(
            description="distance of the line of drains from the heel (m), short of the "
            "joint's far end, measured along the upstream axis (horizontally: on an inclined "
            "joint its horizontal projection); default none"
        ),
    ] = None
    drain_efficiency: Annotated[
        float, Field(ge=0.0, le=1.0, description="drain efficiency E in [0, 1]")
    ] = 0.0
    upstream: Annotated[
        Literal["-x", "+x", "-y", "+y"],
        Field(description="where the reservoir is: '-x' (the heel is the joint's end of least "
              "x), '+x', or in 3D '-y', '+y'"),
    ] = "-x"  # fmt: skip
    shaking: Annotated[
        Literal["keep", "full", "zero"],
        Field(description="uplift during the shaking: 'keep' the pre-earthquake uplift; "
              "'full' headwater pressure where a pair opens in the crack from the heel; 'zero' "
              "none where a pair opens"),
    ] = "keep"  # fmt: skip
    density: Annotated[FluidDensity, Field(description="water density ρ_w (kg/m³)")] = 1000.0

    @model_validator(mode="after")
    def _drains_with_efficiency(self) -> UpliftTable:
        # either key alone changed nothing: drains default to an efficiency of 0, an
        # efficiency without drains acts nowhere
        if self.drains is not None and "drain_efficiency" not in self.model_fields_set:
            raise _check("drain_efficiency", "missing (required with drains: the fraction E "
                         "of the head the drains remove, e.g. 0.5; 0 for drains that do "
                         "not work)")  # fmt: skip
        if self.drains is None and self.drain_efficiency > 0:
            raise _check("drains", "missing (required with drain_efficiency: the distance of "
                         "the line of drains from the heel, m)")  # fmt: skip
        return self


class PseudoStatic(_Table):
    """``loads.pseudo_static``: the seismic coefficients of a pseudo-static analysis: the
    inertia force of a uniform acceleration k_h g along a horizontal direction and k_v g
    upward on all the mass: k_h W and k_v W on the blocks (W the weight, ρ g with
    ``loads.gravity``) and, with ``[[loads.westergaard]]``, the reservoir's hydrodynamic
    force on its added mass (Westergaard's k_h (7/12) ρ_w g h² on a vertical face)."""

    kh: Annotated[
        float, Field(ge=0.0, le=2.0),
        Field(description="horizontal seismic coefficient k_h (a fraction of g)"),
    ]  # fmt: skip
    kv: Annotated[
        float, Field(ge=-2.0, le=2.0),
        Field(description="vertical seismic coefficient k_v (a fraction of g, + upward: it "
              "unloads the joints)"),
    ] = 0.0  # fmt: skip
    direction: Annotated[
        Vector | None,
        Field(description="horizontal direction of k_h g (normalised); default +x"),
    ] = None  # fmt: skip


class Loads(_Table):
    """``[loads]``: gravity, pressures, water, silt."""

    gravity: Annotated[
        float, Field(ge=0.0, le=1e3), Unit("m/s²"),
        Field(description="gravitational acceleration (m/s²); 0 for none"),
    ] = 9.81  # fmt: skip
    gravity_direction: Annotated[
        Vector | None, Field(description="unit vector of gravity; default −y (2D), −z (3D)")
    ] = None
    pseudo_static: Annotated[
        PseudoStatic | None,
        Field(description="seismic coefficients of a pseudo-static analysis (a table: kh, "
              "kv, direction): the inertia forces k_h g horizontal and k_v g upward on all "
              "the mass (the blocks and a reservoir's added mass: Westergaard's "
              "hydrodynamic force), in the static analysis and, as constant loads, in a "
              "dynamic one"),
    ] = None  # fmt: skip
    pressure: Annotated[list[Pressure], Field(description="uniform pressures")] = []
    hydrostatic: Annotated[
        list[Hydrostatic], Field(description="hydrostatic pressure ρ_w g (level − z)⁺ on faces")
    ] = []
    silt: Annotated[
        list[Silt],
        Field(description="silt against faces: horizontal pressure K γ' (level − z)⁺ and "
              "the vertical silt weight γ' (level − z)⁺ on inclined faces and floors"),
    ] = []  # fmt: skip
    westergaard: Annotated[
        list[Westergaard],
        Field(description="the reservoir's added mass on the wet faces: Westergaard's "
              "7/8 ρ_w √(H (level − z)) along their normal, or a finite-element reservoir "
              "(model = 'fe')"),
    ] = []  # fmt: skip
    uplift: Annotated[
        list[UpliftTable],
        Field(description="uplift in joints: linear from headwater at the heel to tailwater "
              "at the toe, drains, full headwater in the part cracked from the heel"),
    ] = []  # fmt: skip

    @model_validator(mode="after")
    def _each_load_once(self) -> Loads:
        # the same water on the same face (or joint) in two tables is applied twice
        for name in ("hydrostatic", "silt", "westergaard"):
            seen: dict[str, int] = {}
            for i, table in enumerate(getattr(self, name)):
                for group in table.groups:
                    if group in seen:
                        raise _check(f"{name}[{i}].groups", f"{group!r} is loaded already by "
                                     f"loads.{name}[{seen[group]}]: it would be loaded twice; "
                                     "expected each face in one table")  # fmt: skip
                    seen[group] = i
        joints: dict[str, int] = {}
        for i, up in enumerate(self.uplift):
            if up.interface in joints:
                raise _check(f"uplift[{i}].interface", f"{up.interface!r} has an uplift already "
                             f"(loads.uplift[{joints[up.interface]}]): it would be applied "
                             "twice; expected one table per joint")  # fmt: skip
            joints[up.interface] = i
        return self


class TargetSa(_Table):
    """``ground_motion[].target_sa``: scale the record so that its pseudo-spectral
    acceleration at one period matches a target."""

    period: Annotated[
        float, Field(gt=0.0, le=100.0), Unit("s"), Field(description="period T (s) of the target")
    ]
    value: Annotated[
        float, Field(gt=0.0, le=20.0), Unit("g"),
        Field(description="target pseudo-spectral acceleration Sa(T, ζ) = ω² Sd (g)"),
    ]  # fmt: skip
    damping: Annotated[
        float, Field(gt=0.0, lt=1.0, description="damping ratio ζ of the spectrum")
    ] = 0.05


class RecordFilter(_Table):
    """``ground_motion[].filter``: a zero-phase Butterworth filter of the record (run
    forward and backward, so |H|² per corner; a band-pass is the high-pass and the
    low-pass in cascade; :meth:`pfeie.GroundMotion.filtered`). The corners must lie below
    the record's Nyquist frequency 1/(2Δt), which ``pfeie check`` checks."""

    highpass: Annotated[
        Annotated[float, Field(gt=0.0), Unit("Hz")] | None,
        Field(description="high-pass corner f_c (Hz): removes the periods longer than about "
              "1/f_c, e.g. 0.1"),
    ] = None  # fmt: skip
    lowpass: Annotated[
        Annotated[float, Field(gt=0.0), Unit("Hz")] | None,
        Field(description="low-pass corner (Hz), e.g. 25; above highpass"),
    ] = None
    order: Annotated[
        int, Field(ge=1, le=8), Expect("an integer from 1 to 8"),
        Field(description="order n of each Butterworth (the two passes make the slope 2n)"),
    ] = 4  # fmt: skip

    @model_validator(mode="after")
    def _corners(self) -> RecordFilter:
        if self.highpass is None and self.lowpass is None:
            raise _check("", "expected highpass or lowpass (corner frequencies, Hz), or both")
        low, high = self.highpass, self.lowpass
        if low is not None and high is not None and low >= high:
            raise _check("lowpass", f"expected a corner above highpass = {self.highpass:g} Hz "
                         f"(a band-pass), found {self.lowpass:g} Hz")  # fmt: skip
        return self


class RecordReading(_Table):
    """How a record file is read: its format, units, time step and direction (shared by
    a model file's ``[[ground_motion]]`` and a study file's ``[[records]]``)."""

    format: Annotated[
        Literal["auto", "at2", "two-column", "one-column"],
        Field(description="'auto', 'at2', 'two-column' or 'one-column'"),
    ] = "auto"
    units: Annotated[
        Literal["g", "m/s2", "cm/s2", "gal"] | None,
        Field(
            description="units of the record: 'g', 'm/s2', 'cm/s2' or 'gal' (= cm/s2; AT2: as "
            "its third line states them, g in PEER's files)"
        ),
    ] = None
    dt: Annotated[Positive | None, Field(description="time step of a one-column record (s)")] = None
    component: Annotated[
        Literal["x", "y", "z"], Field(description="direction of the motion: 'x', 'y' or 'z'")
    ] = "x"
    direction: Annotated[
        Vector | None, Field(description="direction vector (instead of component)")
    ] = None
    baseline: Annotated[
        bool, Field(description="remove the drift of the final velocity (absolute form)")
    ] = False
    filter: Annotated[
        RecordFilter | None,
        Field(description="zero-phase Butterworth filter (a table: highpass, lowpass (Hz), "
              "order), applied after scale and before baseline"),
    ] = None  # fmt: skip

    @model_validator(mode="after")
    def _one_direction(self) -> RecordReading:
        if self.direction is not None and "component" in self.model_fields_set:
            raise _check("", "give either component or direction, not both")
        return self


class GroundMotionRecord(RecordReading):
    """``[[ground_motion]]``: an acceleration record, how it is read and scaled."""

    file: Annotated[PathText, Field(description="record file")]
    scale: Annotated[
        float,
        Field(
            description="scale factor (not 0; negative flips the record; beside pga or "
            "target_sa only -1, the polarity)"
        ),
        AfterValidator(_nonzero),
    ] = 1.0
    pga: Annotated[
        Annotated[float, Field(gt=0.0, le=20.0), Unit("g")] | None,
        Field(description="scale the record to this peak ground acceleration (g), instead of "
              "scale; the peak of the motion applied: the record up to analysis.duration"),
    ] = None  # fmt: skip
    target_sa: Annotated[
        TargetSa | None,
        Field(description="scale the record to a pseudo-spectral acceleration Sa(T, ζ) (a "
              "table: period (s), value (g), damping), instead of scale or pga; the Sa of the "
              "motion applied: the record up to analysis.duration"),
    ] = None  # fmt: skip


class Analysis(DynamicSettings):
    """``[analysis]``: the settings of the dynamic analysis (pfeie.dynamics.DynamicSettings:
    same keys, same defaults) and the keys that only a model file has."""

    model_config = ConfigDict(strict=True, allow_inf_nan=False)

    static: Annotated[bool, Field(description="solve the static state (gravity, water) first")] = (
        True
    )
    dynamic: Annotated[bool, Field(description="run the dynamic analysis")] = True
    yield_coefficient: Annotated[
        bool | list[Literal["+x", "-x", "+y", "-y"] | list[float]],
        Expect("true, false or an array of '+x', '-x' (in 3D also '+y', '-y') or of "
               "horizontal vectors such as [0.6, 0.8, 0.0]"), Field(
        description="after the static state, find the yield coefficient k_y along +x and "
        "−x (true), or along the directions listed (in 3D also '+y', '-y'), each made "
        "horizontal, or along horizontal vectors (a wedge whose keel trends obliquely: "
        "[0.6, 0.8, 0.0], normal to gravity): the pseudo-static acceleration, a fraction "
        "of g, at which a joint slides (summary.json yield_coefficient, keyed by the "
        "direction as written; needs static = true)",
    )] = False  # fmt: skip
    strength_reduction: Annotated[bool, Field(
        description="after the static state, the factor of safety by strength reduction: "
        "the least factor F by which every joint's strength (c, tan φ, σ_t, intact and "
        "residual) must be divided for the static equilibrium to be lost (summary.json "
        "strength_reduction; needs static = true)",
    )] = False  # fmt: skip
    post_earthquake: Annotated[bool, Field(
        description="after a completed record, the post-earthquake static state: the "
        "static loads on the joints as the record left them (the pairs it broke at their "
        "residual strength, an uplift's crack from the heel at full headwater), with each "
        "joint's sliding safety factor (summary.json post_earthquake; needs static = true)",
    )] = True  # fmt: skip
    duration: Annotated[
        Annotated[float, Field(gt=0.0), Unit("s")] | None,
        Field(description="duration (s); default: the longest record"),
    ] = None
    form: Annotated[Literal["relative", "absolute"], Field(
        description="ground motion: 'relative' (fixed base) or 'absolute' (moving supports)",
    )] = "relative"  # fmt: skip

    @model_validator(mode="after")
    def _not_too_many_steps(self) -> Analysis:
        if not (self.static or self.dynamic):
            raise _check("dynamic", "nothing to run: static and dynamic are both false; "
                         "expected one of them (or both) true")  # fmt: skip
        if isinstance(self.yield_coefficient, list) and (
            not self.yield_coefficient
            or len({yield_label(v) for v in self.yield_coefficient}) < len(self.yield_coefficient)
        ):
            raise _check("yield_coefficient", "expected true, false or distinct directions "
                         "among '+x', '-x', '+y', '-y' or horizontal vectors")  # fmt: skip
        if self.yield_coefficient and not self.static:
            raise _check("yield_coefficient", "the yield coefficient is found from the "
                         "static state; expected static = true")  # fmt: skip
        if self.strength_reduction and not self.static:
            raise _check("strength_reduction", "the factor of safety is found from the "
                         "static state; expected static = true")  # fmt: skip
        if self.duration is not None:
            try:
                self.steps(self.duration)
            except ValueError as exc:
                raise _check("duration", str(exc)) from None
        return self

    def dynamic_settings(self) -> DynamicSettings:
        """The settings of :class:`pfeie.Dynamic` alone (without the model-file keys)."""
        return DynamicSettings(**{k: getattr(self, k) for k in DynamicSettings.model_fields})


class ProbeAt(_Table):
    """``output.probes.<name> = {at = [...], block = ...}``: a probe at the node of
    ``block`` nearest to ``at``; a bare array of coordinates is ``at`` alone."""

    @model_validator(mode="before")
    @classmethod
    def _point(cls, v: Any) -> Any:
        return {"at": v} if isinstance(v, list) else v

    at: Annotated[Vector, Field(description="probe point coordinates (m); the nearest "
                                "node is used; output.probes.<name> = [x, y(, z)] is short "
                                "for { at = [x, y(, z)] }")]  # fmt: skip
    block: Annotated[
        str | None,
        Field(description="the block whose node is taken: a point on a joint has a node "
              "in each block (without block the first is taken, with a warning naming "
              "them)"),
    ] = None  # fmt: skip


_POINT_JSON = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 3}
#: a probe in the JSON schema: the bare point, or the table (ProbeAt)
_PROBE_JSON: dict[str, Any] = {"anyOf": [
    _POINT_JSON,
    {"type": "object", "additionalProperties": False, "required": ["at"],
     "properties": {"at": _POINT_JSON, "block": {"type": "string"}}},
]}  # fmt: skip


class Output(_Table):
    """``[output]``: where and what to write."""

    folder: Annotated[str, AfterValidator(_folder_text), Field(description="output folder")] = (
        "results"
    )
    every: Annotated[
        int,
        Field(
            gt=0,
            description="record the histories every n-th step "
            "(and the run's last step, off that grid or not)",
        ),
    ] = 1
    field_every: Annotated[
        int, Field(gt=0, description="store the nodal fields (u, v, a) every n-th recorded step")
    ] = 10
    paraview: Annotated[
        bool, Field(description="write the ParaView series (blocks.xdmf, interfaces.xdmf)")
    ] = True
    envelope: Annotated[
        bool,
        Field(description="keep the envelope of the principal stresses (per node and cell, "
              "at every recorded row) in results.h5 and envelope.vtu"),
    ] = True  # fmt: skip
    checkpoint_seconds: Annotated[
        NonNegative,
        Field(description="wall time between two checkpoints of the run in results.h5 (s; "
              "0: at every recorded row, and each costs about 0.1 s on the demo, so 0 makes a "
              "run many times slower); `pfeie run --resume` continues from the last"),
    ] = 30.0  # fmt: skip
    checkpoint_steps: Annotated[
        int, Field(ge=0, le=10**9),
        Field(description="also a checkpoint every this many time steps (at the first "
              "recorded row after them; 0: by wall time only), e.g. for runs on a cluster "
              "whose jobs may be stopped at any time"),
    ] = 0  # fmt: skip
    compression: Annotated[
        Literal["gzip", "lzf", "none"],
        Field(description="compression of the arrays of results.h5 and of the ParaView "
              "series (lossless): 'gzip' (deflate with the byte shuffle; every HDF5 reader, "
              "ParaView and MATLAB included), 'lzf' (faster, a little larger; h5py only, so "
              "the nodal fields, which the ParaView series reads in results.h5, and the "
              "series' own files then use gzip at level 1) or 'none'"),
    ] = "gzip"  # fmt: skip
    compression_level: Annotated[
        int, Field(ge=1, le=9), Expect("an integer from 1 to 9"),
        Field(description="level of 'gzip' compression: 1 fastest to 9 smallest "
              "(not used by 'lzf' and 'none')"),
    ] = 4  # fmt: skip
    field_precision: Annotated[
        Literal["float64", "float32"],
        Field(description="precision of the nodal fields u, v, a in results.h5 and of the "
              "point data of the ParaView series: 'float32' halves them (7 significant "
              "digits); the histories, the mesh and the checkpoint stay float64"),
    ] = "float64"  # fmt: skip
    probes: Annotated[
        dict[str, Annotated[ProbeAt, Expect("an array of 2 to 3 numbers (the point) or a "
                                            "table { at = [...], block = name }"),
                            WithJsonSchema(_PROBE_JSON)]],
        Field(description="probes: each an array of point coordinates (m), or a table "
              "{ at = [x, y(, z)], block = name }; the nearest node is used (of that block "
              "if given: a point on a joint has a node in each block)"),
    ] = {}  # fmt: skip


class ModelFile(_Table):
    """A whole model file (see docs/model-file.md)."""

    title: Annotated[str, Field(description="title of the analysis, for summaries and reports")] = (
        ""
    )
    mesh: MeshFile
    plane: Annotated[
        Literal["strain", "stress"], Field(description="2D hypothesis: 'strain' or 'stress'")
    ] = "strain"
    thickness: Annotated[Thickness, Field(description="out-of-plane thickness in 2D (m)")] = 1.0
    materials: Annotated[
        dict[str, Material], Field(description="isotropic elastic materials by name")
    ]
    blocks: Annotated[
        dict[str, str],
        Field(
            description="material of the block (the block is the physical group of this "
            "name; a key with *, ? or [...] stands for every group it matches)"
        ),
    ]
    damping: Damping = Damping()
    interfaces: Annotated[
        dict[str, Joint], Field(description="interfaces: physical group = joint properties")
    ] = {}
    supports: Annotated[
        list[Support], Field(description="supports (fixed or prescribed displacements)")
    ] = []
    loads: Loads = Loads()
    ground_motion: Annotated[
        list[GroundMotionRecord],
        Field(description="ground-motion records (several components act together)"),
    ] = []
    analysis: Analysis = Analysis()
    output: Output = Output()


# -- the annotations, walked ---------------------------------------------------------------
class _Node(NamedTuple):
    """A type met while walking a key path: its base type and its constraints."""

    tp: Any
    meta: tuple[Any, ...]
    optional: bool = False


def _node(tp: Any, meta: Sequence[Any] = ()) -> _Node:
    """Unwrap Annotated and Optional, collecting the metadata (bounds, Expect)."""
    out: list[Any] = []
    for m in meta:
        out.extend(m.metadata if isinstance(m, FieldInfo) else [m])
    optional = False
    while True:
        origin = typing.get_origin(tp)
        if origin is Annotated:
            args = typing.get_args(tp)
            tp = args[0]
            for m in args[1:]:
                out.extend(m.metadata if isinstance(m, FieldInfo) else [m])
        elif origin in (Union, types.UnionType):
            members = [a for a in typing.get_args(tp) if a is not type(None)]
            optional = optional or len(members) < len(typing.get_args(tp))
            if len(members) != 1:
                break
            tp = members[0]
        else:
            break
    return _Node(tp, tuple(out), optional)


def _field(model: type[BaseModel], name: str) -> _Node:
    f = model.model_fields[name]
    return _node(f.annotation, [f])


def _is_model(tp: Any) -> bool:
    return isinstance(tp, type) and issubclass(tp, BaseModel)


def _walk(
    loc: Sequence[int | str], root: type[BaseModel] | None = None
) -> tuple[int, _Node | None, type[BaseModel] | None]:
    """Follow ``loc`` from ``root`` (default :class:`ModelFile`): how many parts name a key
    (the rest are items of an array of values), the type there, and the table that holds
    it."""
    node: _Node = _Node(ModelFile if root is None else root, ())
    parent: type[BaseModel] | None = None
    for i, part in enumerate(loc):
        origin = typing.get_origin(node.tp)
        if _is_model(node.tp):
            if part not in node.tp.model_fields:
                return i + 1, None, node.tp
            parent, node = node.tp, _field(node.tp, str(part))
        elif origin is dict:
            node = _node(typing.get_args(node.tp)[1])
        elif origin is list and _is_model(_node(typing.get_args(node.tp)[0]).tp):
            node = _node(typing.get_args(node.tp)[0])
        else:  # an item of an array of values: report on the array
            return i, node, parent
    return len(loc), node, parent


# -- words -----------------------------------------------------------------------------------
def _num(x: float) -> str:
    fr = Fraction(x).limit_denominator(12)
    if float(x).is_integer() and abs(x) < 1e6:
        return str(int(x))
    if abs(float(fr) - x) < 1e-12 and fr.denominator in (3, 6, 7, 9, 11, 12):
        return f"{fr.numerator}/{fr.denominator}"
    return f"{x:.6g}"


_NAMES = {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
          list: "an array", dict: "a table"}  # fmt: skip


def _tname(x: Any) -> str:
    return _NAMES.get(type(x), type(x).__name__)


def _bound(meta: Sequence[Any], name: str) -> Any:
    return next((getattr(m, name) for m in meta if getattr(m, name, None) is not None), None)


def _type_words(node: _Node) -> str:
    """The kind of value alone: 'a number', 'one of ...', 'an array of 2 to 3 numbers'."""
    expect = next((m.text for m in node.meta if isinstance(m, Expect)), None)
    if expect is not None and (typing.get_origin(node.tp) is list or _is_model(node.tp)):
        return expect
    tp = node.tp
    if typing.get_origin(tp) is Literal:
        return "one of " + ", ".join(repr(a) for a in typing.get_args(tp))
    if _is_model(tp) or typing.get_origin(tp) is dict:
        return "a table"
    if typing.get_origin(tp) is list:
        item = _node(typing.get_args(tp)[0])
        if _is_model(item.tp):
            return "an array of tables"
        return "an array of " + {float: "numbers", str: "strings"}.get(item.tp, "values")
    return _NAMES.get(tp, str(tp))


def expected(node: _Node) -> str:
    """What a value must be, with its bounds: 'a number in (-1, 0.5)'."""
    expect = next((m.text for m in node.meta if isinstance(m, Expect)), None)
    if expect is not None:
        return expect
    words = _type_words(node)
    lo = [(f"({_num(v)}", f"> {_num(v)}") for v in [_bound(node.meta, "gt")] if v is not None]
    lo += [(f"[{_num(v)}", f">= {_num(v)}") for v in [_bound(node.meta, "ge")] if v is not None]
    hi = [(f"{_num(v)})", f"< {_num(v)}") for v in [_bound(node.meta, "lt")] if v is not None]
    hi += [(f"{_num(v)}]", f"<= {_num(v)}") for v in [_bound(node.meta, "le")] if v is not None]
    unit = next((f" {m.text}" for m in node.meta if isinstance(m, Unit)), "")
    if lo and hi:
        return f"{words} in {lo[0][0]}, {hi[0][0]}{unit}"
    if lo or hi:
        return f"{words} {(lo or hi)[0][1]}{unit}"
    return words + (f" ({unit.strip()})" if unit else "")


_BOUNDS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")


def _item_range(err: Any) -> str:
    """The bound an item of an array of numbers crossed: '> 0'."""
    ops = {"greater_than": ("gt", ">"), "greater_than_equal": ("ge", ">="),
           "less_than": ("lt", "<"), "less_than_equal": ("le", "<=")}  # fmt: skip
    name, op = ops[err["type"]]
    return f"{op} {_num(err['ctx'][name])}"


def _path(loc: Sequence[int | str]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def _at(data: Any, loc: Sequence[int | str]) -> Any:
    for part in loc:
        try:
            data = data[part]
        except (KeyError, IndexError, TypeError):
            return None
    return data


def _found(x: Any) -> str:
    if isinstance(x, dict):
        return "a table"
    return f"{_tname(x)} {x!r}"


@dataclass(frozen=True)
class Problem:
    """One validation error: the key path (its parts) and the message after it."""

    loc: tuple[int | str, ...]
    text: str

    @property
    def key(self) -> str:
        return _path(self.loc) or "top level"


def problems(exc: ValidationError, data: Any, root: type[BaseModel] | None = None) -> list[Problem]:
    """The errors of a validation of ``data`` (the raw TOML) against ``root`` (default
    :class:`ModelFile`) as key paths and words."""
    out: list[Problem] = []
    for err in exc.errors():
        typ, loc, ctx = err["type"], tuple(err["loc"]), err.get("ctx") or {}
        n, node, parent = _walk(loc, root)
        loc = loc[:n]
        if loc and loc[-1] == "at" and isinstance(_at(data, loc[:-1]), list):
            loc = loc[:-1]  # a bare array is the table's ``at`` (ProbeAt): its own key
        found = _at(data, loc) if n < len(err["loc"]) else err["input"]
        if typ == "missing":
            text = "missing (required)"
        elif typ == "extra_forbidden":
            keys = sorted(parent.model_fields) if parent is not None else []
            text = "unknown key; expected one of: " + ", ".join(keys)
        elif typ == "pfeie_check":
            if ctx["key"]:
                loc = (*loc, ctx["key"])
            text = str(ctx["text"])
        elif typ in ("value_error", "assertion_error"):
            text = str(err["msg"]).removeprefix("Value error, ").removeprefix("Assertion failed, ")
        elif node is None:
            text = str(err["msg"])
        elif typing.get_origin(node.tp) in (Union, types.UnionType):
            # a value of none of the union's types: pydantic reports each member; once here
            if any(p.loc == loc for p in out):
                continue
            text = f"expected {expected(node)}, found {_found(found)}"
        elif typ in _BOUNDS and n < len(err["loc"]):  # in an array of numbers
            text = f"expected {expected(node)}, each {_item_range(err)}, found {found!r}"
        elif typ in _BOUNDS:  # the whole range and the unit, not only the bound crossed
            text = f"expected {expected(node)}, found {found!r}"
        elif typ == "finite_number" and n < len(err["loc"]):  # in an array of numbers
            text = f"expected {expected(node)}, each finite, found {found!r}"
        elif typ == "finite_number":
            text = f"expected a finite number, found {found!r}"
        elif typ in ("literal_error", "too_short", "too_long"):
            text = f"expected {expected(node)}, found {found!r}"
        elif (
            typ == "list_type"
            and typing.get_origin(node.tp) is list
            and _is_model(_node(typing.get_args(node.tp)[0]).tp)
        ):
            text = f"expected an array of tables ([[{_path(loc)}]]), found {_found(found)}"
        else:  # the type of the value
            text = f"expected {_type_words(node)}, found {_found(found)}"
        out.append(Problem(loc, text))
    return out


# -- the reference -------------------------------------------------------------------------
class Row(NamedTuple):
    """One key of the reference: key path, expected value, default and meaning."""

    key: str
    expected: str
    default: str
    meaning: str


def _toml(x: Any) -> str:
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, str):
        return f'"{x}"'
    if isinstance(x, float):
        return _num(x) if x.is_integer() or abs(x) >= 1e-3 else f"{x:g}"
    return repr(x)


def _rows(model: type[BaseModel], path: str) -> Iterator[Row]:
    for name, f in model.model_fields.items():
        key = f"{path}.{name}" if path else name
        node = _node(f.annotation, [f])
        origin = typing.get_origin(node.tp)
        if _is_model(node.tp):
            yield from _rows(node.tp, key)
            continue
        if origin is dict:
            item = _node(typing.get_args(node.tp)[1])
            if _is_model(item.tp):
                yield from _rows(item.tp, f"{key}.<name>")
                continue
            key, node = f"{key}.<name>", item
        elif origin is list and _is_model(_node(typing.get_args(node.tp)[0]).tp):
            yield from _rows(_node(typing.get_args(node.tp)[0]).tp, f"{key}[]")
            continue
        if f.is_required():
            default = "required"
        elif f.default is None or key.endswith("<name>"):
            default = "—"
        else:
            default = f"`{_toml(f.default)}`"
        yield Row(key, expected(node), default, f.description or "")


def reference_rows() -> list[Row]:
    """Every key of a model file: (key path, expected, default, meaning)."""
    return list(_rows(ModelFile, ""))


def reference_markdown() -> str:
    """The key reference of docs/model-file.md, as a Markdown table."""
    lines = ["| key | expected | default | meaning |", "|---|---|---|---|"]
    for r in reference_rows():
        lines.append(f"| `{r.key}` | {r.expected} | {r.default} | {r.meaning} |")
    return "\n".join(lines)


# -- JSON Schema ---------------------------------------------------------------------------
class _TomlSchema(GenerateJsonSchema):
    """JSON Schema for TOML: TOML has no null, so an optional key is just optional."""

    def nullable_schema(self, schema: core_schema.NullableSchema) -> JsonSchemaValue:
        return self.generate_inner(schema["schema"])


def _drop_null_defaults(x: Any) -> Any:
    """No ``default`` of null (TOML has none) nor of a whole table (its keys have theirs)."""
    if isinstance(x, dict):
        return {k: _drop_null_defaults(v) for k, v in x.items()
                if not (k == "default" and (v is None or isinstance(v, dict)))}  # fmt: skip
    if isinstance(x, list):
        return [_drop_null_defaults(v) for v in x]
    return x


def json_schema() -> dict[str, Any]:
    """The JSON Schema of a model file. Declared draft 7: the keywords used (``$ref`` to
    ``#/$defs/...``, ``anyOf``, ``enum``, numeric ``exclusiveMinimum``) mean the same
    there, and editors' validators (taplo) support draft 7 but not 2020-12."""
    body = _drop_null_defaults(ModelFile.model_json_schema(schema_generator=_TomlSchema))
    head = {"$schema": "http://json-schema.org/draft-07/schema#",
            "title": "pfeie model file",
            "description": "A pfeie model file (TOML); see docs/model-file.md."}  # fmt: skip
    body.pop("title", None)
    body.pop("description", None)
    return {**head, **body}


def validate(data: Mapping[str, Any]) -> ModelFile:
    """Validate raw TOML data (raises pydantic's ValidationError)."""
    return ModelFile.model_validate(data)


__all__ = ["Analysis", "ModelFile", "Problem", "Row", "json_schema", "problems",
           "reference_markdown", "reference_rows", "validate"]  # fmt: skip
