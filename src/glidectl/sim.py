"""Simulation of glidectl models in open or closed loop (scipy's ``solve_ivp`` integrators).

Every run has budgets (:data:`MAX_STEPS` = 20 000 integrator steps, ``20 max_steps`` right-hand-side evaluations,
an optional wall-time limit): hitting one raises :class:`~glidectl.BudgetError`, or with ``on_budget="stop"``
returns the part computed, with ``stopped_by`` naming the budget. Spans shorter than :data:`MIN_T_FINAL` (1e-9) or
longer than :data:`MAX_T_FINAL` (1e9) are refused.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolution, OdeSolver, Radau
from scipy.optimize import brentq

from . import checks
from .errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, SolverError

__all__ = [
    "COMMAND_KINDS",
    "MAX_NFEV_PER_STEP",
    "MAX_STEPS",
    "MAX_T_FINAL",
    "MIN_T_FINAL",
    "ActuatedSimulation",
    "Ensemble",
    "Model",
    "Simulation",
    "actuator_trace",
    "saturated_mask",
    "simulate",
    "simulate_actuated",
    "simulate_many",
]

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
    x_end : ndarray, shape (n,), or None
        The state where the run ended (at ``stopped_at``, or at ``t_final``), whether or not an output time falls
        there.
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
    x_end: np.ndarray | None = None

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

#: One-step (Runge-Kutta) methods: a run restarted at every sensor sample carries their step size over the sample
#: (:func:`simulate_actuated`); multistep methods (LSODA, BDF) and Radau restart with their own first step.
_ONE_STEP = ("RK45", "RK23", "DOP853")


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
    last_step: float | None = None  # size of the last full step taken (s)


def _integrate(fun: Callable[[float, np.ndarray], Any], a: float, b: float, y: np.ndarray, *, method: str,
               rtol: float, atol: Any, budget: _Budget, dense: bool,
               event: Callable[[float, np.ndarray], float] | None = None, what: str = "simulation",
               first_step: float | None = None) -> _Segment:
    """Step a scipy ``OdeSolver`` from ``a`` to ``b`` (as :func:`~scipy.integrate.solve_ivp` does), checking the
    budgets after every step and a terminal, decreasing ``event`` (``> 0`` at ``a``); ``first_step`` (s), if given,
    is the solver's first step (its own estimate otherwise). The last step size taken is ``seg.last_step``."""
    seg = _Segment(a, y, [], [a], None)
    opts: dict[str, Any] = {} if first_step is None else {"first_step": min(first_step, b - a)}
    try:
        solver = _METHODS[method](fun, a, y, b, rtol=rtol, atol=atol, **opts)
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
        if solver.status != "finished":  # the step that ends on b is cut short by b
            seg.last_step = float(t_new - t_old)
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
    """``model.rhs(x, u)`` (``model.rhs(x, u, t=t)`` for a model whose ``time_varying`` is true, e.g. a glider in a
    current that changes in time), with the library's own arithmetic failures turned into :class:`SolverError`."""
    try:
        if getattr(model, "time_varying", False):
            return model.rhs(x, u, t=t)
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
                      stopped_at, _model_provenance(model), budget.steps, stopped_by, np.array(x, dtype=float))


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


# --------------------------------------------------------------------------------------------- actuated simulation
#: How :func:`simulate_actuated` reads a controller's output: position ``"setpoint"`` of each actuator (or a mapping
#: ``{"m0": ..., "r_P1": ...}``), the thesis inputs ``"acceleration"`` ``(w1, w3, w4)`` of (2.33), or requested
#: ``"rate"`` ``(r_P1_rate, r_P3_rate, m0_rate)``.
COMMAND_KINDS = ("setpoint", "acceleration", "rate")


