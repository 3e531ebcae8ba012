"""Ground motion acting on a model, in the relative or the absolute form (method.md §6).

- ``form="relative"``: a fixed base; each record adds the inertia load
  −(M_ff ι_f + M_fp ι_p) a_g(t) on the free DOFs (ι the influence vector of its
  direction over all DOFs: the supports move with the ground too); the outputs are
  relative to the ground, and the absolute accelerations are a + Σ ι a_g;
- ``form="absolute"``: every prescribed DOF moves with the ground,
  u_p(t) = ū_p + Σ ι d_g(t), with d_g integrated exactly from the piecewise-linear record
  (apply :meth:`GroundMotion.baseline_corrected` first to remove drift); the blocks see
  the loads −K_fp u_p − C_fp v_p − M_fp a_p, and the pairs on the base the prescribed
  relative motion; the outputs are absolute. On the run's grid of steps the supports
  move as the time scheme integrates a_g (:meth:`Excitation.on_grid`, :class:`GridGround`):
  with the exact d_g(t_k) the scheme's acceleration of everything the supports carry
  is d_g differentiated by the scheme, which at the record's kinks is off by O(1) (a
  stiff block fixed to the base read 4.2 m/s² against a PGA of 3.1 under Newmark's
  trapezoidal rule, 0.59 m/s² under the default scheme at Δt = 5 ms); integrated by the
  scheme, the motion relative to the supports obeys the relative form's equation, and a
  rigid body carried by the supports reads a_g(t_k).

The mass is lumped, so M_fp vanishes unless the reservoir's added mass couples a supported
node to its free components (Westergaard's blocks n nᵀ on an inclined face, or a
finite-element reservoir, at a node with a roller support): then it is kept
(:attr:`~pfeie.model.LinearSystem.M_fp`).

Uplift in joints (:class:`~pfeie.model.Uplift`) is a load of the excitation: the
pre-earthquake pressures (of the static state, given as ``uplift``) stay, or, for the
``"full"`` and ``"zero"`` policies, the pressures of the pairs that open follow their
state (:meth:`Excitation.follow`, called by the analysis after every step: one step late).

An :class:`Excitation` belongs to one run: the same factorised analysis takes any number
of records, one run each.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from os import PathLike
from typing import Literal

import numpy as np

from ..errors import ModelError
from ..model import GroundMotion, LinearSystem, Model, Stations
from ..typing import BoolArray, FloatArray

Form = Literal["relative", "absolute"]


def shorter_than_a_step(record: GroundMotion, dt: float) -> str | None:
    """Why a record cannot drive a run of step ``dt`` (s): it lasts less than one step,
    so the steps would see at most its first sample; None when it can."""
    span = float(record.time[-1] - record.time[0])
    if span < dt:
        return (
            f"the record lasts {span:.6g} s, less than one step (analysis.dt = {dt:g} s); "
            "expected a record of at least one step (check its time column or dt)"
        )
    return None


class GridGround:
    """A record's ground motion as the time scheme integrates it on the run's grid
    t_k = t₀ + k h (the supports' motion in the absolute form, :meth:`Excitation.on_grid`).

    The scheme's kinematics with q̈_k = a_g(t_k) from the exact state at t₀ (Newmark's;
    with ``auxiliary``, through the α-weighted auxiliary acceleration a of Arnold & Brüls
    2007, for the schemes that balance a_g at (α_m, α_f): HHT-α and generalised-α, Chung &
    Hulbert 1993, and the nonsmooth generalised-α):

        (1 − α_m) a_{k+1} + α_m a_k = (1 − α_f) q̈_{k+1} + α_f q̈_k   (a = q̈ without it),
        d_{k+1} = d_k + h v_k + h² ((½ − β) a_k + β a_{k+1}),
        v_{k+1} = v_k + h ((1 − γ) a_k + γ a_{k+1});

    with ``theta``, Moreau–Jean's: v_{k+1} = v_k + h a_θ, a_θ = (1 − θ) a_g(t_k) +
    θ a_g(t_{k+1}) (the acceleration given at t_{k+1}: the step's average, as the scheme
    records it), d_{k+1} = d_k + h ((1 − θ) v_k + θ v_{k+1}).

    With ``start_ahead`` the recurrence starts from q̈₀ = a₀ = a_g(t₀ + h): the nonsmooth
    generalised-α starts from the acceleration a trial first step finds, which for a body
    the supports carry is a_g(t₁) (the acceleration given at t₀ stays a_g(t₀)).

    :meth:`motion` gives (d_k, v_k, q̈_k) on the grid, and off it the exact motion plus
    the scheme's drift d_k − d_g(t_k) (and v's) interpolated linearly between the
    neighbouring steps. The rows are computed once, in order, so a run and its resume
    from a checkpoint read the same bits. An event step taken in n sub-steps moves the
    supports by the same recurrence on the finer grid from row k (:meth:`refined`), and
    the grid goes on from where they end (:meth:`rebase`): the supports then move as the
    blocks' own scheme carries a body fixed to the ground, sub-steps included, and the
    absolute form stays the relative one plus that motion. A checkpoint keeps the row of
    its step (:meth:`row`), from which a resumed run goes on (:meth:`restart`).

    >>> from pfeie.model import GroundMotion
    >>> g = GroundMotion.from_samples([0.0, 1.0, 0.0, -1.0, 0.0], dt=0.01, units="m/s2")
    >>> grid = GridGround(g, 0.0, 0.01, beta=0.25, gamma=0.5)
    >>> grid.motion(0.02)[2] == g(0.02), abs(grid.motion(0.04)[0] - g.motion(0.04)[0]) < 1e-7
    (True, True)
    """

    def __init__(
        self,
        g: GroundMotion,
        t0: float,
        h: float,
        *,
        beta: float = 0.25,
        gamma: float = 0.5,
        alpha_m: float = 0.0,
        alpha_f: float = 0.0,
        auxiliary: bool = False,
        theta: float | None = None,
        start_ahead: bool = False,
    ) -> None:
        self.g, self.t0, self.h, self.theta = g, float(t0), float(h), theta
        self.beta, self.gamma, self.alpha_m, self.alpha_f = beta, gamma, alpha_m, alpha_f
        self.auxiliary = auxiliary
        d, v, a = g.motion(self.t0)
        self._a0 = a  # the acceleration given at t₀
        if start_ahead:  # the scheme's own start (see the class)
            a = g.motion(self.t0 + self.h)[2]
        self._rows: list[tuple[float, float, float, float]] = [(d, v, a, a)]  # d, v, q̈, a
        self._k0 = 0  # the step of rows[0]

    def _row(self, k: int) -> tuple[float, float, float, float]:
        rows, h, b, gm = self._rows, self.h, self.beta, self.gamma
        am, af = self.alpha_m, self.alpha_f
        th = self.theta
        if k < self._k0:
            raise ValueError(f"the grid restarted at step {self._k0} holds no step {k}")
        k -= self._k0
        while len(rows) <= k:
            d, v, qdd, a = rows[-1]
            q1 = self.g.motion(self.t0 + (self._k0 + len(rows)) * h)[2]
            if th is not None:  # Moreau–Jean: a holds a_g(t_k), q̈ the step's average
                a_th = (1.0 - th) * a + th * q1
                v1 = v + h * a_th
                rows.append((d + h * ((1.0 - th) * v + th * v1), v1, a_th, q1))
                continue
            a1 = ((1.0 - af) * q1 + af * qdd - am * a) / (1.0 - am) if self.auxiliary else q1
            rows.append((d + h * v + h * h * ((0.5 - b) * a + b * a1),
                         v + h * ((1.0 - gm) * a + gm * a1), q1, a1))  # fmt: skip
        return rows[k]

    def step_of(self, t: float) -> int | None:
        """The step k with t = t₀ + k h (to round-off), None off the grid."""
        k = round((t - self.t0) / self.h)
        tol = 8 * np.spacing(max(abs(t), self.h))
        return k if k >= 0 and abs(t - (self.t0 + k * self.h)) <= tol else None

    def row(self, k: int) -> tuple[float, float, float, float]:
        """Row k of the recurrence: d_k (m), v_k (m/s), q̈_k and a_k (m/s²; for
        Moreau–Jean the step average a_θ and a_g(t_k))."""
        return self._row(k)

    def refined(self, k: int, n: int) -> GridGround:
        """The same recurrence on the grid of h/n from row k (at t_k): the supports'
        motion over the n sub-steps of the event step k → k + 1."""
        tk = self.t0 + k * self.h
        fine = GridGround(self.g, tk, self.h / n, beta=self.beta, gamma=self.gamma,
                          alpha_m=self.alpha_m, alpha_f=self.alpha_f,
                          auxiliary=self.auxiliary, theta=self.theta)  # fmt: skip
        fine._rows = [self._row(k)]
        fine._a0 = self.motion(tk)[2]
        return fine

    def rebase(self, k: int, row: tuple[float, float, float, float]) -> None:
        """Make ``row`` row k (the end of an event step's sub-steps) and forget the rows
        after it: the grid goes on from there."""
        if k <= self._k0:
            raise ValueError(f"cannot rebase step {k} of a grid from step {self._k0}")
        self._row(k - 1)
        del self._rows[k - self._k0 :]
        self._rows.append(tuple(float(x) for x in row))  # type: ignore[arg-type]

    def restart(self, k: int, row: tuple[float, float, float, float]) -> None:
        """Go on from ``row`` as row k (a resumed run, from its checkpoint's row)."""
        if k > 0:
            self._k0 = k
            self._rows = [tuple(float(x) for x in row)]  # type: ignore[list-item]

    def motion(self, t: float) -> tuple[float, float, float]:
        """Displacement (m), velocity (m/s) and acceleration (m/s²) of the ground at t as
        the scheme moves it (see the class)."""
        x = (t - self.t0) / self.h
        k = self.step_of(t)
        if k is not None:
            return self._row(k)[:3] if k else (*self._row(0)[:2], self._a0)
        exact = self.g.motion(t)
        if t < self.t0:
            return exact
        k0 = int(np.floor(x))
        tau = x - k0
        drift = [0.0, 0.0]
        for j, w in ((k0, 1.0 - tau), (k0 + 1, tau)):
            row, ex_j = self._row(j), self.g.motion(self.t0 + j * self.h)
            drift[0] += w * (row[0] - ex_j[0])
            drift[1] += w * (row[1] - ex_j[1])
        return exact[0] + drift[0], exact[1] + drift[1], exact[2]


class Excitation:
    """The loads and prescribed motions of one run (see the module docstring).

    Parameters
    ----------
    model: the model; ``system`` its free-DOF operators with a lumped mass.
    ground: the records (several components act together).
    form: "relative" or "absolute".
    uplift: the uplift pressure at every pair before the shaking (Pa; the static
        state's, :attr:`pfeie.StaticResult.uplift`); default the uncracked joints'.
    open0: the pairs open before the shaking (the static state's): they keep their
        pre-earthquake uplift under every policy.
    """

    def __init__(
        self,
        model: Model,
        system: LinearSystem,
        ground: Sequence[GroundMotion] | GroundMotion | None = (),
        form: str = "relative",
        uplift: FloatArray | None = None,
        open0: BoolArray | None = None,
    ) -> None:
        d = model.dim
        self.model = model
        self._f_up: FloatArray | None = None
        self._open: bytes = b""
        # the stations of each joint with uplift under shaking = "full" (Uplift.stations)
        self._stations: dict[str, Stations] = {}
        if model.uplifts:
            self._p0 = model.uplift_pressure()[0] if uplift is None else np.asarray(uplift)
            self._f_up = model.uplift_load(self._p0)[system.free]
            m = 0 if model.pairs is None else model.pairs.n
            self._open0 = np.zeros(m, dtype=bool) if open0 is None else np.asarray(open0)
        if ground is None:  # no record
            ground = ()
        elif isinstance(ground, GroundMotion):  # one record given alone
            ground = [ground]
        elif isinstance(ground, str | bytes | PathLike) or not isinstance(ground, Iterable):
            raise ModelError(f"ground: expected a pfeie.GroundMotion or a list of them (a "
                             "file is read with pfeie.io.read_record), got "
                             f"{type(ground).__name__} {ground!r}")  # fmt: skip
        self.ground = list(ground)
        for k, g in enumerate(self.ground):
            if not isinstance(g, GroundMotion):
                raise ModelError(f"ground[{k}]: expected a pfeie.GroundMotion (a file is "
                                 "read with pfeie.io.read_record), got "
                                 f"{type(g).__name__} {g!r}")  # fmt: skip
        # (the default direction (1, 0) is x in 3D too)
        self.ground = [g.in_dim(d) for g in self.ground]
        if form not in ("relative", "absolute"):
            raise ModelError(f"ground-motion form must be 'relative' or 'absolute', got {form!r}")
        self.form, self.system, self.dim = form, system, d
        self._supports_work: bool | None = None  # (see supports_work)
        self._key: tuple[str, str] | None = None  # (see key)
        self._last_support: list[tuple[float, FloatArray, float]] = []  # (support_energy)
        free, pres = system.free, system.prescribed
        iota = [np.tile(g.direction, model.mesh.n_points) for g in self.ground]
        Mfp = system.M_fp
        self._iota_M = ([system.M @ i[free] + (0.0 if Mfp is None else Mfp @ i[pres])
                         for i in iota] if form == "relative" else [])  # fmt: skip
        self._iota_p = [i[pres] for i in iota] if form == "absolute" else []
        self._drive: list[tuple[FloatArray, FloatArray | None, FloatArray | None]] = []
        self._grid: list[GridGround] | None = None  # (see on_grid)
        if form == "absolute" and self.ground:
            if not pres.size:
                raise ModelError("the absolute form needs supports that move with the ground")
            K_fp, C_fp = system.K_fp, system.C_fp  # those of the stepping's operators
            assert K_fp is not None
            for ip in self._iota_p:
                self._drive.append((-(K_fp @ ip), None if C_fp is None else -(C_fp @ ip),
                                    None if Mfp is None else -(Mfp @ ip)))  # fmt: skip

    @property
    def follows_pairs(self) -> bool:
        """True when an uplift follows the pairs' state during the shaking."""
        return any(u.shaking != "keep" for u in self.model.uplifts)

    def follow(self, open_: BoolArray) -> None:
        """Set the uplift of the ``"full"`` and ``"zero"`` policies from the pairs open
        now: under ``"full"``, full headwater pressure ρ_w g (H_w − z) where a pair of the
        joint has opened during the shaking in the crack from the heel (the pairs reached
        from the heel's stations through open neighbours, :meth:`Uplift.stations` and
        :meth:`Stations.reached`: along the joint in 2D, across its face in 3D; water from
        the reservoir reaches no other opening); under ``"zero"``, none where a pair
        has opened; the pre-earthquake pressure elsewhere (closed pairs, openings apart
        from the heel's crack under ``"full"``, and the crack open before the shaking)."""
        key = np.packbits(open_).tobytes()
        if key == self._open or self._f_up is None:
            return
        self._open = key
        P = self.model.pairs
        assert P is not None
        p = self._p0.copy()
        for up in self.model.uplifts:
            if up.shaking == "keep":
                continue
            idx = P.of(up.interface)
            new = open_[idx] & ~self._open0[idx]
            if up.shaking == "zero":
                p[idx[new]] = 0.0
                continue
            if up.interface not in self._stations:
                self._stations[up.interface] = up.stations(
                    P, idx, self.model.joint_facets(up.interface)
                )
            o = idx[new & self._stations[up.interface].reached(open_[idx])]
            p[o] = up.density * up.g * np.maximum(up.headwater - P.x[o, -1], 0.0)
        self._f_up = self.model.uplift_load(p)[self.system.free]

    def on_grid(self, t0: float, h: float, *, beta: float = 0.25, gamma: float = 0.5,
                alpha_m: float = 0.0, alpha_f: float = 0.0, auxiliary: bool = False,
                theta: float | None = None, start_ahead: bool = False) -> None:  # fmt: skip
        """Move the supports of the absolute form as the time scheme integrates the
        records on the grid t₀ + k h (:class:`GridGround`, its parameters the scheme's);
        without it (and in the relative form) the records' exact motion."""
        self._last_support = []  # (another grid: other support motions)
        if self.moves_supports:
            self._grid = [GridGround(g, t0, h, beta=beta, gamma=gamma, alpha_m=alpha_m,
                                     alpha_f=alpha_f, auxiliary=auxiliary, theta=theta,
                                     start_ahead=start_ahead)
                          for g in self.ground]  # fmt: skip

    def grid_rows(self, t: float) -> FloatArray | None:
        """The rows of the supports' grids at t (n_records, 4: :meth:`GridGround.row`),
        what a checkpoint keeps; None where the supports follow no grid or t is off it."""
        if self._grid is None:
            return None
        k = self._grid[0].step_of(t)
        if k is None:
            return None
        return np.array([gg.row(k) for gg in self._grid])

    def restart_grid(self, t: float, rows: FloatArray) -> None:
        """Go on from the grids' ``rows`` at t (a checkpoint's, :meth:`grid_rows`)."""
        if self._grid is None:
            return
        k = self._grid[0].step_of(t)
        if k is None or np.shape(rows) != (len(self._grid), 4):
            raise ValueError(f"the supports' grid rows {np.shape(rows)} at t = {t:g} s do "
                             f"not fit {len(self._grid)} records on the grid")  # fmt: skip
        self._last_support = []
        for gg, row in zip(self._grid, rows, strict=True):
            gg.restart(k, tuple(row))

    @contextmanager
    def refined(self, t: float, n: int) -> Iterator[None]:
        """Within it, the supports follow their grids refined to h/n from the step at t
        (:meth:`GridGround.refined`): an event step's n sub-steps; on leaving without an
        error, the grids go on from where the sub-steps end (:meth:`GridGround.rebase`),
        after an error as before."""
        coarse = self._grid
        if coarse is None:
            yield
            return
        k = coarse[0].step_of(t)
        if k is None:
            raise ValueError(f"an event step from t = {t:g} s, off the supports' grid")
        fine = [gg.refined(k, n) for gg in coarse]
        self._grid, self._last_support = fine, []
        try:
            yield
        finally:
            self._grid, self._last_support = coarse, []
        for gg, ff in zip(coarse, fine, strict=True):
            gg.rebase(k + 1, ff.row(n))

    def _motion(self, i: int, t: float) -> tuple[float, float, float]:
        """Record i's ground motion at t as the supports follow it (see :meth:`on_grid`)."""
        return self.ground[i].motion(t) if self._grid is None else self._grid[i].motion(t)

    @property
    def moves_supports(self) -> bool:
        """True when the prescribed DOFs move with the ground (absolute form with records)."""
        return bool(self._iota_p)

    def load(self, t: float) -> FloatArray:
        """External load on the free DOFs at t (N): model loads and ground inertia or drive."""
        f = self.system.load(t)
        if self._f_up is not None:
            f = f + self._f_up
        for g, mi in zip(self.ground, self._iota_M, strict=False):
            f = f - mi * g(t)
        for i, (kg, cg, mg) in enumerate(self._drive):
            d, v, _ = self._motion(i, t)
            f = f + kg * d
            if cg is not None:
                f = f + cg * v
            if mg is not None:
                # the record's own a_g(t), on the grid the scheme's q̈ too, except for
                # Moreau–Jean, whose grid holds the step average a_θ: its θ-blend of
                # the loads makes a_θ of a_g, as of the blocks' own inertia
                f = f + mg * self.ground[i](t)
        return f

    def prescribed(self, t: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Displacement, velocity and acceleration of the prescribed DOFs at t."""
        u = self.system.prescribed_values.copy()
        v, a = np.zeros_like(u), np.zeros_like(u)
        for i, ip in enumerate(self._iota_p):
            dg, vg, ag = self._motion(i, t)
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

    @property
    def key(self) -> tuple[str, str]:
        """What identifies the excitation of a run, for a checkpoint (a run resumed under
        other records or another form would not continue the run): a digest of the form
        and of each record's times, accelerations and direction, and its wording; hashed
        once (a checkpoint is taken at every recorded row)."""
        if self._key is not None:
            return self._key
        h = hashlib.sha256(self.form.encode())
        for g in self.ground:
            for arr in (g.time, g.acceleration, g.direction):
                h.update(np.ascontiguousarray(arr, dtype=float).tobytes())
        names = ", ".join(f"{g.name!r} along {np.round(g.direction, 6).tolist()}"
                          for g in self.ground)  # fmt: skip
        self._key = (h.hexdigest()[:16], f"the {self.form} form, "
                     + (f"records {names}" if names else "no record"))  # fmt: skip
        return self._key

    @property
    def supports_work(self) -> bool:
        """True when the prescribed DOFs are displaced (moving with the ground in the
        absolute form, or held at given values), so that the strain energy of the whole
        model and the work of the supports' reactions differ from the free DOFs' own
        (:meth:`support_energy`)."""
        if self._supports_work is None:
            sy = self.system
            self._supports_work = bool(
                sy.prescribed.size and sy.K_fp is not None and sy.K_pp is not None
                and (self.moves_supports or np.any(sy.prescribed_values)))  # fmt: skip
        return self._supports_work

    def support_energy(self, t: float, u: FloatArray) -> float:
        """The strain energy of the whole model beyond the free DOFs' ½u_fᵀK_ff u_f at t
        (J): u_fᵀK_fp u_p + ½u_pᵀK_pp u_p, with u_p the prescribed displacements. In the
        absolute form a model that moves rigidly with the ground holds no strain energy:
        ½u_fᵀK_ff u_f alone would count its translation (the drive load −K_fp u_p, in
        the external work, balanced it). Zero where the supports are not displaced."""
        if not self.supports_work:
            return 0.0
        # the energy account and the recorder ask for the same states: the last three
        # answers are kept (u by identity: the states' vectors are never modified in place)
        for t_, vec, value in self._last_support:
            if t_ == t and vec is u:
                return value
        sy = self.system
        assert sy.K_fp is not None and sy.K_pp is not None
        up = self.prescribed(t)[0]
        value = float(u @ (sy.K_fp @ up) + 0.5 * (up @ (sy.K_pp @ up)))
        self._last_support = [(t, u, value), *self._last_support[:2]]
        return value

    def support_damping_work(
        self, t0: float, t1: float, u0: FloatArray, u1: FloatArray, v0: FloatArray,
        v1: FloatArray,
    ) -> float:  # fmt: skip
        """The damping's work over a step beyond the free DOFs' ½Δu_f·C_ff(v_f0 + v_f1)
        by the same trapezoidal rule, where the supports move (J):
        ½Δu_f·C_fp(v_p0 + v_p1) + ½Δu_p·(C_pf(v_f0 + v_f1) + C_pp(v_p0 + v_p1)); with it
        a stiffness-proportional damping dissipates nothing in a rigid motion with the
        ground. Zero where the supports do not move or the model is undamped."""
        sy = self.system
        if not self.moves_supports or sy.C_fp is None or sy.C_pp is None:
            return 0.0
        p0, p1 = self.prescribed(t0), self.prescribed(t1)
        vp = p0[1] + p1[1]
        return 0.5 * float(
            (u1 - u0) @ (sy.C_fp @ vp) + (p1[0] - p0[0]) @ (sy.C_fp.T @ (v0 + v1) + sy.C_pp @ vp)
        )

    def ground_displacement(self, t: float) -> FloatArray:
        """Σ ι d_g(t) (d,), the displacement of the ground (as the supports follow it)."""
        return sum((g.direction * self._motion(i, t)[0] for i, g in enumerate(self.ground)),
                   np.zeros(self.dim))  # fmt: skip


__all__ = ["Excitation", "Form", "GridGround"]
