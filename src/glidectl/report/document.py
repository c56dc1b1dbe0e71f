"""Report writer: a multi-page PDF (title, vehicle sections, a results table or a published-vs-glidectl ledger,
tables, figures with captions, text sections), one PNG per figure, and ``numbers.json``.

The PDF's tables flow one under the other on A4-landscape pages: a table goes under the previous one while it
fits, a long one continues on the next pages under its repeated caption and header, and every cell wraps inside
its column (nothing is cut). A vehicle section shows where the vehicle comes from (title, name, file, kind, law,
provenance hash, notes), its parameters and actuators with value, unit and source, and its ``[uncertainty]``
table. Each figure takes a page of its own; the text sections flow after the figures.

``numbers.json`` is a list of entries ``{name, value, unit, published, rel_err, reproduced, tolerance, source,
note}``: ``published`` is the value a publication prints (or null), ``rel_err`` is ``|value - published| /
|published|`` for scalars, ``reproduced`` is true/false/null (null: nothing published to compare with).

The writer never selects a matplotlib backend: it draws its own pages on :class:`matplotlib.figure.Figure`
objects (no pyplot) and saves the figures it is given with ``Figure.savefig``.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Protocol

from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties, findfont, get_font
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle

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


def _fmt(v: Any) -> str:
    """A value as a table cell: floats to 5 digits, complex numbers as ``a+bi``, lists and arrays to their first 8
    entries (``numbers.json`` has all)."""
    import numpy as np

    if isinstance(v, np.ndarray | np.generic):
        v = v.tolist()
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.5g}"
    if isinstance(v, list | tuple):
        more = f" ... ({len(v)} entries in numbers.json)" if len(v) > 8 else ""
        return ", ".join(_fmt(x) for x in v[:8]) + more
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
        """Add a text section (paragraphs separated by blank lines) at the end of the PDF, after the figures.

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
        """Add a table, placed under the previous table while it fits the page (long tables continue on further
        pages; cells wrap inside their column).

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
            self._render(pdf, out.name)
        for _, fig, _ in self.figures:
            _close(fig)
        return pdf_path

    def _render(self, sink: _Sink, label: str) -> int:
        """Draw the report's pages into ``sink`` (a :class:`PdfPages`, or anything with ``savefig(fig)``).

        The title, the vehicle sections, the number table with its notes and the tables flow one under the other
        on landscape pages; each figure takes a page of its own; the text sections flow after the figures (after
        the tables when there are none).

        Parameters
        ----------
        sink : PdfPages or object with a ``savefig(fig)`` method
            Receives one :class:`~matplotlib.figure.Figure` per page, in order.
        label : str
            Name of the report (its folder), printed under the title.

        Returns
        -------
        int
            Number of pages drawn.
        """
        pages = _Pages(sink)
        pages.title(self.title, f"glidectl {_version()} report '{label}', generated "
                    f"{datetime.now(UTC).strftime('%Y-%m-%d %H:%M UTC')}",
                    "Reference: " + self.reference if self.reference else "")
        for v in self.vehicles:
            for table in _vehicle_tables(v):
                pages.table(table)
        if self.numbers:
            pages.table(self._number_table())
            notes = [[n.name, n.note] for n in self.numbers if n.note]
            if notes:
                pages.table(_layout_table("Notes on the numbers", None, notes))
        for caption, header, rows in self.tables:
            pages.table(_layout_table(caption, header, rows))
        if self.figures:
            pages.close()
        for stem, fig, caption in self.figures:
            _figure_page(sink, stem, fig, caption)
        for heading, body in self.sections:
            pages.text(heading, body.split("\n\n"))
        pages.close()
        return pages.count + len(self.figures)

    def _number_table(self) -> _Table:
        """The ledger (published value vs glidectl value) when the report has one, else the results table."""
        if self.has_ledger:
            cells = [[n.name, _fmt(n.value), _fmt(n.published), n.unit,
                      "-" if n.rel_err is None else f"{n.rel_err:.2%}",
                      {True: "yes", False: "NO", None: "-"}[n.reproduced], n.source] for n in self.numbers]
            header = ["name", "glidectl", "published", "unit", "rel. err", "reproduced", "source"]
            return _layout_table("Ledger: published value vs glidectl value", header, cells)
        cells = [[n.name, _fmt(n.value), n.unit, n.source] for n in self.numbers]
        return _layout_table("Results", ["name", "value", "unit", "source"], cells)


def _vehicle_tables(v: Vehicle) -> list[_Table]:
    """The tables of a vehicle's section: where it comes from, its parameters and its uncertainty.

    The first table is a key-value block (title, name, file, kind, law, provenance hash, overrides, the file's
    notes); the second lists :meth:`Vehicle.summary_rows` (parameters, the law, the density profile, actuators
    with their notes) with value, unit and source; a vehicle with an ``[uncertainty]`` table adds its entries
    (kind, nominal value, absolute bounds, standard deviation, source) and, when it has them, the correlations.

    Parameters
    ----------
    v : Vehicle
        The vehicle.

    Returns
    -------
    list of _Table
        The laid-out tables, in reading order.
    """
    facts = [["title", v.title], ["name", v.name], ["file", v.path or "none: built in Python"],
             ["source", v.source or "not given"], ["kind", v.kind], ["law", v.law], ["provenance", v.provenance]]
    if v.overrides:
        facts.append(["overrides", ", ".join(f"{k} = {x:.6g}" for k, x in v.overrides.items())])
    facts.append(["notes", _prose(v.notes) or "none"])
    tables = [_layout_table(f"Vehicle '{v.name}'", None, facts)]
    rows = [list(r) for r in v.summary_rows() if not r[0].startswith("[uncertainty]")]
    for r in rows:  # an actuator's note (the file's ``note``) goes with its source
        act = v.actuators.get(r[0].removeprefix("[actuator] ")) if r[0].startswith("[actuator] ") else None
        if act is not None and act.note:
            r[3] = f"{r[3]}; note: {act.note}" if r[3] else f"note: {act.note}"
    tables.append(_layout_table(f"Parameters of vehicle '{v.name}'", ["key", "value", "unit", "source"], rows))
    if v.uncertainty:
        units = v.units
        rows = [[k, u.kind, f"{v.params[k]:.6g}", _bound(u.low), _bound(u.high), _bound(u.std), units.get(k, ""),
                 u.source] for k, u in v.uncertainty.items()]
        tables.append(_layout_table(f"Uncertainty of vehicle '{v.name}' ([uncertainty] table, absolute values)",
                                   ["key", "kind", "nominal", "low", "high", "std", "unit", "source"], rows))
        if v.correlation:
            tables.append(_layout_table(f"Correlations of vehicle '{v.name}' ([uncertainty.correlation])",
                                       ["keys", "correlation"], [[f"{a}, {b}", f"{r:.6g}"]
                                                                 for (a, b), r in v.correlation]))
    return tables


def _bound(x: float) -> str:
    """An uncertainty bound or standard deviation: ``"-"`` for an interval's missing ``std``."""
    return "-" if math.isnan(x) else f"{x:.6g}"


