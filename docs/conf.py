"""Sphinx configuration: the user guides (Markdown, through MyST) and the API reference (autodoc, numpydoc style).

Build: ``python -m sphinx -W -b html docs docs/_build/html`` (needs ``pip install -e ".[docs]"``).
"""

from importlib import metadata

project = "jointwear"
author = "jointwear contributors"
try:
    release = metadata.version("jointwear")
except metadata.PackageNotFoundError:  # a source tree that is not installed
    release = "0+unknown"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]

# numpydoc-style docstrings only (the house style); Google style would hide malformed sections
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}

# the guides link to their own headings ([Install](#install)) and to each other
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

html_theme = "alabaster"
html_title = f"jointwear {release}"
