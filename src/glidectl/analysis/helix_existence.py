"""The existence scan of §8.2.2's claim about the sign of ``r_P1`` against the sign of ``m0``: where on a grid of
``(m0, r_P1)`` steady motions (helices or straight glides) exist, searched by the cold trim, a multi-start Newton
search and continuation along ``r_P1`` (:func:`existence_scan`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentTypeError, InfeasibleGlideError
from ..models.glider3d import FixedMassGlider3D
from ..params import Vehicle
from ..trim.helix import Helix, helix_newton, helix_trim
from .continuation import (
    MAX_RANDOM_STARTS,
    ContinuationOptions,
    check_options,
    check_solve_budget,
    check_sweep_inputs,
    readonly_array,
)
from .helix_sweeps import helix_sweep

__all__ = ["ExistenceScan", "existence_scan"]

_SOLUTION_KEYS = ("speed", "radius", "pitch", "period", "alpha", "beta", "theta", "phi", "gamma", "psidot",
                  "Omega_norm", "r_bh", "residual", "max_re_eig")


def _wrap_phi(y: np.ndarray) -> np.ndarray:
    y = np.array(y, dtype=float)
    y[5] = math.remainder(y[5], 2 * math.pi)
    return y


def _solution_record(h: Helix, found_by: str) -> dict[str, Any]:
    d = h.as_dict()
    rec: dict[str, Any] = {k: float(d[k]) for k in _SOLUTION_KEYS}
    rec["phi"] = math.remainder(rec["phi"], 2 * math.pi)
    rec.update(stable=h.stable, upright=abs(rec["phi"]) < math.pi / 2, found_by=found_by,
               unknowns=tuple(float(u) for u in _wrap_phi(h.unknowns)))
    return rec


def _add_solution(sols: list[dict[str, Any]], rec: dict[str, Any], tol: float) -> None:
    y = np.asarray(rec["unknowns"])
    for s in sols:
        if float(np.max(np.abs(np.asarray(s["unknowns"]) - y))) <= tol:
            if rec["found_by"] not in s["found_by"].split(", "):
                s["found_by"] += ", " + rec["found_by"]
            return
    sols.append(rec)


def _random_start(rng: np.random.Generator) -> np.ndarray:
    """A random trim start over a wide box: V in [0.05, 1.5] m/s, |alpha| < 1.2 rad, |beta| < 0.8 rad,
    |psidot| < 0.3 rad/s, |theta| < 1.5 rad, any roll (inverted flight included)."""
    V, a, b = rng.uniform(0.05, 1.5), rng.uniform(-1.2, 1.2), rng.uniform(-0.8, 0.8)
    return np.array([V * math.cos(a) * math.cos(b), V * math.sin(b), V * math.sin(a) * math.cos(b),
                     rng.uniform(-0.3, 0.3), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi)])


def _scan_point(veh: Vehicle, r_p: tuple[float, float, float], m0: float, n_starts: int, seed: int,
                opts: ContinuationOptions, tol: float) -> list[dict[str, Any]]:
    """Every distinct steady motion found at one ``(r_P, m0)``: the cold solve of ``helix_trim`` and ``n_starts``
    Newton solves from random starts (module level, for executors)."""
    sols: list[dict[str, Any]] = []
    try:
        h = helix_trim(veh, r_p, m0, continuation_steps=opts.continuation_steps, n_random=opts.n_random,
                       seed=opts.seed)
        _add_solution(sols, _solution_record(h, "cold start"), tol)
    except InfeasibleGlideError:
        pass
    model = FixedMassGlider3D(veh, r_p, m0)
    rng = np.random.default_rng(seed)
    for _ in range(n_starts):
        y, _, ok = helix_newton(model, _random_start(rng))
        if not ok:
            continue
        y = _wrap_phi(y)
        if any(float(np.max(np.abs(np.asarray(s["unknowns"]) - y))) <= tol for s in sols):
            continue
        h = helix_trim(veh, r_p, m0, guess=y, n_random=0)
        if float(np.max(np.abs(_wrap_phi(h.unknowns) - y))) <= tol:
            _add_solution(sols, _solution_record(h, "multi-start"), tol)
    return sols


def _scan_row(veh: Vehicle, r_P1_values: list[float], r_p: tuple[float, float, float], m0: float,
              opts: ContinuationOptions) -> list[list[dict[str, Any]]]:
    """Continuation along ``r_P1`` at fixed ``m0``, walked upwards and downwards (module level, for executors)."""
    out: list[list[dict[str, Any]]] = [[] for _ in r_P1_values]
    for order in (1, -1):
        vals = r_P1_values[::order]
        sw = helix_sweep(veh, "r_P1", vals, r_p=r_p, m0=m0, continuation_steps=opts.continuation_steps,
                         n_random=opts.n_random, seed=opts.seed)
        for i in np.flatnonzero(sw.exists):
            rec: dict[str, Any] = {k: float(sw.column(k)[i]) for k in _SOLUTION_KEYS}
            rec["phi"] = math.remainder(rec["phi"], 2 * math.pi)
            rec.update(stable=bool(sw.stable[i]), upright=abs(rec["phi"]) < math.pi / 2,
                       found_by="continuation in r_P1", unknowns=tuple(float(u) for u in _wrap_phi(sw.unknowns[i])))
            out[i if order == 1 else len(vals) - 1 - i].append(rec)
    return out


@dataclass(frozen=True, eq=False)
class ExistenceScan:
    """Where steady motions exist on a grid of ``(m0, r_P1)`` at fixed ``r_P2``, ``r_P3`` (§8.2.2's claim).

    Attributes
    ----------
    r_P1 : ndarray, shape (n1,)
        Moving-mass positions along body-1 (m).
    m0 : ndarray, shape (n0,)
        Buoyancies (kg); grid arrays are indexed ``[i_m0, j_rP1]``.
    r_P2, r_P3 : float
        Fixed moving-mass components (m).
    solutions : tuple (n0) of tuple (n1) of tuple of dict
        Distinct steady motions found at each grid point (trim unknowns within ``tol``; roll wrapped to
        (-pi, pi]): the quantities of :meth:`Helix.as_dict` (SI, rad) plus ``stable``, ``upright``
        (``|phi| < pi/2``), ``found_by`` and ``unknowns``.
    n_solutions, n_stable, n_upright, n_stable_upright : ndarray of int, shape (n0, n1)
    context : dict
        Vehicle, methods and their settings.
    vehicle : Vehicle
        The vehicle scanned.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    reproduced : bool
        §8.2.2's claim is reproduced on this grid: no steady motion found anywhere in :attr:`claim_region`.
    """

    r_P1: np.ndarray
    m0: np.ndarray
    r_P2: float
    r_P3: float
    solutions: tuple[tuple[tuple[dict[str, Any], ...], ...], ...] = field(repr=False)
    n_solutions: np.ndarray
    n_stable: np.ndarray
    n_upright: np.ndarray
    n_stable_upright: np.ndarray
    context: dict[str, Any] = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    @property
    def exists(self) -> np.ndarray:
        """True where at least one steady motion was found."""
        return self.n_solutions > 0

    @property
    def claim_region(self) -> np.ndarray:
        """Grid points of §8.2.2's claim: ``m0 > 0`` with ``r_P1 < 0``, or ``m0 < 0`` with ``r_P1 > 0``."""
        m, r = self.m0[:, None], self.r_P1[None, :]
        return ((m > 0) & (r < 0)) | ((m < 0) & (r > 0))

    @property
    def reproduced(self) -> bool:
        """True when no steady motion was found anywhere in :attr:`claim_region` (§8.2.2's claim reproduced)."""
        return not bool(np.any(self.exists & self.claim_region))

    def counterexamples(self, *, stable_only: bool = False, upright_only: bool = False) -> list[dict[str, Any]]:
        """Motions found inside :attr:`claim_region`, each with its ``r_P1`` (m) and ``m0`` (kg).

        Parameters
        ----------
        stable_only, upright_only : bool
            Keep only stable (reduced linearization Hurwitz) or upright (``|phi| < pi/2``) motions.

        Returns
        -------
        list of dict
            The solution records of :attr:`solutions` with ``r_P1`` and ``m0`` added.

        Raises
        ------
        ArgumentTypeError
            If a flag is not a bool.
        """
        stable_only = checks.boolean("stable_only", stable_only)
        upright_only = checks.boolean("upright_only", upright_only)
        out = []
        for i, j in zip(*np.nonzero(self.claim_region), strict=True):
            for s in self.solutions[i][j]:
                if (stable_only and not s["stable"]) or (upright_only and not s["upright"]):
                    continue
                out.append({"r_P1": float(self.r_P1[j]), "m0": float(self.m0[i]), **s})
        return out

    def plot(self, ax: Any = None) -> Any:
        """Draw where steady motions were found on the ``(r_P1, m0)`` grid, with the claim region of §8.2.2
        shaded, in the glidectl style (:func:`glidectl.plotting.plot_existence_scan`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into, ``r_P1`` (cm) across and ``m0`` (kg) up; default a new figure.

        Returns
        -------
        matplotlib.axes.Axes
            One marker per grid point by outcome (a stable upright motion, motions but none stable upright, none)
            with the number of motions found, legend below the axes.
        """
        from ..plotting import plot_existence_scan, style

        with style():
            return plot_existence_scan(self, ax)

    def summary(self) -> str:
        """A few lines of text: counts inside and outside the claim region."""
        cr, ex = self.claim_region, self.exists
        lines = [f"existence scan: {self.m0.size} m0 x {self.r_P1.size} r_P1 points, r_P2 = {self.r_P2:g} m, "
                 f"r_P3 = {self.r_P3:g} m",
                 f"  outside the claim region: motions at {int(np.sum(ex & ~cr))} of {int(np.sum(~cr))} points",
                 f"  inside the claim region (m0 r_P1 < 0): motions at {int(np.sum(ex & cr))} of {int(np.sum(cr))} "
                 f"points; at {int(np.sum((self.n_stable_upright > 0) & cr))} of them a stable upright one",
                 f"  claim {'holds' if self.reproduced else 'does not hold'} on this grid"]
        return "\n".join(lines)


def existence_scan(veh: Vehicle, r_P1_values: Sequence[float], m0_values: Sequence[float], *,
                   r_P2: float | None = None, r_P3: float | None = None, n_starts: int = 100, seed: int = 0,
                   continuation: bool = True, tol: float = 1e-6, executor: Executor | None = None,
                   continuation_steps: int = 12, n_random: int = 40) -> ExistenceScan:
    """Search hard for steady motions on a ``(m0, r_P1)`` grid to test §8.2.2's claim: "We could not find any
    equilibrium solutions for a combination of negative buoyancy (m0 > 0) and aft center of gravity (r_P1 < 0) or
    for a combination of positive buoyancy (m0 < 0) and fore center of gravity (r_P1 > 0)".

    At every grid point three searches run and their distinct solutions are merged: the cold solve of
    :func:`helix_trim` (straight longitudinal glide continued in ``r_P2``, then ``n_random`` random starts);
    ``n_starts`` Newton solves of (8.23) = 0 from random starts over a wide box (any roll angle, so inverted motions
    are found too); and, with ``continuation``, :func:`helix_sweep` along ``r_P1`` at each ``m0``, walked both ways.

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (``slocum_ch8``).
    r_P1_values : sequence of float
        Moving-mass positions along body-1 (m), preferably sorted (for the continuation).
    m0_values : sequence of float
        Buoyancies (kg); ``m0 = 0`` has no steady glide and is recorded as empty.
    r_P2, r_P3 : float, optional
        Fixed moving-mass components (m); default the vehicle's nominal values (2 cm, 4 cm for ``slocum_ch8``, those
        of Fig 8.5-8.6).
    n_starts : int
        Random Newton starts per grid point, in ``[0, 10000]``; ``seed`` (``>= 0``) seeds them (grid point ``k``
        uses ``seed + k``).
    continuation : bool
        Also continue along ``r_P1`` at each ``m0`` (both ways).
    tol : float
        Two solutions are the same motion when their trim unknowns differ by at most ``tol`` (> 0).
    executor : concurrent.futures.Executor, optional
        Runs the grid points and the continuation rows in parallel.
    continuation_steps, n_random : int
        Cold-solve settings of :func:`glidectl.trim.helix.helix_trim`, in ``[1, 1000]`` and ``[0, 10000]``.

    Returns
    -------
    ExistenceScan
        With :attr:`ExistenceScan.reproduced`, :meth:`ExistenceScan.counterexamples` and
        :meth:`ExistenceScan.summary`.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, a grid or ``r_P2``/``r_P3``/``tol`` is not real numbers, a count or ``seed``
        is not an integer, ``continuation`` is not a bool, or ``executor`` has no ``submit``.
    ArgumentError
        If ``r_P1_values`` or ``m0_values`` is empty, not one-dimensional or not finite; a count is out of its
        range; ``tol <= 0``; a grid point puts the moving mass farther than 10 m from the centre.
    ModelError
        If the vehicle is not a 3D underwater glider, ``r_P2``/``r_P3`` are omitted and the vehicle has no nominal
        value for them, or an ``m0`` of the grid makes a mass non-positive.
    BudgetError
        If the scan could need more than :data:`~glidectl.analysis.continuation.MAX_NEWTON_SOLVES` Newton solves
        (grid points x (n_starts + 1 + continuation_steps + n_random), plus the continuation rows), checked before
        anything is solved.
    InfeasibleGlideError
        If a helix trim warm-started from a converged multi-start Newton solution fails (only the cold solve's
        failure is absorbed as "no motion").

    Examples
    --------
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> scan = gc.existence_scan(slo, [-0.02, 0.02], [-0.25, 0.25], n_starts=4)  # r_P1 (m) x m0 (kg)
    >>> scan.reproduced  # a stable upright helix exists where section 8.2.2 found none
    False
    >>> print(scan.n_stable_upright)
    [[1 1]
     [1 1]]
    """
    checks.vehicle("veh", veh, "underwater_glider")
    r1 = checks.array("r_P1_values (m)", r_P1_values, ndim=1, min_size=1)
    m0s = checks.array("m0_values (kg)", m0_values, ndim=1, min_size=1)
    n_starts = checks.integer("n_starts", n_starts, lo=0, hi=MAX_RANDOM_STARTS)
    continuation = checks.boolean("continuation", continuation)
    tol = checks.positive("tol", tol)
    opts = check_options(continuation_steps, n_random, seed)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise ArgumentTypeError(f"executor must be a concurrent.futures.Executor (with submit), got "
                                f"{type(executor).__name__}")
    p2 = checks.real("r_P2", veh.r_P2 if r_P2 is None else r_P2, unit="m")
    p3 = checks.real("r_P3", veh.r_P3 if r_P3 is None else r_P3, unit="m")
    cold = 1 + opts.continuation_steps + opts.n_random
    points = r1.size * int(np.count_nonzero(m0s))
    check_solve_budget(f"existence_scan over {m0s.size} x {r1.size} points",
                       points * (n_starts + cold) + (2 * points * (1 + cold) if continuation else 0))
    for m in {float(np.min(m0s)), float(np.max(m0s))}:  # masses are affine in m0: the extremes decide
        check_sweep_inputs(veh, "r_P1", r1, (0.0, p2, p3), m)  # every grid point is a valid model
    seed = opts.seed
    grid = [(i, j) for i in range(m0s.size) for j in range(r1.size)]
    point_args = [(veh, (float(r1[j]), p2, p3), float(m0s[i]), int(n_starts), int(seed) + k, opts, float(tol))
                  for k, (i, j) in enumerate(grid) if m0s[i] != 0]
    row_args = [(veh, [float(x) for x in r1], (0.0, p2, p3), float(m0s[i]), opts)
                for i in range(m0s.size) if continuation and m0s[i] != 0]
    if executor is None:
        point_res = [_scan_point(*a) for a in point_args]
        row_res = [_scan_row(*a) for a in row_args]
    else:
        pf = [executor.submit(_scan_point, *a) for a in point_args]
        rf = [executor.submit(_scan_row, *a) for a in row_args]
        point_res, row_res = [f.result() for f in pf], [f.result() for f in rf]
    sols: list[list[list[dict[str, Any]]]] = [[[] for _ in r1] for _ in m0s]
    it = iter(point_res)
    for i, j in grid:
        if m0s[i] != 0:
            sols[i][j] = next(it)
    rows = iter(row_res)
    for i in range(m0s.size):
        if continuation and m0s[i] != 0:
            for j, recs in enumerate(next(rows)):
                for rec in recs:
                    _add_solution(sols[i][j], rec, tol)

    def count(pred: Any) -> np.ndarray:
        return readonly_array(np.array([[sum(1 for s in sols[i][j] if pred(s)) for j in range(r1.size)]
                                        for i in range(m0s.size)], dtype=int))

    frozen = tuple(tuple(tuple(s) for s in row) for row in sols)
    prov = {"vehicle": veh.name, "vehicle_provenance": veh.provenance, "n_starts": int(n_starts), "seed": int(seed),
            "continuation": bool(continuation), "tol": float(tol), "helix_trim": opts._asdict(),
            "random_box": _random_start.__doc__, "thesis": "Bhatta 2006 §8.2.2"}
    return ExistenceScan(readonly_array(r1), readonly_array(m0s), p2, p3, frozen, count(lambda s: True),
                         count(lambda s: s["stable"]), count(lambda s: s["upright"]),
                         count(lambda s: s["stable"] and s["upright"]), prov, veh, veh.provenance)
