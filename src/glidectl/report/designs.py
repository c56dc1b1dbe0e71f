"""Design files: find, load and build them.

A design file is a Python script that defines

- ``TITLE``: a string, the report's title;
- ``design(progress, quick=False) -> glidectl.report.Report``: the whole design, written with the public API.
  ``progress(message)`` reports what is being computed; ``quick=True`` selects the file's quick settings
  (smaller grids and sample counts, for a first look and for tests).

``glidectl report NAME|PATH|all`` runs designs found in a folder (``./designs`` by default) or any design file; the
report of ``my_glider.py`` is written to ``<out>/my_glider/``. A design file can also run itself::

    if __name__ == "__main__":
        glidectl.report.run_script(__file__)
"""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from ..errors import DesignError, OutputError

if TYPE_CHECKING:
    from .document import Report

__all__ = ["Design", "build_design", "check_writable", "find_designs", "load_design", "run_script"]

Progress = Callable[[str], None]


def _quiet(message: str) -> None:
    """The default progress callback: says nothing."""


@dataclass(frozen=True)
class Design:
    """A loaded design file.

    Attributes
    ----------
    name : str
        The file's stem; the report goes to ``<out>/<name>/``.
    path : Path
        The design file.
    title : str
        Its ``TITLE``.
    module : ModuleType
        The loaded module (its ``design`` function builds the report).
    """

    name: str
    path: Path
    title: str
    module: ModuleType

    def report(self, progress: Progress = _quiet, quick: bool = False) -> Report:
        """Run ``design(progress, quick)`` and return its :class:`~glidectl.report.Report`.

        Parameters
        ----------
        progress : callable, optional
            ``progress(message)`` is called at each step of the design.
        quick : bool
            Use the design's quick settings.

        Returns
        -------
        Report
            The report the design returned (not yet written).

        Raises
        ------
        DesignError
            If ``design`` does not return a :class:`~glidectl.report.Report`.
        """
        from .document import Report

        rep = self.module.design(progress, quick=quick)
        if not isinstance(rep, Report):
            raise DesignError(f"design file {self.path}: design() returned {type(rep).__name__}, not a "
                              "glidectl.report.Report")
        return rep

    def build(self, out: str | Path = "reports", progress: Progress = _quiet, quick: bool = False) -> Path:
        """Check the output folder, run the design and write ``<out>/<name>/``.

        Parameters
        ----------
        out : str or Path
            Parent output folder.
        progress : callable, optional
            Progress callback.
        quick : bool
            Use the design's quick settings.

        Returns
        -------
        Path
            The written ``report.pdf``.

        Raises
        ------
        OutputError
            If the output folder cannot be created or written (checked before computing).
        DesignError
            If the design does not return a Report.
        """
        target = check_writable(Path(out) / self.name)
        return self.report(progress, quick).write(target)


def find_designs(folder: str | Path = "designs") -> dict[str, Path]:
    """The design files of a folder: ``{stem: path}`` for every ``*.py`` not starting with ``_``.

    Parameters
    ----------
    folder : str or Path
        Folder to search (not recursive).

    Returns
    -------
    dict of str to Path
        Design names (file stems, sorted) and their files.

    Raises
    ------
    DesignError
        If ``folder`` does not exist or is not a folder.
    """
    d = Path(folder)
    if not d.is_dir():
        raise DesignError(f"designs folder '{d}' not found: run from a folder that has a designs/ subfolder, pass "
                          "--designs DIR, or give the path of a design file")
    return {p.stem: p for p in sorted(d.glob("*.py")) if not p.name.startswith("_")}


def _module_name(path: Path) -> str:
    stem = "".join(c if c.isalnum() else "_" for c in path.stem)
    return f"glidectl_design_{stem}"


