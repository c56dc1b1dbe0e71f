"""Steady three-dimensional motions of the underwater glider, chapter 8: relative equilibria (Theorem 7), circular
helices and straight glides with the moving mass fixed at ``r_P`` and constant buoyancy ``m0``.

A steady motion has constant ``v``, ``Omega`` and ``zeta = R^T k = (-sin theta, cos theta sin phi, cos theta cos phi)``
(8.27), and ``Omega`` parallel to ``zeta`` (8.31): ``Omega = psidot zeta``. The trim solves the six equations
``(v', Omega') = 0`` of (8.23) for ``(v1, v2, v3, psidot, theta, phi)`` with Newton's method (exact complex-step
Jacobian, :func:`scipy.optimize.root`). Starting values come from the straight glide of the longitudinal
projection (``r_P2 = 0``, found by bracketing the moment balance over the angle of attack) followed by continuation
in ``r_P2`` to the requested value, or from a previous solution (warm start).

Acceptance: a Newton iterate counts as a steady motion only if the residual of the force and of the moment
equations (8.24)-(8.25) is below :data:`RESIDUAL_TOL` relative to the largest term of that equation (net weight,
hydrodynamic force, inertial coupling; gravity moment of the moving mass, hydrodynamic moment, ...). An absolute
tolerance would accept a near-standstill that is no equilibrium when the forces are tiny (``m0 = 1e-300``).

Budgets: :func:`helix_trim` runs at most ``1 + starts * continuation_steps + n_random`` Newton solves (the starts are
the roots of the longitudinal moment balance, at most a few), with ``continuation_steps <=``
:data:`MAX_CONTINUATION_STEPS` and ``n_random <=`` :data:`MAX_RANDOM_STARTS`; each Newton solve is MINPACK ``hybr``
with its default limit of ``200 (n + 1) = 1400`` residual evaluations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq, root

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError, SolverError
from ..hydro import lift_drag, loads_3d
from ..models.glider3d import R_P_MAX, FixedMassGlider3D, ypr_to_quat
from ..params import Vehicle

__all__ = [
    "MAX_CONTINUATION_STEPS",
    "MAX_RANDOM_STARTS",
    "RESIDUAL_TOL",
    "Helix",
    "classify_motion",
    "helix_eigenvalues",
    "helix_equations",
    "helix_newton",
    "helix_trim",
    "reduced_rhs",
    "zeta_of",
]

#: Largest residual of the force or moment equations relative to their largest term, for a converged trim.
RESIDUAL_TOL = 1e-10
#: Budget: largest ``continuation_steps`` of :func:`helix_trim`.
MAX_CONTINUATION_STEPS = 1000
#: Budget: largest ``n_random`` of :func:`helix_trim`.
MAX_RANDOM_STARTS = 1000


def _trailing(name: str, value: Any, n: int) -> np.ndarray:
    a = checks.numeric(name, value)
    if a.ndim == 0 or a.shape[-1] != n:
        raise ArgumentError(f"{name} must have a trailing dimension {n}, got shape {a.shape}")
    return a


def _model(model: Any) -> FixedMassGlider3D:
    if not isinstance(model, FixedMassGlider3D):
        raise ArgumentTypeError(f"model must be a FixedMassGlider3D (the glider with its moving mass fixed), got "
                                f"{type(model).__name__}")
    return model


def zeta_of(theta: Any, phi: Any) -> Any:
    """Body-frame gravity direction ``R^T k`` (8.27).

    Parameters
    ----------
    theta, phi : array_like
        Pitch and roll (rad), real or complex, broadcast together.

    Returns
    -------
    ndarray, shape (..., 3)
        ``(-sin theta, cos theta sin phi, cos theta cos phi)``.

    Raises
    ------
    ArgumentTypeError
        If ``theta`` or ``phi`` is not a number or an array of numbers.
    ArgumentError
        If their shapes do not broadcast.
    """
    theta, phi = checks.numeric("theta", theta), checks.numeric("phi", phi)
    try:
        np.broadcast_shapes(theta.shape, phi.shape)
    except ValueError as exc:
        raise ArgumentError(f"theta and phi must broadcast together, got shapes {theta.shape} and "
                            f"{phi.shape}") from exc
    return np.stack(np.broadcast_arrays(-np.sin(theta), np.cos(theta) * np.sin(phi), np.cos(theta) * np.cos(phi)),
                    -1)


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
        (dimensionless, relative) a screw motion (``v`` parallel to ``Omega``); finite, ``>= 0``.

    Returns
    -------
    dict
        ``{"kind": "straight line" | "pure rotation" | "screw" | "helix", "curvature", "torsion", "xi"}`` with
        curvature and torsion in 1/m (``nan`` where undefined) and ``xi`` the angle between ``Omega`` and ``v``
        (rad).

    Raises
    ------
    ArgumentTypeError
        If ``v`` or ``Omega`` is not an array of real numbers, or ``tol`` not a real number.
    ArgumentError
        If ``v`` or ``Omega`` is not three finite numbers, or ``tol`` is negative or not finite.

    Examples
    --------
    >>> import glidectl as gc
    >>> c = gc.classify_motion([1.0, 0.0, 0.2], [0.0, 0.0, 0.1])  # v (m/s), Omega (rad/s)
    >>> print(c["kind"], round(c["curvature"], 4), round(c["torsion"], 4))
    helix 0.0962 0.0192
    >>> gc.classify_motion([1.0, 0.0, 0.0], [0.0, 0.0, 0.0])["kind"]
    'straight line'
    """
    v = checks.array("v (body velocity, m/s)", v, shape=(3,))
    Om = checks.array("Omega (body angular velocity, rad/s)", Omega, shape=(3,))
    tol = checks.nonnegative("tol", tol)
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
    from (8.28).

    Parameters
    ----------
    model : FixedMassGlider3D
        The glider at fixed ``r_P`` (m) and ``m0`` (kg).
    s : array_like, shape (..., 8)
        Reduced states ``(v (m/s), Omega (rad/s), theta, phi (rad))``, real or complex.

    Returns
    -------
    ndarray, shape (..., 8)
        Their time derivative.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a FixedMassGlider3D or ``s`` not an array of numbers.
    ArgumentError
        If ``s`` does not have a trailing dimension 8.
    """
    _model(model)
    s = _trailing("s", s, 8)
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
    relative_residual : float
        Residual of the force and moment equations relative to their largest term (below :data:`RESIDUAL_TOL`).
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
    relative_residual: float = 0.0

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
        """Sink rate ``zeta·v`` (m/s, positive downwards)."""
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
        """13-state ``(x, y, z, q, v, Omega)`` of :class:`FixedMassGlider3D` on this motion.

        Parameters
        ----------
        psi : float
            Initial yaw (rad), finite.
        position : array_like, shape (3,)
            Initial position (m), finite.

        Returns
        -------
        ndarray, shape (13,)

        Raises
        ------
        ArgumentTypeError
            If ``psi`` is not a real number or ``position`` not an array of real numbers.
        ArgumentError
            If they are not finite or ``position`` is not three numbers.
        """
        psi = checks.real("psi", psi, unit="rad")
        pos = checks.array("position", position, shape=(3,))
        return np.r_[pos, ypr_to_quat(psi, self.theta, self.phi), self.v, self.Omega]

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

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a FixedMassGlider3D or ``y`` not an array of numbers.
    ArgumentError
        If ``y`` does not have a trailing dimension 6.
    """
    _model(model)
    y = _trailing("y", y, 6)
    v, w, th, ph = y[..., 0:3], y[..., 3], y[..., 4], y[..., 5]
    z = zeta_of(th, ph)
    vd, Od = model.accelerations(v, w[..., None] * z, z)
    return np.concatenate([vd, Od], -1)


