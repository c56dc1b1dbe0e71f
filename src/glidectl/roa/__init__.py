"""Region-of-attraction certification by SOS/LMI programs in cvxpy (polynomial layer, exact recasting of the
glidectl models, level maximization, V-lambda alternation with rising degree, a-posteriori verification)."""

from .alternation import Alternation, HistoryRow
from .certificate import ROACertificate, ROAVerification, dVdt
from .certify import certify_roa
from .extent import Certificate, ConvergentSlice, Extent, convergent_extent, convergent_slice
from .moment import MOMENT_POLICY, MomentPolicy, solve_moment
from .options import BudgetOptions, SamplingOptions, SolverOptions, SurrogateOptions
from .polynomial import Poly, monomial_matrix, monomials
from .programs import LevelResult, SOSSize, estimate_sos_size, lyapunov_matrix, lyapunov_quadratic, max_level
from .robust import RobustEllipsoidCertificate, RobustVerification, certify_roa_family
from .scaling import DEFAULT_HALF_WIDTH, box_scale, resolve_box, scaled_lyapunov, validity_box
from .sdp_solvers import SDP_SOLVERS, installed_sdp_solvers
from .sector import sector_system
from .sos import GramCheck, LinPoly, SOSProgram
from .surrogate import RemainderBound, surrogate_error, surrogate_system
from .systems import PolySystem, polynomial_system, recast, taylor_system

__all__ = [
    "DEFAULT_HALF_WIDTH",
    "MOMENT_POLICY",
    "SDP_SOLVERS",
    "Alternation",
    "BudgetOptions",
    "Certificate",
    "ConvergentSlice",
    "Extent",
    "GramCheck",
    "HistoryRow",
    "LevelResult",
    "LinPoly",
    "MomentPolicy",
    "Poly",
    "PolySystem",
    "ROACertificate",
    "ROAVerification",
    "RemainderBound",
    "RobustEllipsoidCertificate",
    "RobustVerification",
    "SOSProgram",
    "SOSSize",
    "SamplingOptions",
    "SolverOptions",
    "SurrogateOptions",
    "box_scale",
    "certify_roa",
    "certify_roa_family",
    "convergent_extent",
    "convergent_slice",
    "dVdt",
    "estimate_sos_size",
    "installed_sdp_solvers",
    "lyapunov_matrix",
    "lyapunov_quadratic",
    "max_level",
    "monomial_matrix",
    "monomials",
    "polynomial_system",
    "recast",
    "resolve_box",
    "scaled_lyapunov",
    "sector_system",
    "solve_moment",
    "surrogate_error",
    "surrogate_system",
    "taylor_system",
    "validity_box",
]
