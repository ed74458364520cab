"""Regenerates this folder from the real-MBDyn 1.7.3 recording refnode_forces/ (README.md here):
every 5th converged kinematics message of the tight run (the message the peer answered 6, step 0
being the start-up exchange) with its values verbatim, and the tight run's .mov rows of the same
steps verbatim. Usage: python3 trim.py <refnode_forces folder>"""
import csv
import gzip
import os
import sys

src, here, every = sys.argv[1], os.path.dirname(os.path.abspath(__file__)), 5
rows = list(csv.DictReader(gzip.open(os.path.join(src, "transcript_tight.csv.gz"), "rt")))
negotiation = next(r for r in rows if r["cmd"] == "7")
converged = [r for i, r in enumerate(rows[:-1])
             if r["dir"] == "mbdyn->peer" and r["cmd"] in ("2", "6") and rows[i + 1]["cmd"] == "6"]
mov = [l for l in gzip.open(os.path.join(src, "tight.mov.gz"), "rt") if l.strip()]
with open(os.path.join(here, "tight_converged.csv"), "w") as f:
    f.write(f"# negotiation {negotiation['values']}\nstep,cmd,values\n")
    for step in range(0, len(converged), every):
        f.write(f"{step},{converged[step]['cmd']},{converged[step]['values']}\n")
with open(os.path.join(here, "tight_steps.mov"), "w") as f:
    for step in range(0, len(converged), every):
        f.write("".join(mov[4 * step:4 * step + 4]))
