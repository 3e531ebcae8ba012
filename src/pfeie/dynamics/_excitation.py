"""Ground motion acting on a model, in the relative or the absolute form (method.md §6).

- ``form="relative"``: a fixed base; each record adds the inertia load −M ι a_g(t) (ι the
  influence vector of its direction); the outputs are relative to the ground, and the
  absolute accelerations are a + Σ ι a_g;
- ``form="absolute"``: every prescribed DOF moves with the ground,
  u_p(t) = ū_p + Σ ι d_g(t), with d_g integrated exactly from the piecewise-linear record
  (apply :meth:`GroundMotion.baseline_corrected` first to remove drift); the blocks see
  the loads −K_fp u_p − C_fp v_p (the mass is lumped, so M_fp = 0), and the pairs on the
  base the prescribed relative motion; the outputs are absolute.

An :class:`Excitation` belongs to one run: the same factorised analysis takes any number
of records, one run each.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from ..errors import ModelError
from ..model import GroundMotion, LinearSystem, Model
from ..typing import FloatArray

Form = Literal["relative", "absolute"]


class Excitation:
    """The loads and prescribed motions of one run (see the module docstring).

    Parameters
    ----------
    model: the model; ``system`` its free-DOF operators with a lumped mass.
    ground: the records (several components act together).
    form: "relative" or "absolute".
    """

    def __init__(
        self,
        model: Model,
        system: LinearSystem,
        ground: Sequence[GroundMotion] = (),
        form: str = "relative",
    ) -> None:
        d = model.dim
        self.ground = list(ground)
        for g in self.ground:
            if g.direction.size != d:
                raise ModelError(f"ground motion {g.name!r}: direction has {g.direction.size} "
                                 f"components, the model is {d}D")  # fmt: skip
        if form not in ("relative", "absolute"):
            raise ModelError(f"ground-motion form must be 'relative' or 'absolute', got {form!r}")
        self.form, self.system, self.dim = form, system, d
        free, pres = system.free, system.prescribed
        iota = [np.tile(g.direction, model.mesh.n_points) for g in self.ground]
        self._iota_M = [system.M @ i[free] for i in iota] if form == "relative" else []
        self._iota_p = [i[pres] for i in iota] if form == "absolute" else []
        self._drive: list[tuple[FloatArray, FloatArray | None]] = []
        if form == "absolute" and self.ground:
            if not pres.size:
                raise ModelError("the absolute form needs supports that move with the ground")
            K_fp = model.stiffness()[free][:, pres]
            C_fp = None
            if model.damping is not None and (model.damping.alpha or model.damping.beta):
                M_full = model.mass(lumped=True)
                C_full = model.damping.alpha * M_full + model.damping.beta * model.stiffness()
                C_fp = C_full[free][:, pres]
            for ip in self._iota_p:
                self._drive.append((-(K_fp @ ip), None if C_fp is None else -(C_fp @ ip)))

    @property
    def moves_supports(self) -> bool:
        """True when the prescribed DOFs move with the ground (absolute form with records)."""
        return bool(self._iota_p)

    def load(self, t: float) -> FloatArray:
        """External load on the free DOFs at t (N): model loads and ground inertia or drive."""
        f = self.system.load(t)
        for g, mi in zip(self.ground, self._iota_M, strict=False):
            f = f - mi * g(t)
        for g, (kg, cg) in zip(self.ground, self._drive, strict=False):
            d, v, _ = g.motion(t)
            f = f + kg * d
            if cg is not None:
                f = f + cg * v
        return f

    def prescribed(self, t: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Displacement, velocity and acceleration of the prescribed DOFs at t."""
        u = self.system.prescribed_values.copy()
        v, a = np.zeros_like(u), np.zeros_like(u)
        for g, ip in zip(self.ground, self._iota_p, strict=False):
            dg, vg, ag = g.motion(t)
            u += ip * dg
            v += ip * vg
            a += ip * ag
        return u, v, a

    def ground_acceleration(self, t: float) -> FloatArray:
        """Σ ι a_g(t) (d,): what turns relative accelerations into absolute ones (zero in
        the absolute form, whose outputs are absolute already)."""
        if self.form != "relative":
            return np.zeros(self.dim)
        return sum((g.direction * g(t) for g in self.ground), np.zeros(self.dim))

    def ground_displacement(self, t: float) -> FloatArray:
        """Σ ι d_g(t) (d,), the displacement of the ground."""
        return sum((g.direction * g.motion(t)[0] for g in self.ground), np.zeros(self.dim))


__all__ = ["Excitation", "Form"]
