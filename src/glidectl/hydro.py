"""Hydrodynamic forces and moments of the underwater glider, (2.9)-(2.14).

All functions are written with numpy ufuncs only, broadcast over leading dimensions and accept complex input,
so they serve simulation (batched real states) and exact complex-step linearization alike.

Argument checks: the vehicle must be an underwater glider (:class:`~glidectl.ModelError` otherwise) and every
array argument an array of numbers (:class:`~glidectl.ArgumentTypeError` for strings, ``None``, booleans or
objects); vectors need the documented trailing dimension (:class:`~glidectl.ArgumentError`). These formulas are
evaluated inside every right-hand side, so values are not checked for finiteness: NaN and infinities propagate
elementwise to the outputs (the public entry points, such as :func:`glidectl.simulate`, refuse non-finite states).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import checks
from .errors import ArgumentError, ArgumentTypeError, ModelError
from .params import Vehicle

__all__ = ["DAMPING_KEYS", "angle_of_attack", "atan2_cs", "best_glide_angle", "damping_moment", "excess_mass",
           "gliderflight_coefficients", "hull_buoyancy_keys", "lift_drag", "loads_3d", "loads_at",
           "longitudinal_loads", "zero_lift_angle"]

_DEG = 180.0 / np.pi

#: Rotational-damping coefficients per body axis ``i = 1, 2, 3`` (roll, pitch, yaw): ``(K_qi, K_Omega1_i,
#: K_Omega2_i)``, the ``V^2``-scaled linear term of (2.12)-(2.14) (pitch: ``K_q`` = ``K_q2``), the chapter-8 linear
#: term without ``V^2`` and the chapter-8 quadratic term (docs/conventions.md, "Damping: one convention").
DAMPING_KEYS = {1: ("K_q1", "K_Omega1_1", "K_Omega2_1"), 2: ("K_q", "K_Omega1_2", "K_Omega2_2"),
                3: ("K_q3", "K_Omega1_3", "K_Omega2_3")}


def _numeric(name: str, value: Any) -> Any:
    """``value`` as a number (returned as is: the scalar calls of simulations) or an array of real or complex
    numbers (:func:`glidectl.checks.numeric`); ArgumentTypeError otherwise."""
    if isinstance(value, float | int | complex) and not isinstance(value, bool):
        return value
    return checks.numeric(name, value)


def _vector3(name: str, value: Any) -> np.ndarray:
    a = np.asarray(_numeric(name, value))
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ArgumentError(f"{name} must have a trailing dimension 3 (body components 1, 2, 3), got shape "
                            f"{a.shape}")
    return a


def _broadcast(names: str, *arrays: Any) -> None:
    shapes = [getattr(a, "shape", ()) for a in arrays]
    if all(sh == shapes[0] or sh == () for sh in shapes):  # fast path
        return
    try:
        np.broadcast_shapes(*shapes)
    except ValueError as exc:
        raise ArgumentError(f"{names} must broadcast together, got shapes {', '.join(map(str, shapes))}") from exc


def _glider(veh: Any) -> Vehicle:
    if isinstance(veh, Vehicle) and veh.kind == "underwater_glider":  # fast path: these run in every rhs call
        return veh
    return checks.vehicle("veh", veh, kind="underwater_glider")  # raises the right error


def atan2_cs(y: Any, x: Any) -> Any:
    """``arctan2(y, x)`` that is analytic in a complex-step perturbation.

    For real input this is :func:`numpy.arctan2`. For complex input the branch is chosen from the real parts and
    the analytic continuation ``2 arctan(y / (sqrt(x^2 + y^2) + x))`` (for ``Re x >= 0``) or
    ``arctan(y/x) +- pi`` (for ``Re x < 0``) is used, so the imaginary part carries the exact derivative.

    Parameters
    ----------
    y, x : array_like
        Numbers (real or complex), broadcast together.

    Returns
    -------
    ndarray
        The angle (rad) in ``(-pi, pi]`` (real part).

    Raises
    ------
    ArgumentTypeError
        If ``y`` or ``x`` is not a number or an array of numbers.
    ArgumentError
        If their shapes do not broadcast.
    """
    if isinstance(y, float) and isinstance(x, float):  # two real numbers (a single-state right-hand side)
        return np.arctan2(y, x)
    y = np.asarray(_numeric("y", y))
    x = np.asarray(_numeric("x", x))
    _broadcast("y and x", y, x)
    if not (np.iscomplexobj(x) or np.iscomplexobj(y)):
        return np.arctan2(y, x)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.sqrt(x * x + y * y)
        right = 2.0 * np.arctan(y / (r + x))
        left = np.arctan(y / x) + np.where(np.real(y) >= 0, np.pi, -np.pi)
    return np.where(np.real(x) >= 0, right, left)


def angle_of_attack(v1: Any, v3: Any) -> Any:
    """Angle of attack ``alpha = atan2(v3, v1)`` (rad), §2.2.4; body 3-axis points down.

    Parameters
    ----------
    v1, v3 : array_like
        Body-frame velocity components (m/s), real or complex.

    Returns
    -------
    ndarray
        ``alpha`` (rad).

    Raises
    ------
    ArgumentTypeError
        If ``v1`` or ``v3`` is not a number or an array of numbers.
    ArgumentError
        If their shapes do not broadcast.
    """
    return atan2_cs(_numeric("v3", v3), _numeric("v1", v1))


def longitudinal_loads(veh: Vehicle, v1: Any, v3: Any, Omega2: Any) -> tuple[Any, Any, Any, Any]:
    """Lift, drag and pitching moment in the longitudinal plane, (2.9), (2.11), (2.13).

    Parameters
    ----------
    veh : Vehicle
        Uses ``K_L0 [kg/m], K_L [kg/m/rad], K_D0 [kg/m], K_D [kg/m/rad^2], K_M0 [kg], K_M [kg/rad]`` and the
        pitch damping of :func:`damping_moment` (``K_q [kg s/rad]``, ``K_Omega1_2``, ``K_Omega2_2``).
    v1, v3 : array_like
        Body-frame velocity components (m/s).
    Omega2 : array_like
        Pitch rate (rad/s).

    Returns
    -------
    alpha : angle of attack (rad)
    L, D : lift and drag (N), ``L = (K_L0 + K_L alpha) V^2``, ``D = (K_D0 + K_D alpha^2) V^2``
    M_DL2 : pitching moment (N m), ``(K_M0 + K_M alpha + K_q Omega2) V^2`` (2.13) plus the chapter-8 pitch damping
        ``K_Omega1_2 Omega2 + K_Omega2_2 Omega2 |Omega2|`` (:func:`damping_moment`)

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or an array argument is not a number or an array of numbers.
    ArgumentError
        If the shapes do not broadcast.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    v1, v3 = _numeric("v1", v1), _numeric("v3", v3)
    alpha = angle_of_attack(v1, v3)
    L, D, M = loads_at(veh, v1 * v1 + v3 * v3, alpha, Omega2)
    return alpha, L, D, M


