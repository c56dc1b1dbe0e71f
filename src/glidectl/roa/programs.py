"""SOS programs of the region-of-attraction certificate: the level problem, the V step, their sizes and the
Lyapunov starts (the programs :func:`glidectl.certify_roa` alternates)."""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sps
from scipy.linalg import solve_continuous_lyapunov

from .. import checks
from ..analysis.measure import unit_sobol
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, SolverError
from . import moment
from .blas_threads import pinned_blas
from .options import MAX_DEGREE
from .polynomial import Poly, monomial_matrix, monomials
from .quotient import angle_quotient
from .sdp_solvers import DEFAULT_SOLVER, check_solver, steering_options
from .sos import (
    GramCheck,
    LinPoly,
    SOSProgram,
    linear_support,
    parity_generators,
    reduce_basis,
    sign_classes,
)
from .surrogate import (
    robust_decrease_bound,
    robust_degree,
    skeleton,
    young_weights,
)
from .systems import PolySystem, recast

__all__ = ["MEMORY_FRACTION", "LevelResult", "SOSSize", "auto_extra", "build_program", "check_candidate",
           "check_degree", "check_iterations", "check_memory", "coverage_objective", "default_memory_limit",
           "estimate_sos_size", "even_up", "from_scaled", "is_certification_model", "linearization", "lyapunov_matrix",
           "lyapunov_quadratic", "max_level", "require_exponential_stability", "rescaled", "scaled_field",
           "solve_level", "solve_v_step", "to_scaled", "variable_scaling"]

#: Default ``memory_limit`` of :func:`certify_roa` and :func:`max_level`: this fraction of the physical memory.
MEMORY_FRACTION = 0.5

#: Bytes of memory per entry of the dense interior-point blocks of the Gram matrices (sum over Gram matrices of
#: ``(k (k + 1) / 2)^2``), measured on Clarabel runs of this module (75-95 bytes; rounded up), and the fixed part.
_BYTES_PER_KKT_ENTRY = 100.0
_BYTES_FIXED = 20e6
_BYTES_PER_GRAM_ENTRY = 1000.0      # the Python polynomials of the builder, per Gram entry



# --------------------------------------------------------------------------------------------- helpers
def _zsq(nz: int) -> Poly:
    return sum((Poly.var(i, nz) ** 2 for i in range(nz)), Poly({}, nz))


def even_up(k: int) -> int:
    return k + (k % 2)


@dataclass(frozen=True)
class _Degrees:
    D: int          # degree of the decrease polynomial
    lam: int        # degree of lambda
    m: int          # N = (z.z)^m


def _degrees(degV: int, degF: int, extra: int = 0) -> _Degrees:
    dVd = degV - 1 + degF
    D = even_up(max(degV + 2, dVd)) + 2 * extra
    return _Degrees(D, D - dVd, (D - degV) // 2)


def auto_extra(ps: PolySystem, extra: int | None) -> int:
    """Extra multiplier degree: 2 for up to 3 polynomial variables (cheap, removes the dependence on ``N``), else 0
    (larger systems would not fit the SDP solver)."""
    return (2 if ps.nz <= 3 else 0) if extra is None else checks.integer("extra", extra, lo=0)


def linearization(ps: PolySystem) -> np.ndarray:
    return jacobians(lambda x, u: ps.rhs(x[None, :])[0], ps.equilibrium, np.zeros(0))[0]


def scaled_field(ps: PolySystem) -> list[Poly]:
    """F divided by its largest coefficient (a positive factor: signs of dV/dt unchanged, better conditioning)."""
    s = max(f.max_abs_coefficient() for f in ps.F)
    return [f / s for f in ps.F]


def lyapunov_matrix(ps: PolySystem) -> np.ndarray:
    """``P`` of ``A^T P + P A = -I`` for the linearization ``A`` of the model at its equilibrium (the Lyapunov
    equation Drake's ``RegionOfAttraction`` uses); raises if the equilibrium is not exponentially stable.

    Parameters
    ----------
    ps : PolySystem
        The recast system (:func:`~glidectl.roa.systems.recast`); ``A`` is the exact (complex-step) Jacobian of its
        ``rhs`` at its equilibrium, in the model's own states and time unit (``ps.time_unit``).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric positive definite ``P`` (time units of the model, e.g. s, or nondimensional for ``t_n``).

    Raises
    ------
    ModelError
        If ``A`` has an eigenvalue with real part >= ``-1e-9 max|lambda|`` (unstable, or marginally stable such as a
        centre: no exponentially stable equilibrium, no region of attraction to certify), or ``ps`` cannot be
        recast.
    ArgumentTypeError
        If ``ps`` is neither a PolySystem nor a model.
    SolverError
        If the Lyapunov equation cannot be solved to a positive definite ``P``.

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.lyapunov_matrix(gc.benchmarks.van_der_pol()).round(6)
    array([[ 1.5, -0.5],
           [-0.5,  1. ]])
    """
    ps = recast(ps)
    A = linearization(ps)
    require_exponential_stability(ps, A)
    try:
        P = solve_continuous_lyapunov(A.T, -np.eye(ps.n))
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"the Lyapunov equation A'P + PA = -I of '{ps.name}' failed: {exc}") from exc
    P = 0.5 * (P + P.T)
    if not np.all(np.isfinite(P)) or np.linalg.eigvalsh(P)[0] <= 0:
        raise SolverError(f"the Lyapunov equation A'P + PA = -I of '{ps.name}' gave a P that is not positive "
                          "definite (ill-conditioned linearization)")
    return P


def require_exponential_stability(ps: Any, A: np.ndarray) -> np.ndarray:
    """The eigenvalues of ``A``; :class:`ModelError` unless every real part is below ``-1e-9 max|lambda|`` (``ps``:
    anything with the system's ``name``)."""
    name = getattr(ps, "name", type(ps).__name__)
    if not np.all(np.isfinite(A)):
        raise ModelError(f"the linearization of '{name}' at its equilibrium is not finite")
    lam = np.linalg.eigvals(A)
    scale = float(np.max(np.abs(lam), initial=0.0))
    worst = float(np.max(lam.real))
    if scale == 0.0 or worst >= -1e-9 * scale:
        kind = ("marginally stable (eigenvalues on the imaginary axis, e.g. a centre)" if abs(worst) <= 1e-9 * scale
                else "unstable")
        raise ModelError(f"the equilibrium of '{name}' is not exponentially stable: its linearization is {kind}, "
                         f"eigenvalues {np.round(lam, 6).tolist()}. A region of attraction is certified only for an "
                         "exponentially stable equilibrium (every eigenvalue with negative real part)")
    return lam


