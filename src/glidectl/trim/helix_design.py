"""Inverse helix design (beyond chapter 8, which calls the symbolic inversion intractable): find the moving-mass
position ``r_P`` and buoyancy ``m0`` that realize a stable circular helix of a requested radius and pitch (drop per
turn) or radius and speed.

Method: bounded nonlinear least squares (:func:`scipy.optimize.least_squares`, trust-region reflective) on the
controls ``c = (r_P1, r_P2, r_P3, m0)``. Each residual evaluation trims the helix (:func:`helix_trim`, warm-started
from the last solution); the residual is the relative error in the two targets, a stability penalty
``max(0, max Re(lambda) + margin)`` and a small pull towards the starting point (the problem has two more unknowns
than targets). Several starting points are tried; the result is polished on the targets alone and accepted only if
the targets are met to ``tol``, the helix is stable and the controls are inside the bounds.

Jacobian: by the implicit function theorem at the trimmed helix, ``dy/dc = -F_y^-1 F_c`` for the trim unknowns ``y``
of ``F(y, c) = 0`` (:func:`helix_equations`), ``F_y`` exact (complex step), ``F_c`` and the stability margin's
derivative by central differences of the model in ``c`` (no trims). One trim per least-squares iteration instead of
``1 + (free controls)`` with finite differences through trims, and the derivatives are free of the trims' solver
noise. At a fold (``F_y`` singular) it falls back to forward differences through trims.

Budget: at most ``n_starts <=`` :data:`MAX_STARTS` starting points, each with at most 60 + 100 least-squares
residual evaluations (plus one Jacobian per accepted step), each a warm-started :func:`helix_trim`; an optional
``time_limit`` (s) stops the search with :class:`~glidectl.BudgetError`. Plausibility limits: ``radius`` and
``|pitch|`` at most :data:`LENGTH_MAX` (10 km), ``speed`` in (0, 100] m/s, moving-mass bounds inside ``R_P_MAX``
(10 m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, GlidectlError, InfeasibleGlideError, ModelError, SolverError
from ..models.glider3d import R_P_MAX, FixedMassGlider3D
from ..params import Vehicle
from .glide import SPEED_MAX
from .helix import Helix, helix_eigenvalues, helix_equations, helix_trim, zeta_of

__all__ = ["DEFAULT_M0_BOUNDS", "DEFAULT_R_P_BOUNDS", "LENGTH_MAX", "MAX_STARTS", "HelixDesign", "design_helix"]

#: default moving-mass travel (m) per body axis and buoyancy range (kg); ours (the thesis gives none)
DEFAULT_R_P_BOUNDS = ((-0.05, 0.05), (-0.05, 0.05), (0.0, 0.08))
DEFAULT_M0_BOUNDS = (-0.5, 0.5)
#: Plausibility limit on the requested radius and ``|pitch|`` (m).
LENGTH_MAX = 1e4
#: Budget: largest number of starting points of the multistart search.
MAX_STARTS = 64
_SCALE = np.array([0.01, 0.01, 0.01, 0.1])  # m, m, m, kg
_FD_STEP = 1e-5 * _SCALE  # central-difference steps in the controls for dF/dc and d max Re(lambda)/dc (m, m, m, kg)


def _target_values(y: Any, key: str) -> Any:
    """``(radius, pitch or speed)`` of the steady motion with trim unknowns ``y`` (shape (..., 6)), complex-safe
    (for complex-step derivatives); the formulas of :attr:`Helix.radius`, :attr:`Helix.pitch`, :attr:`Helix.speed`
    (``|psidot|`` taken with the sign of the real part)."""
    v, w, th, ph = y[..., 0:3], y[..., 3], y[..., 4], y[..., 5]
    z = zeta_of(th, ph)
    V2 = np.sum(v * v, axis=-1)
    vz = np.sum(z * v, axis=-1)
    aw = np.where(np.real(w) < 0, -w, w)
    second = vz * (2 * math.pi) / aw if key == "pitch" else np.sqrt(V2)
    return np.stack([np.sqrt(V2 - vz * vz) / aw, second], -1)


def _control_sensitivity(veh: Vehicle, h: Helix, key: str,
                         penalty: bool) -> tuple[np.ndarray, np.ndarray | None] | None:
    """Derivatives of the helix targets (and of ``max Re(lambda)``) with respect to the controls
    ``c = (r_P1, r_P2, r_P3, m0)`` at the trimmed helix ``h``, by the implicit function theorem: the trim unknowns
    ``y(c)`` solve ``F(y, c) = 0`` (:func:`helix_equations`), so ``dy/dc = -F_y^-1 F_c`` with ``F_y`` exact
    (complex step) and ``F_c`` by central differences of the model in ``c`` (steps :data:`_FD_STEP`). Returns
    ``(dq/dc (2, 4), d max Re(lambda)/dc (4,) or None)``, or None when ``F_y`` is singular (a fold)."""
    y = h.unknowns
    c = np.r_[h.r_p, h.m0]
    model = h.model if h.model is not None else FixedMassGlider3D(veh, h.r_p, h.m0)

    def model_at(dc: np.ndarray) -> FixedMassGlider3D:
        cc = c + dc
        return FixedMassGlider3D(veh, (float(cc[0]), float(cc[1]), float(cc[2])), float(cc[3]))

    with np.errstate(all="ignore"):
        Fy = jacobians(lambda yy, u: helix_equations(model, yy), y, np.zeros(0))[0]
        Fc = np.empty((6, 4))
        steps = np.diag(_FD_STEP)
        for j in range(4):
            Fc[:, j] = (np.asarray(helix_equations(model_at(steps[j]), y), float)
                        - np.asarray(helix_equations(model_at(-steps[j]), y), float)) / (2 * _FD_STEP[j])
        try:
            dy = -np.linalg.solve(Fy, Fc)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(dy)):
            return None
        dq = jacobians(lambda yy, u: _target_values(yy, key), y, np.zeros(0))[0] @ dy
        dmax = None
        if penalty:  # along the branch: y(c +- h e_j) = y +- h dy/dc_j to first order
            dmax = np.empty(4)
            for j in range(4):
                hi = helix_eigenvalues(model_at(steps[j]), y + _FD_STEP[j] * dy[:, j])
                lo = helix_eigenvalues(model_at(-steps[j]), y - _FD_STEP[j] * dy[:, j])
                dmax[j] = (np.max(hi.real) - np.max(lo.real)) / (2 * _FD_STEP[j])
    return dq, dmax


@dataclass(frozen=True)
class HelixDesign:
    """Control parameters that realize a requested helix.

    Attributes
    ----------
    r_p : (3,) moving-mass position (m); m0 : buoyancy (kg); helix : the resulting :class:`Helix`
    target : requested ``{"radius": .., "pitch" or "speed": ..}`` (SI)
    error : max relative error in the targets
    evaluations : helix trims used
    vehicle : the :class:`Vehicle`; provenance : its parameter hash (``str``)
    """

    r_p: tuple[float, float, float]
    m0: float
    helix: Helix
    target: dict[str, float]
    error: float
    evaluations: int
    bounds: tuple[tuple[float, float], ...] = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""


_R_P_AXES = ("r_P1", "r_P2", "r_P3")


def _actuator_bounds(veh: Vehicle, rb: np.ndarray | None, mb: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of ``r_P`` (3, 2) and ``m0`` (2,): the user's, checked against ``veh.actuators``, or the table's."""
    out_r = np.array(DEFAULT_R_P_BOUNDS, dtype=float) if rb is None else rb.copy()
    out_m = np.array(DEFAULT_M0_BOUNDS, dtype=float) if mb is None else mb.copy()
    for name, row, given, unit in ([(n, out_r[k], rb is not None, "m") for k, n in enumerate(_R_P_AXES)]
                                   + [("m0", out_m, mb is not None, "kg")]):
        act = veh.actuators.get(name)
        if act is None:
            continue
        a_lo, a_hi = act.bounds
        if given:
            if not (act.contains(row[0]) and act.contains(row[1])):
                arg = "m0_bounds" if name == "m0" else f"r_p_bounds[{_R_P_AXES.index(name)}]"
                rng = (f"fixed at {act.fixed:g} {unit}: give ({act.fixed:g}, {act.fixed:g}) or leave the bounds to "
                       "the vehicle file" if act.fixed is not None else f"[{a_lo:g}, {a_hi:g}] {unit}")
                raise ArgumentError(f"{arg} = ({row[0]:g}, {row[1]:g}) {unit} reaches outside the range of actuator "
                                    f"'{name}' of vehicle '{veh.name}' ({rng}); keep the bounds within it")
        else:
            row[0] = a_lo if math.isfinite(a_lo) else min(row[0], a_hi)
            row[1] = a_hi if math.isfinite(a_hi) else max(row[1], a_lo)
    return out_r, out_m


