"""The longitudinal glider with its actuators as part of the model: pump mass ``m0`` and moving-mass positions
``r_P1``, ``r_P3`` with the range and rate limits of the vehicle file's ``[actuators]`` table.

Model
-----
:class:`ActuatedGlider` has the state of :class:`~glidectl.models.longitudinal.AccelerationControlledGlider`,
``(x, z, theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)``, and its right-hand side *is* that model's
(which calls the one force right-hand side (2.15)-(2.25)); only the input differs. The input is a vector of
**requested actuator rates** ``(r_P1_rate, r_P3_rate, m0_rate)`` (m/s, m/s, kg/s). The right-hand side limits them
and drives the actuators:

* allowed rate interval of axis ``i`` at position ``p_i``:
  ``[max(-R_i, k_i (min_i - p_i)), min(R_i, k_i (max_i - p_i))]``: the rate limit ``R_i`` (``[actuators]
  <name>.rate``) and a linear taper of slope ``k_i`` (1/s) onto each end of the range (``.min``, ``.max``); a fixed
  actuator has ``R_i = 0``;
* pump: ``m0' = s_m0`` (the limited rate), so ``m0`` cannot cross an end of its range (Gronwall on the taper);
* moving mass: a velocity servo of time constant ``tau`` (:attr:`ActuatedGlider.servo_time`, s) realizes the
  limited velocity ``s_i``, ``w_i = (s_i - rdot_Pi) / tau`` ((2.33)'s mass acceleration), with taper slope
  ``k_i = 1 / (4 tau)`` (critically damped). Then ``|rdot_Pi| <= R_i`` (a first-order filter of a signal bounded by
  ``R_i``) and ``rdot_Pi <= (max_i - p_i) / (2 tau)`` (and the mirror image at ``min_i``) are invariant: on the
  boundary line the derivative of ``rdot - (max - p)/(2 tau)`` is ``(s - k (max - p))/tau <= 0``. So the mass never
  leaves its range either.

These are properties of the exact flow; an integrator keeps them to its tolerance (``atol``, of order 1e-9 here),
and the property test ``tests/test_actuated_sim.py`` checks them on random commands. Nothing is clipped after
integration.

Commands
--------
Controllers need not speak in rates (see :func:`glidectl.sim.simulate_actuated`):

* **setpoints** (positions; the natural interface of a glider's servo loops): ``rate = k_i (clip(c_i) - p_i)``
  (:meth:`ActuatedGlider.setpoint_rates`), ``c_i`` clipped to the range;
* **thesis inputs** ``w = (w1, w3, w4)`` of (2.33) (mass accelerations, pump rate; e.g. an acceleration-form
  :class:`~glidectl.controllers.linear.LinearGlideController`): ``rate = (rdot_P1 + tau w1, rdot_P3 + tau w3, w4)``
  (:meth:`ActuatedGlider.acceleration_rates`), so that inside the limits the servo realizes exactly ``w``; at a
  limit the command passes through the rate/range limiter like any other.

The *position command equivalent* of a requested rate is ``p_i + rate_i / k_i`` (:meth:`position_command`): for a
setpoint controller it is the setpoint itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import InfeasibleGlideError, ModelError
from ..params import Vehicle
from ._validate import require_glider, trailing_array
from .longitudinal import ACCEL_STATES, AccelerationControlledGlider

__all__ = ["ACTUATED_AXES", "ACTUATED_INPUTS", "ACTUATED_UNITS", "ActuatedGlider", "RateLimitedActuators",
           "check_actuator_state", "rate_interval"]

#: The actuators of the longitudinal model, in input order.
ACTUATED_AXES = ("r_P1", "r_P3", "m0")
#: Input names of :class:`ActuatedGlider`: requested rates of the actuators (m/s, m/s, kg/s).
ACTUATED_INPUTS = ("r_P1_rate", "r_P3_rate", "m0_rate")
#: Units of the actuator positions and of the inputs.
ACTUATED_UNITS = {"r_P1": "m", "r_P3": "m", "m0": "kg", "r_P1_rate": "m/s", "r_P3_rate": "m/s", "m0_rate": "kg/s"}

_POS = np.array([6, 8, 10])  # columns of r_P1, r_P3, m0 in ACCEL_STATES


def rate_interval(p: Any, lower: np.ndarray, upper: np.ndarray, rate_limit: np.ndarray,
                  gain: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Allowed rate interval ``(lo, hi)`` of actuators at positions ``p`` (shape ``(..., k)``): the rate limit and
    the linear taper of slope ``gain`` onto the range ends, ``[max(-R, k (min - p)), min(R, k (max - p))]``."""
    with np.errstate(invalid="ignore"):
        lo = np.maximum(-rate_limit, gain * (lower - p))
        hi = np.minimum(rate_limit, gain * (upper - p))
    return lo, hi


