"""The reservoir's added mass (Westergaard 1933), against its closed forms.

On a rigid vertical face of water depth H the pressure per unit normal acceleration is
C(y) = 7/8 ρ_w √(H y), y the depth; its integrals give the added mass and its first and
second moments about the bottom, per metre of face:

    ∫ C dy = 7/12 ρ_w H²,   ∫ C (H − y) dy = 7/30 ρ_w H³,   ∫ C (H − y)² dy = 2/15 ρ_w H⁴.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import pfeie as pf

RHO_W = 1000.0


def test_added_mass_total_converges() -> None:
    """The lumped added mass of a 10 m vertical face sums to 7/12 ρ_w H² as the face is
    refined, at the rate the square root at the surface allows (measured 7.1e-5, 8.9e-6,
    1.1e-6 on 4, 16, 64 cells: rate 1.5; asserted ≥ 1.4 and 2e-6 at 64 cells); it acts
    along the face normal only (x)."""
    errs = []
    ns = [4, 16, 64]
    for n in ns:
        mesh = pf.rectangle(1.0, 10.0, 1, n)
        m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        m.add_westergaard("xmin", water_level=10.0)
        am = m.added_mass().reshape(-1, 2)
        assert am[:, 1].sum() == 0.0 and np.all(am >= 0)
        errs.append(abs(am[:, 0].sum() / (7 / 12 * RHO_W * 10.0**2) - 1))
    rate = np.log(errs[0] / errs[-1]) / np.log(ns[-1] / ns[0])
    assert rate >= 1.4 and errs[-1] < 2e-6, (errs, rate)


def _wet_block(ny: int, westergaard: bool = True) -> pf.Model:
    """A stiff 1 m block (E = 1e14 Pa) on joint springs k_n = k_s = 1e9 Pa/m, its left face
    wet up to its top (H = 1 m), on a fixed base."""
    mesh = pf.rectangle(1.0, 1.5, 4, ny + ny // 2)
    mesh.add_cell_group("base", lambda x: x[:, 1] < 0.5)
    mesh.add_cell_group("block", lambda x: x[:, 1] > 0.5)
    mesh.add_facet_group("joint", lambda x: np.abs(x[:, 1] - 0.5) < 1e-9, False)
    mesh.add_facet_group("wet", lambda x: (x[:, 0] < 1e-9) & (x[:, 1] > 0.5 - 1e-9))
    mat = pf.Elastic(1e14, 0.2, 2400.0)
    joint = pf.Joint(phi=30.0, kn=1e9, ks=1e9)
    m = pf.Model(mesh, [pf.Block("base", mat), pf.Block("block", mat)],
                 interfaces=[pf.Interface("joint", joint)])  # fmt: skip
    m.fix("base")
    if westergaard:
        m.add_westergaard("wet", water_level=1.5)
    return m


def test_added_mass_in_the_modes_of_a_block_on_springs() -> None:
    """The sliding-rocking modes of the wet block: the 2 × 2 rigid-body problem about the
    joint's centre with the block's mass and the added mass's closed-form moments,
    M = [[m + m_a, m h + S_a], [m h + S_a, I + I_a]] (m_a = 7/12 ρ_w H², S_a = 7/30 ρ_w H³,
    I_a = 2/15 ρ_w H⁴), K = diag(k_s A, Σ k_n A_i x_i²); the vertical mode does not see
    the added mass (it acts along x). Errors fall at second order with the face's cells
    (measured 9.7e-4, 2.3e-4, 5.8e-5, 1.6e-5 for the first mode, 5.2e-3 to 8.3e-5 for the
    third: rates 1.87 to 2.07, the last one nearing the block's deformability; asserted
    rates ≥ 1.8, 2e-5 and 1e-4 on 32 cells); the vertical mode within 2e-6
    of √(k_n A/m)/2π (measured 1.6e-6, the block's own deformability)."""
    m_b, h, H = 2400.0, 0.5, 1.0
    m_a, s_a, i_a = 7 / 12 * RHO_W * H**2, 7 / 30 * RHO_W * H**3, 2 / 15 * RHO_W * H**4
    errs = []
    ns = [4, 8, 16, 32]
    for ny in ns:
        model = _wet_block(ny)
        P = model.pairs
        assert P is not None
        x = model.mesh.points[P.node_a, 0] - 0.5
        Mr = np.array([[m_b + m_a, m_b * h + s_a], [m_b * h + s_a, m_b / 6 + m_b * h * h + i_a]])
        Kr = np.diag([1e9 * P.area.sum(), float((1e9 * P.area * x**2).sum())])
        f_hr = np.sqrt(sla.eigh(Kr, Mr, eigvals_only=True)) / (2 * np.pi)
        f_v = np.sqrt(1e9 * P.area.sum() / m_b) / (2 * np.pi)
        f = pf.modal(model, 3).frequencies
        errs.append([abs(f[0] / f_hr[0] - 1), abs(f[2] / f_hr[1] - 1)])
        assert f[1] == pytest.approx(f_v, rel=2e-6)
    e = np.array(errs)
    rates = np.log2(e[:-1] / e[1:])
    assert rates.min() >= 1.8, rates
    assert e[-1, 0] < 2e-5 and e[-1, 1] < 1e-4, e[-1]
    dry = pf.modal(_wet_block(8, westergaard=False), 1).frequencies[0]
    assert dry > 1.05 * pf.modal(_wet_block(8), 1).frequencies[0]  # the water slows it (7 %)


def test_added_mass_errors_and_model_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A water level at or below the reservoir bottom, or a group of cells, is refused
    with the key named; through a model file the added mass reaches the run's M."""
    model = _wet_block(4, westergaard=False)
    with pytest.raises(pf.ModelError, match="must lie above the reservoir bottom"):
        model.add_westergaard("wet", water_level=0.2)
    with pytest.raises(pf.ModelError, match="inside a block"):
        mesh = pf.rectangle(2.0, 1.0, 2, 1)
        mesh.add_facet_group("mid", lambda x: np.abs(x[:, 0] - 1.0) < 1e-9, False)
        pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 1.0))]).add_westergaard("mid", 1.0)
    from pfeie.io import load_job
    from test_cli import SMALL, _write

    text = SMALL.replace("[[supports]]", "[[loads.westergaard]]\ngroups = [\"bottom\"]\n"
                         "water_level = 0.5\n\n[[supports]]")  # fmt: skip
    job = load_job(_write(tmp_path, text))
    assert job.model.added_mass().sum() > 0
    bad = text.replace("water_level = 0.5", "water_level = -5.0")
    with pytest.raises(pf.errors.InputError, match=r"loads.westergaard\[0\]: westergaard"):
        load_job(_write(tmp_path, bad))
