"""Report writer: a multi-page PDF (title, parameters, thesis-vs-glidectl ledger, figures with captions, notes),
one PNG per figure, and ``numbers.json``.

``numbers.json`` is a list of entries ``{name, value, thesis, unit, rel_err, reproduced, source, note}``
(DESIGN.md): ``thesis`` is the printed value or null, ``rel_err`` is ``|value - thesis| / |thesis|`` for scalars,
``reproduced`` is true/false/null (null: nothing printed to compare with).
"""

from __future__ import annotations

import json
import math
import textwrap
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.backends.backend_pdf import PdfPages

from ..params import Vehicle

__all__ = ["Number", "Report"]


@dataclass(frozen=True)
class Number:
    """One ledger line: our value against the thesis's printed value."""

    name: str
    value: Any
    unit: str
    source: str
    thesis: Any = None
    tolerance: float | None = None
    note: str = ""
    verdict: bool | None = None

    @property
    def rel_err(self) -> float | None:
        if isinstance(self.value, bool) or isinstance(self.thesis, bool):
            return None
        if isinstance(self.value, int | float) and isinstance(self.thesis, int | float) and self.thesis != 0:
            return abs(self.value - self.thesis) / abs(self.thesis)
        return None

    @property
    def reproduced(self) -> bool | None:
        """True when within ``tolerance`` (relative) of the thesis; None when there is nothing to compare.

        ``verdict`` (set for non-scalar values such as eigenvalue lists, with the reason in ``note``) overrides.
        """
        if self.verdict is not None:
            return self.verdict
        if self.thesis is None or self.tolerance is None:
            return None
        e = self.rel_err
        return bool(e is not None and e <= self.tolerance)

    def as_json(self) -> dict[str, Any]:
        return {"name": self.name, "value": _jsonable(self.value), "thesis": _jsonable(self.thesis),
                "unit": self.unit, "rel_err": self.rel_err, "reproduced": self.reproduced,
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


@dataclass
class Report:
    """Collects numbers, figures and notes of one design, then writes them (:meth:`write`)."""

    name: str
    title: str
    vehicles: list[Vehicle] = field(default_factory=list)
    numbers: list[Number] = field(default_factory=list)
    figures: list[tuple[str, Any, str]] = field(default_factory=list)
    sections: list[tuple[str, str]] = field(default_factory=list)
    tables: list[tuple[str, list[str], list[list[str]]]] = field(default_factory=list)

    def number(self, *args: Any, **kw: Any) -> Number:
        n = Number(*args, **kw)
        if any(m.name == n.name for m in self.numbers):
            raise ValueError(f"duplicate number {n.name}")
        self.numbers.append(n)
        return n

    def figure(self, stem: str, fig: Any, caption: str) -> None:
        self.figures.append((stem, fig, caption))

    def text(self, heading: str, body: str) -> None:
        self.sections.append((heading, body))

    def table(self, caption: str, header: list[str], rows: list[list[str]]) -> None:
        self.tables.append((caption, header, rows))

    # ------------------------------------------------------------------ writing
    def _text_pages(self, pdf: PdfPages, heading: str, paragraphs: list[str]) -> None:
        lines: list[str] = []
        for p in paragraphs:
            lines.extend(textwrap.wrap(p, 100) or [""])
            lines.append("")
        per = 52
        for k in range(0, max(len(lines), 1), per):
            fig = plt.figure(figsize=(8.27, 11.69))
            fig.text(0.07, 0.95, heading + (" (cont.)" if k else ""), fontsize=14, weight="bold", va="top")
            fig.text(0.07, 0.91, "\n".join(lines[k:k + per]), fontsize=8.5, va="top", family="monospace")
            pdf.savefig(fig)
            plt.close(fig)

    def _table_pages(self, pdf: PdfPages, caption: str, header: list[str], rows: list[list[str]],
                     widths: list[float] | None = None) -> None:
        per = 34
        if widths is None:  # proportional to the longest entry of each column
            lens = [max([len(str(h))] + [len(str(r[i])) for r in rows if i < len(r)]) + 2
                    for i, h in enumerate(header)]
            widths = [x / sum(lens) for x in lens]
        for k in range(0, max(len(rows), 1), per):
            fig = plt.figure(figsize=(11.69, 8.27))
            fig.text(0.04, 0.95, caption + (" (cont.)" if k else ""), fontsize=12, weight="bold", va="top")
            ax = fig.add_axes((0.03, 0.04, 0.94, 0.86))
            ax.axis("off")
            chunk = rows[k:k + per] or [["-"] * len(header)]
            t = ax.table(cellText=chunk, colLabels=header, loc="upper left", cellLoc="left",
                         colWidths=widths)
            t.auto_set_font_size(False)
            t.set_fontsize(7)
            t.scale(1, 1.25)
            pdf.savefig(fig)
            plt.close(fig)

    def write(self, outdir: str | Path) -> Path:
        """Write ``report.pdf``, ``<stem>.png`` per figure and ``numbers.json`` into ``outdir``; return the PDF."""
        out = Path(outdir)
        out.mkdir(parents=True, exist_ok=True)
        (out / "numbers.json").write_text(json.dumps([n.as_json() for n in self.numbers], indent=2))
        for stem, fig, _ in self.figures:
            fig.savefig(out / f"{stem}.png", dpi=130)
        pdf_path = out / "report.pdf"
        with PdfPages(pdf_path) as pdf:
            fig = plt.figure(figsize=(8.27, 11.69))
            fig.text(0.5, 0.75, self.title, ha="center", fontsize=18, weight="bold", wrap=True)
            fig.text(0.5, 0.68, f"glidectl design '{self.name}'", ha="center", fontsize=12)
            stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
            vtxt = "\n".join(f"{v.title}  [{v.name}, provenance {v.provenance}]" for v in self.vehicles)
            fig.text(0.5, 0.6, f"generated {stamp}\n\n{vtxt}", ha="center", va="top", fontsize=9)
            fig.text(0.5, 0.4, "Reference: P. Bhatta, Nonlinear Stability and Control of Gliding Vehicles,\n"
                     "PhD thesis, Princeton University, 2006.", ha="center", fontsize=9, style="italic")
            pdf.savefig(fig)
            plt.close(fig)
            for v in self.vehicles:
                rows = [[k, val, u, s[:70]] for k, val, u, s in v.summary_rows()]
                self._table_pages(pdf, f"Vehicle parameters: {v.title}", ["key", "value", "unit", "source"],
                                  rows, [0.12, 0.12, 0.14, 0.62])
            widths = [0.2, 0.22, 0.16, 0.07, 0.07, 0.07, 0.21]
            rows = [[_clip(c, w) for c, w in zip(
                [n.name, _fmt(_jsonable(n.value)), _fmt(_jsonable(n.thesis)), n.unit,
                 "-" if n.rel_err is None else f"{n.rel_err:.2%}",
                 {True: "yes", False: "NO", None: "-"}[n.reproduced], n.source], widths, strict=True)]
                    for n in self.numbers]
            self._table_pages(pdf, "Ledger: thesis value vs glidectl value",
                              ["name", "glidectl", "thesis", "unit", "rel. err", "reproduced", "source"], rows,
                              widths)
            notes = []
            for n, row in zip(self.numbers, rows, strict=True):
                full = [("glidectl", _fmt(_jsonable(n.value)), row[1]), ("thesis", _fmt(_jsonable(n.thesis)), row[2]),
                        ("unit", n.unit, row[3])]
                clipped = "; ".join(f"{k}: {v}" for k, v, shown in full if v != shown)
                text = " ".join(t for t in (clipped + "." if clipped else "", n.note) if t)
                if text:
                    notes.append(f"{n.name}: {text}")
            if notes:
                self._text_pages(pdf, "Ledger notes", notes)
            for caption, header, trows in self.tables:
                self._table_pages(pdf, caption, header, trows)
            for stem, fig, caption in self.figures:
                fig.suptitle("")
                w, h = fig.get_size_inches()
                fig.set_size_inches(w, h + 0.9)
                txt = fig.text(0.02, 0.005, "\n".join(textwrap.wrap(f"Figure '{stem}': {caption}", 120)),
                               fontsize=7.5, va="bottom")
                fig.get_layout_engine().set(rect=(0, 0.9 / (h + 0.9), 1, 1 - 0.9 / (h + 0.9)))
                pdf.savefig(fig)
                txt.remove()
                fig.set_size_inches(w, h)
                plt.close(fig)
            for heading, body in self.sections:
                self._text_pages(pdf, heading, body.split("\n\n"))
        return pdf_path
