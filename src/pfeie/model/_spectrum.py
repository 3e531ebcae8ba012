r"""Elastic response spectra and intensity measures of an acceleration record.

Response of a linear SDOF oscillator
------------------------------------
A single-degree-of-freedom oscillator of natural period T (s), circular frequency
ω = 2π/T (rad/s) and damping ratio ζ (0 ≤ ζ < 1) on a base that moves with the record
a_g(t) (m/s²) obeys, for the displacement u (m) of the mass *relative to the base*,

.. math::  \ddot u + 2ζω\dot u + ω^2 u = p(t) = -a_g(t),

from rest (u = u̇ = 0 at the first sample t₀). The absolute acceleration of the mass is
ü + a_g = −(2ζω u̇ + ω² u) (m/s²). Signs: u and a_g are positive along the direction of
the record; a base pushed forward leaves the mass behind (u < 0).

The record is piecewise linear between its samples (as :class:`GroundMotion` interpolates
it), so the response is computed *exactly* (to round-off) step by step by the recurrence
of Nigam & Jennings (1969) (Chopra, *Dynamics of Structures*, §5.2, Table 5.2.1). Over a
step of length h from t_i to t_{i+1}, with ω_D = ω√(1−ζ²), E = e^{−ζωh},
S = sin ω_D h, C = cos ω_D h, r = ζ/√(1−ζ²) and k = ω² (unit mass):

.. math::

    u_{i+1} &= A u_i + B \dot u_i + C_p p_i + D_p p_{i+1} \\
    \dot u_{i+1} &= A' u_i + B' \dot u_i + C'_p p_i + D'_p p_{i+1}

    A &= E (r S + C), \qquad B = E S / ω_D \\
    C_p &= \tfrac1k \Big[\tfrac{2ζ}{ωh} + E\Big(\big(\tfrac{1-2ζ^2}{ω_D h} - r\big) S
           - \big(1 + \tfrac{2ζ}{ωh}\big) C\Big)\Big] \\
    D_p &= \tfrac1k \Big[1 - \tfrac{2ζ}{ωh} + E\Big(\tfrac{2ζ^2-1}{ω_D h} S
           + \tfrac{2ζ}{ωh} C\Big)\Big] \\
    A' &= -E \tfrac{ω}{\sqrt{1-ζ^2}} S, \qquad B' = E (C - r S) \\
    C'_p &= \tfrac1k \Big[-\tfrac1h + E\Big(\big(\tfrac{ω}{\sqrt{1-ζ^2}}
            + \tfrac{ζ}{h\sqrt{1-ζ^2}}\big) S + \tfrac1h C\Big)\Big] \\
    D'_p &= \tfrac{1}{kh} \big[1 - E (r S + C)\big]

The coefficients depend on h and T only: they are computed once per distinct step and
all periods are marched together (arrays over the periods, a loop over the time steps).
The recurrence is exact for any h. Where ωh < 1 the closed forms of C_p … D'_p would
lose ε/(ωh)² to cancellation; there they are computed from the integrals of the impulse
response, C_p = I₁/h, D_p = I₀ − I₁/h, C'_p = B − I₀/h, D'_p = I₀/h with
I₀ = ∫₀ʰ g, I₁ = ∫₀ʰ s g, g(s) = e^{−ζωs} sin(ω_D s)/ω_D, summed as power series.

The *peaks* are taken at the samples and at k − 1 equally spaced points inside each
step (where the record is still linear, so the response there is exact too): a peak
between two points is missed by at most 1 − cos(πh/(kT)) relative. By default k is, for
each period, the smallest power of two with h/k ≤ T/20 (1.2 % at most); all periods are
marched at the finest substep and each one's peaks are looked for at its own k points
per step, so the value at a period does not depend on the other periods asked for.
k is at most 64 (:data:`MAX_SUBSTEPS`): below T = 20h/64 the oscillator follows the
record nearly quasi-statically, whose extremes lie at the samples (on El Centro, h =
0.02 s, ζ = 5 %: PSa at T = 1 ms is 1.1e-4 below the PGA, the limit at T = 0, and 1,024
points a step would find 5.9e-4 more). Periods below 1e-3 h (:data:`RIGID_PERIOD`) are
taken as rigid (T = 0); periods beyond 1e4 s are refused.
Peaks are over the duration of the record (t₀ to its last sample); append zeros to a
record to include the free vibration after it.

Spectral values (SI units):

- Sd = max |u| (m), the deformation (displacement) spectrum D;
- PSv = ω Sd (m/s), the pseudo-velocity V;
- PSa = ω² Sd (m/s²), the pseudo-acceleration A (Sa of design codes);
- Sa_abs = max |ü + a_g| (m/s²), the peak absolute acceleration (equal to PSa when ζ = 0);
- Sv = max |u̇| (m/s), the peak relative velocity.

At T = 0 (a rigid oscillator) Sd = PSv = Sv = 0 and PSa = Sa_abs = PGA.

Intensity measures
------------------
Of the piecewise-linear record, integrated exactly (as :meth:`GroundMotion.motion`: the
ground starts at rest at t₀):

- PGA = max |a_g| (m/s²); PGV = max |v_g| (m/s); PGD = max |d_g| (m), over the record
  (the extremes inside a step, where a_g or v_g changes sign, included);
- Arias intensity I_a = π/(2g) ∫ a_g² dt (m/s), g = 9.81 m/s²; per step the integral is
  h (a_i² + a_i a_{i+1} + a_{i+1}²)/3;
- cumulative absolute velocity CAV = ∫ |a_g| dt (m/s);
- significant duration D5-95 = t₉₅ − t₅ (s), between the times where the Husid curve
  ∫₀ᵗ a_g² dτ reaches 5 % and 95 % of its final value (solved inside the step);
- Sa(T₁, ζ) = PSa(T₁) (m/s²).

>>> import numpy as np
>>> t = np.arange(0.0, 10.0 + 1e-9, 0.01)
>>> a = 0.5 * 9.81 * np.ones_like(t)          # a step of 0.5 g from t = 0
>>> s = response_spectrum(t, a, [0.5, 1.0], damping=0.0)
>>> np.round(s.sd / (0.5 * 9.81 / s.omega**2), 6)   # the undamped overshoot: 2 u_static
array([2., 2.])
>>> round(float(s.psa[0] / 9.81), 6)          # PSa = 2 × 0.5 g
1.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..errors import ModelError
from ..typing import FloatArray

#: g (m/s²) of the Arias intensity and of records in g (the project's convention)
G = 9.81
#: automatic substeps: h/k ≤ T / POINTS_PER_PERIOD at each period (k a power of two)
POINTS_PER_PERIOD = 20
#: the most automatic substeps per record step: an oscillator of a period below
#: POINTS_PER_PERIOD h / MAX_SUBSTEPS follows the record quasi-statically, whose extremes
#: lie at the samples, so finer points find nothing more and cost a loop each
MAX_SUBSTEPS = 64
#: periods below RIGID_PERIOD × the shortest record step are taken as T = 0 (a rigid
#: oscillator, Sa = PGA): ω h > 6,000 there, the oscillator's own motion below 1e-3 of
#: the ground's, and ω² would overflow on the way to T = 0
RIGID_PERIOD = 1e-3
#: the longest period (s) of a spectrum: spectra stop at 10 to 20 s; beyond 1e4 s, ω²
#: underflows on the way to T = ∞ (Sd = PGD there)
PERIOD_MAX = 1e4
#: largest number of coefficient arrays (distinct steps × periods) kept in memory
_CACHE = 4_000_000


@dataclass(frozen=True)
class ResponseSpectrum:
    """The elastic response spectrum of a record at the periods ``periods`` (s), for the
    damping ratio ``damping``: arrays over the periods, in SI units (see the module doc).

    ``sd`` (m), ``psv`` = ω sd (m/s), ``psa`` = ω² sd (m/s²), ``sa_abs`` peak absolute
    acceleration (m/s²), ``sv`` peak relative velocity (m/s); ``substeps`` the points
    per record step where the peaks were looked for, per period."""

    periods: FloatArray
    damping: float
    sd: FloatArray
    sv: FloatArray
    sa_abs: FloatArray
    substeps: npt.NDArray[np.int64]

    @property
    def omega(self) -> FloatArray:
        """Circular frequencies ω = 2π/T (rad/s); ``inf`` at T = 0."""
        with np.errstate(divide="ignore", over="ignore"):
            return np.asarray(2.0 * np.pi / self.periods, dtype=float)

    @property
    def _rigid(self) -> npt.NDArray[np.bool_]:
        """The periods taken as T = 0 (below :data:`RIGID_PERIOD` × the record's step)."""
        return np.asarray((self.periods == 0) | ((self.sd == 0) & (self.sa_abs > 0)))

    @property
    def psv(self) -> FloatArray:
        """Pseudo-velocity ω Sd (m/s); 0 where the oscillator is taken as rigid."""
        w = np.where(self._rigid, 0.0, self.omega)
        return np.asarray(w * self.sd, dtype=float)

    @property
    def psa(self) -> FloatArray:
        """Pseudo-acceleration ω² Sd (m/s²); the peak ground acceleration at T = 0 (and
        below :data:`RIGID_PERIOD` × the record's step)."""
        w = np.where(self._rigid, 0.0, self.omega)
        return np.where(self._rigid, self.sa_abs, w * w * self.sd)


def _check(time: npt.ArrayLike, acc: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    t = np.asarray(time, dtype=float).ravel()
    a = np.asarray(acc, dtype=float).ravel()
    if t.size < 2 or t.shape != a.shape:
        raise ModelError(f"a record needs at least 2 samples and one time per sample; got "
                         f"{t.size} times and {a.size} accelerations")  # fmt: skip
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a)) and np.all(np.diff(t) > 0)):
        raise ModelError("a record needs finite accelerations at strictly increasing times")
    return t, a


