"""Proximal-point semismooth Newton: the robust fallback of the interface solver.

The interface problem of a step (method.md §5) asks for the pair forces X (m, d) with

    s = s_free + W X,      F(X, s) = 0,

F the Alart-Curnier natural map of the pair law with the parameter r = 1/mean diag W
(signs of pfeie: X positive in compression, normal last; s the relative displacement,
positive when the pair opens; for a broken pair of residual strength c A, μ, σ_t A,
Y = X_n + σ_t A, Δs = s − s_prev and τ = max(0, c A + μ X_n), the cohesion ramp near
the tension cut-off):

    F_n = Y − max(0, Y − r s_n)                   (closed: s_n = 0; open: Y = 0),
    F_t = X_t − Π_{B(τ)}(X_t − r Δs_t)            (stick: Δs_t = 0; slide: X_t = −τ ŝ),

intact pairs F = r (s − s_prev), pairs held open F = X, pairs sliding along a given
direction ŝ: F_t = X_t + τ ŝ. When W is singular (redundant pairs: more constraints than
the motions they tie, e.g. a stiff block on many coplanar pairs) or badly scaled, the
semismooth Newton on F has singular or ill-conditioned Jacobians and stalls on
round-off. The proximal-point method (Rockafellar; for contact Acary, Brémond and Huber
2018, the most robust of their comparison, and Siconos' ``fc3d_proximal``) solves instead
a sequence of regularised problems: given the iterate X^k and σ > 0, X^{k+1} solves

    s̃ = s_free − σ X^k + (W + σ I) X = s + σ (X − X^k),      F(X, s̃) = 0,

the pair law for the shifted operator W + σ I, whose Jacobians are regular and well
conditioned whatever the rank of W. A fixed point (X^{k+1} = X^k) solves the original
problem, since then s̃ = s; the natural map of the true s differs from the subproblem's by
at most r σ |X^{k+1} − X^k| per pair, and the outer iterations converge linearly at a
rate of about σ/(σ + λ), λ the stiffness of the slowest mode (small near a mechanism):
so σ (relative to w̄ = mean diag W) falls tenfold with each subproblem solved, down to
σ_min, and rises tenfold when a subproblem's Newton fails, which brings the subproblem
closer to the previous iterate and so easier (and stays there a while). Lowering σ with
the residual instead (σ ≤ ‖F‖/f) crawled at 6 % an iteration near an arch's hinge
mechanism and stopped, short, after 30. The redundant forces are not unique; the
proximal term picks the answer nearest to the start, and the relative motions, which are
unique, converge.

Each subproblem is solved by a semismooth Newton with an Armijo line search on |F̃|. Its
generalised Jacobian has the block form (one d × d block per pair)

    J = A (W + σ I) + B,      A = ∂F/∂s,  B = ∂F/∂X   (block diagonal),

so a sparse W (many blocks, each with few pairs, as in granular media) gives a sparse J,
factorised by a sparse LU; a dense W a dense J. The per-pair blocks:

- intact: A = r I, B = 0;
- normal, contact (Y − r s_n > 0): A_nn = r; separation: B_nn = 1;
- tangential, stick (|z| ≤ τ, z = X_t − r Δs_t): A_tt = r I;
- tangential, slide: with ẑ = z/|z| and P = (τ/|z|)(I − ẑ ẑᵀ):
  B_tt = I − P, A_tt = r P, B_tn = −μ ẑ where τ grows with X_n;
- given slip direction: B_tt = I, B_tn = μ ŝ where τ grows; held open: B = I.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..linalg import symmetric_product
from ..typing import BoolArray, FloatArray
from ._laws import cone

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PairLaw:
    """The pair law of one solve, per pair, as the natural map reads it."""

    c: FloatArray  # (m,) cohesive strength c A (N)
    mu: FloatArray  # (m,) friction coefficient
    t: FloatArray  # (m,) tensile strength σ_t A (N)
    broken: BoolArray  # (m,)
    fixed: BoolArray  # (m,) sliding along the given slip_dir
    inactive: BoolArray  # (m,) held open
    s_prev: FloatArray  # (m, d) relative displacement at the start of the step
    slip_dir: FloatArray  # (m, d - 1) the given slip directions of fixed pairs


def natural_map(
    X: FloatArray, s: FloatArray, law: PairLaw, r: FloatArray, jac: bool = True
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """F(X, s) (m, d) and, if ``jac``, the blocks A = ∂F/∂s and B = ∂F/∂X (m, d, d)
    (module doc), with the parameter r (m,) of each pair; without ``jac`` A and B are
    empty."""
    m, d = X.shape
    F = np.empty((m, d))
    A = np.zeros((m, d, d) if jac else (0, d, d))
    B = np.zeros((m, d, d) if jac else (0, d, d))
    br = law.broken
    it = ~br
    F[it] = r[it, None] * (s[it] - law.s_prev[it])
    Xn = X[:, -1]
    Y = Xn + law.t
    g = s[:, -1]
    contact = br & (Y - r * g > 0)
    sep = br & ~contact
    F[:, -1] = np.where(contact, r * g, np.where(sep, Y, F[:, -1]))
    Xt = X[:, :-1]
    z = Xt - r[:, None] * (s[:, :-1] - law.s_prev[:, :-1])
    nz = np.sqrt(np.einsum("ki,ki->k", z, z))
    # the cone and dτ/dX_n, the residual cohesion mobilised near parting on its ramp
    tau, dtau = cone(law.c, law.mu, law.t, Xn, br)
    cut = sep & (law.c > 0)  # a separated pair carries no shear, whatever its cohesion
    tau[cut] = 0.0
    dtau[cut] = 0.0
    fixed = br & law.fixed
    stick = br & (nz <= tau) & ~fixed
    slide = br & ~stick & ~fixed
    with np.errstate(invalid="ignore", divide="ignore"):
        zh = np.where(nz[:, None] > 0, z / nz[:, None], 0.0)
    Ft = F[:, :-1]
    Ft[stick] = Xt[stick] - z[stick]
    Ft[slide] = Xt[slide] - tau[slide, None] * zh[slide]
    Ft[fixed] = Xt[fixed] + tau[fixed, None] * law.slip_dir[fixed]
    off = law.inactive
    F[off] = X[off]
    if not jac:
        return F, A, B
    eye = np.eye(d)
    A[it] = r[it, None, None] * eye
    A[contact, -1, -1] = r[contact]
    B[sep, -1, -1] = 1.0
    grows = dtau != 0
    if d > 1:
        et = np.eye(d - 1)
        A[stick, :-1, :-1] = r[stick, None, None] * et
        sk = np.flatnonzero(slide)
        zk = zh[sk]
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(nz[sk] > 0, tau[sk] / nz[sk], 0.0)
        P = (et[None] - zk[:, :, None] * zk[:, None, :]) * ratio[:, None, None]
        B[sk, :-1, :-1] = et[None] - P
        A[sk, :-1, :-1] = r[sk, None, None] * P
        gk = grows[sk]
        B[sk[gk], :-1, -1] = -zk[gk] * dtau[sk[gk], None]
        fk = np.flatnonzero(fixed)
        B[fk, :-1, :-1] = et[None]
        gf = fk[grows[fk]]
        B[gf, :-1, -1] = dtau[gf, None] * law.slip_dir[gf]
    A[off] = 0.0
    B[off] = eye
    return F, A, B


class ShiftedOperator:
    """W (dense, with an optional sparse copy), an optional border E (M, k), and the
    Newton systems of the natural map for W + σ I: J = A (W + σ I) + B with
    block-diagonal A and B (module doc); with the border (dense W only), the bordered
    system of :func:`proximal_newton`."""

    def __init__(
        self, W: FloatArray, sparse: sp.csr_array | None = None, border: FloatArray | None = None
    ) -> None:
        if sparse is not None and border is not None:
            raise ValueError("a border goes with the dense W only (the solver keeps W sparse "
                             "only without one)")  # fmt: skip
        self.W = W
        self.sparse = sparse
        self.n = W.shape[0]
        self.E = border

    @property
    def k(self) -> int:
        """The border's columns (0 without a border)."""
        return 0 if self.E is None else int(self.E.shape[1])

    def matvec(self, x: FloatArray) -> FloatArray:
        """W x."""
        if self.sparse is not None:
            return np.asarray(self.sparse @ x)
        return symmetric_product(self.W, x)

    def solve(
        self, A: FloatArray, B: FloatArray, shift: FloatArray, rhs: FloatArray,
        wbar: float = 1.0, sigma: float = 0.0,
    ) -> FloatArray:  # fmt: skip
        """The solution of (A (W + S) + B) x = rhs, S = diag(shift) (M,); with the
        border, of the bordered system [[A (W + S) + B, A E], [Eᵀ / w̄, −σ I]] (x, z) =
        rhs (M + k,); raises ``np.linalg.LinAlgError`` when the system is singular."""
        m, d, _ = A.shape
        k = self.k
        D = A * shift.reshape(m, 1, d) + B
        if self.sparse is not None:
            idx = np.arange(m + 1)
            Ab = sp.bsr_array((A, idx[:-1], idx), shape=(self.n, self.n))
            Db = sp.bsr_array((D, idx[:-1], idx), shape=(self.n, self.n))
            Js = sp.csc_array(Ab @ self.sparse + Db)
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", spla.MatrixRankWarning)
                    lu = spla.splu(Js)
            except RuntimeError as exc:  # "Factor is exactly singular"
                raise np.linalg.LinAlgError(str(exc)) from exc
            x = lu.solve(rhs)
            if not np.all(np.isfinite(x)):
                raise np.linalg.LinAlgError("singular Newton system")
            return np.asarray(x)
        Wr = self.W.reshape(m, d, self.n)
        J = np.einsum("kij,kjn->kin", A, Wr)
        J4 = J.reshape(m, d, m, d)
        ar = np.arange(m)
        J4[ar, :, ar, :] += D
        if not k:
            return np.asarray(np.linalg.solve(J.reshape(self.n, self.n), rhs))
        assert self.E is not None
        AE = np.einsum("kij,kjn->kin", A, self.E.reshape(m, d, k)).reshape(self.n, k)
        Jb = np.block([[J.reshape(self.n, self.n), AE], [self.E.T / wbar, -sigma * np.eye(k)]])
        return np.asarray(np.linalg.solve(Jb, rhs))


