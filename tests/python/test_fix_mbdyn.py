"""fix mbdyn (issue 6 glue; doc/fix_mbdyn.md) against the independent MBDyn test peer
(coupling/testpeer): split spring-mass vs the analytic damped oscillation (loose, sub-cycled,
tight), rigid group loads vs an independent compute, serial vs 2 MPI ranks, and robustness
(peer never connects, peer dies mid-run with a dump, faults on the wire, bad input), each bounded
by a timeout. Plugin from $DEMBRIDGE_PLUGIN, test peer from $DEMBRIDGE_MBDYN_TESTPEER or the
build tree next to the plugin."""
import math
import os
import shutil
import subprocess
import tempfile
import time

import pytest

from dembridge import lmp_executable, mpiexec, plugin_path
from dembridge.outputs import read_dump_rows as read_dump


def find_testpeer():
    env = os.environ.get("DEMBRIDGE_MBDYN_TESTPEER")
    if env:
        return env
    base = os.path.dirname(os.path.abspath(plugin_path()))
    for cand in (os.path.join(base, "coupling", "mbdyn_testpeer"), os.path.join(base, "mbdyn_testpeer")):
        if os.path.exists(cand):
            return cand
    return None


PEER = find_testpeer()
pytestmark = pytest.mark.skipif(PEER is None or not os.path.exists(plugin_path()),
                                reason="needs the plugin and the mbdyn_testpeer executable (build both)")


@pytest.fixture
def sockdir():
    # Unix socket paths are limited to 108 bytes: keep them short, outside pytest's tmp tree.
    d = tempfile.mkdtemp(prefix="mbd", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


class Peer:
    """mbdyn_testpeer in the background, listening (MBDyn `create, yes`) before LAMMPS starts."""

    def __init__(self, sock, *args, traj=None, timeout=30):
        cmd = [PEER, "--path", sock, "--accept-timeout", str(timeout), "--io-timeout", str(timeout)] + list(args)
        if traj:
            cmd += ["--trajectory", traj]
        self.p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        line = self.p.stdout.readline()
        assert "listening" in line, line

    def finish(self, timeout=60):
        out, _ = self.p.communicate(timeout=timeout)
        return self.p.returncode, out


def run_lammps(deck_text, workdir, nprocs=1, timeout=120):
    path = os.path.join(workdir, "in.lmp")
    open(path, "w").write(deck_text)
    cmd = [lmp_executable(), "-in", path, "-nocite", "-log", "none", "-echo", "none",
           "-var", "plugin", plugin_path()]
    if nprocs > 1:
        cmd = [mpiexec(), "-n", str(nprocs)] + cmd
    t0 = time.monotonic()
    p = subprocess.run(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=timeout, stdin=subprocess.DEVNULL)
    return p.returncode, p.stdout, time.monotonic() - t0


def read_traj(path):
    return [[float(v) for v in l.split()] for l in open(path) if l.strip() and not l.startswith("#")]


def error_line(out):
    return "\n".join(l for l in out.splitlines() if "ERROR" in l)


# ------------------------------------------------------------------------------------------------
# A. split spring-mass: MBDyn (the test peer) has the mass m, LAMMPS the spring k and dashpot c
#    acting on the coupled atom (fix spring tether + fix viscous, defined before fix mbdyn).

M, K, C, X0 = 2.0, 50.0, 0.4, 0.1


def analytic_x(t):
    w0 = math.sqrt(K / M)
    z = C / (2 * math.sqrt(K * M))
    wd = w0 * math.sqrt(1 - z * z)
    return math.exp(-z * w0 * t) * (X0 * math.cos(wd * t) + z * w0 * X0 / wd * math.sin(wd * t))


def spring_mass_deck(sock, h, substeps, steps, coupling="loose", extra=""):
    return f"""plugin load ${{plugin}}
units si
atom_style sphere
boundary f f f
region box block -1 1 -1 1 -1 1
create_box 1 box
create_atoms 1 single {X0} 0 0 units box
set atom 1 diameter 0.05 density 1000
timestep {h!r}
fix S all spring tether {K} 0 0 0 0
fix D all viscous {C}
fix M all mbdyn path {sock} node atom 1 orientation none coupling {coupling} substeps {substeps} connect_timeout 20 io_timeout 20 {extra}
thermo_style custom step f_M[1] f_M[2] f_M[1][1]
thermo_modify format float %.15g
thermo {max(1, steps // 4)}
run {steps}
"""


def spring_mass_error(sockdir, dt, substeps=1, coupling="loose", T=2.0, nprocs=1, extra="", peer_extra=(),
                      before_fix=""):
    sock = os.path.join(sockdir, "s.sock")
    traj = os.path.join(sockdir, f"traj_{dt}_{substeps}_{coupling}.txt")
    ksteps = int(round(T / dt))
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--coupling", coupling, "--steps", str(ksteps),
                "--dt", repr(dt), "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", *peer_extra, traj=traj)
    deck = spring_mass_deck(sock, dt / substeps, substeps, ksteps * substeps, coupling, extra)
    if before_fix:
        deck = deck.replace("fix M all mbdyn", before_fix + "\nfix M all mbdyn")
    rc, out, _ = run_lammps(deck, sockdir, nprocs=nprocs)
    prc, pout = peer.finish()
    assert rc == 0, out[-3000:]
    assert prc == 0, pout
    rows = read_traj(traj)
    assert len(rows) == ksteps + 1
    err = max(abs(r[1] - analytic_x(r[0])) for r in rows)
    return err, rows, pout