def lyapunov_quadratic(ps: PolySystem) -> Poly:
    """``V0 = x^T P x`` (:func:`lyapunov_matrix`) in ``z``: an angle ``x_i`` enters as ``s_i`` in cross terms and as
    ``2 c_i`` (``= x_i^2 + O(x_i^4)``, positive on the whole circle) when squared; other states as themselves.

    Parameters
    ----------
    ps : PolySystem
        The recast system (:func:`~glidectl.roa.systems.recast`).

    Returns
    -------
    Poly
        The quadratic candidate in the ``ps.nz`` polynomial variables ``z`` (units of ``P`` times the squared state
        units; nondimensional for the glidectl models).

    Raises
    ------
    ModelError
        If the equilibrium is not exponentially stable (from :func:`lyapunov_matrix`).
    ArgumentTypeError
        If ``ps`` is neither a PolySystem nor a model.
    SolverError
        If the Lyapunov equation fails.

    Examples
    --------
    >>> import glidectl as gc
    >>> sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    >>> ps = gc.recast(sp.reduced_model())
    >>> ps.z_names
    ('Vbar', 'sin(gammabar)', '1-cos(gammabar)')
    >>> gc.lyapunov_quadratic(ps)                   # gammabar^2 enters as 2 (1 - cos(gammabar))
    Poly(+0.823641*z2 +0.238908*z0*z1 +0.33818*z0^2)
    """
    ps = recast(ps)
    P = lyapunov_matrix(ps)
    Z = Poly.variables(ps.nz)
    lin = [Z[sl[0]] for sl in ps.slots]
    sq = [2.0 * Z[sl[1]] if i in ps.angle_states else Z[sl[0]] ** 2 for i, sl in enumerate(ps.slots)]
    V = Poly({}, ps.nz)
    for i in range(ps.n):
        V = V + P[i, i] * sq[i]
        for j in range(i + 1, ps.n):
            V = V + 2 * P[i, j] * lin[i] * lin[j]
    return V


# --------------------------------------------------------------------------------------------- program sizes
def _n_monomials(nvars: int, max_degree: int, min_degree: int = 0, n_capped: int = 0) -> int:
    """``len(monomials(nvars, max_degree, min_degree, caps))`` for ``n_capped`` variables capped at exponent 1, in
    closed form (nothing is enumerated, so huge degrees cost nothing)."""
    free = nvars - n_capped

    def exact(k: int, m: int) -> int:          # monomials of degree exactly m in k variables
        if m < 0:
            return 0
        return math.comb(k + m - 1, m) if k > 0 else int(m == 0)

    return sum(math.comb(n_capped, j) * exact(free, d - j)
               for d in range(max(min_degree, 0), max_degree + 1) for j in range(min(n_capped, d) + 1))


@dataclass(frozen=True)
class SOSSize:
    """Size of the largest SOS program :func:`certify_roa` builds for one degree of ``V`` (its V step), estimated
    before anything is built (:func:`estimate_sos_size`).

    Attributes
    ----------
    degree : int
        Degree of ``V``.
    n_vars : int
        Polynomial variables ``z``.
    gram : tuple of (str, int)
        Name and size ``k`` of every Gram matrix (``k x k``, positive semidefinite).
    n_gram_entries : int
        Unknowns in the Gram matrices, ``sum k (k + 1) / 2``.
    n_free : int
        Free coefficients (``V``, ``lambda`` and the equality multipliers).
    n_constraints : int
        Coefficient-matching equalities (an upper bound: every monomial up to each constraint's degree).
    bytes : float
        Estimated peak memory of building and solving it (bytes): about 100 bytes per entry of the dense
        interior-point blocks, ``sum (k (k + 1) / 2)^2``, measured with Clarabel (within a factor 2), plus the
        builder's polynomials and a fixed 20 MB.
    """

    degree: int
    n_vars: int
    gram: tuple[tuple[str, int], ...]
    n_gram_entries: int
    n_free: int
    n_constraints: int
    bytes: float

    @property
    def largest_gram(self) -> int:
        """Size of the largest Gram matrix."""
        return max((k for _, k in self.gram), default=0)

    def summary(self) -> str:
        """One line: degree, variables, largest Gram matrix, unknowns, constraints and memory."""
        return (f"degree {self.degree} in {self.n_vars} variables: {len(self.gram)} Gram matrices (largest "
                f"{self.largest_gram} x {self.largest_gram}), {self.n_gram_entries + self.n_free} unknowns, "
                f"<= {self.n_constraints} equalities, ~{_fmt_bytes(self.bytes)}")


def _fmt_bytes(b: float) -> str:
    for unit, k in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if b >= k:
            return f"{b / k:.3g} {unit}"
    return f"{b / 1e3:.3g} kB"


