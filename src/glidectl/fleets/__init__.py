"""Fleets: gliders coordinated at their surfacings (thesis chapter 3): the fleet simulator and its coordinators."""

from .coverage import Coverage, CurvePatrol, coverage_metric, mapping_error
from .drifter import DrifterTracking, drift_track
from .fleet import FleetRun, fly_fleet
from .formation import SHAPES, FormationControl, GradientClimbing, shape_offsets

__all__ = ["SHAPES", "Coverage", "CurvePatrol", "DrifterTracking", "FleetRun", "FormationControl", "GradientClimbing",
           "coverage_metric",
           "drift_track", "fly_fleet", "mapping_error", "shape_offsets"]
