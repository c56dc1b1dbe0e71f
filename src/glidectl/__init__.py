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
from .analysis.helix_maps import ExistenceScan, HelixSweep, existence_scan, helix_sweep, straight_glides
from .analysis.helix_stability import HelixRbhLocus, helix_rbh_locus, resolved_crossing
from .analysis.jacobian import hessian, jacobians
from .analysis.linear import Modes, RankTest, controllability, glide_model, linearize_glide, modes, observability
from .analysis.locus import BreakPoint, ParameterLocus, mbar_locus, parameter_locus, rbh_locus, uncontrolled_eigs
from .batch import BatchResult, integrate_batch
from .controllers.buoyancy import (
    BuoyancyController,
    BuoyancyEquilibrium,
    BuoyancyGlider,
    BuoyancyLyapunovCheck,
    buoyancy_equilibrium,
    buoyancy_lyapunov_check,
)
from .controllers.ctol import ClosedLoopCTOL, SteadyGlideController
from .controllers.ctol import closed_loop_eigenvalues as ctol_closed_loop_eigenvalues
from .controllers.ctol_inversion import (
    ApproximateLinearizationController,
    BlowUp,
    ExtendedCTOL,
    FeedbackLinearizingController,
    StableInversion,
    ZeroDynamics,
    approximate_linearization_eigenvalues,
    feedback_linearization_blowup,
    stable_inversion,
    track_approximate_linearization,
    track_stable_inversion,
    zero_dynamics,
)
from .controllers.ctol_runs import TrackingRun
from .controllers.ctol_tracking import GlideTracking, ParetoStudy, pareto_front, track_with_steady_glides, tracking_grid
from .controllers.ctol_trajectory import ClimbTrajectory, climb_trajectory
from .controllers.elevator import (
    ElevatorBuoyancyController,
    ElevatorBuoyancyGlider,
    ElevatorEquilibrium,
    ElevatorExample,
    elevator_equilibrium,
    elevator_example,
)
from .controllers.elevator import closed_loop_eigenvalues as elevator_closed_loop_eigenvalues
from .controllers.linear import (
    DecoupledAccelerationFeedback,
    LinearGlideController,
    decoupled_gain_matrix,
    lqr_glide,
    place_glide,
)
from .controllers.moving_mass import RealizedTorqueComparison, compare_realized_torque
from .controllers.torque import (
    TorqueControlledGlider,
    TorqueDesign,
    TorqueGainFamily,
    closed_loop_formulas,
    design_torque_control,
    torque_gain_family,
)
from .errors import GlidectlError, InfeasibleGlideError, ModelError, SolverError, VehicleFileError
from .models import phugoid_hamiltonian
from .models.ctol import CTOLAircraft, CTOLReduced
from .models.glider3d import FixedMassGlider3D, Glider3D, R_to_ypr, quat_to_R, ypr_to_quat, ypr_to_R
from .models.longitudinal import AccelerationControlledGlider, GlidePathModel, LongitudinalGlider
from .models.phugoid import C_STEADY, PhugoidClass, PhugoidModel, classify_C, initial_state_for_C, orbit_period
from .models.reduced import ReducedLongitudinalGlider
from .params import Vehicle, list_presets, load_vehicle
from .roa import (
    PolySystem,
    ROACertificate,
    certify_roa,
    dVdt,
    lyapunov_matrix,
    lyapunov_quadratic,
    max_level,
    recast,
    taylor_system,
)
from .sim import Ensemble, Simulation, simulate, simulate_many
from .stability.composite import CompositeCertificate, Domain, composite_lyapunov
from .stability.ctol_lyapunov import CTOLLyapunovCertificate, ctol_lyapunov
from .stability.singular_perturbation import NondimensionalModel, SingularPerturbation, SlowModel, singular_perturbation
from .stability.unequal_mass import UnequalMassCheck, allowable_delta_m_ratio, unequal_mass_check
from .trim.ctol import CTOLGlide, ctol_glide
from .trim.glide import SteadyGlide, permissible_gamma, steady_glide
from .trim.helix import Helix, classify_motion, helix_trim
from .trim.helix_design import HelixDesign, design_helix

