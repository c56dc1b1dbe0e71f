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

from ..errors import InfeasibleGlideError, SolverError
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
    """
    z = zeta_of(nominal.theta, nominal.phi)
    r = np.asarray(nominal.r_p) + (rbh - nominal.r_bh) * z
    return (float(r[0]), float(r[1]), float(r[2]))


def helix_rbh_locus(veh: Vehicle, r_p: Sequence[float], m0: float, rbh_values: Sequence[float], *,
                    frozen: bool = True) -> HelixRbhLocus:
    """Eigenvalues of the reduced helix linearization versus bottom-heaviness ``r_bh`` (m), Fig 8.13-8.14.

    Parameters
    ----------
    veh : Vehicle
        3D glider (``slocum_ch8``).
    r_p, m0 : nominal moving-mass position (m) and buoyancy (kg); §8.3 uses (0.02, -0.02, 0.04), 0.25.
    rbh_values : increasing r_bh values (m).
    frozen : see the module docstring.

    Returns
    -------
    HelixRbhLocus
        The eight eigenvalue branches (1/s) versus ``r_bh`` (m) with crossings and break points, the nominal helix,
        the residual ``max |(v', Omega')|`` (m/s^2, rad/s^2) of the state used at each ``r_bh`` and those states'
        trim unknowns (m/s, rad/s, rad).

    Raises
    ------
    ModelError
        If ``veh`` lacks the 3D parameters, ``r_p`` is not three finite numbers, or ``m0`` is not finite or makes a
        body mass non-positive (from :func:`~glidectl.trim.helix.helix_trim` and the model).
    InfeasibleGlideError
        If no steady motion is found at the nominal ``(r_p, m0)`` (or, when ``frozen=False``, at some ``r_bh``),
        or ``m0 = 0``.
    GlidectlError
        If ``rbh_values`` is not a strictly increasing grid of at least 2 points (from
        :func:`~glidectl.analysis.locus.parameter_locus`).
    SolverError
        As in :func:`~glidectl.analysis.locus.parameter_locus`.
    """
    nominal = helix_trim(veh, r_p, m0)
    y_nom = nominal.unknowns
    vals = np.asarray(rbh_values, dtype=float)
    cache: dict[float, tuple[np.ndarray, float, np.ndarray]] = {}
    solved: dict[float, Helix] = {nominal.r_bh: nominal}

    def state(rbh: float) -> tuple[np.ndarray, float, np.ndarray]:
        rbh = float(rbh)
        if rbh in cache:
            return cache[rbh]
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
                          vehicle=veh)
    res = np.array([state(r)[1] for r in vals])
    return HelixRbhLocus(loc, nominal, frozen, res, np.array([state(r)[2] for r in vals]))


def resolved_crossing(veh: Vehicle, r_p: Sequence[float], m0: float, *, step: float = 5e-4,
                      stop: float = -0.05) -> tuple[float | None, Helix]:
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
        Lowest ``r_bh`` visited (m).

    Returns
    -------
    r_bh : float or None
        Bottom-heaviness (m) where the stability of the branch changes, or None if it does not change down to
        ``stop``.
    helix : Helix
        The helix on the stable side of the crossing (or the last one visited when there is none).

    Raises
    ------
    ModelError
        If ``veh`` lacks the 3D parameters, ``r_p`` is not three finite numbers, or ``m0`` is not finite or makes a
        body mass non-positive.
    InfeasibleGlideError
        If the nominal helix or a continuation step cannot be trimmed, or ``m0 = 0``.
    SolverError
        If stability changes without an eigenvalue crossing zero (the branch folds or jumps; retry with a smaller
        ``step``).

    Notes
    -----
    The bisection assumes the nominal helix is stable (stable above, unstable below the crossing); the nominal
    stability is not checked.
    """
    nominal = helix_trim(veh, r_p, m0)
    h = nominal
    r = nominal.r_bh
    while r - step >= stop:
        r_new = r - step
        h_new = helix_trim(veh, mass_position_at_rbh(nominal, r_new), m0, guess=h, n_random=0, continuation_steps=1)
        if h_new.stable != h.stable:
            lo, hi, h_lo = r_new, r, h  # unstable at lo, stable at hi
            while hi - lo > 1e-9:
                mid = 0.5 * (lo + hi)
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
