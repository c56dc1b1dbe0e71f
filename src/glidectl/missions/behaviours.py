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
from ..controllers.output_feedback import lqg_glide
from ..errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError
from ..models.actuated3d import ActuatedGlider3D
from ..params import Vehicle
from ..trim.glide import SteadyGlide, steady_glide
from ..trim.turn import TurnDesign, steering_axis, turn_helix

__all__ = ["LQR_DESIGN_SENSORS", "LQR_STATES", "STEER_PROBE", "DiveLQR", "DivePlan", "GliderBehaviours",
           "PitchBehaviourLaw", "dead_zone", "pitch_heading", "wrap_angle"]

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

    def prepare(self, plan: DivePlan) -> GliderBehaviours:
        """The law to fly ``plan`` with: itself, once the plan is checked against the turn it may hold.

        Raises
        ------
        ArgumentError
            If the turn was designed for another glide, steering actuator or vehicle.
        """
        t = self.turn
        if t is None:
            return self
        if t.steer != plan.steer or t.vehicle.provenance != plan.plant.vehicle.provenance or any(
                abs(t.glides[p].gamma - plan.glide(p).gamma) > 1e-12 or abs(t.glides[p].speed - plan.glide(p).speed)
                > 1e-12 for p in (1, -1)):
            raise ArgumentError("the turn was designed for another glide, vehicle or heading actuator than the "
                                f"mission's ({t.steer} at speed {t.glides[1].speed:g} m/s, gamma "
                                f"{math.degrees(-t.glides[1].gamma):.4g} deg); design it with the mission's gamma, "
                                "speed and steer")
        return self

    def rates(self, plant: ActuatedGlider3D, plan: DivePlan, x: Any, phase: int, heading_ref: Any) -> np.ndarray:
        """Requested actuator rates ``(r_P1_rate, roll_rate, m0_rate, rudder_rate)`` at plant states ``x`` (shape
        ``(..., 19)``) in a dive (``phase = +1``) or climb (``-1``) toward heading ``heading_ref`` (rad)."""
        x = np.asarray(x)
        g = plan.glide(phase)
        theta, _ = pitch_heading(x)
        theta_ref = g.theta if self.turn is None else self.turn.helices[phase].theta   # a turn pitches differently
        battery = plant.rho / self.pitch_time * dead_zone(theta - theta_ref, self.pitch_deadband)
        steer = self.steering(plan, x, phase, heading_ref)
        setpoints = np.zeros((*x.shape[:-1], 4))
        setpoints[..., 2] = g.m0
        setpoints[..., 1 if plan.steer == "roll" else 3] = steer
        rates = plant.setpoint_rates(x, setpoints)
        rates[..., 0] = battery
        return rates

    def pitch_loop(self, veh: Vehicle, glide: SteadyGlide, *, servo_time: float = 0.5,
                   pump_gain: float = 0.5) -> Any:
        """The longitudinal closed loop of the pitch behaviour once the pitch error is out of its deadband: the
        battery rate ``(rho / pitch_time) (theta - theta_ref)`` (the dead zone's slope-1 branch, ``rho`` the battery
        offset ``r_P3``) and the pump held at the glide's ``m0`` by its servo, on the actuated glider
        (:class:`~glidectl.ActuatedGlider`) at the glide ``glide``.

        This is the loop whose poles say whether the behaviour's correction converges (for eigen-analysis and
        :func:`~glidectl.robust_stability`); inside the deadband the battery holds and the glider flies open loop.
        The horizontal position and the depth drift along the glide; nothing in the loop depends on them.

        Parameters
        ----------
        veh : Vehicle
            The glider (with its ``[uncertainty]`` table for :func:`~glidectl.robust_stability`).
        glide : SteadyGlide
            The glide flown: the pitch reference ``theta_ref`` and the pump setting ``m0``.
        servo_time, pump_gain : float
            The actuated glider's servo time (s) and pump gain (1/s).

        Returns
        -------
        ClosedLoop
            With the glide's actuated state at 0 m as its equilibrium.

        Raises
        ------
        ModelError
            If the vehicle has no actuators or no battery offset (``r_P3 = 0``: the behaviour's gain is zero).
        InfeasibleGlideError
            If the glide is outside the actuator ranges.
        """
        from ..controllers.closed_loop import closed_loop
        from ..models.actuated import ActuatedGlider

        if not isinstance(glide, SteadyGlide):
            raise ArgumentTypeError(f"glide must be a SteadyGlide (glidectl.steady_glide), got {type(glide).__name__}")
        plant = ActuatedGlider(veh, servo_time=servo_time, pump_gain=pump_gain)
        x_eq = glide.accel_state(0.0, 0.0)
        plant.check_state(x_eq, "the glide of the pitch loop")
        rho = float(x_eq[8])
        if rho == 0.0:
            raise ModelError(f"vehicle '{veh.name}' has its battery on the axis (r_P3 = 0): the pitch behaviour's "
                             "gain rho / pitch_time is zero")
        law = PitchBehaviourLaw(plant, rho / self.pitch_time, float(x_eq[2]), plant.positions(x_eq))
        return closed_loop(plant, law, equilibrium=x_eq)

    def steering(self, plan: DivePlan, x: Any, phase: int, heading_ref: Any) -> Any:
        """Steering setpoint (rad) of the heading actuator: the dead-zone heading law, or the held turn."""
        if self.turn is not None:
            return np.full(np.shape(x)[:-1], self.turn.settings[phase])
        _, psi = pitch_heading(np.asarray(x))
        return dead_zone(wrap_angle(heading_ref - psi), self.heading_deadband) / (
            self.heading_time * plan.turn_gain[phase])


