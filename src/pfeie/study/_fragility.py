r"""Lognormal fragility functions fitted to a study's demands (Baker 2015).

A fragility function gives the probability that a limit state is reached or exceeded at an
intensity measure IM = x,

    P(DS ≥ ds | IM = x) = Φ(ln(x/θ) / β),

the lognormal CDF of the capacity IM_c with median θ and logarithmic standard deviation β.

Fits (all return a :class:`Fragility`):

- :func:`fit_moments`, IDA data with every capacity observed (Baker 2015, IDA): the
  mean and standard deviation of ln IM_c,

      ln θ̂ = (1/n) Σ ln IM_c,i,    β̂² = 1/(n − 1) Σ (ln IM_c,i − ln θ̂)²,

  with SE(ln θ̂) = β̂/√n and SE(β̂) = β̂/√(2(n − 1)) (SE(ln β̂) = 1/√(2(n − 1)));
- :func:`fit_stripes`, multiple-stripe analysis (MSA) or any (IM, exceeded or not) data:
  the maximum of the binomial likelihood (Baker 2015, MSA) of z_j exceedances in n_j
  runs at IM x_j,

      ln L = Σ_j [ln C(n_j, z_j) + z_j ln Φ(u_j) + (n_j − z_j) ln Φ(−u_j)],
      u_j = ln(x_j/θ)/β;

- :func:`fit_censored`, IDA data with censoring: each record's capacity is known to lie in
  an interval, lower < IM_c ≤ upper, or is observed exactly (lower = upper); the
  likelihood is

      ln L = Σ_exact [ln φ(u_i) − ln β − ln x_i] + Σ_censored ln[Φ(u(upper_i)) − Φ(u(lower_i))],

  so that a record that never reaches the limit state up to its largest IM x_max adds
  ln Φ(−u(x_max)) (right-censored). The stripes' likelihood is the special case where an
  exceedance at x is IM_c ∈ (0, x] and a non-exceedance IM_c ∈ (x, ∞);
- :func:`fit_ida`: the IDA fit of an :class:`~pfeie.study.Exceedance`: the moments when
  every capacity is exact, the censored likelihood otherwise;
- :func:`fit_limit_states`: one fit per :class:`~pfeie.study.LimitState` of a demand table.

The likelihood is maximised in (ln θ, ln β) (both unconstrained, and the likelihood nearer
to quadratic in ln β than in β) by SciPy's trust-region method with the analytic gradient
and Hessian. The standard errors come from the observed Fisher information, the inverse
of minus the Hessian at the optimum, Cov(ln θ̂, ln β̂) = (−∇²ln L)⁻¹; SE(θ̂) = θ̂ SE(ln θ̂)
and SE(β̂) = β̂ SE(ln β̂) (delta method).

The confidence band of the curve (:meth:`Fragility.band`) is the delta method on the
probit u = (ln x − ln θ)/β: Var(û) = g Cov g with g = ∂u/∂(ln θ, ln β) = −(1/β, u), and

    band(x) = Φ(û ± k √Var(û)),

k = Φ⁻¹((1 + level)/2) (pointwise) or √χ²₂(level) (simultaneous over all x,
Working–Hotelling). It is closed-form and vectorised, it stays within [0, 1] and is
asymmetric there, and on the probit scale it is exact for the asymptotic normality of the
estimates; a profile-likelihood band would follow the likelihood's skew better for a
handful of records, at the price of one constrained optimisation per IM, and agrees with
it for a few tens of records.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..typing import FloatArray
from ._ida import (
    Exceedance,
    LimitState,
    NanPolicy,
    Stripes,
    Table,
    first_exceedance,
    ida_curves,
)

log = logging.getLogger(__name__)

_LOG_SQRT_2PI = 0.5 * float(np.log(2.0 * np.pi))


@dataclass(frozen=True, eq=False)
class Fragility:
    """A fitted lognormal fragility function P(DS ≥ ds | IM = x) = Φ(ln(x/θ)/β).

    ``cov`` is the covariance of (ln θ̂, ln β̂); ``se_theta`` and ``se_beta`` the standard
    errors of θ̂ and β̂. ``n_records`` counts the observations (records of an IDA fit, runs
    of a stripes fit), ``n_exceeded`` those that reach the limit state, ``n_censored`` the
    records of an IDA fit whose capacity is only bounded (never reached, reached at the
    first run, or a failed run). ``method`` is ``"moments"``, ``"mle-censored"`` or
    ``"mle-stripes"``; ``loglik`` the log-likelihood at the estimate; ``empirical`` the
    observed fractions of exceedance at each stripe (when known).

    >>> f = fit_moments([0.31, 0.42, 0.48, 0.55, 0.61, 0.78])
    >>> round(f.theta, 3), round(f.beta, 3), round(f.se_theta, 3), round(f.se_beta, 3)
    (0.504, 0.318, 0.065, 0.101)
    >>> p, lo, hi = f.evaluate([0.3, 0.5, 0.8])
    >>> p.round(3), lo.round(3), hi.round(3)
    (array([0.052, 0.49 , 0.927]), array([0.002, 0.205, 0.598]), array([0.367, 0.781, 0.996]))
    """

    theta: float
    beta: float
    se_theta: float
    se_beta: float
    cov: FloatArray
    n_records: int
    n_exceeded: int
    method: str
    loglik: float
    name: str = ""
    n_censored: int = 0
    empirical: Stripes | None = None

    def _u(self, im: ArrayLike) -> tuple[FloatArray, FloatArray]:
        x = np.asarray(im, dtype=float)
        if np.any(np.isnan(x) | (x < 0)):
            raise ModelError("a fragility function is evaluated at IM values ≥ 0")
        with np.errstate(divide="ignore"):
            return x, (np.log(x) - np.log(self.theta)) / self.beta

    def probability(self, im: ArrayLike) -> FloatArray:
        """Φ(ln(x/θ)/β) at the IM values ``im`` (0 at IM = 0)."""
        from scipy import special

        return np.asarray(special.ndtr(self._u(im)[1]), dtype=float)

    def __call__(self, im: ArrayLike) -> FloatArray:
        return self.probability(im)

    def _k(self, level: float, simultaneous: bool) -> float:
        from scipy import stats

        if not 0 < level < 1:
            raise ModelError(f"a confidence level is in (0, 1), found {level!r}")
        if simultaneous:
            return float(np.sqrt(stats.chi2.ppf(level, 2)))
        return float(stats.norm.ppf(0.5 + level / 2))

    def band(
        self, im: ArrayLike, level: float = 0.95, *, simultaneous: bool = False
    ) -> tuple[FloatArray, FloatArray]:
        """The confidence band (lower, upper) of the curve at ``im``: Φ(û ± k sd(û)), the
        delta method on the probit û = ln(x/θ̂)/β̂ with Var(û) = Cov₀₀/β² + 2û Cov₀₁/β +
        û² Cov₁₁ (Cov of ln θ̂, ln β̂); pointwise, or simultaneous over all IM
        (k = √χ²₂(level))."""
        from scipy import special

        x, u = self._u(im)
        k = self._k(level, simultaneous)
        c = self.cov
        pos = np.isfinite(u)
        uu = np.where(pos, u, 0.0)
        var = c[0, 0] / self.beta**2 + 2 * uu * c[0, 1] / self.beta + uu**2 * c[1, 1]
        sd = np.sqrt(np.maximum(var, 0.0))
        end = np.where(x > 0, 1.0, 0.0)  # IM = 0 or inf
        lo = np.where(pos, special.ndtr(uu - k * sd), end)
        hi = np.where(pos, special.ndtr(uu + k * sd), end)
        return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)

    def evaluate(
        self, im: ArrayLike, level: float = 0.95, *, simultaneous: bool = False
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(probability, band lower, band upper) at ``im``."""
        lo, hi = self.band(im, level, simultaneous=simultaneous)
        return self.probability(im), lo, hi

    def interval(self, level: float = 0.95) -> tuple[tuple[float, float], tuple[float, float]]:
        """Confidence intervals of θ and β, each exp(ln θ̂ ± k SE(ln θ̂)) (Wald intervals on
        the log scale, where the estimates are nearer to normal)."""
        k = self._k(level, False)
        st, sb = np.sqrt(np.diag(self.cov))
        return (
            (self.theta * float(np.exp(-k * st)), self.theta * float(np.exp(k * st))),
            (self.beta * float(np.exp(-k * sb)), self.beta * float(np.exp(k * sb))),
        )


