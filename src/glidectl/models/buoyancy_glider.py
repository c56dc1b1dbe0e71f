"""Chapter-5 glider with a buoyancy engine, thesis §6.2 (and the loaded right-hand side reused by the elevator
model of §6.3, :mod:`glidectl.models.elevator_glider`).

:class:`BuoyancyGlider` has the dimensional state ``(V, gamma, alpha, Omega2, m0)`` (m/s, rad, rad, rad/s, kg) and
the input ``u1 = dm0/dt`` (kg/s). Its right-hand side is :meth:`glidectl.models.reduced.ReducedLongitudinalGlider.rhs`
evaluated with the vehicle's ``m0`` replaced by the state's ``m0`` (so for the ``added`` mass model ``m1 = m3 = m +
m0`` follows the buoyancy, as in §6.3), plus the buoyancy engine ``m0' = pump(m0, u1)``:

* rate limit ``|m0'| <= u4_max`` (``[actuators] m0.rate``, kg/s; the saturation of ``u4`` of (2.8), §2.2
  assumption 2);
* range ``m0_min <= m0 <= m0_max`` (``[actuators] m0``, kg): at a bound the pump cannot push further out.

A limit the vehicle does not define is not applied (:class:`ActuatorLimits`, :func:`actuator_limits`).
:func:`loaded_rates` adds an external body-3 force and pitch moment to the same right-hand side (the elevator of
§6.3), so there is still one vector field. The buoyancy law (6.9) is in :mod:`glidectl.controllers.buoyancy`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ModelError
from ..params import Vehicle
from ._validate import numeric_array, require_glider, trailing_array
from .reduced import ReducedLongitudinalGlider

__all__ = [
    "BUOYANCY_STATES",
    "BUOYANCY_UNITS",
    "ActuatorLimits",
    "BuoyancyGlider",
    "actuator_limits",
    "loaded_rates",
]

BUOYANCY_STATES = ("V", "gamma", "alpha", "Omega2", "m0")
BUOYANCY_UNITS = {"V": "m/s", "gamma": "rad", "alpha": "rad", "Omega2": "rad/s", "m0": "kg", "u1": "kg/s",
                  "u2": "rad"}

_M0_TINY = 1e-12  # kg: ReducedLongitudinalGlider refuses m0 = 0 exactly (chapter-5 assumption 2)


# ------------------------------------------------------------------------------------------------ actuators
@dataclass(frozen=True)
class ActuatorLimits:
    """Pump and elevator limits of a vehicle, from its ``[actuators]`` table (``inf`` where it defines none).

    Attributes
    ----------
    u4_max : float
        Buoyancy pump rate limit ``|dm0/dt| <= u4_max`` (kg/s): ``[actuators] m0.rate``.
    m0_max : float
        Upper end of the buoyancy range ``m0 <= m0_max`` (kg): ``[actuators] m0.max``.
    u2_max : float
        Upper elevator saturation ``u2 <= u2_max`` (rad, control angle of attack of §6.3).
    m0_min : float, optional
        Lower end of the buoyancy range (kg); default ``-m0_max``.
    u2_min : float, optional
        Lower elevator saturation (rad); default ``-u2_max``.

    Raises
    ------
    ArgumentTypeError
        If a limit is not a real number.
    ArgumentError
        If a limit is not positive (``inf``: no limit) or a lower end is not below its upper end.
    """

    u4_max: float = math.inf
    m0_max: float = math.inf
    u2_max: float = math.inf
    m0_min: float | None = None
    u2_min: float | None = None

    def __post_init__(self) -> None:
        for k, unit in (("u4_max", "kg/s"), ("m0_max", "kg"), ("u2_max", "rad")):
            object.__setattr__(self, k, checks.positive(k, getattr(self, k), allow_inf=True, unit=unit))
        for k, hi, unit in (("m0_min", self.m0_max, "kg"), ("u2_min", self.u2_max, "rad")):
            lo = getattr(self, k)
            lo = -hi if lo is None else checks.real(k, lo, allow_inf=True, unit=unit)
            if not lo < hi:
                raise ArgumentError(f"{k} = {lo:g} {unit} must be below the upper limit {hi:g} {unit}")
            object.__setattr__(self, k, lo)

    def pump(self, m0: Any, u1: Any) -> Any:
        """Rate ``dm0/dt`` (kg/s) the pump delivers for the command ``u1`` (kg/s) at buoyancy ``m0`` (kg).

        ``clip(u1, -u4_max, u4_max)``, and 0 where ``m0`` is at (or beyond) a range bound and the command
        pushes outward.
        """
        m0 = np.real(numeric_array("m0", m0))
        rate = _saturate(u1, -self.u4_max, self.u4_max)
        re = np.real(rate)
        blocked = ((m0 >= self.m0_max) & (re > 0)) | ((m0 <= self.m0_min) & (re < 0))
        return np.where(blocked, 0.0, rate)

    def elevator(self, u2: Any) -> Any:
        """Saturated elevator input ``clip(u2, u2_min, u2_max)`` (rad)."""
        numeric_array("u2", u2)
        return _saturate(u2, self.u2_min, self.u2_max)

    def m0_in_range(self, m0: float) -> bool:
        """Whether the buoyancy ``m0`` (kg) is within ``[m0_min, m0_max]``."""
        return bool(self.m0_min <= m0 <= self.m0_max)


def _saturate(u: Any, lo: float, hi: float) -> Any:
    """``clip(u, lo, hi)`` that carries a complex step: the input passes unchanged (derivative 1) inside the
    bounds, the bound (derivative 0) outside."""
    u = numeric_array("u", u)
    re = np.real(u)
    return np.where(re > hi, hi, np.where(re < lo, lo, u))


def actuator_limits(veh: Vehicle) -> ActuatorLimits:
    """Pump and elevator limits from the vehicle's ``[actuators]`` table; ``inf`` for those it does not set.

    ``m0`` gives ``m0_min``, ``m0_max`` and the pump rate ``u4_max``; ``elevator`` gives ``u2_min``, ``u2_max``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If it is not an underwater glider, or a limit is one-sided in a way the symmetric chapter-6 models
        cannot use (a range that does not contain 0).
    """
    veh = require_glider(veh)
    m0 = veh.actuators.get("m0")
    el = veh.actuators.get("elevator")
    m0_lo, m0_hi = m0.bounds if m0 is not None else (-math.inf, math.inf)
    u2_lo, u2_hi = el.bounds if el is not None else (-math.inf, math.inf)
    rate = m0.rate if m0 is not None else math.inf
    for name, lo, hi in (("m0", m0_lo, m0_hi), ("elevator", u2_lo, u2_hi)):
        if not lo < 0 < hi:
            raise ModelError(f"vehicle '{veh.name}': [actuators] {name} range [{lo:g}, {hi:g}] must contain 0 "
                             "for the pump/elevator models of chapter 6")
    return ActuatorLimits(u4_max=rate, m0_max=m0_hi, u2_max=u2_hi, m0_min=m0_lo, u2_min=u2_lo)


# ------------------------------------------------------------------------------------------------ model
def _reduced_at(veh: Vehicle, m0: float) -> ReducedLongitudinalGlider:
    m0 = float(m0)
    if m0 == 0.0:
        m0 = _M0_TINY
    return ReducedLongitudinalGlider(veh.with_overrides(m0=m0))


def loaded_rates(veh: Vehicle, x: Any, f3: Any = 0.0, M2: Any = 0.0) -> np.ndarray:
    """``(V', gamma', alpha', Omega2')`` of the chapter-5 glider at the buoyancy ``m0 = x[..., 4]``, with an extra
    force ``f3`` along body 3 (N, positive down) and pitch moment ``M2`` (N m, positive nose up).

    The rates are :meth:`ReducedLongitudinalGlider.rhs` with the per-state buoyancy ``m0`` (vectorized; ``m0``
    may carry a complex step too) plus the exact effect of the extra load on the body-frame equations (2.18)-(2.20):
    ``v3' += f3 / M3`` and ``Omega2' += M2 / J2``, i.e. ``V' += sin(alpha) f3 / M3``,
    ``alpha' += cos(alpha) f3 / (M3 V)``, ``gamma' -= cos(alpha) f3 / (M3 V)``.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (``r_P = 0``).
    x : array_like, shape (..., 5)
        ``(V, gamma, alpha, Omega2, m0)`` in m/s, rad, rad, rad/s, kg (may be complex: complex-step derivatives).
    f3, M2 : array_like, broadcastable to ``x[..., 0]``
        Extra body-3 force (N) and pitch moment (N m).

    Returns
    -------
    ndarray, shape (..., 4)
        ``(V', gamma', alpha', Omega2')`` (m/s^2, rad/s, rad/s, rad/s^2).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or an argument is not an array of numbers.
    ArgumentError
        If ``x`` does not have a trailing dimension 5.
    ModelError
        If ``veh`` is not an underwater glider accepted by the chapter-5 model.
    """
    require_glider(veh)
    return _loaded_rates(_reduced_at(veh, veh.m0), x, f3, M2)


def _loaded_rates(model: ReducedLongitudinalGlider, x: Any, f3: Any = 0.0, M2: Any = 0.0) -> np.ndarray:
    """:func:`loaded_rates` with the chapter-5 model of the vehicle already built (the models keep theirs)."""
    veh = model.vehicle
    x = trailing_array("x", x, 5, BUOYANCY_STATES)
    f3, M2 = numeric_array("f3", f3), numeric_array("M2", M2)
    m0 = x[..., 4]
    r = np.asarray(model.rhs(x[..., :4], m0=m0))
    M3 = veh.mass(3, m0) + veh.mbar
    V, al = x[..., 0], x[..., 2]
    a3 = np.asarray(f3) / M3
    dal = np.cos(al) * a3 / V
    dOm = np.asarray(M2) / veh.J2
    return np.stack(np.broadcast_arrays(r[..., 0] + np.sin(al) * a3, r[..., 1] - dal, r[..., 2] + dal,
                                        r[..., 3] + dOm), axis=-1)


@dataclass(frozen=True)
class BuoyancyGlider:
    """Chapter-5 glider with a buoyancy engine, §6.2: state ``(V, gamma, alpha, Omega2, m0)``, input ``u1``.

    ``(V, gamma, alpha, Omega2)' `` are (5.4)-(5.7) at the current ``m0`` (:func:`loaded_rates` without extra
    load); ``m0' = pump(m0, u1)`` is (6.8) in seconds with the vehicle's rate limit ``u4_max`` and range ``m0_max``
    (:class:`ActuatorLimits`).

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider; ``u4_max`` (kg/s) and ``m0_max`` (kg) are used when defined.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If it is not an underwater glider accepted by the chapter-5 model.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = BUOYANCY_STATES
    input_names: tuple[str, ...] = ("u1",)

    def __post_init__(self) -> None:
        self._reduced  # noqa: B018 - the chapter-5 model must accept the vehicle

    @cached_property
    def _reduced(self) -> ReducedLongitudinalGlider:
        """The chapter-5 model of the vehicle (built once: the right-hand side is called many times)."""
        return _reduced_at(require_glider(self.vehicle), self.vehicle.m0)

    @cached_property
    def limits(self) -> ActuatorLimits:
        """Pump and elevator limits of the vehicle (:func:`actuator_limits`)."""
        return actuator_limits(self.vehicle)

    def loaded_rates(self, x: Any, f3: Any = 0.0, M2: Any = 0.0) -> np.ndarray:
        """:func:`loaded_rates` of this vehicle, with its chapter-5 model built once (for right-hand sides called
        many times, e.g. the elevator model of §6.3).

        Parameters
        ----------
        x : array_like, shape (..., 5)
            ``(V, gamma, alpha, Omega2, m0)`` in m/s, rad, rad, rad/s, kg (may be complex).
        f3, M2 : array_like, broadcastable to ``x[..., 0]``
            Extra body-3 force (N) and pitch moment (N m).

        Returns
        -------
        ndarray, shape (..., 4)
            ``(V', gamma', alpha', Omega2')`` (m/s^2, rad/s, rad/s, rad/s^2).

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If ``x`` does not have a trailing dimension 5.
        """
        return _loaded_rates(self._reduced, x, f3, M2)

    def rhs(self, x: Any, u: Any) -> np.ndarray:
        """``x'`` for ``x = (V, gamma, alpha, Omega2, m0)`` (shape (..., 5)) and ``u = (u1,)`` (kg/s, shape
        (..., 1)).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 5, self.state_names)
        u1 = trailing_array("u", u, 1, self.input_names)[..., 0]
        r = self.loaded_rates(x)
        return np.concatenate([r, self.limits.pump(x[..., 4], u1)[..., None]], axis=-1)