def _size(ps: PolySystem, degree: int, extra: int) -> SOSSize:
    """The V-step program of :func:`build_program` at ``degree`` (plus ``lambda`` of the level problem), counted."""
    nz, nc = ps.nz, len(ps.s_caps)
    degF = robust_degree(degree, ps.degree) if ps.remainder else ps.degree
    dg = _degrees(degree, degF, extra)
    gram = [("decrease", _n_monomials(nz, dg.D // 2, 1, nc))]
    lows = _tau_low_degrees(ps)
    gram += [(f"tau{k}", _n_monomials(nz, (dg.D - g.degree) // 2, lows[k]))
             for k, g in enumerate(ps.cuts + ps.valid)]
    # equalities matched modulo the angle quotient have no multipliers, and the equations are on its standard
    # monomials (each s at most linear)
    quot = _quotient(ps, gram[0][1])
    eqs_m = [h for h in ps.equalities if quot is None or not quot.covers(h)]
    nq = len(quot.pairs) if quot is not None else 0
    free = _n_monomials(nz, degree, 1) + _n_monomials(nz, dg.lam)
    free += sum(_n_monomials(nz, dg.D - h.degree) for h in eqs_m)
    eqs = _n_monomials(nz, dg.D, 0, nq)
    for k, g in enumerate(ps.cuts):
        dk = even_up(max(degree, g.degree))
        gram += [(f"containment{k}", _n_monomials(nz, dk // 2, 0, nc)),
                 (f"sigma{k}", _n_monomials(nz, (dk - g.degree) // 2))]
        free += sum(_n_monomials(nz, dk - h.degree) for h in eqs_m)
        eqs += _n_monomials(nz, dk, 0, nq)
    gram.append(("positivity", _n_monomials(nz, degree // 2, 1, nc)))
    free += sum(_n_monomials(nz, degree - h.degree) for h in eqs_m)
    eqs += _n_monomials(nz, degree, 0, nq)
    kkt = sum((k * (k + 1) // 2) ** 2 for _, k in gram)
    entries = sum(k * (k + 1) // 2 for _, k in gram)
    nbytes = _BYTES_FIXED + _BYTES_PER_KKT_ENTRY * kkt + _BYTES_PER_GRAM_ENTRY * sum(k * k for _, k in gram)
    return SOSSize(degree, nz, tuple(gram), entries, free, eqs, float(nbytes))


def default_memory_limit() -> float:
    """:data:`MEMORY_FRACTION` of the physical memory (and of the address-space limit, if one is set); 4 GB when the
    system does not say."""
    total = None
    try:
        total = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        pass
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
            total = float(soft) if total is None else min(total, float(soft))
    except (ImportError, ValueError, OSError):
        pass
    return MEMORY_FRACTION * total if total else 4e9


def estimate_sos_size(system: Any, degree: int, *, extra: int | None = None, speed_floor: float = 0.1,
                      surrogate_degree: int = 3) -> SOSSize:
    """Size and memory of the largest SOS program :func:`certify_roa` would build for a ``V`` of ``degree``, computed
    from monomial counts before anything is built (milliseconds, whatever the degree).

    Parameters
    ----------
    system : PolySystem or glidectl model
        As for :func:`certify_roa` (a model is recast first, :func:`~glidectl.roa.systems.recast`).
    degree : int
        Even degree of ``V``, >= 2.
    extra : int, optional
        Extra multiplier degree (steps of 2), as in :func:`certify_roa`.
    speed_floor : float
        ``delta`` of the denominator cut for recast models.
    surrogate_degree : int
        For a closed loop that is neither a PolySystem nor a model built for certification (``gc.closed_loop``):
        the size of the surrogate route (:mod:`glidectl.roa.surrogate`) with a surrogate of this degree (2 to 5),
        counted without evaluating the model (the route :func:`certify_roa` checks first).

    Returns
    -------
    SOSSize
        The Gram matrix sizes, the number of unknowns and coefficient constraints, and the estimated bytes.

    Raises
    ------
    ArgumentTypeError
        If ``degree`` or ``extra`` is not an integer, or ``system`` is neither a PolySystem nor a model.
    ArgumentError
        If ``degree`` is odd or below 2, or ``extra`` is negative.
    ModelError
        If ``system`` cannot be recast exactly.

    Examples
    --------
    >>> import glidectl as gc
    >>> size = gc.estimate_sos_size(gc.benchmarks.van_der_pol(), degree=4)
    >>> size.gram, f"{size.bytes / 1e6:.0f} MB"
    ((('decrease', 20), ('positivity', 5)), '25 MB')
    """
    degree = check_degree(degree)
    if (not isinstance(system, PolySystem) and not is_certification_model(system) and hasattr(system, "state_names")
            and callable(getattr(system, "rhs", None))):
        sd = checks.integer("surrogate_degree", surrogate_degree, lo=2, hi=5)
        ps = skeleton(len(tuple(system.state_names)), sd)
    else:
        ps = recast(system, speed_floor=speed_floor)
    return _size(ps, degree, auto_extra(ps, extra))


def check_degree(degree: Any, name: str = "degree") -> int:
    d = checks.integer(name, degree, lo=2)
    if d % 2:
        raise ArgumentError(f"{name} must be an even integer >= 2 (V is a sum of even-degree terms), got {d}")
    return d


def check_iterations(iterations: Any, degree: int) -> tuple[int, ...]:
    """The V steps of each degree 2, 4, ..., ``degree`` from :func:`certify_roa`'s ``iterations``: one integer
    (>= 1) for all, or a sequence of ``degree // 2`` of them.

    Raises
    ------
    ArgumentTypeError
        If ``iterations`` is neither an integer nor a sequence of integers.
    ArgumentError
        If a count is below 1, or the sequence does not have one count per degree.
    """
    n = degree // 2
    if not ((isinstance(iterations, Sequence) and not isinstance(iterations, str | bytes))
            or (isinstance(iterations, np.ndarray) and iterations.ndim == 1)):
        return (checks.integer("iterations", iterations, lo=1),) * n
    its = tuple(checks.integer(f"iterations[{i}]", v, lo=1) for i, v in enumerate(iterations))
    if len(its) != n:
        raise ArgumentError(f"iterations must be one integer or one per degree 2, ..., {degree} ({n} of them), got "
                            f"{len(its)}: {list(its)}")
    return its


def check_memory(ps: PolySystem, degree: int, extra: int, max_degree: int, memory_limit: float,
                  what: str) -> SOSSize:
    """:class:`BudgetError`, saying which degree would fit, unless the program of ``degree`` is within the limits."""
    size = _size(ps, degree, extra)
    if degree <= max_degree and size.bytes <= memory_limit:
        return size
    fits = []
    for d in range(2, max_degree + 1, 2):       # sizes grow with the degree: stop at the first that does not fit
        if _size(ps, d, extra).bytes > memory_limit:
            break
        fits.append(d)
    best = (f"the largest degree within the limits is {fits[-1]} ({_size(ps, fits[-1], extra).summary()})" if fits
            else "no degree fits: raise memory_limit")
    why = (f"degree {degree} is above max_degree = {max_degree}" if degree > max_degree
           else f"it would need ~{_fmt_bytes(size.bytes)}, above memory_limit = {_fmt_bytes(memory_limit)}")
    raise BudgetError(f"{what} refused before building anything: {why} ({size.summary()}); {best}. Raise "
                      "max_degree / memory_limit to try anyway (SDP time grows even faster than memory)")


# --------------------------------------------------------------------------------------------- level problem
@dataclass(frozen=True)
class LevelResult:
    """Solution of the level problem for a fixed ``V``."""

    rho: float
    lam: Poly = field(repr=False)
    checks: tuple[GramCheck, ...]
    solve_time: float
    status: str
    compile_time: float = 0.0       # cvxpy compilation (s), part of solve_time
    solver_time: float = 0.0        # time reported by the SDP solver (s)
    n_sdp: int = 1                  # SDPs solved


def _symmetry(ps: PolySystem, F: list[Poly], fixed: tuple[Poly, ...]) -> np.ndarray:
    """Generators (over GF(2)) of the sign symmetries ``z -> D_s z`` of the program: ``F`` equivariant
    (``F_i(D z) = (-1)^{s_i} F_i(z)``), the denominator, cuts, valid inequalities and the fixed polynomials
    (``V`` of a level problem, ``lambda`` of a V step) invariant, each equality mapped to plus or minus itself. The
    program is then invariant, and restricting every unknown to the invariant (or matching) monomials loses nothing:
    averaging a feasible point over the group gives a feasible invariant one with the same level."""
    nz = ps.nz
    rows: list[tuple[int, ...]] = []
    for i, f in enumerate(F):
        rows += [tuple(a + (j == i) for j, a in enumerate(e)) for e in f.terms]
    for q in (ps.den, *ps.cuts, *ps.valid, *fixed):
        rows += list(q.terms)
    for h in ps.equalities:
        e0 = next(iter(h.terms), None)
        rows += [tuple(a + b for a, b in zip(e, e0, strict=True)) for e in h.terms]
    return parity_generators(rows, nz) if rows else np.eye(nz, dtype=int)


def _char(G: np.ndarray, q: Poly | None) -> tuple[int, ...]:
    """Parity class of ``q`` under ``G`` (constant over its support by construction of :func:`_symmetry`)."""
    e = next(iter(q.terms), None) if q is not None else None
    if e is None or G.size == 0:
        return (0,) * G.shape[0]
    return tuple(int(v) for v in (G @ np.asarray(e)) % 2)


def _sym(basis: list[tuple[int, ...]], G: np.ndarray, char: tuple[int, ...]) -> list[tuple[int, ...]]:
    """The monomials of ``basis`` in parity class ``char``."""
    if G.size == 0:
        return basis
    want = np.asarray(char, dtype=int)
    E = np.asarray(basis, dtype=int).reshape(len(basis), -1)
    ok = np.all((E @ G.T) % 2 == want, axis=1)
    return [b for b, k in zip(basis, ok, strict=True) if k]


def _sym_blocks(basis: list[tuple[int, ...]], G: np.ndarray) -> list[list[tuple[int, ...]]]:
    """Half basis of an invariant SOS multiplier: one Gram block per parity class (its square terms are then all
    invariant)."""
    return sign_classes(basis, G) if basis else []


def build_program(ps: PolySystem, F: list[Poly], degV: int, *, V: Poly | None, lam: Poly | None, rho: float | None,
           eps: float, extra: int = 0, margin: bool = False, symmetry: bool = True, cone: str = "sos",
           V0: Poly | None = None) -> tuple[SOSProgram, dict[str, Any]]:
    """Common builder. Exactly one of ``V`` (level problem) and ``lam`` (V step) is given. With ``symmetry``, the
    unknowns are restricted to the sign symmetries of the program (:func:`_symmetry`; exact), and every SOS
    constraint's half basis is reduced exactly (:func:`~glidectl.roa.sos.reduce_basis`).

    Surrogate route: the level problem bounds ``dV/dt`` by ``grad V . F`` plus the robust term of
    :func:`~glidectl.roa.surrogate.robust_decrease_bound` (sound). The V step, where that term would not be
    linear in the unknown ``V``, adds the robust term of the previous ``V0`` instead: a guide only, since every
    ``V`` it returns is certified by a level problem."""
    nz = ps.nz
    degF = max(f.degree for f in F)
    R, B = _remainder(ps, F)                                # surrogate route: |true - F| <= R + B q^1.5
    if R:
        degF = robust_degree(degV, degF)
    dg = _degrees(degV, degF, extra)
    prog = SOSProgram(nz, reduce=symmetry, cone=cone)
    quot = _quotient(ps, _n_monomials(nz, dg.D // 2, 1, len(ps.s_caps)))
    prog.quotient = quot
    out: dict[str, Any] = {}

    def ideal(name: str, basis: list[tuple[int, ...]], h: Poly, extra: set[tuple[int, ...]]) -> Any:
        """``phi h`` for a free multiplier ``phi`` on ``basis``; none for an equality of the quotient (matched
        modulo it: the monomials ``phi h`` would have go to ``extra``, for the basis reduction)."""
        if quot is not None and quot.covers(h):
            extra.update(tuple(a + b for a, b in zip(m, e, strict=True)) for m in basis for e in h.terms)
            return None
        return prog.free_poly(name, basis)[1] * h
    fixed = tuple(p for p in (V, lam) if p is not None)
    G = _symmetry(ps, F, fixed) if symmetry else np.zeros((0, nz), dtype=int)
    out["symmetry"] = G
    zero = (0,) * G.shape[0]
    if margin:
        out["margin"] = prog.enable_margin()
    N = _zsq(nz) ** dg.m
    if V is not None:
        Vl = _lin(V)
        lam_u, lam_l = prog.free_poly("lambda", _sym(monomials(nz, dg.lam), G, zero))
        out["lambda"] = lam_u
        W = V.lie(F)
        if R:   # robust decrease: dV/dt <= grad V . F + sum_i r_i |dV/dz_i| <= W (a polynomial, Young)
            grads = [V.diff(i) for i in range(nz)]
            W = W + robust_decrease_bound(ps, grads, R, B, young_weights(ps, V, R, B))
        out["W"] = W
        dec = Vl * N + _times(lam_l, W)
    else:
        V_u, Vl = prog.free_poly("V", _sym(_state_monomials(ps, degV), G, zero))
        out["V"] = V_u
        Vd = Vl.lie(F)
        if R and V0 is not None:    # the previous V's robust term: a guide (see the docstring)
            Vd = Vd + robust_decrease_bound(ps, [V0.diff(i) for i in range(nz)], R, B, young_weights(ps, V0, R, B))
        dec = _plus(Vl * N, _times(Vd, lam))
    if rho is None:
        rho_u, rho_l = prog.scalar("rho")
        out["rho"] = rho_u
    else:
        rho_l = _lin(rho if isinstance(rho, _Fixed) else Poly.const(rho, nz))
    dec = dec - rho_l * N
    lows = _tau_low_degrees(ps)
    for k, g in enumerate(ps.cuts + ps.valid):
        _, tau = prog.sos_poly_blocks(f"tau{k}", _sym_blocks(monomials(nz, (dg.D - g.degree) // 2, lows[k]), G))
        dec = dec - tau * g
    extra: set[tuple[int, ...]] = set()
    for j, h in enumerate(ps.equalities):
        if h.degree > dg.D:     # (a cubic graph equality of a saturated loop with a low-degree program)
            continue
        psi_h = ideal(f"psi{j}", _sym(monomials(nz, dg.D - h.degree), G, _char(G, h)), h, extra)
        if psi_h is not None:
            dec = dec + psi_h
    _add_sos(prog, "decrease", dec, monomials(nz, dg.D // 2, 1, ps.s_caps), extra)
    for k, g in enumerate(ps.cuts):
        dk = even_up(max(degV, g.degree))
        # a cut in the states alone (a box cut of a saturated loop): V - rho + sigma g has no saturated-input
        # variable unless the multipliers bring one in, and a certificate without them is a certificate; with them,
        # the rows of the Gram matrix in those variables are forced towards 0 (a structural zero eigenvalue that no
        # backoff removes), so sigma, the equality multipliers and the half basis leave them out
        no_in = _drop_inputs(ps) if ps.inputs and not _uses(g, ps.inputs) else (lambda b: b)
        _, sig = prog.sos_poly_blocks(f"sigma{k}", _sym_blocks(no_in(monomials(nz, (dk - g.degree) // 2)), G))
        cont = Vl - rho_l + sig * g
        extra = set()
        for j, h in enumerate(ps.equalities):
            if h.degree > dk or (ps.inputs and not _uses(g, ps.inputs) and _uses(h, ps.inputs)):
                continue
            phi_h = ideal(f"phi{k}_{j}", _sym(no_in(monomials(nz, dk - h.degree)), G, _char(G, h)), h, extra)
            if phi_h is not None:
                cont = cont + phi_h
        _add_sos(prog, f"containment{k}", cont, no_in(monomials(nz, dk // 2, 0, ps.s_caps)), extra)
    if V is None:
        pos = Vl - _state_zsq(ps) * eps
        # V and |x|^2 have no saturated-input variable: as for the containment of a state cut, leave them out
        no_in = _drop_inputs(ps) if ps.inputs else (lambda b: b)
        extra = set()
        for j, h in enumerate(ps.equalities):
            if h.degree > degV or (ps.inputs and _uses(h, ps.inputs)):
                continue
            chi_h = ideal(f"chi{j}", _sym(no_in(monomials(nz, degV - h.degree)), G, _char(G, h)), h, extra)
            if chi_h is not None:
                pos = pos + chi_h
        _add_sos(prog, "positivity", pos, no_in(monomials(nz, degV // 2, 1, ps.s_caps)), extra)
    return prog, out


def _quotient(ps: PolySystem, n_decrease: int) -> Any:
    """The angle quotient of ``ps`` (:func:`~glidectl.roa.quotient.angle_quotient`) for a program whose decrease
    Gram matrix has order ``n_decrease`` (unreduced count), or None
    (:attr:`~glidectl.roa.moment.MomentPolicy.quotient_min_block`)."""
    return angle_quotient(ps.nz, ps.equalities) if moment.MOMENT_POLICY.uses_quotient(n_decrease) else None


def _tau_low_degrees(ps: PolySystem) -> list[int]:
    """Lowest degree of the half basis of each S-procedure multiplier ``tau_k`` of the decrease condition
    (``ps.cuts + ps.valid``): 1 for a cut with ``g_k(0) > 0``, else 0.

    The decrease polynomial has no constant term and its half basis no constant monomial, so
    ``sum_k tau_k(0) g_k(0) = 0``. When no cut is negative at the equilibrium and no equality has a constant term
    (which ``psi_j h_j`` could balance), every ``tau_k`` with ``g_k(0) > 0`` has ``tau_k(0) = 0``, hence (its Gram
    matrix being PSD) no linear terms either: its half basis starts at degree 1. An exact facial reduction: the
    program keeps a strictly feasible point, and no solver residual is left on the constant monomial that no Gram
    entry reaches (the ``low`` residual of :class:`~glidectl.roa.sos.GramCheck`)."""
    zero = (0,) * ps.nz
    g0 = [g.terms.get(zero, 0.0) for g in ps.cuts + ps.valid]
    ok = all(h.terms.get(zero, 0.0) == 0.0 for h in ps.equalities) and min(g0, default=0.0) >= 0.0
    return [1 if ok and v > 0.0 else 0 for v in g0]


def _uses(p: Poly, idx: tuple[int, ...]) -> bool:
    """Whether the polynomial ``p`` has a term in any of the variables ``idx``."""
    return any(e[i] for e in p.terms for i in idx)


def _drop_inputs(ps: PolySystem) -> Any:
    """A filter of monomial lists: the monomials without the saturated-input variables ``ps.inputs``."""
    return lambda basis: [e for e in basis if not any(e[i] for i in ps.inputs)]


def _state_monomials(ps: PolySystem, degree: int) -> list[tuple[int, ...]]:
    """Monomials of ``V`` (degrees 1 to ``degree``): none in the saturated-input variables ``ps.inputs``."""
    return [e for e in monomials(ps.nz, degree, 1) if not any(e[i] for i in ps.inputs)]


def _state_zsq(ps: PolySystem) -> Poly:
    """``|z|^2`` over the variables of the states (all but the saturated-input variables ``ps.inputs``)."""
    return sum((Poly.var(i, ps.nz) ** 2 for i in range(ps.nz) if i not in ps.inputs), Poly({}, ps.nz))


class _Fixed:
    """A fixed polynomial of a program given as cvxpy ``Parameter``s: ``sum_j p[j] q_j`` (``q_j`` known
    polynomials, ``p`` one Parameter vector), so that the same compiled program is re-solved for new coefficients
    (``V`` of the level problems, ``lambda`` of the V steps, the level of the centering problem). ``terms`` is the
    generic support (every ``q_j``), which :func:`_symmetry` and the basis reduction see: an outer approximation of
    the support of every instance, so both stay exact."""

    def __init__(self, q: list[Poly]) -> None:
        self.q = q
        self.nvars = q[0].nvars
        self.p = cp.Parameter(len(q))
        self.terms = {e: 1.0 for qj in q for e in qj.terms}

    @classmethod
    def on(cls, basis: list[tuple[int, ...]], nvars: int) -> _Fixed:
        return cls([Poly({e: 1.0}, nvars) for e in basis])

    @property
    def degree(self) -> int:
        return max(qj.degree for qj in self.q)

    def lie(self, F: list[Poly]) -> _Fixed:
        out = _Fixed.__new__(_Fixed)
        out.q, out.nvars, out.p = [qj.lie(F) for qj in self.q], self.nvars, self.p
        out.terms = {e: 1.0 for qj in out.q for e in qj.terms}
        return out

    def set(self, P: Poly) -> bool:
        """Set the Parameters to the coefficients of ``P`` on monomial ``q_j``; False if ``P`` has a term outside."""
        pos = {next(iter(qj.terms)): j for j, qj in enumerate(self.q)}
        if any(e not in pos for e in P.terms):
            return False
        v = np.zeros(len(self.q))
        for e, c in P.terms.items():
            v[pos[e]] = c
        self.p.value = v
        return True


class _PLin:
    """``L_0 + sum_(p, j) p[j] L_pj``: a :class:`~glidectl.roa.sos.LinPoly` plus Parameter-weighted ones (the
    expressions of a program with :class:`_Fixed` polynomials; affine in the unknowns for fixed Parameters).
    ``parts`` maps ``(id(p), j)`` to ``(p, L_pj)``."""

    def __init__(self, L0: LinPoly, parts: dict[tuple[int, int], tuple[Any, LinPoly]]) -> None:
        self.L0, self.parts = L0, parts

    def __add__(self, other: Any) -> _PLin:
        if isinstance(other, _PLin):
            parts = dict(self.parts)
            for k, (p, L) in other.parts.items():
                parts[k] = (p, parts[k][1] + L) if k in parts else (p, L)
            return _PLin(self.L0 + other.L0, parts)
        return _PLin(self.L0 + other, dict(self.parts))

    __radd__ = __add__

    def __neg__(self) -> _PLin:
        return self * -1.0

    def __sub__(self, other: Any) -> _PLin:
        return self + (-other)

    def __rsub__(self, other: Any) -> _PLin:
        return (-self) + other

    def __mul__(self, k: Any) -> _PLin:
        return _PLin(self.L0 * k, {key: (p, L * k) for key, (p, L) in self.parts.items()})

    __rmul__ = __mul__

    def lie(self, F: list[Poly]) -> _PLin:
        return _PLin(self.L0.lie(F), {key: (p, L.lie(F)) for key, (p, L) in self.parts.items()})

    def value(self, values: Any = None) -> Poly:
        """The polynomial at the solved unknowns (``values[u]`` instead where given, see LinPoly.value) and the
        current Parameter values."""
        out = self.L0.value(values)
        for (_, j), (p, L) in self.parts.items():
            out = out + L.value(values) * float(p.value[j])
        return out


def _lin(P: Any) -> Any:
    """``LinPoly(P)`` of a known polynomial, or the :class:`_PLin` of a :class:`_Fixed` one."""
    if isinstance(P, _Fixed):
        return _PLin(LinPoly(Poly({}, P.nvars)), {(id(P.p), j): (P.p, LinPoly(qj)) for j, qj in enumerate(P.q)})
    return LinPoly(P)


def _times(L: LinPoly, P: Any) -> Any:
    """``L * P`` for a :class:`~glidectl.roa.sos.LinPoly` ``L`` and a known or :class:`_Fixed` polynomial ``P``."""
    if isinstance(P, _Fixed):
        return _PLin(LinPoly(Poly({}, P.nvars)), {(id(P.p), j): (P.p, L * qj) for j, qj in enumerate(P.q)})
    return L * P


def _plus(a: Any, b: Any) -> Any:
    """``a + b`` where ``b`` may be a :class:`_PLin` and ``a`` a LinPoly (LinPoly does not know _PLin)."""
    return b + a if isinstance(b, _PLin) and not isinstance(a, _PLin) else a + b


def _add_sos(prog: SOSProgram, name: str, expr: Any, half_basis: list[tuple[int, ...]],
             ideal_support: set[tuple[int, ...]] | None = None) -> None:
    """:meth:`SOSProgram.add_sos`, also for a :class:`_PLin` ``expr``: the half basis is reduced on the union of
    the supports of all its parts (an outer approximation of the support for any Parameter values: exact) and
    ``ideal_support`` (the monomials of the multiples of the equalities the quotient form leaves out), and the
    coefficient equalities are ``A_0 x + b_0 + sum p[j] (A_pj x + b_pj) = 0`` (DPP: compiled once), of the normal
    forms with a :attr:`~glidectl.roa.sos.SOSProgram.quotient`."""
    extra = ideal_support or set()
    if not isinstance(expr, _PLin):
        prog.add_sos(name, expr, half_basis, support=sorted(extra))
        return
    support = linear_support(expr.L0) | extra
    for _, L in expr.parts.values():
        support |= linear_support(L)
    blocks = reduce_basis(support, half_basis) if prog.reduce else [list(half_basis)]
    us, g = prog.sos_poly_blocks(name + ".gram", blocks, margin=True)
    nf = prog.quotient.linpoly if prog.quotient is not None else (lambda L: L)
    L0 = nf(expr.L0 - g)
    parts = [(p, j, nf(L)) for (_, j), (p, L) in expr.parts.items()]
    monos: dict[tuple[int, ...], int] = {}
    for e in sorted(set().union(linear_support(L0), *(linear_support(L) for _, _, L in parts))):
        monos[e] = len(monos)
    lhs = _coefficient_map(L0, monos)
    for p, j, L in parts:
        lhs = lhs + p[j] * _coefficient_map(L, monos)
    prog.constraints.append(lhs == 0)
    prog.sos_constraints.append((name, expr, us))
    prog.full_bases[name] = [tuple(b) for b in half_basis]


def _coefficient_map(L: LinPoly, monos: dict[tuple[int, ...], int]) -> Any:
    """The coefficients of ``L`` on ``monos`` as a cvxpy expression ``sum_u A_u x_u + b``."""
    m = len(monos)
    b = np.zeros(m)
    for e, c in L.const.terms.items():
        b[monos[e]] = c
    out: Any = b
    for u, cols in L.parts.items():
        rows, cidx, vals = [], [], []
        for k, c in enumerate(cols):
            for e, x in c.terms.items():
                rows.append(monos[e])
                cidx.append(k)
                vals.append(x)
        out = out + sps.csr_matrix((vals, (rows, cidx)), shape=(m, u.size)) @ u.flat
    return out


def _remainder(ps: PolySystem, F: list[Poly]) -> tuple[list[Poly], np.ndarray]:
    """The remainder bound of a surrogate system (its polynomial parts and cubic coefficients) divided by the factor
    ``F`` was divided by (``scaled_field``)."""
    if not ps.remainder:
        return [], np.zeros(0)
    k = max(f.max_abs_coefficient() for f in ps.F) / max(max(f.max_abs_coefficient() for f in F), 1e-300)
    return [r / k for r in ps.remainder], np.asarray(ps.remainder_cubic, dtype=float) / k


def variable_scaling(ps: PolySystem) -> np.ndarray:
    """Scale of each polynomial variable (largest ``|z_i|`` over the box; angle pairs keep 1)."""
    lo, hi = ps.box
    Z = ps.lift(lo + (hi - lo) * unit_sobol(ps.n, 3, 1024))
    k = np.max(np.abs(Z), axis=0)
    for i in ps.angle_states + ps.mixed_states:   # (x, s, c) of angles keep their natural scale
        k[list(ps.slots[i])] = 1.0
    return np.where(k > 0, k, 1.0)


def rescaled(ps: PolySystem, k: np.ndarray) -> PolySystem:
    """The same system in ``zhat = z / k`` (better conditioned SDPs; SOS is invariant under the scaling)."""
    Z = Poly.variables(ps.nz)
    Kz = [Z[i] * float(k[i]) for i in range(ps.nz)]
    lift0 = ps.lift
    return dataclasses.replace(
        ps, F=tuple(f.substitute(Kz) / float(k[i]) for i, f in enumerate(ps.F)), den=ps.den.substitute(Kz),
        equalities=tuple(h.substitute(Kz) for h in ps.equalities), cuts=tuple(g.substitute(Kz) for g in ps.cuts),
        valid=tuple(g.substitute(Kz) for g in ps.valid),
        remainder=tuple(r.substitute(Kz) / float(k[i]) for i, r in enumerate(ps.remainder)),
        remainder_cubic=tuple(float(b) / float(k[i]) for i, b in enumerate(ps.remainder_cubic)),
        remainder_norm=None if ps.remainder_norm is None else ps.remainder_norm.substitute(Kz),
        lift=lambda X: lift0(X) / k)


def to_scaled(V: Poly, k: np.ndarray) -> Poly:
    Z = Poly.variables(V.nvars)
    return V.substitute([Z[i] * float(k[i]) for i in range(V.nvars)])


def from_scaled(V: Poly, k: np.ndarray) -> Poly:
    Z = Poly.variables(V.nvars)
    return V.substitute([Z[i] / float(k[i]) for i in range(V.nvars)])


def _centers_by_level(prog: SOSProgram, solver: str) -> bool:
    """Whether the centering multiplier comes from the level program itself re-solved with ``rho <= (1 - center)
    rho*`` (its optimal face is the feasibility program's set; the solver returns a point inside it) instead of
    the feasibility program by Clarabel: with the ``CVXOPT_MOMENT`` solver (which takes such a program on the
    moment form when :func:`~glidectl.roa.moment.moment_pays`) and a Gram block of order
    :attr:`~glidectl.roa.moment.MomentPolicy.center_by_level_min_block` or more."""
    largest = max((max(b, default=0) for b in prog.gram_sizes().values()), default=0)
    return moment.MOMENT_POLICY.centers_by_level(solver, largest)


def _capped_centre(prog: SOSProgram, out: dict[str, Any], cap: Any, rho: float, center: float,
                   solver: str) -> Poly:
    """The multiplier of the level program ``prog`` (solved, with ``rho <= cap``) re-solved with its cap at
    ``(1 - center) rho`` (:func:`_centers_by_level`)."""
    cap.value = (1 - center) * rho
    prog.resolve(solver=solver)
    return out["lambda"].poly()


def solve_level(ps: PolySystem, F: list[Poly], V: Poly, *, rho_cap: float, solver: str, center: float,
           extra: int, cache: dict | None = None, basis: Any = None, cone: str = "sos") -> LevelResult:
    """The level problem for a fixed ``V``: ``rho`` is a variable of the SDP (no bisection). With ``center > 0``
    a multiplier with slack for the V step is found at ``(1 - center) rho*``: by the level program re-solved with
    ``rho <= (1 - center) rho*`` where :func:`_centers_by_level` says so, else by a feasibility SDP at that level
    (the interior-point solution of the program built with that fixed level). With a ``cache`` (exact route), the
    programs are built once per monomial ``basis`` of ``V`` with ``V`` and the levels as cvxpy Parameters and
    re-solved (:func:`_level_reused`)."""
    if cache is not None and not ps.remainder and cone == "sos":
        res = _level_reused(ps, F, V, rho_cap=rho_cap, solver=solver, center=center, extra=extra, cache=cache,
                            basis=sorted(V.terms) if basis is None else list(basis))
        if res is not None:
            return res
    degV = even_up(V.degree)
    prog, out = build_program(ps, F, degV, V=V, lam=None, rho=None, eps=0.0, extra=extra, cone=cone)
    cap = cp.Parameter(value=rho_cap)
    prog.constraints.append(out["rho"].var <= cap)
    prog.solve(cp.Maximize(out["rho"].var[0]), solver=solver)
    rho = float(out["rho"].value()[0])
    checks, status, lam = tuple(prog.check()), prog.status, out["lambda"].poly()
    t, tc, ts, n = prog.solve_time, prog.compile_time, prog.solver_time, 1
    if center > 0:
        if _centers_by_level(prog, solver):
            lam, prog2 = _capped_centre(prog, out, cap, rho, center, solver), prog
        else:
            prog2, out2 = build_program(ps, F, degV, V=V, lam=None, rho=(1 - center) * rho, eps=0.0, extra=extra,
                                 cone=cone)
            prog2.solve(cp.Minimize(0), solver=solver)
            lam = out2["lambda"].poly()
        t, tc, ts, n = t + prog2.solve_time, tc + prog2.compile_time, ts + prog2.solver_time, 2
    return LevelResult(rho, lam, checks, t, status, tc, ts, n)


def _level_reused(ps: PolySystem, F: list[Poly], V: Poly, *, rho_cap: float, solver: str, center: float,
                  extra: int, cache: dict, basis: list[tuple[int, ...]]) -> LevelResult | None:
    """:func:`solve_level` through programs built once per (degree, basis of ``V``) with the coefficients of ``V`` and
    the levels as cvxpy Parameters: the same SOS conditions, compiled once and re-solved. None if ``V`` has a term
    outside ``basis``."""
    degV = even_up(V.degree)
    basis = sorted(basis)
    key = ("level", degV, tuple(basis))
    if key not in cache:
        Vp = _Fixed.on(basis, ps.nz)
        prog, out = build_program(ps, F, degV, V=Vp, lam=None, rho=None, eps=0.0, extra=extra)
        cap = cp.Parameter(value=rho_cap)
        prog.constraints.append(out["rho"].var <= cap)
        cache[key] = (prog, out, Vp, cap)
    prog, out, Vp, cap = cache[key]
    if not Vp.set(V):
        return None
    cap.value = rho_cap
    if prog.problem is None:
        prog.solve(cp.Maximize(out["rho"].var[0]), solver=solver)
    else:
        prog.resolve(solver=solver)
    rho = float(out["rho"].value()[0])
    checks, status, lam = tuple(prog.check()), prog.status, out["lambda"].poly()
    t, tc, ts, n = prog.solve_time, prog.compile_time, prog.solver_time, 1
    if center > 0 and _centers_by_level(prog, solver):
        lam = _capped_centre(prog, out, cap, rho, center, solver)
        t, tc, ts, n = t + prog.solve_time, tc + prog.compile_time, ts + prog.solver_time, 2
    elif center > 0:
        key2 = ("center", degV, tuple(basis))
        if key2 not in cache:
            Vc, rp = _Fixed.on(basis, ps.nz), _Fixed([Poly.const(1.0, ps.nz)])
            prog2, out2 = build_program(ps, F, degV, V=Vc, lam=None, rho=rp, eps=0.0, extra=extra)
            cache[key2] = (prog2, out2, Vc, rp)
        prog2, out2, Vc, rp = cache[key2]
        Vc.set(V)
        rp.p.value = np.array([(1 - center) * rho])
        if prog2.problem is None:
            prog2.solve(cp.Minimize(0), solver=solver)
        else:
            prog2.resolve(solver=solver)
        lam = out2["lambda"].poly()
        t, tc, ts, n = t + prog2.solve_time, tc + prog2.compile_time, ts + prog2.solver_time, 2
    return LevelResult(rho, lam, checks, t, status, tc, ts, n)


def solve_v_step(ps: PolySystem, F: list[Poly], degV: int, lam: Poly, Zt: np.ndarray, *, eps: float, extra: int,
            solver: str, cache: dict | None, V0: Poly | None = None) -> tuple[SOSProgram, dict[str, Any]]:
    """The V step for the multiplier ``lam`` (solved): ``V`` of degree ``degV`` minimizing ``mean(max(V - 1, 0))``
    over the simulated points ``Zt``. With a ``cache`` (exact route) the program is built once per (degree, support
    of ``lam``) with the coefficients of ``lam`` as cvxpy Parameters and re-solved."""
    key = ("V step", degV, tuple(sorted(lam.terms)))
    if cache is None or ps.remainder or lam.is_zero:
        prog, out = build_program(ps, F, degV, V=None, lam=lam, rho=1.0, eps=eps, extra=extra, V0=V0)
    elif key not in cache:
        lp = _Fixed.on(list(key[2]), ps.nz)
        prog, out = build_program(ps, F, degV, V=None, lam=lp, rho=1.0, eps=eps, extra=extra)
        cache[key] = (prog, out, lp)
    if cache is not None and key in cache:
        prog, out, lp = cache[key]
        lp.set(lam)
        if prog.problem is not None:
            prog.resolve(solver=solver, **steering_options(solver))
            return prog, out
    prog.solve(coverage_objective(prog, out["V"], Zt), solver=solver, **steering_options(solver))
    return prog, out


def coverage_objective(prog: SOSProgram, V: Any, Zt: np.ndarray) -> Any:
    """The V step's objective ``mean(max(V(z_k) - 1, 0))`` over the simulated points ``Zt``, with its constraints
    added to ``prog``: ``max(V(z_k) - 1, 0) = p_k`` at the optimum of ``min sum p`` with ``V(z_k) - 1 = p_k - q_k``,
    ``p, q >= 0``. Each ``p_k``, ``q_k`` sits in one cone row, so the moment form of ``CVXOPT_MOMENT`` eliminates
    both and keeps one equation per sample; ``cp.pos`` would make one variable in two rows, two equations per
    sample (the same optimum)."""
    M = monomial_matrix(Zt, V.basis)
    p, q = cp.Variable(len(Zt), nonneg=True), cp.Variable(len(Zt), nonneg=True)
    prog.constraints.append(M @ V.var - 1 == p - q)
    return cp.Minimize(cp.sum(p) / len(Zt))


@pinned_blas
def max_level(system: Any, V: Poly, *, rho_cap: float = 1e6, solver: str = DEFAULT_SOLVER,
              extra: int | None = None, max_degree: int = MAX_DEGREE, memory_limit: float | None = None) -> LevelResult:
    """Largest ``rho`` of the level problem for a fixed ``V`` (one SDP, no bisection).

    Parameters
    ----------
    system : PolySystem or glidectl model (recast with :func:`~glidectl.roa.systems.recast`)
    V : Poly
        Candidate in the system's polynomial variables, ``V(0) = 0``, positive definite.
    rho_cap : float
        Upper bound on ``rho`` (a globally valid ``V`` would make the program unbounded).
    extra : int, optional
        Extra degree (in steps of 2) of the multipliers above the smallest that balances the degrees; default 2
        for up to 3 polynomial variables, else 0 (with the smallest multipliers the level depends on the scaling
        of ``N = (z.z)^m``; richer multipliers remove that dependence).
    max_degree, memory_limit :
        Budgets checked before anything is built, as in :func:`certify_roa`.

    Returns
    -------
    LevelResult
        ``lam`` is returned in the scaled variables used internally (see :func:`certify_roa`).

    Raises
    ------
    ArgumentTypeError
        If ``V`` is not a Poly, or an option has the wrong type.
    ArgumentError
        If ``V`` is not in the system's ``nz`` variables or ``V(0) != 0``, ``rho_cap`` is not a positive finite
        number, or ``solver`` is not an installed SDP solver.
    BudgetError
        If the degree of ``V`` exceeds ``max_degree`` or the program would exceed ``memory_limit``.
    SolverError
        If the SDP solver fails or returns a status other than optimal.
    ModelError
        If ``system`` is a model that cannot be recast exactly (:func:`~glidectl.roa.systems.recast`).

    Examples
    --------
    >>> import glidectl as gc
    >>> vdp = gc.benchmarks.van_der_pol()
    >>> res = gc.max_level(vdp, gc.lyapunov_quadratic(vdp))
    >>> res.status, f"rho = {res.rho:.1f}"
    ('optimal', 'rho = 2.3')
    """
    ps = recast(system)
    check_candidate(V, ps, "V")
    rho_cap = checks.positive("rho_cap", rho_cap)
    check_solver(solver)
    ex = auto_extra(ps, extra)
    max_degree = checks.integer("max_degree", max_degree, lo=2)
    limit = default_memory_limit() if memory_limit is None else checks.positive("memory_limit", memory_limit)
    check_memory(ps, even_up(max(V.degree, 2)), ex, max_degree, limit, "max_level")
    k = variable_scaling(ps)
    pss = rescaled(ps, k)
    return solve_level(pss, scaled_field(pss), to_scaled(V, k), rho_cap=rho_cap, solver=solver, center=0.0, extra=ex)


def check_candidate(V: Any, ps: PolySystem, name: str) -> Poly:
    if not isinstance(V, Poly):
        raise ArgumentTypeError(f"{name} must be a glidectl.roa.Poly in the system's {ps.nz} polynomial variables "
                                f"{ps.z_names}, got {type(V).__name__}")
    if V.nvars != ps.nz:
        raise ArgumentError(f"{name} has {V.nvars} variables; the system '{ps.name}' has {ps.nz}: {ps.z_names}")
    c0 = V.terms.get((0,) * V.nvars, 0.0)
    if V.is_zero or abs(c0) > 1e-12 * V.max_abs_coefficient():
        raise ArgumentError(f"{name} must vanish at the equilibrium (V(0) = 0) and not be zero, got V(0) = {c0:g}")
    if not all(math.isfinite(c) for c in V.terms.values()):
        raise ArgumentError(f"{name} has non-finite coefficients")
    return V

def is_certification_model(system: Any) -> bool:
    """A model built for certification: equilibrium at 0 and its own box (``sp.reduced_model()``...)."""
    eq = getattr(system, "equilibrium", None)
    return (hasattr(system, "box") and eq is not None and not callable(system.box)
            and np.all(np.asarray(eq, dtype=float) == 0.0))
