"""Fragility functions and IDA curves of a study (pfeie.study, pfeie.plot; docs/fragility.md).

Synthetic data with known parameters: capacities ln IM_c ~ N(ln θ, β²) with θ = 0.5,
β = 0.4 (Baker 2015's setting), and binomial stripes with P = Φ(ln(x/θ)/β). The fits must
recover θ and β within their standard errors, their 95 % intervals must cover the truth
in about 95 % of 200 samples, censoring must remove the bias of the naive fit, and the
first exceedance must match hand-computed interpolations.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, special, stats

from pfeie.errors import ModelError, PfeieError
from pfeie.plot import plot_fragility, plot_ida, save_figure
from pfeie.study import (
    LimitState,
    first_exceedance,
    fit_censored,
    fit_ida,
    fit_limit_states,
    fit_moments,
    fit_stripes,
    ida_curves,
    ida_summary,
)

THETA, BETA = 0.5, 0.4
STRIPES = np.linspace(0.1, 1.0, 10)
# A 3-standard-error test on one sample fails about 0.5 % of the time per parameter even
# for a perfect estimator (seeds 5 and 7 draw samples whose own mean is 2.6 and 3.3 SE
# from ln θ); the per-seed tests use the seeds below, the 200-sample coverage tests carry
# the statistical claim.
SEEDS = range(100, 106)


def capacities(seed: int, n: int = 40) -> np.ndarray:
    return np.exp(np.random.default_rng(seed).normal(np.log(THETA), BETA, n))


def stripe_counts(seed: int, runs: int = 20) -> np.ndarray:
    p = special.ndtr(np.log(STRIPES / THETA) / BETA)
    return np.random.default_rng(seed).binomial(runs, p)


def censored(seed: int, cap: float = 0.6, n: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """IDA capacities of records run up to IM = cap: (lower, upper)."""
    x = capacities(seed, n)
    return np.minimum(x, cap), np.where(x <= cap, x, np.inf)


def z_scores(fit) -> tuple[float, float]:  # type: ignore[no-untyped-def]
    return (fit.theta - THETA) / fit.se_theta, (fit.beta - BETA) / fit.se_beta


def covers(fit) -> tuple[bool, bool]:  # type: ignore[no-untyped-def]
    (t0, t1), (b0, b1) = fit.interval(0.95)
    return t0 <= THETA <= t1, b0 <= BETA <= b1


# --------------------------------------------------------------------------- moments


@pytest.mark.parametrize("seed", SEEDS)
def test_moments_recover_theta_and_beta(seed: int) -> None:
    fit = fit_moments(capacities(seed))
    zt, zb = z_scores(fit)
    assert abs(zt) < 3 and abs(zb) < 3, (fit.theta, fit.beta, zt, zb)
    assert fit.method == "moments" and fit.n_records == fit.n_exceeded == 40
    ln = np.log(capacities(seed))
    assert fit.theta == pytest.approx(np.exp(ln.mean()), rel=1e-12)
    assert fit.beta == pytest.approx(ln.std(ddof=1), rel=1e-12)
    assert fit.se_theta == pytest.approx(fit.theta * fit.beta / np.sqrt(40), rel=1e-12)
    assert fit.se_beta == pytest.approx(fit.beta / np.sqrt(2 * 39), rel=1e-12)


def coverage(fits: list) -> tuple[float, float]:  # type: ignore[type-arg]
    c = np.array([covers(f) for f in fits])
    return float(c[:, 0].mean()), float(c[:, 1].mean())


def test_moments_intervals_cover_the_truth() -> None:
    """95 % intervals of θ and β cover the true values in 90–99 % of 200 samples, and so
    does the pointwise band of the curve at IM = θ e^β (true P = Φ(1) = 0.841)."""
    fits = [fit_moments(capacities(seed)) for seed in range(1000, 1200)]
    ct, cb = coverage(fits)
    assert 0.90 <= ct <= 0.99 and 0.90 <= cb <= 0.99, (ct, cb)
    x = THETA * np.exp(BETA)
    band = np.array([f.band(x) for f in fits])
    cp = np.mean((band[:, 0] <= stats.norm.cdf(1)) & (stats.norm.cdf(1) <= band[:, 1]))
    assert 0.90 <= cp <= 0.99, cp


# --------------------------------------------------------------------------- stripes


@pytest.mark.parametrize("seed", SEEDS)
def test_stripes_mle_recovers_theta_and_beta(seed: int) -> None:
    fit = fit_stripes(STRIPES, stripe_counts(seed), np.full(10, 20))
    zt, zb = z_scores(fit)
    assert abs(zt) < 3 and abs(zb) < 3, (fit.theta, fit.beta, zt, zb)
    assert fit.method == "mle-stripes" and fit.n_records == 200


def test_stripes_mle_intervals_cover_the_truth() -> None:
    fits = [fit_stripes(STRIPES, stripe_counts(s), np.full(10, 20)) for s in range(2000, 2200)]
    ct, cb = coverage(fits)
    assert 0.90 <= ct <= 0.99 and 0.90 <= cb <= 0.99, (ct, cb)


def test_stripes_mle_matches_an_independent_binomial_fit() -> None:
    """The maximum, the log-likelihood (with the binomial coefficients) and the observed
    information against scipy.stats.binom, Nelder–Mead and a finite-difference Hessian;
    one yes/no entry per run gives the same estimates."""
    z, n = stripe_counts(7), np.full(10, 20)

    def nll(p: np.ndarray) -> float:
        prob = special.ndtr(np.log(STRIPES / np.exp(p[0])) / np.exp(p[1]))
        return -float(stats.binom.logpmf(z, n, prob).sum())

    ref = optimize.minimize(nll, [np.log(0.4), np.log(0.3)], method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-13})  # fmt: skip
    fit = fit_stripes(STRIPES, z, n)
    assert np.log([fit.theta, fit.beta]) == pytest.approx(ref.x, abs=1e-6)
    assert fit.loglik == pytest.approx(-ref.fun, abs=1e-9)
    h, p0, e = 1e-4, np.log([fit.theta, fit.beta]), np.eye(2)
    hess = np.array([[(nll(p0 + h * e[i] + h * e[j]) - nll(p0 + h * e[i] - h * e[j])
                       - nll(p0 - h * e[i] + h * e[j]) + nll(p0 - h * e[i] - h * e[j]))
                      / (4 * h * h) for j in range(2)] for i in range(2)])  # fmt: skip
    assert fit.cov == pytest.approx(np.linalg.inv(hess), rel=1e-5)
    im = np.repeat(STRIPES, 20)
    yes = (np.arange(20)[None, :] < z[:, None]).ravel()
    single = fit_stripes(im, yes)
    assert (single.theta, single.beta) == pytest.approx((fit.theta, fit.beta), rel=1e-8)
    assert single.empirical is not None
    assert single.empirical.fraction == pytest.approx(z / 20)


# --------------------------------------------------------------------------- censoring


@pytest.mark.parametrize("seed", SEEDS)
def test_censored_mle_recovers_theta_and_beta(seed: int) -> None:
    lower, upper = censored(seed)
    fit = fit_censored(lower, upper)
    zt, zb = z_scores(fit)
    assert abs(zt) < 3 and abs(zb) < 3, (fit.theta, fit.beta, zt, zb)
    assert fit.n_censored == np.isinf(upper).sum() > 0
    assert fit.n_exceeded == 40 - fit.n_censored
    full = fit_moments(capacities(seed))  # the same records, run until they all fail
    assert abs(fit.theta - full.theta) < 1.5 * fit.se_theta
    assert abs(fit.beta - full.beta) < 1.5 * fit.se_beta


def test_censoring_removes_the_bias_of_the_naive_fit() -> None:
    """Records run up to IM 0.6 (a third never reach the limit state): the moments of the
    exceeded ones alone give θ ≈ 0.40, biased by several standard errors; the censored
    likelihood gives θ ≈ 0.5, and its intervals cover the truth."""
    naive, mle = [], []
    for seed in range(3000, 3200):
        lower, upper = censored(seed)
        naive.append(fit_moments(upper[np.isfinite(upper)]))
        mle.append(fit_censored(lower, upper))
    t_naive = np.array([f.theta for f in naive])
    t_mle = np.array([f.theta for f in mle])
    b_mle = np.array([f.beta for f in mle])
    z_naive = np.array([(f.theta - THETA) / f.se_theta for f in naive])
    assert np.median(t_naive) < 0.43 and np.median(z_naive) < -2.5
    assert abs(t_mle.mean() - THETA) < 0.01 and abs(b_mle.mean() - BETA) < 0.02
    ct, cb = coverage(mle)
    assert 0.90 <= ct <= 0.99 and 0.90 <= cb <= 0.99, (ct, cb)


def ida_table(
    seed: int, cap: float = 0.6, stripes: int = 12
) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """An IDA table whose demand IM/IM_c is linear in IM (so interpolation is exact), with
    the safety-factor-like column 1.5 − 0.5 IM/IM_c, ``stripes`` runs per record up to
    IM = cap."""
    x = capacities(seed)
    im = np.arange(1, stripes + 1) * cap / stripes
    rec = np.repeat(np.arange(x.size), im.size)
    ims = np.tile(im, x.size)
    ratio = ims / x[rec]
    order = np.random.default_rng(seed).permutation(rec.size)  # rows in any order
    table = {"record": rec[order], "im": ims[order], "drift": ratio[order],
             "fs": (1.5 - 0.5 * ratio)[order]}  # fmt: skip
    return table, x


def test_limit_states_of_an_ida_table() -> None:
    """fit_limit_states on an IDA table: the capacities interpolated between stripes, the
    records never reaching the limit state right-censored; a ≤ limit state on the falling
    column gives the same fit."""
    table, x = ida_table(11)
    states = [LimitState("drift", "drift", 1.0), LimitState("fs", "fs", 1.0, "<=")]
    fits = fit_limit_states(table, states)
    direct = fit_censored(np.minimum(x, 0.6), np.where(x <= 0.6, x, np.inf))
    for f in fits.values():
        assert f.method == "mle-censored"
        assert (f.theta, f.beta) == pytest.approx((direct.theta, direct.beta), rel=1e-6)
        assert f.n_censored == int((x > 0.6).sum()) and f.empirical is not None
    e = first_exceedance(ida_curves(table, "fs"), 1.0, "<=")
    assert e.im[x <= 0.6] == pytest.approx(x[x <= 0.6], rel=1e-12)
    assert np.all(np.isinf(e.im[x > 0.6]))
    full = fit_limit_states(ida_table(11, cap=3.0, stripes=60)[0], states[:1])["drift"]
    assert full.method == "moments"  # up to IM 3: every record reaches the limit state
    assert (full.theta, full.beta) == pytest.approx((np.exp(np.log(x).mean()),
                                                     np.log(x).std(ddof=1)), rel=1e-12)


def test_ida_method_choice() -> None:
    table, _ = ida_table(12, cap=3.0, stripes=60)
    e = first_exceedance(ida_curves(table, "drift"), 1.0)
    assert e.exact.all()
    assert fit_ida(e).method == "moments"
    assert fit_ida(e, method="mle").method == "mle-censored"
    e2 = first_exceedance(ida_curves(table, "drift"), 5.0)  # some never reach it
    with pytest.raises(ModelError, match="method='mle'"):
        fit_ida(e2, method="moments")


# --------------------------------------------------------------------------- IDA


def hand_table() -> dict[str, list]:  # type: ignore[type-arg]
    rows = [  # record, IM, slip, safety factor
        ("A", 0.1, 0.00, 1.8), ("A", 0.2, 0.02, 1.4), ("A", 0.3, 0.08, 1.1), ("A", 0.4, 0.20, 0.9),
        ("B", 0.1, 0.00, 2.0), ("B", 0.2, 0.01, 1.9), ("B", 0.3, 0.02, 1.7), ("B", 0.4, 0.03, 1.5),
        ("C", 0.1, 0.07, 1.0), ("C", 0.2, 0.30, 0.8),
        ("D", 0.1, 0.00, 1.6), ("D", 0.2, 0.06, 1.2), ("D", 0.3, 0.03, 1.3), ("D", 0.4, 0.10, 1.0),
        ("E", 0.1, 0.00, 1.7), ("E", 0.2, 0.04, 1.3), ("E", 0.3, np.nan, np.nan),
    ]  # fmt: skip
    rows = rows[::-1]  # any row order
    return {k: [r[i] for r in rows] for i, k in enumerate(("record", "im", "slip", "fs"))}


def test_first_exceedance_by_hand() -> None:
    """slip ≥ 0.05: A between 0.2 (0.02) and 0.3 (0.08): 0.2 + 0.03/0.06·0.1 = 0.25;
    B never (right-censored at 0.4); C beyond at its first run (0, 0.1]; D non-monotone,
    the first crossing 0.1 + 0.05/0.06·0.1; E fails at 0.3 (NaN): (0.2, 0.3]."""
    with pytest.raises(ModelError, match="NaN"):
        ida_curves(hand_table(), "slip")
    c = ida_curves(hand_table(), "slip", nan_policy="exceeded")
    assert list(c.records) == ["A", "B", "C", "D", "E"]
    assert c.curve(0)[0] == pytest.approx([0.1, 0.2, 0.3, 0.4])
    e = first_exceedance(c, 0.05)
    assert e.lower == pytest.approx([0.25, 0.4, 0.0, 0.1 + 0.05 / 0.06 * 0.1, 0.2])
    assert e.upper == pytest.approx([0.25, np.inf, 0.1, 0.1 + 0.05 / 0.06 * 0.1, 0.3])
    assert list(e.exact) == [True, False, False, True, False]
    assert list(e.exceeded) == [True, False, True, True, True]
    # cumulative fractions: at 0.1 C; at 0.2 C, D; at 0.3 A, C, D, E; at 0.4 the same,
    # out of the records run there or already beyond (C and E stopped)
    assert list(e.stripes.im) == pytest.approx([0.1, 0.2, 0.3, 0.4])
    assert list(e.stripes.n_exceeded) == [1, 2, 4, 4]
    assert list(e.stripes.n_total) == [5, 5, 5, 5]
    # safety factor ≤ 1.0: A 0.3 + (1.0 − 1.1)/(0.9 − 1.1)·0.1 = 0.35; D at 0.4 exactly
    f = first_exceedance(ida_curves(hand_table(), "fs", nan_policy="omit"), 1.0, "<=")
    assert f.im == pytest.approx([0.35, np.inf, 0.1, 0.4, np.inf])
    assert f.lower == pytest.approx([0.35, 0.4, 0.0, 0.4, 0.2])


def test_ida_summary_counts_collapsed_records() -> None:
    """Fractiles across records at each IM; a record that collapsed counts as +inf, so the
    84 % curve is infinite once more than 16 % collapsed; unknown records are left out."""
    c = ida_curves(hand_table(), "slip", nan_policy="exceeded")
    collapse = first_exceedance(c, 0.05)
    s = ida_summary(c, grid=[0.1, 0.15, 0.4], collapse=collapse)
    assert s.percentiles == (16.0, 50.0, 84.0)
    # at 0.1: C collapsed; the others 0 → (0, 0, inf)
    assert s.demand[:, 0] == pytest.approx([0.0, 0.0, np.inf])
    assert s.n_known[0] == 5 and s.n_collapsed[0] == 1
    # at 0.15: A 0.01, B 0.005, D 0.03, E 0.02, C inf → sorted 0.005 0.01 0.02 0.03 inf
    assert s.demand[:, 1] == pytest.approx([0.0082, 0.02, np.inf])
    # at 0.4: B 0.03 and four collapsed records
    assert s.demand[:, 2] == pytest.approx([np.inf, np.inf, np.inf])
    assert s.n_collapsed[2] == 4
    plain = ida_summary(c, grid=[0.35], percentiles=(50.0,))
    assert plain.n_known[0] == 3  # A, B, D run beyond 0.35; C, E stopped
    assert plain.demand[0, 0] == pytest.approx(0.065)  # median of 0.14, 0.025, 0.065
    with pytest.raises(ModelError, match="percentiles"):
        ida_summary(c, percentiles=(50.0, 120.0))


# --------------------------------------------------------------------------- band


def test_band_contains_the_curve_and_has_its_closed_form_at_the_median() -> None:
    """For the moments, at IM = θ̂ (û = 0): Var(û) = Var(ln θ̂)/β̂² = 1/n, so the band is
    Φ(±1.96/√n); the simultaneous band is wider; the band is 0 at IM 0."""
    fit = fit_moments(capacities(3))
    lo, hi = fit.band(fit.theta)
    k = stats.norm.ppf(0.975)
    closed = stats.norm.cdf([-k / np.sqrt(40), k / np.sqrt(40)])
    assert (float(lo), float(hi)) == pytest.approx(closed)
    x = np.linspace(0, 2, 41)
    p, lo, hi = fit.evaluate(x)
    assert np.all((lo <= p) & (p <= hi)) and lo[0] == hi[0] == p[0] == 0
    slo, shi = fit.band(x, simultaneous=True)
    assert np.all((slo <= lo) & (shi >= hi)) and np.all(shi[1:] - slo[1:] > hi[1:] - lo[1:])
    assert fit(fit.theta) == pytest.approx(0.5)


# --------------------------------------------------------------------------- errors


def test_errors_name_the_problem() -> None:
    table = hand_table()
    with pytest.raises(ModelError, match=r"no demand column 'drift'.*'slip'"):
        ida_curves(table, "drift")
    with pytest.raises(ModelError, match=r"two rows at the intensity 0\.1"):
        ida_curves({"record": [1, 1], "im": [0.1, 0.1], "d": [0, 1]}, "d")
    with pytest.raises(ModelError, match="finite numbers > 0"):
        ida_curves({"record": [1, 1], "im": [0.0, 0.1], "d": [0, 1]}, "d")
    with pytest.raises(ModelError, match="direction"):
        LimitState("x", "d", 1.0, "<")  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="no observation reaches"):
        fit_stripes([0.1, 0.2], [0, 0], [10, 10])
    with pytest.raises(ModelError, match="every observation reaches"):
        fit_stripes([0.1, 0.2], [10, 10], [10, 10])
    with pytest.raises(ModelError, match=r"single capacity IM in \(0.2, 0.3\]"):
        fit_stripes([0.1, 0.2, 0.3, 0.4], [0, 0, 10, 10], [10] * 4)
    with pytest.raises(ModelError, match="IM_c"):
        fit_moments([0.3, np.inf])
    with pytest.raises(PfeieError, match="0 ≤ lower ≤ upper"):
        fit_censored([0.5], [0.4])
    # 3 of 4 beyond at the lowest IM (0.15) and the 4th not at the highest (0.3): the same
    # share at both, no rise; the likelihood grows as β → ∞ (a new user's study wrote
    # θ = 0, β = 1.7e5 with an empty note)
    with pytest.raises(ModelError, match=r"maximum-likelihood β is .*, beyond 5: the share "
                       r"of runs that reach the limit state does not rise"):  # fmt: skip
        fit_censored([0, 0, 0, 0.3], [0.15, 0.15, 0.15, np.inf])
    with pytest.raises(ModelError, match="limit state names"):
        fit_limit_states(table, [LimitState("a", "slip", 0.1)] * 2, nan_policy="omit")


def test_pyarrow_table() -> None:
    pa = pytest.importorskip("pyarrow")
    table, _ = ida_table(5)
    fits = fit_limit_states(pa.table(table), [LimitState("drift", "drift", 1.0)])
    assert fits["drift"].theta == pytest.approx(fit_limit_states(table, [
        LimitState("drift", "drift", 1.0)])["drift"].theta)  # fmt: skip
    with pytest.raises(ModelError, match="intensity column 'pga'"):
        ida_curves(pa.table(table), "drift", intensity="pga")


def test_stripes_method_on_a_table_of_one_run_per_record() -> None:
    z = stripe_counts(4)
    rec = np.arange(200)
    im = np.repeat(STRIPES, 20)
    slip = (np.arange(20)[None, :] < z[:, None]).ravel() * 0.2
    fits = fit_limit_states({"record": rec, "im": im, "slip": slip}, [LimitState("s", "slip", 0.1)])
    ref = fit_stripes(STRIPES, z, np.full(10, 20))
    assert fits["s"].method == "mle-stripes"
    assert (fits["s"].theta, fits["s"].beta) == pytest.approx((ref.theta, ref.beta), rel=1e-8)


# --------------------------------------------------------------------------- plots


def test_plots_have_the_expected_lines(tmp_path) -> None:  # type: ignore[no-untyped-def]
    table, _ = ida_table(2)
    c = ida_curves(table, "drift")
    s = ida_summary(c, collapse=first_exceedance(c, 1.0))
    fig = plot_ida(c, s, threshold=1.0)
    ax = fig.axes[0]
    assert len(ax.lines) == 40 + 3 + 1
    assert [ln.get_linewidth() for ln in ax.lines[40:43]] == [2.2] * 3
    assert len(plot_ida(c).axes[0].lines) == 40
    fits = fit_limit_states(table, [LimitState("drift", "drift", 1.0),
                                    LimitState("fs", "fs", 0.8, "<=")])  # fmt: skip
    fig2 = plot_fragility(list(fits.values()))
    ax2 = fig2.axes[0]
    assert len(ax2.lines) == 4 and len(ax2.collections) == 2  # curve + points, band
    x, y = ax2.lines[1].get_data()
    e = fits["drift"].empirical
    assert e is not None and np.allclose(x, e.im) and np.allclose(y, e.fraction)
    bare = fit_moments(capacities(0))
    assert len(plot_fragility(bare).axes[0].lines) == 1
    for f, name in ((fig, "sub/ida.png"), (fig2, "fragility.png")):
        p = save_figure(f, tmp_path / name)
        assert p.stat().st_size > 5000


def test_a_degenerate_dispersion_is_warned(caplog: pytest.LogCaptureFixture) -> None:
    """Two records of one motion (a new user gave El Centro as an .AT2 file and as a
    two-column file in m/s²): their capacities agree to round-off, so the moments' β is
    9e-9 (ln of capacities 1e-8 apart, over √2); the fit stands, with a warning that β
    lies below BETA_DEGENERATE and why. A real dispersion (0.22) gets none."""
    with caplog.at_level("WARNING"):
        f = fit_moments([0.0752, 0.0752 * (1 + 1.3e-8)])
    # 2e-7: the capacities carry round-off of 1e-16 in a difference of 1.3e-8 (measured
    # 2.0e-8 relative)
    assert f.beta == pytest.approx(1.3e-8 / np.sqrt(2), rel=2e-7)
    assert "β = 9.2e-09, below 0.001: the records cross the limit state at one intensity" \
        in caplog.text
    caplog.clear()
    with caplog.at_level("WARNING"):
        fit_moments([0.4, 0.5, 0.625])
    assert "below 0.001" not in caplog.text
