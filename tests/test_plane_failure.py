"""Plane failure with a water-filled tension crack: the yield coefficient against Hoek and
Bray's limit equilibrium, and what a foundation with mass changes (docs/theory.md, "The
yield coefficient").

The model (tests/data/rock_plane_crack.msh, a new user's): a slope H = 30 m high, its face
at ψ_f = 60°, a sliding plane at ψ_p = 35° from the toe, a vertical tension crack z = 10 m
deep at x = 28.56 m; ρ = 2,600 kg/m³, E = 20 GPa; the plane an existing joint with
c_r = 100 kPa, φ = 30°; the crack full of water (z_w = 10 m: `loads.hydrostatic` on it)
and the plane's uplift falling linearly from the crack to the toe (`loads.uplift`,
headwater at the crack's top). Per metre of slope (Hoek and Bray, Rock Slope Engineering,
§6.3, with the horizontal pseudo-static force k W out of the slope):

    FS(k) = (c A + (W (cos ψ_p − k sin ψ_p) − U − V sin ψ_p) tan φ)
            / (W (sin ψ_p + k cos ψ_p) + V cos ψ_p),

A = (H − z)/sin ψ_p, U = ½ γ_w z_w A, V = ½ γ_w z_w², W the block's weight from its
corners; FS(k_y) = 1 gives k_y = 0.12429012 (FS(0) = 1.22906).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest

from pfeie.cli import main

ROOT = Path(__file__).resolve().parents[1]
MESH = ROOT / "tests" / "data" / "rock_plane_crack.msh"

MODEL = """
title = "plane failure, a tension crack full of water"
plane = "strain"
[mesh]
file = "rock_plane_crack.msh"
[materials.rock]
E = 20.0e9
nu = 0.25
rho = 2600.0
[materials.found]
E = 20.0e9
nu = 0.25
rho = {rho_found}
[blocks]
block = "rock"
rock = "found"
[interfaces.plane]
friction_angle = 30.0
residual_cohesion = 100.0e3
[interfaces.crack]
friction_angle = 30.0
[[supports]]
group = "base"
[analysis]
dynamic = false
yield_coefficient = ["-x"]
[output]
folder = "out"
[[loads.hydrostatic]]
groups = ["crack"]
water_level = 30.0
[[loads.uplift]]
interface = "plane"
headwater = 30.0
upstream = "+x"
"""


def _hand_ky() -> float:
    """Hoek and Bray's k_y of the module doc."""
    H, z, zw, c, phi = 30.0, 10.0, 10.0, 100e3, math.radians(30.0)
    psi_p, psi_f = math.radians(35.0), math.radians(60.0)
    gam, gw = 2600.0 * 9.81, 1000.0 * 9.81
    xc = (H - z) / math.tan(psi_p)
    corners = [(0.0, 0.0), (xc, H - z), (xc, H), (H / math.tan(psi_f), H)]
    area = 0.5 * abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1)
                         in zip(corners, corners[1:] + corners[:1], strict=True)))  # fmt: skip
    W, A = gam * area, (H - z) / math.sin(psi_p)
    U, V = 0.5 * gw * zw * A, 0.5 * gw * zw**2
    s, co, t = math.sin(psi_p), math.cos(psi_p), math.tan(phi)
    return (c * A + (W * co - U - V * s) * t - W * s - V * co) / (W * (co + s * t))


def _yield(tmp: Path, rho_found: float) -> dict[str, float]:
    shutil.copy(MESH, tmp / MESH.name)
    p = tmp / "model.toml"
    p.write_text(MODEL.format(rho_found=repr(rho_found)))
    assert main(["run", str(p), "--quiet"]) == 0
    y: dict[str, float] = json.loads((tmp / "out" / "summary.json").read_text())[
        "yield_coefficient"]["-x"]  # fmt: skip
    return y


def test_massless_foundation_gives_hoek_and_bray(tmp_path: Path) -> None:
    """With the rock mass massless (ρ = 1 kg/m³: no pseudo-static load of its own), the
    block's limit is the rigid block's: the margins' affine root to 5e-11 of the hand's
    k_y (measured 9e-12: no pair state changes up to the limit, so the margin is
    affine in k), k_y itself within the search's 1e-6, sliding on the plane."""
    y = _yield(tmp_path, 1.0)
    ky = _hand_ky()
    assert y["limit"] == "sliding" and y["joint"] == "plane"
    assert y["k_affine"] == pytest.approx(ky, rel=5e-11)
    assert y["k_y"] == pytest.approx(ky, rel=1e-6)


@pytest.mark.slow
def test_a_foundation_with_mass_leans_on_the_block(tmp_path: Path) -> None:
    """With the rock mass at 2,600 kg/m³ its own k g pushes the rock behind the crack onto
    the block's top: the block slides earlier, k_y between 1 % and 2 % below the hand's
    (measured 0.122527, 1.42 % below), still a sliding limit on the plane. It read
    0.11899 (4.3 % below) where the Newtons failed from k = 0.1207 on; the bordered
    proximal Newton holds those analyses (their equilibria balance the reactions to
    2e-11, docs/theory.md)."""
    y = _yield(tmp_path, 2600.0)
    ky = _hand_ky()
    assert y["limit"] == "sliding" and y["joint"] == "plane"
    assert 0.98 * ky < y["k_y"] < 0.99 * ky
