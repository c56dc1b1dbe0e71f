"""Approximate trajectory tracking of the CTOL aircraft by steady gliding, §7.3.2 (Theorem 6) and §7.3.3.

At each replanning instant ``t_k = k dt`` the aircraft at position ``p(t_k)`` is given the steady glide that flies
from ``p(t_k)`` to the desired position ``p_d(t_k + dt)`` in ``dt``: speed ``|p_d(t_k + dt) - p(t_k)| / dt`` and
flight-path angle ``atan2`` of that chord. Theorem 4 (:func:`glidectl.trim.ctol.ctol_glide`) gives ``alpha_e, k1,
k2`` and the controller (7.16)-(7.20) (:class:`glidectl.controllers.ctol.SteadyGlideController`) flies it until
``t_k + dt``. Each interval is integrated separately (the control switches at ``t_k``) with LSODA, which switches
to BDF where large ``k3, k4`` make the pitch loop stiff (a lightly damped pitch loop must be resolved: the printed
gains ring at 1522 rad/s, decaying at only ``k4 T / (2 J) = 125`` 1/s, so the ringing lasts the whole 0.1 s interval
and is part of the answer: it is in ``u2`` and in the force ``eps u2``). The implicit methods (LSODA's BDF phases,
``"BDF"``, ``"Radau"``) get the exact Jacobian of the closed loop (complex step of the one right-hand side,
:func:`glidectl.derivatives.jacobians`) instead of finite differences. With the printed gains LSODA, Radau and
BDF with that Jacobian agree (``bench/bench_ch7_integrators.py``; ``tests/test_ctol_stiff.py`` checks the first
interval against DOP853 at ``rtol = 1e-12``); scipy's Radau and BDF are slower here because the ringing must be
resolved whatever the method.

Metrics are computed on a grid that includes both ends of every interval, so the input jumps at ``t_k`` (the pitch
set-point ``theta_e`` changes discontinuously and ``w22`` of (7.20) jumps by ``(k3/eps) sin(delta theta_e)``) are
in the peaks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from itertools import product
from typing import Any, ClassVar

import numpy as np
from scipy.integrate import solve_ivp

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, InfeasibleGlideError, ModelError, SolverError
from ..models._validate import require_ctol_vehicle, require_instance
from ..models.ctol import CTOLAircraft
from ..params import Vehicle
from ..trim.ctol import ALPHA_MAX, CTOLGlide, ctol_glide
from .ctol import SteadyGlideController
from .ctol_runs import TrackingRun
from .ctol_trajectory import ClimbTrajectory

__all__ = ["MAX_GRID_POINTS", "MAX_INTERVALS", "MAX_NFEV", "GlideTracking", "ParetoStudy", "pareto_front",
           "track_with_steady_glides", "tracking_grid"]

#: Largest number of replanning intervals ``ceil(t_final / dt)`` of :func:`track_with_steady_glides`.
MAX_INTERVALS = 1_000_000
#: Default budget of right-hand-side evaluations of one :func:`track_with_steady_glides` run (all intervals).
MAX_NFEV = 20_000_000
#: Largest number of runs of :func:`tracking_grid` (``len(dts) * len(gains)``).
MAX_GRID_POINTS = 10_000
_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")
_NO_INPUT = np.zeros(0)


class _OutOfBudget(Exception):
    """Raised inside the integrand when the evaluation budget is spent (turned into :class:`BudgetError`)."""


@dataclass(frozen=True)
class GlideTracking:
    """A tracking run by steady gliding: the common :class:`TrackingRun` (time histories, metrics) plus the glide
    of each replanning interval and the settings.

    Attributes
    ----------
    run : TrackingRun
        ``run.t`` holds each replanning instant twice (end of one interval, start of the next) so the input jumps
        are in the peaks; ``run.stopped_at`` is set when a replanning step found no steady glide or the integration
        failed (``run.note`` says why).
    glides : tuple of CTOLGlide
        The steady glide of each interval.
    dt, k3, k4, T : float
        Settings.
    """

    run: TrackingRun
    glides: tuple[CTOLGlide, ...] = field(repr=False)
    dt: float
    k3: float
    k4: float
    T: float

    # the run's histories and metrics, for convenience
    t = property(lambda self: self.run.t, doc="``run.t``")
    x = property(lambda self: self.run.x, doc="``run.x``")
    u = property(lambda self: self.run.u, doc="``run.u``")
    error = property(lambda self: self.run.error, doc="``run.error``")
    max_error = property(lambda self: self.run.max_error, doc="``run.max_error``")
    peak_u1 = property(lambda self: self.run.peak_u1, doc="``run.peak_u1``")
    peak_u2 = property(lambda self: self.run.peak_u2, doc="``run.peak_u2``")
    rms_u1 = property(lambda self: self.run.rms_u1, doc="``run.rms_u1``")
    rms_u2 = property(lambda self: self.run.rms_u2, doc="``run.rms_u2``")
    effort = property(lambda self: self.run.effort, doc="``run.effort``")
    note = property(lambda self: self.run.note, doc="``run.note``")
    stopped_at = property(lambda self: self.run.stopped_at, doc="``run.stopped_at``")
    completed = property(lambda self: self.run.completed, doc="``run.completed``")
    method = property(lambda self: self.run.method, doc="``run.method``")

    def plot(self, ax: Any = None, **kw: Any) -> Any:
        """``run.plot(ax, **kw)``: position error and inputs versus time (:meth:`TrackingRun.plot`)."""
        return self.run.plot(ax, **kw)


def _level_start(veh: Vehicle, traj: ClimbTrajectory) -> np.ndarray:
    return ctol_glide(veh, traj.speed, 0.0).full_state((0.0, 0.0))


def track_with_steady_glides(veh: Vehicle, traj: ClimbTrajectory, *, dt: float = 0.1, k3: float = 7e5,
                             k4: float = 2.5e2, T: float = 1.0, t_final: float = 40.0, x0: Any = None,
                             alpha_max: float = ALPHA_MAX, method: str = "LSODA",
                             rtol: float = 1e-8, atol: float = 1e-10, max_nfev: int = MAX_NFEV,
                             time_limit: float | None = None) -> GlideTracking:
    """Track ``traj`` with steady glides replanned every ``dt`` seconds (§7.3.2).

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``dc8_ctol``).
    traj : ClimbTrajectory
        Desired trajectory (:func:`glidectl.controllers.ctol_trajectory.climb_trajectory`).
    dt : float
        Replanning interval (s); the thesis uses 0.1.
    k3, k4, T : float
        Pitch gains and reference time of (7.20); §7.3.3 prints ``k3 = 7 exp(5)``, ``k4 = 2.5 exp(2)`` (read as
        7e5 and 2.5e2; the literal 7 e^5 = 1038.9 and 2.5 e^2 = 18.47 are the other reading).
    t_final : float
        End time (s).
    x0 : array (6,), optional
        Initial state; default the level steady glide at the trajectory speed at (0, 0) (§7.3.3).
    alpha_max : float
        Passed to :func:`ctol_glide` (rad, in ``(0, pi/2)``).
    method, rtol, atol
        :func:`scipy.integrate.solve_ivp` settings per interval (``rtol`` in ``[1e-14, 1)``, ``atol > 0``).
    max_nfev : int
        Budget of right-hand-side evaluations over the whole run (default :data:`MAX_NFEV`); the number of
        intervals ``ceil(t_final / dt)`` is at most :data:`MAX_INTERVALS`.
    time_limit : float, optional
        Wall-time budget (s); default none.

    Returns
    -------
    GlideTracking
        ``completed = False`` (with the reason in ``note``) if a replanning step has no physical steady glide or
        the integration fails; the run up to that time is returned.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory, or a number has the wrong type.
    ArgumentError
        If ``dt``, ``k3``, ``k4``, ``T`` or ``t_final`` is not a positive finite number, ``dt > t_final``, there
        would be more than :data:`MAX_INTERVALS` intervals, ``x0`` is not six finite numbers, ``alpha_max``,
        ``method``, a tolerance or a budget is out of range.
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0``.
    InfeasibleGlideError
        If ``x0`` is omitted and there is no level steady glide at the trajectory speed (the default start).
    BudgetError
        If the run spends ``max_nfev`` right-hand-side evaluations or ``time_limit`` seconds.
    SolverError
        If the very first replanning interval fails (no steady glide or failed integration), so there is no run.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> run = gc.track_with_steady_glides(veh, gc.climb_trajectory(veh), dt=1.0, k3=10.0, k4=10.0, t_final=10.0)
    >>> run.completed, f"max error {run.max_error:.3f} m"
    (True, 'max error 0.159 m')
    """
    require_ctol_vehicle(veh, "veh")
    require_instance("traj", traj, ClimbTrajectory, " (from gc.climb_trajectory)")
    t_final = checks.positive("t_final", t_final, unit="s")
    dt = checks.real("dt", dt, lo=0.0, hi=t_final, lo_open=True, unit="s")
    if t_final / dt > MAX_INTERVALS:
        raise ArgumentError(f"t_final / dt = {t_final / dt:.3g} replanning intervals; at most {MAX_INTERVALS} are "
                            "allowed (raise dt)")
    if not veh.epsilon > 0:
        raise ModelError(f"vehicle '{veh.name}' has epsilon = {veh.epsilon:g}: the steady-glide law divides by eps")
    k3, k4, T = (checks.positive(n, v) for n, v in (("k3", k3), ("k4", k4), ("T", T)))
    alpha_max = checks.real("alpha_max", alpha_max, lo=0.0, hi=math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    checks.choice("method", method, _METHODS)
    rtol = checks.real("rtol", rtol, lo=1e-14, hi=1.0, hi_open=True)
    atol = checks.positive("atol", atol)
    max_nfev = checks.integer("max_nfev", max_nfev, lo=1)
    deadline = checks.Deadline(time_limit, "tracking by steady gliding")
    model = CTOLAircraft(veh)
    x = _level_start(veh, traj) if x0 is None else checks.array("x0", x0, shape=(6,))
    n = math.ceil(t_final / dt - 1e-9)
    spent = [0]
    ts, xs, us, glides = [], [], [], []
    note, completed = "", True
    quad = np.zeros(3)  # exact integrals of u1^2, u2^2, |u|^2 (quadrature states)
    for k in range(n):
        tk, tk1 = k * dt, min((k + 1) * dt, t_final)
        target = traj.position(tk1)
        chord = target - x[:2]
        V = float(np.hypot(*chord)) / (tk1 - tk)
        gam = float(math.atan2(chord[1], chord[0]))
        try:
            glide = ctol_glide(veh, V, gam, alpha_max=alpha_max)
        except (InfeasibleGlideError, ModelError, ArgumentError, SolverError) as exc:
            note, completed = f"t = {tk:.3f} s: no steady glide to the next waypoint ({exc})", False
            break
        ctrl = SteadyGlideController(veh, glide, k3, k4, T)
        try:
            with np.errstate(all="ignore"):
                kw = {"jac": _closed_loop_jacobian(model, ctrl)} if method in _IMPLICIT else {}
                sol = solve_ivp(_with_quadrature(model, ctrl, spent, max_nfev, deadline), (tk, tk1),
                                np.r_[x, 0.0, 0.0, 0.0], method=method, rtol=rtol, atol=atol, **kw)
        except _OutOfBudget as exc:
            raise BudgetError(f"tracking by steady gliding stopped at t = {tk:.3f} s: {exc}; raise max_nfev, or use "
                              "smaller pitch gains k3, k4 (a stiff, lightly damped pitch loop is expensive)") from None
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            note, completed = f"t = {tk:.3f} s: integration failed ({sol.message})", False
            break
        X = sol.y[:6].T
        ts.append(sol.t)
        xs.append(X)
        us.append(ctrl(0.0, X))
        quad += sol.y[6:, -1]
        glides.append(glide)
        x = X[-1]
    if not ts:
        raise SolverError(f"tracking could not start: {note}")
    t = np.concatenate(ts)
    X = np.concatenate(xs)
    U = np.concatenate(us)
    err = X[:, :2] - traj.position(t)
    method_name = f"steady gliding (dt = {dt:g}, k3 = {k3:g}, k4 = {k4:g}, T = {T:g})"
    span = float(t[-1] - t[0])
    run = TrackingRun.from_arrays(method_name, t, X, U, err, note=note or "completed",
                                  stopped_at=None if completed else float(t[-1]),
                                  mean_squares=tuple(float(q) / span for q in quad))
    return GlideTracking(run, tuple(glides), float(dt), float(k3), float(k4), float(T))


def _augmented(model: CTOLAircraft, ctrl: SteadyGlideController, z: Any) -> Any:
    """Closed-loop right-hand side augmented with ``d/dt (int u1^2, int u2^2, int |u|^2)`` for states ``z`` of shape
    ``(..., 9)`` (batch- and complex-safe: the one model rhs and the one control law)."""
    x = z[..., :6]
    u = ctrl.u(x)
    if u.ndim == 1 and u.dtype.kind == "f":  # one real state (the solvers' calls): scalar squares, same values
        u1, u2 = u.tolist()
        q1, q2 = u1 * u1, u2 * u2
        out = np.empty(9)
        out[:6] = model.rhs(x, u)
        out[6], out[7], out[8] = q1, q2, q1 + q2
        return out
    sq = u * u
    return np.concatenate([model.rhs(x, u), sq, sq[..., :1] + sq[..., 1:]], axis=-1)


def _with_quadrature(model: CTOLAircraft, ctrl: SteadyGlideController, spent: list[int], max_nfev: int,
                     deadline: checks.Deadline) -> Any:
    """Closed-loop right-hand side augmented with ``d/dt (int u1^2, int u2^2, int |u|^2)``, counting evaluations."""

    def f(t: float, z: np.ndarray) -> np.ndarray:
        spent[0] += 1
        if spent[0] > max_nfev:
            raise _OutOfBudget(f"it used its budget of max_nfev = {max_nfev} right-hand-side evaluations")
        if spent[0] % 1000 == 0:
            deadline.check(f"t = {t:.6g} s")
        return _augmented(model, ctrl, z)

    return f


def _closed_loop_jacobian(model: CTOLAircraft, ctrl: SteadyGlideController) -> Any:
    """``jac(t, z)``: the exact (complex-step, :func:`glidectl.derivatives.jacobians`) Jacobian of the
    augmented closed-loop right-hand side ``(9, 9)``, for the implicit methods of :func:`solve_ivp`."""

    def jac(t: float, z: np.ndarray) -> np.ndarray:
        return jacobians(lambda X, U: _augmented(model, ctrl, X), z, _NO_INPUT)[0]

    return jac


def _run_point(args: tuple[Vehicle, ClimbTrajectory, float, float, float, float, float]) -> dict[str, Any]:
    veh, traj, dt, k3, k4, T, t_final = args
    r = track_with_steady_glides(veh, traj, dt=dt, k3=k3, k4=k4, T=T, t_final=t_final)
    return {"dt": dt, "k3": k3, "k4": k4, **r.run.as_dict()}


@dataclass(frozen=True)
class ParetoStudy:
    """Tracking error against control effort over a grid of ``(dt, k3, k4)``.

    ``records`` has one dict per grid point (settings, ``completed``, ``max_error`` (m), ``effort`` (time-RMS
    ``||u||``), RMS and peak ``|u1|``, ``|u2|``); ``front`` indexes the completed runs not dominated in
    ``(max_error, effort)``, sorted by effort.

    Attributes
    ----------
    records : tuple of dict
        One per ``(dt, k3, k4)`` grid point: ``dt`` (s), ``k3`` (N), ``k4`` (N m) and the
        :meth:`TrackingRun.as_dict` metrics (errors in m, thrust ``u1`` in N, elevator moment ``u2`` in N m).
    front : tuple of int
        Indices into ``records`` of the Pareto-optimal completed runs, sorted by effort.
    t_final : float
        Horizon of every run (s).
    """

    records: tuple[dict[str, Any], ...]
    front: tuple[int, ...]
    t_final: float

    def front_records(self) -> list[dict[str, Any]]:
        """The records on the Pareto front, sorted by effort.

        Returns
        -------
        list of dict
            ``[records[i] for i in front]``.
        """
        return [self.records[i] for i in self.front]

    TABLE_HEADER: ClassVar[tuple[str, ...]] = ("dt [s]", "k3", "k4", "completed", "max |e| [m]", "effort",
                                                "peak |u2|", "front")
    """Column names of :meth:`table_rows`."""

    def table_rows(self) -> list[list[str]]:
        """One row of text per grid point, as :data:`TABLE_HEADER`: the settings, whether the run completed (else
        when it stopped), max position error (m), effort (time-RMS ``||u||``), peak ``|u2|`` (N m), and ``*`` for the
        points on the front.

        Returns
        -------
        list of list of str
            In the order of :attr:`records`; numbers to 3 significant digits (settings with ``%g``).

        Raises
        ------
        ArgumentError
            If a record lacks one of the keys of :func:`tracking_grid`'s records (a hand-built study).
        """
        rows = []
        try:
            for i, r in enumerate(self.records):
                rows.append([f"{r['dt']:g}", f"{r['k3']:g}", f"{r['k4']:g}", "yes" if r["completed"] else
                             f"no ({r['stopped_at']:.1f} s)", f"{r['max_error']:.3g}", f"{r['effort']:.3g}",
                             f"{r['peak_u2']:.3g}", "*" if i in self.front else ""])
        except KeyError as exc:
            raise ArgumentError(f"ParetoStudy record {len(rows)} has no {exc}: records must be those of "
                                "tracking_grid") from exc
        return rows

    def plot(self, ax: Any = None) -> Any:
        """Draw max position error against control effort for the completed runs, with the Pareto front, in the
        glidectl style (:func:`glidectl.plotting.plot_pareto_study`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into, effort (time-RMS ``||u||``) across and max position error (m) up, each on a log
            scale when it spans a decade; default a new figure.

        Returns
        -------
        matplotlib.axes.Axes
            A marker per completed run (colour: gains, shape: ``dt``, filled on the front) and the front as a line.
        """
        from ..plotting import plot_pareto_study, style

        with style():
            return plot_pareto_study(self, ax)


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points not dominated in both coordinates (smaller is better), sorted by the second.

    Parameters
    ----------
    points : sequence of (float, float)
        The points, e.g. ``(max position error (m), control effort)``; any units, compared per coordinate.

    Returns
    -------
    list of int
        Indices of the non-dominated points (a point is dominated when another is ``<=`` in both coordinates and
        ``<`` in one; equal points are all kept), sorted by the second coordinate, then the first.

    Raises
    ------
    ArgumentTypeError
        If ``points`` is not real numbers.
    ArgumentError
        If the points are not finite pairs (an array of shape ``(N, 2)``; ``N = 0`` gives ``[]``).

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.pareto_front([(1.0, 5.0), (2.0, 2.0), (3.0, 3.0), (4.0, 1.0)])    # (3, 3) is dominated by (2, 2)
    [3, 1, 0]
    """
    pts = checks.array("points", points)
    if pts.size == 0:
        return []
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ArgumentError(f"points must be pairs, an array of shape (N, 2); got shape {pts.shape}")
    keep = []
    for i, p in enumerate(pts):
        dominated = np.any(np.all(pts <= p, axis=1) & np.any(pts < p, axis=1))
        if not dominated:
            keep.append(i)
    return sorted(keep, key=lambda i: (pts[i, 1], pts[i, 0]))


def tracking_grid(veh: Vehicle, traj: ClimbTrajectory, dts: Sequence[float], gains: Sequence[tuple[float, float]],
                  *, T: float = 1.0, t_final: float = 40.0, executor: Executor | None = None) -> ParetoStudy:
    """Run :func:`track_with_steady_glides` for every replanning interval in ``dts`` and every pitch-gain pair
    ``(k3, k4)`` in ``gains`` (optionally on an executor) and extract the Pareto front of ``(max position error,
    control effort)`` among the completed runs.

    ``gains`` is a list of pairs rather than a product because useful ``k4`` scale with ``sqrt(k3 / eps)`` (the
    pitch loop's natural frequency); lightly damped pairs with large ``k3`` are also the expensive ones to simulate.

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``dc8_ctol``).
    traj : ClimbTrajectory
        Desired trajectory.
    dts : sequence of float
        Replanning intervals (s).
    gains : sequence of (float, float)
        Pitch-gain pairs ``(k3, k4)`` of (7.20) (N, N m).
    T : float
        Reference time of (7.11) (s).
    t_final : float
        Horizon of every run (s).
    executor : concurrent.futures.Executor, optional
        Runs the grid points in parallel (``executor.map``).

    The grid has at most :data:`MAX_GRID_POINTS` runs, each bounded by the budgets of
    :func:`track_with_steady_glides`.

    Returns
    -------
    ParetoStudy
        One record per ``(dt, (k3, k4))`` and the Pareto front of the completed runs.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory, ``executor`` has no ``map``, or ``dts``,
        ``gains`` are not real numbers.
    ArgumentError
        If ``dts`` or ``gains`` is empty, a ``dt`` or gain is not a positive finite number, ``gains`` is not pairs,
        the grid has more than :data:`MAX_GRID_POINTS` runs, or a run's settings are invalid (see
        :func:`track_with_steady_glides`).
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0``.
    InfeasibleGlideError
        If there is no level steady glide at the trajectory speed (the default start of every run).
    BudgetError
        If a run spends its evaluation budget (see :func:`track_with_steady_glides`).
    SolverError
        If a run fails in its first replanning interval (one such run aborts the whole grid).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> study = gc.tracking_grid(veh, gc.climb_trajectory(veh), dts=[0.5, 1.0], gains=[(10.0, 10.0), (10.0, 5.0)],
    ...                          t_final=10.0)
    >>> len(study.records), [(r["dt"], r["k3"], r["k4"]) for r in study.front_records()]    # the Pareto front
    (4, [(0.5, 10.0, 10.0)])
    """
    require_ctol_vehicle(veh, "veh")
    require_instance("traj", traj, ClimbTrajectory, " (from gc.climb_trajectory)")
    d_arr = checks.array("dts", dts, ndim=1)
    g_arr = checks.array("gains", gains)
    if d_arr.size == 0 or g_arr.size == 0:
        raise ArgumentError("tracking_grid needs at least one dt and one (k3, k4) pair")
    if g_arr.ndim != 2 or g_arr.shape[1] != 2:
        raise ArgumentError(f"gains must be (k3, k4) pairs, an array of shape (N, 2); got shape {g_arr.shape}")
    if not (np.all(d_arr > 0) and np.all(g_arr > 0)):
        raise ArgumentError("every dt (s) and gain k3 (N), k4 (N m s) must be positive")
    if d_arr.size * g_arr.shape[0] > MAX_GRID_POINTS:
        raise ArgumentError(f"the grid has {d_arr.size * g_arr.shape[0]} runs; at most {MAX_GRID_POINTS} are allowed")
    T, t_final = checks.positive("T", T, unit="s"), checks.positive("t_final", t_final, unit="s")
    if executor is not None and not callable(getattr(executor, "map", None)):
        raise ArgumentTypeError(f"executor must have a map method (concurrent.futures.Executor), got "
                                f"{type(executor).__name__}")
    pairs = [(float(a), float(b)) for a, b in g_arr]
    args = [(veh, traj, float(d), k3, k4, T, t_final) for d, (k3, k4) in product(d_arr, pairs)]
    recs = list(executor.map(_run_point, args)) if executor is not None else [_run_point(a) for a in args]
    ok = [i for i, r in enumerate(recs) if r["completed"]]
    front = [ok[j] for j in pareto_front([(recs[i]["max_error"], recs[i]["effort"]) for i in ok])] if ok else []
    return ParetoStudy(tuple(recs), tuple(front), float(t_final))
