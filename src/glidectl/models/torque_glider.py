"""Chapter-5 glider with a pure control torque, thesis §6.1, equations (6.1)-(6.4).

:class:`TorqueControlledGlider` is :class:`~glidectl.models.reduced.ReducedLongitudinalGlider` with the control
torque ``u`` (N m) added to the pitch equation, ``J2 Omega2' = ... + u`` (6.4). The torque law (6.5) and the gain
design are in :mod:`glidectl.controllers.torque`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..params import Vehicle
from ._validate import trailing_array
from .reduced import REDUCED_STATES, ReducedLongitudinalGlider

__all__ = ["TORQUE_INPUTS", "TorqueControlledGlider"]

TORQUE_INPUTS = ("torque",)


@dataclass(frozen=True)
class TorqueControlledGlider:
    """Chapter-5 glider with a pure control torque, (6.1)-(6.4).

    State ``(V, gamma, alpha, Omega2)`` (m/s, rad, rad, rad/s); input ``("torque",)``, ``u`` in N m about body 2.
    The right-hand side is :meth:`ReducedLongitudinalGlider.rhs` plus ``u / J2`` in ``Omega2'`` (the torque enters
    the moment balance (2.20)/(5.7) only; the masses are those of the reduced model, ``M_i = m_i + mbar``).

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider accepted by :class:`ReducedLongitudinalGlider` (``m0 != 0``).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If :class:`ReducedLongitudinalGlider` refuses it.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = TORQUE_INPUTS

    def __post_init__(self) -> None:
        ReducedLongitudinalGlider(self.vehicle)  # same validity conditions

    @cached_property
    def open_loop(self) -> ReducedLongitudinalGlider:
        """The uncontrolled model (the one right-hand side)."""
        return ReducedLongitudinalGlider(self.vehicle)

    def rhs(self, x: Any, u: Any) -> np.ndarray:
        """``(V', gamma', alpha', Omega2')`` of (6.1)-(6.4).

        Parameters
        ----------
        x : array_like, shape (..., 4)
            State (m/s, rad, rad, rad/s).
        u : array_like, shape (..., 1)
            Control torque (N m).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 4, self.state_names)
        u = trailing_array("torque input u (N m)", u, 1, self.input_names)
        d = self.open_loop.rhs(x)
        zero = np.zeros((*np.broadcast_shapes(x.shape[:-1], u.shape[:-1]), 3))
        return d + np.concatenate([zero, u[..., :1] / self.vehicle.J2], axis=-1)
