"""History memory follows the contacts present (issue 15, acceptance C; deck
tests/decks/in.history_memory): a dense phase in which one sphere has ~60 contacts, then dilution.
Before issue 15 every atom's partner storage kept the stride of the busiest atom ever (64 partners x
32 bytes here) and never shrank. Now:
* in the dense phase the contact storage (per-atom pool + list-order slots) costs at most 120 bytes
  per contact (measured 98), independent of the busiest atom;
* after dilution the contact storage is released to at most 1 kB in total (measured 0 bytes), and
  the total held by the fix falls by at least 90 % of the dense contact storage (measured serial
  964 kB -> 322 kB, 2 ranks 1249 kB -> 602 kB; what is left is the per-atom index, sized by the
  owned+ghost atom count like any per-atom property)."""
import os
import re
import subprocess

import pytest

import dembridge

DECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "decks", "in.history_memory")


def phases(tmp_path, nprocs):
    (tmp_path / "in.w").write_text(f"plugin load {dembridge.plugin_path()}\ninclude {DECK}\n")
    cmd = [dembridge.lmp_executable(), "-in", "in.w", "-log", "log", "-screen", "none"]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=tmp_path, check=True, timeout=300)
    out = {}
    for m in re.finditer(r"^(DENSE|DILUTE) bytes (\S+) contacts (\S+) slots (\S+) cbytes (\S+) atoms (\d+)",
                         (tmp_path / "log").read_text(), re.M):
        out[m.group(1)] = dict(bytes=float(m.group(2)), contacts=float(m.group(3)), slots=float(m.group(4)),
                               cbytes=float(m.group(5)), atoms=int(m.group(6)))
    return out["DENSE"], out["DILUTE"]


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_memory_falls_after_dilution(tmp_path, nprocs):
    dense, dilute = phases(tmp_path, nprocs)
    print(f"{nprocs} ranks: dense {dense}, dilute {dilute}, contact bytes per contact {dense['cbytes'] / dense['contacts']:.1f}")
    assert dense["contacts"] > 6000, "the dense phase must have many contacts"
    assert dense["cbytes"] / dense["contacts"] <= 120.0
    assert dilute["contacts"] == 0
    assert dilute["cbytes"] <= 1024.0
    # the total falls by (nearly) the whole contact storage; the per-atom index stays
    assert dense["bytes"] - dilute["bytes"] >= 0.9 * dense["cbytes"]
