"""The saturated form ``X' = F(X, sat(K (X - X_e)))`` of the closed loops of this package's controllers, an input-free
model (:class:`~glidectl.models.saturated_loop.SaturatedLoop`) for simulation and for the LMI path of the
region-of-attraction layer (:func:`glidectl.roa.lmi.certify_roa_lmi`): :func:`saturated_loop`.

The chapter-6 buoyancy and elevator loops saturate in the pump (rate limit ``[actuators] m0.rate``); a linear glide
regulator saturates where the vehicle file gives a rate in the input's unit (the pump rate ``u4``/``w4``); a
:class:`~glidectl.analysis.closed_loop.StateFeedback` carries its own ``u_min``/``u_max``. The extracted form is
checked against the loop's own right-hand side, so a certificate is of the loop itself.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .. import checks
from ..analysis.closed_loop import StateFeedback
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from ..models.actuated import ActuatedGlider
from ..models.buoyancy_glider import actuator_limits
from ..models.closed_loop import ClosedLoop
from ..models.saturated_loop import AffineLimit, SaturatedLoop, held_motion, held_points
from ..roa.scaling import DEFAULT_HALF_WIDTH, validity_box
from .buoyancy import BuoyancyController
from .elevator import ElevatorBuoyancyController
from .linear import ACTUATOR_OF_INPUT, LinearGlideController

__all__ = ["DEFAULT_HALF_WIDTH", "saturated_loop"]


def _levels(u_min: Any, u_max: Any, u_e: np.ndarray, names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    m = len(names)
    lo = np.full(m, -np.inf) if u_min is None else checks.array("u_min", u_min, shape=(m,), finite=False)
    hi = np.full(m, np.inf) if u_max is None else checks.array("u_max", u_max, shape=(m,), finite=False)
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or not (np.all(lo < u_e) and np.all(u_e < hi)):
        raise ArgumentError(f"u_min < u_e < u_max is needed in every input {list(names)}: u_min = {lo.tolist()}, "
                            f"u_e = {u_e.tolist()}, u_max = {hi.tolist()}")
    return lo - u_e, hi - u_e


def _check_truth(sl: SaturatedLoop, truth: Callable[[np.ndarray], Any], what: str) -> None:
    """ModelError unless ``F(X, sat(K dX))`` equals the loop's own right-hand side on random points of the box."""
    X = held_points(sl.box, sl.equilibrium, sl.held)
    with np.errstate(all="ignore"):
        a = np.asarray(truth(X), dtype=float)
        b = np.asarray(sl.plant_rhs(X, sl.feedback(X)), dtype=float)
    scale = np.maximum(np.max(np.abs(a), axis=0), 1e-300)
    err = float(np.max(np.abs(a - b) / scale))
    if not err <= 1e-9:
        raise ModelError(f"{what}: the loop is not of the form F(x, sat(K (x - x_e))) the LMI path needs (relative "
                         f"mismatch {err:.2g} on box points)")
    held = list(sl.held)
    if held and held_motion(a, held) > 1e-12:
        raise ModelError(f"{what}: the held states {[sl.state_names[i] for i in held]} move when held at their "
                         "equilibrium values, so they cannot be left out of the certificate")


