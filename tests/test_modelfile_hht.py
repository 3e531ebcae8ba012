"""HHT-α through the model file: ``analysis.alpha = -0.1`` runs HHT-α, not a Newmark rule
with α bolted on.

The defect this guards against: the model-file schema used to default ``beta = 0.25`` and
``gamma = 0.5``, overriding HHT's β = (1 − α)²/4, γ = (1 − 2α)/2; with α = −0.1 that
scheme is only first order (HHT needs γ = 1/2 − α) and, undamped, it grows: its spectral
radius is 1.011 at ωΔt = 0.5 and 1.054 at ωΔt = 2 (asserted > 1 below).

References, computed here independently of pfeie's integrator:

- (a) the exact response of the discrete (space-discretised) system: a block released
  under its own weight from rest at u = 0, M ü + K u = f (constant f, lumped M), is
  u(t) = Σᵢ φᵢ (φᵢᵀ f / ωᵢ²)(1 − cos ωᵢ t) over the mass-normalised modes of
  K φ = ω² M φ (scipy.linalg.eigh on pfeie's assembled K, M);
- (b) the amplification matrix of HHT-α for u'' + ω² u = 0 (Hilber, Hughes & Taylor,
  "Improved numerical dissipation for time integration algorithms in structural
  dynamics", Earthquake Eng. Struct. Dyn. 5 (1977) 283–292; Hughes, The Finite Element
  Method, 2000, §9.3): (u, Δt v, Δt² a)_{n+1} = A(Ω) (u, Δt v, Δt² a)_n with Ω = ωΔt,
  built from the scheme's definition and its eigenvalues taken numerically. Its
  principal pair λ = ρ e^{±iΩ̄} gives the numerical dissipation: the amplitude is
  multiplied by ρ per step, ρ^{2π/Ω̄} per cycle; the algorithmic damping ratio is
  ξ̄ = −ln ρ / Ω̄.

Measured (the same through the model file, pfeie.Dynamic and pfeie.Newmark): observed
orders 2.017 and 2.005 for Δt = T₁/320, T₁/640, T₁/1280 (relative error 3.0e-4 at the
finest); ξ̄ measured against ξ̄ of A(Ω) to ≤ 8.1e-13 relative and ρ to ≤ 1.2e-15, at
Ω = 0.5, 1, 2, 4. Tolerances: order ≥ 1.9, error < 1e-3, ξ̄ to 5e-12, ρ to 1e-14.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

import pfeie as pf
from pfeie._job import dynamic_analysis
from pfeie.io import load_job, read_mesh

ALPHA = -0.1
E, NU, RHO = 1.0e6, 0.2, 1000.0


def write_msh(path: Path, nx: int, ny: int) -> None:
    """A unit square of nx × ny 4-node quads (gmsh MSH 2.2): physical groups 'block'
    (the cells), 'bottom' and 'top' (the edges)."""
    xs, ys = np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 1.0, ny + 1)

    def nid(i: int, j: int) -> int:
        return j * (nx + 1) + i + 1

    nodes = [f"{nid(i, j)} {float(x)!r} {float(y)!r} 0" for j, y in enumerate(ys)
             for i, x in enumerate(xs)]  # fmt: skip
    els = [f"1 2 1 1 {nid(i, 0)} {nid(i + 1, 0)}" for i in range(nx)]
    els += [f"1 2 2 2 {nid(i + 1, ny)} {nid(i, ny)}" for i in range(nx)]
    els += [f"3 2 3 3 {nid(i, j)} {nid(i + 1, j)} {nid(i + 1, j + 1)} {nid(i, j + 1)}"
            for j in range(ny) for i in range(nx)]  # fmt: skip
    path.write_text(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"bottom\"\n"
        "1 2 \"top\"\n2 3 \"block\"\n$EndPhysicalNames\n"
        f"$Nodes\n{len(nodes)}\n" + "\n".join(nodes) + "\n$EndNodes\n"
        f"$Elements\n{len(els)}\n" + "\n".join(f"{k + 1} {e}" for k, e in enumerate(els))
        + "\n$EndElements\n"
    )  # fmt: skip


MODEL = """
title = "a block released under its own weight"
[mesh]
file = "block.msh"
[materials.m]
E = {E}
nu = {nu}
rho = {rho}
[blocks]
block = "m"
[[supports]]
group = "bottom"
{rollers}
[analysis]
static = false          # gravity applied at t = 0 on the block at rest: a load step
dt = {dt!r}
duration = {T!r}
alpha = {alpha}         # HHT-α: beta and gamma follow
[output]
folder = "out"
paraview = false
probes = {{ top = [1.0, 1.0] }}
"""

ROLLERS = '[[supports]]\ngroup = "top"\ncomponents = ["x"]'


def model_file(tmp: Path, dt: float, T: float, *, nu: float = NU, rollers: bool = False) -> Path:
    p = tmp / "block.toml"
    p.write_text(MODEL.format(E=E, nu=nu, rho=RHO, rollers=ROLLERS if rollers else "", dt=float(dt),
                              T=float(T), alpha=ALPHA))  # fmt: skip
    return p


def run_model_file(p: Path) -> tuple[np.ndarray, np.ndarray, pf.Model, int]:
    """The model-file path: load_job, then the job's dynamic analysis exactly as run_job
    builds it (:func:`pfeie._job.dynamic_analysis`), over job.n_steps."""
    job = load_job(p)
    an = dynamic_analysis(job)
    assert (an.nm.beta, an.nm.gamma, an.nm.alpha) == pytest.approx((0.3025, 0.6, ALPHA))
    node = job.probes["top"]
    res = an.run(n_steps=job.n_steps, probes=[node])
    assert res.completed and res.t[-1] == pytest.approx(job.duration)
    return res.t, res.probe_u[:, 0, 1], job.model, node


def discrete_system(model: pf.Model, node: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Modes of the free DOFs (ω, mass-normalised φ), the load f and the probe's DOF."""
    s = model.system(lumped_mass=True)
    w2, phi = sla.eigh(s.K.toarray(), s.M.toarray())
    k = int(np.flatnonzero(s.free == node * model.dim + 1)[0])
    return np.sqrt(w2), phi, s.load(0.0), k


