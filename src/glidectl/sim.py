"""Simulation of glidectl models in open or closed loop (scipy's ``solve_ivp`` integrators).

Every run has budgets (:data:`MAX_STEPS` = 20 000 integrator steps, ``20 max_steps`` right-hand-side evaluations,
an optional wall-time limit): hitting one raises :class:`~glidectl.BudgetError`, or with ``on_budget="stop"``
returns the part computed, with ``stopped_by`` naming the budget. Spans shorter than :data:`MIN_T_FINAL` (1e-9) or
longer than :data:`MAX_T_FINAL` (1e9) are refused.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolution, OdeSolver, Radau
from scipy.optimize import brentq

from . import checks
from .errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, SolverError

__all__ = ["MAX_NFEV_PER_STEP", "MAX_STEPS", "MAX_T_FINAL", "MIN_T_FINAL", "Ensemble", "Model", "Simulation",
           "simulate", "simulate_many"]

_EPS = float(np.finfo(float).eps)
_MIN_RTOL = 100 * _EPS


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
        Time (s) at which the run ended early: where the ``stop`` condition of :func:`simulate` fell through zero,
        or where a budget stopped it (``on_budget="stop"``); None: ran to ``t_final``.
    provenance : str
        The simulated model's provenance: its vehicle's parameter hash (``""`` for a model without a vehicle).
    n_steps : int
        Integrator steps taken.
    stopped_by : str
        What ended the run: ``"t_final"``, ``"stop"`` (the stop condition), or the budget that was hit
        (``"max_steps"``, ``"max_nfev"``, ``"time_limit"``).
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
    n_steps: int = 0
    stopped_by: str = "t_final"

    def state(self, name: str) -> np.ndarray:
        """Time history of one named state or input.

        Parameters
        ----------
        name : str
            A name of ``state_names`` or ``input_names``.

        Returns
        -------
        ndarray, shape (N,)
            Its values at the output times ``t`` (model units).

        Raises
        ------
        ArgumentTypeError
            If ``name`` is not a string.
        ArgumentError
            If there is no such state or input.
        """
        if not isinstance(name, str):
            raise ArgumentTypeError(f"name must be a state or input name (str), got {type(name).__name__} {name!r}")
        if name in self.state_names:
            return self.x[:, self.state_names.index(name)]
        if name in self.input_names:
            return self.u[:, self.input_names.index(name)]
        raise ArgumentError(f"no state or input '{name}'; have {self.state_names + self.input_names}")

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

        Raises
        ------
        ArgumentError
            If a name is not a state or input of the simulation.
        """
        from .plotting import plot_simulation, style

        if isinstance(ax, str) or (isinstance(ax, Sequence) and ax and all(isinstance(a, str) for a in ax)):
            names, ax = ax, names  # sim.plot(["V", "gamma"], ax): the former order, names first
        with style():
            return plot_simulation(self, [names] if isinstance(names, str) else names, ax=ax, scale=scale, **line)


# --------------------------------------------------------------------------------------------- budgets and stepping
_METHODS: dict[str, type[OdeSolver]] = {"RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF,
                                        "LSODA": LSODA}

#: Shortest simulated span :func:`simulate` and :func:`simulate_many` accept, in the model's time unit (s, or the
#: nondimensional time of a nondimensional model): below it the span is degenerate (and LSODA never returns).
MIN_T_FINAL = 1e-9

#: Longest simulated span accepted (model time unit; 1e9 s is 32 years): a plausibility limit.
MAX_T_FINAL = 1e9

#: Default cap on the integrator steps of one :func:`simulate` / :func:`simulate_many` call (all restarts together).
#: Converging runs of the designs and tests take under 3 000 steps; the longest, a diverging recovery run of the
#: chapter-2 design ended by its stop condition, 11 200. A run that needs more is usually spinning up without bound.
MAX_STEPS = 20_000

#: Default cap on right-hand-side evaluations per step of the cap above (implicit methods evaluate the right-hand
#: side for their finite-difference Jacobians): ``max_nfev = MAX_NFEV_PER_STEP * max_steps`` unless given.
MAX_NFEV_PER_STEP = 20

_ON_BUDGET = ("raise", "stop")