def saturated_loop(system: Any, feedback: Any = None, *, box: tuple[Any, Any] | None = None,
                   u_min: Any = None, u_max: Any = None, actuator_limits: bool = True) -> SaturatedLoop:
    """Extract ``F``, ``K``, the saturation levels, the equilibrium and a box from a glidectl closed loop.

    Recognized forms:

    * ``gc.closed_loop(BuoyancyController)`` (6.9): ``u1 = sat(-(K_b/tau_s)(m0 - m0e))`` at the pump rate limit
      ``u4_max`` (:func:`~glidectl.models.buoyancy_glider.actuator_limits`);
    * ``gc.closed_loop(ElevatorBuoyancyController)`` (6.21)-(6.22): the same pump law; the elevator input is the
      constant ``clip(u2e)`` (not fed back: part of ``F``);
    * ``gc.closed_loop(LinearGlideController)`` (:func:`~glidectl.controllers.linear.lqr_glide`,
      :func:`~glidectl.controllers.linear.place_glide`): ``w = -K (x_r - x_r,e)``, saturated by ``u_min``/``u_max``
      or by default at the vehicle's rate limits where the units agree (``u4``/``w4`` at ``[actuators] m0.rate``,
      kg/s; accelerations and forces have no constant limit in the vehicle file); the states locked by inputs left
      out of ``actuate`` are held. With ``actuator_limits`` (default) the actuators also obey the
      :class:`~glidectl.models.actuated.ActuatedGlider` law, as state-dependent limits
      (:class:`~glidectl.models.saturated_loop.AffineLimit`): the pump rate tapers onto the ends of the ``m0``
      range (gain ``pump_gain``), and the battery acceleration ``w1`` is limited so that the battery velocity
      stays within its rate limit and its taper onto the ends of the ``r_P1`` range (velocity servo of time
      constant ``servo_time``, taper gain ``1 / (4 servo_time)``; ActuatedGlider's defaults);
    * a plant with ``feedback`` a :class:`~glidectl.analysis.closed_loop.StateFeedback`
      (:func:`~glidectl.analysis.closed_loop.lqr_state_feedback`): ``u = sat(u_e - K (x - x_e))`` at its
      ``u_min``/``u_max``.

    The default box is the validity box of the states (:func:`~glidectl.roa.scaling.validity_box`, the same default
    as :func:`glidectl.certify_roa`): the vehicle's actuator ranges (``m0``, ``r_P1``) and rates (``rdot_P1``), and
    :data:`DEFAULT_HALF_WIDTH` about the equilibrium for the glider states, shrunk by 0.1 % (so a range end is never
    reached); a state it does not know is refused (pass ``box=``). Inside a certified ellipsoid (invariant, inside
    the box) the actuator range and rate limits are therefore never reached.

    Parameters
    ----------
    system : ClosedLoop or model
        A closed loop of the forms above, or a plant (``rhs(x, u)``, ``state_names``, ``input_names``) with
        ``feedback``.
    feedback : StateFeedback, optional
        The saturated linear law, for a plant.
    box : (array_like, array_like), optional
        ``(lo, hi)`` in the states' units; default the validity box above.
    u_min, u_max : array_like, optional
        Absolute input limits (one per plant input; a LinearGlideController loop only, overriding the defaults).
    actuator_limits : bool
        A LinearGlideController loop only: also limit the pump and battery by their ranges and the battery by its
        rate, as the actuators do (above); False keeps the constant levels only.

    Returns
    -------
    SaturatedLoop
        An input-free model (``input_names == ()``, fed-back channels in ``feedback_names``, ``equilibrium``,
        ``rhs(x)``) that :func:`glidectl.simulate`, :func:`glidectl.simulate_many`, :func:`glidectl.jacobians`,
        :func:`glidectl.certify_roa` and :func:`glidectl.certify_roa_lmi` take; checked against the loop's own
        right-hand side on 65 points of the box.

    Raises
    ------
    ArgumentTypeError
        If ``system`` is not a recognized closed loop (another law, e.g. a torque or CTOL law, or an arbitrary
        ``closed_loop(model, law)``: give the plant and a StateFeedback instead), or ``feedback`` is not a
        StateFeedback.
    ArgumentError
        If ``u_min``/``u_max`` do not bracket the equilibrium input, are given for another loop, the box does not
        contain the equilibrium, or (no ``box``) the validity box does not know a state.
    ModelError
        If the loop does not equal ``F(x, sat(K (x - x_e)))`` on the box, a held state moves, or the chapter-6
        pump is not rate limited (no saturation to certify: use the SOS path).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> ctrl = gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0)
    >>> sl = gc.saturated_loop(gc.closed_loop(ctrl))
    >>> sl.feedback_names, float(sl.u_hi[0])                # the pump rate limit (kg/s)
    (('u1',), 0.02)
    """
    if feedback is not None:
        return _state_feedback_loop(system, feedback, box, u_min, u_max)
    if not isinstance(system, ClosedLoop):
        raise ArgumentTypeError(f"saturated_loop() needs a glidectl ClosedLoop (gc.closed_loop(controller)) or a "
                                f"plant with feedback=StateFeedback, got {type(system).__name__}")
    ctrl = getattr(system.law, "__self__", None)
    if isinstance(ctrl, BuoyancyController | ElevatorBuoyancyController) and getattr(system.law, "__name__", "") == "u":
        sl = _chapter6_loop(system, ctrl, box, u_min, u_max)
        _check_truth(sl, system.rhs, system.name)
        return sl
    if isinstance(ctrl, LinearGlideController) and getattr(system.law, "__name__", "") == "path_input":
        return _linear_glide_loop(system, ctrl, box, u_min, u_max, checks.boolean("actuator_limits",
                                                                                  actuator_limits))
    law = getattr(system.law, "__qualname__", type(system.law).__name__)
    raise ArgumentTypeError(
        f"saturated_loop() does not know the law '{law}' of {system.name!r} as a saturated linear state feedback "
        "u = u_e + sat(K (x - x_e)): supported are the closed loops of BuoyancyController, "
        "ElevatorBuoyancyController and LinearGlideController, or a plant with feedback=StateFeedback "
        "(gc.lqr_state_feedback). Other loops go to gc.certify_roa (SOS path)")


