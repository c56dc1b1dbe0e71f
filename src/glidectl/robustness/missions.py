"""Missions under uncertainty: dive cycles and 3-D waypoint missions flown by vehicles drawn from the
``[uncertainty]`` table while the controller keeps the nominal design (:func:`dive_cycle_ensemble`,
:func:`mission_ensemble`, :class:`DiveStudy`, :class:`MissionStudy`).

Each sample flies :func:`glidectl.dive_cycle` or :func:`glidectl.fly_mission` with ``design_vehicle`` the nominal
vehicle: the controller's gains and set points (the legs' glides, the speeds of dead reckoning) are those of the
vehicle the engineer designed for, and the sampled vehicle is the one that flies. The samples run through
:func:`~glidectl.robustness.monte_carlo.monte_carlo` (a process pool or a dask cluster's executor), so the result
is a :class:`~glidectl.robustness.monte_carlo.MonteCarlo` with the per-sample metrics, their quantiles and
``plot()``.
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

from .. import checks
from ..controllers.dive_cycle import CONTROLLER_NAMES, cycle_summary, dive_cycle, dive_cycles_batched
from ..errors import ArgumentError, ArgumentTypeError, GlidectlError
from ..missions import Mission, fly_mission
from ..params import Vehicle
from .monte_carlo import MonteCarlo, monte_carlo

__all__ = ["DIVE_METRICS", "MISSION_METRICS", "DiveStudy", "MissionStudy", "dive_cycle_ensemble", "mission_ensemble"]

#: Keyword arguments of :func:`glidectl.dive_cycle` that the batched flight takes
#: (:func:`~glidectl.controllers.dive_cycle.dive_cycles_batched`).
BATCH_OPTIONS = frozenset(inspect.signature(dive_cycles_batched).parameters) - {"vehicles", "design_vehicle", "cycles"}

#: The numbers of a dive-cycle sample (:meth:`DiveStudy.__call__`), with their units.
DIVE_METRICS: Mapping[str, str] = {
    "energy_per_km": "J/km", "cycle_time": "s", "saturated_time": "s", "max_overshoot": "m",
    "distance_per_cycle": "m", "energy_per_cycle": "J"}


@dataclass(frozen=True)
class DiveStudy:
    """Dive cycles of a sampled vehicle under the controller designed on ``design_vehicle`` (picklable: it crosses
    process pools).

    Parameters
    ----------
    design_vehicle : Vehicle
        The nominal vehicle the controller is designed on.
    controller : str
        A named controller of :func:`glidectl.dive_cycle` (``"lqr"``, ``"lqg"``, ``"nonlinear"``, ``"pid"``).
    cycles : int
        Dive cycles per sample.
    options : tuple of (str, Any)
        Further keyword arguments of :func:`glidectl.dive_cycle` (depths, speed, gamma, ...).
    """

    design_vehicle: Vehicle = field(repr=False)
    controller: str = "lqr"
    cycles: int = 3
    options: tuple[tuple[str, Any], ...] = ()
    batched: bool = True

    @property
    def units(self) -> dict[str, str]:
        """The unit of each metric (:data:`DIVE_METRICS`)."""
        return dict(DIVE_METRICS)

    @property
    def name(self) -> str:
        """What the study flies, for tables and titles."""
        return f"dive_cycle({self.controller}, {self.cycles} cycles, designed on '{self.design_vehicle.name}')"

    def __call__(self, veh: Vehicle) -> dict[str, float]:
        """The metrics of :data:`DIVE_METRICS` for ``veh``: per-cycle means of the pump energy per km of horizontal
        distance, the cycle time, the saturated time, the distance and the energy, and the largest overshoot of a
        depth limit."""
        run = dive_cycle(veh, self.controller, cycles=self.cycles, design_vehicle=self.design_vehicle,
                         **dict(self.options))
        return _dive_numbers(run.as_dict())

    @property
    def can_batch(self) -> bool:
        """Whether :meth:`batch` flies the vehicles together: the ``"lqr"`` controller, with options
        :func:`~glidectl.controllers.dive_cycle.dive_cycles_batched` takes (no sensors, noise or integrator
        choice)."""
        return self.batched and self.controller == "lqr" and all(k in BATCH_OPTIONS for k, _ in self.options)

    def batch(self, vehicles: list[Vehicle]) -> list[dict[str, float] | GlidectlError]:
        """:meth:`__call__` on each vehicle: flown together when :attr:`can_batch`
        (:func:`~glidectl.controllers.dive_cycle.dive_cycles_batched`), else one by one; per vehicle its metrics or
        the GlidectlError that stopped it."""
        if not self.can_batch:
            out: list[dict[str, float] | GlidectlError] = []
            for veh in vehicles:
                try:
                    out.append(self(veh))
                except GlidectlError as exc:
                    out.append(exc)
            return out
        runs = dive_cycles_batched(vehicles, self.design_vehicle, cycles=self.cycles, **dict(self.options))
        return [r if isinstance(r, GlidectlError) else _dive_numbers(cycle_summary(r)) for r in runs]


def _dive_numbers(d: Mapping[str, float]) -> dict[str, float]:
    """:data:`DIVE_METRICS` from a dive cycle's per-cycle means
    (:func:`~glidectl.controllers.dive_cycle.cycle_summary`)."""
    return {"energy_per_km": 1000.0 * d["energy_per_cycle"] / d["distance_per_cycle"],
            "cycle_time": d["duration_per_cycle"], "saturated_time": d["saturated_time_per_cycle"],
            "max_overshoot": d["max_overshoot"], "distance_per_cycle": d["distance_per_cycle"],
            "energy_per_cycle": d["energy_per_cycle"]}


def dive_cycle_ensemble(veh: Vehicle, n: int = 1000, seed: int = 0, controller: str = "lqr", cycles: int = 3, *,
                        executor: Executor | None = None, chunks: int | None = None, batched: bool = True,
                        **options: Any) -> MonteCarlo:
    """Dive cycles of ``n`` vehicles drawn from ``veh``'s ``[uncertainty]`` table, each flown by the controller
    designed on ``veh`` (module docstring).

    The ``"lqr"`` samples of a chunk fly together (``batched``,
    :func:`~glidectl.controllers.dive_cycle.dive_cycles_batched`): one stacked state, each sample with its own step
    size and depth switches, many times faster than one by one (``bench/README.md``); their metrics agree with
    :func:`glidectl.dive_cycle` to its integration tolerance (about 1e-5 on times and distances, 3e-4 on
    energies and overshoots), not to the bit (Dormand-Prince against LSODA).

    Parameters
    ----------
    veh : Vehicle
        The nominal vehicle, with an ``[uncertainty]`` table.
    n, seed : int
        Samples and their seed (the same samples whatever the executor).
    controller : str
        ``"lqr"``, ``"lqg"``, ``"nonlinear"`` or ``"pid"`` (:func:`glidectl.dive_cycle`).
    cycles : int
        Dive cycles per sample (>= 1).
    executor, chunks :
        As :func:`glidectl.monte_carlo` (a process pool, a dask cluster's executor; batched, the default chunks
        are one per CPU).
    batched : bool
        Fly the ``"lqr"`` samples of a chunk together (ignored for the other controllers, and for options the
        batched flight does not take: ``sensors``, ``noise``, ``method``...).
    **options
        Further keyword arguments of :func:`glidectl.dive_cycle` (``depths``, ``speed``, ``gamma``, ...).

    Returns
    -------
    MonteCarlo
        One row per sample with :data:`DIVE_METRICS`; a sample whose glide does not exist, or whose legs do not
        reach their depths, is a failure with its reason.

    Raises
    ------
    ArgumentError
        If ``controller`` is not a named controller, ``design_vehicle`` is given (it is ``veh``), or as
        :func:`glidectl.monte_carlo`.
    """
    checks.choice("controller", controller, CONTROLLER_NAMES)
    cycles = checks.integer("cycles", cycles, lo=1, hi=1000)
    if "design_vehicle" in options:
        raise ArgumentError("design_vehicle is veh itself in dive_cycle_ensemble: the samples fly, veh designs")
    dive_cycle(veh, controller, cycles=1, **options)      # the nominal mission first: bad options fail here, once
    study = DiveStudy(veh, controller, cycles, tuple(sorted(options.items())), checks.boolean("batched", batched))
    return monte_carlo(study, veh, n, seed, executor=executor, chunks=chunks)


#: The numbers of a waypoint-mission sample (:meth:`MissionStudy.__call__`), with their units.
MISSION_METRICS: Mapping[str, str] = {
    "mission_time": "h", "energy_per_km": "J/km", "max_arrival_error": "m", "max_dead_reckoning_error": "m",
    "waypoints_reached": "-", "distance_made_good": "km"}


@dataclass(frozen=True)
class MissionStudy:
    """A waypoint mission of a sampled vehicle whose dive plan is ``design_vehicle``'s (picklable).

    Parameters
    ----------
    design_vehicle : Vehicle
        The nominal vehicle the plan and the controller are made for.
    mission : Mission
    controller : str
        ``"behaviours"`` or ``"lqr"`` (:func:`glidectl.fly_mission`).
    options : tuple of (str, Any)
        Further keyword arguments of :func:`glidectl.fly_mission` (``current``, ``model``, ``gps_noise``, ...).
    """

    design_vehicle: Vehicle = field(repr=False)
    mission: Mission = field(repr=False)
    controller: str = "behaviours"
    options: tuple[tuple[str, Any], ...] = ()

    @property
    def units(self) -> dict[str, str]:
        """The unit of each metric (:data:`MISSION_METRICS`)."""
        return dict(MISSION_METRICS)

    @property
    def name(self) -> str:
        """What the study flies, for tables and titles."""
        return (f"fly_mission({self.controller}, {len(self.mission.waypoints)} waypoints, designed on "
                f"'{self.design_vehicle.name}')")

    def __call__(self, veh: Vehicle) -> dict[str, float]:
        """The metrics of :data:`MISSION_METRICS` for ``veh``: mission time, pump energy per km made good, the
        largest arrival and dead-reckoning errors over the legs, the fraction of waypoints reached and the distance
        made good."""
        run = fly_mission(veh, self.mission, self.controller, design_vehicle=self.design_vehicle,
                          **dict(self.options))
        legs = run.legs
        return {"mission_time": run.duration / 3600.0, "energy_per_km": run.energy_per_km,
                "max_arrival_error": max(leg.arrival_error for leg in legs),
                "max_dead_reckoning_error": max(leg.dead_reckoning_error for leg in legs),
                "waypoints_reached": sum(leg.arrived for leg in legs) / len(legs),
                "distance_made_good": run.distance_made_good / 1000.0}


def mission_ensemble(veh: Vehicle, mission: Mission, n: int = 200, seed: int = 0, controller: str = "behaviours", *,
                     executor: Executor | None = None, chunks: int | None = None, model: str = "fast",
                     **options: Any) -> MonteCarlo:
    """The 3-D waypoint ``mission`` flown by ``n`` vehicles drawn from ``veh``'s ``[uncertainty]`` table, each
    with the dive plan and controller made for ``veh`` (module docstring).

    Parameters
    ----------
    veh : Vehicle
        The nominal vehicle, with an ``[uncertainty]`` table.
    mission : Mission
    n, seed : int
        Samples and their seed (the same samples whatever the executor).
    controller : str
        ``"behaviours"`` or ``"lqr"``.
    executor, chunks :
        As :func:`glidectl.monte_carlo`.
    model : {"fast", "full"}
        :func:`glidectl.fly_mission`'s model; ``"fast"`` (default) replays one full-model dive per sample along each
        dive's track, 5-6 times faster.
    **options
        Further keyword arguments of :func:`glidectl.fly_mission` (``current``, ``gps_noise``, ...; the GPS noise
        has fly_mission's seed 0 in every sample).

    Returns
    -------
    MonteCarlo
        One row per sample with :data:`MISSION_METRICS`.

    Raises
    ------
    ArgumentTypeError
        If ``mission`` is not a Mission.
    ArgumentError
        If ``controller`` is not ``"behaviours"`` or ``"lqr"``, ``design_vehicle`` is among ``options``, or as
        :func:`glidectl.monte_carlo`.
    """
    if not isinstance(mission, Mission):
        raise ArgumentTypeError(f"mission must be a glidectl.Mission, got {type(mission).__name__}")
    checks.choice("controller", controller, ("behaviours", "lqr"))
    if "design_vehicle" in options:
        raise ArgumentError("design_vehicle is veh itself in mission_ensemble: the samples fly, veh plans")
    options = {**options, "model": model}
    study = MissionStudy(veh, mission, controller, tuple(sorted(options.items())))
    study(veh)                                             # the nominal mission first: bad options fail here, once
    return monte_carlo(study, veh, n, seed, executor=executor, chunks=chunks)