def exact(model: pf.Model, node: int, t: np.ndarray) -> np.ndarray:
    """u_y(t) at the probe: released from rest at u = 0 under the constant load f."""
    w, phi, f, k = discrete_system(model, node)
    q = phi.T @ f / w**2
    return (phi[k] * q) @ (1.0 - np.cos(np.outer(w, t)))


def amplification(Om: float, alpha: float, beta: float | None = None,
                  gamma: float | None = None) -> np.ndarray:  # fmt: skip
    """HHT-α for u'' + ω²u = 0 with Δt = 1, ω = Ω (Hilber, Hughes & Taylor 1977):

        a_{n+1} + (1 + α) Ω² u_{n+1} − α Ω² u_n = 0,
        u_{n+1} = u_n + v_n + (½ − β) a_n + β a_{n+1},  v_{n+1} = v_n + (1 − γ) a_n + γ a_{n+1},

    β = (1 − α)²/4, γ = (1 − 2α)/2 unless given."""
    beta = (1 - alpha) ** 2 / 4 if beta is None else beta
    gamma = (1 - 2 * alpha) / 2 if gamma is None else gamma
    w2 = Om**2
    lhs = np.array([[1.0, 0.0, -beta], [0.0, 1.0, -gamma], [(1 + alpha) * w2, 0.0, 1.0]])
    rhs = np.array([[1.0, 1.0, 0.5 - beta], [0.0, 1.0, 1.0 - gamma], [alpha * w2, 0.0, 0.0]])
    return np.linalg.solve(lhs, rhs)


def principal(A: np.ndarray) -> tuple[float, float]:
    """(ρ, Ω̄) of the complex pair of eigenvalues of A."""
    ev = np.linalg.eigvals(A)
    lam = ev[np.argmax(np.abs(ev.imag))]
    return float(abs(lam)), float(abs(np.angle(lam)))


def fitted(d: np.ndarray, skip: int = 20) -> tuple[float, float]:
    """(ρ, Ω̄) of a sampled free oscillation d_n = Re(c λⁿ): the least-squares fit of
    d_{n+1} = 2ρ cos Ω̄ d_n − ρ² d_{n−1} after ``skip`` steps (the spurious root of the
    scheme, |λ₃| < 0.08 here, is then below round-off)."""
    A = np.c_[d[skip + 1 : -1], d[skip:-2]]
    c, *_ = np.linalg.lstsq(A, d[skip + 2 :], rcond=None)
    rho = float(np.sqrt(-c[1]))
    return rho, float(np.arccos(c[0] / (2 * rho)))


def orders(errs: list[float]) -> np.ndarray:
    e = np.asarray(errs)
    return np.log2(e[:-1] / e[1:])


