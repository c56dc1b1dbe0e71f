"""Boxes, scales and starting Lyapunov functions for certifying any closed loop.

A closed loop of this package (:func:`glidectl.closed_loop`) lives in the plant's state units with its equilibrium
``x_e`` somewhere in state space. Before any SOS program is built its states are mapped to ``y = (x - x_e) / s``
with ``s_i = max(x_e,i - lo_i, hi_i - x_e,i)``, so that the box is inside ``[-1, 1]^n`` and touches ``-1`` or ``1``
in every state (:func:`box_scale`). The box comes from the caller (``box=``), from the model's own ``box`` (models
built for certification) or from the validity box of the states (:func:`validity_box`, the one default of both
:func:`glidectl.certify_roa` and :func:`glidectl.saturated_loop`): the actuator ranges and rates of the vehicle file
(``Vehicle.actuators``), a narrow band about a fixed actuator, and the documented half-widths
:data:`DEFAULT_HALF_WIDTH` of the glider states about the equilibrium. A state none of these knows is refused with a
message asking for ``box=`` (no generic width in arbitrary units). The starting ``V`` is ``y^T P y`` with
``A_y^T P + P A_y = -I`` for the scaled linearization ``A_y = S^-1 A S`` (:func:`scaled_lyapunov`), so its level
sets are shaped by the box, not by the SI units.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from scipy.linalg import solve_continuous_lyapunov

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from .polynomial import Poly

__all__ = ["DEFAULT_HALF_WIDTH", "box_scale", "resolve_box", "scaled_lyapunov", "validity_box"]


#: Half-widths of the validity box of the glider states without an actuator limit (state units; ``"rel"`` entries
#: are relative to the equilibrium value, ``"abs"`` ones absolute). Actuator states take the vehicle's ``[actuators]``
#: range, their rate states its rate (:func:`validity_box`).
DEFAULT_HALF_WIDTH: dict[str, tuple[float, str]] = {
    "V": (0.5, "rel"), "gamma": (0.5, "abs"), "alpha": (0.2, "abs"), "Omega2": (0.3, "abs"),
    "z_prime": (2.0, "abs"), "theta": (0.5, "abs"), "v1": (0.5, "rel"), "v3": (0.1, "abs"),
}

#: rate state -> actuator (its position state)
_RATE_STATES = {"rdot_P1": "r_P1", "rdot_P2": "r_P2", "rdot_P3": "r_P3"}
_ACTUATOR_STATES = ("m0", "r_P1", "r_P2", "r_P3")
#: validity boxes stay strictly inside actuator ranges (0.1 % shrink about their centre: no pump blocking on them)
_SHRINK = 1.0 - 1e-3
#: half-width of the band about a fixed actuator's value and its zero rate, relative to max(|value|, 1) (state
#: units): the part does not move, the band only keeps the box non-degenerate
_FIXED_BAND = 1e-3


def _validity_entries(names: tuple[str, ...], xe: np.ndarray, veh: Any) -> dict[str, tuple[float, float]]:
    """``{state name: (lo, hi)}`` of the states :func:`validity_box` knows (the others are left out)."""
    acts = dict(getattr(veh, "actuators", None) or {})
    out: dict[str, tuple[float, float]] = {}
    for i, nm in enumerate(names):
        x = float(xe[i])
        pos = nm if nm in _ACTUATOR_STATES else _RATE_STATES.get(nm)
        a = acts.get(pos) if pos is not None else None
        if a is not None and a.fixed is not None:
            c = float(a.fixed) if nm in _ACTUATOR_STATES else 0.0
            w = _FIXED_BAND * max(abs(c), 1.0)
            lo, hi = c - w, c + w
        elif a is not None and nm in _ACTUATOR_STATES and math.isfinite(a.min) and math.isfinite(a.max) \
                and a.max > a.min:
            lo, hi = float(a.min), float(a.max)
        elif a is not None and nm in _RATE_STATES and math.isfinite(a.rate) and a.rate > 0:
            lo, hi = -float(a.rate), float(a.rate)
        elif veh is not None and nm in DEFAULT_HALF_WIDTH:
            w, kind = DEFAULT_HALF_WIDTH[nm]
            w = w * abs(x) if kind == "rel" and x != 0 else w
            lo, hi = x - w, x + w
        else:
            continue
        c = 0.5 * (lo + hi)
        out[nm] = (c + _SHRINK * (lo - c), c + _SHRINK * (hi - c))
    return out


def _names_of(model: Any) -> tuple[str, ...]:
    if isinstance(model, str):
        raise ArgumentTypeError("expected a model or a sequence of state names, got a single string")
    names = getattr(model, "state_names", None)
    if names is None:
        try:
            names = tuple(model)
        except TypeError:
            raise ArgumentTypeError(f"expected a glidectl model (state_names) or a sequence of state names, got "
                                    f"{type(model).__name__}") from None
    names = tuple(names)
    if not all(isinstance(n, str) for n in names):
        raise ArgumentTypeError(f"state names must be strings, got {names}")
    return names


def validity_box(model: Any, equilibrium: Any = None, vehicle: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """The validity box of a model's states: the default region of interest of :func:`glidectl.certify_roa` and
    :func:`glidectl.saturated_loop`.

    Per state, in this order:

    * an actuator state (``m0``, ``r_P1``, ``r_P2``, ``r_P3``) with a non-fixed actuator in the vehicle file's
      ``[actuators]`` table: its range ``[min, max]`` (kg, m);
    * a rate state (``rdot_P1``, ``rdot_P2``, ``rdot_P3``) of such an actuator: ``[-rate, rate]`` (m/s);
    * a state of a fixed actuator (``fixed`` in the table) and its rate state: the fixed value (0 for the rate)
      ``+- 1e-3 max(|value|, 1)``: the part does not move, the band only keeps the box non-degenerate;
    * a glider state of :data:`DEFAULT_HALF_WIDTH` (``V``, ``gamma``, ``alpha``, ``theta``, ``Omega2``,
      ``z_prime``, ``v1``, ``v3``) of a model of a vehicle: that half-width about the equilibrium (``"rel"``:
      relative to ``|x_e|``); without a vehicle the names are not taken to be a glider's (a pendulum's ``theta`` is
      not a pitch angle);

    each interval shrunk by 0.1 % about its centre, so that a range end is never reached. A state none of these
    knows is refused: there is no generic width in arbitrary units.

    Parameters
    ----------
    model : glidectl model or sequence of str
        A model (``state_names``, and unless given ``equilibrium`` and ``vehicle``) or the state names.
    equilibrium : array_like (n,), optional
        ``x_e`` in state units (default the model's ``equilibrium``).
    vehicle : Vehicle, optional
        Whose ``[actuators]`` table gives the actuator limits (default the model's ``vehicle``; with none, no
        state is known).

    Returns
    -------
    (ndarray, ndarray)
        ``lo`` and ``hi`` of shape ``(n,)`` (state units).

    Raises
    ------
    ArgumentTypeError
        If ``model`` is neither a model nor a sequence of state names.
    ArgumentError
        If a state is unknown (the message lists the states and the limits found and asks for ``box=``), the
        equilibrium is missing or has the wrong shape, or it is not strictly inside the box.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> loop = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0))
    >>> lo, hi = gc.validity_box(loop)
    >>> loop.state_names[4], round(float(lo[4]), 6), round(float(hi[4]), 6)   # m0: the pump's range, less 0.1 %
    ('m0', -0.999, 0.999)
    """
    names = _names_of(model)
    n = len(names)
    xe = getattr(model, "equilibrium", None) if equilibrium is None else equilibrium
    if xe is None:
        raise ArgumentError("validity_box needs the equilibrium (the model has none): pass equilibrium=x_e")
    xe = checks.array("equilibrium", xe, shape=(n,))
    veh = getattr(model, "vehicle", None) if vehicle is None else vehicle
    known = _validity_entries(names, xe, veh)
    _refuse_missing(model, names, known)
    lo = np.array([known[k][0] for k in names])
    hi = np.array([known[k][1] for k in names])
    _check_inside(names, xe, lo, hi)
    return lo, hi


def _refuse_missing(model: Any, names: tuple[str, ...], known: dict[str, tuple[float, float]]) -> None:
    missing = [k for k in names if k not in known]
    if missing:
        what = getattr(model, "name", None) or type(model).__name__
        raise ArgumentError(
            f"no limits known for states {missing} of '{what}' (neither the vehicle's [actuators] table nor the "
            f"validity half-widths DEFAULT_HALF_WIDTH know them; known: {known or 'none'}): pass box=(lo, hi) in "
            f"state units for all {len(names)} states {names}, or box={{name: (lo, hi)}} for the missing ones")


def _check_inside(names: tuple[str, ...], xe: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> None:
    out = [names[i] for i in range(len(names)) if not lo[i] < xe[i] < hi[i]]
    if out:
        raise ArgumentError(f"the equilibrium {xe.tolist()} is not strictly inside the box in states {out}: "
                            f"lo = {lo.tolist()}, hi = {hi.tolist()}")


def resolve_box(model: Any, box: Any = None, equilibrium: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """The region of interest of a certification, in the model's state units.

    Parameters
    ----------
    model : glidectl model
        Needs ``state_names``; its ``box`` (models built for certification), else the validity box of its states
        (:func:`validity_box`: the actuator limits of its ``vehicle``, the half-widths :data:`DEFAULT_HALF_WIDTH`
        about the equilibrium) are the defaults.
    box : (array_like, array_like) or mapping, optional
        ``(lo, hi)`` of shape ``(n,)`` each, or ``{state name: (lo, hi)}`` for some states (the others from the
        defaults).
    equilibrium : array_like (n,), optional
        Must lie strictly inside the box (default the model's ``equilibrium``); the half-widths are about it.

    Returns
    -------
    (ndarray, ndarray)
        ``lo`` and ``hi`` (state units).

    Raises
    ------
    ArgumentTypeError
        If ``box`` is neither a pair nor a mapping.
    ArgumentError
        If a state has no limit (neither ``box=`` nor a model box nor :func:`validity_box` knows it): the message
        lists the states and the limits found; an unknown state name; ``lo >= hi``; or the equilibrium outside the
        box.
    """
    names = tuple(getattr(model, "state_names", ()))
    n = len(names)
    lo = np.full(n, np.nan)
    hi = np.full(n, np.nan)
    xe = getattr(model, "equilibrium", None) if equilibrium is None else equilibrium
    xe = None if xe is None else checks.array("equilibrium", xe, shape=(n,))
    own = getattr(model, "box", None)
    if own is not None and not callable(own):
        lo[:], hi[:] = (checks.array("model box", b, shape=(n,)) for b in own)
    else:                       # half-widths need the equilibrium: NaN (unknown) without one
        x0 = np.full(n, np.nan) if xe is None else xe
        for k, (a, b) in _validity_entries(names, x0, getattr(model, "vehicle", None)).items():
            i = names.index(k)
            lo[i], hi[i] = a, b
    if box is not None:
        if isinstance(box, Mapping):
            for k, v in box.items():
                if k not in names:
                    raise ArgumentError(f"box names state '{k}', which is not a state of {names}")
                pair = checks.array(f"box['{k}']", v, shape=(2,))
                i = names.index(k)
                lo[i], hi[i] = pair
        elif isinstance(box, tuple | list) and len(box) == 2:
            lo = checks.array("box lo", box[0], shape=(n,)).copy()
            hi = checks.array("box hi", box[1], shape=(n,)).copy()
        else:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({n},) or a mapping "
                                    f"{{state name: (lo, hi)}}, got {type(box).__name__}")
    ok = np.isfinite(lo) & np.isfinite(hi)
    _refuse_missing(model, names, {names[i]: (float(lo[i]), float(hi[i])) for i in range(n) if ok[i]})
    if np.any(lo >= hi):
        raise ArgumentError(f"box must have lo < hi in every state, got lo = {lo.tolist()}, hi = {hi.tolist()}")
    if xe is not None:
        _check_inside(names, xe, lo, hi)
    return lo, hi


def box_scale(box: tuple[Any, Any], equilibrium: Any) -> np.ndarray:
    """``s_i = max(x_e,i - lo_i, hi_i - x_e,i)``: ``y = (x - x_e) / s`` maps the box into ``[-1, 1]^n``.

    Parameters
    ----------
    box : (array_like, array_like)
        ``(lo, hi)`` in state units, ``lo < x_e < hi``.
    equilibrium : array_like
        ``x_e`` (state units).

    Returns
    -------
    ndarray
        The positive scale of each state (state units).

    Raises
    ------
    ArgumentError
        If the shapes differ or the equilibrium is not strictly inside the box.
    """
    xe = checks.array("equilibrium", equilibrium, ndim=1)
    lo = checks.array("box lo", box[0], shape=xe.shape)
    hi = checks.array("box hi", box[1], shape=xe.shape)
    if np.any(lo >= xe) or np.any(xe >= hi):
        raise ArgumentError("the equilibrium must be strictly inside the box")
    return np.maximum(xe - lo, hi - xe)


def scaled_lyapunov(A: Any, scale: Any, weight: Any = None) -> Poly:
    """Starting ``V(y) = y^T P y`` with ``A_y^T P + P A_y = -W_y``, ``A_y = S^-1 A S`` (``S = diag(scale)``).

    ``W_y = I`` by default; with ``weight = Q + K^T R K`` (state units) of an LQR law ``u = -K (x - x_e)``,
    ``W_y = S weight S`` and ``V`` is the closed loop's quadratic cost-to-go ``(x - x_e)^T P_x (x - x_e)`` (the
    Riccati solution when ``K`` is the LQR gain of ``A``), written in ``y``.

    Parameters
    ----------
    A : array_like (n, n)
        Linearization in state units (per the model's time unit).
    scale : array_like (n,)
        State scale ``s`` of ``y = (x - x_e) / s``.
    weight : array_like (n, n), optional
        Symmetric positive definite weight in state units (default: ``W_y = I``).

    Returns
    -------
    Poly
        The quadratic in the ``n`` scaled variables, normalized to largest coefficient 1 (nondimensional).

    Raises
    ------
    ArgumentError
        If ``weight`` has the wrong shape or is not positive definite.
    ModelError
        If ``A`` is not Hurwitz (the equation has no positive definite solution).
    SolverError
        If the Lyapunov equation fails.
    """
    A = checks.array("A", A, ndim=2)
    s = checks.array("scale", scale, shape=(A.shape[0],))
    Ay = A * s[None, :] / s[:, None]
    Wy = np.eye(len(s))
    if weight is not None:
        Wx = checks.array("weight", weight, shape=(len(s), len(s)))
        Wy = 0.5 * (Wx + Wx.T) * s[:, None] * s[None, :]
        if np.linalg.eigvalsh(Wy)[0] <= 0:
            raise ArgumentError("weight must be symmetric positive definite (e.g. Q + K^T R K of an LQR law)")
    if np.max(np.linalg.eigvals(Ay).real) >= 0:
        raise ModelError(f"the linearization is not Hurwitz (eigenvalues {np.round(np.linalg.eigvals(A), 6)}): no "
                         "quadratic Lyapunov function to start from")
    try:
        P = solve_continuous_lyapunov(Ay.T, -Wy)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"the scaled Lyapunov equation failed: {exc}") from exc
    P = 0.5 * (P + P.T)
    P = P / np.max(np.abs(P))
    return Poly.quadratic(P)
