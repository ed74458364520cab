"""Serve MathJax from the built site: copies the parts of Debian's libjs-mathjax (MathJax 2) that the
TeX-AMS_CHTML configuration loads into <html>/_static/mathjax, so formulas render offline."""
import os
import shutil

from sphinx.errors import ExtensionError

SOURCE = os.environ.get("DEMBRIDGE_MATHJAX", "/usr/share/javascript/mathjax")
# MathJax.js loads these on demand for TeX input and CommonHTML output (fonts as woff only)
PARTS = ["MathJax.js", "config", "extensions", "jax/input/TeX", "jax/output/CommonHTML", "jax/element",
         "fonts/HTML-CSS/TeX/woff", "localization/en"]


def _check(app):
    if app.builder.format == "html" and not os.path.isfile(os.path.join(SOURCE, "MathJax.js")):
        raise ExtensionError(
            f"MathJax not found in {SOURCE}: install Debian's libjs-mathjax (apt-get install libjs-mathjax; "
            "./dembridge does it) or point DEMBRIDGE_MATHJAX at a MathJax 2 folder")


def _copy(app, exc):
    if exc is not None or app.builder.format != "html":
        return
    dest = os.path.join(app.outdir, "_static", "mathjax")
    for part in PARTS:
        src = os.path.join(SOURCE, part)
        if os.path.isdir(src):
            shutil.copytree(src, os.path.join(dest, part), dirs_exist_ok=True)
        elif os.path.isfile(src):
            os.makedirs(os.path.dirname(os.path.join(dest, part)), exist_ok=True)
            shutil.copy2(src, os.path.join(dest, part))


def setup(app):
    app.connect("builder-inited", _check)
    app.connect("build-finished", _copy)
    return {"parallel_read_safe": True}
