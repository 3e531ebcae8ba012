"""Zero-phase Butterworth filtering of ground-motion records
(:meth:`pfeie.GroundMotion.filtered`, ``read_record(highpass=, lowpass=)``, the model
file's ``ground_motion[].filter``).

References: the closed-form magnitude of a Butterworth filter run forward and backward,
|H(f)|² = 1/(1 + (f/f_c)^(2n)) (low-pass) and 1/(1 + (f_c/f)^(2n)) (high-pass), and of
its digital form by the bilinear transform with the corner pre-warped, f → tan(π f Δt)
(Oppenheim & Schafer, Discrete-Time Signal Processing, §7.1); amplitudes and phases
measured by an independent least-squares fit of sines and cosines at the known
frequencies; the symmetry of a symmetric pulse through a zero-phase filter; the
trapezoidal final velocity of the record.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.signal import butter, sosfilt

import pfeie as pf
from pfeie.errors import ModelError
from pfeie.io import applied_part, load_job, read_record
from test_cli import SMALL

DT, LENGTH, EDGE = 0.002, 80.0, 25.0  # s: the step, the record, the part left out each end


def sines_through(freqs: list[float], **settings: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit sines at ``freqs`` (Hz), summed, filtered; the sine and cosine amplitude of each
    frequency in the filtered record, fitted by least squares on its middle part (the
    filter's transients at the record's ends left out, steady state)."""
    t = np.arange(round(LENGTH / DT) + 1) * DT
    gm = pf.GroundMotion.from_samples(sum(np.sin(2 * np.pi * f * t) for f in freqs), dt=DT)
    y = gm.filtered(**settings).acceleration  # type: ignore[arg-type]
    mid = (t > EDGE) & (t < LENGTH - EDGE)
    w = 2 * np.pi * np.asarray(freqs)[None, :] * t[mid, None]
    coef, *_ = np.linalg.lstsq(np.hstack([np.sin(w), np.cos(w)]), y[mid], rcond=None)
    return coef[: len(freqs)], coef[len(freqs) :]


def butterworth2(f: np.ndarray, highpass: float | None, lowpass: float | None, order: int,
                 warp: bool) -> np.ndarray:  # fmt: skip
    """|H(f)|² of the forward-backward Butterworth, analogue (f) or digital (tan(π f Δt))."""

    def w(x: np.ndarray | float) -> np.ndarray:
        return np.tan(np.pi * np.asarray(x) * DT) if warp else np.asarray(x, dtype=float)

    h = np.ones_like(f)
    if lowpass is not None:
        h = h / (1 + (w(f) / w(lowpass)) ** (2 * order))
    if highpass is not None:
        h = h / (1 + (w(highpass) / w(f)) ** (2 * order))
    return h


CASES = {  # settings, frequencies (Hz) below, at and above the corners
    "low-pass": ({"lowpass": 5.0, "order": 4}, [1.0, 3.0, 5.0, 7.0, 10.0]),
    "high-pass": ({"highpass": 0.5, "order": 4}, [0.2, 0.35, 0.5, 0.8, 2.0]),
    "band-pass": ({"highpass": 0.5, "lowpass": 5.0, "order": 2}, [0.3, 0.5, 1.5, 5.0, 8.0]),
}


@pytest.mark.parametrize("kind", list(CASES))
def test_amplitude_ratio_is_butterworth_squared(kind: str) -> None:
    """A sum of unit sines, filtered: each sine's steady-state amplitude is |H(f)|², the
    Butterworth magnitude squared (forward and backward): ½ at a corner, and no cosine
    part (zero phase). Against the digital closed form (the corner pre-warped, tan(π f
    Δt)): measured 2.3e-13 at most, asserted 1e-12. Against the analogue one,
    1/(1 + (f/f_c)^(2n)): measured 2.4e-4 at most (at 1/Δt = 500 Hz the bilinear
    transform's warping shifts the slope: tan(π f Δt) ≠ π f Δt), asserted 1e-3. Phase
    (the cosine amplitudes): measured 1.5e-13, asserted 1e-12."""
    settings, freqs = CASES[kind]
    sine, cosine = sines_through(freqs, **settings)
    f = np.asarray(freqs)
    args = (settings.get("highpass"), settings.get("lowpass"), int(settings["order"]))
    np.testing.assert_allclose(sine, butterworth2(f, *args, warp=True), rtol=0, atol=1e-12)
    np.testing.assert_allclose(sine, butterworth2(f, *args, warp=False), rtol=0, atol=1e-3)
    corner = [i for i, x in enumerate(freqs) if x in (args[0], args[1])]
    if kind != "band-pass":  # one corner: half the amplitude there
        assert sine[corner[0]] == pytest.approx(0.5, abs=1e-12)
    np.testing.assert_allclose(cosine, 0.0, atol=1e-12)