@dataclass(frozen=True)
class PitchBehaviourLaw:
    """Requested rates of :meth:`GliderBehaviours.pitch_loop` on the actuated glider's states (picklable).

    Attributes
    ----------
    plant : ActuatedGlider
    k_theta : float
        Battery rate per rad of pitch error (m/(s rad)).
    theta_ref : float
        Pitch reference (rad).
    setpoints : ndarray, shape (3,)
        Actuator setpoints ``(r_P1, r_P3, m0)`` of the glide (the battery's entry is not used).
    """

    plant: Any = field(repr=False)
    k_theta: float
    theta_ref: float
    setpoints: np.ndarray = field(repr=False)

    def __call__(self, x: Any) -> np.ndarray:
        """``(r_P1_rate, r_P3_rate, m0_rate)`` at states ``x`` (shape ``(..., 11)``)."""
        x = np.asarray(x)
        rates = self.plant.setpoint_rates(x, np.broadcast_to(self.setpoints, (*x.shape[:-1], 3)))
        rates[..., 0] = self.k_theta * (x[..., 2] - self.theta_ref)
        return rates


#: Sensors and noise (m, rad, rad/s) of the longitudinal LQG design whose regulator :class:`DiveLQR` flies (the
#: regulator does not depend on them).
LQR_DESIGN_SENSORS = {"z": 0.05, "theta": math.radians(0.5), "Omega2": math.radians(0.2)}


