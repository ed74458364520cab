"""Restart of a coupled run: fix mbdyn ... mapping (MBDyn's `external structural mapping`) driving
a deforming mesh with particles on it, played by the test peer (15 mapped points, free point
masses with an initial bending velocity; the grid of tests/data/mbdyn-ext/mapping_beam).
10 MBDyn steps of 3 LAMMPS steps, loose and tight, 1 rank (and 2). The split runs write_restart after 15 LAMMPS
steps (the end of MBDyn step 5) or after 16 (between two sub-steps of step 6) and end (LAMMPS answers 5, the peer
saves its state); a new LAMMPS process reads the restart file and runs the remaining steps with a
new peer process resumed from the saved state. The reference is one LAMMPS process with the same
two `run` commands and one peer process: LAMMPS itself recomputes the forces at a run's setup
(with the velocities of the step's end, so the dissipative contacts differ from a single `run 30`
by round-off); a restart must add nothing to that. Bit for bit (tolerance 0): the particles
(x, v, omega, f) and the mesh vertices at every step from the restart on, every loads message the
peer received and the peer's trajectory.
Bad input after read_restart is an ERROR naming what differs: another point count, another mesh,
other sub-steps, and a peer that does not continue the coupling (a new one sending its t0)."""
import os
import subprocess

import pytest

from dembridge import lmp_executable, mpiexec, plugin_path
from gran_deck import HOOKE_ONE_TYPE
from test_fix_mbdyn import PEER, error_line
from test_mbdyn_mapping_mesh import M_POINTS, PARTICLES, RADIUS, STL, messages, transcript

pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")

DT, SUB, STEPS = 0.002, 3, 10  # LAMMPS timestep, LAMMPS steps per MBDyn step, MBDyn steps
G = 9.81


def rest_points():
    """The mapped points at rest: MBDyn's t0 message of the recorded cantilever (the grid's vertices)."""
    q = messages(transcript())[0][0]
    return [q[3 * j:3 * j + 3] for j in range(M_POINTS)]


def peer_args(sock, traj, loads, save=None, resume=None, coupling="loose"):
    args = [PEER, "--path", sock, "--accept-timeout", "30", "--io-timeout", "30", "--nodes", str(M_POINTS),
            "--orientation", "none", "--coupling", coupling, "--steps", str(STEPS), "--dt", str(SUB * DT), "--mass", "2",
            "--trajectory", traj, "--loads-log", loads]
    for x, y, z in rest_points():
        args += ["--x0", f"{x!r},{y!r},{z!r}", "--v0", f"0,0,{0.4 * x * x!r}"]  # bending upwards
    if coupling == "tight":
        # a constant force on the points: MBDyn's initial residual is not zero, so its derivatives
        # solve exchanges the t0 pose (the mesh's rest pose) first
        args += ["--force", "0,0,1"]
    if save:
        args += ["--save-state", save]
    if resume:
        args += ["--resume", resume]
    return args


def head(sock, fix_extra):
    return f"""neighbor 0.005 bin
{HOOKE_ONE_TYPE}
fix plate all mesh/surface/stress file {STL} type 1
fix walls all wall/gran model hooke tangential history mesh n_meshes 1 meshes plate
fix I all nve/sphere
fix M all mbdyn path {sock} mapping plate points {M_POINTS} orientation none mbdyn_dt {SUB * DT} &
  connect_timeout 30 io_timeout 30 {fix_extra}
fix g all gravity {G} vector 0 0 -1
"""


def outputs(wd, tag):
    return f"""fix D all mesh/dump 1 stl {wd}/{tag}.mesh.* plate
dump A all custom 1 {wd}/{tag}.atoms.* id x y z vx vy vz omegax omegay omegaz fx fy fz
dump_modify A format float %.17g sort id
"""


def fresh_deck(sock, wd, tag, steps, fix_extra="", write=None, then=None):
    atoms = "\n".join(f"create_atoms 1 single {x} {y} {RADIUS - 1e-3} units box" for x, y in PARTICLES)
    tail = f"write_restart {write}\n" if write else ""
    tail += f"run {then}\n" if then else ""
    return f"""plugin load ${{plugin}}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.2 1.8 -0.3 0.3 -0.2 0.3 units box
create_box 1 box
{atoms}
set type 1 diameter {2 * RADIUS}
set type 1 density 100000
timestep {DT}
{head(sock, fix_extra)}{outputs(wd, tag)}run {steps}
{tail}"""


