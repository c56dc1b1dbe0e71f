"""Turns of a glider on a mission: the steering setting (battery roll or rudder) that turns a designed glide into a
steady helix of a requested radius.

:func:`~glidectl.design_helix` chooses the battery position and buoyancy of a helix; on a mission the pump and the
battery along the hull are committed to the dive's glide, and a turn is made with the heading actuator alone. So
:func:`design_turn` keeps the glide's ``m0`` and ``r_P1`` (:func:`~glidectl.steady_glide` at the requested speed
and flight-path angle) and solves ``radius(u) = R`` for the steering setting ``u`` with :func:`~glidectl.helix_trim`
(a scan of the setting's magnitude from the straight glide, continued trim by trim, brackets the radius on the
first stable branch; Brent's method on ``log radius`` finishes), in the direction asked for, within the actuator's
range. The radius need not fall monotonically with the setting (on the Slocum model the rudder's tightest dive turn
is at 0.3 rad, not at the end of its range), so the scan stops where the branch turns unstable or reverses.

A battery rolled by ``phi`` sits at ``r_P = (r_P1, rho sin(phi), rho cos(phi))`` (``rho`` the battery offset, the
vehicle's ``r_P3`` setting); a rudder angle enters the loads (:func:`~glidectl.hydro.loads_3d`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from .. import checks
from ..errors import ArgumentError, InfeasibleGlideError, ModelError
from ..params import Vehicle
from .glide import SteadyGlide, steady_glide
from .helix import Helix, helix_trim

__all__ = ["STEER_MIN", "TurnDesign", "battery_offset", "design_turn", "steering_axis", "turn_helix"]

#: Smallest steering setting (rad) searched: a turn wider than this setting's is a straight glide for any mission.
STEER_MIN = 1e-3
_SCAN = 16   # settings scanned (geometric, STEER_MIN to the range's end) to bracket the radius


def battery_offset(veh: Vehicle) -> float:
    """The battery's offset ``rho`` below the body-1 axis (m): the fixed ``[actuators] r_P3`` or the ``r_P3``
    parameter (0 when neither is given)."""
    act = veh.actuators.get("r_P3")
    if act is not None and act.fixed is not None:
        return float(act.fixed)
    return float(veh.params.get("r_P3", 0.0))


def steering_axis(veh: Vehicle, steer: str = "auto") -> str:
    """The heading actuator a vehicle steers with: ``"roll"`` or ``"rudder"`` (``"auto"``: roll when the file moves
    its battery in roll, else the rudder).

    Raises
    ------
    ArgumentError
        If ``steer`` is not ``"auto"``, ``"roll"`` or ``"rudder"``.
    ModelError
        If the vehicle has no moving heading actuator (the message says how to add one), or not the one asked for.
    """
    checks.choice("steer", steer, ("auto", "roll", "rudder"))
    moving = [a for a in ("roll", "rudder") if a in veh.actuators and veh.actuators[a].fixed is None
              and veh.actuators[a].rate > 0]
    if steer == "auto":
        if not moving:
            raise ModelError(
                f"vehicle '{veh.name}' cannot steer: a mission needs a heading actuator, [actuators] roll (battery "
                "roll by rotation, rad) or rudder (rad, with K_SF_rudder and K_MY_rudder); add one to the vehicle "
                "file or with veh.with_actuators(roll={'min': -0.5, 'max': 0.5, 'rate': 0.1})")
        return moving[0]
    if steer not in moving:
        raise ModelError(f"vehicle '{veh.name}' has no moving [actuators] {steer}: steer={steer!r} needs it (the file "
                         f"moves {moving or 'no heading actuator'})")
    return steer


def turn_helix(veh: Vehicle, glide: SteadyGlide, steer: str, setting: float, guess: Helix | None = None) -> Helix:
    """The steady motion of ``glide``'s buoyancy and battery position with the heading actuator ``steer``
    (``"roll"`` or ``"rudder"``) held at ``setting`` (rad)."""
    rho = battery_offset(veh)
    if steer == "roll":
        r_p = (glide.r_p1, rho * math.sin(setting), rho * math.cos(setting))
        return helix_trim(veh, r_p, glide.m0, guess=guess)
    return helix_trim(veh, (glide.r_p1, 0.0, rho), glide.m0, guess=guess, rudder=setting)


@dataclass(frozen=True)
class TurnDesign:
    """Steering settings that turn a mission's glides into helices of one radius (:func:`design_turn`).

    Attributes
    ----------
    radius : float
        Requested turn radius (m).
    direction : int
        ``+1`` turns to starboard (heading increasing), ``-1`` to port.
    steer : str
        ``"roll"`` or ``"rudder"``.
    settings : dict of int to float
        Steering setting (rad) for the down (``+1``) and up (``-1``) glide.
    helices : dict of int to Helix
        The steady turns (radius, drop per turn, period, stability) of the two glides.
    glides : dict of int to SteadyGlide
        The glides turned.
    vehicle : Vehicle
    provenance : str
        The vehicle's parameter hash.
    """

    radius: float
    direction: int
    steer: str
    settings: dict[int, float]
    helices: dict[int, Helix] = field(repr=False)
    glides: dict[int, SteadyGlide] = field(repr=False)
    vehicle: Vehicle = field(repr=False)
    provenance: str = ""


def _solve(veh: Vehicle, glide: SteadyGlide, steer: str, radius: float, direction: int) -> tuple[float, Helix]:
    """The setting of one glide's turn: a scan of the setting's magnitude (continued from the straight glide) for the
    first stable bracket of the radius, then Brent's method in it (module docstring)."""
    lo, hi = veh.actuators[steer].bounds
    probe = turn_helix(veh, glide, steer, STEER_MIN)
    sign = direction * (1 if probe.psidot > 0 else -1)          # setting sign that turns the asked way
    reach = hi if sign > 0 else -lo
    side = "starboard" if direction > 0 else "port"
    leg = "dive" if glide.gamma < 0 else "climb"
    if not reach > STEER_MIN:
        raise InfeasibleGlideError(f"the {steer} of vehicle '{veh.name}' cannot turn its {leg} to {side}: its range "
                                   f"[{lo:g}, {hi:g}] rad has no room on that side")
    grid = np.geomspace(STEER_MIN, reach, _SCAN)
    helices = [probe]
    for mag in grid[1:]:
        h = turn_helix(veh, glide, steer, sign * mag, guess=helices[-1])
        if not (h.stable and h.psidot * direction > 0):
            break                  # past the last turn of this branch: stop the scan there
        helices.append(h)
    radii = np.array([h.radius for h in helices])
    k = int(np.argmax(radii <= radius)) if np.any(radii <= radius) else -1
    if k <= 0:
        if k == 0:
            raise InfeasibleGlideError(f"a {radius:g} m turn is wider than the {steer} of {STEER_MIN:g} rad gives "
                                       f"({radii[0]:.4g} m): for any mission this is a straight glide")
        tight = int(np.argmin(radii))
        raise InfeasibleGlideError(
            f"a {radius:g} m turn to {side} is out of reach of vehicle '{veh.name}' on its {leg} (gamma "
            f"{math.degrees(glide.gamma):.3g} deg, speed {glide.speed:g} m/s): its tightest stable turn is "
            f"{radii[tight]:.4g} m, at {steer} = {sign * grid[tight]:.3g} rad; ask for a wider turn or a slower glide")
    guess = [helices[k - 1]]

    def gap(mag: float) -> float:
        h = turn_helix(veh, glide, steer, sign * mag, guess=guess[0])
        return math.log(h.radius / radius)

    mag = brentq(gap, grid[k - 1], grid[k], xtol=1e-12, rtol=1e-12)
    return sign * mag, turn_helix(veh, glide, steer, sign * mag, guess=guess[0])


