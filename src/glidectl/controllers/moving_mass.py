"""Realizing the pure torque of §6.1 with the internal moving mass of the longitudinal model (2.15)-(2.25).

§6.1 approximates internal-mass actuation by a pure torque, arguing from (2.20): at a steady glide
(``Omega2 = 0``, ``rdot_P = 0``, ``u1 = u3 = 0``) the moving-mass position enters only the moment balance, through
the gravity torque ``-mbar g (r_P1 cos(theta) + r_P3 sin(theta))`` (N m). Here the torque law (6.5) is closed through
that mechanism on :class:`~glidectl.models.longitudinal.AccelerationControlledGlider` (input ``w`` of (2.33), sign of
(2.32) corrected there):

- commanded position ``r_P1c = -(u_des + mbar g r_P3 sin(theta)) / (mbar g cos(theta))`` so that the gravity
  torque equals ``u_des = TorqueLaw.torque`` at the current ``(V, gamma, alpha, Omega2)``;
- PD tracking on the mass acceleration, ``w1 = omega_n^2 (r_P1c - r_P1) - 2 zeta omega_n rdot_P1``, and
  ``w3 = -omega_n^2 (r_P3 - r_P3c) - 2 zeta omega_n rdot_P3`` holding ``r_P3``; ``w4 = 0`` (constant buoyancy).

The two closed loops share the steady glide exactly (the equilibrium of (2.18)-(2.20) with this ``r_P1`` is that of
(6.1)-(6.4) with ``M_i = m_i + mbar``); transients differ by the mass' finite tracking bandwidth and by the inertial
coupling terms of (2.18)-(2.20) (``r_P x u``, ``Omega2 (r_P . P_P)``), which the pure torque leaves out.
:func:`compare_realized_torque` measures the difference. The closed-loop vector field is the model
:class:`~glidectl.models.realized_torque.RealizedTorqueLoop`; :func:`simulate_realized_torque` integrates it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, BudgetError, ModelError, SolverError
from ..hydro import angle_of_attack
from ..models._validate import require_glider, require_instance, trailing_array
from ..models.glider3d import R_P_MAX
from ..models.longitudinal import ACCEL_INPUTS, AccelerationControlledGlider
from ..models.realized_torque import RealizedTorqueLoop
from ..models.reduced import REDUCED_STATES
from ..models.torque_glider import TorqueControlledGlider
from ..params import Vehicle
from ..sim import Simulation, simulate
from ..stability.singular_perturbation import singular_perturbation
from .torque import TorqueLaw

__all__ = ["MAX_NFEV", "MovingMassTorque", "RealizedTorqueComparison", "compare_realized_torque",
           "reduced_from_accel", "simulate_realized_torque"]

#: Default budget of right-hand-side evaluations of :func:`simulate_realized_torque` (the designs use < 10^5).
MAX_NFEV = 2_000_000
_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


class _OutOfBudget(Exception):
    """Raised inside the integrand when a budget is hit (turned into :class:`BudgetError`)."""


def reduced_from_accel(xa: Any, veh: Vehicle | None = None) -> np.ndarray:
    """``(V, gamma, alpha, Omega2)`` (m/s, rad, rad, rad/s) of an acceleration-form longitudinal state, (5.1)-(5.3).

    Parameters
    ----------
    xa : array_like, shape (..., 11)
        :class:`AccelerationControlledGlider` state.
    veh : Vehicle, optional
        Given: the velocity is the *system* velocity ``(m_i v_i + P_Pi)/(m_i + mbar)`` (hull plus moving mass,
        ``P_P`` from (2.31)), which the mass' own acceleration does not change (``(m1 v1 + P_P1)' = X1`` is free of
        ``u1``) and which equals the hull velocity when the mass is at rest in the hull. Omitted: the hull velocity.

    Returns
    -------
    ndarray, shape (..., 4)
        ``(V, gamma, alpha, Omega2)``.

    Raises
    ------
    ArgumentTypeError
        If ``xa`` is not an array of numbers or ``veh`` not a Vehicle.
    ArgumentError
        If ``xa`` does not have a trailing dimension 11.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    xa = trailing_array("xa", xa, 11)
    if veh is not None:
        require_glider(veh, "veh")
    th, Om, v1, v3 = xa[..., 2], xa[..., 3], xa[..., 4], xa[..., 5]
    if veh is not None:
        mb = veh.mbar
        m1, m3 = veh.mass(1, xa[..., 10]), veh.mass(3, xa[..., 10])
        PP1 = mb * (xa[..., 7] + v1 + xa[..., 8] * Om)
        PP3 = mb * (xa[..., 9] + v3 - xa[..., 6] * Om)
        v1, v3 = (m1 * v1 + PP1) / (m1 + mb), (m3 * v3 + PP3) / (m3 + mb)
    al = angle_of_attack(v1, v3)
    return np.stack([np.sqrt(v1 * v1 + v3 * v3), th - al, al, Om], axis=-1)