__version__ = "0.1.0"

#: public names grouped by task (docs/api.md lists the same groups)
API_GROUPS: dict[str, tuple[str, ...]] = {
    "vehicles": ("Vehicle", "list_presets", "load_vehicle"),
    "models": (
        "AccelerationControlledGlider", "BuoyancyGlider", "CTOLAircraft", "CTOLReduced", "ElevatorBuoyancyGlider",
        "ExtendedCTOL", "FixedMassGlider3D", "GlidePathModel", "Glider3D", "LongitudinalGlider", "NondimensionalModel",
        "PhugoidClass", "PhugoidModel", "ReducedLongitudinalGlider", "TorqueControlledGlider", "C_STEADY",
        "classify_C", "initial_state_for_C", "orbit_period", "phugoid_hamiltonian", "R_to_ypr", "quat_to_R",
        "ypr_to_R", "ypr_to_quat", "benchmarks",
    ),
    "trims": (
        "BuoyancyEquilibrium", "CTOLGlide", "ElevatorEquilibrium", "Helix", "HelixDesign", "SteadyGlide",
        "buoyancy_equilibrium", "classify_motion", "ctol_glide", "design_helix", "elevator_equilibrium",
        "helix_trim", "permissible_gamma", "steady_glide",
    ),
    "linear analysis": (
        "BreakPoint", "ExistenceScan", "HelixRbhLocus", "HelixSweep", "Modes", "ParameterLocus", "RankTest",
        "controllability", "existence_scan", "glide_model", "helix_rbh_locus", "helix_sweep", "hessian", "jacobians",
        "linearize_glide", "mbar_locus", "modes", "observability", "parameter_locus", "rbh_locus",
        "resolved_crossing", "straight_glides", "uncontrolled_eigs",
    ),
    "controllers": (
        "ApproximateLinearizationController", "BlowUp", "BuoyancyController", "ClimbTrajectory", "ClosedLoopCTOL",
        "DecoupledAccelerationFeedback", "ElevatorBuoyancyController", "ElevatorExample",
        "FeedbackLinearizingController", "GlideTracking", "LinearGlideController", "ParetoStudy",
        "RealizedTorqueComparison", "StableInversion", "StateFeedback", "SteadyGlideController", "TorqueDesign",
        "TorqueGainFamily", "TrackingRun", "ZeroDynamics", "approximate_linearization_eigenvalues",
        "climb_trajectory", "closed_loop_formulas", "compare_realized_torque", "ctol_closed_loop_eigenvalues",
        "decoupled_gain_matrix", "design_torque_control", "elevator_closed_loop_eigenvalues", "elevator_example",
        "feedback_linearization_blowup", "lqr_glide", "lqr_state_feedback", "pareto_front", "place_glide",
        "stable_inversion", "torque_gain_family", "track_approximate_linearization", "track_stable_inversion",
        "track_with_steady_glides", "tracking_grid", "zero_dynamics",
    ),
    "stability and certificates": (
        "BuoyancyLyapunovCheck", "CTOLLyapunovCertificate", "CompositeCertificate", "Domain", "PolySystem",
        "ROACertificate", "SingularPerturbation", "SlowModel", "UnequalMassCheck", "allowable_delta_m_ratio",
        "buoyancy_lyapunov_check", "certify_roa", "composite_lyapunov", "ctol_lyapunov", "dVdt", "lyapunov_matrix",
        "lyapunov_quadratic", "max_level", "recast", "singular_perturbation", "taylor_system", "unequal_mass_check",
    ),
    "simulation": (
        "BatchComparison", "BatchResult", "ControllerRecord", "Ensemble", "Simulation", "compare_controllers",
        "integrate_batch", "simulate", "simulate_many",
    ),
    "errors": ("GlidectlError", "InfeasibleGlideError", "ModelError", "SolverError", "VehicleFileError"),
}

