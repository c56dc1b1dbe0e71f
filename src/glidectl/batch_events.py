"""Many non-autonomous runs integrated together, each with its own step size, its own clock and its own terminal
event: :func:`integrate_batch_events`, :class:`EventBatchResult`.

The method is the explicit Dormand-Prince 5(4) pair with its 4th-order continuous extension, the coefficients
and the step-size rule of :class:`scipy.integrate.RK45`, applied row by row: every run has its own step size, error
norm (RMS over its own components of ``err / (atol + rtol max(|x|, |x_new|))``) and acceptance, but one call of
the right-hand side advances all of them, so ``N`` runs cost about as many Python calls as one. A run ends when its
event function crosses from positive to non-positive (located on the continuous extension by bisection), when it
reaches ``t_final``, or when it fails (a non-finite state, a step-size underflow, ``max_steps``). Samples on a
uniform grid of each run's own time are read from the continuous extension.

This is the non-stiff, event-aware counterpart of :func:`glidectl.batch.integrate_batch` (autonomous, stiff,
Rosenbrock). It serves the batched dive cycles (:func:`glidectl.controllers.dive_cycle.dive_cycles_batched`),
whose legs are autonomous in the leg's own time and end at a depth that each sample reaches at its own moment.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import RK45

from . import checks
from .batch import DIVERGED, FINISHED, MAX_STEPS, STATUS_NAMES, STEP_UNDERFLOW
from .errors import ArgumentError

__all__ = ["EVENT", "EventBatchResult", "integrate_batch_events"]

#: Status of a run that ended at its event.
EVENT = 5

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0     # scipy's RK45 step-size rule
_EXPONENT = -1.0 / (RK45.error_estimator_order + 1)
_BISECTIONS = 48                                        # event located to 2^-48 of a step


@dataclass(frozen=True)
class EventBatchResult:
    """Outcome of :func:`integrate_batch_events` (immutable).

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time each run ended: its event time, ``t_final``, or the time of failure.
    x : ndarray, shape (N, n)
        State of each run at ``t``.
    status : ndarray of int, shape (N,)
        :data:`EVENT`, :data:`~glidectl.batch.FINISHED` (``t_final`` reached without the event) or a failure
        (:data:`~glidectl.batch.DIVERGED`, :data:`~glidectl.batch.STEP_UNDERFLOW`,
        :data:`~glidectl.batch.MAX_STEPS`).
    t_step : float
        Spacing of the sample grid ``t0 + k t_step`` (0: no samples).
    samples : ndarray, shape (N, m, n)
        States on the grid, NaN after a run's end (``m`` covers the longest run).
    n_samples : ndarray of int, shape (N,)
        Grid points at or before each run's end (valid entries of ``samples``).
    n_steps, n_rejected : ndarray of int, shape (N,)
    nfev : int
        Calls of the right-hand side (each on all ``N`` rows).
    method : str
    """

    t: np.ndarray = field(repr=False)
    x: np.ndarray = field(repr=False)
    status: np.ndarray = field(repr=False)
    t_step: float
    samples: np.ndarray = field(repr=False)
    n_samples: np.ndarray = field(repr=False)
    n_steps: np.ndarray = field(repr=False)
    n_rejected: np.ndarray = field(repr=False)
    nfev: int
    method: str = "Dormand-Prince 5(4), per-run adaptive"

    @property
    def stopped(self) -> np.ndarray:
        """Runs that ended at their event (bool, shape (N,))."""
        return self.status == EVENT

    def reason(self, i: int) -> str:
        """Why run ``i`` ended, in words."""
        return "event" if self.status[i] == EVENT else STATUS_NAMES.get(int(self.status[i]), "unknown")


def _initial_step(f: Callable, t: np.ndarray, X: np.ndarray, F: np.ndarray, rtol: float, atol: float,
                  t_span: float) -> tuple[np.ndarray, int]:
    """Per-row first step (Hairer, Norsett and Wanner, II.4; scipy's ``select_initial_step``)."""
    scale = atol + np.abs(X) * rtol
    d0 = np.sqrt(np.mean((X / scale) ** 2, axis=1))
    d1 = np.sqrt(np.mean((F / scale) ** 2, axis=1))
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.where(d1 > 0, d1, 1.0))
    h0 = np.minimum(h0, t_span)
    F1 = f(t + h0, X + h0[:, None] * F)
    d2 = np.sqrt(np.mean(((F1 - F) / scale) ** 2, axis=1)) / h0
    big = np.maximum(d1, d2)
    h1 = np.where(big <= 1e-15, np.maximum(1e-6, h0 * 1e-3),
                  (0.01 / np.where(big > 0, big, 1.0)) ** (1.0 / (RK45.error_estimator_order + 1)))
    return np.minimum(np.minimum(100 * h0, h1), t_span), 1