class _BudgetHit(Exception):
    """Raised inside the right-hand side to leave the integrator when a budget is exhausted (never escapes)."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


class _Budget:
    """Steps, right-hand-side evaluations and wall time of one call."""

    def __init__(self, max_steps: int, max_nfev: int, time_limit: float | None) -> None:
        self.max_steps, self.max_nfev, self.time_limit = max_steps, max_nfev, time_limit
        self.start = time.perf_counter()
        self.steps = 0
        self.nfev = 0

    def evaluation(self) -> None:
        """Count one right-hand-side evaluation; leave the integrator when a budget is exhausted."""
        if self.nfev >= self.max_nfev:
            raise _BudgetHit("max_nfev")
        self.nfev += 1
        if self.time_limit is not None and time.perf_counter() - self.start > self.time_limit:
            raise _BudgetHit("time_limit")

    def step(self) -> str | None:
        """Count one accepted step; the name of an exhausted budget, or None."""
        self.steps += 1
        if self.steps >= self.max_steps:
            return "max_steps"
        if self.time_limit is not None and time.perf_counter() - self.start > self.time_limit:
            return "time_limit"
        return None

    def message(self, reason: str, what: str, t: float) -> str:
        if reason == "max_steps":
            limit = f"max_steps = {self.max_steps} integrator steps"
        elif reason == "max_nfev":
            limit = f"max_nfev = {self.max_nfev} right-hand-side evaluations"
        else:
            limit = f"time_limit = {self.time_limit:g} s of wall time"
        return (f"{what} stopped at t = {t:.6g} after {self.steps} steps and {self.nfev} right-hand-side "
                f"evaluations ({time.perf_counter() - self.start:.3g} s): it hit {limit}. A run that needs this much "
                "work usually diverges or is very stiff (try method='LSODA' or 'Radau'); raise the limit to go on, "
                "or pass on_budget='stop' to get the partial result")


@dataclass
class _Segment:
    t: float                       # time reached
    y: np.ndarray                  # state there
    interpolants: list[Any]        # dense output per step (when asked for)
    t_steps: list[float]           # step boundaries
    reason: str | None             # "stop" (event), a budget name, or None (reached the end)


def _integrate(fun: Callable[[float, np.ndarray], Any], a: float, b: float, y: np.ndarray, *, method: str,
               rtol: float, atol: Any, budget: _Budget, dense: bool,
               event: Callable[[float, np.ndarray], float] | None = None, what: str = "simulation") -> _Segment:
    """Step a scipy ``OdeSolver`` from ``a`` to ``b`` (as :func:`~scipy.integrate.solve_ivp` does), checking the
    budgets after every step and a terminal, decreasing ``event`` (``> 0`` at ``a``)."""
    seg = _Segment(a, y, [], [a], None)
    try:
        solver = _METHODS[method](fun, a, y, b, rtol=rtol, atol=atol)
    except _BudgetHit as hit:
        seg.reason = hit.reason
        return seg
    g = event(a, y) if event is not None else 0.0
    while True:
        try:
            msg = solver.step()
        except _BudgetHit as hit:       # exhausted inside a step: keep the steps already taken
            seg.reason = hit.reason
            return seg
        if solver.status == "failed":
            raise SolverError(f"{what}: the {method} integrator failed at t = {solver.t:.6g}: {msg}; try "
                              "method='LSODA' or 'Radau' (stiff dynamics) or looser tolerances")
        t_old, t_new, y_new = solver.t_old, solver.t, solver.y
        if not np.all(np.isfinite(y_new)):
            raise SolverError(f"{what}: the states became non-finite between t = {t_old:.6g} and {t_new:.6g} "
                              "(the motion diverges or leaves the model's domain); shorten the run or pass a stop "
                              "condition")
        interp = solver.dense_output() if dense or event is not None else None
        if event is not None:
            g_new = float(event(t_new, y_new))
            if g >= 0 >= g_new:
                budget.step()
                root = t_new
                if g_new < 0:
                    root = brentq(lambda s, f=interp: float(event(s, f(s))), t_old, t_new, xtol=4 * _EPS,
                                  rtol=4 * _EPS)
                seg.t, seg.y, seg.reason = float(root), np.asarray(interp(root), dtype=float), "stop"
                if dense:
                    seg.interpolants.append(interp)
                    seg.t_steps.append(seg.t)
                return seg
            g = g_new
        seg.t, seg.y = float(t_new), y_new.copy()
        if dense:
            seg.interpolants.append(interp)
            seg.t_steps.append(seg.t)
        reason = budget.step()
        if solver.status == "finished":
            return seg
        if reason is not None:
            seg.reason = reason
            return seg


def _check_common(t_final: Any, method: Any, rtol: Any, atol: Any, n: int, max_steps: Any, max_nfev: Any,
                  time_limit: Any, on_budget: Any) -> tuple[float, float, Any, _Budget]:
    tf = checks.real("t_final", t_final, lo=0.0, lo_open=True, hi=MAX_T_FINAL, unit="s")
    if tf < MIN_T_FINAL:
        raise ArgumentError(f"t_final = {tf!r} is below the shortest span simulated, MIN_T_FINAL = {MIN_T_FINAL:g} "
                            "(model time unit, s): a degenerate run; ask for a longer span")
    checks.choice("method", method, _METHODS)
    rt = checks.real("rtol", rtol, lo=_MIN_RTOL, hi=1.0, hi_open=True)
    if isinstance(atol, np.ndarray | list | tuple):
        at: Any = checks.array("atol", atol, shape=(n,))
        if np.any(at < 0) or not np.any(at > 0):
            raise ArgumentError(f"atol must be >= 0 in every component (and not all zero), got {atol!r}")
    else:
        at = checks.positive("atol", atol)
    steps = checks.integer("max_steps", max_steps, lo=1)
    nfev = MAX_NFEV_PER_STEP * steps if max_nfev is None else checks.integer("max_nfev", max_nfev, lo=1)
    limit = None if time_limit is None else checks.positive("time_limit", time_limit, unit="s")
    checks.choice("on_budget", on_budget, _ON_BUDGET)
    return tf, rt, at, _Budget(steps, nfev, limit)


def _check_model(model: Any) -> tuple[tuple[str, ...], tuple[str, ...]]:
    names = getattr(model, "state_names", None)
    inputs = getattr(model, "input_names", None)
    if not (isinstance(names, Sequence) and isinstance(inputs, Sequence) and callable(getattr(model, "rhs", None))):
        raise ArgumentTypeError(f"model must be a glidectl model (state_names, input_names and rhs(x, u)), got "
                                f"{type(model).__name__}")
    if not names:
        raise ArgumentError(f"model {type(model).__name__} has no states")
    return tuple(names), tuple(inputs)


def _model_rhs(model: Any, x: np.ndarray, u: Any, t: float) -> Any:
    """``model.rhs(x, u)``, with the library's own arithmetic failures turned into :class:`SolverError`."""
    try:
        return model.rhs(x, u)
    except (ZeroDivisionError, OverflowError, FloatingPointError, np.linalg.LinAlgError) as exc:
        raise SolverError(f"the right-hand side of {type(model).__name__} failed at t = {t:.6g}: "
                          f"{type(exc).__name__}: {exc}") from exc


