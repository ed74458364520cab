"""The fenced code blocks of the docs (doc/**/*.md), with their language tags.

Convention (doc/getting_started.md, "Code blocks in these pages"): every block names its language;
``lammps`` = a complete deck, run by test_docs.py; ``lammps-fragment`` = lines of a deck, not run.
"""
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DOC = os.path.join(ROOT, "doc")
RUNNABLE = "lammps"
# every language a block may be tagged with; anything else is a typo or a new kind of block
KNOWN = {RUNNABLE, "lammps-fragment", "bash", "console", "sh", "python", "pycon", "cpp", "c", "cmake",
         "text", "none", "mbdyn", "json", "csv", "toml", "yaml", "ini", "diff"}
_FENCE = re.compile(r"^(?P<indent> {0,3})(?P<fence>`{3,}|~{3,})(?P<info>.*)$")


def pages():
    """Every Markdown page of the site (doc/, without build output)."""
    out = []
    for d, dirs, files in os.walk(DOC):
        dirs[:] = [x for x in dirs if not x.startswith("_")]
        out += [os.path.join(d, f) for f in files if f.endswith(".md")]
    return sorted(out)


def blocks(path):
    """(line number, language or '' if untagged, body) of each fenced block of one page;
    directives (```{toctree}, ```{eval-rst}, ...) are skipped, except {code-block}/{code} LANG."""
    lines = open(path, encoding="utf-8").read().splitlines()
    out, i = [], 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, info = m.group("fence"), m.group("info").strip()
        j = i + 1
        while j < len(lines) and not (lines[j].strip().startswith(fence) and lines[j].strip().strip(fence[0]) == ""):
            j += 1
        body = "\n".join(lines[i + 1:j]) + "\n"
        lang = info.split()[0] if info else ""
        if lang.startswith("{"):
            directive = lang
            lang = info.split()[1] if len(info.split()) > 1 else ""
            if directive not in ("{code-block}", "{code}", "{sourcecode}"):
                i = j + 1
                continue
            body = "\n".join(l for l in lines[i + 1:j] if not l.startswith(":")) + "\n"
        out.append((i + 1, lang, body))
        i = j + 1
    return out


def rel(path):
    return os.path.relpath(path, ROOT)


def decks():
    """(id 'doc/page.md:LINE', deck text) of every block tagged ``lammps``."""
    return [(f"{rel(p)}:{n}", body) for p in pages() for n, lang, body in blocks(p) if lang == RUNNABLE]


# A ```lammps-fragment block that is not a synopsis (`fix ID group-ID style ...`) says, on the line before its
# fence, how the docs test treats it:
#   <!-- docs-test: deck PROLOGUE -->     the block runs as one deck after the prologue (fragment_decks.py)
#   <!-- docs-test: lines PROLOGUE -->    each command of the block runs on its own after the prologue
#   <!-- docs-test: not run: REASON -->   why it cannot run on its own (on purpose)
_MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(?P<how>deck|lines|not run:)\s*(?P<what>.*?)\s*-->\s*$")


def line_before(lines, n):
    """The last non-blank line before the fence on line n (1-based) of a page: where a docs-test marker goes."""
    return next((lines[k] for k in range(n - 2, -1, -1) if lines[k].strip()), "")


def is_synopsis(body):
    words = body.split()
    return len(words) > 1 and words[1] == "ID"


def fragments():
    """(id 'doc/page.md:LINE', body, marker) of every ```lammps-fragment block that is not a synopsis;
    marker = (how, what) from the docs-test comment before the fence, or None."""
    out = []
    for p in pages():
        lines = open(p, encoding="utf-8").read().splitlines()
        for n, lang, body in blocks(p):
            if lang != "lammps-fragment" or is_synopsis(body):
                continue
            m = _MARKER.match(line_before(lines, n))
            out.append((f"{rel(p)}:{n}", body, (m.group("how").rstrip(":"), m.group("what")) if m else None))
    return out
