"""Steady three-dimensional motions of the underwater glider, chapter 8: relative equilibria (Theorem 7), circular
helices and straight glides with the moving mass fixed at ``r_P`` and constant buoyancy ``m0``.

A steady motion has constant ``v``, ``Omega`` and ``zeta = R^T k = (-sin theta, cos theta sin phi, cos theta cos phi)``
(8.27), and ``Omega`` parallel to ``zeta`` (8.31): ``Omega = psidot zeta``. The trim solves the six equations
``(v', Omega') = 0`` of (8.23) for ``(v1, v2, v3, psidot, theta, phi)`` with Newton's method (exact complex-step
Jacobian, :func:`scipy.optimize.root`). Starting values come from the straight glide of the longitudinal
projection (``r_P2 = 0``, found by bracketing the moment balance over the angle of attack) followed by continuation
in ``r_P2`` to the requested value, or from a previous solution (warm start).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq, root

from ..analysis.jacobian import jacobians
from ..errors import InfeasibleGlideError, ModelError
from ..models.glider3d import FixedMassGlider3D, ypr_to_quat
from ..params import Vehicle

__all__ = [
    "Helix",
    "classify_motion",
    "helix_eigenvalues",
    "helix_equations",
    "helix_newton",
    "helix_trim",
    "reduced_rhs",
    "zeta_of",
]

_RES_TOL = 1e-10


def zeta_of(theta: Any, phi: Any) -> Any:
    """Body-frame gravity direction ``R^T k`` (8.27)."""
    return np.stack([-np.sin(theta), np.cos(theta) * np.sin(phi), np.cos(theta) * np.cos(phi)], -1)


def classify_motion(v: Any, Omega: Any, tol: float = 1e-9) -> dict[str, Any]:
    """Relative equilibrium type of a constant ``(v, Omega)`` pair, Theorem 7, with curvature (8.18) and torsion
    (8.22).

    Parameters
    ----------
    v : array (3,)
        Body-frame velocity (m/s).
    Omega : array (3,)
        Body-frame angular velocity (rad/s).
    tol : float
        ``|Omega| <= tol`` (rad/s) is a straight line, ``|v| <= tol`` (m/s) a pure rotation, and ``|sin xi| <= tol``
        (dimensionless, relative) a screw motion (``v`` parallel to ``Omega``).

    Returns
    -------
    dict
        ``{"kind": "straight line" | "pure rotation" | "screw" | "helix", "curvature", "torsion", "xi"}`` with
        curvature and torsion in 1/m (``nan`` where undefined) and ``xi`` the angle between ``Omega`` and ``v``
        (rad).

    Raises
    ------
    ModelError
        If ``v`` or ``Omega`` is not three finite numbers.
    """
    v, Om = np.asarray(v, float), np.asarray(Omega, float)
    if v.shape != (3,) or Om.shape != (3,) or not (np.all(np.isfinite(v)) and np.all(np.isfinite(Om))):
        raise ModelError(f"v and Omega must be three finite numbers each, got {v!r}, {Om!r}")
    V, W = float(np.linalg.norm(v)), float(np.linalg.norm(Om))
    if W <= tol:
        return {"kind": "straight line", "curvature": 0.0, "torsion": 0.0, "xi": float("nan")}
    if V <= tol:
        return {"kind": "pure rotation", "curvature": float("nan"), "torsion": float("nan"), "xi": float("nan")}
    xi = math.acos(float(np.clip(np.dot(v, Om) / (V * W), -1, 1)))
    kappa, tau = W / V * abs(math.sin(xi)), W / V * math.cos(xi)
    kind = "screw" if abs(math.sin(xi)) <= tol else "helix"
    return {"kind": kind, "curvature": kappa, "torsion": tau, "xi": xi}


def reduced_rhs(model: FixedMassGlider3D, s: Any) -> Any:
    """Reduced dynamics with position and yaw dropped: ``s = (v, Omega, theta, phi)`` (8 states), ``(theta, phi)``
    from (8.28)."""
    s = np.asarray(s)
    v, Om, th, ph = s[..., 0:3], s[..., 3:6], s[..., 6], s[..., 7]
    vd, Od = model.accelerations(v, Om, zeta_of(th, ph))
    O1, O2, O3 = Om[..., 0], Om[..., 1], Om[..., 2]
    thd = O2 * np.cos(ph) - O3 * np.sin(ph)
    phd = O1 + (O2 * np.sin(ph) + O3 * np.cos(ph)) * np.tan(th)
    return np.concatenate([vd, Od, thd[..., None], phd[..., None]], -1)


@dataclass(frozen=True, eq=False)
class Helix:
    """A steady motion (circular helix, or straight glide when ``psidot = 0``) of the fixed-mass glider.

    All quantities are in SI units, angles in radians.

    Attributes
    ----------
    r_p, m0 : tuple of float, float
        Control parameters: moving-mass position (m) and net buoyancy (kg).
    v, Omega : ndarray, shape (3,)
        Body velocity (m/s) and angular velocity (rad/s), ``Omega = psidot zeta``.
    theta, phi, psidot : float
        Pitch, roll (rad) and yaw rate (rad/s), (8.26)-(8.29).
    speed, alpha, beta, gamma : float
        ``|v|`` (m/s), angle of attack, sideslip, flight-path angle (``-asin(zeta . v / V)``, positive up) (rad).
    vertical_speed : float
        Sink rate ``zeta . v`` (m/s, positive downwards).
    radius, pitch, period : float
        Helix radius (m), drop per turn (m, positive downwards) and period (s); ``inf`` for a straight glide.
    curvature, torsion : float
        (8.18), (8.22) (1/m).
    r_bh : float
        Bottom-heaviness ``r_P . zeta`` (m).
    residual : float
        max ``|(v', Omega')|`` at the solution (m/s^2 and rad/s^2 mixed).
    eigenvalues : ndarray of complex
        Of the 8-state reduced linearization (position and yaw dropped), sorted by real part (1/s).
    stable : bool
        All eigenvalues have negative real part.
    vehicle : Vehicle
        The vehicle.
    provenance : str
        Its parameter hash.
    model : FixedMassGlider3D or None
        The model the motion was trimmed on.
    """

    r_p: tuple[float, float, float]
    m0: float
    v: np.ndarray
    Omega: np.ndarray
    theta: float
    phi: float
    psidot: float
    residual: float
    eigenvalues: np.ndarray = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""
    model: FixedMassGlider3D | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("v", "Omega", "eigenvalues"):
            a = np.array(getattr(self, name))
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def unknowns(self) -> np.ndarray:
        """``(v1, v2, v3, psidot, theta, phi)``: the trim unknowns (warm start for neighbours)."""
        return np.r_[self.v, self.psidot, self.theta, self.phi]

    @property
    def zeta(self) -> np.ndarray:
        return zeta_of(self.theta, self.phi)

    @property
    def speed(self) -> float:
        return float(np.linalg.norm(self.v))

    @property
    def alpha(self) -> float:
        return float(math.atan2(self.v[2], self.v[0]))

    @property
    def beta(self) -> float:
        return float(math.asin(self.v[1] / self.speed))

    @property
    def vertical_speed(self) -> float:
        """Sink rate ``zeta . v`` (m/s, positive downwards)."""
        return float(np.dot(self.zeta, self.v))

    @property
    def gamma(self) -> float:
        """Flight-path angle (rad, positive up)."""
        return float(-math.asin(np.clip(self.vertical_speed / self.speed, -1, 1)))

    @property
    def is_straight(self) -> bool:
        return abs(self.psidot) < 1e-12

    @property
    def period(self) -> float:
        return float("inf") if self.is_straight else 2 * math.pi / abs(self.psidot)

    @property
    def radius(self) -> float:
        vh = math.sqrt(max(self.speed**2 - self.vertical_speed**2, 0.0))
        return float("inf") if self.is_straight else vh / abs(self.psidot)

    @property
    def pitch(self) -> float:
        return float("inf") if self.is_straight else self.vertical_speed * self.period

    @property
    def curvature(self) -> float:
        return float(classify_motion(self.v, self.Omega)["curvature"])

    @property
    def torsion(self) -> float:
        return float(classify_motion(self.v, self.Omega)["torsion"])

    @property
    def r_bh(self) -> float:
        return float(np.dot(self.r_p, self.zeta))

    @property
    def stable(self) -> bool:
        return bool(np.max(self.eigenvalues.real) < 0)

    def initial_state(self, psi: float = 0.0, position: Any = (0.0, 0.0, 0.0)) -> np.ndarray:
        """13-state ``(x, y, z, q, v, Omega)`` of :class:`FixedMassGlider3D` on this motion."""
        return np.r_[np.asarray(position, float), ypr_to_quat(psi, self.theta, self.phi), self.v, self.Omega]

    def as_dict(self) -> dict[str, float]:
        return {"r_P1": self.r_p[0], "r_P2": self.r_p[1], "r_P3": self.r_p[2], "m0": self.m0, "speed": self.speed,
                "radius": self.radius, "pitch": self.pitch, "period": self.period, "alpha": self.alpha,
                "beta": self.beta, "theta": self.theta, "phi": self.phi, "gamma": self.gamma,
                "psidot": self.psidot, "Omega_norm": float(np.linalg.norm(self.Omega)), "r_bh": self.r_bh,
                "residual": self.residual, "max_re_eig": float(np.max(self.eigenvalues.real))}


def helix_equations(model: FixedMassGlider3D, y: Any) -> Any:
    """Residual ``(v', Omega')`` of (8.23)-(8.25) on the steady-motion ansatz ``Omega = psidot zeta`` (8.31).

    Parameters
    ----------
    model : FixedMassGlider3D
        The glider with its moving mass fixed at ``r_P`` (m) and buoyancy ``m0`` (kg).
    y : array_like, shape (..., 6)
        Trim unknowns ``(v1, v2, v3, psidot, theta, phi)``: body velocity (m/s), yaw rate (rad/s), pitch and roll
        (rad); may be complex (complex-step Jacobians).

    Returns
    -------
    ndarray, shape (..., 6)
        ``(v1', v2', v3')`` (m/s^2) and ``(Omega1', Omega2', Omega3')`` (rad/s^2); zero at a steady helix or glide.
    """
    y = np.asarray(y)
    v, w, th, ph = y[..., 0:3], y[..., 3], y[..., 4], y[..., 5]
    z = zeta_of(th, ph)
    vd, Od = model.accelerations(v, w[..., None] * z, z)
    return np.concatenate([vd, Od], -1)


def helix_newton(model: FixedMassGlider3D, y0: np.ndarray) -> tuple[np.ndarray, float, bool]:
    """Newton solve of :func:`helix_equations` ``= 0`` from one start (MINPACK ``hybr``, exact complex-step
    Jacobian, ``xtol = 1e-13``).

    Parameters
    ----------
    model : FixedMassGlider3D
        The glider at fixed ``r_P`` (m) and ``m0`` (kg).
    y0 : ndarray, shape (6,)
        Start ``(v1, v2, v3, psidot, theta, phi)`` (m/s, rad/s, rad).

    Returns
    -------
    y : ndarray, shape (6,)
        Final iterate (the start itself if the solver raised).
    residual : float
        ``max |helix_equations(model, y)|`` (m/s^2, rad/s^2); ``inf`` for a non-finite iterate.
    ok : bool
        Converged to a forward-gliding upright-pitch motion: ``residual < 1e-10``, ``v1 > 0`` and
        ``|theta| < pi/2``.
    """

    def fun(y: np.ndarray) -> np.ndarray:
        return np.asarray(helix_equations(model, y), float)

    def jac(y: np.ndarray) -> np.ndarray:
        return jacobians(lambda yy, u: helix_equations(model, yy), y, np.zeros(0))[0]

    with np.errstate(all="ignore"):
        try:
            sol = root(fun, y0, jac=jac, method="hybr", options={"xtol": 1e-13})
        except (ValueError, FloatingPointError):
            return y0, float("inf"), False
    y = sol.x
    res = float(np.max(np.abs(fun(y)))) if np.all(np.isfinite(y)) else float("inf")
    ok = bool(np.isfinite(res) and res < _RES_TOL and y[0] > 0 and abs(y[4]) < math.pi / 2)
    return y, res, ok


def _straight_guesses(veh: Vehicle, r_p: np.ndarray, m0: float) -> list[np.ndarray]:
    """Straight longitudinal glides for ``(r_P1, 0, r_P3)``: roots in alpha of the pitch-moment balance, with V and
    gamma from the force balance (lift and drag balance the net weight m0 g)."""
    KL0, KL, KD0, KD = veh.K_L0, veh.K_L, veh.K_D0, veh.K_D
    g, mbar = veh.g, veh.mbar
    m1, m3 = veh.mass(1, m0), veh.mass(3, m0)

    def glide(a: float) -> tuple[float, float, float] | None:
        CL, CD = KL0 + KL * a, KD0 + KD * a * a
        if m0 * CL <= 0:
            return None
        gam = math.atan2(-CD / m0, CL / m0)
        V = math.sqrt(abs(m0) * g / math.hypot(CD, CL))
        return V, gam, gam + a

    def moment(a: float) -> float:
        gl = glide(a)
        if gl is None:
            return float("nan")
        V, _, th = gl
        v1, v3 = V * math.cos(a), V * math.sin(a)
        M = (veh.K_M0 + veh.K_M * a) * V * V
        # fixed r_P, Omega = 0: (8.25) moment about body-2 (the mass matrix does not matter at rest)
        return (m3 - m1) * v1 * v3 - mbar * g * (r_p[0] * math.cos(th) + r_p[2] * math.sin(th)) + M

    grid = np.linspace(-0.7, 0.7, 281)
    vals = np.array([moment(a) for a in grid])
    out = []
    for i in range(grid.size - 1):
        a, b = vals[i], vals[i + 1]
        if np.isfinite(a) and np.isfinite(b) and a * b < 0:
            al = brentq(moment, grid[i], grid[i + 1], xtol=1e-14)
            V, _, th = glide(al)  # type: ignore[misc]
            out.append(np.array([V * math.cos(al), 0.0, V * math.sin(al), 0.0, th, 0.0]))
    return out


def helix_eigenvalues(model: FixedMassGlider3D, y: np.ndarray) -> np.ndarray:
    """Eigenvalues (1/s) of the 8-state reduced dynamics :func:`reduced_rhs` linearized at a steady motion.

    Parameters
    ----------
    model : FixedMassGlider3D
        The glider at fixed ``r_P`` (m) and ``m0`` (kg).
    y : ndarray, shape (6,)
        Trim unknowns ``(v1, v2, v3, psidot, theta, phi)`` (m/s, rad/s, rad) of the motion; the reduced state is
        ``(v, psidot zeta(theta, phi), theta, phi)``. The point need not be an exact equilibrium (the frozen locus
        of :func:`glidectl.analysis.helix_stability.helix_rbh_locus` evaluates it off the equilibrium).

    Returns
    -------
    ndarray, shape (8,)
        Sorted by real part, then imaginary part (exact complex-step Jacobian).
    """
    v, w, th, ph = y[0:3], y[3], y[4], y[5]
    s = np.r_[v, w * zeta_of(th, ph), th, ph]
    A, _ = jacobians(lambda ss, u: reduced_rhs(model, ss), s, np.zeros(0))
    lam = np.linalg.eigvals(A)
    return lam[np.lexsort((lam.imag, lam.real))]


def helix_trim(veh: Vehicle, r_p: Any = None, m0: float | None = None, *, guess: Any = None,
               continuation_steps: int = 12, n_random: int = 40, seed: int = 0) -> Helix:
    """Steady helix (or straight glide) of ``veh`` with the moving mass at ``r_p`` (m) and buoyancy ``m0`` (kg).

    Solves ``(v', Omega') = 0`` of (8.23)-(8.25) with ``Omega = psidot zeta`` (8.31) for
    ``(v1, v2, v3, psidot, theta, phi)``; the residual is checked (``< 1e-10``).

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (e.g. ``slocum_ch8``).
    r_p : (3,) array, optional
        Moving-mass position in body axes (m); defaults to the vehicle file's ``r_P1, r_P2, r_P3``.
    m0 : float, optional
        Net buoyancy (kg, positive heavy: descent); defaults to the file's ``m0``. ``m0 = 0`` has no glide.
    guess : Helix or array (v1, v2, v3, psidot, theta, phi), optional
        Warm start (continuation). Without it (or if it fails) the longitudinal straight glide is continued in
        ``r_P2`` over ``continuation_steps`` steps; if that fails, ``n_random`` random starting points are tried.
    continuation_steps : int
        Number of ``r_P2`` continuation steps (>= 1).
    n_random : int
        Random restarts as the last resort (>= 0); ``seed`` seeds them.

    Returns
    -------
    Helix
        Radius, pitch, period, speed, angles and the eigenvalues of the 8-state reduced linearization.

    Raises
    ------
    ModelError
        ``r_p`` not three finite numbers, ``m0`` not finite or making a mass non-positive, bad solver options.
    InfeasibleGlideError
        ``m0 = 0``, or no steady motion found (the message says what was tried).
    """
    if r_p is None:
        r_p = (veh.r_P1, veh.r_P2, veh.r_P3)
    if m0 is None:
        m0 = veh.m0
    try:
        r = np.asarray(r_p, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"r_p must be three finite numbers in m, got {r_p!r}") from exc
    if r.shape != (3,) or not np.all(np.isfinite(r)):
        raise ModelError(f"r_p must be three finite numbers in m, got {r_p!r}")
    try:
        m0 = float(m0)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"m0 must be a finite number in kg, got {m0!r}") from exc
    if not math.isfinite(m0):
        raise ModelError(f"m0 must be a finite number in kg, got {m0!r}")
    if m0 == 0:
        raise InfeasibleGlideError("m0 = 0: a neutrally buoyant glider has no steady glide (no net weight to balance "
                                   "drag); use m0 != 0")
    if int(continuation_steps) != continuation_steps or continuation_steps < 1:
        raise ModelError(f"continuation_steps must be an integer >= 1, got {continuation_steps!r}")
    if int(n_random) != n_random or n_random < 0:
        raise ModelError(f"n_random must be an integer >= 0, got {n_random!r}")
    model = FixedMassGlider3D(veh, (float(r[0]), float(r[1]), float(r[2])), m0)
    tried: list[str] = []
    y = None
    if guess is not None:
        y0 = guess.unknowns if isinstance(guess, Helix) else np.asarray(guess, float)
        if y0.shape != (6,) or not np.all(np.isfinite(y0)):
            raise ModelError(f"guess must be a Helix or six finite numbers (v1, v2, v3, psidot, theta, phi), got "
                             f"{guess!r}")
        y1, res, ok = helix_newton(model, y0)
        tried.append("warm start")
        if ok:
            y = y1
    if y is None:
        starts = _straight_guesses(veh, r, m0)
        tried.append(f"{len(starts)} longitudinal straight glide(s) continued in r_P2")
        for y0 in starts:
            yk = y0
            ok = True
            for k in range(1, continuation_steps + 1):
                rk = (r[0], r[1] * k / continuation_steps, r[2])
                yk, res, ok = helix_newton(FixedMassGlider3D(veh, rk, m0), yk)
                if not ok:
                    break
            if ok:
                y = yk
                break
    if y is None and n_random > 0:
        rng = np.random.default_rng(seed)
        tried.append(f"{n_random} random starts")
        for _ in range(n_random):
            V = rng.uniform(0.1, 1.5)
            a, b = rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)
            y0 = np.array([V * math.cos(a) * math.cos(b), V * math.sin(b), V * math.sin(a) * math.cos(b),
                           rng.uniform(-0.05, 0.05), rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2)])
            y1, res, ok = helix_newton(model, y0)
            if ok:
                y = y1
                break
    if y is None:
        raise InfeasibleGlideError(
            f"no steady helix or glide found for r_P = {tuple(np.round(r, 5))} m, m0 = {m0:g} kg on vehicle "
            f"'{veh.name}' (tried: {'; '.join(tried)}). Try a warm start from a nearby solution "
            "(glidectl.helix_sweep continues along a parameter) or more random starts")
    res = float(np.max(np.abs(helix_equations(model, y))))
    if abs(y[3]) < 1e-13:
        y = y.copy()
        y[3] = 0.0
    z = zeta_of(y[4], y[5])
    return Helix((float(r[0]), float(r[1]), float(r[2])), m0, y[0:3].copy(), y[3] * z, float(y[4]), float(y[5]),
                 float(y[3]), res, helix_eigenvalues(model, y), veh, veh.provenance, model)
