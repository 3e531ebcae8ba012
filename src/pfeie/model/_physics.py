"""Physics objects: materials, blocks, supports, loads, damping, interfaces.

These hold data only; turning them into matrices and vectors is the job of
:class:`pfeie.Model` with the kernels of :mod:`pfeie.assembly`. Units are SI:
Pa for moduli and stresses, kg/m³ for density, N for forces, m/s² for accelerations.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..interface import JointLaw, check_law
from ..typing import FloatArray, IntArray, is_number

Amplitude = Callable[[float], float]
VectorField = FloatArray | Sequence[float] | Callable[[FloatArray], FloatArray]


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elastic material.

    Parameters: Young's modulus ``E`` (Pa), Poisson's ratio ``nu``, density ``rho``
    (kg/m³), and optionally the ``tensile_strength`` f_t (Pa) that the demand-capacity
    ratio σ₁/f_t and the cumulative inelastic duration of a run are measured against
    (:class:`pfeie.dynamics.StressEnvelope`; for an earthquake, the dynamic tensile
    strength, about 1.5 × the static one in USACE EM 1110-2-6053). It changes no
    stiffness: the material stays linear elastic.

    >>> [round(x / 1e9, 6) for x in Elastic(E=30e9, nu=0.2, rho=2400).lame(3)]  # GPa
    [8.333333, 12.5]
    """

    E: float
    nu: float
    rho: float = 0.0
    tensile_strength: float | None = None

    def __post_init__(self) -> None:
        for key, unit in (("E", "Pa"), ("nu", ""), ("rho", "kg/m³"), ("tensile_strength", "Pa")):
            v = getattr(self, key)
            if (v is None and key == "tensile_strength") or _is_number(v):
                continue
            raise ModelError(f"Elastic: {key}: expected a number{f' ({unit})' if unit else ''}, "
                             f"got {type(v).__name__} {v!r}")  # fmt: skip
        if not (np.isfinite(self.E) and self.E > 0):
            raise ModelError(f"Young's modulus E must be a finite number > 0 Pa, got {self.E}")
        if not -1.0 < self.nu < 0.5:
            raise ModelError(f"Poisson's ratio nu must lie in (-1, 0.5), got {self.nu}")
        if not (np.isfinite(self.rho) and self.rho >= 0):
            raise ModelError(f"density rho must be a finite number >= 0 kg/m³, got {self.rho}")
        ft = self.tensile_strength
        if ft is not None and not (np.isfinite(ft) and ft > 0):
            raise ModelError(f"tensile strength must be a finite number > 0 Pa, got {ft}")

    def lame(self, dim: int, plane: str = "strain") -> tuple[float, float]:
        """Lamé constants (λ, μ); in 2D plane stress λ is the reduced λ* = 2λμ/(λ + 2μ)."""
        lam = self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))
        mu = self.E / (2 * (1 + self.nu))
        if dim == 2 and plane == "stress":
            lam = 2 * lam * mu / (lam + 2 * mu)
        return lam, mu

    def wave_speeds(self) -> tuple[float, float]:
        """P-wave (constrained modulus) and S-wave speeds (m/s)."""
        lam, mu = self.lame(3)
        if self.rho <= 0:
            raise ModelError("wave speeds need a density rho > 0")
        return float(np.sqrt((lam + 2 * mu) / self.rho)), float(np.sqrt(mu / self.rho))


_is_number = is_number  # (the API's rule: pfeie.typing.is_number)


@dataclass(frozen=True)
class Block:
    """A block: a named cell group of the mesh with its own material.

    ``group`` defaults to ``name``. Blocks that share nodes form one continuum until an
    interface separates them.
    """

    name: str
    material: Elastic
    group: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not (self.group is None
                                                  or isinstance(self.group, str)):  # fmt: skip
            raise ModelError(f"Block: name and group: expected strings, got {self.name!r} "
                             f"and {self.group!r}")  # fmt: skip
        if not isinstance(self.material, Elastic):
            raise ModelError(f"block {self.name!r}: material: expected a pfeie.Elastic, got "
                             f"{type(self.material).__name__} {self.material!r}")  # fmt: skip

    @property
    def cell_group(self) -> str:
        return self.group if self.group is not None else self.name


#: the largest damping ratio ζ that :meth:`Rayleigh.from_ratio` and the model file's
#: ``damping.ratio`` take: critical damping (a percentage given as the ratio, 5 for 5 %,
#: lies far above)
DAMPING_RATIO_MAX = 1.0


