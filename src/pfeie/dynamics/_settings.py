"""Settings of a dynamic analysis: the one source of every option and default.

The model file's ``[analysis]`` table, the Python API (:class:`pfeie.Dynamic`) and the
command line all validate through :class:`DynamicSettings`, so a default lives here and
nowhere else.

Time scheme. Newmark's β, γ and the HHT-α parameter α (Hilber, Hughes & Taylor 1977)
are related: when ``alpha`` is not 0 and β, γ are not given, they follow from it,

    β = (1 − α)²/4,   γ = (1 − 2α)/2,

which makes HHT-α second order and unconditionally stable for α ∈ [−1/3, 0]; α = 0 is
Newmark's average-acceleration rule (β = 1/4, γ = 1/2). Explicit β and γ override.

>>> [round(x, 12) for x in DynamicSettings(dt=0.01, alpha=-0.1).newmark()]  # β, γ, α
[0.3025, 0.6, -0.1]
>>> DynamicSettings(dt=0.01).steps(1.0)
100
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from ..interface import SolverSettings, Tolerance
from ..typing import Settings, Unit
from ._newmark import scheme_parameters

_SOLVER = SolverSettings()


#: the Moreau-Jean scheme's default θ (fully implicit, the robust choice for impacts)
_THETA = 1.0


class DynamicSettings(Settings):
    """Options of a dynamic analysis (see the module docstring)."""

    dt: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False), Unit("s"),
                  Field(description="time step (s)")] = 0.01  # fmt: skip
    scheme: Annotated[Literal["nonsmooth-alpha", "newmark", "moreau-jean"], Field(
        description="time stepping: 'nonsmooth-alpha' (generalised-α on the smooth forces, "
        "pair forces at the acceleration level and Coulomb impulses at the velocity level; "
        "rho_inf, default 0), 'newmark' (the Newmark / HHT-α / generalised-α family, for "
        "models without interfaces) or 'moreau-jean' (the θ-method with velocity-level "
        "contact impulses, robust for impacts, dissipative: see theta); default "
        "'nonsmooth-alpha', or 'newmark' when alpha, beta or gamma is given",
    )] = "nonsmooth-alpha"  # fmt: skip
    theta: Annotated[float, Field(
        ge=0.5, le=1.0, allow_inf_nan=False,
        description="θ of the Moreau-Jean scheme in [0.5, 1] (with interfaces in [0.55, 1]: "
        "θ = 1/2 lets blocks hop); algorithmic damping ratio ≈ (θ − 1/2) ω Δt; only with "
        "scheme = 'moreau-jean'",
    )] = _THETA  # fmt: skip
    beta: Annotated[float | None, Field(
        gt=0.0, le=1.0, allow_inf_nan=False,
        description="Newmark β; default 1/4, or (1 − α)²/4 with HHT-α",
    )] = None  # fmt: skip
    gamma: Annotated[float | None, Field(
        ge=0.5, le=1.5, allow_inf_nan=False,
        description="Newmark γ; default 1/2, or (1 − 2α)/2 with HHT-α",
    )] = None  # fmt: skip
    alpha: Annotated[float, Field(
        ge=-1.0 / 3.0, le=0.0, allow_inf_nan=False,
        description="HHT-α parameter in [−1/3, 0] (0: Newmark); sets β and γ unless given",
    )] = 0.0  # fmt: skip
    rho_inf: Annotated[float | None, Field(
        ge=0.0, le=1.0, allow_inf_nan=False,
        description="spectral radius at infinity in [0, 1] of the nonsmooth-alpha scheme "
        "(default 0; > 0 with interfaces needs a Rayleigh beta > 0) or, with scheme = "
        "'newmark', of Chung & Hulbert's generalised-α (1993), instead of alpha",
    )] = None  # fmt: skip
    large_rotation: Annotated[bool, Field(
        description="carry finite rotations of the floating blocks in body frames "
        "(rocking, toppling); with either scheme, scheme = 'moreau-jean' the robust one "
        "where blocks land and impact repeatedly (see docs/theory.md)",
    )] = False  # fmt: skip
    position_correction: Annotated[Literal["local", "rigid"], Field(
        description="the nonsmooth-alpha scheme's position correction of penetrating pairs: "
        "'local' (the pairs' nodes moved apart in the lumped-mass metric, the default) or "
        "'rigid' (the floating blocks moved as rigid bodies, in the metric of their mass: "
        "no strain stored; for a block that lands on a few pairs, a drop or a rockfall, "
        "where 'local' stores the landing's penetration as strain energy and throws the "
        "block back up at a coarse dt; not for a structure resting on its joints, whose "
        "other pairs it opens: docs/theory.md, 'Drops and bounces'); not with "
        "large_rotation",
    )] = "local"  # fmt: skip
    event_substeps: Annotated[int, Field(
        ge=1, le=16,
        description="a step in which a pair changes state (breaks, opens, closes, starts or "
        "stops sliding) is taken again as this many sub-steps of dt/event_substeps, with "
        "the step matrix factorised once more for them; the recorded rows stay on the "
        "grid of dt; 1: off. It resolves the events of crack growth and slip onsets at a "
        "coarse dt; it does not make the sliding between them any finer (a rigid block's "
        "one-way slip under a record stays 2 to 3 % short at dt = 10 ms): halve dt for "
        "that (docs/theory.md, 'Event sub-steps'); not with large_rotation",
    )] = 1  # fmt: skip
    tolerance: Annotated[Tolerance, Field(
        description=SolverSettings.model_fields["tolerance"].description,
    )] = _SOLVER.tolerance  # fmt: skip
    backend: Annotated[Literal["auto", "cholmod", "superlu"], Field(
        description="sparse factorisation of the blocks: 'auto' (CHOLMOD when installed, "
        "else SuperLU), 'cholmod' or 'superlu'",
    )] = "auto"  # fmt: skip

    @model_validator(mode="before")
    @classmethod
    def _implied_scheme(cls, data: object) -> object:
        """Newmark's own options (alpha, beta, gamma) imply scheme = 'newmark' when no
        scheme is given. ``stabilize`` (the contact-stabilised Newmark step, removed) gets
        a message of its own."""
        if isinstance(data, dict) and "stabilize" in data:
            raise ValueError(
                "stabilize was removed with the contact-stabilised Newmark step: models "
                "with interfaces run scheme = 'nonsmooth-alpha' (the default) or "
                "'moreau-jean'; delete the key"
            )
        own = ("alpha", "beta", "gamma")
        if (
            isinstance(data, dict)
            and data.get("scheme") is None
            and any(data.get(k) not in (None, 0.0) for k in own)
        ):
            data = {**data, "scheme": "newmark"}
        return data

    @model_validator(mode="after")
    def _one_scheme(self) -> DynamicSettings:
        if self.alpha != 0.0 and self.rho_inf is not None:
            raise ValueError("give either alpha (HHT-α) or rho_inf (generalised-α), not both")
        if self.large_rotation and (
            self.scheme == "newmark" and (self.alpha != 0.0 or self.rho_inf is not None)
        ):  # fmt: skip
            raise ValueError("large_rotation runs on the nonsmooth-alpha or Moreau-Jean "
                             "scheme or on the Newmark rule (alpha = 0, no rho_inf)")  # fmt: skip
        if self.large_rotation and self.event_substeps > 1:
            raise ValueError(
                "event_substeps > 1 does not run with large_rotation (the "
                "sub-steps' body frames are not carried); use event_substeps = 1"
            )
        if self.scheme == "nonsmooth-alpha" and (
            self.alpha != 0.0 or self.beta is not None or self.gamma is not None
        ):
            raise ValueError("the nonsmooth-alpha scheme takes rho_inf, not alpha, beta or "
                             "gamma (those select scheme = 'newmark')")  # fmt: skip
        if self.position_correction != "local" and (
                self.scheme != "nonsmooth-alpha" or self.large_rotation):  # fmt: skip
            raise ValueError(
                f"position_correction = {self.position_correction!r} is the nonsmooth-alpha "
                "scheme's, without large_rotation (the rigid modes are the undeformed "
                "geometry's); this analysis runs "
                + ("large_rotation" if self.large_rotation else f"the {self.scheme} scheme")
            )
        if self.scheme != "moreau-jean" and self.theta != _THETA:
            # (by value: settings copied whole carry the default θ, given or not)
            raise ValueError(
                f"theta = {self.theta:g} is the Moreau-Jean scheme's θ, and this analysis "
                f"runs the {self.scheme} scheme, which takes no theta: set scheme = "
                "'moreau-jean' to run it, or delete theta"
            )
        if self.scheme == "moreau-jean" and (self.alpha != 0.0 or self.rho_inf is not None):
            name, value = ("rho_inf", self.rho_inf) if self.rho_inf is not None else (
                "alpha", self.alpha)  # fmt: skip
            raise ValueError(
                f"the Moreau-Jean scheme takes theta, not alpha or rho_inf (found {name} = "
                f"{value:g}): delete {name} (from the command line, --set 'analysis = "
                '{scheme = "moreau-jean", dt = ...}\' gives the whole [analysis] table)'
            )
        return self

    def newmark(self) -> tuple[float, float, float]:
        """(β, γ, α) of the scheme, with β and γ derived from α (or ρ∞) unless given."""
        beta, gamma, _, _ = scheme_parameters(self.alpha, self.rho_inf, self.beta, self.gamma)
        return beta, gamma, float(self.alpha)

    def nonsmooth_alpha(self) -> float:
        """ρ∞ of the nonsmooth generalised-α scheme: ``rho_inf``, 0 when not given."""
        return 0.0 if self.rho_inf is None else float(self.rho_inf)

    def generalized_alpha(self) -> tuple[float, float]:
        """(α_m, α_f) of the balance instants: (0, −α) for HHT-α, Chung & Hulbert's
        ((2ρ∞ − 1)/(ρ∞ + 1), ρ∞/(ρ∞ + 1)) for generalised-α."""
        _, _, am, af = scheme_parameters(self.alpha, self.rho_inf)
        return am, af

    def solver(self) -> SolverSettings:
        """The interface solver's settings."""
        return SolverSettings(tolerance=self.tolerance)

    def steps(self, duration: float) -> int:
        """Number of steps that cover ``duration`` (s): round(duration / dt)."""
        if not (math.isfinite(duration) and duration >= 0.0):
            raise ValueError(f"duration must be a finite number >= 0 s, got {duration}")
        n = duration / self.dt
        if n > 1e9:
            raise ValueError(f"duration {duration} s is {n:.3g} steps of {self.dt} s: too many")
        if duration > 0 and round(n) == 0:
            raise ValueError(
                f"duration {duration} s is less than half a time step (dt = "
                f"{self.dt} s): no step to take; expected at least one step"
            )
        return round(n)


__all__ = ["DynamicSettings"]
