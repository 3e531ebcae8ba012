"""Natural frequencies and wave arrival against closed forms.

- Shear column (fixed base, free top, only the horizontal motion free): continuum
  frequencies f_n = (2n − 1) c_s/(4H) (e.g. Kramer, Geotechnical Earthquake
  Engineering, §7.2). Linear elements with consistent mass reproduce exactly the
  dispersion relation of the discrete chain, ω_h² = (6c²/h²)(1 − cos kh)/(2 + cos kh),
  at k = (2n − 1)π/(2H) (mirror symmetry of the free end), an overestimate of
  ω by (kh)²/24 + O(h⁴): checked to 1e-12 (measured 1.1e-13), and the continuum's error
  equals (kh)²/24 to 5e-3 (measured 8.4e-4, the O(h⁴) term).
- Cantilever, L/h = 20, ν = 0: the Timoshenko beam (shear with κ = 5/6, Cowper's for a
  rectangle at ν = 0, and rotary inertia), its frequencies computed here independently
  by the transfer matrix exp(A L) of the beam's four first-order equations and the
  free end's two conditions (M = EIψ' = 0, V = κGA(w' − ψ) = 0): 2.793364 and
  17.33684 Hz, 0.164 % and 1.127 % below Euler-Bernoulli's (β_n L)²/(2πL²) √(EI/(ρA)),
  against which the test compared before with 0.5 % and 1.5 % (a discretisation error of
  0.3 % would have passed). The 2D Q8 model (40 × 4) reaches 5.8e-6 and 5.1e-5 of them
  (tolerances 5e-5, 5e-4), the 3D Tet10 (20 × 2 × 2) 9.8e-5 and 7.1e-4 (tolerances
  1e-3, 5e-3); the two bending directions of the square 3D section agree to 5e-4
  (measured 5.7e-5).
- A pulse crossing a column arrives at L/c within two element transit times (measured
  1.25, the peak of a 20-element pulse on a mesh of one element per step of 4), with the
  particle velocity of a plane wave v = σ/(ρc) to 1 % (measured 0.24 %).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import pfeie as pf
from pfeie.dynamics import Newmark

ROCK = pf.Elastic(E=1e9, nu=0.25, rho=2000.0)


@pytest.mark.parametrize("dim", [2, 3])
def test_shear_column_frequencies(dim: int) -> None:
    H, ne = 30.0, 30
    h = H / ne
    if dim == 2:
        mesh = pf.rectangle(h, H, 1, ne, cell="quad")
        base, lateral = "ymin", [1]
    else:
        mesh = pf.box(h, h, H, 1, 1, ne, cell="hexahedron")
        base, lateral = "zmin", [1, 2]
    model = pf.Model(mesh, [pf.Block("all", ROCK)])
    model.fix(base)
    model.fix(np.arange(mesh.n_points), lateral)
    res = pf.modal(model, 3)
    cs = ROCK.wave_speeds()[1]
    n = np.arange(1, 4)
    k = (2 * n - 1) * np.pi / (2 * H)
    f_cont = (2 * n - 1) * cs / (4 * H)
    f_chain = np.sqrt(6 * cs**2 / h**2 * (1 - np.cos(k * h)) / (2 + np.cos(k * h))) / (2 * np.pi)
    np.testing.assert_allclose(res.frequencies, f_chain, rtol=1e-12)
    err = res.frequencies / f_cont - 1
    np.testing.assert_allclose(err, (k * h) ** 2 / 24, rtol=5e-3)
    # the modal masses of shear-column modes sum towards the free mass
    assert res.effective_mass[:, 0].sum() < model.total_mass()


def euler_bernoulli(n_modes: int) -> np.ndarray:
    """Roots β_n L of cos x cosh x = −1."""
    roots = []
    for n in range(1, n_modes + 1):
        guess = (n - 0.5) * np.pi
        roots.append(brentq(lambda x: np.cos(x) * np.cosh(x) + 1, guess - 1.0, guess + 1.0))
    return np.array(roots)


def timoshenko_cantilever(
    L: float, h: float, mat: pf.Elastic, f_guess: np.ndarray, kappa: float = 5 / 6
) -> np.ndarray:
    """The bending frequencies (Hz) of a Timoshenko cantilever of length L and a
    rectangular section of depth h (per unit width; EI/(κGA) and I/A do not depend on
    the width), one near each guess: the roots of the free end's conditions on the
    transfer matrix of y = (w, w', ψ, ψ'), y' = A(ω) y, from the clamped end (w = ψ = 0):
        w'' = ψ' − ρω²/(κG) w,   ψ'' = −κGA/(EI) (w' − ψ) − ρω²/E ψ."""
    from scipy.linalg import expm

    E, rho = mat.E, mat.rho
    G, area, inertia = E / (2 * (1 + mat.nu)), h, h**3 / 12
    c = kappa * G * area / (E * inertia)

    def end(f: float) -> float:
        w2 = (2 * np.pi * f) ** 2
        A = np.array([[0.0, 1.0, 0.0, 0.0], [-rho * w2 / (kappa * G), 0.0, 0.0, 1.0],
                      [0.0, 0.0, 0.0, 1.0], [0.0, -c, c - rho * w2 / E, 0.0]])  # fmt: skip
        Y = expm(A * L)[:, [1, 3]]  # from w'(0) = 1 and from ψ'(0) = 1
        return float(np.linalg.det(np.array([Y[3], Y[1] - Y[2]])))  # ψ' = 0, w' − ψ = 0

    out = []
    for fg in f_guess:  # the Timoshenko root lies a little below Euler-Bernoulli's
        fs = np.linspace(0.9 * fg, 1.02 * fg, 121)
        d = np.array([end(f) for f in fs])
        k = int(np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0])
        out.append(brentq(end, fs[k], fs[k + 1], xtol=1e-14, rtol=1e-15))
    return np.array(out)


@pytest.mark.parametrize("dim", [2, 3])
def test_cantilever_frequencies(dim: int) -> None:
    L, h = 10.0, 0.5
    mat = pf.Elastic(E=30e9, nu=0.0, rho=2500.0)
    if dim == 2:
        mesh = pf.rectangle(L, h, 40, 4, cell="quad8")
        model = pf.Model(mesh, [pf.Block("all", mat)], plane="stress")
        n_modes, pick = 2, [0, 1]
    else:
        mesh = pf.box(L, h, h, 20, 2, 2, cell="tetra10")
        model = pf.Model(mesh, [pf.Block("all", mat)])
        n_modes, pick = 4, [0, 2]  # two bending directions share each frequency
    model.fix("xmin")
    f = pf.modal(model, n_modes).frequencies
    bl = euler_bernoulli(2)
    inertia, area = h**3 / 12, h  # per unit thickness in 2D; × h in 3D cancels
    f_eb = bl**2 / (2 * np.pi * L**2) * np.sqrt(mat.E * inertia / (mat.rho * area))
    f_t = timoshenko_cantilever(L, h, mat, f_eb)
    np.testing.assert_allclose(f_t / f_eb - 1, [-1.64112e-3, -1.12723e-2], rtol=1e-4)
    tol = (5e-5, 5e-4) if dim == 2 else (1e-3, 5e-3)
    assert f[pick[0]] == pytest.approx(f_t[0], rel=tol[0])
    assert f[pick[1]] == pytest.approx(f_t[1], rel=tol[1])
    if dim == 3:
        assert f[1] == pytest.approx(f[0], rel=5e-4)


@pytest.mark.parametrize("dim", [2, 3])
def test_pulse_arrives_at_l_over_c(dim: int) -> None:
    """2D: P-wave (lateral displacement fixed). 3D: S-wave (vertical and y fixed)."""
    h, n_el, n_receiver = 1.0, 120, 80  # receiver 80 elements below the loaded end
    Lt = h * n_el
    cp, cs = ROCK.wave_speeds()
    if dim == 2:
        mesh = pf.rectangle(h, Lt, 1, n_el, cell="quad")
        c, top, base, free, fixed = cp, "ymax", "ymin", 1, [0]
    else:
        mesh = pf.box(h, h, Lt, 1, 1, n_el, cell="hexahedron")
        c, top, base, free, fixed = cs, "zmax", "zmin", 0, [1, 2]
    model = pf.Model(mesh, [pf.Block("all", ROCK)])
    model.fix(base)
    model.fix(np.arange(mesh.n_points), fixed)
    td, sigma = 20 * h / c, 1e5
    direction = np.zeros(dim)
    direction[free] = -1.0
    model.add_traction(top, sigma * direction,
                       amplitude=lambda t: np.sin(np.pi * t / td) if t < td else 0.0)  # fmt: skip
    system = model.system()
    depth = Lt - n_receiver * h
    receiver = model.nearest_node([0.0] * (dim - 1) + [depth])
    dof = int(np.searchsorted(system.free, receiver * dim + free))
    dt = 0.25 * h / c
    nm = Newmark(system, dt=dt)
    hist = nm.run(int(1.4 * n_receiver * h / c / dt), record=[dof])
    v = -hist.v[:, 0]
    arrival = hist.t[np.argmax(v)] - td / 2
    assert arrival == pytest.approx(n_receiver * h / c, abs=2 * h / c)
    assert v.max() == pytest.approx(sigma / (ROCK.rho * c), rel=1e-2)


def test_modes_of_a_rigid_block_on_joint_springs() -> None:
    """A (nearly) rigid 1 m block (2400 kg) on a joint with k_n = k_s = 1e9 Pa/m, modal
    analysis with bonded interfaces: vertical mode √(k_n A/m)/2π = 102.734 Hz; the
    horizontal-rocking pair from the 2 × 2 rigid-body problem about the base centre
    (mass [[m, m h], [m h, I_base]], stiffness diag(k_s A, Σ k_n A_i x_i²)), to 1e-5
    (measured 2.6e-6: the block, E = 1e14 Pa, is not quite rigid); the vertical mode's
    effective mass is m to 2e-11 (measured 2.2e-12)."""
    import scipy.linalg as sla

    from pfeie.verification._models import block_on_base

    model = block_on_base(joint=pf.Joint(phi=30.0, kn=1e9, ks=1e9), E=1e14, n=4,
                          gravity=False)  # fmt: skip
    res = pf.modal(model, 3)
    m, h = 2400.0, 0.5
    P = model.pairs
    assert P is not None
    x = model.mesh.points[P.node_a, 0] - 0.5
    Mr = np.array([[m, m * h], [m * h, m / 6 + m * h * h]])
    Kr = np.diag([1e9 * P.area.sum(), float((1e9 * P.area * x**2).sum())])
    f_hr = np.sqrt(sla.eigh(Kr, Mr, eigvals_only=True)) / (2 * np.pi)
    ref = np.sort([*f_hr, np.sqrt(1e9 * P.area.sum() / m) / (2 * np.pi)])
    assert np.allclose(res.frequencies, ref, rtol=1e-5)
    assert res.effective_mass[1, 1] == pytest.approx(m, rel=2e-11)  # the vertical mode


def test_modal_options_are_checked() -> None:
    """Errors for unsupported options; with free interfaces the block floats: its rigid
    modes are below 5e-5 of the lowest bonded frequency (measured 6.0e-6)."""
    from pfeie.errors import SolverError
    from pfeie.verification._models import block_on_base

    model = block_on_base(joint=pf.Joint(phi=30.0, kn=1e9), gravity=False)
    with pytest.raises(SolverError, match="both stiffnesses"):
        pf.modal(model, 2)
    with pytest.raises(SolverError, match="bonded"):
        pf.modal(model, 2, interfaces="glued")
    free = pf.modal(model, 3, interfaces="free").frequencies  # the block floats
    assert (
        free.max()
        < 5e-5 * pf.modal(block_on_base(joint=pf.Joint(phi=30.0), gravity=False), 1).frequencies[0]
    )
