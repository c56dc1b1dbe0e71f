"""Design studies: each reproduces (and goes beyond) a chapter of the thesis and writes a report.

:data:`REGISTRY` maps a design name to its module; each module has ``NAME``, ``TITLE`` and
``build(outdir, progress)``.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from pathlib import Path
from types import ModuleType

REGISTRY: dict[str, str] = {
    "ch2_longitudinal": "glidectl.studies.ch2_longitudinal",
    "ch4_phugoid": "glidectl.studies.ch4_phugoid",
    "ch5_singular_perturbation": "glidectl.studies.ch5_singular_perturbation",
    "ch6_controllers": "glidectl.studies.ch6_controllers",
    "ch7_ctol": "glidectl.studies.ch7_ctol",
    "ch8_helix": "glidectl.studies.ch8_helix",
    "roa_certification": "glidectl.studies.roa_certification",
}


def get(name: str) -> ModuleType:
    """The study module for a design name (raises GlidectlError for unknown names)."""
    from ..errors import GlidectlError

    if name not in REGISTRY:
        raise GlidectlError(f"unknown design '{name}'; available: {', '.join(sorted(REGISTRY))}")
    return import_module(REGISTRY[name])


def build_study(module: ModuleType, outdir: str | Path, progress: Callable[[str], None]) -> Path:
    """Shared ``build`` of the studies: ``module.compute`` -> ``module.report`` -> ``<outdir>/<NAME>/``."""
    res = module.compute(progress)
    progress("figures and report")
    return module.report(res).write(Path(outdir) / module.NAME)


def run_design(name: str, argv: list[str] | None = None) -> Path:
    """Entry point of the ``designs/*.py`` scripts: ``python designs/NAME.py [OUTDIR]`` (default ``reports``)."""
    import sys

    args = sys.argv[1:] if argv is None else argv
    out = args[0] if args else "reports"
    pdf = get(name).build(out, progress=lambda msg: print("  ", msg, flush=True))
    print(pdf)
    return pdf
