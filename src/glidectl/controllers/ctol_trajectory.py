"""Desired CTOL trajectory of §7.3.3 (Fig 7.2): constant horizontal speed ``x_d = 0.85 t / sqrt(a_L)`` and the smooth
climb ``y_d`` solving (7.91),

    y^(5) + 3.5 y^(4) + 4.9 y^(3) + 3.4 y'' + 1.2 y' + 0.17 y - 1.7 = 0,   y^(k)(0) = 0, k = 0..4,

so ``y_d`` rises from 0 to 1.7 / 0.17 = 10. The ODE is linear with constant coefficients; ``y_d`` and its first
four derivatives are the state of the companion system, evaluated exactly with the matrix exponential (no
integration error); the fifth derivative follows from (7.91). Before ``t = 0`` the trajectory is the level line
``y_d = 0`` at the same speed (as needed by non-causal inversion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.linalg import expm

from .. import checks
from ..errors import ArgumentError, ModelError
from ..models._validate import speed_arg
from ..models.ctol import require_ctol
from ..params import Vehicle

__all__ = ["CLIMB_COEFFS", "ClimbTrajectory", "climb_trajectory"]

CLIMB_COEFFS = (1.0, 3.5, 4.9, 3.4, 1.2, 0.17)  # s^5 ... s^0 of (7.91)
CLIMB_FORCING = 1.7


@dataclass(frozen=True)
class ClimbTrajectory:
    """``(x_d(t), y_d(t))`` of §7.3.3 with derivatives; ``speed`` is the horizontal speed (m/s).

    Evaluation is vectorized over time in the modal form of the companion system,
    ``y_state(t) = W diag((exp(lambda t) - 1) / lambda) W^-1 b f`` (exact; the five poles of (7.91) are distinct),
    checked at construction against the augmented matrix exponential.

    Parameters
    ----------
    speed : float
        Horizontal speed ``x_d'`` (m/s; normalized units of §7.1 for ``dc8_ctol``), in ``(0, 100]``.
    coeffs : tuple of float
        The 6 coefficients of ``s^5 ... s^0`` of (7.91) (the coefficient of ``s^k`` in 1/s^(5-k) relative to the
        leading one); default :data:`CLIMB_COEFFS`. Finite, leading coefficient nonzero, roots distinct, nonzero
        and stable (negative real parts: the climb settles).
    forcing : float
        Constant right-hand side of (7.91) (m/s^5 times the leading coefficient), finite; default 1.7, so the final
        altitude is ``forcing / coeffs[-1] = 10`` m.

    Raises
    ------
    ArgumentTypeError
        If ``speed``, ``forcing`` or ``coeffs`` is not real numbers.
    ArgumentError
        If ``speed`` is not in ``(0, 100]``, ``coeffs`` is not 6 finite numbers with a nonzero leading one, or
        ``forcing`` is not finite.
    ModelError
        If the polynomial has a zero, repeated or unstable root (the climb would not settle), or the modal
        evaluation disagrees with the matrix exponential.
    """

    speed: float
    coeffs: tuple[float, ...] = CLIMB_COEFFS
    forcing: float = CLIMB_FORCING
    _modal: tuple[np.ndarray, np.ndarray, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "speed", speed_arg("speed", self.speed))
        c = checks.array("coeffs", self.coeffs, shape=(6,))
        if c[0] == 0:
            raise ArgumentError(f"coeffs must be the 6 coefficients s^5..s^0, leading one nonzero, got {self.coeffs}")
        object.__setattr__(self, "coeffs", tuple(float(v) for v in c))
        object.__setattr__(self, "forcing", checks.real("forcing", self.forcing))
        lam, W = np.linalg.eig(self._companion())
        if np.min(np.abs(lam)) == 0 or np.linalg.cond(W) > 1e8:
            raise ModelError(f"the climb polynomial {self.coeffs} has a zero or repeated root; no modal form")
        if np.max(lam.real) >= 0:
            raise ModelError(f"the climb polynomial {self.coeffs} has roots {np.round(lam, 6)} with real part >= 0: "
                             "the climb would not settle (the desired trajectory must be bounded)")
        b = np.zeros(5, dtype=complex)
        b[4] = self.forcing / self.coeffs[0]
        object.__setattr__(self, "_modal", (lam, W, np.linalg.solve(W, b)))
        for ti in (0.3, 2.0, 7.5, 21.0):
            if not np.allclose(self.derivatives(ti, 4)[:, 1], self._ystate_expm(ti), rtol=1e-9, atol=1e-11):
                raise ModelError("modal evaluation of the climb disagrees with the matrix exponential")

    def _companion(self) -> np.ndarray:
        c = np.asarray(self.coeffs, float) / self.coeffs[0]
        A = np.zeros((5, 5))
        A[:4, 1:] = np.eye(4)
        A[4] = -c[:0:-1]  # y^(5) = f - (c5 y + c4 y' + ... + c1 y^(4))
        return A

    @property
    def final_altitude(self) -> float:
        return self.forcing / self.coeffs[-1]

    @property
    def poles(self) -> np.ndarray:
        """Roots of the characteristic polynomial of (7.91) (1/s)."""
        return np.sort_complex(np.roots(self.coeffs))

    def _ystate_expm(self, t: float) -> np.ndarray:
        """``(y, y', ..., y^(4))`` at one time by the augmented matrix exponential (reference evaluation)."""
        if t <= 0:
            return np.zeros(5)
        M = np.zeros((6, 6))
        M[:5, :5] = self._companion()
        M[4, 5] = self.forcing / self.coeffs[0]
        return expm(M * t)[:5, 5]

    def derivatives(self, t: Any, order: int = 2) -> np.ndarray:
        """``[[x_d, y_d], [x_d', y_d'], ...]`` up to ``order`` (<= 5) at each time: shape ``(..., order + 1, 2)``
        (m, m/s, ..., m/s^5). Before ``t = 0`` the trajectory is level flight at ``y = 0``.

        Raises
        ------
        ArgumentTypeError
            If ``t`` is not real numbers or ``order`` not an integer.
        ArgumentError
            If ``t`` is not finite or ``order`` is not in 0..5.
        """
        order = checks.integer("order", order, lo=0, hi=5)
        tt = checks.array("t", t)
        ts = np.atleast_1d(tt).ravel()
        lam, W, beta = self._modal
        E = np.expm1(np.outer(np.maximum(ts, 0.0), lam)) / lam
        ys = np.real((E * beta) @ W.T)  # (N, 5): y, y', ..., y^(4)
        c = np.asarray(self.coeffs, float) / self.coeffs[0]
        y5 = self.forcing / self.coeffs[0] - ys @ c[:0:-1]
        ys[ts <= 0] = 0.0
        y5[ts <= 0] = 0.0
        out = np.zeros((ts.size, order + 1, 2))
        out[:, :, 1] = np.column_stack([ys, y5])[:, : order + 1]
        out[:, 0, 0] = self.speed * ts
        if order >= 1:
            out[:, 1, 0] = self.speed
        return out.reshape((*tt.shape, order + 1, 2))

    def position(self, t: Any) -> np.ndarray:
        """``(x_d, y_d)`` (m), shape ``(..., 2)``."""
        return self.derivatives(t, 0)[..., 0, :]


def climb_trajectory(veh: Vehicle, mach_like: float = 0.85) -> ClimbTrajectory:
    """The §7.3.3 trajectory for ``veh``: horizontal speed ``0.85 / sqrt(a_L)`` (normalized units).

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle (its lift coefficient ``a_L``, nondimensional, sets the speed).
    mach_like : float
        The factor ``0.85`` of ``x_d = 0.85 t / sqrt(a_L)`` (nondimensional), ``> 0`` (the speed must stay within
        ``(0, 100]``).

    Returns
    -------
    ClimbTrajectory
        Horizontal speed ``mach_like / sqrt(a_L)`` (m/s, normalized units) and the climb of (7.91) from 0 to 10 m.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``mach_like`` not a real number.
    ArgumentError
        If ``mach_like`` is not a positive finite number, or the speed it gives exceeds 100.
    ModelError
        If ``veh`` is not a CTOL aircraft.

    Examples
    --------
    >>> import glidectl as gc
    >>> traj = gc.climb_trajectory(gc.load_vehicle("dc8_ctol"))
    >>> print(f"{traj.speed:.4f}")                          # 0.85 / sqrt(a_L), a_L = 30 (normalized units)
    0.1552
    >>> print(f"{traj.derivatives(60.0, 0)[0, 1]:.3f}")      # altitude (m) once the climb has settled
    10.000
    """
    require_ctol(veh)
    mach_like = checks.positive("mach_like", mach_like)
    return ClimbTrajectory(mach_like / math.sqrt(veh.a_L))
