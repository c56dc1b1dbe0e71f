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

__all__ = ["ClosedLoopCTOL", "ClosedLoopCTOLAlpha", "SteadyGlideController", "closed_loop_eigenvalues"]


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

    def roa_model(self, box: tuple[Any, Any] | None = None) -> ClosedLoopCTOLAlpha:
        """This closed loop in ``(Vbar, gammabar, alphabar, Omega2bar)``, ``alphabar = thetabar - gammabar``, for
        region-of-attraction certification (:func:`glidectl.certify_roa`); ``box`` is the region of interest
        (default ``|Vbar| <= 0.5``, ``|gammabar| <= 0.5``, ``|alphabar| <= 0.3``, ``|Omega2bar| <= 1``)."""
        if box is None:
            box = (np.array([-0.5, -0.5, -0.3, -1.0]), np.array([0.5, 0.5, 0.3, 1.0]))
        return ClosedLoopCTOLAlpha(self, (np.asarray(box[0], dtype=float), np.asarray(box[1], dtype=float)))


@dataclass(frozen=True)
class ClosedLoopCTOLAlpha:
    """:class:`ClosedLoopCTOL` with ``thetabar`` replaced by ``alphabar = thetabar - gammabar`` (a shear, volume
    preserving). The right-hand side is the closed loop's own, ``alphabar' = thetabar' - gammabar'``.

    In these states ``gammabar`` enters only through ``sin``/``cos`` and ``alphabar`` both polynomially (lift and
    drag (7.1)-(7.2)) and through ``sin``/``cos`` (``angle_states``, ``mixed_angle_states`` for
    :func:`glidectl.roa.recast`); the ``1/V`` of (7.13) is the ``positive_state``.
    """

    closed_loop: ClosedLoopCTOL
    box: tuple[np.ndarray, np.ndarray]
    state_names: tuple[str, ...] = ("Vbar", "gammabar", "alphabar", "Omega2bar")
    input_names: tuple[str, ...] = ()
    angle_states: tuple[int, ...] = (1,)
    mixed_angle_states: tuple[int, ...] = (2,)
    positive_state: int = 0
    time_unit: str = "s"

    @property
    def name(self) -> str:
        cl = self.closed_loop
        return (f"{cl.vehicle.name} closed loop (7.16)-(7.20), V_e = {cl.glide.speed:.4g}, "
                f"gamma_e = {cl.glide.gamma:.4g}, k3 = {cl.k3:g}, k4 = {cl.k4:g}")

    @property
    def provenance(self) -> str:
        return self.closed_loop.vehicle.provenance

    @property
    def equilibrium(self) -> np.ndarray:
        return np.zeros(4)

    def to_theta(self, x: Any) -> np.ndarray:
        """``(Vbar, gammabar, alphabar, Omega2bar) -> (Vbar, gammabar, thetabar, Omega2bar)``."""
        x = np.asarray(x)
        return np.stack([x[..., 0], x[..., 1], x[..., 2] + x[..., 1], x[..., 3]], axis=-1)

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        d = self.closed_loop.rhs(self.to_theta(x))
        return np.stack([d[..., 0], d[..., 1], d[..., 2] - d[..., 1], d[..., 3]], axis=-1)


def closed_loop_eigenvalues(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float = 1.0) -> np.ndarray:
    """Eigenvalues (1/s) of the closed loop linearized at the steady glide, sorted by real part."""
    lam = np.linalg.eigvals(ClosedLoopCTOL(veh, glide, k3, k4, T).jacobian())
    return lam[np.lexsort((lam.imag, lam.real))]

