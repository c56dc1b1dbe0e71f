"""Reduced longitudinal glider of chapter 5: internal mass fixed at the centre of buoyancy, constant buoyancy.

State ``(V, gamma, alpha, Omega2)`` (m/s, rad, rad, rad/s), equations (5.4)-(5.7) for equal added masses and their
generalization (5.86)-(5.89) for ``m1 != m3``. One right-hand side serves both: the body-frame equations of the
foundation model (2.18)-(2.20) with ``r_P = 0``, ``rdot_P = 0`` (so the moving mass rides with the hull and adds to
both translational masses, ``M_i = m_i + mbar``), rewritten in ``(V, gamma, alpha)`` by (5.1)-(5.3):

``M1 v1' = -M3 v3 Om - m0 g sin(theta) + L sin(alpha) - D cos(alpha)``,
``M3 v3' =  M1 v1 Om + m0 g cos(theta) - L cos(alpha) - D sin(alpha)``,
``J2 Om' = (M3 - M1) v1 v3 + M_DL2``, with ``v1 = V cos(alpha)``, ``v3 = V sin(alpha)``, ``theta = gamma + alpha``,
and ``V' = (v1 v1' + v3 v3')/V``, ``alpha' = (v1 v3' - v3 v1')/V^2``, ``gamma' = Om - alpha'``.

Tests check that this equals the foundation model (acceleration form, ``w = 0``, ``r_P = rdot_P = 0``), that it
equals the printed (5.4)-(5.7) for ``m1 = m3``, and (5.86)-(5.89) otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import ModelError
from ..hydro import loads_at
from ..params import Vehicle
from ._validate import numeric_array, require_glider, trailing_array

__all__ = ["REDUCED_STATES", "REDUCED_UNITS", "ReducedLongitudinalGlider", "require_centred_mass",
           "require_v2_pitch_damping"]

REDUCED_STATES = ("V", "gamma", "alpha", "Omega2")
REDUCED_UNITS = {"V": "m/s", "gamma": "rad", "alpha": "rad", "Omega2": "rad/s"}


def require_centred_mass(veh: Vehicle, what: str, assumption: str = "chapter 5 assumption 1 (§5.1)") -> None:
    """Refuse a vehicle whose moving mass is not at the centre of buoyancy (``r_P = 0``).

    The reduced models of chapters 4-6 keep the moving mass ``mbar`` at the centre of buoyancy, so the centres of
    gravity and buoyancy coincide; a file that places it elsewhere (a nonzero nominal ``r_P1, r_P2, r_P3``, or an
    ``[actuators]`` range that excludes 0) would have its gravity torque ``-mbar g (r_P1 cos(theta) + r_P3
    sin(theta))`` silently dropped. A vehicle without a moving mass (``mbar = 0``) or without nominal positions
    passes (the reduced model places the mass at 0).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    what : str
        The analysis refusing (for the message), e.g. ``"singular_perturbation"``.
    assumption : str
        How the assumption is numbered where ``what`` comes from (for the message).

    Returns
    -------
    None

    Raises
    ------
    ModelError
        If ``mbar > 0`` and a nominal ``r_P_i`` is nonzero, or an actuated ``r_P_i`` cannot reach 0.
    """
    if not veh.mbar > 0:
        return
    off = [f"{k} = {veh.params[k]:g} m" for k in ("r_P1", "r_P2", "r_P3") if veh.params.get(k, 0.0) != 0.0]
    for k in ("r_P1", "r_P2", "r_P3"):
        act = veh.actuators.get(k)
        if act is not None and act.fixed is None and not act.min <= 0.0 <= act.max:
            off.append(f"{k} actuator range [{act.min:g}, {act.max:g}] m excludes 0")
    if off:
        raise ModelError(
            f"{what} needs {assumption}: moving mass at the centre of buoyancy (r_P = 0, centres of gravity and "
            f"buoyancy coincident); vehicle '{veh.name}' has mbar = {veh.mbar:g} kg with {', '.join(off)}. The "
            "reduced model would drop its gravity torque -mbar g (r_P1 cos(theta) + r_P3 sin(theta)). Use the "
            "full longitudinal model (steady_glide, linearize_glide) for this vehicle, or override r_P1 = r_P2 = "
            "r_P3 = 0")


def require_v2_pitch_damping(veh: Vehicle, what: str) -> None:
    """Refuse a vehicle whose pitch damping is not the ``V^2``-scaled ``K_q`` of (2.13).

    The small parameters (5.16)-(5.17) and the rate scale (5.15) of chapter 5 are built from ``K_q`` alone; the
    chapter-8 terms ``K_Omega1_2 Omega2 + K_Omega2_2 Omega2 |Omega2|`` (no ``V^2``) do not fit them.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    what : str
        The analysis refusing (for the message).

    Returns
    -------
    None

    Raises
    ------
    ModelError
        If ``K_Omega1_2`` or ``K_Omega2_2`` is nonzero.
    """
    bad = [f"{k} = {veh.params[k]:g}" for k in ("K_Omega1_2", "K_Omega2_2") if veh.params.get(k, 0.0) != 0.0]
    if bad:
        raise ModelError(
            f"{what} needs the chapter-5 pitch damping K_q Omega2 V^2 of (2.13) (the scalings (5.15)-(5.17) are "
            f"built from K_q); vehicle '{veh.name}' gives the chapter-8 form {', '.join(bad)} (no V^2), K_q = "
            f"{veh.params.get('K_q', 0.0):g}. Give the pitch damping as K_q (kg s/rad) for this analysis")


@dataclass(frozen=True)
class ReducedLongitudinalGlider:
    """Chapter-5 longitudinal glider with ``r_P = 0`` and constant ``m0`` (no inputs).

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider; uses ``m1, m3`` (or the added-mass model), ``mbar``, ``J2``, ``m0``, ``g`` and the
        hydrodynamic coefficients. The effective translational masses are ``M_i = m_i + mbar`` (the moving mass
        rides with the hull); for the chapter-5 sphere ``mbar = 0`` and ``M_i = m_i = 28 kg``.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If it is not an underwater glider, has its moving mass off the centre of buoyancy (``mbar > 0`` and a
        nonzero ``r_P``: chapter 5 assumption 1, :func:`require_centred_mass`), has no ``m0`` or ``m0 = 0``
        (assumption 2), or its translational masses ``M_i`` at ``m0`` are not positive.

    Notes
    -----
    Pitch damping is read through :func:`glidectl.hydro.damping_moment` like every other model, so chapter-8
    terms in a file are kept here; analyses whose scalings use ``K_q`` alone refuse them
    (:func:`require_v2_pitch_damping`). Assumption 3 (``m1 = m3``) is not needed: unequal masses give (5.86)-(5.89).
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        v = require_glider(self.vehicle)
        require_centred_mass(v, "the reduced chapter-5 model (5.4)-(5.7)")
        if v.m0 == 0:
            raise ModelError(f"vehicle '{v.name}' has m0 = 0: chapter 5 needs a constant nonzero buoyancy mass "
                             "(chapter 5 assumption 2 of §5.1); set m0 in the file or as an override")
        masses = self.masses
        if not min(masses) > 0:
            raise ModelError(f"vehicle '{v.name}' has translational masses M1, M3 = {masses} kg at m0 = {v.m0:g} kg: "
                             "they must be positive (the ballast cannot be that light)")

    @cached_property
    def masses(self) -> tuple[float, float]:
        """Effective translational masses ``(M1, M3) = (m1 + mbar, m3 + mbar)`` in kg."""
        v = self.vehicle
        return float(v.mass(1, v.m0) + v.mbar), float(v.mass(3, v.m0) + v.mbar)

    @property
    def delta_m(self) -> float:
        """``Delta m = m3 - m1`` (kg), §5.4."""
        M1, M3 = self.masses
        return M3 - M1

    def body_rates(self, x: Any, m0: Any = None) -> tuple[Any, Any, Any]:
        """Body-frame ``(v1', v3', Omega2')`` for state ``x = (V, gamma, alpha, Omega2)``.

        ``m0`` (kg, scalar or broadcastable to ``x[..., 0]``, may be complex) replaces the vehicle's buoyancy mass
        in the weight and, for the ``added`` mass model, in the masses (used by the buoyancy-controlled models of
        chapter 6, where ``m0`` is a state); default the vehicle's ``m0``. ``x`` has shape ``(..., 4)``.
        """
        x = trailing_array("x", x, 4, REDUCED_STATES)
        veh = self.vehicle
        if m0 is None:
            M1, M3 = self.masses
            m0 = veh.m0
        else:
            m0 = numeric_array("m0", m0)
            M1, M3 = veh.mass(1, m0) + veh.mbar, veh.mass(3, m0) + veh.mbar
        V, gam, al, Om = x[..., 0], x[..., 1], x[..., 2], x[..., 3]
        sa, ca = np.sin(al), np.cos(al)
        v1, v3 = V * ca, V * sa
        th = gam + al
        L, D, M = loads_at(veh, V * V, al, Om)
        m0g = m0 * veh.g
        v1d = (-M3 * v3 * Om - m0g * np.sin(th) + L * sa - D * ca) / M1
        v3d = (M1 * v1 * Om + m0g * np.cos(th) - L * ca - D * sa) / M3
        Omd = ((M3 - M1) * v1 * v3 + M) / veh.J2
        return v1d, v3d, Omd

    def rhs(self, x: Any, u: Any = None, *, m0: Any = None) -> Any:
        """``(V', gamma', alpha', Omega2')`` of (5.4)-(5.7) / (5.86)-(5.89); defined for ``V > 0``.

        Parameters
        ----------
        x : array_like, shape (..., 4)
        u : ignored (the model has no inputs; accepted for :func:`glidectl.sim.simulate`)
        m0 : array_like, optional
            Buoyancy mass (kg) per state, see :meth:`body_rates`; default the vehicle's.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` is not an array of numbers with a trailing dimension 4.
        """
        x = trailing_array("x", x, 4, self.state_names)
        V, al, Om = x[..., 0], x[..., 2], x[..., 3]
        v1d, v3d, Omd = self.body_rates(x, m0)
        sa, ca = np.sin(al), np.cos(al)
        Vd = ca * v1d + sa * v3d
        ald = (ca * v3d - sa * v1d) / V
        return np.stack([Vd, Om - ald, ald, Omd], axis=-1)

    def trim_alpha(self) -> float:
        """Equilibrium angle of attack (rad): (5.10) for ``m1 = m3``, the root of (5.90) otherwise.

        ``K_M0 + K_M alpha + Delta m sin(alpha) cos(alpha) = 0`` is solved by Newton's method from (5.10); an error
        is raised if it does not converge to a root with ``|alpha| < pi/4`` (the range §5.4 assumes).
        """
        v = self.vehicle
        if v.K_M == 0:
            raise ModelError(f"vehicle '{v.name}' has K_M = 0: no pitch stiffness, no steady glide in chapter 5")
        a = -v.K_M0 / v.K_M
        dm = self.delta_m
        if dm == 0:
            return float(a)
        for _ in range(60):
            F = v.K_M0 + v.K_M * a + dm * np.sin(a) * np.cos(a)
            dF = v.K_M + dm * np.cos(2 * a)
            step = F / dF
            a -= step
            if abs(step) < 1e-15:
                break
        scale = abs(v.K_M0) + abs(v.K_M * a) + abs(dm * np.sin(a) * np.cos(a))  # the moments balanced (kg)
        if not (abs(v.K_M0 + v.K_M * a + dm * np.sin(a) * np.cos(a)) <= 1e-12 * scale and abs(a) < np.pi / 4):
            raise ModelError(f"no equilibrium angle of attack from (5.90) for vehicle '{v.name}' (Delta m = {dm:g} "
                             "kg): Newton's method did not converge to |alpha_e| < pi/4")
        return float(a)