@dataclass(frozen=True)
class MovingMassTorque:
    """Torque law (6.5) realized by the moving mass: controller ``(t, xa) -> w`` for
    :class:`AccelerationControlledGlider` (see the module docstring).

    Actuator limits: this law does not saturate its own commands. Run it through
    :class:`~glidectl.models.actuated.ActuatedGlider` (:func:`glidectl.sim.simulate_actuated`,
    :func:`glidectl.controllers.dive_cycle.dive_cycle`) to have the vehicle's ``[actuators]`` ranges and rates
    enforced; :func:`glidectl.sim.simulate` on the plain model applies no limits.

    Attributes
    ----------
    vehicle : Vehicle
        Glider with a moving mass ``mbar > 0`` (kg).
    law : TorqueLaw
        Desired torque (6.5).
    r_p3 : float
        Held body-3 position of the moving mass (m).
    omega_n : float
        Bandwidth of the PD position loop (rad/s).
    zeta : float
        Damping ratio of the PD position loop.
    feedback : {"system", "hull"}
        Velocity fed to (6.5): the system velocity of :func:`reduced_from_accel` (default) or the hull's. With the
        hull's, accelerating the mass pushes the hull back (``m1 v1' = X1 - u1``) and turns ``alpha`` by
        ``delta alpha = mbar v3 delta rdot_P1/(m1 V^2)``, so the law feeds the mass velocity back into its own
        command with gain ``c = -K_Mu v3 / (m1 g cos(theta))`` (rad-free, ~0.03 for the sphere): the position loop
        ``r'' = omega_n^2 (c r' - r) - 2 zeta omega_n r'`` is unstable once ``c omega_n > 2 zeta``, far below the
        bandwidth the stiff pitch loop needs. The system velocity is free of that reaction.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``law`` not a TorqueLaw or a number not a real number.
    ArgumentError
        If ``r_p3`` is not finite with ``|r_p3| <= 10`` m, ``omega_n`` or ``zeta`` is not a positive finite number,
        or ``feedback`` is not ``"system"`` or ``"hull"``.
    ModelError
        If the vehicle is not an underwater glider with a moving mass ``mbar > 0``.
    """

    vehicle: Vehicle
    law: TorqueLaw
    r_p3: float = 0.0
    omega_n: float = 2000.0
    zeta: float = 1.0
    feedback: str = "system"

    def __post_init__(self) -> None:
        AccelerationControlledGlider(self.vehicle)  # needs an underwater glider with mbar > 0
        require_instance("law", self.law, TorqueLaw)
        object.__setattr__(self, "r_p3", checks.real("r_p3", self.r_p3, lo=-R_P_MAX, hi=R_P_MAX, unit="m"))
        object.__setattr__(self, "omega_n", checks.positive("omega_n", self.omega_n, unit="rad/s"))
        object.__setattr__(self, "zeta", checks.positive("zeta", self.zeta))
        checks.choice("feedback", self.feedback, ("system", "hull"))

    def reduced_state(self, xa: Any) -> np.ndarray:
        """``(V, gamma, alpha, Omega2)`` fed to the law (see ``feedback``)."""
        return reduced_from_accel(xa, self.vehicle if self.feedback == "system" else None)

    def mass_torque(self, xa: Any) -> Any:
        """Gravity torque of the moving mass in (2.20), ``-mbar g (r_P1 cos(theta) + r_P3 sin(theta))`` (N m)."""
        xa = trailing_array("xa", xa, 11)
        v = self.vehicle
        th = xa[..., 2]
        return -v.mbar * v.g * (xa[..., 6] * np.cos(th) + xa[..., 8] * np.sin(th))

    def r_p1_command(self, xa: Any) -> Any:
        """``r_P1c`` (m): the position whose gravity torque equals the desired torque at the current state."""
        xa = trailing_array("xa", xa, 11)
        v = self.vehicle
        th = xa[..., 2]
        u = self.law.torque(self.reduced_state(xa))
        return -(u + v.mbar * v.g * self.r_p3 * np.sin(th)) / (v.mbar * v.g * np.cos(th))

    def __call__(self, t: float, xa: Any) -> Any:
        """Accelerations ``w = (w1, w3, w4)`` at acceleration-form states ``xa`` (shape ``(..., 11)``)."""
        xa = trailing_array("xa", xa, 11)
        wn2, c = self.omega_n**2, 2 * self.zeta * self.omega_n
        w1 = wn2 * (self.r_p1_command(xa) - xa[..., 6]) - c * xa[..., 7]
        w3 = wn2 * (self.r_p3 - xa[..., 8]) - c * xa[..., 9]
        return np.stack([w1, w3, np.zeros_like(w1)], axis=-1)

    def initial_state(self, x0: Any) -> np.ndarray:
        """Acceleration-form state matching a reduced state ``(V, gamma, alpha, Omega2)``: ``x = z = 0``, the mass at
        rest (relative to the hull) at ``(r_P1c, r_P3)``, ``m0`` of the vehicle.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x0`` is not four finite numbers with ``V > 0``.
        """
        x0 = checks.array("x0", x0, shape=(4,))
        if not x0[0] > 0:
            raise ArgumentError(f"x0 must start at a positive speed V > 0, got V = {x0[0]:g} m/s")
        V, gam, al, Om = (float(c) for c in x0)
        xa = np.array([0.0, 0.0, gam + al, Om, V * math.cos(al), V * math.sin(al), 0.0, 0.0, self.r_p3, 0.0,
                       self.vehicle.m0])
        xa[6] = float(self.r_p1_command(xa))
        return xa


