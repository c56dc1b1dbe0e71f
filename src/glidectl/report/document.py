"""Report writer: a multi-page PDF (title, vehicle parameters, a results table or a published-vs-glidectl ledger,
tables, figures with captions, notes), one PNG per figure, and ``numbers.json``.

``numbers.json`` is a list of entries ``{name, value, unit, published, rel_err, reproduced, tolerance, source,
note}``: ``published`` is the value a publication prints (or null), ``rel_err`` is ``|value - published| /
|published|`` for scalars, ``reproduced`` is true/false/null (null: nothing published to compare with).

The writer never selects a matplotlib backend: it draws its own pages on :class:`matplotlib.figure.Figure`
objects (no pyplot) and saves the figures it is given with ``Figure.savefig``.
"""

from __future__ import annotations

import json
import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from ..errors import ArgumentError, ArgumentTypeError, OutputError
from ..params import Vehicle

__all__ = ["BHATTA_2006", "Number", "Report"]


@dataclass(frozen=True)
class Number:
    """One line of a report's number table: a value, its unit and source, and optionally a published value.

    Attributes
    ----------
    name : str
        Key of the entry in ``numbers.json`` (unique within a report).
    value : Any
        The value glidectl computed (scalar, list, array, bool or str).
    unit : str
        Unit of ``value`` (SI; ``"-"`` for dimensionless).
    source : str
        Where the quantity comes from (equation, section, "our design").
    published : Any, optional
        The value a publication prints, when there is one to compare with.
    tolerance : float, optional
        Relative tolerance within which ``value`` reproduces ``published``.
    note : str
        Explanation printed in the ledger notes (why a value is or is not reproduced).
    verdict : bool, optional
        Explicit reproduced/not verdict for non-scalar values; overrides the tolerance test.
    """

    name: str
    value: Any
    unit: str
    source: str = ""
    published: Any = None
    tolerance: float | None = None
    note: str = ""
    verdict: bool | None = None

    @property
    def rel_err(self) -> float | None:
        """``|value - published| / |published|`` for real scalars, None otherwise."""
        if isinstance(self.value, bool) or isinstance(self.published, bool):
            return None
        if isinstance(self.value, int | float) and isinstance(self.published, int | float) and self.published != 0:
            return abs(self.value - self.published) / abs(self.published)
        return None

    @property
    def reproduced(self) -> bool | None:
        """True when within ``tolerance`` (relative) of the published value; None when there is nothing to compare.

        ``verdict`` (set for non-scalar values such as eigenvalue lists, with the reason in ``note``) overrides.
        """
        if self.verdict is not None:
            return self.verdict
        if self.published is None or self.tolerance is None:
            return None
        e = self.rel_err
        return bool(e is not None and e <= self.tolerance)

    def as_json(self) -> dict[str, Any]:
        """The ``numbers.json`` entry of this number."""
        return {"name": self.name, "value": _jsonable(self.value), "unit": self.unit,
                "published": _jsonable(self.published), "rel_err": self.rel_err, "reproduced": self.reproduced,
                "tolerance": self.tolerance, "source": self.source, "note": self.note}


def _jsonable(v: Any) -> Any:
    import numpy as np

    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist())
    if isinstance(v, complex | np.complexfloating):
        return [float(v.real), float(v.imag)]
    if isinstance(v, list | tuple):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.floating | np.integer):
        return v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return str(v)
    return v


def _clip(text: str, width: float) -> str:
    """Cut a ledger cell to what fits a column of ``width`` (fraction of the A4-landscape table) at 7 pt; the full
    text goes to the ledger notes."""
    n = max(int(width * 150), 6)
    return text if len(text) <= n else text[:n - 1] + "\u2026"


def _fmt(v: Any) -> str:
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.5g}"
    if isinstance(v, list | tuple):
        return ", ".join(_fmt(x) for x in v[:4]) + (" ..." if len(v) > 4 else "")
    if isinstance(v, complex):
        return f"{v.real:.4g}{v.imag:+.4g}i"
    return str(v)


