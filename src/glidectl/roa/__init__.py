"""Region-of-attraction certification by SOS/LMI programs in cvxpy (polynomial layer, exact recasting of the
glidectl models, level maximization, V-lambda alternation with rising degree, a-posteriori verification)."""

from .certify import (
    LevelResult,
    ROACertificate,
    ROAVerification,
    SOSSize,
    certify_roa,
    dVdt,
    estimate_sos_size,
    lyapunov_matrix,
    lyapunov_quadratic,
    max_level,
)
from .polynomial import Poly, monomial_matrix, monomials
from .scaling import DEFAULT_HALF_WIDTH, box_scale, resolve_box, scaled_lyapunov, validity_box
from .sdp_solvers import MOMENT_MIN_BLOCK, SDP_SOLVERS, installed_sdp_solvers, solve_moment
from .sector import sector_system
from .sos import GramCheck, LinPoly, SOSProgram
from .surrogate import RemainderBound, surrogate_error, surrogate_system
from .systems import PolySystem, polynomial_system, recast, taylor_system

__all__ = [
    "DEFAULT_HALF_WIDTH",
    "MOMENT_MIN_BLOCK",
    "SDP_SOLVERS",
    "GramCheck",
    "LevelResult",
    "LinPoly",
    "Poly",
    "PolySystem",
    "ROACertificate",
    "ROAVerification",
    "RemainderBound",
    "SOSProgram",
    "SOSSize",
    "box_scale",
    "certify_roa",
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
