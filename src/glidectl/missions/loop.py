"""The closed loop a glider flies between two events of a mission: the actuated 3-D glider, its onboard law and its
dead reckoning, as one input-free model.

State: the 19 states of :class:`~glidectl.models.actuated3d.ActuatedGlider3D` followed by the dead-reckoned
position ``(dr_east, dr_north)`` (m) and the pump energy spent (J), ``E' =``
:func:`~glidectl.controllers.dive_cycle.pump_power` (the integrand of :func:`~glidectl.pump_energy`, integrated with
the motion instead of on samples).

Dead reckoning uses what the glider measures: the depth rate ``zdot`` (pressure), pitch ``theta`` and heading
``psi`` (compass), and the flight model of the leg's designed glide (angle of attack ``alpha_e``), as Slocum's
onboard dead reckoning does:

    gamma_est = theta - alpha_e (kept at least 0.1 rad from horizontal, on the side of the phase),
    u_est = max(-zdot / tan(gamma_est), 0),
    (dr_east, dr_north)' = u_est (sin psi, cos psi) + c_est,

with ``c_est`` the depth-averaged current estimated at the last surfacing. The heading reference points the water
velocity so that, with ``c_est``, the ground track heads for the waypoint (the current correction of Slocum and
Seaglider): with ``d`` the unit vector from the dead-reckoned position to the waypoint, ``c_perp`` the part of
``c_est`` across it and ``U`` the glide's horizontal speed, the glider heads along ``sqrt(U^2 - |c_perp|^2) d -
c_perp`` (along ``-c_perp`` when the cross current is faster than the glider).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..controllers.dive_cycle import pump_power
from ..models.actuated3d import ACTUATED3D_STATES, ActuatedGlider3D
from ..models.glider3d import ypr_to_quat
from .behaviours import DivePlan, pitch_heading

__all__ = ["DR_GAMMA_MIN", "MISSION_STATES", "MissionLoop", "current_corrected_heading", "rest_state"]

#: State names of :class:`MissionLoop`.
MISSION_STATES = (*ACTUATED3D_STATES, "dr_east", "dr_north", "pump_energy")
#: Smallest glide-path angle (rad) the dead reckoning divides by.
DR_GAMMA_MIN = 0.1


def current_corrected_heading(position: Any, target: Any, current: Any, speed: float) -> Any:
    """Heading (rad, from north toward east) that makes good a track from ``position`` to ``target`` (east, north;
    m) through a current ``current`` (east, north; m/s) at horizontal water speed ``speed`` (m/s)."""
    d = np.asarray(target, dtype=float) - np.asarray(position, dtype=float)
    dist = np.hypot(d[..., 0], d[..., 1])
    dhat = d / np.maximum(dist, 1e-9)[..., None]
    c = np.asarray(current, dtype=float)
    c_par = np.sum(c * dhat, axis=-1)
    c_perp = c - c_par[..., None] * dhat
    a = np.sqrt(np.maximum(speed * speed - np.sum(c_perp * c_perp, axis=-1), 0.0))
    w = a[..., None] * dhat - c_perp
    return np.arctan2(w[..., 0], w[..., 1])


@dataclass(frozen=True)
class MissionLoop:
    """One phase of a mission (a dive ``phase = +1`` or a climb ``-1``) as an input-free model (module docstring).

    Parameters
    ----------
    plant : ActuatedGlider3D
        The glider and the current.
    plan : DivePlan
        The designed glides.
    law : object
        The onboard law: ``law.rates(plant, plan, x, phase, heading_ref)`` returns requested actuator rates.
    phase : int
        ``+1`` dive, ``-1`` climb.
    target : (float, float) or None
        Waypoint ``(east, north)`` (m); None: hold the heading ``hold_heading`` (after the last waypoint).
    current_estimate : (float, float)
        Depth-averaged current ``(east, north)`` (m/s) the glider believes in.
    t_offset : float
        Mission time (s) at the model's ``t = 0`` (a time-varying current reads ``t_offset + t``).
    hold_heading : float
        Heading (rad) held when there is no waypoint.
    """

    plant: ActuatedGlider3D
    plan: DivePlan
    law: Any
    phase: int
    target: tuple[float, float] | None
    current_estimate: tuple[float, float] = (0.0, 0.0)
    t_offset: float = 0.0
    hold_heading: float = 0.0

    state_names = MISSION_STATES
    input_names = ()

    @property
    def vehicle(self) -> Any:
        """The plant's vehicle."""
        return self.plant.vehicle

    @property
    def time_varying(self) -> bool:
        """Whether the current changes in time."""
        return self.plant.time_varying

    def heading_reference(self, x: Any) -> Any:
        """Heading reference (rad) at states ``x`` (shape ``(..., 22)``) from their dead-reckoned positions."""
        x = np.real(np.asarray(x))
        if self.target is None:
            return np.full(x.shape[:-1], self.hold_heading)
        return current_corrected_heading(x[..., 19:21], self.target, self.current_estimate,
                                         self.plan.horizontal_speed(self.phase))

    def dead_reckoning_rate(self, x: Any, zdot: Any) -> Any:
        """``(dr_east, dr_north)'`` (m/s) at states ``x`` with depth rate ``zdot`` (m/s)."""
        theta, psi = pitch_heading(np.asarray(x))
        p = self.phase
        gamma = -p * np.maximum(-p * (theta - self.plan.glide(p).alpha), DR_GAMMA_MIN)
        u = np.maximum(-zdot / np.tan(gamma), 0.0)
        return np.stack([u * np.sin(psi) + self.current_estimate[0], u * np.cos(psi) + self.current_estimate[1]], -1)

    def rhs(self, x: Any, u: Any = None, t: float = 0.0) -> Any:
        """Time derivative of the 22 states ``x`` (shape ``(..., 22)``; ``u`` is ignored: the loop has no inputs)."""
        x = np.asarray(x)
        xp = x[..., :19]
        rates = self.law.rates(self.plant, self.plan, xp, self.phase, self.heading_reference(x))
        d = self.plant.rhs(xp, rates, self.t_offset + t)
        veh = self.plant.vehicle
        power = pump_power(np.real(xp[..., 2]), np.real(d[..., 17]), efficiency=veh.params.get("pump_efficiency", 1.0),
                           rho=self._rho, g=veh.g)
        return np.concatenate([d, self.dead_reckoning_rate(xp, d[..., 2]), power[..., None]], -1)

    @property
    def _rho(self) -> float:
        return float(self.plant.vehicle.water_density(0.0))

    def distance_to_target(self, x: Any) -> float:
        """Dead-reckoned distance (m) from states ``x`` (shape (22,)) to the waypoint (inf without one)."""
        if self.target is None:
            return math.inf
        return math.hypot(float(np.real(x[19])) - self.target[0], float(np.real(x[20])) - self.target[1])


def rest_state(plan: DivePlan, position: np.ndarray, fix: np.ndarray, heading: float,
                energy: float = 0.0) -> np.ndarray:
    """At rest at the surface at ``position`` (east, north), pitched as the dive, heading ``heading``, pump and
    battery at the dive's settings, dead reckoning started at ``fix``, ``energy`` (J) spent so far."""
    g = plan.down
    x = np.zeros(len(MISSION_STATES))
    x[0], x[1] = position[1], position[0]
    x[3:7] = ypr_to_quat(heading, g.theta, 0.0)
    x[13], x[17] = g.r_p1, g.m0
    x[19], x[20], x[21] = fix[0], fix[1], energy
    return x
