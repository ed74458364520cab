"""Every page of the built site rendered in one headless Chromium (Debian `chromium`, installed by
./dembridge): once MathJax has typeset it, a page fails on raw TeX or an untypeset formula, on a formula
written as plain text in a table cell or in running text (sqrt(...), x_{...}, powers, R*...: write it as $...$), on a link to a
page or anchor of the site that does not exist, and a command page (doc/{pair,fix,compute,dump}_*.md)
fails when it lacks a section of the LAMMPS layout."""
import os
import sys
import urllib.parse

import pytest

from doc_blocks import DOC
from headless_chromium import Chromium, find_chromium

sys.path.insert(0, os.path.join(DOC, "_ext"))
import command_index  # noqa: E402

LAYOUT = ["Syntax", "Examples", "Description", "Output info", "Restart info", "Restrictions",
          "Related commands", "Default", "References"]
CHECKS = open(os.path.join(os.path.dirname(__file__), "page_checks.js"), encoding="utf-8").read()
COMMAND_PAGES = {os.path.splitext(os.path.basename(p))[0] + ".html" for p in command_index.command_pages(DOC)}


@pytest.fixture(scope="module")
def rendered(built_site):
    out, build = built_site
    assert build.returncode == 0, "the site did not build (see test_sphinx_builds_the_site_without_warnings)"
    exe = find_chromium()
    assert exe, "chromium not found: apt-get install chromium (./dembridge installs it)"
    pages = sorted(p for p in os.listdir(out) if p.endswith(".html") and p not in ("genindex.html", "search.html"))
    browser = Chromium(exe)
    try:
        results = {}
        for page in pages:
            browser.open((out / page).as_uri())
            results[page] = browser.evaluate(CHECKS)
    finally:
        browser.close()
    return out, results


def test_every_page_was_rendered(rendered):
    _, results = rendered
    assert "index.html" in results and "commands.html" in results and "pair_gran.html" in results
    assert len(results) >= 30


def test_formulas_are_typeset_and_no_raw_tex_is_left(rendered):
    _, results = rendered
    bad = [f"{p}: raw TeX ...{s}..." for p, r in results.items() for s in r["raw"]]
    bad += [f"{p}: formula not typeset: {s}" for p, r in results.items() for s in r["untypeset"]]
    assert not bad, "\n".join(bad)


def test_the_formula_tables_use_math(rendered):
    _, results = rendered
    bad = [f"{p}: {cell}" for p, r in results.items() for cell in r["plainFormulas"]]
    assert not bad, "table cells with a formula written as text (write it as $...$ math):\n" + "\n".join(bad)


def test_formulas_in_running_text_use_math(rendered):
    _, results = rendered
    bad = [f"{p}: ...{s}..." for p, r in results.items() for s in r["plainProse"]]
    assert not bad, ("paragraphs or list items with a formula written as text (sqrt(...), x_{...}, powers, "
                     "R*...: write it as $...$ math):\n" + "\n".join(bad))


def test_pair_gran_formulas_are_rendered_by_mathjax(rendered):
    """The check above must see typeset math somewhere, or it tests nothing."""
    out, results = rendered
    assert (out / "_static" / "mathjax" / "MathJax.js").is_file()
    html = (out / "pair_gran.html").read_text()
    assert "_static/mathjax/MathJax.js" in html and 'class="math' in html
    assert not results["pair_gran.html"]["untypeset"]


def test_no_dead_internal_links(rendered):
    out, results = rendered
    bad = []
    for page, r in results.items():
        for href in r["links"]:
            url = urllib.parse.urlsplit(href)
            if url.scheme or href.startswith("//"):
                continue
            target = os.path.normpath(os.path.join(os.path.dirname(page), urllib.parse.unquote(url.path))) \
                if url.path else page
            if not (out / target).exists():
                bad.append(f"{page}: link to {href}: no such page")
            elif url.fragment and target in results and url.fragment not in results[target]["ids"]:
                bad.append(f"{page}: link to {href}: no such anchor")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("page", sorted(COMMAND_PAGES))
def test_command_page_has_the_lammps_layout(rendered, page):
    _, results = rendered
    headings = results[page]["headings"]
    missing = [s for s in LAYOUT if s not in headings]
    assert not missing, (f"{page} lacks the sections {missing} of the LAMMPS layout {LAYOUT} "
                         f"(its sections: {headings}); write 'none' where a section does not apply")