def restarted_deck(sock, wd, tag, steps, restart, fix_extra="", mesh_id="plate", points=M_POINTS):
    text = head(sock, fix_extra).replace(f"points {M_POINTS}", f"points {points}")
    if mesh_id != "plate":
        text = text.replace("mapping plate", f"mapping {mesh_id}").replace(
            "fix walls", f"fix {mesh_id} all mesh/surface/stress file {STL} type 1\nfix walls").replace(
            "meshes plate", f"meshes {mesh_id}")
    return f"""plugin load ${{plugin}}
atom_modify map array
read_restart {restart}
newton off
comm_modify vel yes
{text}{outputs(wd, tag)}run {steps}
"""


def lammps(wd, deck, name, nprocs=1):
    path = os.path.join(wd, f"in.{name}")
    open(path, "w").write(deck)
    cmd = [lmp_executable(), "-in", path, "-nocite", "-log", "none", "-echo", "none", "-var", "plugin", plugin_path()]
    if nprocs > 1:
        cmd = [mpiexec(), "-n", str(nprocs)] + cmd
    return subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=120, stdin=subprocess.DEVNULL)


def coupled(wd, deck, name, nprocs=1, **peer):
    sock = os.path.join(wd, "s.sock")
    traj, loads = os.path.join(wd, f"{name}.traj"), os.path.join(wd, f"{name}.loads")
    p = subprocess.Popen(peer_args(sock, traj, loads, **peer), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True)
    line = p.stdout.readline()
    assert "listening" in line, line
    run = lammps(wd, deck(sock), name, nprocs)
    out, _ = p.communicate(timeout=60)
    return run, p.returncode, out, traj, loads


def lines(path):
    return [l.rstrip("\n") for l in open(path) if l.strip() and not l.startswith("#")]


def snapshot(wd, tag, step):
    """The mesh dump (STL at 17 digits) and the atom dump of one step, without the header lines that
    name the file."""
    mesh = open(f"{wd}/{tag}.mesh.{step}").read().splitlines()
    atoms = open(f"{wd}/{tag}.atoms.{step}").read().split("ITEM: ATOMS")[1]
    return mesh[1:-1], atoms


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    wd = str(tmp_path_factory.mktemp("mbr"))
    assert len(wd) < 90, wd  # a Unix socket path has at most 107 bytes
    return wd


def reference(wd, first, coupling, nprocs=1):
    """One LAMMPS process (`run first`, `run` the rest) and one peer process."""
    tag = f"ref{first}{coupling}{nprocs}"
    run, rc, out, traj, loads = coupled(
        wd, lambda s: fresh_deck(s, wd, tag, first, f"coupling {coupling}", then=SUB * STEPS - first), tag, nprocs,
        coupling=coupling)
    assert run.returncode == 0 and rc == 0, (run.stdout[-3000:], out)
    return tag, lines(traj), lines(loads)


def split_run(wd, first, tag, coupling, nprocs=1):
    """`run first` + write_restart; a new process reads it and runs to the end; new peer processes."""
    restart = os.path.join(wd, f"{tag}.restart")
    state = os.path.join(wd, f"{tag}.state")
    fix = f"coupling {coupling}"
    run1, rc1, out1, traj1, loads1 = coupled(
        wd, lambda s: fresh_deck(s, wd, tag + "1", first, fix, write=restart), tag + "1", nprocs, save=state,
        coupling=coupling)
    assert run1.returncode == 0, run1.stdout[-3000:]
    assert rc1 == 2 and "peer requested end" in out1, out1  # LAMMPS answered 5 when it ended
    run2, rc2, out2, traj2, loads2 = coupled(
        wd, lambda s: restarted_deck(s, wd, tag + "2", SUB * STEPS - first, restart, fix), tag + "2", nprocs,
        resume=state, coupling=coupling)
    assert run2.returncode == 0 and rc2 == 0, (run2.stdout[-3000:], out2)
    return lines(traj1), lines(loads1), lines(traj2), lines(loads2)


@pytest.mark.parametrize("coupling,first,nprocs", [
    ("loose", SUB * 5, 1), ("loose", SUB * 5 + 1, 1), ("tight", SUB * 5 + 1, 1),
    pytest.param("loose", SUB * 5 + 1, 2, marks=pytest.mark.two_cores)],
    ids=["loose_end_of_mbdyn_step", "loose_between_substeps", "tight_between_substeps", "loose_between_substeps_2_ranks"])