def _periods(periods: npt.ArrayLike, damping: float) -> FloatArray:
    T = np.atleast_1d(np.asarray(periods, dtype=float))
    if T.ndim != 1 or T.size == 0 or not np.all(np.isfinite(T)) or np.any(T < 0):
        raise ModelError(f"periods: expected finite periods >= 0 s, got {T.tolist()}")
    if np.any(T > PERIOD_MAX):
        raise ModelError(f"periods: expected periods of at most {PERIOD_MAX:g} s, got "
                         f"{T[T > PERIOD_MAX].tolist()}")  # fmt: skip
    if not (math.isfinite(damping) and 0.0 <= damping < 1.0):
        raise ModelError(f"damping: expected a ratio in [0, 1), got {damping}")
    return T


ComplexArray = npt.NDArray[np.complex128]


def _series_integrals(z: ComplexArray) -> tuple[ComplexArray, ComplexArray]:
    """φ₁(z) = (e^z − 1)/z = Σ zⁿ/(n+1)! and ψ(z) = ∫₀¹ x e^{zx} dx = Σ zⁿ/(n!(n+2)),
    by their series (|z| < 1: 24 terms leave < 1e-24)."""
    phi = np.zeros_like(z)
    psi = np.zeros_like(z)
    term = np.ones_like(z)  # zⁿ/n!
    for n in range(24):
        phi += term / (n + 1)
        psi += term / (n + 2)
        term = term * z / (n + 1)
    return phi, psi


