"""Fleets: gliders coordinated at their surfacings (thesis chapter 3): the fleet simulator and its coordinators."""

from .drifter import DrifterTracking, drift_track
from .fleet import FleetRun, fly_fleet
from .formation import SHAPES, FormationControl, shape_offsets

__all__ = ["SHAPES", "DrifterTracking", "FleetRun", "FormationControl", "drift_track", "fly_fleet", "shape_offsets"]
