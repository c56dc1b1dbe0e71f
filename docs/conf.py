"""Sphinx configuration of the glidectl documentation.

Build (warnings are errors, broken cross-references too; no network needed)::

    MPLBACKEND=Agg python -m sphinx -W --keep-going -n -b html docs docs/_build/html
    MPLBACKEND=Agg python -m sphinx -W -b doctest docs docs/_build/doctest

Generated at build time (ignored by git, see ``docs/.gitignore``): the API reference ``api/`` from
``glidectl.API_GROUPS`` (``_ext/glidectl_api.py``) and the galleries ``auto_examples/``, ``auto_tutorials/``,
``auto_howto/`` from the scripts in ``examples/``, ``tutorials/``, ``howto/`` (sphinx-gallery, every script run).
The vehicle-file reference's tables come from ``glidectl.params`` (``_ext/glidectl_vehicle_file.py``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")  # no display on CI; sphinx-gallery also selects Agg itself

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import glidectl  # noqa: E402  (after the environment is set up)

# -- project ----------------------------------------------------------------------------------------------------------
project = "glidectl"
author = "the glidectl developers"
copyright = "glidectl developers, MIT licence"
release = glidectl.__version__
version = ".".join(release.split(".")[:2])

# -- general ----------------------------------------------------------------------------------------------------------
extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.doctest",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "glidectl_api",  # docs/_ext: API reference pages from glidectl.API_GROUPS
    "glidectl_vehicle_file",  # docs/_ext: vehicle-file tables from glidectl.params' validation specs
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "**.ipynb_checkpoints",
    # sphinx-gallery's sources (scripts and GALLERY_HEADER.rst): the pages are generated into auto_*/
    "examples", "tutorials", "howto",
]
default_role = "code"  # `x` in reST docstrings and pages is inline code, as in the Markdown pages
nitpicky = True  # the build command also passes -n

# Names of other packages that docstrings cross-reference (:func:`scipy.integrate.solve_ivp`,
# :class:`control.StateSpace`...). They would resolve through intersphinx, which needs the network (not available on
# CI), so they are exempt from -n. Only external packages belong here: a broken reference to a glidectl object must
# be fixed in its docstring (Python's builtins need no entry: Sphinx resolves them itself).
nitpick_ignore_regex = [
    (r"py:.*", r"(control|scipy|numpy|matplotlib|cvxpy|cvxopt|dask|distributed|xarray|concurrent|dataclasses"
               r"|collections|typing|pathlib)\..*"),
]

# -- autodoc / autosummary / numpydoc ------------------------------------------------------------------------------
autodoc_typehints = "none"  # the numpydoc sections give the types (with units); annotations would only duplicate them
autodoc_default_options = {"member-order": "bysource"}
autodoc_class_signature = "mixed"
autodoc_inherit_docstrings = True
autosummary_generate = False  # the object pages are written by docs/_ext/glidectl_api.py
numpydoc_show_class_members = False  # methods come from autodoc's :members:; a second listing would duplicate them
numpydoc_show_inherited_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True  # "Attributes" render as a parameter list, not as duplicate objects
numpydoc_xref_param_type = False  # types in Parameters are plain text (many are prose: "(n, 3) ndarray, m")

# -- doctest -----------------------------------------------------------------------------------------------------
doctest_global_setup = """
import numpy as np
import glidectl as gc
"""
doctest_test_doctest_blocks = "default"  # every >>> block of the API pages (numpydoc Examples) is run

# -- MyST (the Markdown pages) -----------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3  # [text](page.md#a-heading) links to headings work as on GitHub
myst_links_external_new_tab = False

# -- sphinx-gallery ----------------------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": ["examples", "tutorials", "howto"],
    "gallery_dirs": ["auto_examples", "auto_tutorials", "auto_howto"],
    "filename_pattern": r"\.py$",  # run every script, not only plot_*.py
    "ignore_pattern": r"(__init__|conftest|_helpers?)\.py$",
    "within_subsection_order": "FileNameSortKey",  # order by file name: 01_first.py, 02_second.py...
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "reset_modules": ("matplotlib",),
    "remove_config_comments": True,
    "download_all_examples": False,
    "show_memory": False,
    "show_signature": False,
    "min_reported_time": 1,
    "doc_module": ("glidectl",),
    "reference_url": {"glidectl": None},  # link names in the examples' code to the local API pages
    "backreferences_dir": "gen_modules/backreferences",
}

# -- HTML --------------------------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"glidectl {release}"
html_static_path = ["_static"]
html_css_files = ["glidectl.css"]
html_show_sourcelink = False
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "navbar_align": "left",
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
