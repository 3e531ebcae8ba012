"""Make the synthetic records of the study example (``records/*.csv``).

Each record is stationary white noise filtered by the Kanai-Tajimi ground filter
(Kanai 1957; Tajimi 1960) and shaped by the envelope of Jennings, Housner and Tsai (1968):
a quadratic rise over t1, a plateau to t2, then exp(-c (t - t2)). The ground's frequency
and damping differ per record (firm to soft soil), so that the suite has spread. The
records are synthetic, made to exercise a study; for an assessment, use recorded
motions selected for the site. Columns: time (s), acceleration (g), PGA 0.3 g (a study
scales them anyway). Run ``python make_records.py`` to make them again (same bits: the
seeds are fixed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import signal

DT, DURATION = 0.01, 15.0
# (seed, ground frequency f_g (Hz), ground damping ζ_g, t1, t2 (s), decay c (1/s))
RECORDS = [(1, 2.5, 0.6, 1.5, 6.0, 0.35), (2, 1.2, 0.4, 2.0, 7.0, 0.25),
           (3, 4.0, 0.6, 1.0, 5.0, 0.45), (4, 1.8, 0.5, 1.5, 8.0, 0.30)]  # fmt: skip


def record(seed: int, fg: float, zg: float, t1: float, t2: float, c: float,
           duration: float = DURATION) -> np.ndarray:  # fmt: skip
    """The acceleration (g) at t = 0, DT, ... duration: filtered noise times the envelope."""
    t = np.arange(0.0, duration + DT / 2, DT)
    w = np.random.default_rng(seed).standard_normal(t.size)
    wg = 2 * np.pi * fg
    kt = signal.lti([2 * zg * wg, wg * wg], [1.0, 2 * zg * wg, wg * wg])
    _, a, _ = signal.lsim(kt, w, t)
    env = np.where(t < t1, (t / t1) ** 2, np.where(t < t2, 1.0, np.exp(-c * (t - t2))))
    a = a * env
    a -= np.linspace(a[0], a[-1], t.size)  # start and end at rest
    return np.c_[t, 0.3 * a / np.abs(a).max()]


def main() -> None:
    out = Path(__file__).parent / "records"
    out.mkdir(exist_ok=True)
    for seed, fg, zg, t1, t2, c in RECORDS:
        np.savetxt(out / f"synthetic_{seed}.csv", record(seed, fg, zg, t1, t2, c),
                   delimiter=",", header="time (s),acceleration (g)", fmt="%.6g")  # fmt: skip


if __name__ == "__main__":
    main()
