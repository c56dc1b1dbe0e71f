"""Steady straight glides of the longitudinal model: (2.26)-(2.29) reconstructed and solved in closed form.

Derivation (Leonard & Graver 2001, rewritten in this thesis's notation)
-----------------------------------------------------------------------
At a steady glide (Omega2 = 0, u = 0, rdot_P = 0) the force equations (2.18)-(2.19), rotated to the wind frame, are
``D = -m0 g sin(gamma)`` and ``L = m0 g cos(gamma)`` (as (5.4)-(5.5)), so ``tan(gamma) = -K_D(alpha)/K_L(alpha)``
with ``K_D(a) = K_D0 + K_D a^2`` and ``K_L(a) = K_L0 + K_L a``. A heavy vehicle (m0 > 0) glides down with
positive lift; a light one glides up with negative lift. Minimizing ``K_D/|K_L|`` over alpha gives the shallowest
glides, i.e. the permissible set (2.26) (missing from the text):

    gamma < -atan(2 K_D/K_L (sqrt((K_L0/K_L)^2 + K_D0/K_D) - K_L0/K_L))      (downward)
    gamma >  atan(2 K_D/K_L (sqrt((K_L0/K_L)^2 + K_D0/K_D) + K_L0/K_L))      (upward)

Given gamma, alpha solves the quadratic ``K_D a^2 -+ |tan gamma| K_L a + K_D0 -+ |tan gamma| K_L0 = 0``; of its two
roots the one of smaller ``|alpha|`` is taken (the other lies on the back side of the drag polar). Then
``m0 = K_L(alpha) V^2 / (g cos gamma)``; the moment equation (2.20) (equivalently (2.29)) fixes the component of
``r_P`` perpendicular to gravity, ``r_P1 cos(theta) + r_P3 sin(theta) = ((m3 - m1) v1 v3 + M_DL2)/(mbar g)``,
leaving the bottom-heaviness ``r_bh = r_P . R^T k = -r_P1 sin(theta) + r_P3 cos(theta)`` free.
(2.27)-(2.28) as printed are the inverse map; (2.28) returns theta, not gamma (docs/thesis-errata.md).

One solver: :func:`glide_trim_arrays` evaluates this trim elementwise over arrays of speeds and flight-path angles
(numpy, no Python loop); :func:`steady_glide` calls it for one point and turns its status codes into errors, and
:func:`~glidectl.trim.envelope.glide_envelope` calls it for a whole grid. When the vehicle file has an
``[actuators]`` table, :func:`steady_glide` also refuses trims that need ``m0``, ``r_P1`` or ``r_P3`` outside it.

Argument limits (plausibility): speeds in ``(0, SPEED_MAX]`` = (0, 100] m/s, moving-mass offsets ``|r_p3|, |r_bh| <=
R_P_MAX`` = 10 m; a speed so small that the forces underflow is refused. The trim is accepted only when the residual
of every equation is below ``RESIDUAL_TOL`` (1e-9) relative to the largest term of that equation.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError, SolverError
from ..hydro import best_glide_angle, lift_drag, zero_lift_angle
from ..models.glider3d import R_P_MAX
from ..models.longitudinal import LongitudinalGlider
from ..params import Vehicle
from .flight import efficient_root

__all__ = ["RESIDUAL_TOL", "SPEED_MAX", "SteadyGlide", "alpha_for_gamma", "permissible_gamma", "steady_glide"]

#: Largest glide speed accepted (m/s): a plausibility limit for underwater gliders.
SPEED_MAX = 100.0
#: Largest residual of a trim equation relative to the largest term of that equation.
RESIDUAL_TOL = 1e-9


def _check_glider(veh: Any) -> Vehicle:
    checks.vehicle("veh", veh)
    if veh.kind != "underwater_glider":
        raise ModelError(f"vehicle '{veh.name}' is a {veh.kind}; steady glides here are for underwater gliders "
                         "(use ctol_glide for the CTOL aircraft)")
    return veh


def _shallowest_law(veh: Vehicle, speed: float | None) -> tuple[float, float, float, float]:
    """alpha and |tan gamma| of the shallowest glides of a law other than the thesis's: the smallest drag-to-lift
    ratio, found numerically (its lift and drag are odd and even in alpha, so the up glide mirrors the down one)."""
    if veh.law == "seaglider" and speed is None:
        raise ArgumentError(f"vehicle '{veh.name}' uses the seaglider law, whose glide ratio depends on the speed "
                            "(drag hd_b q^(-1/4)): pass speed= (m/s)")
    V2 = 1.0 if speed is None else float(speed) ** 2
    a = float(best_glide_angle(veh, V2))
    if not math.isfinite(a):
        raise InfeasibleGlideError(f"vehicle '{veh.name}': the '{veh.law}' law's drag has no alpha^2 term, so the "
                                   "glide ratio has no minimum and the permissible set (2.26) is not defined")
    L, D = lift_drag(veh, V2, a)
    return a, float(D / L), -a, float(D / L)


def _shallowest(veh: Vehicle, speed: float | None = None) -> tuple[float, float, float, float]:
    """alpha and |tan gamma| of the shallowest downward and upward glides."""
    if veh.law != "thesis":
        return _shallowest_law(veh, speed)
    KD0, KD, KL0, KL = veh.K_D0, veh.K_D, veh.K_L0, veh.K_L
    if KD == 0:
        raise InfeasibleGlideError(
            f"vehicle '{veh.name}' has K_D = 0: the glide ratio has no minimum and the permissible set (2.26) is "
            "not defined")
    root = math.sqrt((KL0 / KL) ** 2 + KD0 / KD)
    a_down = -KL0 / KL + root
    a_up = -KL0 / KL - root
    return a_down, 2 * KD * a_down / KL, a_up, -2 * KD * a_up / KL


def permissible_gamma(veh: Vehicle, speed: float | None = None) -> tuple[float, float]:
    """Bounds of the permissible flight-path-angle set (2.26), reconstructed (see module docstring).

    For the thesis law the bounds are closed-form; for the other lift and drag laws
    (:func:`glidectl.hydro.lift_drag`) they come from the smallest drag-to-lift ratio, found numerically.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (thesis law: ``K_D0, K_D, K_L0, K_L``).
    speed : float, optional
        Glide speed (m/s): needed for the seaglider law, whose glide ratio improves with speed; the thesis and
        gliderflight laws' ratios do not depend on it.

    Returns
    -------
    (lo, hi) : tuple of float
        Radians, ``lo <= 0 <= hi``: steady glides exist for ``gamma < lo`` (down) or ``gamma > hi`` (up), with
        ``|gamma| < pi/2``. ``lo = hi = 0`` only when ``K_D0 = K_L0 = 0``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If ``veh`` is not an underwater glider.
    InfeasibleGlideError
        If ``K_D = 0`` (the glide ratio has no minimum, so the permissible set is not defined).
    ArgumentError
        For the seaglider law without ``speed``, or a speed that is not positive and finite.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> lo, hi = gc.permissible_gamma(gc.load_vehicle("rogue"))
    >>> print(f"glides for gamma < {np.degrees(lo):.2f} deg or gamma > {np.degrees(hi):.2f} deg")
    glides for gamma < -16.15 deg or gamma > 16.15 deg
    """
    _check_glider(veh)
    if speed is not None:
        speed = checks.real("speed", speed, lo=0.0, lo_open=True, hi=SPEED_MAX, unit="m/s")
    _, t_down, _, t_up = _shallowest(veh, speed)
    return -math.atan(t_down), math.atan(t_up)


@dataclass(frozen=True)
class SteadyGlide:
    """A steady straight glide of the longitudinal model (a relative equilibrium of (2.17)-(2.25)).

    Attributes
    ----------
    speed : float
        V_e (m/s).
    gamma, alpha, theta : float
        Flight-path angle, angle of attack, pitch angle (rad), ``theta = gamma + alpha``.
    m0 : float
        Net buoyancy (kg); > 0 heavy (down glide), < 0 light (up glide).
    r_p1, r_p3, r_bh : float
        Moving-mass position (m) and bottom-heaviness ``r_bh = r_P . R^T k`` (m).
    v1, v3 : float
        Body velocities (m/s).
    residual : float
        max ``|f(x_e, 0)|`` over the relative-equilibrium states (SI units), evaluated on the force model.
    vehicle : Vehicle
        The vehicle (``vehicle.name`` for its name).
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    mbar : float
        Moving mass (kg) of that vehicle.
    """

    speed: float
    gamma: float
    alpha: float
    theta: float
    m0: float
    r_p1: float
    r_p3: float
    r_bh: float
    v1: float
    v3: float
    residual: float
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str
    mbar: float

    @property
    def P_p1(self) -> float:
        """Equilibrium momentum of the moving mass along body 1 (kg m/s): ``mbar v1``."""
        return self.mbar * self.v1

    @property
    def P_p3(self) -> float:
        """Equilibrium momentum of the moving mass along body 3 (kg m/s): ``mbar v3``."""
        return self.mbar * self.v3

    def force_state(self, x: float = 0.0, z: float = 0.0) -> np.ndarray:
        """Equilibrium state of :class:`~glidectl.models.longitudinal.LongitudinalGlider`.

        Parameters
        ----------
        x, z : float
            Inertial position (m), finite.

        Returns
        -------
        ndarray, shape (11,)

        Raises
        ------
        ArgumentTypeError
            If ``x`` or ``z`` is not a real number.
        ArgumentError
            If it is not finite.
        """
        x, z = checks.real("x", x, unit="m"), checks.real("z", z, unit="m")
        return np.array([x, z, self.theta, 0.0, self.v1, self.v3, self.r_p1, self.r_p3,
                         self.mbar * self.v1, self.mbar * self.v3, self.m0])

    def accel_state(self, x: float = 0.0, z: float = 0.0) -> np.ndarray:
        """Equilibrium state of :class:`~glidectl.models.longitudinal.AccelerationControlledGlider`.

        Parameters
        ----------
        x, z : float
            Inertial position (m), finite.

        Returns
        -------
        ndarray, shape (11,)

        Raises
        ------
        ArgumentTypeError
            If ``x`` or ``z`` is not a real number.
        ArgumentError
            If it is not finite.
        """
        x, z = checks.real("x", x, unit="m"), checks.real("z", z, unit="m")
        return np.array([x, z, self.theta, 0.0, self.v1, self.v3, self.r_p1, 0.0, self.r_p3, 0.0, self.m0])

    def as_dict(self) -> dict[str, float | str]:
        """Plain dict (SI units, radians) for tables and JSON."""
        out: dict[str, float | str] = {k: getattr(self, k) for k in ("speed", "gamma", "alpha", "theta", "m0", "r_p1",
                                                                     "r_p3", "r_bh", "v1", "v3", "residual")}
        return {**out, "vehicle": self.vehicle.name, "provenance": self.provenance}


def alpha_for_gamma(veh: Vehicle, gamma: float, speed: float | None = None) -> float:
    """Angle of attack (rad) of the steady glide at flight-path angle ``gamma`` (rad): the force balance (2.26).

    In a steady glide the lift and drag balance the net weight, so ``tan(gamma) = -K_D(alpha) / K_L(alpha)`` with
    ``K_D = K_D0 + K_D alpha^2`` and ``K_L = K_L0 + K_L alpha`` (kg/m). With ``t = |tan(gamma)|`` and ``s`` the sign
    of the lift (``s = 1`` gliding down, ``gamma < 0``; ``s = -1`` gliding up) this is the quadratic
    ``K_D alpha^2 - s t K_L alpha + (K_D0 - s t K_L0) = 0``; of its roots with lift of sign ``s`` the one of
    smallest ``|alpha|`` is returned (solved in the cancellation-free form). The speed does not enter. For the
    other lift and drag laws the balance ``D cos(gamma) + L sin(gamma) = 0`` is solved numerically for the root
    nearest zero lift (:func:`glidectl.trim.flight.efficient_root`); the seaglider law needs the speed.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider; uses ``K_D0``, ``K_D``, ``K_L0``, ``K_L`` (kg/m, kg/m/rad^2, kg/m, kg/m/rad).
    gamma : float
        Flight-path angle (rad), ``0 < |gamma| < pi/2``; negative gliding down.
    speed : float, optional
        Glide speed (m/s); needed for the seaglider law only.

    Returns
    -------
    float
        ``alpha`` (rad).

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle or ``gamma`` not a real number.
    ArgumentError
        ``gamma`` is not finite.
    ModelError
        ``veh`` is not an underwater glider.
    InfeasibleGlideError
        ``gamma`` outside the permissible set (no real root with lift of the right sign), or ``|gamma| >= pi/2``;
        see :func:`permissible_gamma`.
    """
    _check_glider(veh)
    gamma = checks.real("gamma (flight-path angle)", gamma, unit="rad")
    if not abs(gamma) < math.pi / 2:
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg: a steady glide needs "
                                   "|gamma| < 90 deg")
    if speed is None and veh.law == "seaglider":
        raise ArgumentError(f"vehicle '{veh.name}' uses the seaglider law, whose glide angle of attack depends on "
                            "the speed: pass speed= (m/s)")
    alpha, why = _alpha_array(veh, np.array([gamma]), None if speed is None else np.array([float(speed)]))
    if why[0] == _NO_ROOT:
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg for vehicle "
                                   f"'{veh.name}': outside the permissible set (2.26)")
    if why[0] == _WRONG_SIGN:
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg for vehicle "
                                   f"'{veh.name}': no angle of attack gives lift of the sign the glide needs (2.26)")
    return float(alpha[0])


# reasons _alpha_array finds no angle of attack
_NO_ROOT, _WRONG_SIGN = 1, 2


def _alpha_law(veh: Vehicle, gamma: np.ndarray, speed: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_alpha_array` for a law other than the thesis's: the root of ``D/L + tan(gamma)`` (lift of the sign
    the glide needs) nearest zero lift, searched up to the best glide ratio's angle (:func:`best_glide_angle`), at
    speed ``speed`` (m/s; 1 where the law's ratio does not depend on it): no glide where the ratio there is above
    ``|tan(gamma)|``."""
    gam, V = np.broadcast_arrays(gamma, 1.0 if speed is None else np.asarray(speed, dtype=float))
    g, V2 = gam.ravel(), (V * V).ravel()

    def residual(alpha: np.ndarray, rows: np.ndarray) -> np.ndarray:
        gr, vr = (g[rows], V2[rows]) if alpha.ndim == 1 else (g[rows, None], V2[rows, None])
        L, D = lift_drag(veh, vr, alpha)
        with np.errstate(divide="ignore", invalid="ignore"):
            return D / np.abs(L) - np.abs(np.tan(gr))

    inside = (np.abs(g) < math.pi / 2) & (g != 0)
    alpha, found = efficient_root(residual, zero_lift_angle(veh), np.where(inside, -np.sign(g), 0.0),
                                  best_glide_angle(veh, V2))
    why = np.where(found, 0, _NO_ROOT).astype(np.int8)
    return alpha.reshape(gam.shape), why.reshape(gam.shape)


