"""The manual speaks to users: no development-log wording in doc/*.md (issue numbers, acceptance letters,
deliverables, spec section numbers) and no paths outside the repository, and the command index lists every
command page (doc/_ext/command_index.py builds it from the pages)."""
import os
import re
import sys

from doc_blocks import DOC, pages, rel

sys.path.insert(0, os.path.join(DOC, "_ext"))
import command_index  # noqa: E402

FORBIDDEN = {
    "an issue number": re.compile(r"\bissues?\s*#?\d+", re.I),
    "an acceptance point": re.compile(r"\bacceptance\b", re.I),
    "a deliverable": re.compile(r"\bdeliverables?\b", re.I),
    "a spec section number": re.compile(r"§|\bspec\s+[PT]\d+\b", re.I),
    "a path outside the repository": re.compile(r"\.\./shared|/work/|\bshared/(?:spec|seeds|oracle)\b|/home/"),
}


def test_the_manual_has_no_development_log_wording_or_outside_paths():
    bad = []
    for page in pages():
        for n, line in enumerate(open(page, encoding="utf-8"), 1):
            bad += [f"{rel(page)}:{n}: {what}: {line.strip()[:120]}"
                    for what, rx in FORBIDDEN.items() if rx.search(line)]
    assert not bad, ("User pages must not read like a development log or point outside the repository "
                     "(say what the user needs instead):\n" + "\n".join(bad))


def test_the_forbidden_patterns_catch_what_they_name():
    samples = {"an issue number": "fixed in issue 12", "an acceptance point": "(acceptance B)",
               "a deliverable": "deliverable 3", "a spec section number": "spec §4.3",
               "a path outside the repository": "see ../shared/spec/x.md"}
    for what, text in samples.items():
        assert FORBIDDEN[what].search(text), what
    assert not any(rx.search("the issue of rounding; a specific seed") for rx in FORBIDDEN.values())


def test_the_command_index_lists_every_command_page_with_a_line():
    table = command_index.table(DOC)
    pages_ = command_index.command_pages(DOC)
    assert len(pages_) >= 20
    for page in pages_:
        name = os.path.basename(page)
        rows = [r for r in table.splitlines() if f"]({name}#" in r]
        assert rows, f"{name} has no row in the command index (no '# command' heading?)"
        for r in rows:
            assert r.split("|")[2].strip(), f"the index row of {name} has no description: {r}"


# styles the plugin registers for its own use, not for decks
INTERNAL = {("fix", "dembridge/contact/history")}


def registered_styles():
    """(kind, name) of every style the plugin registers (RegisterStyle objects, DEMBRIDGE_PAIR entries)."""
    import glob
    import re
    root = os.path.dirname(DOC)
    reg = re.compile(r'RegisterStyle\s+\w+\s*[({]\s*"(\w+)"\s*,\s*"([^"]+)"')
    pair = re.compile(r'DEMBRIDGE_PAIR\(\s*\w+\s*,\s*"([^"]+)"')
    out = set()
    for src in glob.glob(os.path.join(root, "**", "*.cpp"), recursive=True):
        if os.sep + "build" in src[len(root):] or os.sep + "tests" + os.sep in src[len(root):]:
            continue
        text = open(src, encoding="utf-8", errors="replace").read()
        out |= set(reg.findall(text))
        out |= {("pair", n) for n in pair.findall(text)}
    return out - INTERNAL


def test_every_registered_style_is_documented_on_a_command_page():
    styles = registered_styles()
    assert ("fix", "wall/gran") in styles and ("pair", "gran/hooke") in styles, "the source scan found no styles"
    text = "\n".join(open(p, encoding="utf-8").read() for p in command_index.command_pages(DOC))
    missing = sorted(f"{kind} {name}" for kind, name in styles if name not in text)
    assert not missing, ("registered styles that no command page (doc/{pair,fix,compute,dump}_*.md) names: "
                         + ", ".join(missing))
