"""Robust regions of attraction of a controller kept at its nominal design: :func:`certify_roa_robust`.

The controller's loop on every vehicle of the ``[uncertainty]`` box is the nominal law on that vehicle's plant
(:func:`~glidectl.robustness.stability.with_vehicle`), about its own equilibrium (found by Newton from the nominal
one, :func:`~glidectl.robustness.stability.loop_poles`), extracted as a saturated loop exactly as the nominal one
(:func:`glidectl.saturated_loop`). :func:`glidectl.certify_roa_family` then certifies one ellipsoid shape about
every member's equilibrium (corner LMIs with common multipliers; see :mod:`glidectl.roa.robust`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..controllers.closed_loop import closed_loop
from ..controllers.output_feedback import PlantWithEstimator
from ..controllers.saturation import saturated_loop
from ..errors import ArgumentTypeError
from ..models.closed_loop import ClosedLoop
from ..models.saturated_loop import SaturatedLoop
from ..params import Vehicle
from ..roa.robust import RobustEllipsoidCertificate, certify_roa_family
from .stability import loop_poles, with_vehicle

__all__ = ["ControllerMember", "certify_roa_robust"]


@dataclass(frozen=True)
class ControllerMember:
    """``member(vehicle)`` of :func:`glidectl.certify_roa_family` for a glidectl closed loop: the nominal law on
    ``vehicle``'s plant, at its own equilibrium, as a saturated loop (picklable).

    Attributes
    ----------
    loop : ClosedLoop
        The nominal closed loop (with its equilibrium).
    free : tuple of int
        The states solved for (the nominal saturated loop's ``free``); the others stay at the nominal values.
    actuator_limits : bool
        As :func:`glidectl.saturated_loop`.
    """

    loop: ClosedLoop
    free: tuple[int, ...]
    actuator_limits: bool = True

    def __call__(self, vehicle: Vehicle) -> SaturatedLoop:
        """The saturated loop of the nominal controller on ``vehicle``.

        Raises
        ------
        ModelError
            If the loop has no equilibrium near the nominal one on ``vehicle``.
        """
        lv = with_vehicle(self.loop, vehicle)
        xe = loop_poles(lv, self.loop.equilibrium, self.free).equilibrium
        return saturated_loop(ClosedLoop(lv.plant, lv.law, xe, lv.description), actuator_limits=self.actuator_limits)


def certify_roa_robust(controller: Any, vehicle: Vehicle | None = None, *, actuator_limits: bool = True,
                       **options: Any) -> RobustEllipsoidCertificate:
    """A region of attraction of ``controller``'s loop valid for every vehicle in the box of the ``[uncertainty]``
    table, the controller kept at its nominal design: one ellipsoid shape about each vehicle's own equilibrium.

    Parameters
    ----------
    controller : controller or ClosedLoop
        A state-feedback controller :func:`glidectl.closed_loop` takes (:func:`glidectl.lqr_glide`,
        :func:`glidectl.place_glide`, the chapter-6 buoyancy and elevator controllers), or its closed loop.
    vehicle : Vehicle, optional
        The nominal vehicle with its ``[uncertainty]`` table (default the loop's vehicle, which must then have one).
    actuator_limits : bool
        Model the actuators' range and rate limits as state-dependent saturations (:func:`glidectl.saturated_loop`).
    **options
        Keyword arguments of :func:`glidectl.certify_roa_family` (``max_vertices``, ``n_samples``, ``seed``,
        ``rounds``, ...).

    Returns
    -------
    RobustEllipsoidCertificate
        Compare ``cert.extent()`` with the nominal certificate's (:func:`glidectl.certify_roa` of
        ``gc.saturated_loop(gc.closed_loop(controller))``) through ``cert.extent_ratio(nominal)``.

    Raises
    ------
    ArgumentTypeError
        If ``controller`` is an output-feedback loop (its estimator would have to keep the nominal vehicle) or
        not a controller :func:`glidectl.closed_loop` takes.
    ArgumentError, ModelError, SolverError
        As :func:`glidectl.certify_roa_family`: no ``[uncertainty]`` table, a box too wide for one shape (the
        message says to try a smaller box), a vehicle of the box without an equilibrium near the nominal one.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5").with_uncertainty({"K_D0": {"rel": 0.05}})
    >>> ctrl = gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0)
    >>> cert = gc.certify_roa_robust(ctrl, rounds=1, n_radii=4, refine=1, n_samples=2, n_hessian=128, n_verify=200,
    ...                              n_simulate=2)
    >>> cert.certified, cert.rigorous
    (True, False)
    """
    loop = controller if isinstance(controller, ClosedLoop) else closed_loop(controller)
    if isinstance(loop.plant, PlantWithEstimator):
        raise ArgumentTypeError("certify_roa_robust takes state-feedback loops: in an output-feedback loop the "
                                "estimator must keep the nominal vehicle while the plant changes")
    sl = saturated_loop(loop, actuator_limits=actuator_limits)
    member = ControllerMember(loop, tuple(int(i) for i in sl.free), actuator_limits)
    return certify_roa_family(sl, member, vehicle, **options)
