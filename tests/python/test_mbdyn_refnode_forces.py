"""fix mbdyn with MBDyn's `reference node`, `use reference node forces`, `labels, yes` and
`sorted, no`, driven by the kinematics the real MBDyn 1.7.3 sent (tests/data/mbdyn-ext/
refnode_forces, loose and tight): it must answer the loads the recording peer answered, to
<= 1e-12 of each field's largest value, with the same command bytes and labels. The recording
peer's law (point i: F = -k (x~ - x~0) in the reference frame, no moments; the reference record: the
constant total resultant F0 = (0, 0.2, 0), M0 = (0, 0, 0.05), reference frame, moment about the
reference node) is written as a LAMMPS deck: point atoms pulled by fix addforce towards anchor atoms
that follow the reference node (`reference group`), the anchors pulled back equally, and a constant
force and couple along the reference node's axes on the reference body, so the body's and the
points' loads add up to F0, M0. Also every new keyword's bad values give an ERROR naming it."""
import csv
import gzip
import os
import shutil
import socket
import struct
import tempfile
import threading

import pytest

from dembridge import plugin_path
from test_fix_mbdyn import PEER, error_line, run_lammps

pytestmark = pytest.mark.skipif(not os.path.exists(plugin_path()), reason="needs the plugin (build dembridgeplugin)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "mbdyn-ext", "refnode_forces")
K_SPRING = 25.0
# the wire layouts of this element (3 points, labels, orientation matrix, reference node):
# kinematics: ref label + pad, x_r, R_r, v_r, w_r; 3 labels + pad; x~, R~, v~, w~
KIN = "=2I18d4I54d"
# loads: ref label + pad, F0, M0; 3 labels + pad; F, M
LOADS = "=2I6d4I18d"
# (name, first, last) value index ranges of the loads message, for the per-field comparison
LOAD_FIELDS = [("F0", 2, 5), ("M0", 5, 8), ("F", 12, 21), ("M", 21, 30)]


def read(name):
    with gzip.open(os.path.join(DATA, name), "rt") as f:
        return [(int(r["seq"]), r["dir"], int(r["cmd"]), r["values"].split()) for r in csv.DictReader(f)]


def pack(fmt, vals):
    codes = []
    for n, c in __import__("re").findall(r"(\d*)([Id])", fmt):
        codes += [c] * int(n or 1)
    assert len(codes) == len(vals)
    return struct.pack(fmt, *[int(v) if c == "I" else float(v) for c, v in zip(codes, vals)])


class RecordedMbdyn(threading.Thread):
    """Listens like MBDyn `create, yes`, plays the recorded kinematics and collects the answers."""

    def __init__(self, path, rows):
        super().__init__(daemon=True)
        self.rows, self.answers, self.error = rows, [], None
        self.srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.srv.bind(path)
        self.srv.listen(1)
        self.srv.settimeout(120)
        self.start()

    def recv(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.conn.recv(n - len(buf))
            if not chunk:
                raise ConnectionError(f"fix mbdyn closed after {len(buf)} of {n} bytes")
            buf += chunk
        return buf

    def run(self):
        try:
            self.conn, _ = self.srv.accept()
            self.conn.settimeout(120)
            for seq, d, cmd, vals in self.rows:
                if d == "mbdyn->peer":
                    self.conn.sendall(bytes([cmd]) + (pack(KIN, vals) if cmd in (2, 6) else b""))
                elif cmd == 7:
                    self.answers.append((seq, 7, list(struct.unpack("=BII", self.recv(9))[1:])))
                else:
                    c = self.recv(1)[0]
                    body = self.recv(struct.calcsize(LOADS)) if c in (2, 6) else b""
                    self.answers.append((seq, c, list(struct.unpack(LOADS, body)) if body else []))
            self.conn.close()
        except Exception as e:  # reported by the test
            self.error = repr(e)
        finally:
            self.srv.close()


DECK = """plugin load ${{plugin}}
units si
atom_style atomic
atom_modify map array
boundary f f f
region box block -5 5 -5 5 -5 5
create_box 1 box
mass 1 1.0
# atoms 1-3 carry MBDyn's points 20, 30, 40; atoms 4-6 are their rest places and atom 7 the
# reference node itself, all on the body that follows the reference node (at t0: REF at the origin, R = I)
create_atoms 1 single 1 0 0 units box
create_atoms 1 single 0 1 0 units box
create_atoms 1 single 0 0 1 units box
create_atoms 1 single 1 0 0 units box
create_atoms 1 single 0 1 0 units box
create_atoms 1 single 0 0 1 units box
create_atoms 1 single 0 0 0 units box
group refbody id 4:7
timestep 0.002
{springs}
# the reference frame's y axis is x[5] - x[7]: 0.2 along it on the body in all, 0.15 at the node and
# 0.05 at x_r + R e_x, with -0.05 of those at the node: a couple 0.05 about the frame's z axis
variable r7x equal 0.15*(x[5]-x[7])
variable r7y equal 0.15*(y[5]-y[7])
variable r7z equal 0.15*(z[5]-z[7])
group a7 id 7
fix r7 a7 addforce v_r7x v_r7y v_r7z
fix M all mbdyn path {sock} node atom 1 node atom 2 node atom 3 reference group refbody reference_node yes &
    labels yes sorted no orientation matrix coupling {coupling} reference_forces yes rotate_reference_forces yes &
    connect_timeout 120 io_timeout 120 {extra}
run {steps}
"""


def springs():
    lines = []
    for i in (1, 2, 3):
        a = i + 3
        for c in "xyz":
            lines.append(f"variable p{i}{c} equal -{K_SPRING}*({c}[{i}]-{c}[{a}])")
            couple = f"+0.05*({c}[5]-{c}[7])" if a == 4 else ""
            lines.append(f"variable a{a}{c} equal {K_SPRING}*({c}[{i}]-{c}[{a}]){couple}")
        lines += [f"group p{i} id {i}", f"fix p{i} p{i} addforce v_p{i}x v_p{i}y v_p{i}z",
                  f"group a{a} id {a}", f"fix a{a} a{a} addforce v_a{a}x v_a{a}y v_a{a}z"]
    return "\n".join(lines)


@pytest.fixture
def sockdir():
    d = tempfile.mkdtemp(prefix="mbrf", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


@pytest.mark.parametrize("coupling,nprocs", [("loose", 1), ("tight", 1),
                                             pytest.param("loose", 2, marks=pytest.mark.two_cores)])
def test_fix_mbdyn_answers_the_recorded_refnode_loads(coupling, nprocs, sockdir):
    rows = read(f"transcript_{coupling}.csv.gz")
    steps = sum(1 for _, d, c, _ in rows if d == "peer->mbdyn" and c == 6) - 1  # minus the start-up answer
    sock = os.path.join(sockdir, "r.sock")
    mbdyn = RecordedMbdyn(sock, rows)
    # tight: the recording peer converged when no double of the message moved by more than 1e-10;
    # on this run that is a change of the global pose <= 4.4e-16 (converged) against >= 7.4e-14
    extra = "tolerance 1e-14" if coupling == "tight" else ""
    rc, out, secs = run_lammps(DECK.format(springs=springs(), sock=sock, coupling=coupling, extra=extra, steps=steps),
                               sockdir, nprocs=nprocs, timeout=300)
    mbdyn.join(120)
    assert mbdyn.error is None, (mbdyn.error, out[-3000:])
    assert rc == 0, out[-3000:]
    expected = [(s, c, v) for s, d, c, v in rows if d == "peer->mbdyn"]
    got = mbdyn.answers
    assert [(s, c) for s, c, _ in got] == [(s, c) for s, c, _ in expected]
    assert got[0][2] == [534, 3]  # NODAL | REF_NODE | LABELS | matrix, 3 points
    data = [(g, [float(x) for x in e]) for (_, c, g), (_, _, e) in zip(got, expected) if c in (2, 6)]
    for g, e in data:  # reference label, pad, the labels in the received order (20 30 40), pad
        assert [int(x) for x in g[0:2] + g[8:12]] == [int(x) for x in e[0:2] + e[8:12]] == [10, 0, 20, 30, 40, 0]
    report = []
    for name, a, b in LOAD_FIELDS:
        scale = max(max(abs(x) for x in e[a:b]) for _, e in data)
        worst = max(max(abs(x - y) for x, y in zip(g[a:b], e[a:b])) for g, e in data)
        report.append(f"{name} {worst / scale if scale else worst:.1e}" + ("" if scale else " (absolute)"))
        assert worst <= 1e-12 * (scale if scale else 1.0), (name, worst, scale)
    print(f"refnode {coupling}, {nprocs} rank(s): {len(data)} answers in {secs:.1f} s; worst deviation per field "
          f"(relative to its largest value): {', '.join(report)}")


BAD = {
    "sorted_value": ("sorted no", "sorted maybe", ["keyword 'sorted' expects yes or no", "'maybe'"]),
    "sorted_without_labels": ("labels yes sorted no", "labels no sorted no", ["'sorted no' needs 'labels yes'"]),
    "reference_forces_value": ("reference_forces yes", "reference_forces 1", ["keyword 'reference_forces' expects yes or no", "'1'"]),
    "rotate_value": ("rotate_reference_forces yes", "rotate_reference_forces on",
                     ["keyword 'rotate_reference_forces' expects yes or no", "'on'"]),
    "reference_forces_without_node": ("reference group refbody reference_node yes", "reference_node no",
                                      ["'reference_forces' and 'rotate_reference_forces' need 'reference_node yes'"]),
    "reference_body_without_node": ("reference_node yes", "reference_node no", ["'reference' need", "'reference_node yes'"]),
    "reference_body_unused": ("reference_forces yes", "reference_forces no", ["'reference' needs 'reference_forces yes'"]),
    "reference_kind": ("reference group refbody", "reference mesh refbody",
                       ["keyword 'reference' expects 'atom ATOM-ID' or 'group GROUP-ID'", "'mesh'"]),
    "reference_group": ("reference group refbody", "reference group nobody", ["reference: group 'nobody' does not exist"]),
    "reference_atom": ("reference group refbody", "reference atom 99", ["reference (atom 99): no atom with ID 99"]),
    "reference_twice": ("reference group refbody", "reference group refbody reference atom 7",
                        ["keyword 'reference' given twice"]),
    "reference_is_a_node": ("reference group refbody", "reference atom 1", ["node 1 and reference are both 'atom 1'"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_refnode_keywords_bad_input(case, sockdir):
    old, new, expect = BAD[case]
    deck = DECK.format(springs=springs(), sock=os.path.join(sockdir, "never.sock"), coupling="loose",
                       extra="", steps=1)
    assert old in deck
    rc, out, secs = run_lammps(deck.replace(old, new, 1), sockdir, timeout=60)
    err = error_line(out)
    assert rc != 0
    assert "Fix mbdyn (id M)" in err, out[-2000:]
    for e in expect:
        assert e in err, err
    assert secs < 15  # before any connect attempt
