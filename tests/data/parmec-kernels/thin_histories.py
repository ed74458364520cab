#!/usr/bin/env python3
"""Writes the thinned copies of the long Parmec recordings (README.md) from the oracle's own files, lines
copied unchanged (k = row index = step number of the row, the initial state k = 0 included):

- history_sampled.csv.gz of the five full recordings (history.csv.gz): the header, every sample k < 1000,
  then every 10th. The rule is RowSample{first 1000, every 10} of tests/unit/springs/test_oracle_dynamic.cpp,
  so the replay compares the same rows on either file.
- history_thinned.csv.gz of spring_stroke_offset and unspring, from the oracle's history_thinned.csv.gz
  (already every step for k <= 2000 and in its event windows, every 10th elsewhere, oracle README): the
  header, k <= 2000, every row of the event windows (the offset ramp's kinks t = 5 s, 10 s +- 0.05 s; the
  UNSPRING trigger step +- 500), then every 100th. The windows are given here and checked against the
  oracle's own dense runs (so no event row is lost); test_oracle_dynamic.cpp's RowSample for
  spring_stroke_offset uses the same rule.

usage: python3 thin_histories.py /work/shared/oracle/parmec
"""
import gzip
import json
import os
import sys

CASES = ["spring", "spring_chain", "spring_contact_plane", "spring_contact_plane_kskn", "fixedQ1Q3/spring_contact_plane"]
FIRST, EVERY = 1000, 10
# event-thinned recordings: (first dense rows k <= DENSE, every EVENT_EVERY-th row, windows)
DENSE, EVENT_EVERY = 2000, 100
WINDOWS = {"spring_stroke_offset": {"time": [(4.95, 5.05), (9.95, 10.05)]},  # ramp kinks of offset_tseries
           "unspring": {"step": [(36809 - 500, 36809 + 499)]}}  # spr16..19 SS -2 -> -1 at step 36809
HERE = os.path.dirname(os.path.abspath(__file__))


def write(out, lines):
    with open(out, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0, filename="") as gz:
        gz.write("".join(lines).encode())


def read(path):
    with gzip.open(path, "rt", newline="") as fh:
        return fh.read().splitlines(keepends=True)


def sampled(oracle):
    for case in CASES:
        lines = read(os.path.join(oracle, case, "history.csv.gz"))
        keep = [lines[0]] + [l for k, l in enumerate(lines[1:]) if k < FIRST or k % EVERY == 0]
        out = os.path.join(HERE, case, "history_sampled.csv.gz")
        write(out, keep)
        print(f"{case}: {len(lines) - 1} -> {len(keep) - 1} rows, {os.path.getsize(out) / 1e6:.2f} MB")


def in_window(case, k, t):
    w = WINDOWS[case]
    return any(a <= t <= b for a, b in w.get("time", [])) or any(a <= k <= b for a, b in w.get("step", []))


def event_thinned(oracle):
    for case in WINDOWS:
        step = json.load(open(os.path.join(oracle, case, "meta.json")))["step"]
        lines = read(os.path.join(oracle, case, "history_thinned.csv.gz"))
        rows = [(round(float(l.split(",", 1)[0]) / step), float(l.split(",", 1)[0]), l) for l in lines[1:]]
        present = {k for k, _, _ in rows}
        dense = {k for k in present if k - 1 in present or k + 1 in present}
        keep = [l for k, t, l in rows if k <= DENSE or in_window(case, k, t) or k % EVENT_EVERY == 0]
        kept = {k for k, t, _ in rows if k <= DENSE or in_window(case, k, t)}
        assert dense <= kept, f"{case}: oracle rows kept every step outside the windows: {sorted(dense - kept)[:5]}"
        out = os.path.join(HERE, case, "history_thinned.csv.gz")
        write(out, [lines[0]] + keep)
        print(f"{case}: {len(rows)} -> {len(keep)} rows, {os.path.getsize(out) / 1e6:.2f} MB")


if __name__ == "__main__":
    src = sys.argv[1] if len(sys.argv) > 1 else "/work/shared/oracle/parmec"
    sampled(src)
    event_thinned(src)
