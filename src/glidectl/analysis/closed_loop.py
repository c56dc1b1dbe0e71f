"""Closed-loop comparison tools: an LQR state feedback on the exact linearization of any glidectl model at an
equilibrium (with input saturation), and a batch-simulation comparison of controllers over a box of initial
conditions (simulated region of attraction, peak and integrated actuator effort, settling time).

Every model here is a glidectl model (``rhs(x, u)``, ``state_names``, ``input_names``, batch-capable); the
linearization is the complex-step Jacobian of that one right-hand side.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np
from scipy import sparse
from scipy.integrate import solve_ivp

from ..errors import ModelError, SolverError
from .jacobian import jacobians

__all__ = ["BatchComparison", "ControllerRecord", "StateFeedback", "compare_controllers", "lqr_state_feedback"]


@dataclass(frozen=True)
class StateFeedback:
    """``u = sat(u_e - K (x - x_e))``: a linear state feedback about an equilibrium, saturated elementwise to
    ``[u_min, u_max]``.

    Attributes
    ----------
    x_e, u_e : ndarray
        Equilibrium state and input (the model's units).
    K : ndarray, shape (m, n)
        Gain.
    u_min, u_max : ndarray, shape (m,)
        Saturation (``-inf``/``inf`` for none).
    closed_loop_poles : ndarray
        Eigenvalues of ``A - B K`` of the unsaturated linearization (1/s).
    Q, R : ndarray
        LQR weights.
    """

    x_e: np.ndarray = field(repr=False)
    u_e: np.ndarray = field(repr=False)
    K: np.ndarray = field(repr=False)
    u_min: np.ndarray = field(repr=False)
    u_max: np.ndarray = field(repr=False)
    closed_loop_poles: np.ndarray
    Q: np.ndarray = field(repr=False)
    R: np.ndarray = field(repr=False)
    name: str = "LQR"

    def __call__(self, t: float, x: Any) -> np.ndarray:
        x = np.asarray(x)
        u = self.u_e - (x - self.x_e) @ self.K.T
        return np.clip(u, self.u_min, self.u_max)


def lqr_state_feedback(model: Any, x_e: Any, u_e: Any, *, Q: Any = None, R: Any = None,
                       u_min: Sequence[float] | None = None, u_max: Sequence[float] | None = None,
                       name: str = "LQR") -> StateFeedback:
    """LQR (python-control ``lqr``) on the complex-step linearization of ``model`` at ``(x_e, u_e)``.

    Parameters
    ----------
    model
        A glidectl model with inputs.
    x_e, u_e : array_like
        Equilibrium; ``model.rhs(x_e, u_e)`` must vanish (checked, relative 1e-8).
    Q, R : array_like, optional
        Weights (default identity); a 1-D array is a diagonal.
    u_min, u_max : sequence of float, optional
        Input saturation applied by the controller.
    name : str
        Label of the controller (for comparisons and reports).

    Returns
    -------
    StateFeedback
        The saturated law ``u = sat(u_e - K (x - x_e))`` (gain in input units per state unit), the closed-loop
        poles of the unsaturated linearization (1/s) and the weights used.

    Raises
    ------
    ModelError
        Not an equilibrium, bad shapes.
    SolverError
        The LQR problem has no stabilizing solution (python-control's message is included).
    """
    x_e, u_e = np.asarray(x_e, dtype=float), np.asarray(u_e, dtype=float)
    n, m = len(model.state_names), len(model.input_names)
    if x_e.shape != (n,) or u_e.shape != (m,) or m == 0:
        raise ModelError(f"need x_e of shape ({n},) and u_e of shape ({m},) with m > 0, got {x_e.shape}, {u_e.shape}")
    f0 = np.asarray(model.rhs(x_e, u_e), dtype=float)
    if np.max(np.abs(f0)) > 1e-8 * (1 + np.max(np.abs(x_e))):
        raise ModelError(f"(x_e, u_e) is not an equilibrium of {type(model).__name__}: "
                         f"|rhs| = {np.max(np.abs(f0)):.3g}")
    A, B = jacobians(model.rhs, x_e, u_e)
    Qm = np.eye(n) if Q is None else np.asarray(Q, dtype=float)
    Rm = np.eye(m) if R is None else np.asarray(R, dtype=float)
    Qm = np.diag(Qm) if Qm.ndim == 1 else Qm
    Rm = np.diag(Rm) if Rm.ndim == 1 else Rm
    try:
        K, _, poles = control.lqr(A, B, Qm, Rm)
    except Exception as exc:  # python-control raises several types
        raise SolverError(f"LQR failed for {type(model).__name__} at the equilibrium: {exc}") from exc
    lo = np.full(m, -np.inf) if u_min is None else np.asarray(u_min, dtype=float)
    hi = np.full(m, np.inf) if u_max is None else np.asarray(u_max, dtype=float)
    return StateFeedback(x_e, u_e, np.asarray(K), lo, hi, np.asarray(poles), Qm, Rm, name)


@dataclass(frozen=True)
class ControllerRecord:
    """Batch-simulation metrics of one controller over the initial conditions of a :class:`BatchComparison`.

    Attributes
    ----------
    name : str
    converged : ndarray of bool (N,)
        Final scaled error ``max_i |x_i - x_e,i| / scale_i <= tol`` and never frozen.
    peak_u : ndarray (N, m)
        ``max_t |u_j - u_e,j|`` per run (input units), sampled on the output grid.
    integrated_u : ndarray (N, m)
        ``int_0^T |u_j - u_e,j| dt`` per run (exact quadrature state).
    settling_time : ndarray (N,)
        First output time after which the scaled error stays below ``settle`` (s); ``inf`` if never.
    """

    name: str
    converged: np.ndarray = field(repr=False)
    peak_u: np.ndarray = field(repr=False)
    integrated_u: np.ndarray = field(repr=False)
    settling_time: np.ndarray = field(repr=False)

    @property
    def fraction(self) -> float:
        """Fraction of the initial conditions that converge (the simulated region of attraction in the box)."""
        return float(np.mean(self.converged))

    def as_dict(self, common: np.ndarray | None = None) -> dict[str, Any]:
        """Medians over the converged runs (or over ``common``, a mask of runs all controllers converged from), as a
        plain dict for tables and JSON."""
        sel = self.converged if common is None else common
        if not np.any(sel):
            return {"name": self.name, "fraction": self.fraction, "n": 0}
        return {"name": self.name, "fraction": self.fraction, "n": int(np.sum(sel)),
                "median_peak_u": np.median(self.peak_u[sel], axis=0).tolist(),
                "max_peak_u": np.max(self.peak_u[sel], axis=0).tolist(),
                "median_integrated_u": np.median(self.integrated_u[sel], axis=0).tolist(),
                "median_settling_time": float(np.median(self.settling_time[sel]))}

    def summary(self, common: np.ndarray | None = None) -> str:
        """One line of text: the converged fraction and the medians of :meth:`as_dict`."""
        d = self.as_dict(common)
        text = f"{self.name}: {100 * d['fraction']:.1f}% of the runs converge"
        if d["n"]:
            peak = ", ".join(f"{v:.3g}" for v in d["median_peak_u"])
            text += (f"; over {d['n']} runs median peak |u - u_e| ({peak}), median settling time "
                     f"{d['median_settling_time']:.3g} s")
        return text


@dataclass(frozen=True)
class BatchComparison:
    """Controllers compared from the same initial conditions (see :func:`compare_controllers`).

    Attributes
    ----------
    x0 : ndarray, shape (N, n)
        Initial states (model units).
    x_e : ndarray, shape (n,)
        The equilibrium regulated to (model units).
    scale : ndarray, shape (n,)
        Per-state scale of the error norm (model units).
    t_final : float
        Horizon (s).
    tol, settle : float
        Convergence and settling thresholds on the scaled error (nondimensional).
    records : Mapping[str, ControllerRecord]
        Metrics of each controller, by name.
    common : ndarray of bool, shape (N,)
        Runs from which every controller converged.
    state_names : tuple of str
        The model's state names (columns of ``x0``; empty for a comparison built without them).
    """

    x0: np.ndarray = field(repr=False)
    x_e: np.ndarray = field(repr=False)
    scale: np.ndarray = field(repr=False)
    t_final: float
    tol: float
    settle: float
    records: Mapping[str, ControllerRecord] = field(repr=False)
    state_names: tuple[str, ...] = ()

    @property
    def common(self) -> np.ndarray:
        """Runs from which every controller converged (effort comparisons use these)."""
        return np.logical_and.reduce([r.converged for r in self.records.values()])

    def plot(self, ax: Any = None, *, dims: Sequence[Any] = (0, 1)) -> Any:
        """Draw the initial states in the plane of two states, marked by outcome for each controller (the
        simulated regions of attraction), in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane (the initial box is projected on it).

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_batch_comparison`.
        """
        from ..plotting import plot_batch_comparison, style

        with style():
            return plot_batch_comparison(self, ax, dims=dims)


def compare_controllers(model: Any, controllers: Mapping[str, Callable[[float, Any], Any]], x0: Any, x_e: Any,
                        u_e: Any, t_final: float, *, scale: Any = None, tol: float = 0.02, settle: float = 0.05,
                        n_out: int = 401, method: str = "BDF", rtol: float = 1e-6, atol: float = 1e-9,
                        diverged: Callable[[np.ndarray], np.ndarray] | None = None) -> BatchComparison:
    """Simulate every controller from every initial state (one stacked, vectorized ODE per controller).

    Parameters
    ----------
    model
        glidectl model with inputs; ``rhs`` batch-capable.
    controllers : mapping name -> controller
        Time-invariant feedback ``controller(t, X)`` accepting a batch ``X`` of shape (N, n).
    x0 : array_like (N, n)
        Initial states.
    x_e, u_e : array_like
        The equilibrium all controllers regulate to (metrics are deviations from it).
    t_final : float
        Horizon (s).
    scale : array_like (n,), optional
        Per-state scale of the error norm (default ones).
    tol, settle : float
        Convergence (at ``t_final``) and settling thresholds on ``max_i |x_i - x_e,i| / scale_i``.
    n_out : int
        Number of evenly spaced output times on which peaks and settling are evaluated.
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp`; default ``"BDF"`` (with the block-diagonal Jacobian
        sparsity of the independent runs for ``"BDF"`` and ``"Radau"``).
    rtol, atol : float
        Integrator tolerances (relative, nondimensional; absolute, in state and integrated-input units).
    diverged : callable, optional
        ``X (N, n) -> bool (N,)``: runs that leave the model's domain (e.g. speed near zero) are frozen there and
        count as not converged.

    Returns
    -------
    BatchComparison
        One :class:`ControllerRecord` per controller (convergence mask, peak and integrated input deviation in
        input units and input units x s, settling times in s), with the settings used.

    Raises
    ------
    ModelError
        If ``t_final`` is not a positive finite number.
    SolverError
        If the batch integration of a controller fails.
    ValueError
        If ``x0`` is not two-dimensional, or the controller's output cannot be reshaped to ``(N, m)``.
    """
    X0 = np.asarray(x0, dtype=float)
    x_e, u_e = np.asarray(x_e, dtype=float), np.asarray(u_e, dtype=float)
    N, n = X0.shape
    m = u_e.size
    sc = np.ones(n) if scale is None else np.asarray(scale, dtype=float)
    if not (math.isfinite(t_final) and t_final > 0):
        raise ModelError(f"t_final must be positive, got {t_final!r}")
    te = np.linspace(0.0, t_final, n_out)
    # runs are independent: block-diagonal Jacobian, so the implicit methods difference N runs at once
    sparsity = sparse.block_diag([np.ones((n + m, n + m))] * N, format="csr")
    records = {}
    for name, ctrl in controllers.items():
        frozen = np.zeros(N, dtype=bool)

        def f(t: float, y: np.ndarray, ctrl: Callable[[float, Any], Any] = ctrl,
              frozen: np.ndarray = frozen) -> np.ndarray:
            Y = y.reshape(N, n + m)
            X = Y[:, :n]
            if diverged is not None:
                frozen |= np.asarray(diverged(X), dtype=bool)
            U = np.asarray(ctrl(t, X), dtype=float).reshape(N, m)
            d = np.empty_like(Y)
            with np.errstate(all="ignore"):
                d[:, :n] = np.asarray(model.rhs(X, U), dtype=float)
            d[:, n:] = np.abs(U - u_e)
            d[frozen] = 0.0
            d[~np.isfinite(d)] = 0.0
            return d.ravel()

        y0 = np.concatenate([X0, np.zeros((N, m))], axis=1).ravel()
        kw = {"jac_sparsity": sparsity} if method in ("BDF", "Radau") else {}
        sol = solve_ivp(f, (0.0, t_final), y0, method=method, t_eval=te, rtol=rtol, atol=atol, **kw)
        if not sol.success:
            raise SolverError(f"batch simulation of '{name}' failed at t = {sol.t[-1]:.4g} s: {sol.message}")
        Y = sol.y.reshape(N, n + m, -1)
        X = Y[:, :n, :]
        err = np.max(np.abs(X - x_e[None, :, None]) / sc[None, :, None], axis=1)  # (N, T)
        conv = (err[:, -1] <= tol) & ~frozen
        U = np.stack([np.asarray(ctrl(t, X[:, :, k]), dtype=float).reshape(N, m) for k, t in enumerate(sol.t)], -1)
        peak = np.max(np.abs(U - u_e[None, :, None]), axis=2)
        above = err > settle
        last = np.where(above.any(axis=1), above.shape[1] - 1 - np.argmax(above[:, ::-1], axis=1), -1)
        ts = np.where(last + 1 < sol.t.size, sol.t[np.minimum(last + 1, sol.t.size - 1)], np.inf)
        ts[~conv] = np.inf
        records[name] = ControllerRecord(name, conv, peak, Y[:, n:, -1], ts)
    return BatchComparison(X0, x_e, sc, float(t_final), tol, settle, records, tuple(model.state_names))
