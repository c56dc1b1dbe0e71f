"""The report PDF's layout: cells wrap inside their columns (nothing is cut), the vehicle section carries the
vehicle's provenance and uncertainty table, small tables share a page, long tables continue under their header.

Pages are collected as matplotlib figures (``Report._render`` into a collector) and their texts read back; the
page count of a written PDF is read from its page tree (``/Count``), so no PDF tool is needed."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.text import Text
from matplotlib.textpath import TextToPath

import glidectl as gc
from glidectl.report import Report
from glidectl.report.document import (
    _CELL_PT,
    _CONTENT_W,
    _LEADING,
    _MARGIN,
    _MIN_ROWS,
    _PAGE_H,
    _PAGE_W,
    _column_widths,
    _fit,
    _layout_table,
    _text_width,
    _wrap,
)

LONG_SOURCE = ("Measured in the towing tank of the laboratory over three campaigns (2019, 2021, 2023) with the "
               "hull fitted with its wings and rudder; the value is the mean of 42 runs at 0.2-0.5 m/s, corrected "
               "for blockage and the tank walls, and it agrees with the CFD estimate to within 4 % (see report TR-17, "
               "section 5.3, table 9).")


class Pages:
    """Collects the pages :meth:`Report._render` draws (as PdfPages would save them)."""

    def __init__(self) -> None:
        self.figs: list[Figure] = []

    def savefig(self, fig: Figure) -> None:
        self.figs.append(fig)


def _render(rep: Report) -> list[Figure]:
    pages = Pages()
    assert rep._render(pages, "test") == len(pages.figs)
    return pages.figs


def _texts(fig: Figure) -> list[str]:
    return [t.get_text() for t in fig.texts]


def _flat(text: str) -> str:
    """``text`` without white space: wrapping moves line breaks, never characters."""
    return "".join(text.split())


def _all_text(figs: list[Figure]) -> str:
    return _flat("".join(s for f in figs for s in _texts(f)))


def _extent(t: Text) -> tuple[float, float, float, float]:
    """Left, right, top and bottom of a page's text (pt from the page's bottom-left corner), measured as the PDF
    draws it (:class:`TextToPath`: the font's own metrics, with kerning)."""
    x, y = (72 * c for c in t.get_position())
    width = TextToPath().get_text_width_height_descent(t.get_text(), t.get_fontproperties(), ismath=False)[0]
    left = x - width / 2 if t.get_horizontalalignment() == "center" else x
    return left, left + width, y, y - _LEADING * t.get_fontsize()


def _pdf_pages(pdf: Path) -> int:
    """Page count of a PDF written by matplotlib (its page tree's ``/Count``)."""
    counts = re.findall(rb"/Count (\d+)", pdf.read_bytes())
    assert len(counts) == 1
    return int(counts[0])


@pytest.fixture(scope="module")
def long_source_vehicle(tmp_path_factory) -> gc.Vehicle:
    """ROGUE from a file of its own: one source of 300 characters, and an [uncertainty] table."""
    from importlib.resources import files

    text = (files("glidectl") / "vehicles" / "rogue.toml").read_text(encoding="utf-8")
    text = text.replace('source = "§2.3.1 (Nm(s/m)^2)"', f'source = "{LONG_SOURCE}"')
    assert LONG_SOURCE in text and len(LONG_SOURCE) > 300
    path = tmp_path_factory.mktemp("vehicles") / "long_rogue.toml"
    path.write_text(text, encoding="utf-8")
    veh = gc.load_vehicle(path)
    assert veh.sources["K_M"] == LONG_SOURCE
    return veh.with_uncertainty({"K_L": {"std": 12.5, "source": "spread of the tank runs"},
                                 "K_D": {"std": 7.0, "min": 95.0, "max": 125.0, "source": "drag fits"},
                                 "K_M": {"min": -40.0, "max": -33.0, "source": "pitch-moment bracket"}},
                                correlation={"K_D,K_L": 0.35})


# ------------------------------------------------------------------------------------------ wrapping
def test_wrap_keeps_every_character_and_respects_the_width():
    words = " ".join(f"word{i}" for i in range(300))
    for text, width in ((words, 37), ("x" * 2000, 50), ("a\nb c", 80), ("", 10), ("5-95 % range", 6)):
        lines = _wrap(text, width)
        assert lines and all(len(line) <= width for line in lines)
        assert _flat("".join(lines)) == _flat(text)
    assert _wrap("5-95 % range", 6)[0] == "5-95 %"  # no break at the hyphen
    assert _wrap("a\nb c", 80) == ["a", "b c"]     # the text's own line breaks are kept
    assert len(_wrap("x" * 2000, 50)) == 40        # a word longer than a line is broken, not dropped


def test_fit_lines_fit_their_width_and_short_text_stays_on_one_line():
    width = 150.0
    lines = _fit(LONG_SOURCE, width, _CELL_PT)
    assert len(lines) > 5 and _flat("".join(lines)) == _flat(LONG_SOURCE)
    assert all(_text_width(line, _CELL_PT) <= width for line in lines)
    assert max(_text_width(line, _CELL_PT) for line in lines) > 0.8 * width  # the lines fill the column
    word = "controllability"
    assert _fit(word, _text_width(word, _CELL_PT) + 0.5, _CELL_PT) == [word]
    assert _fit(word, _text_width(word, _CELL_PT, True) + 0.5, _CELL_PT, True) == [word]


def test_text_width_matches_what_the_pdf_draws():
    """The estimate (glyph advances, no kerning) is the width the PDF draws (the font's metrics with kerning) to
    within 1 %, rather above it."""
    for text, bold in ((LONG_SOURCE[:120], False), ("0123456789 -0.0060384 kg*m^2/s", False), ("key WW", True),
                       ("n " * 100, False)):
        prop = FontProperties(size=_CELL_PT, weight="bold" if bold else "normal")
        drawn = TextToPath().get_text_width_height_descent(text, prop, ismath=False)[0]
        assert 0.999 * drawn <= _text_width(text, _CELL_PT, bold) <= 1.01 * drawn


def test_column_widths_keep_narrow_columns_and_share_the_rest():
    assert _column_widths([30.0, 50.0, 60.0], 500.0) == [30.0, 50.0, 60.0]
    widths = _column_widths([30.0, 40.0, 900.0, 700.0], 600.0)
    assert widths[:2] == [30.0, 40.0]
    assert widths[2] == pytest.approx(widths[3]) == pytest.approx(265.0)
    assert sum(widths) == pytest.approx(600.0)
    widths = _column_widths([300.0, 280.0, 310.0], 600.0)
    assert widths == pytest.approx([200.0, 200.0, 200.0])


def test_laid_out_cells_fit_their_columns():
    rows = [["K_M", "-36.5", "kg/rad", LONG_SOURCE], ["g", "9.81", "m/s^2", "standard gravity"]]
    t = _layout_table("Parameters", ["key", "value", "unit", "source"], rows)
    assert sum(t.widths) <= _CONTENT_W + 1e-9
    for row in (t.header, *t.rows):
        for lines, w in zip(row.cells, t.widths, strict=True):
            assert all(_text_width(line, _CELL_PT) <= w for line in lines)
    assert t.rows[1].cells[3] == ("standard gravity",)
    assert _flat("".join(t.rows[0].cells[3])) == _flat(LONG_SOURCE)


def test_a_page_leaves_no_lone_rows_for_the_next():
    t = _layout_table("rows", ["a"], [[f"{i}"] for i in range(30)])
    row = t.rows[0].height
    assert all(r.height == row for r in t.rows)
    room = t.top(t.caption) + 29.5 * row                       # 29 rows fit: 1 would be left alone
    assert t.take(0, room, t.caption, fresh=True) == 30 - _MIN_ROWS
    assert t.take(0, room + row, t.caption, fresh=True) == 30   # all fit
    assert t.take(0, t.top(t.caption) + 5.5 * row, t.caption, fresh=False) == 5
    assert t.take(28, room, t.caption, fresh=False) == 2
    assert t.take(0, 1.0, t.caption, fresh=False) == 0
    assert t.take(0, 1.0, t.caption, fresh=True) == 1          # a fresh page takes a row whatever its height


# ------------------------------------------------------------------------------------------ whole reports
def test_the_whole_source_and_the_vehicle_provenance_are_in_the_pdf(long_source_vehicle):
    veh = long_source_vehicle
    figs = _render(Report("provenance", vehicle=veh))
    text = _all_text(figs)
    assert _flat(LONG_SOURCE) in text
    for s in (veh.title, veh.source, veh.name, veh.path, veh.kind, veh.law, veh.provenance, veh.notes):
        assert s and _flat(s) in text, s                      # the file's own [vehicle] source too
    for k, u in veh.uncertainty.items():
        assert _flat(f"{k}{u.kind}{veh.params[k]:.6g}") in text
        assert _flat(u.source) in text
    assert _flat("K_Lnormal306-infinf12.5") in text       # an untruncated normal entry
    assert _flat("K_Dnormal10995125") in text            # a truncated one (std 7 follows)
    assert _flat("K_Minterval-36.5-40-33-") in text       # an interval has no std
    assert _flat("K_D,K_L0.35") in text                   # the correlation
    # the parameter table lists the parameters, the uncertainty table its entries (not twice)
    assert "[uncertainty] K_L" not in text


def test_a_vehicle_built_in_python_says_so():
    veh = dataclasses.replace(gc.load_vehicle("rogue"), path="")
    text = _all_text(_render(Report("t", vehicle=veh)))
    assert _flat("none: built in Python") in text
    assert _flat("preset 'rogue'") in _all_text(_render(Report("t", vehicle=gc.load_vehicle("rogue"))))


def test_actuators_are_in_the_parameter_table():
    veh = gc.load_vehicle("slocum_shallow")
    text = _all_text(_render(Report("t", vehicle=veh)))
    for k, a in veh.actuators.items():
        assert _flat(f"[actuator] {k}{a.describe()}") in text
        assert _flat(a.source) in text


def test_three_small_tables_share_one_page(tmp_path):
    rep = Report("three tables")
    for k in range(3):
        rep.table(f"table {k}", ["gamma [deg]", "m0 [kg]"], [[f"{g}", f"{0.1 * g:.4f}"] for g in range(5)])
    figs = _render(rep)
    assert len(figs) == 1
    assert {"table 0", "table 1", "table 2"} <= set(_texts(figs[0]))
    assert _pdf_pages(rep.write(tmp_path / "r")) == 1


def test_tables_flow_until_the_page_is_full():
    rep = Report("many tables")
    for k in range(12):
        rep.table(f"table {k}", ["a", "b"], [[f"{k}.{i}", "x"] for i in range(6)])
    figs = _render(rep)
    assert 2 <= len(figs) <= 4
    seen = [s for f in figs for s in _texts(f) if s.startswith("table ")]
    assert seen == [f"table {k}" for k in range(12)]  # each once, in order, none split (6 rows each)


def test_a_long_table_continues_under_its_repeated_header():
    rep = Report("long")
    rep.table("A long table", ["alpha", "beta"], [[f"row-{i:03d}", f"{i * i}"] for i in range(150)])
    figs = _render(rep)
    assert len(figs) >= 3
    for k, fig in enumerate(figs):
        texts = _texts(fig)
        assert "alpha" in texts and "beta" in texts
        assert ("A long table (continued)" in texts) == (k > 0)
    rows = [s for f in figs for s in _texts(f) if s.startswith("row-")]
    assert rows == [f"row-{i:03d}" for i in range(150)]
    assert min(sum(1 for s in _texts(f) if s.startswith("row-")) for f in figs) >= _MIN_ROWS


def test_a_very_long_cell_is_not_lost(tmp_path):
    rep = Report("long cells")
    medium = " ".join(f"m{i:04d}" for i in range(350))          # about 2,000 characters
    huge = " ".join(f"h{i:05d}" for i in range(4000))            # several pages of one cell
    rep.table("Cells", ["key", "text"], [["medium", medium], ["huge", huge], ["after", "the last row"]])
    figs = _render(rep)
    texts = [s for f in figs for s in _texts(f)]
    assert _flat("".join(s for s in texts if s.startswith("m0"))) == _flat(medium)
    assert _flat("".join(s for s in texts if s.startswith("h0"))) == _flat(huge)   # split over pages, in order
    assert texts[-1] == "the last row" and texts.count("Cells (continued)") == len(figs) - 2
    assert len(figs) >= 4
    on_pages = [sum(1 for s in _texts(f) if s.startswith("m0")) for f in figs]
    assert max(on_pages) == sum(on_pages) >= 4    # the 2,000 characters wrap over lines of one page
    assert _pdf_pages(rep.write(tmp_path / "r")) == len(figs)


def test_notes_keep_only_the_note_texts():
    rep = Report("notes")
    long_value = list(range(20))
    rep.number("with_note", long_value, "m", source=LONG_SOURCE, note="why it differs")
    rep.number("without_note", 1.0, "m", source="our design")
    figs = _render(rep)
    texts = [s for f in figs for s in _texts(f)]
    assert "Notes on the numbers" in texts
    assert "why it differs" in texts and "without_note" in texts
    assert texts.count("with_note") == 2 and texts.count("without_note") == 1  # table and notes; table only
    assert _flat(LONG_SOURCE) in _all_text(figs)                              # the source is in the table
    assert not any("glidectl:" in s for s in texts)
    assert any("(20 entries in numbers.json)" in s for s in texts)


def test_every_text_stays_on_its_page(long_source_vehicle):
    rep = Report("A report whose title is long enough to wrap over two lines of the title block at the top of "
                 "the first page", vehicle=[long_source_vehicle, gc.load_vehicle("slocum_shallow")],
                 reference=gc.report.BHATTA_2006)
    rep.number("x", [1 + 2j, 3 - 1j], "1/s", source=LONG_SOURCE, published=[1.0], verdict=False, note="n " * 300)
    rep.text("Method", "\n\n".join(LONG_SOURCE for _ in range(40)))
    figs = _render(rep)
    assert len(figs) >= 4
    for fig in figs:
        for t in fig.texts:
            left, right, top, bottom = _extent(t)
            assert _MARGIN - 0.5 <= left and right <= _PAGE_W - _MARGIN + 0.5, t.get_text()
            assert top <= _PAGE_H - _MARGIN + 0.5 and bottom >= _MARGIN - 0.5, t.get_text()
    assert "1+2i, 3-1i" in [s for f in figs for s in _texts(f)]