def actuator_trace(run: Any, name: str, *, commanded: bool = False, rate: bool = False) -> np.ndarray:
    """One actuator's trajectory from an actuated run (``ActuatedSimulation``, ``DiveCycleRun``): achieved
    position, commanded position, or (``rate=True``) achieved or commanded rate.

    The run provides ``actuator_names``, ``state_names``, ``state(name)``, ``u`` (commanded rates), ``rates``
    (limited rates) and ``commanded`` (commanded positions). The achieved battery rate is the integrated mass
    velocity state (``rdot_P1``, ``rdot_P3``) when the model has it.

    Parameters
    ----------
    run : ActuatedSimulation or DiveCycleRun
    name : str
        Actuator (``"m0"``, ``"r_P1"``, ...).
    commanded, rate : bool
        Which trace.

    Returns
    -------
    ndarray, shape (len(run.t),)

    Raises
    ------
    ArgumentTypeError
        If ``name`` is not a string or a flag is not a bool.
    ArgumentError
        If ``name`` is not an actuator of the run.
    """
    if not isinstance(name, str):
        raise ArgumentTypeError(f"name must be an actuator name (str), got {type(name).__name__} {name!r}")
    checks.boolean("commanded", commanded)
    checks.boolean("rate", rate)
    if name not in run.actuator_names:
        raise ArgumentError(f"no actuator '{name}'; have {run.actuator_names}")
    i = run.actuator_names.index(name)
    if rate:
        if commanded:
            return run.u[:, i]
        vel = {"r_P1": "rdot_P1", "r_P3": "rdot_P3"}.get(name)
        return run.state(vel) if vel in run.state_names else run.rates[:, i]
    return run.commanded[:, i] if commanded else run.state(name)


@dataclass(frozen=True)
class ActuatedSimulation(Simulation):
    """A run of :func:`simulate_actuated`: a :class:`Simulation` of an actuated model (``u`` holds the requested
    actuator rates) plus the commanded and achieved actuator trajectories and the measured outputs.

    Attributes
    ----------
    actuator_names : tuple of str
        ``("r_P1", "r_P3", "m0")``.
    commanded : ndarray, shape (N, 3)
        Position command equivalent of the controller's request at each output time (m, m, kg): the setpoint for a
        setpoint controller, ``p + rate / k`` otherwise (:meth:`~glidectl.ActuatedGlider.position_command`).
    rates : ndarray, shape (N, 3)
        Limited rates the actuators were driven with (m/s, m/s, kg/s): ``m0' `` exactly; the velocity target of the
        mass servo for ``r_P1``, ``r_P3``.
    sensors : tuple of str
        Names of the measured outputs (states of the model).
    y : ndarray, shape (N, len(sensors))
        Measured outputs the controller saw (with noise).
    noise : dict of str to float
        Standard deviation of the noise of each noisy sensor (its unit).
    seed : int or None
        Seed of the noise generator (drawn and recorded when the caller gave none; None without noise).
    sensor_period : float
        Sample-and-hold period of the noise and sample period of a sampled-data controller (s); 0 without noise
        and without such a controller.
    command : str
        How the controller output was read (:data:`COMMAND_KINDS`).
    controller_states : tuple of str
        Names of a dynamic controller's states; ``xc`` holds them, shape (N, len(controller_states)).
    xc : ndarray
    lower, upper, rate_limit : ndarray, shape (3,)
        The actuator limits used (m, m, kg; m/s, m/s, kg/s).
    """

    actuator_names: tuple[str, ...] = ()
    commanded: np.ndarray | None = None
    rates: np.ndarray | None = None
    sensors: tuple[str, ...] = ()
    y: np.ndarray | None = None
    noise: dict[str, float] | None = None
    seed: int | None = None
    sensor_period: float = 0.0
    command: str = "setpoint"
    controller_states: tuple[str, ...] = ()
    xc: np.ndarray | None = None
    lower: np.ndarray | None = None
    upper: np.ndarray | None = None
    rate_limit: np.ndarray | None = None

    def actuator(self, name: str, *, commanded: bool = False, rate: bool = False) -> np.ndarray:
        """Trajectory of one actuator at the output times.

        Parameters
        ----------
        name : str
            ``"m0"`` (kg), ``"r_P1"`` or ``"r_P3"`` (m).
        commanded : bool
            False: achieved; True: commanded (position command equivalent, or the requested rate with ``rate``).
        rate : bool
            False: positions; True: rates (unit/s): achieved (``m0'``, the mass velocity ``rdot_P``) or requested.

        Returns
        -------
        ndarray, shape (N,)

        Raises
        ------
        ArgumentTypeError
            If ``name`` is not a string or a flag is not a bool.
        ArgumentError
            If ``name`` is not an actuator of the run.
        """
        return actuator_trace(self, name, commanded=commanded, rate=rate)

    @property
    def saturated(self) -> np.ndarray:
        """Per output time, whether an actuated axis is at a limit: its requested rate was cut by more than 1e-6 of
        the rate limit, or it is within 1e-3 of its range width from an end (bool, shape (N,))."""
        p = np.stack([self.state(n) for n in self.actuator_names], axis=1)
        return saturated_mask(self.u, self.rates, p, self.lower, self.upper, self.rate_limit)


