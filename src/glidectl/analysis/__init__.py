"""Analysis of models and their steady motions: exact complex-step Jacobians and Hessians (from
:mod:`glidectl.derivatives`), linearization about steady glides with modes, controllability and observability
(§2.3.1), root loci over physical parameters (§2.3), maps, existence scans and stability of steady helices (chapter
8, with the continuation engine behind them), and the closed-loop comparison of controllers by LQR design and batch
simulation."""

from ..derivatives import central_difference_jacobians, hessian, jacobians
from .closed_loop import BatchComparison, ControllerRecord, StateFeedback, compare_controllers, lqr_state_feedback
from .continuation import (
    AGREE_TOL,
    COLUMN_UNITS,
    COLUMNS,
    PARAMETERS,
    ContinuationOptions,
    ContinuationPoint,
    check_sweep_inputs,
    chunk_bounds,
    readonly_array,
    reconcile_chunks,
    sweep_controls,
    walk_chunk,
)
from .helix_existence import ExistenceScan, existence_scan
from .helix_stability import HelixRbhLocus, helix_rbh_locus, mass_position_at_rbh, resolved_crossing
from .helix_sweeps import HelixSweep, helix_sweep, straight_glides
from .linear import Modes, RankTest, controllability, glide_model, linearize_glide, modes, observability
from .locus import (
    BreakPoint,
    ParameterLocus,
    eta_r_eigenvalues,
    mbar_locus,
    parameter_locus,
    rbh_locus,
    uncontrolled_eigs,
)
from .measure import box_measure, box_points

__all__ = [
    "AGREE_TOL",
    "COLUMNS",
    "COLUMN_UNITS",
    "PARAMETERS",
    "BatchComparison",
    "BreakPoint",
    "ContinuationOptions",
    "ContinuationPoint",
    "ControllerRecord",
    "ExistenceScan",
    "HelixRbhLocus",
    "HelixSweep",
    "Modes",
    "ParameterLocus",
    "RankTest",
    "StateFeedback",
    "box_measure",
    "box_points",
    "central_difference_jacobians",
    "check_sweep_inputs",
    "chunk_bounds",
    "compare_controllers",
    "controllability",
    "eta_r_eigenvalues",
    "existence_scan",
    "glide_model",
    "helix_rbh_locus",
    "helix_sweep",
    "hessian",
    "jacobians",
    "linearize_glide",
    "lqr_state_feedback",
    "mass_position_at_rbh",
    "mbar_locus",
    "modes",
    "observability",
    "parameter_locus",
    "rbh_locus",
    "readonly_array",
    "reconcile_chunks",
    "resolved_crossing",
    "straight_glides",
    "sweep_controls",
    "uncontrolled_eigs",
    "walk_chunk",
]