def _prose(text: str) -> str:
    """``text`` with the line breaks of a hard-wrapped file (single newlines) joined; blank lines stay breaks."""
    paragraphs = (" ".join(p.split()) for p in text.split("\n\n"))
    return "\n".join(p for p in paragraphs if p)


# ---------------------------------------------------------------------------------------------------- page layout
# Tables and text flow on A4-landscape pages, measured in points from the top-left corner of the page. Text is
# wrapped with textwrap to a character capacity, width / (em x font size): em starts at the text's mean character
# width and shrinks while the widest line, measured with the glyph advances of the font the text is drawn in, is
# wider than its column; lines fill their column without running out of it.

_PAGE_IN = (11.69, 8.27)            # A4 landscape (inches)
_PAGE_W, _PAGE_H = 72 * _PAGE_IN[0], 72 * _PAGE_IN[1]
_MARGIN = 36.0                       # page margin on every side (pt)
_CONTENT_W = _PAGE_W - 2 * _MARGIN
_CONTENT_H = _PAGE_H - 2 * _MARGIN
_GAP = 16.0                          # space between two blocks (pt)
_TITLE_PT = 17.0                     # font size of the report's title
_CAPTION_PT = 10.5                   # table captions and section headings
_CELL_PT = 8.0                       # table cells
_BODY_PT = 9.5                       # text sections
_BODY_W = 660.0                      # width of their lines (pt): about 130 characters, still easy to read
_LEADING = 1.3                       # line height, in font sizes
_PAD = 3.0                           # cell padding on every side (pt)
_KEEP_ROWS = 10                      # a table of at most this many rows is not split while it fits a page
_MIN_ROWS = 4                        # rows of a split table on either page, at least
_HEADER_FILL, _SHADE_FILL, _RULE, _THIN = "#dde3ea", "#f1f3f6", "#555555", "#bbbbbb"