def test_restart_equals_the_split_run_bitwise(workdir, coupling, first, nprocs):
    wd = workdir
    ref, traj, loads = reference(wd, first, coupling, nprocs)
    answers = [l.split()[1] for l in loads]  # the command of each loads message: 6 converged, 2 an iterate
    assert len(traj) == STEPS + 1 and answers.count("6") == STEPS + 1
    assert (coupling == "tight") == ("2" in answers)
    tag = f"r{first}{coupling}{nprocs}"
    traj1, loads1, traj2, loads2 = split_run(wd, first, tag, coupling, nprocs)
    done = first // SUB  # MBDyn steps solved with LAMMPS' loads before the restart
    # the peer: its trajectory (t, then x v theta theta' per point at 17 digits) and every loads
    # message it received (without the answer index, which each process counts from 0)
    assert traj1[:done + 1] == traj[:done + 1]
    assert traj2 == traj[done:], "the resumed peer's trajectory differs from the one peer's"
    received = [l.split(" ", 1)[1] for l in loads1 + loads2]
    assert received == [l.split(" ", 1)[1] for l in loads], "the loads sent to the peer differ"
    # LAMMPS: the particles and the mesh vertices at every step from the restart on; at the step of
    # the restart the first process's dump (the one-process run writes a step once; the new process
    # writes it again at its setup, with the forces of the setup)
    differ = [step for step in range(first, SUB * STEPS + 1)
              if snapshot(wd, ref, step) != snapshot(wd, tag + ("1" if step == first else "2"), step)]
    assert not differ, f"steps {differ} differ"
    # the particles do press on the mesh (else the loads would be zero and the test would check little)
    pressing = sum(1 for l in loads if max(abs(float(v)) for v in l.split()[2:]) > 1.0)
    print(f"{coupling}, {nprocs} rank(s), restart after {first} LAMMPS steps: {len(received)} loads messages, {len(traj2)} peer states, "
          f"{SUB * STEPS - first + 1} steps of particles and vertices equal bit for bit; {pressing} exchanges "
          f"with point loads > 1 N")
    assert pressing >= STEPS - 1


def test_restart_bad_input(workdir):
    wd = workdir
    restart = os.path.join(wd, "bad.restart")
    state = os.path.join(wd, "bad.state")
    run1, _, out1, _, _ = coupled(wd, lambda s: fresh_deck(s, wd, "bad1", SUB * 2 + 1, write=restart), "bad1",
                                  save=state)
    assert run1.returncode == 0, run1.stdout[-3000:]
    sock = os.path.join(wd, "s.sock")
    cases = [
        (dict(points=14), "the restart file's coupling has 15 mapped points ('mapping plate points M'), this command 14"),
        (dict(mesh_id="plate2"), "the restart file's mapped points drive mesh 'plate', this command's mesh 'plate2'"),
        (dict(fix_extra="coupling tight"), "the restart file's coupling is loose, this command's tight ('coupling')"),
    ]
    for kw, expected in cases:
        run = lammps(wd, restarted_deck(sock, wd, "bad", 3, restart, **kw), "bad")
        err = error_line(run.stdout)
        assert run.returncode != 0 and expected in err, (kw, run.stdout[-2000:])
    # the mesh read from another file: fix mesh/surface's own restart record refuses it
    paddle = os.path.join(os.path.dirname(STL), "..", "..", "liggghts-walls", "mesh_move_rotate_paddle", "paddle.stl")
    run = lammps(wd, restarted_deck(sock, wd, "bad", 3, restart).replace(STL, paddle), "bad")
    assert run.returncode != 0 and "(id plate) restart" in error_line(run.stdout), run.stdout[-2000:]
    # other sub-steps: the timestep changed (mbdyn_dt stays), so one MBDyn step is 6 LAMMPS steps
    deck = restarted_deck(sock, wd, "bad", 3, restart).replace("fix I all", "timestep 0.001\nfix I all")
    run = lammps(wd, deck, "bad")
    assert run.returncode != 0 and "the restart file's coupling has 3 LAMMPS steps per MBDyn step, this command " \
                                   "and timestep 6" in error_line(run.stdout), run.stdout[-2000:]
    # a peer that starts anew (its t0 message) instead of continuing: written between sub-steps,
    # the message of the current step must come again, the same bytes
    run, rc, out, _, _ = coupled(wd, lambda s: restarted_deck(s, wd, "bad", 3, restart), "bad2")
    err = error_line(run.stdout)
    assert run.returncode != 0 and "is not the one received before write_restart" in err, run.stdout[-2000:]
    assert "the peer does not continue the same coupling" in err
    # resume no: the same peer starting anew is a new coupling (its t0 message is the rest pose; the
    # restored mesh is bent by up to 1.3 cm, bound again within match_tolerance)
    run, rc, out, _, loads = coupled(wd, lambda s: restarted_deck(s, wd, "new", 3, restart,
                                                                  "resume no match_tolerance 0.04"), "new")
    assert run.returncode == 0, run.stdout[-2000:]
    assert "resume no: the coupling state of the restart file is ignored" in run.stdout
    assert rc == 2 and len(lines(loads)) == 2  # the t0 answer and MBDyn step 1; step 2 refused with 5
