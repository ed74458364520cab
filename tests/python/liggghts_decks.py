"""Runs a deck of tests/data/liggghts_decks three ways, each in its own copy of the folder: the real
LIGGGHTS 3.8 (/usr/bin/liggghts, live), and dembridge-liggghts serial and on 2 MPI ranks. Shared by
the launcher tests."""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from dembridge import mpiexec

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "oracle"))
from oracle_harness import liggghts_env, liggghts_exe  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "tests" / "data" / "liggghts_decks"
LAUNCHER = [sys.executable, "-m", "dembridge.liggghts"]
# What LAMMPS prints when the plugin loads; LIGGGHTS has no plugins, so these are no LIGGGHTS warnings.
PLUGIN_LOAD_WARNING = re.compile(r"^WARNING: Overriding built-in \w+ style \S+ from plugin")


def copy_deck(deck, where):
    """A fresh copy of the deck, its included files and meshes in `where` (with an empty post/)."""
    where = Path(where)
    if where.exists():
        shutil.rmtree(where)
    where.mkdir(parents=True)
    shutil.copytree(DECKS / "meshes", where / "meshes")
    for f in DECKS.iterdir():
        if f.is_file() and (f.name == deck or f.name.startswith("inc.")):
            shutil.copyfile(f, where / f.name)
    (where / "post").mkdir()
    return where


def run(cmd, cwd, timeout=300, stdin=None, env=None):
    """(returncode, stdout+stderr) of cmd in cwd."""
    with open(stdin) if stdin else open(os.devnull) as fh:
        p = subprocess.run(cmd, cwd=cwd, stdin=fh, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=timeout, env=env)
    return p.returncode, p.stdout


def run_liggghts(deck, where):
    # stdbuf: an error->one message is lost otherwise (MPI_Abort before the buffer is flushed)
    return run(["stdbuf", "-o0", str(liggghts_exe()), "-in", deck], copy_deck(deck, where), env=liggghts_env())


def launcher_env():
    return dict(os.environ, PYTHONPATH=str(ROOT / "python"))


def run_launcher(deck, where, nprocs=1, args=()):
    cmd = LAUNCHER + ["-in", deck] + list(args)
    if nprocs > 1:
        cmd = [mpiexec(), "-n", str(nprocs)] + cmd
    return run(cmd, copy_deck(deck, where), env=launcher_env())


def errors(text):
    return [ln for ln in text.splitlines() if ln.startswith("ERROR") or "ERROR on proc" in ln]


def warnings(text):
    """The WARNING lines without their source location ' (file.cpp:123)', plugin-load notices left out."""
    out = set()
    for ln in text.splitlines():
        if ln.startswith("WARNING") and not PLUGIN_LOAD_WARNING.match(ln):
            out.add(re.sub(r" \([^()]*:\d+\)\s*$", "", ln).strip())
    return out
