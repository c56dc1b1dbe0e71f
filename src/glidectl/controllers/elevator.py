"""Elevator and buoyancy control, §6.3: equilibrium (6.20) of the model (6.14)-(6.19) for a requested
``(V_e, gamma_e)``, the laws (6.21)-(6.22), Theorem 3's condition (6.23), and the numerical example of Fig 6.2.

Model and sign convention
-------------------------
The plant, :class:`glidectl.models.elevator_glider.ElevatorBuoyancyGlider`, and the sign convention of the elevator
force and moment (with the corrections of (6.14), (6.18), (6.20), (6.23), (6.25) it implies) are documented in
:mod:`glidectl.models.elevator_glider`. In short: elevator moment ``K_M u2 V^2`` (N m, nose up positive), force
``-delta u2 V^2`` along body 3 (N, positive down); ``alpha_e = -K_M0/K_M - u2e`` ((6.20) prints ``+ u2e``),
``K'_De = K_D0 + K_D alpha_e^2 + delta u2e sin(alpha_e)`` and ``K'_Le = K_L0 + K_L alpha_e + delta u2e cos(alpha_e)``.

Fig 6.2 numbers
---------------
``J2`` is not printed; the vehicle file's ``J2 = 0.1 kg m^2`` is inferred from the printed ``eps2 = 0.012``
(:func:`infer_J2`). ``alpha_e`` does not depend on ``g``; the printed ``m0e = 2.657 kg`` is reproduced with
``g = 9.8`` (2.6573 kg), while the vehicle file's ``g = 9.81`` gives 2.6546 kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, InfeasibleGlideError, ModelError, SolverError
from ..models._validate import angle_arg, require_glider, require_instance, speed_arg, trailing_array
from ..models.buoyancy_glider import ActuatorLimits, actuator_limits
from ..models.elevator_glider import ElevatorBuoyancyGlider, effective_coefficients
from ..models.reduced import require_v2_pitch_damping
from ..params import Vehicle
from ..sim import Simulation, simulate
from ..stability.singular_perturbation import singular_perturbation

__all__ = [
    "ALPHA_MAX",
    "ElevatorBuoyancyController",
    "ElevatorEquilibrium",
    "ElevatorExample",
    "closed_loop_eigenvalues",
    "elevator_equilibrium",
    "elevator_example",
    "infer_J2",
]

ALPHA_MAX = 0.35  # rad: largest |alpha_e| accepted (validity of the linear lift / quadratic drag model)


@dataclass(frozen=True)
class ElevatorEquilibrium:
    """Closed-loop steady glide of §6.3 for a requested ``(V_e, gamma_e)``.

    Attributes
    ----------
    speed, gamma : float
        Requested ``V_e`` (m/s) and ``gamma_e`` (rad).
    alpha : float
        Equilibrium angle of attack ``alpha_e`` (rad).
    m0e : float
        Equilibrium buoyancy (kg).
    u2e : float
        Equilibrium elevator input (rad), ``-K_M0/K_M - alpha_e`` (corrected (6.20)).
    K_De, K_Le : float
        ``K_D0 + K_D alpha_e^2`` and ``K_L0 + K_L alpha_e`` (kg/m), without the elevator.
    K_De_eff, K_Le_eff : float
        ``K'_De``, ``K'_Le`` of Theorem 3 (kg/m), corrected (6.23) and (6.26).
    K_De_eff_printed : float
        (6.23) as printed, ``K_D0 + K_D alpha_e^2 - delta u2e V_e^2 sin(alpha_e)`` (mixed units), for comparison.
    m_e : float
        ``M3 = m3 + mbar`` at ``m0e`` (kg) (``m1 = m3 = m + m0e`` in §6.3).
    tau_s : float
        ``m_e / (K'_De V_e)`` (s), (6.27).
    eps1, eps2 : float
        ``(K_q/K_M)/tau_s`` and ``-J2/(K_q V_e^2 tau_s)``, (5.16)-(5.17) with (6.27).
    g : float
        Gravity used (m/s^2).
    alpha_roots : tuple of float
        All roots of the force balance with ``|alpha| <= alpha_max`` (rad); ``alpha`` is the smallest in size.
    residual : float
        ``max |x'|`` of :class:`ElevatorBuoyancyGlider` at the equilibrium with ``u = (0, u2e)``.
    vehicle : Vehicle
        The vehicle.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    certified : bool
        Theorem 3's condition (6.23), corrected: ``K'_De > 0`` (the laws (6.21)-(6.22) are certified here).
    """

    speed: float
    gamma: float
    alpha: float
    m0e: float
    u2e: float
    K_De: float
    K_Le: float
    K_De_eff: float
    K_Le_eff: float
    K_De_eff_printed: float
    m_e: float
    tau_s: float
    eps1: float
    eps2: float
    g: float
    alpha_roots: tuple[float, ...]
    residual: float
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = field(default="", repr=False)

    @property
    def certified(self) -> bool:
        """Theorem 3's condition (6.23), corrected: ``K'_De > 0``."""
        return self.K_De_eff > 0

    @property
    def state(self) -> np.ndarray:
        """``(speed, gamma, alpha, 0, m0e)``."""
        return np.array([self.speed, self.gamma, self.alpha, 0.0, self.m0e])

    @property
    def alpha_printed_620(self) -> float:
        """(6.20) as printed, ``-K_M0/K_M + u2e`` (rad): not the equilibrium with the stated torque."""
        return self.alpha + 2 * self.u2e


def _angle_balance(veh: Vehicle, gamma: float, a: Any) -> Any:
    """``K'_D(a) cos(gamma) + K'_L(a) sin(gamma)`` with ``u2 = -K_M0/K_M - a``: zero at a steady glide."""
    kd, kl = effective_coefficients(veh, a, -veh.K_M0 / veh.K_M - a)
    return kd * np.cos(gamma) + kl * np.sin(gamma)


def elevator_equilibrium(veh: Vehicle, speed: float, gamma: float, *,
                         alpha_max: float = ALPHA_MAX) -> ElevatorEquilibrium:
    """Equilibrium ``(m0e, alpha_e, u2e)`` of §6.3 for the requested steady glide ``(V_e, gamma_e)``.

    Moment balance (6.19) at ``Omega2 = 0``: ``u2e = -K_M0/K_M - alpha_e`` (corrected (6.20)). Force balance along
    and across the velocity ((6.14)-(6.15) at equilibrium, corrected):
    ``m0 g sin(gamma_e) = -K'_D V_e^2`` and ``m0 g cos(gamma_e) = K'_L V_e^2``, so ``alpha_e`` solves
    ``K'_D cos(gamma_e) + K'_L sin(gamma_e) = 0`` and ``m0e = (K'_L cos(gamma_e) - K'_D sin(gamma_e)) V_e^2 / g``.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with ``delta``; ``u2_max`` (rad) and ``m0_max`` (kg) are enforced when defined.
    speed : float
        ``V_e`` (m/s), in ``(0, 100]``.
    gamma : float
        ``gamma_e`` (rad), ``|gamma_e| < pi/2`` (positive climbing; ``gamma_e = 0`` has no steady glide).
    alpha_max : float
        Largest ``|alpha_e|`` accepted (rad), in ``(0, pi/2)``; the root of smallest ``|alpha|`` is returned.

    Returns
    -------
    ElevatorEquilibrium
        ``alpha_e`` (rad), ``m0e`` (kg), ``u2e`` (rad), the drag and lift coefficients with and without the elevator
        (kg/m), ``tau_s`` (s), ``eps1, eps2`` (nondimensional), all roots found (rad) and the equilibrium residual.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or a number is not a real number.
    ArgumentError
        If ``speed`` is not in ``(0, 100]`` m/s, ``gamma`` is not finite with ``|gamma_e| < pi/2`` rad, or
        ``alpha_max`` is not in ``(0, pi/2)``.
    InfeasibleGlideError
        No force balance with ``|alpha| <= alpha_max`` (e.g. ``gamma_e = 0``: level gliding needs zero drag),
        ``|u2e| > u2_max`` or ``|m0e| > m0_max``, or ``m0e = 0``.
    ModelError
        If ``veh`` is not an underwater glider, has no ``delta`` (or another parameter the model reads), or has
        ``K_M = 0``.
    SolverError
        If the root finder fails, or the equilibrium residual is not small relative to the forces at the glide.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> ev = gc.load_vehicle("elevator_ch6")
    >>> eq = gc.elevator_equilibrium(ev, speed=1.0, gamma=-np.pi / 4)
    >>> print(f"alpha_e = {np.degrees(eq.alpha):.3f} deg, m0e = {eq.m0e:.4f} kg, u2e = {np.degrees(eq.u2e):.3f} deg")
    alpha_e = 3.519 deg, m0e = 2.6546 kg, u2e = -2.087 deg
    """
    require_glider(veh, "veh")
    speed = speed_arg("speed V_e", speed)
    gamma = angle_arg("gamma_e", gamma, math.pi / 2, open_ends=True)
    alpha_max = checks.real("alpha_max", alpha_max, lo=0.0, hi=math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    model = ElevatorBuoyancyGlider(veh)
    if veh.K_M == 0:
        raise ModelError(f"vehicle '{veh.name}' has K_M = 0: the elevator moment K_M u2 V^2 vanishes")
    grid = np.linspace(-alpha_max, alpha_max, 4001)
    F = _angle_balance(veh, gamma, grid)
    roots = []
    if not np.all(np.isfinite(F)):
        raise SolverError(f"the force balance of vehicle '{veh.name}' is not finite on |alpha| <= {alpha_max:g} rad")
    for i in np.nonzero(np.sign(F[:-1]) * np.sign(F[1:]) <= 0)[0]:
        if F[i] == 0:
            roots.append(float(grid[i]))
        elif F[i + 1] != 0:
            try:
                roots.append(brentq(lambda a: float(_angle_balance(veh, gamma, a)), grid[i], grid[i + 1],
                                    xtol=1e-15, rtol=4 * np.finfo(float).eps))
            except (ValueError, RuntimeError) as exc:
                raise SolverError(f"root finding of the elevator force balance failed: {exc}") from exc
    roots = sorted(set(roots))
    if not roots:
        kd, kl = effective_coefficients(veh, grid, -veh.K_M0 / veh.K_M - grid)
        shallow = float(np.degrees(np.min(np.arctan2(np.abs(kd), np.abs(kl)))))
        raise InfeasibleGlideError(
            f"no steady glide at gamma_e = {math.degrees(gamma):.4g} deg for vehicle '{veh.name}': with |alpha| <= "
            f"{alpha_max:g} rad the drag/lift balance allows only |gamma_e| >= {shallow:.3g} deg (level or "
            "shallower gliding would need less drag); ask for a steeper glide")
    a_e = min(roots, key=abs)
    u2e = -veh.K_M0 / veh.K_M - a_e                                                        # (6.20), corrected
    lim = actuator_limits(veh)
    if not lim.u2_min <= u2e <= lim.u2_max:
        a_lo, a_hi = sorted((-veh.K_M0 / veh.K_M - lim.u2_max, -veh.K_M0 / veh.K_M - lim.u2_min))
        raise InfeasibleGlideError(
            f"gamma_e = {math.degrees(gamma):.4g} deg needs alpha_e = {a_e:.4g} rad and elevator u2e = {u2e:.4g} "
            f"rad, beyond the saturation [{lim.u2_min:g}, {lim.u2_max:g}] rad of vehicle '{veh.name}' "
            f"([actuators] elevator); reachable angles of attack are [{a_lo:.4g}, {a_hi:.4g}] rad")
    kd, kl = effective_coefficients(veh, a_e, u2e)
    m0e = float((kl * math.cos(gamma) - kd * math.sin(gamma)) * speed**2 / veh.g)
    if not lim.m0_in_range(m0e):
        raise InfeasibleGlideError(
            f"V_e = {speed:g} m/s, gamma_e = {math.degrees(gamma):.4g} deg needs buoyancy m0e = {m0e:.4g} kg, outside "
            f"the range [{lim.m0_min:g}, {lim.m0_max:g}] kg of vehicle '{veh.name}' ([actuators] m0); ask for a "
            "lower speed")
    if m0e == 0:
        raise InfeasibleGlideError("the requested glide needs neutral buoyancy m0e = 0 (no steady glide)")
    K_De = veh.K_D0 + veh.K_D * a_e**2
    K_Le = veh.K_L0 + veh.K_L * a_e
    printed = K_De - veh.delta * u2e * speed**2 * math.sin(a_e)                            # (6.23) as printed
    m_e = float(veh.mass(3, m0e) + veh.mbar)
    require_v2_pitch_damping(veh, "the elevator equilibrium's small parameters (5.16)-(5.17)")
    if not (m_e > 0 and kd != 0 and veh.K_q != 0):
        raise ModelError(f"vehicle '{veh.name}' at the glide V_e = {speed:g} m/s, gamma_e = {gamma:g} rad has "
                         f"M3 = {m_e:g} kg, K'_De = {float(kd):g} kg/m, K_q = {veh.K_q:g}: the time scale (6.27) and "
                         "the small parameters (5.16)-(5.17) need M3 > 0, K'_De != 0 and K_q != 0")
    tau_s = m_e / (kd * speed)                                                             # (6.27)
    eps1 = (veh.K_q / veh.K_M) / tau_s                                                     # (5.16)
    eps2 = -(veh.J2 / (veh.K_q * speed**2)) / tau_s                                        # (5.17)
    x_e = np.array([speed, gamma, a_e, 0.0, m0e])
    res = float(np.max(np.abs(model.rhs(x_e, np.array([0.0, u2e])))))
    scale = max(abs(m0e) * veh.g / m_e, speed / abs(tau_s))  # the accelerations involved
    if not res <= 1e-8 * scale:
        raise SolverError(f"the elevator equilibrium at V_e = {speed:g} m/s, gamma_e = {gamma:g} rad has a residual "
                          f"{res:.3g} (relative {res / scale:.3g}): not an equilibrium to working accuracy")
    return ElevatorEquilibrium(float(speed), float(gamma), float(a_e), m0e, float(u2e), float(K_De), float(K_Le),
                               float(kd), float(kl), float(printed), m_e, float(tau_s), float(eps1), float(eps2),
                               float(veh.g), tuple(roots), res, veh, veh.provenance)


def infer_J2(veh: Vehicle, eps2: float, speed: float, gamma: float) -> float:
    """``J2`` (kg m^2) for which :func:`elevator_equilibrium` gives a printed ``eps2``: ``J2 = eps2 |K_q| V_e^2
    tau_s`` with ``tau_s`` of (6.27) (independent of ``J2``).

    Parameters
    ----------
    veh : Vehicle
        Elevator glider (its own ``J2`` is not used).
    eps2 : float
        Small parameter (5.17) to reproduce (dimensionless); the thesis Fig 6.2 example prints ``0.012``.
    speed : float
        ``V_e`` (m/s) of the glide; the Fig 6.2 example uses 1.0.
    gamma : float
        ``gamma_e`` (rad); the Fig 6.2 example uses ``-pi/4``.

    Returns
    -------
    float
        Pitch inertia ``J2`` (kg m^2) that gives ``eps2`` at this glide.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or a number is not a real number.
    ArgumentError
        If ``eps2`` is not a positive finite number, or ``speed``/``gamma`` are out of range (see
        :func:`elevator_equilibrium`).
    ModelError
        If ``veh`` is not an elevator glider, or has ``K_q >= 0`` (no pitch damping: (5.17) needs ``K_q < 0``).
    InfeasibleGlideError
        If no steady glide exists at ``(speed, gamma)`` (see :func:`elevator_equilibrium`).
    SolverError
        If the equilibrium computation fails (see :func:`elevator_equilibrium`).

    Examples
    --------
    >>> import math
    >>> import glidectl as gc
    >>> J2 = gc.infer_J2(gc.load_vehicle("elevator_ch6"), eps2=0.012, speed=1.0, gamma=-math.pi / 4)
    >>> print(f"{J2:.4f} kg m^2")
    0.0999 kg m^2
    """
    eps2 = checks.positive("eps2", eps2)
    eq = elevator_equilibrium(veh, speed, gamma)
    if not veh.K_q < 0:
        raise ModelError(f"vehicle '{veh.name}' has K_q = {veh.K_q:g}: eps2 = -J2/(K_q V_e^2 tau_s) (5.17) needs "
                         "pitch damping K_q < 0")
    return float(-eps2 * veh.K_q * speed**2 * eq.tau_s)


@dataclass(frozen=True)
class ElevatorBuoyancyController:
    """Laws (6.21)-(6.22): ``controller(t, x) -> (u1 [kg/s], u2 [rad])``, saturations applied.

    ``u1 = (m_e/tau_s)(-K mbar0) = -(K/tau_s)(m0 - m0e)`` through the pump limits (rate ``u4_max``, range
    ``m0_max``), ``u2 = clip(u2e, -u2_max, u2_max)``.

    Parameters
    ----------
    eq : ElevatorEquilibrium
    vehicle : Vehicle
    K : float
        Gain of (6.21), > 0 (nondimensional, time ``t_n = t/tau_s`` of (6.27)).

    Raises
    ------
    ArgumentTypeError
        If ``eq`` is not an ElevatorEquilibrium, ``vehicle`` not a Vehicle or ``K`` not a real number.
    ArgumentError
        If ``K`` is not a positive finite number.
    ModelError
        If ``vehicle`` is not an underwater glider.
    VehicleMismatchError
        If ``eq`` was computed for another vehicle.
    """

    eq: ElevatorEquilibrium
    vehicle: Vehicle
    K: float = 1.0

    def __post_init__(self) -> None:
        require_instance("eq", self.eq, ElevatorEquilibrium, " (from gc.elevator_equilibrium)")
        require_glider(self.vehicle)
        checks.same_vehicle("eq", self.eq, self.vehicle)
        object.__setattr__(self, "K", checks.positive("the buoyancy gain K of (6.21)", self.K))

    @cached_property
    def _limits(self) -> ActuatorLimits:
        """Pump and elevator limits of the vehicle (built once: the law is called many times)."""
        return actuator_limits(self.vehicle)

    def __call__(self, t: float, x: Any) -> np.ndarray:
        return self.u(x)

    def u(self, x: Any) -> np.ndarray:
        """Inputs ``(u1 [kg/s], u2 [rad])``, shape ``x.shape[:-1] + (2,)``, at states
        ``x = (V, gamma, alpha, Omega2, m0)`` (shape ``(..., 5)``)."""
        lim = self._limits
        m0 = trailing_array("x", x, 5)[..., 4]
        u1 = lim.pump(m0, -(self.K / self.eq.tau_s) * (m0 - self.eq.m0e))
        u2 = np.broadcast_to(lim.elevator(self.eq.u2e), np.shape(u1))
        return np.stack([u1, u2], axis=-1)


def closed_loop_eigenvalues(eq: ElevatorEquilibrium, veh: Vehicle, K: float = 1.0) -> np.ndarray:
    """Eigenvalues (1/s) of the closed loop (6.14)-(6.18), (6.21)-(6.22) linearized at the equilibrium.

    Theorem 3 claims local asymptotic stability when ``K'_De > 0``; all real parts negative confirms it for this
    vehicle. Exact complex-step Jacobian of the one closed-loop right-hand side (``m0`` and the saturations carry
    the complex step).

    Parameters
    ----------
    eq : ElevatorEquilibrium
        The equilibrium (:func:`elevator_equilibrium` for ``veh``).
    veh : Vehicle
        The elevator glider (underwater glider with ``delta``).
    K : float
        Gain of (6.21), ``> 0`` (nondimensional).

    Returns
    -------
    numpy.ndarray, shape (5,)
        Eigenvalues (1/s) of the linearized closed loop in ``(V, gamma, alpha, Omega2, m0)``, sorted by real part,
        then imaginary part.

    Raises
    ------
    ArgumentTypeError
        If ``eq`` is not an ElevatorEquilibrium, ``veh`` not a Vehicle or ``K`` not a real number.
    ArgumentError
        If ``K`` is not a positive finite number.
    VehicleMismatchError
        If ``eq`` was computed for another vehicle than ``veh``.
    ModelError
        If ``veh`` is not an underwater glider or has no ``delta``.
    SolverError
        If the Jacobian is not finite or the eigenvalue computation fails.

    Examples
    --------
    >>> import math
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("elevator_ch6")
    >>> eq = gc.elevator_equilibrium(veh, 1.0, -math.pi / 4)
    >>> ev = gc.elevator_closed_loop_eigenvalues(eq, veh, K=1.0)
    >>> ev.shape, f"{ev.real.max():.3f}"                     # Theorem 3: locally asymptotically stable
    ((5,), '-0.601')
    """
    ctrl = ElevatorBuoyancyController(eq, veh, K)
    model = ElevatorBuoyancyGlider(veh)
    A, _ = jacobians(lambda x, u: model.rhs(x, ctrl(0.0, x)), eq.state, np.zeros(0))
    if not np.all(np.isfinite(A)):
        raise SolverError("the Jacobian of the elevator closed loop at the equilibrium is not finite")
    try:
        lam = np.linalg.eigvals(A)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of the elevator closed loop did not converge: {exc}") from exc
    return lam[np.lexsort((lam.imag, lam.real))]


@dataclass(frozen=True)
class ElevatorExample:
    """Closed-loop run of the §6.3 example (Fig 6.2).

    Attributes
    ----------
    eq : ElevatorEquilibrium
    sim : Simulation
    x0 : ndarray
        Initial state ``(V, gamma, alpha, Omega2, m0)``.
    initial_condition : str
        How ``x0`` was chosen (the thesis does not print it).
    final_error : ndarray
        ``x(t_final) - x_e``.
    max_abs_u2, max_abs_m0dot, max_abs_m0 : float
        Largest elevator input (rad), pump rate (kg/s) and buoyancy (kg) along the run.
    limits : ActuatorLimits
    """

    eq: ElevatorEquilibrium
    sim: Simulation = field(repr=False)
    x0: np.ndarray
    initial_condition: str
    final_error: np.ndarray
    max_abs_u2: float
    max_abs_m0dot: float
    max_abs_m0: float
    limits: ActuatorLimits


def elevator_example(veh: Vehicle, speed: float, gamma: float, *, t_final: float = 10.0, K: float = 1.0,
                     m0_start: float = 2.5, x0: Any = None) -> ElevatorExample:
    """Close the loop (6.21)-(6.22) on :class:`ElevatorBuoyancyGlider` towards ``(speed, gamma)`` and simulate
    ``t_final`` seconds, as in the example of Fig 6.2.

    The thesis Fig 6.2 example is ``speed = 1.0`` m/s, ``gamma = -pi/4`` rad on the ``elevator_ch6`` vehicle; it
    prints ``alpha_e = 3.51`` deg, ``m0e = 2.657`` kg, ``eps1 = 0.075`` and ``eps2 = 0.012`` (see
    :func:`elevator_equilibrium` and the module docstring for the reproduction).

    The thesis prints no initial condition. The default start is the steady glide the same vehicle flies with the
    elevator neutral (``u2 = 0``) and buoyancy ``m0_start`` kg (chapter-5 equilibrium (5.8)-(5.10), from
    :func:`glidectl.stability.singular_perturbation.singular_perturbation`): for ``elevator_ch6`` and 2.5 kg that is
    ``V = 1.120 m/s``, ``gamma = -67.46 deg``, ``alpha = -K_M0/K_M = 1.43 deg``; towards the Fig 6.2 target the
    controller then brings the glide to ``(1 m/s, -45 deg)``, the pump working at its rate limit at first.

    Parameters
    ----------
    veh : Vehicle
    speed : float
        Target ``V_e`` (m/s); 1.0 in Fig 6.2.
    gamma : float
        Target ``gamma_e`` (rad); ``-pi/4`` in Fig 6.2.
    t_final : float
        Duration (s), in ``(0, 10^5]``; the run is bounded by the integration budgets of
        :func:`glidectl.sim.simulate`.
    K : float
        Gain of (6.21).
    m0_start : float
        Buoyancy (kg) of the default initial glide, finite and nonzero.
    x0 : array_like, optional
        Explicit initial state ``(V, gamma, alpha, Omega2, m0)`` (m/s, rad, rad, rad/s, kg), finite, ``V > 0``.

    Returns
    -------
    ElevatorExample
        The equilibrium, the simulation, the initial state and how it was chosen, the final error ``x(t_final) -
        x_e`` (state units), and the largest elevator input (rad), pump rate (kg/s) and buoyancy (kg) of the run.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or an argument has the wrong type.
    ArgumentError
        If ``speed``/``gamma`` are out of range, ``K`` or ``t_final`` is not a positive finite number
        (``t_final <= 10^5`` s), ``m0_start`` is not finite and nonzero, or ``x0`` is not 5 finite numbers with
        ``V > 0``.
    InfeasibleGlideError
        If the target glide does not exist within the vehicle's limits (:func:`elevator_equilibrium`).
    ModelError
        If ``veh`` is not an underwater glider, lacks ``delta``, has ``K_M = 0``, or (default start) has no
        chapter-5 steady glide at ``m0_start`` (from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).
    BudgetError
        If the integration hits its step or evaluation budget (:func:`glidectl.sim.simulate`).
    SolverError
        If the equilibrium computation or the integration fails.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import glidectl as gc
    >>> ex = gc.elevator_example(gc.load_vehicle("elevator_ch6"), 1.0, -math.pi / 4)    # Fig 6.2
    >>> print(f"m0e = {ex.eq.m0e:.3f} kg, pump rate up to {ex.max_abs_m0dot:.3f} kg/s")
    m0e = 2.655 kg, pump rate up to 0.050 kg/s
    >>> bool(np.abs(ex.final_error).max() < 1e-3)            # at the target glide after 10 s
    True
    """
    t_final = checks.real("t_final", t_final, lo=0.0, hi=1e5, lo_open=True, unit="s")
    if x0 is not None:
        x0 = checks.array("x0", x0, shape=(5,))
        if not x0[0] > 0:
            raise ArgumentError(f"x0 must start at a positive speed V > 0, got V = {x0[0]:g} m/s")
    else:
        m0_start = checks.real("m0_start", m0_start, unit="kg")
        if m0_start == 0:
            raise ArgumentError("m0_start must be nonzero (a neutrally buoyant glider has no steady glide)")
    eq = elevator_equilibrium(veh, speed, gamma)
    model = ElevatorBuoyancyGlider(veh)
    ctrl = ElevatorBuoyancyController(eq, veh, K)
    if x0 is None:
        sp = singular_perturbation(veh.with_overrides(m0=m0_start))
        x0 = np.array([sp.speed, sp.gamma, sp.alpha, 0.0, m0_start])
        how = (f"steady glide of the vehicle with u2 = 0 and m0 = {m0_start:g} kg (thesis prints no initial "
               "condition)")
    else:
        how = "given by the caller"
    sim = simulate(model, x0, t_final, ctrl, method="LSODA", rtol=1e-9, atol=1e-11)
    m0dot = model.rhs(sim.x, sim.u)[:, 4]
    return ElevatorExample(eq, sim, x0, how, sim.x[-1] - eq.state, float(np.max(np.abs(sim.u[:, 1]))),
                           float(np.max(np.abs(m0dot))), float(np.max(np.abs(sim.x[:, 4]))), model.limits)