#: the reference cited on the title page of the designs that reproduce the thesis
BHATTA_2006 = ("P. Bhatta, Nonlinear Stability and Control of Gliding Vehicles, PhD thesis, "
               "Princeton University, 2006.")


class Report:
    """Collects the numbers, tables, figures and text of one design, then writes them (:meth:`write`).

    Parameters
    ----------
    title : str
        Title of the report (first page).
    vehicle : Vehicle or sequence of Vehicle, optional
        Vehicle(s) whose parameter (and actuator) tables are printed after the title page.
    reference : str, optional
        Publication the design compares with; cited on the title page only when given.

    Raises
    ------
    ArgumentTypeError
        If ``title`` or ``reference`` is not a string or ``vehicle`` is not a :class:`~glidectl.Vehicle` (or a
        sequence of them); also a :class:`TypeError`.

    Examples
    --------
    >>> rep = Report("My glider", vehicle=gc.load_vehicle("rogue"))       # doctest: +SKIP
    >>> rep.number("glide_speed", 0.3, "m/s", source="our design")         # doctest: +SKIP
    >>> rep.write("reports/my_glider")                                     # doctest: +SKIP
    """

    def __init__(self, title: str, vehicle: Vehicle | Sequence[Vehicle] | None = None,
                 reference: str | None = None) -> None:
        if not isinstance(title, str):
            raise ArgumentTypeError(f"Report title must be a string, got {title!r}")
        ok = vehicle is None or isinstance(vehicle, Vehicle) or (
            isinstance(vehicle, Sequence) and not isinstance(vehicle, str)
            and all(isinstance(v, Vehicle) for v in vehicle))
        if not ok:
            hint = f" (load it first: gc.load_vehicle({vehicle!r}))" if isinstance(vehicle, str) else ""
            raise ArgumentTypeError(f"Report vehicle must be a glidectl Vehicle or a sequence of them{hint}")
        vehicles = [] if vehicle is None else [vehicle] if isinstance(vehicle, Vehicle) else list(vehicle)
        if reference is not None and not isinstance(reference, str):
            raise ArgumentTypeError(f"Report reference must be a string, got {reference!r}")
        self.title = title
        self.reference = reference
        self.vehicles: list[Vehicle] = vehicles
        self.numbers: list[Number] = []
        self.figures: list[tuple[str, Any, str]] = []
        self.sections: list[tuple[str, str]] = []
        self.tables: list[tuple[str, list[str], list[list[str]]]] = []

    def __repr__(self) -> str:
        return (f"Report({self.title!r}: {len(self.numbers)} numbers, {len(self.tables)} tables, "
                f"{len(self.figures)} figures, {len(self.sections)} sections)")

    def number(self, name: str, value: Any, unit: str, source: str = "", published: Any = None,
               tolerance: float | None = None, note: str = "", verdict: bool | None = None) -> Number:
        """Add one entry of the number table (and of ``numbers.json``).

        Parameters
        ----------
        name : str
            Unique key of the entry.
        value : Any
            The computed value (scalar, list, array, bool or str).
        unit : str
            Unit of ``value``.
        source : str
            Where it comes from (equation, section, "our design").
        published : Any, optional
            The value a publication prints; the report then carries a ledger.
        tolerance : float, optional
            Relative tolerance for ``reproduced``.
        note : str
            Explanation printed with the table.
        verdict : bool, optional
            Explicit reproduced verdict for non-scalar values.

        Returns
        -------
        Number
            The entry that was added.

        Raises
        ------
        ArgumentTypeError
            If ``name``, ``unit``, ``source`` or ``note`` is not a string.
        ArgumentError
            If an entry called ``name`` already exists, or ``tolerance`` is not a positive finite number.
        """
        for key, val in (("name", name), ("unit", unit), ("source", source), ("note", note)):
            if not isinstance(val, str):
                raise ArgumentTypeError(f"number {key} must be a string, got {type(val).__name__} {val!r}")
        if tolerance is not None:
            from ..checks import positive

            tolerance = positive("tolerance", tolerance)
        n = Number(name, value, unit, source, published=published, tolerance=tolerance, note=note, verdict=verdict)
        if any(m.name == n.name for m in self.numbers):
            raise ArgumentError(f"duplicate number {n.name}")
        self.numbers.append(n)
        return n

    def figure(self, stem: str, fig: Any, caption: str) -> None:
        """Add a matplotlib figure, written as ``<stem>.png`` and as a PDF page with ``caption`` below it.

        Parameters
        ----------
        stem : str
            File stem of the PNG (unique within a report).
        fig : matplotlib.figure.Figure
            The figure (the report closes it after writing).
        caption : str
            Caption printed under the figure in the PDF.

        Raises
        ------
        ArgumentTypeError
            If ``stem`` or ``caption`` is not a string, or ``fig`` is not a matplotlib figure.
        ArgumentError
            If a figure called ``stem`` already exists, or ``stem`` is not a plain file stem.
        """
        if not isinstance(stem, str) or not isinstance(caption, str):
            raise ArgumentTypeError(f"figure stem and caption must be strings, got {stem!r}, {caption!r}")
        if not isinstance(fig, Figure):
            raise ArgumentTypeError(f"figure '{stem}' must be a matplotlib Figure, got {type(fig).__name__}")
        if not stem or "/" in stem or "\\" in stem or stem in (".", ".."):
            raise ArgumentError(f"figure stem must be a plain file name without folders, got {stem!r}")
        if any(f[0] == stem for f in self.figures):
            raise ArgumentError(f"duplicate figure {stem}")
        self.figures.append((stem, fig, caption))

    def text(self, heading: str, body: str) -> None:
        """Add a text section (paragraphs separated by blank lines) at the end of the PDF.

        Parameters
        ----------
        heading : str
            Section heading.
        body : str
            Section text; blank lines separate paragraphs.

        Raises
        ------
        ArgumentTypeError
            If ``heading`` or ``body`` is not a string.
        """
        if not isinstance(heading, str) or not isinstance(body, str):
            raise ArgumentTypeError(f"text heading and body must be strings, got {type(heading).__name__} and "
                                    f"{type(body).__name__}")
        self.sections.append((heading, body))

    def table(self, caption: str, header: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
        """Add a table page (long tables continue on further pages).

        Parameters
        ----------
        caption : str
            Caption printed above the table.
        header : sequence of str
            Column headings.
        rows : sequence of sequences
            Cells; each row has ``len(header)`` entries (converted with ``str``).

        Raises
        ------
        ArgumentTypeError
            If ``caption`` is not a string, or ``header`` or a row is not a sequence.
        ArgumentError
            If a row's length differs from the header's.
        """
        if not isinstance(caption, str):
            raise ArgumentTypeError(f"table caption must be a string, got {caption!r}")
        if isinstance(header, str) or not isinstance(header, Sequence) or any(
                isinstance(r, str) or not isinstance(r, Sequence) for r in rows):
            raise ArgumentTypeError(f"table '{caption}': header and rows must be sequences (lists) of cells")
        header = [str(h) for h in header]
        cells = [[str(c) for c in r] for r in rows]
        bad = [i for i, r in enumerate(cells) if len(r) != len(header)]
        if bad:
            raise ArgumentError(f"table '{caption}': row {bad[0]} has {len(cells[bad[0]])} cells, header has "
                                f"{len(header)}")
        self.tables.append((caption, header, cells))

    @property
    def has_ledger(self) -> bool:
        """True when at least one number has a published value to compare with (the table is then a ledger)."""
        return any(n.published is not None or n.verdict is not None for n in self.numbers)

    # ------------------------------------------------------------------ writing
    def _text_pages(self, pdf: PdfPages, heading: str, paragraphs: list[str]) -> None:
        lines: list[str] = []
        for p in paragraphs:
            lines.extend(textwrap.wrap(p, 100) or [""])
            lines.append("")
        per = 52
        for k in range(0, max(len(lines), 1), per):
            fig = Figure(figsize=(8.27, 11.69))
            fig.text(0.07, 0.95, heading + (" (cont.)" if k else ""), fontsize=14, weight="bold", va="top")
            fig.text(0.07, 0.91, "\n".join(lines[k:k + per]), fontsize=8.5, va="top", family="monospace")
            pdf.savefig(fig)

    def _table_pages(self, pdf: PdfPages, caption: str, header: list[str], rows: list[list[str]],
                     widths: list[float] | None = None) -> None:
        per = 34
        if widths is None:  # proportional to the longest entry of each column
            lens = [max([len(str(h))] + [len(str(r[i])) for r in rows if i < len(r)]) + 2
                    for i, h in enumerate(header)]
            widths = [x / sum(lens) for x in lens]
        for k in range(0, max(len(rows), 1), per):
            fig = Figure(figsize=(11.69, 8.27))
            # a long caption wraps (about 110 characters of 12 pt bold across the landscape page), the table below it
            lines = textwrap.wrap(caption + (" (cont.)" if k else ""), 110) or [""]
            fig.text(0.04, 0.95, "\n".join(lines), fontsize=12, weight="bold", va="top")
            ax = fig.add_axes((0.03, 0.04, 0.94, 0.86 - 0.025 * (len(lines) - 1)))
            ax.axis("off")
            chunk = rows[k:k + per] or [["-"] * len(header)]
            t = ax.table(cellText=chunk, colLabels=header, loc="upper left", cellLoc="left",
                         colWidths=widths)
            t.auto_set_font_size(False)
            t.set_fontsize(7)
            t.scale(1, 1.25)
            pdf.savefig(fig)

    def _title_page(self, pdf: PdfPages, label: str) -> None:
        fig = Figure(figsize=(8.27, 11.69))
        fig.text(0.5, 0.75, "\n".join(textwrap.wrap(self.title, 60)), ha="center", va="center", fontsize=18,
                 weight="bold")
        fig.text(0.5, 0.66, f"glidectl {_version()} report '{label}'", ha="center", fontsize=12)
        stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
        vtxt = "\n".join(f"{v.title}  [{v.name}, provenance {v.provenance}]" for v in self.vehicles)
        fig.text(0.5, 0.6, f"generated {stamp}\n\n{vtxt}", ha="center", va="top", fontsize=9)
        if self.reference:
            fig.text(0.5, 0.4, "Reference: " + "\n".join(textwrap.wrap(self.reference, 90)), ha="center",
                     fontsize=9, style="italic")
        pdf.savefig(fig)

    def _number_rows(self) -> tuple[str, list[str], list[list[str]], list[float]]:
        if self.has_ledger:
            widths = [0.2, 0.22, 0.16, 0.07, 0.07, 0.07, 0.21]
            cells = [[n.name, _fmt(_jsonable(n.value)), _fmt(_jsonable(n.published)), n.unit,
                      "-" if n.rel_err is None else f"{n.rel_err:.2%}",
                      {True: "yes", False: "NO", None: "-"}[n.reproduced], n.source] for n in self.numbers]
            header = ["name", "glidectl", "published", "unit", "rel. err", "reproduced", "source"]
            caption = "Ledger: published value vs glidectl value"
        else:
            widths = [0.28, 0.3, 0.1, 0.32]
            cells = [[n.name, _fmt(_jsonable(n.value)), n.unit, n.source] for n in self.numbers]
            header = ["name", "value", "unit", "source"]
            caption = "Results"
        rows = [[_clip(c, w) for c, w in zip(r, widths, strict=True)] for r in cells]
        return caption, header, rows, widths

    def _notes(self, rows: list[list[str]]) -> list[str]:
        notes = []
        for n, row in zip(self.numbers, rows, strict=True):
            full = [("glidectl", _fmt(_jsonable(n.value)), row[1])]
            if self.has_ledger:
                full += [("published", _fmt(_jsonable(n.published)), row[2]), ("unit", n.unit, row[3])]
            else:
                full += [("unit", n.unit, row[2])]
            clipped = "; ".join(f"{k}: {v}" for k, v, shown in full if v != shown)
            text = " ".join(t for t in (clipped + "." if clipped else "", n.note) if t)
            if text:
                notes.append(f"{n.name}: {text}")
        return notes

    def write(self, outdir: str | Path) -> Path:
        """Write ``report.pdf``, ``<stem>.png`` per figure and ``numbers.json`` into ``outdir``.

        Parameters
        ----------
        outdir : str or Path
            Output folder (created if missing).

        Returns
        -------
        Path
            Path of ``report.pdf``.

        Raises
        ------
        OutputError
            If ``outdir`` cannot be created or written (also an :class:`OSError`).
        ArgumentTypeError
            If ``outdir`` is not a path.
        """
        if not isinstance(outdir, str | Path):
            raise ArgumentTypeError(f"outdir must be a folder path (str or Path), got {type(outdir).__name__}")
        out = Path(outdir)
        try:
            return self._write(out)
        except OutputError:
            raise
        except OSError as exc:
            raise OutputError(f"cannot write the report to '{out}': {exc.strerror or exc}; choose another "
                              "folder") from exc

    def _write(self, out: Path) -> Path:
        out.mkdir(parents=True, exist_ok=True)
        (out / "numbers.json").write_text(json.dumps([n.as_json() for n in self.numbers], indent=2))
        for stem, fig, _ in self.figures:
            fig.savefig(out / f"{stem}.png", dpi=130)
        pdf_path = out / "report.pdf"
        with PdfPages(pdf_path) as pdf:
            self._title_page(pdf, out.name)
            for v in self.vehicles:
                rows = [[k, val, u, s[:70]] for k, val, u, s in v.summary_rows()]
                self._table_pages(pdf, f"Vehicle parameters: {v.title}", ["key", "value", "unit", "source"],
                                  rows, [0.12, 0.12, 0.14, 0.62])
            if self.numbers:
                caption, header, rows, widths = self._number_rows()
                self._table_pages(pdf, caption, header, rows, widths)
                notes = self._notes(rows)
                if notes:
                    self._text_pages(pdf, "Notes on the numbers", notes)
            for caption, header, trows in self.tables:
                self._table_pages(pdf, caption, header, trows)
            for stem, fig, caption in self.figures:
                _figure_page(pdf, stem, fig, caption)
            for heading, body in self.sections:
                self._text_pages(pdf, heading, body.split("\n\n"))
        for _, fig, _ in self.figures:
            _close(fig)
        return pdf_path


def _figure_page(pdf: PdfPages, stem: str, fig: Any, caption: str) -> None:
    """One PDF page: the figure with its caption below (the figure is restored afterwards)."""
    fig.suptitle("")
    w, h = fig.get_size_inches()
    fig.set_size_inches(w, h + 0.9)
    txt = fig.text(0.02, 0.005, "\n".join(textwrap.wrap(f"Figure '{stem}': {caption}", 120)), fontsize=7.5,
                   va="bottom")
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.set(rect=(0, 0.9 / (h + 0.9), 1, 1 - 0.9 / (h + 0.9)))
    else:
        fig.subplots_adjust(bottom=0.9 / (h + 0.9) + 0.08)
    pdf.savefig(fig)
    txt.remove()
    fig.set_size_inches(w, h)


def _close(fig: Any) -> None:
    """Release a figure made with pyplot (figures made with ``Figure()`` need nothing)."""
    import sys

    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


def _version() -> str:
    from .. import __version__

    return __version__