def _input(u: Any, m: int, inputs: tuple[str, ...], t: float) -> np.ndarray:
    """The controller's output as a float array of shape ``(m,)``."""
    a = np.asarray(u)
    if a.dtype.kind not in "iuf":
        raise ArgumentTypeError(f"the controller must return {m} real input(s) {inputs}, got {type(u).__name__} "
                                f"{u!r} at t = {t:.6g}")
    if a.shape != (m,):
        if a.ndim > 1 or a.size != m:
            raise ArgumentError(f"the controller returned an array of shape {a.shape} at t = {t:.6g}; it must return "
                                f"shape ({m},), one value per input {inputs}")
        a = a.reshape(m)
    return a.astype(float, copy=False)


def simulate(model: Model, x0: Any, t_final: float, controller: Callable[[float, Any], Any] | None = None, *,
             t_eval: Any = None, method: str = "LSODA", rtol: float = 1e-8, atol: float = 1e-10,
             breakpoints: Sequence[float] = (), stop: Callable[[float, np.ndarray], float] | None = None,
             max_steps: int = MAX_STEPS, max_nfev: int | None = None, time_limit: float | None = None,
             on_budget: str = "raise") -> Simulation:
    """Integrate ``x' = f(x, controller(t, x))`` from ``x0`` over ``[0, t_final]`` seconds.

    Parameters
    ----------
    model : Model
        A glidectl model (``rhs``, ``state_names``, ``input_names``).
    x0 : array_like, shape (n,)
        Initial state, in the units of the model's states (e.g. :data:`glidectl.models.longitudinal.STATE_UNITS`);
        finite.
    t_final : float
        Final time (s, or the model's time unit), in ``[MIN_T_FINAL, MAX_T_FINAL] = [1e-9, 1e9]``.
    controller : callable, optional
        ``(t, x) -> u``, one real value per input (shape ``(m,)``; a scalar when ``m = 1``); zero input when
        omitted. If it has ``switch_times``, integration restarts there so that discontinuous set-point changes are
        resolved exactly. Exceptions it raises reach the caller unchanged.
    t_eval : array_like, optional
        Sorted output times in ``[0, t_final]`` (s); default 2001 evenly spaced points. Times outside the span are
        refused (times beyond it by rounding only, ``1e-12 t_final``, are moved onto its ends).
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp` (``"RK45"``, ``"RK23"``, ``"DOP853"``, ``"Radau"``,
        ``"BDF"``, ``"LSODA"``); default ``"LSODA"`` (switches automatically on stiff closed loops).
    rtol, atol : float
        Relative (nondimensional, in ``[2.2e-14, 1)``) and absolute (state units, > 0; or one value >= 0 per
        state) tolerances of the integrator.
    breakpoints : sequence of float
        Extra restart times (s); times outside ``(0, t_final)`` have no effect.
    stop : callable, optional
        ``(t, x) -> float``, continuous, positive while the run should go on; the run ends (recorded in
        ``Simulation.stopped_at``, ``stopped_by = "stop"``) where it falls through zero. Use it to end diverging
        runs early, e.g. ``lambda t, x: 5.0 - abs(z_prime(x))``.
    max_steps : int
        Budget of integrator steps for the whole run (default :data:`MAX_STEPS` = 20 000; converging runs of the
        designs take under 3 000).
    max_nfev : int, optional
        Budget of right-hand-side evaluations (default ``20 max_steps``; implicit methods spend some on Jacobians).
        It also bounds a single step that never completes.
    time_limit : float, optional
        Wall-time budget (s); default none.
    on_budget : {"raise", "stop"}
        What hitting a budget does: raise :class:`~glidectl.BudgetError` (default), or return the run up to where
        it stopped, with ``stopped_by`` naming the budget and ``stopped_at`` the time reached.

    Returns
    -------
    Simulation
        Times (s), states and the inputs applied at the output times (model units), the integrator settings,
        the number of steps and right-hand-side evaluations, ``stopped_at`` (s, or None) and ``stopped_by``.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a model, an argument is not a number / array / callable, or the controller returns
        something other than real numbers.
    ArgumentError
        If ``x0`` is not finite or not of shape ``(n,)``, ``t_final`` is not in ``[MIN_T_FINAL, MAX_T_FINAL]``,
        ``t_eval`` is unsorted or leaves ``[0, t_final]``, a tolerance or budget is out of range, the controller
        returns the wrong number of inputs, the right-hand side is not finite at ``x0``, or the ``stop``
        condition is already met at ``t = 0``.
    ModelError
        If ``model.rhs`` returns an array of the wrong shape.
    BudgetError
        If the run hits ``max_steps``, ``max_nfev`` or ``time_limit`` (unless ``on_budget="stop"``).
    SolverError
        If the integrator fails, the model's arithmetic fails, or the states become non-finite.
    """
    names, inputs = _check_model(model)
    n, m = len(names), len(inputs)
    x0 = checks.array("x0", x0, shape=(n,))
    tf, rtol, atol, budget = _check_common(t_final, method, rtol, atol, n, max_steps, max_nfev, time_limit,
                                           on_budget)
    if controller is not None:
        checks.function("controller", controller)
    if stop is not None:
        checks.function("stop", stop)
    bps = checks.array("breakpoints", breakpoints, ndim=1)
    if t_eval is None:
        te = np.linspace(0.0, tf, 2001)
    else:
        te = checks.array("t_eval", t_eval, ndim=1, min_size=1)
        if np.any(np.diff(te) < 0):
            raise ArgumentError("t_eval must be sorted in increasing order")
        slack = 1e-12 * tf
        if te[0] < -slack or te[-1] > tf + slack:
            outside = te[(te < -slack) | (te > tf + slack)]
            raise ArgumentError(f"t_eval has {outside.size} time(s) outside [0, t_final] = [0, {tf:g}] (e.g. "
                                f"{outside[0]:g}); simulate up to the last output time or drop those times")
        te = np.clip(te, 0.0, tf)

    if controller is None:
        zero = np.zeros(m)

        def ctrl(t: float, x: np.ndarray) -> np.ndarray:
            return zero
    else:
        def ctrl(t: float, x: np.ndarray) -> np.ndarray:
            return _input(controller(t, x), m, inputs, t)   # the user's exceptions pass through

    d0 = np.asarray(_model_rhs(model, x0, ctrl(0.0, x0), 0.0))
    if d0.shape != (n,):
        raise ModelError(f"{type(model).__name__}.rhs returned shape {d0.shape} for a state of shape ({n},)")
    if d0.dtype.kind not in "iufc" or not np.all(np.isfinite(d0)):
        raise ArgumentError(f"the right-hand side is not finite at t = 0, x0 = {x0.tolist()} ({d0.tolist()}): x0 "
                            "lies where the model is singular, or the controller returns non-finite inputs there")
    event = None
    if stop is not None:
        g0 = checks.real("stop(0, x0)", stop(0.0, x0))
        if g0 <= 0:
            raise ArgumentError(f"the stop condition is already met at t = 0 (stop(0, x0) = {g0:g} <= 0)")

        def event(t: float, y: np.ndarray) -> float:
            return float(stop(t, y))

    def fun(t: float, y: np.ndarray) -> Any:
        budget.evaluation()
        return _model_rhs(model, y, ctrl(t, y), t)

    switches = checks.array("controller.switch_times", getattr(controller, "switch_times", ()), ndim=1)
    cuts = sorted({0.0, tf, *[s for s in switches if 0 < s < tf], *[float(b) for b in bps if 0 < b < tf]})
    label = f"simulate({type(model).__name__})"
    ts, xs = [], []
    x = x0
    stopped_at, stopped_by = None, "t_final"
    for a, b in itertools.pairwise(cuts):
        last = b == cuts[-1]
        seg = _integrate(fun, a, b, x, method=method, rtol=rtol, atol=atol, budget=budget, dense=True,
                         event=event, what=label)
        if seg.reason is not None:
            stopped_at, stopped_by = seg.t, seg.reason
            if seg.reason != "stop" and on_budget == "raise":
                raise BudgetError(budget.message(seg.reason, label, seg.t))
            sel = te[(te >= a) & (te <= seg.t)]
        else:
            sel = te[(te >= a) & ((te <= b) if last else (te < b))]
        if sel.size and seg.interpolants:
            sol = OdeSolution(seg.t_steps, seg.interpolants)
            ts.append(sel)
            xs.append(np.atleast_2d(sol(sel).T))
        elif sel.size:      # stopped before the first step of the segment: only its start is known
            sel = sel[sel <= seg.t]
            ts.append(sel)
            xs.append(np.tile(seg.y, (sel.size, 1)))
        x = seg.y
        if stopped_at is not None:
            break
    t = np.concatenate(ts) if ts else np.empty(0)
    X = np.concatenate(xs) if xs else np.empty((0, n))
    U = np.array([ctrl(ti, xi) for ti, xi in zip(t, X, strict=True)]).reshape(len(t), m)
    vname = getattr(getattr(model, "vehicle", None), "name", "?")
    return Simulation(t, X, U, names, inputs, method, rtol, atol, budget.nfev, f"{type(model).__name__}({vname})",
                      stopped_at, _model_provenance(model), budget.steps, stopped_by)


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
    n_steps : int
        Integrator steps taken.
    stopped_at : float or None
        Time (s) the ensemble reached when a budget stopped it (``on_budget="stop"``); None: ran to ``t_final``.
    stopped_by : str
        ``"t_final"``, or the budget that was hit (``"max_steps"``, ``"max_nfev"``, ``"time_limit"``).
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
    n_steps: int = 0
    stopped_at: float | None = None
    stopped_by: str = "t_final"

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

        Raises
        ------
        GlidectlError
            For ``dims``, ``x_e`` or ``scale`` that do not fit the ensemble (see
            :func:`glidectl.plotting.plot_ensemble`).
        """
        from .plotting import plot_ensemble, style

        with style():
            return plot_ensemble(self, ax, dims=dims, x_e=x_e, tol=tol, scale=scale)


def simulate_many(model: Model, X0: Any, t_final: float, *, method: str = "RK45", rtol: float = 1e-6,
                  atol: float = 1e-9, freeze: Callable[[np.ndarray], np.ndarray] | None = None,
                  max_steps: int = MAX_STEPS, max_nfev: int | None = None, time_limit: float | None = None,
                  on_budget: str = "raise") -> Ensemble:
    """Integrate an input-free model from many initial states at once (one stacked, vectorized ODE).

    Intended for region-of-attraction studies (thousands of short runs). A trajectory for which ``freeze(x)`` is
    True stops evolving (its derivative is set to zero), so one diverging run (e.g. a glider whose speed tends to
    zero, where the model is singular) does not stall the others.

    Parameters
    ----------
    model : Model
        Model with ``input_names == ()``; ``rhs`` must accept a batch of states, shape (N, n).
    X0 : array_like, shape (N, n)
        Initial states, one per row, in the units of the model's states; finite.
    t_final : float
        Final time (s), in ``[MIN_T_FINAL, MAX_T_FINAL] = [1e-9, 1e9]``.
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp`; default ``"RK45"``.
    rtol, atol : float
        Relative (nondimensional) and absolute (state units) tolerances, applied to the stacked state.
    freeze : callable, optional
        ``x (N, n) -> bool (N,)``. Evaluated at every right-hand-side call (including the integrator's trial
        stages), and a trajectory once frozen stays frozen.
    max_steps, max_nfev, time_limit, on_budget :
        Budgets of the whole ensemble and what hitting one does, as in :func:`simulate` (with ``on_budget="stop"``
        ``x_final`` holds the states where the ensemble stopped, ``stopped_at`` the time).

    Returns
    -------
    Ensemble
        Initial and final states (model units), the frozen mask, ``t_final`` (s), the integrator settings, the
        number of steps and right-hand-side evaluations, ``stopped_at`` and ``stopped_by``.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a model or an argument has the wrong type.
    ArgumentError
        If ``X0`` is not a finite array of shape ``(N, n)``, the model has inputs, ``t_final`` is not in
        ``[MIN_T_FINAL, MAX_T_FINAL]``, a tolerance or budget is out of range, or ``freeze`` returns the wrong shape.
    ModelError
        If ``model.rhs`` returns an array of the wrong shape for the batch.
    BudgetError
        If the ensemble hits ``max_steps``, ``max_nfev`` or ``time_limit`` (unless ``on_budget="stop"``).
    SolverError
        If the integrator fails.
    """
    names, inputs = _check_model(model)
    n = len(names)
    X0 = checks.array("X0", X0, shape=(None, n), min_size=1)
    if inputs:
        raise ArgumentError(f"simulate_many is for input-free models; {type(model).__name__} has inputs {inputs} "
                            "(close the loop inside the model, e.g. gc.closed_loop)")
    tf, rtol, atol, budget = _check_common(t_final, method, rtol, atol, n, max_steps, max_nfev, time_limit,
                                           on_budget)
    N = X0.shape[0]
    atol_stacked = np.tile(atol, N) if isinstance(atol, np.ndarray) else atol

    def frozen_mask(X: np.ndarray) -> np.ndarray:
        mask = np.asarray(freeze(X))
        if mask.shape != (N,):
            raise ArgumentError(f"freeze must return one bool per trajectory, shape ({N},), got {mask.shape}")
        return mask.astype(bool)

    if freeze is not None:
        checks.function("freeze", freeze)
    frozen = np.zeros(N, dtype=bool) if freeze is None else frozen_mask(X0)
    with np.errstate(all="ignore"):
        d0 = np.asarray(_model_rhs(model, X0, None, 0.0))
    if d0.shape != X0.shape:
        raise ModelError(f"{type(model).__name__}.rhs returned shape {d0.shape} for a batch of shape {X0.shape}; "
                         "simulate_many needs a batch-capable right-hand side")

    def f(t: float, y: np.ndarray) -> np.ndarray:
        budget.evaluation()
        X = y.reshape(N, n)
        if freeze is not None:
            frozen[:] |= frozen_mask(X)
        d = np.array(_model_rhs(model, X, None, t), dtype=float)
        d[frozen] = 0.0
        return d.ravel()

    label = f"simulate_many({type(model).__name__}, {N} runs)"
    with np.errstate(all="ignore"):
        seg = _integrate(f, 0.0, tf, X0.ravel(), method=method, rtol=rtol, atol=atol_stacked, budget=budget,
                         dense=False, what=label)
    if seg.reason is not None and on_budget == "raise":
        raise BudgetError(budget.message(seg.reason, label, seg.t))
    XF = seg.y.reshape(N, n)
    vname = getattr(getattr(model, "vehicle", None), "name", "?")
    return Ensemble(X0, XF, frozen.copy(), tf, method, rtol, atol, budget.nfev, f"{type(model).__name__}({vname})",
                    names, _model_provenance(model), budget.steps, None if seg.reason is None else seg.t,
                    seg.reason or "t_final")
