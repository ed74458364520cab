"""The documentation site (issue 14, deliverable 4, acceptance C).

* every fenced block in doc/**/*.md names its language (so a deck cannot hide as an untagged block);
* the Sphinx + MyST build of doc/ has zero warnings (``-W``), pages found automatically;
* every block tagged ``lammps`` runs as a deck with the plugin (lmp, serial) and exits 0.
"""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
import dembridge  # noqa: E402
from doc_blocks import DOC, KNOWN, ROOT, blocks, decks, pages, rel  # noqa: E402

HOW_TO_TAG = (
    "Tag each code block in doc/ with its language: ```lammps for a complete deck (the docs test runs it, "
    "so it must run on its own with the plugin, in seconds), ```lammps-fragment for deck lines that are "
    "not a runnable deck (syntax lines, examples of single commands), or bash/python/cpp/text/mbdyn/... "
    f"Known tags: {', '.join(sorted(KNOWN))} (tests/docs/doc_blocks.py).")


def test_the_docs_have_pages():
    assert os.path.join(DOC, "index.md") in pages()
    assert len(pages()) >= 10


def test_every_code_block_names_its_language():
    bad = [f"{rel(p)}:{n}: {'untagged' if not lang else 'unknown tag ' + repr(lang)}"
           for p in pages() for n, lang, _ in blocks(p) if lang not in KNOWN]
    assert not bad, HOW_TO_TAG + "\n" + "\n".join(bad)


def test_sphinx_builds_the_site_without_warnings(tmp_path):
    import importlib.util
    missing = [m for m in ("sphinx", "myst_parser") if importlib.util.find_spec(m) is None]
    assert not missing, f"{missing} not installed in {sys.prefix}: ./dembridge test installs requirements.txt"
    out = tmp_path / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", DOC, str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    hint = (
        "The docs site must build without warnings (sphinx -W). Common fixes: a new page must be in a toctree: "
        "pages named pair_*.md, fix_*.md, compute_*.md are listed under Commands automatically; add any other "
        "page to a toctree in doc/index.md. Headings must not skip levels (# then ##, not #  then ###). "
        "Links between pages are [text](other_page.md); a link to a repository file is written as `path` "
        "(code), not as a link. Reproduce: .venv/bin/python -m sphinx -W --keep-going -b html doc /tmp/html")
    assert p.returncode == 0, f"{hint}\n\n{p.stderr[-6000:]}"
    for page in pages():
        name = os.path.splitext(os.path.relpath(page, DOC))[0] + ".html"
        assert (out / name).is_file(), f"{rel(page)} was not built into {name}"
    assert (out / "python_api.html").read_text().count("dembridge.run_deck") > 0  # autodoc ran


DECKS = decks()


def test_there_are_documented_decks():
    assert len(DECKS) >= 1


@pytest.mark.parametrize("where,deck", DECKS, ids=[w for w, _ in DECKS])
def test_documented_deck_runs(where, deck, tmp_path):
    run = dembridge.run_deck(deck, cwd=str(tmp_path), timeout=300, check=False)
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "ERROR" not in out, (
        f"the deck in {where} (a ```lammps block) failed; fix the deck or, if it is not meant to run on "
        f"its own, tag the block ```lammps-fragment.\n{out[-3000:]}")
    assert "Total wall time" in out, f"the deck in {where} did not run to its end:\n{out[-3000:]}"
