"""fix parmec/spring: the loops per spring kind (centre-to-centre point springs, planes carried by part2 from
part1's centre) against the general loop, which every spring takes with 'loops general'. The kind loops claim
the general loop's results bitwise (fixes/springs/fix_parmec_spring_centre_loop.cpp, _plane_loop.cpp): positions,
velocities, forces, angular velocities, torques and every local output row are compared as text (%.17g),
after 300 steps with a reneighbour every 7 and an atom sort every 23, on 1 rank, 2 ranks and 1 rank x 2 threads.

Lattice: the springs benchmark's (bench/run_springs_bench.py), 6x7x9 atoms (bpm/sphere: the planes rotate with
part2), every bond of a kind in turn: follower + ratio, table dashpot, no dashpot, point-to-plane + ratio,
point-to-plane + friction (stick-slip), unload + ylim; top atoms tied to points or planes in space (general loop)."""
import re
import subprocess

import pytest

import spring_lattice
from dembridge import lmp_executable, plugin_path

NX, NY, NZ = 6, 7, 9
STEPS = 300
KINDS = ["K ratio 0.05", "K dashpot D", "K", "KP ratio 0.05 plane", "KP ratio 0.05 friction 0.1 kskn 0.5 plane",
         "K ratio 0.05 unload U ylim -50 50"]


def top(n, a, i, j, k):  # to space: a horizontal plane (general loop) or the point above
    if n % 2:
        return f"spring {n} {a} centre -1 {i} {j} {k} KP ratio 0.05 plane 0 0 1"
    return f"spring {n} {a} centre -1 {i} {j} {k + 1} K ratio 0.05"


def run(tmp_path, name, loops, ranks=1, threads=0):
    """(atom dumps, local rows sorted per snapshot, log) of the lattice run with 'loops LOOPS'."""
    d = tmp_path / name
    d.mkdir()
    spring_lattice.springs_file(d / "lattice.springs", KINDS, top, NX, NY, NZ)
    log = spring_lattice.run(
        d, NX, NY, NZ, f"loops {loops}", ["atom_modify map array sort 23 1.0", "neigh_modify every 7 delay 0 check no"],
        ["thermo 50", "dump D all custom 50 atoms.dump id x y z vx vy vz fx fy fz omegax omegay omegaz tqx tqy tqz",
         "dump_modify D sort id format float %.17g",
         "dump L all local 50 local.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7] f_S[8]",
         "dump_modify L format float %.17g"], STEPS, threads, ranks)
    snaps = []
    for s in (d / "local.dump").read_text().split("ITEM: TIMESTEP")[1:]:  # rows in rank order: sort them
        head, _, body = s.partition("ITEM: ENTRIES")
        snaps.append((head.split("\n")[1], sorted(body.strip().split("\n")[1:])))
    return (d / "atoms.dump").read_text(), snaps, log


def per_loop(log):
    m = re.search(r"springs per loop: centre (\d+), plane (\d+), general (\d+)", log)
    assert m, log[-2000:]
    return tuple(int(v) for v in m.groups())


@pytest.mark.parametrize("ranks,threads", [(1, 0), pytest.param(2, 0, marks=pytest.mark.two_cores),
                                           pytest.param(1, 2, marks=pytest.mark.two_cores)],
                         ids=["1rank", "2ranks", "1rank_2threads"])
def test_kind_loops_equal_general_loop_bitwise(tmp_path, ranks, threads):
    n = spring_lattice.springs_file(tmp_path / "count.springs", KINDS, top, NX, NY, NZ)
    atoms_k, local_k, log_k = run(tmp_path, "kinds", "kinds", ranks, threads)
    atoms_g, local_g, log_g = run(tmp_path, "general", "general", ranks, threads)
    centre, plane, general = per_loop(log_k)
    # the kind loops took their springs: centre springs of four kinds, planes with and without friction
    assert centre > n // 2 and plane > n // 4 and 0 < general < n // 8 and centre + plane + general == n
    assert per_loop(log_g) == (0, 0, n)
    assert len(local_k) == STEPS // 50 + 1 and all(len(rows) == n for _, rows in local_k)
    assert atoms_k.count("ITEM: ATOMS") == STEPS // 50 + 1
    assert atoms_k == atoms_g
    assert local_k == local_g


def test_loops_keyword_checked(tmp_path):
    d = tmp_path / "bad"
    d.mkdir()
    (d / "in.bad").write_text(f"plugin load {plugin_path()}\nunits si\natom_style sphere\nregion b block 0 2 0 2 0 2\n"
                              "create_box 1 b\ncreate_atoms 1 single 1 1 1\n"
                              "fix S all parmec/spring table K -1 -1 1 1 spring 1 1 centre -1 1 1 2 K loops fast\n")
    p = subprocess.run([lmp_executable(), "-in", "in.bad", "-log", "none", "-nocite"], cwd=d, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode != 0
    out = p.stdout + p.stderr
    assert "ERROR" in out and "loops" in out and "kinds" in out and "general" in out, out[-2000:]
