"""Restart of fix mbdyn ... modal with a deforming mesh: the plate and spheres of test_mbdyn_modal_mesh
(type modal, the test peer's clamped modal body), loose and tight, 1 rank and 2. The split run writes
a restart file after FIRST steps (the spheres on the plate) and ends (LAMMPS answers MBDyn's next
message with 5; the peer saves its state); a new LAMMPS process reads the restart file and runs to
the end with a new peer process resumed from the saved state. The reference is one LAMMPS process
with the same two `run` commands and one peer process. Bit for bit (tolerance 0): the spheres (x, v,
omega, f) and the mesh vertices at every step from the restart on, every loads message the peer
received (2 and 6 in tight coupling) and the peer's trajectory (q, q', q'', p per step).
Bad input after read_restart is an ERROR naming the argument that differs."""
import os
import subprocess

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import PEER, error_line
from test_mbdyn_modal_mesh import model, peer_args, spheres_deck, write_fem, write_stl
from test_mbdyn_restart import lammps, lines, outputs, snapshot, workdir  # noqa: F401 (fixture)

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

STEPS, FIRST = 24, 18  # the spheres land at step 15
TIGHT = "coupling tight tolerance 1e-10 max_iterations 6"


def fix_extra(coupling):
    return TIGHT if coupling == "tight" else ""


def fresh(sock, wd, tag, steps, extra, write=None, then=None):
    tail = (f"write_restart {write}\n" if write else "") + (f"run {then}\n" if then else "")
    return f"{spheres_deck()}{model(sock, wd, extra)}{outputs(wd, tag)}run {steps}\n{tail}"


def restarted(sock, wd, tag, steps, restart, extra):
    return f"""plugin load ${{plugin}}
atom_modify map array
read_restart {restart}
newton off
comm_modify vel yes
{model(sock, wd, extra)}{outputs(wd, tag)}run {steps}
"""


def coupled(wd, deck, name, coupling, nprocs=1, save=None, resume=None):
    sock = os.path.join(wd, "s.sock")
    args = peer_args(sock, wd, STEPS, f"{name}.traj") + ["--coupling", coupling, "--loads-log", f"{wd}/{name}.loads"]
    args += ["--save-state", save] if save else []
    args += ["--resume", resume] if resume else []
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    line = p.stdout.readline()
    assert "listening" in line, line
    run = lammps(wd, deck(sock), name, nprocs)
    out, _ = p.communicate(timeout=60)
    return run, p.returncode, out, lines(f"{wd}/{name}.traj"), lines(f"{wd}/{name}.loads")


def prepare(wd):
    if not os.path.exists(f"{wd}/plate.fem"):
        write_fem(f"{wd}/plate.fem")
        write_stl(f"{wd}/plate.stl")


def split_run(wd, tag, coupling, nprocs):
    restart, state, extra = f"{wd}/{tag}.restart", f"{wd}/{tag}.state", fix_extra(coupling)
    run1, rc1, out1, traj1, loads1 = coupled(wd, lambda s: fresh(s, wd, tag + "1", FIRST, extra, write=restart),
                                             tag + "1", coupling, nprocs, save=state)
    assert run1.returncode == 0, run1.stdout[-3000:]
    assert rc1 == 2 and "peer requested end" in out1, out1  # LAMMPS answered 5 when it ended
    run2, rc2, out2, traj2, loads2 = coupled(wd, lambda s: restarted(s, wd, tag + "2", STEPS - FIRST, restart, extra),
                                             tag + "2", coupling, nprocs, resume=state)
    assert run2.returncode == 0 and rc2 == 0, (run2.stdout[-3000:], out2)
    return traj1, loads1, traj2, loads2


@pytest.mark.parametrize("coupling,nprocs", [
    ("loose", 1), ("tight", 1), pytest.param("loose", 2, marks=pytest.mark.two_cores),
    pytest.param("tight", 2, marks=pytest.mark.two_cores)])