def _damping(p: Any, V2: Any, Om: Any, axis: int) -> Any:
    """The damping moment about body axis ``axis`` (unchecked; ``p`` is ``veh.params``)."""
    kq, k1, k2 = DAMPING_KEYS[axis]
    out = p.get(kq, 0.0) * Om * V2
    c1, c2 = p.get(k1, 0.0), p.get(k2, 0.0)
    if np.any(c1 != 0.0):                       # arrays: a stacked vehicle (VehicleSample.stacked)
        out = out + c1 * Om
    if np.any(c2 != 0.0):
        out = out + c2 * Om * np.sqrt(Om * Om)  # Omega_i |Omega_i|, analytic in a complex step
    return out


def damping_moment(veh: Vehicle, V2: Any, Omega: Any, axis: int) -> Any:
    """Rotational damping moment about one body axis (N m): the one convention every model reads.

    ``M_damp_i = K_qi Omega_i V^2 + K_Omega1_i Omega_i + K_Omega2_i Omega_i |Omega_i|``: the ``V^2``-scaled
    linear damping of (2.12)-(2.14) (pitch: ``K_q`` of (2.13)) plus the chapter-8 damping of §8.2.2 (no ``V^2``;
    the thesis writes ``Omega_i^2``, implemented as ``Omega_i |Omega_i|`` so that it opposes the rotation for
    either sign). Absent coefficients count as 0; keys in :data:`DAMPING_KEYS`. A vehicle file may not give the
    linear term in both forms (nonzero ``K_qi`` and ``K_Omega1_i``): :func:`glidectl.load_vehicle` refuses it.
    The longitudinal models (through :func:`loads_at`) and the 3-D models (through :func:`loads_3d`) call this
    function, so a file's damping is the same in 2-D and 3-D (docs/conventions.md, "Damping: one convention").

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (uses ``K_qi`` [kg s/rad], ``K_Omega1_i`` [kg m^2 s/rad], ``K_Omega2_i``
        [kg m^2 s^2/rad^2]).
    V2 : array_like
        Squared speed (m^2/s^2), real or complex.
    Omega : array_like
        Angular rate ``Omega_i`` about the axis (rad/s), real or complex; broadcast with ``V2``.
    axis : int
        Body axis: 1 (roll), 2 (pitch) or 3 (yaw).

    Returns
    -------
    ndarray
        The damping moment ``M_damp_i`` (N m).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``V2`` or ``Omega`` is not a number or an array of numbers, or ``axis`` is not
        an int.
    ArgumentError
        If ``axis`` is not 1, 2 or 3, or the shapes do not broadcast.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    if isinstance(axis, bool) or not isinstance(axis, int | np.integer):
        raise ArgumentTypeError(f"axis must be the int 1, 2 or 3 (body axis), got {type(axis).__name__} {axis!r}")
    if int(axis) not in DAMPING_KEYS:
        raise ArgumentError(f"axis must be 1 (roll), 2 (pitch) or 3 (yaw), got {axis}")
    V2, Omega = _numeric("V2", V2), _numeric("Omega", Omega)
    _broadcast("V2 and Omega", V2, Omega)
    return _damping(veh.params, V2, Omega, int(axis))


def loads_at(veh: Vehicle, V2: Any, alpha: Any, Omega2: Any) -> tuple[Any, Any, Any]:
    """Lift, drag and pitching moment (N, N, N m) for squared speed ``V2`` (m^2/s^2), angle of attack ``alpha``
    (rad, not wrapped: models with alpha as a state, chapter 5, use it directly) and pitch rate (rad/s).

    ``L = (K_L0 + K_L alpha) V^2`` (2.11), ``D = (K_D0 + K_D alpha^2) V^2`` (2.9) for the thesis law, or the lift
    and drag of the vehicle's ``[hydrodynamics]`` law (:func:`lift_drag`),
    ``M_DL2 = (K_M0 + K_M alpha) V^2 + damping_moment(veh, V^2, Omega2, 2)``, i.e. ``(K_M0 + K_M alpha + K_q Omega2)
    V^2`` (2.13) plus the chapter-8 terms ``K_Omega1_2 Omega2 + K_Omega2_2 Omega2 |Omega2|`` when the file gives them
    (docs/conventions.md, "Damping: one convention"); for chapter-5 vehicles this is (5.24)-(5.25).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (uses ``K_L0, K_L, K_D0, K_D, K_M0, K_M`` and the pitch damping ``K_q, K_Omega1_2,
        K_Omega2_2`` of :func:`damping_moment`).
    V2 : array_like
        Squared speed (m^2/s^2).
    alpha : array_like
        Angle of attack (rad).
    Omega2 : array_like
        Pitch rate (rad/s).

    Returns
    -------
    L, D, M_DL2 : ndarray
        Lift (N), drag (N) and pitching moment (N m), broadcast over the inputs.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or an array argument is not a number or an array of numbers.
    ArgumentError
        If the shapes do not broadcast.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    V2, alpha, Omega2 = _numeric("V2", V2), _numeric("alpha", alpha), _numeric("Omega2", Omega2)
    _broadcast("V2, alpha and Omega2", V2, alpha, Omega2)
    p = veh.params
    L, D = _lift_drag(veh, V2, alpha, None)
    M = (p["K_M0"] + p["K_M"] * alpha) * V2 + _damping(p, V2, Omega2, 2)
    return L, D, M