def _alpha_array(veh: Vehicle, gamma: np.ndarray, speed: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Vectorized core of :func:`alpha_for_gamma`: ``alpha`` (NaN where none) and a reason code per point.

    Same quadratic and root choice as documented there, elementwise over ``gamma`` (rad, any shape, finite). The
    reason is 0 (found), ``_NO_ROOT`` (no real root, ``|gamma| >= pi/2`` or ``K_D = 0`` at ``gamma = 0``) or
    ``_WRONG_SIGN`` (no root with lift of the sign the glide needs). Laws other than the thesis's:
    :func:`_alpha_law` at ``speed`` (m/s).
    """
    gamma = np.asarray(gamma, dtype=float)
    if veh.law != "thesis":
        return _alpha_law(veh, gamma, speed)
    KD0, KD, KL0, KL = veh.K_D0, veh.K_D, veh.K_L0, veh.K_L
    with np.errstate(all="ignore"):
        t = np.abs(np.tan(gamma))
        s = np.where(gamma < 0, 1.0, -1.0)  # sign of the lift coefficient K_L(alpha) (= sign of m0)
        # K_D a^2 - s t K_L a + (K_D0 - s t K_L0) = 0
        a1, a0 = -s * t * KL, KD0 - s * t * KL0
        if KD == 0:
            has_root = a1 != 0  # K_D = 0 and gamma = 0: no lift is needed and none can balance the drag
            r1 = np.where(has_root, -a0 / np.where(has_root, a1, 1.0), np.nan)
            r2 = r1
        else:
            disc = a1 * a1 - 4 * KD * a0
            has_root = disc >= 0
            sq = np.sqrt(np.where(has_root, disc, 0.0))
            q = -0.5 * (a1 + np.copysign(sq, a1))  # numerically stable pair
            qz = q == 0
            r1 = np.where(qz, 0.0, q / KD)
            r2 = np.where(qz, 0.0, a0 / np.where(qz, 1.0, q))
        ok1 = has_root & (s * (KL0 + KL * r1) > 0)
        ok2 = has_root & (s * (KL0 + KL * r2) > 0)
    has_root &= np.abs(gamma) < math.pi / 2
    ok1 &= has_root
    ok2 &= has_root
    pick1 = ok1 & (~ok2 | (np.abs(r1) <= np.abs(r2)))
    alpha = np.where(pick1, r1, np.where(ok2, r2, np.nan))
    why = np.where(ok1 | ok2, 0, np.where(has_root, _WRONG_SIGN, _NO_ROOT)).astype(np.int8)
    return alpha, why


def steady_glide(veh: Vehicle, speed: float, gamma: float, *, r_p3: float | None = None,
                 r_bh: float | None = None) -> SteadyGlide:
    """Steady glide of the longitudinal model for a requested speed and flight-path angle.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with ``mbar > 0``.
    speed : float
        Glide speed V_e (m/s), in ``(0, SPEED_MAX]`` = (0, 100] m/s.
    gamma : float
        Flight-path angle (rad), in the permissible set (2.26): ``gamma < lo`` or ``gamma > hi`` of
        :func:`permissible_gamma`, and ``|gamma| < pi/2``.
    r_p3 : float, optional
        Vertical moving-mass position (m), ``|r_p3| <= R_P_MAX`` (10 m); selects one member of the one-parameter
        family of mass positions.
    r_bh : float, optional
        Bottom-heaviness ``r_P . R^T k`` (m), ``|r_bh| <= R_P_MAX``; the alternative parameterization. Give exactly
        one of the two.

    Returns
    -------
    SteadyGlide
        With the trim residual checked: every equation's residual is below :data:`RESIDUAL_TOL` (1e-9) relative to
        the largest term of that equation, else :class:`~glidectl.errors.SolverError`.

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle, or ``speed``, ``gamma``, ``r_p3`` or ``r_bh`` is not a real number (``str``,
        ``None``, ``bool``...; 0-d numpy arrays are accepted). Arrays of one or more elements are refused with a
        pointer to :func:`~glidectl.trim.envelope.glide_envelope`, which trims a whole grid at once.
    ArgumentError
        Not exactly one of ``r_p3`` and ``r_bh`` given; a non-finite value; ``speed`` outside ``(0, 100]`` m/s or so
        small that the hydrodynamic forces underflow; ``|r_p3|`` or ``|r_bh|`` above 10 m.
    ModelError
        ``veh`` is not an underwater glider or has no moving mass (``mbar = 0``).
    InfeasibleGlideError
        gamma outside the permissible set (the message states the set), or a mass position that cannot realize
        the moment balance (r_p3 given at ``|theta| = 90 deg``, or a moment balance that needs the moving mass more
        than R_P_MAX = 10 m from the centre, as near-vertical glides do). Also when the vehicle's ``[actuators]``
        table limits ``m0``, ``r_P1`` or ``r_P3`` and the trim needs a setting outside that range (or off a fixed
        setting); the message names the actuator and the limit. Vehicles without the table are not limited.
    SolverError
        The relative residual check fails (please report the vehicle file).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)
    >>> print(f"m0 = {g.m0:.4f} kg, alpha = {np.degrees(g.alpha):.2f} deg, r_p1 = {g.r_p1:.4f} m")
    m0 = 0.2386 kg, alpha = 3.44 deg, r_p1 = 0.0353 m
    """
    _check_glider(veh)
    LongitudinalGlider(veh)  # validates mbar > 0
    for name, value in (("speed", speed), ("gamma", gamma), ("r_p3", r_p3), ("r_bh", r_bh)):
        if isinstance(value, list | tuple | np.ndarray) and np.ndim(value) > 0:
            raise ArgumentTypeError(f"steady_glide takes one glide: {name} must be a real number, got an array of "
                                    f"shape {np.shape(value)}; for a grid of speeds and flight-path angles use "
                                    "glide_envelope(veh, speeds, gammas)")
    if (r_p3 is None) == (r_bh is None):
        raise ArgumentError("give exactly one of r_p3= (m) or r_bh= (m) to pick the moving-mass position "
                            "from the one-parameter family of equilibria")
    V = checks.real("speed (glide speed)", speed, lo=0.0, lo_open=True, hi=SPEED_MAX, unit="m/s")
    gamma = checks.real("gamma (flight-path angle)", gamma, unit="rad")
    if r_p3 is not None:
        r_p3 = checks.real("r_p3 (vertical moving-mass position)", r_p3, lo=-R_P_MAX, hi=R_P_MAX, unit="m")
    if r_bh is not None:
        r_bh = checks.real("r_bh (bottom-heaviness)", r_bh, lo=-R_P_MAX, hi=R_P_MAX, unit="m")
    lo, hi = permissible_gamma(veh, V if veh.law == "seaglider" else None)
    set_text = (f"permissible flight-path angles for '{veh.name}' (2.26): gamma < {math.degrees(lo):.4f} deg "
                f"(down) or gamma > {math.degrees(hi):.4f} deg (up), |gamma| < 90 deg")
    tr = glide_trim_arrays(veh, np.array([V]), np.array([gamma]), r_p3=r_p3, r_bh=r_bh)
    status = int(tr.status[0])
    q = {k: float(getattr(tr, k)[0]) for k in ("alpha", "theta", "m0", "r_p1", "r_p3", "r_bh", "v1", "v3",
                                                "residual", "relative_residual")}
    if status == NO_GLIDE:
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg: {set_text}")
    if status == UNDERFLOW:
        raise ArgumentError(f"speed = {V:g} m/s is so small that the hydrodynamic forces and the net buoyancy m0 "
                            f"= {q['m0']:g} kg underflow; ask for a speed of at least 1e-150 m/s")
    if status == PITCH_90:
        raise InfeasibleGlideError("pitch angle is 90 deg: r_p3 cannot select the mass position; give r_bh")
    if status == NON_FINITE:
        raise InfeasibleGlideError(f"non-finite equilibrium for speed={V}, gamma={gamma}")
    if status == BEYOND_R_P_MAX:
        rp1, rp3, rbh = q["r_p1"], q["r_p3"], q["r_bh"]
        given = f"r_p3 = {rp3:g} m" if r_bh is None else f"r_bh = {rbh:g} m"
        raise InfeasibleGlideError(
            f"the moment balance of the glide at gamma = {math.degrees(gamma):.4f} deg with {given} needs the moving "
            f"mass at r_P = ({rp1:.4g}, {rp3:.4g}) m, {math.hypot(rp1, rp3):.4g} m from the centre of buoyancy: "
            f"beyond the plausibility limit R_P_MAX = {R_P_MAX:g} m; choose a shallower glide or another "
            "r_p3 / r_bh")
    if status == RESIDUAL_FAILED:
        raise SolverError(f"steady-glide residual {q['residual']:.3e} is {q['relative_residual']:.2e} of the largest "
                          f"term of its equation (tolerance {RESIDUAL_TOL:g}); please report this vehicle file")
    for name, value in (("m0", q["m0"]), ("r_P1", q["r_p1"]), ("r_P3", q["r_p3"])):
        _check_actuator(veh, name, value, V, gamma)
    return SteadyGlide(speed=V, gamma=float(gamma), alpha=q["alpha"], theta=q["theta"], m0=q["m0"], r_p1=q["r_p1"],
                       r_p3=q["r_p3"], r_bh=q["r_bh"], v1=q["v1"], v3=q["v3"], residual=q["residual"], vehicle=veh,
                       provenance=veh.provenance, mbar=veh.mbar)


_ACTUATOR_WORDS = {"m0": ("net buoyancy m0", "kg", "buoyancy pump"),
                   "r_P1": ("moving-mass position r_P1", "m", "moving mass along the hull"),
                   "r_P3": ("moving-mass position r_P3", "m", "vertical moving-mass offset")}


def _check_actuator(veh: Vehicle, name: str, value: float, V: float, gamma: float) -> None:
    """InfeasibleGlideError when the trim needs actuator ``name`` at ``value`` outside ``veh.actuators[name]``."""
    act = veh.actuators.get(name)
    if act is None or act.contains(value):
        return
    what, unit, part = _ACTUATOR_WORDS[name]
    lo, hi = act.bounds
    if act.fixed is not None:
        limit = f"its fixed setting {act.fixed:g} {unit}"
    elif value > hi:
        limit = f"its max {hi:g} {unit}"
    else:
        limit = f"its min {lo:g} {unit}"
    hint = ("pass r_p3 equal to the fixed setting (or r_bh that puts it there)" if name == "r_P3" else
            "choose another speed or flight-path angle (glide_envelope(veh, speeds, gammas) maps the reachable ones)")
    raise InfeasibleGlideError(
        f"the steady glide at speed = {V:g} m/s, gamma = {math.degrees(gamma):.4f} deg needs {what} = {value:.6g} "
        f"{unit}, outside the range of actuator '{name}' ({part}) of vehicle '{veh.name}': {limit} "
        f"([actuators] {name}: {act.describe()}); {hint}")


#: Status codes of :func:`glide_trim_arrays` (0: a steady glide).
OK, NO_GLIDE, UNDERFLOW, PITCH_90, NON_FINITE, BEYOND_R_P_MAX, RESIDUAL_FAILED = range(7)


@dataclass(frozen=True)
class GlideTrimArrays:
    """Steady glides on a grid of speeds and flight-path angles (the vectorized core of :func:`steady_glide`).

    Every field has the broadcast shape of the inputs; ``status`` says, per point, whether the glide exists (``OK``)
    or why not (``NO_GLIDE``: gamma outside (2.26); ``UNDERFLOW``: forces underflow; ``PITCH_90``: r_p3 given at
    ``|theta| = 90 deg``; ``NON_FINITE``; ``BEYOND_R_P_MAX``: the moment balance needs ``|r_P| > R_P_MAX``;
    ``RESIDUAL_FAILED``: the relative residual is above :data:`RESIDUAL_TOL`). Values are NaN where no angle of
    attack exists and otherwise computed (also for the non-OK codes, for diagnostics). Internal: not exported.
    """

    status: np.ndarray
    alpha: np.ndarray
    theta: np.ndarray
    m0: np.ndarray
    r_p1: np.ndarray
    r_p3: np.ndarray
    r_bh: np.ndarray
    v1: np.ndarray
    v3: np.ndarray
    residual: np.ndarray
    relative_residual: np.ndarray


def glide_trim_arrays(veh: Vehicle, speed: np.ndarray, gamma: np.ndarray, *, r_p3: Any = None,
                      r_bh: Any = None) -> GlideTrimArrays:
    """Steady glides at every point of broadcast arrays ``speed`` (m/s) and ``gamma`` (rad): the one trim solver.

    Implements the closed-form trim of the module docstring ((2.26)-(2.29) reconstructed) elementwise and checks
    each point's residual on :meth:`LongitudinalGlider.rhs` (2.17)-(2.25) as :func:`steady_glide` documents. The
    caller has validated the vehicle (an underwater glider with ``mbar > 0`` and ``K_D != 0``), the finite inputs and
    exactly one of ``r_p3`` / ``r_bh`` (m, scalars or arrays broadcasting with the grid). No argument checks here.
    """
    V, gam = np.broadcast_arrays(np.asarray(speed, dtype=float), np.asarray(gamma, dtype=float))
    alpha, _ = _alpha_array(veh, gam, V)
    if veh.law == "thesis":
        lo, hi = permissible_gamma(veh)
        inside = (np.abs(gam) < math.pi / 2) & ((gam < lo) | (gam > hi))
    else:  # the root search decides: no root, no glide
        inside = np.abs(gam) < math.pi / 2
    status = np.where(inside & np.isfinite(alpha), OK, NO_GLIDE).astype(np.int8)
    g, mbar = veh.g, veh.mbar
    with np.errstate(all="ignore"):
        if veh.law == "thesis":
            m0 = (veh.K_L0 + veh.K_L * alpha) * V * V / (g * np.cos(gam))
        else:
            m0 = lift_drag(veh, V * V, alpha)[0] / (g * np.cos(gam))
        status[(status == OK) & ~(np.abs(m0) >= sys.float_info.min)] = UNDERFLOW
        theta = gam + alpha
        v1, v3 = V * np.cos(alpha), V * np.sin(alpha)
        m1, m3 = veh.mass(1, m0), veh.mass(3, m0)
        moment = (m3 - m1) * v1 * v3 + (veh.K_M0 + veh.K_M * alpha) * V * V
        a_perp = moment / (mbar * g)  # r_P1 cos(theta) + r_P3 sin(theta)
        st, ct = np.sin(theta), np.cos(theta)
        if r_bh is not None:
            rbh = np.broadcast_to(np.asarray(r_bh, dtype=float), V.shape)
            rp1 = a_perp * ct - rbh * st
            rp3 = a_perp * st + rbh * ct
        else:
            rp3 = np.broadcast_to(np.asarray(r_p3, dtype=float), V.shape).copy()
            status[(status == OK) & (np.abs(ct) < 1e-9)] = PITCH_90
            rp1 = (a_perp - rp3 * st) / ct
            rbh = -rp1 * st + rp3 * ct
        finite = np.isfinite(rp1) & np.isfinite(rp3) & np.isfinite(rbh) & np.isfinite(m0)
        status[(status == OK) & ~finite] = NON_FINITE
        status[(status == OK) & (np.hypot(rp1, rp3) > R_P_MAX)] = BEYOND_R_P_MAX
    residual = np.full(V.shape, np.nan)
    rel = np.full(V.shape, np.nan)
    ok = status == OK
    if np.any(ok):
        a, Vk, m0k, m1k, m3k = alpha[ok], V[ok], m0[ok], m1[ok] if np.ndim(m1) else m1, m3[ok] if np.ndim(m3) else m3
        v1k, v3k, rp1k, rp3k, mom = v1[ok], v3[ok], rp1[ok], rp3[ok], moment[ok]
        zero = np.zeros_like(Vk)
        xe = np.stack([zero, zero, theta[ok], zero, v1k, v3k, rp1k, rp3k, mbar * v1k, mbar * v3k, m0k], axis=-1)
        f = LongitudinalGlider(veh).rhs(xe, np.zeros((Vk.size, 3)))
        residual[ok] = np.max(np.abs(f[:, 2:]), axis=1)
        if veh.law == "thesis":
            L, D = (veh.K_L0 + veh.K_L * a) * Vk * Vk, (veh.K_D0 + veh.K_D * a * a) * Vk * Vk
        else:
            L, D = lift_drag(veh, Vk * Vk, a)
        force = np.maximum(np.maximum(np.abs(m0k) * g, np.abs(L)), np.abs(D))  # largest term of (2.18)-(2.19)
        cor = np.abs((m3k - m1k) * v1k * v3k)
        torque = np.maximum(np.maximum(cor, np.abs(mom - (m3k - m1k) * v1k * v3k)), mbar * g * np.hypot(rp1k, rp3k))
        scaled = [(f[:, 3], torque / veh.J2), (f[:, 4], force / m1k), (f[:, 5], force / m3k), (f[:, 6], Vk),
                  (f[:, 7], Vk)] + [(f[:, k], zero) for k in (2, 8, 9, 10)]
        with np.errstate(all="ignore"):
            rels = [np.where(sc > 0, np.abs(r) / np.where(sc > 0, sc, 1.0), np.where(r == 0, 0.0, np.inf))
                    for r, sc in scaled]
        rel[ok] = np.max(np.stack(rels), axis=0)
        bad = np.zeros(V.shape, bool)
        bad[ok] = ~(rel[ok] <= RESIDUAL_TOL)
        status[bad] = RESIDUAL_FAILED
    return GlideTrimArrays(status=status, alpha=alpha, theta=theta, m0=m0, r_p1=rp1, r_p3=np.asarray(rp3),
                           r_bh=np.asarray(rbh), v1=v1, v3=v3, residual=residual, relative_residual=rel)
