"""glidectl: control-systems design for gliding vehicles (after Bhatta, Princeton 2006).

Public API (chapter 2, longitudinal underwater glider)::

    import glidectl as gc
    veh = gc.load_vehicle("rogue")                 # preset name or path to a TOML file
    lo, hi = gc.permissible_gamma(veh)             # rad; glides need gamma < lo or gamma > hi
    g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)
    sys = gc.linearize_glide(veh, g, inputs="force")   # control.StateSpace with named states/inputs

Chapter 8 (3D glider, circular helices)::

    veh = gc.load_vehicle("slocum_ch8")
    h = gc.helix_trim(veh, r_p=(0.02, 0.02, 0.04), m0=0.25)   # h.radius, h.pitch, h.period, h.eigenvalues
    sw = gc.helix_sweep(veh, "r_P1", np.linspace(0.002, 0.06, 59))   # maps; any Executor via executor=
    d = gc.design_helix(veh, radius=50.0, pitch=150.0)         # d.r_p, d.m0, d.helix

Chapter 7 (CTOL aircraft, normalized units)::

    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=0.155, gamma=0.1)   # gl.alpha_e, gl.k1, gl.k2, gl.thrust (Theorem 4)
    cert = gc.ctol_lyapunov(veh, gl, k3=10.0, k4=5.0)  # Theorem 5 constants, cert.verify() samples every bound

Chapter 6 (nonlinear steady-glide controllers)::

    eq = gc.elevator_equilibrium(gc.load_vehicle("elevator_ch6"), speed=1.0, gamma=-np.pi / 4)
    eq.m0e, eq.alpha_e, eq.u2e, eq.eps1, eq.eps2, eq.K_De_eff    # K_De_eff = K'_De of Theorem 3 (corrected)
    # controllers, tracking and baselines: glidectl.controllers.ctol, ctol_tracking, ctol_inversion

Region-of-attraction certificates (SOS programs in cvxpy)::

    cert = gc.certify_roa(gc.benchmarks.van_der_pol(), degree=6)   # cert.verified, cert.contains(X), cert.volume()
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    cert = gc.certify_roa(sp.reduced_model(), degree=4)          # exact recasting (sin, 1 - cos, 1/V cleared)
"""

from . import benchmarks
from .analysis.helix_maps import ExistenceScan, HelixSweep, existence_scan, helix_sweep, straight_glides
from .analysis.helix_stability import HelixRbhLocus, helix_rbh_locus, resolved_crossing
from .analysis.jacobian import central_difference_jacobians, jacobians
from .analysis.linear import (
    Modes,
    RankTest,
    controllability,
    glide_model,
    linearize_glide,
    modes,
    observability,
)
from .analysis.locus import (
    BreakPoint,
    ParameterLocus,
    mbar_locus,
    parameter_locus,
    rbh_locus,
    uncontrolled_eigs,
)
from .controllers.buoyancy import (
    BuoyancyController,
    BuoyancyEquilibrium,
    BuoyancyGlider,
    buoyancy_equilibrium,
    buoyancy_lyapunov_check,
)
from .controllers.elevator import (
    ElevatorBuoyancyController,
    ElevatorBuoyancyGlider,
    ElevatorEquilibrium,
    elevator_equilibrium,
)
from .controllers.linear import (
    DecoupledAccelerationFeedback,
    LinearGlideController,
    decoupled_gain_matrix,
    lqr_glide,
    place_glide,
)
from .errors import GlidectlError, InfeasibleGlideError, ModelError, SolverError, VehicleFileError
from .models.glider3d import FixedMassGlider3D, Glider3D
from .models.longitudinal import AccelerationControlledGlider, GlidePathModel, LongitudinalGlider
from .models.reduced import ReducedLongitudinalGlider
from .params import Vehicle, list_presets, load_vehicle
from .roa import PolySystem, ROACertificate, certify_roa, recast
from .sim import Simulation, simulate
from .stability.composite import CompositeCertificate, Domain, composite_lyapunov
from .stability.ctol_lyapunov import CTOLLyapunovCertificate, ctol_lyapunov
from .stability.singular_perturbation import SingularPerturbation, SlowModel, singular_perturbation
from .stability.unequal_mass import UnequalMassCheck, allowable_delta_m_ratio, unequal_mass_check
from .trim.ctol import CTOLGlide, ctol_glide
from .trim.glide import SteadyGlide, permissible_gamma, steady_glide
from .trim.helix import Helix, classify_motion, helix_trim
from .trim.helix_design import HelixDesign, design_helix

__version__ = "0.1.0"

__all__ = [
    "AccelerationControlledGlider",
    "BreakPoint",
    "BuoyancyController",
    "BuoyancyEquilibrium",
    "BuoyancyGlider",
    "CTOLGlide",
    "CTOLLyapunovCertificate",
    "CompositeCertificate",
    "DecoupledAccelerationFeedback",
    "Domain",
    "ElevatorBuoyancyController",
    "ElevatorBuoyancyGlider",
    "ElevatorEquilibrium",
    "ExistenceScan",
    "FixedMassGlider3D",
    "GlidePathModel",
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
    "ParameterLocus",
    "PolySystem",
    "ROACertificate",
    "RankTest",
    "ReducedLongitudinalGlider",
    "Simulation",
    "SingularPerturbation",
    "SlowModel",
    "SolverError",
    "SteadyGlide",
    "UnequalMassCheck",
    "Vehicle",
    "VehicleFileError",
    "allowable_delta_m_ratio",
    "benchmarks",
    "buoyancy_equilibrium",
    "buoyancy_lyapunov_check",
    "central_difference_jacobians",
    "certify_roa",
    "classify_motion",
    "composite_lyapunov",
    "controllability",
    "ctol_glide",
    "ctol_lyapunov",
    "decoupled_gain_matrix",
    "design_helix",
    "elevator_equilibrium",
    "existence_scan",
    "glide_model",
    "helix_rbh_locus",
    "helix_sweep",
    "helix_trim",
    "jacobians",
    "linearize_glide",
    "list_presets",
    "load_vehicle",
    "lqr_glide",
    "mbar_locus",
    "modes",
    "observability",
    "parameter_locus",
    "permissible_gamma",
    "place_glide",
    "rbh_locus",
    "recast",
    "resolved_crossing",
    "simulate",
    "singular_perturbation",
    "steady_glide",
    "straight_glides",
    "uncontrolled_eigs",
    "unequal_mass_check",
]