def simulate_realized_torque(loop: RealizedTorqueLoop, y0: Any, te: np.ndarray, *, method: str = "BDF",
                             rtol: float = 1e-9, atol: float = 1e-11, max_nfev: int = MAX_NFEV,
                             time_limit: float | None = None) -> Simulation:
    """Integrate a :class:`~glidectl.models.realized_torque.RealizedTorqueLoop` with
    :func:`scipy.integrate.solve_ivp` and the exact Jacobian (implicit methods need it: the finite-difference Jacobian
    of the stiff mass loop makes BDF/LSODA crawl).

    Parameters
    ----------
    loop : RealizedTorqueLoop
        The closed loop (its ``controller`` gives the commanded inputs recorded in the result).
    y0 : array_like, shape (9,)
        Initial ``(theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)`` (rad, rad/s, m/s, m/s, m, m/s, m, m/s,
        kg), e.g. ``MovingMassTorque.initial_state(x0)[2:]``.
    te : ndarray
        Nondecreasing, finite output times (s) in ``[0, te[-1]]`` with ``te[-1] > 0``; the run ends at ``te[-1]``.
    method : str
        Integrator of :func:`scipy.integrate.solve_ivp`; ``"BDF"``, ``"Radau"`` and ``"LSODA"`` get the exact
        (complex-step) Jacobian.
    rtol, atol : float
        Relative (nondimensional, in ``[1e-14, 1)``) and absolute (state units, > 0) tolerances.
    max_nfev : int
        Budget of right-hand-side evaluations (Jacobian columns included); default :data:`MAX_NFEV`.
    time_limit : float, optional
        Wall-time budget (s); default none.

    Returns
    -------
    Simulation
        States of ``loop`` at ``te``; its inputs are the commanded ``(w1, w3, w4)`` (m/s^2, m/s^2, kg/s).

    Raises
    ------
    ArgumentTypeError
        If ``loop`` is not a RealizedTorqueLoop or an argument has the wrong type.
    ArgumentError
        If ``y0`` is not 9 finite numbers, ``te`` is not as described, ``method`` is unknown or a tolerance or
        budget is out of range.
    BudgetError
        If the run hits ``max_nfev`` or ``time_limit``.
    SolverError
        If the integration fails or its states stop being finite.
    """
    require_instance("loop", loop, RealizedTorqueLoop)
    y0 = checks.array("y0", y0, shape=(len(loop.state_names),))
    te = checks.array("te", te, ndim=1, min_size=1)
    if te[0] < 0 or np.any(np.diff(te) < 0) or not te[-1] > 0:
        raise ArgumentError("te must be nondecreasing output times from t >= 0 to a final time > 0 (s)")
    checks.choice("method", method, _METHODS)
    rtol = checks.real("rtol", rtol, lo=1e-14, hi=1.0, hi_open=True)
    atol = checks.positive("atol", atol)
    max_nfev = checks.integer("max_nfev", max_nfev, lo=1)
    deadline = checks.Deadline(time_limit, "the moving-mass closed loop integration")
    t_final = float(te[-1])
    count = [0]

    def spend(k: int, t: float) -> None:
        count[0] += k
        if count[0] > max_nfev:
            raise _OutOfBudget(f"it used its budget of max_nfev = {max_nfev} right-hand-side evaluations at "
                               f"t = {t:.6g} s")
        deadline.check(f"t = {t:.6g} s")

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        spend(1, t)
        return loop.rhs(y)

    def jac_fun(t: float, y: np.ndarray) -> np.ndarray:
        spend(y.size, t)
        return jacobians(lambda yy, _u: loop.rhs(yy), y, np.zeros(0))[0]

    jac = jac_fun if method in ("BDF", "Radau", "LSODA") else None
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(fun, (0.0, t_final), y0, method=method, rtol=rtol, atol=atol, dense_output=True,
                            jac=jac)
    except _OutOfBudget as exc:
        raise BudgetError(f"moving-mass closed loop: {exc}; raise max_nfev or shorten the run") from None
    except (ZeroDivisionError, OverflowError, FloatingPointError, np.linalg.LinAlgError) as exc:
        raise SolverError(f"moving-mass closed loop: integration failed: {type(exc).__name__}: {exc}") from exc
    if not sol.success or not np.all(np.isfinite(sol.y)):
        raise SolverError(f"moving-mass closed loop: integration failed at t = {sol.t[-1]:.4g} s: {sol.message}")
    X = np.atleast_2d(sol.sol(te).T)
    U = np.asarray(loop.controller(0.0, loop.full_state(X)), dtype=float)
    return Simulation(np.asarray(te, dtype=float), X, U, loop.state_names, ACCEL_INPUTS, method, rtol, atol,
                      int(sol.nfev), f"{type(loop).__name__}({loop.vehicle.name})", None, loop.vehicle.provenance)