def gliderflight_coefficients(veh: Vehicle) -> tuple[float, float, float]:
    """Lift slope, parasitic and induced drag coefficients ``(ah + aw, Cd0, Cd1)`` of the ``"gliderflight"`` law.

    ``aw`` defaults to the swept-wing estimate ``2 pi AR / (2 + sqrt(AR^2 (1 + tan^2 Omega) + 4))`` and ``Cd1`` to
    ``aw^2 / (pi eOsborne AR) + Cd1_hull`` where the vehicle file gives neither (gliderflight's
    ``awEstimate`` and ``cd1Estimate``, Merckelbach et al. 2019).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider of the ``"gliderflight"`` law.

    Returns
    -------
    (float, float, float)
        ``ah + aw`` (1/rad), ``Cd0`` (1), ``Cd1`` (1/rad^2).

    Raises
    ------
    ModelError
        If the vehicle is not an underwater glider of the ``"gliderflight"`` law.
    """
    _glider(veh)
    if veh.law != "gliderflight":
        raise ModelError(f"vehicle '{veh.name}' uses the '{veh.law}' law, not 'gliderflight'")
    p = veh.params
    aw = p["aw"] if "aw" in p else (2.0 * np.pi * p["AR"]
                                    / (2.0 + np.sqrt(p["AR"] ** 2 * (1.0 + np.tan(p["Omega"]) ** 2) + 4.0)))
    cd1 = p["Cd1"] if "Cd1" in p else aw * aw / (np.pi * p["eOsborne"] * p["AR"]) + p["Cd1_hull"]
    return float(p["ah"] + aw), float(p["Cd0"]), float(cd1)


