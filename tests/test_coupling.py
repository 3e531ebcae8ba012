"""The coupling layer: the storage strategies of the Delassus operator agree with each
other and with its definition, and one factorised analysis serves many records with the
same bits as separate analyses."""

from __future__ import annotations

import numpy as np
import pytest

import pfeie as pf
from pfeie.coupling import PairOperator, delassus
from pfeie.linalg import factorize
from pfeie.verification._models import block_on_base


def _two_joint_model() -> pf.Model:
    """A 20 m × 12 m section: a fixed rock block, a bonded base joint and a lift joint."""
    mesh = pf.rectangle(20.0, 12.0, 20, 12)
    mesh.add_cell_group("rock", lambda x: x[:, 1] < 4)
    mesh.add_cell_group("dam", lambda x: x[:, 1] > 4)
    mesh.add_facet_group("base", lambda x: np.abs(x[:, 1] - 4) < 1e-6, boundary_only=False)
    mesh.add_facet_group("lift", lambda x: np.abs(x[:, 1] - 8) < 1e-6, boundary_only=False)
    mat = pf.Elastic(25e9, 0.2, 2400.0)
    joints = [
        pf.Interface("base", pf.Joint(c=5e4, phi=45.0, tensile=2e4, initial="intact")),
        pf.Interface("lift", pf.Joint(c=3e4, phi=40.0, tensile=1e4, initial="intact")),
    ]
    model = pf.Model(mesh, [pf.Block("rock", mat), pf.Block("dam", mat)], interfaces=joints)
    model.fix("ymin")
    model.add_gravity()
    return model


def test_delassus_strategies_agree_with_the_definition() -> None:
    """W = G K̂⁻¹ Gᵀ from its definition (a dense inverse of the small K̂) equals the dense,
    matrix-free and per-joint storages to 1e-12 relative (measured 2e-14 to 7e-14), as do
    W X and the corrector K̂⁻¹ Gᵀ X."""
    model = _two_joint_model()
    an = pf.Dynamic(model, 0.01)
    op: PairOperator = an.op
    Khat = an.ga.S.toarray()  # type: ignore[union-attr]
    G = op.G.toarray()
    W_def = G @ np.linalg.solve(Khat, G.T)
    parts = np.repeat(model.pairs.interface, model.dim)  # type: ignore[union-attr]
    X = np.random.default_rng(1).standard_normal(G.shape[0])
    du_def = np.linalg.solve(Khat, G.T @ X)
    scale = np.abs(W_def).max()
    for strategy in ("dense", "matrix-free", "blocks"):
        D = delassus(an.factor, op.G, strategy=strategy, parts=parts)  # type: ignore[arg-type]
        assert np.abs(D.matrix() - W_def).max() < 1e-12 * scale, strategy
        assert np.abs(D.apply(X) - W_def @ X).max() < 1e-12 * np.abs(W_def @ X).max()
        assert np.abs(D.correct(X) - du_def).max() < 1e-12 * np.abs(du_def).max()
    with pytest.raises(pf.ModelError, match="needs the joint of each component"):
        delassus(factorize(an.ga.S), op.G, strategy="blocks")  # type: ignore[union-attr]


def test_one_analysis_runs_many_records() -> None:
    """Two records through one factorised analysis give bit for bit the histories of two
    separate analyses: nothing of a run leaks into the next (the interface solver's and
    the projection's caches hold only functions of the pair states)."""
    model = _two_joint_model()
    static = pf.solve_static(model)
    top = [model.nearest_node([10.0, 12.0])]
    records = [pf.GroundMotion.from_function(lambda t, f=f: 30.0 * np.sin(2 * np.pi * f * t),
                                             1.0, 0.01) for f in (2.0, 3.5)]  # fmt: skip
    shared = pf.Dynamic(model, 0.01)
    together = [shared.run(1.0, ground=[r], start=static, probes=top) for r in records]
    apart = [pf.Dynamic(model, 0.01).run(1.0, ground=[r], start=static, probes=top)
             for r in records]  # fmt: skip
    for a, b in zip(together, apart, strict=True):
        assert np.array_equal(a.probe_u, b.probe_u) and np.array_equal(a.X, b.X)
    assert not np.array_equal(together[0].probe_u, together[1].probe_u)
    assert together[1].final is not None and together[1].final.pairs.broken.any()