def saturated_mask(requested: np.ndarray, rates: np.ndarray, positions: np.ndarray, lower: Any, upper: Any,
                   rate_limit: Any) -> np.ndarray:
    """Per row, whether an actuated axis is at a limit (:attr:`ActuatedSimulation.saturated`): its requested rate
    was cut by more than 1e-6 of the rate limit, or its position is within 1e-3 of its range width from an end.

    Parameters
    ----------
    requested, rates, positions : ndarray, shape (N, k)
        Requested and limited rates (unit/s) and positions (unit) of the ``k`` actuators.
    lower, upper, rate_limit : array_like, shape (k,)
        Their ranges and rate limits (a rate limit of 0 marks a fixed part, never saturated).

    Returns
    -------
    ndarray of bool, shape (N,)
    """
    lo, hi, R = (np.asarray(a, dtype=float) for a in (lower, upper, rate_limit))
    act = R > 0
    scale = np.where(np.isfinite(R), R, 1.0)
    cut = np.abs(requested - rates) > 1e-6 * scale
    width = np.where(np.isfinite(hi - lo), hi - lo, np.inf)
    with np.errstate(invalid="ignore"):
        end = (positions - lo <= 1e-3 * width) | (hi - positions <= 1e-3 * width)
    return np.any((cut | end) & act, axis=1)


def _command_kind(controller: Any, command: Any) -> str:
    if command != "auto":
        return str(checks.choice("command", command, (*COMMAND_KINDS, "auto")))
    declared = getattr(controller, "command", None)
    if isinstance(declared, str) and declared in COMMAND_KINDS:
        return declared
    inputs = getattr(controller, "inputs", None)
    if inputs == "acceleration":
        return "acceleration"
    if inputs == "force":
        raise ArgumentError("the controller was designed on the force inputs (u1, u3, u4); an actuated glider takes "
                            "setpoints, the thesis accelerations (w1, w3, w4) or rates: design it with "
                            "inputs='acceleration' (e.g. gc.lqr_glide(veh, glide, inputs='acceleration'))")
    return "auto"  # decided per call: a mapping is setpoints, an array needs a declared kind