def _lift_drag(veh: Vehicle, V2: Any, alpha: Any, density: Any) -> tuple[Any, Any]:
    """Lift and drag (N) of the vehicle's law (unchecked; ``density`` None: the vehicle's)."""
    p = veh.params
    law = veh.law
    if law == "thesis":
        return (p["K_L0"] + p["K_L"] * alpha) * V2, (p["K_D0"] + p["K_D"] * alpha * alpha) * V2
    rho = veh.density if density is None else density
    if law == "seaglider":
        ql2 = 0.5 * rho * V2 * p["length"] ** 2  # q l^2 (N)
        a = alpha * _DEG
        # D = (hd_b q^(-1/4) + hd_c a^2) q l^2, written with q^(3/4) so that it is 0 (not 0 * inf) at rest
        return p["hd_a"] * a * ql2, p["hd_b"] * (0.5 * rho * V2) ** 0.75 * p["length"] ** 2 + p["hd_c"] * a * a * ql2
    slope, cd0, cd1 = gliderflight_coefficients(veh)
    qs = 0.5 * rho * p["S"] * V2
    return qs * slope * alpha, qs * (cd0 + cd1 * alpha * alpha)


def lift_drag(veh: Vehicle, V2: Any, alpha: Any, density: Any = None) -> tuple[Any, Any]:
    """Lift and drag (N) of the vehicle's hydrodynamic law at squared speed ``V2`` and angle of attack ``alpha``.

    One function per law, chosen by the vehicle file's ``[hydrodynamics] law`` (``veh.law``):

    * ``"thesis"``: ``L = (K_L0 + K_L alpha) V^2`` (2.11), ``D = (K_D0 + K_D alpha^2) V^2`` (2.9);
    * ``"seaglider"`` (Eriksen et al. 2001, the basestation's model): with ``q = rho V^2 / 2`` and ``a`` the angle
      of attack in degrees, ``L = hd_a q l^2 a``, ``D = (hd_b q^(-1/4) + hd_c a^2) q l^2``;
    * ``"gliderflight"`` (Merckelbach et al. 2019): ``L = q S (ah + aw) alpha``, ``D = q S (Cd0 + Cd1 alpha^2)``
      (:func:`gliderflight_coefficients`).

    Every model's right-hand side reaches it through :func:`loads_at`; it broadcasts and is analytic in a complex
    step (exact linearization).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    V2 : array_like
        Squared speed (m^2/s^2).
    alpha : array_like
        Angle of attack (rad).
    density : array_like, optional
        Sea-water density (kg/m^3) for the laws written with ``q = rho V^2 / 2``; default ``veh.density``. The
        thesis law's coefficients already hold the density and ignore it.

    Returns
    -------
    L, D : ndarray
        Lift and drag (N), broadcast over the inputs.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or an array argument is not a number or an array of numbers.
    ArgumentError
        If the shapes do not broadcast.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    V2, alpha = _numeric("V2", V2), _numeric("alpha", alpha)
    if density is not None:
        density = _numeric("density", density)
    _broadcast("V2, alpha and density", V2, alpha, 0.0 if density is None else density)
    return _lift_drag(veh, V2, alpha, density)


def best_glide_angle(veh: Vehicle, V2: Any = 1.0) -> Any:
    """Angle of attack (rad) of the smallest drag-to-lift ratio of a downward glide: the shallowest steady glide
    (the bound of the permissible set (2.26)).

    Thesis law: ``-K_L0/K_L + sqrt((K_L0/K_L)^2 + K_D0/K_D)``; seaglider law: ``sqrt(hd_b q^(-1/4) / hd_c)``
    degrees at ``q = rho V^2 / 2``; gliderflight law: ``sqrt(Cd0 / Cd1)``. ``inf`` where the drag has no
    ``alpha^2`` term (no minimum).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    V2 : array_like, optional
        Squared speed (m^2/s^2); only the seaglider law's ratio depends on it.

    Returns
    -------
    ndarray or float
        The angle (rad), shaped like ``V2`` for the seaglider law.

    Raises
    ------
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    p = veh.params
    with np.errstate(divide="ignore"):
        if veh.law == "thesis":
            r = p["K_L0"] / p["K_L"]
            return -r + np.sqrt(r * r + p["K_D0"] / p["K_D"]) if p["K_D"] > 0 else np.inf
        if veh.law == "seaglider":
            q = 0.5 * veh.density * np.asarray(V2, dtype=float)
            return np.sqrt(p["hd_b"] * q ** -0.25 / p["hd_c"]) / _DEG if p["hd_c"] > 0 else np.inf
        _, cd0, cd1 = gliderflight_coefficients(veh)
        return float(np.sqrt(cd0 / cd1)) if cd1 > 0 else np.inf


