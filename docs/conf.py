"""Sphinx configuration of the prbdm_pin documentation.

Build with ``sphinx-build -W --keep-going -b html docs docs/_build/html`` from the repository root.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# the package documented is the one in this tree, installed or not
sys.path.insert(0, str(ROOT))
# the docs build's own hooks (sphinx-gallery's argv and figure scraper)
sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

import prbdm_pin  # noqa: E402

project = "prbdm_pin"
author = "prbdm_pin developers"
copyright = "prbdm_pin developers"  # noqa: A001
release = prbdm_pin.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx.ext.intersphinx",
    "sphinx_copybutton",
    "sphinx_gallery.gen_gallery",
    "sphinxarg.ext",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = [
    "_build",
    # the benchmark tables are included into benchmarks.md, not pages of their own
    "benchmarks/*.md",
    # the viewing page's table (scripts/view_figures.py) is included there
    "guide/viewing/*.md",
    # sphinx-gallery's own by-products beside the pages it writes
    "gallery/*.ipynb",
    "gallery/*.py",
    "gallery/*.md5",
    "gallery/*.zip",
]

myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False

# links to numpy, scipy, matplotlib, python-control and pymoo where their inventories can be had
# (docs/_ext/intersphinx_reach.py: a closed network leaves them out rather than failing -W)
from intersphinx_reach import intersphinx_mapping as _reach  # noqa: E402

intersphinx_mapping, _unreached = _reach()
for _note in _unreached:
    print(_note)
intersphinx_timeout = 10

# furo: a fluid body (wide diagrams and CLI tables are not cut at a fixed width), light and dark
html_theme = "furo"
html_title = f"prbdm_pin {release}"
# copy a command without its prompt or a doctest's output
copybutton_prompt_text = r">>> |\.\.\. |\$ "
copybutton_prompt_is_regexp = True

# the examples gallery: every script of examples/ runs on each build in quick mode (1D beam
# truth, seconds each), its --out under docs/_build/gallery_out/, and its page shows the script,
# what it printed and the figure it wrote; the full-mode numbers and figures are on the example
# pages of docs/examples/ (scripts/docs_example_figures.py writes those figures)
sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"\.py$",  # run every example, not only plot_*.py
    "reset_argv": "gallery_hooks.quick_argv",
    "image_scrapers": ("gallery_hooks.png_scraper",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "min_reported_time": 1,
    "show_memory": False,
    # no execution-times page (it loads its table scripts from CDNs)
    "write_computation_times": False,
    "show_signature": False,
    # an example that fails stops the build (CI sees it), not a page showing its traceback
    "abort_on_example_error": True,
}
