"""Closed loop of §6.1's pure torque realized by the internal moving mass: the acceleration-form longitudinal glider
(2.15)-(2.25), (2.31)-(2.34) under a moving-mass controller, with the position states ``(x, z)`` dropped.

The controller (the torque law (6.5) turned into moving-mass accelerations) is
:class:`glidectl.controllers.moving_mass.MovingMassTorque`; this module holds only the closed-loop vector field, which
is :meth:`~glidectl.models.longitudinal.AccelerationControlledGlider.rhs` (the one model) evaluated at ``x = z = 0``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentTypeError
from ..params import Vehicle
from ._validate import trailing_array
from .longitudinal import ACCEL_STATES, AccelerationControlledGlider

__all__ = ["RealizedTorqueLoop"]


@dataclass(frozen=True)
class RealizedTorqueLoop:
    """Input-free closed loop :class:`AccelerationControlledGlider` + a moving-mass controller, without ``(x, z)``.

    State ``(theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)`` (rad, rad/s, m/s, m/s, m, m/s, m, m/s, kg):
    the positions feed back into nothing, and dropping them lets a stiff integrator use the exact (complex-step)
    Jacobian of :meth:`rhs`. The right-hand side is :meth:`AccelerationControlledGlider.rhs` (the one model)
    evaluated at ``x = z = 0``. :func:`glidectl.controllers.moving_mass.simulate_realized_torque` integrates it.

    Parameters
    ----------
    controller : callable
        ``(t, xa) -> w``: the accelerations ``w = (w1, w3, w4)`` (m/s^2, m/s^2, kg/s) of (2.33) at an 11-state
        :class:`AccelerationControlledGlider` state ``xa`` of shape ``(..., 11)`` (batch-capable; called with
        ``t = 0``: the law must be time-invariant), with a ``vehicle`` attribute (:class:`Vehicle`, a glider with
        ``mbar > 0``), e.g. :class:`glidectl.controllers.moving_mass.MovingMassTorque`.
    state_names : tuple of str
        The 9 states, default ``ACCEL_STATES[2:]`` (units in :data:`glidectl.models.longitudinal.STATE_UNITS`).
    input_names : tuple of str
        Empty: the loop is input-free.

    Attributes
    ----------
    vehicle : Vehicle
        The controller's vehicle.

    Raises
    ------
    ArgumentTypeError
        If ``controller`` is not callable or has no ``vehicle`` Vehicle.
    ModelError
        If that vehicle is not a glider with a moving mass (:class:`AccelerationControlledGlider`).
    """

    controller: Callable[[float, Any], Any]
    state_names: tuple[str, ...] = ACCEL_STATES[2:]
    input_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        checks.function("controller", self.controller)
        veh = getattr(self.controller, "vehicle", None)
        if veh is None:
            raise ArgumentTypeError(f"controller {type(self.controller).__name__} has no 'vehicle' attribute (use "
                                    "glidectl.controllers.moving_mass.MovingMassTorque)")
        AccelerationControlledGlider(veh)

    @property
    def vehicle(self) -> Vehicle:
        return self.controller.vehicle  # type: ignore[attr-defined]

    def full_state(self, y: Any) -> np.ndarray:
        """Pad ``(theta, ...)`` (shape ``(..., 9)``) with ``x = z = 0`` to the 11-state acceleration form."""
        y = trailing_array("y", y, 9, self.state_names)
        return np.concatenate([np.zeros((*y.shape[:-1], 2), dtype=y.dtype), y], axis=-1)

    def rhs(self, y: Any, u: Any = None) -> np.ndarray:
        """Closed-loop derivative of the 9 states, ``y`` of shape ``(..., 9)`` (``u`` ignored).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``y`` is not an array of numbers with a trailing dimension 9.
        """
        xa = self.full_state(y)
        return AccelerationControlledGlider(self.vehicle).rhs(xa, self.controller(0.0, xa))[..., 2:]