def test_spring_mass_loose_follows_analytic_and_converges(sockdir):
    e1, rows, pout = spring_mass_error(sockdir, 0.004)
    e2, _, _ = spring_mass_error(sockdir, 0.002)
    e3, _, _ = spring_mass_error(sockdir, 0.001)
    print(f"loose N=1: max |x - x_analytic| dt=4ms {e1:.3e}, 2ms {e2:.3e}, 1ms {e3:.3e}; "
          f"ratios {e1 / e2:.2f} {e2 / e3:.2f}")
    assert e1 < 0.01 * X0
    # the coupling lag error falls at least linearly with dt (MBDyn's crank nicolson predictor sends
    # v_{k-1} and x_{k-1} + dt v_{k-1}: first order, as with the real MBDyn, tests/data/mbdyn)
    assert e1 / e2 > 1.8 and e2 / e3 > 1.8


def test_spring_mass_subcycled(sockdir):
    """One MBDyn step = 4 LAMMPS steps: kinematics interpolated, loads averaged over the sub-steps."""
    e4, rows, pout = spring_mass_error(sockdir, 0.004, substeps=4)
    e2, _, _ = spring_mass_error(sockdir, 0.002, substeps=4)
    e1, _, _ = spring_mass_error(sockdir, 0.004, substeps=1)
    print(f"sub-cycled N=4: dt_MBDyn=4ms {e4:.3e}, 2ms {e2:.3e} (ratio {e4 / e2:.2f}); N=1 at 4ms {e1:.3e}")
    assert "501 kinematics messages, 501 answers, 500 steps" in pout
    # The sub-step average is centred half an MBDyn step earlier than the end-of-step load MBDyn's
    # trapezoidal rule takes it for: a first-order lag (the acceptance A), unlike N = 1.
    assert e4 < 0.05 * X0
    assert 1.8 < e4 / e2 < 2.3


def test_spring_mass_subcycled_extrapolated_loads(sockdir):
    """'loads extrapolate' shifts the sub-step average to the end of the MBDyn step: second order again."""
    e4, _, _ = spring_mass_error(sockdir, 0.004, substeps=4, extra="loads extrapolate")
    e2, _, _ = spring_mass_error(sockdir, 0.002, substeps=4, extra="loads extrapolate")
    ea, _, _ = spring_mass_error(sockdir, 0.004, substeps=4)
    print(f"sub-cycled N=4, loads extrapolate: dt_MBDyn=4ms {e4:.3e}, 2ms {e2:.3e} (ratio {e4 / e2:.2f}); "
          f"loads average at 4ms {ea:.3e}")
    assert e4 / e2 > 3.0
    assert e4 < ea / 10


def test_spring_mass_mbdyn_dt_keyword_matches_substeps(sockdir):
    e_a, rows_a, _ = spring_mass_error(sockdir, 0.004, substeps=4, T=0.4)
    sock = os.path.join(sockdir, "s.sock")
    traj = os.path.join(sockdir, "t_dt.txt")
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "100", "--dt", "0.004",
                "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", traj=traj)
    deck = spring_mass_deck(sock, 0.001, 1, 400).replace("substeps 1", "mbdyn_dt 0.004")
    rc, out, _ = run_lammps(deck, sockdir)
    assert rc == 0, out[-2000:]
    assert peer.finish()[0] == 0
    rows_b = read_traj(traj)
    assert max(abs(a[1] - b[1]) for a, b in zip(rows_a, rows_b)) == 0.0


def monolithic_trapezoid(dt, steps):
    """m x'' + c x' + k x = 0 integrated by the trapezoidal rule as ONE implicit system: what the
    tight coupling must converge to (the test peer integrates its mass with the same rule)."""
    x, v = X0, 0.0
    a = (-K * x - C * v) / M
    out = [x]
    for _ in range(steps):
        # x1 = x + dt/2 (v + v1), v1 = v + dt/2 (a + a1), a1 = (-K x1 - C v1) / M
        h = dt / 2
        # substitute x1: a1 = (-K (x + h v + h v1) - C v1) / M ; v1 = v + h a + h a1
        # => v1 (1 + h (K h + C) / M) = v + h a + h (-K (x + h v)) / M
        v1 = (v + h * a - h * K * (x + h * v) / M) / (1 + h * (K * h + C) / M)
        x1 = x + h * (v + v1)
        a = (-K * x1 - C * v1) / M
        x, v = x1, v1
        out.append(x)
    return out


