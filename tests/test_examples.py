"""The README's snippet and the examples run, and check physically meaningful numbers."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[1]


def test_readme_snippet_runs(capsys: pytest.CaptureFixture[str]) -> None:
    text = (ROOT / "README.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S)
    assert code is not None
    scope: dict[str, object] = {}
    exec(compile(code.group(1), "README.md", "exec"), scope)
    # Beam references with Timoshenko's shear correction (L/h = 10, plane stress, κ = 5/6):
    # f1 = (β₁L)²/(2πL²) √(EI/(ρA)) × (1 − ½(β₁r/L)²(1 + E/(κG))), r² = I/A;
    # tip under self-weight q: qL⁴/(8EI) + qL²/(2κGA).
    E, nu, rho, L, h = 30e9, 0.2, 2400.0, 10.0, 1.0
    G, kappa, inertia, area = E / (2 * (1 + nu)), 5 / 6, h**3 / 12, h
    beta1 = brentq(lambda x: np.cos(x) * np.cosh(x) + 1, 1.0, 2.5)  # cos βL cosh βL = −1
    f_eb = beta1**2 / (2 * np.pi * L**2) * np.sqrt(E * inertia / (rho * area))
    shear = 0.5 * (beta1 / L) ** 2 * inertia / area * (1 + E / (kappa * G))
    assert float(scope["f1"]) == pytest.approx(f_eb * (1 - shear), rel=3e-3)  # type: ignore[arg-type]
    q = rho * 9.81 * area
    tip = q * L**4 / (8 * E * inertia) + q * L**2 / (2 * kappa * G * area)
    static = scope["static"]
    assert -static.u[:, 1].min() == pytest.approx(tip, rel=3e-3)  # type: ignore[attr-defined]
    assert "tip" in capsys.readouterr().out


def test_readme_sliding_block(capsys: pytest.CaptureFixture[str]) -> None:
    """The second README snippet reproduces V2b: u = 0.179804 m (Newmark 1965; the
    closed form of verification-cases.md), to 1 %."""
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    scope: dict[str, object] = {}
    exec(compile(blocks[1], "README.md", "exec"), scope)
    assert -float(scope["slip"]) == pytest.approx(0.179804, rel=1e-2)  # type: ignore[arg-type]
    assert "slip" in capsys.readouterr().out


def test_dam_demo_short() -> None:
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import dam_monolith
    finally:
        sys.path.pop(0)
    r = dam_monolith.main(duration=3.0)
    assert r["reaction_error_horizontal"] < 1e-8  # base shear = ρ_w g h²/2
    assert r["reaction_error_vertical"] < 1e-8  # base normal force = weight
    assert r["energy_balance_error"] < 1e-8  # T + U + D = W (average acceleration)
    assert 2.0 < r["f1_hz"] < 3.5  # gravity dams of ~100 m: 2.5–3.5 Hz on rigid rock
    assert r["peak_crest_acc_g"] > r["pga_g"]  # the crest amplifies the ground motion