def design_turn(veh: Vehicle, radius: float, *, gamma: float = math.radians(25.0), speed: float = 0.35,
                direction: int = 1, steer: str = "auto") -> TurnDesign:
    """Steering settings for a steady turn of ``radius`` (m) on a mission's dive and climb (module docstring).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with the 3D parameters, a battery and a moving heading actuator (``[actuators] roll`` or
        ``rudder``).
    radius : float
        Turn radius (m), > 0.
    gamma, speed : float
        Flight-path angle magnitude (rad, in ``(0, pi/2)``) and speed (m/s) of the glides (a
        :class:`~glidectl.Mission`'s ``gamma`` and ``speed``).
    direction : {1, -1}
        Turn to starboard (``+1``, heading increasing) or port (``-1``).
    steer : {"auto", "roll", "rudder"}
        Heading actuator (:func:`steering_axis`).

    Returns
    -------
    TurnDesign

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or a number is not real.
    ArgumentError
        If a number is out of range or ``direction`` is not 1 or -1.
    ModelError
        If the vehicle has no heading actuator or lacks the 3D parameters.
    InfeasibleGlideError
        If no setting in the actuator's range gives the radius (the message gives the tightest turn), or a glide is
        outside the flight envelope.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("slocum_shallow")  # steered by its rudder
    >>> turn = gc.design_turn(veh, radius=120.0, gamma=np.radians(25.0), speed=0.35)
    >>> dive, climb = np.degrees(turn.settings[1]), np.degrees(turn.settings[-1])  # keys: +1 dive, -1 climb
    >>> print(f"{turn.steer}: dive {dive:+.1f} deg, climb {climb:+.1f} deg")
    rudder: dive +13.4 deg, climb -1.7 deg
    """
    checks.vehicle("veh", veh, "underwater_glider")
    radius = checks.positive("radius", radius, unit="m")
    gamma = checks.real("gamma", gamma, lo=0.0, hi=math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    speed = checks.positive("speed", speed, unit="m/s")
    if direction not in (1, -1):
        raise ArgumentError(f"direction must be 1 (starboard) or -1 (port), got {direction!r}")
    axis = steering_axis(veh, steer)
    rho = battery_offset(veh)
    glides = {p: steady_glide(veh, speed, -p * gamma, r_p3=rho) for p in (1, -1)}
    solved = {p: _solve(veh, glides[p], axis, radius, direction) for p in (1, -1)}
    return TurnDesign(radius, direction, axis, {p: float(s[0]) for p, s in solved.items()},
                      {p: s[1] for p, s in solved.items()}, glides, veh, veh.provenance)
