#!/usr/bin/env python3
"""Writes the thinned copies history_sampled.csv.gz of the long Parmec recordings (README.md) from the
oracle's own files: the header, every sample k < 1000, then every 10th (k = row index, the initial state
k = 0 included), lines copied unchanged. The rule is RowSample{first 1000, every 10} of
tests/unit/springs/test_oracle_dynamic.cpp, so the replay compares the same rows on either file.

usage: python3 thin_histories.py /work/shared/oracle/parmec
"""
import gzip
import os
import sys

CASES = ["spring", "spring_chain", "spring_contact_plane", "spring_contact_plane_kskn", "fixedQ1Q3/spring_contact_plane"]
FIRST, EVERY = 1000, 10
HERE = os.path.dirname(os.path.abspath(__file__))


def main(oracle):
    for case in CASES:
        with gzip.open(os.path.join(oracle, case, "history.csv.gz"), "rt", newline="") as fh:
            lines = fh.read().splitlines(keepends=True)
        keep = [lines[0]] + [l for k, l in enumerate(lines[1:]) if k < FIRST or k % EVERY == 0]
        out = os.path.join(HERE, case, "history_sampled.csv.gz")
        with open(out, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0, filename="") as gz:
            gz.write("".join(keep).encode())
        print(f"{case}: {len(lines) - 1} -> {len(keep) - 1} rows, {os.path.getsize(out) / 1e6:.2f} MB")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "/work/shared/oracle/parmec")
