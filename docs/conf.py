"""Sphinx configuration of the prbdm_pin documentation.

Build with ``sphinx-build -W --keep-going -b html docs docs/_build/html`` from the repository root.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# the package documented is the one in this tree, installed or not
sys.path.insert(0, str(ROOT))

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
    "sphinx_copybutton",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = [
    "_build",
    # the benchmark tables are included into benchmarks.md, not pages of their own
    "benchmarks/*.md",
    # the viewing page's table (scripts/view_figures.py) is included there
    "guide/viewing/*.md",
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

# furo: a fluid body (wide diagrams and CLI tables are not cut at a fixed width), light and dark
html_theme = "furo"
html_title = f"prbdm_pin {release}"
# copy a command without its prompt or a doctest's output
copybutton_prompt_text = r">>> |\.\.\. |\$ "
copybutton_prompt_is_regexp = True