@dataclass
class ProximalResult:
    """The outcome of :func:`proximal_newton`."""

    X: FloatArray  # (m, d) pair forces
    s: FloatArray  # (m, d) relative displacement s_free + W X (+ E z)
    residual: float  # max_k |F_k| / fscale of the true problem (and the border's gap)
    iterations: int  # Newton iterations (linear systems solved)
    outer: int  # proximal (outer) iterations
    z: FloatArray  # (k,) the border's unknowns (empty without a border)


def _pair_norm(F: FloatArray) -> FloatArray:
    return np.sqrt(np.einsum("ki,ki->k", F, F))


def proximal_newton(
    op: ShiftedOperator,
    s_free: FloatArray,
    X0: FloatArray,
    law: PairLaw,
    rho: float,
    tol: float,
    fscale: float,
    *,
    e: FloatArray | None = None,
    z0: FloatArray | None = None,
    max_outer: int = 300,
    max_newton: int = 1500,
    sigma0: float = 1e-2,
    sigma_min: float = 1e-6,
    max_inner: int = 60,
    max_stall: int = 30,
) -> ProximalResult:
    """Proximal-point iterations with a semismooth Newton per subproblem (module doc),
    from X0, until max_k |F_k(X, s)| ≤ tol · fscale with F the natural map of parameter
    ``rho`` (the measure of the solver). The subproblems use r_k = 1/mean diag W_kk per
    pair (the same solutions, better balanced when the pairs' flexibilities differ), and
    σ relative to each pair's diagonal: the shift is σ D with D = diag(1/r_k).

    With a border (``op.E``, statics with floating blocks, method.md §5.2) the unknowns
    are X and z (k,), s = s_free + W X + E z, and the equilibrium Eᵀ X = ``e`` joins the
    law; the proximal term acts on z too, as a spring that holds each floating block near
    its last position (a pseudo-dynamic regularisation):

        s̃ = s + σ D (X − X^k),      Eᵀ X − e = σ w̄ (z − z^k),

    whose Jacobian [[A (W + σ D) + B, A E], [Eᵀ/w̄, −σ I]] stays regular where a block
    is nearly free (every pair of it sliding or open near a hinge mechanism), where the
    unregularised Newton meets singular systems. A fixed point solves the original
    problem; the outer measure adds the equilibrium gap |Eᵀ X − e|, row by row relative
    to the row's |E|ᵀ|X| or |e|, whichever is larger. Converging to a fixed point needs an
    equilibrium: where none exists (beyond the limit load) the iterations stall and the
    best iterate is returned, its residual above ``tol``."""
    m, d = X0.shape
    k = op.k
    E = op.E
    if k and (E is None or e is None):
        raise ValueError("a bordered proximal Newton needs the border's right-hand side e")
    diag = np.diag(op.W).reshape(m, d).mean(axis=1)
    wbar = float(diag.mean())
    dpos = np.where(diag > 1e-12 * max(wbar, 1e-300), diag, wbar)
    rk = 1.0 / dpos
    rg = np.full(m, rho)
    X = X0.copy()
    z = np.zeros(k) if z0 is None or not k else np.asarray(z0, dtype=float).copy()

    def border(zv: FloatArray) -> FloatArray:  # E z as (m, d)
        return (E @ zv).reshape(m, d) if k and E is not None else np.zeros((m, d))

    def gap(Xv: FloatArray) -> FloatArray:  # Eᵀ X − e
        return E.T @ Xv.ravel() - e if k and E is not None and e is not None else np.zeros(0)

    def outer_residual(Xv: FloatArray, sv: FloatArray) -> float:
        F, _, _ = natural_map(Xv, sv, law, rg, jac=False)
        r = float(_pair_norm(F).max(initial=0.0)) / fscale
        if k and E is not None:
            # row by row: a rotation's row (lever arms of metres) must not set the
            # measure of a translation's
            size = np.maximum(np.abs(E).T @ np.abs(Xv.ravel()), np.abs(e) if e is not None else 0.0)
            size = np.maximum(size, 1e-12 * float(size.max(initial=0.0)) + 1e-300)
            r = max(r, float((np.abs(gap(Xv)) / size).max(initial=0.0)))
        return r

    s = s_free + op.matvec(X.ravel()).reshape(m, d) + border(z)
    res = outer_residual(X, s)
    sig = sigma0
    floor = sigma_min
    stall = 0
    total = 0
    outer = 0
    best = (res, X.copy(), s.copy(), z.copy())
    while outer < max_outer and total < max_newton and res > tol:
        outer += 1
        shift = (sig * dpos)[:, None]  # σ D, per pair
        Xk, zk = X.copy(), z.copy()
        # the subproblem to well below the outer residual (inexact proximal point)
        target = max(0.1 * tol, 1e-3 * res) * fscale * rk / rho
        target_eq = max(0.1 * tol, 1e-3 * res) * fscale

        def sub(
            Xi: FloatArray, si: FloatArray, zi: FloatArray, jac: bool,
            shift: FloatArray = shift, Xk: FloatArray = Xk, zk: FloatArray = zk,
            sig: float = sig,
        ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:  # fmt: skip
            """The subproblem's natural map and its equilibrium rows (and A, B)."""
            Fi, A, B = natural_map(Xi, si + shift * (Xi - Xk), law, rk, jac=jac)
            Fe = gap(Xi) / wbar - sig * (zi - zk)
            return Fi, Fe, A, B

        ok = False
        why = "iterations"
        Xi, si, zi = X.copy(), s.copy(), z.copy()
        for _ in range(max_inner):
            Fi, Fe, A, B = sub(Xi, si, zi, True)
            if bool((_pair_norm(Fi) <= target).all()) and bool((np.abs(Fe) <= target_eq).all()):
                ok = True
                break
            nF = float(np.sqrt(np.linalg.norm(Fi) ** 2 + np.linalg.norm(Fe) ** 2))
            total += 1
            try:
                dv = op.solve(A, B, np.repeat(shift[:, 0], d), -np.concatenate([Fi.ravel(), Fe]),
                              wbar, sig)  # fmt: skip
            except np.linalg.LinAlgError:
                why = "singular"
                break
            dX, dz = dv[: m * d].reshape(m, d), dv[m * d :]
            dS = op.matvec(dX.ravel()).reshape(m, d) + border(dz)
            step = 1.0
            for _ in range(30):
                X2, z2 = Xi + step * dX, zi + step * dz
                s2 = si + step * dS
                F2, Fe2, _, _ = sub(X2, s2, z2, False)
                if np.sqrt(np.linalg.norm(F2) ** 2 + np.linalg.norm(Fe2) ** 2) <= (
                        1 - 1e-4 * step) * nF:  # fmt: skip
                    break
                step *= 0.5
            else:
                why = f"no descent at {nF:.2e}"
                break  # no descent: the subproblem's Newton failed
            Xi, si, zi = X2, s2, z2
            if total >= max_newton:
                break
        if not ok:
            Fi, Fe, _, _ = sub(Xi, si, zi, False)
            n1 = max(float((_pair_norm(Fi) / target).max(initial=0.0)),
                     float(np.abs(Fe).max(initial=0.0)) / target_eq)  # fmt: skip
            F0, _, _ = natural_map(X, s, law, rg, jac=False)
            n0 = max(float((_pair_norm(F0) * (rk / rho) / target).max(initial=0.0)),
                     float(np.abs(gap(X)).max(initial=0.0)) / wbar / target_eq)  # fmt: skip
            if not n1 <= 0.5 * n0:
                # a harder subproblem than its Newton can take: more regularisation, and
                # not less than that for a while
                sig = min(10.0 * sig, 1e6)
                floor = max(floor, sig)
                log.debug("proximal: subproblem failed (%s), σ → %.1e", why, sig)
                stall += 1
                if stall > max_stall:
                    break
                continue
            # not to its target, but a step forward: an inexact proximal step
        X, s, z = Xi, si, zi
        res = outer_residual(X, s)
        log.debug("proximal %d: σ %.1e, residual %.2e, %d Newton", outer, sig, res, total)
        if res < 0.5 * best[0]:
            stall = 0
        else:
            stall += 1
            if stall > max_stall:
                log.debug("proximal: no progress in %d iterations", max_stall)
                if res < best[0]:
                    best = (res, X.copy(), s.copy(), z.copy())
                break
        if res < best[0]:
            best = (res, X.copy(), s.copy(), z.copy())
        if ok:
            floor = max(sigma_min, 0.5 * floor)
            # tenfold down per subproblem solved with the border (near a hinge mechanism
            # it crawled at 6 % an iteration when tied to the residual); without it, not
            # below the residual (a 30 m block sliding at Δt = 1.25 ms, undamped: a pair
            # problem the faster fall left at 4.5e-5, tests/test_friction_excited.py)
            sig = max(floor, 0.1 * sig) if k else max(floor, 0.1 * sig, min(sig, res))
    res, X, s, z = best
    return ProximalResult(X, s, res, total, outer, z)


__all__ = ["PairLaw", "ProximalResult", "ShiftedOperator", "natural_map", "proximal_newton"]