class _Sink(Protocol):
    """Where pages go: :class:`PdfPages`, or a test's collector."""

    def savefig(self, figure: Figure) -> None: ...


@functools.lru_cache(maxsize=8192)
def _advance(char: str, font_file: str) -> float:
    """Advance width of ``char`` in the font ``font_file``, in font sizes (cached: a report measures thousands
    of lines made of a few dozen characters)."""
    font = get_font(font_file)
    font.set_size(100.0, 72.0)
    return font.load_char(ord(char)).linearHoriAdvance / 65536 / 100.0


def _text_width(text: str, size: float, bold: bool = False) -> float:
    """Width (pt) of one line of ``text`` in matplotlib's current default font (without kerning, which only
    narrows a line).

    Parameters
    ----------
    text : str
        One line.
    size : float
        Font size (pt).
    bold : bool
        Bold weight.

    Returns
    -------
    float
        The width in points.
    """
    font_file = findfont(FontProperties(weight="bold" if bold else "normal"))
    return size * sum(_advance(c, font_file) for c in text)


def _capacity(width: float, size: float, em: float) -> int:
    """How many characters of ``em`` font sizes each fit ``width`` points at ``size`` points (at least one)."""
    return max(int(width / (em * size)), 1)


def _wrap(text: str, width: int) -> list[str]:
    """Lines of at most ``width`` characters holding all of ``text``.

    Line breaks of ``text`` are kept, lines break at spaces (not at hyphens, which would split ``5-95``), and a
    word longer than a line is broken across lines, so nothing is dropped.

    Parameters
    ----------
    text : str
        The text.
    width : int
        Characters per line (at least 1).

    Returns
    -------
    list of str
        At least one line (``[""]`` for an empty text).
    """
    lines: list[str] = []
    for part in text.split("\n"):
        lines.extend(textwrap.wrap(part, max(width, 1), break_on_hyphens=False) or [""])
    return lines


def _fit(text: str, width: float, size: float, bold: bool = False) -> list[str]:
    """``text`` wrapped so that every line fits ``width`` points at ``size`` points.

    The character capacity starts from the text's mean character width (a text that fits stays on one line) and
    shrinks in proportion to the widest line until every line fits.

    Parameters
    ----------
    text : str
        The text (its line breaks are kept).
    width : float
        Available width (pt).
    size : float
        Font size (pt).
    bold : bool
        Bold weight.

    Returns
    -------
    list of str
        The lines (all of ``text``; a single character wider than ``width`` stays on a line of its own).
    """
    flat = text.replace("\n", "")
    chars = _capacity(width, size, max(_text_width(flat, size, bold) / (size * max(len(flat), 1)), 0.1))
    while True:
        lines = _wrap(text, chars)
        widest = max(_text_width(line, size, bold) for line in lines)
        if widest <= width or chars == 1:
            return lines
        chars = max(min(chars - 1, int(chars * width / widest)), 1)


def _column_widths(natural: Sequence[float], total: float) -> list[float]:
    """Widths of a table's columns: their natural widths when these fit ``total``, else a water filling.

    The narrow columns (keys, units) keep their natural width and the wide ones share what is left equally, so a
    long source column wraps while the short ones stay on one line.

    Parameters
    ----------
    natural : sequence of float
        Width each column needs for its longest line (pt).
    total : float
        Available width (pt).

    Returns
    -------
    list of float
        Column widths (pt): the natural widths when they fit, else widths summing to ``total``.
    """
    if sum(natural) <= total:
        return list(natural)
    widths = list(natural)
    order = sorted(range(len(natural)), key=natural.__getitem__)
    left = total
    for k, j in enumerate(order):
        share = left / (len(order) - k)
        if natural[j] > share:
            for i in order[k:]:
                widths[i] = share
            break
        left -= natural[j]
    return widths


