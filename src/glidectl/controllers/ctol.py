"""Steady-glide controller of the CTOL aircraft, (7.16)-(7.20), for the full model, and the eigenvalues of its closed
loop.

    u1 = w11 = -k1 sin theta - k2 cos theta                                   (7.16), (7.18)
    u2 = w21 + w22,  w21 = (k1 cos theta - k2 sin theta) / eps                (7.17), (7.19)
                     w22 = -(k3 / eps) sin(theta - theta_e) - k4 T Omega2     (7.20)

``T Omega2`` is the nondimensional pitch rate ``Omega2bar`` of (7.11). ``k1, k2`` place the equilibrium (Theorem 4,
:func:`glidectl.trim.ctol.ctol_glide`); ``k3, k4 > 0`` stabilize the pitch. The law itself and the closed loop in the
reduced states are models: :func:`glidectl.models.ctol_closed_loop.steady_glide_inputs` and
:class:`glidectl.models.ctol_closed_loop.ClosedLoopCTOL`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SolverError
from ..models._validate import single_real_state, trailing_array
from ..models.ctol_closed_loop import ClosedLoopCTOL, check_steady_glide_law, steady_glide_inputs
from ..params import Vehicle
from ..trim.ctol import CTOLGlide

__all__ = ["SteadyGlideController", "closed_loop_eigenvalues"]


@dataclass(frozen=True)
class SteadyGlideController:
    """(7.16)-(7.20) for the full CTOL model: ``controller(t, x) -> (u1, u2)`` with ``x = (x, y, xdot, ydot, theta,
    Omega2)``.

    Parameters
    ----------
    vehicle : Vehicle
        A CTOL aircraft with ``epsilon > 0``.
    glide : CTOLGlide
        The steady glide to stabilize (gains ``k1, k2`` and ``theta_e``), from :func:`glidectl.ctol_glide` for
        ``vehicle``.
    k3 : float
        Pitch stiffness gain (N; enters as ``k3 / eps``), > 0.
    k4 : float
        Pitch damping gain on ``Omega2bar = T Omega2`` (N m s), > 0.
    T : float
        Reference time of (7.11) (s), > 0.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``glide`` not a CTOLGlide, or a gain not a real number.
    ArgumentError
        If ``k3``, ``k4`` or ``T`` is not a positive finite number.
    ModelError
        If ``vehicle`` is not a CTOL aircraft or has ``epsilon = 0`` (the law divides by eps).
    VehicleMismatchError
        If ``glide`` was computed for another vehicle.
    """

    vehicle: Vehicle
    glide: CTOLGlide
    k3: float
    k4: float
    T: float = 1.0

    def __post_init__(self) -> None:
        k3, k4, T = check_steady_glide_law(self.vehicle, self.glide, self.k3, self.k4, self.T)
        object.__setattr__(self, "k3", k3)
        object.__setattr__(self, "k4", k4)
        object.__setattr__(self, "T", T)

    def u(self, x: Any) -> np.ndarray:
        """Inputs ``(u1, u2)`` (N, N m), shape ``(..., 2)``, at full states ``x = (x, y, xdot, ydot, theta,
        Omega2)`` (shape ``(..., 6)``)."""
        x = trailing_array("x", x, 6)
        th, Om = x[4:].tolist() if single_real_state(x) else (x[..., 4], x[..., 5])  # Python floats for one state
        return steady_glide_inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, th, Om)

    def reduced_input(self, s: Any) -> np.ndarray:
        """Inputs ``(u1, u2)`` (N, N m) at reduced states ``s = (Vbar, gammabar, thetabar, Omega2bar)`` of
        (7.8)-(7.11) about :attr:`glide` (``theta = thetabar + theta_e``, ``Omega2 = Omega2bar / T``): the law of
        :class:`~glidectl.models.ctol_closed_loop.ClosedLoopCTOL` (``s`` of shape ``(..., 4)``)."""
        s = trailing_array("s", s, 4)
        tb, Ob = (s[2], s[3]) if single_real_state(s) else (s[..., 2], s[..., 3])
        return steady_glide_inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, tb + self.glide.theta,
                                   Ob / self.T)

    def __call__(self, t: float, x: Any) -> np.ndarray:
        return self.u(x)


def closed_loop_eigenvalues(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float = 1.0) -> np.ndarray:
    """Eigenvalues (1/s) of the closed loop linearized at the steady glide, sorted by real part.

    The Jacobian is the exact (complex-step) one of :class:`~glidectl.models.ctol_closed_loop.ClosedLoopCTOL` at the
    origin of the reduced states ``(Vbar, gammabar, thetabar, Omega2bar)``.

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle with ``epsilon > 0``.
    glide : CTOLGlide
        The steady glide (:func:`glidectl.trim.ctol.ctol_glide` for ``veh``): ``V_e`` (m/s), ``theta_e`` (rad),
        ``k1, k2`` (N).
    k3 : float
        Pitch stiffness gain of (7.20) (N; enters as ``k3 / eps``), ``> 0``.
    k4 : float
        Pitch damping gain of (7.20) on ``Omega2bar = T Omega2`` (N m), ``> 0``.
    T : float
        Reference time of (7.11) (s), ``> 0``.

    Returns
    -------
    numpy.ndarray, shape (4,)
        Complex eigenvalues (1/s), sorted by real part, then imaginary part.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a CTOLGlide, or a gain not a real number.
    ArgumentError
        If ``k3``, ``k4`` or ``T`` is not a positive finite number.
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0`` (the law divides by eps).
    VehicleMismatchError
        If ``glide`` was computed for another vehicle.
    SolverError
        If the Jacobian is not finite or the eigenvalue computation fails.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> glide = gc.ctol_glide(veh, 0.155, 0.0)              # level flight
    >>> ev = gc.ctol_closed_loop_eigenvalues(veh, glide, k3=10.0, k4=5.0)
    >>> print(np.round(ev.real, 2))
    [-24.82  -4.02  -2.5   -2.5 ]
    """
    J = ClosedLoopCTOL(veh, glide, k3, k4, T).jacobian()
    try:
        lam = np.linalg.eigvals(J)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of the CTOL closed loop did not converge: {exc}") from exc
    return lam[np.lexsort((lam.imag, lam.real))]

