"""Maps of steady circular helices versus one control parameter, §8.2.2 (Fig 8.5-8.12).

:func:`helix_sweep` solves the helix trim (:func:`glidectl.trim.helix.helix_trim`, equations (8.23)-(8.31)) at each
value of one control parameter (``r_P1``, ``r_P2``, ``r_P3`` in m or ``m0`` in kg) with the others held fixed, and
returns a frozen :class:`HelixSweep` with one row of helix quantities per value (NaN and ``exists = False`` where no
steady motion was found) and a note per point saying how it was found or why not.

The continuation along the values (warm starts, chunks on an executor, reconciliation with the serial walk) is
:mod:`glidectl.analysis.continuation`.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, GlidectlError, SolverError
from ..params import Vehicle
from ..trim.helix import Helix, helix_trim
from .continuation import (
    COLUMN_UNITS,
    COLUMNS,
    PARAMETERS,
    check_executor,
    check_options,
    check_solve_budget,
    check_sweep_inputs,
    chunk_bounds,
    readonly_array,
    reconcile_chunks,
    run_chunks,
    sweep_controls,
    walk_chunk,
)

__all__ = ["HelixSweep", "helix_sweep", "straight_glides"]


def _column_property(name: str) -> property:
    return property(lambda self: self.column(name), doc=f"``{name}`` column ({COLUMN_UNITS[name]}); NaN where no "
                                                        "motion was found.")


@dataclass(frozen=True, eq=False)
class HelixSweep:
    """Steady helices (or straight glides) along a sweep of one control parameter, §8.2.2 (Fig 8.5-8.12).

    Attributes
    ----------
    parameter : str
        ``"r_P1"``, ``"r_P2"``, ``"r_P3"`` (moving-mass position, m) or ``"m0"`` (buoyancy, kg); ``unit`` its unit.
    values : ndarray, shape (n,)
        Swept values, in the order walked.
    columns : tuple of str
        Names of the columns of ``data`` (:data:`COLUMNS`; units in :data:`COLUMN_UNITS`): helix radius, speed,
        pitch (drop per turn, positive down) and period (``inf`` for a straight glide), angle of attack, sideslip,
        pitch and roll angles, flight-path angle, yaw rate, ``|Omega|``, max real part of the eigenvalues of the
        8-state reduced linearization, trim residual, bottom-heaviness ``r_bh`` and the body velocity.
    data : ndarray, shape (n, len(columns))
        One row per value; NaN where no steady motion was found.
    exists : ndarray of bool, shape (n,)
    unknowns : ndarray, shape (n, 6)
        Trim unknowns ``(v1, v2, v3, psidot, theta, phi)`` (warm starts for :func:`helix_trim`); NaN where missing.
    how : tuple of str
        Per point: ``"cold"``, ``"warm"`` (continuation), ``"cold (warm failed)"`` or ``"none"``.
    notes : tuple of str
        Per point: how the motion was found, or why not (the solver's message).
    r_p : tuple of float
        Moving-mass position (m) held fixed (the swept component is the base value it replaces).
    m0 : float
        Buoyancy (kg) held fixed (unless swept).
    context : dict
        Vehicle name and provenance hash, solver settings, chunking and reconciliation log.
    vehicle : Vehicle
        The vehicle the sweep was computed for.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).

    All arrays are read-only.
    """

    parameter: str
    unit: str
    values: np.ndarray
    columns: tuple[str, ...]
    data: np.ndarray
    exists: np.ndarray
    unknowns: np.ndarray
    how: tuple[str, ...]
    notes: tuple[str, ...]
    r_p: tuple[float, float, float]
    m0: float
    context: dict[str, Any] = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    radius = _column_property("radius")
    speed = _column_property("speed")
    pitch = _column_property("pitch")
    period = _column_property("period")
    alpha = _column_property("alpha")
    beta = _column_property("beta")
    theta = _column_property("theta")
    phi = _column_property("phi")
    gamma = _column_property("gamma")
    psidot = _column_property("psidot")
    Omega_norm = _column_property("Omega_norm")
    max_re_eig = _column_property("max_re_eig")
    residual = _column_property("residual")
    r_bh = _column_property("r_bh")

    def column(self, name: str) -> np.ndarray:
        """One column of :attr:`data` by name (read-only view).

        Parameters
        ----------
        name : str
            One of :attr:`columns` (units in :data:`~glidectl.analysis.continuation.COLUMN_UNITS`).

        Returns
        -------
        ndarray, shape (n,)
            NaN where no motion was found.

        Raises
        ------
        ArgumentError
            If ``name`` is not a column.
        """
        if not (isinstance(name, str) and name in self.columns):
            raise ArgumentError(f"unknown column {name!r}; available: {', '.join(self.columns)}")
        return self.data[:, self.columns.index(name)]

    @property
    def stable(self) -> np.ndarray:
        """Existing points whose reduced linearization has all eigenvalues in the open left half plane."""
        with np.errstate(invalid="ignore"):
            return self.exists & (np.nan_to_num(self.max_re_eig, nan=1.0) < 0)

    def controls(self, i: int) -> tuple[tuple[float, float, float], float]:
        """``(r_p (m), m0 (kg))`` at point ``i``.

        Parameters
        ----------
        i : int
            Index into :attr:`values` (negative counts from the end).

        Returns
        -------
        tuple
            ``((r_P1, r_P2, r_P3), m0)``.

        Raises
        ------
        ArgumentTypeError
            If ``i`` is not an integer.
        ArgumentError
            If ``i`` is outside the sweep.
        """
        n = self.values.size
        i = checks.integer("i", i, lo=-n, hi=n - 1)
        return sweep_controls(self.parameter, float(self.values[i]), self.r_p, self.m0)

    def records(self) -> list[dict[str, Any]]:
        """One dict per point: the swept value, ``exists``, every column, ``how`` and ``note``."""
        return [{self.parameter: float(x), "exists": bool(e), **dict(zip(self.columns, map(float, row), strict=True)),
                 "how": h, "note": t}
                for x, e, row, h, t in zip(self.values, self.exists, self.data, self.how, self.notes, strict=True)]

    @property
    def branch_jumps(self) -> np.ndarray:
        """Values (left end of the interval) where consecutive existing solutions jump: a step in the trim unknowns
        more than 10x the median of its ten neighbouring steps. The continuation then left its branch (a fold, or
        coexisting motions); empty for a smooth map."""
        idx = np.flatnonzero(self.exists)
        if idx.size < 3:
            return np.empty(0)
        y = self.unknowns[idx]
        d = np.linalg.norm(np.diff(y, axis=0), axis=1)
        loc = np.array([np.median(np.r_[d[max(i - 5, 0):i], d[i + 1:i + 6]]) for i in range(d.size)])
        return self.values[idx[:-1]][d > 10 * np.maximum(loc, 1e-12)]

    def mirror_error(self, column: str, parity: int = 1) -> float:
        """Largest ``|y(x) - parity y(-x)|`` of a column over the sweep points whose mirror ``-x`` is also a point
        (both with a motion found): the symmetry of the map about a zero of the swept parameter (e.g. the equilibria
        for ``r_P2`` and ``-r_P2`` are mirror images: ``radius`` even, ``beta`` and ``phi`` odd, §8.2.2).

        Parameters
        ----------
        column : str
            One of :attr:`columns`.
        parity : {1, -1}
            1 for an even quantity, -1 for an odd one.

        Returns
        -------
        float
            The largest mirror error in the column's unit; NaN when no point has its mirror on the grid (mirrors
            are matched to 1e-12 in the swept value; ``x = 0`` is skipped).

        Raises
        ------
        ArgumentError
            If ``column`` is not a column or ``parity`` is not 1 or -1.
        """
        y = self.column(column)
        if parity not in (1, -1) or isinstance(parity, bool):
            raise ArgumentError(f"parity must be 1 (even quantity) or -1 (odd quantity), got {parity!r}")
        x = self.values
        errs = []
        for i, xi in enumerate(x):
            if xi == 0:
                continue
            j = np.flatnonzero(np.isclose(x, -xi, atol=1e-12))
            if j.size and self.exists[i] and self.exists[j[0]]:
                errs.append(abs(y[i] - parity * y[j[0]]))
        return float(np.max(errs)) if errs else float("nan")

    def branch_end(self, i: int, target: float, step: float) -> tuple[float, float]:
        """Walk the branch of steady motions through point ``i`` towards ``target`` in steps of ``step``, each
        trim warm-started from the previous one only (no random restarts), and return where it ends: the last
        value reached and the largest real part of the eigenvalues there (near 0 at a fold, a saddle-node).

        The walk stops at ``target``, where the trim fails, or where the step in the trim unknowns exceeds ten times
        the previous one (Newton jumped to another branch).

        Parameters
        ----------
        i : int
            Index of the starting point (negative counts from the end); a point without a motion has no branch to
            walk and gives ``(x_i, nan)``.
        target : float
            Value of the swept parameter to walk towards (its unit: m or kg).
        step : float
            Step (> 0, same unit); the walk makes ``int(|target - x_i| / step)`` steps at most.

        Returns
        -------
        tuple of float
            ``(value, max Re eigenvalue (1/s))`` at the last point reached (point ``i`` itself when the first step
            fails).

        Raises
        ------
        ArgumentTypeError
            If ``i`` is not an integer or ``target``/``step`` not real numbers.
        ArgumentError
            If ``i`` is outside the sweep, ``target`` is not finite or ``step`` is not positive and finite.
        BudgetError
            If the walk would take more than 10**6 steps.
        """
        n = self.values.size
        i = checks.integer("i", i, lo=-n, hi=n - 1)
        target = checks.real("target", target)
        step = checks.real("step", step, lo=0.0, lo_open=True)
        x0 = float(self.values[i])
        k_max = int(abs(target - x0) / step)
        if k_max > 10**6:
            raise BudgetError(f"walking from {x0:g} to {target:g} in steps of {step:g} takes {k_max} steps (more than "
                              "10**6): use a larger step")
        guess: Any = self.unknowns[i]
        last = (x0, float(self.max_re_eig[i]))
        prev = float("inf")
        for k in range(1, k_max + 1):
            x = x0 + np.sign(target - x0) * k * step
            r_p, m0 = sweep_controls(self.parameter, x, self.r_p, self.m0)
            try:
                h = helix_trim(self.vehicle, r_p, m0, guess=guess, n_random=0)
            except GlidectlError:
                break
            d = float(np.linalg.norm(h.unknowns - guess))
            if d > 10 * prev:
                break  # a step ten times the previous one: Newton jumped to another branch
            prev = d
            guess, last = h.unknowns, (x, float(np.max(h.eigenvalues.real)))
        return last

    def plot(self, ax: Any = None, column: str = "radius", **kw: Any) -> Any:
        """Draw one column against the swept value in the glidectl style (one panel of Fig 8.5-8.12).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        column : str
            A column of :attr:`columns` (units in :data:`~glidectl.analysis.continuation.COLUMN_UNITS`).
        **kw
            Passed to :meth:`matplotlib.axes.Axes.plot` for the curve.

        Returns
        -------
        matplotlib.axes.Axes
            The curve (broken at :attr:`branch_jumps`), unstable points marked ``x``; see
            :func:`glidectl.plotting.plot_helix_sweep`.

        Raises
        ------
        ArgumentError
            If ``column`` is not a column.
        """
        from ..plotting import plot_helix_sweep, style

        self.column(column)  # unknown column: ArgumentError before anything is drawn
        with style():
            return plot_helix_sweep(self, ax, column=column, **kw)


def helix_sweep(veh: Vehicle, parameter: str, values: Sequence[float] | np.ndarray, *,
                r_p: Sequence[float] | None = None, m0: float | None = None, executor: Executor | None = None,
                chunks: int | None = None, continuation: bool = True, continuation_steps: int = 12,
                n_random: int = 40, seed: int = 0) -> HelixSweep:
    """Steady helices of ``veh`` along a sweep of one control parameter, §8.2.2 (maps of Fig 8.5-8.12).

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (``slocum_ch8``).
    parameter : {"r_P1", "r_P2", "r_P3", "m0"}
        Swept control parameter: a component of the moving-mass position ``r_P`` (m, body frame) or the buoyancy
        ``m0`` (kg, positive = heavy).
    values : sequence of float
        Values of ``parameter`` (m or kg), walked in the order given (sorted order gives the smoothest
        continuation). Non-empty, finite.
    r_p : 3 floats, optional
        Moving-mass position (m) for the components not swept; default the vehicle's nominal ``(r_P1, r_P2, r_P3)``.
    m0 : float, optional
        Buoyancy (kg) when not swept; default the vehicle's nominal ``m0``.
    executor : concurrent.futures.Executor, optional
        Runs the chunks (``executor.submit``); e.g. ``ProcessPoolExecutor(4)`` or
        ``dask.distributed.Client(...).get_executor()``. ``None``: in this process.
    chunks : int, optional
        Number of contiguous chunks; default 1 without an executor, ``min(n, os.cpu_count())`` with one. The result
        does not depend on it (module docstring).
    continuation : bool
        Warm-start each point from the previous solution (True) or cold-solve every point independently (False).
    continuation_steps, n_random, seed : int
        Cold-solve settings of :func:`glidectl.trim.helix.helix_trim` (steps of the ``r_P2`` continuation from the
        longitudinal straight glide, in ``[1, 1000]``; number of random starts, in ``[0, 10000]``; their seed,
        ``>= 0``).

    Returns
    -------
    HelixSweep
        Frozen; ``exists`` is False (and the row NaN) where no steady motion was found, with the reason in
        ``notes``. No exception is raised for missing points.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle; ``values``, ``r_p`` or ``m0`` are not real numbers; ``chunks``,
        ``continuation_steps``, ``n_random`` or ``seed`` are not integers; ``continuation`` is not a bool;
        ``executor`` has no ``submit``.
    ArgumentError
        Unknown parameter; empty, multi-dimensional or non-finite values; ``r_p`` not three finite numbers; a
        setting out of its range; a swept point with the moving mass farther than 10 m from the centre.
    ModelError
        A vehicle that is not a 3D underwater glider, or a swept point whose ``m0`` makes a mass non-positive.
    BudgetError
        If the sweep could need more than :data:`~glidectl.analysis.continuation.MAX_NEWTON_SOLVES` Newton
        solves (values x (1 + continuation_steps + n_random)).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> sw = gc.helix_sweep(slo, "r_P1", [0.01, 0.02, 0.03, 0.04], r_p=(0.02, 0.02, 0.04), m0=0.25)
    >>> sw.how
    ('cold', 'warm', 'warm', 'warm')
    >>> print(np.round(sw.radius, 1))
    [ 35.8  66.6 187.8 113.3]
    """
    vals, rp, m = check_sweep_inputs(veh, parameter, values, r_p, m0)
    n = vals.size
    check_executor(executor)
    if chunks is None:
        chunks = 1 if executor is None else min(n, os.cpu_count() or 1)
    chunks = checks.integer("chunks", chunks, lo=1)
    continuation = checks.boolean("continuation", continuation)
    opts = check_options(continuation_steps, n_random, seed)
    check_solve_budget(f"helix_sweep over {n} values", n * (2 + opts.continuation_steps + opts.n_random))
    bounds = chunk_bounds(n, min(int(chunks), n))
    args = [(veh, parameter, [float(x) for x in vals[a:b]], rp, m, opts, bool(continuation)) for a, b in bounds]
    results = run_chunks(walk_chunk, args, executor)
    pts, log = reconcile_chunks(veh, parameter, vals, rp, m, opts, bool(continuation), bounds, results)
    prov = {"vehicle": veh.name, "vehicle_provenance": veh.provenance, "parameter": parameter,
            "fixed_r_p": rp, "fixed_m0": m, "continuation": bool(continuation), "chunks": len(bounds),
            "chunk_bounds": bounds, "chunk_seeds": [s for _, s, _ in results],
            "executor": None if executor is None else type(executor).__module__ + "." + type(executor).__qualname__,
            "helix_trim": opts._asdict(), "reconciliation": log, "thesis": "Bhatta 2006 §8.2.2, Fig 8.5-8.12"}
    return HelixSweep(parameter, PARAMETERS[parameter][0], readonly_array(vals), COLUMNS,
                      readonly_array(np.array([p.row for p in pts])), readonly_array(np.array([p.exists for p in pts])),
                      readonly_array(np.array([p.unknowns for p in pts])), tuple(p.how for p in pts),
                      tuple(p.note for p in pts), rp, m, prov, veh, veh.provenance)


def straight_glides(veh: Vehicle, sweep: HelixSweep, *, xtol: float = 1e-10) -> tuple[Helix, ...]:
    """Steady straight glides on the branch of a sweep: the values where the yaw rate ``psidot`` changes sign
    between two neighbouring points found by continuation, refined by Brent's method on ``psidot`` (each trim
    warm-started from the left neighbour).

    There ``Omega = 0`` and the helix degenerates to a straight line (Theorem 7); with ``r_P2 != 0`` it is not in
    the longitudinal plane (``beta != 0``), as §8.2.2 says of Fig 8.9. Intervals across a branch jump
    (:attr:`HelixSweep.branch_jumps`) are skipped.

    Parameters
    ----------
    veh : Vehicle
        The vehicle the sweep was computed for.
    sweep : HelixSweep
        From :func:`helix_sweep` for ``veh``.
    xtol : float
        Absolute tolerance on the swept value (m or kg), ``> 0``.

    Returns
    -------
    tuple of Helix
        One per sign change, with ``psidot`` zero to the trim tolerance (``|psidot| < 1e-9`` rad/s).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``sweep`` is not a :class:`HelixSweep` or ``xtol`` is not a real number.
    ArgumentError
        If ``xtol`` is not positive and finite.
    VehicleMismatchError
        If ``sweep`` was computed for another vehicle.
    ModelError
        If ``veh`` is not a 3D underwater glider.
    InfeasibleGlideError
        If a warm-started trim inside the bracket fails.
    SolverError
        If the re-solved ``psidot`` has the same sign at both ends of a bracket, or Brent's method does not
        converge (at most 100 iterations per bracket).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> sw = gc.helix_sweep(slo, "r_P3", np.linspace(0.0, 0.08, 9), r_p=(0.02, 0.02, 0.04), m0=0.25)
    >>> (h,) = gc.straight_glides(slo, sw)  # psidot changes sign once along the sweep
    >>> print(f"r_P3 = {h.r_p[2] * 100:.2f} cm, |psidot| < 1e-9 rad/s: {abs(h.psidot) < 1e-9}")
    r_P3 = 2.15 cm, |psidot| < 1e-9 rad/s: True
    """
    from scipy.optimize import brentq

    checks.vehicle("veh", veh, "underwater_glider")
    if not isinstance(sweep, HelixSweep):
        raise ArgumentTypeError(f"sweep must be a HelixSweep from gc.helix_sweep(...), got {type(sweep).__name__}")
    checks.same_vehicle("sweep", sweep, veh)
    xtol = checks.positive("xtol", xtol, unit=sweep.unit)
    jumps = set(np.round(sweep.branch_jumps, 12))
    out = []
    idx = np.flatnonzero(sweep.exists)
    for i, j in itertools.pairwise(idx):
        if j != i + 1 or round(float(sweep.values[i]), 12) in jumps:
            continue
        a, b = float(sweep.values[i]), float(sweep.values[j])
        if not sweep.psidot[i] * sweep.psidot[j] < 0:
            continue
        guess = sweep.unknowns[i]

        def trim(x: float, guess: np.ndarray = guess) -> Helix:
            r_p, m0 = sweep_controls(sweep.parameter, x, sweep.r_p, sweep.m0)
            return helix_trim(veh, r_p, m0, guess=guess, n_random=0)

        fa, fb = trim(a).psidot, trim(b).psidot
        if not fa * fb < 0:
            raise SolverError(f"re-solved psidot has the same sign at {sweep.parameter} = {a:g} and {b:g} "
                              f"({fa:.3g}, {fb:.3g} rad/s): the warm-started trims left the sweep's branch")
        x0, info = brentq(lambda x: trim(x).psidot, a, b, xtol=xtol, maxiter=100, full_output=True, disp=False)
        if not info.converged:
            raise SolverError(f"Brent's method did not converge on psidot = 0 between {sweep.parameter} = {a:g} and "
                              f"{b:g}: {info.flag}")
        out.append(trim(x0))
    return tuple(out)
