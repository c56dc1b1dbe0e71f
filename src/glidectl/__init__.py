"""glidectl: control-systems design for gliding vehicles (underwater gliders, CTOL aircraft).

One flat namespace, organised by task (see ``docs/api.md``)::

    import glidectl as gc
    veh = gc.load_vehicle("rogue")                      # vehicles: preset name or path to a TOML file
    g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)      # trims
    sys = gc.linearize_glide(veh, g, inputs="force")    # linear analysis: control.StateSpace, named signals
    ctrl = gc.lqr_glide(veh, g)                         # controllers
    sim = gc.simulate(gc.LongitudinalGlider(veh), g.force_state(), 60.0, ctrl)   # simulation
    cert = gc.certify_roa(gc.benchmarks.van_der_pol(), degree=4)                 # certificates

Reports are built with :mod:`glidectl.report` (``Report``) from design scripts (``designs/*.py``).
"""

from . import benchmarks
from .analysis.closed_loop import (
    BatchComparison,
    ControllerRecord,
    StateFeedback,
    compare_controllers,
    lqr_state_feedback,
)
from .analysis.flight_fit import FlightFit, fit_flight_model, law_start, predict_flight
from .analysis.helix_existence import ExistenceScan, existence_scan
from .analysis.helix_stability import HelixRbhLocus, helix_rbh_locus, resolved_crossing
from .analysis.helix_sweeps import HelixSweep, helix_sweep, straight_glides
from .analysis.linear import (
    DepthGlidePathModel,
    FixedActuatorModel,
    Modes,
    ModeStates,
    RankTest,
    controllability,
    design_model,
    fixed_actuators,
    glide_model,
    linearize_glide,
    modes,
    observability,
)
from .analysis.locus import BreakPoint, ParameterLocus, mbar_locus, parameter_locus, rbh_locus, uncontrolled_eigs
from .analysis.measure import box_measure, box_points
from .batch import BatchResult, integrate_batch
from .controllers.buoyancy import (
    BuoyancyController,
    BuoyancyEquilibrium,
    BuoyancyLyapunovCheck,
    buoyancy_equilibrium,
    buoyancy_lyapunov_check,
)
from .controllers.closed_loop import closed_loop
from .controllers.ctol import SteadyGlideController
from .controllers.ctol import closed_loop_eigenvalues as ctol_closed_loop_eigenvalues
from .controllers.ctol_approximate_linearization import (
    ApproximateLinearizationController,
    approximate_linearization_eigenvalues,
    track_approximate_linearization,
)
from .controllers.ctol_feedback_linearization import (
    BlowUp,
    FeedbackLinearizingController,
    feedback_linearization_blowup,
)
from .controllers.ctol_map import CTOLGlideMap, ctol_glide_map
from .controllers.ctol_runs import TrackingRun
from .controllers.ctol_stable_inversion import StableInversion, stable_inversion, track_stable_inversion
from .controllers.ctol_tracking import GlideTracking, ParetoStudy, pareto_front, track_with_steady_glides, tracking_grid
from .controllers.ctol_trajectory import ClimbTrajectory, climb_trajectory
from .controllers.ctol_zero_dynamics import ZeroDynamics, zero_dynamics
from .controllers.dive_cycle import (
    CycleMetrics,
    DiveCycleRun,
    MissionComparison,
    PitchPID,
    SampledGlideLQG,
    ScheduledGlideLQG,
    ScheduledGlideLQR,
    compare_missions,
    dive_cycle,
    lqg_filter_noise,
    pump_energy,
    tune_pitch_pid,
)
from .controllers.elevator import (
    ElevatorBuoyancyController,
    ElevatorEquilibrium,
    ElevatorExample,
    elevator_equilibrium,
    elevator_example,
    infer_J2,
)
from .controllers.elevator import closed_loop_eigenvalues as elevator_closed_loop_eigenvalues
from .controllers.linear import (
    DecoupledAccelerationFeedback,
    LinearGlideController,
    decoupled_gain_matrix,
    default_actuate,
    lqr_glide,
    place_glide,
)
from .controllers.moving_mass import RealizedTorqueComparison, compare_realized_torque
from .controllers.output_feedback import LQGController, SampledLQG, lqg_glide
from .controllers.saturation import saturated_loop
from .controllers.torque import (
    TorqueDesign,
    TorqueGainFamily,
    closed_loop_formulas,
    design_torque_control,
    torque_gain_family,
)
from .derivatives import hessian, jacobians
from .environment import Current
from .errors import (
    ArgumentError,
    ArgumentTypeError,
    BudgetError,
    DesignError,
    GlidectlError,
    InfeasibleGlideError,
    ModelError,
    OutputError,
    RecordError,
    SolverError,
    VehicleFileError,
    VehicleMismatchError,
)
from .fleets import (
    Coverage,
    CurvePatrol,
    DrifterTracking,
    FleetRun,
    FormationControl,
    GradientClimbing,
    coverage_metric,
    drift_track,
    fly_fleet,
)
from .hydro import excess_mass, lift_drag
from .iosys import to_iosys
from .missions import (
    DiveLQR,
    DiveMetrics,
    DivePlan,
    GliderBehaviours,
    GliderFlight,
    LegMetrics,
    Mission,
    MissionRun,
    fly_mission,
)
from .models import phugoid_hamiltonian
from .models.actuated import ActuatedGlider
from .models.actuated3d import ActuatedGlider3D
from .models.buoyancy_glider import BuoyancyGlider
from .models.closed_loop import ClosedLoop
from .models.ctol import CTOLAircraft, CTOLReduced, ExtendedCTOL
from .models.ctol_closed_loop import ClosedLoopCTOL
from .models.elevator_glider import ElevatorBuoyancyGlider
from .models.glider3d import FixedMassGlider3D, Glider3D, R_to_ypr, quat_to_R, ypr_to_quat, ypr_to_R
from .models.longitudinal import STATE_UNITS, AccelerationControlledGlider, GlidePathModel, LongitudinalGlider
from .models.nondimensional import NondimensionalModel, NondimensionalScaling, SlowModel
from .models.phugoid import C_STEADY, PhugoidClass, PhugoidModel, classify_C, initial_state_for_C, orbit_period
from .models.realized_torque import RealizedTorqueLoop
from .models.reduced import ReducedLongitudinalGlider
from .models.saturated_loop import AffineLimit
from .models.torque_glider import TorqueControlledGlider
from .params import Actuator, Vehicle, VehicleSample, list_presets, load_vehicle
from .records import DiveRecord, MaskSettings, example_record_path, read_dive_record
from .roa import (
    BudgetOptions,
    Certificate,
    ConvergentSlice,
    Extent,
    HistoryRow,
    PolySystem,
    RemainderBound,
    ROACertificate,
    ROAVerification,
    SamplingOptions,
    SolverOptions,
    SOSSize,
    SurrogateOptions,
    certify_roa,
    convergent_extent,
    convergent_slice,
    dVdt,
    estimate_sos_size,
    installed_sdp_solvers,
    lyapunov_matrix,
    lyapunov_quadratic,
    max_level,
    recast,
    surrogate_error,
    surrogate_system,
    taylor_system,
    validity_box,
)
from .roa.lmi import EllipsoidCertificate, EllipsoidVerification, SaturatedLoop, certify_roa_lmi
from .roa.robust import RobustEllipsoidCertificate, RobustVerification, certify_roa_family
from .robustness import (
    DiveStudy,
    LoopPoles,
    MissionStudy,
    MonteCarlo,
    RobustStability,
    WorstCase,
    certify_roa_robust,
    dive_cycle_ensemble,
    loop_poles,
    mission_ensemble,
    monte_carlo,
    robust_stability,
    with_vehicle,
)
from .sim import ActuatedSimulation, Ensemble, Simulation, simulate, simulate_actuated, simulate_many
from .stability.composite import CompositeCertificate, CompositeVerification, Domain, composite_lyapunov
from .stability.ctol_lyapunov import CTOLLyapunovCertificate, CTOLVerification, ctol_lyapunov
from .stability.singular_perturbation import SingularPerturbation, singular_perturbation
from .stability.unequal_mass import UnequalMassCheck, allowable_delta_m_ratio, unequal_mass_check
from .trim.ctol import CTOLGlide, ctol_glide
from .trim.envelope import GlideEnvelope, glide_envelope
from .trim.flight import SteadyFlight, steady_flight
from .trim.glide import SteadyGlide, permissible_gamma, steady_glide
from .trim.helix import Helix, classify_motion, helix_trim
from .trim.helix_design import HelixDesign, design_helix
from .trim.turn import TurnDesign, design_turn
from .uncertainty import Uncertainty