# -- (a) order of accuracy -----------------------------------------------------------------
def order_study(tmp: Path, run) -> tuple[list[float], np.ndarray]:  # type: ignore[no-untyped-def]
    """Relative max error of the probe history over two fundamental periods at
    Δt = T₁/320, T₁/640, T₁/1280 (ω_max Δt ≤ 0.18: all 18 modes resolved)."""
    write_msh(tmp / "block.msh", 2, 3)
    probe = model_file(tmp, 1e-3, 1e-3)
    _, _, model, node = run_model_file(probe)
    w, *_ = discrete_system(model, node)
    T1 = 2 * np.pi / w[0]
    errs = []
    for n in (320, 640, 1280):
        t, u, model, node = run(tmp, T1 / n, 2 * T1)
        ref = exact(model, node, t)
        errs.append(float(np.abs(u - ref).max() / np.abs(ref).max()))
    return errs, w


def test_hht_order_through_the_model_file(tmp_path: Path) -> None:
    """A 2 × 3 quad block (ν = 0.2, 18 free DOFs, several modes excited) released under
    its own weight: the probe history converges to the discrete system's exact response
    at second order (observed ≥ 1.9; achieved 2.017, 2.005), error 3.0e-4 at T₁/1280
    (asserted < 1e-3)."""

    def run(tmp: Path, dt: float, T: float):  # type: ignore[no-untyped-def]
        return run_model_file(model_file(tmp, dt, T))

    errs, _ = order_study(tmp_path, run)
    assert np.all(orders(errs) >= 1.9), (errs, orders(errs))
    assert errs[-1] < 1e-3, errs


# -- (b) numerical dissipation -------------------------------------------------------------
OMEGAS = (0.5, 1.0, 2.0, 4.0)


def dissipation_study(tmp: Path, run) -> list[tuple[float, float, float, float, float]]:  # type: ignore[no-untyped-def]
    """One quad (ν = 0, the top on rollers, lumped mass): the free DOFs are the two top
    nodes' u_y, whose symmetric and antisymmetric modes have the same ω, so the response
    is one oscillation about the static position. For each Ω = ωΔt: (Ω, ρ measured, ρ of
    A(Ω), ξ̄ measured, ξ̄ of A(Ω)), over 400 steps."""
    write_msh(tmp / "block.msh", 1, 1)
    _, _, model, node = run_model_file(model_file(tmp, 1e-3, 1e-3, nu=0.0, rollers=True))
    w, _, f, k = discrete_system(model, node)
    assert w.size == 2 and w[1] == pytest.approx(w[0], rel=1e-12)  # one frequency
    s = model.system(lumped_mass=True)
    u_static = np.linalg.solve(s.K.toarray(), f)[k]
    out = []
    for Om in OMEGAS:
        dt = Om / w[0]
        _, u, model, node = run(tmp, dt, 400 * dt)
        rho, Ombar = fitted(u - u_static)
        rho_t, Ombar_t = principal(amplification(Om, ALPHA))
        out.append((Om, rho, rho_t, -np.log(rho) / Ombar, -np.log(rho_t) / Ombar_t))
    return out


def test_hht_dissipation_through_the_model_file(tmp_path: Path) -> None:
    """The measured amplitude decay per step ρ and algorithmic damping ratio ξ̄ equal the
    HHT-α amplification matrix's: |ρ − ρ(A)| < 1e-14 (achieved ≤ 1.2e-15) and ξ̄ to 5e-12
    relative (achieved ≤ 8.1e-13), at Ω = 0.5 … 4 (per cycle the amplitude falls by
    0.7 % at Ω = 0.5, 27 % at Ω = 4). The scheme of the old defaults (β = 1/4, γ = 1/2
    with α = −0.1) would grow instead: ρ > 1."""

    def run(tmp: Path, dt: float, T: float):  # type: ignore[no-untyped-def]
        return run_model_file(model_file(tmp, dt, T, nu=0.0, rollers=True))

    for Om, rho, rho_t, xi, xi_t in dissipation_study(tmp_path, run):
        assert abs(rho - rho_t) < 1e-14, (Om, rho, rho_t)
        assert xi == pytest.approx(xi_t, rel=5e-12), (Om, xi, xi_t)
        assert rho < 1.0
        per_cycle = rho_t ** (2 * np.pi / principal(amplification(Om, ALPHA))[1])
        assert 0.0 < 1.0 - per_cycle < 0.3
        assert max(abs(np.linalg.eigvals(amplification(Om, ALPHA, 0.25, 0.5)))) > 1.0
    # the closed form's limit checks the matrix: ρ∞ = (1 + α)/(1 − α) (HHT 1977)
    assert principal(amplification(1e6, ALPHA))[0] == pytest.approx((1 + ALPHA) / (1 - ALPHA),
                                                                     rel=1e-6)  # fmt: skip