def _coefficients(h: FloatArray, omega: FloatArray, zeta: float) -> FloatArray:
    """The 8 coefficients (A, B, C_p, D_p, A', B', C'_p, D'_p) of the recurrence for the
    steps ``h`` (m,) and circular frequencies ``omega`` (n,): shape (m, 8, n).

    Where ωh < 1 the forcing coefficients, whose closed forms lose ε/(ωh)² to
    cancellation, come from the integrals of the impulse response g(s) = e^{−ζωs}
    sin(ω_D s)/ω_D, I₀ = ∫₀ʰ g ds and I₁ = ∫₀ʰ s g ds, summed as series of z = λh,
    λ = −ζω + iω_D (I₀ = Im(h φ₁(z))/ω_D, I₁ = Im(h² ψ(z))/ω_D): C_p = I₁/h,
    D_p = I₀ − I₁/h, C'_p = g(h) − I₀/h, D'_p = I₀/h (g(h) = B)."""
    hh = h[:, None]
    w = omega[None, :]
    sq = math.sqrt(1.0 - zeta * zeta)
    wd = w * sq
    r = zeta / sq
    E = np.exp(-zeta * w * hh)
    S = np.sin(wd * hh)
    C = np.cos(wd * hh)
    k = w * w
    z2 = 2.0 * zeta / (w * hh)
    A = E * (r * S + C)
    B = E * S / wd
    out = np.empty((h.size, 8, omega.size))
    out[:, 0] = A
    out[:, 1] = B
    out[:, 2] = (z2 + E * (((1.0 - 2.0 * zeta**2) / (wd * hh) - r) * S - (1.0 + z2) * C)) / k
    out[:, 3] = (1.0 - z2 + E * ((2.0 * zeta**2 - 1.0) / (wd * hh) * S + z2 * C)) / k
    out[:, 4] = -E * (w / sq) * S
    out[:, 5] = E * (C - r * S)
    out[:, 6] = (-1.0 / hh + E * ((w / sq + zeta / (hh * sq)) * S + C / hh)) / k
    out[:, 7] = (1.0 - A) / (k * hh)
    small = np.broadcast_to(w * hh < 1.0, A.shape)
    if np.any(small):
        hs = np.broadcast_to(hh, A.shape)[small]
        ws = np.broadcast_to(w, A.shape)[small]
        wds = ws * sq
        phi, psi = _series_integrals(np.asarray((-zeta * ws + 1j * wds) * hs, dtype=complex))
        i0 = hs * phi.imag / wds
        i1 = hs * hs * psi.imag / wds
        out[:, 2][small] = i1 / hs
        out[:, 3][small] = i0 - i1 / hs
        out[:, 6][small] = B[small] - i0 / hs
        out[:, 7][small] = i0 / hs
    return out