def load_design(spec: str | Path, designs: str | Path = "designs") -> Design:
    """Load a design by name (looked up in ``designs``) or by the path of a design file.

    Parameters
    ----------
    spec : str or Path
        A design name such as ``"ch2_longitudinal"``, or the path of a ``.py`` design file.
    designs : str or Path
        Folder where names are looked up.

    Returns
    -------
    Design
        The loaded design.

    Raises
    ------
    DesignError
        If no such design exists, the file cannot be imported, or it lacks ``TITLE`` or ``design``.
    """
    spec_s = str(spec)
    path = Path(spec_s)
    if not (spec_s.endswith(".py") or os.sep in spec_s or path.is_file()):
        found = find_designs(designs)
        if spec_s not in found:
            raise DesignError(f"unknown design '{spec_s}' in {designs}/; available: {', '.join(found) or 'none'}")
        path = found[spec_s]
    if not path.is_file():
        raise DesignError(f"design file '{path}' not found")
    path = path.resolve()
    name = _module_name(path)
    mod_spec = importlib.util.spec_from_file_location(name, path)
    if mod_spec is None or mod_spec.loader is None:
        raise DesignError(f"'{path}' is not a Python file that can be imported")
    module = importlib.util.module_from_spec(mod_spec)
    sys.modules[name] = module  # dataclasses and process pools look the module up by name
    try:
        mod_spec.loader.exec_module(module)
    except Exception as exc:
        del sys.modules[name]
        raise DesignError(f"design file '{path}' failed to import: {type(exc).__name__}: {exc}") from exc
    title = getattr(module, "TITLE", None)
    if not isinstance(title, str) or not callable(getattr(module, "design", None)):
        raise DesignError(f"design file '{path}' must define TITLE (a string) and design(progress, quick=False) "
                          "returning a glidectl.report.Report")
    return Design(path.stem, path, title, module)


def check_writable(folder: str | Path) -> Path:
    """Create ``folder`` if needed and check that files can be written in it.

    Parameters
    ----------
    folder : str or Path
        Output folder.

    Returns
    -------
    Path
        The folder.

    Raises
    ------
    OutputError
        If it cannot be created or written, with the reason.
    """
    d = Path(folder)
    try:
        d.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=d, prefix=".glidectl-write-check"):
            pass
    except OSError as exc:
        raise OutputError(f"cannot write reports to '{d}': {exc.strerror or exc}; choose another folder with "
                          "--out DIR") from exc
    return d


def load_design_source(name: str, path: str | Path, source: bytes) -> Design:
    """Load a design from its file when the file is there with this content, else from ``source`` (remote workers).

    Parameters
    ----------
    name : str
        The design's name (file stem), used for the temporary copy.
    path : str or Path
        Where the design file was when the build started.
    source : bytes
        The content the build is running.

    Returns
    -------
    Design
        The loaded design (module name ``glidectl_design_<stem>`` either way).

    Raises
    ------
    DesignError
        If the design cannot be loaded.
    """
    p = Path(path)
    try:
        same = p.is_file() and p.read_bytes() == source
    except OSError:
        same = False
    if same:
        return load_design(p)
    folder = Path(tempfile.mkdtemp(prefix="glidectl-design-"))
    f = folder / f"{name}.py"
    f.write_bytes(source)
    return load_design(f)


def build_design(spec: str | Path, out: str | Path = "reports", *, designs: str | Path = "designs",
                 quick: bool = False, progress: Progress = _quiet) -> Path:
    """Load a design (name or path) and write its report to ``<out>/<name>/``.

    Parameters
    ----------
    spec : str or Path
        Design name or design file path.
    out : str or Path
        Parent output folder.
    designs : str or Path
        Folder where names are looked up.
    quick : bool
        Use the design's quick settings.
    progress : callable, optional
        Progress callback.

    Returns
    -------
    Path
        The written ``report.pdf``.

    Raises
    ------
    DesignError
        If the design cannot be found or loaded.
    OutputError
        If the output folder is not writable (checked before computing).
    """
    return load_design(spec, designs).build(out, progress, quick)


def run_script(path: str | Path, argv: Sequence[str] | None = None) -> Path:
    """Entry point for ``python designs/NAME.py [OUTDIR] [--quick]``: build that design (default ``reports``).

    Parameters
    ----------
    path : str or Path
        The design file (pass ``__file__``).
    argv : sequence of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    Path
        The written ``report.pdf``.

    Raises
    ------
    DesignError, OutputError
        As :func:`build_design`.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    quick = "--quick" in args
    rest = [a for a in args if a != "--quick"]
    out = rest[0] if rest else "reports"
    t0 = time.perf_counter()
    pdf = build_design(Path(path), out, quick=quick,
                       progress=lambda m: print(f"  {time.perf_counter() - t0:7.1f} s  {m}", flush=True))
    print(pdf)
    return pdf