def _state_feedback_loop(plant: Any, feedback: Any, box: Any, u_min: Any, u_max: Any) -> SaturatedLoop:
    """A plant closed by a saturated :class:`~glidectl.analysis.closed_loop.StateFeedback`."""
    if not isinstance(feedback, StateFeedback):
        raise ArgumentTypeError(f"feedback must be a StateFeedback (gc.lqr_state_feedback), got "
                                f"{type(feedback).__name__}")
    if u_min is not None or u_max is not None:
        raise ArgumentError("u_min/u_max come from the StateFeedback; do not give them again")
    for attr in ("rhs", "state_names", "input_names"):
        if not hasattr(plant, attr):
            raise ArgumentTypeError(f"{type(plant).__name__} is not a glidectl model (no '{attr}')")
    names, inputs = tuple(plant.state_names), tuple(plant.input_names)
    xe, ue = np.asarray(feedback.x_e, float), np.asarray(feedback.u_e, float)
    Kf = -np.asarray(feedback.K, float)
    lo_d, hi_d = feedback.u_min - ue, feedback.u_max - ue
    ch = [i for i in range(len(inputs)) if np.any(Kf[i])]

    def full_u(W: np.ndarray, ch: list[int] = ch) -> np.ndarray:
        U = np.broadcast_to(ue, (*W.shape[:-1], len(ue))).astype(W.dtype).copy()
        U[..., ch] = ue[ch] + W
        return U

    truth = (lambda X: plant.rhs(X, feedback(0.0, X)))  # noqa: E731
    sl = SaturatedLoop(f"{type(plant).__name__} closed by {feedback.name}", names, tuple(inputs[i] for i in ch),
                       lambda X, W: plant.rhs(X, full_u(W)), xe, Kf[ch], lo_d[ch], hi_d[ch],
                       box if box is not None else validity_box(plant, xe),
                       truth=truth, provenance=str(getattr(getattr(plant, "vehicle", None), "provenance", "")),
                       vehicle=getattr(plant, "vehicle", None))
    _check_truth(sl, truth, sl.name)
    return sl