def test_zero_phase_keeps_the_peak_in_place() -> None:
    """A pulse symmetric about the middle of the record (a Gaussian-windowed 8 Hz cosine)
    stays symmetric through the filter, its peak at the same sample (measured asymmetry
    6e-14 of the peak, asserted 1e-12); the same Butterworth run once, forward only,
    moves the peak by 10 samples (50 ms): the check can fail."""
    dt, n = 0.005, 4001
    t = np.arange(n) * dt
    t0 = t[n // 2]
    x = np.exp(-(((t - t0) / 0.05) ** 2)) * np.cos(2 * np.pi * 8.0 * (t - t0))
    gm = pf.GroundMotion.from_samples(x, dt=dt)
    for settings in ({"lowpass": 10.0}, {"highpass": 0.2, "lowpass": 10.0}, {"highpass": 1.0}):
        y = gm.filtered(**settings).acceleration  # type: ignore[arg-type]
        assert int(np.argmax(np.abs(y))) == n // 2
        assert np.abs(y - y[::-1]).max() < 1e-12 * np.abs(y).max()
    causal = sosfilt(butter(4, 10.0, output="sos", fs=1 / dt), x)
    assert int(np.argmax(np.abs(causal))) - n // 2 >= 5


RECORD = 'file = "pulse.csv"\nunits = "g"\n'
assert RECORD in SMALL
MODEL = SMALL.replace("DURATION", "0.1").replace(RECORD, (
    'file = "record.csv"\nunits = "g"\nbaseline = true\npga = 0.3\n'
    "filter = { highpass = 0.2, lowpass = 20.0, order = 3 }\n"))  # fmt: skip


def _velocity_end(gm: pf.GroundMotion) -> float:
    """The final ground velocity (m/s), the trapezoidal integral of the record."""
    return float(np.sum(0.5 * (gm.acceleration[1:] + gm.acceleration[:-1]) * np.diff(gm.time)))


def test_model_file_filter_is_the_api_filter(tmp_path: Path) -> None:
    """A model file's ``filter`` table gives the record of the API: read, filtered,
    baseline-corrected, then scaled to its ``pga``, met by the motion applied up to the
    run's 0.1 s (:func:`pfeie.io.applied_part`; the same operations: measured equal bit
    for bit, asserted 1e-12 of the PGA), as does ``read_record`` with the same
    settings; the summary says so. The baseline correction comes last: the record as
    applied ends at rest (final velocity measured 3.6e-18 of PGA × duration; asserted
    1e-15, the round-off of a 4000-term sum, which varies with the record), which the
    other order (correct, then filter) misses (measured 1.5e-4; asserted > 1e-5)."""
    rng = np.random.default_rng(7)
    t = np.arange(4000) * 0.005
    acc = 0.02 + 0.1 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-(((t - 8) / 4) ** 2))
    acc = acc + 0.02 * rng.standard_normal(t.size)  # noise up to the Nyquist 100 Hz
    np.savetxt(tmp_path / "record.csv", np.c_[t, acc], delimiter=",", header="t,a", comments="")
    (tmp_path / "model.toml").write_text(MODEL)
    job = load_job(tmp_path / "model.toml")
    (got,) = job.records
    ref = read_record(tmp_path / "record.csv", units="g").filtered(
        highpass=0.2, lowpass=20.0, order=3).baseline_corrected()  # fmt: skip
    ref_acc = ref.acceleration * (0.3 * 9.81 / applied_part(ref, 0.1)[0].pga)
    np.testing.assert_allclose(got.acceleration, ref_acc, rtol=0, atol=1e-12 * got.pga)
    assert applied_part(got, 0.1)[0].pga == pytest.approx(0.3 * 9.81, rel=1e-12)
    same = read_record(tmp_path / "record.csv", units="g", highpass=0.2, lowpass=20.0, order=3,
                       baseline=True)  # fmt: skip
    np.testing.assert_array_equal(same.acceleration, ref.acceleration)
    assert "band-pass 0.2–20 Hz (Butterworth order 3, zero phase), baseline-corrected" in (
        got.summary())  # fmt: skip
    scale = got.pga * got.duration
    assert abs(_velocity_end(got)) < 1e-15 * scale
    other = read_record(tmp_path / "record.csv", units="g").baseline_corrected()
    other = other.filtered(highpass=0.2, lowpass=20.0, order=3)
    assert abs(_velocity_end(other)) * (got.pga / other.pga) > 1e-5 * scale


@pytest.mark.parametrize(
    ("settings", "words"),
    [
        ({"lowpass": 60.0}, "filter: lowpass: expected a corner frequency in (0, 50) Hz"),
        ({"highpass": 0.0}, "filter: highpass: expected a corner frequency in (0, 50) Hz"),
        ({"highpass": 8.85e-250}, "filter: highpass: expected a corner of at least 0.010101 Hz "
         "(a period of at most 100 times the record's duration, 0.99 s)"),
        ({"lowpass": 2.51e-269}, "filter: lowpass: expected a corner of at least 0.010101 Hz "
         "(a period of at most 100 times the record's duration, 0.99 s)"),
        ({"highpass": 5.0, "lowpass": 2.0}, "filter: lowpass: expected a corner above highpass"),
        ({"lowpass": 5.0, "order": 9}, "filter: order: expected an integer in [1, 8], found 9"),
        ({"lowpass": 5.0, "order": 2.0}, "filter: order: expected an integer in [1, 8]"),
        ({}, "filter: expected a highpass or a lowpass corner"),
    ],
)
def test_wrong_settings_name_the_setting(settings: dict[str, float], words: str) -> None:
    """Wrong corners or orders raise a ModelError that names the record and the setting
    (a record of 0.99 s sampled at 0.01 s: Nyquist frequency 50 Hz; a high-pass corner
    or low-pass corner whose period exceeds 100 record lengths, whose padding would not
    fit in memory, is refused: the fuzzer found 8.85e-250 Hz and 2.51e-269 Hz)."""
    gm = pf.GroundMotion.from_samples(np.zeros(100), dt=0.01, name="rec")
    with pytest.raises(ModelError) as err:
        gm.filtered(**settings)  # type: ignore[arg-type]
    assert "ground motion 'rec'" in str(err.value) and words in str(err.value)


def test_uneven_samples_are_refused() -> None:
    """The filter needs one time step: a record with uneven times is refused, by name."""
    gm = pf.GroundMotion.from_samples([0.0, 1.0, 0.0, -1.0], time=[0.0, 0.01, 0.03, 0.04])
    with pytest.raises(ModelError, match="not equally spaced"):
        gm.filtered(lowpass=5.0)
