"""Event sub-steps (``event_substeps``): a step in which a pair changes state is taken
again as k sub-steps of Δt/k (docs/theory.md, "Event sub-steps").

References: V8c of the verification cases (a bonded block under a rising base
acceleration k t breaks when m |a| = c A + m g tan φ, then slides with μ = tan φ: the slip
in closed form), the same run without sub-steps, and the energy balance."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.verification._models import block_on_base, slip_x

G = 9.81
C, PHI, RAMP = 2e3, 35.0, 10.0  # V8c: cohesion (Pa), friction angle (°), ramp (m/s³)
MU = np.tan(np.radians(PHI))
T_BREAK = (C / 2400.0 + G * MU) / RAMP  # 0.77024 s


def _v8c() -> pf.Model:
    joint = pf.Joint(c=C, phi=PHI, tensile=C / MU, initial="intact")
    return block_on_base(joint=joint, height=1e-3, n=4, ny=1, rho=2.4e6, check_units=False)


def _slip_ref(t: np.ndarray) -> np.ndarray:
    """The rigid block's slip after the break at T_BREAK (m; V8c)."""
    s = t - T_BREAK
    return np.where(s > 0, -(RAMP * s**3 / 6 + (RAMP * T_BREAK - MU * G) * s**2 / 2), 0.0)


@pytest.fixture(scope="module")
def v8c() -> tuple[pf.Model, pf.StaticResult, pf.GroundMotion]:
    model = _v8c()
    t = np.arange(1201) * 1e-3
    return model, pf.solve_static(model), pf.GroundMotion.from_samples(RAMP * t, time=t)


@pytest.mark.parametrize("dt", [0.01, 0.005])
def test_the_break_resolved_by_sub_steps(
    v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion], dt: float
) -> None:
    """The break, detected at the end of the step in which the bond's force exceeds its
    strength, is found at the end of a sub-step of Δt/4: the slip at 1.2 s against V8c's
    closed form is 9 and 15 times closer at Δt = 10 and 5 ms (relative errors measured
    1.1e-2 → 1.2e-3, 5.2e-3 → 3.5e-4). One event step; the balance closes."""
    model, static, gm = v8c
    errors = []
    for k in (1, 4):
        an = pf.Dynamic(model, dt, event_substeps=k)
        res = an.run(1.2, start=static, ground=[gm])
        x = slip_x(res) - slip_x(res)[0]
        ref = _slip_ref(res.t)
        errors.append(abs(x[-1] - ref[-1]) / abs(ref[-1]))
        assert an.event_steps == (k > 1)  # the break; then it slides without a change
        assert int(res.solver["substeps"].sum()) == (4 if k > 1 else 0)
        # the balance to round-off of the input (measured ≤ 3.0e-16 of 5.4 kJ)
        assert abs(res.energy["balance"][-1]) < 3e-15 * res.energy["external_work"][-1]
    without, with_ = errors
    assert without > 4e-3  # the break's O(Δt) error (measured 1.1e-2, 5.2e-3)
    assert with_ < without / 5  # (measured 1/9 and 1/15)


def test_no_event_no_change(v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion]) -> None:
    """Where no pair changes state (the ramp stops before the bond's strength), the run
    with sub-steps is the run without them, to the bit, and the fine step matrix is never
    factorised."""
    model, static, gm = v8c
    runs = []
    for k in (1, 8):
        an = pf.Dynamic(model, 0.01, event_substeps=k)
        runs.append(an.run(0.6, start=static, ground=[gm]))
        assert an.event_steps == 0 and an._fine is None
    for key in ("t", "rigid", "X", "state"):
        np.testing.assert_array_equal(getattr(runs[0], key), getattr(runs[1], key))
    for key, values in runs[0].energy.items():
        np.testing.assert_array_equal(values, runs[1].energy[key], err_msg=key)


