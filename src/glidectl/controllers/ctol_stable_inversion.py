"""Stable (non-causal) inversion of the CTOL aircraft along the §7.3.3 climb (Devasia, Chen and Paden; §7.3.1), and
exact tracking with it.

Stable inversion (Devasia, Chen and Paden). The internal dynamics driven by the desired output,
``theta'' = f(t, theta, theta')``, has a unique bounded solution on the whole line; it is non-causal (it starts to
move before ``t = 0``, the *pre-action*). It is computed on ``[t0, t1]`` with :func:`scipy.integrate.solve_bvp`
and the boundary conditions: at ``t0 < 0`` (level flight) the state lies on the unstable eigenvector of the
linearized internal dynamics about the level-flight equilibrium (no stable component), at ``t1`` on the stable
eigenvector about the frozen-time equilibrium of the end of the climb (level flight at ``y = 10`` up to the
exponentially small tail of (7.91)). The feedforward ``(u1_ff, u2_ff)`` is (7.80)-(7.81) with ``w = p_d''`` along
that reference, so the plant started on the reference state reproduces ``p_d`` exactly. The inverse is unstable to
perturbations (the saddle), so it is flown with feedback: (7.80)-(7.81) at the measured state with the outer loop
on ``(x, y)``, plus a pitch correction ``delta u2 = -K(t) (x - x_ref(t))`` from a finite-horizon, time-varying LQR
designed on the exact (complex-step) linearization of that feedback-linearized loop along the reference.

The linearizing inputs and the internal dynamics are those of :mod:`glidectl.controllers.ctol_zero_dynamics`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np
from scipy.integrate import solve_bvp, solve_ivp
from scipy.interpolate import CubicSpline

from .. import checks
from ..derivatives import complex_step, jacobians, jacobians_batch
from ..errors import ArgumentError, BudgetError, SolverError
from ..models._validate import require_instance
from ..models.ctol import CTOLAircraft
from ..params import Vehicle
from .ctol_runs import TrackingRun, simulate_window
from .ctol_trajectory import ClimbTrajectory, climb_trajectory
from .ctol_zero_dynamics import (
    feedback_linearizing_inputs,
    frozen_internal_dynamics,
    internal_acceleration,
    level_flight_state,
    outer_loop_acceleration,
    require_inversion_vehicle,
    saddle_directions,
    zero_dynamics,
)

__all__ = ["InternalEquilibrium", "InversionTracker", "StableInversion", "stable_inversion", "track_stable_inversion"]

_H = 1e-30  # complex step
_RICCATI_NFEV = 5_000_000  # evaluation budget of the backward Riccati integration of InversionTracker


@dataclass(frozen=True)
class InternalEquilibrium:
    """Frozen-time equilibrium of the internal dynamics at a window end (boundary conditions of the inversion).

    Attributes
    ----------
    t : float
        Time (s).
    theta : float
        Equilibrium pitch (rad) of ``theta'' = f(t, theta, 0)`` with the trajectory frozen at ``t``.
    eigenvalues : ndarray (2,)
        Of the frozen linearization (1/s), ascending.
    unstable_vector, stable_vector : ndarray (2,)
        Eigenvectors in ``(theta, Omega2)``.
    """

    t: float
    theta: float
    eigenvalues: np.ndarray
    unstable_vector: np.ndarray = field(repr=False)
    stable_vector: np.ndarray = field(repr=False)


@dataclass(frozen=True, eq=False)
class StableInversion:
    """Bounded, non-causal solution ``theta_ref(t)`` of the internal dynamics (7.84) driven by ``p_d`` on
    ``[t0, t1]`` and the exact feedforward (7.80)-(7.81) with ``w = p_d''``.

    Attributes
    ----------
    vehicle : Vehicle
    trajectory : ClimbTrajectory
    t0, t1 : float
        Window (s).
    mesh : ndarray (M,)
        Final collocation mesh of :func:`scipy.integrate.solve_bvp` (s).
    theta, Omega2 : ndarray (M,)
        Solution at the mesh (rad, rad/s).
    rms_residual : float
        Largest relative collocation residual reported by ``solve_bvp``.
    max_residual : float
        ``max |Omega2_ref' - theta''(t, theta_ref)|`` on a grid of 20 points per mesh interval (rad/s^2):
        the reference satisfies (7.84) to this accuracy.
    bc_residual : float
        Largest boundary-condition residual (rad/s).
    start, end : InternalEquilibrium
        Frozen internal equilibria at ``t0`` (level flight: the zero dynamics) and ``t1``.
    provenance : str
        The vehicle's parameter hash (:attr:`Vehicle.provenance`).
    """

    vehicle: Vehicle = field(repr=False, compare=False)
    trajectory: ClimbTrajectory = field(repr=False)
    t0: float
    t1: float
    mesh: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    Omega2: np.ndarray = field(repr=False)
    rms_residual: float
    max_residual: float
    bc_residual: float
    start: InternalEquilibrium
    end: InternalEquilibrium
    _sol: Any = field(repr=False)
    _desired: ClimbTrajectory = field(repr=False)
    provenance: str = field(default="", repr=False)

    def _check_t(self, t: Any) -> np.ndarray:
        t = checks.array("t", t)
        if np.any(t < self.t0 - 1e-9) or np.any(t > self.t1 + 1e-9):
            raise ArgumentError(f"the reference exists on [{self.t0:g}, {self.t1:g}] s only")
        return np.clip(t, self.t0, self.t1)

    def pitch(self, t: Any) -> np.ndarray:
        """``(theta_ref, Omega2_ref)`` at ``t`` (rad, rad/s), shape ``(..., 2)``."""
        t = self._check_t(t)
        return np.moveaxis(self._sol(t), 0, -1)

    def reference_state(self, t: Any) -> np.ndarray:
        """Reference state ``(x_d, y_d, x_d', y_d', theta_ref, Omega2_ref)``, shape ``(..., 6)``."""
        t = self._check_t(t)
        d = self._desired.derivatives(t, 1)
        return np.concatenate([d[..., 0, :], d[..., 1, :], self.pitch(t)], -1)

    def feedforward(self, t: Any) -> np.ndarray:
        """``(u1_ff, u2_ff)`` (N, N m): (7.80)-(7.81) with ``w = p_d''`` on the reference, shape ``(..., 2)``."""
        t = self._check_t(t)
        return feedback_linearizing_inputs(self.vehicle, self.reference_state(t), self._desired.derivatives(t, 2)[
            ..., 2, :])


def _internal_along(veh: Vehicle, desired: ClimbTrajectory, t: Any, theta: Any, Omega: Any) -> Any:
    d = desired.derivatives(t, 2)
    X = np.stack(np.broadcast_arrays(d[..., 0, 0], d[..., 0, 1], d[..., 1, 0], d[..., 1, 1], theta, Omega), -1)
    return internal_acceleration(veh, X, d[..., 2, :])


def _quasi_static(veh: Vehicle, desired: ClimbTrajectory, t: np.ndarray, theta0: float) -> np.ndarray:
    """Pitch of zero internal acceleration at each frozen time (vectorized Newton from the level-flight alpha)."""
    d = desired.derivatives(t, 1)
    th = np.arctan2(d[:, 1, 1], d[:, 1, 0]) + theta0
    z = np.zeros_like(th)

    def acceleration(theta: np.ndarray) -> Any:
        return _internal_along(veh, desired, t, theta, z)

    for _ in range(50):
        f, df = complex_step(acceleration, th, 1.0, _H, value=True)   # value and d/dtheta in one call
        step = f / df
        th = th - np.clip(step, -0.2, 0.2)
        if np.max(np.abs(step)) < 1e-13:
            break
    return th


def _window_equilibrium(veh: Vehicle, desired: ClimbTrajectory, t: float, theta0: float) -> InternalEquilibrium:
    th = float(_quasi_static(veh, desired, np.array([t]), theta0)[0])
    d = desired.derivatives(t, 2)
    x = np.r_[d[0], d[1], 0.0, 0.0]
    Jac, _ = jacobians(lambda Y, U: frozen_internal_dynamics(veh, x, d[2], Y), np.array([th, 0.0]), np.zeros(0))
    ev, vu, vs = saddle_directions(Jac)
    if not (np.all(np.isreal(ev)) and ev[0] < 0 < ev[1]):
        raise SolverError(f"the frozen internal dynamics at t = {t:g} s is not a saddle (eigenvalues {ev}); the "
                          "stable-inversion boundary conditions need one stable and one unstable direction")
    return InternalEquilibrium(float(t), th, ev, vu, vs)


def stable_inversion(veh: Vehicle, traj: ClimbTrajectory | None = None, *, t0: float = -15.0, t1: float = 45.0,
                     tol: float = 1e-8, nodes: int = 1501) -> StableInversion:
    """Bounded non-causal solution of the internal dynamics (7.84) along the desired climb (stable inversion).

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``dc8_ctol``).
    traj : ClimbTrajectory, optional
        Desired trajectory; default :func:`climb_trajectory` (§7.3.3).
    t0 : float
        Window start (s), < 0: the pre-action starts in the level flight before the climb. The neglected stable
        component decays like ``exp(-lambda |t0|)`` (``lambda ~ 3.8 1/s``), far below the solver tolerance for
        ``t0 = -15``.
    t1 : float
        Window end (s), > 0; the climb (7.91) has settled to ~1e-8 m by 45 s. Simulations must end by ``t1``.
        The window is at most 10^4 s long.
    tol : float
        ``solve_bvp`` tolerance (relative collocation residual), in ``[1e-12, 1e-2]``.
    nodes : int
        Initial mesh size (uniform), in ``[10, 100000]``; the solver may refine the mesh up to 100000 nodes (its
        budget).

    Returns
    -------
    StableInversion

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory, or a number has the wrong type.
    ArgumentError
        Bad window (``t0 < 0 < t1`` finite, ``t1 - t0 <= 10^4`` s), ``tol`` or ``nodes``.
    ModelError
        If ``veh`` is not a CTOL aircraft with ``epsilon != 0``.
    SolverError
        ``solve_bvp`` did not converge (within 100000 mesh nodes), the boundary equilibria are not saddles, or the
        residual check failed.

    Examples
    --------
    >>> import glidectl as gc
    >>> inv = gc.stable_inversion(gc.load_vehicle("dc8_ctol"), t1=25.0)
    >>> bool(inv.max_residual < 1e-6), f"pitch {inv.start.theta:.4f} -> {inv.end.theta:.4f} rad"
    (True, 'pitch 0.0633 -> 0.0706 rad')
    """
    require_inversion_vehicle(veh)
    traj = climb_trajectory(veh) if traj is None else require_instance("traj", traj, ClimbTrajectory,
                                                                          " (from gc.climb_trajectory)")
    t0 = checks.real("t0", t0, unit="s")
    t1 = checks.real("t1", t1, unit="s")
    if not t0 < 0 < t1:
        raise ArgumentError(f"need t0 < 0 < t1 (the window must contain the level flight before t = 0), got "
                            f"[{t0!r}, {t1!r}]")
    if t1 - t0 > 1e4:
        raise ArgumentError(f"the window [{t0:g}, {t1:g}] s is longer than 10^4 s")
    tol = checks.real("tol", tol, lo=1e-12, hi=1e-2)
    nodes = checks.integer("nodes", nodes, lo=10, hi=100_000)
    desired = traj
    zd = zero_dynamics(veh, traj.speed)
    start = _window_equilibrium(veh, desired, t0, zd.theta)
    end = _window_equilibrium(veh, desired, t1, zd.theta)
    # the boundary conditions: the left eigenvector of the unwanted eigenvalue annihilates the deviation
    wl0 = np.linalg.inv(np.column_stack([start.stable_vector, start.unstable_vector]))[0]  # stable coordinate
    wl1 = np.linalg.inv(np.column_stack([end.stable_vector, end.unstable_vector]))[1]  # unstable coordinate
    y0, y1 = np.array([start.theta, 0.0]), np.array([end.theta, 0.0])

    def fun(t: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.vstack([y[1], _internal_along(veh, desired, t, y[0], y[1])])

    def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
        return np.array([wl0 @ (ya - y0), wl1 @ (yb - y1)])

    mesh = np.linspace(t0, t1, nodes)
    guess = _quasi_static(veh, desired, mesh, zd.theta)
    if not np.all(np.isfinite(guess)):
        raise SolverError("the quasi-static pitch along the trajectory (the initial guess) is not finite")
    try:
        with np.errstate(all="ignore"):
            sol = solve_bvp(fun, bc, mesh, np.vstack([guess, np.gradient(guess, mesh)]), tol=tol, max_nodes=100000,
                            bc_tol=tol)
    except (np.linalg.LinAlgError, ZeroDivisionError, OverflowError, FloatingPointError) as exc:
        raise SolverError(f"solve_bvp failed for the stable inversion: {type(exc).__name__}: {exc}") from exc
    if sol.status != 0:
        raise SolverError(f"solve_bvp did not converge for the stable inversion: {sol.message}")
    # residual of (7.84) on a fine grid
    tf = np.linspace(t0, t1, 20 * (sol.x.size - 1) + 1)
    yf, dyf = sol.sol(tf), sol.sol(tf, 1)
    res = np.max(np.abs(dyf - fun(tf, yf)))
    bcr = float(np.max(np.abs(bc(sol.y[:, 0], sol.y[:, -1]))))
    if not np.isfinite(res) or res > 1e3 * tol * (1 + np.max(np.abs(fun(tf, yf)))):
        raise SolverError(f"stable-inversion reference fails the residual check: max |residual| = {res:.3g}")
    return StableInversion(veh, traj, float(t0), float(t1), sol.x, sol.y[0], sol.y[1],
                           float(np.max(sol.rms_residuals)), float(res), bcr, start, end, sol.sol, desired,
                           veh.provenance)


@dataclass(frozen=True, eq=False)
class InversionTracker:
    """Stable-inversion tracking controller: (7.80)-(7.81) at the measured state with
    ``w = p_d'' + kd (p_d' - p') + kp (p_d - p)``, plus ``delta u2 = -K(t) (x - x_ref(t))``.

    On the reference the law returns the feedforward exactly. ``K(t)`` is the finite-horizon LQR gain of the
    exact (complex-step) linearization ``z' = A(t) z + B(t) delta u2`` of that feedback-linearized loop along the
    reference, cost ``int z' Q z + r delta_u2^2 dt``, with the terminal weight the algebraic-Riccati solution at
    ``t1`` (python-control ``lqr``); the Riccati equation is integrated backwards over ``[t0, t1]``.

    Why not a fixed PD on ``theta - theta_ref``: the internal dynamics is a saddle whose unstable eigenvalue grows
    from 3.8 1/s in level flight to ~25 1/s at the climb's peak speed, so a fixed pitch stiffness that stabilizes
    the climb is far too stiff in level flight, and the added ``u2`` pushes on the position through ``eps u2``,
    which the outer loop feeds back into ``u2`` through (7.81) with gain ``1 / eps``; the LQR on the coupled
    6-state linearization accounts for both.

    Parameters
    ----------
    inversion : StableInversion
    kp, kd : float
        Outer-loop gains (1/s^2, 1/s).
    q : sequence of 6 floats
        Diagonal state weights on ``x - x_ref`` (1/m^2, 1/m^2, s^2/m^2, s^2/m^2, 1/rad^2, s^2/rad^2).
    r : float
        Weight on ``delta u2`` (1/(N m)^2).
    dt_gain : float
        Grid (s) on which ``A, B`` are evaluated (linearly interpolated in the Riccati equation) and ``K`` stored;
        at most 10^6 grid points over the window.

    Raises
    ------
    ArgumentTypeError
        If ``inversion`` is not a StableInversion or a weight or gain is not a real number.
    ArgumentError
        If ``q`` is not 6 nonnegative finite weights, or ``r``, ``dt_gain``, ``kp``, ``kd`` is not a positive finite
        number, or ``dt_gain`` gives more than 10^6 grid points.
    ModelError
        If the inversion's vehicle is not a CTOL aircraft with ``epsilon != 0``.
    BudgetError
        If the backward Riccati integration needs more than 5 million evaluations.
    SolverError
        If the end-point LQR or the time-varying Riccati equation fails.
    """

    inversion: StableInversion
    kp: float = 1.0
    kd: float = 2.0
    q: tuple[float, ...] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    r: float = 1.0
    dt_gain: float = 0.01
    _grid: np.ndarray = field(init=False, repr=False)
    _K: CubicSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        inv = require_instance("inversion", self.inversion, StableInversion, " (from stable_inversion)")
        q = checks.array("q", self.q, shape=(6,))
        if np.any(q < 0):
            raise ArgumentError(f"q must be 6 nonnegative weights, got {self.q!r}")
        object.__setattr__(self, "q", tuple(float(v) for v in q))
        for k in ("r", "dt_gain", "kp", "kd"):
            object.__setattr__(self, k, checks.positive(k, getattr(self, k)))
        if (inv.t1 - inv.t0) / self.dt_gain > 1e6:
            raise ArgumentError(f"dt_gain = {self.dt_gain:g} s gives more than 10^6 gain grid points on "
                                f"[{inv.t0:g}, {inv.t1:g}] s")
        require_inversion_vehicle(inv.vehicle)
        tg = np.linspace(inv.t0, inv.t1, math.ceil((inv.t1 - inv.t0) / self.dt_gain) + 1)
        Ag, Bg = self.linearization(tg)
        Q, Rinv = np.diag(q), 1.0 / float(self.r)
        try:
            _, P1, _ = control.lqr(Ag[-1], Bg[-1], Q, np.array([[float(self.r)]]))
        except Exception as exc:  # python-control raises several types
            raise SolverError(f"no stabilizing LQR at the end of the window t1 = {inv.t1:g} s: {exc}") from exc
        sg = inv.t1 - tg[::-1]  # reversed time s = t1 - t, increasing
        Ar, Br = Ag[::-1], Bg[::-1]

        spent = [0]

        def riccati(s: float, p: np.ndarray) -> np.ndarray:
            spent[0] += 1
            if spent[0] > _RICCATI_NFEV:
                raise BudgetError(f"the time-varying Riccati equation used its budget of {_RICCATI_NFEV} evaluations "
                                  f"(at t = {inv.t1 - s:.4g} s); the linearization along the reference is too stiff")
            k = min(max(int(np.searchsorted(sg, s)) - 1, 0), sg.size - 2)
            f = (s - sg[k]) / (sg[k + 1] - sg[k])
            A, B = (1 - f) * Ar[k] + f * Ar[k + 1], (1 - f) * Br[k] + f * Br[k + 1]
            P = p.reshape(6, 6)
            PB = P @ B
            dP = A.T @ P + P @ A - Rinv * (PB @ PB.T) + Q
            return (0.5 * (dP + dP.T)).ravel()

        if not np.all(np.isfinite(np.asarray(P1, dtype=float))):
            raise SolverError(f"the LQR at the end of the window t1 = {inv.t1:g} s is not finite")
        try:
            sol = solve_ivp(riccati, (0.0, sg[-1]), np.asarray(P1, dtype=float).ravel(), method="LSODA", rtol=1e-6,
                            atol=1e-8, t_eval=sg)
        except (ZeroDivisionError, OverflowError, FloatingPointError, np.linalg.LinAlgError) as exc:
            raise SolverError(f"the time-varying Riccati equation failed: {exc}") from exc
        if not sol.success or not np.all(np.isfinite(sol.y)):
            raise SolverError(f"the time-varying Riccati equation failed: {sol.message}")
        P = sol.y.T.reshape(-1, 6, 6)[::-1]
        object.__setattr__(self, "_grid", tg)
        object.__setattr__(self, "_K", CubicSpline(tg, Rinv * np.einsum("nij,nik->nk", Bg, P)))

    def outer(self, t: Any, x: Any) -> Any:
        """Outer-loop acceleration ``w(t, x)`` (m/s^2) of (7.82)-(7.83) along the inversion's trajectory, shape
        ``(..., 2)`` (see :func:`glidectl.controllers.ctol_zero_dynamics.outer_loop_acceleration`)."""
        return outer_loop_acceleration(self.inversion.trajectory, self.kp, self.kd, t, x)

    def closed_loop(self, t: Any, x: Any, du2: Any) -> Any:
        """Plant right-hand side under the law with an extra pitch input ``du2`` (shape ``(..., 1)``; complex-safe,
        ``t`` broadcasting with ``x[..., 0]``)."""
        x = np.asarray(x)
        du2 = np.asarray(du2)[..., 0]
        u = feedback_linearizing_inputs(self.inversion.vehicle, x, self.outer(t, x))
        u = u + np.stack(np.broadcast_arrays(0.0 * du2, du2), -1)
        return CTOLAircraft(self.inversion.vehicle).rhs(x, u)

    def linearization(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(A(t), B(t))`` of the feedback-linearized loop along the reference (complex step, batched over ``t``):
        shapes ``(..., 6, 6)`` and ``(..., 6, 1)``."""
        t = np.asarray(t, dtype=float)
        xr = self.inversion.reference_state(t)
        return jacobians_batch(lambda X, U: self.closed_loop(t[..., None], X, U), xr,
                               np.zeros((*xr.shape[:-1], 1)), _H)

    def gain(self, t: float) -> np.ndarray:
        """``K(t)`` (6,) (N m per unit state error): cubic spline through the ``dt_gain`` grid (smooth in ``t``, so
        the closed loop stays smooth for the integrator)."""
        tg = self._grid
        return self._K(min(max(float(t), tg[0]), tg[-1]))

    def __call__(self, t: float, x: Any) -> np.ndarray:
        """Inputs ``(u1, u2)`` (N, N m) at time ``t`` (s) and the state ``x`` (shape ``(6,)``)."""
        inv = self.inversion
        tc = min(max(checks.real("t", t, unit="s"), inv.t0), inv.t1)
        x = checks.array("x", x, shape=(6,))
        du2 = -float(self.gain(tc) @ (x - inv.reference_state(tc)))
        u = feedback_linearizing_inputs(inv.vehicle, x, self.outer(t, x))
        return u + np.array([0.0, du2])


