"""MBDyn's `external structural mapping` with a wall of particles, one atom per mapped point.
Without reference node and labels its messages are those of `external structural` with
`orientation none` and N = the mapped points: q[3M] then q'[3M], answered with p[3M] (flags 0x2).
fix mbdyn with 15 `node atom` entries and `orientation none`, driven by the kinematics the real
MBDyn 1.7.3 sent in the recorded cantilever runs (tests/data/mbdyn-ext/mapping_beam, loose and
tight), must answer the loads the recording peer answered, to <= 1e-12 of the largest load, with
the same command bytes. The peer's law, F_j = f0 + (-k (q_j - q0_j) - c q'_j) on the tip points
j = 12, 13, 14 and F_j = f0 on the others (k = 20, c = 0.5, f0 = (0, 0, -0.2), q0 = the t0
message), is the deck: fix addforce f0 on every atom, fix spring tether and fix viscous on the tips."""
import csv
import gzip
import os

import pytest

from dembridge import plugin_path
from mbdyn_transcripts import FakeMbdyn
from test_fix_mbdyn import run_lammps
from test_mbdyn_refnode_forces import sockdir  # noqa: F401 (the fixture: a short folder for the socket)

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "mapping_beam")
M_POINTS, TIPS = 15, (12, 13, 14)


def read(name):
    with gzip.open(os.path.join(DATA, name), "rt") as f:
        return [(int(r["seq"]), r["dir"], int(r["cmd"]), r["values"].split()) for r in csv.DictReader(f)]


def deck(sock, q0, coupling, steps, extra):
    atoms = "\n".join(f"create_atoms 1 single {q0[3 * j]!r} {q0[3 * j + 1]!r} {q0[3 * j + 2]!r} units box"
                      for j in range(M_POINTS))
    tips = "\n".join(f"group tip{j} id {j + 1}\nfix k{j} tip{j} spring tether 20 {q0[3 * j]!r} {q0[3 * j + 1]!r} "
                     f"{q0[3 * j + 2]!r} 0" for j in TIPS)
    nodes = " ".join(f"node atom {j + 1}" for j in range(M_POINTS))
    return f"""plugin load ${{plugin}}
units si
atom_style atomic
atom_modify map array
boundary f f f
region box block -1 3 -1 1 -1 1
create_box 1 box
mass 1 1.0
{atoms}
timestep 0.002
group tips id {' '.join(str(j + 1) for j in TIPS)}
{tips}
fix c tips viscous 0.5
fix f0 all addforce 0 0 -0.2
fix M all mbdyn path {sock} {nodes} orientation none coupling {coupling} connect_timeout 120 io_timeout 120 {extra}
run {steps}
"""


@pytest.mark.parametrize("coupling", ["loose", "tight"])
def test_wall_of_atoms_answers_the_recorded_mapping_loads(coupling, sockdir):
    rows = read(f"transcript_{coupling}.csv.gz")
    q0 = [float(v) for v in next(v for _, d, c, v in rows if d == "mbdyn->peer" and c in (2, 6))][:3 * M_POINTS]
    steps = sum(1 for _, d, c, _ in rows if d == "peer->mbdyn" and c == 6) - 1  # minus the start-up answer
    sock = os.path.join(sockdir, "m.sock")
    fake = FakeMbdyn(sock, rows, timeout=120)
    # tight: the recording peer accepted an iterate when no value moved by more than 1e-10; the
    # velocities dominate, and crank nicolson's v = 2/dt (x - x_prev) - v_prev makes that a change
    # of the positions <= 1e-10 dt/2 = 1e-13 (on the recording: accepted <= 9.99e-14, others >= 1.0002e-13)
    extra = "tolerance 1e-13" if coupling == "tight" else ""
    rc, out, secs = run_lammps(deck(sock, q0, coupling, steps, extra), sockdir, timeout=300)
    answers = fake.join()
    assert fake.error is None, (fake.error, out[-3000:])
    assert rc == 0, out[-3000:]
    expected = [(s, c, [float(x) for x in v]) for s, d, c, v in rows if d == "peer->mbdyn"]
    assert answers[0][2] == [2, M_POINTS]  # NODAL, no rotation: what MBDyn's mapping element expects
    assert [(s, c) for s, c, _ in answers] == [(s, c) for s, c, _ in expected]
    data = [(a, e) for (_, c, a), (_, _, e) in zip(answers, expected) if c in (2, 6)]
    scale = max(abs(x) for _, e in data for x in e)
    worst = max(abs(x - y) for a, e in data for x, y in zip(a, e))
    print(f"mapping {coupling}: {len(data)} answers in {secs:.1f} s, worst deviation {worst / scale:.1e} "
          f"of the largest load {scale:.3g}")
    assert worst <= 1e-12 * scale
