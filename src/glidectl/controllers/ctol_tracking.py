"""Approximate trajectory tracking of the CTOL aircraft by steady gliding, §7.3.2 (Theorem 6) and §7.3.3.

At each replanning instant ``t_k = k dt`` the aircraft at position ``p(t_k)`` is given the steady glide that flies
from ``p(t_k)`` to the desired position ``p_d(t_k + dt)`` in ``dt``: speed ``|p_d(t_k + dt) - p(t_k)| / dt`` and
flight-path angle ``atan2`` of that chord. Theorem 4 (:func:`glidectl.trim.ctol.ctol_glide`) gives ``alpha_e, k1,
k2`` and the controller (7.16)-(7.20) (:class:`glidectl.controllers.ctol.SteadyGlideController`) flies it until
``t_k + dt``. Each interval is integrated separately (the control switches at ``t_k``) with LSODA, which switches
to BDF where large ``k3, k4`` make the pitch loop stiff (a lightly damped pitch loop must be resolved: the printed
gains ring at 1522 rad/s).

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
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .._checks import positive_number
from ..errors import GlidectlError, InfeasibleGlideError, ModelError
from ..models.ctol import CTOLAircraft
from ..params import Vehicle
from ..trim.ctol import ALPHA_MAX, CTOLGlide, ctol_glide
from .ctol import SteadyGlideController
from .ctol_runs import TrackingRun
from .ctol_trajectory import ClimbTrajectory

__all__ = ["GlideTracking", "ParetoStudy", "pareto_front", "track_with_steady_glides", "tracking_grid"]


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
                             rtol: float = 1e-8, atol: float = 1e-10) -> GlideTracking:
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
        Passed to :func:`ctol_glide`.
    method, rtol, atol
        :func:`scipy.integrate.solve_ivp` settings per interval.

    Returns
    -------
    GlideTracking
        ``completed = False`` (with the reason in ``note``) if a replanning step has no physical steady glide or
        the integration fails; the run up to that time is returned.

    Raises
    ------
    ModelError
        If ``dt``, ``k3``, ``k4``, ``T`` or ``t_final`` is not a positive finite number, ``veh`` is not a CTOL
        aircraft or has ``epsilon <= 0``, or ``x0`` is not six finite numbers.
    InfeasibleGlideError
        If ``x0`` is omitted and there is no level steady glide at the trajectory speed (the default start).
    GlidectlError
        If the very first replanning interval fails (no steady glide or failed integration), so there is no run.
    """
    for name, v in (("dt", dt), ("k3", k3), ("k4", k4), ("T", T), ("t_final", t_final)):
        positive_number(name, v)
    model = CTOLAircraft(veh)
    x = _level_start(veh, traj) if x0 is None else np.asarray(x0, dtype=float)
    if x.shape != (6,) or not np.all(np.isfinite(x)):
        raise ModelError(f"x0 must be six finite numbers {model.state_names}, got {x0!r}")
    n = math.ceil(t_final / dt - 1e-9)
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
        except (InfeasibleGlideError, ModelError) as exc:
            note, completed = f"t = {tk:.3f} s: no steady glide to the next waypoint ({exc})", False
            break
        ctrl = SteadyGlideController(veh, glide, float(k3), float(k4), float(T))
        sol = solve_ivp(_with_quadrature(model, ctrl), (tk, tk1), np.r_[x, 0.0, 0.0, 0.0], method=method,
                        rtol=rtol, atol=atol)
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
        raise GlidectlError(f"tracking could not start: {note}")
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


def _with_quadrature(model: CTOLAircraft, ctrl: SteadyGlideController) -> Any:
    """Closed-loop right-hand side augmented with ``d/dt (int u1^2, int u2^2, int |u|^2)``."""

    def f(t: float, z: np.ndarray) -> np.ndarray:
        u = ctrl(t, z[:6])
        return np.r_[model.rhs(z[:6], u), u[0] ** 2, u[1] ** 2, u[0] ** 2 + u[1] ** 2]

    return f


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
        return [self.records[i] for i in self.front]

    def plot(self, ax: Any = None) -> Any:
        """Draw max position error against control effort for the completed runs, with the Pareto front, in the
        glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_pareto_study`.
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
    ValueError
        If ``points`` cannot be converted to a float array.
    IndexError
        If the points are not pairs (array of shape ``(N, 2)``).
    """
    pts = np.asarray(points, dtype=float)
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

    Returns
    -------
    ParetoStudy
        One record per ``(dt, (k3, k4))`` and the Pareto front of the completed runs.

    Raises
    ------
    ModelError
        If ``dts`` or ``gains`` is empty, or a run's settings or vehicle are invalid (see
        :func:`track_with_steady_glides`).
    InfeasibleGlideError
        If there is no level steady glide at the trajectory speed (the default start of every run).
    GlidectlError
        If a run fails in its first replanning interval (one such run aborts the whole grid).
    """
    pairs = [(float(a), float(b)) for a, b in gains]
    if not dts or not pairs:
        raise ModelError("tracking_grid needs at least one dt and one (k3, k4) pair")
    args = [(veh, traj, float(d), k3, k4, float(T), float(t_final)) for d, (k3, k4) in product(dts, pairs)]
    recs = list(executor.map(_run_point, args)) if executor is not None else [_run_point(a) for a in args]
    ok = [i for i, r in enumerate(recs) if r["completed"]]
    front = [ok[j] for j in pareto_front([(recs[i]["max_error"], recs[i]["effort"]) for i in ok])] if ok else []
    return ParetoStudy(tuple(recs), tuple(front), float(t_final))
