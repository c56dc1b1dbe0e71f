"""Region-of-attraction certificates by SOS programs: level maximization, V-lambda alternation, verification.

For ``dz/dt = F(z)/den(z)`` on ``{h = 0} ∩ {g >= 0}`` (:class:`~glidectl.roa.systems.PolySystem`) and a polynomial
``V`` with ``V(0) = 0``, the *level problem* (one SDP, linear in the level ``rho``; the form used by Drake's
``RegionOfAttraction``, extended by S-procedure terms for cuts and equality multipliers) is::

    maximize rho  s.t.  (V - rho) N + lambda * (grad V . F) - sum_k tau_k g_k + sum_j psi_j h_j  is SOS,
                        (V - rho) + sigma_k g_k + sum_j phi_kj h_j                             is SOS (each k),
                        tau_k, sigma_k SOS,  lambda, psi, phi free,   N = (z . z)^m.

The first line says: wherever ``dV/dt = 0`` inside the cuts, ``V >= rho``; with ``dV/dt < 0`` near the equilibrium
(checked from the linearization) the connected component of ``{V < rho}`` containing the equilibrium has
``dV/dt < 0`` except at the equilibrium. The second says: outside a cut, ``V >= rho``, so that component stays
where the denominator is positive. Its closure is compact (``V >= eps |z|^2``), hence positively invariant and in
the region of attraction (LaSalle).

The *V step* fixes ``lambda`` (taken from the level problem re-solved slightly below its optimum, so that it has
slack) and solves for ``V`` and every other multiplier at ``rho = 1`` with ``V - eps |z|^2`` SOS, minimizing
``mean(max(V - 1, 0))`` over box points whose simulations converge: the simulated region of attraction steers the
search, the certificate never depends on it. The previous ``V`` stays feasible, the best ``V`` by sampled volume is
kept, and the degree of ``V`` is raised 2 -> 4 -> 6 with the previous ``V`` as the starting point.

**Speed** (exact, no certificate is weakened): every SOS constraint's half basis is reduced by the Newton polytope,
diagonal consistency and sign symmetry (:func:`~glidectl.roa.sos.reduce_basis`), and when the system has sign
symmetries (odd Van der Pol: ``x -> -x``) every unknown is restricted to the matching monomials (:func:`_symmetry`);
in the large programs, the angle equalities ``s^2 + c^2 - 2 c = 0`` of a recast are not multiplied by free ``psi_j``,
``phi_kj``: every coefficient is matched modulo them instead (:mod:`glidectl.roa.quotient`,
:data:`QUOTIENT_MIN_BLOCK`; the same feasible set);
the level is a variable of one SDP (no bisection), the back-off re-solves reuse the compiled program through a cvxpy
``Parameter`` (the level), and the final level is not searched again (the kept ``V`` is normalized by its
own optimal level). Each history entry records ``sdp_time`` and, split, ``compile_time`` (cvxpy) and
``solver_time`` (the solver's own time).

Every certificate is stated at a backed-off level ``rho_c = (1 - backoff) rho*``, re-solved at that fixed level
with the largest Gram eigenvalue margin, and verified a posteriori (:class:`ROAVerification`): exact SOS by Gram
eigenvalue margins against coefficient residuals, the local conditions at the equilibrium, ``dV/dt < 0`` of the
*true model* at sampled points of the set, and convergence of simulations started in it.
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import cvxpy as cp
import numpy as np
import scipy.sparse as sps
from scipy.linalg import solve_continuous_lyapunov
from scipy.stats import qmc

from .. import checks
from ..analysis.jacobian import hessian, jacobians
from ..analysis.measure import MIN_SOBOL_HITS, box_measure
from ..batch import integrate_batch
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, SolverError
from .blas_threads import pinned_blas
from .lmi import SaturatedLoop, held_motion, held_points
from .polynomial import Poly, monomial_matrix, monomials
from .quotient import angle_quotient
from .scaling import resolve_box, scaled_lyapunov
from .sdp_solvers import DEFAULT_SOLVER, MOMENT, check_solver, steering_options
from .sector import sector_system
from .sos import (
    GRAM_CONES,
    GramCheck,
    LinPoly,
    SOSProgram,
    linear_support,
    parity_generators,
    reduce_basis,
    sign_classes,
)
from .surrogate import (
    refine_equilibrium,
    robust_decrease_bound,
    robust_degree,
    skeleton,
    surrogate_system,
    young_weights,
)
from .systems import PolySystem, recast

__all__ = ["MAX_DEGREE", "MEMORY_FRACTION", "LevelResult", "ROACertificate", "ROAVerification", "SOSSize",
           "certify_roa", "dVdt", "estimate_sos_size", "lyapunov_matrix", "lyapunov_quadratic", "max_level"]

QUOTIENT_MIN_BLOCK = 64
"""Programs whose decrease Gram matrix has at least this order (as :func:`estimate_sos_size` counts it) match the
coefficients of every SOS condition modulo the angle equalities ``s^2 + c^2 - 2 c = 0`` of a recast
(:mod:`glidectl.roa.quotient`) instead of through free multipliers ``psi_j``: the same feasible set, fewer
equations and no multiplier unknowns. These are the programs the whole alternation solves on the moment route
(:data:`CENTER_BY_LEVEL_MIN_BLOCK`), where the equations set the order of the dense factorization: on the CTOL
closed loop of ``bench/bench_roa.py`` the certificate took 54.3 s against 88.7 s with the V step's tolerances
(:data:`~glidectl.roa.sdp_solvers.STEERING_TOLERANCES`), 36.0 s against 81.5 s with the elimination of its sample
equations too (:data:`~glidectl.roa.sdp_solvers.ELIMINATE_DIAGONAL`), volume 0.00216064 throughout (2026-12-04,
one thread). Smaller programs keep the multiplier form: their V steps and centering programs are
Clarabel's, whose points on an optimal face or at a centre follow the equations as written, so the quotient form
changes their alternation's path for no measurable time (the full glider at K_M = -100, degree 2, 8 iterations:
29.0 s against 31.4 s, volume 0.1512 against 0.1687, one V step that gained less early on). ``math.inf``: never;
0: always (for comparisons)."""

#: Default largest degree of ``V`` that :func:`certify_roa` accepts (its ``max_degree``): degree 8 in 2 variables
#: takes ~20 s, degree 6 in 3 variables ~10 min, degree 4 in 5 variables about a minute (the 4-state glider on
#: the moment route, ``bench/bench_roa.py``'s glider4_staged; hours with Clarabel).
MAX_DEGREE = 8

#: Default ``memory_limit`` of :func:`certify_roa` and :func:`max_level`: this fraction of the physical memory.
MEMORY_FRACTION = 0.5

#: Bytes of memory per entry of the dense interior-point blocks of the Gram matrices (sum over Gram matrices of
#: ``(k (k + 1) / 2)^2``), measured on Clarabel runs of this module (75-95 bytes; rounded up), and the fixed part.
_BYTES_PER_KKT_ENTRY = 100.0
_BYTES_FIXED = 20e6
_BYTES_PER_GRAM_ENTRY = 1000.0      # the Python polynomials of the builder, per Gram entry

#: Largest monomial basis the automatic route tries to recast a closed loop with before using a surrogate (the
#: least-squares recovery costs seconds per thousand monomials; ``method="exact"`` tries up to degree 4).
_AUTO_RECAST_BASIS = 500

#: Smallest Gram block for which the centering multiplier of the alternation (``certify_roa``'s ``center``) comes
#: from the level program re-solved with ``rho <= (1 - center) rho*`` on the moment route, instead of the
#: feasibility program by Clarabel (:func:`_centers_by_level`). Clarabel factors the dense ``n(n+1)/2`` Hessian
#: block of each Gram matrix: a few seconds at the chapter-5 glider's 49 x 49, 65-95 s per program at the CTOL
#: loop's 103 x 103 and 45-60 s at the degree-4 glider's 104 x 104, where the moment route re-solves the level
#: program in 10-20 s. Below it the feasibility program stays: the two give different interior points, and on the
#: degree-2 glider the re-solved level program's multiplier steered the alternation to a smaller set (0.1436
#: against 0.1543).
CENTER_BY_LEVEL_MIN_BLOCK = 64

#: A V step whose new V has no positive level (or whose SDP fails) is tried once more, with the multiplier of the
#: current V's level problem at ``(1 - RETRY_CENTER) rho*`` instead of ``(1 - center) rho*`` (a history row "V step
#: failed (...): retried ..."); if that fails too, the alternation stops at the best V so far, as it did before.
#: The multiplier centred just inside the limit lets the V step push the new V's decrease condition to where
#: rounding decides it. On the saturated user glider (roa_certification), with Clarabel's iterative refinement
#: off (or at one step), the first V step of the second remainder-box round gave a level of -2.6e-9 (-2.8e-7), the
#: round was dropped and the certificate stayed at 4.7e-15; with the retry the round went on to 2.98e-12 (3.48e-12
#: with the default settings, where no step fails; ``bench/bench_roa_retry.py``). Not a tuned value: a multiplier
#: from well inside the set (a quarter of the way in).
RETRY_CENTER = 0.25


# --------------------------------------------------------------------------------------------- helpers
def _zsq(nz: int) -> Poly:
    return sum((Poly.var(i, nz) ** 2 for i in range(nz)), Poly({}, nz))


def _even_up(k: int) -> int:
    return k + (k % 2)


@dataclass(frozen=True)
class _Degrees:
    D: int          # degree of the decrease polynomial
    lam: int        # degree of lambda
    m: int          # N = (z.z)^m


def _degrees(degV: int, degF: int, extra: int = 0) -> _Degrees:
    dVd = degV - 1 + degF
    D = _even_up(max(degV + 2, dVd)) + 2 * extra
    return _Degrees(D, D - dVd, (D - degV) // 2)


def _auto_extra(ps: PolySystem, extra: int | None) -> int:
    """Extra multiplier degree: 2 for up to 3 polynomial variables (cheap, removes the dependence on ``N``), else 0
    (larger systems would not fit the SDP solver)."""
    return (2 if ps.nz <= 3 else 0) if extra is None else checks.integer("extra", extra, lo=0)


def _linearization(ps: PolySystem) -> np.ndarray:
    return jacobians(lambda x, u: ps.rhs(x[None, :])[0], ps.equilibrium, np.zeros(0))[0]


def _scaled(ps: PolySystem) -> list[Poly]:
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
    """
    ps = recast(ps)
    A = _linearization(ps)
    _require_exponential_stability(ps, A)
    try:
        P = solve_continuous_lyapunov(A.T, -np.eye(ps.n))
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"the Lyapunov equation A'P + PA = -I of '{ps.name}' failed: {exc}") from exc
    P = 0.5 * (P + P.T)
    if not np.all(np.isfinite(P)) or np.linalg.eigvalsh(P)[0] <= 0:
        raise SolverError(f"the Lyapunov equation A'P + PA = -I of '{ps.name}' gave a P that is not positive "
                          "definite (ill-conditioned linearization)")
    return P


def _require_exponential_stability(ps: Any, A: np.ndarray) -> np.ndarray:
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


def _V_of(V: Poly, ps: PolySystem, X: np.ndarray) -> np.ndarray:
    return V(ps.lift(X))


_PATH_BATCH = 32_000
"""Most segment points :func:`_contains` evaluates in one call: below it the per-call cost of the polynomial
evaluation dominates and the whole segments go at once; above it the ``t``-by-``t`` loop, which drops the points that
leave, is faster (one saturated chapter-6 loop, 33 segment points: 5.3 ms against 15.2 ms for 500 points, 209 ms
against 111 ms for 8000)."""


def _contains(ps: PolySystem, V: Poly, rho: float, X: np.ndarray, n_path: int = 33) -> np.ndarray:
    """``V(lift(x_e + t (x - x_e))) <= rho`` and the cuts for ``t`` on the grid ``1, 1 - 1/n_path, ...,
    1/n_path`` (the component of the equilibrium). The end points ``t = 1`` are evaluated first (most points outside
    the set fail there); then, for the points still inside, the rest of their segments in one evaluation if that is
    at most :data:`_PATH_BATCH` points, else ``t`` by ``t`` (a point that fails once is not evaluated again).
    Polynomial evaluation is elementwise, so both give bitwise the same answer."""
    X = np.asarray(X, dtype=float)
    ok = np.all(np.isfinite(X), axis=-1)
    x0 = np.asarray(ps.equilibrium, dtype=float)
    ts = np.linspace(1.0, 0.0, n_path, endpoint=False)
    for j, t in enumerate(ts):
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            break
        rest = ts[j:]
        if j > 0 and idx.size * len(rest) <= _PATH_BATCH:       # small: the rest of the segments at once
            Y = (x0 + rest[:, None, None] * (X[idx] - x0)[None]).reshape(-1, X.shape[-1])
            Z = ps.lift(Y)
            good = (V(Z) <= rho) & ps.in_cuts(Y, Z)
            ok[idx] = np.all(good.reshape(len(rest), idx.size), axis=0)
            break
        Y = x0 + t * (X[idx] - x0)
        Z = ps.lift(Y)
        ok[idx] = (V(Z) <= rho) & ps.in_cuts(Y, Z)
    return ok


class _PathPoints:
    """Fixed points ``X`` with the lifted segment points ``lift(x_e + t (x - x_e))`` and their cut masks cached for
    every ``t`` of :func:`_contains` (they do not depend on ``V``): :meth:`contains` then evaluates only ``V``, on the
    points still inside, and gives exactly :func:`_contains` ``(ps, V, rho, X, n_path)``."""

    def __init__(self, ps: PolySystem, X: np.ndarray, n_path: int = 33) -> None:
        X = np.asarray(X, dtype=float)
        self.finite = np.all(np.isfinite(X), axis=-1)
        x0 = np.asarray(ps.equilibrium, dtype=float)
        Xf = np.where(self.finite[:, None], X, x0)
        self.Z, self.cut = [], []
        for t in np.linspace(1.0, 0.0, n_path, endpoint=False):
            Y = x0 + t * (Xf - x0)
            self.Z.append(ps.lift(Y))
            self.cut.append(ps.in_cuts(Y, self.Z[-1]))

    def contains(self, V: Poly, rho: float) -> np.ndarray:
        ok = self.finite.copy()
        for Z, cut in zip(self.Z, self.cut, strict=True):
            idx = np.flatnonzero(ok)
            if idx.size == 0:
                break
            ok[idx] = (V(Z[idx]) <= rho) & cut[idx]
        return ok