class RateLimitedActuators:
    """The actuator limiter shared by the actuated models (module docstring): needs ``positions(x)``, ``lower``,
    ``upper``, ``rate_limit``, ``gain``, ``input_names`` and ``actuator_names``."""

    lower: np.ndarray
    upper: np.ndarray
    rate_limit: np.ndarray
    gain: np.ndarray
    input_names: tuple[str, ...]
    actuator_names: tuple[str, ...]

    def positions(self, x: Any) -> np.ndarray:  # pragma: no cover - every model defines its own
        raise NotImplementedError

    def rate_bounds(self, x: Any) -> tuple[np.ndarray, np.ndarray]:
        """Allowed rate interval ``(lo, hi)`` of each actuator at states ``x`` (shape ``(..., k)`` each, the
        actuators' units per second): the rate limit and the linear taper onto the range ends."""
        return rate_interval(self.positions(x), self.lower, self.upper, self.rate_limit, self.gain)

    def limited_rates(self, x: Any, u: Any) -> np.ndarray:
        """Requested rates ``u`` (shape ``(..., k)``) limited to :meth:`rate_bounds` (what the actuators do)."""
        u = trailing_array("u", u, len(self.input_names), self.input_names)
        lo, hi = self.rate_bounds(x)
        return np.minimum(np.maximum(u, lo), hi)

    def setpoint_rates(self, x: Any, setpoints: Any) -> np.ndarray:
        """Requested rates of the servo loops for position setpoints (shape ``(..., k)``, in
        ``actuator_names`` order): ``k_i (clip(c_i) - p_i)``, ``c_i`` clipped to the range."""
        c = trailing_array("setpoints", setpoints, len(self.actuator_names), self.actuator_names)
        return self.gain * (np.clip(c, self.lower, self.upper) - self.positions(x))


def check_actuator_state(plant: Any, x: np.ndarray, what: str, servo_columns: dict[int, int],
                         units: dict[str, str]) -> None:
    """Refuse a state of an actuated model whose actuators are outside their ranges, or whose servo rates (the
    columns ``servo_columns[i]`` of ``x`` for actuator ``i``) leave the servo's invariant set: faster than the rate
    limit, or too fast to stop inside the range (``|rate| <= 2 k (end - p)``).

    ``plant`` has ``positions(x)``, ``lower``, ``upper``, ``rate_limit``, ``gain``, ``actuator_names``,
    ``input_names`` and ``vehicle``; ``units`` maps actuator and input names to units.

    Raises
    ------
    InfeasibleGlideError
        With the actuator, its value and its range or rate limit.
    """
    p = plant.positions(x)
    for i, name in enumerate(plant.actuator_names):
        lo, hi = plant.lower[i], plant.upper[i]
        slack = 1e-9 * max(1.0, abs(lo), abs(hi)) if math.isfinite(hi - lo) else 0.0
        if not lo - slack <= p[i] <= hi + slack:
            raise InfeasibleGlideError(
                f"{what} has {name} = {p[i]:.6g} {units[name]}, outside the range [{lo:g}, {hi:g}] of vehicle "
                f"'{plant.vehicle.name}' ([actuators] {name}); choose a state the actuators can reach")
    for i, j in servo_columns.items():
        v, R = x[j], plant.rate_limit[i]
        k2 = 2.0 * plant.gain[i]
        top, bot = k2 * (plant.upper[i] - p[i]), k2 * (plant.lower[i] - p[i])
        if abs(v) > R * (1 + 1e-9) + 1e-15 or v > top + 1e-12 or v < bot - 1e-12:
            unit = units[plant.input_names[i]]
            raise InfeasibleGlideError(
                f"{what} moves {plant.actuator_names[i]} at {v:.6g} {unit}: beyond its rate limit {R:g} {unit} or "
                "too fast to stop inside its range; start from a state with the actuator at rest")


