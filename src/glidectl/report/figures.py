"""Figure helpers of the report API, kept here for existing imports: they live in :mod:`glidectl.plotting`.

``from glidectl.report import STYLE, label, new_figure, style`` keeps working; new code imports
:mod:`glidectl.plotting`.
"""

from __future__ import annotations

from ..plotting import STYLE, label, new_figure, plot_locus, plot_locus_real, plot_simulation, style

__all__ = ["STYLE", "label", "new_figure", "plot_locus", "plot_locus_real", "plot_simulation", "style"]
