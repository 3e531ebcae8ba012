"""The fast verification suite passes through the command line, and the manual is
written: a page and a figure per case, the summary table, the unsupported case listed."""

from __future__ import annotations

from pathlib import Path

import pytest

from pfeie.cli import main
from pfeie.verification import CASES, Check, run


def test_fast_suite_passes_and_writes_the_manual(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["verify", "--fast", "--manual", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert f"{len(CASES)} of {len(CASES)} cases pass" in out
    for name in CASES:
        assert (tmp_path / f"{name}.md").is_file()
    index = (tmp_path / "index.md").read_text()
    assert "| [V4](V4.md) | extreme slip |" in index
    assert "| [V7b](V7b.md) | quarter period |" in index and "Not run" not in index
    # every case of verification-cases.md (V1-V10) is run, some in parts (V7a, V7b)
    for k in range(1, 11):
        assert any(n == f"V{k}" or (n[:-1] == f"V{k}" and n[-1].isalpha()) for n in CASES)
    assert (tmp_path / "V6.png").stat().st_size > 10_000


def test_check_arithmetic_and_unknown_case() -> None:
    c = Check("x", 2.0, 2.01, 1e-2)
    assert c.passed and c.error == pytest.approx(0.005)
    assert not Check("y", 0.0, 3e-3, 2e-3, relative=False, unit="m").passed
    with pytest.raises(Exception, match="unknown verification case"):
        run(True, ["V99"])
    assert main(["verify", "--case", "V99"]) == 2
