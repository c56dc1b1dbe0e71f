"""Robustness to what is not known about a vehicle: Monte Carlo of any study over its ``[uncertainty]`` table
(:mod:`~glidectl.robustness.monte_carlo`), dive cycles and waypoint missions flown by sampled vehicles under the
nominal design (:mod:`~glidectl.robustness.missions`) and the stability of a closed loop whose controller keeps its
nominal design (:mod:`~glidectl.robustness.stability`) and its region of attraction over the whole box
(:mod:`~glidectl.robustness.certificates`)."""

from .certificates import ControllerMember, certify_roa_robust
from .missions import (
    DIVE_METRICS,
    MISSION_METRICS,
    DiveStudy,
    MissionStudy,
    dive_cycle_ensemble,
    mission_ensemble,
)
from .monte_carlo import MonteCarlo, monte_carlo
from .stability import LoopPoles, RobustStability, WorstCase, loop_poles, robust_stability, with_vehicle

__all__ = ["DIVE_METRICS", "MISSION_METRICS", "ControllerMember", "DiveStudy", "LoopPoles", "MissionStudy",
           "MonteCarlo", "RobustStability", "WorstCase", "certify_roa_robust", "dive_cycle_ensemble", "loop_poles",
           "mission_ensemble", "monte_carlo", "robust_stability", "with_vehicle"]
