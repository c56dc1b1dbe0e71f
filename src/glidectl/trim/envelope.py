"""Glide envelope: the steady straight glides a vehicle can fly within its actuator ranges, on a grid of speeds and
flight-path angles, computed at once (vectorized over the grid).

Every point is the steady glide of :func:`~glidectl.trim.glide.steady_glide` (the closed-form trim (2.26)-(2.29)
reconstructed, with its residual check on (2.17)-(2.25)); both call the one solver
:func:`~glidectl.trim.glide.glide_trim_arrays`. A point is *feasible* when that glide exists and its net buoyancy
``m0`` and moving-mass position ``r_P1`` lie within the ranges of the vehicle's ``[actuators]`` table (an axis the
table does not list is not limited), at the vertical moving-mass offset ``r_P3`` fixed by the file. So
``env.feasible[i, j]`` is exactly "``steady_glide(veh, speeds[i], gammas[j], r_p3=env.r_p3)`` returns a glide".

Binding codes (:data:`BINDING_LABELS`, ``env.binding``; :attr:`GlideEnvelope.binding_labels` gives the strings)::

    0  "none"       feasible: the glide exists within every actuator range
    1  "no glide"   aerodynamically impossible: gamma outside the permissible set (2.26), or |gamma| >= 90 deg
    2  "m0 min"     the glide needs m0 below the pump's min
    3  "m0 max"     the glide needs m0 above the pump's max
    4  "r_P1 min"   the glide needs r_P1 below the moving mass's min
    5  "r_P1 max"   the glide needs r_P1 above the moving mass's max
    6  "no trim"    the moment balance has no plausible mass position at this r_P3 (|r_P| > R_P_MAX = 10 m, or
                    theta = +-90 deg), or the trim failed its residual check

When both ``m0`` and ``r_P1`` are out of range the code names the one farther out, measured as a fraction of the
actuator's range width (width 1 of its unit for a one-sided or fixed range).

Plausibility limits: speeds in ``(0, 100]`` m/s (:data:`~glidectl.trim.glide.SPEED_MAX`), finite gammas, at most
:data:`MAX_POINTS` grid points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, InfeasibleGlideError, ModelError
from ..models.glider3d import R_P_MAX
from ..models.longitudinal import LongitudinalGlider
from ..params import Vehicle
from .glide import (
    NO_GLIDE,
    OK,
    SPEED_MAX,
    UNDERFLOW,
    glide_trim_arrays,
    permissible_gamma,
)

__all__ = ["BINDING_LABELS", "MAX_POINTS", "GlideEnvelope", "glide_envelope"]

#: Labels of the binding codes of :attr:`GlideEnvelope.binding` (index = code); see the module docstring.
BINDING_LABELS: tuple[str, ...] = ("none", "no glide", "m0 min", "m0 max", "r_P1 min", "r_P1 max", "no trim")
NONE, NO_GLIDE_CODE, M0_MIN, M0_MAX, R_P1_MIN, R_P1_MAX, NO_TRIM = range(7)
#: Largest grid (speeds x gammas) accepted: a plausibility / memory limit.
MAX_POINTS = 4_000_000


@dataclass(frozen=True)
class GlideEnvelope:
    """Steady glides on a ``(speed, gamma)`` grid, with where the actuator ranges allow them.

    Arrays have shape ``(len(speeds), len(gammas))``; row ``i`` is ``speeds[i]``, column ``j`` is ``gammas[j]``.

    Attributes
    ----------
    speeds : ndarray, shape (N,)
        Glide speeds V_e (m/s).
    gammas : ndarray, shape (M,)
        Flight-path angles (rad, positive climbing).
    r_p3 : float
        Vertical moving-mass position used at every point (m).
    feasible : ndarray of bool, shape (N, M)
        The steady glide exists and ``m0``, ``r_P1`` are within the actuator ranges.
    binding : ndarray of int8, shape (N, M)
        Which limit binds: an index into :data:`BINDING_LABELS` (0 ``"none"`` where feasible).
    m0 : ndarray, shape (N, M)
        Net buoyancy of the glide (kg; > 0 heavy, down glides); NaN where no glide exists (codes 1 and 6).
    r_p1 : ndarray, shape (N, M)
        Moving-mass position along the hull (m) of the glide (moment balance (2.29)); NaN where no glide exists.
    alpha, theta : ndarray, shape (N, M)
        Angle of attack and pitch (rad), ``theta = gamma + alpha``; NaN where no glide exists.
    horizontal_speed : ndarray, shape (N, M)
        ``V cos(gamma)`` (m/s); NaN where no glide exists.
    vertical_speed : ndarray, shape (N, M)
        Sink rate ``-V sin(gamma)`` (m/s, positive downwards, as :attr:`Helix.vertical_speed`); NaN where no glide
        exists.
    m0_bounds, r_p1_bounds : (float, float)
        The ranges applied (``veh.actuator_bounds``; ``(-inf, inf)`` for an axis the file does not list).
    gamma_bounds : (float, float)
        ``(lo, hi)`` of the permissible set (2.26) (:func:`~glidectl.trim.glide.permissible_gamma`, rad).
    vehicle : Vehicle
        The vehicle.
    provenance : str
        Its parameter hash.
    """

    speeds: np.ndarray
    gammas: np.ndarray
    r_p3: float
    feasible: np.ndarray
    binding: np.ndarray
    m0: np.ndarray
    r_p1: np.ndarray
    alpha: np.ndarray
    theta: np.ndarray
    horizontal_speed: np.ndarray
    vertical_speed: np.ndarray
    m0_bounds: tuple[float, float]
    r_p1_bounds: tuple[float, float]
    gamma_bounds: tuple[float, float]
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    @property
    def binding_labels(self) -> np.ndarray:
        """:attr:`binding` as strings (:data:`BINDING_LABELS`), shape (N, M)."""
        return np.asarray(BINDING_LABELS, dtype=object)[self.binding]

    @property
    def exists(self) -> np.ndarray:
        """Where the steady glide exists, whatever the actuator ranges (bool, shape (N, M))."""
        return (self.binding != NO_GLIDE_CODE) & (self.binding != NO_TRIM)

    def counts(self) -> dict[str, int]:
        """Number of grid points per binding label.

        Returns
        -------
        dict of str to int
            ``{label: count}`` over :data:`BINDING_LABELS`.
        """
        n = np.bincount(self.binding.ravel(), minlength=len(BINDING_LABELS))
        return {lab: int(n[k]) for k, lab in enumerate(BINDING_LABELS)}

    def summary(self) -> str:
        """A few lines: grid, ranges applied, and the points per binding limit.

        Returns
        -------
        str
        """
        c = self.counts()
        n = self.feasible.size
        lines = [f"glide envelope of '{self.vehicle.name}': {self.speeds.size} speeds x {self.gammas.size} gammas at "
                 f"r_P3 = {self.r_p3:g} m; m0 in [{self.m0_bounds[0]:g}, {self.m0_bounds[1]:g}] kg, r_P1 in "
                 f"[{self.r_p1_bounds[0]:g}, {self.r_p1_bounds[1]:g}] m",
                 f"feasible: {c['none']} of {n} points",
                 "binding: " + ", ".join(f"{k} {v}" for k, v in c.items() if k != "none" and v)]
        return "\n".join(lines)

    def plot(self, ax: Any = None) -> Any:
        """Draw the envelope in the glide polar (horizontal speed against sink rate), coloured by binding limit.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn into (see :func:`glidectl.plotting.plot_glide_envelope`; ``ax.figure`` is the figure).
        """
        from ..plotting import plot_glide_envelope, style

        with style():
            return plot_glide_envelope(self, ax)


def _default_r_p3(veh: Vehicle) -> float:
    act = veh.actuators.get("r_P3")
    if act is not None and act.fixed is not None:
        return float(act.fixed)
    if "r_P3" in veh.params:
        return float(veh.params["r_P3"])
    raise ArgumentError(f"vehicle '{veh.name}' fixes no r_P3 (neither [parameters] r_P3 nor a fixed [actuators] "
                        "r_P3); pass r_p3= (m), the vertical moving-mass position to trim at")


def _excess(value: np.ndarray, bounds: tuple[float, float], inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Violation below / above ``bounds`` as a fraction of the range width (0 where ``inside``)."""
    lo, hi = bounds
    width = hi - lo if math.isfinite(hi - lo) and hi > lo else 1.0
    with np.errstate(invalid="ignore"):
        below = np.where(~inside & (value < lo), (lo - value) / width, 0.0)
        above = np.where(~inside & (value > hi), (value - hi) / width, 0.0)
    return np.nan_to_num(below), np.nan_to_num(above)


