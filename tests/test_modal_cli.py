"""``pfeie modal`` with and without the reservoir's added mass (``--dry``), on the Pine
Flat demo (examples/pine_flat: a finite-element reservoir, ``[[loads.westergaard]]``
with model = 'fe').

References: the same model file with its ``[[loads.westergaard]]`` table removed (an
independent path: the model is built without a reservoir, so its mass matrix never
holds an added mass); the Rayleigh quotient, by which an added mass M_a ≥ 0 can only
lower the first frequency, ω₁² = min φᵀKφ / φᵀ(M + M_a)φ ≤ min φᵀKφ / φᵀMφ.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest

import pfeie as pf
from pfeie.cli import main
from pfeie.io import load_job

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "examples" / "pine_flat"
MODEL = FOLDER / "pine_flat.toml"
N = 4


def without_reservoir(tmp: Path) -> Path:
    """The Pine Flat model file with its ``[[loads.westergaard]]`` table cut out (the
    mesh and the record then named by absolute paths)."""
    text = MODEL.read_text()
    table = re.search(r"\[\[loads\.westergaard\]\].*?\n\n", text, re.S)
    assert table is not None and 'model = "fe"' in table.group(0)
    text = text.replace(table.group(0), "")
    text = text.replace('"pine_flat.msh"', f'"{FOLDER / "pine_flat.msh"}"')
    text = text.replace('"../data/', f'"{FOLDER.parent / "data"}/')
    assert "westergaard" not in text
    p = tmp / "no_reservoir.toml"
    p.write_text(text)
    return p


def frequencies(folder: Path) -> np.ndarray:
    rows = list(csv.DictReader((folder / "modes.csv").open()))
    return np.array([float(r["frequency_hz"]) for r in rows])


def test_dry_modes_are_those_without_the_reservoir(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``pfeie modal --dry`` gives the frequencies of the model file without its reservoir
    (modes.csv: the same 9 significant digits; :func:`pfeie.modal`: frequencies and
    effective masses the same to round-off, asserted 1e-12, measured 0), and the table
    says which mass it used. Without ``--dry`` the reservoir's added mass lowers the first frequency
    (Rayleigh: it cannot raise it; measured 2.0353 Hz wet, 2.4600 Hz dry)."""
    bare = without_reservoir(tmp_path)
    runs = {"wet": [str(MODEL)], "dry": [str(MODEL), "--dry"], "bare": [str(bare)]}
    said = {}
    for name, argv in runs.items():
        assert main(["modal", *argv, "-n", str(N), "--out", str(tmp_path / name)]) == 0
        said[name] = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("mass:")]
    f_wet, f_dry, f_bare = (frequencies(tmp_path / k) for k in ("wet", "dry", "bare"))
    np.testing.assert_array_equal(f_dry, f_bare)
    assert f_wet[0] < f_dry[0]
    assert said["wet"][0].startswith("mass: wet") and "--dry leaves it out" in said["wet"][0]
    assert said["dry"][0].startswith("mass: dry") and "without the added mass" in said["dry"][0]
    assert said["bare"][0].startswith("mass: the blocks' only") and "no reservoir" in (
        said["bare"][0])  # fmt: skip
    # the library, at full precision: the dry modes equal the bare model's (measured
    # equal bit for bit: the same matrices, the same seeded Lanczos start; 1e-12 leaves
    # room for another summation order only)
    dry = pf.modal(load_job(MODEL).model, N, added_mass=False)
    ref = pf.modal(load_job(bare).model, N)
    np.testing.assert_allclose(dry.frequencies, ref.frequencies, rtol=1e-12)
    np.testing.assert_allclose(dry.total_mass, ref.total_mass, rtol=1e-12)
    np.testing.assert_allclose(dry.effective_mass, ref.effective_mass, rtol=0.0,
                               atol=1e-12 * ref.total_mass.max())  # fmt: skip