def _march(
    t: FloatArray, a: FloatArray, omega: FloatArray, zeta: float,
    substeps: npt.NDArray[np.int64], history: bool,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray | None, FloatArray | None]:  # fmt: skip
    """March the oscillators of ``omega`` (> 0) through the record at the finest of
    ``substeps`` (per period, powers of two or all equal): peaks of |u|, |u̇|, |ü + a_g|
    (each period at its own substeps) and (if ``history``) u, u̇ at the samples, shape
    (len(t), len(omega))."""
    n, m = t.size, omega.size
    K = int(substeps.max())
    stride = K // substeps
    # where[j]: the periods whose own points include the end of substep j (None: all)
    where = [None if np.all(stride == 1) else (j + 1) % stride == 0 for j in range(K)]
    h = np.diff(t) / K
    uniq, inv = np.unique(h, return_inverse=True)
    cached = uniq.size * 8 * m <= _CACHE
    coef = _coefficients(uniq, omega, zeta) if cached else None
    p = -a
    u = np.zeros(m)
    v = np.zeros(m)
    peak_u, peak_v, peak_a = np.zeros(m), np.zeros(m), np.zeros(m)
    cu, ck = 2.0 * zeta * omega, omega * omega
    hist_u = np.zeros((n, m)) if history else None
    hist_v = np.zeros((n, m)) if history else None
    frac = np.arange(K + 1) / K
    for i in range(n - 1):
        c = coef[inv[i]] if coef is not None else _coefficients(h[i : i + 1], omega, zeta)[0]
        ps = p[i] + (p[i + 1] - p[i]) * frac
        for j in range(K):
            p0, p1 = ps[j], ps[j + 1]
            u, v = (c[0] * u + c[1] * v + (c[2] * p0 + c[3] * p1),
                    c[4] * u + c[5] * v + (c[6] * p0 + c[7] * p1))  # fmt: skip
            w = where[j]
            if w is None:
                np.maximum(peak_u, np.abs(u), out=peak_u)
                np.maximum(peak_v, np.abs(v), out=peak_v)
                np.maximum(peak_a, np.abs(cu * v + ck * u), out=peak_a)
            else:
                np.maximum(peak_u, np.abs(u), out=peak_u, where=w)
                np.maximum(peak_v, np.abs(v), out=peak_v, where=w)
                np.maximum(peak_a, np.abs(cu * v + ck * u), out=peak_a, where=w)
        if hist_u is not None and hist_v is not None:
            hist_u[i + 1], hist_v[i + 1] = u, v
    return peak_u, peak_v, peak_a, hist_u, hist_v


def _substeps(t: FloatArray, T: FloatArray, substeps: int | None) -> npt.NDArray[np.int64]:
    """Substeps per period: ``substeps`` for all, or by default the smallest power of two
    k with h_max/k ≤ T/POINTS_PER_PERIOD, at most :data:`MAX_SUBSTEPS` (1 at T = 0)."""
    if substeps is not None:
        if not (isinstance(substeps, int | np.integer) and substeps >= 1):
            shown = substeps.item() if isinstance(substeps, np.generic) else substeps
            raise ModelError(f"substeps: expected an integer >= 1, got {shown!r}")
        return np.full(T.size, int(substeps), dtype=np.int64)
    hmax = float(np.diff(t).max())
    with np.errstate(divide="ignore", over="ignore"):
        need = np.where(T > 0, POINTS_PER_PERIOD * hmax / np.where(T > 0, T, 1.0), 1.0)
    # (less 1e-9: 20 × 0.02/0.1 is 4 and a bit in floating point, and asks for 4)
    need = np.minimum(need, MAX_SUBSTEPS)
    return np.asarray(2 ** np.ceil(np.log2(np.maximum(need, 1.0)) - 1e-9), dtype=np.int64)


