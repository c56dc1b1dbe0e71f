"""Control laws and their designs: linear (LQR, pole placement, decoupled acceleration feedback) glide-path
controllers of chapter 2, the torque, moving-mass, buoyancy and elevator controllers of chapter 6, and the CTOL
controllers and trajectory-tracking methods of chapter 7 (steady-glide controller, tracking by steady gliding,
feedback linearization, stable inversion, approximate linearization), with :func:`closed_loop` turning a designed
controller into a model. ``closed_loop_eigenvalues`` exists in both :mod:`~glidectl.controllers.ctol` and
:mod:`~glidectl.controllers.elevator`; it is re-exported as ``ctol_closed_loop_eigenvalues`` and
``elevator_closed_loop_eigenvalues``."""

from .buoyancy import (
    BuoyancyController,
    BuoyancyEquilibrium,
    BuoyancyLyapunovCheck,
    buoyancy_equilibrium,
    buoyancy_lyapunov_check,
    nu_b_derivative,
)
from .closed_loop import closed_loop
from .ctol import SteadyGlideController
from .ctol import closed_loop_eigenvalues as ctol_closed_loop_eigenvalues
from .ctol_approximate_linearization import (
    ApproximateLinearizationController,
    approximate_linearization_eigenvalues,
    track_approximate_linearization,
)
from .ctol_feedback_linearization import BlowUp, FeedbackLinearizingController, feedback_linearization_blowup
from .ctol_map import CTOLGlideMap, ctol_glide_map
from .ctol_runs import TrackingRun, simulate_window
from .ctol_stable_inversion import (
    InternalEquilibrium,
    InversionTracker,
    StableInversion,
    stable_inversion,
    track_stable_inversion,
)
from .ctol_tracking import GlideTracking, ParetoStudy, pareto_front, track_with_steady_glides, tracking_grid
from .ctol_trajectory import CLIMB_COEFFS, ClimbTrajectory, climb_trajectory
from .ctol_zero_dynamics import (
    ZeroDynamics,
    feedback_linearizing_inputs,
    frozen_internal_dynamics,
    internal_acceleration,
    level_flight_state,
    outer_loop_acceleration,
    require_inversion_vehicle,
    saddle_directions,
    zero_dynamics,
)
from .elevator import (
    ALPHA_MAX,
    ElevatorBuoyancyController,
    ElevatorEquilibrium,
    ElevatorExample,
    elevator_equilibrium,
    elevator_example,
    infer_J2,
)
from .elevator import closed_loop_eigenvalues as elevator_closed_loop_eigenvalues
from .linear import (
    DEFAULT_MAX_DEVIATION,
    DecoupledAccelerationFeedback,
    LinearGlideController,
    decoupled_gain_matrix,
    lqr_glide,
    place_glide,
)
from .moving_mass import (
    MovingMassTorque,
    RealizedTorqueComparison,
    compare_realized_torque,
    reduced_from_accel,
    simulate_realized_torque,
)
from .torque import (
    TorqueDesign,
    TorqueGainFamily,
    TorqueLaw,
    alpha_for_target,
    closed_loop_formulas,
    design_torque_control,
    peak_torque,
    torque_gain_family,
)

__all__ = [
    "ALPHA_MAX",
    "CLIMB_COEFFS",
    "DEFAULT_MAX_DEVIATION",
    "ApproximateLinearizationController",
    "BlowUp",
    "BuoyancyController",
    "BuoyancyEquilibrium",
    "BuoyancyLyapunovCheck",
    "CTOLGlideMap",
    "ClimbTrajectory",
    "DecoupledAccelerationFeedback",
    "ElevatorBuoyancyController",
    "ElevatorEquilibrium",
    "ElevatorExample",
    "FeedbackLinearizingController",
    "GlideTracking",
    "InternalEquilibrium",
    "InversionTracker",
    "LinearGlideController",
    "MovingMassTorque",
    "ParetoStudy",
    "RealizedTorqueComparison",
    "StableInversion",
    "SteadyGlideController",
    "TorqueDesign",
    "TorqueGainFamily",
    "TorqueLaw",
    "TrackingRun",
    "ZeroDynamics",
    "alpha_for_target",
    "approximate_linearization_eigenvalues",
    "buoyancy_equilibrium",
    "buoyancy_lyapunov_check",
    "climb_trajectory",
    "closed_loop",
    "closed_loop_formulas",
    "compare_realized_torque",
    "ctol_closed_loop_eigenvalues",
    "ctol_glide_map",
    "decoupled_gain_matrix",
    "design_torque_control",
    "elevator_closed_loop_eigenvalues",
    "elevator_equilibrium",
    "elevator_example",
    "feedback_linearization_blowup",
    "feedback_linearizing_inputs",
    "frozen_internal_dynamics",
    "infer_J2",
    "internal_acceleration",
    "level_flight_state",
    "lqr_glide",
    "nu_b_derivative",
    "outer_loop_acceleration",
    "pareto_front",
    "peak_torque",
    "place_glide",
    "reduced_from_accel",
    "require_inversion_vehicle",
    "saddle_directions",
    "simulate_realized_torque",
    "simulate_window",
    "stable_inversion",
    "torque_gain_family",
    "track_approximate_linearization",
    "track_stable_inversion",
    "track_with_steady_glides",
    "tracking_grid",
    "zero_dynamics",
]
