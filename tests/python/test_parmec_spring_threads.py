"""fix parmec/spring under 'package omp N' (issue 12, Threads): the spring loop runs on N OpenMP threads,
and the result is the same for every thread count (each spring is evaluated on its own; every atom sums
its springs in spring order afterwards), so 2 threads equal 1 thread and the plain run bitwise.

Lattice of the springs benchmark (bench/run_springs_bench.py), 6x7x9 atoms and 1017 springs of three
kinds at once: follower + ratio dashpot, point-to-plane + friction (stick-slip), unload + ylim."""
import os
import subprocess

import pytest

from dembridge import lmp_executable, mpiexec, plugin_path

NX, NY, NZ = 6, 7, 9
STEPS = 300


def springs_file(path):
    aid = lambda i, j, k: 1 + i + NX * (j + NY * k)  # noqa: E731
    kinds = ["K ratio 0.05", "KP ratio 0.05 friction 0.1 kskn 0.5 plane", "K ratio 0.05 unload U ylim -50 50"]
    n = 0
    with open(path, "w") as f:
        f.write("table K -1 -2e4 -0.01 -1e2 0.01 1e2 1 2e4\ntable KP -1 2e4 -0.01 1e2 0.01 -1e2 1 -2e4\n"
                "table U -1 -1e6 1 1e6\n")
        for k in range(NZ):
            for j in range(NY):
                for i in range(NX):
                    a = aid(i, j, k)
                    for (di, dj, dk) in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                        if i + di < NX and j + dj < NY and k + dk < NZ:
                            n += 1
                            b, kind = aid(i + di, j + dj, k + dk), kinds[n % 3]
                            if kind.endswith("plane"):
                                f.write(f"spring {n} {a} centre {b} {i} {j} {k} {kind} {di} {dj} {dk}\n")
                            else:
                                f.write(f"spring {n} {a} centre {b} centre {kind}\n")
                    if k == NZ - 1:
                        n += 1
                        f.write(f"spring {n} {a} centre -1 {i} {j} {k + 1} K ratio 0.05\n")
    return n


def run(tmp_path, name, threads, ranks=1):
    """Final positions, velocities, forces and torques (text, %.17g, sorted by atom ID) and the log."""
    d = tmp_path / name
    d.mkdir()
    springs_file(d / "lattice.springs")
    lines = [f"plugin load {plugin_path()}"]
    if threads:
        lines.append(f"package omp {threads}")
    lines += ["units si", "atom_style bpm/sphere", "boundary m m m", "atom_modify map array",
              "comm_modify vel yes cutoff 2.5", "neighbor 0.3 bin", "neigh_modify every 10 delay 0 check yes",
              "lattice sc 1.0", f"region box block -0.5 {NX - 0.5} -0.5 {NY - 0.5} -0.5 {NZ - 0.5} units box",
              "create_box 1 box", "create_atoms 1 region box", "set group all diameter 0.5", "set group all mass 1.0",
              "variable vx atom 0.5*sin(12.9898*x+78.233*y+37.719*z)", "variable vy atom 0.5*sin(39.346*x+11.135*y+83.155*z)",
              "variable vz atom 0.5*sin(73.156*x+52.235*y+9.151*z)", "velocity all set v_vx v_vy v_vz",
              "fix S all parmec/spring file lattice.springs", "fix I all nve/bpm/sphere",
              "fix G all gravity 10.0 vector 0 0 -1", "timestep 2e-4", "thermo 100",
              f"dump D all custom {STEPS} final.dump id x y z vx vy vz fx fy fz tqx tqy tqz",
              "dump_modify D sort id format float %.17g", f"run {STEPS}"]
    (d / "in.lattice").write_text("\n".join(lines) + "\n")
    cmd = [lmp_executable(), "-in", "in.lattice", "-log", "log.lammps", "-screen", "none", "-nocite"]
    if ranks > 1:
        cmd = [mpiexec(), "-n", str(ranks)] + cmd
    env = dict(os.environ, OMP_NUM_THREADS=str(threads or 1))
    p = subprocess.run(cmd, cwd=d, capture_output=True, text=True, env=env, timeout=600)
    log = (d / "log.lammps").read_text() if (d / "log.lammps").exists() else ""
    assert p.returncode == 0, p.stdout + p.stderr + log[-3000:]
    dump = (d / "final.dump").read_text().split("ITEM: ATOMS")[-1]
    return dump, log


def test_threads_equal_one_thread_bitwise(tmp_path):
    plain, _ = run(tmp_path, "plain", 0)
    one, log1 = run(tmp_path, "omp1", 1)
    two, log2 = run(tmp_path, "omp2", 2)
    again, _ = run(tmp_path, "omp2again", 2)
    assert len(plain.split("\n")) > NX * NY * NZ
    assert "spring loop on 2 OpenMP threads" in log2, log2[-2000:]
    assert "spring loop on" not in log1
    assert one == plain
    assert two == plain
    assert again == two


def test_two_ranks_two_threads_match_one_thread(tmp_path):
    """2 ranks x 2 threads against 1 rank x 1 thread: the decomposition changes nothing beyond round-off
    (ghost contributions arrive by reverse communication, still summed in spring order)."""
    ref, _ = run(tmp_path, "ref", 0)
    got, log = run(tmp_path, "r2t2", 2, ranks=2)
    assert "spring loop on 2 OpenMP threads" in log
    rows = lambda t: [[float(v) for v in l.split()] for l in t.strip().split("\n")[1:]]  # noqa: E731
    a, b = rows(ref), rows(got)
    assert len(a) == len(b) == NX * NY * NZ
    for ra, rb in zip(a, b):
        assert ra[0] == rb[0]
        for x, y in zip(ra[1:], rb[1:]):
            assert x == pytest.approx(y, rel=1e-9, abs=1e-9)