@dataclass(frozen=True)
class RealizedTorqueComparison:
    """Pure torque (6.1)-(6.5) versus the same law realized by the moving mass, from one initial condition.

    Attributes
    ----------
    pure : Simulation
        :class:`TorqueControlledGlider` under :class:`TorqueLaw` (states ``(V, gamma, alpha, Omega2)``).
    realized : Simulation
        :class:`RealizedTorqueLoop` (states ``(theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)``,
        inputs ``w``).
    realized_reduced : ndarray, shape (N, 4)
        ``(V, gamma, alpha, Omega2)`` of the hull in ``realized`` at the same times (hull velocity: what the
        hydrodynamics see).
    max_difference : dict
        ``max_t |x_pure - x_realized|`` per reduced state (m/s, rad, rad, rad/s), hull velocity.
    max_difference_system : dict
        The same with the system velocity of :func:`reduced_from_accel` (hull plus moving mass), which is what the
        pure-torque model's ``V`` (with ``M_i = m_i + mbar``) represents.
    final_difference : dict
        ``|x_pure - x_realized|`` at ``t_final``.
    max_torque_error : float
        ``max_t |mass gravity torque - desired torque|`` (N m) along ``realized``.
    equilibrium : ndarray, shape (4,)
        Closed-loop steady glide ``(V_e, gamma_e, alpha_e, 0)`` of (6.1)-(6.5).
    r_p1_equilibrium : float
        Moving-mass position (m) realizing the equilibrium torque.
    max_r_p1, max_rdot_p1 : float
        ``max_t |r_P1|`` (m) and ``max_t |rdot_P1|`` (m/s) along ``realized``.
    controller : MovingMassTorque
    """

    pure: Simulation = field(repr=False)
    realized: Simulation = field(repr=False)
    realized_reduced: np.ndarray = field(repr=False)
    max_difference: dict[str, float]
    max_difference_system: dict[str, float]
    final_difference: dict[str, float]
    max_torque_error: float
    equilibrium: np.ndarray
    r_p1_equilibrium: float
    max_r_p1: float
    max_rdot_p1: float
    controller: MovingMassTorque = field(repr=False)

    @property
    def final_pure(self) -> np.ndarray:
        """Final ``(V, gamma, alpha, Omega2)`` of the pure-torque loop."""
        return self.pure.x[-1]

    @property
    def final_realized(self) -> np.ndarray:
        """Final ``(V, gamma, alpha, Omega2)`` of the moving-mass loop."""
        return self.realized_reduced[-1]