#: a fitted dispersion β below this gets a warning: record-to-record dispersions of
#: structures lie at 0.2 to 0.6 (FEMA P-58), and β → 0 means that every record crossed the
#: limit state at the same intensity (a new user's study of one motion given twice, as an
#: .AT2 file and as a two-column file: β = 9e-9)
BETA_DEGENERATE = 1e-3


def _make(
    mu: float,
    s: float,
    cov: FloatArray,
    method: str,
    loglik: float,
    n: int,
    n_exc: int,
    name: str,
    n_censored: int = 0,
    empirical: Stripes | None = None,
) -> Fragility:
    theta, beta = float(np.exp(mu)), float(np.exp(s))
    se_lnt, se_lnb = (float(v) for v in np.sqrt(np.diag(cov)))
    fit = Fragility(theta=theta, beta=beta, se_theta=theta * se_lnt, se_beta=beta * se_lnb,
                    cov=cov, n_records=n, n_exceeded=n_exc, method=method,
                    loglik=float(loglik), name=name, n_censored=n_censored,
                    empirical=empirical)  # fmt: skip
    msg = "fragility %s (%s): θ = %.4g ± %.2g, β = %.3g ± %.2g, %d of %d exceeded"
    log.info(msg, name or "-", method, theta, fit.se_theta, beta, fit.se_beta, n_exc, n)
    if beta < BETA_DEGENERATE:
        log.warning("fragility %s (%s): β = %.2g, below %g: the records cross the limit "
                    "state at one intensity (the same motion more than once?); a "
                    "fragility's dispersion needs records of different motions",
                    name or "-", method, beta, BETA_DEGENERATE)  # fmt: skip
    return fit