def _chapter6_loop(system: ClosedLoop, ctrl: Any, box: Any, u_min: Any, u_max: Any) -> SaturatedLoop:
    """The chapter-6 buoyancy (6.9) or elevator-buoyancy (6.21)-(6.22) loop, its pump rate saturated."""
    if u_min is not None or u_max is not None:
        raise ArgumentError("u_min/u_max are the vehicle's pump limits for the chapter-6 loops; change the "
                            "vehicle's [actuators] table instead")
    plant, names = system.plant, tuple(system.state_names)
    xe = None if system.equilibrium is None else np.asarray(system.equilibrium, float)
    veh = getattr(plant, "vehicle", None)
    lim = actuator_limits(ctrl.vehicle)
    if not math.isfinite(lim.u4_max):
        raise ModelError(f"vehicle '{ctrl.vehicle.name}' has no pump rate limit ([actuators] m0.rate): the loop "
                         "is not saturated; certify it with gc.certify_roa (SOS path)")
    k = ctrl.rate_gain if isinstance(ctrl, BuoyancyController) else ctrl.K / ctrl.eq.tau_s
    K = np.zeros((1, 5))
    K[0, 4] = -k
    if isinstance(ctrl, BuoyancyController):
        def F(X: np.ndarray, W: np.ndarray) -> np.ndarray:
            return np.asarray(plant.rhs(X, W))
    else:
        u2c = float(np.real(lim.elevator(ctrl.eq.u2e)))

        def F(X: np.ndarray, W: np.ndarray) -> np.ndarray:
            return np.asarray(plant.rhs(X, np.concatenate([W, u2c + 0.0 * W], axis=-1)))
    return SaturatedLoop(system.name, names, ("u1",), F, xe, K, np.array([-lim.u4_max]), np.array([lim.u4_max]),
                         box if box is not None else validity_box(system, xe, veh), truth=system.rhs,
                         provenance=system.provenance, vehicle=veh)


def actuator_affine_limits(names: tuple[str, ...], channels: tuple[str, ...], xe: np.ndarray, veh: Any,
                           servo_time: float = ActuatedGlider.servo_time,
                           pump_gain: float = ActuatedGlider.pump_gain) -> tuple[AffineLimit, ...]:
    """The :class:`~glidectl.models.actuated.ActuatedGlider` actuator law as affine limits of the fed-back
    ``channels`` of a loop on states ``names`` at equilibrium ``xe``.

    The pump rate (``u4``/``w4``, kg/s) is limited by ``k_p (m0_max - m0)`` above and ``k_p (m0_min - m0)`` below;
    the battery acceleration ``w1`` (m/s^2) by ``(R - rdot_P1) / tau`` and ``(k (r_max - r_P1) - rdot_P1) / tau``
    above, ``(-R - rdot_P1) / tau`` and ``(k (r_min - r_P1) - rdot_P1) / tau`` below (``R`` the rate limit, ``tau``
    the servo time, ``k = 1 / (4 tau)``): the requested rate ``rdot_P1 + tau w1`` clipped to the rate interval of
    :func:`~glidectl.models.actuated.rate_interval`. Channels whose actuator, range or states are missing get no
    limit (infinite ends give none)."""
    acts = getattr(veh, "actuators", {}) or {}
    out: list[AffineLimit] = []

    def unit(state: str) -> np.ndarray:
        e = np.zeros(len(names))
        e[names.index(state)] = 1.0
        return e

    for ch, nm in enumerate(channels):
        a = acts.get(ACTUATOR_OF_INPUT.get(nm, ""))
        if a is None:
            continue
        if nm in ("u4", "w4") and "m0" in names:
            m0 = xe[names.index("m0")]
            for upper, end in ((True, a.max), (False, a.min)):
                if math.isfinite(end):
                    out.append(AffineLimit(ch, upper, -pump_gain * unit("m0"), pump_gain * (end - m0),
                                           f"m0 {'max' if upper else 'min'} (pump taper)"))
        if nm == "w1" and "r_P1" in names and "rdot_P1" in names:
            p, v = xe[names.index("r_P1")], xe[names.index("rdot_P1")]
            k, ev, ep = 0.25 / servo_time, unit("rdot_P1"), unit("r_P1")
            for upper, sign, end in ((True, 1.0, a.max), (False, -1.0, a.min)):
                if math.isfinite(a.rate):
                    out.append(AffineLimit(ch, upper, -ev / servo_time, (sign * a.rate - v) / servo_time,
                                           f"r_P1 rate {'+' if upper else '-'}{a.rate:g} m/s"))
                if math.isfinite(end):
                    out.append(AffineLimit(ch, upper, (-k * ep - ev) / servo_time, (k * (end - p) - v) / servo_time,
                                           f"r_P1 {'max' if upper else 'min'} (rate taper)"))
    return tuple(out)