@dataclass(frozen=True)
class ActuatedGlider(RateLimitedActuators):
    """Longitudinal glider whose pump and moving mass obey the vehicle's ``[actuators]`` limits (module docstring).

    State ``(x, z, theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)`` (SI units, as
    :class:`~glidectl.models.longitudinal.AccelerationControlledGlider`); input: requested rates
    ``(r_P1_rate, r_P3_rate, m0_rate)`` (m/s, m/s, kg/s), limited inside :meth:`rhs`.

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider with a moving mass (``mbar > 0``) and ``[actuators]`` entries ``m0``, ``r_P1`` and
        ``r_P3`` (each actuated with a range and a rate, or ``fixed``).
    servo_time : float
        Time constant ``tau`` (s) of the moving-mass velocity servo, > 0 (default 0.5 s). The range taper and the
        setpoint gain of the mass are ``1 / (4 tau)`` (1/s).
    pump_gain : float
        Setpoint gain and range taper ``k`` of the pump (1/s), > 0 (default 0.5 1/s).

    Attributes
    ----------
    lower, upper, rate_limit, gain : ndarray, shape (3,)
        Range ends (m, m, kg), rate limits (m/s, m/s, kg/s; 0 for a fixed axis) and taper/setpoint gains (1/s) of
        ``ACTUATED_AXES``.
    accel_model : AccelerationControlledGlider
        The acceleration-controlled model whose right-hand side :meth:`rhs` evaluates.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle or a number is not real.
    ArgumentError
        If ``servo_time`` or ``pump_gain`` is not a positive finite number.
    ModelError
        If the vehicle is not an underwater glider with ``mbar > 0``, or its ``[actuators]`` table lacks an entry
        for ``m0``, ``r_P1`` or ``r_P3`` (the message shows how to add them with ``veh.with_actuators``).
    """

    vehicle: Vehicle = field(repr=False)
    servo_time: float = 0.5
    pump_gain: float = 0.5
    lower: np.ndarray = field(init=False, repr=False, compare=False)
    upper: np.ndarray = field(init=False, repr=False, compare=False)
    rate_limit: np.ndarray = field(init=False, repr=False, compare=False)
    gain: np.ndarray = field(init=False, repr=False, compare=False)
    accel_model: AccelerationControlledGlider = field(init=False, repr=False, compare=False)

    state_names = ACCEL_STATES
    input_names = ACTUATED_INPUTS
    actuator_names = ACTUATED_AXES

    def __post_init__(self) -> None:
        veh = require_glider(self.vehicle)
        object.__setattr__(self, "accel_model", AccelerationControlledGlider(veh))  # checks mbar > 0
        tau = checks.positive("servo_time", self.servo_time, unit="s")
        kp = checks.positive("pump_gain", self.pump_gain, unit="1/s")
        object.__setattr__(self, "servo_time", tau)
        object.__setattr__(self, "pump_gain", kp)
        missing = [a for a in ACTUATED_AXES if a not in veh.actuators]
        if missing:
            raise ModelError(
                f"vehicle '{veh.name}' has no [actuators] entr{'y' if len(missing) == 1 else 'ies'} for "
                f"{', '.join(missing)}: an actuated simulation needs the range and rate of the pump (m0) and of the "
                "moving mass (r_P1, r_P3; a part that does not move is 'fixed'). Add an [actuators] table to the "
                "vehicle file, or e.g. veh.with_actuators(m0={'min': -0.25, 'max': 0.25, 'rate': 0.01}, "
                "r_P1={'min': -0.025, 'max': 0.025, 'rate': 0.005}, r_P3={'fixed': 0.0})")
        acts = [veh.actuators[a] for a in ACTUATED_AXES]
        object.__setattr__(self, "lower", np.array([a.bounds[0] for a in acts]))
        object.__setattr__(self, "upper", np.array([a.bounds[1] for a in acts]))
        object.__setattr__(self, "rate_limit", np.array([0.0 if a.fixed is not None else a.rate for a in acts]))
        object.__setattr__(self, "gain", np.array([0.25 / tau, 0.25 / tau, kp]))

    def positions(self, x: Any) -> np.ndarray:
        """Actuator positions ``(r_P1, r_P3, m0)`` (m, m, kg) of states ``x`` (shape ``(..., 11)``)."""
        return trailing_array("x", x, 11, self.state_names)[..., _POS]

    def acceleration_rates(self, x: Any, w: Any) -> np.ndarray:
        """Requested rates realizing the thesis inputs ``w = (w1, w3, w4)`` of (2.33) inside the limits:
        ``(rdot_P1 + tau w1, rdot_P3 + tau w3, w4)``."""
        tau = self.servo_time
        x = trailing_array("x", x, 11, self.state_names)
        w = trailing_array("w", w, 3, ("w1", "w3", "w4"))
        if x.ndim == 1 and w.ndim == 1 and x.dtype.kind == "f" and w.dtype.kind == "f":  # one real state
            return np.array((x[7] + tau * w[0], x[9] + tau * w[1], w[2]))
        return np.stack([x[..., 7] + tau * w[..., 0], x[..., 9] + tau * w[..., 1], w[..., 2]], axis=-1)

    def position_command(self, x: Any, u: Any) -> np.ndarray:
        """Position command equivalent ``p_i + u_i / k_i`` of requested rates ``u`` (the setpoint that would request
        them; m, m, kg)."""
        u = trailing_array("u", u, 3, self.input_names)
        return self.positions(x) + u / self.gain

    def rhs(self, x: Any, u: Any) -> Any:
        """Time derivative of the state: the acceleration-form right-hand side (2.33)-(2.36) driven by the limited
        rates (module docstring).

        Parameters
        ----------
        x : array_like, shape (..., 11)
        u : array_like, shape (..., 3)
            Requested rates (m/s, m/s, kg/s).

        Returns
        -------
        ndarray, shape (..., 11)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 11, self.state_names)
        u = trailing_array("u", u, 3, self.input_names)
        lo, hi = rate_interval(x[..., _POS], self.lower, self.upper, self.rate_limit, self.gain)
        s = np.minimum(np.maximum(u, lo), hi)
        tau = self.servo_time
        if s.ndim == 1 and x.ndim == 1 and s.dtype.kind == "f" and x.dtype.kind == "f":  # one real state
            w = np.array(((s[0] - x[7]) / tau, (s[1] - x[9]) / tau, s[2]))
        else:
            w = np.stack([(s[..., 0] - x[..., 7]) / tau, (s[..., 1] - x[..., 9]) / tau, s[..., 2]], axis=-1)
        return self.accel_model.rhs(x, w)

    def check_state(self, x: Any, what: str = "x0") -> np.ndarray:
        """``x`` (shape (11,)) if its actuators are inside their ranges and its mass velocities inside the invariant
        set of the servo (module docstring).

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If ``x`` is not 11 finite numbers.
        InfeasibleGlideError
            If an actuator is outside its range or moves faster than its rate limit allows there.
        """
        x = checks.array(what, x, shape=(11,))
        check_actuator_state(self, x, what, {0: 7, 1: 9}, ACTUATED_UNITS)
        return x
