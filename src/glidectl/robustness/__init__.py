"""Robustness to what is not known about a vehicle: Monte Carlo of any study over its ``[uncertainty]`` table
(:mod:`~glidectl.robustness.monte_carlo`) and the stability of a closed loop whose controller keeps its nominal
design (:mod:`~glidectl.robustness.stability`)."""

from .monte_carlo import MonteCarlo, monte_carlo, run_chunks
from .stability import LoopPoles, RobustStability, WorstCase, loop_poles, robust_stability, with_vehicle

__all__ = ["LoopPoles", "MonteCarlo", "RobustStability", "WorstCase", "loop_poles", "monte_carlo",
           "robust_stability", "run_chunks", "with_vehicle"]
