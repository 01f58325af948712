# Sphinx configuration of the nhc documentation site, built by `cmake --build build --target docs`
# (docs/CMakeLists.txt) from a copy of docs/ with the generated pages beside it.
import os
import sys

project = "nhc"
author = "the nhc authors"
release = os.environ.get("NHC_VERSION", "")
version = release

# The compiled module is imported from the build tree for autodoc (NHC_PYTHON_DIR).
if os.environ.get("NHC_PYTHON_DIR"):
    sys.path.insert(0, os.environ["NHC_PYTHON_DIR"])

extensions = ["myst_parser", "nbsphinx", "sphinx.ext.autodoc", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "animate/**", "compare/**/*.md"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
# The pages cite source files by path (examples/…, codegen/…) as text; links between pages resolve.
suppress_warnings = ["myst.header"]

# The notebooks are run by the test python:test_notebooks and here, so the site shows their outputs.
nbsphinx_execute = os.environ.get("NHC_DOCS_EXECUTE", "always")
nbsphinx_timeout = 600
nbsphinx_kernel_name = "python3"

# MathJax from Debian's libjs-mathjax, copied beside the pages: the site works offline.
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS-MML_HTMLorMML"
nbsphinx_requirejs_path = ""

html_theme = "furo"
html_title = "nhc — the nonholonomic compiler"
html_static_path = []
autodoc_member_order = "bysource"
autodoc_typehints = "description"
