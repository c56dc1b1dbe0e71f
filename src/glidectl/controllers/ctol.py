"""Steady-glide controller of the CTOL aircraft, (7.16)-(7.20), and its closed loop.

    u1 = w11 = -k1 sin theta - k2 cos theta                                   (7.16), (7.18)
    u2 = w21 + w22,  w21 = (k1 cos theta - k2 sin theta) / eps                (7.17), (7.19)
                     w22 = -(k3 / eps) sin(theta - theta_e) - k4 T Omega2     (7.20)

``T Omega2`` is the nondimensional pitch rate ``Omega2bar`` of (7.11). ``k1, k2`` place the equilibrium (Theorem 4,
:func:`glidectl.trim.ctol.ctol_glide`); ``k3, k4 > 0`` stabilize the pitch.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._checks import positive_number
from ..analysis.jacobian import jacobians
from ..errors import ModelError
from ..models.ctol import REDUCED_STATES, CTOLReduced
from ..params import Vehicle
from ..trim.ctol import CTOLGlide

__all__ = ["ClosedLoopCTOL", "SteadyGlideController", "closed_loop_eigenvalues"]


def _inputs(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, theta: Any, Omega2: Any) -> Any:
    eps = veh.epsilon
    k1, k2 = glide.k1, glide.k2
    u1 = -k1 * np.sin(theta) - k2 * np.cos(theta)
    u2 = (k1 * np.cos(theta) - k2 * np.sin(theta)) / eps - (k3 / eps) * np.sin(theta - glide.theta_e) - k4 * T * Omega2
    return np.stack(np.broadcast_arrays(u1, u2), -1)


@dataclass(frozen=True)
class SteadyGlideController:
    """(7.16)-(7.20) for the full CTOL model: ``controller(t, x) -> (u1, u2)`` with ``x = (x, y, xdot, ydot, theta,
    Omega2)``.

    Parameters
    ----------
    vehicle : Vehicle
    glide : CTOLGlide
        The steady glide to stabilize (gains ``k1, k2`` and ``theta_e``).
    k3 : float
        Pitch stiffness gain (N; enters as ``k3 / eps``), > 0.
    k4 : float
        Pitch damping gain on ``Omega2bar = T Omega2`` (N m s), > 0.
    T : float
        Reference time of (7.11) (s).
    """

    vehicle: Vehicle
    glide: CTOLGlide
    k3: float
    k4: float
    T: float = 1.0

    def __post_init__(self) -> None:
        if self.vehicle.epsilon <= 0:
            raise ModelError("the steady-glide controller divides by eps: it needs epsilon > 0")
        for name in ("k3", "k4", "T"):
            positive_number(name, getattr(self, name))

    def __call__(self, t: float, x: Any) -> np.ndarray:
        x = np.asarray(x)
        return _inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, x[..., 4], x[..., 5])


@dataclass(frozen=True)
class ClosedLoopCTOL:
    """Input-free closed loop (7.12)-(7.20) in the reduced states ``(Vbar, gammabar, thetabar, Omega2bar)``; the
    equilibrium is the origin (the interconnected system (7.28)-(7.39))."""

    vehicle: Vehicle
    glide: CTOLGlide
    k3: float
    k4: float
    T: float = 1.0
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = ()

    @property
    def reduced(self) -> CTOLReduced:
        return CTOLReduced(self.vehicle, self.glide.speed, self.glide.gamma, self.glide.theta_e, self.T)

    def rhs(self, s: Any, u: Any = None) -> Any:
        s = np.asarray(s)
        th = s[..., 2] + self.glide.theta_e
        uu = _inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, th, s[..., 3] / self.T)
        return self.reduced.rhs(s, uu)

    def jacobian(self) -> np.ndarray:
        """Exact (complex-step) Jacobian at the origin."""
        return jacobians(lambda s, u: self.rhs(s), np.zeros(4), np.zeros(0))[0]


def closed_loop_eigenvalues(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float = 1.0) -> np.ndarray:
    """Eigenvalues (1/s) of the closed loop linearized at the steady glide, sorted by real part."""
    lam = np.linalg.eigvals(ClosedLoopCTOL(veh, glide, k3, k4, T).jacobian())
    return lam[np.lexsort((lam.imag, lam.real))]

