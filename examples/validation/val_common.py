"""Shared helpers of the dembridge validation benchmarks (doc/validation.md).

Every benchmark builds a small LAMMPS deck with the dembridge plugin loaded in-process
(`dembridge.new_lammps`), records the state of the moving particle every few steps with `fix print`
and compares the record with closed forms computed here from the same inputs.

Output folder: $DEMBRIDGE_VALIDATION_OUT, default examples/validation/out (git-ignored). Each run
writes its deck (`*.lmp`), its raw record (`*.txt`) and a plot (`*.png`) there.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))

import numpy as np  # noqa: E402

G = 9.81
# The "rigid plane" of Chung & Ooi tests 2-4 and the flat surface of Ai et al.: a frozen sphere this
# many times larger than the particle (R* = R/(1 + 1/ratio)), see doc/validation.md.
WALL_RATIO = 1.0e4


def out_dir():
    d = os.environ.get("DEMBRIDGE_VALIDATION_OUT", os.path.join(HERE, "out"))
    os.makedirs(d, exist_ok=True)
    return d


def out_path(name):
    return os.path.join(out_dir(), name)


def pyplot():
    from dembridge.plotting import pyplot as _pyplot  # shared by the examples
    return _pyplot()


# ---------------------------------------------------------------------------------------------
# closed forms (spec granular-models §4, §5; validation-benchmarks §4.1)

def mass(rho, R):
    return rho * 4.0 / 3.0 * math.pi * R**3


def e_star(E1, nu1, E2, nu2):
    return 1.0 / ((1 - nu1**2) / E1 + (1 - nu2**2) / E2)


def hertz_force(Es, Rs, delta):
    return 4.0 / 3.0 * Es * math.sqrt(Rs) * np.power(np.maximum(delta, 0.0), 1.5)


def hertz_impact(Es, Rs, ms, V):
    """Elastic Hertz impact at relative normal speed V: (alpha_max, P_max, t_c).
    alpha_max from (1/2) m* V^2 = (8/15) E* sqrt(R*) alpha^(5/2); t_c = 2 ∫ dα/v =
    (4/5) B(2/5, 1/2) alpha_max / V (exact, = 2.9432 alpha_max/V)."""
    amax = (15.0 * ms * V**2 / (16.0 * Es * math.sqrt(Rs))) ** 0.4
    pmax = 4.0 / 3.0 * Es * math.sqrt(Rs) * amax**1.5
    beta = math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
    tc = 0.8 * beta * amax / V
    return amax, pmax, tc


def rel(measured, closed):
    return (measured - closed) / closed


# ---------------------------------------------------------------------------------------------
# running decks

def run_deck(lines, name):
    """Runs the deck lines in a fresh in-process LAMMPS with the plugin; writes them to out/<name>.lmp
    (runnable with `lmp -in` after a `plugin load` line) and returns the instance (caller closes)."""
    from dembridge import new_lammps, plugin_path
    with open(out_path(name + ".lmp"), "w") as f:
        f.write(f"plugin load {plugin_path()}\n")
        f.write("\n".join(lines) + "\n")
    lmp = new_lammps()
    for line in lines:
        lmp.command(line)
    return lmp


def print_fix(every, path, quantities):
    """A fix print line recording the given LAMMPS expressions with 17 digits."""
    fields = " ".join(f"$({q}:%.17g)" for q in quantities)
    return f'fix rec all print {every} "{fields}" file {path} screen no'


def read_record(path):
    return np.loadtxt(path, comments="#", ndmin=2)


def material_lines(types, friction, restitution, extra=()):
    """fix property/global lines: types = [(E, nu), ...] per atom type; friction and restitution are
    scalars used for every type pair."""
    n = len(types)
    E = " ".join(f"{t[0]!r}" for t in types)
    nu = " ".join(f"{t[1]!r}" for t in types)
    mu = " ".join([f"{friction!r}"] * (n * n))
    e = " ".join([f"{restitution!r}"] * (n * n))
    return [
        f"fix m1 all property/global youngsModulus peratomtype {E}",
        f"fix m2 all property/global poissonsRatio peratomtype {nu}",
        f"fix m3 all property/global coefficientRestitution peratomtypepair {n} {e}",
        f"fix m4 all property/global coefficientFriction peratomtypepair {n} {mu}",
        *extra,
    ]


def header(box):
    return [
        "units si",
        "atom_style sphere",
        "atom_modify map array",
        "boundary f f f",
        "newton off",
        "comm_modify vel yes",
        f"region box block {-box} {box} {-box} {box} {-box} {box} units box",
    ]


def contact_interval(t, delta):
    """(t_start, t_end, i_start, i_end) of the first contact, with the δ = 0 crossings interpolated
    linearly between samples."""
    on = np.nonzero(delta > 0)[0]
    i0 = on[0]
    gaps = np.nonzero(np.diff(on) > 1)[0]
    i1 = on[gaps[0]] if len(gaps) else on[-1]
    if i1 + 1 >= len(t):
        raise RuntimeError("the contact did not end within the run")

    def cross(a, b):
        return t[a] + (t[b] - t[a]) * (0 - delta[a]) / (delta[b] - delta[a])
    return cross(i0 - 1, i0), cross(i1, i1 + 1), i0, i1