def track_stable_inversion(veh: Vehicle, traj: ClimbTrajectory | None = None, *,
                           inversion: StableInversion | None = None, start: str = "reference",
                           t_final: float = 40.0, kp: float = 1.0, kd: float = 2.0,
                           q: Sequence[float] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0), r: float = 1.0,
                           dt: float = 0.01) -> TrackingRun:
    """Exact tracking of the climb by stable inversion with feedback (:class:`InversionTracker`).

    Parameters
    ----------
    veh : Vehicle
    traj : ClimbTrajectory, optional
        Default :func:`climb_trajectory`.
    inversion : StableInversion, optional
        Computed with :func:`stable_inversion` if omitted.
    start : {"reference", "level"}
        ``"reference"``: start at ``t0 < 0`` on the reference state (the aircraft flies level and performs the
        pre-action before ``t = 0``). ``"level"``: start at ``t = 0`` in the §7.3.3 level-flight state
        (``theta = theta*``, no pre-action); the feedback absorbs the pitch mismatch.
    t_final : float
        End (s), ``0 < t_final <= inversion.t1`` (at most 10^4 s).
    kp, kd, q, r
        Gains and LQR weights, see :class:`InversionTracker`.
    dt : float
        Output spacing (s), ``0 < dt <= t_final``.

    Returns
    -------
    TrackingRun
        Metrics on ``[0, t_final]``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory, ``inversion`` not a StableInversion, or a
        number has the wrong type.
    ArgumentError
        If ``t_final`` is not a positive finite number (at most 10^4 s) or is past ``inversion.t1``; ``inversion``
        belongs to another trajectory; ``start`` is not ``"reference"`` or ``"level"``; ``dt`` is not in
        ``(0, t_final]``; or ``kp``, ``kd``, ``q``, ``r`` are invalid (:class:`InversionTracker`). All are checked
        before the inversion is computed.
    VehicleMismatchError
        If ``inversion`` was computed for another vehicle.
    ModelError
        If ``veh`` is not a CTOL aircraft with ``epsilon != 0``.
    BudgetError
        If the integration hits its step budget (:func:`glidectl.sim.simulate`).
    SolverError
        If the stable inversion (when computed here) does not converge, the tracker's LQR or Riccati equation
        fails, the zero dynamics have no level-flight equilibrium (``start="level"``), or the integration fails.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> inv = gc.stable_inversion(veh, t0=-10.0, t1=20.0)
    >>> run = gc.track_stable_inversion(veh, inversion=inv, t_final=10.0)
    >>> run.completed, bool(run.max_error < 1e-6)             # exact tracking, with pre-action before t = 0
    (True, True)
    """
    require_inversion_vehicle(veh)
    traj = climb_trajectory(veh) if traj is None else require_instance("traj", traj, ClimbTrajectory,
                                                                          " (from gc.climb_trajectory)")
    t_final = checks.real("t_final", t_final, lo=0.0, hi=1e4, lo_open=True, unit="s")
    checks.choice("start", start, ("reference", "level"))
    dt = checks.real("dt", dt, lo=0.0, hi=t_final, lo_open=True, unit="s")
    qa = checks.array("q", q, shape=(6,))
    if np.any(qa < 0):
        raise ArgumentError(f"q must be 6 nonnegative weights, got {q!r}")
    kp, kd, r = checks.positive("kp", kp), checks.positive("kd", kd), checks.positive("r", r)
    if inversion is not None:
        require_instance("inversion", inversion, StableInversion, " (from stable_inversion)")
        checks.same_vehicle("inversion", inversion, veh)
        if inversion.trajectory != traj:
            raise ArgumentError("inversion was computed for another trajectory than traj")
        if t_final > inversion.t1:
            raise ArgumentError(f"t_final = {t_final:g} s is past the end of the inversion window "
                                f"({inversion.t1:g} s)")
    inv = stable_inversion(veh, traj, t1=max(45.0, t_final + 5.0)) if inversion is None else inversion
    tracker = InversionTracker(inv, kp, kd, tuple(float(v) for v in qa), r)
    if start == "reference":
        t_start, x0 = inv.t0, inv.reference_state(inv.t0)
        note = f"started on the reference at t0 = {inv.t0:g} s (pre-action before t = 0)"
    else:
        zd = zero_dynamics(veh, traj.speed)
        t_start, x0 = 0.0, level_flight_state(traj.speed, zd.theta)
        note = "started at t = 0 in level flight (theta = theta*), no pre-action"
    t, X, U, _ = simulate_window(CTOLAircraft(veh), x0, t_start, t_final, tracker, dt)
    keep = t >= -1e-12
    t, X, U = t[keep], X[keep], U[keep]
    err = X[:, :2] - traj.position(t)
    return TrackingRun.from_arrays(f"stable inversion + FL + TV-LQR (kp = {kp:g}, kd = {kd:g}, r = {r:g})", t, X, U,
                                   err, note=note)
