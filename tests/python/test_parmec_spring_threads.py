"""fix parmec/spring under 'package omp N' (issue 12, Threads): the spring loop runs on N OpenMP threads,
and the result is the same for every thread count (each spring is evaluated on its own; every atom sums
its springs in spring order afterwards), so 2 threads equal 1 thread and the plain run bitwise.

Lattice of the springs benchmark (bench/run_springs_bench.py), 6x7x9 atoms and 1017 springs of three
kinds at once: follower + ratio dashpot, point-to-plane + friction (stick-slip), unload + ylim."""
import pytest

import spring_lattice

pytestmark = pytest.mark.two_cores  # OpenMP threads (2) in most tests

NX, NY, NZ = 6, 7, 9
STEPS = 300
KINDS = ["K ratio 0.05", "KP ratio 0.05 friction 0.1 kskn 0.5 plane", "K ratio 0.05 unload U ylim -50 50"]


def run(tmp_path, name, threads, ranks=1):
    """Final positions, velocities, forces and torques (text, %.17g, sorted by atom ID) and the log."""
    d = tmp_path / name
    d.mkdir()
    spring_lattice.springs_file(d / "lattice.springs", KINDS,
                                lambda n, a, i, j, k: f"spring {n} {a} centre -1 {i} {j} {k + 1} K ratio 0.05", NX, NY, NZ)
    log = spring_lattice.run(d, NX, NY, NZ, "", ["atom_modify map array", "neigh_modify every 10 delay 0 check yes"],
                             ["thermo 100", f"dump D all custom {STEPS} final.dump id x y z vx vy vz fx fy fz tqx tqy tqz",
                              "dump_modify D sort id format float %.17g"], STEPS, threads, ranks)
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
