"""The commands the example READMEs tell a user to type (```bash blocks of examples/*/README.md, and the
blocks of the top README.md that go into examples/), with the docs-test marker on the line before each
fence saying how the tests run them:

  <!-- docs-test: run | short FILE ARGS | writes PATH... -->
      test_example_readmes.py runs the block as written with bash, from the top of a scratch copy of the
      source tree; `short` inserts ARGS (options the README documents) after the word ending in FILE,
      to make a long run short; `writes` names the files (relative to the example folder) it must write.
  <!-- docs-test: run by tests/python/test_x.py::test_name -->
      another test runs the same command (no second run here): that test must exist and name the example.
"""
import os
import re

from doc_blocks import ROOT, blocks, line_before, rel

_MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(?P<what>run\b.*?)\s*-->\s*$")
_BY = re.compile(r"^run by (?P<file>tests/\S+\.py)::(?P<test>\w+)$")


def readmes():
    ex = os.path.join(ROOT, "examples")
    return [os.path.join(ROOT, "README.md")] + sorted(
        os.path.join(ex, d, "README.md") for d in os.listdir(ex) if os.path.isfile(os.path.join(ex, d, "README.md")))


def example_of(path, body):
    """The example folder a block belongs to: its README's folder, or for the top README the one its commands
    (not their comments) name."""
    if os.path.dirname(path) != ROOT:
        return os.path.basename(os.path.dirname(path))
    m = re.search(r"examples/(\w+)", "\n".join(line.split(" #")[0] for line in body.splitlines()))
    return m.group(1) if m else None


def commands():
    """(id 'README:LINE', example folder, body, marker text or None) of every command block."""
    out = []
    for path in readmes():
        lines = open(path, encoding="utf-8").read().splitlines()
        for n, lang, body in blocks(path):
            example = example_of(path, body)
            if lang not in ("bash", "sh", "console") or example is None:
                continue
            m = _MARKER.match(line_before(lines, n))
            out.append((f"{rel(path)}:{n}", example, body, m.group("what") if m else None))
    return out


def parse(what):
    """A marker's text -> ('by', file, test) or ('run', [(FILE, ARGS)], [PATH...])."""
    by = _BY.match(what)
    if by:
        return "by", by.group("file"), by.group("test")
    parts = [p.strip() for p in what.split("|")]
    if parts[0] != "run":
        raise ValueError(f"a docs-test marker starts with 'run' or 'run by FILE::TEST', not {what!r}")
    short, writes = [], []
    for p in parts[1:]:
        key, _, rest = p.partition(" ")
        if key == "short":
            word, _, args = rest.partition(" ")
            short.append((word, args))
        elif key == "writes":
            writes += rest.split()
        else:
            raise ValueError(f"unknown part {p!r} of the docs-test marker {what!r} (short, writes)")
    return "run", short, writes


def shortened(body, short):
    """The block with each `short` FILE's ARGS inserted after the first word ending in FILE on every line."""
    out = body
    for word, args in short:
        pat = re.compile(r"(\S*" + re.escape(word) + r")(?=\s|$)")
        new = "\n".join(pat.sub(lambda m: m.group(1) + " " + args, line, count=1) for line in out.splitlines())
        if new == out:
            raise ValueError(f"short {word!r}: no word ends in it in\n{body}")
        out = new + "\n"
    return out
