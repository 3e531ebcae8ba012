"""Findings of the twenty-ninth review.

Each test reproduces the defect and checks the fix against an independent number.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.io import Results, read_record
from test_checkpoint import run_then_stop
from test_cli import SMALL
from test_review28 import _block_on_a_joint

DATA = Path(__file__).resolve().parents[1] / "examples" / "data"


# -- the absolute form with event sub-steps ------------------------------------------------


@pytest.fixture(scope="module")
def sliding_block() -> tuple[pf.Model, pf.StaticResult, pf.GroundMotion]:
    """The README's block (μ = 0.2) under 2 × El Centro: it slides and sticks again and
    again, so that many steps are events."""
    model, _ = _block_on_a_joint()
    gm = read_record(DATA / "elcentro_1940_ns_chopra.csv", units="g", scale=2.0)
    return model, pf.solve_static(model), gm


def test_absolute_form_with_event_sub_steps_is_the_relative_form(
    sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """Over an event step's sub-steps the supports followed the record's exact motion
    plus the coarse grid's drift interpolated, not the scheme's recurrence on the finer
    grid that carries the blocks: a body fixed to the base was strained, and the slip of
    the block differed between the forms by 1.7 % of its peak (204 sub-steps in 3 s).
    Now the supports take the recurrence of the sub-steps and the grid goes on from
    where they end. Independent computation: the relative form (the slips at the joint
    do not depend on the form); measured 1.8e-9 of the peak slip, as without sub-steps
    (2.0e-9: round-off through the stiff contact)."""
    model, static, gm = sliding_block
    slip = {}
    for form in ("relative", "absolute"):
        an = pf.Dynamic(model, 0.01, event_substeps=4)
        res = an.run(3.0, ground=[gm], start=static, form=form)
        slip[form] = res.s[:, :, 0].mean(axis=1)
        assert int(res.solver["substeps"].sum()) > 100  # many events (measured 136)
    peak = np.abs(slip["relative"]).max()
    assert peak > 0.03  # it slides (measured 59 mm)
    assert np.abs(slip["absolute"] - slip["relative"]).max() < 2e-8 * peak


def test_absolute_form_resumed_after_events_gives_the_same_bits(
    sliding_block: tuple[pf.Model, pf.StaticResult, pf.GroundMotion],
) -> None:
    """A checkpoint keeps the supports' grid row (events moved it off the grid's own
    recurrence); a run resumed from it after events gives the bits of the run that never
    stopped. Before, the resumed supports restarted from the grid's own recurrence: a
    jump of the ground's displacement at the resume."""
    model, static, gm = sliding_block
    cks: list[pf.dynamics.Checkpoint] = []
    full = pf.Dynamic(model, 0.01, event_substeps=4).run(
        2.0, ground=[gm], start=static, form="absolute", on_checkpoint=cks.append)
    events = np.flatnonzero(full.solver["substeps"])
    row = int(events[len(events) // 2]) + 1  # after half of the events
    ck = cks[row - 1]
    assert ck.state.step == row and ck.supports is not None and ck.supports.shape == (1, 4)
    rest = pf.Dynamic(model, 0.01, event_substeps=4).run(
        n_steps=200 - row, resume=ck, ground=[gm], form="absolute")  # fmt: skip
    for key in ("rigid", "X", "s", "state", "ground"):
        np.testing.assert_array_equal(getattr(rest, key), getattr(full, key)[row:],
                                      err_msg=key)  # fmt: skip
    for key, values in full.energy.items():
        np.testing.assert_array_equal(rest.energy[key], values[row:], err_msg=key)


def test_absolute_form_with_events_resumed_from_the_results_file(tmp_path: Path) -> None:
    """``pfeie run --resume`` of a run in the absolute form with event sub-steps: the
    checkpoint in results.h5 holds ``kin/supports`` and the resumed file equals the
    uninterrupted run's, history for history."""
    text = SMALL.replace("[analysis]", '[analysis]\nform = "absolute"\nevent_substeps = 4')
    text = text.replace('units = "g"', 'units = "g"\nscale = 2.0')
    p = run_then_stop(tmp_path, text, 0.8, 0.4)
    ref_dir, ext_dir = tmp_path / "ref", tmp_path / "ext"
    with Results(ext_dir / "out" / "results.h5") as res:
        assert "kin/supports" in res.f["checkpoint"]
        assert res.f["history/solver/substeps"][:].sum() > 0  # events before the resume
    assert main(["run", str(p), "--quiet", "--resume"]) == 0
    with Results(ref_dir / "out" / "results.h5") as ref, \
            Results(ext_dir / "out" / "results.h5") as got:  # fmt: skip
        for name in ("ground", "time", "solver/substeps", "energy/balance", "energy/interface"):
            np.testing.assert_array_equal(got.f[f"history/{name}"][:], ref.f[f"history/{name}"][:],
                                          err_msg=name)  # fmt: skip
        for key, value in ref.pairs().items():
            np.testing.assert_array_equal(got.pairs()[key], value, err_msg=key)