def _positive(values: ArrayLike, what: str) -> FloatArray:
    try:
        x = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ModelError(f"{what}: expected numbers") from None
    ok = (x > 0) & np.isfinite(x)
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise ModelError(f"{what}: expected finite numbers > 0; entry {i} is {x[i]!r}")
    return x


def fit_moments(im_c: ArrayLike, *, name: str = "", empirical: Stripes | None = None) -> Fragility:
    """The method of moments on the capacities IM_c of n records (Baker 2015, IDA):
    ln θ̂ = mean(ln IM_c), β̂ = std(ln IM_c) with n − 1 degrees of freedom;
    SE(ln θ̂) = β̂/√n, SE(ln β̂) = 1/√(2(n − 1)), uncorrelated (normal samples).

    Every capacity must be observed: for records that never reach the limit state use
    :func:`fit_censored` or :func:`fit_ida`.

    >>> f = fit_moments([0.4, 0.5, 0.625])
    >>> round(f.theta, 6), round(f.beta, 4)
    (0.5, 0.2231)
    """
    x = _positive(im_c, "fit_moments: the capacities IM_c")
    n = x.size
    if n < 2:
        raise ModelError(f"fit_moments needs at least 2 capacities, found {n}")
    ln = np.log(x)
    mu = float(ln.mean())
    beta = float(ln.std(ddof=1))
    if not beta > 0:
        raise ModelError("fit_moments: every capacity is the same; β would be 0")
    cov = np.diag([beta**2 / n, 1.0 / (2 * (n - 1))])
    u = (ln - mu) / beta
    loglik = float(np.sum(-0.5 * u**2 - np.log(beta) - ln - _LOG_SQRT_2PI))
    return _make(mu, float(np.log(beta)), cov, "moments", loglik, n, n, name, 0, empirical)


def _log_diff_ndtr(a: FloatArray, b: FloatArray) -> FloatArray:
    """ln(Φ(b) − Φ(a)) for a < b (±inf allowed), accurate in both tails."""
    from scipy import special

    flip = a > 0
    x = np.where(flip, -b, a)
    y = np.where(flip, -a, b)
    ly, lx = special.log_ndtr(y), special.log_ndtr(x)
    with np.errstate(divide="ignore"):
        return np.asarray(ly + np.log1p(-np.exp(lx - ly)), dtype=float)