def dVdt(V: Poly, lift: Any, rhs: Any, X: Any) -> np.ndarray:
    """``d/dt V(lift(x))`` along ``x' = rhs(x)`` at states ``X`` (N, n), by complex step through the lift (exact to
    rounding). With a certificate's ``system.lift`` and ``system.rhs`` this is the true model's derivative.

    Parameters
    ----------
    V : Poly
        Function of the polynomial variables ``z``.
    lift : callable
        ``x (N, n) -> z (N, nz)``, complex-safe (e.g. ``PolySystem.lift``).
    rhs : callable
        ``x (N, n) -> dx/dt (N, n)`` (e.g. ``PolySystem.rhs``).
    X : array_like, shape (N, n)
        States (the model's units).

    Returns
    -------
    numpy.ndarray, shape (N,)
        ``dV/dt`` at each state (units of ``V`` per the model's time unit: 1/s, or per ``t_n`` for nondimensional
        models).

    Raises
    ------
    ArgumentTypeError
        If ``V`` is not a Poly, ``lift`` or ``rhs`` is not callable, or ``X`` is not numeric.
    ArgumentError
        If ``X`` is not a finite (N, n) array, or the shapes of ``X``, ``rhs(X)`` and ``lift`` do not agree.
    """
    if not isinstance(V, Poly):
        raise ArgumentTypeError(f"V must be a glidectl.roa.Poly, got {type(V).__name__}")
    checks.function("lift", lift)
    checks.function("rhs", rhs)
    X = checks.array("X", X, ndim=2)
    D = np.asarray(rhs(X))
    if D.shape != X.shape:
        raise ArgumentError(f"rhs returned shape {D.shape} for states of shape {X.shape}")
    h = 1e-30
    return np.imag(V(lift(X + 1j * h * D))) / h


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
    """The V-step program of :func:`_build` at ``degree`` (plus ``lambda`` of the level problem), counted."""
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
        dk = _even_up(max(degree, g.degree))
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