@dataclass(frozen=True)
class _Row:
    """One row of a laid-out table: the wrapped lines of each cell.

    Attributes
    ----------
    cells : tuple of tuple of str
        Lines of each cell.
    shaded : bool
        Whether the row is drawn on a shaded background (every other row of the source table; the parts of a
        split row keep their row's shade).
    """

    cells: tuple[tuple[str, ...], ...]
    shaded: bool = False

    @property
    def lines(self) -> int:
        """Lines of the tallest cell (at least one)."""
        return max(1, max((len(c) for c in self.cells), default=1))

    @property
    def height(self) -> float:
        """Height of the row (pt): its tallest cell's lines plus the padding."""
        return self.lines * _LEADING * _CELL_PT + 2 * _PAD

    def split(self, max_lines: int) -> list[_Row]:
        """The row cut into consecutive rows of at most ``max_lines`` lines (a row taller than a page)."""
        if self.lines <= max_lines:
            return [self]
        return [_Row(tuple(c[k:k + max_lines] for c in self.cells), self.shaded)
                for k in range(0, self.lines, max_lines)]


@dataclass(frozen=True)
class _Table:
    """A table laid out for the page: wrapped caption and cells, column widths, rows no taller than a page.

    Attributes
    ----------
    caption, continued : tuple of str
        Lines of the caption, and of the caption repeated on a continuation page.
    widths : tuple of float
        Column widths (pt).
    header : _Row or None
        The header row, repeated on every page of the table; None for a key-value block (first column bold).
    rows : tuple of _Row
        The body rows.
    """

    caption: tuple[str, ...]
    continued: tuple[str, ...]
    widths: tuple[float, ...]
    header: _Row | None
    rows: tuple[_Row, ...]

    def top(self, caption: Sequence[str]) -> float:
        """Height (pt) of a caption of ``caption``'s lines and the header row, above the body rows."""
        return len(caption) * _LEADING * _CAPTION_PT + 3.0 + (0.0 if self.header is None else self.header.height)

    @property
    def height(self) -> float:
        """Height of the whole table on one page (pt)."""
        return self.top(self.caption) + sum(r.height for r in self.rows)

    def take(self, start: int, room: float, caption: Sequence[str], fresh: bool) -> int:
        """How many body rows from ``start`` go on a page with ``room`` points left under ``caption`` and the header.

        A fresh page takes at least one row (no row is taller than a page), and a page leaves the next one at least
        :data:`_MIN_ROWS` rows when it can keep as many itself (no lone last row on a page of its own).
        """
        left, n = room - self.top(caption), 0
        while start + n < len(self.rows) and self.rows[start + n].height <= left:
            left -= self.rows[start + n].height
            n += 1
        n = max(n, 1) if fresh else n
        rest = len(self.rows) - start - n
        if 0 < rest < _MIN_ROWS <= n - (_MIN_ROWS - rest):
            n -= _MIN_ROWS - rest
        return n