def compare_realized_torque(veh: Vehicle, law: TorqueLaw, x0: Any, t_final: float, *, r_p3: float = 0.0,
                            omega_n: float = 2000.0, zeta: float = 1.0, feedback: str = "system", t_eval: Any = None,
                            method: str = "BDF", rtol: float = 1e-9, atol: float = 1e-11, max_nfev: int = MAX_NFEV,
                            time_limit: float | None = None) -> RealizedTorqueComparison:
    """Simulate (6.1)-(6.5) with a pure torque and with the moving mass realizing it, and compare.

    Parameters
    ----------
    veh : Vehicle
        Glider with ``mbar > 0`` and ``m0 != 0``; the pure-torque model uses ``M_i = m_i + mbar`` (the mass riding
        with the hull), the realized loop the full longitudinal model (2.15)-(2.25).
    law : TorqueLaw
        Torque law (6.5), e.g. ``design_torque_control(...).law``.
    x0 : array_like, shape (4,)
        Initial ``(V, gamma, alpha, Omega2)`` (m/s, rad, rad, rad/s); the realized loop starts with the mass at rest
        at its commanded position (:meth:`MovingMassTorque.initial_state`).
    t_final : float
        Duration (s).
    r_p3, omega_n, zeta, feedback
        See :class:`MovingMassTorque` (m, rad/s, -, "system" or "hull").
    t_eval : array_like, optional
        Output times (s) in ``[0, t_final]``, sorted; default 2001 evenly spaced points plus 400 log-spaced ones in
        the first 1 % of the run, which resolve the fast initial transient of the mass (the maxima below are taken
        over these samples).
    method : str
        Integrator of the realized loop (:func:`simulate_realized_torque`; the pure loop uses LSODA).
    rtol, atol
        Tolerances of both runs.
    max_nfev : int
        Budget of right-hand-side evaluations of the realized loop (:func:`simulate_realized_torque`).
    time_limit : float, optional
        Wall-time budget (s) of each of the two runs.

    Returns
    -------
    RealizedTorqueComparison
        Both simulations, the hull states of the realized loop, the largest and final differences per reduced
        state (m/s, rad, rad, rad/s), the largest torque error (N m), the closed-loop equilibrium, the moving-mass
        position realizing it (m) and the largest mass excursion (m) and speed (m/s).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``law`` not a TorqueLaw, or an argument has the wrong type.
    ArgumentError
        If ``x0`` is not four finite numbers with ``V > 0``, ``t_final`` is not a positive finite number, ``t_eval``
        is not sorted within ``[0, t_final]``, or ``r_p3``, ``omega_n``, ``zeta``, ``feedback``, ``method``, a
        tolerance or a budget is invalid.
    ModelError
        If the vehicle has no moving mass (``mbar = 0``), is not an underwater glider, has ``m0 = 0``, or the
        closed loop of ``law`` has no singularly perturbed chapter-5 glide.
    BudgetError
        If a run hits its evaluation, step or time budget.
    SolverError
        If either integration fails (for ``feedback="hull"`` the message suggests ``"system"``).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5", mbar=2.0, m1=26.0, m3=26.0)    # a 2 kg moving mass
    >>> d = gc.design_torque_control(veh, speed=1.6)
    >>> xe = np.array([d.speed, d.gamma, d.alpha, 0.0])
    >>> c = gc.compare_realized_torque(veh, d.law, xe + [0.16, 0.1, 0.0, 0.0], 5.0)
    >>> bool(c.max_difference["gamma"] < 1e-3), f"mass excursion {c.max_r_p1:.3f} m"
    (True, 'mass excursion 0.035 m')
    """
    require_glider(veh, "veh")
    require_instance("law", law, TorqueLaw)
    if veh.mbar <= 0:
        raise ModelError(f"vehicle '{veh.name}' has mbar = {veh.mbar:g} kg: realizing the torque needs a moving "
                         "mass (override mbar > 0 and reduce m1, m3 by the same amount to keep M_i = m_i + mbar)")
    x0 = checks.array("x0", x0, shape=(4,))
    if not x0[0] > 0:
        raise ArgumentError(f"x0 must start at a positive speed V > 0, got V = {x0[0]:g} m/s")
    ctrl = MovingMassTorque(veh, law, r_p3, omega_n, zeta, feedback)
    t_final = checks.positive("t_final", t_final, unit="s")
    if t_eval is None:
        te = np.unique(np.r_[np.linspace(0.0, t_final, 2001), np.geomspace(1e-7 * t_final, 1e-2 * t_final, 400)])
    else:
        te = checks.array("t_eval", t_eval, ndim=1, min_size=1)
        if te[0] < 0 or te[-1] > t_final or np.any(np.diff(te) < 0):
            raise ArgumentError(f"t_eval must be sorted output times in [0, t_final] = [0, {t_final:g}] s")
    pure = simulate(TorqueControlledGlider(veh), x0, t_final, law, t_eval=te, rtol=rtol, atol=atol,
                    time_limit=time_limit)
    loop = RealizedTorqueLoop(ctrl)
    try:
        real = simulate_realized_torque(loop, ctrl.initial_state(x0)[2:], te, method=method, rtol=rtol, atol=atol,
                                        max_nfev=max_nfev, time_limit=time_limit)
    except SolverError as exc:
        hint = (" With feedback='hull' the mass loop is unstable above omega_n ~ 2 zeta / c (see MovingMassTorque); "
                "use feedback='system'." if feedback == "hull" else "")
        raise SolverError(f"{exc}.{hint}") from None
    xa = loop.full_state(real.x)
    red = reduced_from_accel(xa)
    red_sys = reduced_from_accel(xa, veh)
    diff, diff_sys = np.abs(pure.x - red), np.abs(pure.x - red_sys)
    sp = singular_perturbation(law.closed_loop_vehicle(veh))
    xe = sp.equilibrium
    xa_e = np.array([0, 0, sp.gamma + sp.alpha, 0, sp.speed * math.cos(sp.alpha), sp.speed * math.sin(sp.alpha),
                     0, 0, r_p3, 0, veh.m0])
    names = REDUCED_STATES
    return RealizedTorqueComparison(
        pure, real, red,
        {k: float(diff[:, i].max()) for i, k in enumerate(names)},
        {k: float(diff_sys[:, i].max()) for i, k in enumerate(names)},
        {k: float(diff[-1, i]) for i, k in enumerate(names)},
        float(np.max(np.abs(ctrl.mass_torque(xa) - law.torque(ctrl.reduced_state(xa))))),
        xe, float(ctrl.r_p1_command(xa_e)), float(np.max(np.abs(real.state("r_P1")))),
        float(np.max(np.abs(real.state("rdot_P1")))), ctrl)
