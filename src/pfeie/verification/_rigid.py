"""Exact rigid sliding-block integrator: the independent reference of V2–V5.

A rigid block slides on a plane with Coulomb friction under a base acceleration given
as a piecewise-linear record. Its relative displacement x obeys, while sliding in the
direction σ = sign(ẋ),

    ẍ = p(t) − σ q,          p(t) = κ (−a_g(t)) + p₀,

and stays stuck while |p(t)| ≤ q (two-way) or p(t) ≤ q (one-way: only σ = +1 allowed).
On each linear piece of p the motion is a cubic in time, so the stop instants (ẋ = 0)
and the start instants (p = ±q) are roots of quadratics and lines: the integration is
exact (no time step). Used for: the horizontal plane (κ = 1, q = μ g, Newmark 1965); the
one-way Newmark block (p = −a_g, q = k_y g); an incline (κ, q from the geometry).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import numpy.typing as npt


def _roots_in(c2: float, c1: float, c0: float, lo: float, hi: float) -> list[float]:
    """Real roots of c2 τ² + c1 τ + c0 in (lo, hi]."""
    if abs(c2) < 1e-300:
        if abs(c1) < 1e-300:
            return []
        r = [-c0 / c1]
    else:
        disc = c1 * c1 - 4 * c2 * c0
        if disc < 0:
            return []
        sq = np.sqrt(disc)
        q = -0.5 * (c1 + np.copysign(sq, c1))
        r = [q / c2] + ([c0 / q] if q != 0 else [])
    return sorted(x for x in r if lo < x <= hi)


class RigidBlock:
    """Event-driven exact integration (see module doc).

    Parameters: record times ``t`` and values ``a`` (m/s², linearly interpolated, zero
    after the end), ``q`` (m/s²), ``kappa`` (default 1), ``two_way`` (default True),
    ``t_end`` (s).
    """

    def __init__(
        self, t: np.ndarray, a: np.ndarray, q: float, *, kappa: float = 1.0,
        two_way: bool = True, t_end: float | None = None,
    ) -> None:  # fmt: skip
        t = np.asarray(t, float)
        p = -kappa * np.asarray(a, float)
        if t_end is not None and t_end > t[-1]:
            t = np.r_[t, t[-1] + 1e-12, t_end]
            p = np.r_[p, 0.0, 0.0]
        self.q, self.two_way = q, two_way
        self.knots = [0.0]
        self.state = [(0.0, 0.0, 0)]  # x, v, sigma at each knot (sigma 0: stuck)
        self.p = (t, p)
        self.starts: list[float] = []
        self.stops: list[float] = []
        self._integrate(t, p)

    def _integrate(self, t: np.ndarray, p: np.ndarray) -> None:
        x, v, sig = 0.0, 0.0, 0
        q = self.q
        for i in range(t.size - 1):
            ta, tb = t[i], t[i + 1]
            pa, slope = p[i], (p[i + 1] - p[i]) / (tb - ta)
            tau = 0.0
            L = tb - ta
            while tau < L - 1e-15:
                p0 = pa + slope * tau
                if sig == 0:
                    # stuck: find when p crosses +q (or −q two-way)
                    cands = []
                    if p0 > q * (1 + 1e-12) or (self.two_way and p0 < -q * (1 + 1e-12)):
                        # the drive already exceeds the friction: it slides on at once (a
                        # reversal through v = 0); the knot starts the slide, so that the
                        # motion between here and the next knot is evaluated as sliding
                        sig = 1 if p0 > 0 else -1
                        self._push(ta + tau, x, v, sig)
                    else:
                        for level in [q, -q] if self.two_way else [q]:
                            cands += [r for r in _roots_in(0.0, slope, p0 - level, 1e-15, L - tau)
                                      if (slope > 0) == (level > 0)]  # fmt: skip
                        if not cands:
                            self._push(ta + L, x, v, 0)
                            tau = L
                            break
                        dt_ = min(cands)
                        tau += dt_
                        sig = 1 if pa + slope * tau > 0 else -1
                        self._push(ta + tau, x, v, sig)
                    self.starts.append(ta + tau)
                    continue
                net = (p0 - sig * q) * sig  # drive along the slip direction
                if v * sig <= 1e-12 and (net < -1e-12 * q or (net <= 0 and slope * sig <= 0)):
                    v, sig = 0.0, 0  # stopped exactly at a knot
                    self.stops.append(ta + tau)
                    self._push(ta + tau, x, v, sig)
                    continue
                # sliding: v(τ') = v + (p0 − σq) τ' + slope τ'²/2
                c2, c1, c0 = 0.5 * slope, p0 - sig * q, v
                stop = _roots_in(c2, c1, c0, 1e-14, L - tau)
                stop = [r for r in stop if (c1 + 2 * c2 * r) * sig <= 0]
                h = stop[0] if stop else L - tau
                x = x + v * h + 0.5 * c1 * h * h + slope * h**3 / 6
                v = v + c1 * h + c2 * h * h
                tau += h
                if stop:
                    v = 0.0
                    sig = 0
                    self.stops.append(ta + tau)
                self._push(ta + tau, x, v, sig)

    def _push(self, tk: float, x: float, v: float, sig: int) -> None:
        self.knots.append(tk)
        self.state.append((x, v, sig))

    def displacement(self, times: npt.ArrayLike) -> np.ndarray:
        """x at the given times (exact, from the knots): between a knot t_k and the next
        no record sample lies (the integration puts a knot at each), so p is linear there,
        p(t_k + h) = p_k + p' h, and while sliding in the direction σ

            x(t_k + h) = x_k + v_k h + ½ (p_k − σ q) h² + p' h³/6;

        stuck (σ = 0), x = x_k. All times at once (no loop over them)."""
        tk = np.asarray(self.knots)
        t, p = self.p
        times = np.atleast_1d(np.asarray(times, dtype=float))
        i = np.maximum(np.searchsorted(tk, times, side="right") - 1, 0)
        state = np.asarray(self.state, dtype=float)  # (knots, 3): x, v, σ
        x, v, sig = state[i, 0], state[i, 1], state[i, 2]
        h = np.maximum(times - tk[i], 0.0)
        # the record's piece that holds the interval (its midpoint: a knot at a sample may
        # sit a round-off below it); beyond the record p = 0
        j = np.searchsorted(t, tk[i] + 0.5 * h, side="right") - 1
        inside = (j >= 0) & (j < t.size - 1)
        jj = np.clip(j, 0, t.size - 2)
        slope = np.where(inside, (p[jj + 1] - p[jj]) / (t[jj + 1] - t[jj]), 0.0)
        p0 = np.where(inside, p[jj] + slope * (tk[i] - t[jj]), 0.0)
        moved = v * h + 0.5 * (p0 - sig * self.q) * h * h + slope * h**3 / 6.0
        return np.where(sig == 0, x, x + moved)

    def acceleration(self, times: npt.ArrayLike) -> np.ndarray:
        """ẍ at the given times (exact): p(t) − σ q while sliding, 0 while stuck; at a
        knot, the value just after it."""
        tk = np.asarray(self.knots)
        t, p = self.p
        times = np.atleast_1d(np.asarray(times, dtype=float))
        i = np.maximum(np.searchsorted(tk, times, side="right") - 1, 0)
        sig = np.array([s for _, _, s in self.state], dtype=float)[i]
        return np.where(sig == 0, 0.0, np.interp(times, t, p, right=0.0) - sig * self.q)


def sampled(fn: Callable[[np.ndarray], np.ndarray], t_end: float, dt: float) -> tuple:
    """(t, a) samples of a function on [0, t_end] at step dt."""
    t = np.arange(round(t_end / dt) + 1) * dt
    return t, fn(t)


def rocking(
    alpha: float, p: float, theta0: float, eta: float, t_end: float, n: int = 4001
) -> tuple[np.ndarray, np.ndarray, list[float]]:
    """Housner's rigid rocking block released at rest from the tilt θ₀ (rad).

    Between impacts the block turns about one base corner (θ > 0 about one, θ < 0 about
    the other) and obeys the exact nonlinear equation

        θ'' = −p² sin(α sgn θ − θ),     p² = 3 g/(4 R) for a rectangle 2b × 2h,

    α = atan(b/h), R = √(b² + h²) (Housner 1963). Each impact (θ = 0) multiplies the
    angular velocity by η. Integrated with a tight-tolerance Runge-Kutta method and event
    location; returns (t, θ(t)) on n samples and the impact instants.
    """
    from scipy.integrate import solve_ivp

    def rhs(_: float, y: np.ndarray) -> list[float]:
        s = 1.0 if y[0] > 0 or (y[0] == 0 and y[1] > 0) else -1.0
        return [y[1], -(p**2) * np.sin(alpha * s - y[0])]

    def hit(_: float, y: np.ndarray) -> float:
        return float(y[0])

    hit.terminal = True  # type: ignore[attr-defined]
    hit.direction = 0  # type: ignore[attr-defined]
    ts = np.linspace(0.0, t_end, n)
    th = np.zeros(n)
    t0, y0, impacts = 0.0, np.array([theta0, 0.0]), []
    while t0 < t_end:
        sol = solve_ivp(rhs, (t0, t_end), y0, events=hit, dense_output=True, rtol=1e-11,
                        atol=1e-13)  # fmt: skip
        t1 = float(sol.t[-1])
        sel = (ts >= t0) & (ts <= t1)
        if sel.any():
            th[sel] = sol.sol(ts[sel])[0]
        if sol.status != 1:
            break
        impacts.append(t1)
        w = eta * sol.y_events[0][0][1]
        dt = 1e-9  # leave θ = 0 before the event function is watched again
        y0 = np.array([w * dt, w])
        t0 = t1 + dt
    return ts, th, impacts