class _Likelihood:
    """The interval-censored lognormal log-likelihood in p = (ln θ, ln β) with its
    gradient and Hessian; observations weighted by ``w`` (counts)."""

    def __init__(self, lower: FloatArray, upper: FloatArray, w: FloatArray) -> None:
        exact = lower == upper
        self.ln_x = np.log(lower[exact])
        self.w_x = w[exact]
        with np.errstate(divide="ignore"):
            self.ln_a = np.log(lower[~exact])
            self.ln_b = np.log(upper[~exact])
        self.w_i = w[~exact]

    def __call__(self, p: FloatArray) -> tuple[float, FloatArray, FloatArray]:
        mu, s = float(p[0]), float(p[1])
        beta = float(np.exp(s))
        # exact: ln φ(u) − ln β − ln x
        u, w = (self.ln_x - mu) / beta, self.w_x
        ll = float(np.sum(w * (-0.5 * u**2 - s - self.ln_x - _LOG_SQRT_2PI)))
        g = np.array([np.sum(w * u) / beta, np.sum(w * (u**2 - 1))])
        h = np.array(
            [
                [-np.sum(w) / beta**2, -2 * np.sum(w * u) / beta],
                [-2 * np.sum(w * u) / beta, -2 * np.sum(w * u**2)],
            ]
        )
        # censored: ln(Φ(u_b) − Φ(u_a))
        w = self.w_i
        if w.size:
            ua, ub = (self.ln_a - mu) / beta, (self.ln_b - mu) / beta
            lp = _log_diff_ndtr(ua, ub)
            ra = np.exp(-0.5 * ua**2 - _LOG_SQRT_2PI - lp)  # φ(u_a)/P, 0 at −inf
            rb = np.exp(-0.5 * ub**2 - _LOG_SQRT_2PI - lp)
            ua = np.where(np.isfinite(ua), ua, 0.0)
            ub = np.where(np.isfinite(ub), ub, 0.0)
            gm = -(rb - ra) / beta
            gs = -(ub * rb - ua * ra)
            hmm = (ua * ra - ub * rb) / beta**2 - gm**2
            hms = (rb * (1 - ub**2) - ra * (1 - ua**2)) / beta - gm * gs
            hss = ub * rb * (1 - ub**2) - ua * ra * (1 - ua**2) - gs**2
            ll += float(np.sum(w * lp))
            g += [np.sum(w * gm), np.sum(w * gs)]
            h += [[np.sum(w * hmm), np.sum(w * hms)], [np.sum(w * hms), np.sum(w * hss)]]
        return ll, g, h


def _check_identified(lower: FloatArray, upper: FloatArray, what: str) -> None:
    """A finite maximum needs data that no single capacity explains: if one IM c lies in
    every interval (lower, upper] (and equals every exact capacity), the likelihood grows
    without bound as β → 0 (or θ → 0, ∞)."""
    exact = lower == upper
    lo = float(lower[~exact].max(initial=0.0))
    hi = float(upper[~exact].min(initial=np.inf))
    xs = lower[exact]
    degenerate = bool(xs.min() == xs.max() and lo < xs[0] <= hi) if xs.size else lo < hi
    if not degenerate:
        return
    if not np.isfinite(hi) and not xs.size:
        raise ModelError(
            f"{what}: no observation reaches the limit state (none at or below "
            f"IM {lo:g}): θ is not bounded above; run higher intensities"
        )
    if lo == 0 and not xs.size:
        raise ModelError(
            f"{what}: every observation reaches the limit state (all at or "
            f"below IM {hi:g}): θ is not bounded below; run lower intensities"
        )
    raise ModelError(
        f"{what}: the data do not identify a lognormal fragility: a single capacity IM in "
        f"({lo:g}, {hi:g}] explains every observation (no stripe has both exceeding and "
        "non-exceeding runs), so the maximum-likelihood β is 0; add runs at intensities "
        "in that range"
    )


