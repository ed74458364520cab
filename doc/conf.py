# Sphinx + MyST configuration of the dembridge documentation site.
# Build: .venv/bin/python -m sphinx -W --keep-going -b html doc build/doc/html
# (run by the test tests/python/test_docs.py, which also runs every ```lammps block as a deck).
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # the API reference documents this tree
sys.path.insert(0, os.path.join(HERE, "_ext"))

project = "dembridge"
author = "dembridge developers"
from dembridge import __version__ as release  # noqa: E402

version = release

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "deck_lexers"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_ext", "README.md"]
myst_enable_extensions = ["dollarmath", "deflist"]
myst_heading_anchors = 3
# Links to the repository's files (decks, scripts, tests) are plain paths, not documents.
suppress_warnings = []
autodoc_member_order = "bysource"
autodoc_mock_imports = ["lammps", "mpi4py", "matplotlib"]
html_theme = "alabaster"
html_title = f"dembridge {release}"
html_static_path = []
