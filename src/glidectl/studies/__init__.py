"""Design studies: each reproduces (and goes beyond) a chapter of the thesis and writes a report.

:data:`REGISTRY` maps a design name to its module; each module has ``NAME``, ``TITLE`` and
``build(outdir, progress)``.
"""

from __future__ import annotations

from importlib import import_module
from types import ModuleType

REGISTRY: dict[str, str] = {
    "ch2_longitudinal": "glidectl.studies.ch2_longitudinal",
    "ch4_phugoid": "glidectl.studies.ch4_phugoid",
    "ch5_singular_perturbation": "glidectl.studies.ch5_singular_perturbation",
}


def get(name: str) -> ModuleType:
    """The study module for a design name (raises GlidectlError for unknown names)."""
    from ..errors import GlidectlError

    if name not in REGISTRY:
        raise GlidectlError(f"unknown design '{name}'; available: {', '.join(sorted(REGISTRY))}")
    return import_module(REGISTRY[name])
