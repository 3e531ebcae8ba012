"""Input checks of the Python API: wrong shapes, types and values raise the typed errors of
:mod:`pfeie.errors` with a message that names the argument and what was expected, where a
new user found them taken silently (a wrong answer) or failing deep in NumPy or SciPy
(2026-11-27). Each case states what used to happen."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp

import pfeie as pf
from pfeie.dynamics import MatrixSystem
from pfeie.errors import ModelError, PfeieError, SolverError
from pfeie.verification._models import block_on_base


def _block() -> pf.Model:
    return block_on_base(joint=pf.Joint(phi=30.0), n=2)


def _raises(fn: Callable[[], Any], error: type[PfeieError], *words: str) -> None:
    with pytest.raises(error) as info:
        fn()
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_ground_motions() -> None:
    """A two-column array given as the values was flattened into a record of interleaved
    times and accelerations, twice as long; the constructor took times that went back
    (a(0.15) = 3.75 on [0, .2, .1, .3]) and NaN accelerations, which surfaced steps later
    as a diverged interface problem. A column vector (n, 1) stays a record."""
    data = np.arange(6.0).reshape(3, 2)
    _raises(lambda: pf.GroundMotion.from_samples(data, dt=0.01), ModelError,
            "expected a 1D array of accelerations, got shape (3, 2)", "values=data[:, 1]")
    assert pf.GroundMotion.from_samples(data[:, 1:], dt=0.01).time.size == 3
    e = np.array([1.0, 0.0])
    _raises(lambda: pf.GroundMotion(np.array([0.0, 0.2, 0.1, 0.3]), np.zeros(4), e),
            ModelError, "times must increase strictly; sample 2 is at 0.1 s after 0.2 s")
    _raises(lambda: pf.GroundMotion(np.array([0.0, 0.1]), np.array([0.0, np.nan]), e),
            ModelError, "expected finite times and accelerations")
    _raises(lambda: pf.GroundMotion(np.array([0.0, 0.1]), np.zeros(2), np.array([2.0, 0.0])),
            ModelError, "expected a unit direction")


def test_initial_fields_probes_and_steps() -> None:
    """u0 and v0 of the wrong shape were raveled (a transposed v0 gave a block 0.398 and
    0.067 m/s instead of 0.920 and 0), or failed with an IndexError; probes −1 recorded the
    last node and 10⁶ an IndexError; 2.5 steps ran 2; a float as the start failed with an
    AttributeError."""
    m = _block()
    an = pf.Dynamic(m, 0.01)
    n = m.mesh.n_points
    _raises(lambda: an.initial(v0=np.zeros((2, n))), ModelError,
            f"v0: expected finite values of shape ({n}, 2)")
    _raises(lambda: an.initial(u0=np.zeros(7)), ModelError, "u0: expected finite values")
    assert an.initial(v0=np.tile([1.0, 0.0], (n, 1))).kin.v.max() == 1.0
    for probes in ([-1], [10**6], [0.5]):
        _raises(lambda p=probes: an.run(n_steps=1, probes=p), ModelError,  # type: ignore[misc]
                f"probes: expected node indices in [0, {n})")
    _raises(lambda: an.run(n_steps=2.5), ModelError, "n_steps: expected a whole number")
    assert an.run(n_steps=2.0).t.size == 3
    _raises(lambda: an.run(n_steps=1, start=3.0), ModelError,  # type: ignore[arg-type]
            "start: expected a static result")


def test_model_loads_damping_and_settings() -> None:
    """A single Block for the list failed with "'Block' object is not iterable"; a NaN
    nodal force gave NaN displacements without a word, one of the wrong dimension failed
    at the solve; a negative Rayleigh α was taken (a negative damping ratio); dt = "0.01"
    was converted where E = "30e9" was refused; 0 modes failed in ARPACK and −3 Newmark
    steps in NumPy."""
    mesh = pf.rectangle(1.0, 1.0, 1, 1)
    mat = pf.Elastic(1e9, 0.2, 2000.0)
    _raises(lambda: pf.Model(mesh, pf.Block("all", mat)), ModelError,  # type: ignore[arg-type]
            "blocks: expected a list of pfeie.Block")
    m = pf.Model(mesh, [pf.Block("all", mat)])
    m.fix("ymin")
    _raises(lambda: m.add_nodal_force([3], [np.nan, 0.0]), ModelError,
            "nodal force: expected a finite vector of 2 components (N), got [nan, 0.0]")
    _raises(lambda: m.add_nodal_force([3], [1.0, 2.0, 3.0]), ModelError,
            "expected a finite vector of 2 components")
    _raises(lambda: pf.Rayleigh(alpha=-1.0), ModelError, "Rayleigh: alpha must be a finite "
            "number >= 0")  # fmt: skip
    _raises(lambda: pf.Dynamic(m, "0.01"), ModelError, "Dynamic:")  # type: ignore[arg-type]
    _raises(lambda: pf.modal(m, 0), SolverError, "n_modes: expected a whole number of modes")
    nm = pf.Newmark(MatrixSystem(M=sp.csr_matrix([[1.0]]), K=sp.csr_matrix([[1.0]])), 0.1)
    _raises(lambda: nm.run(-3), ModelError, "n_steps: expected a whole number of steps >= 0")


def test_joints_groups_loads_and_starts() -> None:
    """A researcher's mistakes that raised bare TypeError, ValueError, AttributeError or
    IndexError, or went through silently (a 3D rock engineer's session, 2026-11-27):
    ``Joint(phi='30')`` (TypeError from a comparison), ``pairs.of('nope')``
    (``tuple.index``), ``Model(damping=0.05)`` (AttributeError at ``Dynamic``),
    ``run(every=2.5)`` (TypeError deep in NumPy), ``run(start=)`` another model's static
    state (IndexError); ``add_cell_group('g', lambda x: True)`` (the first cell alone),
    ``add_body_force(blocks=['nope'])`` (no load), ``Elastic(rho=inf)`` and a NaN node (NaN
    displacements), ``fix(value=nan)`` (a misleading mechanism)."""
    from pfeie.errors import InterfaceError, MeshError

    _raises(lambda: pf.Joint(phi="30"), ModelError, "Joint: phi: expected a finite number "
            "(degrees), got str '30'")  # fmt: skip
    _raises(lambda: pf.Joint(phi=None), ModelError, "Joint: phi", "got NoneType None")
    _raises(lambda: pf.Joint(c="1e5"), ModelError, "Joint: c: expected a finite number (Pa)")
    _raises(lambda: pf.Joint(kn=np.inf), ModelError, "Joint: kn", "or None, got float inf")
    assert pf.Joint(phi=np.float64(30.0), phi_r=None).phi == 30.0
    m = _block()
    _raises(lambda: m.pairs.of("nope"), InterfaceError, "no interface 'nope'",
            "the model's interfaces are 'joint'")
    mesh = pf.rectangle(1.0, 1.0, 2, 2)
    _raises(lambda: pf.Model(mesh, [pf.Block("b", pf.Elastic(1e9, 0.2, 2000.0),
                                             group=None)], damping=0.05),  # type: ignore[arg-type]
            ModelError, "damping: expected pfeie.Rayleigh", "got float 0.05")  # fmt: skip
    st = pf.solve_static(m)
    an = pf.Dynamic(m, 0.005)
    _raises(lambda: an.run(0.02, start=st, every=2.5), ModelError,  # type: ignore[arg-type]
            "every: expected a whole number of steps >= 1, got 2.5")  # fmt: skip
    other = pf.Model(pf.rectangle(1.0, 1.0, 2, 2), [pf.Block("all", pf.Elastic(1e9, 0.2, 2e3))])
    other.fix("ymin")
    _raises(lambda: an.run(0.02, start=pf.solve_static(other)), ModelError,
            "start: the static result is of another model (9 nodes and 0 pairs")
    _raises(lambda: pf.rectangle(1.0, 1.0, 2, 2).add_cell_group("g", lambda x: True), MeshError,
            "cell group 'g': where(x) must return one boolean per centroid, shape (4,)")
    _raises(lambda: pf.rectangle(1.0, 1.0, 2, 2).add_facet_group("f", lambda x: x[:2, 0] > 0),
            MeshError, "facet group 'f': where(x) must return one boolean per centroid")
    _raises(lambda: m.add_body_force([0.0, -1.0], blocks=["nope"]), ModelError,
            "add_body_force: blocks: no block 'nope'")  # fmt: skip
    _raises(lambda: pf.Elastic(1e9, 0.2, np.inf), ModelError, "rho must be a finite number")
    bad = pf.rectangle(1.0, 1.0, 2, 2)
    bad.points[4, 0] = np.nan
    _raises(lambda: pf.Model(bad, [pf.Block("all", pf.Elastic(1e9, 0.2, 2e3))]), MeshError,
            "1 node(s) with a coordinate that is not a finite number, the first node 4")
    _raises(lambda: other.fix("ymin", value=np.nan), ModelError,
            "fix ymin: value: expected a finite displacement (m), got nan")
