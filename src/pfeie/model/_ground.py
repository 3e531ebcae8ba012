"""Ground motion: an acceleration record applied as a base excitation.

A :class:`GroundMotion` is a record a_g(t) (m/s²) along a unit direction ι. In the
*relative* form (the usual dam analysis) the base is fixed and every block receives the
inertia load −M ι a_g(t); displacements, velocities and accelerations are then relative
to the ground, and absolute accelerations are a + ι a_g.

The record is linearly interpolated to the analysis times (which need not coincide with
its samples) and is zero before its first sample and after its last.

Processing (:meth:`GroundMotion.filtered`, :meth:`GroundMotion.baseline_corrected`):
a record read from a file is scaled, then band-limited by a zero-phase Butterworth
filter, then baseline-corrected, in this order (:func:`pfeie.io.read_record`, the model
file's ``[[ground_motion]]``). Scaling is linear and commutes with both; the baseline
correction comes last because the filter's pads and transients change the final
velocity that the correction brings to zero, and a constant removed before the filter
would become two steps at the record's ends, which the filter turns into long-period
transients.

>>> gm = GroundMotion.from_samples([0.0, 0.1, -0.1], dt=0.02, units="g", direction=[1, 0])
>>> round(gm(0.01), 6), round(gm(0.03), 6), gm(1.0)   # m/s², halfway between samples
(0.4905, 0.0, 0.0)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..errors import ModelError
from ..typing import FloatArray, is_number

if TYPE_CHECKING:
    from ._spectrum import ResponseSpectrum

G_STANDARD = 9.80665
#: the filter's zero pads at each end last PAD_PERIODS × order / (lowest corner) seconds
PAD_PERIODS = 1.5
G_UNITS = {"g": 9.81, "m/s2": 1.0, "m/s^2": 1.0, "cm/s2": 0.01, "gal": 0.01}
#: the lowest high-pass corner, in cycles per record duration (a period of at most 100
#: record lengths)
HIGHPASS_MIN_CYCLES = 0.01


#: s, the largest sampling interval of a record (as a PEER .AT2 header's DT is checked):
#: a larger one is a record with its times or dt in ms
RECORD_DT_MAX = 10.0
#: s, a sampling interval above which a record gets a warning (strong-motion records are
#: sampled every 0.005 to 0.05 s)
RECORD_DT_COARSE = 0.1


def _median_step(t: npt.ArrayLike) -> float:
    """The median of the steps of the times ``t`` (s), a record's sampling interval."""
    return float(np.median(np.diff(t)))


def _floats(x: object, what: str, expected: str) -> FloatArray:
    """``x`` as an array of floats; a :class:`ModelError` naming ``what`` and the
    ``expected`` values where it holds something else (a string, None, objects)."""
    if isinstance(x, str | bytes):
        raise ModelError(f"{what}: expected {expected}, got the string {x!r}")
    try:
        return np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"{what}: expected {expected}, got {type(x).__name__} "
                         f"{x!r}"[:300]) from None  # fmt: skip