def test_resume_across_an_event(
    v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """A run stopped before the break and resumed by a new analysis object gives the bits
    of the run that never stopped (the sub-steps' analysis is built anew there); a twin
    for a study shares the fine factor."""
    model, static, gm = v8c
    kw = {"ground": [gm], "every": 3, "event_substeps": 4}
    an = pf.Dynamic(model, 0.01, event_substeps=4)
    full = an.run(1.0, start=static, ground=[gm], every=3)
    cks: list[pf.dynamics.Checkpoint] = []
    pf.Dynamic(model, 0.01, event_substeps=4).run(0.5, start=static, ground=[gm], every=3,
                                                 on_checkpoint=cks.append)  # fmt: skip
    ck = cks[-1]
    del kw["event_substeps"]
    rest = pf.Dynamic(model, 0.01, event_substeps=4).run(n_steps=100 - ck.state.step,
                                                        resume=ck, **kw)  # fmt: skip
    assert full.broken[-1].all() and not full.broken[ck.row].any()
    for key in ("rigid", "X", "w", "s", "state", "broken"):
        both = np.concatenate([getattr(full, key)[: ck.row + 1], getattr(rest, key)[1:]])
        np.testing.assert_array_equal(both, getattr(full, key), err_msg=key)
    for key, values in full.energy.items():
        np.testing.assert_array_equal(np.r_[values[: ck.row + 1], rest.energy[key][1:]],
                                      values, err_msg=key)  # fmt: skip
    assert an.twin().fine().factor is an.fine().factor


def test_resume_next_to_an_event(
    v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """Resumed at the row before the event step, at the event step's row and after it:
    the energy terms too are those of the run that never stopped (Φ is taken in each
    step's own step size, at both of its ends, not from a cache of the other size)."""
    model, static, gm = v8c
    cks: list[pf.dynamics.Checkpoint] = []
    full = pf.Dynamic(model, 0.01, event_substeps=4).run(1.0, start=static, ground=[gm],
                                                         on_checkpoint=cks.append)  # fmt: skip
    (event,) = np.flatnonzero(full.solver["substeps"])  # the break, step 77
    for row in (event - 1, event, event + 5):
        rest = pf.Dynamic(model, 0.01, event_substeps=4).run(
            n_steps=100 - row, resume=cks[row - 1], ground=[gm])  # fmt: skip
        np.testing.assert_array_equal(rest.rigid, full.rigid[row:], err_msg=str(row))
        for key, values in full.energy.items():
            np.testing.assert_array_equal(rest.energy[key], values[row:], err_msg=key)


def test_a_failed_sub_step_keeps_the_step(
    v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion], monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:  # fmt: skip
    """A pair problem that fails in an event's sub-steps: the sub-steps are undone (their
    energy terms with them) and the step of Δt, which converged, is kept: the run goes on,
    its balance closed, and says so."""
    import logging

    from pfeie.coupling import InterfaceStep

    model, static, gm = v8c
    an = pf.Dynamic(model, 0.01, event_substeps=4)
    fine = an.fine()
    assert fine.istep is not None
    calls = {"n": 0}
    solve = InterfaceStep.solve

    def failing(self: InterfaceStep, *args: object, **kw: object) -> object:
        if self is fine.istep:
            calls["n"] += 1
            if calls["n"] == 3:  # the third smooth problem of the sub-steps
                raise pf.InterfaceError("forced")
        return solve(self, *args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(InterfaceStep, "solve", failing)
    with caplog.at_level(logging.WARNING):
        res = an.run(1.2, start=static, ground=[gm])
    assert res.completed and an.event_steps == 0 and calls["n"] == 3
    assert "the event's sub-steps failed (forced); the step of dt is kept" in caplog.text
    assert abs(res.energy["balance"][-1]) < 3e-15 * res.energy["external_work"][-1]


def test_moreau_jean_sub_steps(
    v8c: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """The Moreau-Jean scheme takes its events in sub-steps too (θ = 1). Its sliding is
    first order, and that error dominates: the slip's relative error against V8c's
    closed form goes from 7.1e-2 to 5.8e-2 at Δt = 10 ms (the break's part removed). The
    balance closes to the θ-method's round-off (measured 7e-10 and 2.7e-9 of the input;
    criterion 8 of the contact-dynamics issue asks 1e-8)."""
    model, static, gm = v8c
    errors = []
    for k in (1, 4):
        res = pf.Dynamic(model, 0.01, scheme="moreau-jean", event_substeps=k).run(
            1.2, start=static, ground=[gm])  # fmt: skip
        x = slip_x(res) - slip_x(res)[0]
        errors.append(abs(x[-1] - _slip_ref(res.t)[-1]) / abs(_slip_ref(res.t)[-1]))
        assert abs(res.energy["balance"][-1]) < 2e-8 * res.energy["external_work"][-1]
    assert errors[1] < 0.9 * errors[0]  # (measured 0.81)


def test_settings_refused() -> None:
    """Out of range, or with large rotations: a clear error naming the key."""
    model = _v8c()
    with pytest.raises(pf.ModelError, match="event_substeps"):
        pf.Dynamic(model, 0.01, event_substeps=0)
    with pytest.raises(pf.ModelError, match="event_substeps"):
        pf.Dynamic(model, 0.01, event_substeps=17)
    with pytest.raises(pf.ModelError, match="large_rotation"):
        pf.Dynamic(model, 0.01, event_substeps=4, large_rotation=True)
