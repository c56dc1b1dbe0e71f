"""Theorem 4 over a grid of steady glides of the CTOL aircraft: where the closed loop (7.16)-(7.20) has a steady
glide, the angle of attack and thrust it needs, and the stability of each glide for given pitch gains."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, InfeasibleGlideError
from ..models._validate import require_ctol_vehicle
from ..params import Vehicle
from ..trim.ctol import ctol_glide
from .ctol import closed_loop_eigenvalues

__all__ = ["MAX_MAP_POINTS", "CTOLGlideMap", "ctol_glide_map"]

#: largest number of (speed, gamma) grid points of one map
MAX_MAP_POINTS = 250_000


@dataclass(frozen=True)
class CTOLGlideMap:
    """Steady glides of the CTOL closed loop over a ``(speed, gamma)`` grid (Theorem 4).

    Attributes
    ----------
    speed : ndarray, shape (n,)
        Glide speeds ``V_e`` (m/s; normalized units for ``dc8_ctol``).
    gamma : ndarray, shape (m,)
        Flight-path angles ``gamma_e`` (rad).
    alpha : ndarray, shape (n, m)
        Angle of attack of the glide (rad; the root of (7.25) of smallest ``|alpha|``), NaN where there is none with
        ``|alpha_e| <= ALPHA_MAX``.
    thrust : ndarray, shape (n, m)
        Equilibrium thrust ``u1 = -k1 sin theta_e - k2 cos theta_e`` (N), NaN where there is no glide.
    max_residual : float
        Largest residual of (7.21)-(7.23) over the glides found (N).
    max_real_eig : Mapping[tuple[float, float], float]
        For each pitch-gain pair ``(k3, k4)``, the largest real part of the closed-loop eigenvalues over every glide
        found (1/s; ``-inf`` when none was found).
    vehicle : Vehicle
    provenance : str
        The vehicle's provenance.
    """

    speed: np.ndarray = field(repr=False)
    gamma: np.ndarray = field(repr=False)
    alpha: np.ndarray = field(repr=False)
    thrust: np.ndarray = field(repr=False)
    max_residual: float
    max_real_eig: Mapping[tuple[float, float], float]
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    @property
    def feasible(self) -> np.ndarray:
        """Grid points with a steady glide (bool, shape (n, m))."""
        return ~np.isnan(self.alpha)

    @property
    def negative_thrust_fraction(self) -> float:
        """Fraction of the glides found that need negative thrust (a brake); 0 when none was found."""
        n = int(np.sum(self.feasible))
        return int(np.sum(self.thrust < 0)) / max(n, 1)

    def summary(self) -> str:
        """A few lines of text: grid, glides found, thrust sign, stability per gain pair."""
        lines = [f"Theorem 4 map: {self.speed.size} speeds x {self.gamma.size} flight-path angles, "
                 f"{int(np.sum(self.feasible))} steady glides (max residual {self.max_residual:.3g} N), "
                 f"{100 * self.negative_thrust_fraction:.1f}% of them with negative thrust"]
        lines += [f"  k3 = {k3:g}, k4 = {k4:g}: largest real part of the closed-loop eigenvalues {v:.4g} 1/s"
                  for (k3, k4), v in self.max_real_eig.items()]
        return "\n".join(lines)


def ctol_glide_map(veh: Vehicle, speeds: Sequence[float], gammas: Sequence[float],
                   gains: Sequence[tuple[float, float]] = ()) -> CTOLGlideMap:
    """Theorem 4 at every ``(speed, gamma)`` of a grid: the steady glide (:func:`glidectl.trim.ctol.ctol_glide`),
    its thrust, and for each pitch-gain pair the largest real part of the closed-loop eigenvalues (7.12)-(7.20)
    (:func:`glidectl.controllers.ctol.closed_loop_eigenvalues`).

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle.
    speeds : sequence of float
        Glide speeds (m/s; normalized units for ``dc8_ctol``), finite and ``> 0``.
    gammas : sequence of float
        Flight-path angles (rad), finite, in ``[-pi, pi]``.
    gains : sequence of (float, float)
        Pitch-gain pairs ``(k3, k4)`` (N, N m), each ``> 0``, whose closed loops are checked over the map.

    Returns
    -------
    CTOLGlideMap
        Points without a steady glide (:class:`~glidectl.errors.InfeasibleGlideError`) are NaN.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a CTOL Vehicle or a grid or gain is not real numbers.
    ArgumentError
        If a grid is empty, not one-dimensional or not finite, a speed is not positive, a ``gamma`` is outside
        ``[-pi, pi]``, or a gain pair is not two positive finite numbers.
    BudgetError
        If the grid has more than :data:`MAX_MAP_POINTS` points.
    ModelError, SolverError
        As :func:`glidectl.trim.ctol.ctol_glide` and :func:`glidectl.controllers.ctol.closed_loop_eigenvalues`.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> m = gc.ctol_glide_map(veh, speeds=[0.15, 0.2], gammas=[-0.1, 0.0, 0.1], gains=[(10.0, 5.0)])
    >>> m.thrust.shape, bool(m.feasible.all())
    ((2, 3), True)
    >>> print(f"{m.max_real_eig[(10.0, 5.0)]:.3f}")          # stable over the whole map
    -2.241
    """
    veh = require_ctol_vehicle(veh, "veh")
    V = checks.array("speeds", speeds, ndim=1, min_size=1)
    G = checks.array("gammas", gammas, ndim=1, min_size=1)
    if np.any(V <= 0):
        raise ArgumentError(f"speeds must be > 0 m/s, got {float(V.min())!r}")
    if np.any(np.abs(G) > math.pi):
        raise ArgumentError(f"gammas must be in [-pi, pi] rad, got {float(G[np.argmax(np.abs(G))])!r}")
    if V.size * G.size > MAX_MAP_POINTS:
        raise BudgetError(f"the map has {V.size * G.size} points, more than MAX_MAP_POINTS = {MAX_MAP_POINTS}: use "
                          "coarser grids")
    if isinstance(gains, str | bytes) or not isinstance(gains, Sequence):
        raise ArgumentTypeError(f"gains must be a sequence of (k3, k4) pairs, got {type(gains).__name__}")
    pairs: list[tuple[float, float]] = []
    for g in gains:
        if not isinstance(g, Sequence) or len(g) != 2:
            raise ArgumentError(f"each gain must be a pair (k3, k4), got {g!r}")
        pairs.append((checks.real("k3", g[0], lo=0.0, lo_open=True), checks.real("k4", g[1], lo=0.0, lo_open=True)))
    A = np.full((V.size, G.size), np.nan)
    Th = A.copy()
    res = 0.0
    max_re: dict[tuple[float, float], float] = {p: -math.inf for p in pairs}
    for i, v in enumerate(V):
        for j, g in enumerate(G):
            try:
                gl = ctol_glide(veh, float(v), float(g))
            except InfeasibleGlideError:
                continue
            A[i, j], Th[i, j] = gl.alpha, gl.thrust
            res = max(res, gl.residual)
            for k3, k4 in pairs:
                max_re[(k3, k4)] = max(max_re[(k3, k4)],
                                       float(np.max(closed_loop_eigenvalues(veh, gl, k3, k4).real)))
    for arr in (V, G, A, Th):
        arr.setflags(write=False)
    return CTOLGlideMap(V, G, A, Th, float(res), max_re, veh, veh.provenance)
