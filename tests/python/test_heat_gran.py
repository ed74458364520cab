"""fix heat/gran, LIGGGHTS's fix property/atom and fix check/timestep/gran: closed forms (two spheres
in contact reach their mean temperature; a heat source adds Q t) and LIGGGHTS 3.8 run live on
tests/data/liggghts-heat (Temp, heatFlux, the thermal energy and the time-step fractions to 1e-12)."""
import math
import re
import sys
from pathlib import Path

import pytest

from dembridge import new_lammps
from dembridge.liggghts_deck import translate_text

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "oracle"))
import oracle_harness as oh  # noqa: E402

from dembridge import thermo_rows  # noqa: E402

CASE = ROOT / "tests" / "data" / "liggghts-heat"
GAS = ROOT / "tests" / "data" / "liggghts" / "gas200_periodic"  # its data.txt
R, D = 0.005, 0.0098           # two spheres of radius R at distance D (overlapping)
K, C, RHO = 50.0, 2.0, 2500.0   # conductivity, capacity (small: a quick exchange), density
DT = 1e-4


def two_spheres(extra=(), ntypes=1):
    lmp = new_lammps()
    for c in ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off",
              "comm_modify vel yes", "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", f"create_box {ntypes} box",
              f"create_atoms 1 single {-D / 2} 0 0 units box", f"create_atoms 1 single {D / 2} 0 0 units box",
              f"set group all diameter {2 * R} density {RHO}",
              "fix m1 all property/global youngsModulus peratomtype 5.e7",
              "fix m2 all property/global poissonsRatio peratomtype 0.3",
              "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
              "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
              "pair_style gran model hertz tangential history", "pair_coeff * *", f"timestep {DT}",
              f"fix k all property/global thermalConductivity peratomtype {K}",
              f"fix c all property/global thermalCapacity peratomtype {C}",
              "fix ht all heat/gran initial_temperature 300.",
              "set atom 2 d_Temp 500.",
              "thermo_style custom step f_ht"]:
        lmp.command(c)
    for c in extra:
        lmp.command(c)
    return lmp


def temperatures(lmp):
    """(T of atom 1, T of atom 2) from the per-atom output of fix Temp."""
    n = lmp.extract_global("nlocal")
    ids = lmp.numpy.extract_atom("id")[:n]
    T = lmp.numpy.extract_fix("Temp", 1, 1)[:n]
    by_id = dict(zip(ids.tolist(), T.tolist()))
    return by_id[1], by_id[2]


def test_two_spheres_reach_their_mean_temperature():
    """No integrator: the spheres stay put, the overlap is fixed. Explicit Euler on
    dT1 = h (T2 - T1) dt / (m c), dT2 = -h (T2 - T1) dt / (m c): the mean stays, the difference
    shrinks by (1 - 2 h dt / (m c)) per step; h = 2 K sqrt(A), A = pi (R^2 - (D/2)^2)."""
    lmp = two_spheres()
    m = 4.0 / 3.0 * math.pi * R ** 3 * RHO
    h = 2 * K * math.sqrt(math.pi * (R * R - D * D / 4))
    g = 1 - 2 * h * DT / (m * C)
    lmp.command("run 100")
    T1, T2 = temperatures(lmp)
    assert abs((T1 + T2) / 2 - 400.0) <= 1e-12 * 400.0
    expect = 200.0 * g ** 100
    assert abs((T2 - T1) - expect) <= 1e-12 * 200.0, (T2 - T1, expect)
    # the continuous solution exp(-2 h t / (m c)): the explicit step is first order, n (1 - g)^2 / 2 ~ 1 %
    exact = 200.0 * math.exp(-2 * h * 100 * DT / (m * C))
    assert abs((T2 - T1) - exact) < 100 * (1 - g) ** 2 * exact
    lmp.command(f"run {int(40 / (1 - g))}")  # 200 g^n < 1e-12 * 400
    T1, T2 = temperatures(lmp)
    assert abs(T1 - 400.0) <= 1e-12 * 400.0 and abs(T2 - 400.0) <= 1e-12 * 400.0, (T1, T2)
    lmp.close()


def test_heat_source_adds_q_times_t_to_the_thermal_energy():
    lmp = two_spheres(["set atom 1 d_heatSource 3.0"])
    lmp.command("run 0")
    lmp.command("variable E equal f_ht")
    e0 = lmp.extract_variable("E")
    m = 4.0 / 3.0 * math.pi * R ** 3 * RHO
    assert abs(e0 - C * m * 800.0) <= 1e-12 * e0
    lmp.command("run 500")
    e1 = lmp.extract_variable("E")
    assert abs((e1 - e0) - 3.0 * 500 * DT) <= 1e-12 * e1
    lmp.close()