def design_helix(veh: Vehicle, *, radius: float, pitch: float | None = None, speed: float | None = None,
                 r_p_bounds: tuple[tuple[float, float], ...] | None = None,
                 m0_bounds: tuple[float, float] | None = None, stability_margin: float = 1e-3,
                 tol: float = 1e-6, seed: int = 0, n_starts: int = 8,
                 time_limit: float | None = None) -> HelixDesign:
    """Find ``(r_P, m0)`` within bounds giving a stable helix of ``radius`` (m) and ``pitch`` (m, drop per turn,
    positive downwards) or ``speed`` (m/s).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with the 3D parameters of :class:`~glidectl.models.glider3d.FixedMassGlider3D`.
    radius : float
        Requested helix radius (m), in ``(0, LENGTH_MAX]`` (10 km).
    pitch : float, optional
        Requested drop per turn (m, positive downwards: a descending helix, ``m0 > 0``), nonzero, ``|pitch| <=
        LENGTH_MAX``. Give exactly one of ``pitch`` and ``speed``.
    speed : float, optional
        Requested speed ``|v|`` (m/s), in ``(0, 100]``.
    r_p_bounds : tuple of three (float, float), optional
        ``(lo, hi)`` travel of the moving mass along body axes 1, 2, 3 (m), ``lo <= hi`` (``lo = hi`` fixes that
        axis), every corner of the box within ``R_P_MAX`` (10 m) of the centre. Default: from the vehicle's
        ``[actuators]`` table, axis by axis (``r_P1``, ``r_P2``, ``r_P3``; a fixed actuator fixes the axis; an
        unbounded side, or an axis the table does not list, takes :data:`DEFAULT_R_P_BOUNDS`). Bounds given must
        lie within the actuator ranges.
    m0_bounds : (float, float), optional
        ``(lo, hi)`` range of the net buoyancy (kg), ``lo <= hi``, keeping every body mass (and for the ``added``
        mass model the solid mass ``m + m0 - mbar``) positive. Default: the ``[actuators] m0`` range (an unbounded
        side, or no entry: :data:`DEFAULT_M0_BOUNDS`). Bounds given must lie within the actuator range.
    stability_margin : float
        Required ``-max Re(lambda)`` of the helix's reduced linearization (1/s), finite, ``>= 0``.
    tol : float
        Relative tolerance on the targets (nondimensional), in ``(0, 0.1]``.
    seed : int
        Seed (>= 0) of the random starting points. The search first tries up to 12 structured starts (fewer
        distinct ones when an axis is fixed); random starts, uniform in the bounds, fill up to ``n_starts`` only
        after them. So with the default ``n_starts = 8`` and no fixed axis the search is deterministic and ``seed``
        has no effect; it matters when ``n_starts`` exceeds the number of distinct structured starts.
    n_starts : int
        Number of starting points tried, 1 to :data:`MAX_STARTS` (64).
    time_limit : float, optional
        Wall-time budget (s) of the whole search; ``None``: no limit beyond ``n_starts``.

    Returns
    -------
    HelixDesign
        The controls ``r_p`` (m) and ``m0`` (kg), the resulting stable :class:`~glidectl.trim.helix.Helix`, the
        target, the achieved relative error and the number of helix trims used.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, a number is not a real number (``str``, ``None``, ``bool``), the bounds are not
        arrays of real numbers, or ``seed`` / ``n_starts`` is not an integer.
    ArgumentError
        If not exactly one of ``pitch`` and ``speed`` is given, a value is not finite or outside its range above,
        or the bounds are not three ``(lo, hi)`` pairs for ``r_P`` and one for ``m0`` with ``lo <= hi`` inside the
        plausibility limits, or they reach outside the vehicle's actuator ranges (the message names the actuator),
        or every control is fixed.
    ModelError
        If ``veh`` is not an underwater glider, lacks the 3D parameters, or ``m0_bounds`` reach a buoyancy that
        leaves a non-positive mass.
    InfeasibleGlideError
        If no stable helix meeting the targets to ``tol`` (relative) was found within the bounds; the message gives
        the best attempt. Also when the ``m0`` bounds exclude the sign a pitch needs.
    BudgetError
        If ``time_limit`` ran out.

    Examples
    --------
    >>> import glidectl as gc
    >>> slo = gc.load_vehicle("slocum_ch8")
    >>> d = gc.design_helix(slo, radius=80.0, pitch=185.0)  # pitch: drop per turn (m)
    >>> print(f"radius {d.helix.radius:.1f} m, pitch {d.helix.pitch:.1f} m, stable {d.helix.stable}")
    radius 80.0 m, pitch 185.0 m, stable True
    >>> print(f"m0 = {d.m0:.3f} kg")
    m0 = 0.256 kg
    """
    checks.vehicle("veh", veh)
    if veh.kind != "underwater_glider":
        raise ModelError(f"vehicle '{veh.name}' is a {veh.kind}, not an underwater glider: helices are steady "
                         "motions of the 3D glider")
    if (pitch is None) == (speed is None):
        raise ArgumentError("give radius and exactly one of pitch= (m per turn) or speed= (m/s)")
    radius = checks.real("radius", radius, lo=0.0, lo_open=True, hi=LENGTH_MAX, unit="m")
    if pitch is not None:
        key, val = "pitch", checks.real("pitch (drop per turn)", pitch, lo=-LENGTH_MAX, hi=LENGTH_MAX, unit="m")
        if val == 0:
            raise ArgumentError("pitch must be nonzero (a helix with zero pitch is a level circle, which needs "
                                "m0 = 0: no steady glide)")
    else:
        key, val = "speed", checks.real("speed", speed, lo=0.0, lo_open=True, hi=SPEED_MAX, unit="m/s")
    rb = (checks.array("r_p_bounds (three (lo, hi) pairs, m)", r_p_bounds, shape=(3, 2)) if r_p_bounds is not None
          else None)
    mb = checks.array("m0_bounds ((lo, hi), kg)", m0_bounds, shape=(2,)) if m0_bounds is not None else None
    rb, mb = _actuator_bounds(veh, rb, mb)
    lo = np.r_[rb[:, 0], mb[0]]
    hi = np.r_[rb[:, 1], mb[1]]
    if np.any(lo > hi):
        raise ArgumentError(f"bounds must have lo <= hi for each of r_P1, r_P2, r_P3 (m) and m0 (kg), got "
                            f"r_p_bounds = {rb.tolist()}, m0_bounds = {mb.tolist()}")
    free = lo < hi
    if not np.any(free):
        raise ArgumentError("every control (r_P1, r_P2, r_P3, m0) is fixed by the bounds or the actuator table: "
                            "nothing to design; use helix_trim(veh, r_p, m0) for the helix they give")
    corner = float(np.linalg.norm(np.maximum(np.abs(rb[:, 0]), np.abs(rb[:, 1]))))
    if corner > R_P_MAX:
        raise ArgumentError(f"r_p_bounds reach {corner:.4g} m from the centre of buoyancy; at most R_P_MAX = "
                            f"{R_P_MAX:g} m is plausible")
    stability_margin = checks.nonnegative("stability_margin", stability_margin, unit="1/s")
    tol = checks.real("tol", tol, lo=0.0, lo_open=True, hi=0.1)
    seed = checks.integer("seed", seed, lo=0)
    n_starts = checks.integer("n_starts", n_starts, lo=1, hi=MAX_STARTS)
    deadline = checks.Deadline(time_limit, "design_helix")
    low_m0 = float(lo[3])
    if veh.mass_model == "added" and not veh.m + low_m0 - veh.mbar > 0:
        raise ModelError(f"m0_bounds reach m0 = {low_m0:g} kg, which leaves vehicle '{veh.name}' a solid mass "
                         f"m + m0 - mbar = {veh.m + low_m0 - veh.mbar:g} kg <= 0; raise the lower bound")
    FixedMassGlider3D(veh, (0.0, 0.0, 0.0), low_m0)  # ModelError: no 3D parameters, or a body mass <= 0 at lo
    r_p_bounds = tuple((float(a), float(b)) for a, b in rb)  # type: ignore[assignment]
    m0_bounds = (float(mb[0]), float(mb[1]))
    sign = 1.0 if (key == "speed" or val > 0) else -1.0  # descending helices need m0 > 0
    if key == "pitch" and not ((sign > 0 and hi[3] > 0) or (sign < 0 and lo[3] < 0)):
        raise InfeasibleGlideError(f"a pitch of {val:g} m needs m0 of sign {sign:+.0f}, outside {m0_bounds}")
    target = {"radius": float(radius), key: val}
    state: dict[str, Any] = {"last": None, "n": 0}

    def trim(c: np.ndarray) -> Helix | None:
        deadline.check(f"after {state['n']} helix trims")
        state["n"] += 1
        try:
            h = helix_trim(veh, c[:3], float(c[3]), guess=state["last"], n_random=0, continuation_steps=6)
        except (InfeasibleGlideError, SolverError):
            return None
        state["last"] = h
        return h

    def target_err(h: Helix) -> np.ndarray:
        got = h.pitch if key == "pitch" else h.speed
        if not (math.isfinite(h.radius) and math.isfinite(got)):
            return np.array([10.0, 10.0])
        return np.array([(h.radius - radius) / radius, (got - val) / abs(val)])

    def full(x: np.ndarray) -> np.ndarray:
        """All four controls from the free ones (fixed axes at their bound)."""
        c = lo.copy()
        c[free] = x
        return c

    def residual(x: np.ndarray, x0: np.ndarray, reg: float) -> np.ndarray:
        h = trim(full(x))
        state["x"], state["h"] = np.array(x, float), h
        if h is None:
            return np.r_[10.0, 10.0, 10.0, reg * (x - x0) / _SCALE[free]]
        pen = 10.0 * max(0.0, float(np.max(h.eigenvalues.real)) + stability_margin)
        return np.r_[target_err(h), pen, reg * (x - x0) / _SCALE[free]]

    n_free = int(np.count_nonzero(free))
    targets = np.array([radius, abs(val)])

    def jacobian(x: np.ndarray, x0: np.ndarray, reg: float) -> np.ndarray:
        """Exact-to-rounding Jacobian of :func:`residual` by the implicit function theorem (no extra trims at
        the point least_squares just evaluated), instead of finite differences through one trim per control."""
        h = state["h"] if state.get("x") is not None and np.array_equal(state["x"], x) else trim(full(x))
        J = np.zeros((3 + n_free, n_free))
        J[3:] = np.diag(reg / _SCALE[free])
        if h is None or not np.all(np.isfinite(target_err(h))) or not math.isfinite(h.radius):
            return J
        active = float(np.max(h.eigenvalues.real)) + stability_margin > 0
        sens = _control_sensitivity(veh, h, key, active)
        if sens is None:  # singular trim Jacobian (a fold): fall back to forward differences through trims
            f0 = residual(x, x0, reg)
            for j in range(n_free):
                dx = np.zeros(n_free)
                dx[j] = 1.49e-8 * max(1.0, abs(float(x[j])))
                J[:, j] = (residual(x + dx, x0, reg) - f0) / dx[j]
            return J
        dq, dmax = sens
        J[0:2] = dq[:, free] / targets[:, None]
        if dmax is not None:
            J[2] = 10.0 * dmax[free]
        return J

    rng = np.random.default_rng(seed)
    m0s = np.clip(sign * np.array([0.25, 0.1, 0.4]), lo[3], hi[3])
    starts: list[np.ndarray] = []
    for m in m0s:  # structured starts, clipped into the box; duplicates (fixed axes) dropped
        for s2 in (0.02, -0.02, 0.005, -0.005):
            c0 = np.clip(np.array([sign * 0.02, s2, 0.04, m]), lo, hi)
            if not any(np.array_equal(c0, c) for c in starts):
                starts.append(c0)
    while len(starts) < n_starts:
        starts.append(lo + (hi - lo) * rng.random(4))
    lo_f, hi_f = lo[free], hi[free]
    eps = np.minimum(1e-9, 0.25 * (hi_f - lo_f))  # start strictly inside the box
    best: tuple[float, np.ndarray, Helix | None] = (float("inf"), starts[0], None)
    for c0 in starts[:n_starts]:
        x0 = np.clip(c0[free], lo_f + eps, hi_f - eps)
        state["last"] = None
        if trim(full(x0)) is None:
            continue
        try:
            sol = least_squares(residual, x0, jac=jacobian, args=(x0, 1e-3), bounds=(lo_f, hi_f),
                                x_scale=_SCALE[free], xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=60)
            if np.max(np.abs(sol.fun[:3])) > 0.05:  # far from the targets: not worth polishing this start
                if np.max(np.abs(sol.fun[:2])) < best[0]:
                    hb = trim(full(sol.x))
                    if hb is not None:
                        best = (float(np.max(np.abs(target_err(hb)))), full(sol.x), hb)
                continue
            # polish on the targets (and stability) alone
            sol = least_squares(residual, sol.x, jac=jacobian, args=(sol.x, 0.0), bounds=(lo_f, hi_f),
                                x_scale=_SCALE[free],
                                xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=100)
        except GlidectlError:
            raise
        except (ValueError, np.linalg.LinAlgError):  # scipy refusing a start
            continue
        h = trim(full(sol.x))
        if h is None:
            continue
        err = float(np.max(np.abs(target_err(h))))
        ok = err <= tol and h.stable and float(np.max(h.eigenvalues.real)) <= -stability_margin * 0.999
        if err < best[0] or (ok and best[2] is not None and not best[2].stable):
            best = (err, full(sol.x), h)
        if ok:
            c = full(sol.x)
            return HelixDesign((float(c[0]), float(c[1]), float(c[2])), float(c[3]), h, target, err, state["n"],
                               (tuple(r_p_bounds[0]), tuple(r_p_bounds[1]), tuple(r_p_bounds[2]), tuple(m0_bounds)),
                               veh, veh.provenance)
    e, c, h = best
    what = "no helix could be trimmed" if h is None else (
        f"best: r_P = {tuple(round(float(x), 5) for x in c[:3])} m, m0 = {c[3]:.4g} kg gives radius {h.radius:.4g} m, "
        f"{key} {h.pitch if key == 'pitch' else h.speed:.4g}, max Re(lambda) = {np.max(h.eigenvalues.real):.3g} 1/s, "
        f"relative error {e:.2e}")
    raise InfeasibleGlideError(f"no stable helix with radius {radius:g} m and {key} {val:g} within r_P bounds "
                               f"{r_p_bounds} m and m0 bounds {m0_bounds} kg ({n_starts} starts; {what})")
