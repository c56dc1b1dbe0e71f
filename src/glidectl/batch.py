"""Vectorized, stiff-aware integration of many independent initial conditions at once.

:func:`integrate_batch` advances ``N`` runs of an autonomous ODE ``x' = f(x)`` in lockstep, each with its own
adaptive step size, using the 4th-order Rosenbrock method of Shampine (1982) with an embedded 3rd-order error
estimate (the "stiff" parameter set of Numerical Recipes, §16.6; A-stable). Each iteration

* builds the ``(N, n, n)`` stack of Jacobians of the active runs with one batched call of ``f`` on ``n N`` rows
  (complex step, exact to rounding, or central differences for right-hand sides that are not complex-safe),
* inverts the ``(N, n, n)`` stack ``I / (gamma h) - J`` once and applies it to the four stages,
* evaluates ``f`` three more times on the active rows only,
* accepts or rejects the step per run from a mixed absolute/relative RMS error norm.

The right-hand side must accept a batch of states of shape ``(M, n)`` and return derivatives of the same shape
(every model ``rhs`` in glidectl does). Runs stop independently on reaching ``t_final``, on divergence (non-finite
state, ``|x|`` above ``bound`` or a user ``diverged(X)`` mask), on step-size underflow or on ``max_steps``; a
failing run never stalls the others.

This is the stiff counterpart of :func:`glidectl.sim.simulate_many`, whose single stacked ``solve_ivp`` shares
one step size among all runs.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import checks
from .derivatives import complex_step
from .errors import ArgumentError, ModelError, SolverError

__all__ = [
    "DIVERGED",
    "FINISHED",
    "MAX_STEPS",
    "STEP_UNDERFLOW",
    "TIME_LIMIT",
    "BatchResult",
    "batch_jacobian",
    "integrate_batch",
]

FINISHED = 0
DIVERGED = 1
STEP_UNDERFLOW = 2
MAX_STEPS = 3
TIME_LIMIT = 4
STATUS_NAMES = {FINISHED: "finished", DIVERGED: "diverged", STEP_UNDERFLOW: "step-size underflow",
                MAX_STEPS: "max_steps reached", TIME_LIMIT: "stopped by time_limit"}

# Shampine (1982) parameter set of the 4-stage Rosenbrock method (Numerical Recipes 2nd ed., routine stiff).
_GAM = 1.0 / 2.0
_A21 = 2.0
_A31, _A32 = 48.0 / 25.0, 6.0 / 25.0
_C21 = -8.0
_C31, _C32 = 372.0 / 25.0, 12.0 / 5.0
_C41, _C42, _C43 = -112.0 / 125.0, -54.0 / 125.0, -2.0 / 5.0
_B = (19.0 / 9.0, 1.0 / 2.0, 25.0 / 108.0, 125.0 / 108.0)
_E = (17.0 / 54.0, 7.0 / 36.0, 0.0, 125.0 / 108.0)
_ORDER_EST = 3  # order of the embedded solution: error ~ h^4


@dataclass(frozen=True)
class BatchResult:
    """Outcome of :func:`integrate_batch` (immutable).

    Attributes
    ----------
    t_final : float
        Requested final time.
    t : ndarray, shape (N,)
        Time reached by each run (``t_final`` for finished runs, the time of failure otherwise).
    x_final : ndarray, shape (N, n)
        State of each run at ``t`` (the last accepted state for failed runs).
    t_eval : ndarray, shape (m,)
        Requested sample times (empty if none were asked for).
    samples : ndarray, shape (N, m, n)
        States at ``t_eval`` (steps are clipped to hit them exactly); NaN where a run stopped before the time.
    status : ndarray of int, shape (N,)
        :data:`FINISHED`, :data:`DIVERGED`, :data:`STEP_UNDERFLOW`, :data:`MAX_STEPS` or :data:`TIME_LIMIT` per
        run.
    n_steps, n_rejected : ndarray of int, shape (N,)
        Accepted and rejected steps per run.
    nfev : int
        Right-hand-side calls (each on a batch of rows).
    nrows : int
        Total number of states passed to the right-hand side (rows summed over all calls, Jacobians included).
    method : str
    rtol, atol : float or ndarray
    stopped_by : str
        What ended the call: ``"t_final"`` (every run ended by itself: finished, diverged, step-size underflow or
        its own ``max_steps``) or ``"time_limit"`` (the runs still going then have status :data:`TIME_LIMIT`).
    wall_time : float
        Seconds spent.
    """

    t_final: float
    t: np.ndarray = field(repr=False)
    x_final: np.ndarray = field(repr=False)
    t_eval: np.ndarray = field(repr=False)
    samples: np.ndarray = field(repr=False)
    status: np.ndarray = field(repr=False)
    n_steps: np.ndarray = field(repr=False)
    n_rejected: np.ndarray = field(repr=False)
    nfev: int
    nrows: int
    method: str
    rtol: Any
    atol: Any
    stopped_by: str = "t_final"
    wall_time: float = 0.0

    @property
    def finished(self) -> np.ndarray:
        """Boolean mask of runs that reached ``t_final``."""
        return self.status == FINISHED

    @property
    def diverged(self) -> np.ndarray:
        """Boolean mask of runs flagged as diverged."""
        return self.status == DIVERGED

    def converged_to(self, x_eq: Any, tol: float) -> np.ndarray:
        """Runs that reached ``t_final`` within ``tol`` (Euclidean) of ``x_eq``: the simulated region of
        attraction of an equilibrium.

        Parameters
        ----------
        x_eq : array_like, shape (n,)
            The equilibrium (finite).
        tol : float
            Distance (> 0, state units).

        Returns
        -------
        ndarray of bool, shape (N,)
            The runs that finished within ``tol`` of ``x_eq``.

        Raises
        ------
        ArgumentTypeError
            If ``x_eq`` or ``tol`` is not numeric.
        ArgumentError
            If ``x_eq`` does not have shape ``(n,)`` or is not finite, or ``tol`` is not a positive finite number.
        """
        x_eq = checks.array("x_eq", x_eq, shape=(self.x_final.shape[1],))
        tol = checks.positive("tol", tol)
        return self.finished & (np.linalg.norm(self.x_final - x_eq, axis=1) < tol)

    @property
    def all_finished(self) -> bool:
        """True if every run reached ``t_final`` (not convergence: see :meth:`converged_to`)."""
        return bool(np.all(self.status == FINISHED))

    def summary(self) -> str:
        """One line: counts per status, steps and right-hand-side work."""
        counts = ", ".join(f"{int(np.sum(self.status == k))} {name}" for k, name in STATUS_NAMES.items())
        return (f"{len(self.status)} runs to t = {self.t_final:g}: {counts}; steps median "
                f"{np.median(self.n_steps):.0f} (max {int(self.n_steps.max(initial=0))}), {self.nfev} rhs calls "
                f"on {self.nrows} rows ({self.method})")


def _call(f: Callable[[np.ndarray], Any], X: np.ndarray, n: int, dtype: Any = float) -> np.ndarray:
    D = np.asarray(f(X))
    if D.shape != X.shape:
        raise ModelError(f"the right-hand side returned shape {D.shape} for a batch of shape {X.shape}; it must "
                         f"accept (M, {n}) states and return (M, {n}) derivatives")
    return D.astype(dtype, copy=False)


def batch_jacobian(f: Callable[[np.ndarray], Any], X: np.ndarray, F: np.ndarray | None = None, *,
                   method: str = "complex", columns: int | None = None) -> np.ndarray:
    """Jacobians ``df/dx`` at each row of ``X`` with one batched right-hand-side call.

    Parameters
    ----------
    f : callable
        ``(M, n) -> (M, n)``, batch-capable.
    X : ndarray, shape (N, n)
    F : ndarray, optional
        ``f(X)`` (unused by the complex step and central differences; accepted for a uniform signature).
    method : {"complex", "central"}
        ``"complex"``: complex step ``Im f(x + i h e_j) / h`` with ``h = 1e-30`` (exact to rounding; needs a
        complex-safe ``f``). ``"central"``: central differences with relative steps ``~ eps^(1/3)`` (``2 n N``
        rows).
    columns : int, optional
        Differentiate with respect to the first ``columns`` states only; the other columns of the Jacobian are
        zero (states that do not enter ``f``, such as running integrals of an input). Default: all ``n``.

    Returns
    -------
    ndarray, shape (N, n, n)

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable or ``X`` is not a real array.
    ArgumentError
        If ``X`` is not a finite (N, n) array, ``method`` is unknown or ``columns`` is not in ``1..n``.
    ModelError
        If ``f`` returns the wrong shape, or drops the imaginary part of complex states (use ``"central"``).
    """
    checks.function("f", f)
    X = checks.array("X", X, shape=(None, None), min_size=1)
    checks.choice("method", method, ("complex", "central"))
    N, n = X.shape
    c = n if columns is None else checks.integer("columns", columns, lo=1, hi=n)
    eye = np.eye(n)[:c]
    if method == "complex":
        h = 1e-30

        def rows(Z: np.ndarray) -> np.ndarray:        # Z (j, N, n): x_k + i h e_j, direction-major
            Z = Z.reshape(c * N, n)
            D = np.asarray(f(Z))
            if D.shape != Z.shape:
                raise ModelError(f"the right-hand side returned shape {D.shape} for a batch of shape {Z.shape}")
            return D

        cols = complex_step(rows, X[None, :, :], eye[:, None, :], h, name="the right-hand side",
                            advice="use jacobian='central' for right-hand sides that are not complex-safe"
                            ).reshape(c, N, n)        # (j, N, i) = d f_i / d x_j
    elif method == "central":
        step = np.cbrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(X[:, :c]))   # (N, c)
        dX = step.T[:, :, None] * eye[:, None, :]                                # (j, N, n)
        Z = np.concatenate([(X[None] + dX).reshape(c * N, n), (X[None] - dX).reshape(c * N, n)])
        D = _call(f, Z, n).reshape(2, c, N, n)
        cols = (D[0] - D[1]) / (2.0 * step.T[:, :, None])
    J = np.zeros((N, n, n))
    J[:, :, :c] = np.transpose(cols, (1, 2, 0))       # (N, i, j)
    return J


def _check_tol(tol: Any, name: str, n: int) -> np.ndarray:
    if isinstance(tol, np.ndarray | list | tuple):
        a = checks.array(name, tol, shape=(n,))
    else:
        a = np.array(checks.real(name, tol))
    if np.any(a < 0):
        raise ArgumentError(f"{name} must be >= 0 (a scalar or a length-{n} vector), got {tol!r}")
    return np.broadcast_to(a, (n,)).copy()


def _inverse(W: np.ndarray) -> np.ndarray:
    """Inverses of a stack of matrices; a singular one gives NaN (its step is rejected and retried smaller)."""
    if W.shape[-1] == 2:                # closed form (LAPACK's per-matrix overhead dominates at this size)
        a, b, c, d = W[:, 0, 0], W[:, 0, 1], W[:, 1, 0], W[:, 1, 1]
        det = a * d - b * c
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.where(det != 0, 1.0 / det, np.nan)
        return np.stack([np.stack([d * r, -b * r], axis=-1), np.stack([-c * r, a * r], axis=-1)], axis=-2)
    try:
        return np.linalg.inv(W)
    except np.linalg.LinAlgError:
        out = np.full_like(W, np.nan)
        for i in range(W.shape[0]):
            try:
                out[i] = np.linalg.inv(W[i])
            except np.linalg.LinAlgError:
                pass
        return out


def integrate_batch(f: Callable[[np.ndarray], Any], X0: Any, t_final: float, *, t0: float = 0.0,
                    t_eval: Any = None, rtol: Any = 1e-6, atol: Any = 1e-9, h0: float | None = None,
                    h_max: float = np.inf, h_min_rel: float = 1e-12, max_steps: int = 100_000,
                    jacobian: str | Callable[[np.ndarray], Any] = "complex",
                    diverged: Callable[[np.ndarray], Any] | None = None, bound: float = np.inf,
                    time_limit: float | None = None, on_budget: str = "raise") -> BatchResult:
    """Integrate ``x' = f(x)`` from each row of ``X0`` over ``[t0, t_final]`` (vectorized, stiff-aware).

    Every run has its own adaptive step size (4th-order Rosenbrock method, embedded 3rd-order error estimate,
    RMS norm of ``err / (atol + rtol max(|x|, |x_new|))`` per run); all active runs are advanced together, one
    attempted step each per iteration.

    Parameters
    ----------
    f : callable
        Autonomous, batch-capable right-hand side ``(M, n) -> (M, n)``; with ``jacobian="complex"`` it must also
        accept complex states (the glidectl models do).
    X0 : array_like, shape (N, n)
        Initial states (one row may be given as shape ``(n,)``); a row with NaN or inf is flagged
        :data:`DIVERGED` at ``t0``.
    t_final : float
        Final time (``> t0``, finite).
    t0 : float, optional
        Initial time (the system is autonomous; only the time axis shifts).
    t_eval : array_like, optional
        Increasing sample times in ``(t0, t_final]``; states there are returned in ``samples``.
    rtol, atol : float or array_like of length n
        Relative and absolute tolerances (``rtol >= 1e-12``).
    h0 : float, optional
        Initial step (default: per-run estimate ``0.01 |x| / |f(x)|`` in the error norm).
    h_max : float, optional
        Largest step.
    h_min_rel : float, optional
        A run whose step falls below ``h_min_rel * max(1, |t|, |t_final - t0|)`` stops with status
        :data:`STEP_UNDERFLOW`.
    max_steps : int, optional
        Attempted steps per run (accepted + rejected) before status :data:`MAX_STEPS` (a per-run outcome, like
        divergence: the call goes on with the other runs; at most ``max_steps`` iterations in all).
    jacobian : {"complex", "central"} or callable
        How the ``(N, n, n)`` Jacobians are formed: see :func:`batch_jacobian`, or a callable
        ``(M, n) -> (M, n, n)``.
    diverged : callable, optional
        ``(M, n) -> bool (M,)``; runs for which it is True (checked at ``X0`` and after every accepted step) stop
        with status :data:`DIVERGED`.
    bound : float, optional
        Runs with ``max |x_i| > bound`` are flagged :data:`DIVERGED` (default: no bound; non-finite states and
        derivatives are always flagged).
    time_limit : float, optional
        Wall-time budget of the whole call (s), checked every iteration; default none.
    on_budget : {"raise", "stop"}
        What hitting ``time_limit`` does: raise :class:`~glidectl.BudgetError` (default), or return with the runs
        still going marked :data:`TIME_LIMIT` (at the time and state they reached) and ``stopped_by="time_limit"``.

    Returns
    -------
    BatchResult

    Raises
    ------
    ArgumentTypeError
        If ``f``, ``jacobian`` or ``diverged`` is not callable (or a known method name), or a number or array has
        the wrong type.
    ArgumentError
        For a bad ``X0`` (shape, empty), time span, tolerances, step options, ``t_eval`` (unsorted or outside
        ``(t0, t_final]``) or budget.
    ModelError
        For a right-hand side, Jacobian or ``diverged`` mask with the wrong output shape.
    BudgetError
        If ``time_limit`` is hit (unless ``on_budget="stop"``).
    SolverError
        If a run is left without a status (an internal consistency check).
    """
    checks.function("f", f)
    X0 = checks.array("X0", X0, min_size=1, finite=False)   # non-finite rows are flagged DIVERGED (documented)
    if X0.ndim == 1:
        X0 = X0[None, :]
    if X0.ndim != 2 or X0.shape[1] == 0:
        raise ArgumentError(f"X0 must have shape (N, n) (one initial state per row), got {np.shape(X0)}")
    X0 = X0.copy()
    N, n = X0.shape
    t0 = checks.real("t0", t0)
    t_final = checks.real("t_final", t_final)
    if not t_final > t0:
        raise ArgumentError(f"need t0 < t_final, got t0 = {t0!r}, t_final = {t_final!r}")
    rt, at = _check_tol(rtol, "rtol", n), _check_tol(atol, "atol", n)
    if np.any(rt < 1e-12) or np.any(rt + at == 0):
        raise ArgumentError(f"rtol must be >= 1e-12 (got {rtol!r}) and rtol + atol > 0 in every component")
    max_steps = checks.integer("max_steps", max_steps, lo=1)
    h_max = checks.positive("h_max", h_max, allow_inf=True)
    h0 = None if h0 is None else checks.positive("h0", h0)
    h_min_rel = checks.positive("h_min_rel", h_min_rel)
    bound = checks.positive("bound", bound, allow_inf=True)
    if not callable(jacobian):
        checks.choice("jacobian", jacobian, ("complex", "central"))
    if diverged is not None:
        checks.function("diverged", diverged)
    deadline = checks.Deadline(time_limit, f"integrate_batch ({N} runs)")
    checks.choice("on_budget", on_budget, ("raise", "stop"))
    te = np.empty(0) if t_eval is None else np.atleast_1d(checks.array("t_eval", t_eval))
    if te.ndim != 1 or np.any(np.diff(te) <= 0) or (te.size and (te[0] <= t0 or te[-1] > t_final)):
        raise ArgumentError(f"t_eval must be strictly increasing and inside (t0, t_final] = ({t0:g}, {t_final:g}]")
    targets = np.append(te, t_final) if (te.size == 0 or te[-1] < t_final) else te

    def jac(X: np.ndarray) -> np.ndarray:
        if callable(jacobian):
            J = np.asarray(jacobian(X), dtype=float)
            if J.shape != (X.shape[0], n, n):
                raise ModelError(f"the Jacobian callable returned shape {J.shape}, expected {(X.shape[0], n, n)}")
            return J
        return batch_jacobian(f, X, method=jacobian)

    def flag_diverged(X: np.ndarray, F: np.ndarray | None) -> np.ndarray:
        bad = ~np.all(np.isfinite(X), axis=1) | (np.max(np.abs(X), axis=1) > bound)
        if F is not None:
            bad |= ~np.all(np.isfinite(F), axis=1)
        if diverged is not None:
            mask = np.asarray(diverged(X))
            if mask.size != X.shape[0]:
                raise ModelError(f"diverged returned {mask.size} values for {X.shape[0]} states; it must return one "
                                 "bool per row")
            bad |= mask.astype(bool).reshape(X.shape[0])
        return bad

    span = t_final - t0
    t = np.full(N, float(t0))
    X = X0.copy()
    status = np.full(N, -1, dtype=np.int8)          # -1: still running
    n_steps = np.zeros(N, dtype=np.int64)
    n_rej = np.zeros(N, dtype=np.int64)
    samples = np.full((N, te.size, n), np.nan)
    k_target = np.zeros(N, dtype=np.int64)
    nfev = nrows = 0
    stopped_by = "t_final"

    with np.errstate(all="ignore"):
        F = _call(f, X, n)
        nfev += 1
        nrows += N
        bad0 = flag_diverged(X, F)
        status[bad0] = DIVERGED
        if h0 is None:
            sc = at + rt * np.abs(X)
            d0 = np.sqrt(np.mean((X / sc) ** 2, axis=1))
            d1 = np.sqrt(np.mean((F / sc) ** 2, axis=1))
            h = np.where((d0 > 1e-5) & (d1 > 1e-5), 0.01 * d0 / np.where(d1 > 0, d1, 1.0), 1e-6 * span)
            h = np.clip(h, 1e-10 * span, 0.1 * span)
        else:
            h = np.full(N, float(h0))
        h = np.minimum(h, h_max)

        act = np.flatnonzero(status < 0)
        while act.size:
            Xa, Fa, ta, ha = X[act], F[act], t[act], h[act]
            t_stop = targets[k_target[act]]
            hit = ta + ha >= t_stop - 1e-12 * span
            ha = np.where(hit, t_stop - ta, ha)
            m = act.size
            J = jac(Xa)
            nfev += 1
            nrows += 0 if callable(jacobian) else (n if jacobian == "complex" else 2 * n) * m
            W = np.eye(n)[None] / (_GAM * ha)[:, None, None] - J
            Winv = _inverse(W)
            ih = (1.0 / ha)[:, None]

            def solve(R: np.ndarray, Winv: np.ndarray = Winv) -> np.ndarray:
                return np.einsum("mij,mj->mi", Winv, R)

            g1 = solve(Fa)
            F2 = _call(f, Xa + _A21 * g1, n)
            g2 = solve(F2 + _C21 * g1 * ih)
            F3 = _call(f, Xa + _A31 * g1 + _A32 * g2, n)
            g3 = solve(F3 + (_C31 * g1 + _C32 * g2) * ih)
            g4 = solve(F3 + (_C41 * g1 + _C42 * g2 + _C43 * g3) * ih)
            nfev += 2
            nrows += 2 * m
            Xn = Xa + _B[0] * g1 + _B[1] * g2 + _B[2] * g3 + _B[3] * g4
            err = _E[0] * g1 + _E[1] * g2 + _E[2] * g3 + _E[3] * g4
            sc = at + rt * np.maximum(np.abs(Xa), np.abs(Xn))
            en = np.sqrt(np.mean((err / sc) ** 2, axis=1))
            ok = np.isfinite(en) & (en <= 1.0)
            fac = np.where(np.isfinite(en), 0.9 * np.maximum(en, 1e-10) ** (-1.0 / (_ORDER_EST + 1)), 0.1)
            fac = np.clip(fac, 0.1, np.where(ok, 5.0, 0.9))
            h_new = np.minimum(ha * fac, h_max)

            idx_ok, idx_rej = act[ok], act[~ok]
            n_rej[idx_rej] += 1
            h[idx_rej] = h_new[~ok]
            if idx_ok.size:
                Xok = Xn[ok]
                Fok = _call(f, Xok, n)
                nfev += 1
                nrows += Xok.shape[0]
                X[idx_ok], F[idx_ok] = Xok, Fok
                t_ok = np.where(hit[ok], t_stop[ok], ta[ok] + ha[ok])
                t[idx_ok] = t_ok
                n_steps[idx_ok] += 1
                # keep the controller's step across a step clipped to hit a target
                h[idx_ok] = np.where(hit[ok], np.maximum(h_new[ok], h[idx_ok]), h_new[ok])
                status[idx_ok[flag_diverged(Xok, Fok)]] = DIVERGED
                hit_idx = idx_ok[hit[ok] & (status[idx_ok] < 0)]
                if hit_idx.size:
                    k = k_target[hit_idx]
                    is_sample = k < te.size
                    samples[hit_idx[is_sample], k[is_sample]] = X[hit_idx[is_sample]]
                    done = k == targets.size - 1
                    status[hit_idx[done]] = FINISHED
                    k_target[hit_idx[~done]] += 1
            still = act[status[act] < 0]
            h_min = h_min_rel * np.maximum(1.0, np.maximum(np.abs(t[still]), span))
            status[still[h[still] < h_min]] = STEP_UNDERFLOW
            status[still[(n_steps[still] + n_rej[still] >= max_steps) & (status[still] < 0)]] = MAX_STEPS
            act = np.flatnonzero(status < 0)
            if act.size and deadline.limit is not None and deadline.elapsed > deadline.limit:
                if on_budget == "raise":
                    deadline.check(f"{act.size} of {N} runs still going, the slowest at t = {np.min(t[act]):.6g}; "
                                   "pass on_budget='stop' for the runs finished so far")
                status[act] = TIME_LIMIT
                stopped_by = "time_limit"
                act = act[:0]

    if np.any(status < 0):  # pragma: no cover - the loop only exits when every run has a status
        raise SolverError("internal error: integrate_batch left runs without a status")
    return BatchResult(float(t_final), t, X, te, samples, status.astype(np.int64), n_steps, n_rej, nfev, nrows,
                       "Rosenbrock4(3) Shampine, per-run adaptive", rtol, atol, stopped_by, deadline.elapsed)
