"""Thermo rows of a LAMMPS log: every line between a 'Step ...' header and 'Loop time', split into
words (warnings skipped), for tests comparing runs printed with the same thermo format."""
import re


def thermo_rows(log):
    rows, on = [], False
    for line in open(log):
        if re.match(r"^\s*Step\s", line):
            on = True
            continue
        if on and line.startswith("Loop time"):
            on = False
        if on and line.strip() and not line.startswith("WARNING"):
            rows.append(line.split())
    return rows
