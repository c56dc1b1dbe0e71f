"""Sum-of-squares programs in cvxpy with sparse coefficient matching.

The unknowns of an SOS program are polynomials with free coefficients (:meth:`SOSProgram.free_poly`), SOS
polynomials given by a positive semidefinite Gram matrix on a monomial basis (:meth:`SOSProgram.sos_poly`) and
scalars (:meth:`SOSProgram.scalar`). Every expression the algorithms write is *affine* in the unknowns: a
:class:`LinPoly` is a constant polynomial plus, for each unknown, one known polynomial per unknown coefficient (the
columns of a linear map). ``expr in SOS`` (:meth:`SOSProgram.add_sos`) introduces a Gram matrix ``Q >= 0`` and the
equalities ``coeff_alpha(expr) = sum_{b_i + b_j = alpha} Q_ij`` for every monomial ``alpha``, assembled as one
``scipy.sparse`` matrix per unknown and passed to cvxpy as ``A @ x + b == 0``.

After the solve, :meth:`SOSProgram.check` recomputes every SOS constraint in floating point from the solved
unknowns and returns the smallest Gram eigenvalue and the coefficient residual: when
``lambda_min(Q) > n_basis * max|residual|`` the residual can be absorbed in ``Q`` (a symmetric matrix ``R`` with
``m^T R m = residual`` has ``||R||_2 <= n_basis max|r|``), so the polynomial is exactly SOS.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sps

from ..errors import BudgetError, SolverError
from .polynomial import Exp, Poly

__all__ = ["GramCheck", "LinPoly", "SOSProgram", "Unknown"]


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

    def value(self) -> Poly:
        """The polynomial at the solved unknowns."""
        t = dict(self.const.terms)          # accumulated in place: one pass over the columns' terms
        for u, cols in self.parts.items():
            v = u.value().ravel(order="F")
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
    ``lambda_min(Q) > 0``); ``passed`` is ``slack > 0`` (equivalently ``margin > 1``).
    """

    name: str
    n_basis: int
    min_eig: float
    max_residual: float

    @property
    def slack(self) -> float:
        """``lambda_min(Q) - n_basis max|residual|``: positive means exactly SOS (see module docstring)."""
        return self.min_eig - self.n_basis * self.max_residual

    @property
    def margin(self) -> float:
        """``lambda_min(Q) / (n_basis max|residual|)``: ``> 1`` means exactly SOS."""
        bound = self.n_basis * self.max_residual
        if bound > 0:
            return self.min_eig / bound
        return float("inf") if self.min_eig > 0 else 0.0

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
    solve_time: float = 0.0
    status: str = ""
    margin: Any = None      # optional cvxpy scalar t: Gram matrices of add_sos constraints satisfy Q >= t I

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
        v = cp.Variable(len(basis), name=name)
        u = Unknown(name, v, len(basis), basis, nvars=self.nvars)
        self.unknowns.append(u)
        return u, LinPoly(Poly({}, self.nvars), {u: [Poly({e: 1.0}, self.nvars) for e in basis]})

    def sos_poly(self, name: str, half_basis: Sequence[Exp], *, margin: bool = False) -> tuple[Unknown, LinPoly]:
        """SOS polynomial ``m^T Q m``, ``Q >= 0`` (``Q >= t I`` with ``margin`` and :meth:`enable_margin`) on the
        monomials ``half_basis``."""
        hb = [tuple(e) for e in half_basis]
        n = len(hb)
        Q = cp.Variable((n, n), symmetric=True, name=name)
        u = Unknown(name, Q, n * n, hb, gram=True, nvars=self.nvars)
        self.unknowns.append(u)
        if margin and self.margin is not None:
            self.constraints.append(Q - self.margin * np.eye(n) >> 0)
        else:
            self.constraints.append(Q >> 0)
        cols = []
        for j in range(n):          # column-major: index i + n j
            for i in range(n):
                e = tuple(a + b for a, b in zip(hb[i], hb[j], strict=True))
                cols.append(Poly({e: 1.0}, self.nvars))
        return u, LinPoly(Poly({}, self.nvars), {u: cols})

    def add_sos(self, name: str, expr: LinPoly, half_basis: Sequence[Exp]) -> Unknown:
        """Constrain ``expr`` to be SOS on ``half_basis`` (returns the Gram unknown)."""
        u, g = self.sos_poly(name + ".gram", half_basis, margin=True)
        self.add_zero(expr - g)
        self.sos_constraints.append((name, expr, u))
        return u

    def add_zero(self, expr: LinPoly) -> None:
        """All coefficients of ``expr`` are zero."""
        self.equalities.append(expr)
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

    def solve(self, objective: Any, *, solver: str = "CLARABEL", **kw: Any) -> float:
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
        prob = cp.Problem(objective, self.constraints)
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():   # "solution may be inaccurate": the status is checked below
                warnings.simplefilter("ignore", UserWarning)
                val = prob.solve(solver=solver, **kw)
        except MemoryError as exc:
            raise BudgetError(f"SDP solver {solver} ran out of memory on a program with {len(self.unknowns)} "
                              "unknown blocks: lower the degree (see glidectl.estimate_sos_size)") from exc
        except (cp.error.SolverError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            raise SolverError(f"SDP solver {solver} failed: {type(exc).__name__}: {exc}") from exc
        self.solve_time = time.perf_counter() - t0
        self.status = prob.status
        if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or val is None or not np.isfinite(val):
            raise SolverError(f"SDP {solver} returned status '{prob.status}' (value {val}): the SOS program is "
                              "infeasible at this degree/level or numerically ill-posed")
        return float(val)

    def check(self) -> list[GramCheck]:
        """Gram eigenvalues against coefficient residuals for every SOS constraint (:class:`GramCheck`)."""
        out = []
        for name, expr, u in self.sos_constraints:
            Q = u.value()
            Q = 0.5 * (Q + Q.T)
            res = expr.value() - u.poly()
            out.append(GramCheck(name, Q.shape[0], float(np.linalg.eigvalsh(Q)[0]), res.max_abs_coefficient()))
        return out