#: the largest dispersion β a fit accepts: fragilities of structures have 0.2 to 0.8 (FEMA
#: P-58; with modelling uncertainty up to about 1); a β of 5 spreads the 16 % to 84 % range
#: over a factor e¹⁰ of the intensity, a curve flat over any data. Data whose share of
#: exceedances does not rise with the intensity drive β → ∞ (a new user's study: 3 of 4
#: records beyond at 0.15 g and the 4th not at 0.3 g gave θ = 0, β = 1.7e5)
BETA_MAX = 5.0


def _mle(
    lower: FloatArray, upper: FloatArray, w: FloatArray, what: str
) -> tuple[float, float, FloatArray, float]:
    """(ln θ̂, ln β̂, Cov, ln L) of the interval-censored lognormal likelihood."""
    keep = w > 0
    lower, upper, w = lower[keep], upper[keep], w[keep]
    _check_identified(lower, upper, what)
    from scipy import optimize

    nll = _Likelihood(lower, upper, w)
    exact = lower == upper
    if np.count_nonzero(exact) >= 2 and np.ptp(np.log(lower[exact])) > 0:
        ln = np.log(lower[exact])
        x0 = np.array([ln.mean(), np.log(max(ln.std(), 0.05))])
    else:
        b = np.concatenate([lower[lower > 0], upper[np.isfinite(upper)]])
        x0 = np.array([np.median(np.log(b)), np.log(0.5)])
    cache: dict[bytes, tuple[float, FloatArray, FloatArray]] = {}

    def ev(p: FloatArray) -> tuple[float, FloatArray, FloatArray]:
        key = np.asarray(p, dtype=float).tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = nll(p)
        return cache[key]

    def fun(p: FloatArray) -> tuple[float, FloatArray]:
        ll, g, _ = ev(p)
        return -ll, -g

    def hess(p: FloatArray) -> FloatArray:
        return -ev(p)[2]

    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # its trial steps
        res = optimize.minimize(
            fun, x0, jac=True, hess=hess, method="trust-exact",
            options={"gtol": 1e-9, "maxiter": 200},
        )  # fmt: skip
    if res.x[1] > np.log(BETA_MAX):
        # the likelihood grows as β → ∞: the share of exceedances does not rise with IM
        raise ModelError(
            f"{what}: the maximum-likelihood β is {np.exp(res.x[1]):.3g}, beyond "
            f"{BETA_MAX:g}: the share of runs that reach the limit state does not rise with "
            "the intensity over the data (e.g. the same share at the lowest and the highest "
            "intensity), so no lognormal curve fits; add runs at lower and higher "
            "intensities, or check the limit state"
        )
    ll, g, h = nll(res.x)
    info = -h
    ok = bool(np.all(np.isfinite(info))) and np.linalg.eigvalsh(info).min() > 0
    scale = 1.0 + float(np.sum(w))
    if not ok or not np.all(np.abs(g) < 1e-5 * scale) or not np.isfinite(ll):
        raise ModelError(
            f"{what}: the likelihood has no proper maximum (optimizer: "
            f"{res.message}; ln θ = {res.x[0]:.4g}, ln β = {res.x[1]:.4g})"
        )
    if res.x[1] < np.log(1e-4):
        raise ModelError(
            f"{what}: the maximum-likelihood β is {np.exp(res.x[1]):.2g}: the "
            "data nearly separate at one IM; add runs around it"
        )
    return float(res.x[0]), float(res.x[1]), np.asarray(np.linalg.inv(info), dtype=float), ll