def _layout_table(caption: str, header: Sequence[str] | None, rows: Sequence[Sequence[str]]) -> _Table:
    """Lay out a table: column widths from the content, every cell wrapped in its column, tall rows split.

    Each column's natural width is its widest line (its bold header's included); when the columns do not fit the
    page, :func:`_column_widths` narrows the widest. Each cell is wrapped to its column (:func:`_fit`); a row
    taller than a page (a very long cell) is split into rows that fit one.

    Parameters
    ----------
    caption : str
        Caption printed above the table (wrapped).
    header : sequence of str or None
        Column headings; None for a key-value block (the keys, first column, in bold).
    rows : sequence of sequence of str
        The cells; an empty table gets one row of ``"-"``.

    Returns
    -------
    _Table
        The laid-out table.
    """
    ncol = len(header) if header is not None else max((len(r) for r in rows), default=2)
    cells = [[str(c) for c in r] for r in rows] or [["-"] * ncol]
    bold = [header is None and j == 0 for j in range(ncol)]
    widths = _column_widths(_natural_widths(header, cells, bold), _CONTENT_W)
    head = None if header is None else _Row(tuple(
        tuple(_fit(h, w - 2 * _PAD, _CELL_PT, True)) for h, w in zip(header, widths, strict=True)))
    frame = _Table(tuple(_fit(caption, _CONTENT_W, _CAPTION_PT, True)),
                   tuple(_fit(caption + " (continued)", _CONTENT_W, _CAPTION_PT, True)), tuple(widths), head, ())
    max_lines = max(int((_CONTENT_H - frame.top(frame.continued) - 2 * _PAD) / (_LEADING * _CELL_PT)), 1)
    body = []
    for i, r in enumerate(cells):
        row = _Row(tuple(tuple(_fit(c, w - 2 * _PAD, _CELL_PT, b)) for c, w, b in zip(r, widths, bold, strict=True)),
                   shaded=i % 2 == 1)
        body.extend(row.split(max_lines))
    return dataclasses.replace(frame, rows=tuple(body))


def _natural_widths(header: Sequence[str] | None, cells: list[list[str]], bold: list[bool]) -> list[float]:
    """Width (pt) each column needs for its widest line, its bold header's included, and the padding."""
    natural = []
    for j, heavy in enumerate(bold):
        lines = [line for r in cells for line in r[j].split("\n")]
        widest = max((_text_width(line, _CELL_PT, heavy) for line in lines), default=0.0)
        if header is not None:
            widest = max(widest, _text_width(header[j], _CELL_PT, True))
        natural.append(widest + 2 * _PAD + 1.0)
    return natural


