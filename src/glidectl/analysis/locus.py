"""Root loci over physical parameters (bottom-heaviness r_bh, moving mass mbar), §2.3.1-§2.3.2, Fig 2.7.

A locus is computed on a grid, its branches are made continuous by optimal matching of eigenvalues between
consecutive grid points (Hungarian assignment on distance), stability boundaries are located by Brent's method on
``max Re(lambda)``, and break-away/break-in points (real eigenvalues meeting and leaving the real axis, and the
reverse) by bisection on the number of real eigenvalues, which LAPACK reports exactly (``Im = 0``) for real
matrices.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq, linear_sum_assignment

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from ..models.longitudinal import AccelerationControlledGlider, LongitudinalGlider
from ..params import Vehicle
from ..trim.glide import steady_glide

__all__ = ["BreakPoint", "ParameterLocus", "eta_r_eigenvalues", "mbar_locus", "parameter_locus", "rbh_locus",
           "uncontrolled_eigs"]

ETA_R = ("theta", "Omega2", "v1", "v3")


@dataclass(frozen=True)
class BreakPoint:
    """A point where two real eigenvalues meet (``break-away``: they leave the real axis as the parameter
    increases) or a complex pair lands on the real axis (``break-in``).

    Attributes
    ----------
    kind : str
        ``"break-away"`` or ``"break-in"``.
    parameter : float
        Parameter value of the transition (unit of the locus parameter, e.g. m for ``r_bh``, kg for ``mbar``),
        located by bisection to about 1e-13 relative.
    eigenvalue : float
        Real eigenvalue where the pair meets (1/s), estimated as the midpoint of the two closest real eigenvalues
        at the transition; NaN if fewer than two are real there.
    """

    kind: str
    parameter: float
    eigenvalue: float


@dataclass(frozen=True)
class ParameterLocus:
    """Eigenvalues of a parameter-dependent matrix along a grid, with continuous branches.

    Attributes
    ----------
    parameter : str
        Name of the varied parameter; ``unit`` its unit.
    values : ndarray, shape (N,)
    branches : ndarray, shape (N, k)
        ``branches[i, j]`` is eigenvalue branch j at ``values[i]``; consecutive rows are matched.
    crossings : tuple of float
        Parameter values where ``max Re(lambda)`` changes sign (located by Brent's method, xtol 1e-13).
    breakpoints : tuple of BreakPoint
    max_step_jump : float
        Largest eigenvalue movement between consecutive grid points after matching (a continuity diagnostic).
    context : dict
        What the matrix is (vehicle name, glide, block, settings).
    vehicle : Vehicle or None
        The vehicle the matrix belongs to (``None`` for a locus of a plain matrix function).
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`; ``""`` without a vehicle).
    """

    parameter: str
    unit: str
    values: np.ndarray
    branches: np.ndarray
    crossings: tuple[float, ...]
    breakpoints: tuple[BreakPoint, ...]
    max_step_jump: float
    context: dict[str, Any]
    vehicle: Vehicle | None = field(default=None, repr=False, compare=False)
    provenance: str = ""

    def stable_at(self, i: int) -> bool:
        """True when every branch has negative real part at grid index ``i``.

        Parameters
        ----------
        i : int
            Grid index, ``-N <= i < N`` (negative counts from the end).

        Returns
        -------
        bool

        Raises
        ------
        ArgumentTypeError
            If ``i`` is not an integer.
        ArgumentError
            If ``i`` is outside the grid.
        """
        n = self.values.size
        i = checks.integer("i", i, lo=-n, hi=n - 1)
        return bool(np.all(self.branches[i].real < 0))

    def plot(self, ax: Any = None, *, kind: str = "complex", **kw: Any) -> Any:
        """Draw the locus in the glidectl style (:func:`glidectl.plotting.style`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        kind : {"complex", "real"}
            ``"complex"``: root locus in the complex plane, coloured by the parameter, crossings and break points
            marked (:func:`glidectl.plotting.plot_locus`); ``"real"``: real parts of the branches versus the
            parameter (:func:`glidectl.plotting.plot_locus_real`).
        **kw
            Passed to :func:`~glidectl.plotting.plot_locus` (``zoom``) for ``kind="complex"``.

        Returns
        -------
        matplotlib.axes.Axes

        Raises
        ------
        ArgumentError
            If ``kind`` is neither ``"complex"`` nor ``"real"``.
        """
        from ..plotting import plot_locus, plot_locus_real, style

        checks.choice("kind", kind, ("complex", "real"))
        with style():
            return plot_locus(self, ax=ax, **kw) if kind == "complex" else plot_locus_real(self, ax=ax, **kw)


class _Passthrough(Exception):
    """Carries an exception raised by ``eig_fn`` through :func:`scipy.optimize.brentq` unchanged."""


def _match(prev: np.ndarray, new: np.ndarray) -> np.ndarray:
    cost = np.abs(prev[:, None] - new[None, :])
    _, col = linear_sum_assignment(cost)
    return new[col]


def _n_real(lam: np.ndarray) -> int:
    return int(np.sum(lam.imag == 0))


def _grid(name: str, values: Any) -> np.ndarray:
    vals = checks.array(name, values, ndim=1, min_size=2)
    if np.any(np.diff(vals) <= 0):
        raise ArgumentError(f"{name} must be a strictly increasing 1-D grid of >= 2 points, got {vals!r}")
    return vals


def parameter_locus(eig_fn: Callable[[float], np.ndarray], values: Sequence[float], parameter: str,
                    unit: str, context: dict[str, Any] | None = None, *,
                    vehicle: Vehicle | None = None, time_limit: float | None = None) -> ParameterLocus:
    """Eigenvalue locus of ``eig_fn(p)`` over ``values`` with branch matching, crossings and break points.

    Parameters
    ----------
    eig_fn : callable
        ``p -> eigenvalues`` (fixed count), e.g. of an exact Jacobian at a re-solved equilibrium.
    values : sequence of float
        Increasing parameter grid.
    parameter, unit : str
        Name and unit of p, for plots and reports.
    context : dict, optional
        What the matrix is (vehicle, glide, block), stored as :attr:`ParameterLocus.context`.
    vehicle : Vehicle, optional
        The vehicle the matrix belongs to; the locus keeps it and its parameter hash as ``provenance``.
    time_limit : float, optional
        Wall-time budget (s) of the whole computation; default none. The work is otherwise bounded: one
        ``eig_fn`` call per grid point, at most 200 Brent iterations per stability crossing and 80 bisection steps
        per break point.

    Returns
    -------
    ParameterLocus
        Matched eigenvalue branches (units of ``eig_fn``'s eigenvalues, 1/s for glidectl models), the stability
        crossings and break points (in the unit ``unit`` of the parameter), and the largest eigenvalue jump between
        consecutive grid points after matching.

    Raises
    ------
    ArgumentTypeError
        If ``eig_fn`` is not callable, ``values`` is not an array of real numbers, ``parameter``/``unit`` are not
        strings, ``context`` is not a mapping, ``vehicle`` is not a Vehicle, or ``eig_fn`` returns something that is
        not an array of numbers.
    ArgumentError
        If ``values`` is not a finite, strictly increasing one-dimensional grid of at least 2 points, or ``eig_fn``
        returns an empty or multi-dimensional array.
    ModelError
        If ``eig_fn`` returns a non-finite eigenvalue.
    SolverError
        If the number of eigenvalues changes along the grid, or Brent's method fails on a sign change of
        ``max Re(lambda)``.
    BudgetError
        If ``time_limit`` is reached.
    Exception
        Whatever ``eig_fn`` raises passes through unchanged.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> loc = gc.parameter_locus(lambda k: np.linalg.eigvals([[0.0, 1.0], [-1.0, 1.0 - k]]),
    ...                          np.linspace(0.0, 4.0, 41), "k", "1/s")  # s^2 + (k - 1) s + 1
    >>> [round(c, 6) for c in loc.crossings], [(b.kind, round(b.parameter, 6)) for b in loc.breakpoints]
    ([1.0], [('break-in', 3.0)])
    """
    checks.function("eig_fn", eig_fn)
    vals = _grid("values", values)
    for nm, txt in (("parameter", parameter), ("unit", unit)):
        if not isinstance(txt, str):
            raise ArgumentTypeError(f"{nm} must be a string, got {type(txt).__name__} {txt!r}")
    if context is not None and not isinstance(context, Mapping):
        raise ArgumentTypeError(f"context must be a mapping (dict) or None, got {type(context).__name__}")
    if vehicle is not None:
        checks.vehicle("vehicle", vehicle)
    deadline = checks.Deadline(time_limit, f"locus over {parameter}")

    def eig_at(p: float) -> np.ndarray:
        deadline.check(f"at {parameter} = {p:g}")
        raw = eig_fn(float(p))
        try:
            lam = np.asarray(raw, dtype=complex)
        except (TypeError, ValueError) as exc:
            raise ArgumentTypeError(f"eig_fn must return an array of eigenvalues, got {type(raw).__name__} at "
                                    f"{parameter} = {p:g}") from exc
        if lam.ndim != 1 or lam.size == 0:
            raise ArgumentError(f"eig_fn must return a non-empty 1-D array of eigenvalues, got shape {lam.shape} at "
                                f"{parameter} = {p:g}")
        if not np.all(np.isfinite(lam)):
            raise ModelError(f"eig_fn returned non-finite eigenvalues at {parameter} = {p:g}: the matrix is not "
                             "finite there")
        return lam

    eigs = [eig_at(float(p)) for p in vals]
    k = eigs[0].size
    branches = np.empty((vals.size, k), dtype=complex)
    branches[0] = np.sort_complex(eigs[0])
    for i in range(1, vals.size):
        if eigs[i].size != k:
            raise SolverError(f"eigenvalue count changed along the locus at {parameter} = {vals[i]:g}")
        branches[i] = _match(branches[i - 1], eigs[i])
    jump = float(np.max(np.abs(np.diff(branches, axis=0)))) if vals.size > 1 else 0.0

    def h(p: float) -> float:
        try:
            return float(np.max(eig_at(p).real))
        except Exception as exc:  # eig_fn's own errors (and budget) must not be mistaken for Brent's
            raise _Passthrough(exc) from exc

    hv = np.array([np.max(e.real) for e in eigs])
    crossings: list[float] = []
    sg = np.sign(hv)
    nz = np.nonzero(sg)[0]  # grid points with a definite sign; exact zeros are handled between them
    for i, j in itertools.pairwise(nz):
        if sg[i] * sg[j] > 0:
            continue
        if j > i + 1:  # max Re(lambda) is exactly 0 on the grid points between i and j
            crossings.append(float(vals[(i + j) // 2]))
            continue
        try:
            crossings.append(float(brentq(h, vals[i], vals[j], xtol=1e-13, rtol=1e-12, maxiter=200)))
        except _Passthrough as wrapped:
            raise wrapped.args[0] from None
        except (ValueError, RuntimeError) as exc:  # pragma: no cover - brentq is guaranteed by the sign change
            raise SolverError(
                f"stability boundary search failed between {vals[i]:g} and {vals[j]:g}: {exc}") from exc
    bps: list[BreakPoint] = []
    nr = np.array([_n_real(e) for e in eigs])
    for i in np.nonzero(nr[:-1] != nr[1:])[0]:
        a, b, na = vals[i], vals[i + 1], nr[i]
        for _ in range(80):
            mid = 0.5 * (a + b)
            if _n_real(eig_at(mid)) == na:
                a = mid
            else:
                b = mid
            if b - a <= 1e-13 * max(1.0, abs(a)):
                break
        lam = eig_at(b)
        kind = "break-away" if nr[i + 1] < nr[i] else "break-in"
        # the meeting point: the real eigenvalue pair (or complex pair) closest to each other at the transition
        cand = eig_at(a) if kind == "break-away" else lam
        re = np.sort(cand[cand.imag == 0].real)
        loc = float(re[np.argmin(np.diff(re))] + np.min(np.diff(re)) / 2) if re.size >= 2 else float("nan")
        bps.append(BreakPoint(kind, float(0.5 * (a + b)), loc))
    return ParameterLocus(parameter, unit, vals, branches, tuple(crossings), tuple(bps), jump, dict(context or {}),
                          vehicle, "" if vehicle is None else vehicle.provenance)


SPEED_MAX = 100.0  # m/s, plausibility limit of a glide speed


def _glide_args(veh: Vehicle, speed: Any, gamma: Any, family: dict[str, Any] | None) -> tuple[float, float,
                                                                                               dict[str, float]]:
    """Check the arguments of a steady glide at the boundary: vehicle kind, speed in (0, 100] m/s, finite gamma
    and (when given) exactly one of ``r_p3=`` / ``r_bh=`` (m)."""
    checks.vehicle("veh", veh, "underwater_glider")
    speed = checks.real("speed", speed, lo=0.0, hi=SPEED_MAX, lo_open=True, unit="m/s")
    gamma = checks.real("gamma", gamma, lo=-math.pi / 2, hi=math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    if family is None:
        return speed, gamma, {}
    unknown = sorted(set(family) - {"r_p3", "r_bh"})
    if unknown:
        raise ArgumentTypeError(f"unknown keyword argument(s) {unknown}; the mass position is given by r_p3= or "
                                "r_bh= (m)")
    if len(family) != 1:
        raise ArgumentError("give exactly one of r_p3= (m) or r_bh= (m) to pick the moving-mass position from the "
                            f"one-parameter family of equilibria, got {sorted(family) or 'neither'}")
    (key, value), = family.items()
    return speed, gamma, {key: checks.real(key, value, unit="m")}


def _eigvals(M: np.ndarray, what: str) -> np.ndarray:
    try:
        return np.linalg.eigvals(M)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of {what} did not converge: {exc}") from exc


def _block_eigenvalues(model: Any, x: np.ndarray, block: Sequence[str], what: str) -> np.ndarray:
    """Eigenvalues of the ``block`` rows and columns (state names) of the exact Jacobian of ``model.rhs`` at ``x``
    with zero input (3 inputs, as the glider models)."""
    A, _ = jacobians(model.rhs, x, np.zeros(3))
    idx = [model.state_names.index(s) for s in block]
    return _eigvals(A[np.ix_(idx, idx)], what)


def _locus_info(veh: Vehicle, speed: float, gamma: float, matrix: str, **extra: float) -> dict[str, Any]:
    """The ``info`` of a glider locus: vehicle name and provenance, the glide, which matrix and what is held."""
    return {"vehicle": veh.name, "provenance": veh.provenance, "speed": speed, "gamma": gamma, "matrix": matrix,
            **extra}


def eta_r_eigenvalues(veh: Vehicle, speed: float, gamma: float, **family: float) -> np.ndarray:
    """Eigenvalues (1/s) of the ``eta_r = (theta, Omega2, v1, v3)`` block ``dq_r/deta_r`` of (2.35) at a steady
    glide of the acceleration-controlled glider.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with a moving mass (``mbar > 0``).
    speed : float
        Glide speed (m/s).
    gamma : float
        Flight-path angle (rad).
    **family : float
        The member of the family of mass positions, ``r_p3=`` or ``r_bh=`` (m), as in
        :func:`glidectl.trim.glide.steady_glide`.

    Returns
    -------
    ndarray, shape (4,)
        Eigenvalues of the 4x4 block of the exact (complex-step) Jacobian (unsorted).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``speed``, ``gamma`` or the family value is not a real number, or a keyword
        other than ``r_p3``/``r_bh`` is given.
    ArgumentError
        If ``speed`` is not in (0, 100] m/s, ``gamma`` not in (-pi/2, pi/2), a value is not finite, or not exactly
        one of ``r_p3``, ``r_bh`` is given.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``, or the linearization is not finite.
    InfeasibleGlideError
        If no steady glide exists at ``speed`` and ``gamma``.
    SolverError
        If the steady glide's residual check or the eigenvalue computation fails.
    """
    speed, gamma, family = _glide_args(veh, speed, gamma, family)
    acc = AccelerationControlledGlider(veh)
    return _block_eigenvalues(acc, steady_glide(veh, speed, gamma, **family).accel_state(), ETA_R, "dq_r/deta_r")


def rbh_locus(veh: Vehicle, speed: float, gamma: float, rbh_values: Sequence[float], *,
              time_limit: float | None = None) -> ParameterLocus:
    """Eigenvalues of ``dq_r/deta_r`` (acceleration-controlled glider, (2.35)) versus bottom-heaviness (Fig 2.7).

    At each ``r_bh`` the steady glide (speed in m/s, gamma in rad) is re-solved (the speed, gamma, alpha and m0 do
    not change; r_P does) and the 4x4 block for ``eta_r = (theta, Omega2, v1, v3)`` of the exact Jacobian is taken.
    Its eigenvalues decide stability of the closed loop (2.35)-(2.37) for any Hurwitz A + BK (block triangular).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with a moving mass (``mbar > 0``).
    speed : float
        Glide speed (m/s).
    gamma : float
        Flight-path angle (rad), in the permissible set (2.26).
    rbh_values : sequence of float
        Strictly increasing grid of bottom-heaviness values ``r_bh`` (m), at least 2 points, finite.
    time_limit : float, optional
        Wall-time budget (s); see :func:`parameter_locus` for the bounded work.

    Returns
    -------
    ParameterLocus
        The four eigenvalue branches (1/s) versus ``r_bh`` (m), stability crossings and break points.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``speed`` or ``gamma`` is not a real number, or ``rbh_values`` not real numbers.
    ArgumentError
        If ``speed`` is not in (0, 100] m/s, ``gamma`` not in (-pi/2, pi/2), or ``rbh_values`` is not a finite,
        strictly increasing grid of at least 2 points.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    InfeasibleGlideError
        If no steady glide exists at ``speed`` and ``gamma`` (:func:`glidectl.trim.glide.steady_glide`).
    SolverError
        If a steady glide's residual check fails, or as in :func:`parameter_locus`.
    BudgetError
        If ``time_limit`` is reached.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> loc = gc.rbh_locus(veh, 0.3, -np.pi / 4, np.linspace(-0.02, 0.10, 25))
    >>> loc.branches.shape
    (25, 4)
    >>> print(f"stable for r_bh > {loc.crossings[0] * 1000:.2f} mm")
    stable for r_bh > -6.04 mm
    """
    speed, gamma, _ = _glide_args(veh, speed, gamma, None)
    vals = _grid("rbh_values", rbh_values)
    return parameter_locus(lambda r: eta_r_eigenvalues(veh, speed, gamma, r_bh=r), vals, "r_bh", "m",
                           _locus_info(veh, speed, gamma, "dq_r/deta_r of (2.35), acceleration control"),
                           vehicle=veh, time_limit=time_limit)


UNCONTROLLED_BLOCK = ("theta", "Omega2", "v1", "v3", "r_P1", "r_P3")


def uncontrolled_eigs(veh: Vehicle, speed: float, gamma: float, **family: float) -> np.ndarray:
    """Nonzero eigenvalues of the uncontrolled force model (u = 0) at a steady glide.

    With ``u = 0`` the rows of ``P_P1, P_P3, m0`` (and the column of z') vanish, so the spectrum is four exact zeros
    plus that of the block :data:`UNCONTROLLED_BLOCK`, which itself has one zero eigenvalue (moving ``r_P`` along
    gravity at fixed momentum keeps an equilibrium). That structural zero (smallest magnitude) is removed.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with a moving mass (``mbar > 0``).
    speed : float
        Glide speed (m/s).
    gamma : float
        Flight-path angle (rad), in the permissible set (2.26).
    **family : float
        The member of the family of mass positions, ``r_p3=`` or ``r_bh=`` (m), as in
        :func:`glidectl.trim.glide.steady_glide`.

    Returns
    -------
    numpy.ndarray, shape (5,)
        Eigenvalues (1/s) of the :data:`UNCONTROLLED_BLOCK` of the exact Jacobian with the structural zero removed
        (unsorted).

    Raises
    ------
    ArgumentTypeError, ArgumentError, ModelError, InfeasibleGlideError, SolverError
        For the arguments and cases of :func:`eta_r_eigenvalues` (this function linearizes the uncontrolled force
        model instead of the acceleration-controlled glider).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> lam = gc.uncontrolled_eigs(gc.load_vehicle("rogue"), 0.3, -np.pi / 4, r_p3=0.05)
    >>> print(np.sort_complex(np.round(lam, 3)))
    [-2.918+0.j    -0.505-2.493j -0.505+2.493j -0.493-2.014j -0.493+2.014j]
    """
    speed, gamma, family = _glide_args(veh, speed, gamma, family)
    model = LongitudinalGlider(veh)
    lam = _block_eigenvalues(model, steady_glide(veh, speed, gamma, **family).force_state(), UNCONTROLLED_BLOCK,
                             "the uncontrolled block")
    return np.delete(lam, np.argmin(np.abs(lam)))


def mbar_locus(veh: Vehicle, speed: float, gamma: float, mbar_values: Sequence[float], *,
               time_limit: float | None = None, **family: float) -> ParameterLocus:
    """Nonzero eigenvalues of the uncontrolled glider versus the moving mass mbar (kg) (§2.3.1, 0.257 kg).

    The glide is re-trimmed at each mbar holding ``r_p3`` (or ``r_bh``) given in ``family`` fixed.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider; its ``mbar`` is overridden at each grid point.
    speed : float
        Glide speed (m/s).
    gamma : float
        Flight-path angle (rad), in the permissible set (2.26).
    mbar_values : sequence of float
        Strictly increasing grid of moving masses (kg), at least 2 points, all finite and ``> 0``.
    time_limit : float, optional
        Wall-time budget (s); see :func:`parameter_locus` for the bounded work.
    **family : float
        ``r_p3=`` or ``r_bh=`` (m), held fixed along the locus.

    Returns
    -------
    ParameterLocus
        The five nonzero eigenvalue branches (1/s) of :func:`uncontrolled_eigs` versus ``mbar`` (kg).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``speed``, ``gamma`` or the family value is not a real number, a keyword other
        than ``r_p3``/``r_bh`` is given, or ``mbar_values`` is not real numbers.
    ArgumentError
        If ``speed`` is not in (0, 100] m/s, ``gamma`` not in (-pi/2, pi/2), not exactly one of ``r_p3``, ``r_bh``
        is given, or ``mbar_values`` is not a finite, strictly increasing grid of at least 2 positive masses.
    ModelError
        If ``veh`` is not an underwater glider.
    InfeasibleGlideError
        If no steady glide exists at ``speed`` and ``gamma``.
    SolverError
        If a steady glide's residual check fails, or as in :func:`parameter_locus`.
    BudgetError
        If ``time_limit`` is reached.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> loc = gc.mbar_locus(veh, 0.3, -np.pi / 4, np.linspace(0.1, 0.5, 9), r_p3=0.05)
    >>> print(f"unstable above mbar = {loc.crossings[0]:.4f} kg")
    unstable above mbar = 0.2564 kg
    """
    speed, gamma, family = _glide_args(veh, speed, gamma, family)
    vals = _grid("mbar_values", mbar_values)
    if vals[0] <= 0:
        raise ArgumentError(f"mbar_values must be moving masses > 0 kg, got {vals[0]!r}")
    return parameter_locus(lambda mb: uncontrolled_eigs(veh.with_overrides(mbar=mb), speed, gamma, **family),
                           vals, "mbar", "kg",
                           _locus_info(veh, speed, gamma, "uncontrolled force model, u = 0", **family),
                           vehicle=veh, time_limit=time_limit)
