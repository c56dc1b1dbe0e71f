"""Closed loop of the CTOL aircraft under the steady-glide law (7.16)-(7.20), in the reduced nondimensional states
of (7.8)-(7.11) about the glide (the interconnected system (7.28)-(7.39)); its equilibrium is the origin.

    u1 = w11 = -k1 sin theta - k2 cos theta                                   (7.16), (7.18)
    u2 = w21 + w22,  w21 = (k1 cos theta - k2 sin theta) / eps                (7.17), (7.19)
                     w22 = -(k3 / eps) sin(theta - theta_e) - k4 T Omega2     (7.20)

``T Omega2`` is the nondimensional pitch rate ``Omega2bar`` of (7.11); ``k1, k2`` place the equilibrium (Theorem 4,
:func:`glidectl.trim.ctol.ctol_glide`) and ``k3, k4 > 0`` stabilize the pitch. The law is
:func:`steady_glide_inputs` (the controller object for the full model is
:class:`glidectl.controllers.ctol.SteadyGlideController`); :class:`ClosedLoopCTOL` is the one closed-loop right-hand
side used by the Theorem-5 certificate (:mod:`glidectl.stability.ctol_lyapunov`) and the region-of-attraction
certification (:class:`ClosedLoopCTOLAlpha`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.jacobian import jacobians
from ..params import Vehicle
from ..trim.ctol import CTOLGlide
from .ctol import REDUCED_STATES, CTOLReduced

__all__ = ["ClosedLoopCTOL", "ClosedLoopCTOLAlpha", "steady_glide_inputs"]


def steady_glide_inputs(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, theta: Any,
                        Omega2: Any) -> Any:
    """Inputs ``(u1, u2)`` of the steady-glide law (7.16)-(7.20) at pitch ``theta`` and pitch rate ``Omega2``.

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``epsilon > 0``: the law divides by it).
    glide : CTOLGlide
        The steady glide (gains ``k1``, ``k2`` in N and ``theta_e`` in rad).
    k3 : float
        Pitch stiffness gain (N; enters as ``k3 / eps``).
    k4 : float
        Pitch damping gain on ``Omega2bar = T Omega2`` (N m s).
    T : float
        Reference time of (7.11) (s).
    theta, Omega2 : array_like
        Pitch angle (rad) and pitch rate (rad/s), broadcasting together (may be complex: complex-step Jacobians).

    Returns
    -------
    ndarray, shape (..., 2)
        Thrust ``u1`` (N) and elevator moment ``u2`` (N m).
    """
    eps = veh.epsilon
    k1, k2 = glide.k1, glide.k2
    u1 = -k1 * np.sin(theta) - k2 * np.cos(theta)
    u2 = (k1 * np.cos(theta) - k2 * np.sin(theta)) / eps - (k3 / eps) * np.sin(theta - glide.theta) - k4 * T * Omega2
    return np.stack(np.broadcast_arrays(u1, u2), -1)


@dataclass(frozen=True)
class ClosedLoopCTOL:
    """Input-free closed loop (7.12)-(7.20) in the reduced states ``(Vbar, gammabar, thetabar, Omega2bar)``; the
    equilibrium is the origin (the interconnected system (7.28)-(7.39)).

    Parameters
    ----------
    vehicle : Vehicle
        A ``kind = "ctol"`` vehicle with ``epsilon > 0`` (the law divides by it).
    glide : CTOLGlide
        The steady glide flown (:func:`glidectl.trim.ctol.ctol_glide`): ``V_e`` (m/s), ``gamma_e``, ``theta_e``
        (rad) and the gains ``k1, k2`` (N).
    k3 : float
        Pitch stiffness gain of (7.20) (N; enters as ``k3 / eps``).
    k4 : float
        Pitch damping gain of (7.20) on the nondimensional rate ``Omega2bar = T Omega2`` (N m, since ``u2`` is a
        moment).
    T : float
        Reference time of (7.11) (s); default 1.
    state_names : tuple of str
        Names of the 4 nondimensional states; default ``("Vbar", "gammabar", "thetabar", "Omega2bar")``.
    input_names : tuple of str
        Empty: the loop is closed.

    Notes
    -----
    Nothing is validated on construction; :meth:`rhs` builds :class:`~glidectl.models.ctol.CTOLReduced` and so
    raises :class:`ModelError` for a non-CTOL vehicle or a non-positive ``glide.speed`` or ``T``.
    """

    vehicle: Vehicle
    glide: CTOLGlide
    k3: float
    k4: float
    T: float = 1.0
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = ()

    @property
    def reduced(self) -> CTOLReduced:
        return CTOLReduced(self.vehicle, self.glide.speed, self.glide.gamma, self.glide.theta, self.T)

    def rhs(self, s: Any, u: Any = None) -> Any:
        s = np.asarray(s)
        th = s[..., 2] + self.glide.theta
        uu = steady_glide_inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, th, s[..., 3] / self.T)
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