def zero_lift_angle(veh: Vehicle) -> float:
    """Angle of attack of zero lift (rad): ``-K_L0 / K_L`` for the thesis law, 0 for the others.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.

    Returns
    -------
    float

    Raises
    ------
    ModelError
        If ``veh`` is not an underwater glider.
    """
    _glider(veh)
    return -veh.params["K_L0"] / veh.params["K_L"] if veh.law == "thesis" else 0.0


def _opt(veh: Vehicle, key: str) -> float:
    """Optional 3D coefficient: 0 when the vehicle file does not define it."""
    return float(veh.params.get(key, 0.0))


def loads_3d(veh: Vehicle, v: Any, Omega: Any, rudder: Any = 0.0) -> tuple[Any, Any, Any, Any, Any]:
    """Hydrodynamic force and moment in body coordinates, (2.9)-(2.14), rotated from the wind frame.

    Parameters
    ----------
    veh : Vehicle
        Needs ``K_D0, K_D, K_L0, K_L, K_beta, K_M0, K_M, K_MR, K_MY`` and the damping coefficients: the
        ``V^2``-scaled ``K_q1, K_q (= K_q2), K_q3`` of (2.12)-(2.14) and the chapter-8 ``K_Omega1_i Omega_i +
        K_Omega2_i Omega_i^2`` (without ``V^2``); absent damping coefficients count as 0.
    v : array_like, shape (..., 3)
        Body velocity (m/s).
    Omega : array_like, shape (..., 3)
        Body angular velocity (rad/s).
    rudder : float or array_like, shape (...)
        Rudder angle ``delta_r`` (rad, > 0 turns the nose to starboard); it adds ``K_SF_rudder delta_r V^2`` to the
        side force and ``K_MY_rudder delta_r V^2`` to the yaw moment (coefficients absent count as 0). Default 0.

    Returns
    -------
    F : (..., 3) body-frame force (N): ``C_bw (-D, -SF, -L)`` with ``C_bw = [e_V, e_2, e_3]``,
        ``e_V = v/V = (ca cb, sb, sa cb)``, ``e_2 = (-ca sb, cb, -sa sb)``, ``e_3 = (-sa, 0, ca)``. The side force
        ``SF = (K_beta beta + K_SF_rudder delta_r) V^2`` opposes sideslip (docs/conventions.md); with ``beta = 0``
        and no rudder this is (2.18)-(2.19)'s ``(L sin a - D cos a, 0, -L cos a - D sin a)``.
    T : (..., 3) body-frame moment (N m):
        ``(K_MR beta V^2, (K_M0 + K_M alpha) V^2, (K_MY beta + K_MY_rudder delta_r) V^2)`` plus damping
        ``K_qi Omega_i V^2 + K_Omega1_i Omega_i + K_Omega2_i Omega_i |Omega_i|`` about each body axis, from
        :func:`damping_moment` (the pitch row is :func:`loads_at`'s ``M_DL2``, the same as the 2-D models').
    alpha, beta, V : angle of attack ``atan2(v3, v1)``, sideslip ``asin(v2/V)`` (rad) and speed (m/s); at rest
        (``V = 0``) ``beta = 0`` (every term it enters carries ``V^2``).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``v`` or ``Omega`` is not an array of numbers.
    ArgumentError
        If ``v`` or ``Omega`` does not have a trailing dimension 3, or their shapes do not broadcast.
    ModelError
        If ``veh`` is not an underwater glider.

    Notes
    -----
    The quadratic chapter-8 damping is implemented as ``K_Omega2_i Omega_i |Omega_i|`` so that it opposes the
    rotation for either sign (the thesis writes ``Omega_i^2``; Table 8.1 sets these coefficients to 0).
    """
    _glider(veh)
    v = _vector3("v", v)
    Om = _vector3("Omega", Omega)
    _broadcast("v and Omega", v, Om)
    p = veh.params
    v1, v2, v3 = v[..., 0], v[..., 1], v[..., 2]
    V2 = v1 * v1 + v2 * v2 + v3 * v3
    V = np.sqrt(V2)
    alpha = atan2_cs(v3, v1)
    at_rest = np.real(V2) == 0
    beta = np.arcsin(v2 / np.where(at_rest, 1.0, V))  # v2 = 0 at rest, so beta = 0 there
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    L, D, M2 = loads_at(veh, V2, alpha, Om[..., 1])  # pitch moment including pitch damping
    SF = _opt(veh, "K_beta") * beta * V2
    yaw = _opt(veh, "K_MY") * beta * V2
    if not (np.isscalar(rudder) and rudder == 0.0):  # the rudder acts like a sideslip of its own
        SF = SF + _opt(veh, "K_SF_rudder") * rudder * V2
        yaw = yaw + _opt(veh, "K_MY_rudder") * rudder * V2
    F = np.stack([-D * ca * cb + SF * ca * sb + L * sa,
                  -D * sb - SF * cb,
                  -D * sa * cb + SF * sa * sb - L * ca], axis=-1)
    T = np.stack([_opt(veh, "K_MR") * beta * V2 + _damping(p, V2, Om[..., 0], 1),
                  M2,
                  yaw + _damping(p, V2, Om[..., 2], 3)], axis=-1)
    return F, T, alpha, beta, V


