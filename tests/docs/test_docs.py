"""The documentation site (issue 14, deliverable 4, acceptance C).

* every fenced block in doc/**/*.md names its language (so a deck cannot hide as an untagged block);
* the Sphinx + MyST build of doc/ has zero warnings (``-W``), pages found automatically;
* every block tagged ``lammps`` runs as a deck with the plugin (lmp, serial) and exits 0;
* every ``lammps-fragment`` block that is not a synopsis runs after a small prologue (as one deck, or each
  command on its own) or says on purpose why it cannot (doc_blocks.fragments, fragment_decks.py).
"""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
import dembridge  # noqa: E402
from doc_blocks import DOC, KNOWN, ROOT, blocks, decks, fragments, pages, rel  # noqa: E402
import fragment_decks  # noqa: E402

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


def test_sphinx_builds_the_site_without_warnings(built_site):
    out, p = built_site
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


FRAGMENTS = fragments()
HOW_TO_MARK = ("Put one of these on the line before the ```lammps-fragment fence: <!-- docs-test: deck PROLOGUE --> "
               "(the block runs after the prologue), <!-- docs-test: lines PROLOGUE --> (each command runs on its own "
               f"after it), <!-- docs-test: not run: WHY -->. Prologues: {sorted(fragment_decks.PROLOGUES)} "
               "(tests/docs/fragment_decks.py). A synopsis (`fix ID group-ID ...`) needs nothing.")


def test_every_fragment_runs_or_says_why():
    bad = [f"{where}: {'no docs-test comment' if m is None else m}" for where, _, m in FRAGMENTS
           if m is None or (m[0] == "not run" and not m[1]) or (m[0] != "not run" and m[1] not in fragment_decks.PROLOGUES)]
    assert not bad, HOW_TO_MARK + "\n" + "\n".join(bad)


FRAGMENT_RUNS = [(f"{where}:{label}", where, deck) for where, body, m in FRAGMENTS if m and m[0] != "not run"
                 for label, deck in fragment_decks.decks(m[0], m[1], body)]


def test_fragments_run_somewhere():
    assert len({w for _, w, _ in FRAGMENT_RUNS}) >= 6


@pytest.mark.parametrize("name,where,deck", FRAGMENT_RUNS, ids=[n for n, _, _ in FRAGMENT_RUNS])
def test_documented_fragment_runs(name, where, deck, tmp_path):
    fragment_decks.prepare(str(tmp_path), deck)
    run = dembridge.run_deck(deck, cwd=str(tmp_path), timeout=120, check=False)
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "ERROR" not in out and "Total wall time" in out, (
        f"the fragment in {where} ({name}) fails after its prologue (tests/docs/fragment_decks.py); fix it or "
        f"mark it <!-- docs-test: not run: WHY -->.\n{out[-3000:]}")
    runs = int(name.rsplit("lines:", 1)[1]) if "lines:" in name else 1
    assert out.count("Loop time of") == runs, f"{where}: {out.count('Loop time of')} of {runs} runs ended"