def glide_envelope(veh: Vehicle, speeds: Any, gammas: Any, *, r_p3: float | None = None) -> GlideEnvelope:
    """Steady glides on the grid ``speeds x gammas`` and where the vehicle's actuator ranges allow them.

    Vectorized over the grid: one call of the trim solver shared with :func:`~glidectl.trim.glide.steady_glide`
    (closed-form (2.26)-(2.29), residuals of (2.17)-(2.25) checked to 1e-9 relative), then the ``[actuators]``
    ranges of ``m0`` and ``r_P1``. See the module docstring for the binding codes.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with a moving mass (``mbar > 0``) and ``K_D > 0``.
    speeds : array_like, shape (N,)
        Glide speeds V_e (m/s), each in ``(0, 100]``, N >= 1.
    gammas : array_like, shape (M,)
        Flight-path angles (rad, negative gliding down), finite, M >= 1; angles outside the permissible set (2.26)
        get binding code 1 (``"no glide"``).
    r_p3 : float, optional
        Vertical moving-mass position (m), ``|r_p3| <= R_P_MAX`` (10 m). Default the file's: the fixed
        ``[actuators] r_P3``, else ``[parameters] r_P3``. It must lie in the ``r_P3`` actuator range when the file
        lists one.

    Returns
    -------
    GlideEnvelope
        Arrays of shape ``(N, M)``: ``feasible``, ``binding``, ``m0``, ``r_p1``, ``alpha``, ``theta``,
        ``horizontal_speed``, ``vertical_speed``.

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle; ``speeds`` / ``gammas`` are not arrays of real numbers; ``r_p3`` is not a real
        number.
    ArgumentError
        ``speeds`` or ``gammas`` not 1-D, empty, or holding NaN / inf; a speed outside ``(0, 100]`` m/s or so small
        that the forces underflow; more than :data:`MAX_POINTS` grid points; ``|r_p3| > 10`` m; no ``r_p3`` given
        and the file fixes none.
    ModelError
        ``veh`` is not an underwater glider (e.g. the CTOL aircraft) or has no moving mass (``mbar = 0``).
    InfeasibleGlideError
        ``K_D = 0`` (no permissible set), or ``r_p3`` outside the vehicle's ``r_P3`` actuator range.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("slocum_shallow")  # its [actuators] table limits m0 and r_P1
    >>> env = gc.glide_envelope(veh, [0.2, 0.5], np.radians([-45.0, -25.0, -10.0]))
    >>> print(env.binding_labels)  # rows: speeds, columns: flight-path angles
    [['r_P1 max' 'none' 'none']
     ['r_P1 max' 'none' 'm0 max']]
    >>> int(env.feasible.sum())
    3
    """
    checks.vehicle("veh", veh)
    if veh.kind != "underwater_glider":
        raise ModelError(f"vehicle '{veh.name}' is a {veh.kind}; glide envelopes here are for underwater gliders "
                         "(use ctol_glide for the CTOL aircraft's steady glides)")
    LongitudinalGlider(veh)  # ModelError: mbar = 0
    V = checks.array("speeds (glide speeds, m/s)", speeds, ndim=1, min_size=1)
    G = checks.array("gammas (flight-path angles, rad)", gammas, ndim=1, min_size=1)
    if not (np.all(V > 0) and np.all(V <= SPEED_MAX)):
        bad = V[~((V > 0) & (V <= SPEED_MAX))][0]
        raise ArgumentError(f"speeds must lie in (0, {SPEED_MAX:g}] m/s, got {bad!r}")
    if V.size * G.size > MAX_POINTS:
        raise ArgumentError(f"the grid has {V.size} x {G.size} = {V.size * G.size} points; at most {MAX_POINTS} are "
                            "accepted (split it)")
    if r_p3 is None:
        r3 = _default_r_p3(veh)
    else:
        r3 = checks.real("r_p3 (vertical moving-mass position)", r_p3, lo=-R_P_MAX, hi=R_P_MAX, unit="m")
    act3 = veh.actuators.get("r_P3")
    if act3 is not None and not act3.contains(r3):
        raise InfeasibleGlideError(f"r_p3 = {r3:g} m is outside the range of actuator 'r_P3' of vehicle "
                                   f"'{veh.name}' ({act3.describe()}); leave r_p3 at its default or choose one "
                                   "in range")
    # InfeasibleGlideError when K_D = 0; the seaglider law's set widens with speed: the widest (fastest) is drawn
    gamma_bounds = permissible_gamma(veh, float(V.max()) if veh.law == "seaglider" else None)
    tr = glide_trim_arrays(veh, V[:, None], G[None, :], r_p3=r3)
    if np.any(tr.status == UNDERFLOW):
        i = int(np.argmax(np.any(tr.status == UNDERFLOW, axis=1)))
        raise ArgumentError(f"speed = {V[i]:g} m/s is so small that the hydrodynamic forces and the net buoyancy "
                            "underflow; ask for speeds of at least 1e-150 m/s")
    exists = tr.status == OK
    nan = np.where(exists, 1.0, np.nan)
    m0, rp1 = tr.m0 * nan, tr.r_p1 * nan
    m0_b = veh.actuator_bounds("m0")
    rp1_b = veh.actuator_bounds("r_P1")
    in_m0 = veh.actuators["m0"].contains(m0) if "m0" in veh.actuators else np.ones(m0.shape, bool)
    in_rp1 = veh.actuators["r_P1"].contains(rp1) if "r_P1" in veh.actuators else np.ones(m0.shape, bool)
    feasible = exists & in_m0 & in_rp1
    ex = np.stack([*_excess(m0, m0_b, in_m0 | ~exists), *_excess(rp1, rp1_b, in_rp1 | ~exists)])
    binding = np.where(feasible, NONE, M0_MIN + np.argmax(ex, axis=0)).astype(np.int8)
    binding[tr.status == NO_GLIDE] = NO_GLIDE_CODE
    binding[~exists & (tr.status != NO_GLIDE)] = NO_TRIM
    gam = np.broadcast_to(G[None, :], m0.shape)
    Vg = np.broadcast_to(V[:, None], m0.shape)
    out = GlideEnvelope(
        speeds=V.copy(), gammas=G.copy(), r_p3=float(r3), feasible=feasible, binding=binding, m0=m0, r_p1=rp1,
        alpha=tr.alpha * nan, theta=tr.theta * nan, horizontal_speed=Vg * np.cos(gam) * nan,
        vertical_speed=-Vg * np.sin(gam) * nan, m0_bounds=(float(m0_b[0]), float(m0_b[1])),
        r_p1_bounds=(float(rp1_b[0]), float(rp1_b[1])), gamma_bounds=gamma_bounds, vehicle=veh,
        provenance=veh.provenance)
    for a in (out.speeds, out.gammas, out.feasible, out.binding, out.m0, out.r_p1, out.alpha, out.theta,
              out.horizontal_speed, out.vertical_speed):
        a.setflags(write=False)
    return out