__version__ = "0.1.0"

#: public names grouped by task (docs/api.md lists the same groups)
API_GROUPS: dict[str, tuple[str, ...]] = {
    "vehicles": (
        "Actuator", "list_presets", "load_vehicle", "Uncertainty", "Vehicle", "VehicleSample",
    ),
    "models": (
        "AccelerationControlledGlider", "benchmarks", "BuoyancyGlider", "C_STEADY", "classify_C", "ClosedLoop",
        "ClosedLoopCTOL", "CTOLAircraft", "CTOLReduced", "ElevatorBuoyancyGlider", "ExtendedCTOL",
        "FixedMassGlider3D", "GlidePathModel", "Glider3D", "initial_state_for_C", "LongitudinalGlider",
        "NondimensionalModel", "NondimensionalScaling", "orbit_period", "phugoid_hamiltonian", "PhugoidClass",
        "PhugoidModel", "quat_to_R", "R_to_ypr", "RealizedTorqueLoop", "ReducedLongitudinalGlider", "SlowModel",
        "TorqueControlledGlider", "ypr_to_quat", "ypr_to_R",
        "DepthGlidePathModel",
        "ActuatedGlider", "ActuatedGlider3D",
        "STATE_UNITS",
    ),
    "flight models and dive records": (
        "DiveRecord", "example_record_path", "excess_mass", "fit_flight_model", "FlightFit", "law_start",
        "lift_drag", "MaskSettings", "predict_flight", "read_dive_record", "steady_flight", "SteadyFlight",
    ),
    "trims": (
        "buoyancy_equilibrium", "BuoyancyEquilibrium", "classify_motion", "ctol_glide", "CTOLGlide",
        "design_helix", "elevator_equilibrium", "ElevatorEquilibrium", "Helix", "helix_trim", "HelixDesign",
        "permissible_gamma", "steady_glide", "SteadyGlide",
        "glide_envelope", "GlideEnvelope",
        "design_turn", "TurnDesign",
    ),
    "linear analysis": (
        "BreakPoint", "controllability", "existence_scan", "ExistenceScan", "glide_model", "helix_rbh_locus",
        "helix_sweep", "HelixRbhLocus", "HelixSweep", "hessian", "jacobians", "linearize_glide", "mbar_locus",
        "Modes", "modes", "observability", "parameter_locus", "ParameterLocus", "RankTest", "rbh_locus",
        "resolved_crossing", "straight_glides", "uncontrolled_eigs",
        "design_model", "fixed_actuators", "FixedActuatorModel", "ModeStates",
    ),
    "controllers": (
        "approximate_linearization_eigenvalues", "ApproximateLinearizationController", "BlowUp",
        "BuoyancyController", "climb_trajectory", "ClimbTrajectory", "closed_loop", "closed_loop_formulas",
        "compare_realized_torque", "ctol_closed_loop_eigenvalues", "ctol_glide_map", "CTOLGlideMap",
        "decoupled_gain_matrix",
        "DecoupledAccelerationFeedback", "design_torque_control", "elevator_closed_loop_eigenvalues",
        "elevator_example", "ElevatorBuoyancyController", "ElevatorExample", "feedback_linearization_blowup",
        "FeedbackLinearizingController", "GlideTracking", "infer_J2", "LinearGlideController", "lqr_glide",
        "lqr_state_feedback", "pareto_front", "ParetoStudy", "place_glide", "RealizedTorqueComparison",
        "stable_inversion", "StableInversion", "StateFeedback", "SteadyGlideController", "torque_gain_family",
        "TorqueDesign", "TorqueGainFamily", "track_approximate_linearization", "track_stable_inversion",
        "track_with_steady_glides", "tracking_grid", "TrackingRun", "zero_dynamics", "ZeroDynamics",
        "default_actuate", "lqg_glide", "LQGController",
        "PitchPID", "ScheduledGlideLQR", "tune_pitch_pid",
        "ScheduledGlideLQG",
        "lqg_filter_noise", "SampledGlideLQG", "SampledLQG",
    ),
    "stability and certificates": (
        "allowable_delta_m_ratio", "box_measure", "box_points", "buoyancy_lyapunov_check", "BuoyancyLyapunovCheck",
        "certify_roa", "Certificate", "convergent_extent", "convergent_slice", "ConvergentSlice", "Extent",
        "SamplingOptions", "BudgetOptions",
        "SurrogateOptions", "SolverOptions", "HistoryRow",
        "composite_lyapunov", "CompositeCertificate", "CompositeVerification", "ctol_lyapunov",
        "CTOLLyapunovCertificate", "CTOLVerification", "Domain", "dVdt", "estimate_sos_size", "lyapunov_matrix",
        "installed_sdp_solvers", "lyapunov_quadratic", "max_level", "PolySystem", "recast", "ROACertificate",
        "ROAVerification",
        "singular_perturbation", "SingularPerturbation", "SOSSize", "taylor_system", "unequal_mass_check",
        "UnequalMassCheck",
        "certify_roa_lmi", "EllipsoidCertificate", "EllipsoidVerification", "SaturatedLoop", "saturated_loop",
        "AffineLimit",
        "RemainderBound", "surrogate_error", "surrogate_system",
        "validity_box",
        "certify_roa_family", "RobustEllipsoidCertificate", "RobustVerification",
    ),
    "simulation": (
        "BatchComparison", "BatchResult", "compare_controllers", "ControllerRecord", "Ensemble",
        "integrate_batch", "simulate", "simulate_many", "Simulation",
        "to_iosys",
        "ActuatedSimulation", "compare_missions", "CycleMetrics", "dive_cycle", "DiveCycleRun", "MissionComparison",
        "pump_energy", "simulate_actuated",
    ),
    "missions": (
        "Current", "DiveLQR", "DiveMetrics", "DivePlan", "fly_mission", "GliderBehaviours", "GliderFlight",
        "LegMetrics", "Mission", "MissionRun",
    ),
    "fleets": (
        "Coverage", "coverage_metric", "CurvePatrol", "drift_track", "DrifterTracking", "FleetRun", "fly_fleet",
        "FormationControl", "GradientClimbing",
    ),
    "robustness": (
        "dive_cycle_ensemble", "DiveStudy", "LoopPoles", "loop_poles", "mission_ensemble", "MissionStudy",
        "monte_carlo", "MonteCarlo", "robust_stability", "RobustStability", "with_vehicle", "WorstCase",
        "certify_roa_robust",
    ),
    "errors": (
        "ArgumentError", "ArgumentTypeError", "BudgetError", "DesignError", "GlidectlError", "InfeasibleGlideError",
        "ModelError", "OutputError", "RecordError", "SolverError", "VehicleFileError", "VehicleMismatchError",
    ),
}