class _Pages:
    """The flow of landscape pages: blocks go one under the other, a new page begins when the next does not fit.

    Parameters
    ----------
    sink : PdfPages or object with ``savefig(fig)``
        Receives each finished page.

    Attributes
    ----------
    count : int
        Pages handed to ``sink`` so far.
    """

    def __init__(self, sink: _Sink) -> None:
        self.sink = sink
        self.count = 0
        self.fig: Figure | None = None
        self.y = _MARGIN                 # top of the free space of the page (pt from the page's top)

    @property
    def room(self) -> float:
        """Free height left on the page (pt); a whole page when none is open."""
        return _CONTENT_H if self.fig is None else _PAGE_H - _MARGIN - self.y

    @property
    def fresh(self) -> bool:
        """True when nothing is drawn on the page yet."""
        return self.fig is None or self.y == _MARGIN

    def close(self) -> None:
        """Hand the open page, if any, to the sink."""
        if self.fig is not None:
            self.sink.savefig(self.fig)
            self.count += 1
            self.fig = None

    def _page(self) -> Figure:
        """The open page, opening one when needed."""
        if self.fig is None:
            self.fig = Figure(figsize=_PAGE_IN)
            self.y = _MARGIN
        return self.fig

    def _start(self, needed: float) -> None:
        """Begin a block whose first part is ``needed`` points tall: under a gap when it fits, else on a new page."""
        if not self.fresh and needed + _GAP > self.room:
            self.close()
        self._page()
        if not self.fresh:
            self.y += _GAP

    def _text(self, x: float, s: str, size: float, **kw: Any) -> None:
        """Draw ``s`` (literally: no mathtext) with its top at the current line, ``x`` points from the left edge."""
        fig = self._page()
        fig.text(x / 72, (_PAGE_H - self.y) / 72, s, transform=fig.dpi_scale_trans, fontsize=size, va="top",
                 parse_math=False, **kw)

    def _box(self, top: float, width: float, height: float, color: str) -> None:
        fig = self._page()
        fig.add_artist(Rectangle((_MARGIN / 72, (_PAGE_H - top - height) / 72), width / 72, height / 72,
                                 facecolor=color, edgecolor="none", transform=fig.dpi_scale_trans))

    def _rule(self, y: float, width: float, lw: float = 0.6, color: str = _RULE) -> None:
        fig = self._page()
        fig.add_artist(Line2D([_MARGIN / 72, (_MARGIN + width) / 72], [(_PAGE_H - y) / 72] * 2, linewidth=lw,
                              color=color, transform=fig.dpi_scale_trans))

    def _lines(self, lines: Sequence[str], size: float, x: float = _MARGIN, **kw: Any) -> None:
        """Draw ``lines`` one under the other from the current line and move below them."""
        for line in lines:
            if line:
                self._text(x, line, size, **kw)
            self.y += _LEADING * size

    def title(self, title: str, subtitle: str, reference: str) -> None:
        """The report's title block, centred at the top of the first page, and a rule under it."""
        self._page()
        self.y += 8.0
        centre: dict[str, Any] = {"x": _PAGE_W / 2, "ha": "center"}
        self._lines(_fit(title, 0.8 * _CONTENT_W, _TITLE_PT, True), _TITLE_PT, weight="bold", **centre)
        self.y += 4.0
        self._lines([subtitle], 9.5, **centre)
        if reference:
            self._lines(_fit(reference, 0.8 * _CONTENT_W, 9.0), 9.0, style="italic", **centre)
        self.y += 6.0
        self._rule(self.y, _CONTENT_W)
        self.y += 1.0

    def table(self, t: _Table) -> None:
        """Place a table under the previous block when it fits there, else from the top of a new page.

        A table that does not fit the room left is split there only when it is long (more than
        :data:`_KEEP_ROWS` rows, or taller than a page) and at least :data:`_MIN_ROWS` rows go on either side;
        its continuation pages repeat the caption (marked continued) and the header.
        """
        if not self.fresh and t.height + _GAP > self.room:
            here = t.take(0, self.room - _GAP, t.caption, fresh=False)
            long = len(t.rows) > _KEEP_ROWS or t.height > _CONTENT_H
            if not (long and here >= _MIN_ROWS and len(t.rows) - here >= _MIN_ROWS):
                self.close()
        i, caption = 0, t.caption
        while True:
            self._start(t.top(caption) + t.rows[i].height)
            n = t.take(i, self.room, caption, self.fresh)
            self._lines(caption, _CAPTION_PT, weight="bold")
            self.y += 3.0
            if t.header is not None:
                self._row(t, t.header, _HEADER_FILL, bold=True)
            else:
                self._rule(self.y, sum(t.widths), 0.3, _THIN)
            for row in t.rows[i:i + n]:
                self._row(t, row, _SHADE_FILL if row.shaded and t.header is not None else None)
            if t.header is not None:
                self._rule(self.y, sum(t.widths))
            i += n
            if i >= len(t.rows):
                return
            self.close()
            caption = t.continued

    def _row(self, t: _Table, row: _Row, fill: str | None, bold: bool = False) -> None:
        """Draw one row at the current line (shaded, or ruled below in a key-value block) and move below it."""
        top, x = self.y, _MARGIN
        if fill is not None:
            self._box(top, sum(t.widths), row.height, fill)
        elif t.header is None:
            self._rule(top + row.height, sum(t.widths), 0.3, _THIN)
        for j, (lines, w) in enumerate(zip(row.cells, t.widths, strict=True)):
            self.y = top + _PAD
            heavy = bold or (t.header is None and j == 0)
            self._lines(lines, _CELL_PT, x + _PAD, weight="bold" if heavy else "normal")
            x += w
        self.y = top + row.height

    def text(self, heading: str, paragraphs: Sequence[str]) -> None:
        """Place a text section: its heading, then its paragraphs (blank line between), flowing over pages."""
        lines: list[str] = []
        for p in paragraphs:
            lines.extend([*_fit(" ".join(p.split()), _BODY_W, _BODY_PT), ""])
        lines.pop()
        step = _LEADING * _BODY_PT
        i, head = 0, _fit(heading, _CONTENT_W, _CAPTION_PT, True)
        while True:
            self._start(len(head) * _LEADING * _CAPTION_PT + 3.0 + 3 * step)
            self._lines(head, _CAPTION_PT, weight="bold")
            self.y += 3.0
            while i < len(lines) and step <= self.room:
                self._lines([lines[i]], _BODY_PT)
                i += 1
            if i >= len(lines):
                return
            self.close()
            head = _fit(heading + " (continued)", _CONTENT_W, _CAPTION_PT, True)


def _figure_page(pdf: _Sink, stem: str, fig: Any, caption: str) -> None:
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