def _default_memory_limit() -> float:
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
    """
    degree = _check_degree(degree)
    if (not isinstance(system, PolySystem) and not _is_roa_model(system) and hasattr(system, "state_names")
            and callable(getattr(system, "rhs", None))):
        sd = checks.integer("surrogate_degree", surrogate_degree, lo=2, hi=5)
        ps = skeleton(len(tuple(system.state_names)), sd)
    else:
        ps = recast(system, speed_floor=speed_floor)
    return _size(ps, degree, _auto_extra(ps, extra))


def _check_degree(degree: Any, name: str = "degree") -> int:
    d = checks.integer(name, degree, lo=2)
    if d % 2:
        raise ArgumentError(f"{name} must be an even integer >= 2 (V is a sum of even-degree terms), got {d}")
    return d


def _check_iterations(iterations: Any, degree: int) -> tuple[int, ...]:
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


def _check_memory(ps: PolySystem, degree: int, extra: int, max_degree: int, memory_limit: float,
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


def _build(ps: PolySystem, F: list[Poly], degV: int, *, V: Poly | None, lam: Poly | None, rho: float | None,
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
    R, B = _remainder(ps, F)                                # surrogate route (issue 17): |true - F| <= R + B q^1.5
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
        dk = _even_up(max(degV, g.degree))
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
    Gram matrix has order ``n_decrease`` (unreduced count), or None (:data:`QUOTIENT_MIN_BLOCK`)."""
    return angle_quotient(ps.nz, ps.equalities) if n_decrease >= QUOTIENT_MIN_BLOCK else None


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
    ``F`` was divided by (``_scaled``)."""
    if not ps.remainder:
        return [], np.zeros(0)
    k = max(f.max_abs_coefficient() for f in ps.F) / max(max(f.max_abs_coefficient() for f in F), 1e-300)
    return [r / k for r in ps.remainder], np.asarray(ps.remainder_cubic, dtype=float) / k


def _scaling(ps: PolySystem) -> np.ndarray:
    """Scale of each polynomial variable (largest ``|z_i|`` over the box; angle pairs keep 1)."""
    lo, hi = ps.box
    Z = ps.lift(lo + (hi - lo) * qmc.Sobol(ps.n, seed=3).random(1024))
    k = np.max(np.abs(Z), axis=0)
    for i in ps.angle_states + ps.mixed_states:   # (x, s, c) of angles keep their natural scale
        k[list(ps.slots[i])] = 1.0
    return np.where(k > 0, k, 1.0)


def _rescale(ps: PolySystem, k: np.ndarray) -> PolySystem:
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


def _to_scaled(V: Poly, k: np.ndarray) -> Poly:
    Z = Poly.variables(V.nvars)
    return V.substitute([Z[i] * float(k[i]) for i in range(V.nvars)])


def _from_scaled(V: Poly, k: np.ndarray) -> Poly:
    Z = Poly.variables(V.nvars)
    return V.substitute([Z[i] / float(k[i]) for i in range(V.nvars)])


def _centers_by_level(prog: SOSProgram, solver: str) -> bool:
    """Whether the centering multiplier comes from the level program itself re-solved with ``rho <= (1 - center)
    rho*`` (its optimal face is the feasibility program's set; the solver returns a point inside it) instead of
    the feasibility program by Clarabel: with the ``CVXOPT_MOMENT`` solver (which takes such a program on the
    moment form when :func:`~glidectl.roa.sdp_solvers.moment_pays`) and a Gram block of order
    :data:`CENTER_BY_LEVEL_MIN_BLOCK` or more (see there)."""
    return solver == MOMENT and max((max(b, default=0) for b in prog.gram_sizes().values()), default=0) \
        >= CENTER_BY_LEVEL_MIN_BLOCK


def _capped_centre(prog: SOSProgram, out: dict[str, Any], cap: Any, rho: float, center: float,
                   solver: str) -> Poly:
    """The multiplier of the level program ``prog`` (solved, with ``rho <= cap``) re-solved with its cap at
    ``(1 - center) rho`` (:func:`_centers_by_level`)."""
    cap.value = (1 - center) * rho
    prog.resolve(solver=solver)
    return out["lambda"].poly()


def _level(ps: PolySystem, F: list[Poly], V: Poly, *, rho_cap: float, solver: str, center: float,
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
    degV = _even_up(V.degree)
    prog, out = _build(ps, F, degV, V=V, lam=None, rho=None, eps=0.0, extra=extra, cone=cone)
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
            prog2, out2 = _build(ps, F, degV, V=V, lam=None, rho=(1 - center) * rho, eps=0.0, extra=extra,
                                 cone=cone)
            prog2.solve(cp.Minimize(0), solver=solver)
            lam = out2["lambda"].poly()
        t, tc, ts, n = t + prog2.solve_time, tc + prog2.compile_time, ts + prog2.solver_time, 2
    return LevelResult(rho, lam, checks, t, status, tc, ts, n)


def _level_reused(ps: PolySystem, F: list[Poly], V: Poly, *, rho_cap: float, solver: str, center: float,
                  extra: int, cache: dict, basis: list[tuple[int, ...]]) -> LevelResult | None:
    """:func:`_level` through programs built once per (degree, basis of ``V``) with the coefficients of ``V`` and
    the levels as cvxpy Parameters: the same SOS conditions, compiled once and re-solved. None if ``V`` has a term
    outside ``basis``."""
    degV = _even_up(V.degree)
    basis = sorted(basis)
    key = ("level", degV, tuple(basis))
    if key not in cache:
        Vp = _Fixed.on(basis, ps.nz)
        prog, out = _build(ps, F, degV, V=Vp, lam=None, rho=None, eps=0.0, extra=extra)
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
            prog2, out2 = _build(ps, F, degV, V=Vc, lam=None, rho=rp, eps=0.0, extra=extra)
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


def _v_step(ps: PolySystem, F: list[Poly], degV: int, lam: Poly, Zt: np.ndarray, *, eps: float, extra: int,
            solver: str, cache: dict | None, V0: Poly | None = None) -> tuple[SOSProgram, dict[str, Any]]:
    """The V step for the multiplier ``lam`` (solved): ``V`` of degree ``degV`` minimizing ``mean(max(V - 1, 0))``
    over the simulated points ``Zt``. With a ``cache`` (exact route) the program is built once per (degree, support
    of ``lam``) with the coefficients of ``lam`` as cvxpy Parameters and re-solved."""
    key = ("V step", degV, tuple(sorted(lam.terms)))
    if cache is None or ps.remainder or lam.is_zero:
        prog, out = _build(ps, F, degV, V=None, lam=lam, rho=1.0, eps=eps, extra=extra, V0=V0)
    elif key not in cache:
        lp = _Fixed.on(list(key[2]), ps.nz)
        prog, out = _build(ps, F, degV, V=None, lam=lp, rho=1.0, eps=eps, extra=extra)
        cache[key] = (prog, out, lp)
    if cache is not None and key in cache:
        prog, out, lp = cache[key]
        lp.set(lam)
        if prog.problem is not None:
            prog.resolve(solver=solver, **steering_options(solver))
            return prog, out
    prog.solve(_coverage_objective(prog, out["V"], Zt), solver=solver, **steering_options(solver))
    return prog, out


def _coverage_objective(prog: SOSProgram, V: Any, Zt: np.ndarray) -> Any:
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
    """
    ps = recast(system)
    _check_V(V, ps, "V")
    rho_cap = checks.positive("rho_cap", rho_cap)
    check_solver(solver)
    ex = _auto_extra(ps, extra)
    max_degree = checks.integer("max_degree", max_degree, lo=2)
    limit = _default_memory_limit() if memory_limit is None else checks.positive("memory_limit", memory_limit)
    _check_memory(ps, _even_up(max(V.degree, 2)), ex, max_degree, limit, "max_level")
    k = _scaling(ps)
    pss = _rescale(ps, k)
    return _level(pss, _scaled(pss), _to_scaled(V, k), rho_cap=rho_cap, solver=solver, center=0.0, extra=ex)


def _check_V(V: Any, ps: PolySystem, name: str) -> Poly:
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


# --------------------------------------------------------------------------------------------- certificate
@dataclass(frozen=True)
class ROAVerification:
    """A-posteriori checks of a certificate (all must pass for :attr:`ROACertificate.certified`).

    ``margins`` has one entry per check (``>= 1`` holds): ``"Gram <name>"`` (:attr:`GramCheck.margin` of each SOS
    constraint), ``"Hessian of V positive definite"``, ``"A'H + HA negative definite"`` and ``"sampled dV/dt < 0"``
    (``inf`` when they hold, ``0.0`` when not) and ``"simulations converged"`` (``n_converged / n_simulated``).
    ``passed`` is every check passing (each Gram check exactly SOS, ``slack > 0``); ``failing()`` the margins
    below 1.

    Attributes
    ----------
    gram : tuple of GramCheck
        Exact-SOS check of every SOS constraint of the final program.
    hessian_V_min : float
        Smallest eigenvalue of the Hessian ``H`` of ``V(lift(x))`` at the equilibrium (must be > 0; units of ``V``
        per squared state unit).
    lyapunov_max : float
        Largest eigenvalue of ``A^T H + H A`` (must be < 0; per time unit of the model).
    n_sampled : int
        Sampled points of the certified set.
    max_Vdot : float
        Largest true ``dV/dt / |x - x_e|^2`` over them (must be < 0).
    n_simulated, n_converged : int
        Simulations started in the set and those that converged to the equilibrium.
    horizon : float
        Length of those simulations (model time unit: s, or ``t_n``).
    """

    gram: tuple[GramCheck, ...]
    hessian_V_min: float            # smallest eigenvalue of the Hessian of V(lift(x)) at the equilibrium
    lyapunov_max: float             # largest eigenvalue of A^T H + H A (must be < 0)
    n_sampled: int                  # sampled points of the certified set
    max_Vdot: float                 # largest true dV/dt / |x - x_e|^2 over them (must be < 0)
    n_simulated: int
    n_converged: int
    horizon: float

    @property
    def gram_passed(self) -> bool:
        """Every SOS constraint is exactly SOS (:attr:`GramCheck.passed`)."""
        return all(c.passed for c in self.gram)

    @property
    def unsampled_passed(self) -> bool:
        """The checks that need no sampling pass: every Gram check, the Hessian of V positive definite and
        ``A'H + HA`` negative definite (what gates a second remainder-box round of :func:`certify_roa`)."""
        return bool(self.gram_passed and self.hessian_V_min > 0 and self.lyapunov_max < 0)

    @property
    def passed(self) -> bool:
        return bool(self.unsampled_passed and self.n_sampled > 0 and self.max_Vdot < 0
                    and self.n_converged == self.n_simulated)

    @property
    def margins(self) -> dict[str, float]:
        inf = math.inf
        out: dict[str, float] = {}
        for c in self.gram:
            key = f"Gram {c.name}"
            out[key if key not in out else f"{key} #{len(out)}"] = c.margin
        out["Hessian of V positive definite"] = inf if self.hessian_V_min > 0 else 0.0
        out["A'H + HA negative definite"] = inf if self.lyapunov_max < 0 else 0.0
        out["sampled dV/dt < 0"] = inf if self.n_sampled > 0 and self.max_Vdot < 0 else 0.0
        out["simulations converged"] = self.n_converged / self.n_simulated if self.n_simulated else 1.0
        return out

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1 (relative tolerance 1e-9)."""
        return {k: m for k, m in self.margins.items() if not m >= 1 - 1e-9}

    def summary(self) -> str:
        """One line: the smallest Gram margin and slack, the local conditions, sampled dV/dt, simulations."""
        g = min((c.margin for c in self.gram), default=float("nan"))
        sl = min((c.slack for c in self.gram), default=float("nan"))
        shift = max((c.multiplier_shift for c in self.gram), default=0.0)
        made = f"; S-procedure multipliers shifted by <= {shift:.2g} to be SOS" if shift > 0 else ""
        return (f"Gram margin {g:.3g} (slack {sl:.3g}, {'exact' if self.gram_passed else 'NOT exact'}{made}), "
                f"Hessian min {self.hessian_V_min:.3g}, A'H+HA max {self.lyapunov_max:.3g}, max dV/dt/|x|^2 on "
                f"{self.n_sampled} samples {self.max_Vdot:.3g}, simulations {self.n_converged}/{self.n_simulated} "
                f"converged in {self.horizon:g}")


@dataclass(frozen=True)
class ROACertificate:
    """Certified region of attraction ``{x : V(lift(x)) <= rho}`` (component of the equilibrium).

    Attributes
    ----------
    system : PolySystem
    V : Poly
        Lyapunov function in the polynomial variables ``z = lift(x)``.
    rho : float
        Certified (backed-off) level.
    rho_star : float
        Optimal level of the last level problem (``rho = (1 - backoff) rho_star``).
    degree : int
        Degree of ``V``.
    history : tuple of dict
        Per iteration: degree, level, sampled volume in the box, SDP time.
    verification : ROAVerification
        A-posteriori checks; ``certified`` is ``verification.passed``.
    solve_time : float
        Total SDP solver time (s); ``wall_time`` includes building and verification. Both are those of the whole
        :func:`certify_roa` call, remainder-box rounds that were not kept included (the SDP time of a round stopped
        by an error is not counted).
    provenance : str
        The system's provenance (its vehicle's parameter hash for recast glidectl models).
    stopped_by : str
        What ended the V-lambda alternation at the final degree: ``"iterations"`` (all ran), ``"no improvement"``
        (two V steps without a larger sampled volume), ``"solver failure"`` (a V step or level problem failed; the
        best V so far is kept) or ``"time_limit"`` (``on_budget="stop"``).
    method : str
        The route: ``"exact recast"`` (the SOS programs see the model itself) or ``"surrogate+remainder"`` (a
        polynomial surrogate whose distance to the model is bounded on the box, :mod:`glidectl.roa.surrogate`;
        the decrease condition holds for every field within that bound) or ``"sos-sector"`` (a saturated loop:
        the saturated inputs are extra variables on the exact graph of the saturation,
        :mod:`glidectl.roa.sector`) or ``"sos-sector+remainder"`` (the same with a surrogate of a plant that is not
        polynomial).
    scale : ndarray or None
        Scale of each polynomial variable ``z`` in the programs (``z / scale`` is what the SDPs see): for the
        surrogate route the state scale ``s`` of ``(x - x_e) / s`` times the internal rescaling (state units).
    held : tuple of str
        States held at their equilibrium values (``system.equilibrium``): a closed loop's locked states, whose
        derivative is zero on the box with them there (e.g. ``r_P3``, ``rdot_P3`` of a glider whose vehicle file
        fixes ``r_P3``). The set is certified on the other states, for the held ones AT those values: every method
        takes full states, :meth:`contains` is false unless the held states are at their values (relative 1e-12),
        :meth:`sample` returns them there and :meth:`volume` is the volume in the other states. Empty if none.
    """

    system: PolySystem = field(repr=False)
    V: Poly = field(repr=False)
    rho: float
    rho_star: float
    degree: int
    history: tuple[dict[str, Any], ...] = field(repr=False)
    verification: ROAVerification = field(repr=False)
    solve_time: float
    wall_time: float
    provenance: str = ""
    stopped_by: str = ""
    method: str = "exact recast"
    scale: np.ndarray | None = field(default=None, repr=False)
    held: tuple[str, ...] = ()

    @property
    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lo, hi)``: the region of interest the certificate was computed in (state units); the certified set
        lies inside it for the surrogate route (its cuts)."""
        return self.system.box

    def sample(self, n: int, seed: int = 0, *, boundary: bool = False) -> np.ndarray:
        """Points of the certified set, in state units.

        The set is star-shaped about the equilibrium (:meth:`contains` checks the segment from it), so directions
        ``u`` are drawn uniformly in the box-scaled coordinates, the largest radius ``R(u)`` inside the set is found
        by bisection (40 steps) and the point is ``x_e + R(u) U^(1/n) u`` with ``U`` uniform, the direction kept
        with probability ``(R(u) / R_max)^n``: uniform in the set up to the largest radius seen. A set too thin
        for that (its expected acceptance projects to more than 20 rounds of ``max(2 n, 256)`` directions after 3
        rounds, or to more than the 200 allowed after one) is sampled instead with directions proposed along the
        Hessian of ``V`` at the equilibrium (angular central Gaussian) and kept with their importance weight
        ``R(u)^n / q(u)`` over the largest weight proposed: uniform in the set as long as that largest weight bounds
        the weights (exact for an ellipsoid), and the same points as before whenever the first way succeeds.

        Parameters
        ----------
        n : int
            Number of points, >= 1.
        seed : int
            Seed (>= 0).
        boundary : bool
            Return the outermost points ``x_e + R(u) (1 - 1e-9) u`` instead (uniform directions): starting points
            for convergence checks.

        Returns
        -------
        ndarray (n, n_states)
            Points with :meth:`contains` true (state units).

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer, or ``boundary`` not a bool.
        ArgumentError
            If ``n < 1`` or ``seed < 0``.
        SolverError
            If the set is empty in every sampled direction (no certified set).
        """
        n = checks.integer("n", n, lo=1, hi=2**22)
        seed = checks.integer("seed", seed, lo=0)
        boundary = checks.boolean("boundary", boundary)
        return _sample_set(self.system, self.V, self.rho, n, seed, boundary)

    @property
    def certified(self) -> bool:
        """True only if every a-posteriori check passed."""
        return self.verification.passed

    def _states(self, X: Any, finite: bool) -> np.ndarray:
        n = self.system.n
        X = checks.array("X", X, finite=finite)
        X = np.atleast_2d(X)
        if X.ndim != 2 or X.shape[-1] != n:
            raise ArgumentError(f"X must hold states of dimension {n} ({', '.join(self.system.state_names)}), "
                                f"shape (N, {n}) or ({n},); got shape {np.shape(X)}")
        return X

    def value(self, X: Any) -> np.ndarray:
        """``V(lift(x))`` at states ``X``.

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States in the system's coordinates (finite).

        Returns
        -------
        ndarray, shape (N,)
            The Lyapunov function there.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric.
        ArgumentError
            If ``X`` has the wrong shape or is not finite.
        """
        return _V_of(self.V, self.system, self._states(X, finite=True))

    def contains(self, X: Any, n_path: int = 33) -> np.ndarray:
        """Membership of the certified set for states ``X`` in the system's coordinates.

        A point belongs when it and the straight segment from the equilibrium to it satisfy ``V <= rho`` and the
        cuts (so it lies in the connected component of the equilibrium; ``n_path`` points on the segment, the
        point itself included).

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States; a state with NaN or inf is reported outside.
        n_path : int
            Points checked on each segment, >= 1.

        Returns
        -------
        ndarray of bool, shape (N,)
            Membership.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric or ``n_path`` is not an integer.
        ArgumentError
            If ``X`` has the wrong shape or ``n_path < 1``.
        """
        X = self._states(X, finite=False)
        n_path = checks.integer("n_path", n_path, lo=1)
        return _contains(self.system, self.V, self.rho, X, n_path)

    def volume(self, box: tuple[Any, Any] | None = None, n: int = 2**16, seed: int = 0,
               method: str = "auto") -> float:
        """Volume (area for 2 states) of the certified set inside ``box`` (default the system's); with :attr:`held`
        states, the volume in the other states (the held ones at their values).

        ``method="sobol"`` counts the scrambled Sobol points of the box that :meth:`contains` accepts
        (:func:`~glidectl.analysis.measure.box_measure`): ``prod(hi - lo) k / n`` for ``k`` points inside. A thin
        set in many states holds none of them (the 8 free states of a glider's LQR loop): that estimate is then 0.
        ``method="directed"`` integrates along rays from the equilibrium ``x_e`` instead (the set is star-shaped
        about it): in the box-scaled free states ``y = (x - x_e) / w`` (``w`` the largest distance from ``x_e`` to a
        face of the system's box), with ``R(u)`` the largest radius inside the set and the box along the unit
        direction ``u`` (40 bisection steps on :meth:`contains`) and ``H`` the Hessian of ``V(lift(x))`` at the
        equilibrium in those coordinates,

            vol = prod(w_free) |S^(nf-1)| / (nf sqrt(det H)) E[W(u)],   W(u) = (R(u)^2 u' H u)^(nf/2),

        the mean over ``m = ceil(n / 16)`` directions ``u = z / |z|``, ``z ~ N(0, H^-1)`` (angular central
        Gaussian, density ``det(H)^(1/2) (u' H u)^(-nf/2)`` relative to the uniform law on the sphere; ``nf`` free
        states; ``H``'s eigenvalues clipped at 1e-8 of the largest). It is exact for an ellipsoid (``W``
        constant) and has the relative standard error ``std(W) / (mean(W) sqrt(m))`` otherwise; the box must
        contain the equilibrium. ``method="auto"`` returns the Sobol estimate when at least 100 of its points are
        inside (relative counting error below about 1/10; the same number as ``"sobol"``, bit for bit) and the
        directed one otherwise (or the Sobol one if the box does not contain the equilibrium).

        Parameters
        ----------
        box : (array_like, array_like), optional
            ``(lo, hi)``, each of shape (n,), finite, ``lo < hi`` (in the free states); default the system's box.
        n : int
            Sobol points (>= 1; a power of 2 keeps the sequence balanced); the directed estimate draws
            ``ceil(n / 16)`` directions (each costs 41 membership tests of a point: the default, 4096 directions,
            takes about 2 s on an 8-free-state glider loop).
        seed : int
            Seed of the scrambled Sobol sequence and of the directions (>= 0).
        method : {"auto", "sobol", "directed"}
            The estimate, as above.

        Returns
        -------
        float
            The estimated volume (product of the state units of the free states).

        Raises
        ------
        ArgumentTypeError
            If an argument has the wrong type.
        ArgumentError
            If ``box`` has the wrong shape, is not finite or has ``lo >= hi``, ``n`` or ``seed`` is out of range,
            ``method`` is not one of the three, or ``method="directed"`` with a box that does not contain the
            equilibrium.
        """
        method = checks.choice("method", method, ("auto", "sobol", "directed"))
        ps = self.system
        if method != "directed":
            hits: list[int] = []
            vol = self._volume_sobol(box, n, seed, hits)
            if method == "sobol" or hits[0] >= MIN_SOBOL_HITS:
                return vol
        lo, hi = self._volume_box(box)
        n = checks.integer("n", n, lo=1, hi=2**24)
        seed = checks.integer("seed", seed, lo=0)
        free = [i for i in range(ps.n) if i not in ps.held]
        xe = np.asarray(ps.equilibrium, dtype=float)
        if np.any(xe[free] < lo[free]) or np.any(xe[free] > hi[free]):
            if method == "auto":
                return vol
            raise ArgumentError(f"volume(method='directed') integrates along rays from the equilibrium "
                                f"{xe.tolist()}, which must lie in the box (lo {lo.tolist()}, hi {hi.tolist()}): "
                                "enlarge the box or use method='sobol'")
        return _volume_directed(ps, self.V, self.rho, lo, hi, -(-n // _DIRECTED_PER_SOBOL), seed)[0]

    def _volume_box(self, box: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(lo, hi)`` of :meth:`volume` over all states, checked (``lo < hi`` in the free states)."""
        ps = self.system
        if box is None:
            box = ps.box
        if not isinstance(box, tuple | list) or len(box) != 2:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({ps.n},)")
        lo = checks.array("box lo", box[0], shape=(ps.n,))
        hi = checks.array("box hi", box[1], shape=(ps.n,))
        free = [i for i in range(ps.n) if i not in ps.held]
        if np.any(lo[free] >= hi[free]):
            raise ArgumentError(f"box must have lo < hi in every coordinate, got lo {lo.tolist()}, hi {hi.tolist()}")
        return lo, hi

    def _volume_sobol(self, box: Any, n: int, seed: int, hits: list[int]) -> float:
        """The Sobol estimate of :meth:`volume`; appends the number of points inside to ``hits``."""
        ps = self.system

        def counted(inside: np.ndarray) -> np.ndarray:
            hits.append(int(np.count_nonzero(inside)))
            return inside

        if not ps.held:
            return box_measure(lambda X: counted(self.contains(X)), box if box is not None else ps.box, n, seed,
                               dim=ps.n)
        lo, hi = self._volume_box(box)
        free = [i for i in range(ps.n) if i not in ps.held]
        xe = np.asarray(ps.equilibrium, dtype=float)

        def inside(Y: np.ndarray) -> np.ndarray:      # the free states; the held ones at their values
            X = np.tile(xe, (len(Y), 1))
            X[:, free] = Y
            return counted(self.contains(X))

        return box_measure(inside, (lo[free], hi[free]), n, seed, dim=len(free))

    HISTORY_HEADER: ClassVar[tuple[str, ...]] = ("problem", "deg", "step", "rho", "measure", "SDP s")
    """Column names of :meth:`history_table`."""

    def history_table(self, label: str = "") -> list[list[str]]:
        """The alternation :attr:`history` as rows of text, one per iteration, as :data:`HISTORY_HEADER`.

        Parameters
        ----------
        label : str
            Text of the first column (the problem's name, so that the rows of several certificates can share one
            table).

        Returns
        -------
        list of list of str
            ``[label, degree, step (first 60 characters), level rho (6 significant digits), sampled area/volume in
            the box (4 digits, product of the state units), SDP time (s, 2 decimals)]`` per iteration.

        Raises
        ------
        ArgumentTypeError
            If ``label`` is not a string.
        """
        if not isinstance(label, str):
            raise ArgumentTypeError(f"label must be a string (the table's first column), got {type(label).__name__}")
        return [[label, str(h["degree"]), h["step"][:60], f"{h['rho']:.6g}", f"{h['volume']:.4g}",
                 f"{h['sdp_time']:.2f}"] for h in self.history]

    def plot(self, ax: Any = None, dims: Any = (0, 1), fixed: Any = None, n: int = 201,
             samples: bool = True) -> Any:
        """Draw a 2-D slice of the certified set through the equilibrium, in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane of the slice (axes labelled with the system's state names).
        fixed : array_like (n,) or mapping, optional
            Values of the other states on the slice (a full state whose ``dims`` entries are ignored, or
            ``{name: value}``); default the equilibrium.
        n : int
            Grid points per axis over the system's box (:meth:`contains` on the grid), and the number of points of
            the set drawn when ``samples``.
        samples : bool
            Draw ``n`` random points of the slice that are in the set (the :attr:`verification` keeps counts, not
            its sampled points).

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_roa_certificate`.

        Raises
        ------
        GlidectlError
            For ``dims`` or ``fixed`` that do not fit the system (see :func:`glidectl.plotting.plot_roa_certificate`).
        """
        from ..plotting import plot_roa_certificate, style

        with style():
            return plot_roa_certificate(self, ax, dims=dims, fixed=fixed, n=n, samples=samples)


def _sobol(d: int, seed: int, n: int) -> np.ndarray:
    """``n`` scrambled Sobol points in ``[0, 1)^d`` (the balance warning for ``n`` not a power of 2 is silenced)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(d, seed=seed).random(n)


_SWITCH_ROUNDS = 3       # rejection rounds of _sample_set before it may switch to the directed sampler
_SWITCH_PROJECTED = 20   # ... which it does if the rejection sampler projects to more rounds than this
_ROUNDS = 200            # rounds of directions at most (each sampler)
_DIRECTED_PER_SOBOL = 16  # volume(n=...): the directed estimate draws ceil(n / 16) directions (40 bisection steps each)


def _radii(ps: PolySystem, V: Poly, rho: float, x0: np.ndarray, D: np.ndarray, lo: np.ndarray, hi: np.ndarray,
           check: Any = None) -> np.ndarray:
    """Largest ``R`` with ``x0 + R D`` in the set (the box limits it), per row of ``D``: 40 bisection steps on
    :func:`_contains`."""
    m = D.shape[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        tb = np.min(np.where(D > 0, (hi - x0) / D, np.where(D < 0, (lo - x0) / D, np.inf)), axis=1)
    a, b = np.zeros(m), tb * (1 - 1e-12)
    inside = _contains(ps, V, rho, x0 + b[:, None] * D)
    a[inside] = b[inside]
    for _ in range(40):
        if check is not None:
            check()
        mid = 0.5 * (a + b)
        ok = _contains(ps, V, rho, x0 + mid[:, None] * D) | inside
        a, b = np.where(ok, mid, a), np.where(ok, b, mid)
    return a


def _sample_set(ps: PolySystem, V: Poly, rho: float, n: int, seed: int, boundary: bool,
                check: Any = None) -> np.ndarray:
    """Points of the star-shaped set ``{V <= rho}`` (component of the equilibrium): see ROACertificate.sample.
    ``check()`` (optional) is called before every batch of directions and every bisection step (a time budget).

    Interior points come from rejection: uniform directions ``u`` (box-scaled, free states), kept with probability
    ``(R(u) / R_max)^nf`` (``R_max`` the largest radius of the batch), radius ``R(u) U^(1/nf)``. If after
    ``_SWITCH_ROUNDS`` rounds the expected acceptance (sum of those probabilities) projects to more than
    ``_SWITCH_PROJECTED`` rounds in all, or after any earlier round to more than ``_ROUNDS`` (the rounds allowed),
    the set is thin in many states: the points drawn so far are dropped and :func:`_sample_directed` draws all
    ``n`` (another random stream); otherwise the result is that of the rejection rounds alone, unchanged."""
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    w = np.maximum(x0 - lo, hi - x0)
    free = [i for i in range(ps.n) if i not in ps.held]      # held states stay at their values
    nf = len(free)
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    got = 0
    expected = 0.0      # expected accepted count of the rounds so far (sum of the acceptance probabilities)

    for k in range(_ROUNDS):
        if check is not None:
            check()
        m = max(2 * n, 256)
        U = np.zeros((m, ps.n))
        U[:, free] = rng.standard_normal((m, nf))
        U /= np.linalg.norm(U, axis=1, keepdims=True)
        D = U * w                                   # directions in state units
        R = _radii(ps, V, rho, x0, D, lo, hi, check)
        if boundary:
            keep = R > 0
            pts = x0 + (R[keep] * (1 - 1e-9))[:, None] * D[keep]
        else:
            if not np.any(R > 0):
                continue
            acc = (R / np.max(R)) ** nf
            expected += float(np.sum(acc[R > 0]))
            keep = (rng.random(m) < acc) & (R > 0)
            rad = R[keep] * rng.random(int(keep.sum())) ** (1.0 / nf)
            pts = x0 + rad[:, None] * D[keep]
        out.append(pts)
        got += len(pts)
        if got >= n:
            break
        if not boundary and k + 1 <= _SWITCH_ROUNDS and expected > 0 and n * (k + 1) / expected > (
                _SWITCH_PROJECTED if k + 1 == _SWITCH_ROUNDS else _ROUNDS):
            return _sample_directed(ps, V, rho, n, seed, check)
    if got == 0:
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    return np.concatenate(out)[:n]


def _acg_proposal(ps: PolySystem, V: Poly) -> tuple[np.ndarray, np.ndarray, list[int], np.ndarray, np.ndarray,
                                                   np.ndarray]:
    """The angular central Gaussian proposal of :func:`_sample_directed` and :func:`_volume_directed`: ``(x0, w,
    free, Hs, L, lam)`` with ``x0`` the equilibrium, ``w`` the largest distance from it to a face of the system's
    box per state, ``free`` the states not held, ``Hs`` the Hessian of ``V(lift(x))`` at ``x0`` in the box-scaled
    free states ``(x - x0) / w`` (eigenvalues ``lam`` clipped at 1e-8 of the largest; the identity when it has no
    positive curvature) and ``L`` with ``L g ~ N(0, Hs^-1)`` for ``g ~ N(0, I)``."""
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    w = np.maximum(x0 - lo, hi - x0)
    free = [i for i in range(ps.n) if i not in ps.held]
    nf = len(free)
    try:
        H = hessian(lambda X: _V_of(V, ps, X), x0)[np.ix_(free, free)] * np.outer(w[free], w[free])
        lam, Q = np.linalg.eigh(0.5 * (H + H.T))
        ok = bool(np.all(np.isfinite(lam)) and lam[-1] > 0)
    except (np.linalg.LinAlgError, ValueError, FloatingPointError):
        ok = False
    if not ok:                          # no curvature to follow: uniform directions (still exact)
        lam, Q = np.ones(nf), np.eye(nf)
    lam = np.maximum(lam, 1e-8 * lam[-1])
    Hs = (Q * lam) @ Q.T
    L = Q / np.sqrt(lam)                # z = L g ~ N(0, Hs^-1)
    return x0, w, free, Hs, L, lam


def _directed_weights(ps: PolySystem, V: Poly, rho: float, G: np.ndarray, proposal: tuple, lo: np.ndarray,
                      hi: np.ndarray, check: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For standard normal draws ``G`` (m, nf) and the ``(x0, w, free, Hs, L)`` of :func:`_acg_proposal`: the
    directions ``u = L g / |L g|`` (angular central Gaussian), their log importance weights
    ``log W(u) = nf/2 log(R(u)^2 u' Hs u)`` (``-inf`` where ``R = 0``), the radii ``R(u)`` in the set and the box
    (:func:`_radii`) and the directions ``D`` in state units (rows ``x0 + R D`` are on the boundary)."""
    x0, w, free, Hs, L = proposal
    nf = len(free)
    Z = G @ L.T
    Z /= np.linalg.norm(Z, axis=1, keepdims=True)
    U = np.zeros((len(Z), ps.n))
    U[:, free] = Z
    D = U * w
    R = _radii(ps, V, rho, x0, D, lo, hi, check)
    with np.errstate(divide="ignore"):
        return 0.5 * nf * np.log(R ** 2 * np.einsum("ij,jk,ik->i", Z, Hs, Z)), R, D


def _sample_directed(ps: PolySystem, V: Poly, rho: float, n: int, seed: int, check: Any = None) -> np.ndarray:
    """``n`` points of the star-shaped set ``{V <= rho}`` (component of the equilibrium), uniform in its volume, for
    thin sets in many states where the rejection of :func:`_sample_set` accepts too few directions.

    A uniform point of a star-shaped set is a direction ``u`` with density proportional to ``R(u)^nf`` (``R(u)`` the
    boundary radius, ``nf`` the free states) times the radius ``R(u) U^(1/nf)``, ``U`` uniform. Directions are
    proposed from the angular central Gaussian: ``u = z / |z|``, ``z ~ N(0, H^-1)`` with ``H`` the Hessian of
    ``V(lift(x))`` at the equilibrium (box-scaled free states, eigenvalues clipped at 1e-8 of the largest), whose
    density on the sphere is proportional to ``(u' H u)^(-nf/2)``: exactly ``R(u)^nf`` for an ellipsoid. A proposal
    is kept with probability ``W(u) / W_max``, ``W(u) = (R(u)^2 u' H u)^(nf/2)`` the importance weight and
    ``W_max`` the largest weight among ALL the directions proposed (the acceptance of every proposal is re-decided
    with the final ``W_max``, its uniform number drawn once): the points are exactly uniform in the set whenever
    ``W_max`` bounds ``W``; directions whose weight exceeds every one seen (a part of the set rarer than one in the
    number proposed) are under-weighted, as the rejection of :func:`_sample_set` is with its batch's ``R_max``."""
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    x0, w, free, Hs, L, _ = _acg_proposal(ps, V)
    nf = len(free)
    rng = np.random.default_rng([seed, 17])
    logW, logU, Rs, Vs, Ds = [], [], [], [], []
    for _ in range(_ROUNDS):
        if check is not None:
            check()
        m = max(2 * n, 256)
        lw, R, D = _directed_weights(ps, V, rho, rng.standard_normal((m, nf)), (x0, w, free, Hs, L), lo, hi, check)
        logW.append(lw)
        logU.append(np.log(rng.random(m)))
        Vs.append(rng.random(m) ** (1.0 / nf))
        Rs.append(R)
        Ds.append(D)
        lw = np.concatenate(logW)
        top = float(np.max(lw))
        if not np.isfinite(top):
            continue
        keep = (np.concatenate(logU) < lw - top) & (np.concatenate(Rs) > 0)
        if int(keep.sum()) >= n:
            idx = np.flatnonzero(keep)[:n]
            rad = (np.concatenate(Rs) * np.concatenate(Vs))[idx]
            return x0 + rad[:, None] * np.concatenate(Ds)[idx]
    lw = np.concatenate(logW)
    if not np.any(np.isfinite(lw)):
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    keep = (np.concatenate(logU) < lw - np.max(lw)) & (np.concatenate(Rs) > 0)
    if not np.any(keep):
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    idx = np.flatnonzero(keep)          # fewer than n points after every round (as _sample_set)
    return x0 + (np.concatenate(Rs) * np.concatenate(Vs))[idx][:, None] * np.concatenate(Ds)[idx]


_VOLUME_CHUNK = 4096     # directions per batch of _volume_directed (bounds memory; the result does not depend on it)


def _step_volume(ps: PolySystem, points: _PathPoints, V: Poly, lo: np.ndarray, hi: np.ndarray, seed: int,
                 rho: float = 1.0) -> float:
    """Volume of ``{V <= rho}`` in the box ``[lo, hi]`` by which the alternation of :func:`certify_roa` judges a step
    (and its history records the final level), chosen as :meth:`ROACertificate.volume` ``(method="auto")`` chooses:
    ``prod(hi - lo)`` times the fraction of the fixed Sobol ``points`` inside when at least ``MIN_SOBOL_HITS`` of
    them are, else the directed estimate (:func:`_volume_directed`, ``ceil(N / 16)`` directions for ``N`` points,
    with the same seeded Gaussian draws at every step; the directions also depend on each V's Hessian).

    A thin set holds a handful of the points or none. The user glider's unsaturated LQR loop (8 free states) held
    none at every step, so no V step ever counted as an improvement and its certificate was the starting V's
    (1.55e-12); judged by the directed estimate, the alternation keeps its V steps (3.63e-11, certified).

    Parameters
    ----------
    ps : PolySystem
        The (scaled) system of the alternation, in its free states (it holds none); its box contains the
        equilibrium.
    points : _PathPoints
        The fixed Sobol points of the box, with their segment points cached.
    V : Poly
        The candidate; the set is ``{V <= rho}``.
    lo, hi : ndarray, shape (n,)
        The box.
    seed : int
        Seed of the directions.
    rho : float
        The level (1 for the alternation's steps, whose V is normalized by its level).

    Returns
    -------
    float
        The volume, in the units of ``ps``'s states.
    """
    inside = points.contains(V, rho)
    if np.count_nonzero(inside) >= MIN_SOBOL_HITS:
        return float(np.prod(hi - lo) * np.mean(inside))
    return _volume_directed(ps, V, rho, lo, hi, -(-len(inside) // _DIRECTED_PER_SOBOL), seed)[0]


def _volume_directed(ps: PolySystem, V: Poly, rho: float, lo: np.ndarray, hi: np.ndarray, n: int, seed: int,
                     check: Any = None) -> tuple[float, float]:
    """Volume of the star-shaped set ``{V <= rho}`` (component of the equilibrium ``x_e``) inside the box
    ``[lo, hi]`` (which must contain ``x_e``), in the free states, and its standard error: ``n`` directions of the
    angular central Gaussian of :func:`_acg_proposal` (another random stream than the samplers).

    In the box-scaled free states ``y = (x - x_e) / w`` (``w`` the largest distance from ``x_e`` to a face of the
    system's box, per state) a star-shaped set with boundary radius ``R(u)`` (:func:`_radii`, which stops every ray
    at ``[lo, hi]``: the radius of the set intersected with the box) has volume
    ``(1 / nf) int_{S^(nf-1)} R(u)^nf du = |B^nf| E_unif[R(u)^nf]`` (``|B^nf| = pi^(nf/2) / Gamma(nf/2 + 1)``, the
    unit ball). The angular central Gaussian ``u = z / |z|``, ``z ~ N(0, H^-1)``, has density
    ``det(H)^(1/2) (u' H u)^(-nf/2)`` relative to the uniform law on the sphere, so

        vol_y = |B^nf| / sqrt(det H) E_ACG[W(u)],    W(u) = (R(u)^2 u' H u)^(nf/2),

    and the volume in state units is ``prod(w[free]) vol_y``. For an ellipsoid ``y' H y <= c`` (not cut by the box)
    ``W = c^(nf/2)`` in every direction: the estimate is exact. The standard error is the sample standard deviation
    of ``W`` over ``sqrt(n)`` times the same factor. ``check()`` (optional) is called before every batch of
    directions and every bisection step (a time budget). Returns ``(0.0, 0.0)`` if every radius is zero."""
    x0, w, free, Hs, L, lam = _acg_proposal(ps, V)
    nf = len(free)
    G = np.random.default_rng([seed, 23]).standard_normal((n, nf))
    lw = np.empty(n)                    # log W(u)
    for a in range(0, n, _VOLUME_CHUNK):
        if check is not None:
            check()
        g = G[a:a + _VOLUME_CHUNK]
        lw[a:a + len(g)] = _directed_weights(ps, V, rho, g, (x0, w, free, Hs, L), lo, hi, check)[0]
    top = float(np.max(lw))
    if not np.isfinite(top):
        return 0.0, 0.0
    e = np.exp(lw - top)
    log_c = (0.5 * nf * math.log(math.pi) - math.lgamma(0.5 * nf + 1) - 0.5 * float(np.sum(np.log(lam)))
             + float(np.sum(np.log(w[free]))) + top)
    c = math.exp(log_c)
    err = c * float(np.std(e, ddof=1)) / math.sqrt(n) if n > 1 else math.inf
    return c * float(np.mean(e)), err


_VERIFY_CHUNK = 4096     # points per membership / dV/dt batch of the verification (time checks between batches)


def _verify(ps: PolySystem, V: Poly, rho: float, gram: tuple[GramCheck, ...], *, n_verify: int,
            n_simulate: int, horizon: float, seed: int, deadline: checks.Deadline | None = None) -> ROAVerification:
    """The a-posteriori checks. With a ``deadline`` (``time_limit`` of :func:`certify_roa`, ``on_budget="raise"``),
    every step is bounded by it: :class:`BudgetError` naming the step and what to lower, never fewer samples or
    simulations than asked for."""

    def remaining() -> float:
        return math.inf if deadline is None or deadline.limit is None else deadline.limit - deadline.elapsed

    def budget(step: str, lower: str) -> None:
        if remaining() < 0:
            raise BudgetError(f"certify_roa stopped at its time limit of {deadline.limit:g} s in the final "
                              f"verification, while {step} (the SOS certificate itself was found): raise time_limit, "
                              f"or lower {lower}; the verification is never shortened to fit")

    sampling = (f"sampling the certified set (n_verify = {n_verify} points) and checking the true dV/dt there",
                "n_verify")
    x0 = ps.equilibrium
    hmin, lmax = _local_checks(ps, V)
    # sample the certified set (rejection from the system's box)
    lo, hi = ps.box
    rng = np.random.default_rng(seed)
    X = lo + (hi - lo) * rng.random((n_verify, ps.n))
    inside = np.zeros(n_verify, dtype=bool)
    for a in range(0, n_verify, _VERIFY_CHUNK):
        budget(*sampling)
        inside[a:a + _VERIFY_CHUNK] = _contains(ps, V, rho, X[a:a + _VERIFY_CHUNK])
    Xs = X[inside]
    if ps.remainder or Xs.shape[0] < n_verify // 20:
        # a thin set in many states (or the surrogate route): add points drawn in the set and on its boundary
        try:
            Xs = np.concatenate([Xs, _sample_set(ps, V, rho, max(n_verify // 4, 1), seed, False,
                                                 lambda: budget(*sampling)),
                                 _sample_set(ps, V, rho, max(n_verify // 4, 1), seed + 1, True,
                                             lambda: budget(*sampling))])
        except SolverError:
            pass
    max_vd = float("nan")
    if Xs.shape[0]:
        vd = []
        for a in range(0, Xs.shape[0], _VERIFY_CHUNK):
            budget(*sampling)
            Xa = Xs[a:a + _VERIFY_CHUNK]
            vd.append(dVdt(V, ps.lift, ps.rhs, Xa) / np.maximum(np.sum((Xa - x0) ** 2, axis=1), 1e-300))
        max_vd = float(np.max(np.concatenate(vd)))
    # simulations from the outermost sampled points
    nsim = min(n_simulate, Xs.shape[0])
    conv = 0
    if nsim:
        sims = (f"simulating n_simulate = {nsim} runs of length horizon = {horizon:g} from the outermost samples",
                "n_simulate or horizon")
        budget(*sims)
        pick = Xs[np.argsort(_V_of(V, ps, Xs))[::-1][:nsim]]
        left = remaining()
        try:
            res = integrate_batch(ps.rhs, pick, horizon, rtol=1e-7, atol=1e-10, max_steps=200_000,
                                  time_limit=None if math.isinf(left) else max(left, 1e-3))
        except BudgetError as exc:
            raise BudgetError(f"certify_roa's final verification ran out of its time limit while {sims[0]}: "
                              f"raise time_limit, or lower {sims[1]} ({exc})") from exc
        conv = int(np.sum(res.converged_to(x0, 1e-3 * max(1.0, float(np.max(hi - lo))))))
    return ROAVerification(gram, hmin, lmax, int(Xs.shape[0]), max_vd, nsim, conv, horizon)


def _local_checks(ps: PolySystem, V: Poly) -> tuple[float, float]:
    """The checks of :class:`ROAVerification` at the equilibrium: the smallest eigenvalue of the Hessian ``H`` of
    ``V(lift(x))`` there and the largest of ``A'H + HA`` (``A`` the linearization)."""
    H = hessian(lambda X: _V_of(V, ps, X), ps.equilibrium)
    A = _linearization(ps)
    return float(np.linalg.eigvalsh(H)[0]), float(np.linalg.eigvalsh(A.T @ H + H @ A)[-1])


def _default_horizon(ps: PolySystem) -> float:
    """25 time constants of the slowest mode of the linearization."""
    return 25.0 / float(np.min(np.abs(np.linalg.eigvals(_linearization(ps)).real)))


def _ground_truth(ps: PolySystem, n: int, horizon: float, seed: int,
                  deadline: checks.Deadline | None = None) -> np.ndarray:
    """Sobol points of the box (inside the cuts) whose simulations converge to the equilibrium (bounded by the
    ``deadline``, if it has a limit: :class:`BudgetError` saying to lower ``n_truth`` or ``horizon``)."""
    lo, hi = ps.box
    X = lo + (hi - lo) * _sobol(ps.n, seed + 5, n)
    X = X[ps.in_cuts(X)]
    if X.shape[0] == 0:
        return X
    left = None if deadline is None or deadline.limit is None else deadline.limit - deadline.elapsed
    what = (f"certify_roa stopped at its time limit of {deadline.limit if left is not None else 0:g} s while "
            f"simulating n_truth = {n} box points over horizon = {horizon:g} (the points that steer the V step): "
            "raise time_limit, or lower n_truth or horizon")
    if left is not None and left <= 0:
        raise BudgetError(what)
    try:
        res = integrate_batch(ps.rhs, X, horizon, rtol=1e-6, atol=1e-9, max_steps=50_000,
                              bound=1e3 * float(np.max(np.abs(np.concatenate([lo, hi])))), time_limit=left)
    except BudgetError as exc:
        raise BudgetError(f"{what} ({exc})") from exc
    return X[res.converged_to(ps.equilibrium, 1e-3)]


@pinned_blas
def certify_roa(system: Any, degree: int = 6, *, iterations: int | Sequence[int] = 4, backoff: float = 0.01,
                eps: float = 1e-6, initial: Poly | np.ndarray | None = None, speed_floor: float = 0.1,
                extra: int | None = None, n_truth: int = 2048, n_verify: int = 20_000, n_simulate: int = 256,
                horizon: float | None = None,
                solver: str = DEFAULT_SOLVER, seed: int = 0, center: float = 0.05, max_degree: int = MAX_DEGREE,
                time_limit: float | None = None, memory_limit: float | None = None,
                on_budget: str = "raise", box: Any = None, method: str = "auto", surrogate_degree: int = 3,
                margin: float = 2.0, reuse: bool = True, inner: str = "sos", box_search: int = 6,
                box_rounds: int = 2) -> ROACertificate:
    """Certify a region of attraction of the equilibrium of ``system`` with a polynomial Lyapunov function.

    Parameters
    ----------
    system : PolySystem or glidectl model
        A polynomial system (e.g. :func:`glidectl.benchmarks.van_der_pol`) or a model at an equilibrium with the
        attributes :func:`~glidectl.roa.systems.recast` needs (``sp.reduced_model()``, ``sp.full_model()``). Its
        equilibrium must be exponentially stable. A :class:`~glidectl.roa.lmi.SaturatedLoop`
        (:func:`glidectl.saturated_loop`) is certified with its saturation as S-procedure terms
        (:func:`~glidectl.roa.sector.sector_system`; the states are its free states): ``method = "sos-sector"``
        with a polynomial plant, ``"sos-sector+remainder"`` with a surrogate of one that is not. A closed loop
        whose locked states never move (the states its law locks, as :func:`glidectl.saturated_loop` holds them, and
        states whose derivative is zero on the box once those are fixed; e.g. ``r_P3``, ``rdot_P3`` when the vehicle
        file fixes ``r_P3``) is certified on its other states with the locked ones held at their equilibrium
        values: ``cert.held`` names them, and the set is certified for them AT those values.
    degree : int
        Final (even, >= 2) degree of ``V``; the search runs through 2, 4, ..., ``degree``.
    iterations : int or sequence of int
        Alternations (V step + level problem) per degree, >= 1; the best ``V`` (largest sampled volume) is kept.
        One number for every degree, or one per degree 2, 4, ..., ``degree`` (the counts of degrees below that of
        the starting ``V`` go unused). The V steps of a low degree are much cheaper, and a ``V`` taken further
        there leaves less to do at the high degree: on the chapter-5 glider (4 states, ``K_M = -50``),
        ``degree=4, iterations=(9, 1)`` certified a volume of 0.197 in 109 s where ``iterations=4`` gives 0.155 in
        322 s (``bench/bench_roa.py``, cases ``glider4_staged`` and ``glider4``, one run).
    backoff : float
        Certified level ``(1 - backoff) rho*``, ``backoff`` in ``[0, 1)``; tripled (up to 3 times, at most 0.25;
        from 0.01 when it is 0) when the Gram margins at that level do not exceed the coefficient residuals
        (recorded in ``history``). With ``solver="CVXOPT_MOMENT"``, if no backoff passes, the same steps are
        taken again with Clarabel (the moment route stops at a singular Schur complement with residuals near
        1e-6).
    eps : float
        ``V - eps |z|^2`` must be SOS in the V step (strict positivity), ``eps > 0``.
    initial : Poly or array_like (n, n), optional
        Starting ``V`` in the system's polynomial variables, ``V(0) = 0``; or a weight matrix ``W`` (state units,
        e.g. ``Q + K^T R K`` of an LQR law): the start is then the cost-to-go ``(x - x_e)^T P (x - x_e)`` with
        ``A^T P + P A = -W`` (:func:`~glidectl.roa.scaling.scaled_lyapunov`). Default: the Lyapunov equation with
        ``W = I`` of the scaled linearization for the surrogate route (states scaled to the box), else
        :func:`lyapunov_quadratic`.
    speed_floor : float
        ``delta`` of the denominator cut for recast models, in ``(0, 1)``.
    extra : int, optional
        Extra multiplier degree (steps of 2, >= 0); default 2 for up to 3 polynomial variables, else 0.
    n_truth : int
        Box points simulated once (>= 1); the V step minimizes ``mean(max(V - 1, 0))`` over those that converge
        (the simulated region of attraction guides the search, the certificate never depends on it).
    n_verify, n_simulate, horizon :
        Sampling of the certified set on the true model (>= 1), number of simulations from the outermost samples
        (>= 0) and their length (> 0; default 25 slowest time constants).
    solver : str
        An SDP solver of :func:`glidectl.roa.installed_sdp_solvers` (default ``"CVXOPT_MOMENT"``: programs with
        a Gram block of order 40 or more whose moment form is the smaller side by CVXOPT on that form, 2-5 times
        faster per program, the others by Clarabel; see :mod:`glidectl.roa.sdp_solvers`).
    seed : int
        Seed of the sampling (>= 0).
    center : float
        The multiplier of the V step comes from the level problem re-solved at ``(1 - center) rho*``, ``center`` in
        ``[0, 1)``: a feasibility program at that level (Clarabel), or, for a Gram block of order
        :data:`CENTER_BY_LEVEL_MIN_BLOCK` or more on the moment route, the level program itself with ``rho`` capped
        there. A V step that fails (its new V has no positive level, or its SDP fails) is tried once more with the
        multiplier centred at ``(1 - RETRY_CENTER) rho*`` (:data:`RETRY_CENTER`, when larger than ``center``); a
        second failure stops the alternation at the best V so far (``stopped_by = "solver failure"``), and so does a
        first one when the time limit leaves no time for the retry (``stopped_by = "time_limit"``, with
        ``on_budget="stop"``).
    max_degree : int
        Largest ``degree`` accepted (default :data:`MAX_DEGREE` = 8): SDP time grows steeply with the degree.
    time_limit : float, optional
        Wall-time budget (s), checked between SDPs (an SDP under way is not interrupted); default none. With
        ``on_budget="raise"`` it also bounds the ``n_truth`` simulations and every step of the final verification
        (sampling the set in batches, the true ``dV/dt``, the simulations from the outermost samples, given the time
        left): :class:`~glidectl.BudgetError` names the step and what to lower (``n_verify``, ``n_simulate``,
        ``horizon``, ``n_truth``); the verification is never shortened to fit. A budget message also gives the wall
        time of each stage so far and the time the requested run would need.
    memory_limit : float, optional
        Bytes the largest program may need (:func:`estimate_sos_size`, checked before anything is built); default
        :data:`MEMORY_FRACTION` (half) of the physical memory, or of the address-space limit if one is set.
    on_budget : {"raise", "stop"}
        What hitting ``time_limit`` does: raise :class:`~glidectl.BudgetError` (default), or end the alternation and
        certify the best ``V`` found so far (the final certification SDPs and checks still run, in full and past the
        limit), with ``stopped_by = "time_limit"``. ``max_degree`` and ``memory_limit`` always refuse up front.
    box : (array_like, array_like) or mapping, optional
        Region of interest in state units, ``(lo, hi)`` or ``{state name: (lo, hi)}``
        (:func:`~glidectl.roa.scaling.resolve_box`); default the model's own box, else the validity box of its
        states (:func:`~glidectl.roa.scaling.validity_box`: the actuator ranges and rates of its vehicle, the
        half-widths of the glider states about the equilibrium; the same default as :func:`glidectl.saturated_loop`);
        a state none of these knows is refused with a message asking for ``box=``. ``cert.box`` is the box used.
    method : {"auto", "exact", "surrogate"}
        Route (issue 17): ``"exact"`` recasts the model exactly (:func:`~glidectl.roa.systems.recast`; a closed loop
        is shifted to its equilibrium and sampled on the box widened 3x); ``"surrogate"`` certifies a polynomial
        surrogate with a remainder bound on the box (:func:`~glidectl.roa.surrogate.surrogate_system`), for every
        right-hand side within that bound, the true one included; ``"auto"`` (default) tries the exact recast
        (closed loops: small monomial bases only) and falls back to the surrogate. ``cert.method`` says which. A
        SaturatedLoop takes the same choice for its plant (``"sos-sector"`` or ``"sos-sector+remainder"``).
    surrogate_degree : int
        Degree of the surrogate, 2 to 5 (default 3).
    margin : float
        Safety factor (>= 1) of the surrogate's remainder bound (:mod:`glidectl.roa.surrogate`).
    reuse : bool
        Exact route: build the V step, level and centering programs once per degree (and monomial support) with
        the fixed polynomials (the multiplier, ``V``, the centering level) as cvxpy Parameters, and re-solve them
        across alternations instead of rebuilding and recompiling (same SOS conditions; default True).
    inner : {"sos", "sdsos", "dsos"}
        Cone of the Gram matrices of the alternation's inner programs (first level, V steps, level problems;
        :data:`~glidectl.roa.sos.GRAM_CONES`): ``"sos"`` (default, SDPs), or the inner approximations ``"sdsos"``
        (SOCPs) and ``"dsos"`` (LPs) of Ahmadi and Majumdar (2019), cheaper but more conservative. The final
        certificate is always a full SOS one: with an inner approximation the kept ``V`` first gets its full SOS
        level (one more SDP, recorded in ``history`` as ``"final SOS level"``), then the backed-off margin SDP and
        the verification run as with ``"sos"``.
    box_search : int
        Surrogate routes (``"surrogate+remainder"``, ``"sos-sector+remainder"``) with a quadratic start: how many
        smaller boxes to try for the surrogate at most (default 6; 0: the box only). The remainder bound holds on
        the whole box, so a region much smaller than the box pays for curvature far from it. Each round sets the box
        to three times the extents of the best set of the starting ``V0`` so far (clipped to the box), builds its
        surrogate and solves one level SDP of the same ``V0``; the alternation runs on the box with the largest
        level (each round is a ``"remainder box r = ..."`` step of ``history``). ``cert.box`` is the box used.
    box_rounds : int
        Surrogate routes: rounds of certification (default 2; 1: one). After a certificate, the box is set to three
        times the extents of the certified set (clipped to the route's box), the surrogate is built on it and the
        alternation runs again from the certificate's ``V``; the new certificate is kept if it is certified and
        larger (``history`` holds both rounds; a round stops early when the box would not change, the first fails
        its Gram or local checks, or the time limit is reached). Without a ``time_limit``, the first round's sampled
        checks and simulations (``n_verify``, ``n_simulate``) run only if it is the certificate returned.

    The certificate is a function of the arguments only: the call runs with one BLAS thread
    (:data:`glidectl.roa.blas_threads.BLAS_THREADS`) and Clarabel with one thread
    (:data:`glidectl.roa.sdp_solvers.CLARABEL_THREADS`), whose parallel sums would otherwise change it between
    machines.

    Returns
    -------
    ROACertificate
        With ``stopped_by`` saying what ended the alternation at the final degree, ``method`` the route, ``box``
        and ``scale`` what was used, ``held`` the states held at their equilibrium values.

    Raises
    ------
    ArgumentTypeError
        If ``system`` is neither a PolySystem nor a model, or an argument has the wrong type (``degree=4.0``
        included: degrees are integers).
    ArgumentError
        If an argument is out of range: an odd or too small ``degree``, ``backoff`` or ``center`` outside
        ``[0, 1)``, an unknown solver, a bad ``initial``, an unknown ``method`` (or ``"surrogate"`` for a
        SaturatedLoop), a count of ``iterations`` below 1 or a sequence without one per degree; a box that is
        invalid, misses limits for some states or does not contain the equilibrium.
    ModelError
        If the equilibrium is not exponentially stable (unstable, or marginally stable such as a centre; for a
        closed loop, its linearization on the states that are not held, checked before it is recast or a surrogate
        is built), the model
        cannot be recast exactly with ``method="exact"`` (the message names the derivatives that are not
        polynomial in which states), the model has no equilibrium, or its right-hand side is not complex-safe or
        not finite on the box (surrogate route).
    BudgetError
        If ``degree > max_degree`` or the program would need more than ``memory_limit`` (the message gives the
        largest degree that fits), or ``time_limit`` is hit (unless ``on_budget="stop"``), the final verification
        included. For the surrogate route the size is checked before anything is sampled, fitted or built: at once
        for a model built for certification, and after one Jacobian at the equilibrium (which finds the held
        states, not counted) for a closed loop.
    SolverError
        If the first level problem fails (no certificate at all) or no simulated box point converges.
    """
    t_wall = time.perf_counter()
    degree = _check_degree(degree)
    max_degree = checks.integer("max_degree", max_degree, lo=2)
    its = _check_iterations(iterations, degree)
    backoff = checks.real("backoff", backoff, lo=0.0, hi=1.0, hi_open=True)
    eps = checks.positive("eps", eps)
    speed_floor = checks.real("speed_floor", speed_floor, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    n_truth = checks.integer("n_truth", n_truth, lo=1, hi=2**22)
    n_verify = checks.integer("n_verify", n_verify, lo=1, hi=2**24)
    n_simulate = checks.integer("n_simulate", n_simulate, lo=0, hi=2**20)
    horizon = None if horizon is None else checks.positive("horizon", horizon)
    check_solver(solver)
    seed = checks.integer("seed", seed, lo=0)
    center = checks.real("center", center, lo=0.0, hi=1.0, hi_open=True)
    limit = _default_memory_limit() if memory_limit is None else checks.positive("memory_limit", memory_limit)
    deadline = checks.Deadline(time_limit, "certify_roa")
    checks.choice("on_budget", on_budget, ("raise", "stop"))
    # --- route (issue 17): exact recast, or a polynomial surrogate with a remainder bound
    method = checks.choice("method", method, ("auto", "exact", "surrogate"))
    surrogate_degree = checks.integer("surrogate_degree", surrogate_degree, lo=2, hi=5)
    margin = checks.real("margin", margin, lo=1.0)
    reuse = checks.boolean("reuse", reuse)
    inner = checks.choice("inner", inner, GRAM_CONES)
    box_search = checks.integer("box_search", box_search, lo=0, hi=30)
    box_rounds = checks.integer("box_rounds", box_rounds, lo=1, hi=10)
    ps, full, rebuild = _route(system, box=box, method=method, surrogate_degree=surrogate_degree, margin=margin,
                               speed_floor=speed_floor, seed=seed, degree=degree, max_degree=max_degree, limit=limit,
                               extra=extra)
    t_route = deadline.elapsed
    box0 = (np.array(ps.box[0], dtype=float), np.array(ps.box[1], dtype=float))     # (free states)
    if on_budget == "raise":
        deadline.check(f"after building the {ps.method} system of {ps.n} states ({t_route:.1f} s)"
                       + ("" if full is None else f", {', '.join(full.names[i] for i in full.held)} held"))
    weight = None
    if initial is not None and not isinstance(initial, Poly):
        # a weight matrix: the starting V is the quadratic cost-to-go (x - x_e)^T P (x - x_e), A'P + PA = -weight
        weight = checks.array("initial (weight matrix)", initial, shape=(ps.n, ps.n))
        if ps.nz != ps.n:
            raise ArgumentError("initial as a weight matrix needs a system whose polynomial variables are its states "
                                f"(no angle lift); '{ps.name}' has z = {ps.z_names}: give initial as a Poly")
        initial = None
    if initial is not None:
        _check_V(initial, ps, "initial")
    ex = _auto_extra(ps, extra)
    _require_exponential_stability(ps, _linearization(ps))
    _check_memory(ps, degree, ex, max_degree, limit, f"certify_roa(degree={degree})")

    spent: dict[str, float] = {}      # wall time of each stage (s), for the budget message
    v_steps: list[float] = []

    def time_spent() -> str:
        """What took the time so far and what the requested run would need (what would fit)."""
        parts = [f"{k} {v:.1f} s" for k, v in spent.items()]
        if v_steps:
            parts.append(f"{len(v_steps)} V step(s) with their level problems, {max(v_steps):.1f} s at most each")
            per = max(v_steps)
            need = sum(spent.values()) + per * sum(its) + per
            shown = its if len(set(its)) > 1 else its[0]
            est = (f"degree {degree} with iterations = {shown} needs about {need:.0f} s before the final "
                   f"verification: raise time_limit to that, or lower iterations (or degree)")
        else:
            est = "no V step finished within the limit: raise time_limit, or lower degree or n_truth"
        return f"time spent: {', '.join(parts)}; {est}"

    def out_of_time(where: str) -> bool:
        if deadline.limit is None or deadline.elapsed <= deadline.limit:
            return False
        if on_budget == "raise":
            deadline.check(f"{where}; {time_spent()}; or pass on_budget='stop' to certify the best V found so far")
        return True

    if initial is not None:
        V0 = initial
    elif ps.scale is not None or weight is not None:
        V0 = scaled_lyapunov(_linearization(ps), ps.scale[:ps.n] if ps.scale is not None else np.ones(ps.n), weight)
        if ps.nz != ps.n:       # (a saturated loop) the quadratic in the states' own variables of z
            Zv = Poly.variables(ps.nz)
            V0 = V0.substitute([Zv[sl[0]] for sl in ps.slots])
    else:
        V0 = lyapunov_quadratic(ps)
    history: list[dict[str, Any]] = []
    if rebuild is not None and box_search > 0 and V0.degree == 2:
        t_stage = time.perf_counter()
        ps, V0 = _search_box(ps, rebuild, V0, n_boxes=box_search, solver=solver, extra=extra, history=history,
                             out_of_time=out_of_time)
        spent["remainder-box search"] = time.perf_counter() - t_stage
        full = full.with_free_box(ps.box) if full is not None else None
    def run(ps: PolySystem, V0: Poly, full: _Full | None, t_solve: float,
            verify: bool = True) -> tuple[ROACertificate, Callable[[], ROACertificate]]:
        """The alternation from ``V0`` on ``ps`` and its final certificate (a remainder-box round runs it again on
        another box); ``t_solve`` is the SDP time spent before it. Returns the certificate and a function that
        returns it verified (:func:`_verify`). With ``verify=False`` the certificate carries only the checks that
        cost no sampling (Gram, Hessian, ``A'H + HA``; :attr:`ROACertificate.certified` is then False) and the
        sampling and simulations run when that function is called: the first of several remainder-box rounds is
        verified only if it is the one kept."""
        k = _scaling(ps)
        pss = _rescale(ps, k)
        F = _scaled(pss)
        hz = horizon or _default_horizon(ps)
        V = _to_scaled(V0, k)
        # programs re-solved with new Parameter values (per degree); the inner cones build their programs anew
        cache: dict | None = {} if reuse and inner == "sos" else None
        held_note = "" if full is None else (f" (free states; {', '.join(full.names[i] for i in full.held)} held at "
                                             "their equilibrium values)")
        spent[f"building the {ps.method} system of {ps.n} states{held_note}"] = t_route
        t_stage = time.perf_counter()
        try:
            lvl = _level(pss, F, V, rho_cap=1e6, solver=solver, center=center, extra=ex, cache=cache, cone=inner)
        except SolverError as exc:
            if inner == "sos":
                raise
            raise SolverError(f"the first level problem with inner='{inner}' failed ({exc}): the {inner.upper()} inner "
                              "approximation cannot certify the starting V; use inner='sos'") from exc
        if not (math.isfinite(lvl.rho) and lvl.rho > 0):
            if inner == "sos":
                raise SolverError(f"the first level problem gives level {lvl.rho:.3g}, not positive: the starting V "
                                  f"is not certified on any level set of '{ps.name}' (give another initial V, or a "
                                  "smaller box)")
            raise SolverError(f"the first level problem with inner='{inner}' gives level {lvl.rho:.3g} <= 0: the "
                              f"{inner.upper()} inner approximation cannot certify the starting V; use inner='sos'")
        t_solve += lvl.solve_time
        spent["first level problem"] = time.perf_counter() - t_stage
        V, lam = V / lvl.rho, lvl.lam
        lo, hi = ps.box
        Xv = lo + (hi - lo) * _sobol(ps.n, 2, 2**13)

        Pv = _PathPoints(pss, Xv)

        def vol(Vc: Poly) -> float:
            return _step_volume(pss, Pv, Vc, lo, hi, seed)

        cur_vol = vol(V)
        best = (cur_vol, V)
        history.append({"degree": V.degree, "step": "initial level", "rho": lvl.rho, "volume": cur_vol,
                        "sdp_time": lvl.solve_time, "compile_time": lvl.compile_time, "solver_time": lvl.solver_time})
        t_stage = time.perf_counter()
        Zt = pss.lift(_ground_truth(ps, n_truth, hz, seed, deadline if on_budget == "raise" else None))
        spent[f"simulating n_truth = {n_truth} box points"] = time.perf_counter() - t_stage
        if Zt.shape[0] == 0:
            raise SolverError(f"none of the {n_truth} simulated box points of '{ps.name}' converges within {hz:g}: "
                              "nothing to steer the V step towards (check the box and the horizon)")
        stopped_by = "iterations"
        for degV in range(2, degree + 1, 2):
            if degV < _even_up(V.degree):
                continue
            worse = 0
            stopped_by = "iterations"
            if cache is not None:       # programs of a lower degree are not used again
                for old in [k for k in cache if k[1] < degV]:
                    del cache[old]
            for it in range(its[degV // 2 - 1]):
                if out_of_time(f"degree {degV}, before a V step"):
                    stopped_by = "time_limit"
                    break
                t_stage = time.perf_counter()
                step_sdp = 0.0      # SDP time of this step counted in t_solve (its history row shows the same)
                retried = False
                while True:         # the V step, once more after a failure with a multiplier centred deeper
                    try:
                        if inner == "sos":
                            prog, out = _v_step(pss, F, degV, lam, Zt, eps=eps, extra=ex, solver=solver, cache=cache,
                                                V0=V)
                        else:
                            prog, out = _build(pss, F, degV, V=None, lam=lam, rho=1.0, eps=eps, extra=ex, cone=inner,
                                               V0=V)
                            prog.solve(_coverage_objective(prog, out["V"], Zt), solver=solver)
                        t_solve += prog.solve_time
                        step_sdp += prog.solve_time
                        Vn = out["V"].poly()
                        if out_of_time(f"degree {degV}, after a V step"):
                            history.append({"degree": degV, "step": "V step solved, not used: time limit before its "
                                            "level", "rho": math.nan, "volume": math.nan, "sdp_time": step_sdp})
                            stopped_by = "time_limit"
                            break
                        # the centred multiplier only feeds a later V step: none follows the last one (exact saving)
                        last = degV == degree and it == its[-1] - 1
                        lv = _level(pss, F, Vn, rho_cap=1e6, solver=solver, center=0.0 if last else center,
                                    extra=ex, cache=cache, basis=out["V"].basis, cone=inner)
                        t_solve += lv.solve_time
                        step_sdp += lv.solve_time
                        if not (math.isfinite(lv.rho) and lv.rho > 0):
                            # an inaccurate V step can return a V whose level is 0 (or a solver a NaN level): V / rho
                            # would be infinite and its multiplier would steer the next step from nothing (2026-12-04:
                            # a V step solved to 1e-6 on the saturated user glider gave rho = -0.0, then 868)
                            raise SolverError(f"the level of the new V is {lv.rho:.3g}, not positive")
                        break
                    except SolverError as exc:
                        # the V step took its multiplier from the level set just inside the current V's limit and
                        # pushed the new V to where no level is certified: steer once more, from a multiplier centred
                        # deeper inside (the same V, the level problem at (1 - RETRY_CENTER) rho*)
                        why, lvc, stop = f"V step failed: {exc}", None, "solver failure"
                        if not retried and RETRY_CENTER > center:
                            if out_of_time(f"degree {degV}, before a retry"):
                                why, stop = why + "; not retried: time limit", "time_limit"
                            else:
                                try:
                                    lvc = _level(pss, F, V, rho_cap=1e6, solver=solver, center=RETRY_CENTER,
                                                 extra=ex, cache=None, cone=inner)
                                except SolverError as exc2:
                                    why += f"; its retry's multiplier: {exc2}"
                        if lvc is None:
                            history.append({"degree": degV, "step": why, "rho": math.nan, "volume": math.nan,
                                            "sdp_time": step_sdp})
                            stopped_by = stop
                            break
                        t_solve += lvc.solve_time
                        step_sdp += lvc.solve_time
                        history.append({"degree": degV, "step": f"V step failed ({exc}): retried with the multiplier "
                                        f"centred at (1 - {RETRY_CENTER:g}) rho*", "rho": lvc.rho, "volume": math.nan,
                                        "sdp_time": step_sdp})
                        step_sdp = 0.0
                        lam, retried = lvc.lam, True
                if stopped_by in ("time_limit", "solver failure"):
                    break
                V, lam = Vn / lv.rho, lv.lam
                v_steps.append(time.perf_counter() - t_stage)
                cur_vol = vol(V)
                history.append({"degree": degV, "step": "V step + level", "rho": lv.rho, "volume": cur_vol,
                                "sdp_time": prog.solve_time + lv.solve_time,
                                "compile_time": prog.compile_time + lv.compile_time,
                                "solver_time": prog.solver_time + lv.solver_time})
                if cur_vol > best[0]:
                    best, worse = (cur_vol, V), 0
                else:
                    worse += 1
                    if worse >= 2:
                        stopped_by = "no improvement"
                        break
            if stopped_by == "time_limit":
                history.append({"degree": degV, "step": f"time limit of {deadline.limit:g} s: alternation stopped",
                                "rho": math.nan, "volume": math.nan, "sdp_time": 0.0})
                break
        V = best[1]
        if ps.remainder:    # V(0) = 0 and V >= 0 leave no linear terms but rounding ones: they would make dV/dt
            # sign-indefinite at |z| ~ 1e-10, which the local check of the surrogate routes cannot pass; drop them
            V = Poly({e: c for e, c in V.terms.items() if sum(e) >= 2}, V.nvars)
        if stopped_by != "time_limit":
            out_of_time("before the final certification")
        # final certificate at a backed-off level, re-solved at that level, then verified. The kept V is normalized by
        # the optimum of its own level problem (V / rho*), so its level is 1 (no SDP needed to find it again).
        fin_rho = 1.0
        if inner != "sos":          # the kept V's level is an inner-approximation one: its full SOS level is >= 1
            lvs = _level(pss, F, V, rho_cap=1e6, solver=solver, center=0.0, extra=ex)
            t_solve += lvs.solve_time
            if lvs.rho > 1.0:
                V = V / lvs.rho
            history.append({"degree": V.degree, "step": f"final SOS level ({inner} level 1)", "rho": lvs.rho,
                            "volume": vol(V), "sdp_time": lvs.solve_time, "compile_time": lvs.compile_time,
                            "solver_time": lvs.solver_time})
        # the largest Gram eigenvalue margin at rho_c, checked with the residual on monomials no Gram pair reaches
        # cancelled by the free multipliers first (check(polish=True)); if rounding still leaves the margin below
        # the coefficient residuals, back off further (x3, at most 3 times) and re-solve the same compiled program
        # (rho_c is a cvxpy Parameter)
        prog, outf = _build(pss, F, _even_up(V.degree), V=V, lam=None, rho=None, eps=0.0, extra=ex, margin=True)
        rho_p = cp.Parameter(nonneg=True)
        prog.constraints.append(outf["rho"].var == rho_p)

        def margin_steps(fin_solver: str) -> tuple[float, tuple, float]:
            nonlocal t_solve
            bo, tag = backoff, "" if fin_solver == solver else f" ({fin_solver.capitalize()})"
            for i in range(4):
                rho_c = (1 - bo) * fin_rho
                rho_p.value = rho_c
                if prog.problem is None:
                    prog.solve(cp.Maximize(outf["margin"]), solver=fin_solver)
                else:
                    prog.resolve(solver=fin_solver)
                t_solve += prog.solve_time
                outf["rho"].var.value = np.full(outf["rho"].var.shape, rho_c)    # the level checked: rho_c exactly
                checks_ = tuple(prog.check(polish=True))
                rad = max((c.radius for c in checks_ if c.name == "decrease"), default=0.0)
                gram = checks_ + _local_robust(outf.get("W"), pss, rad)
                history.append({"degree": V.degree, "step": f"final margin at backoff {bo:g}{tag}", "rho": rho_c,
                                "volume": _step_volume(pss, Pv, V, lo, hi, seed, rho_c),
                                "sdp_time": prog.solve_time, "compile_time": prog.compile_time,
                                "solver_time": prog.solver_time})
                if all(c.passed for c in gram) or bo >= 0.25 or i == 3:
                    break
                history.append({"degree": V.degree, "step": f"Gram slack {min(c.slack for c in gram):.2g} at "
                                f"backoff {bo:g}: backing off", "rho": rho_c, "volume": math.nan, "sdp_time": 0.0})
                bo = min(3 * bo, 0.25) if bo > 0 else 0.01
            return rho_c, gram, bo

        rho_c, gram, bo = margin_steps(solver)
        if solver == MOMENT and not all(c.passed for c in gram):
            # the moment route stops at a singular Schur complement with residuals near 1e-6, which a small margin
            # may not cover: the same steps with Clarabel
            history.append({"degree": V.degree, "step": f"Gram slack {min(c.slack for c in gram):.2g} at backoff "
                            f"{bo:g}: the same steps by Clarabel from backoff {backoff:g}",
                            "rho": rho_c, "volume": math.nan, "sdp_time": 0.0})
            rho_c, gram, _ = margin_steps("CLARABEL")
        Vz = _from_scaled(V, k)
        scale = k * (ps.scale if ps.scale is not None else 1.0)

        def made(ver: ROAVerification) -> ROACertificate:
            return ROACertificate(ps if full is None else _embed(ps, full), Vz, rho_c, fin_rho, Vz.degree,
                                  tuple(history), ver, t_solve, time.perf_counter() - t_wall, ps.provenance,
                                  stopped_by, method=ps.method, scale=np.asarray(scale, dtype=float),
                                  held=() if full is None else tuple(full.names[i] for i in full.held))

        def verified() -> ROACertificate:
            return made(_verify(ps, Vz, rho_c, gram, n_verify=n_verify, n_simulate=n_simulate, horizon=hz,
                                seed=seed, deadline=deadline if on_budget == "raise" else None))

        if verify:
            cert = verified()
            return cert, lambda: cert
        hmin, lmax = _local_checks(ps, Vz)
        return made(ROAVerification(gram, hmin, lmax, 0, math.nan, 0, 0, hz)), verified

    def note(degree: int, step: str) -> None:
        history.append({"degree": degree, "step": step, "rho": math.nan, "volume": math.nan, "sdp_time": 0.0})

    rounds = range(2, box_rounds + 1 if rebuild is not None else 0)
    # the first round's sampling and simulations wait until it is known to be the certificate kept (a second
    # round, verified in full, replaces it when larger); not under a time limit, which they could then exceed
    pending = bool(rounds) and deadline.limit is None
    searched = float(sum(h["sdp_time"] for h in history))     # the remainder-box search's level programs
    cert, verify_first = run(ps, V0, full, searched, verify=not pending)
    untaken = 0.0           # SDP time of rounds not kept (a round starts its count from the certificate's)
    for rnd in rounds:
        # a remainder-box round: the box three times the extents of the certified set (clipped to the box of the
        # route), a surrogate on it, and the alternation again from the certificate's V; kept if larger
        if not cert.verification.unsampled_passed or cert.stopped_by == "time_limit":
            break
        cur = cert.system if full is None else ps
        free = list(range(cur.n)) if full is None else list(full.free)
        Xb = cert.sample(2000, seed=seed, boundary=True)[:, free]
        xe = np.asarray(cur.equilibrium, dtype=float)
        blo, bhi = _box_about(xe, 3.0 * np.max(np.abs(Xb - xe), axis=0), box0)
        if np.all(np.abs(np.log((bhi - blo) / (np.asarray(cur.box[1]) - np.asarray(cur.box[0])))) < 0.1):
            note(cert.degree, f"remainder-box round {rnd} skipped: the box would change by less than 10 %")
            break
        note(cert.degree, f"remainder-box round {rnd}: the box three times the extents of the certified set")
        try:
            ps2 = rebuild((blo, bhi))
            full2 = full.with_free_box((blo, bhi)) if full is not None else None
            cert2, _ = run(ps2, _transport(cert.V, cur, ps2), full2, cert.solve_time)
        except (BudgetError, SolverError, ModelError) as exc:
            note(cert.degree, f"remainder-box round {rnd} stopped: {exc}")
            break
        if not (cert2.certified and cert2.volume() > cert.volume()):
            note(cert.degree, f"remainder-box round {rnd} not kept (not certified or not larger)")
            untaken += cert2.solve_time - cert.solve_time
            break
        cert, ps, full, pending = cert2, ps2, full2, False
    if pending:                                 # the first round is the certificate kept: its sampled checks
        cert = verify_first()
    # the rounds that were tried, kept or not, in the history, and in the times: a certificate made before a later
    # round was tried (under a time limit, or one kept before a round that was not) would otherwise report its own
    return dataclasses.replace(cert, history=tuple(history), solve_time=cert.solve_time + untaken,
                               wall_time=time.perf_counter() - t_wall)


# --------------------------------------------------------------------------------------------- routes (issue 17)
def _local_robust(W: Poly | None, ps: PolySystem, radius: float = 0.0) -> tuple[GramCheck, ...]:
    """Surrogate routes: the robust upper bound ``W`` of ``dV/dt`` must be negative on ``0 < |z| <= radius``, the
    ball where the decrease certificate does not speak (its unreachable low-degree residual,
    :attr:`~glidectl.roa.sos.GramCheck.radius`), and negative definite at the equilibrium, else ``{W != 0}`` could
    be ``W > 0`` near it. With ``W = W_2 + W_3 + ...`` (by degree) and ``|z^e| <= |z|^|e|``:
    ``W(z) <= (-mu + sum_{|e| >= 3} |w_e| radius^(|e| - 2)) |z|^2`` there, ``mu`` the smallest eigenvalue of
    ``-W_2``; the entry of the Gram checks has ``min_eig = mu`` and ``max_residual`` the sum. With saturated-input
    variables (``ps.inputs``), ``W`` is taken on the loop's own graph near the equilibrium, where no input saturates:
    ``z = T z_x`` with ``T`` the derivative of ``lift`` there (``v = K x``)."""
    if W is None or not ps.remainder:
        return ()
    P = W
    if ps.inputs:
        xe = np.asarray(ps.equilibrium, dtype=float)
        h = 1e-30
        J = np.imag(ps.lift(xe[None, :] + 1j * h * np.eye(len(xe)))).T / h      # J[z, x] = d z / d x
        xz = [i for i in range(ps.nz) if i not in set(ps.inputs)]
        T = J @ np.linalg.inv(J[xz])
        Zx = Poly.variables(len(xz))
        P = W.substitute([sum((Zx[j] * float(T[i, j]) for j in range(len(xz)) if T[i, j] != 0.0), Poly({}, len(xz)))
                          for i in range(ps.nz)])
    mu = float(np.linalg.eigvalsh(-P.quadratic_part())[0])
    if not math.isfinite(radius):
        tail = math.inf
    else:
        tail = sum((abs(c) * radius ** (sum(e) - 2) for e, c in P.terms.items() if sum(e) >= 3), 0.0)
        tail += math.inf if any(sum(e) < 2 and c != 0.0 for e, c in P.terms.items()) else 0.0
    return (GramCheck(f"local robust decrease (-quadratic part of the dV/dt bound, within |z| <= {radius:.2g})", 1,
                      mu, tail),)


class _Shifted:
    """A closed loop in deviations ``x - x_e`` with its box, for :func:`recast` (equilibrium at 0)."""

    def __init__(self, model: Any, xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> None:
        self._f, self._xe = model.rhs, xe
        self.state_names = tuple(model.state_names)
        self.equilibrium = np.zeros(len(xe))
        # the recast is sampled on the box widened 3x about the equilibrium: a smooth non-polynomial field is
        # within 1e-9 of a low-degree polynomial on a small enough box, a polynomial one is polynomial everywhere
        self.box = (3.0 * (box[0] - xe), 3.0 * (box[1] - xe))
        self.name = getattr(model, "name", type(model).__name__)
        self.provenance = str(getattr(model, "provenance", ""))
        self.time_unit = getattr(model, "time_unit", "s")
        for a in ("angle_states", "mixed_angle_states", "positive_state"):
            if hasattr(model, a):
                setattr(self, a, getattr(model, a))

    def rhs(self, X: Any) -> np.ndarray:
        return np.asarray(self._f(np.asarray(X) + self._xe))


def _is_roa_model(system: Any) -> bool:
    """A model built for certification: equilibrium at 0 and its own box (``sp.reduced_model()``...)."""
    eq = getattr(system, "equilibrium", None)
    return (hasattr(system, "box") and eq is not None and not callable(system.box)
            and np.all(np.asarray(eq, dtype=float) == 0.0))


def _held_states(model: Any, xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> tuple[int, ...]:
    """States of a closed loop that never move: the states its law locks (``locked_states`` of its controller, as
    :func:`glidectl.saturated_loop` holds them) and those whose row of the linearization vanishes once the states
    already held are fixed (repeated: ``r_P3' = rdot_P3`` is held once ``rdot_P3`` is), kept only if their derivative
    is zero on box points with them at the equilibrium (:func:`~glidectl.roa.lmi.held_points`,
    :func:`~glidectl.roa.lmi.held_motion`, the check of :func:`glidectl.saturated_loop`): then ``{x_h = x_e,h}`` is
    invariant on the box. Empty if none, or if every state would be held."""
    names = tuple(model.state_names)
    n = len(names)

    def f(X: np.ndarray) -> np.ndarray:
        return np.asarray(model.rhs(X))

    with np.errstate(all="ignore"):
        A = jacobians(lambda x, u: f(x[None, :])[0], xe, np.zeros(0))[0]
    if not np.all(np.isfinite(A)):
        return ()
    ctrl = getattr(getattr(model, "law", None), "__self__", None)
    held = {names.index(q) for q in getattr(ctrl, "locked_states", ()) if q in names}
    tol = 1e-12 * max(1.0, float(np.max(np.abs(A))))
    while True:
        free = [j for j in range(n) if j not in held]
        new = {i for i in free if np.all(np.abs(A[i, free]) <= tol)}
        if not new:
            break
        held |= new
    if not held or len(held) == n:
        return ()
    h = tuple(sorted(held))
    with np.errstate(all="ignore"):
        dX = np.real(f(held_points(box, xe, h)))
    if not np.all(np.isfinite(dX)) or held_motion(dX, h) > 1e-12:
        return ()
    return h


class _Held:
    """A closed loop on its free states, the held ones fixed at their equilibrium values (an input-free model for
    the exact and surrogate routes); angle indices are renumbered."""

    def __init__(self, model: Any, held: tuple[int, ...], xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> None:
        names = tuple(model.state_names)
        self._f, self._xe, self._n = model.rhs, np.asarray(xe, dtype=float).copy(), len(names)
        self.free = [i for i in range(len(names)) if i not in held]
        self.state_names = tuple(names[i] for i in self.free)
        self.equilibrium = self._xe[self.free]
        self.box = (box[0][self.free], box[1][self.free])
        self.name = getattr(model, "name", type(model).__name__)
        self.provenance = str(getattr(model, "provenance", ""))
        self.time_unit = getattr(model, "time_unit", "s")
        new = {i: k for k, i in enumerate(self.free)}
        for a in ("angle_states", "mixed_angle_states"):
            if hasattr(model, a):
                setattr(self, a, tuple(new[i] for i in getattr(model, a) if i in new))
        if getattr(model, "positive_state", None) in new:
            self.positive_state = new[model.positive_state]

    def rhs(self, Y: Any) -> np.ndarray:
        Y = np.asarray(Y)
        X = np.broadcast_to(self._xe, (*Y.shape[:-1], self._n)).astype(Y.dtype).copy()
        X[..., self.free] = Y
        return np.asarray(self._f(X))[..., self.free]


@dataclass(frozen=True)
class _Full:
    """The full states of a loop certified on its free states (:class:`_Held`)."""

    names: tuple[str, ...]
    held: tuple[int, ...]
    free: tuple[int, ...]
    equilibrium: np.ndarray
    box: tuple[np.ndarray, np.ndarray]
    rhs: Any

    def with_free_box(self, box: tuple[Any, Any]) -> _Full:
        """The same states with the free states' part of the box replaced by ``box`` (free states' units)."""
        lo, hi = self.box[0].copy(), self.box[1].copy()
        lo[list(self.free)], hi[list(self.free)] = box
        return dataclasses.replace(self, box=(lo, hi))


def _embed(ps: PolySystem, full: _Full) -> PolySystem:
    """The certified free-state system as a system of all the states (held ones at their equilibrium values): what
    the certificate's contains, value, sample, volume and plot take."""
    free = list(full.free)
    xe = full.equilibrium.copy()
    xe[free] = ps.equilibrium
    lift0 = ps.lift
    return dataclasses.replace(
        ps, state_names=full.names, lift=lambda X: lift0(np.asarray(X)[..., free]), rhs=full.rhs, equilibrium=xe,
        box=(full.box[0].copy(), full.box[1].copy()), held=full.held,
        angle_states=tuple(free[i] for i in ps.angle_states), mixed_states=tuple(free[i] for i in ps.mixed_states))


def _box_about(xe: np.ndarray, half: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The box ``xe +- half`` clipped to ``box`` (the remainder-box search and rounds)."""
    return np.maximum(box[0], xe - half), np.minimum(box[1], xe + half)


def _transport(V: Poly, ps_from: PolySystem, ps_to: PolySystem) -> Poly:
    """``V`` in the variables of one surrogate system as the same function of the states in another's (both
    ``z = (x - x_e) / s``: only the scales differ)."""
    r = np.asarray(ps_to.scale, dtype=float) / np.asarray(ps_from.scale, dtype=float)
    Z = Poly.variables(ps_to.nz)
    return V.substitute([Z[i] * float(r[i]) for i in range(ps_to.nz)])


def _level_on(ps: PolySystem, V: Poly, *, solver: str, extra: int | None) -> LevelResult:
    """The level problem of ``V`` (in ``ps``'s variables) on ``ps``, built as :func:`certify_roa` builds it."""
    k = _scaling(ps)
    pss = _rescale(ps, k)
    return _level(pss, _scaled(pss), _to_scaled(V, k), rho_cap=1e6, solver=solver, center=0.0,
                  extra=_auto_extra(ps, extra))


def _search_box(ps: PolySystem, rebuild: Callable[[tuple[np.ndarray, np.ndarray]], PolySystem], V0: Poly, *,
                n_boxes: int, solver: str, extra: int | None, history: list[dict[str, Any]],
                out_of_time: Callable[[str], bool]) -> tuple[PolySystem, Poly]:
    """The remainder-box search of the surrogate routes: the remainder bound holds on the whole box, so a set much
    smaller than the box pays for curvature far away from it. Starting from the box, each round takes the box
    ``x_e +- 3 sqrt(rho) e`` (``e`` the extents of ``{V0 <= 1}``, ``rho`` the best level so far: three times the
    extents of the best set, clipped to the box), builds its surrogate and finds the level of the same ``V0`` (the
    same function of the states) on it (one SDP; the set must lie in that box). Stops when a round does not raise
    the level or the box changes by less than 10 %, after ``n_boxes`` rounds at most (while the level program
    fails, as it can on the whole box, each round takes an 8 times smaller box). Returns the system and ``V0`` (in
    its variables) of the largest level (the box when none was found); the levels are logged in ``history``."""
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    xe = np.asarray(ps.equilibrium, dtype=float)
    idx = [sl[0] for sl in ps.slots]
    Pz = V0.quadratic_part()[np.ix_(idx, idx)]
    sc = np.asarray(ps.scale, dtype=float)[idx]
    ext = np.sqrt(np.diag(np.linalg.inv(Pz / np.outer(sc, sc))))      # extents of {V0 <= 1}, state units
    r = r_box = float(np.max(np.maximum(xe - lo, hi - xe) / ext))       # the box is the search's first one

    def log(step: str, lv: LevelResult | None) -> None:
        history.append({"degree": V0.degree, "step": step, "rho": lv.rho if lv else math.nan, "volume": math.nan,
                        "sdp_time": lv.solve_time if lv else 0.0, "compile_time": lv.compile_time if lv else 0.0,
                        "solver_time": lv.solver_time if lv else 0.0})

    best: tuple[float, PolySystem, Poly] = (-math.inf, ps, V0)
    try:
        lv = _level_on(ps, V0, solver=solver, extra=extra)
        log(f"remainder box r = {r:.3g} (the box)", lv)
        best = (lv.rho, ps, V0)
    except SolverError as exc:              # (an ill-conditioned program on the whole box: try smaller ones)
        log(f"remainder box r = {r:.3g} (the box): {exc}", None)
    for _ in range(n_boxes):
        # three times the extents of the best set so far; while no level is known, an 8 times smaller box
        r_new = min(3.0 * math.sqrt(best[0]) if best[0] > 0 else r / 8.0, r_box)
        if abs(math.log(max(r_new, 1e-300) / r)) < 0.1 or out_of_time(f"remainder-box search at r = {r_new:.3g}"):
            break
        r = r_new
        b = _box_about(xe, r * ext, (lo, hi))
        try:
            psk = rebuild(b)
            Vk = _transport(V0, ps, psk)
            lv = _level_on(psk, Vk, solver=solver, extra=extra)
        except (SolverError, ModelError) as exc:
            log(f"remainder box r = {r:.3g}: {exc}", None)
            if best[0] > 0:
                break
            continue
        log(f"remainder box r = {r:.3g}", lv)
        if not lv.rho > best[0]:
            break
        best = (lv.rho, psk, Vk)
    return best[1], best[2]


def _route(system: Any, *, box: Any, method: str, surrogate_degree: int, margin: float, speed_floor: float, seed: int,
           degree: int, max_degree: int, limit: float, extra: int | None,
           ) -> tuple[PolySystem, _Full | None, Callable[[tuple[np.ndarray, np.ndarray]], PolySystem] | None]:
    """The PolySystem certified: the system itself, its exact recast, or a surrogate with remainder; when the loop
    has held states (:func:`_held_states`), the full states it is embedded in (else None); and, for a surrogate,
    how to build it again on a smaller box of the free states (else None; :func:`_search_box`). Budgets of the
    surrogate route are checked before anything is sampled; a closed loop's linearization on its free states is
    checked for exponential stability before it is recast or a surrogate is built."""
    if isinstance(system, PolySystem):
        return system, None, None
    if isinstance(system, SaturatedLoop):            # saturation in the SOS path: graph of sat as S-procedure terms
        ps = sector_system(system, seed=seed, method=method, surrogate_degree=surrogate_degree, margin=margin)
        if not ps.remainder:
            return ps, None, None
        return ps, None, lambda b: sector_system(system, seed=seed, method="surrogate",
                                                 surrogate_degree=surrogate_degree, margin=margin, box=b)
    names = getattr(system, "state_names", None)
    if names is None or not callable(getattr(system, "rhs", None)):
        raise ArgumentTypeError(f"certify_roa needs a PolySystem or an input-free glidectl model (state_names, rhs, "
                                f"equilibrium), e.g. gc.closed_loop(controller); got {type(system).__name__}")
    if tuple(getattr(system, "input_names", ())):
        raise ArgumentTypeError(f"{type(system).__name__} has inputs {tuple(system.input_names)}: certify_roa needs "
                                "an input-free model with an equilibrium; close the loop first "
                                "(gc.closed_loop(controller) or gc.closed_loop(plant, law))")
    def surrogate_fits(n: int, note: str = "") -> None:
        if method != "exact":
            sk = skeleton(n, surrogate_degree)
            _check_memory(sk, degree, _auto_extra(sk, extra), max_degree, limit,
                          f"certify_roa(degree={degree}) of a {n}-state surrogate of degree {surrogate_degree}{note}")

    if _is_roa_model(system) and box is None:       # a model built for certification: its own box, x_e = 0
        surrogate_fits(len(tuple(names)))
        try:
            if method in ("auto", "exact"):
                return recast(system, speed_floor=speed_floor), None, None
        except ModelError:
            if method == "exact":
                raise

        def build_own(b: Any) -> PolySystem:
            return surrogate_system(system, b, degree=surrogate_degree, margin=margin, seed=seed)
        return build_own(box), None, build_own
    xe0 = getattr(system, "equilibrium", None)
    if xe0 is None:
        raise ModelError(f"'{getattr(system, 'name', type(system).__name__)}' has no equilibrium (None): a region of "
                         "attraction needs one (e.g. closed_loop(plant, law, equilibrium=...))")
    xe0 = checks.array("equilibrium", xe0, shape=(len(tuple(names)),))
    lo, hi = resolve_box(system, box, xe0)
    held = _held_states(system, xe0, (lo, hi))
    # the size of the surrogate route counts the free states only (the held ones are not variables of the program)
    surrogate_fits(len(tuple(names)) - len(held),
                   f" ({', '.join(tuple(names)[i] for i in held)} held)" if held else "")
    full = None
    model: Any = system
    if held:
        model = _Held(system, held, xe0, (lo, hi))
        full = _Full(tuple(names), held, tuple(model.free), xe0.copy(), (lo, hi), system.rhs)
        lo, hi = model.box
    xe = refine_equilibrium(lambda X: np.asarray(model.rhs(X)), np.asarray(model.equilibrium, dtype=float))
    # fast refusal (issue 17): the linearization on the free states, before anything is recast or fitted
    _require_exponential_stability(model, jacobians(lambda x, u: np.asarray(model.rhs(x[None, :]))[0], xe,
                                                    np.zeros(0))[0])
    if method in ("auto", "exact"):
        try:
            n = len(xe)
            dmax = max((d for d in range(1, 5) if math.comb(n + d, d) <= _AUTO_RECAST_BASIS), default=1)
            ps = recast(_Shifted(model, xe, (lo, hi)), speed_floor=speed_floor,
                        max_degree=4 if method == "exact" else dmax, seed=seed)
            lift0 = ps.lift
            return dataclasses.replace(ps, lift=lambda X: lift0(np.asarray(X) - xe), rhs=model.rhs, equilibrium=xe,
                                       box=(lo, hi)), full, None
        except ModelError:
            if method == "exact":
                raise

    def build(b: Any) -> PolySystem:
        return surrogate_system(model, b, degree=surrogate_degree, margin=margin, seed=seed)
    return build((lo, hi)), full, build
