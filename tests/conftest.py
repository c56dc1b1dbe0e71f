"""Shared fixtures of the test suite.

The design tests (``tests/test_design_<name>.py``) set ``DESIGN = "<name>"`` (a file of ``designs/``) and use
``design`` (the loaded design file, for its settings) and ``quick_build`` (its quick build, written once per test
module). ``python_output`` runs code in a fresh interpreter (for matplotlib backend checks). ``fast_mp`` is the
process start method of the pool tests.

Property tests (hypothesis) run derandomized by default, so a run of the suite is reproducible and CI cannot turn
red by chance; set ``GLIDECTL_HYPOTHESIS_EXPLORE=1`` to draw new examples on every run (what a developer hunting
for counterexamples wants). Counterexamples found that way are added to the tests with ``@example``.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import pytest
from hypothesis import settings

from glidectl.report import Design, Report, load_design

DESIGNS = Path(__file__).resolve().parents[1] / "designs"

settings.register_profile("reproducible", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile("explore" if os.environ.get("GLIDECTL_HYPOTHESIS_EXPLORE") else "reproducible")


class QuickBuild(NamedTuple):
    """A design built with its quick settings: the design, its report, the written ``report.pdf`` and the entries
    of ``numbers.json`` by name."""

    design: Design
    report: Report
    pdf: Path
    numbers: dict[str, dict[str, Any]]


def _design_name(request: pytest.FixtureRequest) -> str:
    name = getattr(request.module, "DESIGN", None)
    if not isinstance(name, str):
        raise pytest.UsageError(f"{request.module.__name__} must set DESIGN = '<name of a file in designs/>'")
    return name


@pytest.fixture(scope="module")
def design(request: pytest.FixtureRequest) -> Design:
    """The design file named by the test module's ``DESIGN`` (loaded, not built)."""
    return load_design(DESIGNS / f"{_design_name(request)}.py")


@pytest.fixture(scope="module")
def quick_build(design: Design, request: pytest.FixtureRequest,
                tmp_path_factory: pytest.TempPathFactory) -> QuickBuild:
    """The test module's design built with ``quick=True`` and written to ``<tmp>/<name>/`` (once per module)."""
    rep = design.report(quick=True)
    pdf = rep.write(tmp_path_factory.mktemp("reports") / _design_name(request))
    numbers = {n["name"]: n for n in json.loads((pdf.parent / "numbers.json").read_text())}
    return QuickBuild(design, rep, pdf, numbers)


@pytest.fixture
def python_output() -> Callable[..., str]:
    """``run(code, timeout=300)``: the stripped stdout of ``python -c code`` in a fresh interpreter (which must exit
    with status 0; its stderr is the failure message)."""

    def run(code: str, timeout: float = 300) -> str:
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
        assert proc.returncode == 0, proc.stderr
        return proc.stdout.strip()

    return run


@pytest.fixture(scope="session")
def fast_mp() -> Any:
    """The multiprocessing context of the pool tests: ``glidectl report`` starts its workers with "spawn" (safe
    everywhere), and each spawned worker imports glidectl anew, seconds on a loaded 2-core machine, so the tests fork
    where the platform can (the jobs are the same picklable calls either way)."""
    return multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")


@pytest.fixture
def moment_policy(monkeypatch: pytest.MonkeyPatch) -> Callable[..., None]:
    """``moment_policy(field=value, ...)`` runs the rest of the test with those fields of
    :data:`glidectl.roa.moment.MOMENT_POLICY` changed (restored afterwards)."""
    import dataclasses

    from glidectl.roa import moment

    def change(**fields: Any) -> None:
        monkeypatch.setattr(moment, "MOMENT_POLICY", dataclasses.replace(moment.MOMENT_POLICY, **fields))

    return change


@pytest.fixture(autouse=True)
def _close_figures() -> Any:
    """Close every pyplot figure a test opened: figures are kept until closed, and more than 20 open in one worker
    turn matplotlib's warning into an error in whichever test comes next."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")
