"""Underwater glider with an aft elevator and a buoyancy engine, thesis §6.3, model (6.14)-(6.19) in dimensional
form.

:class:`ElevatorBuoyancyGlider` is the chapter-5 right-hand side at the current buoyancy ``m0`` plus the elevator
force and moment of :func:`elevator_loads` (through :func:`glidectl.models.buoyancy_glider.loaded_rates`), and the
buoyancy pump. :func:`effective_coefficients` gives the drag and lift coefficients including the elevator force.
The equilibrium (6.20) and the laws (6.21)-(6.22) are in :mod:`glidectl.controllers.elevator`.

Sign convention, and the corrections it implies
------------------------------------------------
The text defines the elevator action as "an external torque ``K_M u2 V^2``" (§6.3 and the caption of Fig 6.1) with
a coupling force of magnitude ``delta u2 V^2`` along body 3, and writes the closed-loop moment (6.19) as
``(K_M0 + K_M alpha + K_q Omega2 + K_M u2) V^2``. glidectl keeps that definition:

* elevator moment ``M_el = K_M u2 V^2`` (N m, positive nose up; ``K_M < 0``);
* elevator force ``f = -delta u2 V^2 e3`` (N, body 3 points down; ``delta >= 0``).

The force direction is fixed by physics, not by choice: an aft elevator at ``r = (-l, 0, 0)`` with force
``f3 e3`` gives the moment ``l f3``, so a nose-up elevator moment (``K_M u2 > 0``, i.e. ``u2 < 0``) needs a down
force ``f3 > 0``; hence ``f3 = -delta u2 V^2`` (implied arm ``l = -K_M / delta > 0``). The body velocity is
``V (cos a, 0, sin a)`` and the lift direction ``(sin a, 0, -cos a)``, so ``f3`` contributes ``+f3 sin a`` along
the velocity and ``-f3 cos a`` along the lift. With ``h = delta u2 V^2 = -f3`` the equations are

``m1 V'     = -m0 g sin(gamma) - D - h sin(alpha)``   ((6.14) prints ``- D + h sin``: sign error),
``m1 V gam' = -m0 g cos(gamma) + L + h cos(alpha)``   ((6.15) as printed),
``eps2 dOmegabar/dt_n = -(alphabar + Omegabar2 + ubar2)(1 + Vbar)^2``   ((6.18) prints ``- ubar2``),
``alpha_e = -K_M0/K_M - u2e``   ((6.20) prints ``+ u2e``),
``K'_De = K_D0 + K_D alpha_e^2 + delta u2e sin(alpha_e)``   ((6.23) prints ``- delta u2e V_e^2 sin``: sign error
and a spurious ``V_e^2``, which makes the sum dimensionally inconsistent),
``K'_Le = K_L0 + K_L alpha_e + delta u2e cos(alpha_e)``   ((6.26) as printed),
and (6.25) should have ``(1 + Vbar)``, not ``(1 + Vbar)^2``, in its denominator (as (6.15) and (5.21)).

The other self-consistent reading, ``u2`` a "control angle of attack" with moment ``K_M (alpha - u2) V^2`` and
force ``+delta u2 V^2 e3``, makes (6.14), (6.18), (6.20), (6.23) right and (6.15), (6.19), (6.26) and the stated
torque ``K_M u2 V^2`` wrong. It only flips the sign of ``u2``; the equilibria, ``K'_De``, ``K'_Le`` and all
trajectories are the same. No reading makes all of (6.14), (6.15), (6.19), (6.20) right: (6.14) and (6.15) together
describe a force that is not along body 3, and (6.14) with (6.19) an elevator ahead of the centre of mass.

Physically, for the Fig 6.2 glide the elevator must pitch the nose up (``alpha_e > -K_M0/K_M``), so its force points
down the body 3-axis: it adds a small thrust (``K'_De < K_De``) and removes lift (``K'_Le < K_Le``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..params import Vehicle
from ._validate import numeric_array, require_glider, trailing_array
from .buoyancy_glider import BUOYANCY_STATES, ActuatorLimits, BuoyancyGlider, actuator_limits

__all__ = ["ElevatorBuoyancyGlider", "effective_coefficients", "elevator_loads"]


def elevator_loads(veh: Vehicle, V2: Any, u2: Any) -> tuple[Any, Any]:
    """Elevator force along body 3 and pitching moment, §6.3 with the sign convention of the module docstring.

    Parameters
    ----------
    veh : Vehicle
        Uses ``delta`` (kg/m/rad) and ``K_M`` (kg/rad).
    V2 : array_like
        Squared speed (m^2/s^2).
    u2 : array_like
        Elevator input (rad).

    Returns
    -------
    f3 : body-3 force (N, positive down), ``-delta u2 V^2``
    M_el : pitching moment (N m, positive nose up), ``K_M u2 V^2`` (6.19)

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``V2``, ``u2`` are not numbers.
    ModelError
        If ``veh`` is not an underwater glider or has no ``delta``.
    """
    require_glider(veh)
    V2, u2 = numeric_array("V2", V2), numeric_array("u2", u2)
    return -veh.delta * u2 * V2, veh.K_M * u2 * V2


def effective_coefficients(veh: Vehicle, alpha: Any, u2: Any) -> tuple[Any, Any]:
    """``(K'_D, K'_L)`` (kg/m) of drag and lift including the elevator force, corrected (6.23) and (6.26).

    ``K'_D = K_D0 + K_D alpha^2 + delta u2 sin(alpha)``, ``K'_L = K_L0 + K_L alpha + delta u2 cos(alpha)``, so that
    the hydrodynamic plus elevator force is ``-K'_D V^2`` along the velocity and ``K'_L V^2`` along the lift.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``alpha``, ``u2`` are not numbers.
    ModelError
        If ``veh`` is not an underwater glider or has no ``delta``.
    """
    require_glider(veh)
    alpha, u2 = numeric_array("alpha", alpha), numeric_array("u2", u2)
    d = veh.delta
    return (veh.K_D0 + veh.K_D * alpha**2 + d * u2 * np.sin(alpha),
            veh.K_L0 + veh.K_L * alpha + d * u2 * np.cos(alpha))


@dataclass(frozen=True)
class ElevatorBuoyancyGlider:
    """Glider with aft elevator and buoyancy engine, §6.3: state ``(V, gamma, alpha, Omega2, m0)``, inputs
    ``(u1, u2)``.

    ``(V, gamma, alpha, Omega2)'`` is the chapter-5 right-hand side at the current ``m0`` plus the elevator force
    and moment of :func:`elevator_loads` (:func:`glidectl.models.buoyancy_glider.loaded_rates`); ``m0' = u1``
    (kg/s) through the pump limits. ``u2`` (rad) is clipped to ``|u2| <= u2_max`` (the elevator cannot exceed its
    travel). This is (6.14)-(6.18) in dimensional form, with the corrections of the module docstring.

    Parameters
    ----------
    vehicle : Vehicle
        Needs ``delta``; ``u2_max`` (rad), ``u4_max`` (kg/s), ``m0_max`` (kg) are used when defined.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If it is not an underwater glider accepted by the chapter-5 model, or has no ``delta``.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = BUOYANCY_STATES
    input_names: tuple[str, ...] = ("u1", "u2")

    def __post_init__(self) -> None:
        self._buoyancy  # noqa: B018 - the same validity conditions as BuoyancyGlider
        self.vehicle.delta  # noqa: B018 - raises ModelError naming the file when the coupling factor is missing

    @cached_property
    def _buoyancy(self) -> BuoyancyGlider:
        """The buoyancy-only model of the vehicle (built once: the right-hand side is called many times)."""
        return BuoyancyGlider(require_glider(self.vehicle))

    @cached_property
    def limits(self) -> ActuatorLimits:
        """Pump and elevator limits of the vehicle (:func:`actuator_limits`)."""
        return actuator_limits(self.vehicle)

    def rhs(self, x: Any, u: Any) -> np.ndarray:
        """``x'`` for ``x = (V, gamma, alpha, Omega2, m0)`` (shape (..., 5)), ``u = (u1 [kg/s], u2 [rad])`` (shape
        (..., 2)).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 5, self.state_names)
        u = trailing_array("u", u, 2, self.input_names)
        lim = self.limits
        u2 = lim.elevator(u[..., 1])
        V = x[..., 0]
        f3, M = elevator_loads(self.vehicle, V * V, u2)
        r = self._buoyancy.loaded_rates(x, f3, M)
        return np.concatenate([r, lim.pump(x[..., 4], u[..., 0])[..., None]], axis=-1)