def response_spectrum(
    time: npt.ArrayLike,
    acceleration: npt.ArrayLike,
    periods: npt.ArrayLike,
    damping: float = 0.05,
    substeps: int | None = None,
) -> ResponseSpectrum:
    """The elastic response spectrum of the record (``time`` s, ``acceleration`` m/s²)
    at ``periods`` (s, ≥ 0) for the damping ratio ``damping`` (0 ≤ ζ < 1).

    ``substeps``: points per record step where the peaks are looked for (the response
    is exact at each); default, per period: the smallest power of two giving at least
    20 points per period (see the module doc).
    Exact recurrence of Nigam & Jennings (1969), see the module doc."""
    t, a = _check(time, acceleration)
    T = _periods(periods, damping)
    k = _substeps(t, T, substeps)
    pga = float(np.abs(a).max())
    sd, sv, sa = np.zeros(T.size), np.zeros(T.size), np.full(T.size, pga)
    rigid = RIGID_PERIOD * float(np.diff(t).min())
    pos = rigid <= T
    k[~pos] = 1
    if np.any(pos):
        omega = 2.0 * np.pi / T[pos]
        sd[pos], sv[pos], sa[pos], _, _ = _march(t, a, omega, float(damping), k[pos], False)
    return ResponseSpectrum(T, float(damping), sd, sv, sa, k)


def sdof_response(
    time: npt.ArrayLike,
    acceleration: npt.ArrayLike,
    periods: npt.ArrayLike,
    damping: float = 0.05,
) -> tuple[FloatArray, FloatArray]:
    """Relative displacement u (m) and velocity u̇ (m/s) of the oscillators of
    ``periods`` (s, > 0) at the samples of the record, shape (len(time), len(periods)),
    by the exact recurrence (see the module doc); the absolute acceleration is
    −(2ζω u̇ + ω² u)."""
    t, a = _check(time, acceleration)
    T = _periods(periods, damping)
    if np.any(T <= 0):
        raise ModelError(f"periods: expected periods > 0 s, got {T.tolist()}")
    ones = np.ones(T.size, dtype=np.int64)
    _, _, _, u, v = _march(t, a, 2.0 * np.pi / T, float(damping), ones, True)
    assert u is not None and v is not None
    return u, v