def _dense(X: np.ndarray, h: np.ndarray, Q: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The continuous extension at the fraction ``theta`` of each row's step (rows of ``X``, ``h``, ``Q``)."""
    p = np.cumprod(np.repeat(theta[:, None], Q.shape[2], axis=1), axis=1)        # theta, theta^2, ...
    return X + h[:, None] * np.einsum("rnk,rk->rn", Q, p)


def _locate(event: Callable, rows: np.ndarray, t: np.ndarray, X: np.ndarray, h: np.ndarray, Q: np.ndarray,
            T_all: np.ndarray, X_all: np.ndarray) -> np.ndarray:
    """Fraction of the step at which the event of each run in ``rows`` first reaches zero (bisection on the
    continuous extension; the event is evaluated on all rows, the others held at ``T_all``, ``X_all``)."""
    lo, hi = np.zeros(rows.size), np.ones(rows.size)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        Tq, Xq = T_all.copy(), X_all.copy()
        Tq[rows], Xq[rows] = t + mid * h, _dense(X, h, Q, mid)
        g = np.asarray(event(Tq, Xq), dtype=float)[rows]
        lo, hi = np.where(g > 0, mid, lo), np.where(g > 0, hi, mid)
    return hi


class _Grid:
    """The growing ``(N, m, n)`` array of samples on ``t0 + k dt``."""

    def __init__(self, N: int, n: int, t0: float, dt: float, X0: np.ndarray) -> None:
        self.t0, self.dt = t0, dt
        self.data = np.full((N, 64 if dt > 0 else 0, n), np.nan)
        if dt > 0:
            self.data[:, 0] = X0

    def fill(self, rows: np.ndarray, t: np.ndarray, t_end: np.ndarray, X: np.ndarray, h: np.ndarray,
             Q: np.ndarray) -> None:
        """Write the grid points in ``(t, t_end]`` of each row from its continuous extension."""
        if self.dt <= 0 or rows.size == 0:
            return
        k_lo = np.floor((t - self.t0) / self.dt).astype(int) + 1
        k_hi = np.floor((t_end - self.t0) / self.dt * (1 + 1e-14)).astype(int)
        count = k_hi - k_lo + 1
        if count.max(initial=0) <= 0:
            return
        need = int(k_hi.max()) + 1
        if need > self.data.shape[1]:
            grow = np.full((self.data.shape[0], max(need, 2 * self.data.shape[1]) - self.data.shape[1],
                            self.data.shape[2]), np.nan)
            self.data = np.concatenate([self.data, grow], axis=1)
        r, j = np.nonzero(np.arange(count.max())[None, :] < count[:, None])
        k = k_lo[r] + j
        theta = np.clip((self.t0 + k * self.dt - t[r]) / h[r], 0.0, 1.0)
        self.data[rows[r], k] = _dense(X[r], h[r], Q[r], theta)


def integrate_batch_events(f: Callable[[np.ndarray, np.ndarray], Any], X0: Any, t_final: float, *,
                           event: Callable[[np.ndarray, np.ndarray], Any] | None = None, t_step: float = 0.0,
                           rtol: float = 1e-6, atol: float = 1e-9, h_max: float = np.inf,
                           max_steps: int = 100_000) -> EventBatchResult:
    """Integrate ``x_i' = f(t_i, x_i)`` for every row ``i`` of ``X0`` from ``t = 0``, each run on its own clock
    and step size, until its event, ``t_final`` or a failure (module docstring).

    Parameters
    ----------
    f : callable
        ``f(t, X) -> X'`` with ``t`` of shape ``(N,)`` (each run's own time) and ``X`` of shape ``(N, n)``. It is
        always called on all ``N`` rows, in their order (a run that has ended, or whose step is being retried,
        carries its current time and state), so a right-hand side with per-row parameters (a stacked vehicle,
        :meth:`glidectl.VehicleSample.stacked`) keeps its rows aligned.
    X0 : array_like, shape (N, n)
    t_final : float
        Longest time (> 0).
    event : callable, optional
        ``event(t, X) -> (N,)``; a run ends where its value first crosses from positive to zero or below. A run
        whose event is not positive at ``t = 0`` ends there.
    t_step : float
        Spacing of the sample grid (0: no samples).
    rtol, atol : float
        Tolerances of each run's error norm.
    h_max : float
        Largest step.
    max_steps : int
        Steps (accepted and rejected) allowed per run.

    Returns
    -------
    EventBatchResult

    Raises
    ------
    ArgumentError
        If the arguments are out of range or ``f`` returns the wrong shape.
    """
    X = np.array(checks.array("X0", X0, ndim=2, finite=True), dtype=float)    # a copy: rows advance in place
    N, n = X.shape
    t_final = checks.positive("t_final", t_final)
    t_step = checks.nonnegative("t_step", t_step)
    rtol = checks.real("rtol", rtol, lo=1e-13)
    atol = checks.positive("atol", atol)
    max_steps = checks.integer("max_steps", max_steps, lo=1)
    A, B, C, E, P = RK45.A, RK45.B, RK45.C, RK45.E, RK45.P
    nfev = 0

    def rhs(T: np.ndarray, Z: np.ndarray) -> np.ndarray:
        nonlocal nfev
        nfev += 1
        out = np.asarray(f(T, Z), dtype=float)
        if out.shape != (N, n):
            raise ArgumentError(f"f(t, X) returned shape {out.shape}, expected {(N, n)}")
        return out

    t = np.zeros(N)
    F = rhs(t, X)
    h, _ = _initial_step(rhs, t, X, F, rtol, atol, t_final)
    h = np.minimum(h, h_max)
    status = np.full(N, -1)
    status[~np.all(np.isfinite(F), axis=1)] = DIVERGED
    g = np.asarray(event(t, X), dtype=float) if event is not None else np.ones(N)
    status[(g <= 0) & (status < 0)] = EVENT
    steps, rejected = np.zeros(N, dtype=int), np.zeros(N, dtype=int)
    was_rejected = np.zeros(N, dtype=bool)
    grid = _Grid(N, n, 0.0, t_step, X)
    K = np.empty((RK45.n_stages + 1, N, n))
    while np.any(status < 0):
        act = status < 0
        hs = np.where(act, np.minimum(h, t_final - t), 0.0)
        K[0] = F
        for s in range(1, RK45.n_stages):
            dX = np.einsum("j,jrn->rn", A[s, :s], K[:s]) * hs[:, None]
            K[s] = rhs(t + C[s] * hs, X + dX)
        X_new = X + hs[:, None] * np.einsum("j,jrn->rn", B, K[:-1])
        F_new = rhs(t + hs, X_new)
        K[-1] = F_new
        err = hs[:, None] * np.einsum("j,jrn->rn", E, K)
        scale = atol + np.maximum(np.abs(X), np.abs(X_new)) * rtol
        with np.errstate(invalid="ignore", over="ignore"):
            en = np.sqrt(np.mean((err / scale) ** 2, axis=1))
        finite = np.isfinite(en) & np.all(np.isfinite(X_new), axis=1)
        ok = act & finite & (en < 1.0)
        bad = act & ~ok
        with np.errstate(divide="ignore", over="ignore"):
            grow = np.where(en == 0, _MAX_FACTOR, np.minimum(_MAX_FACTOR, _SAFETY * en ** _EXPONENT))
            shrink = np.where(finite, np.maximum(_MIN_FACTOR, _SAFETY * en ** _EXPONENT), _MIN_FACTOR)
        grow = np.where(was_rejected, np.minimum(1.0, grow), grow)
        rows = np.flatnonzero(ok)
        if rows.size:
            Q = np.einsum("jrn,jk->rnk", K[:, rows], P)
            t_end = t[rows] + hs[rows]
            stop = np.zeros(rows.size, dtype=bool)
            if event is not None:
                T_try, X_try = t.copy(), X.copy()
                T_try[rows], X_try[rows] = t_end, X_new[rows]
                g_new = np.asarray(event(T_try, X_try), dtype=float)[rows]
                stop = g_new <= 0
                if stop.any():
                    sr = rows[stop]
                    theta = _locate(event, sr, t[sr], X[sr], hs[sr], Q[stop], t, X)
                    t_end[stop] = t[sr] + theta * hs[sr]
                    X_new[sr] = _dense(X[sr], hs[sr], Q[stop], theta)
                    status[sr] = EVENT
            grid.fill(rows, t[rows], t_end, X[rows], hs[rows], Q)
            t[rows], X[rows], F[rows] = t_end, X_new[rows], F_new[rows]
            h[rows] = np.minimum(hs[rows] * grow[rows], h_max)
            steps[rows] += 1
            status[rows[~stop & (t[rows] >= t_final * (1 - 1e-14))]] = FINISHED
        h[bad] = hs[bad] * shrink[bad]
        rejected[bad] += 1
        was_rejected = bad
        live = status < 0
        status[live & (h < 1e-12 * np.maximum(1.0, t))] = STEP_UNDERFLOW
        status[(status < 0) & (steps + rejected >= max_steps)] = MAX_STEPS
        status[(status < 0) & ~np.all(np.isfinite(X), axis=1)] = DIVERGED
    n_samples = (np.minimum(np.floor(t / t_step * (1 + 1e-14)).astype(int) + 1, grid.data.shape[1])
                 if t_step > 0 else np.zeros(N, dtype=int))
    m = int(n_samples.max(initial=0))
    return EventBatchResult(t, X, status, t_step, grid.data[:, :m], n_samples, steps, rejected, nfev)
