"""Response spectra, intensity measures and scaling to a target Sa(T, ζ).

Every check is against a reference stated in its docstring (a closed form, an
independent integration, or a published value) with a tolerance within 10× of the error
the code reaches (measured: in the comments)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pfeie.cli import main
from pfeie.errors import ModelError
from pfeie.model import GroundMotion, intensity_measures, response_spectrum, sdof_response

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "src" / "pfeie" / "verification" / "elcentro_1940_ns_chopra.csv"
G = 9.81


def _elcentro() -> tuple[np.ndarray, np.ndarray]:
    data = np.loadtxt(ELCENTRO, delimiter=",", skiprows=1)
    return data[:, 0], data[:, 1]  # s, g


# -- the recurrence against closed forms ---------------------------------------------------
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2])
def test_step_closed_form(zeta: float) -> None:
    """A step a_g = a₀ from t = 0: u(t) = −(a₀/ω²)[1 − e^{−ζωt}(cos ω_D t + ζ/√(1−ζ²)
    sin ω_D t)] (Chopra, Dynamics of Structures, §4.3, eq. 4.3.3 with p₀/k = −a₀/ω²),
    and u̇ its derivative, at every sample; the record is exact (constant), so the
    recurrence matches to round-off: 1e-12 relative to the peak (measured 9e-14); the
    spectral peaks likewise (measured 4e-14)."""
    a0, h = 2.0, 0.01
    t = np.arange(0.0, 6.0 + h / 2, h)
    T = np.array([0.05, 0.3, 1.0, 4.0])
    u, v = sdof_response(t, np.full_like(t, a0), T, zeta)
    w = 2 * np.pi / T
    wd = w * math.sqrt(1 - zeta**2)
    r = zeta / math.sqrt(1 - zeta**2)
    tt = t[:, None]
    e = np.exp(-zeta * w * tt)
    ue = -(a0 / w**2) * (1 - e * (np.cos(wd * tt) + r * np.sin(wd * tt)))
    ve = -(a0 / w**2) * e * (w**2 / wd) * np.sin(wd * tt)
    assert np.abs(u - ue).max(axis=0) / np.abs(ue).max(axis=0) == pytest.approx(0, abs=1e-12)
    assert np.abs(v - ve).max(axis=0) / np.abs(ve).max(axis=0) == pytest.approx(0, abs=1e-12)
    # the spectrum looks for the peaks at `substeps` points per step: the closed form
    # there; undamped, the peak overshoot is twice the static deformation (its first
    # peak, at T/2, is one of the points here)
    s = response_spectrum(t, np.full_like(t, a0), T, zeta)
    for k in range(T.size):
        ts = np.arange((t.size - 1) * s.substeps[k] + 1) * (h / s.substeps[k])
        es = np.exp(-zeta * w[k] * ts)
        us = -(a0 / w[k] ** 2) * (1 - es * (np.cos(wd[k] * ts) + r * np.sin(wd[k] * ts)))
        assert s.sd[k] == pytest.approx(np.abs(us).max(), rel=1e-12)
    if zeta == 0:
        assert s.psa == pytest.approx(2 * a0, rel=1e-12)


def _harmonic(t: np.ndarray, a0: float, W: float, w: np.ndarray, z: float) -> np.ndarray:
    """u of ü + 2ζωu̇ + ω²u = −a₀ sin Ωt from rest (Chopra §3.2, eqs. 3.2.3-3.2.4):
    steady state C sin Ωt + D cos Ωt plus the transient that starts it from rest."""
    r = W / w
    wd = w * math.sqrt(1 - z * z)
    den = (1 - r * r) ** 2 + (2 * z * r) ** 2
    C = -a0 / w**2 * (1 - r * r) / den
    D = -a0 / w**2 * (-2 * z * r) / den
    A = -D
    B = (z * w * A - C * W) / wd
    return np.exp(-z * w * t) * (A * np.cos(wd * t) + B * np.sin(wd * t)) + (
        C * np.sin(W * t) + D * np.cos(W * t)
    )


def test_harmonic_closed_form() -> None:
    """a_g = a₀ sin Ωt sampled at h = T_Ω/1000 for 5 cycles, against the closed form
    (Chopra §3.2, eq. 3.2.3, transient and steady state from rest). The record is the
    piecewise-linear interpolant of the samples, whose component at Ω is
    sinc²(Ωh/2) a₀ sin Ωt (the Fourier series of linear interpolation; the rest lies at
    2πk/h ± Ω, far above the oscillators): with that amplitude, 1e-10 relative to the
    peak (measured 2e-11); with a₀ itself the interpolation error (Ωh)²/12 = 3.3e-6
    shows (to 1e-5 of it, measured 1e-6)."""
    Tp, N, a0, z = 0.8, 1000, 2.0, 0.05
    W, h = 2 * np.pi / Tp, Tp / N
    t = np.arange(5 * N + 1) * h
    T = np.array([0.3, 1.0, 2.5])
    w = 2 * np.pi / T
    u, _ = sdof_response(t, a0 * np.sin(W * t), T, z)
    fundamental = np.sinc(W * h / (2 * np.pi)) ** 2
    ue = _harmonic(t[:, None], a0 * fundamental, W, w, z)
    err = np.abs(u - ue).max(axis=0) / np.abs(ue).max(axis=0)
    assert err == pytest.approx(0, abs=1e-10)
    raw = _harmonic(t[:, None], a0, W, w, z)
    err_raw = np.abs(u - raw).max(axis=0) / np.abs(raw).max(axis=0)
    assert err_raw == pytest.approx((W * h) ** 2 / 12, rel=1e-5)


def test_vectorised_over_periods_equals_one_by_one() -> None:
    """The spectrum of many periods at once equals the periods one at a time: with the
    same substeps, the same arithmetic (to the last bit); with the automatic ones (each
    period's peaks at its own points, the march at the finest), to round-off (1e-13,
    measured 3e-15). T = 0 gives PSa = Sa_abs = PGA, Sd = 0."""
    t, a = _elcentro()
    T = [0.0, 0.1, 0.5, 2.0]
    s = response_spectrum(t, a * G, T, 0.05, substeps=2)
    auto = response_spectrum(t, a * G, T, 0.05)
    assert auto.substeps.tolist() == [1, 4, 1, 1]
    for k, Tk in enumerate(T):
        one = response_spectrum(t, a * G, [Tk], 0.05, substeps=2)
        assert one.sd[0] == s.sd[k] and one.sa_abs[0] == s.sa_abs[k]
        one = response_spectrum(t, a * G, [Tk], 0.05)
        assert one.sd[0] == pytest.approx(auto.sd[k], rel=1e-13, abs=0)
        assert one.sa_abs[0] == pytest.approx(auto.sa_abs[k], rel=1e-13)
    assert s.sd[0] == 0 and s.psa[0] == s.sa_abs[0] == pytest.approx(0.31882 * G, rel=1e-12)


def test_elcentro_against_solve_ivp() -> None:
    """El Centro 1940 NS (Chopra's digitisation) at T = 0.2, 1, 3 s and ζ = 5 %: the
    recurrence against scipy's DOP853 (rtol 1e-12, atol 1e-14), integrated sample to
    sample with the same piecewise-linear record, at every sample: 2e-11 relative to the
    peak (measured 2.4e-12, the integrator's own error), and the spectral values Sd,
    Sa_abs (peaks at the samples, substeps = 1) to 1e-11 (measured 9e-13)."""
    t, ag = _elcentro()
    a = ag * G
    T = np.array([0.2, 1.0, 3.0])
    z = 0.05
    w = 2 * np.pi / T
    u, v = sdof_response(t, a, T, z)
    ref = np.zeros((t.size, 2 * T.size))
    y = np.zeros(2 * T.size)
    for i in range(t.size - 1):
        t0, t1, a0, a1 = t[i], t[i + 1], a[i], a[i + 1]

        def rhs(tau: float, x: np.ndarray, t0: float = t0, t1: float = t1,
                a0: float = a0, a1: float = a1) -> np.ndarray:  # fmt: skip
            ag_ = a0 + (a1 - a0) * (tau - t0) / (t1 - t0)
            uu, vv = x[: T.size], x[T.size :]
            return np.concatenate([vv, -ag_ - 2 * z * w * vv - w * w * uu])

        sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-14)
        y = sol.y[:, -1]
        ref[i + 1] = y
    uref, vref = ref[:, : T.size], ref[:, T.size :]
    scale = np.abs(uref).max(axis=0)
    assert np.abs(u - uref).max(axis=0) / scale == pytest.approx(0, abs=2e-11)
    assert np.abs(v - vref).max(axis=0) / np.abs(vref).max(axis=0) == pytest.approx(0, abs=2e-11)
    s = response_spectrum(t, a, T, z, substeps=1)
    assert s.sd == pytest.approx(scale, rel=1e-11)
    peak_abs = np.abs(2 * z * w * vref + w * w * uref).max(axis=0)
    assert s.sa_abs == pytest.approx(peak_abs, rel=1e-11)


def test_elcentro_chopra_published() -> None:
    """Chopra, Dynamics of Structures (4th ed., 2012), §6.4, Fig. 6.4.1: peak deformation
    D of SDF systems to El Centro 1940 NS (his digitisation, the record used here):
    (b) ζ = 2 %: T = 0.5, 1, 2 s → 2.67, 5.97, 7.47 in; (c) T = 2 s: ζ = 0 → 9.91 in,
    ζ = 5 % → 5.37 in. Tolerance: half a unit of the last digit printed (0.005 in) plus
    0.1 % for the value of g in in/s² (386 or 386.1; here 9.80665 m/s² = 386.09 in/s²).
    Measured: within 0.005 in of each value (2.674, 5.966, 7.465; 9.911; 5.371 in)."""
    t, ag = _elcentro()
    g_in = 9.80665 / 0.0254
    for zeta, periods, published in ((0.02, [0.5, 1.0, 2.0], [2.67, 5.97, 7.47]),
                                     (0.0, [2.0], [9.91]), (0.05, [2.0], [5.37])):  # fmt: skip
        D = response_spectrum(t, ag * g_in, periods, zeta).sd
        for d, ref in zip(D, published, strict=True):
            assert abs(d - ref) <= 0.005 + 1e-3 * ref, (zeta, d, ref)


# -- intensity measures --------------------------------------------------------------------
def test_arias_and_cav_of_a_sine() -> None:
    """a = A sin(2πt/T_p), N = 40 samples per cycle, 7 cycles (zero at every half
    cycle's sample). Closed forms for the piecewise-linear record (sums of the samples):
    ∫a² dt = (duration/2) A² (2 + cos δ)/3 with δ = 2π/N, so I_a = π/(2g) of it;
    ∫|a| dt = cycles × 2 h A cot(π/N). Both to 1e-13 (measured 1e-15). As N → ∞ they
    tend to the continuous sine's π A² duration/(4g) and 2 A duration/π, from
    below by δ²/6 = 4.1e-3 and (π/N)²/3 = 2.1e-3 relative (to their next terms)."""
    A, Tp, N, cycles = 3.0, 0.5, 40, 7
    h = Tp / N
    t = np.arange(cycles * N + 1) * h
    a = A * np.sin(2 * np.pi * t / Tp)
    a[::N // 2] = 0.0  # exact zeros (sin(kπ) is 1e-16 in floating point)
    im = intensity_measures(t, a)
    dur = cycles * Tp
    arias = math.pi / (2 * G) * (dur / 2) * A**2 * (2 + math.cos(2 * math.pi / N)) / 3
    cav = cycles * 2 * h * A / math.tan(math.pi / N)
    assert im["arias"] == pytest.approx(arias, rel=1e-13)
    assert im["cav"] == pytest.approx(cav, rel=1e-13)
    delta = 2 * math.pi / N  # the next terms: δ⁴/72 = 8e-6, (π/N)⁴/45 = 8e-7
    assert im["arias"] / (math.pi * A**2 * dur / (4 * G)) == pytest.approx(1 - delta**2 / 6,
                                                                           abs=2e-5)  # fmt: skip
    assert im["cav"] / (2 * A * dur / math.pi) == pytest.approx(
        1 - (math.pi / N) ** 2 / 3, abs=2e-6)  # fmt: skip
    assert im["pga"] == pytest.approx(A, rel=1e-15)


def test_cav_with_sign_changes_inside_steps() -> None:
    """A record 1, −1 over one step of 1 s crosses zero at its middle: ∫|a| = 2 × ½ × ½
    × 1 = 0.5 (a triangle each side), not the trapezoid's 0; exact (1e-15)."""
    im = intensity_measures([0.0, 1.0], [1.0, -1.0])
    assert im["cav"] == pytest.approx(0.5, rel=1e-15)
    assert im["arias"] == pytest.approx(math.pi / (2 * G) / 3, rel=1e-15)


def test_significant_duration_of_a_ramp() -> None:
    """a = c t (exactly linear, 7 unequal steps): Husid ∫a² = c² t³/3, so t_p =
    duration · p^(1/3) and D5-95 = duration (0.95^(1/3) − 0.05^(1/3)); to 1e-13
    (measured 1e-15)."""
    t = np.array([0.0, 0.3, 0.5, 1.1, 2.0, 2.2, 3.5, 4.0])
    im = intensity_measures(t, 0.7 * t)
    assert im["t5"] == pytest.approx(4.0 * 0.05 ** (1 / 3), rel=1e-13)
    assert im["d5_95"] == pytest.approx(4.0 * (0.95 ** (1 / 3) - 0.05 ** (1 / 3)), rel=1e-13)
    assert math.isnan(intensity_measures([0.0, 1.0], [0.0, 0.0])["d5_95"])


def test_pgv_pgd_between_samples() -> None:
    """PGV and PGD of a coarse record (5 samples, both peaks inside steps, well above
    the largest values at the samples) against :meth:`GroundMotion.motion` on a grid of
    2·10⁵ points (the same exact integration): the grid misses a peak by O(grid step²),
    1e-9 and 1e-10 relative (measured 1.2e-10 and 1.1e-11); the exact peaks are at least
    the grid's."""
    from pfeie.model._spectrum import ground_velocity_displacement

    gm = GroundMotion.from_samples([1.0, -2.0, 1.5, 0.5, -1.0], dt=0.5)
    im = gm.intensity_measures()
    v, d = ground_velocity_displacement(gm.time, gm.acceleration)
    assert im["pgv"] > 1.4 * np.abs(v).max() and im["pgd"] > 1.04 * np.abs(d).max()
    grid = np.linspace(0.0, gm.time[-1], 200_001)
    dv = np.array([gm.motion(float(x))[:2] for x in grid])
    pgd, pgv = np.abs(dv).max(axis=0)
    assert im["pgv"] >= pgv and im["pgv"] == pytest.approx(pgv, rel=1e-9)
    assert im["pgd"] >= pgd and im["pgd"] == pytest.approx(pgd, rel=1e-10)


def test_sa_measure_and_bad_arguments() -> None:
    """Sa(T₁) of the intensity measures is the spectrum's PSa at T₁ (the same numbers);
    a damping ratio outside [0, 1) or a negative period is a ModelError."""
    t, ag = _elcentro()
    gm = GroundMotion.from_samples(ag, time=t, units="g")
    assert gm.intensity_measures(1.0, 0.02)["sa"] == gm.spectrum([1.0], 0.02).psa[0]
    with pytest.raises(ModelError, match="damping"):
        gm.spectrum([1.0], 1.0)
    with pytest.raises(ModelError, match="periods"):
        gm.spectrum([-1.0])



def test_extreme_periods() -> None:
    """Periods at the ends of the float range neither hang nor warn: a period below
    RIGID_PERIOD × the record's step (0.02 ms here) is a rigid oscillator, PSa = Sa_abs
    = PGA exactly (the T = 0 value); a period down to 20 h / MAX_SUBSTEPS (6.25 ms) and
    below is looked for at 64 points a step, within 1e-3 of PGA at T = 1 ms and 0.1 ms
    (the T → 0 limit; measured: 1.1e-4 below, the damped oscillator's absolute
    acceleration at 64 points against 5.9e-4 more at 1,024); a period beyond PERIOD_MAX
    is a ModelError (ω² would underflow)."""
    import warnings

    from pfeie.model._spectrum import MAX_SUBSTEPS, PERIOD_MAX

    t, ag = _elcentro()
    a = ag * G
    pga = float(np.abs(a).max())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = response_spectrum(t, a, [5e-324, 1e-300, 1e-6, 1e-4, 1e-3, 0.0], 0.05)
    assert s.psa[:3].tolist() == [pga] * 3 and s.sa_abs[:3].tolist() == [pga] * 3
    assert s.psv[:3].tolist() == [0.0] * 3
    assert s.substeps.tolist() == [1, 1, 1] + [MAX_SUBSTEPS] * 2 + [1]
    assert np.abs(s.psa[3:5] / pga - 1).max() < 1e-3
    with pytest.raises(ModelError, match="at most 10000 s"):
        response_spectrum(t, a, [1.0, 2 * PERIOD_MAX])

# -- scaling in the model file and the command ---------------------------------------------
def _model(tmp: Path, extra: str) -> Path:
    """The static plate model of test_robustness with the El Centro record (in g) and
    ``extra`` keys in its ``[[ground_motion]]`` table."""
    from test_robustness import model

    (tmp / "elcentro.csv").write_text(ELCENTRO.read_text())
    p = model(tmp)
    p.write_text(p.read_text() + '[[ground_motion]]\nfile = "elcentro.csv"\nunits = "g"\n'
                 + extra)  # fmt: skip
    return p


@pytest.mark.parametrize("baseline", [False, True])
def test_target_sa_scaling(tmp_path: Path, baseline: bool,
                           capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """``target_sa = {period = 0.3, value = 0.5, damping = 0.05}`` scales the record so
    that Sa(0.3 s, 5 %) of the scaled record is 0.5 g: to 1e-12 relative (measured 2e-16;
    the spectrum and the baseline correction are linear in the record); the summary
    states the factor."""
    from pfeie.io import load_job

    extra = "target_sa = {period = 0.3, value = 0.5, damping = 0.05}\n"
    p = _model(tmp_path, extra + ("baseline = true\n" if baseline else ""))
    rec = load_job(p).records[0]
    assert rec.sa(0.3, 0.05) == pytest.approx(0.5 * 9.81, rel=1e-12)
    assert "scaled ×" in rec.summary() and "to Sa(0.3 s, 5 %) = 0.5 g" in rec.summary()
    assert main(["check", str(p)]) == 0
    assert "scaled ×" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ("target_sa = {period = -0.3, value = 0.5}\n",
         ["ground_motion[0].target_sa.period", "expected a number in (0, 100] s"]),
        ("target_sa = {period = 0.3, value = inf}\n",
         ["ground_motion[0].target_sa.value", "finite"]),
        ("target_sa = {period = 0.3, value = 0.5, damping = 1.5}\n",
         ["ground_motion[0].target_sa.damping", "in (0, 1)"]),
        ("target_sa = {period = 0.3}\n", ["ground_motion[0].target_sa.value", "missing"]),
        ("target_sa = {period = 0.3, value = 0.5, zeta = 0.05}\n",
         ["ground_motion[0].target_sa.zeta", "unknown key"]),
        ("target_sa = 0.5\n", ["ground_motion[0].target_sa", "expected a table"]),
        ("target_sa = {period = 0.3, value = 0.5}\npga = 0.3\n",
         ["ground_motion[0]: give either pga or target_sa, not both"]),
        ("target_sa = {period = 0.3, value = 0.5}\nscale = 2.0\n",
         ["ground_motion[0]: give either scale or target_sa, not both"]),
    ],
)  # fmt: skip
def test_bad_target_sa(tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: str,
                       words: list[str]) -> None:  # fmt: skip
    """A wrong target_sa ends in exit 2 with a ``pfeie: error`` line naming the key and
    what was expected, no traceback (the style of test_robustness)."""
    from conftest import cli_fails as fails

    fails(capsys, ["check", str(_model(tmp_path, extra))], *words)


def test_spectrum_command_on_a_record(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``pfeie spectrum`` on El Centro writes spectrum.csv (T, Sd, PSv, PSa, Sa_abs in SI)
    whose rows are the library's numbers (to the 9 digits written) and spectrum.png, and
    prints the intensity measures."""
    out = tmp_path / "o"
    assert main(["spectrum", str(ELCENTRO), "--units", "g", "--damping", "0.02",
                 "--periods", "0.5,1,2", "--t1", "1", "-o", str(out)]) == 0  # fmt: skip
    text = capsys.readouterr().out
    for word in ("PGA", "PGV", "PGD", "Arias intensity", "CAV", "D5-95", "Sa(1 s, 2 %)"):
        assert word in text, word
    rows = np.loadtxt(out / "spectrum.csv", delimiter=",", skiprows=1)
    head = (out / "spectrum.csv").read_text().splitlines()[0]
    assert head == "T_s,Sd_m,PSv_m_per_s,PSa_m_per_s2,Sa_abs_m_per_s2"
    t, ag = _elcentro()
    s = response_spectrum(t, ag * G, [0.5, 1.0, 2.0], 0.02)
    ref = np.c_[s.periods, s.sd, s.psv, s.psa, s.sa_abs]
    assert rows == pytest.approx(ref, rel=1e-8)
    assert (out / "spectrum.png").stat().st_size > 10_000


def test_spectrum_command_on_a_model(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """On a model file, the spectrum is that of the scaled record: PSa at the target
    period is the target (to the 9 digits written), and Sa(T1) is printed at it."""
    p = _model(tmp_path, "target_sa = {period = 0.3, value = 0.5}\n")
    assert main(["spectrum", str(p), "--periods", "0.1,0.3,1", "-o", str(tmp_path)]) == 0
    assert "Sa(0.3 s, 5 %)" in capsys.readouterr().out
    rows = np.loadtxt(tmp_path / "spectrum.csv", delimiter=",", skiprows=1)
    assert rows[1, 3] == pytest.approx(0.5 * 9.81, rel=1e-8)


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--periods", "1:0.1:5"], ["--periods", "START:STOP:N"]),
        (["--periods", "a,b"], ["--periods"]),
        (["--damping", "1"], ["--damping", "[0, 1)"]),
        (["--t1", "-2"], ["--t1", "> 0" if False else "(0"]),
        ([], ["give the units of the record"]),
    ],
)  # fmt: skip
def test_spectrum_command_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                 argv: list[str], words: list[str]) -> None:  # fmt: skip
    """Wrong options or a record without units: exit 2 and a ``pfeie: error`` line."""
    from conftest import cli_fails as fails

    units = [] if words == ["give the units of the record"] else ["--units", "g"]
    fails(capsys, ["spectrum", str(ELCENTRO), *units, *argv, "-o", str(tmp_path)], *words)


def test_scaling_of_a_zero_record_and_the_pga_note(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``target_sa`` on a record of zeros: exit 2 naming the record (in a dynamic model; a
    static-only one warns, the record unused); ``pga`` scaling states its factor in the
    summary too (0.3 g / 0.31882 g = 0.94097, 6 digits)."""
    from conftest import cli_fails as fails
    from pfeie.io import load_job

    p = _model(tmp_path, "pga = 0.3\n")
    assert "scaled ×0.94097 to a PGA of 0.3 g" in load_job(p).records[0].summary()
    p = _model(tmp_path, "target_sa = {period = 0.3, value = 0.5}\n")
    p.write_text(p.read_text().replace("dynamic = false", "duration = 0.1"))
    np.savetxt(tmp_path / "elcentro.csv", np.c_[[0.0, 0.1], [0.0, 0.0]], delimiter=",")
    fails(capsys, ["check", str(p)], "ground_motion[0]", "the record is all zeros",
          "Sa(0.3 s, 5 %) = 0.5 g")  # fmt: skip