@dataclass(frozen=True)
class Rayleigh:
    """Rayleigh damping C = α M + β K (α in 1/s, β in s).

    With ``deformation_only`` the mass-proportional part spares the rigid motions that the
    supports leave free (all those of a floating body, held by its joints or free; those
    along a roller; :meth:`Model.free_rigid_modes`, R):

        C = α (M − M R (Rᵀ M R)⁻¹ Rᵀ M) + β K,

    so that C R = 0: a block sliding or rocking on its joints feels no viscous drag α m v,
    while every deformation mode φ (Rᵀ M φ = 0) keeps the ratio ζ(ω) = α/(2ω) + βω/2. The
    term is of rank 3 (2D) or 6 (3D) per floating body; the time steps keep their sparse
    factor and add it by Woodbury (:class:`pfeie.linalg.UpdatedFactorization`). The modes
    of a bonded structure, in which floating blocks also move rigidly, lose the α share of
    that motion (:attr:`pfeie.solvers.ModalResult.damping_ratios`; the Koyna demo's first
    mode: 5.09 % → 0.75 %).

    >>> d = Rayleigh.from_ratio(0.05, 1.0, 10.0)
    >>> round(d.ratio(1.0), 12), round(d.ratio(10.0), 12)
    (0.05, 0.05)
    """

    alpha: float = 0.0
    beta: float = 0.0
    deformation_only: bool = False

    def __post_init__(self) -> None:
        for key in ("alpha", "beta"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float, np.floating)) and np.isfinite(v) and v >= 0):
                raise ModelError(f"Rayleigh: {key} must be a finite number >= 0 (negative "
                                 f"damping feeds energy in), got {v!r}")  # fmt: skip

    @classmethod
    def from_ratio(
        cls, zeta: float, f1: float, f2: float, deformation_only: bool = False
    ) -> Rayleigh:
        """The α, β giving damping ratio ζ at the frequencies f1 and f2 (Hz):
        ζ(ω) = α/(2ω) + βω/2, so α = 2ζω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂)."""
        if not (f1 > 0 and f2 > 0 and f1 != f2 and zeta >= 0):
            raise ModelError("Rayleigh.from_ratio needs zeta >= 0 and two distinct f > 0")
        if zeta > DAMPING_RATIO_MAX:  # a percentage given as the ratio (5 for 5 %)?
            raise ModelError(f"Rayleigh.from_ratio: zeta is a ratio of critical damping, "
                             f"at most {DAMPING_RATIO_MAX:g} (0.05 for 5 %), "
                             f"got {zeta:g}")  # fmt: skip
        w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
        return cls(2 * zeta * w1 * w2 / (w1 + w2), 2 * zeta / (w1 + w2), deformation_only)

    def ratio(self, f: float) -> float:
        """Damping ratio at frequency f (Hz, > 0)."""
        if not is_number(f) or not (np.isfinite(f) and f > 0):
            raise ModelError(f"Rayleigh.ratio: expected a frequency > 0 Hz, got {f!r}")
        w = 2 * np.pi * f
        return float(self.alpha / (2 * w) + self.beta * w / 2)


@dataclass(frozen=True)
class Support:
    """Prescribed displacement ``value`` (m) on ``components`` of the nodes of a group."""

    nodes: IntArray
    components: tuple[int, ...]
    value: float
    label: str


@dataclass(frozen=True)
class Load:
    """A spatial load pattern times a time amplitude (1 when ``amplitude`` is None).

    ``kind`` is "body" (force per volume, N/m³), "traction" (N/m² on a facet group),
    "pressure" (N/m², positive pushing into the body), "nodal" (N), "inertia" (M times a
    uniform acceleration ``value``, m/s², the reservoirs' added mass included) or "silt" (a
    geostatic stress on a facet group: ``value`` gives its principal pressures along the
    axes, (..., d) in Pa, and the traction is −diag(value) n with n the outward normal).
    ``level`` (m, on the vertical axis) marks a surface load that vanishes above it and is
    a polynomial below (hydrostatic water, silt): the facets the level cuts are then
    integrated on their wet part alone (:meth:`pfeie.Model.add_pressure`).
    """

    kind: str
    target: str | None
    value: VectorField | float
    amplitude: Amplitude | None
    nodes: IntArray | None = None
    blocks: tuple[str, ...] | None = None
    level: float | None = None


@dataclass(frozen=True)
class Interface:
    """A named facet group of the mesh that cuts blocks apart, with its joint law
    (:class:`pfeie.MohrCoulomb`, :class:`pfeie.SlipWeakening` or any
    :class:`pfeie.interface.JointLaw`)."""

    group: str
    joint: JointLaw

    def __post_init__(self) -> None:
        if isinstance(self.joint, type):  # pf.Joint, not pf.Joint(...)
            raise ModelError(f"interface {self.group!r}: joint: expected a joint law, e.g. "
                             f"pf.Joint(phi=30.0), got the class {self.joint.__name__} "
                             "itself")  # fmt: skip
        joint: object = self.joint
        if not isinstance(joint, JointLaw):  # (None, a material): at once, by name
            missing = [k for k in ("initial", "kn", "ks", "gap", "strength")
                       if not hasattr(joint, k)]  # fmt: skip
            lacks = f", which lacks {', '.join(missing)}" if 0 < len(missing) < 5 else ""
            raise ModelError(f"interface {self.group!r}: joint: expected a joint law, e.g. "
                             f"pf.Joint(phi=30.0) (pfeie.interface.JointLaw: initial, kn, "
                             f"ks, gap and strength), got {type(joint).__name__} "
                             f"{joint!r}{lacks}")  # fmt: skip
        check_law(self.joint, f"interface {self.group!r}")