__all__ = [
    "C_STEADY",
    "STATE_UNITS",
    "AccelerationControlledGlider",
    "ActuatedGlider",
    "ActuatedGlider3D",
    "ActuatedSimulation",
    "Actuator",
    "AffineLimit",
    "ApproximateLinearizationController",
    "ArgumentError",
    "ArgumentTypeError",
    "BatchComparison",
    "BatchResult",
    "BlowUp",
    "BreakPoint",
    "BudgetError",
    "BudgetOptions",
    "BuoyancyController",
    "BuoyancyEquilibrium",
    "BuoyancyGlider",
    "BuoyancyLyapunovCheck",
    "CTOLAircraft",
    "CTOLGlide",
    "CTOLGlideMap",
    "CTOLLyapunovCertificate",
    "CTOLReduced",
    "CTOLVerification",
    "Certificate",
    "ClimbTrajectory",
    "ClosedLoop",
    "ClosedLoopCTOL",
    "CompositeCertificate",
    "CompositeVerification",
    "ControllerRecord",
    "ConvergentSlice",
    "Coverage",
    "Current",
    "CurvePatrol",
    "CycleMetrics",
    "DecoupledAccelerationFeedback",
    "DepthGlidePathModel",
    "DesignError",
    "DiveCycleRun",
    "DiveLQR",
    "DiveMetrics",
    "DivePlan",
    "DiveRecord",
    "DiveStudy",
    "Domain",
    "DrifterTracking",
    "ElevatorBuoyancyController",
    "ElevatorBuoyancyGlider",
    "ElevatorEquilibrium",
    "ElevatorExample",
    "EllipsoidCertificate",
    "EllipsoidVerification",
    "Ensemble",
    "ExistenceScan",
    "ExtendedCTOL",
    "Extent",
    "FeedbackLinearizingController",
    "FixedActuatorModel",
    "FixedMassGlider3D",
    "FleetRun",
    "FlightFit",
    "FormationControl",
    "GlideEnvelope",
    "GlidePathModel",
    "GlideTracking",
    "GlidectlError",
    "Glider3D",
    "GliderBehaviours",
    "GliderFlight",
    "GradientClimbing",
    "Helix",
    "HelixDesign",
    "HelixRbhLocus",
    "HelixSweep",
    "HistoryRow",
    "InfeasibleGlideError",
    "LQGController",
    "LegMetrics",
    "LinearGlideController",
    "LongitudinalGlider",
    "LoopPoles",
    "MaskSettings",
    "Mission",
    "MissionComparison",
    "MissionRun",
    "MissionStudy",
    "ModeStates",
    "ModelError",
    "Modes",
    "MonteCarlo",
    "NondimensionalModel",
    "NondimensionalScaling",
    "OutputError",
    "ParameterLocus",
    "ParetoStudy",
    "PhugoidClass",
    "PhugoidModel",
    "PitchPID",
    "PolySystem",
    "ROACertificate",
    "ROAVerification",
    "R_to_ypr",
    "RankTest",
    "RealizedTorqueComparison",
    "RealizedTorqueLoop",
    "RecordError",
    "ReducedLongitudinalGlider",
    "RemainderBound",
    "RobustEllipsoidCertificate",
    "RobustStability",
    "RobustVerification",
    "SOSSize",
    "SampledGlideLQG",
    "SampledLQG",
    "SamplingOptions",
    "SaturatedLoop",
    "ScheduledGlideLQG",
    "ScheduledGlideLQR",
    "Simulation",
    "SingularPerturbation",
    "SlowModel",
    "SolverError",
    "SolverOptions",
    "StableInversion",
    "StateFeedback",
    "SteadyFlight",
    "SteadyGlide",
    "SteadyGlideController",
    "SurrogateOptions",
    "TorqueControlledGlider",
    "TorqueDesign",
    "TorqueGainFamily",
    "TrackingRun",
    "TurnDesign",
    "Uncertainty",
    "UnequalMassCheck",
    "Vehicle",
    "VehicleFileError",
    "VehicleMismatchError",
    "VehicleSample",
    "WorstCase",
    "ZeroDynamics",
    "allowable_delta_m_ratio",
    "approximate_linearization_eigenvalues",
    "benchmarks",
    "box_measure",
    "box_points",
    "buoyancy_equilibrium",
    "buoyancy_lyapunov_check",
    "certify_roa",
    "certify_roa_family",
    "certify_roa_lmi",
    "certify_roa_robust",
    "classify_C",
    "classify_motion",
    "climb_trajectory",
    "closed_loop",
    "closed_loop_formulas",
    "compare_controllers",
    "compare_missions",
    "compare_realized_torque",
    "composite_lyapunov",
    "controllability",
    "convergent_extent",
    "convergent_slice",
    "coverage_metric",
    "ctol_closed_loop_eigenvalues",
    "ctol_glide",
    "ctol_glide_map",
    "ctol_lyapunov",
    "dVdt",
    "decoupled_gain_matrix",
    "default_actuate",
    "design_helix",
    "design_model",
    "design_torque_control",
    "design_turn",
    "dive_cycle",
    "dive_cycle_ensemble",
    "drift_track",
    "elevator_closed_loop_eigenvalues",
    "elevator_equilibrium",
    "elevator_example",
    "estimate_sos_size",
    "example_record_path",
    "excess_mass",
    "existence_scan",
    "feedback_linearization_blowup",
    "fit_flight_model",
    "fixed_actuators",
    "fly_fleet",
    "fly_mission",
    "glide_envelope",
    "glide_model",
    "helix_rbh_locus",
    "helix_sweep",
    "helix_trim",
    "hessian",
    "infer_J2",
    "initial_state_for_C",
    "installed_sdp_solvers",
    "integrate_batch",
    "jacobians",
    "law_start",
    "lift_drag",
    "linearize_glide",
    "list_presets",
    "load_vehicle",
    "loop_poles",
    "lqg_filter_noise",
    "lqg_glide",
    "lqr_glide",
    "lqr_state_feedback",
    "lyapunov_matrix",
    "lyapunov_quadratic",
    "max_level",
    "mbar_locus",
    "mission_ensemble",
    "modes",
    "monte_carlo",
    "observability",
    "orbit_period",
    "parameter_locus",
    "pareto_front",
    "permissible_gamma",
    "phugoid_hamiltonian",
    "place_glide",
    "predict_flight",
    "pump_energy",
    "quat_to_R",
    "rbh_locus",
    "read_dive_record",
    "recast",
    "resolved_crossing",
    "robust_stability",
    "saturated_loop",
    "simulate",
    "simulate_actuated",
    "simulate_many",
    "singular_perturbation",
    "stable_inversion",
    "steady_flight",
    "steady_glide",
    "straight_glides",
    "surrogate_error",
    "surrogate_system",
    "taylor_system",
    "to_iosys",
    "torque_gain_family",
    "track_approximate_linearization",
    "track_stable_inversion",
    "track_with_steady_glides",
    "tracking_grid",
    "tune_pitch_pid",
    "uncontrolled_eigs",
    "unequal_mass_check",
    "validity_box",
    "with_vehicle",
    "ypr_to_R",
    "ypr_to_quat",
    "zero_dynamics",
]
