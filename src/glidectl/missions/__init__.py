"""Missions: guidance and onboard behaviours of a glider flying waypoints in a current (3-D actuated model,
surfacings, GPS fixes, dead reckoning and the depth-averaged current estimate)."""

from .behaviours import (
    LQR_DESIGN_SENSORS,
    STEER_PROBE,
    DiveLQR,
    DivePlan,
    GliderBehaviours,
    dead_zone,
    pitch_heading,
    wrap_angle,
)
from .fly import CONTROLLER_SETS, DiveMetrics, GliderFlight, LegMetrics, MissionRun, fly_mission
from .loop import DR_GAMMA_MIN, MISSION_STATES, MissionLoop, current_corrected_heading
from .mission import MAX_MISSION_DEPTH, Mission

__all__ = ["CONTROLLER_SETS", "DR_GAMMA_MIN", "LQR_DESIGN_SENSORS", "MAX_MISSION_DEPTH", "MISSION_STATES",
           "STEER_PROBE", "DiveLQR", "DiveMetrics", "DivePlan", "GliderBehaviours", "GliderFlight", "LegMetrics",
           "Mission", "MissionLoop", "MissionRun", "current_corrected_heading", "dead_zone", "fly_mission",
           "pitch_heading", "wrap_angle"]
