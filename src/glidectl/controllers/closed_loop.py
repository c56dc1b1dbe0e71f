"""Closed loops of this package's controllers as models: :func:`closed_loop`.

Every controller is a time-invariant state feedback designed for one plant and one equilibrium;
:func:`closed_loop` returns the input-free :class:`~glidectl.models.closed_loop.ClosedLoop` of that plant under the
controller's law, with that equilibrium, in coordinates where the equilibrium is a point:

* :class:`~glidectl.controllers.linear.LinearGlideController`: the model it was designed on,
  :func:`~glidectl.analysis.linear.design_model`: :class:`~glidectl.models.longitudinal.GlidePathModel` (states
  ``z'`` (m) and the body states; force or acceleration form, as designed), without the states and inputs of the
  actuators the vehicle file fixes (:class:`~glidectl.analysis.linear.FixedActuatorModel`, unless designed with
  ``reduce_fixed=False``), equilibrium the steady glide with ``z' = path_offset``;
* :class:`~glidectl.controllers.output_feedback.LQGController`: the design model (with depth ``z`` when a sensor
  measures it; without fixed actuators, likewise) followed by the estimator's states ``<state>_hat``; equilibrium
  the glide and its estimate (None with depth, which changes along the glide);
* :class:`~glidectl.controllers.torque.TorqueDesign`: :class:`~glidectl.models.torque_glider.TorqueControlledGlider`
  of the open-loop vehicle, equilibrium ``(V_e, gamma_e, alpha_e, 0)``;
* :class:`~glidectl.controllers.buoyancy.BuoyancyController`: :class:`~glidectl.models.buoyancy_glider.BuoyancyGlider`,
  equilibrium ``eq.state = (V_e, gamma_e, alpha_e, 0, m0e)``;
* :class:`~glidectl.controllers.elevator.ElevatorBuoyancyController`:
  :class:`~glidectl.models.elevator_glider.ElevatorBuoyancyGlider`, equilibrium ``eq.state``;
* :class:`~glidectl.controllers.ctol.SteadyGlideController`: :class:`~glidectl.models.ctol.CTOLReduced` (states
  ``(Vbar, gammabar, thetabar, Omega2bar)`` of (7.8)-(7.11) about the glide), equilibrium the origin (the same
  vector field as :class:`~glidectl.models.ctol_closed_loop.ClosedLoopCTOL`).

(The full longitudinal and CTOL states contain the position, which moves along a steady glide, so their closed loops
have no equilibrium; the glide-path and reduced coordinates drop it.) Trajectory-tracking controllers (feedback
linearization, stable inversion, approximate linearization, steady-glide tracking) are time-varying and have no such
closed loop.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from .. import checks
from ..analysis.linear import design_model
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from ..models.buoyancy_glider import BuoyancyGlider
from ..models.closed_loop import ClosedLoop
from ..models.ctol import CTOLReduced
from ..models.elevator_glider import ElevatorBuoyancyGlider
from ..models.torque_glider import TorqueControlledGlider
from .buoyancy import BuoyancyController
from .ctol import SteadyGlideController
from .elevator import ElevatorBuoyancyController
from .linear import LinearGlideController
from .output_feedback import LQGController
from .torque import TorqueDesign

__all__ = ["closed_loop"]


def closed_loop(controller_or_model: Any, law: Callable[[Any], Any] | None = None, *,
                equilibrium: Any = None) -> ClosedLoop:
    """The closed loop of a controller as an input-free model (``rhs(x)``, ``equilibrium``, ``state_names``...).

    Parameters
    ----------
    controller_or_model
        With ``law`` omitted: a controller of this package (see the module docstring for the plant, coordinates
        and equilibrium of each): :class:`~glidectl.controllers.linear.LinearGlideController` (from
        :func:`~glidectl.controllers.linear.lqr_glide` or :func:`~glidectl.controllers.linear.place_glide`),
        :class:`~glidectl.controllers.torque.TorqueDesign`, :class:`~glidectl.controllers.buoyancy.BuoyancyController`,
        :class:`~glidectl.controllers.elevator.ElevatorBuoyancyController`,
        :class:`~glidectl.controllers.ctol.SteadyGlideController` or
        :class:`~glidectl.controllers.output_feedback.LQGController` (plant plus estimator).
        With ``law``: any glidectl model (the plant).
    law : callable, optional
        State feedback ``u = law(x)``, batch-capable (``x`` of shape ``(..., n)`` to ``u`` of shape ``(..., m)``,
        the plant's units). A controller ``c(t, x)`` of this package is time-invariant: pass ``c.u``.
    equilibrium : array_like, optional
        Closed-loop equilibrium (plant state units) when ``law`` is given; with a controller it is the one the
        controller was designed for (giving it too raises).

    Returns
    -------
    ClosedLoop

    Raises
    ------
    ArgumentTypeError
        Not a controller of this package (or a time-varying one, e.g. a tracking controller); with ``law``: the
        plant is not a glidectl model or ``law`` is not callable.
    ArgumentError
        ``equilibrium`` given with a controller, or (with ``law``) not a finite state of the plant.
    ModelError
        A :class:`LinearGlideController` built without its vehicle, or a controller whose plant refuses its vehicle.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> loop = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0))
    >>> loop.state_names, loop.input_names
    (('V', 'gamma', 'alpha', 'Omega2', 'm0'), ())
    >>> sim = gc.simulate(loop, loop.equilibrium + [0.1, 0.0, 0.0, 0.0, 0.0], 100.0)
    >>> bool(np.abs(sim.x[-1] - loop.equilibrium).max() < 1e-6)
    True
    """
    if law is not None:
        checks.function("law", law)
        desc = getattr(law, "__qualname__", type(law).__name__)
        return ClosedLoop(controller_or_model, law, equilibrium, desc)
    c = controller_or_model
    if equilibrium is not None:
        raise ArgumentError("equilibrium= is only for closed_loop(plant, law): a controller brings its own "
                            "(the equilibrium it was designed for)")
    if isinstance(c, LinearGlideController):
        if c.vehicle is None:
            raise ModelError("this LinearGlideController was built without its vehicle (use lqr_glide or "
                                "place_glide), so its plant is unknown; use closed_loop(design_model(veh, glide, "
                                "inputs)[0], controller.path_input)")
        model, xe = design_model(c.vehicle, c.glide, c.inputs,  # type: ignore[arg-type]
                                 reduce_fixed=bool(c.fixed_actuators))
        xe = xe.copy()
        xe[0] = c.path_offset
        return ClosedLoop(model, c.path_input, xe,
                          f"{c.method} glide-path regulator (gamma_e = {np.degrees(c.glide.gamma):.4g} deg)")
    if isinstance(c, LQGController):
        return c.closed_loop()
    if isinstance(c, TorqueDesign):
        if c.plant_vehicle is None:
            raise ModelError("this TorqueDesign does not carry its open-loop vehicle (use design_torque_control); "
                                "use design.law.closed_loop(vehicle, design.equilibrium)")
        return ClosedLoop(TorqueControlledGlider(c.plant_vehicle), c.law.u, c.equilibrium,
                          f"torque law (6.5) for {c.target} = {c.target_value:.6g}")
    if isinstance(c, BuoyancyController):
        return ClosedLoop(BuoyancyGlider(c.vehicle), c.u, c.eq.state, f"buoyancy law (6.9), K_b = {c.K_b:g}")
    if isinstance(c, ElevatorBuoyancyController):
        return ClosedLoop(ElevatorBuoyancyGlider(c.vehicle), c.u, c.eq.state,
                          f"elevator and buoyancy laws (6.21)-(6.22), K = {c.K:g}")
    if isinstance(c, SteadyGlideController):
        g = c.glide
        plant = CTOLReduced(c.vehicle, g.speed, g.gamma, g.theta, c.T)
        return ClosedLoop(plant, c.reduced_input, np.zeros(4),
                          f"steady-glide law (7.16)-(7.20), k3 = {c.k3:g}, k4 = {c.k4:g}")
    raise ArgumentTypeError(
        f"closed_loop() does not know the plant and equilibrium of a {type(c).__name__}: give the plant and a state "
        "feedback, closed_loop(model, law) with u = law(x). Supported controllers: LinearGlideController, "
        "TorqueDesign, BuoyancyController, ElevatorBuoyancyController, SteadyGlideController, LQGController "
        "(tracking controllers "
        "are time-varying)")
