"""Physics objects: materials, blocks, supports, loads, damping.

These hold data only; turning them into matrices and vectors is the job of
:class:`pfeie.Model` with the kernels of :mod:`pfeie.assembly`. Units are SI:
Pa for moduli and stresses, kg/m³ for density, N for forces, m/s² for accelerations.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..element._reference import FloatArray, IntArray
from ..errors import ModelError

Amplitude = Callable[[float], float]
VectorField = FloatArray | Sequence[float] | Callable[[FloatArray], FloatArray]


@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elastic material.

    Parameters: Young's modulus ``E`` (Pa), Poisson's ratio ``nu``, density ``rho``
    (kg/m³).

    >>> [round(x / 1e9, 6) for x in Elastic(E=30e9, nu=0.2, rho=2400).lame(3)]  # GPa
    [8.333333, 12.5]
    """

    E: float
    nu: float
    rho: float = 0.0

    def __post_init__(self) -> None:
        if not self.E > 0:
            raise ModelError(f"Young's modulus E must be > 0 Pa, got {self.E}")
        if not -1.0 < self.nu < 0.5:
            raise ModelError(f"Poisson's ratio nu must lie in (-1, 0.5), got {self.nu}")
        if not self.rho >= 0:
            raise ModelError(f"density rho must be >= 0 kg/m³, got {self.rho}")

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


@dataclass(frozen=True)
class Block:
    """A block: a named cell group of the mesh with its own material.

    ``group`` defaults to ``name``. Blocks that share nodes form one continuum until an
    interface separates them.
    """

    name: str
    material: Elastic
    group: str | None = None

    @property
    def cell_group(self) -> str:
        return self.group if self.group is not None else self.name


@dataclass(frozen=True)
class Rayleigh:
    """Rayleigh damping C = α M + β K (α in 1/s, β in s).

    >>> d = Rayleigh.from_ratio(0.05, 1.0, 10.0)
    >>> round(d.ratio(1.0), 12), round(d.ratio(10.0), 12)
    (0.05, 0.05)
    """

    alpha: float = 0.0
    beta: float = 0.0

    @classmethod
    def from_ratio(cls, zeta: float, f1: float, f2: float) -> Rayleigh:
        """The α, β giving damping ratio ζ at the frequencies f1 and f2 (Hz):
        ζ(ω) = α/(2ω) + βω/2, so α = 2ζω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂)."""
        if not (f1 > 0 and f2 > 0 and f1 != f2 and zeta >= 0):
            raise ModelError("Rayleigh.from_ratio needs zeta >= 0 and two distinct f > 0")
        w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
        return cls(2 * zeta * w1 * w2 / (w1 + w2), 2 * zeta / (w1 + w2))

    def ratio(self, f: float) -> float:
        """Damping ratio at frequency f (Hz)."""
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
    "pressure" (N/m², positive pushing into the body) or "nodal" (N).
    """

    kind: str
    target: str | None
    value: VectorField | float
    amplitude: Amplitude | None
    nodes: IntArray | None = None
    blocks: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Joint:
    """Strength and initial state of an interface (Mohr-Coulomb with a tension cut-off).

    Parameters (SI; angles in degrees):

    - ``c`` cohesion (Pa), ``phi`` friction angle, ``tensile`` tensile strength σ_t (Pa):
      the strength of an intact (bonded) pair;
    - ``c_r``, ``phi_r``, ``tensile_r``: residual values once broken (defaults 0, ``phi``,
      0); an existing joint (``initial="broken"``) has only these;
    - ``initial``: "intact" (bonded until its strength is exceeded) or "broken";
    - ``kn``, ``ks``: optional normal and shear stiffness (Pa/m) of a weak layer; None
      means a rigid contact (no spring, no penetration);
    - ``gap``: initial normal gap (m) of an existing (broken) joint: its pairs start open
      and close when the gap is used up (e.g. a bar moving towards a wall).

    Stresses are X/A with X the force on side b, normal positive in compression. An
    intact pair breaks when σ < −σ_t (opens) or |τ| > c + σ tan φ (slides).

    >>> Joint(phi=30.0).mu_r
    0.5773502691896257
    """

    c: float = 0.0
    phi: float = 30.0
    tensile: float = 0.0
    c_r: float = 0.0
    phi_r: float | None = None
    tensile_r: float = 0.0
    initial: str = "broken"
    kn: float | None = None
    ks: float | None = None
    gap: float = 0.0

    def __post_init__(self) -> None:
        for key in ("c", "tensile", "c_r", "tensile_r"):
            if not getattr(self, key) >= 0:
                raise ModelError(f"joint {key} must be >= 0 Pa, got {getattr(self, key)}")
        for key in ("phi", "phi_r"):
            val = getattr(self, key)
            if val is not None and not 0 <= val < 90:
                raise ModelError(f"joint {key} must lie in [0, 90) degrees, got {val}")
        if self.initial not in ("intact", "broken"):
            raise ModelError(f"joint initial must be 'intact' or 'broken', got {self.initial!r}")
        for key in ("kn", "ks"):
            val = getattr(self, key)
            if val is not None and not val > 0:
                raise ModelError(f"joint {key} must be > 0 Pa/m or None, got {val}")
        if not self.gap >= 0:
            raise ModelError(f"joint gap must be >= 0 m, got {self.gap}")
        if self.gap > 0 and self.initial == "intact":
            raise ModelError("an intact (bonded) joint cannot start with a gap")

    @property
    def mu(self) -> float:
        return float(np.tan(np.radians(self.phi)))

    @property
    def mu_r(self) -> float:
        return float(np.tan(np.radians(self.phi if self.phi_r is None else self.phi_r)))


@dataclass(frozen=True)
class Interface:
    """A named facet group of the mesh that cuts blocks apart, with its joint law."""

    group: str
    joint: Joint