def lammps_deck(deck):
    """The deck as dembridge-liggghts runs it (its translation: atom_style, communicate, dump_modify format,
    set ... property/atom NAME -> d_NAME), after a plugin load line."""
    return f"plugin load {oh.plugin_path()}\n" + translate_text(deck, "in.liggghts", notes=False).text


def read_frames(path):
    frames, step, rows = {}, None, None
    lines = Path(path).read_text().splitlines()
    for k, line in enumerate(lines):
        if line.startswith("ITEM: TIMESTEP"):
            step = int(lines[k + 1])
        elif line.startswith("ITEM: ATOMS"):
            rows = frames.setdefault(step, {})
        elif rows is not None and line and line[0].isdigit() and " " in line:
            w = line.split()
            if len(w) == 7:
                rows[int(w[0])] = [float(x) for x in w[2:]]
    return frames


def close(a, b, scale, rtol=1e-12):
    return abs(a - b) <= rtol * scale


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.two_cores)])
def test_heat_deck_against_liggghts(tmp_path, nprocs):
    if not Path(oh.liggghts_exe()).is_file():
        pytest.fail("LIGGGHTS 3.8 (/usr/bin/liggghts) is missing: the Debian package 'liggghts' is a test requirement")
    deck = (CASE / "in.liggghts").read_text()
    ref = oh.run_liggghts(GAS, tmp_path / "liggghts", deck_text=deck)
    got = oh.run_lammps(lammps_deck(deck), tmp_path / "lammps", nprocs=nprocs, files=[GAS / "data.txt"])
    fr, fg = read_frames(ref), read_frames(got)
    assert sorted(fr) == sorted(fg) == list(range(0, 2001, 250))
    hot, worst = 0, 0.0
    for step in fr:
        assert sorted(fr[step]) == sorted(fg[step]) == list(range(1, 201))
        qscale = max(abs(r[4]) for r in fr[step].values()) or 1.0
        for i, r in fr[step].items():
            g = fg[step][i]
            assert close(r[3], g[3], abs(r[3])), (step, i, "Temp", r[3], g[3])
            assert close(r[4], g[4], qscale), (step, i, "heatFlux", r[4], g[4])
            hot += r[3] not in (800.0, 300.1235)
            worst = max(worst, abs(r[3] - g[3]) / abs(r[3]))
    print(f"largest relative Temp difference {worst:.3g} over {hot} particle-frames away from 800 / 300.1235")
    assert hot > 40  # heat did flow (a sparse gas: few contacts at a time)
    # thermo: thermal energy and the three fractions
    lr = [r for r in thermo_rows(tmp_path / "liggghts" / "log.liggghts") if len(r) == 7]
    lg = [r for r in thermo_rows(tmp_path / "lammps" / "log.lammps") if len(r) == 7]
    lr, lg = lr[-9:], lg[-9:]
    assert [r[0] for r in lr] == [r[0] for r in lg]
    for a, b in zip(lr, lg):
        for col in (3, 4, 5, 6):
            x, y = a[col], b[col]
            assert close(x, y, abs(x)), (a[0], col, x, y)
    # the same warnings, same text, as many times
    warn = lambda p: re.findall(r"WARNING: (time-step is .*?) \(", Path(p).read_text())
    assert warn(tmp_path / "liggghts" / "log.screen") == warn(tmp_path / "lammps" / "screen.lammps")
    assert len(warn(tmp_path / "lammps" / "screen.lammps")) == 8


def test_dense_lattice_deck_against_liggghts(tmp_path):
    """6^3 spheres with 6 contacts each, two types: every particle's Temp and heatFlux every 100 steps."""
    deck = (CASE / "in.lattice").read_text()
    (tmp_path / "case").mkdir()
    ref = oh.run_liggghts(tmp_path / "case", tmp_path / "liggghts", deck_text=deck)
    got = oh.run_lammps(lammps_deck(deck), tmp_path / "lammps")
    fr, fg = read_frames(ref), read_frames(got)
    assert sorted(fr) == sorted(fg) == list(range(0, 501, 100))
    for step in fr:
        assert sorted(fr[step]) == sorted(fg[step]) == list(range(1, 217))
        qscale = max(abs(r[4]) for r in fr[step].values()) or 1.0
        for i, r in fr[step].items():
            g = fg[step][i]
            assert r[:3] == g[:3], (step, i, "position", r[:3], g[:3])
            assert close(r[3], g[3], abs(r[3])), (step, i, "Temp", r[3], g[3])
            assert close(r[4], g[4], qscale), (step, i, "heatFlux", r[4], g[4])
    assert sum(r[3] not in (300.0, 600.0) for r in fr[500].values()) > 100  # heat flowed through the lattice