def _linear_glide_loop(system: ClosedLoop, ctrl: Any, box: Any, u_min: Any, u_max: Any,
                       actuator_limits: bool) -> SaturatedLoop:
    """The loop of a :class:`~glidectl.controllers.linear.LinearGlideController`, saturated by ``u_min``/``u_max``
    or at the vehicle's pump rate, with the actuators' range and rate limits when ``actuator_limits``; checked
    unsaturated against the loop's own right-hand side."""
    plant, names = system.plant, tuple(system.state_names)
    xe = None if system.equilibrium is None else np.asarray(system.equilibrium, float)
    veh = getattr(plant, "vehicle", None)
    prov = system.provenance
    inputs = tuple(plant.input_names)
    ue = np.zeros(len(inputs))
    if u_min is None and u_max is None:
        acts = getattr(veh, "actuators", {}) or {}
        hi = np.full(len(inputs), np.inf)
        for i, nm in enumerate(inputs):
            a = acts.get(ACTUATOR_OF_INPUT.get(nm, ""))
            if nm in ("u4", "w4") and a is not None and math.isfinite(a.rate):
                hi[i] = a.rate
        lo_d, hi_d = -hi, hi
    else:
        lo_d, hi_d = _levels(u_min, u_max, ue, inputs)
    Kf = -np.asarray(ctrl.K, float)
    ch = [i for i in range(len(inputs)) if np.any(Kf[i])]
    held = tuple(names.index(s) for s in ctrl.locked_states)

    def F(X: np.ndarray, W: np.ndarray, ch: list[int] = ch) -> np.ndarray:
        U = np.zeros((*W.shape[:-1], len(inputs)), dtype=W.dtype)
        U[..., ch] = W
        return np.asarray(plant.rhs(X, U))

    sl0 = SaturatedLoop(system.name, names, tuple(inputs[i] for i in ch), F, xe, Kf[ch], lo_d[ch], hi_d[ch],
                        box if box is not None else validity_box(system, xe, veh), held=held, provenance=prov,
                        vehicle=veh)
    # the loop's own law is unsaturated: check F with the unsaturated law against it, then saturate
    lin = SaturatedLoop(sl0.name, names, sl0.feedback_names, F, xe, sl0.K, np.full(len(ch), -np.inf),
                        np.full(len(ch), np.inf), sl0.box, held=held)
    _check_truth(lin, system.rhs, system.name)
    limits = actuator_affine_limits(names, sl0.feedback_names, xe, veh) if actuator_limits else ()
    what = ", ".join(f"{inputs[i]} in [{lo_d[i]:g}, {hi_d[i]:g}]" for i in ch if np.isfinite(lo_d[i])
                     or np.isfinite(hi_d[i]))
    if limits:
        what = ", ".join(q for q in (what, "actuator ranges and battery rate") if q)
    return SaturatedLoop(f"{system.name}, saturated ({what or 'no limit'})", names, sl0.feedback_names, F, xe,
                         sl0.K, sl0.u_lo, sl0.u_hi, sl0.box, held=held, provenance=prov, vehicle=veh, limits=limits)


