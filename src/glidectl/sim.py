"""Simulation of glidectl models in open or closed loop (scipy's ``solve_ivp``)."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from scipy.integrate import solve_ivp

from .errors import GlidectlError, SolverError

__all__ = ["Ensemble", "Model", "Simulation", "simulate", "simulate_many"]


class Model(Protocol):
    """What :func:`simulate` needs of a model."""

    state_names: tuple[str, ...]
    input_names: tuple[str, ...]

    def rhs(self, x: Any, u: Any) -> Any: ...


def _model_provenance(model: Any) -> str:
    """Provenance string of a model: its own ``provenance`` if it has one (a ``str``), else its vehicle's parameter
    hash, else ``""``."""
    prov = getattr(model, "provenance", None)
    if isinstance(prov, str):
        return prov
    prov = getattr(getattr(model, "vehicle", None), "provenance", None)
    return prov if isinstance(prov, str) else ""


@dataclass(frozen=True)
class Simulation:
    """A simulated trajectory.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Times (s).
    x : ndarray, shape (N, n)
        States, columns named by ``state_names``.
    u : ndarray, shape (N, m)
        Inputs applied (evaluated at the output times).
    method, rtol, atol : integrator settings
    nfev : int
        Right-hand-side evaluations.
    model_name : str
        Model class and vehicle name, ``"Class(vehicle)"``.
    stopped_at : float or None
        Time (s) at which the ``stop`` condition of :func:`simulate` ended the run (None: ran to ``t_final``).
    provenance : str
        The simulated model's provenance: its vehicle's parameter hash (``""`` for a model without a vehicle).
    """

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    method: str
    rtol: float
    atol: float
    nfev: int
    model_name: str
    stopped_at: float | None = None
    provenance: str = ""

    def state(self, name: str) -> np.ndarray:
        """Time history of one named state or input."""
        if name in self.state_names:
            return self.x[:, self.state_names.index(name)]
        if name in self.input_names:
            return self.u[:, self.input_names.index(name)]
        raise GlidectlError(f"no state or input '{name}'; have {self.state_names + self.input_names}")

    def plot(self, ax: Any = None, names: Sequence[str] | None = None, *,
             scale: dict[str, tuple[float, str]] | None = None, **line: Any) -> Any:
        """Draw named states and inputs versus time, one axes each, in the glidectl style.

        Parameters
        ----------
        ax : axes or array of axes, optional
            One axes per name; default a new figure.
        names : sequence of str, optional
            States and inputs to draw; default every state. (The former order ``sim.plot(names, ax)``, names
            first, still works.)
        scale : dict, optional
            ``scale[name] = (factor, unit)`` converts units for display, e.g. ``{"theta": (180 / pi, "deg")}``.
        **line
            Passed to :meth:`matplotlib.axes.Axes.plot`.

        Returns
        -------
        ndarray of matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_simulation`.
        """
        from .plotting import plot_simulation, style

        if isinstance(ax, str) or (isinstance(ax, Sequence) and ax and all(isinstance(a, str) for a in ax)):
            names, ax = ax, names  # sim.plot(["V", "gamma"], ax): the former order, names first
        with style():
            return plot_simulation(self, [names] if isinstance(names, str) else names, ax=ax, scale=scale, **line)


def simulate(model: Model, x0: Any, t_final: float, controller: Callable[[float, Any], Any] | None = None, *,
             t_eval: Any = None, method: str = "LSODA", rtol: float = 1e-8, atol: float = 1e-10,
             breakpoints: Sequence[float] = (),
             stop: Callable[[float, np.ndarray], float] | None = None) -> Simulation:
    """Integrate ``x' = f(x, controller(t, x))`` from ``x0`` over ``[0, t_final]`` seconds.

    Parameters
    ----------
    model : Model
        A glidectl model (``rhs``, ``state_names``, ``input_names``).
    x0 : array_like, shape (n,)
        Initial state, in the units of the model's states (e.g. :data:`glidectl.models.longitudinal.STATE_UNITS`).
    t_final : float
        Final time (s).
    controller : callable, optional
        ``(t, x) -> u``; zero input when omitted. If it has ``switch_times``, integration restarts there so that
        discontinuous set-point changes are resolved exactly.
    t_eval : array_like, optional
        Output times (s); default 2001 evenly spaced points. Times outside ``[0, t_final]`` are dropped.
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp`; default ``"LSODA"`` (switches automatically on stiff
        closed loops).
    rtol, atol : float
        Relative (nondimensional) and absolute (state units) tolerances of the integrator.
    breakpoints : sequence of float
        Extra restart times (s).
    stop : callable, optional
        ``(t, x) -> float``, continuous, positive while the run should go on; the run ends (recorded in
        ``Simulation.stopped_at``) where it falls through zero. Use it to end diverging runs early, e.g.
        ``lambda t, x: 5.0 - abs(z_prime(x))``.

    Returns
    -------
    Simulation
        Times (s), states and the inputs applied at the output times (model units), the integrator settings,
        the number of right-hand-side evaluations and ``stopped_at`` (s, or None).

    Raises
    ------
    GlidectlError
        If ``x0`` does not have shape ``(n,)``, ``t_final`` is not a positive finite number, or the ``stop``
        condition is already met at ``t = 0``.
    SolverError
        If :func:`~scipy.integrate.solve_ivp` fails or the states become non-finite.
    """
    x0 = np.asarray(x0, dtype=float)
    n, m = len(model.state_names), len(model.input_names)
    if x0.shape != (n,):
        raise GlidectlError(f"x0 must have shape ({n},) for states {model.state_names}, got {x0.shape}")
    if not (np.isfinite(t_final) and t_final > 0):
        raise GlidectlError(f"t_final must be a positive number of seconds, got {t_final!r}")
    ctrl = controller if controller is not None else (lambda t, x: np.zeros(m))
    te = np.linspace(0.0, t_final, 2001) if t_eval is None else np.asarray(t_eval, dtype=float)
    cuts = sorted({0.0, float(t_final), *[float(s) for s in getattr(controller, "switch_times", ())
                                          if 0 < s < t_final], *[b for b in breakpoints if 0 < b < t_final]})
    events = None
    if stop is not None:
        if stop(0.0, x0) <= 0:
            raise GlidectlError("the stop condition is already met at t = 0 (stop(0, x0) <= 0)")

        def events(t: float, y: np.ndarray) -> float:
            return float(stop(t, y))

        events.terminal = True  # type: ignore[attr-defined]
        events.direction = -1  # type: ignore[attr-defined]
    ts, xs, nfev = [], [], 0
    x = x0
    stopped_at = None
    for a, b in itertools.pairwise(cuts):
        last = b == cuts[-1]
        sol = solve_ivp(lambda t, y: model.rhs(y, ctrl(t, y)), (a, b), x, method=method, rtol=rtol,
                        atol=atol, dense_output=True, events=events)
        if not sol.success:
            raise SolverError(f"integration failed at t = {sol.t[-1]:.4g} s: {sol.message}")
        nfev += sol.nfev
        if sol.status == 1:  # stop condition met
            stopped_at = float(sol.t[-1])
            seg = te[(te >= a) & (te <= stopped_at)]
            last = True
        else:
            seg = te[(te >= a) & ((te <= b) if last else (te < b))]
        ts.append(seg)
        xs.append(np.atleast_2d(sol.sol(seg).T) if seg.size else np.empty((0, n)))
        x = sol.y[:, -1]
        if not np.all(np.isfinite(sol.y)):
            raise SolverError(f"integration produced non-finite states before t = {b:.4g} s")
        if stopped_at is not None:
            break
    t = np.concatenate(ts)
    X = np.concatenate(xs)
    U = np.array([np.asarray(ctrl(ti, xi), dtype=float) for ti, xi in zip(t, X, strict=True)]).reshape(len(t), m)
    vname = getattr(getattr(model, "vehicle", None), "name", "?")
    return Simulation(t, X, U, tuple(model.state_names), tuple(model.input_names), method, rtol, atol, nfev,
                      f"{type(model).__name__}({vname})", stopped_at, _model_provenance(model))


@dataclass(frozen=True)
class Ensemble:
    """Final states of many trajectories integrated together (see :func:`simulate_many`).

    Attributes
    ----------
    x0, x_final : ndarray, shape (N, n)
        Initial and final states.
    frozen : ndarray of bool, shape (N,)
        Trajectories stopped by the ``freeze`` condition (their ``x_final`` is where they were stopped).
    t_final : float
    method, rtol, atol, nfev : integrator settings
    model_name : str
        Model class and vehicle name, ``"Class(vehicle)"``.
    state_names : tuple of str
        Names of the state columns (empty for an ensemble built without them).
    provenance : str
        The simulated model's provenance: its vehicle's parameter hash (``""`` for a model without a vehicle).
    """

    x0: np.ndarray
    x_final: np.ndarray
    frozen: np.ndarray
    t_final: float
    method: str
    rtol: float
    atol: float
    nfev: int
    model_name: str
    state_names: tuple[str, ...] = ()
    provenance: str = ""

    def plot(self, ax: Any = None, *, dims: Sequence[Any] = (0, 1), x_e: Any = None, tol: float = 1e-3,
             scale: Any = None) -> Any:
        """Draw the initial states in the plane of two states, marked by outcome, in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane (the other states are projected out).
        x_e : array_like, optional
            Equilibrium: with it, runs are marked converged (``max_i |x_final,i - x_e,i| / scale_i <= tol`` and not
            frozen), not converged or frozen; without it, frozen or not.
        tol : float
            Convergence tolerance in scaled state units.
        scale : array_like (n,), optional
            Per-state scale of the convergence test (default ones).

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_ensemble`.
        """
        from .plotting import plot_ensemble, style

        with style():
            return plot_ensemble(self, ax, dims=dims, x_e=x_e, tol=tol, scale=scale)


def simulate_many(model: Model, X0: Any, t_final: float, *, method: str = "RK45", rtol: float = 1e-6,
                  atol: float = 1e-9, freeze: Callable[[np.ndarray], np.ndarray] | None = None) -> Ensemble:
    """Integrate an input-free model from many initial states at once (one stacked, vectorized ODE).

    Intended for region-of-attraction studies (thousands of short runs). A trajectory for which ``freeze(x)`` is
    True stops evolving (its derivative is set to zero), so one diverging run (e.g. a glider whose speed tends to
    zero, where the model is singular) does not stall the others.

    Parameters
    ----------
    model : Model
        Model with ``input_names == ()``; ``rhs`` must accept a batch of states, shape (N, n).
    X0 : array_like, shape (N, n)
        Initial states, one per row, in the units of the model's states.
    t_final : float
        Final time (s).
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp`; default ``"RK45"``.
    rtol, atol : float
        Relative (nondimensional) and absolute (state units) tolerances, applied to the stacked state.
    freeze : callable, optional
        ``x (N, n) -> bool (N,)``. Evaluated at every right-hand-side call (including the integrator's trial
        stages), and a trajectory once frozen stays frozen.

    Returns
    -------
    Ensemble
        Initial and final states (model units), the frozen mask, ``t_final`` (s), the integrator settings and the
        number of right-hand-side evaluations.

    Raises
    ------
    GlidectlError
        If ``X0`` is not of shape ``(N, n)``, the model has inputs, or ``t_final`` is not a positive finite
        number.
    SolverError
        If :func:`~scipy.integrate.solve_ivp` fails.
    """
    X0 = np.asarray(X0, dtype=float)
    n = len(model.state_names)
    if X0.ndim != 2 or X0.shape[1] != n:
        raise GlidectlError(f"X0 must have shape (N, {n}) for states {model.state_names}, got {X0.shape}")
    if model.input_names:
        raise GlidectlError("simulate_many is for input-free models (close the loop inside the model)")
    if not (np.isfinite(t_final) and t_final > 0):
        raise GlidectlError(f"t_final must be a positive number of seconds, got {t_final!r}")
    N = X0.shape[0]
    frozen = np.zeros(N, dtype=bool) if freeze is None else np.asarray(freeze(X0), dtype=bool)

    def f(t: float, y: np.ndarray) -> np.ndarray:
        X = y.reshape(N, n)
        if freeze is not None:
            frozen[:] |= np.asarray(freeze(X), dtype=bool)
        d = np.asarray(model.rhs(X, None), dtype=float)
        d[frozen] = 0.0
        return d.ravel()

    with np.errstate(all="ignore"):
        sol = solve_ivp(f, (0.0, float(t_final)), X0.ravel(), method=method, rtol=rtol, atol=atol)
    if not sol.success:
        raise SolverError(f"ensemble integration failed at t = {sol.t[-1]:.4g} s: {sol.message}")
    XF = sol.y[:, -1].reshape(N, n)
    vname = getattr(getattr(model, "vehicle", None), "name", "?")
    return Ensemble(X0, XF, frozen.copy(), float(t_final), method, rtol, atol, sol.nfev,
                    f"{type(model).__name__}({vname})", tuple(model.state_names), _model_provenance(model))