__all__ = [
    "C_STEADY",
    "AccelerationControlledGlider",
    "ApproximateLinearizationController",
    "BatchComparison",
    "BatchResult",
    "BlowUp",
    "BreakPoint",
    "BuoyancyController",
    "BuoyancyEquilibrium",
    "BuoyancyGlider",
    "BuoyancyLyapunovCheck",
    "CTOLAircraft",
    "CTOLGlide",
    "CTOLLyapunovCertificate",
    "CTOLReduced",
    "ClimbTrajectory",
    "ClosedLoopCTOL",
    "CompositeCertificate",
    "ControllerRecord",
    "DecoupledAccelerationFeedback",
    "Domain",
    "ElevatorBuoyancyController",
    "ElevatorBuoyancyGlider",
    "ElevatorEquilibrium",
    "ElevatorExample",
    "Ensemble",
    "ExistenceScan",
    "ExtendedCTOL",
    "FeedbackLinearizingController",
    "FixedMassGlider3D",
    "GlidePathModel",
    "GlideTracking",
    "GlidectlError",
    "Glider3D",
    "Helix",
    "HelixDesign",
    "HelixRbhLocus",
    "HelixSweep",
    "InfeasibleGlideError",
    "LinearGlideController",
    "LongitudinalGlider",
    "ModelError",
    "Modes",
    "NondimensionalModel",
    "ParameterLocus",
    "ParetoStudy",
    "PhugoidClass",
    "PhugoidModel",
    "PolySystem",
    "ROACertificate",
    "R_to_ypr",
    "RankTest",
    "RealizedTorqueComparison",
    "ReducedLongitudinalGlider",
    "Simulation",
    "SingularPerturbation",
    "SlowModel",
    "SolverError",
    "StableInversion",
    "StateFeedback",
    "SteadyGlide",
    "SteadyGlideController",
    "TorqueControlledGlider",
    "TorqueDesign",
    "TorqueGainFamily",
    "TrackingRun",
    "UnequalMassCheck",
    "Vehicle",
    "VehicleFileError",
    "ZeroDynamics",
    "allowable_delta_m_ratio",
    "approximate_linearization_eigenvalues",
    "benchmarks",
    "buoyancy_equilibrium",
    "buoyancy_lyapunov_check",
    "certify_roa",
    "classify_C",
    "classify_motion",
    "climb_trajectory",
    "closed_loop_formulas",
    "compare_controllers",
    "compare_realized_torque",
    "composite_lyapunov",
    "controllability",
    "ctol_closed_loop_eigenvalues",
    "ctol_glide",
    "ctol_lyapunov",
    "dVdt",
    "decoupled_gain_matrix",
    "design_helix",
    "design_torque_control",
    "elevator_closed_loop_eigenvalues",
    "elevator_equilibrium",
    "elevator_example",
    "existence_scan",
    "feedback_linearization_blowup",
    "glide_model",
    "helix_rbh_locus",
    "helix_sweep",
    "helix_trim",
    "hessian",
    "initial_state_for_C",
    "integrate_batch",
    "jacobians",
    "linearize_glide",
    "list_presets",
    "load_vehicle",
    "lqr_glide",
    "lqr_state_feedback",
    "lyapunov_matrix",
    "lyapunov_quadratic",
    "max_level",
    "mbar_locus",
    "modes",
    "observability",
    "orbit_period",
    "parameter_locus",
    "pareto_front",
    "permissible_gamma",
    "phugoid_hamiltonian",
    "place_glide",
    "quat_to_R",
    "rbh_locus",
    "recast",
    "resolved_crossing",
    "simulate",
    "simulate_many",
    "singular_perturbation",
    "stable_inversion",
    "steady_glide",
    "straight_glides",
    "taylor_system",
    "torque_gain_family",
    "track_approximate_linearization",
    "track_stable_inversion",
    "track_with_steady_glides",
    "tracking_grid",
    "uncontrolled_eigs",
    "unequal_mass_check",
    "ypr_to_R",
    "ypr_to_quat",
    "zero_dynamics",
]
