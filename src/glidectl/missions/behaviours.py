"""Onboard control of a glider on a mission, from the signals a submerged glider has: depth, pitch, heading, roll,
pumped volume, battery position (no position under water).

Two pieces:

* :class:`DivePlan`: the designed glides of a mission, down at ``-gamma`` and up at ``+gamma`` at the mission
  speed (:func:`~glidectl.steady_glide` with the battery offset of the vehicle), checked against the actuator
  ranges, and the turn-rate sensitivity of each glide to the steering actuator (from
  :func:`~glidectl.helix_trim`).
* :class:`GliderBehaviours`: the behaviours of Slocum and Seaglider flight software, as a law of the measured
  signals:

  - **pump only near the inflections**: at each inflection the pump runs (at its rate limit) to the next glide's
    buoyancy and then holds;
  - **battery on pitch with a deadband**: the battery moves at a rate proportional to the pitch error beyond the
    deadband, ``r_P1_rate = k_theta dz(theta - theta_ref)`` (``dz`` the dead zone); it holds while the pitch is
    within the deadband. ``k_theta = rho / pitch_time`` from the static pitch sensitivity of a bottom-heavy glider,
    ``d theta / d r_P1 = -1 / rho``, so that the pitch error decays in about ``pitch_time`` seconds;
  - **heading by battery roll or rudder with a deadband**: setpoint ``u = dz(psi_ref - psi) / (heading_time
    dpsidot/du)``, clipped to the actuator's range, with ``dpsidot/du`` the steady turn rate per unit setting of
    the leg's glide (its sign differs between dive and climb for a rolled battery; the plan computes it).

The law is a continuous function of the state (the dead zones have no hysteresis), so the closed loop integrates
with large steps in steady glides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError
from ..models.actuated3d import ActuatedGlider3D
from ..params import Vehicle
from ..trim.glide import SteadyGlide, steady_glide
from ..trim.turn import TurnDesign, steering_axis, turn_helix

__all__ = ["STEER_PROBE", "DivePlan", "GliderBehaviours", "dead_zone", "pitch_heading", "wrap_angle"]

#: Settings (rad) of the steering actuators at which :class:`DivePlan` measures the turn-rate sensitivity: small
#: enough to stay linear, large enough to stand out of the trim's residual.
STEER_PROBE = {"roll": 0.05, "rudder": 0.02}


def dead_zone(e: Any, width: float) -> Any:
    """``sign(e) max(|e| - width, 0)``: zero inside the deadband, continuous."""
    return np.sign(e) * np.maximum(np.abs(e) - width, 0.0)


def wrap_angle(a: Any) -> Any:
    """Angle (rad) wrapped to ``[-pi, pi)``."""
    return (a + math.pi) % (2 * math.pi) - math.pi


@dataclass(frozen=True)
class DivePlan:
    """The designed glides of a mission and their steering sensitivity.

    Parameters
    ----------
    plant : ActuatedGlider3D
        The vehicle with its actuators.
    gamma : float
        Glide-path angle magnitude (rad).
    speed : float
        Speed through the water (m/s).
    steer : {"auto", "roll", "rudder"}
        Steering actuator; ``"auto"`` takes the battery roll when the vehicle has one, else the rudder.

    Attributes
    ----------
    down, up : SteadyGlide
        The glides at ``-gamma`` and ``+gamma``.
    steer : str
        The steering actuator chosen.
    turn_gain : dict of int to float
        Steady turn rate per unit steering setting (1/s) of the down (``+1``) and up (``-1``) glide.

    Raises
    ------
    ModelError
        If the vehicle has no heading actuator (the message says how to add one).
    InfeasibleGlideError
        If a glide is outside the flight envelope or needs a buoyancy or battery position outside the actuator
        ranges (the message names the actuator and the range).
    """

    plant: ActuatedGlider3D
    gamma: float
    speed: float
    steer: str = "auto"
    down: SteadyGlide = field(init=False, repr=False)
    up: SteadyGlide = field(init=False, repr=False)
    turn_gain: dict[int, float] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        plant = self.plant
        veh = plant.vehicle
        object.__setattr__(self, "steer", steering_axis(veh, self.steer))
        glides = {}
        for phase, gam in ((1, -self.gamma), (-1, self.gamma)):
            g = steady_glide(veh, self.speed, gam, r_p3=plant.rho)
            _check_in_range(plant, g, "dive" if phase > 0 else "climb")
            glides[phase] = g
        object.__setattr__(self, "down", glides[1])
        object.__setattr__(self, "up", glides[-1])
        object.__setattr__(self, "turn_gain", {p: _turn_gain(veh, glides[p], self.steer) for p in (1, -1)})

    def glide(self, phase: int) -> SteadyGlide:
        """The down (``phase = +1``) or up (``-1``) glide."""
        return self.down if phase > 0 else self.up

    def horizontal_speed(self, phase: int) -> float:
        """Horizontal speed through the water (m/s) of a glide."""
        g = self.glide(phase)
        return g.speed * math.cos(g.gamma)


def _check_in_range(plant: ActuatedGlider3D, g: SteadyGlide, what: str) -> None:
    for i, name, value, unit in ((0, "r_P1", g.r_p1, "m"), (2, "m0", g.m0, "kg")):
        lo, hi = plant.lower[i], plant.upper[i]
        if not lo - 1e-12 <= value <= hi + 1e-12:
            raise InfeasibleGlideError(
                f"the {what} glide (speed {g.speed:g} m/s, gamma {math.degrees(g.gamma):.4g} deg) needs {name} = "
                f"{value:.4g} {unit}, outside the range [{lo:g}, {hi:g}] {unit} of [actuators] {name} of vehicle "
                f"'{plant.vehicle.name}'; choose a slower or steeper glide (glidectl.glide_envelope shows what the "
                "actuators reach)")


def _turn_gain(veh: Vehicle, g: SteadyGlide, steer: str) -> float:
    """Steady turn rate per unit steering setting (1/s per rad) at glide ``g``, from a helix at a small setting."""
    u = STEER_PROBE[steer]
    h = turn_helix(veh, g, steer, u)
    gain = h.psidot / u
    if not abs(gain) > 1e-9:
        raise ModelError(f"steering by {steer} does not turn vehicle '{veh.name}' (turn rate {h.psidot:.3g} rad/s at "
                         f"{steer} = {u:g} rad); check the roll offset r_P3 or the rudder coefficients")
    return float(gain)


@dataclass(frozen=True)
class GliderBehaviours:
    """Slocum/Seaglider-style onboard behaviours (module docstring): pump at the inflections, battery on pitch and
    heading by roll or rudder, each with a deadband.

    Parameters
    ----------
    pitch_deadband : float
        Pitch error (rad) within which the battery holds, >= 0 (default 1 deg).
    heading_deadband : float
        Heading error (rad) within which the steering holds its neutral setting, >= 0 (default 2 deg).
    pitch_time : float
        Time constant (s) of the pitch correction, > 0 (default 20 s).
    heading_time : float
        Time constant (s) of the heading correction, > 0 (default 60 s).
    turn : TurnDesign, optional
        Hold a designed turn (:func:`~glidectl.design_turn`) instead of steering for the waypoint: the heading
        actuator stays at the turn's setting for the dive or the climb (a spiral), and the battery holds the
        helix's pitch (a banked glider pitches differently from the straight glide at the same battery position).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If a value is not a real number in its range.
    """

    pitch_deadband: float = math.radians(1.0)
    heading_deadband: float = math.radians(2.0)
    pitch_time: float = 20.0
    heading_time: float = 60.0
    turn: TurnDesign | None = None
    name = "behaviours"

    def __post_init__(self) -> None:
        if self.turn is not None and not isinstance(self.turn, TurnDesign):
            raise ArgumentTypeError(f"turn must be a TurnDesign (glidectl.design_turn), got {type(self.turn).__name__}")
        for key in ("pitch_deadband", "heading_deadband"):
            object.__setattr__(self, key, checks.real(key, getattr(self, key), lo=0.0, hi=math.pi / 2, unit="rad"))
        for key in ("pitch_time", "heading_time"):
            object.__setattr__(self, key, checks.positive(key, getattr(self, key), unit="s"))

    def check_plan(self, plan: DivePlan) -> None:
        """Refuse a plan whose glides or heading actuator differ from those of the turn this law holds.

        Raises
        ------
        ArgumentError
            If the turn was designed for another glide, steering actuator or vehicle.
        """
        t = self.turn
        if t is None:
            return
        if t.steer != plan.steer or t.vehicle.provenance != plan.plant.vehicle.provenance or any(
                abs(t.glides[p].gamma - plan.glide(p).gamma) > 1e-12 or abs(t.glides[p].speed - plan.glide(p).speed)
                > 1e-12 for p in (1, -1)):
            raise ArgumentError("the turn was designed for another glide, vehicle or heading actuator than the "
                                f"mission's ({t.steer} at speed {t.glides[1].speed:g} m/s, gamma "
                                f"{math.degrees(-t.glides[1].gamma):.4g} deg); design it with the mission's gamma, "
                                "speed and steer")

    def rates(self, plant: ActuatedGlider3D, plan: DivePlan, x: Any, phase: int, heading_ref: Any) -> np.ndarray:
        """Requested actuator rates ``(r_P1_rate, roll_rate, m0_rate, rudder_rate)`` at plant states ``x`` (shape
        ``(..., 19)``) in a dive (``phase = +1``) or climb (``-1``) toward heading ``heading_ref`` (rad)."""
        x = np.asarray(x)
        g = plan.glide(phase)
        theta, psi = pitch_heading(x)
        theta_ref = g.theta if self.turn is None else self.turn.helices[phase].theta   # a turn pitches differently
        battery = plant.rho / self.pitch_time * dead_zone(theta - theta_ref, self.pitch_deadband)
        if self.turn is not None:
            steer = self.turn.settings[phase]
        else:
            steer = dead_zone(wrap_angle(heading_ref - psi), self.heading_deadband) / (
                self.heading_time * plan.turn_gain[phase])
        setpoints = np.zeros((*x.shape[:-1], 4))
        setpoints[..., 2] = g.m0
        setpoints[..., 1 if plan.steer == "roll" else 3] = steer
        rates = plant.setpoint_rates(x, setpoints)
        rates[..., 0] = battery
        return rates


def pitch_heading(x: np.ndarray) -> tuple[Any, Any]:
    """Pitch and heading (rad) from the quaternion columns 3-6 of plant states (YPR of (8.26))."""
    w, a, b, c = x[..., 3], x[..., 4], x[..., 5], x[..., 6]
    n = w * w + a * a + b * b + c * c
    sin_theta = np.clip(-2 * (a * c - w * b) / n, -1.0, 1.0)
    psi = np.arctan2(2 * (a * b + w * c), n - 2 * (b * b + c * c))
    return np.arcsin(sin_theta), psi
