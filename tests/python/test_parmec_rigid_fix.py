"""fix parmec/rigid as a LAMMPS deck (issue 13 acceptance B): a chain of 1000 bodies tied by BALL_JOINTs
(one cluster spanning every rank), drifting and spinning under gravity, gives bitwise the same atoms and
joint reactions on 1, 2 and 4 ranks over 1000 steps, and a write_restart/read_restart split equals the
continuous run bitwise. Also: joint constraints hold (drift of the joint points small and O(h))."""
import math

import pytest

from dembridge.outputs import read_dump_by_id as read_dump
from lmp_runs import run_lmp

N = 1000


def chain_positions():
    return [(1.0 * i, 0.3 * math.sin(0.7 * i), 0.2 * math.cos(0.3 * i)) for i in range(N)]


def deck(tmp, steps, write_at=None, read=None, h=1e-3, out="atoms.dump"):
    pos = chain_positions()
    defs = ["gravity 0 0 -10"]
    for i in range(N - 1):
        mid = [(a + b) / 2 for a, b in zip(pos[i], pos[i + 1])]
        defs.append(f"joint {i} {i + 2} {mid[0]!r} {mid[1]!r} {mid[2]!r} {i + 1}")
    defs.append(f"joint_output {tmp}/joints.csv")
    (tmp / "chain.def").write_text("\n".join(defs) + "\n")
    fix = [f"fix R all parmec/rigid file {tmp}/chain.def"]
    post = [f"timestep {h!r}", f"dump A all custom {steps} {tmp}/{out} id x y z vx vy vz omegax omegay omegaz "
            + " ".join(f"f_R[{k}]" for k in range(1, 10)), "dump_modify A sort id format float %.17g", f"run {steps}"]
    if write_at:
        post.append(f"write_restart {write_at}")
    head = ["units si", "atom_modify map array", "comm_modify vel yes cutoff 3.0"]
    if read:
        return head + [f"read_restart {read}", "atom_modify sort 50 1.0"] + fix + post
    data = [f"chain\n\n{N} atoms\n1 atom types\n-5 {N + 5} xlo xhi\n-30 30 ylo yhi\n-60 10 zlo zhi\n",
            "Atoms # bpm/sphere\n"]
    data += [f"{i + 1} 0 1 0.8 1000 {p[0]!r} {p[1]!r} {p[2]!r}" for i, p in enumerate(pos)]
    (tmp / "chain.data").write_text("\n".join(data) + "\n")
    return head + ["atom_style bpm/sphere", "boundary f f f", f"read_data {tmp}/chain.data",
                   "atom_modify sort 50 1.0",
                   "variable wx atom 2*sin(id*0.37)", "variable wy atom 2*cos(id*0.53)", "variable wz atom sin(id*1.7)",
                   "set group all omega v_wx v_wy v_wz", "variable vy atom 0.3*sin(id*0.11)",
                   "velocity all set 3.0 v_vy 0.0 units box"] + fix + post


def joint_drift(atoms):
    """max distance between the joint point as carried by body i and by body i+1 (rotation Λ dumped by the fix,
    row-major; the bodies start with Λ = I, so the reference arm is the body-frame arm)."""
    pos = chain_positions()
    worst = 0.0
    for i in range(N - 1):
        mid = [(a + b) / 2 for a, b in zip(pos[i], pos[i + 1])]
        pts = []
        for k in (i, i + 1):
            x, L = atoms[k + 1][0:3], atoms[k + 1][9:18]
            R = [L[0:3], L[3:6], L[6:9]]
            arm = [mid[j] - pos[k][j] for j in range(3)]
            pts.append([x[r] + sum(R[r][j] * arm[j] for j in range(3)) for r in range(3)])
        worst = max(worst, math.dist(*pts))
    return worst


