"""The ``CVXOPT_MOMENT`` SDP solver of the ROA programs: CVXOPT on the moment form of a program.

An SOS program in Gram form has many more unknowns than equations: the CTOL level program has one 103 x 103 Gram
matrix (5356 entries) and 1746 coefficient equations. An interior-point method on that primal (Clarabel, or cvxpy's
own CVXOPT interface) factors a KKT system with the dense ``n(n+1)/2`` Hessian block of every Gram matrix, about
``5356^3 / 3`` flops per iteration. The dual of the same program, the *moment* problem, has one unknown per
equation: its Newton system is ``m x m`` with ``m`` the number of equations. ``CVXOPT_MOMENT`` rewrites the conic
data cvxpy compiles for Clarabel (``A x + s = b``, ``s`` in zero x nonnegative x PSD cones) into that dual form,

1. eliminating every variable that is a cone slack in disguise (a variable that appears in one cone row only, such
   as each entry of a Gram matrix: ``x_P = D^-1 (b_P - A_PR x_R - s_P)``),
2. dropping linearly dependent free columns and dependent equations,

and hands it to CVXOPT's ``conelp``, whose *dual* is then the SOS program: CVXOPT's ``z`` is the cone slack ``s``
(the Gram matrices) and its ``y`` the remaining free variables. The result goes back to cvxpy exactly as a Clarabel
result would; the residual of the recovered point in the original data is checked, so a dropped equation that was
not redundant shows as a failure, not as a wrong answer.

The route is exact (no relaxation): the same program, solved from the other side. It is the default
(:data:`~glidectl.roa.sdp_solvers.DEFAULT_SOLVER`; ``solver="CLARABEL"`` for Clarabel throughout). It takes programs
with nonnegative and PSD cones only, a nonzero objective, a PSD block of order :attr:`MomentPolicy.min_block` or more,
and a moment form smaller than the primal (:func:`moment_pays`). Everything else goes to Clarabel unchanged: small
programs, programs whose moment form is the larger side (the glider's V steps, with one equation per simulated sample),
second-order or exponential cones, feasibility programs (a zero objective leaves the moment problem without an interior,
and the alternation's next V step is tuned on Clarabel's analytic-centre-like point; where Clarabel's centering is slow,
from a Gram block of order :attr:`MomentPolicy.center_by_level_min_block`, the alternation centers by the level program
capped at the lower level instead, which has an objective and takes the route), and any program CVXOPT does not solve
within :attr:`MomentPolicy.max_iterations`.

Clarabel always runs with :data:`~glidectl.roa.sdp_solvers.CLARABEL_THREADS` (one) thread, whatever the machine's
cores or ``RAYON_NUM_THREADS`` (:func:`~glidectl.roa.sdp_solvers.solver_options`): its parallel factorization would
make a certificate depend on the thread count.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps
from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import CLARABEL
from cvxpy.reductions.solvers.conic_solvers.conic_solver import ConicSolver

from ..errors import ArgumentError
from .sdp_solvers import MOMENT, solver_options

__all__ = ["MOMENT_POLICY", "CvxoptMoment", "MomentPolicy", "moment_form", "moment_pays", "moment_solver",
           "solve_moment"]

@dataclass(frozen=True)
class MomentPolicy:
    """Which programs the moment route takes, and what the SOS alternation does differently because of it.

    Every threshold of the route is here, so that a measurement that moves one changes one field
    (``bench/README.md`` has the measurements behind each).

    Attributes
    ----------
    min_block : int
        Programs whose largest PSD block is smaller than this go to Clarabel: there the primal KKT system is small
        and the reduction in Python costs more than Clarabel's whole solve.
    max_iterations : int
        Iteration limit of CVXOPT on the moment form, above the iterations the ROA programs take to converge; a run
        that does not converge within it goes to Clarabel.
    center_by_level_min_block : int
        Smallest Gram block for which the alternation's centering multiplier comes from the level program re-solved
        with ``rho <= (1 - center) rho*`` on the moment route, instead of the feasibility program by Clarabel
        (Clarabel factors the dense ``n(n+1)/2`` Hessian block of each Gram matrix: slow from about 100 x 100).
        Below it the feasibility program stays: the two give different interior points, and the feasibility
        program's steers the small programs' alternations better.
    quotient_min_block : int
        Programs whose decrease Gram matrix has at least this order match the coefficients of every SOS condition
        modulo the angle equalities ``s^2 + c^2 - 2 c = 0`` of a recast (:mod:`glidectl.roa.quotient`) instead of
        through free multipliers: the same feasible set, fewer equations, which set the order of the moment route's
        dense factorization. Smaller programs keep the multiplier form (their steps are Clarabel's, whose points
        follow the equations as written). ``math.inf``: never; 0: always.
    eliminate_diagonal_min : int or None
        Fewest diagonal columns of the moment form's Schur complement (the V step's sample equations, each in its
        own nonnegative rows) that are eliminated first, exactly (block elimination, Woodbury for the diagonal
        block plus ``A'A``, ``_SparseKKT``), so that the dense factorization is of the other equations only.
        None: never.
    """

    min_block: int = 40
    max_iterations: int = 50
    center_by_level_min_block: int = 64
    quotient_min_block: float = 64
    eliminate_diagonal_min: int | None = 256

    def takes(self, dims: Any, c: np.ndarray) -> bool:
        """Whether a program with cone dimensions ``dims`` (cvxpy's) and objective ``c`` may go to the moment
        route: nonnegative and PSD cones only, a nonzero objective (a feasibility program's moment problem has no
        interior) and a PSD block of order :attr:`min_block` or more; it then goes if :func:`moment_pays`."""
        return not (dims.soc or dims.exp or getattr(dims, "p3d", None) or getattr(dims, "pnd", None)
                    or max(dims.psd, default=0) < self.min_block or not np.any(c))

    def centers_by_level(self, solver: str, largest_block: int) -> bool:
        """Whether the alternation centres its multiplier by the capped level program (see
        :attr:`center_by_level_min_block`): on the moment route with a Gram block that large."""
        return solver == MOMENT and largest_block >= self.center_by_level_min_block

    def uses_quotient(self, n_decrease: int) -> bool:
        """Whether a program with a decrease Gram matrix of order ``n_decrease`` matches coefficients modulo the
        angle equalities (:attr:`quotient_min_block`)."""
        return n_decrease >= self.quotient_min_block


MOMENT_POLICY = MomentPolicy()
"""The policy the ROA layer uses (replace it, e.g. with :func:`dataclasses.replace`, to compare)."""


_MOMENT_INSTANCE: Any = None


def moment_solver() -> Any:
    """The one :class:`CvxoptMoment` instance (cvxpy keeps a compiled problem per solver object)."""
    global _MOMENT_INSTANCE
    if _MOMENT_INSTANCE is None:
        _MOMENT_INSTANCE = CvxoptMoment()
    return _MOMENT_INSTANCE


@dataclass(frozen=True)
class _MomentForm:
    """The conic program ``min c'x, A x + s = b, s in K`` with its cone-slack variables eliminated:
    ``min g'x_R + h's + const, E_R x_R + E_s s = f, s in K`` (``s`` the cone rows of ``A``, in their order)."""

    E_R: sps.csr_matrix
    E_s: sps.csr_matrix
    f: np.ndarray
    g: np.ndarray
    h: np.ndarray
    R: np.ndarray           # free columns of A (x_R)
    P: np.ndarray           # eliminated columns (x_P), one per pivot cone row
    piv: np.ndarray         # the pivot cone rows (indices into s)
    dinv: np.ndarray        # 1 / A[pivot row, pivot column]
    A_pR: sps.csr_matrix    # pivot rows of A on the free columns
    b_p: np.ndarray         # b on the pivot rows

    def primal(self, x_R: np.ndarray, s: np.ndarray, n: int) -> np.ndarray:
        """The variables ``x`` of the original program from ``x_R`` and the cone slack ``s``."""
        x = np.zeros(n)
        x[self.R] = x_R
        x[self.P] = self.dinv * (self.b_p - self.A_pR @ x_R - s[self.piv])
        return x


def moment_form(A: Any, b: np.ndarray, c: np.ndarray, zero: int) -> _MomentForm:
    """Eliminate the variables of ``min c'x, A x + s = b`` that appear in exactly one cone row.

    Parameters
    ----------
    A : sparse matrix, shape (M, n)
        Constraint matrix; rows ``0..zero-1`` are equations (zero cone), the rest cone rows.
    b : ndarray, shape (M,)
    c : ndarray, shape (n,)
    zero : int
        Number of equations.

    Returns
    -------
    _MomentForm
        The reduced program (see the class): a cone row with such a variable ``x_p`` (the largest coefficient
        ``d`` if several) gives ``x_p = (b_p - A_pR x_R - s_p) / d``; the other cone rows become equations
        ``A_nR x_R + s_n = b_n``.
    """
    A = sps.csr_matrix(A)
    A.eliminate_zeros()
    M, n = A.shape
    Az, Ac = A[:zero], A[zero:]
    nc = M - zero
    Acc = Ac.tocoo()
    count = np.bincount(Acc.col, minlength=n)
    ok = (count[Acc.col] == 1) & (b[zero + Acc.row] == 0)      # a bound row (b != 0) stays an equation
    r, col, v = Acc.row[ok], Acc.col[ok], Acc.data[ok]
    order = np.lexsort((-np.abs(v), r))
    r, col, v = r[order], col[order], v[order]
    first = np.r_[True, r[1:] != r[:-1]] if len(r) else np.zeros(0, bool)
    piv, P, d = r[first], col[first], v[first]
    nonpiv = np.setdiff1d(np.arange(nc), piv)
    R = np.setdiff1d(np.arange(n), P)
    dinv = 1.0 / d
    A_pR = Ac[piv][:, R].tocsr()
    Wz = (Az[:, P] @ sps.diags(dinv)).tocsr()              # A_zP D^-1
    E_R = sps.vstack([Az[:, R] - Wz @ A_pR, Ac[nonpiv][:, R]]).tocsr()
    Wc = Wz.tocoo()                                         # -A_zP D^-1 on the pivot slacks
    Es_z = sps.csr_matrix((-Wc.data, (Wc.row, piv[Wc.col])), shape=(zero, nc))
    Es_n = sps.csr_matrix((np.ones(len(nonpiv)), (np.arange(len(nonpiv)), nonpiv)), shape=(len(nonpiv), nc))
    E_s = sps.vstack([Es_z, Es_n]).tocsr()
    bz, bc = b[:zero], b[zero:]
    f = np.concatenate([bz - Wz @ bc[piv], bc[nonpiv]])
    cP = dinv * c[P]
    g = c[R] - A_pR.T @ cP
    h = np.zeros(nc)
    h[piv] = -cP
    return _MomentForm(E_R, E_s, f, g, h, R, P, piv, dinv, A_pR, bc[piv])


def moment_pays(form: _MomentForm, psd: list[int]) -> bool:
    """Whether the moment form is the cheaper side of a program: its dense Schur complement, of the order ``m`` of
    its equations, against the dense Hessian blocks of the primal's Gram matrices (order ``n_b (n_b + 1) / 2`` each,
    what Clarabel factors), compared by the cubes of the orders (the factorization flops, up to a constant).

    Parameters
    ----------
    form : _MomentForm
        The program's moment form (:func:`moment_form`).
    psd : list of int
        Orders of its PSD blocks.

    Returns
    -------
    bool
        True for the CTOL programs (the level program: ``m = 1739`` against one 103 x 103 Gram matrix, 5356; the
        V step: ``m = 2810`` with its 1024 sample equations) and the glider's level programs (``m`` about 480 against
        a 49 x 49 Gram matrix, 1225); False for the glider's V steps (``m = 2550`` with 2048 sample equations).

    Raises
    ------
    None
    """
    m = form.E_R.shape[0]           # equations of the reduced program (the original ones and unpivoted cone rows)
    primal = sum(float(nb * (nb + 1) // 2) ** 3 for nb in psd)
    return float(m) ** 3 < primal


def _drop_rounding(E: Any, rel: float = 1e-14) -> sps.csr_matrix:
    """``E`` without the entries below ``rel`` times its largest one."""
    E = sps.csr_matrix(E, copy=True)
    if E.nnz:
        E.data[np.abs(E.data) < rel * np.max(np.abs(E.data))] = 0.0
        E.eliminate_zeros()
    return E


def _independent_columns(E: sps.csr_matrix, tol: float = 1e-10) -> np.ndarray:
    """Indices of a maximal set of linearly independent columns of ``E`` (QR with column pivoting)."""
    if E.shape[1] == 0:
        return np.zeros(0, int)
    Ed = E.toarray()
    _, Rm, perm = sla.qr(Ed, mode="economic", pivoting=True)
    dg = np.abs(np.diag(Rm))
    if dg.size == 0 or dg[0] == 0.0:
        return np.zeros(0, int)
    rank = int(np.sum(dg > tol * dg[0]))
    return np.sort(perm[:rank])


def _independent_rows(E: sps.csr_matrix, tol: float = 1e-11) -> np.ndarray:
    """Indices of a maximal set of linearly independent rows of ``E`` (rows of unit norm; pivoted Cholesky of
    ``E E'``)."""
    m = E.shape[0]
    if m == 0:
        return np.zeros(0, int)
    G = (E @ E.T).toarray()
    _, piv, rank, info = sla.lapack.dpstrf(G, lower=1, tol=tol)
    if info < 0:
        return np.arange(m)
    return np.sort(piv[:rank] - 1)


def _cone_map(nonneg: int, psd: list[int]) -> tuple[sps.csr_matrix, list[int], np.ndarray]:
    """Map from the cone rows (nonnegative, then PSD blocks in upper-triangular column-major svec with sqrt(2)
    off-diagonal scaling, cvxpy's Clarabel layout) to CVXOPT's unpacked lower storage; returns the map, CVXOPT's
    block orders, and the position of each svec entry."""
    rows, scale = list(range(nonneg)), [1.0] * nonneg
    off = nonneg
    for nb in psd:
        for j in range(nb):
            for i in range(j + 1):
                rows.append(off + i * nb + j)             # column i, row j >= i: lower storage
                scale.append(1.0 if i == j else 1.0 / math.sqrt(2.0))
        off += nb * nb
    pos = np.array(rows, dtype=int)
    S = sps.csr_matrix((np.array(scale), (pos, np.arange(len(pos)))), shape=(off, len(pos)))
    return S, list(psd), pos


class CvxoptMoment(CLARABEL):
    """cvxpy custom solver ``CVXOPT_MOMENT``: CVXOPT's ``conelp`` on the moment (dual) form of the program, for the
    programs the module docstring lists; Clarabel for the others."""

    MIP_CAPABLE = False

    def name(self) -> str:
        return MOMENT

    def import_solver(self) -> None:
        import clarabel  # noqa: F401
        import cvxopt  # noqa: F401

    def supports_quad_obj(self) -> bool:
        return False

    def solve_via_data(self, data: dict, warm_start: bool, verbose: bool, solver_opts: dict,
                       solver_cache: Any = None) -> Any:
        """Solve the Clarabel-form data by CVXOPT on the moment form; return a Clarabel-like result."""
        dims = data[ConicSolver.DIMS]
        # solver_opts are CVXOPT's: a program handed to Clarabel gets Clarabel's defaults and its thread count
        clarabel_opts = solver_options("CLARABEL")
        if not MOMENT_POLICY.takes(dims, data["c"]):
            return super().solve_via_data(data, warm_start, verbose, clarabel_opts, solver_cache)
        mf = moment_form(data["A"], data["b"], data["c"], dims.zero)
        if not moment_pays(mf, list(dims.psd)):
            return super().solve_via_data(data, warm_start, verbose, clarabel_opts, solver_cache)
        res = solve_moment(data["A"], data["b"], data["c"], dims.zero, dims.nonneg, list(dims.psd),
                           verbose=verbose, form=mf, **solver_opts)
        if res.status in ("Solved", "AlmostSolved", "PrimalInfeasible", "DualInfeasible"):
            return res
        # not converged (a program at the edge of feasibility, such as the level of a V the V step has just
        # pushed to its limit, can leave the moment form without a usable interior): Clarabel, from scratch
        out = super().solve_via_data(data, warm_start, verbose, clarabel_opts, solver_cache)
        return SimpleNamespace(x=out.x, z=out.z, s=out.s, status=str(out.status), obj_val=out.obj_val,
                               solve_time=res.solve_time + out.solve_time, iterations=res.iterations + out.iterations)


def solve_moment(A: Any, b: np.ndarray, c: np.ndarray, zero: int, nonneg: int, psd: list[int], *,
                 verbose: bool = False, form: _MomentForm | None = None, **options: Any) -> SimpleNamespace:
    """``min c'x, A x + s = b, s in {0}^zero x R+^nonneg x PSD(psd)`` by CVXOPT on the moment form.

    Parameters
    ----------
    A, b, c
        cvxpy's Clarabel-form data (PSD blocks as upper-triangular svec with sqrt(2) scaling).
    zero, nonneg : int
        Numbers of equation rows and of nonnegative rows.
    psd : list of int
        Orders of the PSD blocks.
    verbose : bool
        CVXOPT's progress output.
    **options
        CVXOPT solver options (``abstol``, ``reltol``, ``feastol``, ``maxiters``, ``kktsolver``). A run that
        meets a Schur complement that is not numerically positive definite stops there (:func:`_cholesky`); its
        last iterate is ``AlmostSolved`` when its residuals are below 1e-5.

    Returns
    -------
    types.SimpleNamespace
        ``x``, ``z`` (None: no duals), ``s``, ``status`` (Clarabel's status names), ``obj_val``, ``solve_time``,
        ``iterations``, ``residual`` (relative residual of ``A x + s - b`` on the original data).

    Raises
    ------
    ArgumentError
        If ``c`` is zero (a feasibility program: its moment problem has no interior).
    """
    from cvxopt import matrix, solvers

    t0 = time.perf_counter()
    b = np.asarray(b, dtype=float)
    c = np.asarray(c, dtype=float)
    if not np.any(c):
        raise ArgumentError("solve_moment needs a nonzero objective: the moment problem of a feasibility program "
                            "has no interior (CVXOPT_MOMENT hands such programs to Clarabel)")
    n = c.size
    mf = moment_form(A, b, c, zero) if form is None else form
    # a nonnegative row that stays an equation (a bound x_j <= b_i) gets its slack in units of |b_i|: a cap such
    # as rho <= 1e6 would otherwise put 1e6 into the moment objective next to terms of order 1e-3
    w = np.ones(len(mf.h))
    bound = np.setdiff1d(np.arange(nonneg), mf.piv)
    w[bound] = np.maximum(1.0, np.abs(b[zero + bound]))
    E_R, E_s, f0, g0, h0 = mf.E_R, (mf.E_s @ sps.diags(w)).tocsr(), mf.f, mf.g, mf.h * w
    # coefficients at rounding level (cvxpy's canonicalization leaves some of 1e-19) would become constraints of
    # order one when the rows are normalized below: drop them first
    E_R, E_s = _drop_rounding(E_R), _drop_rounding(E_s)
    keep = _independent_columns(E_R)
    E = sps.hstack([E_R[:, keep], E_s]).tocsr()
    norms = np.sqrt(np.asarray(E.multiply(E).sum(axis=1)).ravel())
    live = norms > 0
    if np.any(~live) and np.any(np.abs(f0[~live]) > 0):
        return _result(None, None, "PrimalInfeasible", math.nan, t0, 0, math.inf)
    scale = np.where(live, 1.0 / np.where(live, norms, 1.0), 0.0)
    E = sps.diags(scale) @ E
    rows = np.flatnonzero(live)
    rows = rows[_independent_rows(E[rows])]
    E = E[rows].tocsr()
    f = f0[rows] * scale[rows]
    nR = len(keep)
    Emap, blocks, pos = _cone_map(nonneg, psd)
    G = (Emap @ E[:, nR:].T).tocoo()
    h = Emap @ h0
    AeqT = E[:, :nR].T.tocoo()

    opts = {"show_progress": bool(verbose), "maxiters": MOMENT_POLICY.max_iterations}
    opts.update(options)
    kkt = opts.pop("kktsolver", "sparse")
    cvx_dims = {"l": nonneg, "q": [], "s": blocks}
    if kkt == "sparse":
        kkt = _SparseKKT(G.tocsr(), AeqT.tocsr(), nonneg, blocks)
    kw: dict[str, Any] = {"options": opts, "kktsolver": kkt}
    if nR:
        kw["A"], kw["b"] = _cvx_sparse(AeqT), matrix(g0[keep])
    sol = solvers.conelp(matrix(-f), _cvx_sparse(G), matrix(h), cvx_dims, **kw)
    st = sol["status"]
    if st == "dual infeasible":             # CVXOPT's dual is the program: infeasible
        return _result(None, None, "PrimalInfeasible", math.inf, t0, int(sol.get("iterations", 0)), math.inf)
    if st == "primal infeasible":           # CVXOPT's primal (the moment problem) infeasible: unbounded
        return _result(None, None, "DualInfeasible", -math.inf, t0, int(sol.get("iterations", 0)), math.inf)
    if sol["z"] is None:
        return _result(None, None, "NumericalError", math.nan, t0, int(sol.get("iterations", 0)), math.inf)
    z = np.array(sol["z"]).ravel()
    s = z[pos] / np.asarray(Emap.sum(axis=0)).ravel()
    x_R = np.zeros(E_R.shape[1])
    if nR:
        x_R[keep] = np.array(sol["y"]).ravel()
    s = s * w
    x = mf.primal(x_R, s, n)
    sfull = np.concatenate([np.zeros(zero), s])
    res = float(np.linalg.norm(sps.csr_matrix(A) @ x + sfull - b) / (1.0 + np.linalg.norm(b)))
    if st == "optimal":
        status = "Solved" if res < 1e-6 else "AlmostSolved"
    else:                                   # "unknown": stopped early (iterations, or a singular KKT system)
        ok = all(sol.get(k) is not None and sol[k] < 1e-5 for k in ("primal infeasibility", "dual infeasibility"))
        status = "AlmostSolved" if ok and res < 1e-5 else "InsufficientProgress"
    if res > 1e-4 and status in ("Solved", "AlmostSolved"):
        status = "NumericalError"
    return _result(x, s, status, float(c @ x), t0, int(sol.get("iterations", 0)), res)


_KKT_CHUNK = 256      # columns of a PSD block whose S G_l S are formed at once by _SparseKKT


class _SparseKKT:
    """CVXOPT KKT solver for ``conelp`` that forms the Schur complement ``H = G' (W'W)^-1 G`` block by block from
    the sparse columns of ``G``: for a PSD block with scaling ``W(Z) = r' Z r``, ``(W'W)^-1 Z = S Z S`` with
    ``S = r^-T r^-1``, and ``H_kl = <G_k, S G_l S>`` (CVXOPT's own ``chol``/``qr`` solvers scale and factor the
    dense ``N x m`` matrix ``W^-T G`` instead). A column ``G_l`` of a moment matrix has nonzero entries in a few
    rows ``R_l`` only (those ``p`` with ``alpha_l - b_p`` in the basis), so ``S G_l S = S[:, R_l] (G_l S)[R_l, :]``
    costs ``|R_l| nb^2`` instead of ``nb^3``: the columns are grouped by ``|R_l|`` and each group is one batched
    product. The equations ``A u = b`` enter as ``[H + A'A, A'; A, 0]`` (``A'A`` formed once), solved by two
    Cholesky factorizations."""

    def __init__(self, G: sps.csr_matrix, AeqT: sps.csr_matrix, nonneg: int, blocks: list[int]) -> None:
        self.G, self.m = G, G.shape[1]
        self.Aeq = AeqT.toarray() if AeqT.shape[0] else np.zeros((0, self.m))
        self.AtA = self.Aeq.T @ self.Aeq
        self.nonneg = nonneg
        self.Gl = G[:nonneg].tocsc()
        self.blocks = []
        off = nonneg
        for nb in blocks:
            Gk = G[off:off + nb * nb].tocoo()
            J = np.unique(Gk.col)
            jl = np.searchsorted(J, Gk.col)
            i, j = Gk.row % nb, Gk.row // nb          # lower storage: column j, row i >= j
            sym = i != j
            # full storage of every column: entry (row p, column q) of G_l
            lf = np.concatenate([jl, jl[sym]])
            pf = np.concatenate([i, j[sym]])
            qf = np.concatenate([j, i[sym]])
            vf = np.concatenate([Gk.data, Gk.data[sym]])
            # the rows R_l of each column, numbered 0..|R_l|-1 within it
            key = np.unique(lf * nb + pf)
            kl, kp = key // nb, key % nb
            r = np.bincount(kl, minlength=len(J))
            start = np.concatenate([[0], np.cumsum(r)[:-1]])
            slot = np.searchsorted(key, lf * nb + pf) - start[lf]
            groups = []
            for rg in np.unique(r[r > 0]):
                cols = np.flatnonzero(r == rg)                     # columns (positions in J) with rg rows
                at = np.full(len(J), -1)
                at[cols] = np.arange(len(cols))
                sel = at[lf] >= 0
                Gv = sps.csr_matrix((vf[sel], (at[lf[sel]] * rg + slot[sel], qf[sel])), shape=(len(cols) * rg, nb))
                Rg = kp[(start[cols][:, None] + np.arange(rg)[None, :])]     # (len(cols), rg) row indices
                groups.append((cols, int(rg), Gv, Rg))
            w = np.where(sym, 2.0, 1.0) * Gk.data
            Gw = sps.csr_matrix((w, (jl, np.arange(len(w)))), shape=(len(J), len(w)))
            self.blocks.append((nb, J, groups, Gw, i, j))
            off += nb * nb
        from cvxopt import misc
        self.misc = misc
        self.dims = {"l": nonneg, "q": [], "s": list(blocks)}
        # the diagonal columns: in nonnegative rows only, rows no other column has (the V step's sample equations)
        self.diag = None
        least = MOMENT_POLICY.eliminate_diagonal_min
        if least is not None and nonneg and self.Aeq.shape[0]:
            Gn = self.Gl.tocoo()
            shared = np.bincount(Gn.row, minlength=nonneg) > 1
            bad = np.zeros(self.m, dtype=bool)
            bad[Gn.col[shared[Gn.row]]] = True
            bad[np.unique(G[nonneg:].tocoo().col)] = True
            has = np.zeros(self.m, dtype=bool)
            has[Gn.col] = True
            S = np.flatnonzero(has & ~bad)
            if len(S) >= least:
                self.diag = (S, np.setdiff1d(np.arange(self.m), S))

    def schur(self, W: Any) -> np.ndarray:
        """``H = G' (W'W)^-1 G`` (symmetric, ``m x m``) for CVXOPT's scaling ``W`` (its ``"d"`` and ``"rti"``)."""
        H = np.zeros((self.m, self.m))
        if self.nonneg:
            d = np.array(W["d"]).ravel()
            Gl = sps.diags(1.0 / d) @ self.Gl
            P = (Gl.T @ Gl).tocoo()
            P.sum_duplicates()                  # (a product has none): then bitwise H += P.toarray()
            H[P.row, P.col] += P.data
        for (nb, J, groups, Gw, i, j), rti in zip(self.blocks, W["rti"], strict=True):
            R = np.array(rti)
            S = R @ R.T
            # (|J|, T): S G_l S at G's lower positions. Column-major, so that Ylow.T is C-contiguous: SciPy's sparse
            # times dense copies a dense operand that is not (Ylow.T of a C-ordered Ylow: a copy of the whole array
            # per call, tens of MB on the largest blocks), and the product reads the same numbers either way
            Ylow = np.zeros((len(J), len(i)), order="F")
            for cols, rg, Gv, Rg in groups:
                B = np.asarray(Gv @ S).reshape(len(cols), rg, nb)           # (G_l S)[R_l, :]
                SR = S[:, Rg].transpose(1, 0, 2)                            # S[:, R_l]: (len(cols), nb, rg)
                for a in range(0, len(cols), _KKT_CHUNK):                   # (bounded memory)
                    Ylow[cols[a:a + _KKT_CHUNK]] = np.matmul(SR[a:a + _KKT_CHUNK], B[a:a + _KKT_CHUNK])[:, i, j]
            H[np.ix_(J, J)] += np.asarray(Gw @ Ylow.T)
        # in place: bitwise 0.5 * (H + H.T), with one m x m array fewer (NumPy copies the overlapping H.T)
        H += H.T
        H *= 0.5
        return H

    def _factor(self, W: Any) -> Any:
        """``K = H + A'A`` factored: a function ``R -> K^-1 R``."""
        K = self.schur(W)
        if self.diag is None:
            K += self.AtA
            Lh = _cholesky(K)
            return lambda R: sla.cho_solve(Lh, R, check_finite=False)
        # K = [[D + As'As, As'Ac], [Ac'As, Hcc + Ac'Ac]] with D diagonal: (D + As'As)^-1 by Woodbury through
        # I + N, N = As D^-1 As' (p x p, p the free unknowns), and the Schur complement Hcc + Ac'(I + N)^-1 Ac
        S, C = self.diag
        D = np.diag(K)[S].copy()
        A = self.Aeq
        As, Ac = A[:, S], A[:, C]
        AsD = As / D
        Li = _cholesky(np.eye(A.shape[0]) + AsD @ As.T)
        Kc = K[np.ix_(C, C)]
        Kc += Ac.T @ sla.cho_solve(Li, Ac, check_finite=False)
        Lc = _cholesky(Kc)

        def kss_inv(V: np.ndarray) -> np.ndarray:
            T = V / D[:, None]
            return T - AsD.T @ sla.cho_solve(Li, As @ T, check_finite=False)

        def solve(R: np.ndarray) -> np.ndarray:
            R2 = R.reshape(len(R), -1)
            Y = kss_inv(R2[S])
            XC = sla.cho_solve(Lc, R2[C] - Ac.T @ (As @ Y), check_finite=False)
            X = np.empty_like(R2)
            X[C] = XC
            X[S] = kss_inv(R2[S] - As.T @ (Ac @ XC))
            return X.reshape(R.shape)

        return solve

    def __call__(self, W: Any) -> Any:
        from cvxopt import matrix
        misc = self.misc
        A = self.Aeq
        kinv = self._factor(W)
        if A.shape[0]:
            # A (H + A'A)^-1 A' as A times the solve, not as X'X with X = L^-1 A' (symmetric by construction):
            # near the end of a run whose Schur complement becomes singular, this product loses definiteness first
            # and stops CVXOPT at a good iterate; X'X lets the run go on for a few more iterations to a point whose
            # residuals are larger and fail the Gram check (measurements: bench/README.md)
            HiAt = kinv(A.T)
            Lk = _cholesky(A @ HiAt)
        G, dims = self.G, self.dims
        Gc = _cvx_sparse(G)

        def solve(x: Any, y: Any, z: Any) -> None:
            v = matrix(z)
            misc.scale(v, W, trans="T", inverse="I")
            misc.scale(v, W, trans="N", inverse="I")
            gu = matrix(0.0, (self.m, 1))
            misc.sgemv(Gc, v, gu, dims, trans="T")
            bx = np.array(x).ravel() + np.array(gu).ravel()
            by = np.array(y).ravel()
            rt = bx + A.T @ by
            if A.shape[0]:
                uy = sla.cho_solve(Lk, A @ kinv(rt) - by, check_finite=False)
                ux = kinv(rt - A.T @ uy)
            else:
                uy = np.zeros(0)
                ux = kinv(rt)
            t = matrix(G @ ux) - z
            misc.scale(t, W, trans="T", inverse="I")
            x[:] = matrix(ux)
            if A.shape[0]:
                y[:] = matrix(uy)
            z[:] = t

        return solve


def _cholesky(H: np.ndarray) -> Any:
    """Cholesky factor of a Schur complement, or ArithmeticError if it is not numerically positive definite: CVXOPT
    then stops with its last iterate. Near the optimum of a program whose optimal face is not a point, rounding
    takes the definiteness away. The factor is not regularized (e.g. ``1e-12 max(diag H)`` added to the diagonal):
    that sends the iterates off there, the V step's dual residual growing by orders of magnitude until the iteration
    limit hands it and the next level program to Clarabel. Stopping leaves the V step at a small relative gap, which
    is all it needs (the V step only steers the search; the level program that follows certifies the V it returns).

    So where this factorization fails is part of the method, and a cheaper factorization of the same ``K`` is not a
    drop-in. Eliminating the V step's sample columns first (:attr:`MomentPolicy.eliminate_diagonal_min`,
    :meth:`_SparseKKT._factor`) is exact: their block of ``H`` is diagonal, so ``K_ss = D + A_s'A_s`` inverts by
    Woodbury and the rest is the Schur complement ``H_cc + A_c'(I + N)^-1 A_c`` of the other equations, a smaller
    dense factorization. But it stays numerically positive definite where the whole ``K`` does not, so a V step
    solved to CVXOPT's default tolerances runs on to the iteration limit and to Clarabel, and ends at a smaller
    ``V``. The V step stops at :data:`~glidectl.roa.sdp_solvers.STEERING_TOLERANCES`, before that singular end, so
    the elimination is used for the V steps the moment route takes, at the same objective in less time. Which
    programs the route takes is still decided by the whole ``m`` (:func:`moment_pays`): counting the eliminated
    equations out of it would send the saturated user glider's V steps (54 x 54 Gram matrix) to the moment route,
    where they end on a point of their optimal face whose level program has a negative ``rho`` (Clarabel's point
    gives a positive one) and the certified volume collapses. Measurements: ``bench/README.md``."""
    try:
        return sla.cho_factor(H, lower=True, check_finite=False)
    except np.linalg.LinAlgError as exc:
        raise ArithmeticError(f"Schur complement not positive definite: {exc}") from exc


def _cvx_sparse(M: Any) -> Any:
    from cvxopt import spmatrix
    M = M.tocoo()
    return spmatrix(M.data.tolist(), M.row.tolist(), M.col.tolist(), size=M.shape)


def _result(x: Any, s: Any, status: str, obj: float, t0: float, iters: int, res: float) -> SimpleNamespace:
    return SimpleNamespace(x=x, z=None, s=s, status=status, obj_val=obj, solve_time=time.perf_counter() - t0,
                           iterations=iters, residual=res)
