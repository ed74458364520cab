"""Regenerates the trimmed copies here from the real-MBDyn 1.7.3 recordings (README.md here).
Usage: python3 trim.py <mbdyn-ext folder>. Values are copied verbatim; only whole messages (loose)
or whole steps (tight: the prediction, every iterate and their answers) are left out."""
import csv
import gzip
import io
import os
import sys

src, here = sys.argv[1], os.path.dirname(os.path.abspath(__file__))


def rows_of(path):
    return list(csv.DictReader(gzip.open(path, "rt")))


def steps(rows):
    """[head rows], [[rows of one exchange group]]: a group starts at a kinematics message that
    follows an answer 6 (the start of an MBDyn step); the start-up exchange is group 0."""
    head, groups, new = [], [], True
    for r in rows:
        if r["cmd"] in ("7", "8"):
            head.append(r)
        elif r["cmd"] == "5":
            groups.append([r])
        else:
            if r["dir"] == "mbdyn->peer" and new:
                groups.append([])
                new = False
            groups[-1].append(r)
            if r["dir"] == "peer->mbdyn" and r["cmd"] == "6":
                new = True
    return head, groups


def trim(name, every, case="refnode_forces", out=None):
    """out: a plain .csv name (read by the C++ unit tests, which have no gzip reader)."""
    head, groups = steps(rows_of(os.path.join(src, case, name)))
    keep = head + [r for i, g in enumerate(groups) if i == 0 or i % every == 0 or g[0]["cmd"] == "5" for r in g]
    if out:
        f = open(os.path.join(here, case, out), "w", newline="")
    else:
        raw = gzip.GzipFile(os.path.join(here, case, name), "wb", compresslevel=9, mtime=0)  # reproducible bytes
        f = io.TextIOWrapper(raw, newline="")
    with f:
        w = csv.DictWriter(f, fieldnames=["seq", "dir", "cmd", "values"], lineterminator="\n")
        w.writeheader()
        w.writerows(keep)


trim("transcript_loose.csv.gz", 4)
trim("transcript_tight.csv.gz", 8)
trim("transcript_loose.csv.gz", 10, "mapping_beam")
trim("transcript_tight.csv.gz", 20, "mapping_beam")
trim("transcript_loose.csv.gz", 10, "modal_body", "transcript_loose.csv")
trim("transcript_tight.csv.gz", 20, "modal_body", "transcript_tight.csv")


def first_steps(name, count, out, case="refnode_forces", startup=True):
    """The negotiation, the start-up exchange (if the run has one) and the first `count` MBDyn
    steps whole (every message both ways), then MBDyn's final 5: a shorter run a peer can replay
    step by step."""
    head, groups = steps(rows_of(os.path.join(src, case, name)))
    keep = head + [r for g in groups[:count + (1 if startup else 0)] for r in g] + groups[-1]
    raw = gzip.GzipFile(os.path.join(here, case, out), "wb", compresslevel=9, mtime=0)
    with io.TextIOWrapper(raw, newline="") as f:
        w = csv.DictWriter(f, fieldnames=["seq", "dir", "cmd", "values"], lineterminator="\n")
        w.writeheader()
        w.writerows(keep)


first_steps("transcript_tight.csv.gz", 50, "transcript_tight_first50.csv.gz")
first_steps("transcript_tight.csv.gz", 100, "transcript_tight_first100.csv.gz", "modal_body", startup=False)
first_steps("transcript_tight.csv.gz", 100, "transcript_tight_first100.csv.gz", "mapping_beam")
