"""Steady motions: straight glides of the longitudinal glider (chapter 2, with the permissible flight-path
angles, and the glide envelope: those glides on a grid of speeds and angles within the actuator ranges), steady
glides of the CTOL aircraft under the steady-glide controller (Theorem 4, chapter 7), circular
helices and straight glides of the three-dimensional glider (chapter 8), and the inverse design of a helix (the
moving-mass position and buoyancy that realize a requested one)."""

from .ctol import CTOLGlide, angle_equation, ctol_glide
from .envelope import GlideEnvelope, glide_envelope
from .glide import SteadyGlide, alpha_for_gamma, permissible_gamma, steady_glide
from .helix import (
    Helix,
    classify_motion,
    helix_eigenvalues,
    helix_equations,
    helix_newton,
    helix_trim,
    reduced_rhs,
    zeta_of,
)
from .helix_design import DEFAULT_M0_BOUNDS, DEFAULT_R_P_BOUNDS, HelixDesign, design_helix

__all__ = [
    "DEFAULT_M0_BOUNDS",
    "DEFAULT_R_P_BOUNDS",
    "CTOLGlide",
    "GlideEnvelope",
    "Helix",
    "HelixDesign",
    "SteadyGlide",
    "alpha_for_gamma",
    "angle_equation",
    "classify_motion",
    "ctol_glide",
    "design_helix",
    "glide_envelope",
    "helix_eigenvalues",
    "helix_equations",
    "helix_newton",
    "helix_trim",
    "permissible_gamma",
    "reduced_rhs",
    "steady_glide",
    "zeta_of",
]