def hull_buoyancy_keys(veh: Vehicle) -> dict[str, float]:
    """The hull and water values of :func:`excess_mass` with their defaults.

    ``mass`` defaults to ``m + m0`` (displaced-fluid mass plus the nominal heaviness: the vehicle's mass in air for
    the ``added`` mass model of chapter 8), ``volume`` to ``m / density`` (the hull that displaces ``m`` at the
    surface), ``compressibility``, ``thermal_expansion`` to 0 and ``reference_temperature`` to 10 degC.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.

    Returns
    -------
    dict
        ``mass`` (kg), ``volume`` (m^3), ``compressibility`` (1/Pa), ``thermal_expansion`` (1/K),
        ``reference_temperature`` (degC), ``density`` (kg/m^3).

    Raises
    ------
    ModelError
        If ``mass`` or ``volume`` is neither given nor derivable (a ``fixed`` mass model without them).
    """
    veh = checks.vehicle("veh", veh, kind="underwater_glider")
    p = veh.params
    rho = veh.density
    mass = p.get("mass", p["m"] + p["m0"] if "m" in p and "m0" in p else None)
    volume = p.get("volume", p["m"] / rho if "m" in p else None)
    missing = [k for k, v in (("mass", mass), ("volume", volume)) if v is None]
    if missing:
        raise ModelError(f"vehicle '{veh.name}' gives no {' and no '.join(missing)} in [hydrodynamics] and has no "
                         "displaced-fluid mass 'm' to derive them from; add them to its [hydrodynamics] table")
    return {"mass": float(mass), "volume": float(volume), "compressibility": p.get("compressibility", 0.0),
            "thermal_expansion": p.get("thermal_expansion", 0.0),
            "reference_temperature": p.get("reference_temperature", 10.0), "density": rho}