@dataclass(frozen=True)
class DiveLQR:
    """LQR dive controller: the regulator of the longitudinal LQG design of each phase's glide
    (:func:`~glidectl.lqg_glide`, acceleration inputs on the actuators the file moves, Bryson weights, the
    glide-path deviation ``z'`` not regulated: a dive holds the glide, not a path), flown as state feedback on the
    3-D state (pitch from the attitude, pitch rate, body velocities, battery position and rate, pump), with the
    behaviours' heading law on the steering actuator.

    It uses the body velocities, which a glider does not measure: it is the full-information bound the behaviours
    are compared with, not an onboard law.

    Parameters
    ----------
    heading : GliderBehaviours
        Source of the heading law (deadband, time constant, or a held turn).
    max_deviation : mapping of str to float, optional
        Bryson's-rule overrides of the design (:data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION`).
    """

    heading: GliderBehaviours = field(default_factory=GliderBehaviours)
    max_deviation: Any = None
    gains: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict, repr=False)
    name = "lqr"

    def prepare(self, plan: DivePlan) -> DiveLQR:
        """The controller with the gains of ``plan``'s two glides.

        Raises
        ------
        ArgumentError, SolverError, ModelError
            If a design fails (an unknown ``max_deviation`` name, no stabilizing solution, a design that needs
            inputs or states the mission controller does not have).
        """
        self.heading.prepare(plan)
        veh = plan.plant.vehicle
        gains = {}
        for phase in (1, -1):
            g = plan.glide(phase)
            c = lqg_glide(veh, g, tuple(LQR_DESIGN_SENSORS), LQR_DESIGN_SENSORS, inputs="acceleration",
                          max_deviation=self.max_deviation)
            gains[phase] = _map_gain(c.K, tuple(c.plant.state_labels), tuple(c.plant.input_labels), g)
        return DiveLQR(self.heading, self.max_deviation, gains)

    def rates(self, plant: ActuatedGlider3D, plan: DivePlan, x: Any, phase: int, heading_ref: Any) -> np.ndarray:
        """Requested actuator rates (as :meth:`GliderBehaviours.rates`) from the LQR of the phase's glide."""
        if not self.gains:
            raise ArgumentError("DiveLQR flies a plan it was prepared for: call prepare(plan) first (fly_mission "
                                "does)")
        K, x_e = self.gains[phase]
        x = np.asarray(x)
        theta, _ = pitch_heading(x)
        y = np.stack([theta, x[..., 11], x[..., 7], x[..., 9], x[..., 13], x[..., 14], x[..., 17]], -1)
        w = -(y - x_e) @ K.T                       # (w1, w4): battery acceleration, pump rate
        setpoints = np.zeros((*x.shape[:-1], 4))
        setpoints[..., 1 if plan.steer == "roll" else 3] = self.heading.steering(plan, x, phase, heading_ref)
        rates = plant.setpoint_rates(x, setpoints)
        rates[..., 0] = x[..., 14] + plant.servo_time * w[..., 0]
        rates[..., 2] = w[..., 1]
        return rates


#: The longitudinal states :class:`DiveLQR` feeds back, in the order of its gains.
LQR_STATES = ("theta", "Omega2", "v1", "v3", "r_P1", "rdot_P1", "m0")


def _map_gain(K: np.ndarray, states: tuple[str, ...], inputs: tuple[str, ...], g: SteadyGlide) -> tuple:
    """The gain of ``(w1, w4)`` on :data:`LQR_STATES` and the glide's values of those states; every other state of
    the design must have no gain (``z'``, a fixed actuator's states) and every other input a zero row."""
    rows = [inputs.index(w) for w in ("w1", "w4")]
    cols = [states.index(n) for n in LQR_STATES]
    others = [j for j in range(len(states)) if j not in cols]
    unused = [i for i, w in enumerate(inputs) if w not in ("w1", "w4")]
    if np.any(K[np.ix_(rows, others)] != 0.0) or np.any(K[unused] != 0.0):
        raise ModelError(f"the LQR design of vehicle '{g.vehicle.name}' feeds back states or drives inputs the "
                         f"mission controller does not have (states {[states[j] for j in others]}, inputs "
                         f"{list(inputs)}); DiveLQR flies the battery along the hull and the pump (w1, w4) only")
    x_e = np.array([g.theta, 0.0, g.v1, g.v3, g.r_p1, 0.0, g.m0])
    return K[np.ix_(rows, cols)].copy(), x_e


def pitch_heading(x: np.ndarray) -> tuple[Any, Any]:
    """Pitch and heading (rad) from the quaternion columns 3-6 of plant states (YPR of (8.26))."""
    w, a, b, c = x[..., 3], x[..., 4], x[..., 5], x[..., 6]
    n = w * w + a * a + b * b + c * c
    sin_theta = np.clip(-2 * (a * c - w * b) / n, -1.0, 1.0)
    psi = np.arctan2(2 * (a * b + w * c), n - 2 * (b * b + c * c))
    return np.arcsin(sin_theta), psi