def fit_censored(
    lower: ArrayLike,
    upper: ArrayLike,
    weight: ArrayLike | None = None,
    *,
    name: str = "",
    empirical: Stripes | None = None,
) -> Fragility:
    """Maximum likelihood with censored capacities: record i has lower_i < IM_c ≤ upper_i,
    observed exactly when lower_i = upper_i, right-censored when upper_i = inf (never
    exceeded up to lower_i), left-censored when lower_i = 0. The log-likelihood sums
    ln φ(u_i) − ln β − ln x_i over the exact records and ln[Φ(u(upper_i)) −
    Φ(u(lower_i))] over the others (``weight``: counts, default 1).

    >>> import numpy as np
    >>> x = np.exp(np.log(0.5) + 0.4 * np.array([-1.2, -0.6, -0.2, 0.2, 0.6, 1.2]))
    >>> up = np.where(x < 0.6, x, np.inf)  # the records stopped at IM 0.6
    >>> f = fit_censored(np.minimum(x, 0.6), up)
    >>> round(f.theta, 3), round(f.beta, 3), f.n_censored
    (0.506, 0.335, 2)
    """
    lo = np.asarray(lower, dtype=float).ravel()
    up = np.asarray(upper, dtype=float).ravel()
    w = np.ones(lo.size) if weight is None else np.asarray(weight, dtype=float).ravel()
    if not (lo.size == up.size == w.size) or lo.size == 0:
        raise ModelError(
            f"fit_censored: lower, upper and weight need one entry per record; "
            f"found {lo.size}, {up.size}, {w.size}"
        )
    bad = ~((lo >= 0) & np.isfinite(lo) & (up > 0) & (up >= lo) & (w >= 0) & np.isfinite(w))
    bad |= (lo == up) & (lo == 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ModelError(
            f"fit_censored: record {i} has lower = {lo[i]!r}, upper = {up[i]!r}, "
            f"weight = {w[i]!r}; expected 0 ≤ lower ≤ upper ≤ inf, upper > 0, "
            "finite weights ≥ 0"
        )
    what = f"fragility {name!r}" if name else "fit_censored"
    mu, s, cov, ll = _mle(lo, up, w, what)
    n, n_exc, n_cens = (round(float(w[m].sum())) for m in (w >= 0, np.isfinite(up), lo != up))
    return _make(mu, s, cov, "mle-censored", ll, n, n_exc, name, n_cens, empirical)


def fit_stripes(
    im: ArrayLike,
    exceeded: ArrayLike,
    total: ArrayLike | None = None,
    *,
    name: str = "",
) -> Fragility:
    """Maximum likelihood on stripes (Baker 2015, MSA): at IM ``im[j]``, ``exceeded[j]``
    of ``total[j]`` runs reach the limit state. Without ``total``, each entry is one run
    and ``exceeded`` its yes/no outcome. ln L = Σ_j [ln C(n_j, z_j) + z_j ln Φ(u_j) +
    (n_j − z_j) ln Φ(−u_j)], u_j = ln(x_j/θ)/β, maximised in (ln θ, ln β).

    >>> f = fit_stripes([0.2, 0.4, 0.6, 0.8, 1.0], [1, 6, 12, 16, 18], [20] * 5)
    >>> round(f.theta, 3), round(f.beta, 3), round(f.loglik, 3)
    (0.515, 0.539, -7.181)
    """
    from scipy import special

    x = _positive(im, "fit_stripes: the intensities")
    z = np.asarray(exceeded, dtype=float).ravel()
    n = np.ones(x.size) if total is None else np.asarray(total, dtype=float).ravel()
    if not (x.size == z.size == n.size):
        raise ModelError(
            f"fit_stripes: im, exceeded and total have different lengths: "
            f"{x.size}, {z.size}, {n.size}"
        )
    bad = ~((z >= 0) & (z <= n) & np.isfinite(n) & (z == np.round(z)) & (n == np.round(n)))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ModelError(
            f"fit_stripes: stripe {i} has {z[i]!r} exceedances of {n[i]!r} runs; "
            "expected whole numbers 0 ≤ exceeded ≤ total"
        )
    levels, inv = np.unique(x, return_inverse=True)
    zs = np.bincount(inv.ravel(), weights=z, minlength=levels.size)
    ns = np.bincount(inv.ravel(), weights=n, minlength=levels.size)
    lower = np.concatenate([np.zeros(levels.size), levels])
    upper = np.concatenate([levels, np.full(levels.size, np.inf)])
    w = np.concatenate([zs, ns - zs])
    what = f"fragility {name!r}" if name else "fit_stripes"
    mu, s, cov, ll = _mle(lower, upper, w, what)
    ll += float(
        np.sum(special.gammaln(ns + 1) - special.gammaln(zs + 1) - special.gammaln(ns - zs + 1))
    )
    stripes = Stripes(levels, np.round(zs).astype(np.int64), np.round(ns).astype(np.int64))
    return _make(mu, s, cov, "mle-stripes", ll, int(ns.sum()), int(zs.sum()), name, 0, stripes)


def fit_ida(
    exceedance: Exceedance,
    *,
    method: Literal["auto", "moments", "mle"] = "auto",
    name: str = "",
) -> Fragility:
    """The fragility of the capacities of :func:`~pfeie.study.first_exceedance`:
    ``"moments"`` (:func:`fit_moments`, every capacity interpolated between runs),
    ``"mle"`` (:func:`fit_censored`: records never beyond the threshold are right-censored
    at their largest IM, those beyond at their first run left-censored), ``"auto"``: the
    moments when no record is censored, else the censored likelihood."""
    e = exceedance
    exact = e.exact
    if method == "auto":
        method = "moments" if exact.all() else "mle"
    if method == "moments":
        if not exact.all():
            raise ModelError(
                f"fragility {name!r}: {int((~exact).sum())} of {exact.size} records have no "
                "interpolated capacity (never reached, or reached at the first run); the "
                "moments need every capacity: use method='mle' (censored)"
            )
        return fit_moments(e.lower, name=name, empirical=e.stripes)
    if method != "mle":
        raise ModelError(f"method must be 'auto', 'moments' or 'mle', found {method!r}")
    return fit_censored(e.lower, e.upper, name=name, empirical=e.stripes)


def fit_limit_states(
    table: Table,
    limit_states: Sequence[LimitState],
    *,
    record: str = "record",
    intensity: str = "im",
    method: Literal["auto", "ida", "stripes"] = "auto",
    ida_method: Literal["auto", "moments", "mle"] = "auto",
    nan_policy: NanPolicy = "raise",
) -> dict[str, Fragility]:
    """One fragility per limit state of a demand table (columns ``record``, ``intensity``
    and each limit state's demand column), by name.

    ``method="ida"``: each record's capacity from its IDA curve (:func:`first_exceedance`)
    fitted by :func:`fit_ida` (``ida_method``); ``"stripes"``: every run is one
    (IM, exceeded or not) observation, fitted by :func:`fit_stripes`; ``"auto"``: IDA when
    some record is run at more than one intensity, stripes otherwise. ``nan_policy``: see
    :func:`~pfeie.study.ida_curves`.

    >>> table = {"record": [1, 1, 1, 2, 2, 2, 3, 3, 3], "im": [0.2, 0.4, 0.6] * 3,
    ...          "fs": [1.6, 1.2, 1.0, 1.5, 0.9, 0.8, 1.4, 1.3, 1.1]}
    >>> fits = fit_limit_states(table, [LimitState("sliding", "fs", 1.0, "<=")])
    >>> f = fits["sliding"]
    >>> f.method, f.n_records, f.n_exceeded, f.n_censored
    ('mle-censored', 3, 2, 1)
    """
    names = [ls.name for ls in limit_states]
    if len(set(names)) != len(names):
        raise ModelError(f"limit state names must differ, found {names}")
    if method not in ("auto", "ida", "stripes"):
        raise ModelError(f"method must be 'auto', 'ida' or 'stripes', found {method!r}")
    out: dict[str, Fragility] = {}
    curves: dict[str, Any] = {}
    for ls in limit_states:
        if ls.column not in curves:
            curves[ls.column] = ida_curves(
                table, ls.column, record=record, intensity=intensity, nan_policy=nan_policy
            )
        c = curves[ls.column]
        how = method
        if how == "auto":
            how = "ida" if int(c.n_points.max()) > 1 else "stripes"
        if how == "ida":
            e = first_exceedance(c, ls.threshold, ls.direction)
            out[ls.name] = fit_ida(e, method=ida_method, name=ls.name)
        else:
            valid = np.arange(c.im.shape[1])[None, :] < c.n_points[:, None]
            hit = ls.exceeded(c.demand) | np.isnan(c.demand)
            out[ls.name] = fit_stripes(c.im[valid], hit[valid], name=ls.name)
    return out