# Tight: a constant force in MBDyn and its opposite on the coupled atom (doc/fix_mbdyn.md, the
# start-up remedy) make MBDyn's initial residual non-zero, so the derivatives solve exchanges and
# a0 includes the peer's load; MBDyn's c F0 momentum offset at t0 is switched off in the peer so
# the monolithic trapezoid below is exact.
TIGHT_REMEDY = dict(peer_extra=("--force", "1,0,0", "--derivatives-coefficient", "0"),
                    before_fix="fix R all addforce -1 0 0")


def test_spring_mass_tight(sockdir):
    """Tight: every MBDyn iterate gets the loads for its kinematics, so the coupled run converges to
    the monolithic implicit (trapezoidal) solution of the whole spring-mass system."""
    et1, rows1, pout = spring_mass_error(sockdir, 0.004, coupling="tight", extra="tolerance 1e-12 max_iterations 15",
                                         **TIGHT_REMEDY)
    et2, _, _ = spring_mass_error(sockdir, 0.002, coupling="tight", extra="tolerance 1e-12 max_iterations 15",
                                  **TIGHT_REMEDY)
    el1, rowsl, _ = spring_mass_error(sockdir, 0.004, coupling="loose")
    mono = monolithic_trapezoid(0.004, 500)
    dev_tight = max(abs(r[1] - m) for r, m in zip(rows1, mono))
    dev_loose = max(abs(r[1] - m) for r, m in zip(rowsl, mono))
    # messages = 1 (t0, answered 6) + iterates of every step
    n_msgs = int(pout.split("(")[1].split(" kinematics")[0])
    print(f"tight: err vs analytic dt=4ms {et1:.3e}, 2ms {et2:.3e} (ratio {et1 / et2:.2f}); loose at 4ms {el1:.3e}; "
          f"vs monolithic trapezoid: tight {dev_tight:.2e}, loose {dev_loose:.2e}; "
          f"{n_msgs} messages for 500 steps ({(n_msgs - 1) / 500:.2f} iterates per step)")
    assert 3.5 < et1 / et2 < 4.5          # second order
    assert (n_msgs - 1) / 500 > 2.0       # really iterates
    assert dev_tight < 1e-11
    assert dev_loose > 100 * dev_tight
    # tight with sub-cycling: the iterates re-evaluate the end-of-step sub-step only
    ets, _, pout = spring_mass_error(sockdir, 0.004, substeps=4, coupling="tight",
                                     extra="tolerance 1e-12 max_iterations 15 loads extrapolate predictor correct",
                                     **TIGHT_REMEDY)
    print(f"tight, N=4, loads extrapolate: {ets:.3e} ({pout.strip()})")
    assert ets < 2e-5