@dataclass(frozen=True)
class GroundMotion:
    """An acceleration record: times (s), accelerations (m/s²), a unit direction.

    Build it with :meth:`from_samples` (equally spaced, given Δt, or with a time column).
    ``g = 9.81`` m/s² converts records in g (the convention of the verification cases).
    """

    time: FloatArray
    acceleration: FloatArray
    direction: FloatArray
    name: str = "record"
    #: how the record was scaled, for the summary (e.g. "scaled ×1.23 to PGA 0.3 g")
    scaling: str = ""
    #: how the record was processed, for the summary (e.g. "band-pass 0.1–25 Hz, ...")
    processing: str = ""
    #: the units its values were read in (:data:`G_UNITS`; the accelerations are stored
    #: in m/s²): what a warning about an implausible PGA names
    read_units: str = "m/s2"

    def __post_init__(self) -> None:
        """The record's consistency, checked however it is built (the constructor took
        times that went back and NaN accelerations, which surfaced steps later as a
        diverged interface problem): at least two samples of finite, strictly increasing
        times and finite accelerations, one per time, and a finite unit direction of 2 or
        3 components."""
        t, a = np.asarray(self.time), np.asarray(self.acceleration)
        e = np.asarray(self.direction)
        what = f"ground motion {self.name!r}"
        if t.ndim != 1 or a.shape != t.shape or t.size < 2:
            raise ModelError(f"{what}: expected time and acceleration as 1D arrays of one "
                             f"length, at least 2 samples; got shapes {t.shape} and "
                             f"{a.shape}")  # fmt: skip
        if not (np.isfinite(t).all() and np.isfinite(a).all()):
            raise ModelError(f"{what}: expected finite times and accelerations; the record "
                             "holds NaN or infinite values")  # fmt: skip
        if np.any(np.diff(t) <= 0):
            k = int(np.flatnonzero(np.diff(t) <= 0)[0])
            raise ModelError(f"{what}: times must increase strictly; sample {k + 1} is at "
                             f"{t[k + 1]:g} s after {t[k]:g} s")  # fmt: skip
        if e.shape not in ((2,), (3,)) or not np.isfinite(e).all() or not (
                abs(float(np.linalg.norm(e)) - 1.0) <= 1e-9):  # fmt: skip
            raise ModelError(f"{what}: expected a unit direction of 2 or 3 components, got "
                             f"{e.tolist()} (GroundMotion.from_samples normalises it)")  # fmt: skip

    @classmethod
    def from_samples(
        cls,
        values: npt.ArrayLike,
        *,
        dt: float | None = None,
        time: npt.ArrayLike | None = None,
        units: str = "m/s2",
        scale: float = 1.0,
        direction: Sequence[float] = (1.0, 0.0),
        name: str = "record",
    ) -> GroundMotion:
        """A record from samples with a step ``dt`` (s) or a ``time`` column (s)."""
        raw = _floats(values, f"ground motion {name!r}: values", "accelerations")
        for key, x in (("dt", dt), ("scale", scale)):
            if x is not None and not is_number(x):
                raise ModelError(f"ground motion {name!r}: {key}: expected a number, got "
                                 f"{type(x).__name__} {x!r}")  # fmt: skip
        if raw.ndim > 1 and sum(n > 1 for n in raw.shape) > 1:
            raise ModelError(
                f"ground motion {name!r}: values: expected a 1D array of accelerations, got "
                f"shape {raw.shape}; for the columns of a file of times and accelerations, "
                "give values=data[:, 1], time=data[:, 0] (or pfeie.io.read_record)")  # fmt: skip
        acc = raw.ravel()
        if acc.size < 2:
            raise ModelError(f"ground motion {name!r}: needs at least 2 samples, got {acc.size}")
        if not np.all(np.isfinite(acc)):
            raise ModelError(f"ground motion {name!r}: non-finite acceleration values")
        if units not in G_UNITS:
            raise ModelError(f"ground motion {name!r}: units must be one of {sorted(G_UNITS)}, "
                             f"got {units!r}")  # fmt: skip
        if (dt is None) == (time is None):
            raise ModelError(f"ground motion {name!r}: give either dt or a time column")
        if time is None:
            assert dt is not None
            if not 0 < dt <= RECORD_DT_MAX:
                raise ModelError(f"ground motion {name!r}: dt must lie in (0, "
                                 f"{RECORD_DT_MAX:g}] s (a sampling interval; dt in ms?), "
                                 f"got {dt}")  # fmt: skip
            t = np.arange(acc.size) * float(dt)
        else:
            t = _floats(time, f"ground motion {name!r}: time", "times (s)").ravel()
            if t.shape != acc.shape:
                raise ModelError(f"ground motion {name!r}: {t.size} times for {acc.size} values")
            if np.any(np.diff(t) <= 0):
                raise ModelError(f"ground motion {name!r}: times must increase strictly")
            if t[0] < 0:
                raise ModelError(
                    f"ground motion {name!r}: the times start at {t[0]:g} s; a record is "
                    "applied from t = 0, so its part before 0 would be dropped (and a pga "
                    "measured on it): shift the times to start at 0 (or cut the record)"
                )
            step = _median_step(t)
            if step > RECORD_DT_MAX:
                raise ModelError(f"ground motion {name!r}: the times step by {step:g} s "
                                 f"(median); expected a sampling interval in (0, "
                                 f"{RECORD_DT_MAX:g}] s: times in ms?")  # fmt: skip
        if not np.all(np.isfinite(t)):
            raise ModelError(f"ground motion {name!r}: times beyond the range of a double "
                             f"(last {t[-1]} s); expected finite times")  # fmt: skip
        e = _floats(direction, f"ground motion {name!r}: direction",
                    "the 2 or 3 components of a vector, e.g. (1, 0)")  # fmt: skip
        big = float(np.abs(e).max()) if e.size else 0.0
        e = e / big if np.isfinite(big) and big > 0 else e
        norm = np.linalg.norm(e)
        if not (np.isfinite(norm) and norm > 0 and np.isfinite(big)):
            raise ModelError(f"ground motion {name!r}: direction must be a finite non-zero "
                             f"vector, got {e.tolist()}")  # fmt: skip
        with np.errstate(over="ignore", invalid="ignore"):
            acc_si = np.asarray(acc * G_UNITS[units] * scale, dtype=float)
        if not np.all(np.isfinite(acc_si)):
            raise ModelError(f"ground motion {name!r}: scale {scale} × the record overflows; "
                             "expected finite accelerations (m/s²)")  # fmt: skip
        unit = np.asarray(e / np.linalg.norm(e), dtype=float)
        return cls(np.asarray(t, dtype=float), acc_si, unit, name, read_units=units)

    @classmethod
    def from_function(
        cls, fn: Callable[[float], float], duration: float, dt: float,
        direction: Sequence[float] = (1.0, 0.0), name: str = "function",
    ) -> GroundMotion:  # fmt: skip
        """Sample a function a(t) (m/s²) at step dt over [0, duration]."""
        if not callable(fn):
            raise ModelError(f"ground motion {name!r}: expected a function a(t) (m/s²) of "
                             f"the time t (s), got {type(fn).__name__} {fn!r}")  # fmt: skip
        for key, x in (("dt", dt), ("duration", duration)):
            if not is_number(x):
                raise ModelError(f"ground motion {name!r}: {key}: expected a number (s), got "
                                 f"{type(x).__name__} {x!r}")  # fmt: skip
        if not (np.isfinite(dt) and dt > 0):
            raise ModelError(f"ground motion {name!r}: dt must be > 0 s, got {dt}")
        if not (np.isfinite(duration) and duration > 0):
            raise ModelError(f"ground motion {name!r}: duration must be > 0 s, got {duration}")
        t = np.arange(round(duration / dt) + 1, dtype=float) * dt
        values = np.array([fn(float(x)) for x in t])
        return cls.from_samples(values, time=t, direction=direction, name=name)

    def __call__(self, t: float) -> float:
        """a_g(t) in m/s² (linear interpolation, 0 outside the record)."""
        return float(np.interp(t, self.time, self.acceleration, left=0.0, right=0.0))

    def shifted(self, t0: float) -> GroundMotion:
        """The record delayed by ``t0`` s: its samples at t + t₀, the ground at rest
        before them (:meth:`__call__` is 0 outside the record). A run started from a
        state at t₀ (``Dynamic.run(start=result.final)``) goes on at the state's time and
        reads its records there, so an aftershock recorded from t = 0 is applied after a
        mainshock that ended at t₀ as ``aftershock.shifted(t0)``, in the relative form (in
        the absolute form the supports would jump from where the mainshock's ground left
        them to where the aftershock puts them: refused).

        >>> gm = GroundMotion.from_samples([0.0, 1.0, 0.0], dt=0.5)
        >>> gm.shifted(5.0).time.tolist(), gm.shifted(5.0)(5.5), gm.shifted(5.0)(0.5)
        ([5.0, 5.5, 6.0], 1.0, 0.0)
        """
        shift = float(t0)
        if not np.isfinite(shift):
            raise ModelError(f"ground motion {self.name!r}: shifted: expected a finite time "
                             f"in s, got {t0!r}")  # fmt: skip
        done = ", ".join(x for x in (self.processing, f"shifted by {shift:g} s") if x)
        return dataclasses.replace(self, time=self.time + shift, processing=done)

    def baseline_corrected(self) -> GroundMotion:
        """The record minus the constant acceleration that brings the final ground velocity
        to zero (the zeroth-order baseline correction), for the absolute form."""
        v_end = float(np.sum(0.5 * (self.acceleration[1:] + self.acceleration[:-1])
                             * np.diff(self.time)))  # fmt: skip
        shift = v_end / self.duration
        done = ", ".join(x for x in (self.processing, "baseline-corrected") if x)
        return dataclasses.replace(self, acceleration=self.acceleration - shift,
                                   processing=done)  # fmt: skip

    def filtered(self, *, highpass: float | None = None, lowpass: float | None = None,
                 order: int = 4) -> GroundMotion:  # fmt: skip
        """The record through a zero-phase Butterworth filter: a high-pass (corner
        ``highpass``, Hz: removes the long-period noise), a low-pass (corner ``lowpass``,
        Hz) or both, a band-pass; ``order`` n in 1..8 is that of each Butterworth.

        Each filter is designed digitally (bilinear transform, the corner pre-warped:
        :func:`scipy.signal.butter`, second-order sections) and run forward and backward
        (:func:`scipy.signal.sosfiltfilt`), so the phase is zero (no shift in time) and a
        sine of frequency f (Hz), in steady state, is multiplied by

            low-pass:   |H(f)|² = 1 / (1 + (w(f) / w(f_c))^(2n)),
            high-pass:  |H(f)|² = 1 / (1 + (w(f_c) / w(f))^(2n)),
            w(f) = tan(π f Δt),

        i.e. 1/(1 + (f/f_c)^(2n)) and 1/(1 + (f_c/f)^(2n)) for f ≪ 1/Δt (the analogue
        Butterworth squared): ½ at the corner (−6 dB), the slope that of order 2n. A
        band-pass is the high-pass and the low-pass in cascade, |H|² their product.

        Padding: zeros at both ends, each lasting 1.5 n / f_min (f_min the lowest corner,
        Hz; about the duration of the filter's transient, Converse & Brady 1992), then the
        two passes start from rest, and the pads are cut off: the record keeps its time
        grid, and the transients of its ends lie in the pads. The samples must be equally
        spaced; the corners must satisfy 0.01/D ≤ highpass < lowpass < 1/(2Δt) (D the
        record's duration: :data:`HIGHPASS_MIN_CYCLES` cycles per record at least; the
        Nyquist frequency). Accelerations stay in m/s².

        >>> import numpy as np
        >>> t = np.arange(20000) * 0.005
        >>> gm = GroundMotion.from_samples(np.sin(2*np.pi*1.0*t) + np.sin(2*np.pi*20.0*t),
        ...                                dt=0.005)
        >>> mid = slice(8000, 12000)
        >>> low = gm.filtered(lowpass=5.0).acceleration[mid]   # keeps 1 Hz, removes 20 Hz
        >>> bool(np.abs(low - np.sin(2*np.pi*t[mid])).max() < 1e-4)
        True
        """
        why = self.filter_problem(highpass=highpass, lowpass=lowpass, order=order)
        if why is not None:
            key, text = why
            raise ModelError(f"ground motion {self.name!r}: filter{': ' + key if key else ''}: "
                             f"{text}")  # fmt: skip
        dt = float(self.duration / (self.time.size - 1))
        from scipy.signal import butter, sosfiltfilt

        corners = [(kind, fc) for kind, fc in (("highpass", highpass), ("lowpass", lowpass))
                   if fc is not None]  # fmt: skip
        sos = [butter(int(order), fc, btype=kind, output="sos", fs=1.0 / dt)
               for kind, fc in corners]  # fmt: skip
        f_min = min(fc for _, fc in corners)
        pad = math.ceil(PAD_PERIODS * order / f_min / dt)
        padded = np.concatenate([np.zeros(pad), self.acceleration, np.zeros(pad)])
        out = sosfiltfilt(np.concatenate(sos), padded, padtype=None)[pad : pad + self.time.size]
        band = (f"band-pass {highpass:g}–{lowpass:g} Hz" if highpass and lowpass
                else f"high-pass {highpass:g} Hz" if highpass
                else f"low-pass {lowpass:g} Hz")  # fmt: skip
        note = f"{band} (Butterworth order {order}, zero phase)"
        done = ", ".join(x for x in (self.processing, note) if x)
        return dataclasses.replace(self, acceleration=np.asarray(out, dtype=float),
                                   processing=done)  # fmt: skip

    def filter_problem(self, *, highpass: float | None = None, lowpass: float | None = None,
                       order: int = 4) -> tuple[str, str] | None:  # fmt: skip
        """What is wrong with these settings of :meth:`filtered` for this record, as
        (setting, what was expected and found), the setting "" for the record itself; None
        if they are valid: 0.01/duration ≤ highpass < lowpass < 1/(2Δt) (a low-pass
        alone: 0.01/duration ≤ lowpass), order an integer
        in [1, 8],
        at least one corner, equally spaced samples."""
        integer = isinstance(order, int | np.integer) and not isinstance(order, bool)
        if not (integer and 1 <= order <= 8):
            return "order", f"expected an integer in [1, 8], found {order!r}"
        if highpass is None and lowpass is None:
            return "", "expected a highpass or a lowpass corner (Hz), or both"
        dts = np.diff(self.time)
        dt = float(self.duration / (self.time.size - 1))
        if not np.allclose(dts, dt, rtol=1e-6, atol=0.0):
            return "", (f"the samples are not equally spaced (Δt from {dts.min():g} to "
                        f"{dts.max():g} s); expected a record with one time step")  # fmt: skip
        nyquist = 0.5 / dt
        for key, fc in (("highpass", highpass), ("lowpass", lowpass)):
            if fc is not None and not (math.isfinite(fc) and 0.0 < fc < nyquist):
                return key, (f"expected a corner frequency in (0, {nyquist:g}) Hz (below the "
                             f"Nyquist frequency 1/(2Δt) of the record {self.name!r}, "
                             f"Δt = {dt:g} s), found {fc!r}")  # fmt: skip
        low = HIGHPASS_MIN_CYCLES / float(self.duration)
        for key, fc in (("highpass", highpass), ("lowpass", lowpass)):
            if fc is not None and fc < low:
                # a corner period beyond 100 record lengths: a high-pass filters nothing
                # the record holds, a low-pass all of it, and the padding (1.5 n periods)
                # would not fit in memory
                return key, (f"expected a corner of at least {low:g} Hz (a period of at "
                             f"most 100 times the record's duration, "
                             f"{float(self.duration):g} s), found {fc!r}")  # fmt: skip
        if highpass is not None and lowpass is not None and not highpass < lowpass:
            return "lowpass", (f"expected a corner above highpass = {highpass:g} Hz (a "
                               f"band-pass), found {lowpass:g} Hz")  # fmt: skip
        return None

    def in_dim(self, d: int) -> GroundMotion:
        """The record with a direction of ``d`` components: itself, or in 3D, for the
        default direction (1, 0) of :meth:`from_samples` and ``pfeie.io.read_record``,
        the same record along x = (1, 0, 0). Any other direction of the wrong size is
        refused (another 2D direction is ambiguous in 3D: y is vertical in 2D,
        horizontal in 3D).

        >>> g = GroundMotion.from_samples([0.0, 1.0, 0.0], dt=0.01)
        >>> g.in_dim(3).direction.tolist(), g.in_dim(2) is g
        ([1.0, 0.0, 0.0], True)
        """
        e = self.direction
        if e.size == d:
            return self
        if e.size == 2 and d == 3 and tuple(e) == (1.0, 0.0):
            return dataclasses.replace(self, direction=np.array([1.0, 0.0, 0.0]))
        x, up = ((1, 0, 0), (0, 0, 1)) if d == 3 else ((1, 0), (0, 1))
        raise ModelError(f"ground motion {self.name!r}: direction has {e.size} components, "
                         f"the model is {d}D (y is vertical in 2D, z in 3D): pass "
                         f"direction={x} for x, {up} for the vertical")  # fmt: skip

    def motion(self, t: float) -> tuple[float, float, float]:
        """Ground displacement (m), velocity (m/s) and acceleration (m/s²) at t, integrated
        exactly from the piecewise-linear record (zero before its start, constant velocity
        after its end). The acceleration is the record's at its first and last samples
        too, as :meth:`__call__` gives it (the loads of the relative form): the absolute
        form's supports start from it (it read 0 at t₀, and a record that starts at a
        non-zero acceleration drove the two forms apart from the first step).

        >>> g = GroundMotion.from_samples([2.0, 2.0], dt=0.01)
        >>> g.motion(0.0), g.motion(0.01)[2] == g(0.01) == 2.0
        ((0.0, 0.0, 2.0), True)
        """
        tt, a = self.time, self.acceleration
        h = np.diff(tt)
        if not hasattr(self, "_vd"):
            v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * h)])
            d = np.concatenate([[0.0], np.cumsum(v[:-1] * h + h * h * (2 * a[:-1] + a[1:]) / 6)])
            object.__setattr__(self, "_vd", (v, d))
        v, d = self._vd  # type: ignore[attr-defined]
        if t < tt[0]:
            return 0.0, 0.0, 0.0
        if t >= tt[-1]:
            return (float(d[-1] + v[-1] * (t - tt[-1])), float(v[-1]),
                    float(a[-1]) if t == tt[-1] else 0.0)  # fmt: skip
        i = int(np.searchsorted(tt, t, side="right")) - 1
        tau, hi = t - tt[i], h[i]
        da = (a[i + 1] - a[i]) / hi
        acc = a[i] + da * tau
        vel = v[i] + a[i] * tau + 0.5 * da * tau * tau
        dis = d[i] + v[i] * tau + 0.5 * a[i] * tau * tau + da * tau**3 / 6
        return float(dis), float(vel), float(acc)

    def spectrum(
        self, periods: npt.ArrayLike, damping: float = 0.05, substeps: int | None = None
    ) -> ResponseSpectrum:
        """The elastic response spectrum at ``periods`` (s) for the damping ratio
        ``damping``: Sd (m), PSv (m/s), PSa (m/s²), peak absolute acceleration (m/s²), by
        the exact recurrence for the piecewise-linear record (:mod:`pfeie.model._spectrum`).

        >>> gm = GroundMotion.from_samples([0.0, 1.0, 0.0, -1.0, 0.0], dt=0.1)
        >>> s = gm.spectrum([0.0, 0.2, 1.0])
        >>> float(s.psa[0]), bool(s.psa[1] > 1.0 > s.psa[2])   # PGA at T = 0
        (1.0, True)
        """
        from ._spectrum import response_spectrum

        return response_spectrum(self.time, self.acceleration, periods, damping, substeps)

    def intensity_measures(self, period: float | None = None,
                           damping: float = 0.05) -> dict[str, float]:  # fmt: skip
        """PGA (m/s²), PGV (m/s), PGD (m), Arias intensity (m/s), CAV (m/s), t5, t95,
        D5-95 (s) and, with ``period`` (s), Sa(T₁, ζ) = PSa (m/s²); keys ``pga``,
        ``pgv``, ``pgd``, ``arias``, ``cav``, ``t5``, ``t95``, ``d5_95``, ``sa``
        (see :func:`pfeie.model._spectrum.intensity_measures`)."""
        from ._spectrum import intensity_measures

        return intensity_measures(self.time, self.acceleration, period, damping)

    def sa(self, period: float, damping: float = 0.05) -> float:
        """Sa(T, ζ): the pseudo-spectral acceleration PSa = ω² Sd (m/s²) at ``period``."""
        return float(self.spectrum([period], damping).psa[0])

    @property
    def pga(self) -> float:
        """Peak ground acceleration |a_g|max (m/s²)."""
        return float(np.abs(self.acceleration).max())

    @property
    def duration(self) -> float:
        return float(self.time[-1] - self.time[0])

    @property
    def sampling(self) -> float:
        """The record's sampling interval (s): the median of its time steps."""
        return _median_step(self.time)

    @property
    def along(self) -> str:
        """The record's direction in words (:func:`direction_label`): ``x``, ``-y``, or
        its components."""
        return direction_label(self.direction)

    def summary(self) -> str:
        """One line: name, PGA and its time, duration, Δt, direction."""
        i = int(np.argmax(np.abs(self.acceleration)))
        dts = np.diff(self.time)
        dt = f"{dts[0]:g} s" if np.allclose(dts, dts[0]) else f"{dts.min():g}–{dts.max():g} s"
        return (f"{self.name}: PGA {abs(self.acceleration[i]) / 9.81:.3f} g "
                f"({abs(self.acceleration[i]):.3f} m/s²) at {self.time[i]:.2f} s, "
                f"duration {self.duration:.2f} s, dt {dt}, along {self.along}"
                + (f", {self.processing}" if self.processing else "")
                + (f", {self.scaling}" if self.scaling else ""))  # fmt: skip


def direction_label(direction: Sequence[float] | FloatArray) -> str:
    """A unit direction in words: the axis (``x``, ``-z``) where it is one to 1e-12, else
    its components to three digits.

    >>> direction_label([0.0, 1.0, 0.0]), direction_label([-1.0, 0.0])
    ('y', '-x')
    >>> direction_label([0.8, 0.6, 0.0])
    '(0.8, 0.6, 0)'
    """
    e = np.asarray(direction, dtype=float)
    k = int(np.argmax(np.abs(e)))
    if abs(abs(e[k]) - 1.0) < 1e-12 and np.abs(np.delete(e, k)).max(initial=0.0) < 1e-12:
        return ("-" if e[k] < 0 else "") + "xyz"[k]
    return "(" + ", ".join(f"{c:.3g}" for c in e + 0.0) + ")"