def _relative_residual(model: FixedMassGlider3D, y: np.ndarray) -> float:
    """Residual of the force and moment equations (8.24)-(8.25) at ``y``, relative to their largest term.

    ``max(|Fbar'| / F_scale, |Tbar'| / T_scale)`` where ``F_scale`` is the largest of ``|m0| g``, the hydrodynamic
    force and the inertial coupling ``|(M v + mbar w) x Omega|``, and ``T_scale`` the largest of the moment terms
    (gyroscopic, ``v x M v``, moving-mass coupling, gravity moment ``mbar g r_P x zeta``, hydrodynamic moment).
    """
    veh = model.vehicle
    y = np.asarray(y, float)
    v, w, th, ph = y[0:3], y[3], y[4], y[5]
    z = zeta_of(th, ph)
    Om = w * z
    with np.errstate(all="ignore"):
        Fp, Tp = model.forces(v, Om, z)
        F, T, _, _, _ = loads_3d(veh, v, Om)
        rP = np.asarray(model.r_p, float)
        M = np.array([veh.mass(i, model.m0) for i in (1, 2, 3)], float)
        J = np.array([veh.J1, veh.J2, veh.J3], float)
        mbar, g = veh.mbar, veh.g
        wv = v + np.cross(Om, rP)
        nrm = np.linalg.norm
        f_scale = max(abs(model.m0) * g, nrm(F), nrm(np.cross(M * v + mbar * wv, Om)))
        t_scale = max(nrm(T), nrm(np.cross(J * Om + mbar * np.cross(rP, wv), Om)), nrm(np.cross(v, M * v)),
                      mbar * nrm(np.cross(v, np.cross(Om, rP))), mbar * g * nrm(np.cross(rP, z)))
        parts = []
        for r, sc in ((nrm(Fp), f_scale), (nrm(Tp), t_scale)):
            parts.append(float(r / sc) if sc > 0 else (0.0 if r == 0 else math.inf))
    rel = max(parts)
    return rel if math.isfinite(rel) else math.inf


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
        Converged to a forward-gliding upright-pitch motion: the residual relative to the largest term of the force
        and moment equations (see the module notes) below :data:`RESIDUAL_TOL`, ``v1 > 0`` and
        ``|theta| < pi/2``.

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a FixedMassGlider3D or ``y0`` not an array of real numbers.
    ArgumentError
        If ``y0`` is not six finite numbers.
    """
    _model(model)
    y0 = checks.array("y0 (v1, v2, v3, psidot, theta, phi)", y0, shape=(6,))
    y, res, ok, _ = _newton(model, y0)
    return y, res, ok


def _newton(model: FixedMassGlider3D, y0: np.ndarray) -> tuple[np.ndarray, float, bool, float]:
    """:func:`helix_newton` on checked arguments, also returning the relative residual of the final iterate (``inf``
    when it was not evaluated: a non-finite, backward or overturned iterate), so callers need not recompute it."""

    def fun(y: np.ndarray) -> np.ndarray:
        return np.asarray(helix_equations(model, y), float)

    def jac(y: np.ndarray) -> np.ndarray:
        return jacobians(lambda yy, u: helix_equations(model, yy), y, np.zeros(0))[0]

    with np.errstate(all="ignore"):
        try:
            sol = root(fun, y0, jac=jac, method="hybr", options={"xtol": 1e-13})
        except (ValueError, FloatingPointError, OverflowError, ZeroDivisionError, np.linalg.LinAlgError):
            return y0, float("inf"), False, float("inf")
        y = sol.x
        res = float(np.max(np.abs(fun(y)))) if np.all(np.isfinite(y)) else float("inf")
    if not (math.isfinite(res) and y[0] > 0 and abs(y[4]) < math.pi / 2):
        return y, res, False, float("inf")
    rel = _relative_residual(model, y)
    return y, res, bool(rel < RESIDUAL_TOL), rel


_GUESS_V2 = 0.0625  # (0.25 m/s)^2: where laws other than the thesis's are read for the straight-glide guesses


def _straight_guesses(veh: Vehicle, r_p: np.ndarray, m0: float) -> list[np.ndarray]:
    """Straight longitudinal glides for ``(r_P1, 0, r_P3)``: roots in alpha of the pitch-moment balance, with V and
    gamma from the force balance (lift and drag balance the net weight m0 g)."""
    g, mbar = veh.g, veh.mbar
    m1, m3 = veh.mass(1, m0), veh.mass(3, m0)

    def coefficients(a: float) -> tuple[float, float]:
        # lift and drag per V^2 (kg/m): the thesis law's K_L(a), K_D(a); other laws at 0.25 m/s (a guess only:
        # the seaglider law's drag coefficient varies with speed, and the trim solve is exact)
        if veh.law == "thesis":
            return veh.K_L0 + veh.K_L * a, veh.K_D0 + veh.K_D * a * a
        L, D = lift_drag(veh, _GUESS_V2, a)
        return float(L) / _GUESS_V2, float(D) / _GUESS_V2

    def glide(a: float) -> tuple[float, float, float] | None:
        CL, CD = coefficients(a)
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

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a FixedMassGlider3D or ``y`` not an array of real numbers.
    ArgumentError
        If ``y`` is not six finite numbers.
    SolverError
        If the Jacobian is not finite there or its eigenvalues cannot be computed.
    """
    _model(model)
    y = checks.array("y (v1, v2, v3, psidot, theta, phi)", y, shape=(6,))
    v, w, th, ph = y[0:3], y[3], y[4], y[5]
    s = np.r_[v, w * zeta_of(th, ph), th, ph]
    with np.errstate(all="ignore"):
        A, _ = jacobians(lambda ss, u: reduced_rhs(model, ss), s, np.zeros(0))
    if not np.all(np.isfinite(A)):
        raise SolverError(f"the reduced Jacobian at y = {tuple(y)} is not finite (overflow): no eigenvalues")
    try:
        lam = np.linalg.eigvals(A)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of the reduced Jacobian at y = {tuple(y)} did not converge: {exc}") from exc
    return lam[np.lexsort((lam.imag, lam.real))]


