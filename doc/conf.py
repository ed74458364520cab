# Sphinx + MyST configuration of the dembridge documentation site.
# Build: .venv/bin/python -m sphinx -W --keep-going -b html doc build/doc/html
# (run by the test tests/docs/test_docs.py, which also runs every ```lammps block as a deck).
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # the API reference documents this tree
sys.path.insert(0, os.path.join(HERE, "_ext"))

project = "dembridge"
author = "dembridge developers"
from dembridge import __version__ as release  # noqa: E402

version = release

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax", "deck_lexers",
              "command_index", "local_mathjax"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_ext", "README.md"]
myst_enable_extensions = ["dollarmath", "deflist"]
myst_heading_anchors = 3
# Links to the repository's files (decks, scripts, tests) are plain paths, not documents.
suppress_warnings = []
autodoc_member_order = "bysource"
autodoc_mock_imports = ["lammps", "mpi4py", "matplotlib"]
html_theme = "furo"  # search, navigation sidebar, light/dark; code blocks scroll instead of being cut
html_title = f"dembridge {release}"
html_static_path = []
# Formulas: MyST $...$ / $$...$$ rendered by MathJax 2, served from the site itself (no internet needed):
# doc/_ext/local_mathjax.py copies Debian's libjs-mathjax into _static/mathjax (./dembridge installs it).
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_CHTML"
# MyST marks prose as tex2jax_ignore and formulas with class "math": tell MathJax 2 the same.
mathjax2_config = {"showMathMenu": False, "messageStyle": "none",
                   "tex2jax": {"processClass": "tex2jax_process|mathjax_process|math|output_area",
                               "ignoreClass": "tex2jax_ignore|mathjax_ignore|document",
                               "inlineMath": [["\\(", "\\)"]], "displayMath": [["\\[", "\\]"]]}}
