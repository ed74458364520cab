"""The command index (doc/commands.md): a table of every command page, made from the pages themselves at
build time so it cannot go stale. A command page is doc/{pair,fix,compute,dump}_*.md; each of its level-1
headings "# fix NAME (what it is)" is one row: the command, linked to its heading, and the words in
parentheses, or else the first sentence of the page's Description."""
import glob
import os
import re

PATTERNS = ("pair_*.md", "fix_*.md", "compute_*.md", "dump_*.md")
MARKER = re.compile(r"^```\{command-index\}\s*\n```\s*$", re.M)
_FENCE = re.compile(r"^(`{3,}|~{3,})")


def command_pages(doc_dir):
    """Every command page of the manual, sorted."""
    return sorted({p for pat in PATTERNS for p in glob.glob(os.path.join(doc_dir, pat))})


def _prose(text):
    """The page's lines outside fenced code blocks (a '# comment' in a deck is not a heading)."""
    out, fence = [], None
    for line in text.splitlines():
        m = _FENCE.match(line.strip())
        if m and (fence is None or line.strip().startswith(fence)):
            fence = None if fence else m.group(1)
            continue
        out.append("" if fence else line)
    return out


def _slug(title):
    """MyST's heading anchor (myst_heading_anchors): GitHub style."""
    s = re.sub(r"[^\w\- ]", "", title.strip().lower())
    return s.replace(" ", "-")


def _first_sentence(lines, start):
    para = []
    for line in lines[start:]:
        if line.startswith("#"):
            if para:
                break
            continue
        if not line.strip():
            if para:
                break
            continue
        if line.lstrip().startswith(("<!--", "|", "*", "-", ">")) and not para:
            continue
        para.append(line.strip())
    text = " ".join(para)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links become their words
    m = re.match(r"(.+?[.:;])(\s|$)", text)
    return (m.group(1) if m else text).rstrip(":;.") + "." if text else ""


def entries(path):
    """(command, anchor, one line) for each level-1 heading of one command page."""
    lines = _prose(open(path, encoding="utf-8").read())
    out = []
    for i, line in enumerate(lines):
        if not line.startswith("# "):
            continue
        title = line[2:].strip()
        m = re.match(r"^(.*?)\s*\((.*)\)\s*$", title)
        if m:
            name, what = m.group(1), m.group(2)
        else:
            name, _, what = title.partition(":")
            if not what:
                desc = next((j for j in range(i, len(lines)) if lines[j].strip() == "## Description"), i)
                what = _first_sentence(lines, desc + 1)
        name = re.sub(r"\s+command$", "", name.strip())
        out.append((name.replace("`", ""), _slug(title), what.strip()))
    return out


def table(doc_dir):
    rows = ["| command | what it is |", "|---|---|"]
    for page in command_pages(doc_dir):
        for name, anchor, what in entries(page):
            doc = os.path.basename(page)
            rows.append(f"| [{name}]({doc}#{anchor}) | {what.replace('|', '/')} |")
    return "\n".join(rows) + "\n"


def _fill(app, docname, source):
    if MARKER.search(source[0]):
        source[0] = MARKER.sub(lambda _: table(app.srcdir), source[0])


def _always_reread(app, env, added, changed, removed):
    return [d for d in env.found_docs if d == "commands"]


def setup(app):
    app.connect("source-read", _fill)
    app.connect("env-get-outdated", _always_reread)
    return {"parallel_read_safe": True}
