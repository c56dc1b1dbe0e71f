"""Sum-of-squares programs in cvxpy with sparse coefficient matching.

The unknowns of an SOS program are polynomials with free coefficients (:meth:`SOSProgram.free_poly`), SOS
polynomials given by a positive semidefinite Gram matrix on a monomial basis (:meth:`SOSProgram.sos_poly`) and
scalars (:meth:`SOSProgram.scalar`). Every expression the algorithms write is *affine* in the unknowns: a
:class:`LinPoly` is a constant polynomial plus, for each unknown, one known polynomial per unknown coefficient (the
columns of a linear map). ``expr in SOS`` (:meth:`SOSProgram.add_sos`) introduces a Gram matrix ``Q >= 0`` and the
equalities ``coeff_alpha(expr) = sum_{b_i + b_j = alpha} Q_ij`` for every monomial ``alpha``, assembled as one
``scipy.sparse`` matrix per unknown and passed to cvxpy as ``A @ x + b == 0``. With a :attr:`SOSProgram.quotient`
(the angle equalities of a recast), the coefficients are those of the normal forms modulo its equalities
(:mod:`glidectl.roa.quotient`), and so are the residuals of the check.

After the solve, :meth:`SOSProgram.check` recomputes every SOS constraint in floating point from the solved
unknowns, with every SOS multiplier made exactly SOS first (its Gram matrix shifted to positive semidefinite,
:meth:`SOSProgram.multiplier_values`), and returns the smallest Gram eigenvalue and the coefficient residual: when
``lambda_min(Q) > n_basis * max|residual|`` the residual can be absorbed in ``Q`` (a symmetric matrix ``R`` with
``m^T R m = residual`` has ``||R||_2 <= n_basis max|r|``), so the polynomial is exactly SOS. The check also forms
that ``R`` (the residual spread evenly over the Gram entries that reach each monomial) and takes the smallest
eigenvalue of ``Q + R`` itself (:class:`GramCheck`, projection), which is never the weaker test.

**Basis reduction** (:func:`reduce_basis`, applied by :meth:`SOSProgram.add_sos`): the support ``S`` of ``expr``
is known before the solve (the union of the supports of its constant part and of every column, an outer
approximation whatever the unknowns are). Every Gram decomposition ``m^T Q m = p`` is an SOS decomposition
``sum_k (v_k . m)^2``, whose squares have supports in half the Newton polytope of ``p``, inside ``conv(S) / 2``; so
a monomial ``b`` of the half basis with ``2 b`` outside ``conv(S)`` (tested on the faces ``+-e_i`` and ``+-1``), or
whose diagonal entry ``Q_bb`` can only feed the coefficient of ``2 b`` (``2 b`` not in ``S`` and not the sum of two
other basis monomials: then ``Q_bb = 0`` and its row vanishes), has a zero row in every feasible ``Q`` and is
dropped (iterated). **Sign symmetry**: every ``s in {0, 1}^n`` with ``s . alpha`` even for all ``alpha in S`` (a
subspace over GF(2)) gives ``p(D_s z) = p(z)``, ``D_s = diag((-1)^s)``; averaging ``Q`` over that group keeps it
feasible (and does not lower its smallest eigenvalue) and zeroes the entries between monomials of different parity
classes ``(s_k . b mod 2)_k``: the Gram matrix splits into one block per class. Both reductions are exact: the
reduced program is feasible iff the full one is, with the same optimal value.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sps

from ..errors import ArgumentError, BudgetError, SolverError
from .blas_threads import pinned_blas
from .polynomial import Exp, Poly
from .sdp_solvers import DEFAULT_SOLVER, inaccuracy_checked, solver_argument, solver_options

__all__ = ["GRAM_CONES", "GramCheck", "LinPoly", "SOSProgram", "Unknown", "dd_gram", "linear_support",
           "parity_generators", "reduce_basis", "sign_classes"]

#: Cones of a Gram matrix (:attr:`SOSProgram.cone`): ``"sos"`` positive semidefinite (SDP), ``"sdsos"`` scaled
#: diagonally dominant (SOCP), ``"dsos"`` diagonally dominant (LP) (Ahmadi and Majumdar 2019). SDD and DD matrices are
#: positive semidefinite, so an SDSOS/DSOS certificate is an SOS one (an inner approximation: a smaller feasible set).
GRAM_CONES = ("sos", "sdsos", "dsos")


def parity_generators(support: Sequence[Exp], nvars: int) -> np.ndarray:
    """Generators of the sign symmetries of a support: a basis over GF(2) of ``{s in {0,1}^n : s . alpha even for
    every alpha in support}`` (each ``s`` flips the signs of the variables where ``s_i = 1`` and leaves every
    polynomial with that support unchanged).

    Parameters
    ----------
    support : sequence of exponent tuples
        Monomials (each of length ``nvars``).
    nvars : int
        Number of variables.

    Returns
    -------
    numpy.ndarray of int, shape (k, nvars)
        ``k`` independent generators (``k = 0``: no sign symmetry).
    """
    M = np.array([[e % 2 for e in a] for a in support], dtype=np.uint8).reshape(-1, nvars)
    M = M[np.any(M, axis=1)]
    pivots: list[int] = []
    r = 0
    for c in range(nvars):                     # reduced row echelon form over GF(2)
        if r >= M.shape[0]:
            break
        rows = np.flatnonzero(M[r:, c]) + r
        if rows.size == 0:
            continue
        M[[r, rows[0]]] = M[[rows[0], r]]
        for i in np.flatnonzero(M[:, c]):
            if i != r:
                M[i] ^= M[r]
        pivots.append(c)
        r += 1
    gens = []
    for f in (c for c in range(nvars) if c not in pivots):
        s = np.zeros(nvars, dtype=int)
        s[f] = 1
        for i, pc in enumerate(pivots):
            s[pc] = int(M[i, f])
        gens.append(s)
    return np.array(gens, dtype=int).reshape(-1, nvars)


def sign_classes(basis: Sequence[Exp], gens: np.ndarray) -> list[list[Exp]]:
    """Split ``basis`` by parity class ``(s_k . b mod 2)_k`` under the generators ``gens``
    (:func:`parity_generators`); one class (the whole basis) without generators.

    Parameters
    ----------
    basis : sequence of exponent tuples
    gens : numpy.ndarray, shape (k, nvars)

    Returns
    -------
    list of list of tuple
        The classes, each in the order of ``basis``, ordered by first appearance.
    """
    out: dict[tuple[int, ...], list[Exp]] = {}
    G = np.asarray(gens, dtype=int)
    for b in basis:
        key = tuple(int(v) for v in (G @ np.asarray(b, dtype=int)) % 2) if G.size else ()
        out.setdefault(key, []).append(tuple(b))
    return list(out.values())


def _pair_sums(B: Sequence[Exp], distinct: bool) -> set[Exp]:
    out: set[Exp] = set()
    for i, a in enumerate(B):
        for b in B[i + 1 if distinct else i:]:
            out.add(tuple(x + y for x, y in zip(a, b, strict=True)))
    return out


def reduce_basis(support: Sequence[Exp], half_basis: Sequence[Exp], *,
                 symmetry: bool = True) -> list[list[Exp]]:
    """Exact reduction of the half basis of an SOS constraint ``p = m^T Q m`` whose polynomial ``p`` has its support
    inside ``support`` (see the module docstring): Newton-polytope faces and diagonal consistency drop monomials
    whose row of ``Q`` must vanish, and sign symmetries split the rest into the blocks of a block-diagonal ``Q``.

    Parameters
    ----------
    support : sequence of exponent tuples
        An outer approximation of the support of ``p`` (every monomial it may have).
    half_basis : sequence of exponent tuples
        The candidate monomials ``m``.
    symmetry : bool
        Split by sign symmetry (else one block).

    Returns
    -------
    list of list of tuple
        The blocks (empty when no monomial survives: then ``p`` must be zero).
    """
    S = {tuple(a) for a in support}
    B = [tuple(b) for b in half_basis]
    if not S or not B:
        return []
    n = len(B[0])
    A = np.array(sorted(S), dtype=float).reshape(-1, n)
    dirs = np.vstack([np.eye(n), -np.eye(n), np.ones((1, n)), -np.ones((1, n))])
    top = np.max(A @ dirs.T, axis=0)
    Bm = np.array(B, dtype=float)
    keep = np.all(2 * Bm @ dirs.T <= top + 1e-9, axis=1)
    B = [b for b, k in zip(B, keep, strict=True) if k]
    while B:                                    # diagonal consistency, iterated
        sums = _pair_sums(B, distinct=True)
        drop = {b for b in B if tuple(2 * x for x in b) not in S and tuple(2 * x for x in b) not in sums}
        if not drop:
            break
        B = [b for b in B if b not in drop]
    if not B:
        return []
    if not symmetry:
        return [B]
    return sign_classes(B, parity_generators(sorted(S), n))


def dd_gram(n: int, name: str, cone: str) -> tuple[Any, list[Any]]:
    """A symmetric ``n x n`` Gram matrix in an inner approximation of the PSD cone, as an affine cvxpy expression of
    new variables and the constraints on them (Ahmadi and Majumdar, "DSOS and SDSOS optimization", 2019).

    ``cone="sdsos"``: ``Q = diag(d) + sum_{i<j} E_ij^T M_ij E_ij`` with ``d >= 0`` and every ``2 x 2`` block
    ``M_ij = [[a, b], [b, c]]`` positive semidefinite (``||(2 b, a - c)|| <= a + c``, one 3-dimensional second-order
    cone per pair): ``Q`` is scaled diagonally dominant. ``cone="dsos"``: the same with ``a = c >= |b|`` (linear
    inequalities): ``Q`` is diagonally dominant with a nonnegative diagonal. Both are sums of PSD matrices, hence PSD.

    Parameters
    ----------
    n : int
        Size of the Gram matrix (>= 1).
    name : str
        Prefix of the cvxpy variable names.
    cone : {"sdsos", "dsos"}
        The cone.

    Returns
    -------
    (cvxpy.Expression of shape (n, n), list of cvxpy constraints)

    Raises
    ------
    ArgumentError
        If ``cone`` is not ``"sdsos"`` or ``"dsos"`` or ``n < 1``.
    """
    if cone not in ("sdsos", "dsos") or n < 1:
        raise ArgumentError(f"dd_gram needs cone 'sdsos' or 'dsos' and n >= 1, got cone={cone!r}, n={n}")
    d = cp.Variable(n, nonneg=True, name=f"{name}.d")
    diag = np.arange(n) * (n + 1)                               # column-major index of (i, i)
    Sd = sps.csr_matrix((np.ones(n), (diag, np.arange(n))), shape=(n * n, n))
    vec: Any = Sd @ d
    cons: list[Any] = []
    if n > 1:
        I, J = np.triu_indices(n, 1)
        P = len(I)
        k = np.arange(P)
        b = cp.Variable(P, name=f"{name}.b")
        a = cp.Variable(P, name=f"{name}.a")
        Sa = sps.csr_matrix((np.ones(P), (I * (n + 1), k)), shape=(n * n, P))
        Sc = sps.csr_matrix((np.ones(P), (J * (n + 1), k)), shape=(n * n, P))
        Sb = sps.csr_matrix((np.ones(2 * P), (np.concatenate([I + n * J, J + n * I]), np.concatenate([k, k]))),
                            shape=(n * n, P))
        if cone == "sdsos":
            c = cp.Variable(P, name=f"{name}.c")
            cons.append(cp.SOC(a + c, cp.vstack([2 * b, a - c]), axis=0))
            vec = vec + Sa @ a + Sc @ c + Sb @ b
        else:
            cons += [a >= b, a >= -b]
            vec = vec + (Sa + Sc) @ a + Sb @ b
    return cp.reshape(vec, (n, n), order="F"), cons


@dataclass(eq=False)
class Unknown:
    """An unknown of the program: ``size`` scalars (a vector, or a Gram matrix flattened column-major)."""

    name: str
    var: cp.Variable
    size: int
    basis: list[Exp] | None = None      # free/SOS polynomials: their monomial basis (Gram: the half basis)
    gram: bool = False
    nvars: int = 0

    @property
    def flat(self) -> Any:
        return cp.vec(self.var, order="F") if self.gram else self.var

    def value(self) -> np.ndarray:
        if self.var.value is None:
            raise SolverError(f"unknown '{self.name}' has no value: the SDP was not solved")
        return np.asarray(self.var.value, dtype=float)

    def poly(self) -> Poly:
        """The solved polynomial (free or SOS unknowns)."""
        v = self.value()
        t: dict[Exp, float] = {}
        if self.gram:
            Q = 0.5 * (v + v.T)
            n = len(self.basis)
            for i in range(n):
                for j in range(n):
                    e = tuple(a + b for a, b in zip(self.basis[i], self.basis[j], strict=True))
                    t[e] = t.get(e, 0.0) + Q[i, j]
        else:
            for e, c in zip(self.basis, v.ravel(), strict=True):
                t[e] = t.get(e, 0.0) + float(c)
        return Poly(t, self.nvars)


class LinPoly:
    """Polynomial affine in the unknowns: ``const + sum_u sum_k x_u[k] cols_u[k]``."""

    def __init__(self, const: Poly, parts: dict[Unknown, list[Poly]] | None = None) -> None:
        self.const = const
        self.parts: dict[Unknown, list[Poly]] = parts or {}

    @property
    def nvars(self) -> int:
        return self.const.nvars

    def __add__(self, other: Any) -> LinPoly:
        if isinstance(other, Poly) or np.isscalar(other):
            return LinPoly(self.const + other, dict(self.parts))
        parts = {u: list(c) for u, c in self.parts.items()}
        for u, cols in other.parts.items():
            if u in parts:
                parts[u] = [a + b for a, b in zip(parts[u], cols, strict=True)]
            else:
                parts[u] = list(cols)
        return LinPoly(self.const + other.const, parts)

    __radd__ = __add__

    def __neg__(self) -> LinPoly:
        return self * -1.0

    def __sub__(self, other: Any) -> LinPoly:
        return self + (-other)

    def __mul__(self, k: Any) -> LinPoly:
        """Product with a known polynomial or scalar."""
        return LinPoly(self.const * k, {u: [c * k for c in cols] for u, cols in self.parts.items()})

    __rmul__ = __mul__

    def lie(self, F: Sequence[Poly]) -> LinPoly:
        """Lie derivative along ``F`` (linear, so applied column by column)."""
        return LinPoly(self.const.lie(F), {u: [c.lie(F) for c in cols] for u, cols in self.parts.items()})

    def value(self, values: Mapping[Unknown, np.ndarray] | None = None) -> Poly:
        """The polynomial at the solved unknowns (``values[u]`` instead of ``u.value()`` where given)."""
        t = dict(self.const.terms)          # accumulated in place: one pass over the columns' terms
        for u, cols in self.parts.items():
            v = (values[u] if values is not None and u in values else u.value()).ravel(order="F")
            for c, x in zip(cols, v, strict=True):
                if x != 0.0 and not c.is_zero:
                    xf = float(x)
                    for e, ce in c.terms.items():
                        t[e] = t.get(e, 0.0) + ce * xf
        return Poly(t, self.nvars)


@dataclass(frozen=True)
class GramCheck:
    """Floating-point check of one SOS constraint after the solve.

    ``slack = lambda_min(Q) - n_basis max|residual|`` (positive means exactly SOS, see the module docstring);
    ``margin = lambda_min(Q) / (n_basis max|residual|)`` (``>= 1`` holds; ``inf`` for a zero residual and
    ``lambda_min(Q) > 0``); each the better of that and the same number for the projected Gram matrix (below);
    ``passed`` is ``slack > 0`` (equivalently ``margin > 1``). The residual is that of the
    constraint with every SOS multiplier made exactly SOS first (``multiplier_shift``, see
    :meth:`SOSProgram.multiplier_values`).

    A residual of degree 0 or 1 on a half basis without the constant (the decrease condition: the multipliers of
    cuts have no constant monomial, so that their terms ``tau g`` bring no constant for the solver to leave at its
    tolerance; the equality multipliers' ``psi_j(0) h_j`` meet ``lambda dV/dt`` on the linear ``c`` terms, which
    :meth:`SOSProgram.check` cancels exactly where it can) cannot be absorbed into the Gram matrix
    near ``z = 0``: it is ``low = (|c_0|, |c_1|)``, and the constraint holds where
    ``slack |z|^2 >= |c_0| + |c_1| |z|``, i.e. for ``|z| >= radius`` (``radius = 0`` without such residual; ``inf``
    if the basis lacks a degree-1 monomial). Inside that ball something else must hold (the local check of the
    surrogate routes of :func:`glidectl.certify_roa`). ``slack`` still counts it as if it were absorbable.

    **Projection** (as Peyrl and Parrilo's rounding of an SOS certificate, in floating point): the residual ``r_a``
    on each monomial ``a`` that pairs of the half basis reach is spread evenly over those pairs, ``R_ij = r_a / n_a``
    for the ``n_a`` ordered pairs with ``b_i + b_j = a``, so that ``m^T (Q + R) m`` matches the constraint up to
    rounding; ``projected_min_eig = lambda_min(Q + R)`` and ``projected_residual`` is what is left (rounding, and
    residuals on monomials no pair reaches). Since ``||R||_2 <= ||R||_F <= n_basis max|r|``, the projected check
    passes whenever the unprojected one does; it passes in addition where the solver's residual, though small, is
    not small against ``lambda_min(Q) / n_basis``. ``slack`` and ``margin`` take the better of the two.
    """

    name: str
    n_basis: int
    min_eig: float
    max_residual: float
    multiplier_shift: float = 0.0   # largest ``delta`` added to a multiplier's Gram matrix (``Q + delta I >= 0``)
    low: tuple[float, float] = (0.0, 0.0)   # unreachable residual of degree 0 and 1: (|c_0|, norm of c_1)
    full_linear: bool = True        # the half basis has every degree-1 monomial
    projected_min_eig: float = -math.inf    # lambda_min(Q + R): the residual spread over the Gram entries
    projected_residual: float = math.inf    # what is left of the residual after that (rounding, unreachable terms)

    @property
    def radius(self) -> float:
        """Below this ``|z|`` the unreachable low-degree residual ``low`` may outweigh the Gram matrix: the
        constraint is proved for ``|z| >= radius`` only (see the class docstring)."""
        c0, c1 = self.low
        if c0 == 0.0 and c1 == 0.0:
            return 0.0
        sl = self.slack
        if not self.full_linear or not sl > 0:
            return math.inf
        return (c1 + math.sqrt(c1 * c1 + 4.0 * sl * c0)) / (2.0 * sl)

    @property
    def slack(self) -> float:
        """The larger of ``lambda_min(Q) - n_basis max|residual|`` and ``lambda_min(Q + R) - n_basis
        max|residual left|`` (the projected Gram matrix, see the class docstring): positive means exactly SOS."""
        raw = self.min_eig - self.n_basis * self.max_residual
        if not math.isfinite(self.projected_residual):
            return raw
        return max(raw, self.projected_min_eig - self.n_basis * self.projected_residual)

    @property
    def margin(self) -> float:
        """The larger of ``lambda_min(Q) / (n_basis max|residual|)`` and the same ratio of the projected Gram matrix:
        ``> 1`` means exactly SOS."""
        out = _ratio(self.min_eig, self.n_basis * self.max_residual)
        if math.isfinite(self.projected_residual):
            out = max(out, _ratio(self.projected_min_eig, self.n_basis * self.projected_residual))
        return out

    @property
    def passed(self) -> bool:
        """Exactly SOS: ``slack > 0``."""
        return self.slack > 0


@dataclass
class SOSProgram:
    """Builder of one SOS program in ``nvars`` polynomial variables."""

    nvars: int
    unknowns: list[Unknown] = field(default_factory=list)
    constraints: list[Any] = field(default_factory=list)
    sos_constraints: list[tuple[str, LinPoly, Unknown]] = field(default_factory=list)
    equalities: list[LinPoly] = field(default_factory=list)
    solve_time: float = 0.0         # wall time of the last solve (compilation + solver), s
    compile_time: float = 0.0       # cvxpy compilation of the last solve, s
    solver_time: float = 0.0        # time reported by the solver for the last solve, s
    status: str = ""
    reduce: bool = True             # add_sos reduces its half basis exactly (reduce_basis)
    problem: Any = None             # the cvxpy Problem of the last solve (resolve() re-solves it)
    full_bases: dict[str, list[Exp]] = field(default_factory=dict)   # add_sos half bases before reduction
    margin: Any = None      # optional cvxpy scalar t: Gram matrices of add_sos constraints satisfy Q >= t I
    coefficient_rows: set[int] = field(default_factory=set, repr=False)    # ids of add_zero's constraints
    cone: str = "sos"       # Gram matrices PSD ("sos"), or SDD ("sdsos") / DD ("dsos") inner approximations
    quotient: Any = None    # an AngleQuotient: coefficients are matched modulo its equalities (quotient.py)

    def enable_margin(self, cap: float = 1.0) -> Any:
        """Make every later :meth:`add_sos` Gram matrix satisfy ``Q >= t I`` for a new scalar ``t <= cap``
        (maximize ``t`` for a certificate with the largest eigenvalue margin); returns ``t``."""
        self.margin = cp.Variable(name="gram_margin")
        self.constraints.append(self.margin <= cap)
        return self.margin

    def scalar(self, name: str) -> tuple[Unknown, LinPoly]:
        v = cp.Variable(1, name=name)
        u = Unknown(name, v, 1, [(0,) * self.nvars], nvars=self.nvars)
        self.unknowns.append(u)
        return u, LinPoly(Poly({}, self.nvars), {u: [Poly.const(1.0, self.nvars)]})

    def free_poly(self, name: str, basis: Sequence[Exp]) -> tuple[Unknown, LinPoly]:
        basis = [tuple(e) for e in basis]
        if not basis:                   # nothing to choose: the zero polynomial (no variable)
            return None, LinPoly(Poly({}, self.nvars))  # type: ignore[return-value]
        v = cp.Variable(len(basis), name=name)
        u = Unknown(name, v, len(basis), basis, nvars=self.nvars)
        self.unknowns.append(u)
        return u, LinPoly(Poly({}, self.nvars), {u: [Poly({e: 1.0}, self.nvars) for e in basis]})

    def sos_poly(self, name: str, half_basis: Sequence[Exp], *, margin: bool = False) -> tuple[Unknown, LinPoly]:
        """SOS polynomial ``m^T Q m``, ``Q >= 0`` (``Q >= t I`` with ``margin`` and :meth:`enable_margin`) on the
        monomials ``half_basis``."""
        hb = [tuple(e) for e in half_basis]
        n = len(hb)
        if self.cone != "sos" and n > 0:        # Q (- t I) scaled diagonally dominant / diagonally dominant
            Q, cons = dd_gram(n, name, self.cone)
            if margin and self.margin is not None:
                Q = Q + self.margin * np.eye(n)
            self.constraints.extend(cons)
            u = Unknown(name, Q, n * n, hb, gram=True, nvars=self.nvars)
            self.unknowns.append(u)
            return u, self._gram_poly(u, hb)
        Q = cp.Variable((n, n), symmetric=True, name=name)
        u = Unknown(name, Q, n * n, hb, gram=True, nvars=self.nvars)
        self.unknowns.append(u)
        if margin and self.margin is not None:
            self.constraints.append(Q - self.margin * np.eye(n) >> 0)
        else:
            self.constraints.append(Q >> 0)
        return u, self._gram_poly(u, hb)

    def _gram_poly(self, u: Unknown, hb: list[Exp]) -> LinPoly:
        """``m^T Q m`` of a Gram unknown as a LinPoly (one column per entry, column-major)."""
        n = len(hb)
        cols = []
        for j in range(n):          # column-major: index i + n j
            for i in range(n):
                e = tuple(a + b for a, b in zip(hb[i], hb[j], strict=True))
                cols.append(Poly({e: 1.0}, self.nvars))
        return LinPoly(Poly({}, self.nvars), {u: cols})

    def sos_poly_blocks(self, name: str, blocks: Sequence[Sequence[Exp]], *,
                        margin: bool = False) -> tuple[list[Unknown], LinPoly]:
        """SOS polynomial with a block-diagonal Gram matrix, one block per monomial list of ``blocks``."""
        us: list[Unknown] = []
        total = LinPoly(Poly({}, self.nvars))
        for i, blk in enumerate(blocks):
            u, g = self.sos_poly(f"{name}{i}" if len(blocks) > 1 else name, blk, margin=margin)
            us.append(u)
            total = total + g
        return us, total

    def add_sos(self, name: str, expr: LinPoly, half_basis: Sequence[Exp], *,
                support: Sequence[Exp] = ()) -> list[Unknown]:
        """Constrain ``expr`` to be SOS on ``half_basis``, reduced exactly first (:func:`reduce_basis`, when
        :attr:`reduce`, on the support of ``expr`` and the monomials ``support``: with a :attr:`quotient`, those of
        the multiples of its equalities that the program leaves out); returns the Gram unknowns (one per block)."""
        if self.reduce:
            blocks = reduce_basis(linear_support(expr) | {tuple(e) for e in support}, half_basis)
        else:
            blocks = [list(half_basis)]
        us, g = self.sos_poly_blocks(name + ".gram", blocks, margin=True)
        self.add_zero(expr - g)
        self.sos_constraints.append((name, expr, us))
        self.full_bases[name] = [tuple(b) for b in half_basis]
        return us

    def gram_sizes(self) -> dict[str, list[int]]:
        """Block sizes of the Gram matrix of every SOS constraint."""
        return {name: [len(u.basis) for u in us] for name, _, us in self.sos_constraints}

    def add_zero(self, expr: LinPoly) -> None:
        """All coefficients of ``expr`` are zero (of its normal form, with a :attr:`quotient`)."""
        self.equalities.append(expr)
        if self.quotient is not None:
            expr = self.quotient.linpoly(expr)
        monos: dict[Exp, int] = {}
        for e in expr.const.terms:
            monos.setdefault(e, len(monos))
        for cols in expr.parts.values():
            for c in cols:
                for e in c.terms:
                    monos.setdefault(e, len(monos))
        m = len(monos)
        b = np.zeros(m)
        for e, c in expr.const.terms.items():
            b[monos[e]] = c
        lhs: Any = 0
        for u, cols in expr.parts.items():
            rows, cidx, vals = [], [], []
            for k, c in enumerate(cols):
                for e, x in c.terms.items():
                    rows.append(monos[e])
                    cidx.append(k)
                    vals.append(x)
            A = sps.csr_matrix((vals, (rows, cidx)), shape=(m, u.size))
            lhs = lhs + A @ u.flat
        self.constraints.append(lhs + b == 0)
        self.coefficient_rows.add(id(self.constraints[-1]))

    def solve(self, objective: Any, *, solver: str = DEFAULT_SOLVER, **kw: Any) -> float:
        """Solve ``maximize/minimize objective`` (a cvxpy objective).

        Parameters
        ----------
        objective : cvxpy objective
            ``cp.Maximize(...)`` or ``cp.Minimize(...)`` of the program's variables.
        solver : str
            A cvxpy SDP solver.
        **kw
            Passed to :meth:`cvxpy.Problem.solve`.

        Returns
        -------
        float
            The optimal value.

        Raises
        ------
        SolverError
            If the solver fails, raises a numerical error, or returns a status other than optimal.
        BudgetError
            If the solver runs out of memory.
        """
        self.problem = cp.Problem(objective, self.constraints)
        return self.resolve(solver=solver, **kw)

    @pinned_blas
    def resolve(self, *, solver: str = DEFAULT_SOLVER, **kw: Any) -> float:
        """Solve :attr:`problem` again (after changing the values of its cvxpy ``Parameter``\\ s): cvxpy reuses its
        compilation, so only the solver runs. Returns and raises as :meth:`solve`."""
        prob = self.problem
        if prob is None:
            raise SolverError("resolve() needs a program solved once with solve()")
        t0 = time.perf_counter()
        self.compile_time = self.solver_time = 0.0
        try:
            with inaccuracy_checked():   # the status is checked below, the Gram matrices by check()
                val = prob.solve(solver=solver_argument(solver), **{**solver_options(solver), **kw})
        except MemoryError as exc:
            raise BudgetError(f"SDP solver {solver} ran out of memory on a program with {len(self.unknowns)} "
                              "unknown blocks: lower the degree (see glidectl.estimate_sos_size)") from exc
        except (cp.error.SolverError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            raise SolverError(f"SDP solver {solver} failed: {type(exc).__name__}: {exc}") from exc
        self.solve_time = time.perf_counter() - t0
        self.compile_time = float(prob.compilation_time or 0.0)
        st = prob.solver_stats.solve_time if prob.solver_stats is not None else None
        self.solver_time = float(st) if st is not None else max(self.solve_time - self.compile_time, 0.0)
        self.status = prob.status
        if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or val is None or not np.isfinite(val):
            raise SolverError(f"SDP {solver} returned status '{prob.status}' (value {val}): the SOS program is "
                              "infeasible at this degree/level or numerically ill-posed")
        return float(val)

    def multiplier_values(self) -> dict[Unknown, np.ndarray]:
        """The Gram matrices of the SOS multipliers, made positive semidefinite: ``Q + delta I``.

        A multiplier is an SOS polynomial of :meth:`sos_poly` that is not the Gram matrix of an :meth:`add_sos`
        constraint (the ``tau``/``sigma`` of the S-procedure). The solver returns its Gram matrix ``Q`` only up to
        its tolerance, possibly with a negative eigenvalue; the certificate needs the multiplier exactly SOS. So
        ``delta = max(0, gamma - lambda_min(Q))`` with ``gamma = 4 n eps max|lambda(Q)|`` (above the backward error
        of the symmetric eigensolver), which makes ``Q + delta I`` positive semidefinite, and :meth:`check` evaluates
        every constraint with these matrices (the change ``delta m^T m`` of the multiplier lands in the residuals).

        Returns
        -------
        dict
            ``Unknown -> (n, n) array`` for every multiplier Gram unknown.
        """
        return {u: Q for u, (Q, _) in self._multipliers().items()}

    def _multipliers(self) -> dict[Unknown, tuple[np.ndarray, float]]:
        """:meth:`multiplier_values` with each ``delta``."""
        own = {id(u) for _, _, us in self.sos_constraints for u in us}
        out: dict[Unknown, tuple[np.ndarray, float]] = {}
        for u in self.unknowns:
            if not u.gram or id(u) in own or not u.basis:
                continue
            Q = u.value()
            Q = 0.5 * (Q + Q.T)
            lam = np.linalg.eigvalsh(Q)
            gamma = 4.0 * len(Q) * np.finfo(float).eps * float(np.max(np.abs(lam)))
            delta = max(gamma - float(lam[0]), 0.0)
            out[u] = (Q + delta * np.eye(len(Q)) if delta > 0 else Q, delta)
        return out

    def check(self, polish: bool = False) -> list[GramCheck]:
        """Gram eigenvalues against coefficient residuals for every SOS constraint (:class:`GramCheck`).

        With a block-diagonal Gram matrix, ``min_eig`` is the smallest eigenvalue over the blocks and ``n_basis``
        the size of the whole basis (the residual matrix ``R`` may couple blocks). A residual on a monomial that the
        unreduced basis reaches but the reduced one does not cannot be absorbed: it counts as an infinite residual
        (the reduction never makes a certificate pass that the unreduced program would fail). The constraints are
        evaluated with every SOS multiplier made exactly SOS (:meth:`multiplier_values`): a check that passes
        holds for multipliers that are SOS, not only for the solver's approximately SOS ones.

        With ``polish``, a constraint that fails also gets the residual on every monomial its half basis does not
        reach cancelled by its own free unknowns (:meth:`_cancel_unreached` at every degree, not only 0 and 1), and
        the check of the corrected values is kept if its slack is larger: the solver leaves such residuals at its
        tolerance, and no Gram entry can absorb them (the projected check counts them whole). This changes the
        values of those unknowns (the equality multipliers ``psi_j``, a free ``lambda``), so it is for a final
        check, whose unknowns feed nothing else (``certify_roa``'s final margin), not for the alternation's level
        programs, whose ``lambda`` steers the next V step.

        Parameters
        ----------
        polish : bool
            Cancel the unreached residual of a failing constraint first (above); default False.

        Returns
        -------
        list of GramCheck
            One per SOS constraint, in the order of :attr:`sos_constraints`.
        """
        found = self._multipliers()
        mult = {u: Q for u, (Q, _) in found.items()}
        shifts = {u: d for u, (_, d) in found.items()}
        out = []
        for name, expr, us in self.sos_constraints:
            chk = self._check_one(name, expr, us, mult, shifts)
            if chk.low != (0.0, 0.0):
                saved = self._cancel_unreached(name, expr, us, mult)
                if saved:
                    chk2 = self._check_one(name, expr, us, mult, shifts)
                    if chk2.radius < chk.radius:
                        chk = chk2
                    else:                       # no better: the solver's values stand
                        for u, v in saved.items():
                            u.var.value = v
            if polish and not chk.passed:
                saved = self._cancel_unreached(name, expr, us, mult, max_degree=None)
                if saved:
                    chk2 = self._check_one(name, expr, us, mult, shifts)
                    if chk2.slack > chk.slack and chk2.radius <= chk.radius:
                        chk = chk2
                    else:
                        for u, v in saved.items():
                            u.var.value = v
            out.append(chk)
        return out

    def _check_one(self, name: str, expr: Any, us: list[Unknown], mult: Mapping[Unknown, np.ndarray],
                   shifts: Mapping[Unknown, float]) -> GramCheck:
        """:meth:`check` of one SOS constraint at the current values of the unknowns."""
        nb = sum(len(u.basis) for u in us)
        mins = []
        for u in us:
            Q = u.value()
            mins.append(float(np.linalg.eigvalsh(0.5 * (Q + Q.T))[0]))
        res, basis, reach = _gram_residual(expr, us, mult, self.quotient)
        full = self.full_bases.get(name)
        lost = (_pair_sums(full, distinct=False) - reach) if full is not None else set()
        out_res = max((abs(c) for e, c in res.terms.items() if e in lost), default=0.0)
        r = math.inf if out_res > 0 else res.max_abs_coefficient()
        # residual on monomials of degree 0 and 1 that no basis pair reaches: the constraint holds only
        # outside a ball (GramCheck.radius)
        unreached = {e: c for e, c in res.terms.items() if e not in reach and sum(e) <= 1}
        c0 = sum(abs(c) for e, c in unreached.items() if sum(e) == 0)
        c1 = math.sqrt(sum(c * c for e, c in unreached.items() if sum(e) == 1))
        linear = {tuple(int(k == i) for k in range(self.nvars)) for i in range(self.nvars)}
        shift = max((shifts[u] for u in _unknowns_of(expr) if u in shifts), default=0.0)
        pmin, pres = _projected(us, res) if math.isfinite(r) else (-math.inf, math.inf)
        return GramCheck(name, nb, min(mins, default=math.inf if nb == 0 else 0.0), r, shift, (c0, c1),
                         linear <= set(basis), pmin, pres)

    def _cancel_unreached(self, name: str, expr: Any, us: list[Unknown], mult: Mapping[Unknown, np.ndarray],
                          max_degree: int | None = 1) -> dict[Unknown, np.ndarray] | None:
        """Cancel the residual on monomials of degree 0 and 1 (up to ``max_degree``; None: every degree) that no
        pair of the half basis reaches, with the free unknowns that only this constraint uses (the equality
        multipliers ``psi_j`` of the decrease condition) and that no other constraint of the program holds
        (:attr:`constraints` beyond the coefficient equations: a fixed level ``rho``).

        The solver leaves such residuals at its tolerance (for example ``lambda dV/dt`` and ``psi_j(0) h_j`` both
        have a term in ``1 - cos x``, which must cancel exactly); no Gram entry can absorb them, so they would
        leave a ball around the equilibrium where the certificate does not speak (:attr:`GramCheck.radius`).
        The correction ``delta`` solves ``A delta = -r`` on those monomials in least squares and is kept only if it
        removes the residual to rounding; it moves the other coefficients by ``A' delta``, which the Gram check
        then counts like any residual (:meth:`check` keeps it only if it shrinks :attr:`GramCheck.radius`). The
        identity checked is still exact: nothing is assumed. Returns the previous values of the changed unknowns
        (None if nothing changed)."""
        if not isinstance(expr, LinPoly):
            return None
        others = {id(u) for n2, e2, _ in self.sos_constraints if n2 != name for u in _unknowns_of(e2)}
        # an unknown that a constraint of the caller's also holds (the level rho == rho_c of a final margin program,
        # a cap rho <= c) is not free either: moving it would certify something other than what is reported
        pinned = {id(v) for c in self.constraints if id(c) not in self.coefficient_rows for v in c.variables()}
        free = [u for u in expr.parts if not u.gram and id(u) not in others and id(u.var) not in pinned
                and u.var.value is not None]
        if not free:
            return None
        res, _, reach = _gram_residual(expr, us, mult, self.quotient)
        top = math.inf if max_degree is None else max_degree
        low = sorted(e for e, c in res.terms.items() if e not in reach and sum(e) <= top and c != 0.0)
        if not low:
            return None
        row = {e: i for i, e in enumerate(low)}
        cols = [(u, k) for u in free for k in range(u.size)]
        A = np.zeros((len(low), len(cols)))
        for j, (u, k) in enumerate(cols):
            for e, c in expr.parts[u][k].terms.items():
                if e in row:
                    A[row[e], j] = c
        r = np.array([res.terms[e] for e in low])
        if not np.any(A):
            return None
        delta, *_ = np.linalg.lstsq(A, -r, rcond=None)
        if np.max(np.abs(A @ delta + r)) > 1e-6 * np.max(np.abs(r)):
            return None
        saved = {u: np.array(u.var.value, dtype=float) for u in free}
        j = 0
        for u in free:
            v = np.asarray(u.var.value, dtype=float).ravel(order="F") + delta[j:j + u.size]
            u.var.value = v.reshape(u.var.shape, order="F")
            j += u.size
        return saved


def _gram_residual(expr: Any, us: list[Unknown], mult: Mapping[Unknown, np.ndarray],
                   quotient: Any = None) -> tuple[Poly, list[Exp], set[Exp]]:
    """``expr - m^T Q m`` at the current values (multipliers ``mult`` made SOS), the half basis of the Gram
    unknowns ``us`` and the monomials its pairs reach."""
    res = expr.value(mult)
    for u in us:
        res = res - u.poly()
    basis = [b for u in us for b in u.basis]
    reach = _pair_sums(basis, distinct=False)
    if quotient is not None:
        res = quotient.lift(quotient.nf(res), reach)
    return res, basis, reach


def _projected(us: list[Unknown], res: Poly) -> tuple[float, float]:
    """``(lambda_min(Q + R), max|residual left|)`` for the Gram blocks ``us`` (block diagonal ``Q`` on their joint
    basis) and the residual ``res = expr - m^T Q m``: ``R_ij = r_a / n_a`` on the ``n_a`` ordered pairs of the joint
    basis with ``b_i + b_j = a`` (:class:`GramCheck`, projection). ``R`` may couple blocks. The residual left is
    computed, not assumed: ``|r_a - sum R_ij|`` (rounding) and ``|r_a|`` where no pair reaches ``a``."""
    basis = [b for u in us for b in u.basis]
    n = len(basis)
    if n == 0:
        return math.inf, res.max_abs_coefficient()
    Q = np.zeros((n, n))
    k = 0
    for u in us:
        B = u.value()
        m = len(u.basis)
        Q[k:k + m, k:k + m] = 0.5 * (B + B.T)
        k += m
    index: dict[Exp, int] = {}
    E = np.empty((n, n), dtype=int)
    for i in range(n):
        for j in range(i, n):
            e = tuple(a + b for a, b in zip(basis[i], basis[j], strict=True))
            E[i, j] = E[j, i] = index.setdefault(e, len(index))
    r = np.zeros(len(index))
    left = 0.0
    for e, c in res.terms.items():
        at = index.get(e)
        if at is None:
            left = max(left, abs(c))
        else:
            r[at] = c
    counts = np.bincount(E.ravel(), minlength=len(index))
    R = (r / counts)[E]
    after = np.abs(r - np.bincount(E.ravel(), weights=R.ravel(), minlength=len(index)))
    return float(np.linalg.eigvalsh(Q + R)[0]), max(left, float(np.max(after, initial=0.0)))


def _ratio(eig: float, bound: float) -> float:
    """``eig / bound``; ``inf`` (``eig > 0``) or 0 for a zero bound."""
    if bound > 0:
        return eig / bound
    return float("inf") if eig > 0 else 0.0


def _unknowns_of(expr: Any) -> list[Unknown]:
    """The unknowns an expression of :attr:`SOSProgram.sos_constraints` depends on (LinPoly, or any object with
    ``L0`` and Parameter-weighted ``parts`` of LinPolys)."""
    if isinstance(expr, LinPoly):
        return list(expr.parts)
    return list(expr.L0.parts) + [u for _, L in expr.parts.values() for u in L.parts]


def linear_support(expr: LinPoly) -> set[Exp]:
    """Every monomial ``expr`` can have, whatever its unknowns (constant part and all columns).

    Parameters
    ----------
    expr : LinPoly
        A polynomial affine in the program's unknowns.

    Returns
    -------
    set of tuple of int
        Exponents of the monomials that some value of the unknowns gives a nonzero coefficient.

    Raises
    ------
    None
    """
    S = set(expr.const.terms)
    for cols in expr.parts.values():
        for c in cols:
            S.update(c.terms)
    return S