# -- (c) the same through the Python API -----------------------------------------------------
def python_model(tmp: Path, nu: float, rollers: bool) -> pf.Model:
    mesh = read_mesh(tmp / "block.msh")
    model = pf.Model(mesh, [pf.Block("block", pf.Elastic(E, nu, RHO))])
    model.fix("bottom")
    if rollers:
        model.fix("top", [0])
    model.add_gravity()
    return model


def run_dynamic(tmp: Path, dt: float, T: float, nu: float = NU, rollers: bool = False):  # type: ignore[no-untyped-def]
    """pfeie.Dynamic with alpha = −0.1 (β, γ left to their defaults)."""
    model = python_model(tmp, nu, rollers)
    node = model.nearest_node([1.0, 1.0])
    res = pf.Dynamic(model, dt, alpha=ALPHA).run(T, probes=[node])
    return res.t, res.probe_u[:, 0, 1], model, node


def run_newmark(tmp: Path, dt: float, T: float, nu: float = NU, rollers: bool = False):  # type: ignore[no-untyped-def]
    """pfeie.Newmark with alpha = −0.1 on the model's system (lumped mass)."""
    model = python_model(tmp, nu, rollers)
    node = model.nearest_node([1.0, 1.0])
    s = model.system(lumped_mass=True)
    nm = pf.Newmark(s, dt, alpha=ALPHA)
    k = int(np.flatnonzero(s.free == node * model.dim + 1)[0])
    h = nm.run(round(T / dt), nm.initial_state(), record=[k])
    return h.t, h.u[:, 0], model, node


@pytest.mark.parametrize("run", [run_dynamic, run_newmark], ids=["Dynamic", "Newmark"])
def test_hht_through_the_python_api(tmp_path: Path, run) -> None:  # type: ignore[no-untyped-def]
    """The same order (≥ 1.9) and dissipation (ξ̄ to 5e-12 relative) through pfeie.Dynamic
    and pfeie.Newmark with alpha = −0.1, and the same history as the model file to
    round-off (1e-12 of the motion)."""
    errs, _ = order_study(tmp_path, run)
    assert np.all(orders(errs) >= 1.9), (errs, orders(errs))
    assert errs[-1] < 1e-3

    def rollers(tmp: Path, dt: float, T: float):  # type: ignore[no-untyped-def]
        return run(tmp, dt, T, nu=0.0, rollers=True)

    for Om, rho, rho_t, xi, xi_t in dissipation_study(tmp_path, rollers):
        assert abs(rho - rho_t) < 1e-14, (Om, rho, rho_t)
        assert xi == pytest.approx(xi_t, rel=5e-12), (Om, xi, xi_t)
    t, u, *_ = run(tmp_path, 0.01, 1.0, nu=0.0, rollers=True)
    t_f, u_f, *_ = run_model_file(model_file(tmp_path, 0.01, 1.0, nu=0.0, rollers=True))
    np.testing.assert_allclose(t, t_f, atol=1e-12)
    np.testing.assert_allclose(u, u_f, atol=1e-12 * np.abs(u_f).max())


def test_run_command_runs_hht(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                              capsys: pytest.CaptureFixture[str]) -> None:  # fmt: skip
    """``pfeie run --set analysis.alpha=-0.1`` builds the analysis with HHT's β = 0.3025,
    γ = 0.6 on a model without interfaces; on a model with a joint the Newmark family is
    refused (exit 2, naming the schemes that take interfaces)."""
    import pfeie._job as job_module
    from pfeie.cli import main
    from test_cli import SMALL, _write

    made = []
    real = job_module.Dynamic

    def spy(*args, **kw):  # type: ignore[no-untyped-def]
        an = real(*args, **kw)
        made.append((an.nm.beta, an.nm.gamma, an.nm.alpha))
        return an

    monkeypatch.setattr(job_module, "Dynamic", spy)
    joint = "[interfaces.joint]\nfriction_angle = 26.565\n"
    assert joint in SMALL
    p = _write(tmp_path, SMALL.replace(joint, ""), duration=0.05)
    assert main(["run", str(p), "--quiet", "--set", "analysis.alpha=-0.1"]) == 0
    assert made == [pytest.approx((0.3025, 0.6, -0.1))]
    capsys.readouterr()
    p = _write(tmp_path, SMALL, duration=0.05)
    assert main(["run", str(p), "--quiet", "--set", "analysis.alpha=-0.1"]) == 2
    assert "without interfaces" in capsys.readouterr().err
