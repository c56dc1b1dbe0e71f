"""Stability theory: singular perturbation (chapter 5), composite Lyapunov functions, region-of-attraction estimates:
the singular-perturbation form of the chapter-5 glider (§5.1), the composite Lyapunov function and
region-of-attraction estimate of §5.2-§5.3, the unequal-added-mass condition of §5.4 and the Theorem-5 certificate
of the CTOL closed loop (§7.2). SOS region-of-attraction certification is in :mod:`glidectl.roa`."""

from .composite import CompositeCertificate, CompositeVerification, Domain, composite_lyapunov
from .ctol_lyapunov import CTOLLyapunovCertificate, CTOLVerification, Theorem5Constants, ctol_lyapunov
from .singular_perturbation import SingularPerturbation, singular_perturbation
from .unequal_mass import UnequalMassCheck, allowable_delta_m_ratio, unequal_mass_check

__all__ = [
    "CTOLLyapunovCertificate",
    "CTOLVerification",
    "CompositeCertificate",
    "CompositeVerification",
    "Domain",
    "SingularPerturbation",
    "Theorem5Constants",
    "UnequalMassCheck",
    "allowable_delta_m_ratio",
    "composite_lyapunov",
    "ctol_lyapunov",
    "singular_perturbation",
    "unequal_mass_check",
]
