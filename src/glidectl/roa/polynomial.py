"""Sparse multivariate polynomials with real coefficients, the only algebra the SOS layer needs.

A :class:`Poly` is a mapping ``exponent tuple -> coefficient`` in ``n`` variables. It supports ``+``, ``-``,
``*`` (by polynomials and scalars), powers, partial derivatives, the Lie derivative along a polynomial vector
field, vectorized evaluation (real or complex arguments, so complex-step derivatives of certificates are exact)
and substitution of polynomials for variables. Monomial bases come from :func:`monomials`.

Nothing here is specific to gliders; :mod:`glidectl.roa.sos` builds SOS programs on top of it.
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, BudgetError

#: Largest monomial basis :func:`monomials` enumerates (a bigger one would not fit any SDP anyway).
MAX_BASIS = 10_000_000

__all__ = ["Poly", "field_evaluator", "monomial_matrix", "monomials", "powers_table"]

Exp = tuple[int, ...]


def powers_table(Z: np.ndarray, dmax: int) -> np.ndarray:
    """Powers table of points ``Z``: ``[..., i, k] = Z[..., i]^k`` by repeated products (what :meth:`Poly.__call__`
    evaluates a polynomial on; one table serves several polynomials at the same points, :meth:`Poly.on_powers`).

    Parameters
    ----------
    Z : ndarray (..., nvars)
        Points (real or complex).
    dmax : int
        Largest exponent needed.

    Returns
    -------
    ndarray (..., nvars, dmax + 1)
        The powers ``0..dmax`` of every coordinate.
    """
    pw = np.ones((*Z.shape, dmax + 1), dtype=np.result_type(Z, float))
    for k in range(1, dmax + 1):
        pw[..., k] = pw[..., k - 1] * Z
    return pw


class Poly:
    """Polynomial ``sum_k c_k z^{e_k}`` in ``nvars`` variables (immutable by convention).

    Parameters
    ----------
    terms : mapping exponent tuple -> float
        Coefficients; zero coefficients are dropped.
    nvars : int
        Number of variables.

    Raises
    ------
    ArgumentTypeError
        If ``terms`` is not a mapping, ``nvars`` is not an integer, or a coefficient or exponent is not a number.
    ArgumentError
        If an exponent tuple does not have ``nvars`` non-negative entries, or a coefficient is not finite.
    """

    __slots__ = ("nvars", "terms")

    def __init__(self, terms: Mapping[Exp, float], nvars: int) -> None:
        if isinstance(nvars, bool) or not isinstance(nvars, numbers.Integral) or nvars < 0:
            raise ArgumentTypeError(f"nvars must be a non-negative integer, got {nvars!r}")
        if not isinstance(terms, Mapping):
            raise ArgumentTypeError("terms must be a mapping exponent tuple -> coefficient, got "
                                    f"{type(terms).__name__}")
        self.nvars = int(nvars)
        clean: dict[Exp, float] = {}
        try:
            for e, c in terms.items():
                if len(e) != self.nvars:
                    raise ArgumentError(f"exponent {e} has {len(e)} entries, the polynomial has {nvars} variables")
                if c != 0.0:
                    clean[tuple(int(k) for k in e)] = float(c)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, ArgumentError):
                raise
            raise ArgumentTypeError(f"a polynomial's terms map tuples of integers to real numbers: {exc}") from exc
        if clean and self.nvars and min(min(e) for e in clean) < 0:
            raise ArgumentError("exponents must be non-negative integers")
        if not all(math.isfinite(c) for c in clean.values()):
            raise ArgumentError("polynomial coefficients must be finite")
        self.terms = clean

    @classmethod
    def _make(cls, terms: dict[Exp, float], nvars: int) -> Poly:
        """A polynomial from terms that are already well formed (the arithmetic below); drops zeros only."""
        p = cls.__new__(cls)
        p.nvars = nvars
        p.terms = {e: c for e, c in terms.items() if c != 0.0}
        return p

    # ------------------------------------------------------------------ constructors
    @classmethod
    def const(cls, c: float, nvars: int) -> Poly:
        return cls({(0,) * nvars: float(c)}, nvars)

    @classmethod
    def var(cls, i: int, nvars: int) -> Poly:
        e = [0] * nvars
        e[i] = 1
        return cls({tuple(e): 1.0}, nvars)

    @classmethod
    def variables(cls, nvars: int) -> list[Poly]:
        return [cls.var(i, nvars) for i in range(nvars)]

    @classmethod
    def quadratic(cls, P: Any) -> Poly:
        """The quadratic form ``z^T P z = sum_ij P_ij z_i z_j`` in ``n`` variables.

        Parameters
        ----------
        P : array_like
            Square matrix, shape ``(n, n)``, finite (not symmetrized: ``P_ij`` and ``P_ji`` both enter).

        Returns
        -------
        Poly
            The form, in ``n`` variables.

        Raises
        ------
        ArgumentError
            If ``P`` is not a finite square matrix.
        """
        P = np.asarray(P, dtype=float)
        if P.ndim != 2 or P.shape[0] != P.shape[1] or P.shape[0] == 0 or not np.all(np.isfinite(P)):
            raise ArgumentError(f"a quadratic form needs a finite non-empty square matrix, got shape {P.shape}")
        n = P.shape[0]
        Z = cls.variables(n)
        V = cls({}, n)
        for i in range(n):
            for j in range(n):
                V = V + float(P[i, j]) * Z[i] * Z[j]
        return V

    def quadratic_part(self) -> np.ndarray:
        """The symmetric ``Q`` with ``z^T Q z`` equal to the terms of degree 2 (the inverse of :meth:`quadratic` on
        symmetric matrices).

        Returns
        -------
        numpy.ndarray, shape (nvars, nvars)
        """
        Q = np.zeros((self.nvars, self.nvars))
        for e, c in self.terms.items():
            if sum(e) == 2:
                i, j = (k for k in range(self.nvars) for _ in range(e[k]))
                Q[i, j] += c / 2.0
                Q[j, i] += c / 2.0
        return Q

    # ------------------------------------------------------------------ arithmetic
    def _coerce(self, other: Any) -> Poly:
        if isinstance(other, Poly):
            if other.nvars != self.nvars:
                raise ArgumentError(f"polynomials in {self.nvars} and {other.nvars} variables cannot be combined")
            return other
        return Poly.const(checks.real("polynomial operand", other), self.nvars)

    def __add__(self, other: Any) -> Poly:
        o = self._coerce(other)
        t = dict(self.terms)
        for e, c in o.terms.items():
            t[e] = t.get(e, 0.0) + c
        return Poly._make(t, self.nvars)

    __radd__ = __add__

    def __neg__(self) -> Poly:
        return Poly._make({e: -c for e, c in self.terms.items()}, self.nvars)

    def __sub__(self, other: Any) -> Poly:
        return self + (-self._coerce(other))

    def __rsub__(self, other: Any) -> Poly:
        return self._coerce(other) - self

    def __mul__(self, other: Any) -> Poly:
        if not isinstance(other, Poly):
            s = checks.real("polynomial factor", other)
            return Poly._make({e: s * c for e, c in self.terms.items()}, self.nvars)
        o = self._coerce(other)
        t: dict[Exp, float] = {}
        for e1, c1 in self.terms.items():
            for e2, c2 in o.terms.items():
                e = tuple(a + b for a, b in zip(e1, e2, strict=True))
                t[e] = t.get(e, 0.0) + c1 * c2
        return Poly._make(t, self.nvars)

    __rmul__ = __mul__

    def __truediv__(self, s: float) -> Poly:
        d = checks.real("polynomial divisor", s)
        if d == 0.0:
            raise ArgumentError("a polynomial cannot be divided by zero")
        return self * (1.0 / d)

    def __pow__(self, k: int) -> Poly:
        k = checks.integer("polynomial power", k, lo=0)
        out = Poly.const(1.0, self.nvars)
        for _ in range(int(k)):
            out = out * self
        return out

    # ------------------------------------------------------------------ queries
    @property
    def degree(self) -> int:
        return max((sum(e) for e in self.terms), default=0)

    @property
    def is_zero(self) -> bool:
        return not self.terms

    def max_abs_coefficient(self) -> float:
        return max((abs(c) for c in self.terms.values()), default=0.0)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """``(exponents (m, n) int, coefficients (m,))``."""
        if not self.terms:
            return np.zeros((0, self.nvars), dtype=int), np.zeros(0)
        return np.array(list(self.terms.keys()), dtype=int), np.array(list(self.terms.values()))

    def __call__(self, Z: Any) -> Any:
        """Evaluate at ``Z`` of shape ``(..., nvars)`` (real or complex)."""
        Z = np.asarray(Z)
        if Z.dtype.kind not in "biufc":
            raise ArgumentTypeError(f"a polynomial is evaluated at numbers, got an array of dtype {Z.dtype}")
        if Z.ndim == 0 or Z.shape[-1] != self.nvars:
            raise ArgumentError(f"polynomial in {self.nvars} variables evaluated at points of shape {Z.shape} (the "
                                f"last axis must have length {self.nvars})")
        exps, coef = self.arrays()
        if exps.shape[0] == 0:
            return np.zeros(Z.shape[:-1], dtype=Z.dtype if np.iscomplexobj(Z) else float)
        return self.on_powers(powers_table(Z, int(exps.max(initial=0))), exps, coef)

    def on_powers(self, pw: np.ndarray, exps: np.ndarray | None = None, coef: np.ndarray | None = None) -> Any:
        """The value from a powers table (bitwise the value of :meth:`__call__`: one table serves several
        polynomials at the same points).

        Parameters
        ----------
        pw : ndarray (..., nvars, d + 1)
            :func:`powers_table` of the points, with ``d`` at least this polynomial's largest exponent.
        exps, coef : ndarray, optional
            :meth:`arrays` of this polynomial (computed when omitted).

        Returns
        -------
        ndarray (...)
            The polynomial at the points.
        """
        if exps is None or coef is None:
            exps, coef = self.arrays()
            if exps.shape[0] == 0:
                return np.zeros(pw.shape[:-2], dtype=pw.dtype if np.iscomplexobj(pw) else float)
        out = np.zeros(pw.shape[:-2], dtype=pw.dtype)
        for e, c in zip(exps, coef, strict=True):
            term = c
            for i in np.flatnonzero(e):
                term = term * pw[..., i, e[i]]
            out = out + term
        return out

    def diff(self, i: int) -> Poly:
        """``d/dz_i``."""
        i = checks.integer("i", i, lo=0, hi=self.nvars - 1)
        t: dict[Exp, float] = {}
        for e, c in self.terms.items():
            if e[i] > 0:
                e2 = list(e)
                e2[i] -= 1
                t[tuple(e2)] = t.get(tuple(e2), 0.0) + c * e[i]
        return Poly._make(t, self.nvars)

    def lie(self, F: Sequence[Poly]) -> Poly:
        """Lie derivative ``grad(self) . F`` along the polynomial vector field ``F``."""
        if len(F) != self.nvars:
            raise ArgumentError(f"the vector field has {len(F)} components; the polynomial has {self.nvars} variables")
        out = Poly({}, self.nvars)
        for i, Fi in enumerate(F):
            d = self.diff(i)
            if not d.is_zero:
                out = out + d * Fi
        return out

    def substitute(self, polys: Sequence[Poly]) -> Poly:
        """``self(p_1(y), ..., p_n(y))`` for polynomials ``p_i`` in a common set of variables."""
        if len(polys) != self.nvars or not all(isinstance(p, Poly) for p in polys):
            raise ArgumentError(f"substitute needs {self.nvars} polynomials, got {len(polys)} objects")
        m = polys[0].nvars if polys else 0
        if any(p.nvars != m for p in polys):
            raise ArgumentError("substitute needs polynomials in a common set of variables")
        out = Poly({}, m)
        cache: dict[tuple[int, int], Poly] = {}
        for e, c in self.terms.items():
            term = Poly.const(c, m)
            for i, k in enumerate(e):
                if k:
                    if (i, k) not in cache:
                        cache[(i, k)] = polys[i] ** k
                    term = term * cache[(i, k)]
            out = out + term
        return out

    def __repr__(self) -> str:
        if not self.terms:
            return "Poly(0)"
        parts = []
        for e, c in sorted(self.terms.items(), key=lambda t: (sum(t[0]), t[0])):
            mono = "*".join(f"z{i}" + (f"^{k}" if k > 1 else "") for i, k in enumerate(e) if k)
            parts.append(f"{c:+.6g}" + (f"*{mono}" if mono else ""))
        return "Poly(" + " ".join(parts) + ")"


def monomials(nvars: int, max_degree: int, min_degree: int = 0,
              max_exponent: Mapping[int, int] | None = None) -> list[Exp]:
    """All exponents of total degree in ``[min_degree, max_degree]``, graded order.

    ``max_exponent`` caps single variables (e.g. ``{1: 1}`` keeps ``s`` of an angle pair ``(s, c)`` linear, a basis
    of polynomials modulo ``s^2 + c^2 - 2c``).

    Parameters
    ----------
    nvars : int
        Number of variables, >= 0.
    max_degree, min_degree : int
        Range of total degrees, ``max_degree >= 0``.
    max_exponent : mapping int -> int, optional
        Caps of single variables.

    Returns
    -------
    list of tuple of int
        The exponents.

    Raises
    ------
    ArgumentTypeError
        If a degree or ``nvars`` is not an integer.
    ArgumentError
        If a degree or ``nvars`` is negative.
    BudgetError
        If the basis could exceed :data:`MAX_BASIS` monomials.
    """
    nvars = checks.integer("nvars", nvars, lo=0)
    max_degree = checks.integer("max_degree", max_degree, lo=0)
    min_degree = checks.integer("min_degree", min_degree)
    if math.comb(nvars + max_degree, max_degree) > MAX_BASIS:
        raise BudgetError(f"a monomial basis of degree {max_degree} in {nvars} variables has up to "
                          f"{math.comb(nvars + max_degree, max_degree):.3g} elements, above MAX_BASIS = {MAX_BASIS}")
    cap = dict(max_exponent or {})
    out: list[Exp] = []
    for d in range(min_degree, max_degree + 1):
        for combo in itertools.combinations_with_replacement(range(nvars), d):
            e = [0] * nvars
            for i in combo:
                e[i] += 1
            if all(e[i] <= k for i, k in cap.items()):
                out.append(tuple(e))
    return out


def monomial_matrix(Z: Any, basis: Sequence[Exp]) -> np.ndarray:
    """``M[k, j] = z_k^{basis_j}`` for points ``Z`` (N, nvars): the design matrix of a polynomial fit, or the linear
    map from coefficients on ``basis`` to values at ``Z``.

    Parameters
    ----------
    Z : array_like, shape (N, nvars)
        Points.
    basis : sequence of exponent tuples
        Monomials, each of length ``nvars``.

    Returns
    -------
    ndarray, shape (N, len(basis))

    Raises
    ------
    ArgumentTypeError
        If ``Z`` is not a real array.
    ArgumentError
        If ``Z`` is not 2-D or the exponents do not have ``nvars`` entries.
    """
    Z = checks.array("Z", Z, ndim=2, finite=False)
    try:
        E = np.asarray(list(basis), dtype=int).reshape(len(basis), Z.shape[-1])
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"basis must hold exponent tuples of length {Z.shape[-1]}: {exc}") from exc
    return np.prod(Z[:, None, :] ** E[None, :, :], axis=2)


def field_evaluator(F: Sequence[Poly]) -> Any:
    """``X (..., n) -> (F_1(X), ..., F_m(X))`` stacked on the last axis, for polynomials ``F`` in ``n`` common
    variables: one powers table (by repeated multiplication, so complex steps stay exact), one gather of every
    monomial of the union of supports, and one matrix product with the coefficient matrix, whatever the number of
    terms (the per-term loop of :meth:`Poly.__call__` costs one array operation per term and factor).

    Parameters
    ----------
    F : sequence of Poly
        Polynomials in the same ``n`` variables.

    Returns
    -------
    callable
        ``evaluate(X)`` for ``X`` of shape ``(..., n)`` (real or complex), returning shape ``(..., len(F))``.

    Raises
    ------
    None
    """
    F = tuple(F)
    n = F[0].nvars if F else 0
    monos = sorted({e for f in F for e in f.terms})
    E = np.array(monos, dtype=int).reshape(len(monos), n)
    C = np.zeros((len(monos), len(F)))
    pos = {e: k for k, e in enumerate(monos)}
    for j, f in enumerate(F):
        for e, c in f.terms.items():
            C[pos[e], j] = c
    dmax = int(E.max(initial=0))
    cols = np.arange(n)

    def evaluate(X: Any) -> np.ndarray:
        X = np.asarray(X)
        pw = np.ones((*X.shape, dmax + 1), dtype=np.result_type(X, float))
        for k in range(1, dmax + 1):
            pw[..., k] = pw[..., k - 1] * X
        P = np.prod(pw[..., cols, E], axis=-1)        # (..., n_monomials)
        return P @ C

    return evaluate