def helix_trim(veh: Vehicle, r_p: Any = None, m0: float | None = None, *, guess: Any = None,
               continuation_steps: int = 12, n_random: int = 40, seed: int = 0, rudder: float = 0.0) -> Helix:
    """Steady helix (or straight glide) of ``veh`` with the moving mass at ``r_p`` (m) and buoyancy ``m0`` (kg).

    Solves ``(v', Omega') = 0`` of (8.23)-(8.25) with ``Omega = psidot zeta`` (8.31) for
    ``(v1, v2, v3, psidot, theta, phi)``; the solution is accepted only if the residual of the force and moment
    equations is below :data:`RESIDUAL_TOL` (1e-10) relative to their largest term.

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (e.g. ``slocum_ch8``).
    r_p : (3,) array, optional
        Moving-mass position in body axes (m), ``|r_p| <= R_P_MAX`` (10 m, plausibility limit); defaults to the
        vehicle file's ``r_P1, r_P2, r_P3``.
    m0 : float, optional
        Net buoyancy (kg, positive heavy: descent), finite; defaults to the file's ``m0``. ``m0 = 0`` has no glide.
        For the ``added`` mass model the solid mass ``m + m0 - mbar`` must stay positive.
    guess : Helix or array (v1, v2, v3, psidot, theta, phi), optional
        Warm start (continuation). Without it (or if it fails) the longitudinal straight glide is continued in
        ``r_P2`` over ``continuation_steps`` steps; if that fails, ``n_random`` random starting points are tried.
        Only a starting point: a Helix of another vehicle is accepted, the result is checked anyway.
    continuation_steps : int
        Number of ``r_P2`` continuation steps, 1 to :data:`MAX_CONTINUATION_STEPS` (1000).
    n_random : int
        Random restarts as the last resort, 0 to :data:`MAX_RANDOM_STARTS` (1000).
    seed : int
        Seed (>= 0) of the random restarts.
    rudder : float
        Rudder angle ``delta_r`` (rad, ``|delta_r| <= pi/2``, default 0), held fixed; checked against the range of
        the vehicle's ``[actuators] rudder`` when it lists one. The continuation in ``r_P2`` runs at this rudder
        angle.

    Returns
    -------
    Helix
        Radius, pitch, period, speed, angles and the eigenvalues of the 8-state reduced linearization.

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle; ``r_p``, ``guess`` not arrays of real numbers; ``m0`` not a real number (``str``,
        ``None``, ``bool``); ``continuation_steps``, ``n_random`` or ``seed`` not an integer.
    ArgumentError
        ``r_p`` not three finite numbers or farther than 10 m from the centre; ``m0`` not finite; ``guess`` not six
        finite numbers; an option outside its range.
    ModelError
        ``veh`` is not an underwater glider or lacks the 3D parameters; ``m0`` makes the solid mass ``m + m0 -
        mbar`` or a body mass non-positive; the generalized mass matrix is singular to working precision.
    InfeasibleGlideError
        ``m0 = 0``, or no steady motion found (the message says what was tried); or ``r_p`` / ``m0`` outside the
        ranges of the vehicle's ``[actuators]`` table (``r_P1``, ``r_P2``, ``r_P3``, ``m0``; off a fixed setting),
        the message names the actuator.
    SolverError
        The linearization at the solution is not finite or its eigenvalues cannot be computed.

    Examples
    --------
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> h = gc.helix_trim(slo, r_p=(0.02, 0.02, 0.04), m0=0.25)
    >>> print(f"radius {h.radius:.1f} m, drop per turn {h.pitch:.1f} m, period {h.period:.0f} s, stable {h.stable}")
    radius 66.6 m, drop per turn 206.2 m, period 640 s, stable True
    """
    checks.vehicle("veh", veh)
    if veh.kind != "underwater_glider":
        raise ModelError(f"vehicle '{veh.name}' is a {veh.kind}, not an underwater glider: helices are steady "
                         "motions of the 3D glider")
    if r_p is None:
        r_p = (veh.r_P1, veh.r_P2, veh.r_P3)
    if m0 is None:
        m0 = veh.m0
    r = checks.array("r_p (moving-mass position, m)", r_p, shape=(3,))
    if not float(np.linalg.norm(r)) <= R_P_MAX:
        raise ArgumentError(f"r_p = {tuple(float(x) for x in r)} m puts the moving mass "
                            f"{float(np.linalg.norm(r)):.4g} m from the centre of buoyancy; at most R_P_MAX = "
                            f"{R_P_MAX:g} m is plausible")
    m0 = checks.real("m0 (net buoyancy)", m0, unit="kg")
    continuation_steps = checks.integer("continuation_steps", continuation_steps, lo=1, hi=MAX_CONTINUATION_STEPS)
    n_random = checks.integer("n_random", n_random, lo=0, hi=MAX_RANDOM_STARTS)
    seed = checks.integer("seed", seed, lo=0)
    if guess is not None and not isinstance(guess, Helix):
        guess = checks.array("guess (v1, v2, v3, psidot, theta, phi)", guess, shape=(6,))
    if m0 == 0:
        raise InfeasibleGlideError("m0 = 0: a neutrally buoyant glider has no steady glide (no net weight to balance "
                                   "drag); use m0 != 0")
    rudder = checks.real("rudder (angle)", rudder, lo=-math.pi / 2, hi=math.pi / 2, unit="rad")
    for name, value, unit in (("r_P1", r[0], "m"), ("r_P2", r[1], "m"), ("r_P3", r[2], "m"), ("m0", m0, "kg"),
                              ("rudder", rudder, "rad")):
        if name in ("r_P2", "r_P3") and "roll" in veh.actuators:
            continue  # a rolled battery sits off its translation settings: the roll actuator's range governs it
        act = veh.actuators.get(name)
        if act is not None and not act.contains(float(value)):
            raise InfeasibleGlideError(
                f"{name} = {float(value):.6g} {unit} is outside the range of actuator '{name}' of vehicle "
                f"'{veh.name}' ([actuators] {name}: {act.describe()}); the glider cannot hold this setting: choose "
                "one in range")
    if veh.mass_model == "added" and not veh.m + m0 - veh.mbar > 0:
        raise ModelError(f"m0 = {m0:g} kg leaves vehicle '{veh.name}' a solid mass m + m0 - mbar = "
                         f"{veh.m + m0 - veh.mbar:g} kg <= 0 (m = {veh.m:g} kg, mbar = {veh.mbar:g} kg): no such "
                         "vehicle; the ballast cannot be that light")
    try:
        model = FixedMassGlider3D(veh, (float(r[0]), float(r[1]), float(r[2])), m0, rudder)
    except np.linalg.LinAlgError as exc:
        raise ModelError(f"the generalized mass matrix of (8.23) is singular for r_p = {tuple(map(float, r))} m, "
                         f"m0 = {m0:g} kg on vehicle '{veh.name}'") from exc
    tried: list[str] = []
    y = None
    on_model: tuple[np.ndarray, float, float] | None = None  # (y, residual, relative residual) evaluated on `model`
    if guess is not None:
        y0 = guess.unknowns if isinstance(guess, Helix) else guess
        y1, res, ok, rel = _newton(model, np.asarray(y0, dtype=float))
        tried.append("warm start")
        if ok:
            y = y1
            on_model = (y1, res, rel)
    if y is None:
        starts = _straight_guesses(veh, r, m0)
        tried.append(f"{len(starts)} longitudinal straight glide(s) continued in r_P2")
        for y0 in starts:
            yk = y0
            ok = True
            for k in range(1, continuation_steps + 1):
                rk = (r[0], r[1] * k / continuation_steps, r[2])
                yk, res, ok = helix_newton(FixedMassGlider3D(veh, rk, m0, rudder), yk)
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
            y1, res, ok, rel = _newton(model, y0)
            if ok:
                y = y1
                on_model = (y1, res, rel)
                break
    if y is None:
        raise InfeasibleGlideError(
            f"no steady helix or glide found for r_P = {tuple(round(float(x), 5) for x in r)} m, m0 = {m0:g} kg on "
            f"vehicle '{veh.name}' (tried: {'; '.join(tried)}). Try a warm start from a nearby solution "
            "(glidectl.helix_sweep continues along a parameter) or more random starts")
    known = on_model is not None and on_model[0] is y
    rel = on_model[2] if known else _relative_residual(model, y)  # type: ignore[index]
    if abs(y[3]) < 1e-13:  # a straight glide: snap the rounding-level yaw rate to zero if the trim still holds
        ys = y.copy()
        ys[3] = 0.0
        rel_s = _relative_residual(model, ys)
        if rel_s < RESIDUAL_TOL:
            y, rel, known = ys, rel_s, False
    res = on_model[1] if known else float(np.max(np.abs(helix_equations(model, y))))  # type: ignore[index]
    z = zeta_of(y[4], y[5])
    return Helix((float(r[0]), float(r[1]), float(r[2])), m0, y[0:3].copy(), y[3] * z, float(y[4]), float(y[5]),
                 float(y[3]), res, helix_eigenvalues(model, y), veh, veh.provenance, model, rel)
