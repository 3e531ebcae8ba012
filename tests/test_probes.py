"""Probes on a joint: the point [0.5, 1] lies on the joint between the blocks rock and
dam of the two-block model, where each block has its own node. Without ``block`` the
node taken is named in a warning with both blocks; ``block = "..."`` takes that block's
node (its coordinates the point's, its cells the block's); a misspelt block is an error
naming the key and the blocks."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pytest

from conftest import cli_fails
from pfeie.io import load_job
from test_cli import SMALL, _write


def _model(tmp: Path, probe: str) -> Path:
    return _write(tmp, SMALL.replace("probes = { top = [1.0, 2.0] }", f"probes = {{ {probe} }}"))


@pytest.mark.parametrize("block", ["rock", "dam"])
def test_probe_on_a_joint_takes_the_named_block(tmp_path: Path, block: str,
                                                caplog: pytest.LogCaptureFixture) -> None:
    job = load_job(_model(tmp_path, f'heel = {{ at = [0.5, 1.0], block = "{block}" }}'))
    node = job.probes["heel"]
    assert node in job.model.block_nodes(block)
    np.testing.assert_array_equal(job.model.mesh.points[node], [0.5, 1.0])
    assert "lies on a joint" not in caplog.text


def test_probe_on_a_joint_is_warned(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING):
        job = load_job(_model(tmp_path, "heel = [0.5, 1.0], top = [1.0, 2.0]"))
    node = job.probes["heel"]
    taken = "rock" if node in job.model.block_nodes("rock") else "dam"
    assert ("model.toml: output.probes.heel: the point [0.5, 1.0] lies on a joint, at a node "
            "of each of the blocks rock, dam; the node of " + taken + " is taken (to "
            "choose: output.probes.heel = { at = [0.5, 1.0], block = \"" + taken + "\" })"
            ) in caplog.text  # fmt: skip
    assert "output.probes.top" not in caplog.text  # inside one block: no word


def test_probe_block_misspelt(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = _model(tmp_path, 'heel = { at = [0.5, 1.0], block = "dma" }')
    cli_fails(capsys, ["check", str(p)], "model.toml: output.probes.heel.block: 'dma' is not "
              "a block of the model (its blocks: rock, dam)")  # fmt: skip
    p = _model(tmp_path, 'heel = "a"')
    cli_fails(capsys, ["check", str(p)], "output.probes.heel: expected an array of 2 to 3 "
              "numbers (the point) or a table { at = [...], block = name }, found a string")