def excess_mass(veh: Vehicle, depth: Any, pumped_volume: Any, *, density: Any = None,
                temperature: Any = None, pressure: Any = None) -> np.ndarray:
    """Net heaviness ``m0`` (kg, positive sinks) of a compressible hull with a pumped volume.

    ``m0 = mass - rho (volume (1 - compressibility p + thermal_expansion (T - reference_temperature)) + dV)`` with
    the gauge pressure ``p`` (given, or ``rho g depth``; :func:`hull_buoyancy_keys` for the values and their
    defaults).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider.
    depth : array_like
        Depth (m, positive down).
    pumped_volume : array_like
        Volume added to the hull by the buoyancy engine (m^3; negative: oil drawn in, the glider sinks).
    density : array_like, optional
        In-situ density (kg/m^3); default the vehicle's at ``depth`` (:meth:`glidectl.Vehicle.water_density`: its
        density profile, or its constant density).
    temperature : array_like, optional
        Water temperature (degC); default the reference temperature (no thermal expansion).
    pressure : array_like, optional
        Gauge pressure (Pa) compressing the hull, e.g. a record's own (:attr:`glidectl.DiveRecord.pressure`);
        default ``rho g depth``.

    Returns
    -------
    ndarray
        ``m0`` (kg), broadcast over the inputs.

    Raises
    ------
    ModelError
        If the hull's mass or volume is unknown (:func:`hull_buoyancy_keys`).
    ArgumentTypeError
        If an array argument is not numeric.
    """
    h = hull_buoyancy_keys(veh)
    depth = checks.numeric("depth", depth)
    rho = veh.water_density(depth) if density is None else checks.numeric("density", density)
    dv = checks.numeric("pumped_volume", pumped_volume)
    dT = 0.0 if temperature is None else checks.numeric("temperature", temperature) - h["reference_temperature"]
    p = rho * veh.g * depth if pressure is None else checks.numeric("pressure", pressure)
    hull = h["volume"] * (1.0 - h["compressibility"] * p + h["thermal_expansion"] * dT)
    return np.asarray(h["mass"] - rho * (hull + dv), dtype=float)
