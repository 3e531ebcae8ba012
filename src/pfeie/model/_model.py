"""The model: a mesh cut into blocks, with supports and loads, and its discrete operators.

A :class:`Model` turns the physics objects of :mod:`pfeie.model._physics` into the
matrices of the semi-discrete equations of motion

    M ü + C u̇ + K u = f(t),      u = ū on prescribed DOFs,

with global DOFs numbered node-major (``dof = node · dim + component``). The operators
on the free DOFs are handed to solvers and time integrators through
:class:`LinearSystem`, which knows nothing of meshes.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .. import assembly as asm
from ..element import quadrature, reference
from ..errors import MeshError, ModelError
from ..interface import MohrCoulomb, PairGeometry, PairLaws, SplitMesh, block_pieces, split
from ..linalg import LowRankTerm, null_space
from ..mesh import Mesh
from ..typing import BoolArray, FloatArray, IntArray
from ._physics import Amplitude, Block, Interface, Load, Rayleigh, Support, VectorField
from ._plausible import implausible_gravity, implausible_silt, implausible_water, warn_implausible
from ._reservoir import Reservoir
from ._uplift import MODEL_FILE_KEYS as UPLIFT_FILE_KEYS
from ._uplift import Uplift, uplift_force

log = logging.getLogger(__name__)

#: a record whose direction has more than this share of its length along a tilted gravity
#: shakes partly along gravity (:meth:`Model.along_gravity`; sin 0.06°: a tilt of the
#: model that small is a rounding of its axes)
ALONG_GRAVITY = 1e-3

#: an uplift's joint shorter along its upstream axis than this share of its extent is
#: warned (:meth:`Model.add_uplift`: the wrong upstream axis, every pair at the heel)
UPLIFT_FLAT_SHARE = 1e-3

#: an uplift's joint whose mean plane lies more than this from level (degrees) is warned
#: (:meth:`Model.add_uplift`: a contraction joint or a steep fault)
UPLIFT_STEEP_DEG = 60.0

#: a Westergaard face group more than this share of whose wet area is level is warned
#: (:meth:`Model.add_westergaard`: a reservoir floor listed among the dam's wet faces)
WESTERGAARD_LEVEL_SHARE = 0.25

#: a facet whose normal lies within this of the vertical (degrees) counts as level there
#: (a battered upstream face, 40° from level, is a wet face: Kuo's normal form takes it)
WESTERGAARD_LEVEL_DEG = 20.0

#: an interface group whose pieces between pairs of blocks lie in planes more than this
#: apart (degrees) is warned: its sliding safety factor sums shears of several planes
JOINT_PLANES_DEG = 30.0

#: a surface or nodal load whose part on the free DOFs is at most this share of it (sums
#: of absolute nodal values) acts on supports only and is warned (round-off of the cut)
SUPPORTED_LOAD = 1e-12


@dataclass
class _CellSet:
    """The cells of one type that belong to blocks, with per-cell material data."""

    cell_type: str
    conn: IntArray
    lam: FloatArray
    mu: FloatArray
    rho: FloatArray
    block: IntArray  # index of the owning block per cell
    index: IntArray  # the cell's index among the mesh's cells of its type
    kdeg: int  # the stiffness's quadrature degree (:func:`pfeie.assembly.stiffness_degree`)


@dataclass(frozen=True)
class StressOperators:
    """The stress as a linear map of the full DOF vector u (small strains, the blocks'
    isotropic elastic laws), factored as the strain operator and the Lamé constants of
    each point:

        ε = B u,    σ_ii = λ tr ε + 2μ ε_ii,    σ_ij = μ γ_ij (i ≠ j),

    at the stiffness quadrature points of every block cell (n_q of them). ``strain`` is B,
    its rows component-major (row k · n_q + i for point i and strain component k, the
    engineering shears γ_ij = 2ε_ij): in 3D the six Voigt components of
    :data:`pfeie.assembly.VOIGT` (xx, yy, zz, yz, xz, xy), in 2D the three in-plane ones
    (xx, yy, xy), with σ_zz = λ tr ε in plane strain and 0 in plane stress (``lam`` then the
    plane-stress λ). B holds half the entries of the stress operator DB written out over the
    DOFs in plane strain (2/3 in plane stress, 0.6 on Tet10): a step's stress costs one
    sparse product of B and a few vector operations over the points, rows that the principal
    extremes read contiguously. The nodal stress of :meth:`Model.nodal_stress` is each
    cell's least-squares corner fit of its point values evaluated at its nodes, averaged
    over the cells at a node, the same weights for every component: ``fits`` holds per cell
    type its first point, its number of cells and the fit F (n_q of a cell × its nodes; the
    cell-node values of the c cells are the (c × n_q) point values times F, one dense
    product), ``gather`` (n_points × the cell-node values) the average, a quarter of the
    entries of the map written out (n_points × n_q) on Q4 and Tet10; ``cell``
    (n_q,) the cell of each point, numbered over the mesh's cells type after type in
    ``mesh.cells`` order.

    >>> import numpy as np, pfeie as pf
    >>> mesh = pf.rectangle(1.0, 1.0, 1, 1, cell="quad")
    >>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.25, 2000.0))])
    >>> u = np.zeros(model.n_dof); u[0::2] = 1e-3 * mesh.points[:, 0]  # ε_xx = 1e-3
    >>> model.stress_operators.components(u)[:, 0] / 1e6   # xx, yy, zz, yz, xz, xy (MPa)
    array([1.2, 0.4, 0.4, 0. , 0. , 0. ])
    """

    strain: sp.csr_matrix
    lam: FloatArray
    mu: FloatArray
    plane_strain: bool
    fits: tuple[tuple[int, int, FloatArray], ...]
    gather: sp.csr_matrix
    cell: IntArray

    @property
    def n_q(self) -> int:
        """The number of quadrature points."""
        return int(self.cell.size)

    @property
    def plane(self) -> bool:
        """Plane states (2D): the yz and xz components vanish."""
        return self.strain.shape[0] == 3 * self.n_q

    def components(self, u: FloatArray) -> FloatArray:
        """The Voigt stress at the quadrature points, component-major (6, n_q), Pa, of the
        full DOF vector ``u`` (rows yz and xz zero in plane states)."""
        n, plane = self.n_q, self.plane
        e = self.strain @ np.asarray(u, dtype=float)
        nd = 2 if plane else 3  # the normal components in B
        tr = e[:n] + e[n : 2 * n]
        if not plane:
            tr += e[2 * n : 3 * n]
        tr *= self.lam  # λ tr ε
        out = np.empty((6, n))
        mu2 = 2.0 * self.mu
        for k in range(nd):
            np.multiply(mu2, e[k * n : (k + 1) * n], out=out[k])
            out[k] += tr
        if plane:
            out[2] = tr if self.plane_strain else 0.0
            out[3:5] = 0.0
            np.multiply(self.mu, e[2 * n :], out=out[5])
        else:
            for k in range(3, 6):
                np.multiply(self.mu, e[k * n : (k + 1) * n], out=out[k])
        return out

    def at_points(self, u: FloatArray) -> FloatArray:
        """The Voigt stress at the quadrature points (n_q, 6), Pa, of the full DOF vector
        ``u`` (:meth:`components`, point-major)."""
        return np.ascontiguousarray(self.components(u).T)

    def nodal_components(self, components: FloatArray) -> FloatArray:
        """The nodal stress, component-major (6, n_points), Pa, of the point values
        (6, n_q) of :meth:`components`; zero at nodes of no block cell."""
        out = np.zeros((6, self.gather.shape[0]))
        rows = [0, 1, 2, 5] if self.plane else list(range(6))
        out[rows] = self.nodal_values(components[rows])
        return out

    def nodal_values(self, values: FloatArray) -> FloatArray:
        """The nodal values (k, n_points) of k fields given at the points (k, n_q), by
        the corner fit and the average of :attr:`gather` (the same linear map for every
        field: per cell type one batched dense product with its fit F, then a sparse
        product per field over contiguous rows); zero at nodes of no block cell."""
        k = values.shape[0]
        parts = []
        for q0, c, F in self.fits:
            nq, nen = F.shape
            block = values[:, q0 : q0 + c * nq].reshape(k * c, nq) @ F  # (k c, nen)
            parts.append(block.reshape(k, c * nen))
        corner = parts[0] if len(parts) == 1 else np.concatenate(parts, axis=1)
        out = np.empty((k, self.gather.shape[0]))
        for j in range(k):
            out[j] = self.gather @ corner[j]
        return out

    def at_nodes(self, point_values: FloatArray) -> FloatArray:
        """The nodal stress (n_points, 6), Pa, of the point values (n_q, 6)
        (:meth:`at_points`); zero at nodes of no block cell (and in the yz and xz columns
        of a plane model, whose point values have none)."""
        return np.ascontiguousarray(
            self.nodal_components(np.asarray(point_values, dtype=float).T).T
        )

    @cached_property
    def points(self) -> sp.csr_matrix:
        """The stress operator DB written out over the DOFs (6 n_q × n_dof; row 6 i + k
        for point i and Voigt component k), formed on first use: the same map as
        :meth:`at_points` (which does not use it)."""
        n, B = self.n_q, self.strain
        rows = [B[k * n : (k + 1) * n] for k in range(B.shape[0] // n)]
        z = sp.csr_matrix((n, B.shape[1]))
        lam, mu = sp.diags(self.lam), sp.diags(self.mu)
        if self.plane:
            xx, yy, xy = rows
            tr = lam @ (xx + yy)
            comp = [tr + 2 * mu @ xx, tr + 2 * mu @ yy, tr if self.plane_strain else z,
                    z, z, mu @ xy]  # fmt: skip
        else:
            tr = lam @ (rows[0] + rows[1] + rows[2])
            comp = [tr + 2 * mu @ rows[k] for k in range(3)] + [mu @ rows[k] for k in (3, 4, 5)]
        S = sp.vstack(comp).tocsr()
        order = (np.arange(6)[None, :] * n + np.arange(n)[:, None]).ravel()
        return sp.csr_matrix(S[order])


def _distinct_groups(names: tuple[str, ...], what: str) -> None:
    """Refuse a group named twice (its load or mass would count twice)."""
    twice = sorted({g for g in names if names.count(g) > 1})
    if twice:
        raise ModelError(f"{what}: {', '.join(repr(g) for g in twice)} given twice: its load "
                         "or mass would count twice; expected each group once")  # fmt: skip


@dataclass(frozen=True)
class LinearSystem:
    """M, C, K and loads restricted to the free DOFs, and the maps to full vectors.

    ``C`` is None for an undamped model. ``load(t)`` returns the free-DOF load vector
    f_f(t) − K_fp ū − (C_fp, M_fp terms vanish: prescribed values are constant).
    ``M_fp`` is the mass coupling the free DOFs to the prescribed ones (free × prescribed),
    None where it vanishes (a lumped mass, unless Westergaard's blocks on an inclined face
    or a finite-element reservoir reach a supported node): a moving ground acts through
    it (:class:`~pfeie.dynamics.Excitation`).
    """

    M: sp.csr_matrix
    K: sp.csr_matrix
    C: sp.csr_matrix | None
    free: IntArray
    n_dof: int
    prescribed: IntArray
    prescribed_values: FloatArray
    _patterns: FloatArray
    _amplitudes: tuple[Amplitude | None, ...]
    _constant: FloatArray
    n_pairs: int = 0  # the model's interface pairs, which these operators do not couple
    #: the low-rank part of the damping, C + U B Uᵀ (Rayleigh's ``deformation_only``)
    C_update: LowRankTerm | None = None
    M_fp: sp.csr_matrix | None = None
    #: the stiffness and the damping (None undamped) coupling the free DOFs to the
    #: prescribed ones (free × prescribed), through which a moving ground acts
    K_fp: sp.csr_matrix | None = None
    C_fp: sp.csr_matrix | None = None
    #: the stiffness and the damping among the prescribed DOFs (prescribed × prescribed):
    #: with K_fp and C_fp, the strain energy and the damping of the whole model, supports
    #: included, where the supports move (the absolute form)
    K_pp: sp.csr_matrix | None = None
    C_pp: sp.csr_matrix | None = None
    #: Rayleigh's (α, β) when ``C`` = α M + β K exactly (None otherwise): then
    #: K q + C v = K (q + β v) + α M v, one sweep of K (:meth:`elastic_and_damping`)
    rayleigh: tuple[float, float] | None = None

    @property
    def n(self) -> int:
        return int(self.free.size)

    def elastic_and_damping(self, q: FloatArray, v: FloatArray) -> FloatArray:
        """K q + (C + U B Uᵀ) v (N), the elastic and damping forces on the free DOFs; for
        Rayleigh damping as K (q + β v) + α M v + U B Uᵀ v, one product with K where
        K q + C v takes two (C has K's pattern).

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(2.0, 1.0, 2, 1)
        >>> _ = mesh.add_cell_group("all", lambda x: x[:, 0] > -1)
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(1e9, 0.2, 2400.0))],
        ...              damping=pf.Rayleigh(alpha=0.3, beta=2e-3))
        >>> m.fix("xmin")
        >>> s = m.system(lumped_mass=True)
        >>> q, v = np.linspace(0, 1e-3, s.n), np.linspace(1e-2, 0, s.n)
        >>> bool(np.allclose(s.elastic_and_damping(q, v), s.K @ q + s.C @ v, rtol=1e-13))
        True
        """
        if self.C is None:
            return np.asarray(self.K @ q)
        if self.rayleigh is None:
            out = np.asarray(self.K @ q + self.C @ v)
        else:
            alpha, beta = self.rayleigh
            out = np.asarray(self.K @ (q + beta * v))
            if alpha:
                out += alpha * (self.M @ v)
        if self.C_update is not None:
            out += self.C_update @ v
        return out

    def load(self, t: float) -> FloatArray:
        """Free-DOF load vector at time t (N)."""
        if not self._amplitudes:
            return self._constant.copy()
        amps = np.array([1.0 if a is None else float(a(t)) for a in self._amplitudes])
        return self._constant + self._patterns @ amps

    def expand(self, x_free: FloatArray, prescribed: bool = True) -> FloatArray:
        """Full DOF vector from a free-DOF vector (prescribed DOFs at their values or 0)."""
        out = np.zeros(self.n_dof) if x_free.ndim == 1 else np.zeros((self.n_dof, x_free.shape[1]))
        out[self.free] = x_free
        if prescribed and x_free.ndim == 1:
            out[self.prescribed] = self.prescribed_values
        return out


class Model:
    """Blocks of a mesh with supports and loads.

    Parameters
    ----------
    mesh: the mesh; each block names one of its cell groups.
    blocks: the blocks; every cell used must belong to exactly one block.
    plane: "strain" or "stress", the 2D hypothesis (3D: "stress" is refused).
    thickness: out-of-plane thickness in 2D (m); forces are then per this thickness.
    damping: Rayleigh damping of the whole model, or None.
    interfaces: facet groups that cut the blocks apart, each with its joint law. The mesh
        is split along them (:func:`pfeie.interface.split`); ``self.mesh`` is the split
        mesh and ``self.input_mesh`` the one given. Each connected part of the split mesh
        is a *body* with its own rigid modes.
    check_units: warn (a :class:`UserWarning` and ``logging``) of moduli, densities, joint
        strengths, friction angles and a mesh size that look like wrong units
        (:func:`pfeie.model.warn_implausible`: ``E = 30`` for 30 GPa, ``rho = 2.4`` in
        t/m³, ``c = 0.3`` in MPa, ``phi = 0.5236`` in radians, a mesh in millimetres);
        False for a model with deliberately extreme values (a rigid block of E = 3e13 Pa)
        or built by a caller that reports them itself (the model file, naming its keys).

    Example
    -------
    >>> import pfeie as pf
    >>> mesh = pf.rectangle(4.0, 1.0, 8, 2)
    >>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=1e9, nu=0.25, rho=2000))])
    >>> model.fix("xmin")
    >>> model.add_gravity()
    >>> round(float(-model.load_vector().sum() / 9.81), 6)  # total weight / g = mass, kg
    8000.0
    """

    def __init__(
        self,
        mesh: Mesh,
        blocks: Sequence[Block],
        *,
        plane: str = "strain",
        thickness: float = 1.0,
        damping: Rayleigh | None = None,
        interfaces: Sequence[Interface] = (),
        check_units: bool = True,
    ) -> None:
        if not isinstance(mesh, Mesh):
            raise ModelError(f"mesh: expected a pfeie mesh (pfeie.read_mesh('file.msh'), "
                             f"pfeie.rectangle, pfeie.box), got {type(mesh).__name__} "
                             f"{mesh!r}")  # fmt: skip
        if plane not in ("strain", "stress"):
            raise ModelError(f"plane must be 'strain' or 'stress', got {plane!r}")
        if not 1e-6 <= thickness <= 1e6:  # (a thinner one underflows the facets' normals)
            raise ModelError(f"thickness: expected a number in [1e-06, 1e+06] m, got {thickness}")
        if mesh.dim == 3 and thickness != 1.0:
            raise ModelError(f"thickness = {thickness} m is a 2D setting, but the mesh is 3D; a "
                             "3D model takes no thickness")  # fmt: skip
        if isinstance(blocks, Block) or not all(isinstance(b, Block) for b in blocks):
            raise ModelError("blocks: expected a list of pfeie.Block (e.g. [pf.Block(...)]), "
                             f"got {blocks!r}")  # fmt: skip
        if not blocks:
            raise ModelError("a model needs at least one block")
        bad = np.flatnonzero(~np.isfinite(mesh.points).all(axis=1))
        if bad.size:
            raise MeshError(f"the mesh has {bad.size} node(s) with a coordinate that is not a "
                            f"finite number, the first node {int(bad[0])} at "
                            f"{mesh.points[bad[0]].tolist()}")  # fmt: skip
        if not mesh.checked:
            # a mesh built in Python: the gmsh reader's checks (a quadratic cell whose
            # mid-side node sits past its quarter point, inverted at a corner, has a
            # positive Jacobian at its quadrature points and a wrong stiffness)
            mesh.check()
        if damping is not None and not isinstance(damping, Rayleigh):
            raise ModelError(f"damping: expected pfeie.Rayleigh(alpha, beta) (or "
                             f"Rayleigh.from_ratio(zeta, f1, f2)) or None, got "
                             f"{type(damping).__name__} {damping!r}")  # fmt: skip
        if (isinstance(interfaces, Interface) or not all(
                isinstance(i, Interface) for i in interfaces)):  # fmt: skip
            raise ModelError("interfaces: expected a list of pfeie.Interface, got "
                             f"{interfaces!r}")  # fmt: skip
        if mesh.dim == 3 and plane == "stress":
            raise ModelError("plane = 'stress' is a 2D hypothesis, but the mesh is 3D; a 3D "
                             "model takes no plane hypothesis")  # fmt: skip
        names = [b.name for b in blocks]
        if len(set(names)) != len(names):
            raise ModelError(f"block names must be unique, got {names}")
        for b in blocks:  # a selection that matched no cell (a missing group: below)
            grp = mesh.cell_groups.get(b.cell_group)
            if grp is not None and not sum(np.size(idx) for idx in grp.values()):
                raise ModelError(f"block {b.name!r}: its cell group {b.cell_group!r} holds "
                                 "no cell (a selection that matched none?); expected the "
                                 "block's cells")  # fmt: skip
        owner = _disjoint_blocks(mesh, blocks)
        if check_units:  # before the split: its errors may follow from these
            warn_implausible(mesh, blocks, interfaces, plane)
            left = sum(int((own < 0).sum()) for own in owner.values()) + sum(
                conn.shape[0] for ctype, conn in mesh.cells.items() if ctype not in owner
            )
            if left:  # (a model file says so itself, naming the mesh's groups)
                log.warning("%d cell(s) of the mesh are in no block's group and are left "
                            "out of the model (give them a pfeie.Block to include them)",
                            left)  # fmt: skip
        self._check_units = check_units
        self.input_mesh = mesh
        self.interfaces = list(interfaces)
        for itf in self.interfaces:
            _warn_unused_strength(itf)
        self.split: SplitMesh | None = None
        if self.interfaces:
            mesh = mesh.restrict([b.cell_group for b in blocks])
            names = [i.group for i in self.interfaces]
            if len(set(names)) != len(names):
                raise ModelError(f"interface groups must be unique, got {names}")
            try:
                self.split = split(mesh, names, thickness if mesh.dim == 2 else 1.0)
            except MeshError as exc:
                raise ModelError(str(exc)) from None
            mesh = self.split.mesh
        self.mesh = mesh
        self.blocks = list(blocks)
        self.plane = plane
        self.thickness = thickness if mesh.dim == 2 else 1.0
        self.damping = damping
        self.supports: list[Support] = []
        self.loads: list[Load] = []
        self.reservoirs: list[tuple[tuple[str, ...], float, float, float]] = []
        # Westergaard's nodal blocks for the reservoirs they were computed for
        self._westergaard_cache: tuple[tuple[Any, ...], FloatArray] | None = None
        self.fe_reservoirs: list[Reservoir] = []
        self.uplifts: list[Uplift] = []
        self._warned: set[int] = set()  # the loads warned of (_warn_supported_loads)
        self._cellsets = self._collect_cells()
        self._warn_hanging_nodes()
        self._warn_joint_planes()
        self._warn_bonded_across()

    # -- topology -------------------------------------------------------------------------
    @property
    def dim(self) -> int:
        return self.mesh.dim

    @property
    def n_dof(self) -> int:
        return self.mesh.n_points * self.dim

    def _collect_cells(self) -> list[_CellSet]:
        owner: dict[str, IntArray] = {
            t: np.full(c.shape[0], -1, dtype=np.int64) for t, c in self.mesh.cells.items()
        }
        for ib, blk in enumerate(self.blocks):
            try:
                grp = self.mesh.cell_group(blk.cell_group)
            except MeshError as exc:
                raise ModelError(f"block {blk.name!r}: {exc}") from None
            for ctype, idx in grp.items():
                clash = owner[ctype][idx] >= 0
                if clash.any():
                    other = self.blocks[int(owner[ctype][idx][clash][0])].name
                    raise ModelError(
                        f"block {blk.name!r} shares {int(clash.sum())} {ctype} cell(s) "
                        f"with block {other!r}; a cell belongs to one block"
                    )
                owner[ctype][idx] = ib
        lame = np.array([b.material.lame(self.dim, self.plane) for b in self.blocks])
        rho = np.array([b.material.rho for b in self.blocks])
        sets = []
        for ctype, conn in self.mesh.cells.items():
            which = owner[ctype]
            if np.any(which < 0):
                log.info("%d %s cell(s) belong to no block: ignored", (which < 0).sum(), ctype)
            keep = np.flatnonzero(which >= 0)
            if keep.size == 0:
                continue
            b = which[keep]
            kdeg = asm.stiffness_degree(
                ctype, asm.curved_cells(self.mesh.points, ctype, conn[keep])
            )
            sets.append(_CellSet(ctype, conn[keep], lame[b, 0], lame[b, 1], rho[b], b, keep,
                                 kdeg))  # fmt: skip
        return sets

    @cached_property
    def active_nodes(self) -> IntArray:
        """Nodes used by at least one block cell."""
        return np.unique(np.concatenate([s.conn.ravel() for s in self._cellsets]))

    def pair_text(self, pairs: Sequence[int], limit: int = 5) -> str:
        """Where the pairs ``pairs`` (indices of the model's pairs, as an
        :class:`~pfeie.errors.InterfaceError` names them) lie, for a message: " Pairs:
        8 on 'joints' at (1.25, 3.4) m, between 'v3' and 'v4'; …" (the first ``limit``);
        empty without pairs.

        >>> import pfeie as pf
        >>> from pfeie.verification._models import block_on_base
        >>> block_on_base(joint=pf.Joint(phi=30.0)).pair_text([1])
        " Pairs: 1 on 'joint' at (0.5, 0) m, between 'base' and 'block'."
        """
        P = self.pairs
        idx = [int(k) for k in pairs if P is not None and 0 <= int(k) < P.n][:limit]
        if P is None or not idx:
            return ""
        names, body = self.body_names(), self.body_of_node
        parts = []
        for k in idx:
            a, b = sorted((int(body[P.node_a[k]]), int(body[P.node_b[k]])))
            at = ", ".join(f"{v:.4g}" for v in P.x[k])
            parts.append(f"{k} on {P.names[int(P.interface[k])]!r} at ({at}) m, between "
                         f"{names[a]!r} and {names[b]!r}")  # fmt: skip
        return " Pairs: " + "; ".join(parts) + "."

    def _warn_joint_planes(self) -> None:
        """Warn of an interface group whose pieces (its pairs grouped by the blocks they
        join, :func:`pfeie.interface.block_pieces`) lie in planes more than
        :data:`JOINT_PLANES_DEG` apart (the joints of an arch's voussoirs, or of a wall's
        courses and head joints, in one group): its sliding safety factor, Σ capacity /
        ‖Σ T‖, adds shears that cancel between the planes (a masonry arch read FS 43.9
        with 0.001 kN of shear). The slips, openings and states are per pair and keep
        their meaning."""
        P = self.pairs
        if P is None:
            return
        body = self.body_of_node
        n = self.n_bodies
        for name in P.names:
            idx = P.of(name)
            pieces = block_pieces(body[P.node_a[idx]], body[P.node_b[idx]],
                                  [str(i) for i in range(n)])  # fmt: skip
            if len(pieces) < 2:
                continue
            normals = np.array([(P.frame[idx[k], -1] * P.area[idx[k], None]).sum(axis=0)
                                for k in pieces.values()])  # fmt: skip
            normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
            cos = np.abs(normals @ normals.T)  # (a piece's sides may be either way round)
            i, j = np.unravel_index(int(np.argmin(cos)), cos.shape)
            angle = float(np.degrees(np.arccos(min(float(cos[i, j]), 1.0))))
            if angle > JOINT_PLANES_DEG:
                names = self.body_names()
                label = [" | ".join(names[int(b)] for b in key.split(" | "))
                         for key in pieces]  # fmt: skip
                log.warning(
                    "interface %r joins %d pairs of blocks in planes up to %.0f° apart (%s "
                    "and %s): its sliding safety factor Σ capacity / ‖Σ T‖ adds shears that "
                    "cancel between the planes and means little; give each plane its own "
                    "interface group for a factor of each (its slips, openings and states "
                    "are per pair, unaffected)", name, len(pieces), angle, label[i],
                    label[j])  # fmt: skip

    def _warn_bonded_across(self) -> None:
        """Warn of an interface between two blocks that are one body: bonded to each other
        through the mesh elsewhere (faces between them that no interface names), so that
        the joint cannot open or slide as a joint between blocks, and a limit search
        finds no mechanism (a rock tester's wedge with one of its two planes an interface
        read FS > 20 and k_y > 2, silently). A crack inside one block (both sides in the
        same block) is not warned: it may end inside it."""
        P = self.pairs
        if P is None:
            return
        block = np.full(self.mesh.n_points, -1, dtype=np.int64)
        for cs in self._cellsets:
            block[cs.conn] = cs.block[:, None]
        body = self.body_of_node
        ba, bb = block[P.node_a], block[P.node_b]
        same = (body[P.node_a] == body[P.node_b]) & (ba != bb) & (ba >= 0) & (bb >= 0)
        for name in P.names:
            idx = P.of(name)
            bad = idx[same[idx]]
            if not bad.size:
                continue
            a, b = sorted({self.blocks[int(ba[bad[0]])].name, self.blocks[int(bb[bad[0]])].name})
            log.warning("interface %r: %d of its %d pairs join blocks %r and %r, which are one "
                        "body: bonded to each other through faces that no interface names. "
                        "A crack that ends in the bond is modelled so; a joint meant to "
                        "separate the blocks cannot slide while the bond holds them (a limit "
                        "search finds no mechanism through it): it needs every face between "
                        "the blocks in an interface group (a wedge's two planes, a block's "
                        "base and its release joints)", name, bad.size, idx.size, a, b)  # fmt: skip

    def _warn_hanging_nodes(self) -> None:
        """A warning where the mesh is not conforming: nodes on a cell's edge (a face, in
        3D) that are not its nodes (:meth:`pfeie.Mesh.hanging_nodes`): parts meshed
        separately at other sizes, or a linear cell beside a quadratic one. The cells do
        not share the displacement along that edge, so the coarser side hangs on the
        shared corners (a new user's block on a base meshed at another size settled 87 %
        more than on a conforming mesh) without an interface that pfeie could pair."""
        hang = self.mesh.hanging_nodes(self.active_nodes)
        if not hang.size:
            return
        block = np.full(self.mesh.n_points, -1, dtype=np.int64)
        for cs in self._cellsets:
            block[cs.conn] = cs.block[:, None]
        names = sorted({self.blocks[int(b)].name for b in block[hang] if b >= 0})
        x = self.mesh.points[hang[0]]
        log.warning("the mesh is not conforming: %d node(s) of block(s) %s lie on the edge "
                    "or face of a neighbouring cell without being one of its nodes (the "
                    "first at [%s]): parts meshed separately at other sizes, or linear cells "
                    "beside quadratic ones; the cells do not share their displacement there "
                    "and the coarser side hangs on the shared corners; expected a "
                    "conforming mesh (gmsh: fragment the geometry and mesh it as one, at "
                    "one element order)", hang.size, ", ".join(map(repr, names)),
                    ", ".join(f"{v:.6g}" for v in x))  # fmt: skip

    def unshared_coincident_nodes(self) -> list[tuple[str, str, int, FloatArray]]:
        """Nodes at the same place that no cell and no declared interface joins: cracks
        that the mesh holds but no interface declares (blocks, or the parts of one block,
        meshed separately without sharing their nodes), whose sides are not tied. One
        entry per pair of blocks: the two block names (the same twice inside one block),
        the number of node pairs and the first pair's point (m). The copies of a node made
        by splitting the mesh along the interfaces are not counted."""
        pairs = self.mesh.coincident_nodes(self.active_nodes)
        if self.split is not None and pairs.size:  # copies of one node of the mesh given
            parent = self.split.parent
            pairs = pairs[parent[pairs[:, 0]] != parent[pairs[:, 1]]]
        if not pairs.size:
            return []
        block = np.full(self.mesh.n_points, -1, dtype=np.int64)
        for cs in self._cellsets:
            block[cs.conn] = cs.block[:, None]
        names = [b.name for b in self.blocks]
        ab = np.sort(block[pairs], axis=1)
        out = []
        for key in np.unique(ab, axis=0):
            hit = np.flatnonzero((ab == key).all(axis=1))
            out.append((names[int(key[0])], names[int(key[1])], int(hit.size),
                        self.mesh.points[pairs[hit[0], 0]].copy()))  # fmt: skip
        return out

    def block_nodes(self, name: str) -> IntArray:
        """Nodes of one block."""
        ib = [b.name for b in self.blocks].index(name)
        return np.unique(np.concatenate([s.conn[s.block == ib].ravel() for s in self._cellsets]))

    def _nodes(self, where: str | Iterable[int] | IntArray, what: str) -> tuple[IntArray, str]:
        """The nodes of a group's name or of node indices, and a label; an empty group
        or list is refused (``what`` names the call in the message): a selector that
        matches nothing would otherwise drop the support or load unseen."""
        if isinstance(where, str):
            try:
                nodes = self.mesh.group_nodes(where)
            except MeshError as exc:
                raise ModelError(str(exc)) from None
            if not nodes.size:
                raise ModelError(f"{what}: the group {where!r} has no nodes (its selector "
                                 "matched nothing); expected a group with nodes")  # fmt: skip
            return nodes, where
        given: object = where
        if isinstance(given, int | np.integer) and not isinstance(given, bool):
            given = [given]  # one node
        try:
            raw = np.asarray(given if isinstance(given, np.ndarray) else list(given))  # type: ignore[call-overload]
            if raw.size and raw.dtype.kind not in "iu":  # a mask, or fractional indices
                raise TypeError
            nodes = np.unique(raw.astype(np.int64))
        except (TypeError, ValueError):
            raise ModelError(f"{what}: expected a group's name or integer node indices "
                             f"(for a mask of the nodes, np.flatnonzero(mask)), got "
                             f"{str(where)[:200]}") from None  # fmt: skip
        if not nodes.size:
            raise ModelError(f"{what}: no nodes given; expected a group's name or node "
                             "indices")  # fmt: skip
        if nodes.min() < 0 or nodes.max() >= self.mesh.n_points:
            raise ModelError(f"{what}: node indices must lie in 0..{self.mesh.n_points - 1}")
        return nodes, f"{nodes.size} node(s)"

    def nodes_at(self, where: Callable[[FloatArray], Any]) -> IntArray:
        """Indices of the nodes whose coordinates (n, dim) satisfy ``where``."""
        return np.flatnonzero(np.asarray(where(self.mesh.points), dtype=bool))

    def nearest_node(self, x: Sequence[float]) -> int:
        """Index of the node nearest to a point."""
        try:
            p = np.asarray(x, dtype=float)
        except (TypeError, ValueError):
            p = np.full(1, np.nan)
        if p.shape != (self.dim,) or not np.isfinite(p).all():
            raise ModelError(f"nearest_node: expected a point of {self.dim} finite "
                             f"coordinates (m), got {x!r}")  # fmt: skip
        d = np.linalg.norm(self.mesh.points - p, axis=1)
        return int(np.argmin(d))

    # -- supports and loads ---------------------------------------------------------------
    def _check_load(self, what: str, value: object, amplitude: object,
                    vector: bool = True) -> None:  # fmt: skip
        """Refuse a load that cannot be applied, naming it (``what``): a value that is
        neither a function of the points nor a finite vector of the model's dimension (a
        finite number for a pressure, ``vector`` False), an amplitude that is not a
        function of time."""
        if amplitude is not None and not callable(amplitude):
            raise ModelError(f"{what}: amplitude: expected a function of time t (s) -> "
                             f"factor, or None, got {type(amplitude).__name__} "
                             f"{amplitude!r}")  # fmt: skip
        if callable(value):
            return
        try:
            arr = np.asarray(value, dtype=float)
            texts = [value] if isinstance(value, str) else (
                list(value) if isinstance(value, list | tuple) else [])  # fmt: skip
            if any(isinstance(v, str) for v in texts):
                raise ValueError  # '1e3' is a string, not a number (a typo in a script)
        except (TypeError, ValueError):
            arr = np.full(1, np.nan)
        shape = (self.dim,) if vector else ()
        if arr.shape != shape or not np.isfinite(arr).all():
            want = (f"a finite vector of {self.dim} components" if vector
                    else "a finite number")  # fmt: skip
            raise ModelError(f"{what}: expected {want} or a function of the points x, got "
                             f"{value!r}")  # fmt: skip

    def fix(
        self,
        where: str | Iterable[int] | IntArray,
        components: Sequence[int] | int | None = None,
        value: float = 0.0,
    ) -> None:
        """Prescribe displacement ``value`` (m) on ``components`` (default: all) of the
        nodes of a facet or cell group, or of given node indices."""
        nodes, label = self._nodes(where, "fix")
        comps = tuple(range(self.dim)) if components is None else tuple(np.atleast_1d(components))
        if any(isinstance(c, bool) or not isinstance(c, int | np.integer) or not 0 <= c < self.dim
               for c in comps):  # fmt: skip
            shown = [c.item() if isinstance(c, np.generic) else c for c in comps]  # not np.int64(2)
            raise ModelError(f"fix {label}: components: expected integers in 0..{self.dim - 1} "
                             f"(0 = x), got {shown!r}")  # fmt: skip
        number = isinstance(value, int | float | np.integer | np.floating)
        if isinstance(value, bool) or not number or not np.isfinite(value):
            raise ModelError(f"fix {label}: value: expected a finite displacement (m), got "
                             f"{value!r}")  # fmt: skip
        comps_i = tuple(int(c) for c in comps)
        for other in self.supports:  # the same DOF held at another value: which one?
            shared = set(comps_i) & set(other.components)
            if shared and other.value != float(value) and np.intersect1d(
                    other.nodes, nodes, assume_unique=True).size:  # fmt: skip
                raise ModelError(
                    f"fix {label}: its nodes share component(s) "
                    f"{sorted('xyz'[c] for c in shared)} with the support on {other.label} "
                    f"at another value ({value!r} m against {other.value!r} m): one "
                    "displacement per DOF; expected the same value, or groups apart")  # fmt: skip
        self.supports.append(Support(nodes, comps_i, float(value), label))
        self.__dict__.pop("_dofmap", None)
        self.__dict__.pop("_free_rigid", None)

    def add_gravity(
        self,
        g: float = 9.81,
        direction: Sequence[float] | None = None,
        amplitude: Amplitude | None = None,
    ) -> None:
        """Self-weight ρ g along ``direction`` (default −y in 2D, −z in 3D)."""
        if isinstance(g, bool) or not isinstance(g, int | float | np.integer | np.floating):
            raise ModelError(f"gravity: expected an acceleration in m/s² (a number, e.g. "
                             f"9.81), got {g!r}")  # fmt: skip
        e = np.zeros(self.dim)
        e[-1] = -1.0
        if direction is not None:
            e = np.asarray(direction, dtype=float)
            big = float(np.abs(e).max()) if e.size else 0.0
            if e.shape != (self.dim,) or not (np.isfinite(big) and big > 0):
                raise ModelError(f"gravity direction: expected a finite non-zero vector of "
                                 f"{self.dim} components, got {e.tolist()}")  # fmt: skip
            e = e / big
            e = e / np.linalg.norm(e)
            if e[-1] >= 0.0:
                # the last axis is the vertical one (y in 2D, z in 3D): gravity along or
                # up it lifts every block off its base (a rock tester's wedge pulled out of
                # its V read a "factor of safety")
                log.warning("gravity: the direction %s points %s along %s, the vertical "
                            "axis (pfeie's: up is +%s); expected a downward component, as "
                            "in [0, -1] or a tilted [sin θ, -cos θ]", e.round(6).tolist(),
                            "up" if e[-1] > 0 else "level",
                            "yz"[self.dim - 2], "yz"[self.dim - 2])  # fmt: skip
        if not (np.isfinite(g) and g >= 0):
            raise ModelError(f"gravity: expected a finite acceleration >= 0 m/s², got {g}")
        if self._check_units and implausible_gravity(g) is not None:
            log.warning("gravity %s", implausible_gravity(g))
        self._check_load("gravity", 0.0, amplitude, vector=False)
        massless = [b.cell_group for b in self.blocks if not b.material.rho > 0]
        if massless and g > 0:
            log.warning("gravity: block(s) %s have no density (rho = 0, pfeie.Elastic's "
                        "default): gravity puts no load on them; give their material its "
                        "density (kg/m³)", ", ".join(repr(n) for n in massless))  # fmt: skip
        self.loads.append(Load("gravity", None, g * e, amplitude))

    def along_gravity(
        self, direction: Sequence[float] | FloatArray
    ) -> tuple[float, FloatArray] | None:
        """Where gravity is tilted (a mesh drawn in a slope's own axes) and a record's
        ``direction`` has more than :data:`ALONG_GRAVITY` of its length along it: that
        share and the direction made normal to gravity (horizontal shaking, as the yield
        coefficient and the pseudo-static loads take it); None otherwise (gravity along
        the vertical axis: a record along it is vertical shaking, meant so).

        >>> import pfeie as pf
        >>> m = pf.Model(pf.rectangle(1.0, 1.0, 1, 1), [pf.Block("all", pf.Elastic(1e9, 0.2, 1e3))])
        >>> m.add_gravity(direction=[np.sin(0.1), -np.cos(0.1)])
        >>> share, h = m.along_gravity([1.0, 0.0])
        >>> round(share, 4), [round(float(v), 4) for v in h]
        (0.0998, [0.995, 0.0998])
        """
        grav = [ld.value for ld in self.loads if ld.kind == "gravity"]
        if not grav:
            return None
        g = np.asarray(grav[-1], dtype=float)
        norm = float(np.linalg.norm(g))
        if not (np.isfinite(norm) and norm > 0) or abs(abs(g[-1]) / norm - 1.0) < 1e-12:
            return None
        g = g / norm
        e = np.asarray(direction, dtype=float)
        e = e / np.linalg.norm(e)
        along = float(e @ g)
        if abs(along) <= ALONG_GRAVITY:
            return None
        h = e - along * g
        return abs(along), h / np.linalg.norm(h)

    def warn_along_gravity(self, name: str, direction: Sequence[float] | FloatArray) -> None:
        """The warning of :meth:`along_gravity` for a record ``name`` of the Python API
        (a model file names its keys itself and builds with ``check_units=False``)."""
        found = self.along_gravity(direction) if self._check_units else None
        if found is not None:
            log.warning("ground motion %r: its direction %s has %.3g of its length along the "
                        "tilted gravity: the record shakes partly along gravity; for "
                        "horizontal shaking give direction = [%s] (made normal to gravity)",
                        name, [round(float(v), 6) for v in direction], found[0],
                        ", ".join(f"{v:.6g}" for v in found[1]))  # fmt: skip

    def add_inertia(
        self, acceleration: Sequence[float], amplitude: Amplitude | None = None
    ) -> None:
        """The inertia force of every mass of the model under a uniform field ``a``
        (m/s², a vector): f = M (1 ⊗ a) (N), M the consistent mass with the reservoirs'
        added mass (:meth:`inertia_load`). The load of a seismic coefficient: a = k_h g ι
        gives k_h times the weight turned horizontal on the blocks and Westergaard's
        hydrodynamic force on the wet faces, k_h (7/12) ρ_w g h² on a vertical face of
        depth h (USACE EM 1110-2-2100). It is evaluated with the model's mass when the
        loads are (a reservoir added later counts)."""
        a = np.asarray(acceleration, dtype=float)
        if a.shape != (self.dim,) or not np.isfinite(a).all():
            raise ModelError(f"inertia: expected a finite acceleration of {self.dim} "
                             f"components (m/s²), got {a.tolist()}")  # fmt: skip
        self.loads.append(Load("inertia", None, a, amplitude))

    def inertia_load(self, acceleration: Sequence[float] | FloatArray) -> FloatArray:
        """f = M (1 ⊗ a) on all DOFs (N): the inertia of a uniform acceleration ``a``
        (m/s², a vector) of the blocks (consistent mass: Σ_j N_j = 1, so ∫ρ N_j a dV) and
        of the reservoirs' added mass (:meth:`added_mass_matrix`)."""
        a = np.asarray(acceleration, dtype=float)
        return np.asarray(self.mass() @ np.tile(a, self.mesh.n_points))

    def add_body_force(
        self,
        value: VectorField,
        amplitude: Amplitude | None = None,
        blocks: Sequence[str] | None = None,
    ) -> None:
        """A body force density (N/m³): a vector, or a function of points (..., d); on the
        blocks named in ``blocks`` only (default: all)."""
        if blocks is not None:
            if isinstance(blocks, str):
                blocks = [blocks]
            known = [b.name for b in self.blocks]
            unknown = [b for b in blocks if b not in known]
            if unknown:
                raise ModelError(f"add_body_force: blocks: no block {unknown[0]!r}; the "
                                 f"model's blocks are {', '.join(map(repr, known))}")  # fmt: skip
        self._check_load("add_body_force", value, amplitude)
        self.loads.append(Load("body", None, value, amplitude,
                               blocks=None if blocks is None else tuple(blocks)))  # fmt: skip

    def add_traction(
        self, group: str, value: VectorField, amplitude: Amplitude | None = None
    ) -> None:
        """A traction (N/m²) on a facet group: a vector or a function of points."""
        self._boundary_group(group, "traction")
        self._check_load(f"traction on {group!r}", value, amplitude)
        self.loads.append(Load("traction", group, value, amplitude))

    def add_pressure(
        self,
        group: str,
        value: float | Callable[[FloatArray], FloatArray],
        amplitude: Amplitude | None = None,
        *,
        level: float | None = None,
    ) -> None:
        """A pressure (Pa, positive pushing into the body) on a facet group: faces on the
        boundary of the blocks, or in a joint: an interface's name puts the pressure on
        both its faces (water in the joint, pushing the blocks apart: a uniform or any
        pore pressure, where :meth:`add_uplift` is the dam guideline's heel-to-toe
        distribution), ``"<interface>:a"`` or ``":b"`` on one face (a facet group that
        also holds facets inside a block is refused: a pressure there has no side to
        push). ``value``: a number, or
        a function of the points x, an array (facets, quadrature points, d), that returns
        the pressure at each, shape x.shape[:-1]: write its coordinates x[..., k].

        ``level`` (m, on the vertical axis: y in 2D, z in 3D) declares a pressure that is
        zero above the level and a polynomial in x below it, such as the hydrostatic
        p = ρ g (h − z)⁺ with ``level`` = h. A Gauss rule on a facet the level cuts would
        integrate the kink of p inexactly (about 1e-4 of the facet's load): such facets
        are integrated on their wet part alone, the rule of the reservoirs' added mass
        (:meth:`add_westergaard`): the facet's parameter runs from its wet end to the
        point ξ* where it meets the level, through ξ = ξ* + (ξ_w − ξ*) s², so the depth
        and the shape functions are polynomials in s and Gauss points in s integrate the
        wet part exactly on straight (and, in 2D, curved) facets; in 3D the lines of the
        facet are integrated so, between splits where the level crosses its edges
        (round-off on triangles and bilinear quads). Without ``level`` every facet takes a
        Gauss rule of degree 2p + 2 (exact for a polynomial pressure of degree p + 1 on
        straight facets of degree p).

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(2.0, 10.0, 1, 3)     # nodes at y = 0, 3.33, 6.67, 10
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        >>> m.add_pressure("xmin", lambda x: 9810.0 * np.maximum(5.0 - x[..., 1], 0.0),
        ...                level=5.0)
        >>> bool(np.isclose(m.load_vector()[0::2].sum(), 9810.0 * 5.0**2 / 2, rtol=1e-14))
        True
        """
        if level is not None and not np.isfinite(level):
            raise ModelError(f"pressure on {group!r}: the level must be finite, got {level}")
        self._boundary_group(group, "pressure")
        self._check_load(f"pressure on {group!r}", value, amplitude, vector=False)
        self.loads.append(Load("pressure", group, value, amplitude,
                               level=None if level is None else float(level)))  # fmt: skip

    def add_silt(
        self,
        groups: str | Sequence[str],
        level: float,
        submerged_unit_weight: float,
        *,
        k: float | None = None,
        friction_angle: float | None = None,
        amplitude: Amplitude | None = None,
    ) -> float:
        """Silt deposited against the faces ``groups`` up to the silt surface z_s =
        ``level`` (USACE EM 1110-2-2200 §3-4, EM 1110-2-2100): a saturated cohesionless
        soil whose effective stress at depth z_s − z is geostatic,

            σ_v = γ' (z_s − z)⁺  (vertical),   σ_h = K σ_v  (horizontal),

        with γ' the ``submerged_unit_weight`` (N/m³: the saturated unit weight less the
        water's; the water's own pressure is the hydrostatic load, applied over the whole
        depth) and K the lateral coefficient: ``k`` given (e.g. the active Ka), or at rest
        K0 = 1 − sin φ from the silt's ``friction_angle`` φ (degrees; Jaky). The traction
        on a face of outward normal n is t = −diag(K, [K,] 1) σ_v n: on a vertical face the
        horizontal pressure K γ' (z_s − z); on an inclined face the same horizontal pressure
        on its vertical projection and the vertical silt weight γ' (z_s − z) on its
        horizontal projection (the weight of the silt above the face, as the guidelines
        take it); on the reservoir floor, the silt's weight. z is the vertical axis (y in
        2D, z in 3D). Returns K.

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(2.0, 10.0, 1, 5)
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        >>> m.add_silt("xmin", level=6.0, submerged_unit_weight=9000.0, friction_angle=30.0)
        0.5
        >>> round(float(m.load_vector()[0::2].sum()), 6)   # K γ' H²/2 (N per m), downstream
        81000.0
        """
        names = (groups,) if isinstance(groups, str) else tuple(groups)
        _distinct_groups(names, "silt")
        if not names:
            raise ModelError("silt: no face groups given")
        if not (np.isfinite(level) and np.isfinite(submerged_unit_weight)
                and submerged_unit_weight > 0):  # fmt: skip
            raise ModelError(f"silt: expected a finite level and a submerged unit weight > 0 "
                             f"N/m³, got {level} m and {submerged_unit_weight}")  # fmt: skip
        if (k is None) == (friction_angle is None):
            raise ModelError("silt: give either k (the lateral coefficient, e.g. Ka) or the "
                             "friction_angle φ (at rest: K0 = 1 − sin φ), not both")  # fmt: skip
        if friction_angle is not None:
            if not (np.isfinite(friction_angle) and 0 <= friction_angle < 90):
                raise ModelError(f"silt: the friction angle must lie in [0, 90) degrees, got "
                                 f"{friction_angle}")  # fmt: skip
            k = 1.0 - float(np.sin(np.radians(friction_angle)))
        assert k is not None
        if not (np.isfinite(k) and k > 0):
            raise ModelError(f"silt: the lateral coefficient k must be a finite number > 0, "
                             f"got {k}")  # fmt: skip
        for g in names:
            self._boundary_group(g, "silt")
        if self._check_units and (text := implausible_silt(float(submerged_unit_weight))):
            log.warning("silt: %s", text)
        up, zs, gam, kk = self.dim - 1, float(level), float(submerged_unit_weight), float(k)
        ratio = np.full(self.dim, kk)
        ratio[up] = 1.0

        def stress(x: FloatArray) -> FloatArray:
            return gam * np.maximum(zs - x[..., up], 0.0)[..., None] * ratio

        for g in names:
            self.loads.append(Load("silt", g, stress, amplitude, level=zs))
        return kk

    def facets_of(self, group: str) -> dict[str, IntArray]:
        """The facets (by type) of a facet group of the (split) mesh; for an interface's
        name, those of both its faces, ``"<name>:a"`` and ``":b"`` (a pressure in the joint
        pushes both blocks, each along its own outward normal)."""
        if self.pairs is not None and group in self.pairs.names and (
                group not in self.mesh.facet_groups):  # fmt: skip
            a, b = self.mesh.facet_group(f"{group}:a"), self.mesh.facet_group(f"{group}:b")
            return {t: np.concatenate([c for c in (a.get(t), b.get(t)) if c is not None])
                    for t in {*a, *b}}  # fmt: skip
        return self.mesh.facet_group(group)

    def joint_facets(self, name: str) -> list[tuple[IntArray, int]]:
        """The facets of an interface's side a in the split mesh, by type, each with its
        corner count (:meth:`pfeie.model.Uplift.stations` joins the stations along them);
        empty for a name that is not an interface's."""
        if self.pairs is None or name not in self.pairs.names:
            return []
        group = f"{name}:a" if f"{name}:a" in self.mesh.facet_groups else name
        return [(conn, reference(t).n_corners) for t, conn in self.facets_of(group).items()]

    def _boundary_group(self, group: str, what: str) -> None:
        """Refuse a surface load on facets that are not on the boundary of a block (after
        the interfaces are split, a joint's faces are on the boundary of its blocks), and
        one on a group without facets (its selector matched nothing: the load would be
        dropped unseen)."""
        facets = self.facets_of(group)
        if not sum(conn.shape[0] for conn in facets.values()):
            raise ModelError(f"{what} on {group!r}: the facet group has no facets (its "
                             "selector matched nothing); expected a group with facets")  # fmt: skip
        for ftype, conn in facets.items():
            inside = np.flatnonzero(self.mesh.facet_multiplicity(ftype, conn) > 1)
            if inside.size:
                x = self.mesh.points[conn[inside[0]]].mean(axis=0)
                raise ModelError(
                    f"{what} on {group!r}: {inside.size} of its {conn.shape[0]} facet(s) lie "
                    f"inside a block (shared by two cells), the first at "
                    f"{np.round(x, 6).tolist()}; expected facets on the boundary of a block "
                    "or on an interface"
                )

    def add_westergaard(
        self,
        groups: str | Sequence[str],
        water_level: float,
        *,
        bottom: float | None = None,
        density: float = 1000.0,
    ) -> None:
        """Westergaard's added mass of the reservoir on the wet faces ``groups`` (1933):
        the hydrodynamic pressure on a rigid face accelerated by a (m/s²) is
        p = C(z) a·n (Pa; n the face's outward unit normal, into the water: p > 0 when
        the face moves into the water) with

            C(z) = 7/8 ρ_w √(H (h − z)),   H = h − z_b,   z ≤ h   (kg/m²)

        (ρ_w the water ``density``, kg/m³, h the ``water_level``, z_b the reservoir
        ``bottom``, default the lowest point of the wet faces, m; z the vertical axis, y
        in 2D; C = 0 below the bottom, where a face reaches into the foundation or the
        silt), and it acts on the face along −n: the force −∫ C (a·n) n dA. The added
        mass of a face is ∫ C N_a N_b n nᵀ dA (the normal-direction form, for inclined
        faces too; Kuo 1982), lumped by row sums into a d × d block per wet node (kg),

            m_a = ∫ C N_a n nᵀ dA   (Σ_b N_b = 1; n at each quadrature point),

        so that under a uniform acceleration a of the face the nodal forces m_a a are the
        consistent loads of Westergaard's pressure C (a·n) along n, all components (the
        water's force on the face is −m_a a): on a plane face inclined θ from the
        vertical, wet to the depth H (a wet length H/cos θ), a horizontal a gives
        Σ m_a a = 7/12 ρ_w H² a (cos θ, −sin θ) per metre on a battered face (the water
        above it; +sin θ on an overhanging one), the normal pressure's resultant with
        its vertical part. On a straight facet m_a = μ_a n nᵀ with μ_a = ∫ N_a C dA (on
        a quadratic facet with a negative row sum, a split over its corners that keeps
        its total and centre of pressure, all ≥ 0, the same shares for every component;
        on a curved facet a block that would not be positive semi-definite takes the
        facet's ∫ C n nᵀ dA by those shares); on a face whose normals lie along the axes
        (vertical faces, a level floor) the blocks are diagonal, n_x², n_y² (, n_z²)
        times μ_a, as before the coupling was kept. The blocks' diagonal is
        :meth:`added_mass` (totals, reports), the blocks :meth:`added_mass_matrix`; they
        add to M in the time stepping (as blocks where a face is inclined:
        :meth:`added_mass_coupled`), the ground motion's inertia load, the pseudo-static
        loads (:meth:`inertia_load`), the modal analysis and the kinetic energy (the
        water's); not to the weights of the bodies' rigid motions.

        >>> import numpy as np, pfeie as pf
        >>> mesh = pf.rectangle(1.0, 10.0, 1, 4)
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        >>> m.add_westergaard("xmin", water_level=10.0)
        >>> round(float(m.added_mass().sum()) / (7 / 12 * 1000 * 10.0**2), 3)  # ∫ C dz
        1.0
        >>> x, y = mesh.points[:, 0].copy(), mesh.points[:, 1].copy()
        >>> mesh.points[:, 0] = x - 0.5 * (10.0 - y) * (1.0 - x)   # batter 0.5 H : 1 V
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        >>> m.add_westergaard("xmin", water_level=10.0)
        >>> f = m.added_mass_matrix() @ np.tile([9.81, 0.0], mesh.n_points)  # a = g along x
        >>> np.round(f.reshape(-1, 2).sum(axis=0) / 1e3, 1).tolist()  # kN/m, (cos θ, −sin θ)
        [511.8, -255.9]
        """
        names = (groups,) if isinstance(groups, str) else tuple(groups)
        _distinct_groups(names, "westergaard")
        if not names:
            raise ModelError("westergaard: no wet face groups given")
        for g in names:
            self._boundary_group(g, "westergaard added mass")
        up = self.dim - 1
        low = min(float(self.mesh.points[np.unique(np.concatenate(
            [c.ravel() for c in self.mesh.facet_group(g).values()])), up].min())
            for g in names)  # fmt: skip
        zb = low if bottom is None else float(bottom)
        if not (np.isfinite(water_level) and water_level > zb):
            raise ModelError(f"westergaard: the water level {water_level} m must lie above the "
                             f"reservoir bottom {zb} m")  # fmt: skip
        if not (np.isfinite(density) and density > 0):
            raise ModelError(f"westergaard: the water density must be > 0, got {density}")
        if self._check_units and (text := implausible_water(float(density))) is not None:
            log.warning("westergaard: %s", text)
        for g in names:
            share = self._level_share(g, float(water_level))
            if share > WESTERGAARD_LEVEL_SHARE:
                log.warning(
                    "westergaard on %r: %.0f %% of its wet area is level (its normal within "
                    "20° of the vertical, as a reservoir floor or a gallery's floor): "
                    "Westergaard's added mass (1933) is that of the dam's upstream face, "
                    "and on a level face it adds vertical added mass the water does not "
                    "give; list the dam's wet face(s) only", g, 100.0 * share)  # fmt: skip
        self.reservoirs.append((names, float(water_level), zb, float(density)))

    def _level_share(self, group: str, level: float) -> float:
        """The share of the wet area (below ``level``) of the facet group ``group`` whose
        normal lies within :data:`WESTERGAARD_LEVEL_DEG` of the vertical (by each facet's
        corners)."""
        d, pts = self.dim, self.mesh.points
        area = level_area = 0.0
        for ftype, conn in self.mesh.facet_group(group).items():
            x = pts[conn[:, : reference(ftype).n_corners]]
            if d == 2:
                t = x[:, 1] - x[:, 0]
                n = np.column_stack([t[:, 1], -t[:, 0]])
            else:  # (half) the cross product of the diagonals, or of a triangle's edges
                k = x.shape[1]
                n = np.cross(x[:, 2 % k] - x[:, 0], x[:, 3 % k] - x[:, 1 % k])
            a = np.linalg.norm(n, axis=1)
            wet = x[..., d - 1].min(axis=1) < level
            up = np.abs(n[:, d - 1]) > np.cos(np.radians(WESTERGAARD_LEVEL_DEG)) * a
            area += float(a[wet].sum())
            level_area += float(a[wet & up].sum())
        return level_area / area if area > 0 else 0.0

    def add_reservoir(
        self,
        groups: str | Sequence[str],
        water_level: float,
        *,
        density: float = 1000.0,
        length: float | None = None,
        refine: int = 1,
    ) -> Reservoir:
        """An incompressible finite-element reservoir on the wet faces ``groups`` (2D; Kuo
        1982): Laplace's equation for the hydrodynamic pressure on a mesh of the water
        drawn from the wet face (its nodes on the face are the facets' points, each facet
        cut into ``refine`` pieces) up to the ``water_level`` h, with p = 0 on the surface
        and at the far end, a distance ``length`` upstream (default 3 H), a rigid bottom at
        the lowest point of the wet faces, and ∂p/∂n = −ρ_w ü·n on the face; condensed onto
        the face as the full added-mass matrix M_a = ρ_w t Qᵀ H⁻¹ Q
        (:class:`~pfeie.model.Reservoir`, which has the equations, signs and units).

        M_a enters the consistent mass (modal analysis, ``mass()``,
        :meth:`added_mass_matrix`) as it is, and the lumped mass (``mass(lumped=True)``,
        :meth:`added_mass`) as its row sums per component (:meth:`Reservoir.lumped`); the
        time stepping keeps it whole beside the blocks' lumped mass
        (``system(lumped_mass=True, full_reservoir=True)``), its row sums only in the metric
        of the position correction. Returns the reservoir (its mesh, pressures).

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(1.0, 10.0, 1, 4)
        >>> m = pf.Model(mesh, [pf.Block("all", pf.Elastic(30e9, 0.2, 2400.0))])
        >>> res = m.add_reservoir("xmin", water_level=10.0)
        >>> res.depth, res.length, res.dofs.size     # the x DOFs of the face's 5 nodes
        (10.0, 30.0, 5)
        """
        names = (groups,) if isinstance(groups, str) else tuple(groups)
        _distinct_groups(names, "reservoir")
        if not names:
            raise ModelError("reservoir: no wet face groups given")
        if self.dim != 2:
            raise ModelError("reservoir: the finite-element reservoir is 2D only; in 3D use "
                             "Westergaard's added mass (add_westergaard; model = 'westergaard' "
                             "in a model file)")  # fmt: skip
        facets = []
        for g in names:
            self._boundary_group(g, "finite-element reservoir")
            for ftype, conn in self.mesh.facet_group(g).items():
                fv = asm.facet_values(self.mesh.points, ftype, conn, 2, self.thickness)
                facets.append((ftype, conn, self._outward(ftype, conn, fv)))
        res = Reservoir(self.mesh.points, facets, water_level, n_dof=self.n_dof,
                        density=density, thickness=self.thickness, length=length,
                        refine=refine)  # fmt: skip
        self.fe_reservoirs.append(res)
        return res

    def add_uplift(self, interface: str, headwater: float, **options: Any) -> Uplift:
        """Uplift in the joint ``interface``: the pore pressure of the reservoir, linear
        from the headwater level at the heel to the tailwater level at the toe, with
        drains and full headwater in the part cracked from the heel (options and
        equations: :class:`~pfeie.model.Uplift`). The static analysis finds the crack and
        its uplift together (:func:`pfeie.solve_static`); the dynamic analysis keeps the
        pre-earthquake uplift or follows the pairs' state (``shaking``).

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(4.0, 2.0, 4, 2)
        >>> _ = mesh.add_cell_group("rock", lambda x: x[:, 1] < 1.0)
        >>> _ = mesh.add_cell_group("dam", lambda x: x[:, 1] > 1.0)
        >>> _ = mesh.add_facet_group("base", lambda x: abs(x[:, 1] - 1.0) < 1e-9, False)
        >>> mat = pf.Elastic(30e9, 0.2, 2400)
        >>> m = pf.Model(mesh, [pf.Block("rock", mat), pf.Block("dam", mat)],
        ...              interfaces=[pf.Interface("base", pf.Joint(phi=45.0))])
        >>> up = m.add_uplift("base", headwater=11.0)      # 10 m of water at the heel
        >>> p, _ = m.uplift_pressure()
        >>> [round(float(v) / 9810, 3) for v in p[m.pairs.of("base")][::4]]  # head (m)
        [10.0, 0.0]
        """
        if self.pairs is None or interface not in self.pairs.names:
            have = ", ".join(self.pairs.names) if self.pairs is not None else "none"
            raise ModelError(f"uplift: {interface!r} is not an interface of the model "
                             f"(interfaces: {have})")  # fmt: skip
        known = {f.name for f in fields(Uplift)} - {"interface", "headwater"}
        for key in options:
            if key not in known:
                hint = (
                    f"; {key!r} is the model file's name, the Python keyword is "
                    f"{UPLIFT_FILE_KEYS[key]!r}"
                    if key in UPLIFT_FILE_KEYS
                    else ""
                )
                raise ModelError(f"uplift in {interface!r}: unknown keyword {key!r}{hint} "
                                 f"(expected {', '.join(sorted(known))})")  # fmt: skip
        up = Uplift(interface, float(headwater), **options)
        if self._check_units and (text := implausible_water(float(up.density))) is not None:
            log.warning("uplift in %r: %s", interface, text)
        _, length = up.abscissa(self.pairs, self.pairs.of(interface))  # the axis exists
        if up.drains is not None and not 0.0 < up.drains < length:
            # drains at the heel or at or beyond the toe would be silently without effect
            where = "at the heel" if up.drains <= 0 else "beyond the joint"
            raise ModelError(f"uplift in {interface!r}: the drains at {up.drains:g} m from "
                             f"the heel lie {where}, "
                             f"whose pairs reach {length:g} m from the heel along the flow "
                             f"({up.upstream} upstream); expected 0 < drains < that length "
                             "(drains at the heel or the toe would change nothing)")  # fmt: skip
        idx = self.pairs.of(interface)
        x = self.pairs.x[idx]
        extent = float(np.ptp(x, axis=0).max()) if x.shape[0] else 0.0
        normal = (self.pairs.frame[idx, -1] * self.pairs.area[idx, None]).sum(axis=0)
        # the joint's tilt from level, by its mean normal
        cos_tilt = abs(float(normal[-1])) / max(float(np.linalg.norm(normal)), 1e-300)
        tilt = float(np.degrees(np.arccos(min(cos_tilt, 1.0))))
        if x.shape[0] and tilt > UPLIFT_STEEP_DEG:
            log.warning(
                "uplift in %r: the joint is steep (its mean plane %.0f° from level): uplift "
                "acts on base and lift joints in the guidelines, not on a contraction joint "
                "or a steep fault; its profile runs from the heel along the upstream axis "
                "(%s), %.4g m here", interface, tilt, up.upstream, length)  # fmt: skip
        elif extent > 0 and length < UPLIFT_FLAT_SHARE * extent:
            # every pair at the heel: full headwater over the whole joint
            log.warning(
                "uplift in %r: the joint spans %.4g m along the upstream axis (%s) but %.4g m "
                "in all, so the heel-to-toe profile does not develop: every pair is at the "
                "heel, at full headwater pressure: is the upstream axis another one?",
                interface, length, up.upstream, extent)  # fmt: skip
        self.uplifts.append(up)
        return up

    def uplift_pressure(
        self, open_: BoolArray | None = None, cracks: Sequence[float] | None = None
    ) -> tuple[FloatArray, list[float]]:
        """The uplift pressure at every pair (Pa) and the crack length of each uplift (m):
        from the open pairs ``open_`` (a crack from the heel through open pairs), or the
        given ``cracks``; without either, uncracked joints."""
        P = self.pairs
        if P is None or not self.uplifts:
            return np.zeros(0 if P is None else P.n), []
        p = np.zeros(P.n)
        out = []
        for i, up in enumerate(self.uplifts):
            pi, c = up.pressure(P, open_, None if cracks is None else cracks[i])
            p += pi
            out.append(c)
        return p, out

    def uplift_load(self, p: FloatArray) -> FloatArray:
        """The nodal load (n_dof,) of the pair pressures ``p`` (Pa; :func:`uplift_force`)."""
        if self.pairs is None or not p.size:
            return np.zeros(self.n_dof)
        return uplift_force(self.pairs, p, self.n_dof)

    def added_mass(self) -> FloatArray:
        """The lumped added mass of the reservoirs on every DOF (n_dof,), kg, on the
        diagonal: the diagonal of Westergaard's d × d nodal blocks (:meth:`add_westergaard`;
        n_k² ∫ C N_a dA on a straight facet of normal n) and the finite-element reservoirs'
        row sums (:meth:`add_reservoir`, :meth:`Reservoir.lumped`). The totals and reports
        use it, and the position correction's metric; the coupling of an inclined face's
        components is in :meth:`added_mass_matrix`, which the time stepping keeps for the
        finite-element reservoirs."""
        out = _block_diagonal(self._westergaard_blocks())
        for res in self.fe_reservoirs:
            out += res.lumped()
        return out

    def added_mass_matrix(self) -> sp.csr_matrix:
        """The added mass of the reservoirs as a matrix (n_dof × n_dof, kg): Westergaard's
        lumped d × d block on each wet node (:meth:`add_westergaard`: diagonal on faces
        whose normals lie along the axes, coupling the components of an inclined face's
        nodes), the finite-element reservoirs' full M_a on their wet DOFs."""
        blocks = self._westergaard_blocks()
        if _block_coupled(blocks):
            total = _block_matrix(blocks)
        else:
            total = sp.diags(_block_diagonal(blocks), format="csr")
        for res in self.fe_reservoirs:
            total = total + res.full()
        return sp.csr_matrix(total)

    def added_mass_coupled(self) -> bool:
        """True when the reservoirs' added mass couples DOFs (:meth:`added_mass_matrix`
        is not diagonal): a finite-element reservoir, or Westergaard's added mass on a
        face with a normal off the axes (an inclined face: its blocks' n_i n_j, i ≠ j).
        The time stepping then keeps it as a matrix (``mass(lumped=True,
        full_reservoir=True)``)."""
        return bool(self.fe_reservoirs) or _block_coupled(self._westergaard_blocks())

    def _westergaard_blocks(self) -> FloatArray:
        """Westergaard's lumped added mass as a d × d block per node (n_points, d, d), kg
        (:meth:`add_westergaard`); off-diagonal entries of round-off size (at most 1e-12
        of the block's trace: a face along the axes up to the coordinates' rounding) are
        set to zero. Read-only, computed once for the model's reservoirs (the mesh is
        fixed, as for the stiffness)."""
        key = tuple(self.reservoirs)
        if self._westergaard_cache is not None and self._westergaard_cache[0] == key:
            return self._westergaard_cache[1]
        d = self.dim
        out = np.zeros((self.mesh.n_points, d, d))
        pts = self.mesh.points
        for names, level, zb, rho_w in self.reservoirs:
            H = level - zb
            for g in names:
                for ftype, conn in self.mesh.facet_group(g).items():
                    ref = reference(ftype)
                    # the corners of the lines (2D) and triangles (3D) for the corner
                    # split of a facet with a negative row sum (_westergaard_add)
                    nc = d if (d == 2 or ref.simplex) else 0
                    # C has a square-root singularity where the depth vanishes: a Gauss
                    # rule of degree 2p + 8 integrates it to round-off on a facet whose
                    # top lies more than 4 of its heights below the level; nearer the
                    # square root is mapped out (_wet_line_rule in 2D, _wet_face_rule in
                    # 3D), to round-off
                    z = pts[conn, d - 1]
                    top, span = z.max(axis=1), np.ptp(z, axis=1)
                    near = (span > 0) & (level - top < 4.0 * span) & (z.min(axis=1) < level)
                    rules = [(~near, 2 * ref.degree + 8)]
                    if d == 2 and near.any():
                        N, dA, x, nrm, done = _wet_line_rule(pts, ftype, conn[near], level,
                                                             self.thickness)  # fmt: skip
                        cn = conn[near][done]
                        _westergaard_add(out, cn, N[done], dA[done], x[done], nrm[done],
                                         level, H, rho_w, pts[cn[:, :2]])  # fmt: skip
                        curved = np.zeros_like(near)  # never reaching the level
                        curved[np.flatnonzero(near)[~done]] = True
                        rules.append((curved, 2 * ref.degree + 400))
                    elif near.any():
                        # strongly curved facets, where the level curves can touch the
                        # inner lines: a 25 × 25 rule (about 1e-4 near the level)
                        fits = near.copy()
                        fits[near] = _face_rule_fits(pts, ftype, conn[near])
                        if fits.any():
                            cn = conn[fits]
                            N, dA, x, nrm = _wet_face_rule(pts, ftype, cn, level)
                            _westergaard_add(out, cn, N, dA, x, nrm, level, H, rho_w,
                                             pts[cn[:, :nc]] if nc else None)  # fmt: skip
                        rules.append((near & ~fits, 2 * ref.degree + 48))
                    for sel, order in rules:
                        if sel.any():
                            fv = asm.facet_values(pts, ftype, conn[sel], order, self.thickness)
                            Nb = np.broadcast_to(fv.N, (*fv.dA.shape, fv.N.shape[1]))
                            _westergaard_add(out, conn[sel], Nb, fv.dA, fv.x, fv.normal,
                                             level, H, rho_w,
                                             pts[conn[sel][:, :nc]] if nc else None)  # fmt: skip
        if d > 1 and self.reservoirs:
            trace = np.einsum("pii->p", out)
            off = ~np.eye(d, dtype=bool)[None] & (np.abs(out) <= 1e-12 * trace[:, None, None])
            out[off] = 0.0
        out.setflags(write=False)
        self._westergaard_cache = (key, out)
        return out

    def add_nodal_force(
        self,
        nodes: Iterable[int] | IntArray,
        value: Sequence[float],
        amplitude: Amplitude | None = None,
    ) -> None:
        """A force (N) applied at each of the given nodes: a vector of ``dim`` finite
        components."""
        idx, _ = self._nodes(nodes, "add_nodal_force")
        try:
            f = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(f"nodal force: expected {self.dim} numbers (N), got "
                             f"{value!r}") from None  # fmt: skip
        if f.shape != (self.dim,) or not np.isfinite(f).all():
            raise ModelError(f"nodal force: expected a finite vector of {self.dim} components "
                             f"(N), got {f.tolist()}")  # fmt: skip
        self.loads.append(Load("nodal", None, f, amplitude, idx))

    # -- discrete operators ---------------------------------------------------------------
    def _values(self, cs: _CellSet, degree: int) -> asm.CellValues:
        return asm.cell_values(self.mesh.points, cs.cell_type, cs.conn, degree, self.thickness)

    def stiffness(self) -> sp.csr_matrix:
        """Global stiffness K (n_dof × n_dof, N/m); assembled once per model (blocks and
        materials are fixed at construction)."""
        return self._stiffness

    @cached_property
    def _stiffness(self) -> sp.csr_matrix:
        return self._assemble(lambda cs: asm.stiffness(self._values(cs, cs.kdeg), cs.lam, cs.mu))

    def mass(self, lumped: bool = False, added: bool = True,
             full_reservoir: bool = False) -> sp.csr_matrix:  # fmt: skip
        """Global mass M (kg): consistent, or HRZ-lumped (diagonal) when ``lumped``; with
        the reservoirs' added mass unless ``added`` is False (:meth:`add_westergaard`,
        :meth:`add_reservoir`): lumped, :meth:`added_mass` on the diagonal and the
        coupling of Westergaard's nodal blocks on an inclined face beside it; consistent,
        :meth:`added_mass_matrix` (a finite-element reservoir's full M_a, Westergaard's
        nodal blocks). ``full_reservoir`` with ``lumped``: the blocks' mass lumped, the
        added mass as :meth:`added_mass_matrix` when it couples DOFs
        (:meth:`added_mass_coupled`: a finite-element reservoir, Westergaard's on an
        inclined face), else on the diagonal (what the time integrators use: the dam's
        mass diagonal, the water's coupling kept)."""
        n = self.n_dof
        wet = added and bool(self.reservoirs or self.fe_reservoirs)
        if wet and lumped and full_reservoir and self.added_mass_coupled():
            dry = self.mass(lumped=True, added=False)
            return (dry + self.added_mass_matrix()).tocsr()
        extra = self.added_mass() if wet and lumped else None
        if lumped:
            diag = np.zeros(n)
            for cs in self._cellsets:
                me = asm.scalar_mass(self._values(cs, asm.mass_degree(cs.cell_type)), cs.rho)
                ml = asm.lump_hrz(me)
                dofs = asm.element_dofs(cs.conn, self.dim)
                diag += asm.assemble_vector(dofs, np.repeat(ml, self.dim, axis=1), n)
            if extra is not None:
                diag += extra
            out = sp.diags(diag, format="csr")
            blocks = self._westergaard_blocks() if wet else None
            if blocks is not None and _block_coupled(blocks):
                # Westergaard's nodal blocks on an inclined face, lumped already: their
                # off-diagonal part beside the diagonal (what the time stepping keeps)
                off = np.where(np.eye(self.dim, dtype=bool), 0.0, blocks)
                out = sp.csr_matrix(out + _block_matrix(off))
            return out
        if wet:
            return (self._consistent_mass + self.added_mass_matrix()).tocsr()
        return self._consistent_mass

    @cached_property
    def _consistent_mass(self) -> sp.csr_matrix:
        """The consistent mass of the blocks (assembled once: materials are fixed)."""

        def block(cs: _CellSet) -> FloatArray:
            me = asm.scalar_mass(self._values(cs, asm.mass_degree(cs.cell_type)), cs.rho)
            return np.einsum("cab,ij->caibj", me, np.eye(self.dim)).reshape(
                me.shape[0], me.shape[1] * self.dim, -1
            )

        return self._assemble(block)

    def _assemble(self, kernel: Callable[[_CellSet], FloatArray]) -> sp.csr_matrix:
        total: sp.csr_matrix | None = None
        for cs in self._cellsets:
            m = asm.assemble_matrix(asm.element_dofs(cs.conn, self.dim), kernel(cs), self.n_dof)
            total = m if total is None else total + m
        assert total is not None
        return total

    def load_patterns(self) -> tuple[FloatArray, list[Amplitude | None]]:
        """Spatial load vectors (n_dof, n_loads) and their amplitudes."""
        cols = [self._load_vector(ld) for ld in self.loads]
        pats = np.stack(cols, axis=1) if cols else np.zeros((self.n_dof, 0))
        return pats, [ld.amplitude for ld in self.loads]

    def load_vector(self, t: float = 0.0) -> FloatArray:
        """The total load vector f(t) (N) on all DOFs."""
        pats, amps = self.load_patterns()
        a = np.array([1.0 if f is None else float(f(t)) for f in amps])
        return pats @ a if a.size else np.zeros(self.n_dof)

    def _load_vector(self, ld: Load) -> FloatArray:
        n, d = self.n_dof, self.dim
        f = np.zeros(n)
        if ld.kind in ("gravity", "body"):
            names = [b.name for b in self.blocks]
            for cs in self._cellsets:
                cv = self._values(cs, asm.mass_degree(cs.cell_type) + 2)
                vals = _field(ld.value, cv.x)
                if ld.kind == "gravity":
                    vals = vals * cs.rho[:, None, None]
                if ld.blocks is not None:
                    mask = np.isin(np.asarray(names)[cs.block], ld.blocks)
                    vals = vals * mask[:, None, None]
                fe = asm.load(cv, vals).reshape(cs.conn.shape[0], -1)
                f += asm.assemble_vector(asm.element_dofs(cs.conn, d), fe, n)
        elif ld.kind in ("traction", "pressure", "silt"):
            assert ld.target is not None

            def traction(x: FloatArray, normal: FloatArray, outward: FloatArray) -> FloatArray:
                if ld.kind == "traction":
                    return np.broadcast_to(_field(ld.value, x, f"traction on {ld.target!r}"),
                                           x.shape)  # fmt: skip
                if ld.kind == "silt":  # t = −diag(σ) n, n the outward normal
                    return -_field(ld.value, x) * normal * outward[:, None, None]
                p = _scalar_field(ld.value, x, f"pressure on {ld.target!r}")
                return np.asarray(-p[..., None] * normal * outward[:, None, None])

            pts = self.mesh.points
            for ftype, conn in self.facets_of(ld.target).items():
                fv = asm.facet_values(pts, ftype, conn, 2 * reference(ftype).degree + 2,
                                      self.thickness)  # fmt: skip
                outward = self._outward(ftype, conn, fv)
                fe = asm.facet_load(fv, traction(fv.x, fv.normal, outward))
                if ld.level is not None:
                    # the facets the level cuts: their wet part alone (add_pressure)
                    for sel, (N, dA, x, nrm) in _cut_facet_rules(pts, ftype, conn, ld.level,
                                                                 self.thickness):  # fmt: skip
                        tr = traction(x, nrm, outward[sel])
                        fe[sel] = np.einsum("fq,fqa,fqd->fad", dA, N, tr)
                fe = fe.reshape(conn.shape[0], -1)
                f += asm.assemble_vector(asm.element_dofs(conn, d), fe, n)
        elif ld.kind == "inertia":
            f += self.inertia_load(np.asarray(ld.value, dtype=float))
        elif ld.kind == "nodal":
            assert ld.nodes is not None
            vec = np.asarray(ld.value, dtype=float)
            if vec.shape != (d,):
                raise ModelError(f"nodal force needs {d} components, got {vec.shape}")
            f.reshape(-1, d)[ld.nodes] += vec
        return f

    def _outward(self, ftype: str, conn: IntArray, fv: asm.FacetValues) -> FloatArray:
        """+1 where the facet normal points out of its adjacent cell, −1 otherwise."""
        centre = self.mesh.facet_cell_centres(ftype, conn)
        side = np.einsum("fd,fd->f", fv.x.mean(axis=1) - centre, fv.normal.mean(axis=1))
        return np.where(side >= 0.0, 1.0, -1.0)

    @cached_property
    def _dofmap(self) -> tuple[IntArray, IntArray, FloatArray]:
        d = self.dim
        values = np.full(self.n_dof, np.nan)
        inactive = np.setdiff1d(np.arange(self.mesh.n_points), self.active_nodes)
        values.reshape(-1, d)[inactive] = 0.0
        for s in self.supports:
            for c in s.components:
                values.reshape(-1, d)[s.nodes, c] = s.value
        prescribed = np.flatnonzero(~np.isnan(values))
        free = np.flatnonzero(np.isnan(values))
        return free, prescribed, values[prescribed]

    def system(self, lumped_mass: bool = False, full_reservoir: bool = False) -> LinearSystem:
        """The operators restricted to the free DOFs, for solvers and integrators
        (``full_reservoir``: see :meth:`mass`)."""
        free, pres, pval = self._dofmap
        K = self.stiffness()
        M = self.mass(lumped=lumped_mass, full_reservoir=full_reservoir)
        pats, amps = self.load_patterns()
        self._warn_supported_loads(pats, free)
        Kf, pf_ = K[free], pats[free]
        Kff = Kf[:, free].tocsr()
        Kfp = Kf[:, pres].tocsr()
        shift = -(Kfp @ pval) if pres.size else np.zeros(free.size)
        constant = shift + pf_[:, [a is None for a in amps]].sum(axis=1)
        varying = [i for i, a in enumerate(amps) if a is not None]
        C = Cfp = Cpp = None
        Kpp = K[pres][:, pres].tocsr()
        Mff = M[free][:, free].tocsr()
        Mfp = M[free][:, pres].tocsr()
        Mfp.eliminate_zeros()
        if self.damping is not None and (self.damping.alpha or self.damping.beta):
            Cf = (self.damping.alpha * M + self.damping.beta * K)[free]
            C, Cfp = Cf[:, free].tocsr(), Cf[:, pres].tocsr()
            Cpp = (self.damping.alpha * M + self.damping.beta * K)[pres][:, pres].tocsr()
        return LinearSystem(
            M=Mff, K=Kff, C=C, free=free, n_dof=self.n_dof,
            prescribed=pres, prescribed_values=pval, _patterns=pf_[:, varying],
            _amplitudes=tuple(amps[i] for i in varying), _constant=constant,
            n_pairs=0 if self.pairs is None else int(self.pairs.n),
            C_update=self._rigid_damping(Mff, free) if C is not None else None,
            M_fp=Mfp if Mfp.nnz else None, K_fp=Kfp, C_fp=Cfp, K_pp=Kpp, C_pp=Cpp,
            rayleigh=(None if C is None or self.damping is None
                      else (float(self.damping.alpha), float(self.damping.beta))),
        )  # fmt: skip

    def _warn_supported_loads(self, pats: FloatArray, free: IntArray) -> None:
        """Warn, once per load, of a surface or nodal load that acts on supported DOFs
        only (a reservoir's pressure on the floor of a foundation fixed as a whole, a
        point load on a fixed node): it goes straight into the reactions and moves
        nothing, which the user rarely means. Body loads are not warned (a fixed
        foundation's own weight is the common, harmless case)."""
        for k, ld in enumerate(self.loads):
            if ld.kind not in ("traction", "pressure", "silt", "nodal") or k in self._warned:
                continue
            total = float(np.abs(pats[:, k]).sum())
            if total > 0.0 and float(np.abs(pats[free, k]).sum()) <= SUPPORTED_LOAD * total:
                self._warned.add(k)
                what = f"{ld.kind} on {ld.target!r}" if ld.target else f"{ld.kind} load"
                log.warning(
                    "%s acts on supported DOFs only: every DOF it loads is fixed, so it goes "
                    "straight into the reactions and moves nothing (is its group a face of "
                    "a fixed block, such as a foundation's floor?)", what)  # fmt: skip

    def _rigid_damping(self, Mff: sp.csr_matrix, free: IntArray) -> LowRankTerm | None:
        """−α M R (RᵀMR)⁻¹ RᵀM over the rigid motions that the supports leave free
        (:meth:`rigid_motion_projector`), on the free DOFs (:class:`Rayleigh`
        ``deformation_only``), or None."""
        rd = self.damping
        if rd is None or not rd.deformation_only or not rd.alpha:
            return None
        term = self.rigid_motion_projector(Mff, free)
        return None if term is None else term.scaled(-rd.alpha)

    def free_rigid_modes(self) -> sp.csc_matrix:
        """R (n_dof × r): the rigid motions that the supports leave free, body by body:
        all the rigid modes of a floating body (:meth:`floating_bodies`), and of a body with
        supports the combinations of its rigid modes (:meth:`rigid_modes`) that move none
        of its prescribed DOFs (the null space of the modes on those DOFs: a block on a
        roller keeps the motions along it, a block pinned at a node in 2D its rotation
        about the node); none for a body its supports hold."""
        return self._free_rigid[0]

    def free_rigid_mode_bodies(self) -> IntArray:
        """The body of each column of :meth:`free_rigid_modes` (r,)."""
        return self._free_rigid[1]

    @cached_property
    def _free_rigid(self) -> tuple[sp.csc_matrix, IntArray]:
        k = 3 if self.dim == 2 else 6
        Phi = self.rigid_modes().tocsc()
        _, pres, _ = self._dofmap
        held = np.zeros(self.n_dof, dtype=bool)
        held[pres] = True
        on = Phi[held]  # the modes on the prescribed DOFs
        cols, bodies = [], []
        for b in range(self.n_bodies):  # once per model, over the bodies
            Rb = Phi[:, b * k : (b + 1) * k]
            C = on[:, b * k : (b + 1) * k].toarray()
            if not C.any():
                cols.append(Rb)
                bodies += [b] * k
                continue
            N = null_space(C, 1e-10)
            if N.shape[1]:
                cols.append(sp.csc_matrix(Rb @ N))
                bodies += [b] * N.shape[1]
        R = sp.hstack(cols, format="csc") if cols else sp.csc_matrix((self.n_dof, 0))
        return R, np.array(bodies, dtype=np.int64)

    def rigid_motion_projector(self, M: sp.spmatrix, free: IntArray) -> LowRankTerm | None:
        """M R (Rᵀ M R)⁻¹ Rᵀ M over the rigid motions R that the supports leave free
        (:meth:`free_rigid_modes`) on the DOFs ``free``, as U B Uᵀ with U = M R and
        B = (RᵀMR)⁻¹, one dense block (a finite-element reservoir's added mass couples the
        wet blocks, so RᵀMR need not be block-diagonal); ``M`` (kg) on the same DOFs. For a
        mass-normalised φ, φᵀ(U B Uᵀ)φ is the share of its kinetic energy in those rigid
        motions (the M-orthogonal projection). None when the supports hold every body."""
        R = self.free_rigid_modes().tocsr()[free]  # the free motions move no prescribed DOF
        if not R.shape[1]:
            return None
        U = sp.csc_matrix(M @ R)
        A = np.asarray((R.T @ U).toarray())
        try:
            B = np.linalg.inv(A)
        except np.linalg.LinAlgError:
            raise ModelError(
                "the rigid motions of the unsupported blocks have no mass (a massless "
                "floating block): damping of the deformation only and the modal rigid "
                "shares need the blocks' mass"
            ) from None
        return LowRankTerm(U, B)

    # -- interfaces and bodies -------------------------------------------------------------
    @property
    def pairs(self) -> PairGeometry | None:
        """The interface point pairs, or None without interfaces."""
        return None if self.split is None else self.split.pairs

    @cached_property
    def pair_laws(self) -> PairLaws:
        """The joint laws of the interfaces, gathered per pair."""
        if self.split is None:
            raise ModelError("the model has no interfaces")
        P = self.split.pairs
        its = self.interfaces
        return PairLaws.from_interfaces(P.area, P.interface, [i.joint for i in its], P.dim,
                                        names=[i.group for i in its])  # fmt: skip

    def joint_extent(self, mask: BoolArray) -> FloatArray:
        """The extent of the pairs where ``mask`` (..., m) per interface (..., n_joints):
        the length in 2D (m: the pairs' areas over the thickness), the area in 3D (m²).
        The cracked extent of a joint is that of its broken pairs; the open crack that of
        its broken pairs that are open."""
        P = self.pairs
        if P is None:
            raise ModelError("the model has no interfaces")
        mask = np.asarray(mask, dtype=bool)
        out = np.stack([(mask[..., idx] * P.area[idx]).sum(axis=-1)
                        for idx in (P.of(name) for name in P.names)], axis=-1)  # fmt: skip
        return out / self.thickness if self.dim == 2 else out

    @cached_property
    def body_of_node(self) -> IntArray:
        """Body (connected part) of every node, −1 for unused nodes."""
        if self.split is not None:
            return self.split.body
        from scipy.sparse.csgraph import connected_components

        used = self.active_nodes
        n = self.mesh.n_points
        conn = [s.conn for s in self._cellsets]
        rows = np.concatenate([c.ravel() for c in conn])
        cols = np.concatenate([np.repeat(np.arange(c.shape[0]), c.shape[1]) for c in conn])
        offs = np.cumsum([0] + [c.shape[0] for c in conn])[:-1]
        cols = cols + np.repeat(offs, [c.size for c in conn]) + n
        nt = n + sum(c.shape[0] for c in conn)
        _, lab = connected_components(sp.coo_matrix((np.ones(rows.size), (rows, cols)),
                                                    shape=(nt, nt)), directed=False)  # fmt: skip
        body = np.full(n, -1, dtype=np.int64)
        _, inv = np.unique(lab[used], return_inverse=True)
        body[used] = inv.ravel()
        return body

    @property
    def n_bodies(self) -> int:
        return int(self.body_of_node.max()) + 1

    def body_index(self, name: str) -> int:
        """The index of the body named ``name`` (see :meth:`body_names`: a block's name,
        or the names of the blocks it joins, with '+'), the body axis of the results'
        rigid motions (``result.rigid[:, body]``). Bodies are numbered by the mesh, not in
        the order of the blocks given.

        >>> import pfeie as pf
        >>> mesh = pf.rectangle(1.0, 2.0, 1, 2)
        >>> _ = mesh.add_cell_group("top", lambda x: x[:, 1] > 1.0)
        >>> _ = mesh.add_cell_group("bottom", lambda x: x[:, 1] < 1.0)
        >>> _ = mesh.add_facet_group("j", lambda x: abs(x[:, 1] - 1.0) < 1e-9,
        ...                          boundary_only=False)
        >>> m = pf.Model(mesh, [pf.Block("top", pf.Elastic(1e9, 0.2, 2000.0)),
        ...                     pf.Block("bottom", pf.Elastic(1e9, 0.2, 2000.0))],
        ...              interfaces=[pf.Interface("j", pf.Joint(phi=30.0))])
        >>> m.body_names(), m.body_index("top")
        (['bottom', 'top'], 1)
        """
        names = self.body_names()
        if name not in names:
            raise ModelError(f"no body named {name!r}; the bodies are {names}")
        return names.index(name)

    def body_names(self) -> list[str]:
        """A name per body: its block names joined by '+', numbered when repeated."""
        names = []
        b_of = self.body_of_node
        for ib in range(self.n_bodies):
            blocks = sorted({self.blocks[int(k)].name for cs in self._cellsets
                             for k in np.unique(cs.block[np.isin(cs.conn[:, 0],
                                                np.flatnonzero(b_of == ib))])})  # fmt: skip
            names.append("+".join(blocks))
        seen: dict[str, int] = {}
        out = []
        for n in names:
            seen[n] = seen.get(n, 0) + 1
            out.append(n if names.count(n) == 1 else f"{n}#{seen[n]}")
        return out

    def floating_bodies(self) -> IntArray:
        """The bodies without a support (no prescribed DOF): held by their joints, or
        free; indices into :meth:`body_names`."""
        _, pres, _ = self._dofmap
        held = np.zeros(self.n_dof, dtype=bool)
        held[pres] = True
        on = np.bincount(self.body_of_node[self.active_nodes],
                         held.reshape(-1, self.dim)[self.active_nodes].any(axis=1),
                         minlength=self.n_bodies)  # fmt: skip
        return np.flatnonzero(on == 0).astype(np.int64)

    def unsupported_bodies(self) -> IntArray:
        """The floating bodies that no chain of joints connects to a body with a support
        (every body of a model without supports): nothing holds them against a static
        load, whatever their joints' strength; indices into :meth:`body_names`."""
        floating = self.floating_bodies()
        if not floating.size:
            return floating
        label = self._joint_groups()
        held = np.ones(self.n_bodies, dtype=bool)
        held[floating] = False
        reached = np.zeros(int(label.max()) + 1, dtype=bool)
        reached[label[held]] = True
        return floating[~reached[label[floating]]]

    def _joint_groups(self) -> IntArray:
        """The group of every body (n_bodies,): bodies that joints tie, directly or through
        others, share one (a body without pairs is a group of its own)."""
        n = self.n_bodies
        if self.pairs is None:
            return np.arange(n)
        body = self.body_of_node
        a, b = body[self.pairs.node_a], body[self.pairs.node_b]
        touch = sp.coo_matrix((np.ones(a.size), (a, b)), shape=(n, n))
        return np.asarray(connected_components(touch, directed=False)[1])

    def massless_floating_bodies(self) -> IntArray:
        """The floating bodies (:meth:`floating_bodies`) with no mass, their own or added
        (ρ = 0, as for a massless foundation, without reservoir): a dynamic step's matrix
        s M + β h² K is singular on their rigid modes; indices into :meth:`body_names`."""
        floating = self.floating_bodies()
        if not floating.size:
            return floating
        mdiag = self.mass(lumped=True).diagonal().reshape(-1, self.dim).sum(axis=1)
        b = self.body_of_node
        use = b >= 0
        mass = np.bincount(b[use], mdiag[use], self.n_bodies)
        return floating[~(mass[floating] > 0)]

    def unrestrained_modes(self) -> str:
        """The rigid modes that the supports leave free, per body without interface pairs,
        as text ("body 'a+b': translation y"), or "" when every such body is held. A body
        with pairs may be held by its joints; the static interface problem judges those."""
        paired = np.zeros(self.mesh.n_points, dtype=bool)
        if self.pairs is not None:
            paired[self.pairs.node_a] = paired[self.pairs.node_b] = True
        names = self.body_names()
        out = []
        for b in range(self.n_bodies):
            nodes = np.flatnonzero(self.body_of_node == b)
            if not nodes.size or paired[nodes].any():
                continue
            modes = self._free_rigid_modes(nodes)
            if modes:
                out.append(f"body {names[b]!r} can move freely ({'; '.join(modes)}): no "
                           "support holds it and no joint ties it")  # fmt: skip
        return "; ".join(out)

    def partly_supported_groups(self) -> list[tuple[list[str], list[str]]]:
        """The groups of bodies tied by joints (taken as bonded) that have supports but
        whose supports leave a rigid motion of the whole group free (a support in one
        component only, on one line): each group's body names and its free modes as text.
        No joint strength can hold such a motion against a load along it."""
        if self.pairs is None:
            return []
        label = self._joint_groups()
        body = self.body_of_node
        floating = set(self.floating_bodies().tolist())
        names = self.body_names()
        out = []
        for k in range(int(label.max()) + 1):
            members = np.flatnonzero(label == k)
            if all(int(m) in floating for m in members):
                continue  # no support at all: unsupported_bodies
            nodes = np.flatnonzero(np.isin(body, members))
            modes = self._free_rigid_modes(nodes)
            if modes:
                out.append(([names[m] for m in members], modes))
        return out

    def _free_rigid_modes(self, nodes: IntArray) -> list[str]:
        """The rigid motions of the nodes ``nodes`` taken as one rigid body that their
        prescribed components leave free, as text ("translation y"), [] if none."""
        d = self.dim
        _, pres, _ = self._dofmap
        flat = np.zeros(self.n_dof, dtype=bool)
        flat[pres] = True
        fixed = flat.reshape(-1, d)
        labels = (["translation x", "translation y", "rotation about z"] if d == 2 else
                  ["translation x", "translation y", "translation z", "rotation about x",
                   "rotation about y", "rotation about z"])  # fmt: skip
        X = self.mesh.points[nodes] - self.mesh.points[nodes].mean(axis=0)
        basis = np.zeros((nodes.size, d, len(labels)))
        for i in range(d):
            basis[:, i, i] = 1.0
        if d == 2:
            basis[:, 0, 2], basis[:, 1, 2] = -X[:, 1], X[:, 0]
        else:
            for k, (i, j) in enumerate(((1, 2), (2, 0), (0, 1))):
                basis[:, i, 3 + k], basis[:, j, 3 + k] = -X[:, j], X[:, i]
        held = basis[fixed[nodes]]  # (prescribed components, modes)
        null = _echelon(null_space(held, 1e-9).T)
        return [" + ".join(labels[k] for k in np.flatnonzero(np.abs(v) > 1e-6)) for v in null]

    @cached_property
    def body_weights(self) -> FloatArray:
        """Nodal weights (n_points,) for centroids and rigid-motion fits: the lumped mass,
        or the lumped volume for a massless body."""
        mdiag = self.mass(lumped=True, added=False).diagonal().reshape(-1, self.dim)[:, 0]
        b = self.body_of_node
        use = b >= 0
        mass = np.bincount(b[use], mdiag[use], self.n_bodies)
        massless = np.flatnonzero(mass <= 0)
        if massless.size:
            vol = np.zeros(self.mesh.n_points)
            for cs in self._cellsets:
                cv = self._values(cs, asm.mass_degree(cs.cell_type))
                me = asm.scalar_mass(cv, np.ones(cs.conn.shape[0]))
                vol += np.bincount(cs.conn.ravel(), asm.lump_hrz(me).ravel(), self.mesh.n_points)
            sel = np.isin(b, massless)
            mdiag = np.where(sel, vol, mdiag)
        return np.asarray(mdiag, dtype=float)

    @cached_property
    def body_mass_props(self) -> tuple[FloatArray, FloatArray]:
        """Mass (b,) in kg and centroid (b, d) of every body (of its volume if massless)."""
        mdiag = self.mass(lumped=True, added=False).diagonal().reshape(-1, self.dim)[:, 0]
        w = self.body_weights
        b = self.body_of_node
        use = b >= 0
        mass = np.bincount(b[use], mdiag[use], self.n_bodies).astype(float)
        wsum = np.bincount(b[use], w[use], self.n_bodies)
        cen = np.stack([np.bincount(b[use], (w * self.mesh.points[:, i])[use], self.n_bodies)
                        for i in range(self.dim)], axis=1) / wsum[:, None]  # fmt: skip
        return mass, cen

    def rigid_modes(self) -> sp.csr_matrix:
        """Φ (n_dof × n_bodies·r): the rigid modes of every body about its mass centroid,
        r = 3 in 2D (u_x, u_y, θ_z) and 6 in 3D (u, then rotations θ_x, θ_y, θ_z, rad),
        column body·r + mode."""
        d = self.dim
        r = 3 if d == 2 else 6
        _, cen = self.body_mass_props
        b = self.body_of_node
        nodes = np.flatnonzero(b >= 0)
        x = self.mesh.points[nodes] - cen[b[nodes]]
        rows, cols, vals = [], [], []
        for i in range(d):  # translations
            rows.append(nodes * d + i)
            cols.append(b[nodes] * r + i)
            vals.append(np.ones(nodes.size))
        if d == 2:
            rot = [(2, [(0, -x[:, 1]), (1, x[:, 0])])]
        else:  # ω × x: θx → (0, −z, y); θy → (z, 0, −x); θz → (−y, x, 0)
            rot = [(3, [(1, -x[:, 2]), (2, x[:, 1])]), (4, [(0, x[:, 2]), (2, -x[:, 0])]),
                   (5, [(0, -x[:, 1]), (1, x[:, 0])])]  # fmt: skip
        for mode, comps in rot:
            for i, v in comps:
                rows.append(nodes * d + i)
                cols.append(b[nodes] * r + mode)
                vals.append(v)
        return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(self.n_dof, self.n_bodies * r)).tocsr()  # fmt: skip

    @cached_property
    def _rigid_fit(self) -> sp.csr_matrix:
        """The mass-norm rigid fit as one operator, A = (ΦᵀMΦ)⁻¹(MΦ)ᵀ (n_bodies·r ×
        n_dof), formed once: ΦᵀMΦ is block-diagonal (a node is in one body), so its
        inverse is taken body by body (r × r blocks) and A has the pattern of (MΦ)ᵀ."""
        Phi = self.rigid_modes()
        r = 3 if self.dim == 2 else 6
        nb = self.n_bodies
        MPhi = sp.csr_matrix(Phi.multiply(np.repeat(self.body_weights, self.dim)[:, None]))
        B = sp.coo_matrix(Phi.T @ MPhi)
        blocks = np.zeros((nb, r, r))
        same = B.row // r == B.col // r
        np.add.at(blocks, (B.row[same] // r, B.row[same] % r, B.col[same] % r), B.data[same])
        inv = np.linalg.inv(blocks)
        rows = (np.arange(nb)[:, None, None] * r + np.arange(r)[None, :, None]).repeat(r, 2)
        cols = (np.arange(nb)[:, None, None] * r + np.arange(r)[None, None, :]).repeat(r, 1)
        Binv = sp.csr_matrix((inv.ravel(), (rows.ravel(), cols.ravel())), shape=(nb * r, nb * r))
        return sp.csr_matrix(Binv @ MPhi.T)

    def rigid_motion(self, u: FloatArray) -> FloatArray:
        """Rigid motion (n_bodies, r) of each body about its mass centroid that best fits
        the nodal field u (full DOF vector or (n_points, d)) in the mass norm: the
        translation of the centroid and the rotation (rad)."""
        U = np.asarray(u, dtype=float).reshape(self.n_dof, -1)
        q = self._rigid_fit @ U
        r = 3 if self.dim == 2 else 6
        return (
            q.reshape(self.n_bodies, r, -1).squeeze(-1)
            if U.shape[1] == 1
            else q.reshape(self.n_bodies, r, -1)
        )

    # -- post-processing ------------------------------------------------------------------
    def stress(self, u: FloatArray) -> dict[str, tuple[FloatArray, FloatArray]]:
        """Stress (c, q, 3, 3) in Pa at the stiffness quadrature points of each cell type,
        with the points (c, q, d). ``u`` is a full DOF vector or (n_points, d) array."""
        U = np.asarray(u, dtype=float).reshape(self.mesh.n_points, self.dim)
        out = {}
        for cs in self._cellsets:
            cv = self._values(cs, cs.kdeg)
            sig = asm.stress(asm.strain(cv, U[cs.conn]), cs.lam, cs.mu, self.plane)
            out[cs.cell_type] = (sig, cv.x)
        return out

    @cached_property
    def stress_operators(self) -> StressOperators:
        """The stress operators of the model (:class:`StressOperators`): the strain
        operator B from the shape-function derivatives at the stiffness quadrature points
        (all cells of a type at once), the Lamé constants of each point, and the
        extrapolation of the point values to the nodes."""
        d, n_dof = self.dim, self.n_dof
        offset = {t: 0 for t in self.mesh.cells}
        run = 0
        for t, conn in self.mesh.cells.items():
            offset[t] = run
            run += len(conn)
        # the strain components (i, j), in the order of B's row blocks: 2D xx, yy, xy;
        # 3D the Voigt order (engineering shears)
        comps = ((0, 0), (1, 1), (0, 1)) if d == 2 else asm.VOIGT
        comp, pts, cols, vals, cells, lam, mu = [], [], [], [], [], [], []
        fits, corners = [], []
        cnt = np.zeros(self.mesh.n_points)
        q0 = 0
        for cs in self._cellsets:
            cv = self._values(cs, cs.kdeg)
            c, nen = cs.conn.shape
            nq = cv.dNdx.shape[1]
            qid = (q0 + np.arange(c * nq)).reshape(c, nq)
            for k, (i, j) in enumerate(comps):
                # ε_ii = Σ_a ∂N_a/∂x_i u_ai;  γ_ij = Σ_a (∂N_a/∂x_j u_ai + ∂N_a/∂x_i u_aj)
                for a in range(nen):
                    for along, deriv in ((i, j),) if i == j else ((i, j), (j, i)):
                        comp.append(np.full(c * nq, k))
                        pts.append(qid.ravel())
                        cols.append(np.repeat(cs.conn[:, a] * d + along, nq))
                        vals.append(cv.dNdx[:, :, a, deriv].ravel())
            cells.append(np.repeat(offset[cs.cell_type] + cs.index, nq))
            lam.append(np.repeat(cs.lam, nq))
            mu.append(np.repeat(cs.mu, nq))
            # the nodal stress: the corner fit of the point values, averaged over cells
            lin = reference(reference(cs.cell_type).linear)
            xi, _ = quadrature(cs.cell_type, cs.kdeg)
            Nq, _ = lin.shape_functions(xi)
            Nn, _ = lin.shape_functions(reference(cs.cell_type).nodes)
            fits.append((q0, c, np.ascontiguousarray((Nn @ np.linalg.pinv(Nq)).T)))
            corners.append(cs.conn.ravel())
            cnt += np.bincount(cs.conn.ravel(), minlength=self.mesh.n_points)
            q0 += c * nq
        vals_all = np.concatenate(vals)
        keep = vals_all != 0.0
        rows_all = np.concatenate(comp) * q0 + np.concatenate(pts)
        B = sp.csr_matrix((vals_all[keep], (rows_all[keep], np.concatenate(cols)[keep])),
                          shape=(len(comps) * q0, n_dof))  # fmt: skip
        node = np.concatenate(corners)
        A = sp.csr_matrix((1.0 / np.maximum(cnt, 1.0)[node], (node, np.arange(node.size))),
                          shape=(self.mesh.n_points, node.size))  # fmt: skip
        return StressOperators(B, np.concatenate(lam), np.concatenate(mu),
                               d == 2 and self.plane == "strain", tuple(fits), A,
                               np.concatenate(cells))  # fmt: skip

    def nodal_stress(self, u: FloatArray) -> FloatArray:
        """Nodal stresses (n_points, 3, 3), Pa: per cell, a least-squares fit of the
        Gauss-point values by the corner (linear) shape functions, evaluated at the
        nodes, then averaged over the cells sharing each node (two sparse products,
        :attr:`stress_operators`)."""
        op = self.stress_operators
        v = op.nodal_components(op.components(np.asarray(u, dtype=float).ravel()))
        out = np.empty((v.shape[1], 3, 3))
        for k, (i, j) in enumerate(asm.VOIGT):
            out[:, i, j] = out[:, j, i] = v[k]
        return out

    def _per_cell(self, values: Callable[[_CellSet], FloatArray]) -> FloatArray:
        """A value per cell of the mesh (n_cells, numbered type after type in
        ``mesh.cells`` order), NaN for cells of no block."""
        offset, run = {}, 0
        for t, conn in self.mesh.cells.items():
            offset[t] = run
            run += len(conn)
        out = np.full(run, np.nan)
        for cs in self._cellsets:
            out[offset[cs.cell_type] + cs.index] = values(cs)
        return out

    @cached_property
    def cell_volumes(self) -> FloatArray:
        """The volume of every cell (n_cells, mesh order; m³, in 2D its area × the
        thickness), NaN for cells of no block."""
        return self._per_cell(
            lambda cs: self._values(cs, asm.mass_degree(cs.cell_type)).dV.sum(axis=1)
        )

    @cached_property
    def cell_tensile_strength(self) -> FloatArray:
        """The tensile strength f_t of every cell's material (n_cells, mesh order; Pa),
        NaN where the material gives none or the cell is in no block."""
        given = [getattr(b.material, "tensile_strength", None) for b in self.blocks]
        ft = np.array([np.nan if v is None else float(v) for v in given])
        return self._per_cell(lambda cs: ft[cs.block])

    def total_mass(self) -> float:
        """Mass of all blocks (kg; per unit thickness × thickness in 2D)."""
        total = 0.0
        for cs in self._cellsets:
            cv = self._values(cs, asm.mass_degree(cs.cell_type))
            total += float((cv.dV * cs.rho[:, None]).sum())
        return total

    @property
    def revision(self) -> dict[str, int]:
        """What an analysis built on the model depends on, by count (supports, loads,
        reservoirs, uplifts) and the damping's identity: each ``fix`` and ``add_*`` call
        changes it, so that an analysis can tell that the model changed after it was
        built (its operators and loads are those of that time)."""
        return {"supports": len(self.supports), "loads": len(self.loads),
                "Westergaard reservoirs": len(self.reservoirs),
                "finite-element reservoirs": len(self.fe_reservoirs),
                "uplifts": len(self.uplifts), "damping": id(self.damping)}  # fmt: skip

    def summary(self) -> dict[str, Any]:
        """Counts that describe the model: blocks, cells, nodes, DOFs."""
        free, pres, _ = self._dofmap
        return {
            "dim": self.dim, "blocks": [b.name for b in self.blocks],
            "cells": {cs.cell_type: int(cs.conn.shape[0]) for cs in self._cellsets},
            "nodes": int(self.active_nodes.size), "dof": int(self.n_dof),
            "free_dof": int(free.size), "prescribed_dof": int(pres.size),
        }  # fmt: skip


def _warn_unused_strength(itf: Interface) -> None:
    """Warn when a joint that starts broken is given an intact strength it never uses
    (cohesion or tension with ``initial="broken"``, the default, and no residual ones):
    a user who meant a bonded joint gets a frictional one without a word otherwise."""
    law = itf.joint
    if not isinstance(law, MohrCoulomb) or law.initial != "broken" or law.c_r or law.tensile_r:
        return  # intact, or the residual strength given: the user knows which acts
    unused = [f"{k} = {v:g} Pa" for k, v in (("cohesion", law.c), ("tensile strength", law.tensile))
              if v > 0]  # fmt: skip
    if unused:
        log.warning("interface %r: %s given, but the joint starts broken (initial = 'broken', "
                    "the default), so only its residual strength acts (residual cohesion "
                    "%g Pa, residual tensile strength %g Pa, friction angle %g°): set "
                    "initial = 'intact' for a bonded joint, or the residual values for an "
                    "existing joint with cohesion", itf.group, " and ".join(unused), law.c_r,
                    law.tensile_r, law.phi if law.phi_r is None else law.phi_r)  # fmt: skip


def _disjoint_blocks(mesh: Mesh, blocks: Sequence[Block]) -> dict[str, IntArray]:
    """Refuse cells in two blocks' groups, naming the cells (gmsh element ids); the
    block of each cell by type (−1: none; a type of no block's group absent)."""
    owner: dict[str, IntArray] = {}
    for ib, blk in enumerate(blocks):
        for ctype, idx in mesh.cell_groups.get(blk.cell_group, {}).items():
            own = owner.setdefault(ctype, np.full(mesh.cells[ctype].shape[0], -1, np.int64))
            idx = np.unique(np.asarray(idx, dtype=np.int64))
            clash = idx[own[idx] >= 0]
            if clash.size:
                other = blocks[int(own[clash[0]])]
                cells = ", ".join(mesh.cell_label(ctype, int(c)) for c in clash[:5])
                more = f" and {clash.size - 5} more" if clash.size > 5 else ""
                raise ModelError(
                    f"groups {other.cell_group!r} (block {other.name!r}) and {blk.cell_group!r} "
                    f"(block {blk.name!r}) share {clash.size} {ctype} cell(s): {cells}{more}; "
                    "expected each cell in one block group"
                )
            own[idx] = ib
    return owner


def _field(value: VectorField | float, x: FloatArray, what: str = "load") -> FloatArray:
    """A vector field at the points x (..., d): a constant or a function of x."""
    return _values(value, x, x.shape, what, "a vector of d components per point")


def _scalar_field(value: Any, x: FloatArray, what: str = "pressure") -> FloatArray:
    """A scalar field at the points x (..., d): a constant or a function of x."""
    return _values(value, x, x.shape[:-1], what, "one value per point")


def _values(value: Any, x: FloatArray, shape: tuple[int, ...], what: str,
            expected: str) -> FloatArray:  # fmt: skip
    """A load's values at the quadrature points x (facets or cells, points, d), broadcast
    to ``shape``; a function that returns another shape (it indexed x as a list of
    points, ``x[:, k]``, not ``x[..., k]``) or fails on such an array is named."""
    hint = (f"{what}: a function of the points receives x of shape {x.shape} (facets or "
            "cells, quadrature points, coordinates): index it as x[..., k]; expected "
            f"{expected}, an array of shape {shape}")  # fmt: skip
    try:
        out = value(x) if callable(value) else np.asarray(value, dtype=float)
        return np.broadcast_to(np.asarray(out, dtype=float), shape)
    except (ValueError, IndexError, TypeError) as exc:
        if not callable(value):
            raise
        raise ModelError(f"{hint}; the function gave: {exc}") from None


__all__ = ["LinearSystem", "Model"]


def _westergaard_add(out: FloatArray, conn: IntArray, N: FloatArray, dA: FloatArray,
                     x: FloatArray, normal: FloatArray, level: float, H: float,
                     rho_w: float, corners: FloatArray | None = None) -> None:  # fmt: skip
    """Add the lumped Westergaard masses of the facets ``conn`` (f, n) to ``out``
    (n_points, d, d), a d × d block per node, from their quadrature: shape functions
    N (f, q, n), measures dA (f, q), points x and unit normals (f, q, d). The scalar
    masses are the row sums of ∫ C N_a N_b dA, i.e. the
    consistent nodal loads ∫ N_a C dA of Westergaard's pressure under a unit normal
    acceleration (Σ_b N_b = 1: a rigid motion of the base loads the face exactly as the
    closed form does). A quadratic facet can have a negative row sum (in 2D where the
    surface cuts it; a 6-node triangle wherever C varies over it, its corner loads being
    A/60 (2p_i − p_j − p_k) under a linear p): in 2D its load then goes to its two
    corners, split so that its total and its centre of pressure are kept (both masses
    ≥ 0: the centre lies between them). On a 3D triangle (``corners`` (f, 3, 3)) the
    corner split puts the total on the corners by the barycentric coordinates λ of the
    centre of pressure (≥ 0 on a straight facet, where C ≥ 0; clipped on a curved one),
    and the masses are the least step m + β (split − m), β ∈ [0, 1], from the consistent
    loads m towards it that makes every mass ≥ 0: both keep the total and the centre of
    pressure, so does every step between them. Other facets: HRZ row scaling (total
    kept). Each node's block is its scalar mass times n nᵀ (n the facet's unit normal;
    on a curved facet ∫ C N_a n nᵀ dA with the normal of each point, see below)."""
    d = x.shape[-1]
    # the depth below the surface, above the bottom z_b = h − H only (a face that reaches
    # below the reservoir's bottom, into the foundation or the silt, has no water there)
    z = x[..., d - 1]
    depth = np.where(z >= level - H * (1.0 + 1e-12), np.maximum(level - z, 0.0), 0.0)
    c = 0.875 * rho_w * np.sqrt(H * depth) * dA  # (f, q)
    me = np.einsum("fqa,fqb,fq->fab", N, N, c)
    rows = me.sum(axis=2)  # (f, n)
    neg = ~(rows >= 0).all(axis=1)
    ml = rows.copy()
    if neg.any() and d == 2 and corners is not None:
        total = c[neg].sum(axis=1)
        centre = np.einsum("fq,fqd->fd", c[neg], x[neg]) / total[:, None]
        edge = corners[neg, 1] - corners[neg, 0]
        tau = np.einsum("fd,fd->f", centre - corners[neg, 0], edge) / (edge**2).sum(axis=1)
        tau = np.clip(tau, 0.0, 1.0)
        ml[neg] = 0.0
        ml[neg, 0], ml[neg, 1] = total * (1.0 - tau), total * tau
    elif neg.any() and corners is not None and corners.shape[1] == 3:
        total = c[neg].sum(axis=1)
        centre = np.einsum("fq,fqd->fd", c[neg], x[neg]) / total[:, None]
        e = corners[neg, 1:] - corners[neg, :1]  # (f, 2, 3)
        gram = np.einsum("fid,fjd->fij", e, e)
        rhs = np.einsum("fid,fd->fi", e, centre - corners[neg, 0])
        lam = np.linalg.solve(gram, rhs[..., None])[..., 0]
        bary = np.clip(np.concatenate([1.0 - lam.sum(axis=1, keepdims=True), lam], axis=1),
                       0.0, None)  # fmt: skip
        split = np.zeros_like(rows[neg])
        split[:, :3] = total[:, None] * bary / bary.sum(axis=1, keepdims=True)
        # the least step from the consistent loads towards the corner split that makes
        # every mass ≥ 0 (both have the total and the centre of pressure)
        low = rows[neg] < 0.0
        beta = np.where(low, -rows[neg] / np.where(low, split - rows[neg], 1.0), 0.0)
        blend = rows[neg] + beta.max(axis=1, keepdims=True) * (split - rows[neg])
        ml[neg] = np.maximum(blend, 0.0)  # the round-off of the zeroed row
    elif neg.any():
        ml[neg] = asm.lump_hrz(me[neg])
    # the d × d blocks m_a = ∫ C N_a n nᵀ dA (the row sums of ∫ C N_a N_b n nᵀ dA), whose
    # trace is the scalar row sum (|n| = 1). On a straight facet (n the same at every
    # point, to 1e-12) m_a = ml_a n nᵀ; on a curved one the normal of each point, unless
    # the facet's masses were redistributed (negative row sums: the split keeps the
    # scalar masses' shares w_a = ml_a / ∫ C dA) or a block would not be positive
    # semi-definite (N_a < 0 where n turns): then w_a ∫ C n nᵀ dA. Either way the blocks
    # of a facet total ∫ C n nᵀ dA.
    nrm = normal.mean(axis=1)
    nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    nn = nrm[:, :, None] * nrm[:, None, :]  # (f, d, d)
    blocks = ml[:, :, None, None] * nn[:, None]
    curved = np.abs(normal - nrm[:, None, :]).max(axis=(1, 2)) > 1e-12
    if curved.any():
        cc, nq = c[curved], normal[curved]
        whole = np.einsum("fq,fqi,fqj->fij", cc, nq, nq)  # ∫ C n nᵀ dA
        per = np.einsum("fqa,fq,fqi,fqj->faij", N[curved], cc, nq, nq)
        total = cc.sum(axis=1)
        share = np.divide(ml[curved], total[:, None], out=np.zeros_like(ml[curved]),
                          where=total[:, None] > 0)  # fmt: skip
        least = np.linalg.eigvalsh(per).min(axis=-1)  # (f, n)
        scale = np.abs(np.einsum("faii->fa", per)).max(axis=1, keepdims=True)
        own = ~neg[curved] & (least >= -1e-12 * scale).all(axis=1)
        blocks[curved] = np.where(own[:, None, None, None], per,
                                  share[:, :, None, None] * whole[:, None])  # fmt: skip
    # symmetric to the bit (the per-point products of a curved facet are not, to 1e-17)
    np.add.at(out, conn, 0.5 * (blocks + blocks.swapaxes(-1, -2)))


def _echelon(A: FloatArray, tol: float = 1e-9) -> FloatArray:
    """The reduced row echelon form of the rows of A (k, m), which span a subspace: the
    subspace's one basis whose leading entries are 1 with zeros above and below them, so
    that it does not depend on how a solver chose the rows (the null space's basis from
    an SVD turns with the LAPACK build).

    >>> (_echelon(np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.0]])).round(12) + 0.0).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    """
    A = np.array(A, dtype=float)
    row = 0
    for col in range(A.shape[1]):
        if row == A.shape[0]:
            break
        r = row + int(np.argmax(np.abs(A[row:, col])))
        if abs(A[r, col]) <= tol:
            continue
        A[[row, r]] = A[[r, row]]
        A[row] /= A[row, col]
        others = np.arange(A.shape[0]) != row
        A[others] -= np.outer(A[others, col], A[row])
        row += 1
    return A


def _block_diagonal(blocks: FloatArray) -> FloatArray:
    """The diagonal (n_points · d,) of nodal blocks (n_points, d, d)."""
    return np.einsum("pii->pi", blocks).ravel().copy()


def _block_coupled(blocks: FloatArray) -> bool:
    """True when nodal blocks (n_points, d, d) have an off-diagonal entry."""
    d = blocks.shape[-1]
    return bool(np.any(blocks[:, ~np.eye(d, dtype=bool)]))


def _block_matrix(blocks: FloatArray) -> sp.csr_matrix:
    """The block-diagonal matrix (n_points · d square) of nodal blocks (n_points, d, d),
    its non-zero entries only."""
    n, d = blocks.shape[0], blocks.shape[-1]
    base = (np.arange(n) * d)[:, None, None]
    rows = np.broadcast_to(base + np.arange(d)[None, :, None], blocks.shape)
    cols = np.broadcast_to(base + np.arange(d)[None, None, :], blocks.shape)
    keep = blocks != 0.0
    return sp.csr_matrix((blocks[keep], (rows[keep], cols[keep])), shape=(n * d, n * d))


def _cut_facet_rules(
    points: FloatArray, ftype: str, conn: IntArray, level: float, thickness: float
) -> list[tuple[IntArray, tuple[FloatArray, FloatArray, FloatArray, FloatArray]]]:
    """Quadratures of the wet part (below ``level``) of the facets ``conn`` that the
    level cuts (their nodes' heights on both sides of it), for a surface load that is a
    polynomial below the level and zero above (:meth:`Model.add_pressure` ``level``).
    The rules of the reservoirs' added mass, whose map ξ = ξ* + (ξ_w − ξ*) s² from the
    wet end ξ_w to the level's crossing ξ* keeps a polynomial depth a polynomial in s:
    in 2D :func:`_wet_line_rule` (exact: on a straight facet of degree p the integrand
    N_a p n dA has degree 4p + 1 in s, on a curved one 6p − 1, below the 24 points'
    47); in 3D :func:`_wet_face_rule` (exact along its inner lines; between the splits
    at the level's crossings of the edges the outer integrand is polynomial on quads
    and rational on triangles, where its 2 × 12 points reach round-off), or a Gauss rule
    of degree 2p + 48 on curved facets where it does not fit. Returns the selections
    (indices into ``conn``) with N (f, q, n), dA (f, q), points x (f, q, d) and unit
    normals (f, q, d), the normals oriented as :func:`pfeie.assembly.facet_values`."""
    d = points.shape[1]
    z = points[conn, d - 1]
    cut = np.flatnonzero((z.min(axis=1) < level) & (z.max(axis=1) > level))
    out: list[tuple[IntArray, tuple[FloatArray, FloatArray, FloatArray, FloatArray]]] = []
    if not cut.size:
        return out
    if d == 2:
        N, dA, x, nrm, done = _wet_line_rule(points, ftype, conn[cut], level, thickness)
        out.append((cut[done], (N[done], dA[done], x[done], nrm[done])))
        # facets that do not reach the level along their line (curved: cut only at the
        # nodes) keep the caller's rule
        return out
    fits = _face_rule_fits(points, ftype, conn[cut])
    if fits.any():
        out.append((cut[fits], _wet_face_rule(points, ftype, conn[cut[fits]], level)))
    if (~fits).any():
        rest = cut[~fits]
        fv = asm.facet_values(points, ftype, conn[rest], 2 * reference(ftype).degree + 48,
                              thickness)  # fmt: skip
        N = np.broadcast_to(fv.N, (*fv.dA.shape, fv.N.shape[1]))
        out.append((rest, (N, fv.dA, fv.x, fv.normal)))
    return out


def _wet_line_rule(
    points: FloatArray, ftype: str, conn: IntArray, level: float, thickness: float, n: int = 24
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, BoolArray]:
    """Quadrature of the wet part of 2D facets near the water level, with the square root
    of Westergaard's C mapped out. ξ* is where the facet's map y(ξ) = Σ N_i(ξ) y_i
    reaches the level (bisection, on the facet or on its extension beyond its upper end);
    with ξ_w the facet's wet (lower) end, ξ = ξ* + (ξ_w − ξ*) s² makes the depth κ s²
    (exactly, on a straight facet), so √depth = √κ s and the integrand is a polynomial in
    s: n Gauss points on s ∈ [s₀, 1] (s₀ = 0 where the level cuts the facet, else the
    facet's upper end) integrate it to round-off. Returns N (f, n, nodes), dA (f, n),
    x (f, n, 2), the unit normals (f, n, 2), and a mask (f,) of the facets done (the
    others, curved facets that never reach the level, are left to the caller)."""
    ref = reference(ftype)
    X = points[conn]  # (f, m, 2)
    y = X[..., 1]

    def height(xi: FloatArray) -> FloatArray:
        Nx, _ = ref.shape_functions(xi.reshape(-1, 1))
        return np.asarray(np.einsum("fm,fm->f", Nx.reshape(xi.size, -1), y))

    f = len(conn)
    lo_end, hi_end = height(np.full(f, -1.0)), height(np.full(f, 1.0))
    wet = np.where(lo_end <= hi_end, -1.0, 1.0)  # the lower end
    far = wet - 20.0 * wet  # the search reaches 9 facet lengths beyond the upper end
    done = height(far) >= level
    a, b = wet.copy(), far.copy()  # y(a) ≤ level ≤ y(b)
    for _ in range(80):
        mid = 0.5 * (a + b)
        below = height(mid) <= level
        a, b = np.where(below, mid, a), np.where(below, b, mid)
    star = np.where(done, 0.5 * (a + b), -wet)
    # the end of the wet part: ξ* if the level cuts the facet, else its upper end
    inside = np.abs(star) <= 1.0
    end = np.where(inside, star, -wet)
    s0 = np.sqrt(np.clip((end - star) / (wet - star), 0.0, 1.0))
    u, w = np.polynomial.legendre.leggauss(n)
    u, w = 0.5 * (u + 1.0), 0.5 * w
    s = s0[:, None] + (1.0 - s0)[:, None] * u[None, :]  # (f, n)
    xi = star[:, None] + (wet - star)[:, None] * s**2
    jac_s = 2.0 * np.abs(wet - star)[:, None] * s * (1.0 - s0)[:, None]  # dξ/du
    Nq, dNq = ref.shape_functions(xi.reshape(-1, 1))
    Nq = Nq.reshape(f, n, -1)
    dNq = dNq.reshape(f, n, -1)
    x = np.einsum("fqm,fmd->fqd", Nq, X)
    t = np.einsum("fqm,fmd->fqd", dNq, X)
    jac = np.linalg.norm(t, axis=-1)
    nvec = np.stack([t[..., 1], -t[..., 0]], axis=-1) / jac[..., None]
    return Nq, jac * jac_s * w[None, :] * thickness, x, nvec, done


def _wet_face_rule(
    points: FloatArray, ftype: str, conn: IntArray, level: float, n_in: int = 8, n_out: int = 12
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Quadrature of the wet part of 3D facets near the water level, with the square root
    of Westergaard's C mapped out (the 3D form of :func:`_wet_line_rule`).

    Each facet is parametrised by the square (r, q) ∈ [−1, 1]² through a bilinear map Φ
    of its reference coordinates ξ = Φ(r, q) (the Q4 interpolation of four corner
    images): a quad takes ξ = (r, q) or (q, r), r along the reference direction in which
    the height z changes more (across the facet's middle); a triangle takes the collapsed
    (Duffy) map, corners A, B, V, V with V the corner of middle height, r running parallel
    to the opposite edge AB, and |det Φ'| = (1 − q)/8 a polynomial. On a bilinear quad
    and on a straight-sided triangle z is then linear in r at fixed q.

    Inner lines (r at fixed q): with r_w the line's wet (lower) end and r* where the line
    (extended up to 9 lengths beyond its upper end) first reaches the level (the roots of
    z(r) = level, z a polynomial of degree p in r), r = r* + (r_w − r*) s² makes the depth
    κ s², so √depth = √κ s and the integrand is a polynomial in s: n_in Gauss points on
    s ∈ [s₀, 1] (s₀ = 0 where the level cuts the line, else s₀ = √((r_u − r*)/(r_w − r*)),
    r_u the upper end) integrate it to round-off. A line that never reaches the level is
    wholly wet (r* is then the far end of the search, where the depth is still positive:
    the integrand is smooth), one whose wet end is above the level is dry (weight 0).

    Outer direction q: the line integral I(q) is analytic except where the level crosses
    a line's end, the edges r = ±1 (their extensions too: the real roots of
    z(±1, q) = level, z a polynomial of degree p ≤ 2 in q there), where it behaves as
    |q − q_c|^{3/2}. [−1, 1] is split at the crossings inside it into k + 1 pieces (k the
    most crossings of a facet, ≤ 2 on straight facets; some empty). On a piece, I is
    singular only at some crossings: those of the wet-end edge r = r_w if its lines are
    cut (I = ∫ from r_w to r*, analytic where r* passes the other end), those of both
    edges if they are wholly wet. Each half of a piece is mapped from the nearest such
    crossing q_A beyond its end (else one 20 away), q = q_A ± (q_m − q_A) τ², τ ∈ [τ₀, 1]
    (q_m the piece's middle, τ₀ = 0 at a split), as the inner lines are:
    |q − q_A|^{3/2} ∝ τ³ becomes analytic, also when q_A lies just outside the facet (a
    level just above a corner), and n_out Gauss points in τ reach round-off. The measure
    is dA = |∂x/∂ξ₁ × ∂x/∂ξ₂| |det Φ'| dr dq.

    On a curved 6-node triangle z is quadratic along the lines: the depth is κ s² g(s),
    g analytic and > 0 where z is monotone along them (:func:`_face_rule_fits`), and the
    same rule converges fast instead of being exact (1.8e-15 of the total on faces whose
    inner nodes are moved by up to 0.15 of a cell). Where z is not monotone the level
    curves can touch the lines: such facets are left to the caller.

    Returns N (f, Q, nodes), dA (f, Q) in m², the points x (f, Q, 3) and unit normals
    (f, Q, 3), Q = 2 (k + 1) n_out n_in, k ≤ 2p the most splits of a facet; dry points
    have dA = 0."""
    ref = reference(ftype)
    X = points[conn]  # (f, m, 3)
    z = X[..., 2]
    f = len(conn)
    corners = ref.nodes[: ref.n_corners]  # reference corners
    zc = z[:, : ref.n_corners]
    # the corner images K (f, 4, dim) of the square's corners (−1,−1), (1,−1), (1,1), (−1,1)
    if ref.simplex:
        order = np.argsort(zc, axis=1)  # V, the middle corner, collapses the side q = 1
        lo, middle, hi = (corners[order[:, k]] for k in range(3))
        K = np.stack([lo, hi, middle, middle], axis=1)
    else:
        # z across the middle: ξ from −1 to 1 (corners 1, 2 minus 0, 3), η likewise
        dxi = np.abs(zc[:, 1] + zc[:, 2] - zc[:, 0] - zc[:, 3])
        deta = np.abs(zc[:, 2] + zc[:, 3] - zc[:, 0] - zc[:, 1])
        swap = deta > dxi
        K = np.broadcast_to(corners, (f, 4, 2)).copy()
        K[swap] = corners[[0, 3, 2, 1]]  # (r, q) ↦ ξ = (q, r)
    # Φ(r, q) = a + r b + q c + r q d (f, 1, dim) from the corner images
    signs = np.array([[1, 1, 1, 1], [-1, 1, 1, -1], [-1, -1, 1, 1], [1, -1, 1, -1]]) / 4.0
    a, b, c, d = np.einsum("vk,fkd->vfd", signs, K)[:, :, None]

    def phi(r: FloatArray, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """ξ = Φ(r, q) (f, k, dim) and |det Φ'| (f, k) at r, q (f, k)."""
        r, q = r[..., None], q[..., None]
        xi = a + r * b + q * c + r * q * d
        dr, dq = b + q * d, c + r * d
        return xi, np.abs(dr[..., 0] * dq[..., 1] - dr[..., 1] * dq[..., 0])

    def height(r: FloatArray, q: FloatArray) -> FloatArray:
        xi, _ = phi(r, q)
        Nx, _ = ref.shape_functions(xi.reshape(-1, ref.dim))
        return np.einsum("fkm,fm->fk", Nx.reshape(*r.shape, -1), z)

    # z is a polynomial of degree p in r at fixed q, and in q on the edges r = ±1: its
    # coefficients (…, p + 1) from p + 1 samples, for the roots where it meets the level
    nodes = np.linspace(-1.0, 1.0, ref.degree + 1)
    vinv = np.linalg.inv(np.vander(nodes, increasing=True))

    def horner(c: FloatArray, v: FloatArray | float) -> FloatArray:
        out = c[..., -1]
        for k in range(c.shape[-1] - 2, -1, -1):
            out = out * v + c[..., k]
        return out

    # the outer splits and anchors: where the level crosses the edge lines r = ±1
    # (extended 9 lengths beyond the facet), the real roots of z(±1, q) = level
    sides = np.repeat([-1.0, 1.0], nodes.size)
    edge = height(np.broadcast_to(sides, (f, sides.size)),
                  np.broadcast_to(np.tile(nodes, 2), (f, sides.size)))  # fmt: skip
    c_edge = edge.reshape(f, 2, -1) @ vinv.T  # (f, 2, p + 1)
    roots = _quadratic_roots(c_edge, level).reshape(f, -1)  # (f, 4), NaN for none
    roots = np.where(np.abs(roots) <= 19.0, roots, np.nan)
    inside = np.abs(roots) < 1.0
    k = int(inside.sum(axis=1).max())  # the most splits of a facet (≤ 2 on straight ones)
    splits = np.sort(np.where(inside, roots, 1.0), axis=1)[:, :k]
    brk = np.concatenate([-np.ones((f, 1)), splits, np.ones((f, 1))], axis=1)
    qa, qb = brk[:, :-1], brk[:, 1:]  # (f, k + 1): the pieces, some empty
    # each piece's anchors: its nearest crossing at or below its lower end (else 20 below
    # it) and at or above its upper end, among those where its I(q) is singular: on a
    # piece of cut lines (I = ∫ from r_w to r*, analytic where r* passes r = ±1) those
    # of the wet-end edge r = r_w, on a wholly wet piece those of both edges
    mid = 0.5 * (qa + qb)
    z_mid = horner(c_edge[:, :, None, :], mid[:, None, :])  # (f, 2, k + 1)
    cut_mid = (z_mid.min(axis=1) < level) & (level < z_mid.max(axis=1))
    wet_edge = (z_mid[:, 1] < z_mid[:, 0]).astype(int)  # 0: r = −1, 1: r = +1
    edge_of_root = np.repeat([0, 1], roots.shape[1] // 2)
    keep = ~cut_mid[..., None] | (edge_of_root == wet_edge[..., None])  # (f, k + 1, 4)
    rt = np.where(keep, roots[:, None, :], np.nan)
    lo_anchor = np.fmax(np.nanmax(np.where(rt <= qa[..., None], rt, -np.inf), axis=2), qa - 20.0)
    hi_anchor = np.fmin(np.nanmin(np.where(rt >= qb[..., None], rt, np.inf), axis=2), qb + 20.0)
    t, wt = np.polynomial.legendre.leggauss(n_out)
    t, wt = 0.5 * (t + 1.0), 0.5 * wt
    halves = []
    for anchor, end, sign in ((lo_anchor, qa, 1.0), (hi_anchor, qb, -1.0)):
        reach = sign * (mid - anchor)  # ≥ 0
        tau0 = np.sqrt(np.divide(sign * (end - anchor), reach, out=np.ones_like(reach),
                                 where=reach > 0.0))  # fmt: skip
        tau = tau0[..., None] + (1.0 - tau0)[..., None] * t  # (f, k + 1, n_out)
        dq = 2.0 * reach[..., None] * tau * (1.0 - tau0)[..., None] * wt
        halves.append((anchor[..., None] + sign * reach[..., None] * tau**2, dq))
    q = np.concatenate([h[0] for h in halves], axis=2).reshape(f, -1)  # (f, L)
    wq = np.concatenate([h[1] for h in halves], axis=2).reshape(f, -1)
    n_lines = q.shape[1]
    # the inner lines: wet end, root r*, start s₀
    line = height(np.broadcast_to(nodes, (f, n_lines, nodes.size)).reshape(f, -1),
                  np.repeat(q, nodes.size, axis=1))  # fmt: skip
    c_line = line.reshape(f, n_lines, -1) @ vinv.T  # (f, L, p + 1)
    z_lo, z_hi = horner(c_line, -1.0), horner(c_line, 1.0)
    wet = np.where(z_lo <= z_hi, -1.0, 1.0)
    dry = np.minimum(z_lo, z_hi) >= level
    # r*: the root nearest the wet end towards the upper end, up to 9 line lengths beyond
    far = -19.0 * wet
    ahead = -wet[..., None] * (_quadratic_roots(c_line, level) - wet[..., None])
    ahead = np.where((ahead > 0.0) & (ahead <= 20.0), ahead, np.inf).min(axis=2)
    star = np.where(np.isfinite(ahead), wet - wet * ahead, far)
    end = np.where(np.abs(star) <= 1.0, star, -wet)
    span = np.where(dry, 1.0, wet - star)
    s0 = np.sqrt(np.clip((end - star) / span, 0.0, 1.0))
    u, wu = np.polynomial.legendre.leggauss(n_in)
    u, wu = 0.5 * (u + 1.0), 0.5 * wu
    s = s0[..., None] + (1.0 - s0)[..., None] * u  # (f, L, n_in)
    r = star[..., None] + (wet - star)[..., None] * s**2
    dr = 2.0 * np.abs(span)[..., None] * s * (1.0 - s0)[..., None] * wu
    w = np.where(dry[..., None], 0.0, dr * wq[..., None])
    xi, det = phi(r.reshape(f, -1), np.repeat(q, n_in, axis=1))
    Nx, dNx = ref.shape_functions(xi.reshape(-1, 2))
    Q = n_lines * n_in
    Nx, dNx = Nx.reshape(f, Q, -1), dNx.reshape(f, Q, -1, 2)
    x = Nx @ X
    T = np.swapaxes(dNx, 2, 3) @ X[:, None]  # (f, Q, 2, 3): ∂x/∂ξ₁, ∂x/∂ξ₂
    nvec = np.cross(T[..., 0, :], T[..., 1, :])
    jac = np.linalg.norm(nvec, axis=-1)
    return Nx, jac * det * w.reshape(f, Q), x, nvec / jac[..., None]


def _quadratic_roots(c: FloatArray, level: float) -> FloatArray:
    """The real roots (…, 2) of c₀ + c₁ q + c₂ q² = level for coefficients c (…, k),
    k ≤ 3 (NaN where there are none; one root for a linear polynomial), by the stable
    form q = −(c₁ + sgn c₁ √D)/2 and the roots q/c₂, (c₀ − level)/q."""
    c0 = c[..., 0] - level
    c1 = c[..., 1]
    c2 = c[..., 2] if c.shape[-1] > 2 else np.zeros_like(c0)
    disc = c1**2 - 4.0 * c2 * c0
    with np.errstate(divide="ignore", invalid="ignore"):
        qq = -0.5 * (c1 + np.where(c1 >= 0.0, 1.0, -1.0) * np.sqrt(disc))
        out = np.stack([qq / c2, c0 / qq], axis=-1)
    out[~np.isfinite(out) | (disc < 0.0)[..., None]] = np.nan
    return out


def _face_rule_fits(points: FloatArray, ftype: str, conn: IntArray) -> BoolArray:
    """Which facets (f,) :func:`_wet_face_rule` integrates to round-off: those where the
    height z changes monotonically along its inner lines, so that the level meets each
    line once and never touches one (its level curves are then graphs r*(q)). Straight-
    sided triangles and bilinear quads always; a curved 6-node triangle if its slope along
    AB (the inner direction: A, B its lowest and highest corners) keeps its sign and
    varies by less than a factor 2 over the facet (on a 6 × 6 grid)."""
    ref = reference(ftype)
    if ref.degree == 1 or not ref.simplex:
        return np.ones(len(conn), dtype=bool)
    X = points[conn]
    zc = X[:, : ref.n_corners, 2]
    order = np.argsort(zc, axis=1)
    direction = ref.nodes[order[:, 2]] - ref.nodes[order[:, 0]]  # (f, 2): from A to B
    g = np.linspace(0.0, 1.0, 6)
    grid = np.array([(u, v) for u in g for v in g if u + v <= 1.0 + 1e-12])
    _, dN = ref.shape_functions(grid)
    slope = np.einsum("qmk,fm,fk->fq", dN, X[..., 2], direction)
    lo, hi = slope.min(axis=1), slope.max(axis=1)
    return np.asarray((lo > 0.0) & (hi < 2.0 * lo))
