"""Reports: the public API that design scripts use to write a PDF, one PNG per figure and ``numbers.json``.

A design file (``designs/<name>.py`` or any path) defines ``TITLE`` and ``design(progress, quick=False)`` and
returns a :class:`Report`; ``glidectl report NAME|PATH|all`` builds it into ``<out>/<name>/``::

    from glidectl.report import Report

    TITLE = "My glider"

    def design(progress, quick=False):
        veh = gc.load_vehicle("my_glider.toml")
        rep = Report(TITLE, vehicle=veh)
        rep.number("glide_speed", 0.3, "m/s", source="our design")
        return rep
"""

from .cache import cached
from .designs import Design, build_design, check_writable, find_designs, load_design, run_script
from .document import BHATTA_2006, Number, Report
from .figures import STYLE, label, new_figure, style
from .parts import map_parts

__all__ = [
    "BHATTA_2006",
    "STYLE",
    "Design",
    "Number",
    "Report",
    "build_design",
    "cached",
    "check_writable",
    "find_designs",
    "label",
    "load_design",
    "map_parts",
    "new_figure",
    "run_script",
    "style",
]