def test_spring_mass_over_tcp_and_with_create_no(sockdir):
    """The same split spring-mass over TCP loopback (MBDyn `port`), and with MBDyn `create, no`
    (LAMMPS listens from the fix command on, MBDyn connects): identical trajectories."""
    ref = spring_mass_error(sockdir, 0.004, T=0.4)[1]
    # TCP: the peer picks a free port and prints it
    traj = os.path.join(sockdir, "tcp.txt")
    p = subprocess.Popen([PEER, "--port", "0", "--accept-timeout", "30", "--io-timeout", "30", "--nodes", "1",
                          "--orientation", "none", "--steps", "100", "--dt", "0.004", "--mass", str(M),
                          "--x0", f"{X0},0,0", "--v0", "0,0,0", "--trajectory", traj],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    port = int(p.stdout.readline().split("port")[1])
    deck = spring_mass_deck("X", 0.004, 1, 100).replace("path X", f"port {port} host 127.0.0.1")
    rc, out, _ = run_lammps(deck, sockdir)
    p.communicate(timeout=60)
    assert rc == 0 and p.returncode == 0, out[-2000:]
    assert read_traj(traj) == ref
    # create no: LAMMPS listens, the peer connects (retrying) once started
    sock = os.path.join(sockdir, "cn.sock")
    assert read_traj(run_create_no(sockdir, sock, 100)) == ref


def run_create_no(sockdir, sock, steps):
    """The split spring-mass at 4 ms with `create no`: LAMMPS listens on sock from the fix command
    on, then the peer connects. Returns the peer's trajectory file."""
    traj = os.path.join(sockdir, "cn.txt")
    deck = spring_mass_deck(sock, 0.004, 1, steps).replace("node atom 1", "create no node atom 1")
    path = os.path.join(sockdir, "in.cn")
    open(path, "w").write(deck)
    lmp = subprocess.Popen([lmp_executable(), "-in", path, "-nocite", "-log", "none", "-echo", "none",
                            "-var", "plugin", plugin_path()], cwd=sockdir, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, stdin=subprocess.DEVNULL)
    peer = subprocess.run([PEER, "--path", sock, "--create", "no", "--accept-timeout", "30", "--io-timeout", "30",
                           "--nodes", "1", "--orientation", "none", "--steps", str(steps), "--dt", "0.004",
                           "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", "--trajectory", traj],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    out, _ = lmp.communicate(timeout=60)
    assert lmp.returncode == 0 and peer.returncode == 0, out[-2000:] + peer.stdout
    return traj


def test_split_runs_and_integrated_coupled_atom_change_nothing(sockdir):
    """Two `run` commands that split an MBDyn step (502 + 1498 LAMMPS steps, N = 4) continue the
    coupling exactly; a coupled atom also integrated by fix nve/sphere gets a warning and its motion
    is still MBDyn's; `profile yes` changes no exchanged value and reports each run's figures."""
    ref = spring_mass_error(sockdir, 0.004, substeps=4)[1]
    for change in ("split", "integrated", "profile"):
        sock = os.path.join(sockdir, "s.sock")
        traj = os.path.join(sockdir, f"{change}.txt")
        peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "500", "--dt", "0.004",
                    "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", traj=traj)
        deck = spring_mass_deck(sock, 0.001, 4, 2000)
        if change == "split":
            deck = deck.replace("run 2000", "run 502\nrun 1498")
        elif change == "profile":
            deck = deck.replace("io_timeout 20", "io_timeout 20 profile yes").replace("run 2000", "run 502\nrun 1498")
        else:
            deck = deck.replace("fix S all", "fix I all nve/sphere\nfix S all")
        rc, out, _ = run_lammps(deck, sockdir)
        prc, pout = peer.finish()
        assert rc == 0 and prc == 0, out[-2000:] + pout
        if change == "integrated":
            assert "fix I (style nve/sphere) integrates 1 coupled atoms" in out
        if change == "profile":
            lines = [l for l in out.splitlines() if l.startswith("Fix mbdyn (id M) profile:")]
            assert [l.split(",")[0] for l in lines] == ["Fix mbdyn (id M) profile: 502 steps",
                                                       "Fix mbdyn (id M) profile: 1498 steps"], out[-3000:]
            for l, steps in zip(lines, (502, 1498)):
                timed = int(l.split(" timed;")[0].split()[-1])
                cpu = float(l.split("fix cpu ")[1].split()[0])
                run_cpu = float(l.split("run cpu ")[1].split()[0])
                assert 0 < timed < steps and 0 < cpu and 0 < run_cpu, l  # one step in 8 timed on average
        assert read_traj(traj) == ref, change


@pytest.mark.two_cores
def test_spring_mass_rank_invariance(sockdir):
    e1, rows1, _ = spring_mass_error(sockdir, 0.004, substeps=2, T=0.4)
    e2, rows2, _ = spring_mass_error(sockdir, 0.004, substeps=2, T=0.4, nprocs=2)
    assert rows1 == rows2


# ------------------------------------------------------------------------------------------------
# B. rigid group: a 3x3x1 plate of particles follows a tilted, spinning MBDyn node (orientation
#    matrix, point offset); free particles fly into it (gran/hooke/history, LAMMPS' own). The loads
#    sent must equal the contact force and moment about the point computed by LAMMPS computes
#    (compute reduce over f, and over atom-style variables (x - x_com) x f + torque) and from the
#    dumped forces and torques, serial and on 2 ranks.

def plate_deck(sock, dump, steps=200, procs=""):
    return f"""plugin load ${{plugin}}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
{procs}
region box block -0.5 0.5 -0.5 0.5 -0.5 0.5
create_box 2 box
create_atoms 1 single -0.1 -0.1 0 units box
create_atoms 1 single 0 -0.1 0 units box
create_atoms 1 single 0.1 -0.1 0 units box
create_atoms 1 single -0.1 0 0 units box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 0.1 0 0 units box
create_atoms 1 single -0.1 0.1 0 units box
create_atoms 1 single 0 0.1 0 units box
create_atoms 1 single 0.1 0.1 0 units box
region cloud block -0.35 0.35 -0.35 0.35 0.06 0.3 units box
create_atoms 2 random 40 12345 cloud overlap 0.1 maxtry 200
set type 1 diameter 0.1
set type 2 diameter 0.08
set group all density 1000
group plate type 1
group bed type 2
velocity bed set 0 0 -1 units box
displace_atoms plate move 0 0 0.1 units box
pair_style gran/hooke/history 2000 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 1e-4
fix I bed nve/sphere
fix M all mbdyn path {sock} node group plate orientation matrix connect_timeout 20 io_timeout 20
compute gg plate reduce sum fx fy fz
compute pc plate com
compute tq plate property/atom tqx tqy tqz
variable xc equal c_pc[1]
variable yc equal c_pc[2]
variable zc equal c_pc[3]
variable mx atom (y-v_yc)*fz-(z-v_zc)*fy+c_tq[1]
variable my atom (z-v_zc)*fx-(x-v_xc)*fz+c_tq[2]
variable mz atom (x-v_xc)*fy-(y-v_yc)*fx+c_tq[3]
compute mm plate reduce sum v_mx v_my v_mz
thermo_style custom step f_M[1][1] f_M[1][2] f_M[1][3] f_M[1][4] f_M[1][5] f_M[1][6] c_gg[1] c_gg[2] c_gg[3] c_mm[1] c_mm[2] c_mm[3]
thermo_modify format float %.15g
thermo 20
dump d plate custom 20 {dump} id x y z fx fy fz tqx tqy tqz
dump_modify d format float %.17g sort id
run {steps}
"""


def parse_thermo(out, ncols):
    rows = {}
    for l in out.splitlines():
        p = l.split()
        if len(p) == ncols and p[0].isdigit():
            try:
                rows[int(p[0])] = [float(v) for v in p[1:]]
            except ValueError:
                pass
    return rows


def canonical(snaps):
    """Atom IDs of create_atoms depend on the processor grid: order the atoms by their first position."""
    first = snaps[min(snaps)]
    key = {int(r[0]): tuple(round(v, 9) for v in r[1:4]) for r in first}
    order = sorted(key, key=lambda i: key[i])
    return {step: [dict((int(r[0]), r[1:]) for r in rows)[i] for i in order] for step, rows in snaps.items()}


def run_plate(sockdir, nprocs):
    sock = os.path.join(sockdir, "p.sock")
    dump = os.path.join(sockdir, f"plate{nprocs}.dump")
    # the plate's centroid is the point: node at (0, 0, 0.1) with offset 0 (the test peer's
    # default node 0 state, tilted by 0.3 rad about x, spinning about z at 0.5 rad/s)
    peer = Peer(sock, "--nodes", "1", "--orientation", "matrix", "--steps", "200", "--dt", "1e-4",
                "--mass", "5", "--inertia", "0.05", "--v0", "0,0,0", "--x0", "0,0,0.1")
    procs = "processors 2 1 1" if nprocs == 2 else ""
    rc, out, _ = run_lammps(plate_deck(sock, dump, procs=procs), sockdir, nprocs=nprocs)
    prc, pout = peer.finish()
    assert rc == 0, out[-3000:]
    assert prc == 0, pout
    return parse_thermo(out, 13), read_dump(dump)


@pytest.mark.two_cores
def test_rigid_group_loads_equal_independent_compute_serial_and_2_ranks(sockdir):
    results = {}
    for nprocs in (1, 2):
        thermo, dump = run_plate(sockdir, nprocs)
        results[nprocs] = thermo
        hits = 0
        for step, row in thermo.items():
            if step == 0 or step not in dump:
                continue
            F, Mo, gg, mm = row[0:3], row[3:6], row[6:9], row[9:12]
            atoms = dump[step]
            assert len(atoms) == 9
            c = [sum(a[k] for a in atoms) / 9 for k in (1, 2, 3)]   # the point = plate centroid
            fd = [sum(a[k] for a in atoms) for k in (4, 5, 6)]
            md = [0.0, 0.0, 0.0]
            for a in atoms:
                d = [a[1] - c[0], a[2] - c[1], a[3] - c[2]]
                f = a[4:7]
                md[0] += d[1] * f[2] - d[2] * f[1] + a[7]
                md[1] += d[2] * f[0] - d[0] * f[2] + a[8]
                md[2] += d[0] * f[1] - d[1] * f[0] + a[9]
            scale = max(1e-12, max(abs(v) for v in fd))
            if scale > 1e-9:
                hits += 1
            for k in range(3):
                assert abs(F[k] - gg[k]) <= 1e-9 * scale + 1e-12, (step, F, gg)
                assert abs(F[k] - fd[k]) <= 1e-9 * scale + 1e-12, (step, F, fd)
                assert abs(Mo[k] - md[k]) <= 1e-8 * scale + 1e-12, (step, Mo, md)
                assert abs(Mo[k] - mm[k]) <= 1e-8 * scale + 1e-12, (step, Mo, mm)
        assert hits >= 3, "the bed never touched the plate: the test checks nothing"
    s, p = results[1], results[2]
    assert s.keys() == p.keys()
    for step in s:
        scale = max(1e-9, max(abs(v) for v in s[step][0:3]))
        assert max(abs(a - b) for a, b in zip(s[step], p[step])) <= 1e-8 * scale, step


def test_rigid_group_with_offset_and_reference_node_runs(sockdir):
    """Point offset and reference node: the plate follows the point and the run completes with the
    reference-frame loads MBDyn expects (the peer checks sizes and labels)."""
    sock = os.path.join(sockdir, "r.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "euler123", "--labels", "--reference-node",
                "--steps", "50", "--dt", "1e-4", "--mass", "5", "--offset", "0.01,0.02,0", "--x0", "0,0,0.1")
    deck = plate_deck(sock, os.path.join(sockdir, "r.dump"), steps=50).replace(
        "orientation matrix", "orientation euler123 labels yes reference_node yes")
    rc, out, _ = run_lammps(deck, sockdir)
    prc, pout = peer.finish()
    assert rc == 0, out[-3000:]
    assert prc == 0, pout


# ------------------------------------------------------------------------------------------------
# Robustness: every case bounded by a timeout, none hangs.

def test_peer_never_connects_errors_within_timeout(sockdir):
    sock = os.path.join(sockdir, "nobody.sock")
    rc, out, secs = run_lammps(spring_mass_deck(sock, 0.001, 1, 10).replace("connect_timeout 20", "connect_timeout 1"),
                               sockdir, timeout=60)
    err = error_line(out)
    print(f"peer never connects: ERROR after {secs:.2f} s: {err}")
    assert rc != 0
    assert "Fix mbdyn (id M)" in err and "connect" in err and "nobody.sock" in err
    assert secs < 20


def test_peer_dies_mid_run_errors_and_dump_is_complete(sockdir):
    sock = os.path.join(sockdir, "d.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "1000", "--dt", "0.001",
                "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", "--fault", "die", "--fault-message", "60")
    dump = os.path.join(sockdir, "die.dump")
    deck = spring_mass_deck(sock, 0.001, 1, 1000).replace(
        "run 1000", f"dump d all custom 1 {dump} id x vx fx\nrun 1000")
    rc, out, secs = run_lammps(deck, sockdir, timeout=60)
    peer.finish()
    err = error_line(out)
    print(f"peer dies: ERROR after {secs:.2f} s: {err}")
    assert rc != 0
    assert "closed the connection" in err and "LAMMPS step" in err
    snaps = read_dump(dump)
    last = max(snaps)
    assert last >= 58 and all(len(v) == 1 for v in snaps.values())
    assert open(dump).read().endswith("\n")


@pytest.mark.parametrize("fault,expect", [
    ("garbage-command", "invalid command"),
    ("short-then-close", "closed the connection"),
    ("short-then-stall", "timed out"),
    ("nan", "nan"),
])
def test_wire_faults_error(sockdir, fault, expect):
    sock = os.path.join(sockdir, "f.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "100", "--dt", "0.001",
                "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0", "--fault", fault, "--fault-message", "5",
                timeout=15)
    deck = spring_mass_deck(sock, 0.001, 1, 100).replace("io_timeout 20", "io_timeout 2")
    rc, out, secs = run_lammps(deck, sockdir, timeout=60)
    prc, pout = peer.finish()
    err = error_line(out)
    assert rc != 0, out[-2000:]
    assert expect in err.lower(), err
    assert secs < 30


def test_wrong_node_count_in_negotiation(sockdir):
    sock = os.path.join(sockdir, "n.sock")
    peer = Peer(sock, "--nodes", "2", "--orientation", "none", "--steps", "10", timeout=15)
    rc, out, _ = run_lammps(spring_mass_deck(sock, 0.001, 1, 10), sockdir, timeout=60)
    prc, pout = peer.finish()
    assert rc != 0
    assert "Fix mbdyn (id M)" in error_line(out)
    assert prc == 1 and "mismatch" in pout.lower() or "node" in pout.lower()


def test_mbdyn_shorter_than_lammps_stops_run_cleanly(sockdir):
    sock = os.path.join(sockdir, "e.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "20", "--dt", "0.001",
                "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0")
    rc, out, _ = run_lammps(spring_mass_deck(sock, 0.001, 1, 100), sockdir, timeout=60)
    prc, pout = peer.finish()
    assert rc == 0, out[-2000:]
    assert "MBDyn ended the simulation" in out
    assert prc == 0, pout


def test_lammps_shorter_than_mbdyn_asks_mbdyn_to_stop(sockdir):
    sock = os.path.join(sockdir, "l.sock")
    peer = Peer(sock, "--nodes", "1", "--orientation", "none", "--steps", "100", "--dt", "0.001",
                "--mass", str(M), "--x0", f"{X0},0,0", "--v0", "0,0,0")
    rc, out, _ = run_lammps(spring_mass_deck(sock, 0.001, 1, 30), sockdir, timeout=60)
    prc, pout = peer.finish()
    assert rc == 0, out[-2000:]
    assert prc == 2 and "peer requested end" in pout, pout   # MBDyn's "interrupted" status


BAD = {
    "unknown_atom": ("node atom 1", "node atom 99", ["node 1 (atom 99)", "no atom with ID 99"]),
    "unknown_keyword": ("connect_timeout 20", "connect_timeout 20 frobnicate 3",
                        ["unknown keyword 'frobnicate'", "expected one of"]),
    "bad_node_kind": ("node atom 1", "node body 1", ["'node' expects 'atom ATOM-ID', 'group GROUP-ID' or 'mesh MESH-ID'", "'body'"]),
    "unknown_group": ("node atom 1", "node group wall", ["group 'wall' does not exist"]),
    "bad_timeout": ("io_timeout 20", "io_timeout soon", ["'io_timeout' expects seconds", "'soon'"]),
    "bad_substeps": ("substeps 1", "substeps 0", ["'substeps' expects a positive integer", "'0'"]),
    "no_socket": ("path ", "nopath ", ["unknown keyword 'nopath'"]),
    "bad_mbdyn_dt": ("substeps 1", "mbdyn_dt 0.0015", ["integer multiple of the LAMMPS timestep"]),
    "bad_predictor": ("substeps 1", "substeps 1 predictor taylor", ["keyword 'predictor' expects mbdyn or correct", "'taylor'"]),
    "bad_profile": ("substeps 1", "substeps 1 profile maybe", ["keyword 'profile' expects yes or no", "'maybe'"]),
    "startup_loose": ("substeps 1", "substeps 1 startup_exchange no", ["'startup_exchange no' is for coupling tight"]),
    "unknown_mesh": ("node atom 1", "node mesh nomesh", ["node mesh nomesh"]),
    "mesh_without_stress": ("fix M all mbdyn", "fix nomesh all mesh/surface file "
                            "tri.stl type 1\nfix M all mbdyn", ["needs fix mesh/surface/stress"]),
    "respa": ("run 10", "run_style respa 2 2\nrun 10", ["does not support run_style respa"]),
    "gravity_order": ("fix D all viscous", "fix G all gravity 9.81 vector 0 0 -1\nfix D all viscous",
                      ["gravity no (the default) needs fix G", "after fix mbdyn"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input(case, sockdir):
    old, new, expect = BAD[case]
    deck = spring_mass_deck(os.path.join(sockdir, "never.sock"), 0.001, 1, 10).replace(old, new, 1)
    if case == "mesh_without_stress":
        deck = deck.replace("node atom 1", "node mesh nomesh")
        open(os.path.join(sockdir, "tri.stl"), "w").write(
            "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\nendsolid t\n")
    rc, out, secs = run_lammps(deck, sockdir, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert "Fix mbdyn (id M)" in err, err
    for e in expect:
        assert e in err, err
    assert secs < 15  # reported before any connect attempt


@pytest.mark.two_cores
def test_tight_iterations_do_not_disturb_the_particles(sockdir):
    """Tight iterates re-evaluate forces only (coupled atoms at the iterate's pose, every other atom
    where it is, contact history not updated). With a body so heavy that MBDyn's later iterates
    repeat exactly, runs with 1 and with 2 re-evaluations per step must move the bed identically:
    re-evaluations that leaked into the shear history or the particle state would show here.
    Serial and 2 ranks."""
    dumps, exchanges = {}, {}
    for maxit, nprocs in ((2, 1), (4, 1), (4, 2)):
        sock = os.path.join(sockdir, "t.sock")
        dump = os.path.join(sockdir, f"bed_{maxit}_{nprocs}.dump")
        peer = Peer(sock, "--nodes", "1", "--orientation", "matrix", "--coupling", "tight", "--steps", "200",
                    "--dt", "1e-4", "--mass", "1e12", "--inertia", "1e12", "--v0", "0,0,0", "--x0", "0,0,0.1",
                    "--force", "0,0,1")  # non-zero initial residual: MBDyn's start-up exchange (spec T2)
        deck = plate_deck(sock, os.path.join(sockdir, "p.dump"), procs="processors 2 1 1" if nprocs == 2 else "")
        deck = deck.replace("orientation matrix", f"orientation matrix coupling tight tolerance 0 max_iterations {maxit}")
        deck = deck.replace("run 200", f"dump b bed custom 20 {dump} id x y z vx vy vz\ndump_modify b format float %.17g sort id\nrun 200")
        rc, out, _ = run_lammps(deck, sockdir, nprocs=nprocs)
        prc, pout = peer.finish()
        assert rc == 0, out[-3000:]
        assert prc == 0, pout
        exchanges[(maxit, nprocs)] = int(pout.split("(")[1].split(" kinematics")[0])
        dumps[(maxit, nprocs)] = canonical(read_dump(dump))
    assert exchanges[(2, 1)] == 1 + 2 * 200
    # (the last bits of MBDyn's momentum of a 1e12 kg node depend on the summation order of the
    # contact loads, so the iteration count on 2 ranks may differ by a few; the bed must not)
    assert exchanges[(4, 1)] >= 1 + 3 * 200 and abs(exchanges[(4, 2)] - exchanges[(4, 1)]) <= 5
    ref = dumps[(2, 1)]
    moved = max(abs(a[2] - b[2]) for a, b in zip(ref[0], ref[200]))
    assert moved > 0.005
    for key in ((4, 1), (4, 2)):
        dev = max(abs(x - y) for step in ref for a, b in zip(ref[step], dumps[key][step]) for x, y in zip(a, b))
        print(f"bed deviation, max_iterations 2 (1 re-evaluation/step) vs {key} ({exchanges[key]} messages): "
              f"{dev:.2e} (bed moved {moved:.3f})")
        assert dev < 1e-12


# ------------------------------------------------------------------------------------------------
# fix mbdyn/floor: the bench's floor instrument (issue 12, P5; bench/run_mbdyn_exchange_bench.py).
# It must do exactly one exchange per step, answer every message the way MBDyn expects (the bench
# peer checks each answer's command and length and fails otherwise), end cleanly on the peer's 5,
# and report its profile line per run. A wrong answer or a missed exchange makes the peer fail.

def bench_peer():
    base = os.path.dirname(os.path.abspath(plugin_path()))
    exe = os.path.join(base, "coupling", "mbdyn_bench_peer")
    return exe if os.path.exists(exe) else None


FLOOR_DECK = """plugin load ${{plugin}}
units si
atom_style sphere
boundary f f f
region box block -1 1 -1 1 -1 1
create_box 1 box
create_atoms 1 single 0.1 0 0 units box
set atom 1 diameter 0.05 density 1000
timestep 0.001
fix F all mbdyn/floor {where} nodes 3 profile yes
run 80
run 48
"""


@pytest.mark.skipif(bench_peer() is None, reason="needs the mbdyn_bench_peer executable")
@pytest.mark.parametrize("kind", ["unix", "tcp"])
def test_floor_instrument_exchanges_once_per_step(sockdir, kind):
    exe = bench_peer()
    where = ["--path", os.path.join(sockdir, "f.sock")] if kind == "unix" else ["--port", "0"]
    # 1 t0 message + 128 steps; an exchange more or fewer would fail the peer or LAMMPS
    peer = subprocess.Popen([exe, "serve", *where, "--nodes", "3", "--messages", "129"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    line = peer.stdout.readline()
    assert "listening" in line, line
    at = f"path {where[1]}" if kind == "unix" else f"port {line.split()[-1]}"
    rc, out, _ = run_lammps(FLOOR_DECK.format(where=at), sockdir, timeout=60)
    pout, _ = peer.communicate(timeout=30)
    assert rc == 0, out[-3000:]
    assert peer.returncode == 0, pout
    lines = [l.split(",")[0] for l in out.splitlines() if l.startswith("Fix mbdyn/floor (id F) profile:")]
    assert lines == ["Fix mbdyn/floor (id F) profile: 80 steps", "Fix mbdyn/floor (id F) profile: 48 steps"], out[-3000:]


MAPPING_BENCH_DECK = """plugin load ${{plugin}}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.01 0.03 -0.01 0.02 -0.02 0.03 units box
create_box 1 box
create_atoms 1 single 0.005 0.005 0.004 units box
set type 1 diameter 0.008 density 2500
fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-5
fix plate all mesh/surface/stress file {stl} type 1
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate
fix I all nve/sphere
fix M all mbdyn path {sock} mapping plate points 6 orientation none connect_timeout 30 io_timeout 30
run 20
"""


@pytest.mark.skipif(bench_peer() is None, reason="needs the mbdyn_bench_peer executable")
def test_bench_peer_speaks_the_mapping_layout(sockdir):
    """The bench's mapping rows: `serve --orientation none --grid 3` sends the 6 mapped points of a 3 x 2 grid
    (spacing 0.01) that fix mbdyn ... mapping matches to the mesh's vertices (else an ERROR names the vertex) and
    answers every message with 6 forces (else the peer fails); the bare client speaks the same layout."""
    exe = bench_peer()
    stl = os.path.join(sockdir, "grid.stl")
    v = lambda i, j: f"vertex {i * 0.01!r} {j * 0.01!r} 0.0"  # noqa: E731  the doubles the peer computes
    with open(stl, "w") as fh:
        fh.write("solid g\n")
        for i in range(2):
            for tri in (((i, 0), (i + 1, 0), (i + 1, 1)), ((i, 0), (i + 1, 1), (i, 1))):
                fh.write("facet normal 0 0 1\nouter loop\n" + "\n".join(v(*c) for c in tri) + "\nendloop\nendfacet\n")
        fh.write("endsolid g\n")
    shape = ["--nodes", "6", "--orientation", "none", "--grid", "3", "--spacing", "0.01,0.01,0"]
    for client in ("lammps", "bare"):
        sock = os.path.join(sockdir, f"{client}.sock")
        peer = subprocess.Popen([exe, "serve", "--path", sock, *shape, "--messages", "21"], stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)
        assert "listening" in peer.stdout.readline()
        if client == "lammps":
            rc, out, _ = run_lammps(MAPPING_BENCH_DECK.format(stl=stl, sock=sock), sockdir, timeout=60)
        else:
            r = subprocess.run([exe, "client", "--path", sock, "--nodes", "6", "--orientation", "none"],
                               capture_output=True, text=True, timeout=60)
            rc, out = r.returncode, r.stdout + r.stderr
            assert "20 exchanges" in out, out
        pout, _ = peer.communicate(timeout=30)
        assert rc == 0, out[-3000:]
        assert peer.returncode == 0, pout


@pytest.mark.parametrize("old,new,expect", [
    ("nodes 3", "nodes 0", "keyword 'nodes' expects a positive node count, got 0"),
    ("profile yes", "profile maybe", "keyword 'profile' expects yes or no, got 'maybe'"),
    ("nodes 3", "nodes 3 speed 9", "unknown keyword 'speed'"),
    ("path never.sock", "", "give exactly one socket"),
])
def test_floor_instrument_bad_input(sockdir, old, new, expect):
    rc, out, secs = run_lammps(FLOOR_DECK.format(where="path never.sock").replace(old, new, 1), sockdir, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert "Fix mbdyn/floor (id F)" in err and expect in err, err
    assert secs < 15
