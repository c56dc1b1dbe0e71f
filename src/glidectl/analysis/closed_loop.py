"""Closed-loop comparison tools: an LQR state feedback on the exact linearization of any glidectl model at an
equilibrium (with input saturation), and a batch-simulation comparison of controllers over a box of initial
conditions (simulated region of attraction, peak and integrated actuator effort, settling time).

Every model here is a glidectl model (``rhs(x, u)``, ``state_names``, ``input_names``, batch-capable); the
linearization is the complex-step Jacobian of that one right-hand side.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import control
import numpy as np
from scipy import sparse
from scipy.integrate import solve_ivp

from .. import checks
from ..batch import DIVERGED, FINISHED, batch_jacobian, integrate_batch
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, SolverError

#: integrators accepted by :func:`compare_controllers`: ``"batch"`` (:func:`glidectl.integrate_batch`, every run with
#: its own step size) or a method of :func:`scipy.integrate.solve_ivp` (one stacked ODE, one step size for all runs)
METHODS = ("batch", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: largest stacked ODE (runs x (states + inputs)) and largest output array (that times ``n_out``) of one comparison
MAX_STACKED_STATES = 1_000_000
MAX_OUTPUT_VALUES = 50_000_000
EQUILIBRIUM_RTOL = 1e-8  # |rhs(x_e, u_e)| relative to the size of the linear terms |A| |x_e| + |B| |u_e|


def _check_model(model: Any) -> tuple[int, int]:
    """``(n, m)`` of a glidectl model (``rhs``, ``state_names``, ``input_names``); ArgumentTypeError otherwise."""
    try:
        names, inputs = tuple(model.state_names), tuple(model.input_names)
    except (AttributeError, TypeError):
        names = inputs = None
    if names is None or not callable(getattr(model, "rhs", None)) or not all(
            isinstance(q, str) for q in (*names, *inputs)):
        raise ArgumentTypeError(f"model must be a glidectl model with rhs(x, u), state_names and input_names, got "
                                f"{type(model).__name__}")
    if not names:
        raise ArgumentError(f"model {type(model).__name__} has no states")
    return len(names), len(inputs)


def _weight(name: str, value: Any, k: int, *, definite: bool) -> np.ndarray:
    """An LQR weight: ``None`` (identity), a 1-D diagonal of length k or a symmetric (k, k) matrix, positive
    semidefinite (``definite=False``) or definite."""
    if value is None:
        return np.eye(k)
    W = checks.array(name, value)
    if W.ndim == 1 and W.shape == (k,):
        W = np.diag(W)
    if W.shape != (k, k):
        raise ArgumentError(f"{name} must be a diagonal of length {k} or a ({k}, {k}) matrix, got shape {W.shape}")
    if not np.allclose(W, W.T, rtol=1e-12, atol=0.0):
        raise ArgumentError(f"{name} must be symmetric")
    lam = np.linalg.eigvalsh(0.5 * (W + W.T))
    floor = 1e-12 * max(float(np.max(np.abs(lam))), np.finfo(float).tiny)
    if (definite and not lam[0] > 0) or lam[0] < -floor:
        raise ArgumentError(f"{name} must be positive {'definite' if definite else 'semidefinite'}, its smallest "
                            f"eigenvalue is {lam[0]:.3g}")
    return W


def _bound(name: str, value: Any, m: int, fill: float) -> np.ndarray:
    if value is None:
        return np.full(m, fill)
    b = checks.array(name, value, shape=(m,), finite=False)
    if np.any(np.isnan(b)):
        raise ArgumentError(f"{name} must not contain NaN (use -inf/inf for no bound), got {value!r}")
    return b

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
        """The saturated law at state(s) ``x`` (shape ``(n,)`` or a batch ``(N, n)``); ``t`` is unused.

        Parameters
        ----------
        t : float
            Time (s), unused (the law is time-invariant).
        x : array_like, shape (n,) or (N, n)
            State(s) in model units.

        Returns
        -------
        ndarray, shape (m,) or (N, m)
            ``sat(u_e - K (x - x_e))`` in input units.

        Raises
        ------
        ArgumentError
            If the last dimension of ``x`` is not ``n``.
        """
        x = np.asarray(x)
        if x.ndim == 0 or x.shape[-1] != self.x_e.size:
            raise ArgumentError(f"x must have {self.x_e.size} states in its last dimension, got shape {x.shape}")
        u = self.u_e - (x - self.x_e) @ self.K.T
        return np.clip(u, self.u_min, self.u_max)


def lqr_state_feedback(model: Any, x_e: Any, u_e: Any, *, Q: Any = None, R: Any = None,
                       u_min: Sequence[float] | None = None, u_max: Sequence[float] | None = None,
                       name: str = "LQR") -> StateFeedback:
    """LQR (python-control ``lqr``) on the complex-step linearization of ``model`` at ``(x_e, u_e)``.

    Parameters
    ----------
    model
        A glidectl model with inputs (``rhs(x, u)`` complex-safe, ``state_names``, ``input_names``).
    x_e, u_e : array_like
        Equilibrium, finite, shapes ``(n,)`` and ``(m,)``; ``model.rhs(x_e, u_e)`` must vanish relative to the size
        of the linear terms ``|A| |x_e| + |B| |u_e|`` (relative tolerance 1e-8).
    Q, R : array_like, optional
        Weights (default identity); a 1-D array is a diagonal. ``Q`` symmetric positive semidefinite, ``R``
        symmetric positive definite.
    u_min, u_max : sequence of float, optional
        Input saturation applied by the controller (``-inf``/``inf`` for none); ``u_min < u_max`` and ``u_e``
        within the bounds.
    name : str
        Label of the controller (for comparisons and reports).

    Returns
    -------
    StateFeedback
        The saturated law ``u = sat(u_e - K (x - x_e))`` (gain in input units per state unit), the closed-loop
        poles of the unsaturated linearization (1/s) and the weights used.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a glidectl model, an array is not real numbers or ``name`` is not a string.
    ArgumentError
        Bad shapes, non-finite values, weights that are not symmetric positive (semi)definite, bounds with
        ``u_min >= u_max`` or not containing ``u_e``, a model without inputs.
    ModelError
        ``(x_e, u_e)`` is not an equilibrium of the model, or the linearization there is not finite (or the model
        is not complex-safe).
    SolverError
        The LQR problem has no stabilizing solution (python-control's message is included).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> eq = gc.buoyancy_equilibrium(veh, 1.5)              # steady glide at 1.5 m/s, pump at rest
    >>> rate = veh.actuators["m0"].rate                     # pump rate limit (kg/s)
    >>> fb = gc.lqr_state_feedback(gc.BuoyancyGlider(veh), eq.state, [0.0], u_min=[-rate], u_max=[rate])
    >>> fb.K.shape, bool(fb.closed_loop_poles.real.max() < 0)
    ((1, 5), True)
    """
    n, m = _check_model(model)
    if m == 0:
        raise ArgumentError(f"{type(model).__name__} has no inputs: there is nothing to feed back")
    x_e = checks.array("x_e", x_e, shape=(n,))
    u_e = checks.array("u_e", u_e, shape=(m,))
    if not isinstance(name, str):
        raise ArgumentTypeError(f"name must be a string, got {type(name).__name__}")
    Qm = _weight("Q", Q, n, definite=False)
    Rm = _weight("R", R, m, definite=True)
    lo = _bound("u_min", u_min, m, -np.inf)
    hi = _bound("u_max", u_max, m, np.inf)
    if np.any(lo >= hi) or np.any(u_e < lo) or np.any(u_e > hi):
        raise ArgumentError(f"need u_min < u_max with u_e inside: u_min = {lo}, u_max = {hi}, u_e = {u_e}")
    A, B = jacobians(model.rhs, x_e, u_e)
    with np.errstate(all="ignore"):
        f0 = np.asarray(model.rhs(x_e, u_e), dtype=float)
    if f0.shape != (n,):
        raise ArgumentError(f"model.rhs(x_e, u_e) must return shape ({n},), got {f0.shape}")
    terms = float(np.max(np.abs(A) @ np.abs(x_e) + np.abs(B) @ np.abs(u_e)))
    res = float(np.max(np.abs(f0)))
    if not res <= EQUILIBRIUM_RTOL * terms:
        raise ModelError(f"(x_e, u_e) is not an equilibrium of {type(model).__name__}: |rhs| = {res:.3g}, relative "
                         f"to the linear terms {terms:.3g} (tolerance {EQUILIBRIUM_RTOL:g})")
    try:
        K, _, poles = control.lqr(A, B, Qm, Rm)
    except Exception as exc:  # python-control raises several types
        raise SolverError(f"LQR failed for {type(model).__name__} at the equilibrium: {exc}") from exc
    K = np.asarray(K, dtype=float)
    if not np.all(np.isfinite(K)):
        raise SolverError(f"LQR returned a non-finite gain for {type(model).__name__}")
    return StateFeedback(x_e, u_e, K, lo, hi, np.asarray(poles), Qm, Rm, name)


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
    evaluations : int
        Right-hand-side calls the batch integration used (capped by ``max_evaluations`` of
        :func:`compare_controllers`).
    """

    name: str
    converged: np.ndarray = field(repr=False)
    peak_u: np.ndarray = field(repr=False)
    integrated_u: np.ndarray = field(repr=False)
    settling_time: np.ndarray = field(repr=False)
    evaluations: int = 0

    @property
    def fraction(self) -> float:
        """Fraction of the initial conditions that converge (the simulated region of attraction in the box)."""
        return float(np.mean(self.converged))

    def as_dict(self, common: np.ndarray | None = None) -> dict[str, Any]:
        """Medians over the converged runs (or over ``common``, a mask of runs all controllers converged from), as a
        plain dict for tables and JSON.

        Parameters
        ----------
        common : ndarray of bool, shape (N,), optional
            The runs to summarize (e.g. :attr:`BatchComparison.common`); default the converged ones.

        Returns
        -------
        dict
            ``name``, ``fraction``, ``n`` and, when ``n > 0``, medians and maxima of the metrics.

        Raises
        ------
        ArgumentTypeError
            If ``common`` is not an array of booleans.
        ArgumentError
            If ``common`` does not have one entry per run.
        """
        if common is None:
            sel = self.converged
        else:
            sel = np.asarray(common)
            if sel.dtype != bool:
                raise ArgumentTypeError(f"common must be a boolean mask of the runs, got dtype {sel.dtype}")
            if sel.shape != self.converged.shape:
                raise ArgumentError(f"common must have shape {self.converged.shape} (one flag per run), got "
                                    f"{sel.shape}")
        if not np.any(sel):
            return {"name": self.name, "fraction": self.fraction, "n": 0}
        return {"name": self.name, "fraction": self.fraction, "n": int(np.sum(sel)),
                "median_peak_u": np.median(self.peak_u[sel], axis=0).tolist(),
                "max_peak_u": np.max(self.peak_u[sel], axis=0).tolist(),
                "median_integrated_u": np.median(self.integrated_u[sel], axis=0).tolist(),
                "median_settling_time": float(np.median(self.settling_time[sel]))}

    def summary(self, common: np.ndarray | None = None) -> str:
        """One line of text: the converged fraction and the medians of :meth:`as_dict`.

        Parameters
        ----------
        common : ndarray of bool, shape (N,), optional
            As in :meth:`as_dict`.

        Returns
        -------
        str

        Raises
        ------
        ArgumentTypeError
            If ``common`` is not an array of booleans.
        ArgumentError
            If ``common`` does not have one entry per run.
        """
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

    TABLE_HEADER: ClassVar[tuple[str, ...]] = ("controller", "converged", "median peak |u - u_e|", "max peak",
                                                "median int |u - u_e| dt", "median settling [s]")
    """Column names of :meth:`table_rows` (input units; append them to the headers as the table needs)."""

    def table_rows(self) -> list[list[str]]:
        """One row of text per controller for a comparison table, effort and settling over the common runs.

        Each row is ``[name, fraction converged, median peak |u_j - u_e,j| (one value per input), max of those peaks,
        median int |u_j - u_e,j| dt, median settling time]``, as :data:`TABLE_HEADER`; the effort and settling
        statistics are those of :meth:`ControllerRecord.as_dict` over :attr:`common` (the runs every controller
        converged from), so the controllers are compared on the same initial states. A controller row has ``"-"``
        in the statistics columns when no run is common.

        Returns
        -------
        list of list of str
            One row per controller, in the order of :attr:`records` (fraction as a percentage with one decimal,
            efforts to 3 significant digits, settling time in s with 2 decimals).

        Raises
        ------
        ArgumentError
            If the records do not have one flag per initial state (a hand-built comparison).
        """
        rows = []
        common = self.common
        for name, rec in self.records.items():
            sm = rec.as_dict(common)
            if sm["n"] == 0:
                rows.append([name, f"{rec.fraction:.1%}", "-", "-", "-", "-"])
                continue
            rows.append([name, f"{rec.fraction:.1%}", ", ".join(f"{v:.3g}" for v in sm["median_peak_u"]),
                         ", ".join(f"{v:.3g}" for v in sm["max_peak_u"]),
                         ", ".join(f"{v:.3g}" for v in sm["median_integrated_u"]),
                         f"{sm['median_settling_time']:.2f}"])
        return rows

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


def _inputs(name: str, raw: Any, N: int, m: int) -> np.ndarray:
    """A controller's batch output as an (N, m) float array; ArgumentError/ArgumentTypeError naming it otherwise."""
    try:
        if raw is None or isinstance(raw, str | bytes) or np.iscomplexobj(raw):
            raise TypeError(type(raw).__name__)
        U = np.asarray(raw, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentTypeError(f"controller '{name}' must return real inputs, got {type(raw).__name__}") from exc
    if U.size != N * m:
        raise ArgumentError(f"controller '{name}' must return {m} input(s) per state of the batch (shape ({N}, {m})), "
                            f"got shape {U.shape}")
    return U.reshape(N, m)


def _budget_message(name: str, where: str, max_evaluations: int) -> str:
    return (f"batch simulation of '{name}' stopped {where} after max_evaluations = {max_evaluations} right-hand-side "
            "evaluations; raise max_evaluations, loosen rtol/atol, or shorten t_final")


def _diverged_mask(diverged: Callable[[np.ndarray], np.ndarray], X: np.ndarray) -> np.ndarray:
    """``diverged(X)`` as one bool per row; ArgumentError otherwise."""
    flag = np.asarray(diverged(X))
    if flag.size != X.shape[0]:
        raise ArgumentError(f"diverged must return one flag per run (shape ({X.shape[0]},)), got {flag.shape}")
    return flag.reshape(X.shape[0]).astype(bool)


def _non_finite(name: str, bad: np.ndarray, X: np.ndarray, U: np.ndarray, where: str) -> SolverError:
    k = int(np.flatnonzero(bad)[0])
    what = "input" if not np.all(np.isfinite(U[k])) else "state derivative"
    return SolverError(f"batch simulation of '{name}': {where} has a non-finite {what} at x = {X[k]} "
                       f"({int(np.sum(bad))} run(s) affected): it left the domain of the model or the controller; "
                       "pass diverged=lambda X: ... to freeze runs that leave it")


def _run_solve_ivp(model: Any, name: str, ctrl: Callable[[float, Any], Any], X0: np.ndarray, n: int, m: int,
                   u_e: np.ndarray, te: np.ndarray, rtol: float, atol: float,
                   diverged: Callable[[np.ndarray], np.ndarray] | None, max_evaluations: int,
                   deadline: checks.Deadline, method: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """One controller as a single stacked :func:`scipy.integrate.solve_ivp` ODE (one step size for all runs).

    Returns the output times, the states and input integrals ``(N, n + m, T)`` there, the frozen mask and the number
    of right-hand-side evaluations.
    """
    N = X0.shape[0]
    t_final = float(te[-1])
    frozen = np.zeros(N, dtype=bool)
    count = [0]

    def f(t: float, y: np.ndarray) -> np.ndarray:
        count[0] += 1
        if count[0] > max_evaluations:
            raise BudgetError(_budget_message(name, f"at t = {t:.4g} s (of t_final = {t_final:g} s)",
                                              max_evaluations))
        deadline.check(f"controller '{name}' at t = {t:.4g} s")
        Y = y.reshape(N, n + m)
        X = Y[:, :n]
        if diverged is not None:
            frozen[:] |= _diverged_mask(diverged, X)
        U = _inputs(name, ctrl(t, X), N, m)
        d = np.empty_like(Y)
        with np.errstate(all="ignore"):
            d[:, :n] = np.asarray(model.rhs(X, U), dtype=float)
            d[:, n:] = np.abs(U - u_e)
        d[frozen] = 0.0
        bad = ~np.all(np.isfinite(d), axis=1)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise _non_finite(name, bad, X, U, f"run {k} (x0 = {X0[k]}) at t = {t:.4g} s")
        return d.ravel()

    y0 = np.concatenate([X0, np.zeros((N, m))], axis=1).ravel()
    # runs are independent: block-diagonal Jacobian, so the implicit methods difference N runs at once
    kw = ({"jac_sparsity": sparse.block_diag([np.ones((n + m, n + m))] * N, format="csr")}
          if method in ("BDF", "Radau") else {})
    sol = solve_ivp(f, (0.0, t_final), y0, method=method, t_eval=te, rtol=rtol, atol=atol, **kw)
    if not sol.success:
        raise SolverError(f"batch simulation of '{name}' failed at t = {sol.t[-1]:.4g} s: {sol.message}")
    return sol.t, sol.y.reshape(N, n + m, -1), frozen, count[0]


def _run_batch(model: Any, name: str, ctrl: Callable[[float, Any], Any], X0: np.ndarray, n: int, m: int,
               u_e: np.ndarray, te: np.ndarray, rtol: float, atol: float,
               diverged: Callable[[np.ndarray], np.ndarray] | None, max_evaluations: int,
               deadline: checks.Deadline) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """One controller through :func:`glidectl.integrate_batch` (every run with its own step size), on the state
    ``(x, int |u - u_e| dt)``; a run flagged by ``diverged`` stops (is frozen) at the first accepted state where it
    is flagged. Same returns as :func:`_run_solve_ivp`.
    """
    N = X0.shape[0]
    k = n + m
    count = [0]

    def f(Y: np.ndarray) -> np.ndarray:
        count[0] += 1
        if count[0] > max_evaluations:
            raise BudgetError(_budget_message(name, f"(of t_final = {te[-1]:g} s)", max_evaluations))
        deadline.check(f"controller '{name}'")
        M = Y.shape[0]
        X = Y[:, :n]
        U = _inputs(name, ctrl(0.0, X), M, m)
        d = np.empty((M, k))
        with np.errstate(all="ignore"):
            d[:, :n] = np.asarray(model.rhs(X, U), dtype=float)
            d[:, n:] = np.abs(U - u_e)
        bad = ~np.all(np.isfinite(d), axis=1)
        if np.any(bad) and diverged is not None:
            bad &= ~_diverged_mask(diverged, X)
        if np.any(bad):
            raise _non_finite(name, bad, X, U, "a run")
        return d

    def jac(Y: np.ndarray) -> np.ndarray:
        # central differences in the n states only: the input integrals do not enter the right-hand side
        return batch_jacobian(f, Y, method="central", columns=n)

    stop = None if diverged is None else (lambda Y: _diverged_mask(diverged, Y[:, :n]))
    Y0 = np.concatenate([X0, np.zeros((N, m))], axis=1)
    res = integrate_batch(f, Y0, float(te[-1]), t_eval=te[1:], rtol=rtol, atol=atol, jacobian=jac, diverged=stop,
                          max_steps=max_evaluations)
    failed = (res.status != FINISHED) & (res.status != DIVERGED)
    if np.any(failed):
        i = int(np.flatnonzero(failed)[0])
        raise SolverError(f"batch simulation of '{name}' failed: run {i} (x0 = {X0[i]}) stopped at t = {res.t[i]:.4g} "
                          f"s ({res.summary()}); loosen rtol/atol or pass diverged= to freeze runs that leave the "
                          "model's domain")
    frozen = res.status == DIVERGED
    Y = np.concatenate([Y0[:, None, :], res.samples], axis=1)          # (N, T, k)
    Y = np.where(np.isnan(Y) & frozen[:, None, None], res.x_final[:, None, :], Y)   # frozen where it stopped
    return te, np.transpose(Y, (0, 2, 1)), frozen, count[0]


def compare_controllers(model: Any, controllers: Mapping[str, Callable[[float, Any], Any]], x0: Any, x_e: Any,
                        u_e: Any, t_final: float, *, scale: Any = None, tol: float = 0.02, settle: float = 0.05,
                        n_out: int = 401, method: str = "batch", rtol: float = 1e-6, atol: float = 1e-9,
                        diverged: Callable[[np.ndarray], np.ndarray] | None = None,
                        max_evaluations: int = 2_000_000, time_limit: float | None = None) -> BatchComparison:
    """Simulate every controller from every initial state (one stacked, vectorized ODE per controller).

    Parameters
    ----------
    model
        glidectl model with inputs; ``rhs`` batch-capable.
    controllers : mapping name -> controller
        Time-invariant feedback ``controller(t, X)`` accepting a batch ``X`` of shape (N, n) and returning shape
        (N, m); at least one. With ``method="batch"`` the runs advance at their own times and ``t`` is passed as
        0 during the integration (the output times afterwards).
    x0 : array_like (N, n)
        Initial states, finite, ``N >= 1``.
    x_e, u_e : array_like
        The equilibrium all controllers regulate to (metrics are deviations from it), shapes ``(n,)``, ``(m,)``.
    t_final : float
        Horizon (s), ``> 0``.
    scale : array_like (n,), optional
        Per-state scale of the error norm (default ones), finite and ``> 0``.
    tol, settle : float
        Convergence (at ``t_final``) and settling thresholds on ``max_i |x_i - x_e,i| / scale_i``, ``> 0``.
    n_out : int
        Number of evenly spaced output times on which peaks and settling are evaluated, in ``[2, 100000]``.
    method : str
        Integrator (:data:`METHODS`). Default ``"batch"``: :func:`glidectl.integrate_batch` (4th-order Rosenbrock,
        A-stable) on the state ``(x, int |u - u_e| dt)``, every run with its own step size and its own error test
        (RMS over that run's components), output times hit exactly, Jacobians by central differences in the
        states; a run flagged by ``diverged`` stops at the first accepted state where it is flagged. Otherwise a
        method of :func:`scipy.integrate.solve_ivp` on one stacked ODE (one step size and one error norm for all
        runs; block-diagonal Jacobian sparsity for ``"BDF"`` and ``"Radau"``; ``diverged`` is checked at every
        evaluation).
    rtol, atol : float
        Integrator tolerances (relative, nondimensional; absolute, in state and integrated-input units), ``> 0``.
    diverged : callable, optional
        ``X (N, n) -> bool (N,)``: runs that leave the model's domain (e.g. speed near zero) are frozen there and
        count as not converged.
    max_evaluations : int
        Budget of right-hand-side calls per controller (each evaluates a batch of runs; with ``"batch"`` a
        Jacobian counts as one call), ``>= 1``. The default is about 8 times what the stiffest comparison of the
        chapter-6 design needs with ``"BDF"`` (elevator control, 300 runs over 150 s: 2.6e5); ``"batch"`` needs
        about 4e3 there.
    time_limit : float, optional
        Wall-time budget (s) of the whole comparison; default none.

    Returns
    -------
    BatchComparison
        One :class:`ControllerRecord` per controller (convergence mask, peak and integrated input deviation in
        input units and input units x s, settling times in s, evaluations used), with the settings used.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a glidectl model, ``controllers`` is not a mapping of names to callables, an array or
        number has the wrong type, ``diverged`` is not callable, or a controller returns something that is not real
        numbers.
    ArgumentError
        Bad shapes, non-finite or non-positive values, an unknown ``method``, no controllers, or a controller (or
        ``diverged``) returning the wrong number of values.
    SolverError
        If the batch integration of a controller fails (with ``"batch"``: a run that is not flagged by ``diverged``
        stops on step-size underflow), or a run that is not frozen by ``diverged`` gets a
        non-finite derivative or input (it left the model's or the controller's domain: pass ``diverged`` to
        freeze such runs). Non-finite derivatives are never zeroed silently.
    BudgetError
        If a controller's integration needs more than ``max_evaluations`` right-hand-side evaluations, the
        ``time_limit`` is reached, or the stacked problem exceeds :data:`MAX_STACKED_STATES` states or
        :data:`MAX_OUTPUT_VALUES` output values.
    Exception
        Whatever a controller, ``diverged`` or ``model.rhs`` raises passes through unchanged.
    """
    n, m = _check_model(model)
    if not isinstance(controllers, Mapping):
        raise ArgumentTypeError(f"controllers must be a mapping name -> controller(t, X), got "
                                f"{type(controllers).__name__}")
    if not controllers:
        raise ArgumentError("controllers is empty: give at least one name -> controller(t, X)")
    for name, ctrl in controllers.items():
        if not isinstance(name, str):
            raise ArgumentTypeError(f"controller names must be strings, got {type(name).__name__} {name!r}")
        checks.function(f"controllers[{name!r}]", ctrl)
    X0 = checks.array("x0", x0, shape=(None, n), min_size=1)
    x_e = checks.array("x_e", x_e, shape=(n,))
    u_e = checks.array("u_e", u_e, shape=(m,))
    t_final = checks.positive("t_final", t_final, unit="s")
    sc = np.ones(n) if scale is None else checks.array("scale", scale, shape=(n,))
    if np.any(sc <= 0):
        raise ArgumentError(f"scale must be positive, got {sc}")
    tol = checks.positive("tol", tol)
    settle = checks.positive("settle", settle)
    n_out = checks.integer("n_out", n_out, lo=2, hi=100_000)
    checks.choice("method", method, METHODS)
    rtol = checks.positive("rtol", rtol)
    atol = checks.positive("atol", atol)
    if diverged is not None:
        checks.function("diverged", diverged)
    max_evaluations = checks.integer("max_evaluations", max_evaluations, lo=1)
    deadline = checks.Deadline(time_limit, "compare_controllers")
    N = X0.shape[0]
    if N * (n + m) > MAX_STACKED_STATES or N * (n + m) * n_out > MAX_OUTPUT_VALUES:
        raise BudgetError(f"{N} runs x {n + m} states (x {n_out} output times) exceed the size limits of one "
                          f"comparison ({MAX_STACKED_STATES} stacked states, {MAX_OUTPUT_VALUES} output values); "
                          "compare fewer initial states or output times at once")
    te = np.linspace(0.0, t_final, n_out)
    records = {}
    for name, ctrl in controllers.items():
        args = (model, name, ctrl, X0, n, m, u_e, te, rtol, atol, diverged, max_evaluations, deadline)
        t_out, Y, frozen, evaluations = _run_batch(*args) if method == "batch" else _run_solve_ivp(*args, method)
        X = Y[:, :n, :]
        err = np.max(np.abs(X - x_e[None, :, None]) / sc[None, :, None], axis=1)  # (N, T)
        conv = (err[:, -1] <= tol) & ~frozen
        U = np.stack([_inputs(name, ctrl(t, X[:, :, k]), N, m) for k, t in enumerate(t_out)], -1)
        peak = np.max(np.abs(U - u_e[None, :, None]), axis=2)
        above = err > settle
        last = np.where(above.any(axis=1), above.shape[1] - 1 - np.argmax(above[:, ::-1], axis=1), -1)
        ts = np.where(last + 1 < t_out.size, t_out[np.minimum(last + 1, t_out.size - 1)], np.inf)
        ts[~conv] = np.inf
        records[name] = ControllerRecord(name, conv, peak, Y[:, n:, -1], ts, evaluations)
    return BatchComparison(X0, x_e, sc, float(t_final), tol, settle, records, tuple(model.state_names))