def simulate_actuated(plant: Any, x0: Any, t_final: float, controller: Any = None, *, command: str = "auto",
                      sensors: Sequence[str] | None = None, noise: dict[str, float] | None = None,
                      seed: int | None = None, sensor_period: float = 1.0, t0: float = 0.0, t_eval: Any = None,
                      method: str = "LSODA", rtol: float = 1e-7, atol: float = 1e-10,
                      stop: Callable[[float, np.ndarray, np.ndarray], float] | None = None,
                      max_steps: int = MAX_STEPS, max_nfev: int | None = None, time_limit: float | None = None,
                      on_budget: str = "raise") -> ActuatedSimulation:
    """Simulate an actuated glider (:class:`~glidectl.ActuatedGlider`) under a controller that sees measured outputs.

    The actuator limits are enforced inside the model's right-hand side (never by clipping results). The controller
    is evaluated inside the right-hand side on the measured outputs ``y = x[sensors] + n``; the noise ``n`` is
    Gaussian, drawn from a seeded generator once per ``sensor_period`` and held over it (sample-and-hold; the
    integrator restarts at each sample). Without noise and without a sampled-data controller there are no samples
    and the controller acts continuously.

    Controllers:

    * static: ``controller(t, y) -> command``;
    * dynamic (e.g. a PID's integrator, an estimator): an object with ``controller_states`` (tuple of names),
      ``initial_state(t, y) -> xc0``, ``derivative(t, xc, y) -> xc'`` and ``controller(t, y, xc) -> command``;
      its states are integrated with the plant's;
    * sampled-data (a digital controller: e.g. a discrete-time Kalman filter and a zero-order hold): a dynamic
      controller that also has ``sample(t, xc, y) -> xc``. It is sampled every ``sensor_period`` from ``t0`` on
      (with or without noise): at each sample time ``t_k`` its state jumps to ``sample(t_k, xc, y_k)``, ``y_k`` the
      measurement of that sample (the first sample is at ``t0``, right after ``initial_state``); between samples it
      follows ``derivative`` (zero for a state that is only held). A command computed at the sample and kept in
      the controller's state is a zero-order hold: the integrator then sees a smooth right-hand side between
      samples.

    The command is read as ``command`` says (:data:`COMMAND_KINDS`); ``"auto"``: a mapping ``{"m0": c, ...}`` is
    setpoints (axes it omits keep their position), a controller with ``inputs == "acceleration"`` (an
    acceleration-form :class:`~glidectl.LinearGlideController`) gives ``(w1, w3, w4)``, one with a ``command``
    attribute says which. Setpoints go through the servo loops, accelerations and rates through the rate/range
    limiter (:class:`~glidectl.ActuatedGlider`).

    Parameters
    ----------
    plant : ActuatedGlider
    x0 : array_like, shape (11,)
        Initial state (SI units); actuators inside their ranges, the mass at a rest-compatible velocity.
    t_final : float
        Span simulated (s), in ``[MIN_T_FINAL, MAX_T_FINAL]``; the run covers ``[t0, t0 + t_final]``.
    controller : callable or dynamic controller, optional
        See above; default: hold every actuator where it is.
    command : {"auto", "setpoint", "acceleration", "rate"}
    sensors : sequence of str, optional
        Measured states, in the order the controller receives them; default every state (state feedback).
    noise : dict of str to float, optional
        Noise standard deviation of some sensors (their units), >= 0.
    seed : int, optional
        Seed of the noise (same seed, same noise); default a fresh one, recorded in the result.
    sensor_period : float
        Sample-and-hold period of the noise and sample period of a sampled-data controller (s), > 0.
    t0 : float
        Start time (s) (the controller sees absolute times).
    t_eval : array_like, optional
        Output times in ``[t0, t0 + t_final]`` (s); default 2001 evenly spaced.
    method, rtol, atol : integrator settings, as :func:`simulate` (tolerances in state units); a one-step method
        (``"RK23"``, ``"RK45"``, ``"DOP853"``) restarted at a sample starts with the step it had reached
    stop : callable, optional
        ``(t, x, y) -> float`` on the true state ``x`` and the measurement ``y``; the run ends where it falls through
        zero (``stopped_by = "stop"``). Must be positive at the start.
    max_steps, max_nfev, time_limit, on_budget : budgets, as :func:`simulate`

    Returns
    -------
    ActuatedSimulation
        States, requested rates (``u``), limited rates, position commands, measurements, controller states and the
        limits; ``actuator(name)`` gives positions.

    Raises
    ------
    ArgumentTypeError
        If ``plant`` is not an actuated model, the controller is not callable, or a value has the wrong type.
    ArgumentError
        Unknown sensors or noise keys, negative noise, a bad command kind or controller output, settings out of
        range, a stop condition met at the start.
    InfeasibleGlideError
        If ``x0`` has an actuator outside its range or moving too fast.
    BudgetError
        If a budget is hit (unless ``on_budget="stop"``).
    SolverError
        If the integrator fails or the states become non-finite.
    """
    needed = ("rhs", "limited_rates", "setpoint_rates", "acceleration_rates", "position_command", "check_state")
    if not all(callable(getattr(plant, a, None)) for a in needed):
        raise ArgumentTypeError(f"plant must be an actuated model (gc.ActuatedGlider(veh)), got {type(plant).__name__}")
    names, inputs = tuple(plant.state_names), tuple(plant.input_names)
    axes = tuple(plant.actuator_names)
    n = len(names)
    x0 = plant.check_state(x0)
    tf, rtol, atol, budget = _check_common(t_final, method, rtol, atol, n, max_steps, max_nfev, time_limit,
                                           on_budget)
    t0 = checks.real("t0", t0, unit="s")
    sens = tuple(names if sensors is None else sensors)
    for s in sens:
        if s not in names:
            raise ArgumentError(f"unknown sensor {s!r}; a sensor measures a state: {names}")
    idx = np.array([names.index(s) for s in sens], dtype=int)
    nz = dict(noise or {})
    if noise is not None and not isinstance(noise, dict):
        raise ArgumentTypeError(f"noise must be a dict of sensor name to standard deviation, got "
                                f"{type(noise).__name__}")
    sigma = np.zeros(len(sens))
    for k, v in nz.items():
        if k not in sens:
            raise ArgumentError(f"noise names {k!r}, which is not a sensor; sensors: {sens}")
        nz[k] = checks.nonnegative(f"noise[{k!r}]", v)
        sigma[sens.index(k)] = nz[k]
    noisy = bool(np.any(sigma > 0))
    T = checks.positive("sensor_period", sensor_period, unit="s")
    if controller is not None and not callable(controller):
        raise ArgumentTypeError(f"controller must be callable, got {type(controller).__name__}")
    cstates = tuple(getattr(controller, "controller_states", ()) or ())
    dynamic = bool(cstates)
    if dynamic and not all(callable(getattr(controller, a, None)) for a in ("initial_state", "derivative")):
        raise ArgumentTypeError("a controller with controller_states must define initial_state(t, y) and "
                                "derivative(t, xc, y)")
    sampled = dynamic and callable(getattr(controller, "sample", None))
    nc = len(cstates)
    if noisy:
        if seed is None:
            seed = int(np.random.SeedSequence().entropy % (2**63))
        seed = checks.integer("seed", seed, lo=0)
        count = math.floor(tf / T) + 2
        draws = np.random.default_rng(seed).standard_normal((count, len(sens))) * sigma
    else:
        seed, draws = None, np.zeros((1, len(sens)))
        if not sampled:
            T = 0.0
    kind = "setpoint" if controller is None else _command_kind(controller, command)
    if stop is not None:
        checks.function("stop", stop)

    def measure(x: np.ndarray, row: np.ndarray) -> np.ndarray:
        return x[idx] + row

    def rates(t: float, x: np.ndarray, y: np.ndarray, xc: np.ndarray) -> np.ndarray:
        if controller is None:
            return np.zeros(3)
        out = controller(t, y, xc) if dynamic else controller(t, y)
        k = kind
        if isinstance(out, dict):
            if k not in ("auto", "setpoint"):
                raise ArgumentError(f"the controller returned a mapping at t = {t:.6g}, but command = {kind!r}")
            bad = [a for a in out if a not in axes]
            if bad:
                raise ArgumentError(f"the controller commands unknown actuators {bad}; actuators: {axes}")
            c = plant.positions(x).copy()
            for a, v in out.items():
                c[axes.index(a)] = v
            return plant.setpoint_rates(x, c)
        if k == "auto":
            raise ArgumentError("the controller returned an array; say what it commands with command='setpoint', "
                                "'acceleration' (w1, w3, w4) or 'rate' (or give the controller a 'command' "
                                "attribute, or return a mapping of setpoints)")
        a = _input(out, 3, ("w1", "w3", "w4") if k == "acceleration" else axes, t)
        if k == "setpoint":
            return plant.setpoint_rates(x, a)
        if k == "acceleration":
            return plant.acceleration_rates(x, a)
        return a

    seg_row = draws[0]
    y0 = measure(x0, seg_row)
    xc0 = np.zeros(0)
    if dynamic:
        xc0 = checks.array("controller initial_state", controller.initial_state(t0, y0), shape=(nc,))

    def sample(t: float, x: np.ndarray, xc: np.ndarray, row: np.ndarray) -> np.ndarray:
        out = np.asarray(controller.sample(t, xc, measure(x, row)), dtype=float)
        if out.shape != (nc,) or not np.all(np.isfinite(out)):
            raise ArgumentError(f"the controller's sample(t, xc, y) returned {out!r} at t = {t:.6g}; it must return "
                                f"{nc} finite numbers, its states {cstates}")
        return out

    if sampled:
        xc0 = sample(t0, x0, xc0, seg_row)
    z0 = np.concatenate([x0, xc0])

    def fun(t: float, zz: np.ndarray) -> np.ndarray:
        budget.evaluation()
        x, xc = zz[:n], zz[n:]
        y = measure(x, seg_row)
        u = rates(t, x, y, xc)
        dx = _model_rhs(plant, x, u, t)
        if dynamic:
            return np.concatenate([dx, np.asarray(controller.derivative(t, xc, y), dtype=float).reshape(nc)])
        return np.asarray(dx, dtype=float)

    d0 = fun(t0, z0)
    budget.nfev = 0
    if not np.all(np.isfinite(d0)):
        raise ArgumentError(f"the right-hand side is not finite at t = {t0:g} (the controller returned non-finite "
                            "commands, or x0 lies where the model is singular)")
    event = None
    if stop is not None:
        g0 = checks.real("stop(t0, x0, y0)", stop(t0, x0, y0))
        if g0 <= 0:
            raise ArgumentError(f"the stop condition is already met at the start (stop = {g0:g} <= 0)")

        def event(t: float, zz: np.ndarray) -> float:
            return float(stop(t, zz[:n], measure(zz[:n], seg_row)))

    t_end = t0 + tf
    if t_eval is None:
        te = np.linspace(t0, t_end, 2001)
    else:
        te = checks.array("t_eval", t_eval, ndim=1, min_size=1)
        if np.any(np.diff(te) < 0):
            raise ArgumentError("t_eval must be sorted in increasing order")
        slack = 1e-12 * max(abs(t_end), tf)
        if te[0] < t0 - slack or te[-1] > t_end + slack:
            raise ArgumentError(f"t_eval must lie in [t0, t0 + t_final] = [{t0:g}, {t_end:g}]")
        te = np.clip(te, t0, t_end)
    if noisy or sampled:
        k_last = math.ceil(tf / T)
        cuts = sorted({t0, t_end, *[t0 + k * T for k in range(1, k_last) if t0 + k * T < t_end]})
    else:
        cuts = [t0, t_end]
    label = f"simulate_actuated({type(plant).__name__})"
    warm: float | None = None
    ts, zs, rows = [], [], []
    z = z0
    stopped_at, stopped_by = None, "t_final"
    for k, (a, b) in enumerate(itertools.pairwise(cuts)):
        seg_row = draws[min(k, len(draws) - 1)]
        last = k == len(cuts) - 2
        if sampled and k > 0:  # the sample at the start of the segment (the one at t0 is in z0)
            z = np.concatenate([z[:n], sample(a, z[:n], z[n:], seg_row)])
        if event is not None and k > 0 and event(a, z) <= 0:  # a new noise sample crossed the stop condition
            seg = _Segment(a, z, [], [a], "stop")
        else:
            seg = _integrate(fun, a, b, z, method=method, rtol=rtol, atol=atol, budget=budget, dense=True,
                             event=event, what=label, first_step=warm)
            if method in _ONE_STEP and seg.last_step is not None:
                warm = seg.last_step  # a one-step method restarts at the next sample with the step it had reached
        if seg.reason is not None:
            stopped_at, stopped_by = seg.t, seg.reason
            if seg.reason != "stop" and on_budget == "raise":
                raise BudgetError(budget.message(seg.reason, label, seg.t))
            sel = te[(te >= a) & (te <= seg.t)]
            if seg.reason == "stop" and (not sel.size or sel[-1] < seg.t):
                sel = np.append(sel, seg.t)  # the stop time is always an output time
        else:
            sel = te[(te >= a) & ((te <= b) if last else (te < b))]
        if sel.size and seg.interpolants:
            zs.append(np.atleast_2d(OdeSolution(seg.t_steps, seg.interpolants)(sel).T))
        elif sel.size:
            sel = sel[sel <= seg.t]
            zs.append(np.tile(seg.y, (sel.size, 1)))
        ts.append(sel)
        rows.append(np.tile(seg_row, (sel.size, 1)))
        z = seg.y
        if stopped_at is not None:
            break
    t = np.concatenate(ts) if ts else np.empty(0)
    Z = np.concatenate(zs) if zs else np.empty((0, n + nc))
    R = np.concatenate(rows) if rows else np.empty((0, len(sens)))
    X, XC = Z[:, :n], Z[:, n:]
    Y = X[:, idx] + R
    U = np.array([rates(ti, xi, yi, ci) for ti, xi, yi, ci in zip(t, X, Y, XC, strict=True)]).reshape(len(t), 3)
    S = plant.limited_rates(X, U) if len(t) else np.empty((0, 3))
    C = plant.position_command(X, U) if len(t) else np.empty((0, 3))
    vname = getattr(getattr(plant, "vehicle", None), "name", "?")
    return ActuatedSimulation(
        t, X, U, names, inputs, method, rtol, atol, budget.nfev, f"{type(plant).__name__}({vname})", stopped_at,
        _model_provenance(plant), budget.steps, stopped_by, actuator_names=axes, commanded=C, rates=S,
        sensors=sens, y=Y, noise=nz, seed=seed, sensor_period=T, command=kind, controller_states=cstates, xc=XC,
        lower=np.array(plant.lower, dtype=float), upper=np.array(plant.upper, dtype=float),
        rate_limit=np.array(plant.rate_limit, dtype=float))
