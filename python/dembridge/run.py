"""Running a deck with the wheel's ``lmp`` (serial or under MPICH's ``mpiexec``), plugin available.

A LIGGGHTS 2.x or 3.x deck ported to modern LAMMPS runs unchanged (no ``plugin load`` needed):
``lmp`` loads a pip-installed dembridge itself; for a source-tree build the plugin's folder is put
on ``LAMMPS_PLUGIN_PATH``.
"""
import dataclasses
import os
import shutil
import subprocess
import sys
import tempfile
import weakref

from .locate import installed_plugin, lmp_executable, mpiexec, plugin_path
from .outputs import read_thermo


@dataclasses.dataclass
class Run:
    """What :func:`run_deck` did: the command, its exit code, the log file and the captured output."""
    command: list
    returncode: int
    log: str
    stdout: str
    stderr: str

    def thermo(self, run=-1):
        """The thermo table of one run of the deck (default the last) as dict column -> array."""
        return read_thermo(self.log)[run]

    def check(self):
        """Raise RuntimeError with the end of the output if LAMMPS failed; return self."""
        if self.returncode != 0:
            tail = "\n".join((self.stdout + self.stderr).splitlines()[-20:])
            raise RuntimeError(f"{' '.join(self.command)} exited with {self.returncode}:\n{tail}")
        return self


def _plugin_env(env):
    """Put the source-tree plugin's folder on LAMMPS_PLUGIN_PATH unless pip installed it."""
    env = dict(env)
    if installed_plugin():
        return env  # the lammps.plugins entry point adds it
    folder = os.path.dirname(os.path.abspath(plugin_path()))
    paths = [p for p in env.get("LAMMPS_PLUGIN_PATH", "").split(":") if p]
    if folder not in paths:
        env["LAMMPS_PLUGIN_PATH"] = ":".join([folder] + paths)
    return env


def run_deck(deck, nprocs=1, variables=None, cwd=None, log=None, args=(), timeout=None, check=True, env=None,
             stream=False):
    """Run ``deck`` (a file name, or the text of a deck) with ``lmp`` on ``nprocs`` MPI ranks.

    ``variables`` become ``-var NAME VALUE``; ``cwd`` is the working directory (default: the deck's
    folder, or a new temporary folder for deck text); ``log`` the log file (default ``log.lammps`` in
    ``cwd``); ``args`` extra ``lmp`` arguments. Returns a :class:`Run`; with ``check`` a failed run
    raises RuntimeError showing the end of LAMMPS's output. ``stream=True`` prints LAMMPS's output as
    it comes (progress of a long run; stderr merged into ``Run.stdout``). A temporary folder made for
    deck text is removed when the returned :class:`Run` is garbage-collected (at exit at the latest).
    """
    made = None
    if "\n" in deck or not os.path.isfile(deck):
        if not cwd:
            cwd = made = tempfile.mkdtemp(prefix="dembridge-run-")
        path = os.path.join(cwd, "in.deck")
        with open(path, "w") as fh:
            fh.write(deck if deck.endswith("\n") else deck + "\n")
    else:
        path = os.path.abspath(deck)
        cwd = cwd or os.path.dirname(path)
    log = os.path.abspath(os.path.join(cwd, log or "log.lammps"))
    cmd = [lmp_executable(), "-in", path, "-log", log, "-nocite"]
    for k, v in (variables or {}).items():
        cmd += ["-var", str(k), str(v)]
    cmd += list(args)
    if nprocs > 1:
        cmd = [mpiexec(), "-n", str(nprocs)] + cmd
    if stream:
        returncode, out, err = _streamed(cmd, cwd, _plugin_env(env or os.environ), timeout)
    else:
        p = subprocess.run(cmd, cwd=cwd, env=_plugin_env(env or os.environ), capture_output=True, text=True,
                           timeout=timeout)
        returncode, out, err = p.returncode, p.stdout, p.stderr
    r = Run(cmd, returncode, log, out, err)
    if made:
        weakref.finalize(r, shutil.rmtree, made, True)
    return r.check() if check else r


def _streamed(cmd, cwd, env, timeout):
    """Run ``cmd`` printing each output line as it comes; (exit code, output, "")."""
    lines = []
    with subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          bufsize=1) as p:
        try:
            for line in p.stdout:
                sys.stdout.write(line)
                sys.stdout.flush()
                lines.append(line)
            p.wait(timeout=timeout)
        except BaseException:
            p.kill()
            raise
    return p.returncode, "".join(lines), ""