def test_modal_mesh_restart_equals_the_split_run_bitwise(workdir, coupling, nprocs):  # noqa: F811
    wd = workdir
    prepare(wd)
    ref = f"ref{coupling}{nprocs}"
    run, rc, out, traj, loads = coupled(
        wd, lambda s: fresh(s, wd, ref, FIRST, fix_extra(coupling), then=STEPS - FIRST), ref, coupling, nprocs)
    assert run.returncode == 0 and rc == 0, (run.stdout[-3000:], out)
    answers = [l.split()[1] for l in loads]
    assert len(traj) == STEPS + 1 and answers.count("6") == STEPS + 1
    assert (coupling == "tight") == ("2" in answers)
    tag = f"r{coupling}{nprocs}"
    traj1, loads1, traj2, loads2 = split_run(wd, tag, coupling, nprocs)
    assert traj1 == traj[:FIRST + 1]
    assert traj2 == traj[FIRST:], "the resumed peer's trajectory differs from the one peer's"
    received = [l.split(" ", 1)[1] for l in loads1 + loads2]
    assert received == [l.split(" ", 1)[1] for l in loads], "the loads sent to the peer differ"
    differ = [step for step in range(FIRST, STEPS + 1)
              if snapshot(wd, ref, step) != snapshot(wd, tag + ("1" if step == FIRST else "2"), step)]
    assert not differ, f"steps {differ} differ"
    pressing = sum(1 for l in traj if float(l.split()[7]) < -1.0)  # p1 < -1 N: the spheres on the plate
    print(f"modal mesh restart, {coupling}, {nprocs} rank(s), after {FIRST} of {STEPS} steps: {len(received)} loads "
          f"messages, {len(traj2)} peer states, {STEPS - FIRST + 1} steps of spheres and vertices equal bit for bit; "
          f"{pressing} steps with the spheres pressing")
    assert pressing >= STEPS - FIRST


def test_modal_mesh_restart_bad_input(workdir):  # noqa: F811
    wd = workdir
    prepare(wd)
    restart = f"{wd}/rloose1.restart"  # the loose split run's, if it ran
    if not os.path.exists(restart):
        restart = f"{wd}/bad.restart"
        run1, _, _, _, _ = coupled(wd, lambda s: fresh(s, wd, "bad1", FIRST, "", write=restart), "bad1", "loose",
                                   save=f"{wd}/bad.state")
        assert run1.returncode == 0, run1.stdout[-3000:]
    sock = os.path.join(wd, "none.sock")
    deck = restarted(sock, wd, "bad", 3, restart, "")
    cases = [
        (deck.replace("modes 2", "modes 1"), "the restart file's coupling has 2 modes, this command 1 ('modes')"),
        (deck.replace("type modal mesh plate", "type modal"),
         "the restart file's coupling carries mesh 'plate', this command the group's atoms ('mesh')"),
        (deck.replace("connect_timeout", "coupling tight connect_timeout"),
         "the restart file's coupling is loose, this command's tight ('coupling')"),
        (deck.replace("type modal", "type all"), "the restart file's coupling is type modal, this command's type all "
                                                  "('type')"),
        (deck.replace(f"modal {wd}/plate.fem modes 2 type modal mesh plate", "mapping plate points 15 orientation none"),
         "was written by fix mbdyn ... modal; this command has no 'modal FEM-FILE'"),
    ]
    for text, expected in cases:
        run = lammps(wd, text, "bad")
        err = error_line(run.stdout)
        assert run.returncode != 0 and expected in err, (expected, run.stdout[-2000:])
    # resume no: the restart file's coupling is ignored, a new one starts (the peer's t0 message: the
    # plate at rest, bound again within match of the restored mesh, bent by the spheres)
    run, rc, out, traj, _ = coupled(wd, lambda s: restarted(s, wd, "new", 3, restart, "resume no match 0.01"), "new",
                                    "loose")
    assert run.returncode == 0, run.stdout[-2000:]
    assert "resume no: the coupling state of the restart file is ignored" in run.stdout
