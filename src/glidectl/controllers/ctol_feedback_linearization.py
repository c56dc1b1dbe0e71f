"""Feedback linearization of the CTOL aircraft on the §7.3.3 climb (§7.3.1, (7.80)-(7.84)) and its blow-up.

The linearizing inputs (7.80)-(7.81), the outer loop (7.82)-(7.83) and the zero dynamics (7.84) are in
:mod:`glidectl.controllers.ctol_zero_dynamics` (shared with the other exact-tracking baselines). The zero dynamics in
level flight is a saddle, so the internal dynamics of the feedback-linearized aircraft diverges from the §7.3.3
level-flight start: :func:`feedback_linearization_blowup` measures the divergence against the bounded reference of
the stable inversion (:mod:`glidectl.controllers.ctol_stable_inversion`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, SolverError
from ..models._validate import require_instance
from ..models.ctol import CTOLAircraft
from ..params import Vehicle
from .ctol_runs import TrackingRun, simulate_window
from .ctol_stable_inversion import StableInversion, stable_inversion
from .ctol_trajectory import ClimbTrajectory, climb_trajectory
from .ctol_zero_dynamics import (
    ZeroDynamics,
    feedback_linearizing_inputs,
    frozen_internal_dynamics,
    level_flight_state,
    outer_loop_acceleration,
    require_inversion_vehicle,
    zero_dynamics,
)

__all__ = ["BlowUp", "FeedbackLinearizingController", "feedback_linearization_blowup"]


@dataclass(frozen=True)
class FeedbackLinearizingController:
    """(7.80)-(7.81) with the outer loop ``w = p_d'' + kd (p_d' - p') + kp (p_d - p)`` (7.82)-(7.83).

    The default ``kp = 1, kd = 2`` place both error poles of each axis at ``-1 1/s`` (``(s + 1)^2``).

    Parameters
    ----------
    vehicle : Vehicle
    trajectory : ClimbTrajectory
        Desired ``p_d(t)``.
    kp : float
        Position gain (1/s^2).
    kd : float
        Velocity gain (1/s).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``trajectory`` not a ClimbTrajectory or a gain not a real number.
    ArgumentError
        If ``kp`` or ``kd`` is not a positive finite number.
    ModelError
        If ``vehicle`` is not a CTOL aircraft with ``epsilon != 0``.
    """

    vehicle: Vehicle
    trajectory: ClimbTrajectory
    kp: float = 1.0
    kd: float = 2.0
    _desired: ClimbTrajectory = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        require_inversion_vehicle(self.vehicle)
        require_instance("trajectory", self.trajectory, ClimbTrajectory, " (from gc.climb_trajectory)")
        object.__setattr__(self, "kp", checks.positive("kp", self.kp, unit="1/s^2"))
        object.__setattr__(self, "kd", checks.positive("kd", self.kd, unit="1/s"))
        object.__setattr__(self, "_desired", self.trajectory)

    def outer(self, t: Any, x: Any) -> Any:
        """``w(t, x)`` (m/s^2), shape ``(..., 2)``; ``x`` may be complex, ``t`` an array broadcasting with
        ``x[..., 0]``."""
        return outer_loop_acceleration(self._desired, self.kp, self.kd, t, x)

    def __call__(self, t: float, x: Any) -> np.ndarray:
        """Inputs ``(u1, u2)`` (N, N m) at time ``t`` (s) and states ``x`` (shape ``(..., 6)``)."""
        return feedback_linearizing_inputs(self.vehicle, x, self.outer(t, x))


def _trajectory(veh: Vehicle, traj: Any) -> ClimbTrajectory:
    return climb_trajectory(veh) if traj is None else require_instance("traj", traj, ClimbTrajectory,
                                                                          " (from gc.climb_trajectory)")


@dataclass(frozen=True)
class BlowUp:
    """Feedback linearization on the climb from the §7.3.3 level-flight start: divergence of the internal dynamics.

    Attributes
    ----------
    run : TrackingRun
        The run until it was stopped.
    blowup_time : float or None
        When ``|theta - theta_ref|`` or ``|u|`` crossed its limit (s); None if it never did.
    growth_rate : float
        Least-squares slope of ``ln |theta - theta_ref|`` over ``fit_window`` (1/s).
    fit_window : tuple of float
        (s).
    frozen_rate : float
        Mean over ``fit_window`` of the unstable eigenvalue of the frozen internal dynamics along the reference
        (1/s): the growth rate the linearization predicts along the (accelerating) climb.
    zero_dynamics : ZeroDynamics
        Level-flight zero dynamics (``zero_dynamics.rate`` is the unstable eigenvalue at ``t <= 0``).
    """

    run: TrackingRun
    blowup_time: float | None
    growth_rate: float
    fit_window: tuple[float, float]
    frozen_rate: float
    zero_dynamics: ZeroDynamics


def _frozen_rate(inv: StableInversion, t: np.ndarray) -> np.ndarray:
    d = inv.trajectory.derivatives(t, 2)
    xr = inv.reference_state(t)
    out = np.empty(t.size)
    for i in range(t.size):
        Jac, _ = jacobians(lambda Y, U, i=i: frozen_internal_dynamics(inv.vehicle, xr[i], d[i, 2], Y), xr[i, 4:6],
                           np.zeros(0))
        out[i] = np.max(np.linalg.eigvals(Jac).real)
    return out


def feedback_linearization_blowup(veh: Vehicle, traj: ClimbTrajectory | None = None, *, kp: float = 1.0,
                                  kd: float = 2.0, t_final: float = 40.0, theta_max: float = 1.0,
                                  u_max: float = 50.0, inversion: StableInversion | None = None,
                                  dt: float = 0.005) -> BlowUp:
    """Feedback linearization (7.80)-(7.83) on the climb from the level-flight state at ``(0, 0)`` (§7.3.3 start,
    ``theta = theta*`` of the zero dynamics, ``Omega2 = 0``), stopped when it blows up.

    Parameters
    ----------
    veh : Vehicle
    traj : ClimbTrajectory, optional
        Default :func:`climb_trajectory`.
    kp, kd : float
        Outer-loop gains (1/s^2, 1/s); default poles ``-1, -1`` per axis.
    t_final : float
        Longest run (s).
    theta_max : float
        Stop when ``|theta - theta_ref(t)| >= theta_max`` (rad); ``theta_ref`` is the bounded solution.
    u_max : float
        Stop when ``max(|u1|, |u2|) >= u_max`` (N, N m); default 10x the peak exact-tracking thrust.
    inversion : StableInversion, optional
        Bounded reference (computed if omitted); must cover ``[0, t_final]`` and be the inversion of ``traj`` for
        ``veh``.
    dt : float
        Output spacing (s), ``0 < dt <= t_final``.

    Returns
    -------
    BlowUp
        The growth rate is fitted on the samples with ``0.02 theta_max <= |theta - theta_ref| <= 0.3 theta_max``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory, ``inversion`` not a StableInversion, or a
        number not a real number.
    ArgumentError
        If ``t_final`` (at most 10^4 s), ``theta_max``, ``u_max``, ``kp``, ``kd`` or ``dt`` is not a positive
        finite number, ``dt > t_final``, ``inversion`` ends before ``t_final`` or belongs to another trajectory.
    VehicleMismatchError
        If ``inversion`` was computed for another vehicle.
    ModelError
        If ``veh`` is not a CTOL aircraft with ``epsilon != 0``.
    BudgetError
        If the integration hits its step budget (:func:`glidectl.sim.simulate`).
    SolverError
        If the stable inversion (when computed here) does not converge, the zero dynamics have no level-flight
        equilibrium, the integration fails, or the pitch deviation never grows through the fit band (fewer than 3
        samples in it).

    Examples
    --------
    >>> import glidectl as gc
    >>> b = gc.feedback_linearization_blowup(gc.load_vehicle("dc8_ctol"), t_final=10.0)
    >>> print(f"stopped at {b.blowup_time:.2f} s, growth {b.growth_rate:.1f} 1/s (frozen {b.frozen_rate:.1f} 1/s)")
    stopped at 1.19 s, growth 3.8 1/s (frozen 3.8 1/s)
    """
    require_inversion_vehicle(veh)
    traj = _trajectory(veh, traj)
    t_final = checks.real("t_final", t_final, lo=0.0, hi=1e4, lo_open=True, unit="s")
    theta_max = checks.positive("theta_max", theta_max, unit="rad")
    u_max = checks.positive("u_max", u_max)
    dt = checks.real("dt", dt, lo=0.0, hi=t_final, lo_open=True, unit="s")
    ctrl = FeedbackLinearizingController(veh, traj, kp, kd)
    if inversion is not None:
        require_instance("inversion", inversion, StableInversion, " (from stable_inversion)")
        checks.same_vehicle("inversion", inversion, veh)
        if inversion.trajectory != traj:
            raise ArgumentError("inversion was computed for another trajectory than traj")
        if inversion.t1 < t_final:
            raise ArgumentError(f"the inversion ends at {inversion.t1:g} s < t_final = {t_final:g} s")
    inv = stable_inversion(veh, traj, t1=max(45.0, t_final + 5.0)) if inversion is None else inversion
    zd = zero_dynamics(veh, traj.speed)

    def stop(t: float, x: np.ndarray) -> float:
        dth = abs(x[4] - float(inv.pitch(t)[0]))
        return min(theta_max - dth, u_max - float(np.max(np.abs(ctrl(t, x)))))

    x0 = level_flight_state(traj.speed, zd.theta)
    t, X, U, stopped = simulate_window(CTOLAircraft(veh), x0, 0.0, t_final, ctrl, dt, stop=stop, method="RK45")
    err = X[:, :2] - traj.position(t)
    dth = np.abs(X[:, 4] - inv.pitch(t)[:, 0])
    sel = (dth >= 0.02 * theta_max) & (dth <= 0.3 * theta_max)
    # first contiguous stretch after which the deviation keeps growing
    if np.count_nonzero(sel) < 3:
        raise SolverError("the pitch deviation never grew through the fit band; no growth rate")
    ts = t[sel]
    rate = float(np.polyfit(ts, np.log(dth[sel]), 1)[0])
    window = (float(ts[0]), float(ts[-1]))
    frozen = float(np.mean(_frozen_rate(inv, np.linspace(*window, 21))))
    why = "" if stopped is None else (f"; stopped at t = {stopped:.3f} s (|theta - theta_ref| >= {theta_max:g} rad "
                                      f"or |u| >= {u_max:g})")
    run = TrackingRun.from_arrays(f"feedback linearization (kp = {kp:g}, kd = {kd:g})", t, X, U, err,
                                  note=f"level-flight start at (0, 0), theta = theta* = {zd.theta:.5f} rad{why}",
                                  stopped_at=stopped)
    return BlowUp(run, stopped, rate, window, frozen, zd)