@pytest.mark.two_cores
def test_joint_chain_1000_bodies_rank_invariant_and_restart(tmp_path):
    steps = 1000
    res = {}
    for np_ in (1, 2, 4):
        d = tmp_path / f"np{np_}"
        d.mkdir()
        run_lmp(d, deck(d, steps), np_)
        res[np_] = (read_dump(d / "atoms.dump")[steps], (d / "joints.csv").read_text())
    atoms1, joints1 = res[1]
    assert len(atoms1) == N
    # the chain moved across the box (3 m in x: every atom changed rank) and the joints held
    assert min(a[0] for a in atoms1.values()) > 2.5
    drift = joint_drift(atoms1)
    assert drift < 5e-3, drift  # no position correction (as Parmec): joint points drift slowly
    for np_ in (2, 4):
        atoms, joints = res[np_]
        assert atoms == atoms1, f"{np_} ranks differ from 1 rank"
        assert joints == joints1, f"{np_} ranks: joint reactions differ"
    # restart: 500 steps + write_restart, then read_restart + 500 steps (2 ranks) vs 1000 continuous
    d = tmp_path / "split"
    d.mkdir()
    run_lmp(d, deck(d, steps // 2, write_at=f"{d}/half.restart", out="first.dump"), 2, "in.first")
    run_lmp(d, deck(d, steps // 2, read=f"{d}/half.restart", out="second.dump"), 2, "in.second")
    second = read_dump(d / "second.dump")[steps]
    assert second == res[2][0]
    print(f"[agreement] 1000-body joint chain, 1000 steps: 1/2/4 ranks and restart bitwise equal; "
          f"joint point drift {drift:.3g}")


BAD_DECKS = [
    ("bogus 1", "unknown keyword 'bogus'"),
    ("restrain 1 linear 1 0", "restrain 1 linear: expected 3, 6 or 9 numbers"),
    ("restrain 0 linear 1 0 0", "restrain: expected an atom ID"),
    ("restrain 1 linear 1 0 0 restrain 1 angular 1 0 0", "atom 1 restrained twice"),
    ("prescribe 1 linear x 0 0 0", "expected kind 'v' (velocity) or 'a' (acceleration)"),
    ("prescribe 1", "expected 'linear' and/or 'angular'"),
    ("prescribe 1 linear v 0 0 S", "'S' is neither a number, a v_name variable nor the ID of a 'tseries'"),
    ("prescribe 1 linear v v_nope 0 0", "variable 'nope' does not exist"),
    ("prescribe 9 linear v 0 0 0", "prescribe 9: no atom with this ID"),
    ("gravity 0 0", "'gravity' needs three values"),
    ("damping linear 1 1 1 angle 0 0 0", "expected 'damping linear D D D angular D D D'"),
    ("tseries T 0 1 0 2", "tseries T:"),
    ("tseries 5 0 1", "tseries ID '5' must not be a number"),
    ("inertia J", "inertia: 'J' is not a per-atom d2_ property with 6 columns"),
    ("joint 0 1 0 0 0 1", "joint 0: joins atom 1 with itself"),
    ("joint 0 1 0 0 0 -1 joint 0 2 1 0 0 -1", "joint 0: ID defined twice"),
    ("joint 0 1 0 0 0 7", "joint atom 7: no atom with this ID"),
    ("joint 0 1 0 0 0 -1 joint 1 1 1 0 0 -1", "singular joint cluster (joints 0 1)"),
    ("q1 maybe", "q1: expected 'yes' or 'no'"),
    ("start later", "start: expected 'parmec' (initial half drift) or 'none'"),
    ("file /no/such/file", "/no/such/file"),
]


def _bad_deck(tmp, body, extra=()):
    return ["units si", "atom_style bpm/sphere", "atom_modify map array", "boundary f f f",
            "region b block -5 5 -5 5 -5 5", "create_box 1 b", "create_atoms 1 single 0 0 0 units box",
            "create_atoms 1 single 1 0 0 units box", "set group all diameter 0.5 mass 1.0",
            f"fix R all parmec/rigid {body}", "timestep 0.001"] + list(extra) + ["run 2"]


@pytest.mark.parametrize("body,message", BAD_DECKS, ids=[f"rigid_bad{i:02d}" for i in range(len(BAD_DECKS))])
def test_fix_parmec_rigid_bad_input(tmp_path, body, message):
    from dembridge import new_lammps
    lmp = new_lammps()
    try:
        with pytest.raises(Exception) as e:
            for c in _bad_deck(tmp_path, body):
                lmp.command(c)
        assert "parmec/rigid" in str(e.value) and message in str(e.value), str(e.value)
    finally:
        lmp.close()


def test_fix_parmec_rigid_fix_modify_refuses_joints(tmp_path):
    from dembridge import new_lammps
    lmp = new_lammps()
    try:
        for c in _bad_deck(tmp_path, "gravity 0 0 -1")[:-1] + ["run 1"]:
            lmp.command(c)
        lmp.command("fix_modify R gravity 0 0 -2")  # allowed between runs
        with pytest.raises(Exception) as e:
            lmp.command("fix_modify R prescribe 1 linear v 0 0 0 joint 0 1 0 0 0 -1")
        assert "'joint' cannot change after the fix is defined" in str(e.value)
    finally:
        lmp.close()


def test_fix_parmec_rigid_bodies_are_the_atoms_at_definition(tmp_path):
    """The bodies' states are records of the per-atom state layer, made for the group's atoms when the fix is
    defined: an atom created afterwards in the group has none, which the next run reports."""
    from dembridge import new_lammps
    lmp = new_lammps()
    try:
        with pytest.raises(Exception) as e:
            for c in _bad_deck(tmp_path, "gravity 0 0 -1", ["create_atoms 1 single 2 0 0 units box",
                                                            "set atom 3 diameter 0.5 mass 1.0"]):
                lmp.command(c)
        assert "an atom of the group has no rigid-body state" in str(e.value), str(e.value)
    finally:
        lmp.close()


@pytest.mark.parametrize("six,label", [((0, 0, 0, 0, 0, 0), "all zero"), ((1, 1, 1, 2, 0, 0), "indefinite"),
                                       ((1, 1, -1, 0, 0, 0), "negative moment")])
def test_fix_parmec_rigid_refuses_an_inertia_tensor_that_is_not_positive_definite(tmp_path, six, label):
    """An all-zero or indefinite inertia tensor is an ERROR naming the atom and the tensor (it used to run:
    J⁻¹ of a zero tensor is infinite, an indefinite one spins up without bound)."""
    from dembridge import new_lammps
    lmp = new_lammps()
    try:
        with pytest.raises(Exception) as e:
            for c in _bad_deck(tmp_path, "inertia J", ["fix PJ all property/atom d2_J 6 ghost yes"] +
                               [f"set atom 1 d2_J[{k + 1}] {v}" for k, v in enumerate((1, 1, 1, 0, 0, 0))] +
                               [f"set atom 2 d2_J[{k + 1}] {v}" for k, v in enumerate(six)]):
                lmp.command(c)
        msg = str(e.value)
        assert "parmec/rigid" in msg and "atom 2: its inertia tensor" in msg and "not positive definite" in msg, msg
    finally:
        lmp.close()


DEFINITION_FIXES = {
    "spring": ("fix S all parmec/spring", "table K -1 -1 1 1 spring 1 1 0 0 0 2 0 0 0 K"),
    "torsion": ("fix T all parmec/torsion", "table K -1 1 1 -1 torsion 1 1 2 0 0 1 1 0 0 kyaw K"),
    "rigid": ("fix R all parmec/rigid", "gravity 0 0 -1"),
}


@pytest.mark.parametrize("chain", ["direct", "through_another"])
@pytest.mark.parametrize("fix", sorted(DEFINITION_FIXES))
def test_definition_file_that_includes_itself_is_an_error(tmp_path, fix, chain):
    """`file A` where A says `file A` (or A -> B -> A) is an ERROR naming the chain of files, for every fix
    that reads definition files (it recursed until the stack overflowed: a segfault). Run by lmp in its own
    process, as a crash would take pytest down."""
    import subprocess
    from dembridge import lmp_executable, plugin_path
    cmd, words = DEFINITION_FIXES[fix]
    a, b = tmp_path / "a.def", tmp_path / "b.def"
    if chain == "direct":
        a.write_text(f"{words}\nfile a.def\n")
    else:
        a.write_text(f"{words}\nfile b.def\n")
        b.write_text("# the way back\nfile a.def\n")
    deck = tmp_path / "in.deck"
    deck.write_text("\n".join([f"plugin load {plugin_path()}", "units si", "atom_style bpm/sphere",
                               "atom_modify map array", "boundary f f f", "region b block -5 5 -5 5 -5 5",
                               "create_box 1 b", "create_atoms 1 single 0 0 0 units box",
                               "create_atoms 1 single 2 0 0 units box", "set group all diameter 0.5 mass 1.0",
                               f"{cmd} file a.def", "run 0"]) + "\n")
    p = subprocess.run([lmp_executable(), "-in", str(deck), "-screen", "none", "-log", str(tmp_path / "log"),
                        "-nocite"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    log = (tmp_path / "log").read_text() if (tmp_path / "log").exists() else ""
    assert p.returncode == 1, (p.returncode, p.stdout[-500:], p.stderr[-500:])  # an ERROR, not a signal
    want = "'a.def' -> 'a.def'" if chain == "direct" else "'a.def' -> 'b.def' -> 'a.def'"
    assert "ERROR" in log and "includes itself" in log and want in log, log[-1000:]