def test_settings_are_validated_and_typed() -> None:
    """Options of the Python API go through DynamicSettings: a misspelt or out-of-range
    option is a ModelError naming it; HHT's α sets β and γ, and selects the Newmark
    family, which runs models without interfaces only."""
    model = _two_joint_model()
    with pytest.raises(pf.ModelError, match="alpa"):
        pf.Dynamic(model, 0.01, alpa=-0.1)
    with pytest.raises(pf.ModelError, match="dt"):
        pf.Dynamic(model, -0.01)
    assert pf.DynamicSettings(alpha=-0.1).newmark()[:2] == pytest.approx((0.3025, 0.6),
                                                                         rel=1e-15)  # fmt: skip
    with pytest.raises(pf.ModelError, match="without interfaces"):
        pf.Dynamic(model, 0.01, alpha=-0.1)


def test_static_pins_avoid_the_pairs() -> None:
    """A one-cell block resting on a joint (half of its nodes on the pairs): the temporary
    pins of the static problem must not fall on pair nodes, else the pinned component
    looks prescribed to the interface solver and the joint slips in statics. The static
    state is then symmetric (the two top nodes move ±u_x by the Poisson effect, to 5e-14
    relative; measured 5e-15) and a dynamic run without excitation keeps it exactly (drift
    below 1e-15 m; measured 4e-19 m; before the fix the block sheared by 6.6e-7 m in
    statics and moved 3.6e-7 m in the first steps)."""
    model = block_on_base(joint=pf.Joint(phi=30.0), n=1, E=1e9, rho=1000.0)  # one cell each
    static = pf.solve_static(model)
    top = model.block_nodes("block")
    up = top[model.mesh.points[top, 1] > 0.5]
    ux = static.u[up, 0]
    assert abs(ux.sum()) <= 5e-14 * np.abs(ux).max() and np.abs(ux).max() > 1e-7
    assert static.pairs is not None and np.abs(static.pairs.w).max() < 1e-18
    res = pf.Dynamic(model, 0.01).run(0.1, start=static)
    assert np.abs(res.rigid[:, 1, :2] - res.rigid[0, 1, :2]).max() < 1e-15


def test_inactive_pairs_take_no_part() -> None:
    """Two pairs whose normals are coupled (W_nn' = −0.9): the second is marked inactive
    (its gap predicted open), so it stays open and carries nothing, although the first
    pair's force pulls it closed through the coupling; the first closes with
    X_n = 1 (w_n = −1 + 1·X_n = 0), exactly. Without the sub-problem the inactive pair
    closed and carried 4.47."""
    import scipy.sparse as sp

    from pfeie.coupling import GatheredDelassus, InterfaceStep, PairOperator
    from pfeie.interface import OPEN, PairLaws

    laws = PairLaws.from_interfaces(np.ones(2), np.array([0, 0]), [pf.Joint(phi=30.0)], 2)
    W = np.array([[1.0, 0, 0, 0], [0, 1, 0, -0.9], [0, 0, 1, 0], [0, -0.9, 0, 1.0]])
    op = PairOperator(sp.identity(4, format="csr"), sp.csr_matrix((4, 0)), 2, 2, None, 4,
                      np.arange(4), np.zeros(0, dtype=np.int64))  # fmt: skip
    step = InterfaceStep(op, GatheredDelassus(W, lambda X: np.asarray(W @ X)), laws, 1.0)
    prev = laws.initial_state(2)
    prev.state[1] = OPEN
    sol = step.solve(np.array([0.0, -1.0, 0.0, -0.05]), np.zeros(4), prev,
                     inactive=np.array([False, True]))  # fmt: skip
    assert sol.pairs.state[1] == OPEN and not sol.pairs.X[1].any()
    assert sol.pairs.X[0, 1] == pytest.approx(1.0, abs=1e-12)
    assert sol.pairs.w[1, 1] == pytest.approx(-0.05 - 0.9, abs=1e-12)  # free + coupling
