"""Stability of circular helices versus bottom-heaviness, §8.3 (Fig 8.13-8.14).

``r_bh = r_P . zeta_e`` is the component of the moving-mass position along gravity (body frame). Moving the mass
along ``zeta_e`` changes ``r_bh`` and keeps the perpendicular part (which sets the moment balance). Two loci:

- **frozen** (what §8.3 does): the steady motion ``(v, Omega, theta, phi)`` of the nominal ``r_P`` is kept and only
  the linearization is re-evaluated. §8.3 says ``r_bh`` does not change the equilibrium; it does slightly (through
  the ``m r_P x (v + Omega x r_P)`` terms of (8.25) and the mass matrix of (8.23)), so the frozen state is not an exact
  equilibrium away from the nominal ``r_bh``: the residual is returned with the locus.
- **re-solved**: the helix is re-trimmed at every ``r_bh`` (continuation), so every eigenvalue set belongs to a true
  steady motion.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, InfeasibleGlideError, ModelError, SolverError
from ..models.glider3d import FixedMassGlider3D
from ..params import Vehicle
from ..trim.helix import Helix, helix_eigenvalues, helix_equations, helix_trim, zeta_of
from .locus import ParameterLocus, parameter_locus

__all__ = ["HelixRbhLocus", "helix_rbh_locus", "mass_position_at_rbh", "resolved_crossing"]


@dataclass(frozen=True)
class HelixRbhLocus:
    """Eigenvalue locus of the 8-state reduced linearization versus ``r_bh``.

    Attributes
    ----------
    locus : ParameterLocus
        Branch-matched eigenvalues, stability crossings (Brent) and break points (bisection).
    nominal : Helix
        The steady motion at the nominal ``r_P``.
    frozen : bool
        Equilibrium frozen at the nominal one (True) or re-solved at every ``r_bh`` (False).
    residual : ndarray
        Max ``|(v', Omega')|`` of the state used at each ``r_bh`` (0 up to rounding when re-solved).
    """

    locus: ParameterLocus
    nominal: Helix
    frozen: bool
    residual: np.ndarray
    solutions: np.ndarray  # (n, 6) trim unknowns (v, psidot, theta, phi) used at each r_bh

    @property
    def branch_jumps(self) -> np.ndarray:
        """r_bh grid intervals (left ends) where the re-solved steady motion changes discontinuously (a step in the
        trim unknowns more than 10x the median of its ten neighbouring steps): the equilibrium branch folds or
        bifurcates there, so the continuation lands on another branch. Empty for the frozen locus."""
        if self.frozen or len(self.solutions) < 3:
            return np.empty(0)
        d = np.linalg.norm(np.diff(self.solutions, axis=0), axis=1)
        loc = np.array([np.median(np.r_[d[max(i - 5, 0):i], d[i + 1:i + 6]]) for i in range(d.size)])
        return self.locus.values[:-1][d > 10 * np.maximum(loc, 1e-12)]

    @property
    def crossings(self) -> tuple[float, ...]:
        """Stability crossings of the locus (m)."""
        return self.locus.crossings

    def plot(self, ax: Any = None, *, kind: str = "real", **kw: Any) -> Any:
        """Draw the locus in the glidectl style, the nominal ``r_bh`` marked.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        kind : {"real", "complex"}
            Real parts versus ``r_bh`` (Fig 8.13, default) or the root locus in the complex plane (Fig 8.14).
        **kw
            Passed to :func:`glidectl.plotting.plot_locus` (``zoom``) for ``kind="complex"``.

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_helix_rbh_locus`.
        """
        from ..plotting import plot_helix_rbh_locus, style

        with style():
            return plot_helix_rbh_locus(self, ax, kind=kind, **kw)


def mass_position_at_rbh(nominal: Helix, rbh: float) -> tuple[float, float, float]:
    """Moving-mass position (m) with bottom-heaviness ``rbh`` obtained by moving the mass of ``nominal`` along its
    gravity direction ``zeta_e`` (§8.3): ``r_P = r_P,nominal + (rbh - r_bh,nominal) zeta_e``.

    Parameters
    ----------
    nominal : Helix
        The steady motion whose ``r_P`` (m), ``r_bh`` (m) and ``zeta_e = zeta(theta, phi)`` are used.
    rbh : float
        Requested ``r_bh = r_P . zeta_e`` (m); the component of ``r_P`` perpendicular to ``zeta_e`` is kept.

    Returns
    -------
    tuple of 3 floats
        ``(r_P1, r_P2, r_P3)`` (m).

    Raises
    ------
    ArgumentTypeError
        If ``nominal`` is not a :class:`~glidectl.trim.helix.Helix` or ``rbh`` not a real number.
    ArgumentError
        If ``rbh`` is not finite.
    """
    if not isinstance(nominal, Helix):
        raise ArgumentTypeError(f"nominal must be a Helix from gc.helix_trim(...), got {type(nominal).__name__}")
    rbh = checks.real("rbh", rbh, unit="m")
    z = zeta_of(nominal.theta, nominal.phi)
    r = np.asarray(nominal.r_p) + (rbh - nominal.r_bh) * z
    return (float(r[0]), float(r[1]), float(r[2]))


def _helix_args(veh: Vehicle, r_p: Any, m0: Any) -> tuple[tuple[float, float, float], float]:
    checks.vehicle("veh", veh, "underwater_glider")
    r = checks.array("r_p (m)", r_p, shape=(3,))
    return (float(r[0]), float(r[1]), float(r[2])), checks.real("m0", m0, unit="kg")


def helix_rbh_locus(veh: Vehicle, r_p: Sequence[float], m0: float, rbh_values: Sequence[float], *,
                    frozen: bool = True, time_limit: float | None = None) -> HelixRbhLocus:
    """Eigenvalues of the reduced helix linearization versus bottom-heaviness ``r_bh`` (m), Fig 8.13-8.14.

    Parameters
    ----------
    veh : Vehicle
        3D glider (``slocum_ch8``).
    r_p : sequence of 3 floats
        Nominal moving-mass position (m); §8.3 uses (0.02, -0.02, 0.04).
    m0 : float
        Nominal buoyancy (kg); §8.3 uses 0.25.
    rbh_values : sequence of float
        Strictly increasing, finite ``r_bh`` values (m), at least 2.
    frozen : bool
        Keep the nominal steady motion (True) or re-solve it at every ``r_bh`` (False); see the module docstring.
    time_limit : float, optional
        Wall-time budget (s). Otherwise the work is one trim (re-solved) or one linearization (frozen) per value,
        plus the bounded refinements of :func:`~glidectl.analysis.locus.parameter_locus`.

    Returns
    -------
    HelixRbhLocus
        The eight eigenvalue branches (1/s) versus ``r_bh`` (m) with crossings and break points, the nominal helix,
        the residual ``max |(v', Omega')|`` (m/s^2, rad/s^2) of the state used at each ``r_bh`` and those states'
        trim unknowns (m/s, rad/s, rad).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``r_p``, ``m0`` or ``rbh_values`` are not real numbers, or ``frozen`` is not a
        bool.
    ArgumentError
        If ``r_p`` is not three finite numbers, ``m0`` is not finite, ``rbh_values`` is not a finite, strictly
        increasing grid of at least 2 points, or a moving-mass position is implausible (see the model).
    ModelError
        If ``veh`` is not a 3D underwater glider, or ``m0`` makes a body mass non-positive.
    InfeasibleGlideError
        If no steady motion is found at the nominal ``(r_p, m0)`` (or, when ``frozen=False``, at some ``r_bh``),
        or ``m0 = 0``.
    SolverError
        As in :func:`~glidectl.analysis.locus.parameter_locus`.
    BudgetError
        If ``time_limit`` is reached.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> hl = gc.helix_rbh_locus(slo, (0.02, -0.02, 0.04), 0.25, np.linspace(-0.02, 0.05, 15))
    >>> hl.nominal.stable, hl.locus.branches.shape
    (True, (15, 8))
    >>> print(f"frozen locus crosses at r_bh = {hl.locus.crossings[0] * 1000:.2f} mm")
    frozen locus crosses at r_bh = -7.01 mm
    """
    r_p, m0 = _helix_args(veh, r_p, m0)
    frozen = checks.boolean("frozen", frozen)
    vals = checks.array("rbh_values", rbh_values, ndim=1, min_size=2)
    if np.any(np.diff(vals) <= 0):
        raise ArgumentError(f"rbh_values must be a strictly increasing grid of >= 2 points (m), got {vals!r}")
    deadline = checks.Deadline(time_limit, "helix_rbh_locus")
    nominal = helix_trim(veh, r_p, m0)
    y_nom = nominal.unknowns
    cache: dict[float, tuple[np.ndarray, float, np.ndarray]] = {}
    solved: dict[float, Helix] = {nominal.r_bh: nominal}

    def state(rbh: float) -> tuple[np.ndarray, float, np.ndarray]:
        rbh = float(rbh)
        if rbh in cache:
            return cache[rbh]
        deadline.check(f"at r_bh = {rbh:g} m")
        rp = mass_position_at_rbh(nominal, rbh)
        model = FixedMassGlider3D(veh, rp, m0)
        if frozen:
            y = y_nom
        else:
            near = solved[min(solved, key=lambda r: abs(r - rbh))]  # warm start from the nearest solved point
            try:
                h = helix_trim(veh, rp, m0, guess=near, n_random=0)
            except InfeasibleGlideError:
                h = helix_trim(veh, rp, m0)
            solved[rbh] = h
            y = h.unknowns
        res = float(np.max(np.abs(helix_equations(model, y))))
        out = (helix_eigenvalues(model, y), res, np.asarray(y, float).copy())
        cache[rbh] = out
        return out

    order = np.argsort(np.abs(vals - nominal.r_bh))  # continue outwards from the nominal point
    for k in order if not frozen else range(vals.size):
        state(vals[k])
    loc = parameter_locus(lambda r: state(r)[0], vals, "r_bh", "m",
                          context={"vehicle": veh.name, "r_p_nominal": tuple(r_p), "m0": m0, "frozen": frozen},
                          vehicle=veh, time_limit=None if time_limit is None else max(
                              time_limit - deadline.elapsed, 1e-9))
    res = np.array([state(r)[1] for r in vals])
    return HelixRbhLocus(loc, nominal, frozen, res, np.array([state(r)[2] for r in vals]))


def resolved_crossing(veh: Vehicle, r_p: Sequence[float], m0: float, *, step: float = 5e-4,
                      stop: float = -0.05, max_steps: int = 10_000) -> tuple[float | None, Helix]:
    """Walk the re-solved helix branch from the nominal ``r_bh`` downwards in steps of ``step`` (m), warm-starting each
    trim from the previous one, and locate the first ``r_bh`` where the reduced linearization loses stability
    (bisection on the branch, to 1e-9 m). Returns ``(r_bh or None, the helix at the last stable point)``.

    Parameters
    ----------
    veh : Vehicle
        3D glider (``slocum_ch8``).
    r_p : sequence of float
        Nominal moving-mass position ``(r_P1, r_P2, r_P3)`` (m); the walk moves it along ``zeta_e``.
    m0 : float
        Net buoyancy (kg), nonzero.
    step : float
        Decrement of ``r_bh`` per continuation step (m), ``> 0``.
    stop : float
        Lowest ``r_bh`` visited (m), finite.
    max_steps : int
        Budget of continuation steps, ``>= 1``: ``(r_bh,nominal - stop) / step`` may not exceed it (checked before
        the walk). The bisection takes at most 200 more trims.

    Returns
    -------
    r_bh : float or None
        Bottom-heaviness (m) where the stability of the branch changes, or None if it does not change down to
        ``stop``.
    helix : Helix
        The helix on the stable side of the crossing (or the last one visited when there is none).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``r_p``, ``m0``, ``step`` or ``stop`` are not real numbers, or ``max_steps``
        is not an integer.
    ArgumentError
        If a value is not finite, ``step <= 0`` or ``max_steps < 1``, or a moving-mass position is implausible.
    ModelError
        If ``veh`` is not a 3D underwater glider, ``m0`` makes a body mass non-positive, or the nominal helix is
        not stable (the walk looks for where a stable branch loses stability; start from a stable helix, e.g. a
        larger ``r_bh``).
    InfeasibleGlideError
        If the nominal helix or a continuation step cannot be trimmed, or ``m0 = 0``.
    SolverError
        If stability changes without an eigenvalue crossing zero (the branch folds or jumps; retry with a smaller
        ``step``).
    BudgetError
        If the walk would take more than ``max_steps`` steps.

    Examples
    --------
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> r_bh, h = gc.resolved_crossing(slo, (0.02, -0.02, 0.04), 0.25)
    >>> print(f"stability lost at r_bh = {r_bh * 1000:.2f} mm; helix above it stable: {h.stable}")
    stability lost at r_bh = -27.31 mm; helix above it stable: True
    """
    r_p, m0 = _helix_args(veh, r_p, m0)
    step = checks.positive("step", step, unit="m")
    stop = checks.real("stop", stop, unit="m")
    max_steps = checks.integer("max_steps", max_steps, lo=1)
    nominal = helix_trim(veh, r_p, m0)
    if not nominal.stable:
        raise ModelError(f"the nominal helix at r_p = {r_p} m, m0 = {m0:g} kg is not stable (max Re(lambda) = "
                         f"{float(np.max(nominal.eigenvalues.real)):.3g} 1/s): resolved_crossing walks a stable branch "
                         "down to where it loses stability; start from a stable helix (e.g. a larger r_bh)")
    n_steps = (nominal.r_bh - stop) / step
    if n_steps > max_steps:
        raise BudgetError(f"walking r_bh from {nominal.r_bh:.6g} m down to stop = {stop:g} m in steps of {step:g} m "
                          f"takes {n_steps:.3g} steps, above max_steps = {max_steps}; raise step or stop, or "
                          "max_steps")
    h = nominal
    r = nominal.r_bh
    while r - step >= stop:
        r_new = r - step
        h_new = helix_trim(veh, mass_position_at_rbh(nominal, r_new), m0, guess=h, n_random=0, continuation_steps=1)
        if h_new.stable != h.stable:
            lo, hi, h_lo = r_new, r, h  # unstable at lo, stable at hi
            for _ in range(200):  # bounded: halves the bracket until 1e-9 m or floating-point resolution
                mid = 0.5 * (lo + hi)
                if hi - lo <= 1e-9 or not lo < mid < hi:
                    break
                hm = helix_trim(veh, mass_position_at_rbh(nominal, mid), m0, guess=h_lo, n_random=0,
                                continuation_steps=1)
                if hm.stable:
                    hi, h_lo = mid, hm
                else:
                    lo = mid
            if abs(float(np.max(h_lo.eigenvalues.real))) > 1e-5:
                raise SolverError(
                    f"the re-solved helix branch jumps near r_bh = {0.5 * (lo + hi):.6g} m (stability changes without "
                    "an eigenvalue crossing zero: a fold of the equilibrium branch); retry with a smaller step")
            return 0.5 * (lo + hi), h_lo
        h, r = h_new, r_new
    return None, h