# -- intensity measures ----------------------------------------------------------------------
def ground_velocity_displacement(
    time: npt.ArrayLike, acceleration: npt.ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Ground velocity (m/s) and displacement (m) at the samples, integrated exactly from
    the piecewise-linear record, from rest at the first sample."""
    t, a = _check(time, acceleration)
    h = np.diff(t)
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * h)])
    d = np.concatenate([[0.0], np.cumsum(v[:-1] * h + h * h * (2 * a[:-1] + a[1:]) / 6)])
    return v, d


def _peaks_inside(
    t: FloatArray, a: FloatArray, v: FloatArray, d: FloatArray
) -> tuple[float, float]:
    """The largest |v_g| and |d_g| at the extremes inside the steps (where a_g, resp.
    v_g, changes sign)."""
    h = np.diff(t)
    a0, a1, v0, d0 = a[:-1], a[1:], v[:-1], d[:-1]
    da = (a1 - a0) / h
    # velocity: a_g = 0 at τ = −a0/da inside the step
    flip = a0 * a1 < 0
    tau = -a0[flip] / da[flip]
    pgv = float(np.abs(v0[flip] + 0.5 * a0[flip] * tau).max(initial=0.0))
    # displacement: v0 + a0 τ + da τ²/2 = 0 inside the step (stable quadratic roots)
    q2, q1, q0 = 0.5 * da, a0, v0
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = q1 * q1 - 4.0 * q2 * q0
        sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
        q = -0.5 * (q1 + np.where(q1 >= 0, 1.0, -1.0) * sq)
        roots = np.stack([np.where(q2 != 0, q / q2, -q0 / q1), q0 / q])
    ok = np.isfinite(roots) & (roots > 0) & (roots < h)
    tau_all = np.where(ok, roots, 0.0)
    disp = d0 + v0 * tau_all + 0.5 * a0 * tau_all**2 + da * tau_all**3 / 6
    pgd = float(np.abs(np.where(ok, disp, 0.0)).max(initial=0.0))
    return pgv, pgd


def husid(time: npt.ArrayLike, acceleration: npt.ArrayLike) -> FloatArray:
    """The cumulative ∫₀ᵗ a_g² dτ (m²/s³) at the samples (exact for the piecewise-linear
    record); the Arias intensity is π/(2g) times its last value."""
    t, a = _check(time, acceleration)
    step = np.diff(t) * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3.0
    return np.concatenate([[0.0], np.cumsum(step)])


def _time_at(t: FloatArray, a: FloatArray, cum: FloatArray, level: float) -> float:
    """The time where the Husid curve reaches ``level`` (solved in its step)."""
    i = int(np.searchsorted(cum, level, side="left")) - 1
    i = min(max(i, 0), t.size - 2)
    h = t[i + 1] - t[i]
    a0, da = a[i], (a[i + 1] - a[i]) / h

    def f(tau: float) -> float:
        return cum[i] + a0 * a0 * tau + a0 * da * tau * tau + da * da * tau**3 / 3.0 - level

    lo, hi = 0.0, h
    for _ in range(200):  # bisection of a non-decreasing cubic, to the last bit
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if f(mid) < 0:
            lo = mid
        else:
            hi = mid
    return float(t[i] + 0.5 * (lo + hi))


def intensity_measures(
    time: npt.ArrayLike,
    acceleration: npt.ArrayLike,
    period: float | None = None,
    damping: float = 0.05,
) -> dict[str, float]:
    """PGA (m/s²), PGV (m/s), PGD (m), Arias intensity (m/s), CAV (m/s), t5, t95 and
    D5-95 (s), and with ``period`` Sa(T₁, ζ) = PSa (m/s²) (see the module doc).

    Keys: ``pga``, ``pgv``, ``pgd``, ``arias``, ``cav``, ``t5``, ``t95``, ``d5_95``,
    ``sa`` (only with ``period``). A record of zeros has no significant duration (nan)."""
    t, a = _check(time, acceleration)
    v, d = ground_velocity_displacement(t, a)
    pgv_in, pgd_in = _peaks_inside(t, a, v, d)
    h = np.diff(t)
    a0, a1 = a[:-1], a[1:]
    abs0, abs1 = np.abs(a0), np.abs(a1)
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = np.where(a0 * a1 < 0, (a0 * a0 + a1 * a1) / (2.0 * (abs0 + abs1)), 0.0)
    cav_steps = np.where(a0 * a1 < 0, cross, 0.5 * (abs0 + abs1)) * h
    cum = husid(t, a)
    total = float(cum[-1])
    out = {
        "pga": float(np.abs(a).max()),
        "pgv": max(float(np.abs(v).max()), pgv_in),
        "pgd": max(float(np.abs(d).max()), pgd_in),
        "arias": math.pi / (2.0 * G) * total,
        "cav": float(np.sum(cav_steps)),
    }
    if total > 0:
        t5, t95 = _time_at(t, a, cum, 0.05 * total), _time_at(t, a, cum, 0.95 * total)
    else:
        t5 = t95 = math.nan
    out.update(t5=t5, t95=t95, d5_95=t95 - t5)
    if period is not None:
        out["sa"] = float(response_spectrum(t, a, [period], damping).psa[0])
    return out


#: names and units of the intensity measures, for tables
INTENSITY_MEASURES = {
    "pga": ("PGA", "m/s²"), "pgv": ("PGV", "m/s"), "pgd": ("PGD", "m"),
    "arias": ("Arias intensity", "m/s"), "cav": ("CAV", "m/s"), "t5": ("t5", "s"),
    "t95": ("t95", "s"), "d5_95": ("D5-95", "s"), "sa": ("Sa(T1)", "m/s²"),
}  # fmt: skip

__all__ = ["INTENSITY_MEASURES", "ResponseSpectrum", "ground_velocity_displacement", "husid",
           "intensity_measures", "response_spectrum", "sdof_response"]  # fmt: skip
